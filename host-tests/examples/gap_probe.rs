//! Gaps below `point` 10: for each seed and `point`, the budget a pixel that
//! casts, the share of pixels that cast, and the share of `point` the frame casts.
use lensray::{Renderer, Scene, I16F16};

fn main() {
    let a: Vec<u64> = std::env::args().skip(1).map(|x| x.parse().unwrap()).collect();
    let (first, count, p, w) = (a[0], a[1], a[2] as u32, a[3] as u32);
    let h = w * 3 / 4;
    for seed in first..first + count {
        let g = lensray_testkit::scenegen::generate_lens(seed);
        let text = lensray_host::convergence::with_point(&g, p);
        let mut scene = Scene::<I16F16>::parse(&text).unwrap();
        // The default render, as the campaign judges it.
        scene.camera.sampler = lensray::unstable::sampler::Sampler::Stratified;
        scene.camera.adaptive = true;
        let r = Renderer::new(&scene, w, h);
        let mut rays = 0u64;
        let mut row = vec![Default::default(); w as usize];
        for y in 0..h {
            rays += r.render_row(y, &mut row) as u64;
        }
        let mut cast = 0u64;
        for y in 0..h {
            for x in 0..w {
                cast += r.pixel_rays(x, y).1 as u64;
            }
        }
        let n = (w * h) as f64;
        println!(
            "seed {seed} point {p}: period {} loose {}, budget {:.3}, frame {:.3} rays a pixel ({:.1} %), cast pixels {:.1} %, survey {:.3} a pixel",
            r.gap_period(),
            r.gap_loose(),
            r.gap_budget() as f64 / 256.0,
            rays as f64 / n,
            100.0 * rays as f64 / n / p as f64,
            100.0 * rays as f64 / cast as f64,
            r.adaptive_cap().1 as f64 / n
        );
        let mut hist = [0u64; 17];
        for y in 0..h {
            for x in 0..w {
                hist[(r.pixel_rays(x, y).1 as usize).min(16)] += 1;
            }
        }
        println!("  extends {}; pixels by rays 0..16+: {hist:?}", r.extends());
    }
}
