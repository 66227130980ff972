//! Adaptive lens sampling (`adaptive on`, `--adaptive on`): on Program 1 with
//! 70 rays a pixel it casts at most half the rays of the full render and stays
//! within 40 dB PSNR of it, and the same holds on every scene in `scenes/`
//! (which is why it is on by default only if this holds; see README).

use embedded_graphics::pixelcolor::Rgb888;
use lensray::{Renderer, Scalar, Scene, I16F16};
use lensray_host::{load_scene, Diff, Image};
use rayon::prelude::*;

/// Renders with adaptive sampling on or off; the image and the rays cast.
fn render<S: Scalar>(scene: &Scene<S>, w: u32, h: u32, samples: Option<u32>, adaptive: bool) -> (Image, u64) {
    let mut r = Renderer::new(scene, w, h).with_adaptive(adaptive);
    if let Some(n) = samples {
        r = r.with_samples(n);
    }
    let rows: Vec<(Vec<Rgb888>, u64)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut rays = 0;
            let px = (0..w)
                .map(|x| {
                    let (c, n) = r.pixel_rays(x, y);
                    rays += n as u64;
                    Rgb888::new(c.x.to_u8(), c.y.to_u8(), c.z.to_u8())
                })
                .collect();
            (px, rays)
        })
        .collect();
    let rays = rows.iter().map(|r| r.1).sum();
    let image = Image {
        width: w,
        height: h,
        pixels: rows.into_iter().flat_map(|r| r.0).collect(),
    };
    (image, rays)
}

/// (share of the full render's rays, PSNR against it) for a scene file.
fn measure<S: Scalar>(name: &str, w: u32, h: u32, samples: Option<u32>) -> (f64, f64) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name);
    let scene = load_scene::<S>(&path).unwrap();
    let (full, full_rays) = render(&scene, w, h, samples, false);
    let (adaptive, rays) = render(&scene, w, h, samples, true);
    let psnr = Diff::of(&full, &adaptive).unwrap().psnr;
    let share = rays as f64 / full_rays as f64;
    println!(
        "{name} {} {w}x{h} samples {samples:?}: {:.1} % of the rays, PSNR {psnr:.1} dB",
        S::NAME,
        100.0 * share
    );
    (share, psnr)
}

#[test]
fn program1_with_70_samples_meets_the_bar() {
    let (share, psnr) = measure::<I16F16>("paper-program1.scene", 160, 120, Some(70));
    assert!(share <= 0.5, "{:.1} % of the rays", 100.0 * share);
    assert!(psnr >= 40.0, "PSNR {psnr:.1} dB");
}

/// Whether adaptive sampling meets the bar on a scene at its own sample count:
/// PSNR >= 40 dB against the full render, and at most half its rays (or all of
/// them: a pinhole scene casts one ray a pixel either way).
fn meets_the_bar(name: &str) -> bool {
    let (share, psnr) = measure::<I16F16>(name, 160, 120, None);
    psnr >= 40.0 && (share <= 0.5 || share == 1.0)
}

#[test]
fn on_by_default_only_if_every_scene_meets_the_bar() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".scene"))
        .collect();
    names.sort();
    assert!(names.len() >= 3);
    // Every scene is measured (no short cut), so the output shows each figure.
    let failing: Vec<&String> = names.iter().filter(|n| !meets_the_bar(n)).collect();
    let default = lensray::scene::CameraParams::default().adaptive;
    assert_eq!(
        default,
        failing.is_empty(),
        "adaptive sampling is {} by default, but the scenes failing the bar are {failing:?}",
        if default { "on" } else { "off" }
    );
}

#[test]
fn samples_that_agree_stop_after_the_first_batch_and_others_go_on() {
    use lensray::render::ADAPTIVE_BATCH;
    // A lens camera looking at nothing: every sample misses, all agree.
    let empty = Scene::<I16F16>::parse("radius 0.3\npoint 64\n").unwrap();
    let r = Renderer::new(&empty, 8, 6).with_adaptive(true);
    assert_eq!(r.pixel_rays(3, 2).1, ADAPTIVE_BATCH);
    assert_eq!(Renderer::new(&empty, 8, 6).pixel_rays(3, 2).1, 64, "off: every sample");
    // Program 1's blurred cube edge: samples differ, so that pixel goes on
    // past the first batch, and some pixel of the image casts all 70.
    let p1 =
        load_scene::<I16F16>(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene"))
            .unwrap();
    let r = Renderer::new(&p1, 80, 60).with_adaptive(true);
    let counts: Vec<u32> = (0..60)
        .flat_map(|y| (0..80).map(move |x| (x, y)))
        .map(|(x, y)| r.pixel_rays(x, y).1)
        .collect();
    assert!(counts.contains(&70));
    assert!(counts.contains(&ADAPTIVE_BATCH));
    assert!(counts.iter().all(|&n| n == 70 || n % ADAPTIVE_BATCH == 0));
    // With adaptive sampling off the pixel is exactly the full render's.
    let full = Renderer::new(&p1, 80, 60);
    let adaptive_off = Renderer::new(&p1, 80, 60).with_adaptive(false);
    assert_eq!(full.pixel(40, 30), adaptive_off.pixel(40, 30));
}

#[test]
fn the_scene_keyword_and_the_cli_flag_turn_it_on() {
    let s = Scene::<I16F16>::parse("adaptive on\n").unwrap();
    assert!(s.camera.adaptive && Renderer::new(&s, 4, 3).is_adaptive());
    let s = Scene::<I16F16>::parse("adaptive on\nadaptive off\n").unwrap();
    assert!(!s.camera.adaptive);
    let err = Scene::<I16F16>::parse("adaptive maybe\n").unwrap_err();
    assert_eq!(err.to_string(), "line 1: adaptive: \"maybe\" must be on or off");
}

#[test]
fn the_render_flag_overrides_the_scene() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("adaptive-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene");
    let run = |flag: &str, out: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_lensray"))
            .arg("render")
            .arg(&scene)
            .args(["--width", "40", "--samples", "24", "--adaptive", flag, "-o"])
            .arg(dir.join(out))
            .output()
            .unwrap()
    };
    assert!(run("on", "on.bmp").status.success());
    assert!(run("off", "off.bmp").status.success());
    let on = lensray_host::load_image(&dir.join("on.bmp")).unwrap();
    let off = lensray_host::load_image(&dir.join("off.bmp")).unwrap();
    // Off is the plain render; on differs somewhere but stays close.
    let scene = load_scene::<I16F16>(&scene).unwrap();
    assert_eq!(
        off.pixels,
        lensray_host::render_image(&scene, 40, 30, Some(24), &|| {}).pixels
    );
    let diff = Diff::of(&on, &off).unwrap();
    assert!(diff.psnr.is_finite() && diff.psnr > 30.0, "{:.1} dB", diff.psnr);
    let bad = run("maybe", "bad.bmp");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--adaptive maybe: must be on or off"));
}
