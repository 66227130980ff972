//! Where a frame of very high PSNR loses its levels (diagnosis):
//! `round_probe SEED WIDTH [POINT]` histograms of |error| per channel against
//! the converged reference for the default render, `point` independent and
//! `point` stratified samples, and the worst pixels of the default render;
//! the default's channels off at anchors and at gaps (`SHOW=1`: the first
//! gaps off, with their anchors' and their own unrounded values);
//! the images as round-SEED-{truth,default,independent,stratified}.png in the temp dir.
use embedded_graphics_core::pixelcolor::RgbColor;
use lensray::unstable::number::Scalar;
use lensray::unstable::sampler::Sampler;
use lensray::{Renderer, Scene, I16F16};
use lensray_host::convergence::reference;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let (seed, mut text, w, h) = lensray_host::convergence::seed_frame(&a);
    if let Some(p) = a.get(3).and_then(|p| p.parse().ok()) {
        text = lensray_host::convergence::with_point(&text, p);
    }
    let truth = reference(&text, w, h, 1024, Sampler::Stratified).unwrap();
    let save = |name: &str, img: &lensray_host::Image| {
        let bytes = lensray_host::encode(img, lensray_host::Format::Png).unwrap();
        std::fs::write(std::env::temp_dir().join(format!("round-{seed}-{name}.png")), bytes).unwrap();
    };
    save("truth", &truth);
    let scene = |sampler, adaptive| {
        let mut s = Scene::<I16F16>::parse(&text).unwrap();
        s.camera.sampler = sampler;
        s.camera.adaptive = adaptive;
        s
    };
    let (d, i, st) = (
        scene(Sampler::Stratified, true),
        scene(Sampler::Independent, false),
        scene(Sampler::Stratified, false),
    );
    for (name, sc) in [("default", &d), ("independent", &i), ("stratified", &st)] {
        let r = Renderer::new(sc, w, h);
        let mut hist = [0u64; 6];
        // Channels a level or more off, at anchors and at gaps (period from the renderer).
        let period = r.gap_period();
        let (mut at_anchor, mut at_gap) = (0u64, 0u64);
        let mut worst = Vec::new();
        let mut row = vec![Default::default(); w as usize];
        for y in 0..h {
            r.render_row(y, &mut row);
            for x in 0..w {
                let c: embedded_graphics_core::pixelcolor::Rgb888 = row[x as usize];
                let t = truth.pixels[(y * w + x) as usize];
                let e = [c.r().abs_diff(t.r()), c.g().abs_diff(t.g()), c.b().abs_diff(t.b())];
                for &v in &e {
                    hist[(v as usize).min(5)] += 1;
                    if v > 0 && period >= 2 {
                        if (x + period - lensray::unstable::render::gap_phase(y, period)).is_multiple_of(period) {
                            at_anchor += 1;
                        } else {
                            at_gap += 1;
                            if at_gap <= 12 && std::env::var_os("SHOW").is_some() && x > 0 && x + 1 < w {
                                let l = |x: u32| {
                                    r.pixel_colour(x, y)
                                        .to_array()
                                        .map(|v| (v.to_f64() * 255.0 * 100.0).round() / 100.0)
                                };
                                println!(
                                    "  gap ({x}, {y}): out {c:?} truth {t:?}; left {:?} own {:?} right {:?}",
                                    l(x - 1),
                                    l(x),
                                    l(x + 1)
                                );
                            }
                        }
                    }
                }
                let m = *e.iter().max().unwrap();
                if m >= 2 {
                    worst.push((m, x, y, r.pixel_rays_spread(x, y).1));
                }
            }
        }
        let mut img = truth.clone();
        for y in 0..h {
            r.render_row(y, &mut img.pixels[(y * w) as usize..((y + 1) * w) as usize]);
        }
        save(name, &img);
        worst.sort_by(|a, b| b.cmp(a));
        println!(
            "{name:12} |err| 0..5+: {hist:?} (off at anchors {at_anchor}, at gaps {at_gap}, period {period}); worst {:?}",
            &worst[..worst.len().min(12)]
        );
    }
}
