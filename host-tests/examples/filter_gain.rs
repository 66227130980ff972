//! What the scanline filter buys a generated lens scene: the default render
//! (Q16.16, stratified, adaptive) against its converged reference, with and
//! without the filter, beside `point` independent samples (diagnosis).
//! `LENSRAY_FILTER_GAIN_DUMP=1` also prints where the error is: the squared
//! error and the pixels by their largest channel error.
//!
//! ```sh
//! cargo run --release -p lensray-host --example filter_gain -- WIDTH SEED...
//! ```
use embedded_graphics_core::pixelcolor::RgbColor;
use lensray::unstable::sampler::Sampler;
use lensray::{Renderer, Scene, I16F16};
use lensray_host::convergence::{reference, render_text, Setting};
use lensray_host::{render_image, Diff, Image};
use rayon::prelude::*;

/// The squared error against `truth` and the pixels by their largest channel error (0 to 8 and up).
fn spread(img: &Image, truth: &Image) -> (u64, [u32; 9]) {
    let mut hist = [0u32; 9];
    let mut se = 0u64;
    for (p, q) in img.pixels.iter().zip(&truth.pixels) {
        let d = [p.r().abs_diff(q.r()), p.g().abs_diff(q.g()), p.b().abs_diff(q.b())];
        se += d.iter().map(|&x| (x as u64).pow(2)).sum::<u64>();
        hist[(*d.iter().max().unwrap_or(&0) as usize).min(8)] += 1;
    }
    (se, hist)
}

fn main() {
    let args: Vec<u64> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let Some((&w, seeds)) = args.split_first() else {
        eprintln!("usage: filter_gain WIDTH SEED...");
        std::process::exit(2);
    };
    let (w, h) = (w as u32, (w * 3 / 4) as u32);
    for &seed in seeds {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        let mut scene = Scene::<I16F16>::parse(&text).unwrap();
        if scene.camera.radius == 0.0 {
            println!("seed {seed}: pinhole");
            continue;
        }
        let point = scene.camera.samples;
        scene.camera.sampler = Sampler::Stratified;
        scene.camera.adaptive = true;
        let truth = reference(&text, w, h, 1024, Sampler::Stratified).unwrap();
        let ind = render_text(&text, w, h, Setting::independent(point), false).unwrap().0;
        let on = render_image(&scene, w, h, None, &|| {});
        // Every pixel as `Renderer::pixel` has it: before the filter.
        let r = Renderer::new(&scene, w, h);
        let pixels = (0..w * h).into_par_iter().map(|i| r.pixel(i % w, i / w)).collect();
        let off = Image {
            width: w,
            height: h,
            pixels,
        };
        let psnr = |img: &Image| Diff::of(img, &truth).unwrap().psnr;
        let (ind_db, on_db, off_db) = (psnr(&ind), psnr(&on), psnr(&off));
        println!(
            "seed {seed} point {point}: independent {ind_db:.2} dB, default {on_db:.2} ({:+.2}), unfiltered {off_db:.2} ({:+.2})",
            on_db - ind_db,
            off_db - ind_db
        );
        if std::env::var_os("LENSRAY_FILTER_GAIN_DUMP").is_some() {
            for (name, img) in [("independent", &ind), ("default", &on), ("unfiltered", &off)] {
                let (se, hist) = spread(img, &truth);
                println!("  {name}: squared error {se}, pixels by largest channel error 0..8+: {hist:?}");
            }
        }
    }
}
