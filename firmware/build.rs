//! Build-time configuration of the firmware: the board's memory map, and the
//! scene and image it renders, from environment variables:
//!
//! | variable | meaning | default |
//! |---|---|---|
//! | `LENSRAY_SCENE` | scene file embedded in flash | `../scenes/paper-program1.scene` |
//! | `LENSRAY_WIDTH` | image width in pixels | 160 |
//! | `LENSRAY_HEIGHT` | image height in pixels | round(width / aspect_ratio) |
//! | `LENSRAY_SAMPLES` | rays per pixel, overriding the scene's `point` | the scene's |
//! | `LENSRAY_FLOAT` | `1`: render in f32 instead of Q16.16 | Q16.16 |
//! | `LENSRAY_FAULT` | `panic` or `hardfault`: fail on purpose (tests) | none |
//! | `LENSRAY_CHECK` | `kernels`: check the Cortex-M0's Thumb-1 kernels against the portable Rust first (tests) | none |
//!
//! The scene is parsed here too, so a bad scene fails the build with
//! `FILE:LINE: message` rather than on the board. By default it is also set
//! up here for the image size and baked (`lensray::baked`): the firmware
//! loads the baked bytes and holds no parser and no `f64` set-up. With the
//! feature `parse-on-device` the scene's text is embedded and parsed on the board.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::exit;

/// Largest image side: the camera's limit.
const MAX_SIDE: u32 = lensray::MAX_IMAGE_SIDE;

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
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let target = env::var("TARGET").unwrap_or_default();

    // The board: its memory map (cortex-m-rt's link.x includes it) or, on
    // RISC-V, its whole linker script, and the target it needs.
    let boards = [
        ("microbit", manifest.join("../memory.x"), "thumbv6m-none-eabi"),
        (
            "mps2-an386",
            manifest.join("boards/mps2-an386/memory.x"),
            "thumbv7em-none-eabihf",
        ),
        // The same memory map as the AN386: 4 MiB of flash and of RAM.
        (
            "mps2-an385",
            manifest.join("boards/mps2-an386/memory.x"),
            "thumbv7m-none-eabi",
        ),
        (
            "sifive-e",
            manifest.join("boards/sifive-e/link.x"),
            "riscv32imac-unknown-none-elf",
        ),
    ];
    let chosen: Vec<_> = boards
        .iter()
        .filter(|(name, _, _)| {
            env::var_os(format!("CARGO_FEATURE_{}", name.to_uppercase().replace('-', "_"))).is_some()
        })
        .collect();
    let [(board, memory_x, want_target)] = chosen.as_slice() else {
        fail("pick exactly one board feature: --features microbit (--target thumbv6m-none-eabi), mps2-an385 (--target thumbv7m-none-eabi), mps2-an386 (--target thumbv7em-none-eabihf) or sifive-e (--target riscv32imac-unknown-none-elf)");
    };
    if target != *want_target {
        fail(&format!("board {board} needs --target {want_target}, not {target}"));
    }
    println!("cargo:rerun-if-changed={}", memory_x.display());
    let map = fs::read(memory_x).unwrap_or_else(|e| fail(&format!("{}: {e}", memory_x.display())));
    let script = if target.starts_with("riscv") {
        "link-riscv.x"
    } else {
        "memory.x"
    };
    fs::write(out.join(script), map).unwrap_or_else(|e| fail(&format!("cannot write {script}: {e}")));
    // cortex-m-rt's link.x includes memory.x from the search path. Link
    // arguments set here, not in .cargo/config.toml, survive a RUSTFLAGS variable.
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=--nmagic");
    if target.starts_with("riscv") {
        println!("cargo:rustc-link-arg-bins=-Tlink-riscv.x");
    } else {
        println!("cargo:rustc-link-arg-bins=-Tlink.x");
        // cortex-m-rt's "device" link.x includes device.x (a device crate's
        // handler names): main.rs's `__INTERRUPTS` names its one handler.
        fs::write(
            out.join("device.x"),
            "/* no device crate: see main.rs's __INTERRUPTS */\n",
        )
        .unwrap_or_else(|e| fail(&format!("cannot write device.x: {e}")));
    }

    // The scene, checked now with the renderer's own parser.
    let scene_path = match var("LENSRAY_SCENE") {
        Some(p) => PathBuf::from(p),
        None => manifest.join("../scenes/paper-program1.scene"),
    };
    println!("cargo:rerun-if-changed={}", scene_path.display());
    let bytes = fs::read(&scene_path).unwrap_or_else(|e| fail(&format!("{}: cannot read: {e}", scene_path.display())));
    let scene = lensray::Scene::<lensray::I16F16>::parse_bytes(&bytes)
        .unwrap_or_else(|e| fail(&format!("{}:{}: {}", scene_path.display(), e.line, e.kind)));
    let scene_name = Path::new(&scene_path)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();

    let width = number("LENSRAY_WIDTH", 1, MAX_SIDE).unwrap_or(160);
    let height = number("LENSRAY_HEIGHT", 1, MAX_SIDE).unwrap_or_else(|| {
        // The host's rule (lensray render): round(width / aspect_ratio).
        let h = (width as f64 / scene.camera.aspect_ratio).round();
        if !(1.0..=MAX_SIDE as f64).contains(&h) {
            fail(&format!(
                "height {h} from width {width} / aspect_ratio: set LENSRAY_HEIGHT"
            ));
        }
        h as u32
    });
    let samples = number("LENSRAY_SAMPLES", 1, 65535);
    let float = match var("LENSRAY_FLOAT").as_deref() {
        None | Some("0") => false,
        Some("1") => true,
        Some(v) => fail(&format!("LENSRAY_FLOAT={v}: must be 0 or 1")),
    };
    let fault = match var("LENSRAY_FAULT").as_deref() {
        None => "",
        Some("panic") => "panic",
        Some("hardfault") => "hardfault",
        Some(v) => fail(&format!("LENSRAY_FAULT={v}: must be panic or hardfault")),
    };
    let check = match var("LENSRAY_CHECK").as_deref() {
        None => false,
        Some("kernels") => true,
        Some(v) => fail(&format!("LENSRAY_CHECK={v}: must be kernels")),
    };

    // What goes into flash: the scene's text to parse on the device, or by
    // default its set-up for this image size, baked.
    let parse_on_device = env::var_os("CARGO_FEATURE_PARSE_ON_DEVICE").is_some();
    let embedded = if parse_on_device {
        bytes.clone()
    } else if float {
        bake::<f32>(&bytes, width, height, samples)
    } else {
        bake::<lensray::I16F16>(&bytes, width, height, samples)
    };
    // The report's fixed part, one string: the Cortex-M0's flash.
    let sqrt = if env::var_os("CARGO_FEATURE_HW_SQRT").is_some() {
        "vsqrt.f32"
    } else {
        "libm"
    };
    let report_head = format!(
        "report board={board} number={} f32_sqrt={sqrt} width={width} height={height} scene_form={}",
        if float { "f32" } else { "Q16.16" },
        if parse_on_device { "parsed" } else { "baked" },
    );
    fs::write(out.join("scene.bin"), &embedded).unwrap_or_else(|e| fail(&format!("cannot write the scene: {e}")));
    let config = format!(
        "/// The board's name.\n\
         pub const BOARD: &str = {board:?};\n\
         /// The scene, embedded in flash: its text (feature `parse-on-device`) or baked.\n\
         pub static SCENE: &[u8] = include_bytes!({scene_txt:?});\n\
         /// The scene file's name.\n\
         pub const SCENE_NAME: &str = {scene_name:?};\n\
         /// Image width in pixels.\n\
         pub const WIDTH: u32 = {width};\n\
         /// Image height in pixels.\n\
         pub const HEIGHT: u32 = {height};\n\
         /// Rays per pixel, overriding the scene's `point`.\n\
         pub const SAMPLES: Option<u32> = {samples:?};\n\
         /// The number type of the renderer.\n\
         pub type Number = {number};\n\
         /// A failure on purpose, for the tests: \"\", \"panic\" or \"hardfault\".\n\
         pub const FAULT: &str = {fault:?};\n\
         /// Check the Thumb-1 kernels against the portable Rust before rendering.\n\
         pub const CHECK_KERNELS: bool = {check};\n\
         /// The report line's start: board, number type, square root, size, scene form.\n\
         pub const REPORT_HEAD: &str = {report_head:?};\n",
        scene_txt = out.join("scene.bin").display().to_string(),
        number = if float { "f32" } else { "lensray::I16F16" },
    );
    fs::write(out.join("config.rs"), config).unwrap_or_else(|e| fail(&format!("cannot write config.rs: {e}")));
}

/// The scene set up for `width` x `height` (and `samples`) and baked.
fn bake<S: lensray::baked::BakeScalar>(text: &[u8], width: u32, height: u32, samples: Option<u32>) -> Vec<u8> {
    let scene =
        lensray::Scene::<S>::parse_bytes(text).unwrap_or_else(|e| fail(&format!("line {}: {}", e.line, e.kind)));
    let renderer = lensray::Renderer::new_with_samples(&scene, width, height, samples);
    let mut out = vec![0u8; lensray::baked::baked_len(&renderer)];
    lensray::baked::bake(&renderer, &mut out).unwrap_or_else(|e| fail(&format!("cannot bake the scene: {e}")));
    out
}
