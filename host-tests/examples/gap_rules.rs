//! The small-`point` rules a frame's set-up chose, and where its rays go
//! (diagnosis): `gap_rules SCENE WIDTH [POINT]` renders as the campaign does
//! (stratified, adaptive) and prints the survey's rays, the gap period, the
//! loose rung and whether it fills on checkers, the budget of a pixel that
//! casts, extension, the mean rays a pixel that casts takes, the share of
//! pixels that cast, and the mean rays a pixel.
use lensray::{Renderer, Scene, I16F16};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let mut text = std::fs::read_to_string(&a[1]).unwrap();
    if let Some(p) = a.get(3) {
        text = lensray_host::convergence::with_point(&text, p.parse().unwrap());
    }
    let w: u32 = a[2].parse().unwrap();
    let h = w * 3 / 4;
    // As the campaign renders it: stratified and adaptive whatever the scene says.
    let mut scene = Scene::<I16F16>::parse(&text).unwrap();
    scene.camera.sampler = lensray::unstable::sampler::Sampler::Stratified;
    scene.camera.adaptive = true;
    let r = Renderer::new(&scene, w, h);
    let mut out = vec![Default::default(); w as usize];
    let rays: u64 = (0..h).map(|y| r.render_row(y, &mut out) as u64).sum();
    let every: u64 = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| r.pixel_rays(x, y).1 as u64)
        .sum();
    let n = (w * h) as f64;
    let mean = every as f64 / n;
    println!(
        "point {} (survey rays {:.3} a pixel): period {}, loose {} (checkers {}), budget {:.3}, extends {}, mean rays a pixel if all cast {:.3}, casting share {:.3}, rays a pixel {:.3} ({:.1} %)",
        r.samples(),
        r.adaptive_cap().1 as f64 / (w * h) as f64,
        r.gap_period(),
        r.gap_loose(),
        r.gap_checkers(),
        r.gap_budget() as f64 / 256.0,
        r.extends(),
        mean,
        rays as f64 / n / mean,
        rays as f64 / n,
        100.0 * rays as f64 / n / r.samples() as f64
    );
}
