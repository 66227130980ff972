//! Why stratified lens rays stay noisy on a checkered frame (diagnosis):
//! `checker_probe SEED WIDTH [N]` casts each pixel's first N (16) stratified
//! lens rays as the pilot does and tells per pixel the variance of the rays'
//! colours (levels², summed over RGB) with and without the footprint filter,
//! the share that hit a checker, that was filtered, the footprint in cells,
//! and the squared error of their mean against the converged reference.
use embedded_graphics_core::pixelcolor::RgbColor;
use lensray::unstable::camera::{Camera, CameraSample};
use lensray::unstable::cull::LensCones;
use lensray::unstable::defocus::Defocus;
use lensray::unstable::number::Scalar;
use lensray::unstable::sampler::{PixelSamples, Sampler};
use lensray::{Scene, I16F16};
use lensray_host::convergence::reference;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let (seed, text, w, h) = lensray_host::convergence::seed_frame(&a);
    let n: u32 = a.get(3).map_or(16, |s| s.parse().unwrap());
    let strata: u32 = a.get(4).map_or(n, |s| s.parse().unwrap());
    let truth = reference(&text, w, h, 1024, Sampler::Stratified).unwrap();
    let text2 = match std::env::var("STRIP") {
        Ok(v) => text
            .lines()
            .map(|l| {
                if l.trim_start().starts_with(&v) {
                    String::new()
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n"),
        Err(_) => text.clone(),
    };
    let scene = Scene::<I16F16>::parse(&text2).unwrap();
    println!(
        "materials: {:?}",
        scene
            .objects()
            .iter()
            .map(|o| (o.material.ks.to_f64(), o.material.shine.to_f64()))
            .collect::<Vec<_>>()
    );
    let cam = Camera::new(&scene.camera, w, h);
    let cones = LensCones::new(&scene, scene.camera.lens_position, scene.camera.radius);
    let defocus = Defocus::new(&scene);
    let stratum = defocus.stratum(strata);
    println!(
        "lens radius {} footprint radius {} stratum({strata}) {}",
        scene.camera.radius,
        defocus.radius().to_f64(),
        stratum.radius.to_f64()
    );
    for (i, o) in scene.objects().iter().enumerate() {
        println!("object {i} {:?} texture {}", o.shape, o.texture.to_f64());
    }
    let lv = |c: lensray::unstable::vec3::Vec3<I16F16>| c.to_f64().map(|x| x * 255.0);
    let mut tot = [0f64; 10];
    let mut objhits = vec![0u64; scene.objects().len() + 1];
    let mut hist_cells = [0u64; 8];
    let mut unfilt_reason = [0u64; 3];
    let mut rows = Vec::new();
    let mut rh = [[0u64; 9]; 2];
    let mut capside = [[0f64; 3]; 2];
    // Per object: rays, and sums of the filtered and unfiltered colours and their squares.
    type Sums = (f64, [f64; 3], [f64; 3], [f64; 3], [f64; 3]);
    fn add(g: &mut Sums, c: [f64; 3], cu: [f64; 3]) {
        g.0 += 1.0;
        for k in 0..3 {
            g.1[k] += c[k];
            g.2[k] += c[k] * c[k];
            g.3[k] += cu[k];
            g.4[k] += cu[k] * cu[k];
        }
    }
    let mut grp = std::collections::BTreeMap::<usize, Sums>::new();
    let mut within = [0f64; 2];
    let mut mixed = 0u64;
    let bytes = lensray_host::encode(&truth, lensray_host::Format::Png).unwrap();
    std::fs::write(format!("/tmp/xc/{seed}-truth.png"), bytes).unwrap();
    for y in 0..h {
        for x in 0..w {
            let film = cam.film_point(x, y);
            let mut lens = PixelSamples::new(Sampler::Stratified, x, y);
            let (mut s1, mut s2, mut u1, mut u2) = ([0f64; 3], [0f64; 3], [0f64; 3], [0f64; 3]);
            let (mut tex, mut filt, mut cells) = (0u32, 0u32, 0f64);
            let mut pg = std::collections::BTreeMap::<usize, Sums>::new();
            for _ in 0..n {
                let p_lens = lens.next(cam.aperture());
                let ray = cam.generate_ray(&CameraSample {
                    film: &film,
                    lens: Some(p_lens),
                });
                let pull = cam.lens_offset(p_lens, stratum.pull);
                let carried = lensray::unstable::defocus::Pull {
                    camera: &cam,
                    p_lens,
                    share: stratum.pull,
                };
                let (c, t) = scene.trace_lens_ray(&ray, &cones, Some((&defocus, stratum.radius, carried)));
                let (cu, _) = scene.trace_lens_ray(&ray, &cones, None);
                let (c, cu) = (lv(c), lv(cu));
                for k in 0..3 {
                    s1[k] += c[k];
                    s2[k] += c[k] * c[k];
                    u1[k] += cu[k];
                    u2[k] += cu[k] * cu[k];
                }
                let key = t.map_or(99, |(i, _)| i);
                add(pg.entry(key).or_default(), c, cu);
                add(grp.entry(key).or_default(), c, cu);
                objhits[t.map_or(scene.objects().len(), |(i, _)| i)] += 1;
                if let Some((i, _)) = t {
                    let o = &scene.objects()[i];
                    if o.texture != I16F16::ZERO {
                        tex += 1;
                        let (_, hit) = scene.closest_hit_camera_ray(&ray, &cones).unwrap();
                        let wdt = defocus.width(ray.dir, hit.t, stratum.radius);
                        let shift = defocus.shift(ray.dir, hit.t, pull);
                        let nrm = o.normal(&hit, ray.dir);
                        let ln = hit.local.n.to_f64();
                        let cap = (ln[0] == 0.0 && ln[2] == 0.0) as usize;
                        rh[cap][((c[0] / 32.0) as usize).min(8)] += 1;
                        capside[cap][0] += 1.0;
                        capside[cap][1] += c[0];
                        capside[cap][2] += c[0] * c[0];
                        let f = o.checker_filtered(&hit, ray.dir, nrm, wdt, shift);
                        let wc = wdt.to_f64() / o.texture.to_f64();
                        cells += wc;
                        hist_cells[((wc * 4.0) as usize).min(7)] += 1;
                        if f.is_some() {
                            filt += 1;
                        } else {
                            unfilt_reason[if wdt == I16F16::ZERO {
                                0
                            } else if wc < 0.5 {
                                1
                            } else {
                                2
                            }] += 1;
                        }
                    }
                }
            }
            let nf = n as f64;
            if pg.len() > 1 {
                mixed += 1;
            }
            for g in pg.values() {
                for k in 0..3 {
                    within[0] += g.2[k] - g.1[k] * g.1[k] / g.0;
                    within[1] += g.4[k] - g.3[k] * g.3[k] / g.0;
                }
            }
            let var = |s1: [f64; 3], s2: [f64; 3]| (0..3).map(|k| s2[k] / nf - (s1[k] / nf).powi(2)).sum::<f64>();
            let (vf, vu) = (var(s1, s2), var(u1, u2));
            let t = truth.pixels[(y * w + x) as usize];
            let tt = [t.r() as f64, t.g() as f64, t.b() as f64];
            let err = |s1: [f64; 3]| (0..3).map(|k| ((s1[k] / nf).round() - tt[k]).powi(2)).sum::<f64>();
            let (ef, eu) = (err(s1), err(u1));
            for (j, v) in [vf, vu, ef, eu, tex as f64, filt as f64, cells].into_iter().enumerate() {
                tot[j] += v;
            }
            rows.push((
                ef,
                x,
                y,
                vf,
                vu,
                eu,
                tex,
                filt,
                if tex > 0 { cells / tex as f64 } else { 0.0 },
                s1.map(|v| v / nf),
                tt,
            ));
        }
    }
    let p = (w * h) as f64;
    println!("per pixel means over {n} rays: var filtered {:.1}, unfiltered {:.1}; sq err of mean filtered {:.1}, unfiltered {:.1}; textured rays {:.2}, filtered {:.2}, cells/ray {:.3}",
        tot[0] / p, tot[1] / p, tot[2] / p, tot[3] / p, tot[4] / p, tot[5] / p, tot[6] / tot[4].max(1.0));
    println!("hits by object (last = miss): {objhits:?}");
    println!(
        "footprint radius in cells, quarters 0..7+: {hist_cells:?}; unfiltered: w=0 {}, w<0.5 cell {}, w>=0.5 cell {}",
        unfilt_reason[0], unfilt_reason[1], unfilt_reason[2]
    );
    println!("pixels with rays on more than one object: {mixed} of {}; within-object variance per pixel (of the total above): filtered {:.1}, unfiltered {:.1}", w*h, within[0]/n as f64/p, within[1]/n as f64/p);
    for (i, gt) in &grp {
        let m = |s: [f64; 3]| s.map(|v| v / gt.0);
        let v = |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| b[k] / gt.0 - (a[k] / gt.0).powi(2)).sum::<f64>();
        println!("  object {i}: {} rays, mean colour {:.1?} (unfiltered {:.1?}), frame-wide variance filtered {:.1} unfiltered {:.1}", gt.0, m(gt.1), m(gt.3), v(gt.1,gt.2), v(gt.3,gt.4));
    }
    println!(
        "cone rays R level histogram by 32s [side, cap]: {rh:?}; side n/mean/var {:?} cap {:?}",
        [
            capside[0][0],
            capside[0][1] / capside[0][0],
            capside[0][2] / capside[0][0] - (capside[0][1] / capside[0][0]).powi(2)
        ],
        [
            capside[1][0],
            capside[1][1] / capside[1][0].max(1.0),
            capside[1][2] / capside[1][0].max(1.0) - (capside[1][1] / capside[1][0].max(1.0)).powi(2)
        ]
    );
    rows.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap());
    for r in rows.iter().take(12) {
        println!(
            "  ({},{}) err {:.0} var f {:.0} u {:.0} err u {:.0} tex {} filt {} cells {:.2} mean {:.1?} truth {:?}",
            r.1, r.2, r.0, r.3, r.4, r.5, r.6, r.7, r.8, r.9, r.10
        );
    }
}
