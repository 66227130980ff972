//! Lens samples on a checker plane against float64: `lens_probe FILE OBJ SIDE OPS...`
//! (the plane's transformation, `r x -90 t 1 2 3 s 1 1 1`): at every pixel more
//! than 2 levels off, each sample's checker parity in Q16.16, f32 and f64.
use embedded_graphics::pixelcolor::RgbColor;
use lensray::unstable::camera::basis;
use lensray::unstable::sampler::PixelSamples;
use lensray::unstable::transform::Mat34;
use lensray::CameraSample;
use lensray::{Scene, I16F16};
use lensray_host::render_both;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let text = std::fs::read_to_string(&a[0]).unwrap();
    let k: usize = a[1].parse().unwrap();
    let side: f64 = a[2].parse().unwrap();
    // The plane's transformation lines after SIDE, e.g. `r x -90 t 1 2 3 s 1 1 1`.
    let mut m = Mat34::IDENTITY;
    let mut it = a[3..].iter();
    while let Some(op) = it.next() {
        let mut num = || it.next().unwrap().parse::<f64>().unwrap();
        let step = match op.as_str() {
            "t" => Mat34::translate([num(), num(), num()]),
            "s" => Mat34::scale([num(), num(), num()]),
            _ => {
                let axis = match it.next().unwrap().as_str() {
                    "x" => 0,
                    "y" => 1,
                    _ => 2,
                };
                Mat34::rotate(axis, it.next().unwrap().parse().unwrap())
            }
        };
        m = step.after(&m);
    }
    let inv = m.inverse().unwrap().0;
    let (tx, ty, tz) = (0.0, 0.0, 0.0);
    let mut fixed = Scene::<I16F16>::parse(&text).unwrap();
    let mut float = Scene::<f32>::parse(&text).unwrap();
    fixed.camera.adaptive = false;
    float.camera.adaptive = false;
    let (w, h) = (160u32, 120u32);
    let (ia, ib) = render_both(&fixed, &float, w, h, Some(16));
    let rf = lensray::Renderer::new(&fixed, w, h).with_samples(16);
    let rg = lensray::Renderer::new(&float, w, h).with_samples(16);
    let p = fixed.camera;
    let [u, v, n] = basis(&p).unwrap();
    let pitch = p.width / w as f64;
    let (hw, hh) = (p.width / 2.0, pitch * h as f64 / 2.0);
    let tilt = p.radius * (p.image_distance - p.focal_length) / p.focal_length;
    let parity = |ox: f64, oy: f64| ((ox / side).floor() as i64 + (oy / side).floor() as i64) & 1 == 1;
    let (mut n_px, mut n_s, mut q_bad, mut f_bad, mut qo_bad, mut both_bad) = (0, 0, 0, 0, 0, 0);
    let (mut far_q, mut far_f, mut n_far) = (0, 0, 0);
    let (mut q_err, mut f_err, mut qo_err) = (0.0f64, 0.0f64, 0.0f64);
    for row in 0..h {
        for col in 0..w {
            let i = (row * w + col) as usize;
            let (pa, pb) = (ia.pixels[i], ib.pixels[i]);
            let e = [
                pa.r().abs_diff(pb.r()),
                pa.g().abs_diff(pb.g()),
                pa.b().abs_diff(pb.b()),
            ];
            if *e.iter().max().unwrap() <= 2 {
                continue;
            }
            n_px += 1;
            let mut samples = PixelSamples::new(rf.sampler(), col, row);
            let filmq = rf.camera().film_point(col, row);
            let filmf = rg.camera().film_point(col, row);
            for _ in 0..16 {
                let lens = samples.next(rf.camera().aperture());
                let qr = rf.camera().generate_ray(&CameraSample {
                    film: &filmq,
                    lens: Some(lens),
                });
                let fr = rg.camera().generate_ray(&CameraSample {
                    film: &filmf,
                    lens: Some(lens),
                });
                let (sx, sy) = (lens.0 as f64 / 32768.0, lens.1 as f64 / 32768.0);
                let (ci, cj) = ((2 * col + 1) as f64, (2 * row + 1) as f64);
                let dir: [f64; 3] = core::array::from_fn(|m| {
                    ci * u[m] * pitch / 2.0 - cj * v[m] * pitch / 2.0
                        + (-hw * u[m] + hh * v[m] - p.image_distance * n[m])
                        - sx * tilt * u[m]
                        - sy * tilt * v[m]
                });
                let org: [f64; 3] =
                    core::array::from_fn(|m| p.lens_position[m] + sx * p.radius * u[m] + sy * p.radius * v[m]);
                let hit64 = |o: [f64; 3]| {
                    let row = |r: &[f64; 4], p: [f64; 3]| r[0] * p[0] + r[1] * p[1] + r[2] * p[2];
                    let t = -(row(&inv[2], o) + inv[2][3]) / row(&inv[2], dir);
                    (t > 0.0).then(|| {
                        let p = [0, 1, 2].map(|i| o[i] + t * dir[i]);
                        (row(&inv[0], p) + inv[0][3], row(&inv[1], p) + inv[1][3])
                    })
                };
                let Some((ox, oy)) = hit64(org) else { continue };
                let far = {
                    let row = |r: &[f64; 4], p: [f64; 3]| r[0] * p[0] + r[1] * p[1] + r[2] * p[2];
                    let t = -(row(&inv[2], org) + inv[2][3]) / row(&inv[2], dir);
                    t * (dir.iter().map(|x| x * x).sum::<f64>()).sqrt() > 32000.0
                };
                let _ = (tx, ty, tz);
                let qo = qr.origin.to_f64();
                let (qox, qoy) = hit64(qo).unwrap_or((f64::NAN, f64::NAN));
                let hq =
                    fixed.objects()[k].intersect_dir(qr.origin, qr.dir, qr.precise, I16F16::from_bits(64), I16F16::MAX);
                let hf = float.objects()[k].intersect_dir(fr.origin, fr.dir, fr.precise, 1e-3, f32::MAX);
                let (Some(hq), Some(hf)) = (hq, hf) else { continue };
                n_s += 1;
                let want = parity(ox, oy);
                let q = fixed.objects()[k].in_dark_square(&hq);
                let fl = float.objects()[k].in_dark_square(&hf);
                q_bad += (q != want) as u32;
                far_q += (far && q != want) as u32;
                far_f += (far && fl != want) as u32;
                n_far += far as u32;
                f_bad += (fl != want) as u32;
                both_bad += (q != want && fl != want) as u32;
                qo_bad += (parity(qox, qoy) != want) as u32;
                let dq =
                    ((hq.local.p.x.to_num::<f64>() - ox).powi(2) + (hq.local.p.y.to_num::<f64>() - oy).powi(2)).sqrt();
                let df = ((hf.local.p.x as f64 - ox).powi(2) + (hf.local.p.y as f64 - oy).powi(2)).sqrt();
                let dqo = ((qox - ox).powi(2) + (qoy - oy).powi(2)).sqrt();
                // Beyond the range Q16.16's x and y are a square's middle, not the point.
                if !far {
                    q_err = q_err.max(dq);
                }
                f_err = f_err.max(df);
                qo_err = qo_err.max(dqo);
                if std::env::var("V").is_ok() {
                    println!("({col},{row}) {lens:?} f64 ({ox:.5},{oy:.5}) dq {dq:.2e} df {df:.2e} dq_origin_only {dqo:.2e} par q{} f{} 64{}", q as u8, fl as u8, want as u8);
                }
            }
        }
    }
    println!("{n_px} pixels > 2 levels, {n_s} samples on the plane: parity wrong vs f64: Q16.16 {q_bad}, f32 {f_bad}, both {both_bad}, f64 from Q16.16's origin {qo_bad}");
    println!("of them beyond 32000 of the lens: {n_far}, wrong there: Q16.16 {far_q}, f32 {far_f}");
    println!(
        "largest hit error vs f64: Q16.16 {q_err:.3e}, f32 {f_err:.3e}, f64 from Q16.16's rounded origin {qo_err:.3e}"
    );
}
