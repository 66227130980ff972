//! Where a frame's error is a bias, not noise (diagnosis): `bias_probe SEED
//! WIDTH` renders the generated lens scene SEED in Q16.16 and f32 with the
//! default render, stratified and independent samples at `point`, 16 and
//! 256 (and the default without the terminator filter), and prints each
//! one's PSNR against the converged reference and its mean signed error per
//! channel; `GRID=1` adds the red channel's mean error on an 8x6 grid,
//! `STRIP=keyword` drops the scene's lines starting with it (e.g. `texture`).
use embedded_graphics_core::pixelcolor::RgbColor;
use lensray::unstable::sampler::Sampler;
use lensray::{Scene, I16F16};
use lensray_host::convergence::reference;
use lensray_host::{render_image_counted, Diff, Image};

fn stats(name: &str, img: &Image, truth: &Image) {
    let d = Diff::of(img, truth).unwrap();
    let mut bias = [0f64; 3];
    for (a, b) in img.pixels.iter().zip(&truth.pixels) {
        bias[0] += a.r() as f64 - b.r() as f64;
        bias[1] += a.g() as f64 - b.g() as f64;
        bias[2] += a.b() as f64 - b.b() as f64;
    }
    let n = img.pixels.len() as f64;
    let (w, h) = (img.width as usize, img.height as usize);
    let mut grid = vec![0f64; 48];
    for y in 0..h {
        for x in 0..w {
            let (a, b) = (img.pixels[y * w + x], truth.pixels[y * w + x]);
            grid[(y * 6 / h) * 8 + x * 8 / w] += a.r() as f64 - b.r() as f64;
        }
    }
    if std::env::var_os("GRID").is_some() {
        for r in 0..6 {
            println!(
                "   {:?}",
                (0..8)
                    .map(|c| (grid[r * 8 + c] / (n / 48.0) * 10.0).round() / 10.0)
                    .collect::<Vec<_>>()
            );
        }
    }
    println!(
        "{name}: {:.2} dB, mean signed error {:.2} {:.2} {:.2}",
        d.psnr,
        bias[0] / n,
        bias[1] / n,
        bias[2] / n
    );
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let (_, mut text, w, h) = lensray_host::convergence::seed_frame(&a);
    if let Ok(k) = std::env::var("STRIP") {
        text = text
            .lines()
            .filter(|l| !l.trim_start().starts_with(&k))
            .collect::<Vec<_>>()
            .join("\n");
    }
    let truth = reference(&text, w, h, 1024, Sampler::Stratified).unwrap();
    let point = Scene::<f32>::parse(&text).unwrap().camera.samples;
    for (name, sampler, adaptive, samples, term) in [
        ("default", Sampler::Stratified, true, point, true),
        ("default, no terminator filter", Sampler::Stratified, true, point, false),
        ("stratified point", Sampler::Stratified, false, point, true),
        ("stratified 4", Sampler::Stratified, false, 4, true),
        ("stratified 8", Sampler::Stratified, false, 8, true),
        ("stratified 16", Sampler::Stratified, false, 16, true),
        ("stratified 256", Sampler::Stratified, false, 256, true),
        ("independent point", Sampler::Independent, false, point, true),
        ("independent 256", Sampler::Independent, false, 256, true),
    ] {
        let mut s = Scene::<I16F16>::parse(&text).unwrap();
        s.camera.sampler = sampler;
        s.camera.adaptive = adaptive;
        s.set_terminator_filter(term);
        let (img, _) = render_image_counted(&s, w, h, Some(samples), &|| {});
        stats(name, &img, &truth);
        let mut f = Scene::<f32>::parse(&text).unwrap();
        f.camera.sampler = sampler;
        f.camera.adaptive = adaptive;
        f.set_terminator_filter(term);
        let (img, _) = render_image_counted(&f, w, h, Some(samples), &|| {});
        stats(&format!("  f32 {name}"), &img, &truth);
    }
}
