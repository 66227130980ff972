//! `lensray emulate --board pico`: builds the Raspberry Pi Pico firmware
//! (`firmware/pico`: rp2040-hal and mipidsi, as flashed) with the scene
//! embedded, runs it under rp2040js with a model of its ST7789 panel
//! (`firmware/pico/emu/run.js`, Node), and writes what the panel shows.
//!
//! The picture is the panel's RGB 5-6-5 frame memory as the viewer sees it,
//! widened to 8 bits a channel by embedded-graphics: it equals
//! `lensray render --panel rgb565` of the same scene and size. The frame is
//! timed on the emulated RP2040 in cycles of its 125 MHz clock.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use lensray::{Renderer, Scalar, I16F16};
use lensray_host::panel::image_from_rgb565;
use lensray_host::{encode, load_scene, write_atomic, Image};

use crate::cli::emulate::{
    firmware_dir, lock_target_dir, missing_tools, output_path, run_bounded, EmulateArgs, Tool, WorkDir, DEFAULT_WIDTH,
};
use crate::cli::opts::image_size;
use crate::Fail;

/// The panel in landscape, as the firmware turns it.
const PANEL: (u32, u32) = (320, 240);
/// The RP2040's system clock as the firmware sets it.
const CLOCK_HZ: f64 = 125e6;
const TARGET: &str = "thumbv6m-none-eabi";

pub(crate) fn run(o: &EmulateArgs, scene_path: &Path, soft_sqrt: bool, timeout: Duration) -> Result<(), Fail> {
    if o.float || soft_sqrt {
        return Err(Fail(
            "the pico firmware renders in Q16.16: --float and --soft-sqrt are for the QEMU boards".into(),
        ));
    }
    // The scene first: a bad one fails here, exactly as `render` reports it.
    let scene = load_scene::<I16F16>(scene_path)?;
    let (width, height) = image_size(&o.size, DEFAULT_WIDTH, scene.camera.aspect_ratio)?;
    if width > PANEL.0 || height > PANEL.1 {
        return Err(Fail(format!(
            "{width}x{height} does not fit the pico's {}x{} panel: give --width and --height up to that",
            PANEL.0, PANEL.1
        )));
    }
    let renderer = Renderer::new_with_samples(&scene, width, height, o.size.samples);
    let rays = renderer.rays_per_pixel();
    let (out, format) = output_path(o.out.as_deref(), scene_path, "pico")?;
    let scene_abs = std::fs::canonicalize(scene_path).map_err(|e| Fail(format!("{}: {e}", scene_path.display())))?;
    let firmware = firmware_dir()?;
    let emu = firmware.join("pico/emu");
    missing_tools(&firmware, TARGET, &[Tool::Rp2040js(&emu)])?;

    let work = WorkDir::new()?;
    let elf = build(&firmware, &work.0, &scene_abs, width, height, rays)?;
    eprintln!("running on pico under rp2040js");
    let picture = work.0.join("panel.rgb565");
    let said = run_node(&emu, &elf, &picture, width, height, timeout)?;
    let img = panel_picture(&picture, width, height)?;
    let scene_name = scene_path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default();
    report(&said, &scene_name, (width, height), rays)?;
    let encoded = encode(&img, format)?;
    write_atomic(&out, &encoded).map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())))?;
    eprintln!(
        "wrote {} ({width}x{height}, as the pico's RGB 5-6-5 panel shows it)",
        out.display()
    );
    Ok(())
}

/// The panel's picture as the harness wrote it (RGB 5-6-5 words, little-endian).
fn panel_picture(picture: &Path, width: u32, height: u32) -> Result<Image, Fail> {
    let bytes = std::fs::read(picture).map_err(|e| Fail(format!("the panel's picture cannot be read: {e}")))?;
    let words: Vec<u16> = bytes
        .chunks_exact(2)
        .map(|w| u16::from_le_bytes([w[0], w[1]]))
        .collect();
    image_from_rgb565(&words, width, height).ok_or_else(|| {
        Fail(format!(
            "the panel's picture has {} bytes, not {}",
            bytes.len(),
            width * height * 2
        ))
    })
}

/// Prints the run's figures and its `report` line from the harness's
/// summary (`said`, its line starting `emu `).
fn report(said: &str, scene_name: &str, (width, height): (u32, u32), rays: u32) -> Result<(), Fail> {
    let line = said
        .lines()
        .find_map(|l| l.strip_prefix("emu "))
        .ok_or_else(|| Fail(format!("the emulator finished without its summary; it said:\n{said}")))?;
    let value = |key: &str| -> Result<u64, Fail> {
        line.split_whitespace()
            .filter_map(|kv| kv.split_once('='))
            .find(|(k, _)| *k == key)
            .and_then(|(_, v)| v.parse().ok())
            .ok_or_else(|| Fail(format!("the emulator's summary has no valid {key}: {line}")))
    };
    let frame = value("frame_cycles")?;
    let pixels = width as u64 * height as u64;
    let per_pixel = (frame + pixels / 2) / pixels;
    let seconds = frame as f64 / CLOCK_HZ;
    let two_cores = value("two_core_estimate_cycles")?;
    let two_seconds = two_cores as f64 / CLOCK_HZ;
    println!(
        "board pico (RP2040, Cortex-M0+ at 125 MHz, one core emulated), Q16.16, scene {scene_name}, {width}x{height}, {rays} rays per pixel, progressive passes on an ST7789"
    );
    println!(
        "{per_pixel} cycles per pixel on pico ({frame} cycles a frame of {width}x{height}: {seconds:.3} s at 125 MHz)"
    );
    println!(
        "two cores: about {two_seconds:.3} s at 125 MHz, an estimate from the {} bands' cycles on one core (rp2040js runs one core)",
        value("bands")?
    );
    println!(
        "report board=pico number={} width={width} height={height} rays={rays} setup_cycles={} frame_cycles={frame} \
         cycles_per_pixel={per_pixel} seconds_125mhz={seconds:.6} two_core_estimate_cycles={two_cores} \
         two_core_estimate_seconds_125mhz={two_seconds:.6} spi_bytes={} pixels_written={}",
        I16F16::NAME,
        value("setup_cycles")?,
        value("spi_bytes")?,
        value("pixels_written")?,
    );
    Ok(())
}

/// Builds the Pico firmware for this scene and size, from its own directory
/// (its `.cargo/config.toml` adds to the firmware's); its ELF copied into `dir`.
fn build(firmware: &Path, dir: &Path, scene: &Path, width: u32, height: u32, rays: u32) -> Result<PathBuf, Fail> {
    // Runs in parallel share the target directory: one build at a time.
    let (target_dir, lock) = lock_target_dir(firmware)?;
    eprintln!("building the firmware for pico ({TARGET}) in {}", firmware.display());
    let built = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
        .current_dir(firmware.join("pico"))
        .args(["build", "--release", "-p", "lensray-pico", "--target", TARGET])
        .arg("--target-dir")
        .arg(&target_dir)
        .env("LENSRAY_SCENE", scene)
        .env("LENSRAY_WIDTH", width.to_string())
        .env("LENSRAY_HEIGHT", height.to_string())
        .env("LENSRAY_SAMPLES", rays.to_string())
        // These would replace the firmware's own flags and targets.
        .env_remove("RUSTFLAGS")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_BUILD_RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET")
        .stdin(Stdio::null())
        .output()
        .map_err(|e| Fail(format!("cannot run cargo to build the firmware: {e}")))?;
    if !built.status.success() {
        return Err(Fail(format!(
            "building the pico firmware failed:\n{}",
            String::from_utf8_lossy(&built.stderr).trim_end()
        )));
    }
    let elf = target_dir.join(TARGET).join("release").join("lensray-pico");
    let copy = dir.join("lensray-pico.elf");
    std::fs::copy(&elf, &copy).map_err(|e| Fail(format!("{}: {e}", elf.display())))?;
    drop(lock);
    Ok(copy)
}

/// Runs the harness; its stdout, or an error with what it and the firmware said.
fn run_node(
    emu: &Path,
    elf: &Path,
    picture: &Path,
    width: u32,
    height: u32,
    timeout: Duration,
) -> Result<String, Fail> {
    let mut cmd = Command::new("node");
    cmd.arg(emu.join("run.js"))
        .arg(elf)
        .args(["--width", &width.to_string(), "--height", &height.to_string()])
        .arg("--out")
        .arg(picture);
    let (status, out, said) = run_bounded(&mut cmd, "node", timeout)?;
    match status {
        None => Err(Fail(format!(
            "the firmware on pico did not finish within {} s (--timeout); it said:\n{said}",
            timeout.as_secs()
        ))),
        Some(s) if !s.success() => {
            let what = match s.code() {
                Some(3) => "the panel refused what it was sent".to_string(),
                Some(4) => "the firmware failed".to_string(),
                Some(c) => format!("the emulator failed (exit status {c})"),
                None => "the emulator was killed by a signal".to_string(),
            };
            Err(Fail(format!("on pico {what}:\n{said}")))
        }
        Some(_) => Ok(out),
    }
}
