//! `lensray`: the host simulator.
//!
//! ```text
//! lensray render SCENE [-o OUT] [--width W] [--height H] [--samples N] [--float] [--adaptive on|off]
//!                      [--sampler independent|stratified]
//!                      [--passes DIR [--first-step S] [--preview-samples P]] [--panel rgb565]
//! lensray sheet SCENE... [-o SHEET] [--columns C] [--title TEXT] [render options]
//! lensray emulate SCENE --board microbit|mps2-an385|mps2-an386|sifive-e|pico [-o OUT] [--width W] [--height H] [--samples N] [--float]
//! lensray compare SCENE [--width W] [--height H] [--samples N] [--diff OUT]
//! lensray compare A.bmp B.bmp [--diff OUT]
//! lensray bake SCENE [-o FILE] [--width W] [--height H] [--samples N] [--float]
//! ```
//!
//! Exit status: 0 on success, 2 on any error (bad scene, bad arguments,
//! unwritable output). Errors are one line on stderr: a scene error reads
//! `SCENE:LINE: message` (as compilers print, for editors to jump to), any
//! other `lensray: message`.

use std::process::ExitCode;

mod cmd_bake;
mod cmd_compare;
mod cmd_emulate;
mod cmd_render;
mod cmd_sheet;
mod emulate_pico;
mod opts;

pub(crate) const USAGE: &str = "usage:
  lensray render SCENE [-o OUT] [--width W] [--height H] [--samples N] [--float]
                       [--adaptive on|off] [--sampler independent|stratified]
                       [--passes DIR [--first-step S] [--preview-samples P]] [--panel rgb565]
  lensray sheet SCENE... [-o SHEET] [--columns C] [--title TEXT]
                       [--width W] [--height H] [--samples N] [--float] [--adaptive on|off]
  lensray emulate SCENE --board microbit|mps2-an385|mps2-an386|sifive-e|pico [-o OUT] [--width W] [--height H]
                  [--samples N] [--float] [--soft-sqrt] [--parse-on-device] [--timeout SECONDS]
  lensray compare SCENE [--width W] [--height H] [--samples N] [--diff OUT]
  lensray compare A B [--diff OUT]
  lensray bake SCENE [-o FILE] [--width W] [--height H] [--samples N] [--float] [--adaptive on|off]

  render   renders a scene file to OUT (.bmp or .png; default: the scene's
           name with .bmp, in the current directory). --width defaults to 640,
           --height to round(width / aspect_ratio); --samples overrides the
           scene's `point`; --float renders with the f32 reference instead of
           Q16.16; --adaptive on|off overrides the scene's `adaptive` (a pixel
           stops taking lens samples once its mean is settled) and --sampler
           its `sampler`. Prints the mean lens rays cast a pixel. --passes renders progressively as a display would show
           it and saves the picture after each pass as DIR/pass-1.png ...:
           a preview of SxS blocks (S = --first-step, default 8) with P lens
           samples (--preview-samples, default 1; 0 for none), then the same
           blocks and ever finer ones at the full samples; the last pass is
           the plain render, also written to OUT. --panel rgb565 writes the
           image as a 16-bit panel shows it (each pixel to RGB 5-6-5 and back,
           by embedded-graphics' conversions).
  sheet    renders each scene (--width default 320) and lays them side by side,
           C a row (default up to 4), each captioned with its file name and
           camera, under an optional title, into SHEET (default sheet.png).
  emulate  builds the firmware (../firmware) with the scene embedded, runs it
           under QEMU on the board (qemu-system-arm or -riscv32, instruction
           counting on),
           writes the image the board rendered to OUT (default: the scene's
           name, -BOARD.bmp) and prints its instructions per pixel and memory
           use. --width defaults to 160; --soft-sqrt takes f32 square roots in
           software even on the FPU board; --parse-on-device embeds the
           scene's text and parses it on the board instead of the scene
           baked at build time; --timeout (3600 s) bounds the run. Boards:
           microbit (Cortex-M0), mps2-an385 (Cortex-M3), mps2-an386 (Cortex-M4F),
           sifive-e (32-bit RISC-V without FPU, rv32imac; qemu-system-misc).
           --board pico builds firmware/pico and runs it under rp2040js (Node)
           with a model of its ST7789 panel: writes what the panel shows (equal
           to render --panel rgb565) and prints cycles a pixel and the frame's
           seconds at 125 MHz.
  compare  renders a scene with Q16.16 and with the f32 reference (same size,
           same samples; sizes as for render), or reads two images (.bmp or
           .png), and prints PSNR, mean and max error, the share of pixels
           within 1, 2 and 8 levels, and the worst row and column. --diff
           writes the error as a heat map (.png or .bmp): black where equal,
           brighter where worse, white from 8 levels.
  bake     sets the scene up for one image size (--width default 160, --height
           from aspect_ratio) and writes it as a baked scene (default: the
           scene's name with .lrbk): little-endian, versioned, CRC-32
           checked, what the firmware loads without a parser (README, Baked
           scenes). --float bakes the f32 renderer's set-up.";

/// A one-line error for the user; exit status 2.
pub(crate) struct Fail(pub(crate) String);

impl<T: std::fmt::Display> From<T> for Fail {
    fn from(e: T) -> Self {
        Fail(e.to_string())
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Fail(msg)) => {
            if names_a_line(&msg) {
                eprintln!("{msg}");
            } else {
                eprintln!("lensray: {msg}");
            }
            ExitCode::from(2)
        }
    }
}

/// Whether a message starts `FILE:LINE: `: printed without the program's
/// name, so that editors and IDEs can jump to the line.
fn names_a_line(msg: &str) -> bool {
    let Some((head, _)) = msg.split_once(": ") else {
        return false;
    };
    head.rsplit_once(':')
        .is_some_and(|(file, line)| !file.is_empty() && !line.is_empty() && line.bytes().all(|b| b.is_ascii_digit()))
}

fn run(args: &[String]) -> Result<(), Fail> {
    match args.first().map(String::as_str) {
        Some("render") => cmd_render::run(&args[1..]),
        Some("sheet") => cmd_sheet::run(&args[1..]),
        Some("emulate") => cmd_emulate::run(&args[1..]),
        Some("compare") => cmd_compare::run(&args[1..]),
        Some("bake") => cmd_bake::run(&args[1..]),
        Some("-h") | Some("--help") | Some("help") => {
            println!("{USAGE}");
            Ok(())
        }
        Some(other) => Err(Fail(format!("unknown command \"{other}\"\n{USAGE}"))),
        None => Err(Fail(USAGE.to_string())),
    }
}
