//! Where an adaptive render's error is: squared error against the converged
//! reference by the rays each pixel cast, and its mean signed error beside
//! that of `point` independent samples
//! (diagnosis; `adaptive_diag SCENE WIDTH`).
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use lensray::unstable::sampler::Sampler;
use lensray::{Renderer, Scene, I16F16};
use lensray_host::convergence::reference;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&a[1]).unwrap();
    let w: u32 = a[2].parse().unwrap();
    let h = w * 3 / 4;
    let truth = reference(&text, w, h, 1024, Sampler::Stratified).unwrap();
    let mut scene = Scene::<I16F16>::parse(&text).unwrap();
    scene.camera.sampler = Sampler::Stratified;
    scene.camera.adaptive = true;
    let point = scene.camera.samples;
    let r = Renderer::new(&scene, w, h);
    let mut ind_scene = Scene::<I16F16>::parse(&text).unwrap();
    ind_scene.camera.sampler = Sampler::Independent;
    ind_scene.camera.adaptive = false;
    let ri = Renderer::new(&ind_scene, w, h);
    let mut by: std::collections::BTreeMap<u32, (u32, f64, f64, f64, f64)> = Default::default();
    for y in 0..h {
        for x in 0..w {
            let n = r.pixel_rays(x, y).1;
            let (c, ci) = (r.pixel(x, y), ri.pixel(x, y));
            let t = truth.pixels[(y * w + x) as usize];
            let t = [t.r(), t.g(), t.b()];
            let e = |c: Rgb888| {
                let v = [c.r(), c.g(), c.b()].map(|q| q as f64);
                (v[0] - t[0] as f64).powi(2) + (v[1] - t[1] as f64).powi(2) + (v[2] - t[2] as f64).powi(2)
            };
            let signed =
                |c: Rgb888| (c.r() as f64 - t[0] as f64) + (c.g() as f64 - t[1] as f64) + (c.b() as f64 - t[2] as f64);
            let s = by.entry(n).or_default();
            s.0 += 1;
            s.1 += e(c);
            s.2 += e(ci);
            s.3 += signed(c);
            s.4 += signed(ci);
        }
    }
    println!(
        "gaps {} (period {}, loose {}), extends {}, budget {:.2} rays",
        r.gaps(),
        r.gap_period(),
        r.gap_loose(),
        r.extends(),
        r.gap_budget() as f64 / 256.0
    );
    println!("point {point}: rays -> pixels, default sq err, independent sq err, mean signed error a channel (default, independent)");
    for (n, (k, d, i, b, bi)) in by {
        println!(
            "{n:4}: {k:6} {d:12.0} {i:12.0} {:+8.2} {:+8.2}",
            b / (3.0 * k as f64),
            bi / (3.0 * k as f64)
        );
    }
}
