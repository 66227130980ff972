//! Where a generated lens scene's adaptive error is and what a frame-wide
//! allocation could buy (diagnosis): `adaptive_alloc SEED WIDTH REFERENCE`.
//! Per pixel class (stopped at the pilot or went on; in a lamp's
//! footprint or not; `adaptive_alloc SEED WIDTH REFERENCE POINT` at that `point`) the squared error of the default render and of `point`
//! independent samples; then the frame's PSNR if pixels stopped at the pilot
//! kept it and the others took C stratified samples, for C up to `point`.
use embedded_graphics_core::pixelcolor::RgbColor;
use lensray::unstable::render::adaptive_pilot;
use lensray::unstable::sampler::Sampler;
use lensray::{Renderer, Scene, I16F16};
use lensray_host::convergence::reference;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let (seed, text, w, h) = lensray_host::convergence::seed_frame(&a);
    let ref_n: u32 = a[3].parse().unwrap();
    let truth = reference(&text, w, h, ref_n, Sampler::Stratified).unwrap();
    let mut scene = Scene::<I16F16>::parse(&text).unwrap();
    scene.camera.sampler = Sampler::Stratified;
    scene.camera.adaptive = true;
    // An optional fourth argument: the scene at that `point`.
    if let Some(p) = a.get(4).and_then(|p| p.parse().ok()) {
        scene.camera.samples = p;
    }
    let point = scene.camera.samples;
    let pilot = adaptive_pilot(point);
    let r = Renderer::new(&scene, w, h);
    // The frame's cap from the survey (unsettled pixels' mean share).
    let cap = r.adaptive_cap().0;
    let rs = r.clone().with_adaptive(false);
    let mut ind = Scene::<I16F16>::parse(&text).unwrap();
    ind.camera.sampler = Sampler::Independent;
    ind.camera.adaptive = false;
    ind.camera.samples = point;
    let ri = Renderer::new(&ind, w, h);
    let err = |c: embedded_graphics_core::pixelcolor::Rgb888, x: u32, y: u32| {
        let t = truth.pixels[(y * w + x) as usize];
        let d = |p: u8, q: u8| (p as f64 - q as f64).powi(2);
        d(c.r(), t.r()) + d(c.g(), t.g()) + d(c.b(), t.b())
    };
    let cs: Vec<u32> = (pilot..=point)
        .step_by(((point - pilot) / 8).max(1) as usize)
        .chain([point])
        .collect();
    // class -> (pixels, default err, independent err)
    let mut class: std::collections::BTreeMap<(bool, &str), (u32, f64, f64)> = Default::default();
    let mut alloc = vec![(0.0f64, 0.0f64); cs.len()];
    let psnr = |e: f64| 10.0 * (255.0f64.powi(2) * 3.0 * (w * h) as f64 / e).log10();
    let (mut tot_d, mut tot_i) = (0.0, 0.0);
    for y in 0..h {
        for x in 0..w {
            let (_, n, spread) = r.pixel_rays_spread(x, y);
            let c = r.pixel(x, y);
            let (ed, ei) = (err(c, x, y), err(ri.pixel(x, y), x, y));
            tot_d += ed;
            tot_i += ei;
            let risk = r.bright_footprints().at_risk(x, y);
            let k = match (n == pilot, spread == 0) {
                (false, _) => "on",
                (true, true) => "settled at pilot",
                (true, false) => "share at pilot",
            };
            let s = class.entry((risk, k)).or_default();
            s.0 += 1;
            s.1 += ed;
            s.2 += ei;
            for (j, &cc) in cs.iter().enumerate() {
                let (e, rays) = if n == pilot {
                    (ed, n)
                } else {
                    (err(rs.clone().with_samples(cc).pixel(x, y), x, y), cc)
                };
                alloc[j].0 += e;
                alloc[j].1 += rays as f64;
            }
        }
    }
    println!(
        "seed {seed} point {point} pilot {pilot} cap {cap}: default {:.2} dB, independent {:.2} dB",
        psnr(tot_d),
        psnr(tot_i)
    );
    for ((risk, k), (p, d, i)) in class {
        println!("  lamp {risk:5} {k:6}: {p:6} px ({:5.1} %), default err {:5.1} % of total, independent err {:5.1} % (mean sq {:.1} vs {:.1})",
            100.0 * p as f64 / (w * h) as f64, 100.0 * d / tot_d, 100.0 * i / tot_i, d / p as f64, i / p as f64);
    }
    for (j, &cc) in cs.iter().enumerate() {
        println!(
            "  unsettled at C={cc:3}: {:.2} dB at {:.1} % of point",
            psnr(alloc[j].0),
            100.0 * alloc[j].1 / (w * h) as f64 / point as f64
        );
    }
}
