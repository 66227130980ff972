//! Puts the Pico's memory map (memory.x, beside this file) on the linker's
//! search path, links with cortex-m-rt's link.x, and writes the scene and
//! image the firmware renders from environment variables (as `../build.rs`
//! does for the QEMU boards; `lensray emulate --board pico` sets them):
//!
//! | variable | meaning | default |
//! |---|---|---|
//! | `LENSRAY_SCENE` | scene file embedded in flash | `scenes/paper-program1.scene` |
//! | `LENSRAY_WIDTH` | image width, at most the panel's 320 | 320 |
//! | `LENSRAY_HEIGHT` | image height, at most the panel's 240 | 240 |
//! | `LENSRAY_SAMPLES` | rays per pixel, overriding the scene's `point` | 8 |
//! | `LENSRAY_FAULT` | `panic` or `hardfault`: fail on purpose (tests) | none |
//!
//! The image sits in the panel's top-left corner. The scene is parsed here
//! too, so a bad scene fails the build with `FILE:LINE: message`. Link
//! arguments set here survive a RUSTFLAGS variable, unlike those of
//! .cargo/config.toml.

use std::env;
use std::fs;
use std::path::PathBuf;
use std::process::exit;

/// The panel in landscape.
const PANEL: (u32, u32) = (320, 240);

fn fail(msg: &str) -> ! {
    eprintln!("error: {msg}");
    exit(1)
}

fn var(name: &str) -> Option<String> {
    println!("cargo:rerun-if-env-changed={name}");
    env::var(name).ok().filter(|v| !v.is_empty())
}

fn number(name: &str, lo: u32, hi: u32) -> Option<u32> {
    let v = var(name)?;
    match v.trim().parse::<u32>() {
        Ok(n) if (lo..=hi).contains(&n) => Some(n),
        _ => fail(&format!("{name}={v}: must be a whole number from {lo} to {hi}")),
    }
}

fn main() {
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let map = manifest.join("memory.x");
    fs::copy(&map, out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rerun-if-changed={}", map.display());
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");

    let scene_path = match var("LENSRAY_SCENE") {
        Some(p) => PathBuf::from(p),
        None => manifest.join("../../scenes/paper-program1.scene"),
    };
    println!("cargo:rerun-if-changed={}", scene_path.display());
    let bytes = fs::read(&scene_path).unwrap_or_else(|e| fail(&format!("{}: cannot read: {e}", scene_path.display())));
    if let Err(e) = lensray::Scene::<lensray::I16F16>::parse_bytes(&bytes) {
        fail(&format!("{}:{}: {}", scene_path.display(), e.line, e.kind))
    }
    let width = number("LENSRAY_WIDTH", 1, PANEL.0).unwrap_or(PANEL.0);
    let height = number("LENSRAY_HEIGHT", 1, PANEL.1).unwrap_or(PANEL.1);
    let samples = number("LENSRAY_SAMPLES", 1, 65535).unwrap_or(8);
    let fault = match var("LENSRAY_FAULT").as_deref() {
        None => "",
        Some("panic") => "panic",
        Some("hardfault") => "hardfault",
        Some(v) => fail(&format!("LENSRAY_FAULT={v}: must be panic or hardfault")),
    };
    fs::write(out.join("scene.txt"), &bytes).unwrap_or_else(|e| fail(&format!("cannot write the scene: {e}")));
    let config = format!(
        "/// The scene file's bytes, embedded in flash.\n\
         pub static SCENE: &[u8] = include_bytes!({scene_txt:?});\n\
         /// Image width in pixels (the panel's top-left corner).\n\
         pub const WIDTH: u32 = {width};\n\
         /// Image height in pixels.\n\
         pub const HEIGHT: u32 = {height};\n\
         /// Rays per pixel, overriding the scene's `point`.\n\
         pub const SAMPLES: u32 = {samples};\n\
         /// A failure on purpose, for the tests: \"\", \"panic\" or \"hardfault\".\n\
         pub const FAULT: &str = {fault:?};\n",
        scene_txt = out.join("scene.txt").display().to_string(),
    );
    fs::write(out.join("config.rs"), config).unwrap_or_else(|e| fail(&format!("cannot write config.rs: {e}")));
}
