//! Which generated lens scenes the terminator filter changes (diagnosis):
//! `terminator_frames FIRST COUNT WIDTH` prints, for each lens seed, the
//! share of pixels whose default render differs with the filter off.
use lensray::{Renderer, Scene, I16F16};

fn main() {
    let a: Vec<u64> = std::env::args().skip(1).map(|s| s.parse().unwrap()).collect();
    let (first, count, w) = (a[0], a[1], a[2] as u32);
    let h = w * 3 / 4;
    for seed in first..first + count {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        let mut scene = Scene::<I16F16>::parse(&text).unwrap();
        if scene.camera.radius == 0.0 {
            continue;
        }
        let on = Renderer::new(&scene, w, h);
        let a: Vec<_> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| on.pixel(x, y))
            .collect();
        scene.set_terminator_filter(false);
        let off = Renderer::new(&scene, w, h);
        let changed = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .zip(&a)
            .filter(|&((x, y), c)| off.pixel(x, y) != *c)
            .count();
        if changed > 0 {
            println!("{seed} {:.2}", 100.0 * changed as f64 / (w * h) as f64);
        }
    }
}
