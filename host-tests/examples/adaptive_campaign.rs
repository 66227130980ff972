//! The adaptive floors on many generated lens scenes: for each seed, the
//! default render (Q16.16, stratified, adaptive) against a converged f32
//! reference, beside `point` independent samples.
//!
//! ```sh
//! bash scripts/adaptive-campaign.sh [FIRST_SEED] [SEEDS] [WIDTH] [REFERENCE]
//! ```
//! Defaults: seeds 1..=40, 160x120, 1024 reference samples. A seed whose
//! `point` is below [`lensray::unstable::render::ADAPTIVE_MIN_POINT`] is listed but not
//! judged (below it even the smallest pilot is more than 40 % of `point`).

use lensray::unstable::sampler::Sampler;
use lensray::{Renderer, Scene, I16F16};
use lensray_host::convergence::{measure, reference, Setting};

fn arg(i: usize, default: u64) -> u64 {
    std::env::args().nth(i).and_then(|a| a.parse().ok()).unwrap_or(default)
}

fn main() {
    let (first, count, w, ref_n) = (arg(1, 1), arg(2, 40), arg(3, 160) as u32, arg(4, 1024) as u32);
    let h = w * 3 / 4;
    let (mut judged, mut met, mut share_sum) = (0, 0, 0.0);
    let mut worst_share: f64 = 0.0;
    let mut worst_margin = f64::INFINITY;
    // LENSRAY_CAMPAIGN_SCENES: scene files measured instead of generated ones.
    let files: Vec<String> = std::env::var("LENSRAY_CAMPAIGN_SCENES")
        .map(|v| v.split(',').map(str::to_string).collect())
        .unwrap_or_default();
    let seeds: Vec<u64> = if files.is_empty() {
        (first..first + count).collect()
    } else {
        (0..files.len() as u64).collect()
    };
    for seed in seeds {
        let text = match files.get(seed as usize) {
            Some(f) => std::fs::read_to_string(f).unwrap(),
            None => lensray_testkit::scenegen::generate_lens(seed),
        };
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let point = scene.camera.samples;
        let r = Renderer::new(&scene, w, h);
        let risky = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| r.bright_footprints().at_risk(x, y))
            .count() as f64
            / (w * h) as f64;
        let truth = reference(&text, w, h, ref_n, Sampler::Stratified).unwrap();
        let ind = measure(&text, &truth, Setting::independent(point)).unwrap();
        let def = measure(&text, &truth, Setting::default_render(point)).unwrap();
        // Stratified, every pixel at 40 % of point: what adaptive must beat.
        let flat = measure(
            &text,
            &truth,
            Setting {
                samples: (point * 2 / 5).max(1),
                sampler: Sampler::Stratified,
                adaptive: false,
            },
        )
        .unwrap();
        let share = def.rays / point as f64;
        let margin = if def.psnr.is_infinite() {
            f64::INFINITY
        } else {
            def.psnr - ind.psnr
        };
        let judge = point >= lensray::unstable::render::ADAPTIVE_MIN_POINT;
        let ok = margin >= 0.0 && share <= 0.4;
        if judge {
            judged += 1;
            met += ok as u32;
            share_sum += share;
            worst_share = worst_share.max(share);
            worst_margin = worst_margin.min(margin);
        }
        println!(
            "seed {seed:4} point {point:3}: independent {:6.2} dB, default {:6.2} dB ({margin:+.2}) at {:5.1} rays ({:5.1} %), lamps' footprints {:5.1} % of pixels, stratified at 40 % {:6.2} dB {}",
            ind.psnr,
            def.psnr,
            def.rays,
            100.0 * share,
            100.0 * risky,
            flat.psnr,
            if !judge { "(not judged)" } else if ok { "met" } else { "NOT MET" }
        );
    }
    println!(
        "{met} of {judged} judged seeds meet both floors; mean share {:.1} %, worst share {:.1} %, worst PSNR margin {:+.2} dB",
        100.0 * share_sum / judged.max(1) as f64,
        100.0 * worst_share,
        worst_margin
    );
}
