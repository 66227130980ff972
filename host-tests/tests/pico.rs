//! The Raspberry Pi Pico firmware under rp2040js, through `lensray emulate
//! --board pico`: what its ST7789 shows at the end of the progressive passes
//! is bit for bit the host's render as an RGB 5-6-5 panel shows it (`lensray
//! render --panel rgb565`), for Program 1, pinhole-shapes and scenes drawn
//! from the fuzzer's grammar; its report says what the frame cost; a panic or
//! a fault in the firmware makes `emulate` fail with the firmware's message.
//!
//! They need Node with `npm ci` done in firmware/pico/emu and the thumbv6m
//! target, so they are `#[ignore]`d in a plain `cargo test`;
//! `scripts/firmware-tests.sh` installs what is missing and runs them.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use embedded_graphics::pixelcolor::RgbColor;
use lensray::{Renderer, Scene, I16F16};
use lensray_host::panel::PanelFormat;
use lensray_host::{load_image, load_scene, render_image, Image};
use lensray_testkit::fuzz::{scene_from_grammar, Rng};

const LENSRAY: &str = env!("CARGO_BIN_EXE_lensray");

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn tmp(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(name)
}

fn show(o: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn emulate(scene: &Path, width: u32, height: u32, samples: u32, out: &Path, fault: Option<&str>) -> Output {
    let mut cmd = Command::new(LENSRAY);
    cmd.arg("emulate")
        .arg(scene)
        .args([
            "--board",
            "pico",
            "--width",
            &width.to_string(),
            "--height",
            &height.to_string(),
        ])
        .args(["--samples", &samples.to_string(), "--timeout", "600", "-o"])
        .arg(out);
    match fault {
        Some(f) => cmd.env("LENSRAY_FAULT", f),
        None => cmd.env_remove("LENSRAY_FAULT"),
    };
    cmd.output().expect("run lensray emulate")
}

/// Emulates the scene and checks the panel against the host's Rgb565 render;
/// returns the report.
fn panel_equals_host(scene: &Path, width: u32, height: u32, samples: u32) -> BTreeMap<String, String> {
    let name = scene.file_stem().unwrap().to_string_lossy().into_owned();
    let out = tmp(&format!("pico-{name}-{width}x{height}.png"));
    let _ = std::fs::remove_file(&out);
    let o = emulate(scene, width, height, samples, &out, None);
    assert!(o.status.success(), "{}", show(&o));
    let panel = load_image(&out).expect("read the panel's picture");

    let parsed = load_scene::<I16F16>(scene).unwrap();
    let host = render_image(&parsed, width, height, Some(samples), &|| {});
    // A pinhole casts one ray a pixel whatever the samples.
    let rays = Renderer::new(&parsed, width, height)
        .with_samples(samples)
        .rays_per_pixel();
    let want = PanelFormat::Rgb565.quantise(&host);
    let differing = panel.pixels.iter().zip(&want.pixels).filter(|(a, b)| a != b).count();
    assert_eq!(
        (panel.width, panel.height),
        (width, height),
        "the panel's picture has the wrong size"
    );
    assert_eq!(
        differing,
        0,
        "{differing} of {} pixels of the pico's panel differ from the host's Rgb565 render of {}",
        want.pixels.len(),
        scene.display()
    );

    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    let report: BTreeMap<String, String> = stdout
        .lines()
        .find_map(|l| l.strip_prefix("report "))
        .unwrap_or_else(|| panic!("no report line:\n{stdout}"))
        .split_whitespace()
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let get = |k: &str| -> f64 {
        report
            .get(k)
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("report has no number {k}:\n{stdout}"))
    };
    assert_eq!(report.get("board").map(String::as_str), Some("pico"));
    assert_eq!(
        (get("width"), get("height"), get("rays")),
        (width as f64, height as f64, rays as f64)
    );
    // Cycles a pixel and seconds at 125 MHz both come from the frame's cycles.
    let pixels = (width * height) as f64;
    assert_eq!(get("cycles_per_pixel"), (get("frame_cycles") / pixels).round());
    assert!((get("seconds_125mhz") - get("frame_cycles") / 125e6).abs() < 1e-6);
    // Two cores, estimated from the bands' cycles: faster than one, at best twice as fast.
    let two = get("two_core_estimate_cycles");
    assert!(
        two < get("frame_cycles") && two >= get("frame_cycles") / 2.0,
        "{stdout}"
    );
    // The progressive passes drew more pixels than the frame has (blocks, then finer blocks).
    assert!(get("pixels_written") > pixels, "{stdout}");
    report
}

#[test]
#[ignore = "needs node, npm ci in firmware/pico/emu and thumbv6m-none-eabi; run by scripts/firmware-tests.sh"]
fn the_pico_panel_shows_the_hosts_rgb565_render_bit_for_bit() {
    let scenes = repo().join("scenes");
    // Program 1 with its lens (3 rays a pixel), through the preview and every refinement.
    panel_equals_host(&scenes.join("paper-program1.scene"), 48, 36, 3);
    // All five shapes with shadows, one ray a pixel.
    panel_equals_host(&scenes.join("pinhole-shapes.scene"), 40, 30, 1);

    // The host's plain render is not what the panel shows: the 16-bit check is a real one.
    let host = render_image(
        &load_scene::<I16F16>(&scenes.join("paper-program1.scene")).unwrap(),
        48,
        36,
        Some(3),
        &|| {},
    );
    assert_ne!(host, PanelFormat::Rgb565.quantise(&host));
}

/// A scene from the fuzzer's grammar that parses and whose render is not one flat colour.
fn unseen_scene(rng: &mut Rng) -> Vec<u8> {
    loop {
        let bytes = scene_from_grammar(rng);
        let Ok(scene) = Scene::<I16F16>::parse_bytes(&bytes) else {
            continue;
        };
        let img: Image = render_image(&scene, 16, 12, Some(1), &|| {});
        if img.pixels.iter().any(|p| *p != img.pixels[0]) {
            return bytes;
        }
    }
}

#[test]
#[ignore = "needs node, npm ci in firmware/pico/emu and thumbv6m-none-eabi; run by scripts/firmware-tests.sh"]
fn the_pico_panel_matches_the_host_on_unseen_scenes() {
    // A new seed each run unless LENSRAY_PICO_SEED repeats one; printed for that.
    let seed = std::env::var("LENSRAY_PICO_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .unwrap()
                .as_nanos() as u64
        });
    println!("unseen scenes from seed {seed} (LENSRAY_PICO_SEED={seed} repeats them)");
    let mut rng = Rng::new(seed);
    for i in 0..2 {
        let path = tmp(&format!("pico-unseen-{i}.scene"));
        std::fs::write(&path, unseen_scene(&mut rng)).unwrap();
        panel_equals_host(&path, 24, 18, 2);
    }
}

#[test]
#[ignore = "needs node, npm ci in firmware/pico/emu and thumbv6m-none-eabi; run by scripts/firmware-tests.sh"]
fn a_panic_or_a_fault_on_the_pico_fails_emulate_with_its_message() {
    let scene = repo().join("scenes/pinhole-shapes.scene");
    for (fault, says) in [
        ("panic", "panicked: "),
        ("panic", "failing on purpose (LENSRAY_FAULT=panic)"),
        ("hardfault", "HardFault at pc 0x1"),
    ] {
        let out = tmp(&format!("pico-fault-{fault}.png"));
        let _ = std::fs::remove_file(&out);
        let o = emulate(&scene, 8, 6, 1, &out, Some(fault));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{fault}:\n{}", show(&o));
        assert!(
            err.contains("the firmware failed") && err.contains(says),
            "{fault}:\n{}",
            show(&o)
        );
        assert!(!out.exists(), "a picture was written for a failed run");
    }
}

#[test]
fn render_panel_rgb565_shows_the_render_on_a_16_bit_panel() {
    let scene = repo().join("scenes/pinhole-shapes.scene");
    let out = tmp("panel-rgb565.png");
    let _ = std::fs::remove_file(&out);
    let o = Command::new(LENSRAY)
        .arg("render")
        .arg(&scene)
        .args(["--width", "40", "--height", "30", "--panel", "rgb565", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", show(&o));
    let shown = load_image(&out).unwrap();
    let full = render_image(&load_scene::<I16F16>(&scene).unwrap(), 40, 30, None, &|| {});
    // Each channel is one of the panel's 32 (red, blue) or 64 (green) levels,
    // widened to 0..=255 with rounding, and the nearest such level to the render's.
    let levels = |bits: u32| -> Vec<u8> {
        let max = (1u32 << bits) - 1;
        (0..=max).map(|k| ((k * 255 + max / 2) / max) as u8).collect()
    };
    let (five, six) = (levels(5), levels(6));
    for (s, f) in shown.pixels.iter().zip(&full.pixels) {
        for (v, orig, table, step) in [
            (s.r(), f.r(), &five, 255.0 / 31.0),
            (s.g(), f.g(), &six, 255.0 / 63.0),
            (s.b(), f.b(), &five, 255.0 / 31.0),
        ] {
            assert!(table.contains(&v), "{v} is not a panel level");
            assert!(
                (v as f64 - orig as f64).abs() <= step / 2.0 + 1.0,
                "{orig} shown as {v}"
            );
        }
    }
    assert_ne!(shown, full, "no pixel changed: nothing was quantised");

    let bad = Command::new(LENSRAY)
        .arg("render")
        .arg(&scene)
        .args(["--panel", "rgb666", "-o"])
        .arg(tmp("panel-bad.png"))
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--panel rgb666: unknown panel format"));
}

/// Program 1 at its own defaults (`point` 70, stratified and adaptive): the
/// Pico runs the adaptive pre-pass itself (it parses the scene on the
/// device), and its stop rule, pixels and the progressive passes' last
/// refinement are the host's, bit for bit on the panel.
#[test]
#[ignore = "needs node, npm ci in firmware/pico/emu and thumbv6m-none-eabi; run by scripts/firmware-tests.sh"]
fn the_pico_panel_matches_the_host_at_the_scenes_defaults() {
    let path = repo().join("scenes/paper-program1.scene");
    let scene = load_scene::<I16F16>(&path).unwrap();
    let (w, h) = (32, 24);
    let r = Renderer::new(&scene, w, h);
    let rule = r.stop_rule().expect("Program 1 at its defaults has a stop rule");
    assert!(rule.survey_rays > 0, "{rule:?}");
    // Pixels stop at different counts: the stop rule is at work.
    let counts: std::collections::BTreeSet<u32> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| r.pixel_rays(x, y).1)
        .collect();
    assert!(counts.len() > 1, "every pixel cast {counts:?} rays");
    panel_equals_host(&path, w, h, scene.camera.samples);
}
