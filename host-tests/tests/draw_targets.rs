//! Why the library's entry points document "Panics: never": every kind of
//! target size renders, each pixel of the image delivered exactly once inside
//! the target, in Q16.16 and f32.
//!
//! The sizes that matter are the ones the camera's arithmetic sees: zero
//! sides (nothing to draw), every small size (odd and even centres), every
//! width up to 4096 on one row (pixel pitch from width/1 down to width/4096),
//! one-column images up to and past the camera's limit (a film far taller
//! than wide), sides past [`MAX_IMAGE_SIDE`], and targets placed anywhere in
//! the i32 plane, up to its edges.

use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use lensray::MAX_IMAGE_SIDE;
use lensray::{render, Renderer, Scalar, Scene, I16F16};
use lensray_testkit::fuzz::Canvas;

const PROGRAM1: &str = include_str!("../../scenes/paper-program1.scene");

/// Program 1 as a pinhole: cheap enough for thousands of renders.
fn pinhole<S: Scalar>() -> Scene<S> {
    Scene::parse(&format!("{PROGRAM1}\nradius 0\n")).expect("Program 1 parses")
}

/// Every camera number at its extreme: a film 32767 wide, a lens 32767 wide
/// focused just past the film, objects as far out as the parser allows.
fn extreme<S: Scalar>() -> Scene<S> {
    Scene::parse(
        "width 32767.99\naspect_ratio 0.00002\nimage_distance 32767.9\nfocal_length 0.00002\nradius 32767.9\npoint 2\n\
         lens_position 16383 -16383 16383\nlook 1 0.00002 0\nup 0 0 1\nambient_light 32767 32767 32767\n\
         light_position -16000 16000 0\nlight_intensity 32767 32767 32767\n\
         object sphere gold\nscale 8000 8000 8000\ntranslate 8000 0 0\n\
         object plane\ntexture 0.00002\nrotate x 33\n\
         object cone\nshine 32767\nKs 32767 32767 32767\nscale 0.001 0.001 0.001\n",
    )
    .expect("the extreme scene parses")
}

fn check<S: Scalar>(scene: &Scene<S>, w: u32, h: u32) {
    let mut canvas = Canvas::new(w, h);
    let Ok(()) = render(scene, &mut canvas);
    assert!(canvas.fault.is_none(), "{w}x{h} {}: {:?}", S::NAME, canvas.fault);
    // The image is the camera's size: the target, up to MAX_IMAGE_SIDE a side.
    let (iw, ih) = (w.min(MAX_IMAGE_SIDE), h.min(MAX_IMAGE_SIDE));
    for y in 0..h {
        for x in 0..w {
            let drawn = canvas.pixels[(y * w + x) as usize].is_some();
            assert_eq!(drawn, x < iw && y < ih, "{w}x{h} {}: pixel ({x}, {y})", S::NAME);
        }
    }
}

#[test]
fn every_small_size_from_0x0() {
    let (a, b, c, d) = (
        pinhole::<I16F16>(),
        pinhole::<f32>(),
        extreme::<I16F16>(),
        extreme::<f32>(),
    );
    for w in 0..=9 {
        for h in 0..=9 {
            check(&a, w, h);
            check(&b, w, h);
            check(&c, w, h);
            check(&d, w, h);
        }
    }
}

#[test]
fn every_width_up_to_4096_on_one_row() {
    let (a, b) = (pinhole::<I16F16>(), extreme::<I16F16>());
    for w in 0..=4096 {
        check(&a, w, 1);
    }
    // The extreme scene is slower per pixel (two lens samples): every width up
    // to 64, then the powers of two and their neighbours.
    for w in (0..=64).chain((6..=12).flat_map(|k| [(1 << k) - 1, 1 << k, (1 << k) + 1])) {
        check(&b, w, 1);
        check(&extreme::<f32>(), w, 1);
    }
}

#[test]
fn one_column_up_to_and_past_the_limit() {
    let (a, b) = (pinhole::<I16F16>(), pinhole::<f32>());
    let (c, d) = (extreme::<I16F16>(), extreme::<f32>());
    for k in 0..=13 {
        for h in [(1u32 << k) - 1, 1 << k, (1 << k) + 1] {
            check(&a, 1, h);
            check(&b, 1, h);
            check(&c, 1, h);
            check(&d, 1, h);
        }
    }
    check(&a, 1, 10_000);
    check(&c, 2, 10_000);
}

#[test]
fn rows_past_the_limit_draw_the_first_8192_columns() {
    let a = pinhole::<I16F16>();
    for w in [MAX_IMAGE_SIDE - 1, MAX_IMAGE_SIDE, MAX_IMAGE_SIDE + 1, 10_000] {
        check(&a, w, 1);
    }
    check(&extreme::<I16F16>(), 10_000, 1);
}

#[test]
fn targets_placed_anywhere_in_the_plane() {
    let scene = pinhole::<I16F16>();
    let (max, min) = (i32::MAX, i32::MIN);
    for (x, y) in [
        (0, 0),
        (-5, -5),
        (min, min),
        (max - 3, 0),
        (0, max - 2),
        (max - 3, max - 2),
        (max, max),
    ] {
        let mut canvas = Canvas::at(Point::new(x, y), 8, 6);
        let Ok(()) = render(&scene, &mut canvas);
        assert!(canvas.fault.is_none(), "target at ({x}, {y}): {:?}", canvas.fault);
        // The pixels with an i32 address are drawn, each once; the rest of the
        // image lies beyond the plane.
        let drawn = canvas.pixels.iter().filter(|p| p.is_some()).count() as i64;
        let cols = (max as i64 - x as i64 + 1).min(8);
        let rows = (max as i64 - y as i64 + 1).min(6);
        assert_eq!(drawn, cols * rows, "target at ({x}, {y})");
        assert!(canvas.complete(8, 6), "target at ({x}, {y})");
    }
}

#[test]
#[ignore = "slow: scripts/test-all.sh runs it"]
fn renderer_arguments_at_their_extremes() {
    let scene = extreme::<I16F16>();
    for (w, h) in [(0, 0), (0, u32::MAX), (u32::MAX, 0), (u32::MAX, u32::MAX), (1, 1)] {
        for samples in [0, 1, u32::MAX] {
            let r = Renderer::new(&scene, w, h).with_samples(samples);
            assert!((1..=65535).contains(&r.rays_per_pixel()));
            let (cols, rows) = r.size();
            assert!((1..=MAX_IMAGE_SIDE).contains(&cols) && (1..=MAX_IMAGE_SIDE).contains(&rows));
            // Pixels far outside the image are still answered.
            for (c, row) in [(0, 0), (u32::MAX, u32::MAX), (MAX_IMAGE_SIDE, 0)] {
                if samples != u32::MAX {
                    let _ = r.pixel(c, row);
                }
            }
            let mut row = [Rgb888::BLACK; 3];
            r.render_row(u32::MAX, &mut row);
            r.render_row(0, &mut []);
        }
    }
}

#[test]
fn progressive_passes_placed_anywhere_and_any_step() {
    use lensray::progressive::{render_pass, Pass, Schedule};
    let scene = pinhole::<I16F16>();
    let renderer = Renderer::new(&scene, 8, 6);
    let (max, min) = (i32::MAX, i32::MIN);
    for (x, y) in [(0, 0), (min, min), (max - 3, max - 2), (max, max)] {
        for pass in Schedule::new(4, 1, 2) {
            // A fresh canvas per pass: later passes repaint earlier blocks by design.
            let mut canvas = Canvas::at(Point::new(x, y), 8, 6);
            let Ok(_) = render_pass(&renderer, &mut canvas, &pass);
            assert!(
                canvas.fault.is_none(),
                "pass {pass:?} at ({x}, {y}): {:?}",
                canvas.fault
            );
        }
    }
    // A hand-made pass may hold any step.
    for step in [0, 3, 1 << 31, u32::MAX] {
        for skip_coarser in [false, true] {
            let pass = Pass {
                step,
                skip_coarser,
                samples: 2,
            };
            let mut canvas = Canvas::new(8, 6);
            let Ok(_) = render_pass(&renderer, &mut canvas, &pass);
            assert!(canvas.fault.is_none(), "{pass:?}: {:?}", canvas.fault);
            let _ = pass.computes(u32::MAX, 0);
        }
    }
}

/// Each pass says what its pixels cast: the full-sample passes' rays are
/// each pixel's own (its `pixel_rays`), and together the plain render's.
#[test]
fn progressive_passes_count_the_rays_their_pixels_cast() {
    use lensray::progressive::{render_pass, Schedule};
    for (point, w, h, adaptive) in [
        (40, 48, 36, "on"),
        (12, 40, 30, "on"),
        (4, 33, 21, "on"),
        (12, 40, 30, "off"),
    ] {
        let text = format!("{PROGRAM1}\npoint {point}\nadaptive {adaptive}\n");
        let scene: Scene<I16F16> = Scene::parse(&text).expect("Program 1 parses");
        let renderer = Renderer::new(&scene, w, h);
        let plain: u64 = (0..h)
            .map(|row| renderer.render_row(row, &mut vec![Rgb888::BLACK; w as usize]) as u64)
            .sum();
        let passes: Vec<_> = Schedule::new(8, 1, renderer.rays_per_pixel()).collect();
        let mut full = 0;
        for pass in &passes {
            let mut canvas = Canvas::new(w, h);
            let Ok(rays) = render_pass(&renderer, &mut canvas, pass);
            let pixels = pass.pixel_count(w, h);
            if pass.samples < renderer.rays_per_pixel() {
                // The preview: at most its samples a pixel.
                assert!(rays <= pixels * pass.samples as u64, "point {point}: preview {rays}");
                continue;
            }
            full += rays;
            let want: u64 = (0..h)
                .flat_map(|r| (0..w).map(move |c| (c, r)))
                .filter(|&(c, r)| pass.computes(c, r))
                .map(|(c, r)| renderer.pixel_rays(c, r).1 as u64)
                .sum();
            assert_eq!(rays, want, "point {point}, pass {pass:?}");
            assert!(
                rays <= pixels * renderer.rays_per_pixel() as u64,
                "point {point}: at most `rays_per_pixel` a pixel"
            );
            if adaptive == "on" {
                assert!(
                    rays < pixels * point as u64,
                    "point {point}: adaptive pixels take fewer than `point`"
                );
            } else {
                assert_eq!(rays, pixels * point as u64, "point {point}: every pixel its samples");
            }
        }
        assert_eq!(
            full, plain,
            "point {point}: each pixel computed once, as the plain render"
        );
    }
}
