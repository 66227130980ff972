//! Which number type is right where Q16.16 and f32 disagree (pinhole):
//! `pixel_truth FILE...` lists every pixel more than 2 levels apart with
//! both colours, the float64 one (`lensray_host::reference64`), the object
//! each hits, the margins of the decisions involved (object units) and the
//! shadow rays' near blockers.
use embedded_graphics::pixelcolor::RgbColor;
use lensray::I16F16;
use lensray_host::reference64::Scene64;
use lensray_host::render_both;

fn main() {
    let (w, h) = (160u32, 120u32);
    for path in std::env::args().skip(1) {
        let text = std::fs::read_to_string(&path).expect("read");
        let (fixed, float) = lensray_host::both_unadaptive(&text);
        let s64 = Scene64::parse(&text);
        let (a, b) = render_both(&fixed, &float, w, h, None);
        let rf = lensray::Renderer::new(&fixed, w, h);
        let rg = lensray::Renderer::new(&float, w, h);
        let (mut q_right, mut f_right, mut neither) = (0, 0, 0);
        println!("{path}");
        for i in 0..(w * h) as usize {
            let (pa, pb) = (a.pixels[i], b.pixels[i]);
            let qa = [pa.r(), pa.g(), pa.b()];
            let fb = [pb.r(), pb.g(), pb.b()];
            if (0..3).all(|k| qa[k].abs_diff(fb[k]) <= 2) {
                continue;
            }
            let (c, r) = (i as u32 % w, i as u32 / w);
            let px = s64.pixel(c, r, w, h);
            let want = px.rgb.map(|x| x.clamp(0.0, 255.0).round() as u8);
            let err = |x: [u8; 3]| (0..3).map(|k| x[k].abs_diff(want[k])).max().unwrap();
            let (eq, ef) = (err(qa), err(fb));
            if eq <= 2 && ef > 2 {
                q_right += 1;
            } else if ef <= 2 && eq > 2 {
                f_right += 1;
            } else {
                neither += 1;
            }
            let hq = rf.hit(&rf.camera_ray(c, r, None)).map(|(k, t)| (k, t.to_num::<f64>()));
            let hf = rg.hit(&rg.camera_ray(c, r, None)).map(|(k, t)| (k, t as f64));
            println!(
                "  ({c},{r}) Q {qa:?} f32 {fb:?} f64 {want:?} -> {}",
                if eq <= 2 && ef > 2 {
                    "Q right"
                } else if ef <= 2 && eq > 2 {
                    "f32 right"
                } else {
                    "neither/both"
                }
            );
            println!(
                "    hit Q {hq:?}\n    hit f32 {hf:?}\n    hit f64 {:?}",
                px.hit.map(|(k, h)| (k, h.t, h.p, h.part))
            );
            let mut involved: Vec<usize> = [hq.map(|x| x.0), hf.map(|x| x.0), px.hit.map(|x| x.0)]
                .into_iter()
                .flatten()
                .collect();
            involved.dedup();
            for k in involved {
                println!("    margin of {k} ({:?}): {:?}", s64.objects[k].shape, px.margins[k]);
                let ob = &s64.objects[k];
                if ob.shape != lensray::Shape::Plane {
                    // The exact local ray rounded once, re-origined at its closest approach.
                    let o = s64.camera.lens_position;
                    let d = s64.chief_dir(c, r, w, h);
                    let lo = ob.to_object.apply(o, true);
                    let ld = ob.to_object.apply(d, false);
                    let n = (ld[0] * ld[0] + ld[1] * ld[1] + ld[2] * ld[2]).sqrt();
                    let du = ld.map(|x| x / n);
                    let tc = -(lo[0] * du[0] + lo[1] * du[1] + lo[2] * du[2]);
                    for back in [0.0, 2.0] {
                        let st = tc - back;
                        let p0 = [0, 1, 2].map(|i| lo[i] + du[i] * st);
                        let q = |v: [f64; 3]| lensray::Vec3::<I16F16>::from_f64(v);
                        let hq = ob
                            .shape
                            .intersect::<I16F16>(q(p0), q(du), I16F16::from_bits(-(1 << 30)), I16F16::MAX);
                        let hf = ob.shape.intersect::<f32>(
                            lensray::Vec3::<f32>::from_f64(p0),
                            lensray::Vec3::<f32>::from_f64(du),
                            -16384.0,
                            f32::MAX,
                        );
                        println!(
                            "      rounded exact local ray from {back} before closest approach: Q {:?} f32 {:?}",
                            hq.map(|h| (h.t.to_num::<f64>() + st, h.p.to_f64())),
                            hf.map(|h| (h.t as f64 + st, h.p.to_f64()))
                        );
                    }
                }
            }
            for (l, u) in px.lights.iter().enumerate() {
                if !u.blockers.is_empty() {
                    println!(
                        "    light {l}: blockers {:?}",
                        u.blockers
                            .iter()
                            .map(|(j, m, b)| (j, s64.objects[*j].shape, m.hit, m.face, b))
                            .collect::<Vec<_>>()
                    );
                }
            }
        }
        println!("  Q16.16 right {q_right}, f32 right {f_right}, neither/both {neither}");
    }
}
