//! The small-`point` rules a frame's set-up chose (diagnosis): `gap_rules
//! SCENE WIDTH [POINT]` prints the gap period, the loose rung, the budget
//! of a pixel that casts, extension, and the mean rays a pixel.
use lensray::{Renderer, Scene, I16F16};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let mut text = std::fs::read_to_string(&a[1]).unwrap();
    if let Some(p) = a.get(3) {
        text = lensray_host::convergence::with_point(&text, p.parse().unwrap());
    }
    let w: u32 = a[2].parse().unwrap();
    let h = w * 3 / 4;
    let scene = Scene::<I16F16>::parse(&text).unwrap();
    let r = Renderer::new(&scene, w, h);
    let mut out = vec![Default::default(); w as usize];
    let rays: u64 = (0..h).map(|y| r.render_row(y, &mut out) as u64).sum();
    println!(
        "point {}: gap period {}, loose {}, budget {}/256, extends {}, {:.3} rays a pixel",
        r.samples(),
        r.gap_period(),
        r.gap_loose(),
        r.gap_budget(),
        r.extends(),
        rays as f64 / (w * h) as f64
    );
}
