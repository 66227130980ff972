//! Properties of the adaptive lens sampler (docs/sampling.md), on the scene
//! generator's lens scenes and the paper's Program 1: a pixel depends on
//! itself alone, and the adaptive mean converges to the converged reference
//! as `point` grows, with no bias left by the checker's footprint filter.
//! (The error estimate's calibration is a unit test of the library's,
//! `the_error_estimate_is_calibrated_on_generated_lens_integrands`; the
//! floors against converged references are the sampling bench's.)

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use lensray::{Renderer, Sampler, Scene, I16F16};
use lensray_host::convergence::{reference, render_text, Setting};
use lensray_host::{render_image, Diff, Image};

fn scenes() -> Vec<(String, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut v = vec![(
        "paper-program1".to_string(),
        std::fs::read_to_string(root.join("scenes/paper-program1.scene")).unwrap(),
    )];
    for seed in [31u64, 47, 58, 73] {
        v.push((
            format!("generated lens {seed}"),
            lensray_testkit::scenegen::generate_lens(seed),
        ));
    }
    v
}

/// Every pixel asked alone, in a scrambled order, from a renderer that has
/// drawn nothing else, is the pixel of the whole frame: no pixel reads a
/// neighbour, a row or anything the renderer kept from another pixel.
#[test]
fn a_pixel_depends_on_itself_alone() {
    let (w, h) = (40, 30);
    for (name, text) in scenes() {
        let mut scene = Scene::<I16F16>::parse(&text).unwrap();
        // The generator writes `adaptive off` and `sampler independent` at times.
        (scene.camera.adaptive, scene.camera.sampler) = (true, Sampler::Stratified);
        let frame = render_image(&scene, w, h, None, &|| {});
        let renderer = Renderer::new(&scene, w, h);
        assert!(renderer.stop_rule().is_some(), "{name}: adaptive sampling is on");
        let mut order: Vec<u32> = (0..w * h).collect();
        // A fixed scramble: stride coprime to the pixel count.
        order.sort_by_key(|&i| (i * 577) % (w * h));
        for i in order {
            let (x, y) = (i % w, i / w);
            assert_eq!(
                renderer.pixel(x, y),
                frame.pixels[i as usize],
                "{name}: pixel ({x}, {y})"
            );
            if i % 7 == 0 {
                let alone = Renderer::new(&scene, w, h).pixel(x, y);
                assert_eq!(
                    alone, frame.pixels[i as usize],
                    "{name}: pixel ({x}, {y}) from a fresh renderer"
                );
            }
        }
    }
}

/// The mean signed error of `img` against `truth`, levels a channel.
fn bias(img: &Image, truth: &Image) -> f64 {
    let d = |a: Rgb888, b: Rgb888| {
        (a.r() as f64 - b.r() as f64) + (a.g() as f64 - b.g() as f64) + (a.b() as f64 - b.b() as f64)
    };
    let sum: f64 = img.pixels.iter().zip(&truth.pixels).map(|(&a, &b)| d(a, b)).sum();
    sum / (3.0 * img.pixels.len() as f64)
}

/// The default render (stratified, adaptive) at `point` 16, 64 and 256
/// gets closer to the converged reference every time, by at least what
/// four times the rays give stratified samples less a margin, and its mean
/// signed error at 256 is within a tenth of a level: the footprint filter's
/// blur shrinks with the rays and leaves no bias.
#[test]
fn the_adaptive_mean_converges_to_the_reference_as_point_grows() {
    let (w, h) = (48, 36);
    for (name, text) in scenes() {
        let truth = reference(&text, w, h, 4096, Sampler::Stratified).unwrap();
        let mut last = f64::NEG_INFINITY;
        for point in [16u32, 64, 256] {
            let (img, rays) = render_text(&text, w, h, Setting::default_render(point), true).unwrap();
            let psnr = Diff::of(&img, &truth).unwrap().psnr;
            let b = bias(&img, &truth);
            eprintln!("{name} point {point}: {psnr:.2} dB at {rays:.1} rays, bias {b:+.3} levels");
            assert!(
                rays <= 0.4 * point as f64 + 1e-9,
                "{name} point {point}: {rays:.2} rays"
            );
            assert!(
                psnr >= last + 3.0 || psnr.is_infinite(),
                "{name} point {point}: {psnr:.2} dB after {last:.2} dB at a quarter the rays"
            );
            if point == 256 {
                assert!(b.abs() <= 0.1, "{name}: mean signed error {b:+.3} levels at point 256");
            }
            last = psnr;
        }
    }
}
