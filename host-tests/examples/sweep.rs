//! The long random-scene campaign: Q16.16 against f32 on generated scenes.
//!
//! `cargo run --release -p lensray-host --example sweep -- [COUNT] [FIRST_SEED] [WIDTH] [HEIGHT]`
//! (defaults 1000 scenes from seed 0 at 160x120), pinhole and lens scenes of
//! each seed. Prints the distribution, and the seeds under the floors
//! (40 dB, 99.5 % within 2 levels, no row or column above 2 levels), and for
//! a pinhole one which type float64 sides with where they differ.
use lensray_host::sweep::{run, scene_text, truth_sides, Summary};
use lensray_testkit::scenegen::Camera;

fn main() {
    let arg = |i: usize, d: u64| std::env::args().nth(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (count, first, w, h) = (arg(1, 1000), arg(2, 0), arg(3, 160) as u32, arg(4, 120) as u32);
    let mut all = Vec::new();
    for (name, camera) in [("pinhole", Camera::Pinhole), ("lens, 16 samples", Camera::Lens)] {
        let results = run(first..first + count, camera, w, h);
        println!("{name} at {w}x{h}: {}", Summary::of(&results));
        all.extend(results);
    }
    println!("all: {}", Summary::of(&all));
    let failed: Vec<String> = all
        .iter()
        .filter(|r| !r.meets(40.0, 0.995, 2.0))
        .map(|r| {
            // Pinhole failures judged by float64: whose error it is.
            let truth = if r.lens {
                String::new()
            } else {
                let (q, f, n) = truth_sides(&scene_text(r.seed, Camera::Pinhole), w, h);
                format!(" (f64 sides with Q16.16 in {q} pixels, with f32 in {f}, neither {n})")
            };
            format!(
                "{} {:.1} dB {:.2} % line {:.1}{truth}",
                r.name(),
                r.psnr,
                r.within2 * 100.0,
                r.worst_line
            )
        })
        .collect();
    println!("{} under the floors", failed.len());
    for f in failed {
        println!("  {f}");
    }
}
