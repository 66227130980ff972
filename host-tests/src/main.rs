//! `lensray`: the host simulator.
//!
//! ```text
//! lensray render SCENE [-o OUT] [--width W] [--height H] [--samples N] [--float]
//! lensray compare SCENE [--width W] [--height H] [--samples N] [--diff OUT]
//! lensray compare A.bmp B.bmp [--diff OUT]
//! ```
//!
//! Exit status: 0 on success, 2 on any error (bad scene, bad arguments,
//! unwritable output). Errors are one line on stderr; a scene error reads
//! `SCENE:LINE: message`.

use std::process::ExitCode;

mod cmd_compare;
mod cmd_render;
mod opts;

pub(crate) const USAGE: &str = "usage:
  lensray render SCENE [-o OUT] [--width W] [--height H] [--samples N] [--float]
  lensray compare SCENE [--width W] [--height H] [--samples N] [--diff OUT]
  lensray compare A B [--diff OUT]

  render   renders a scene file to OUT (.bmp or .png; default: the scene's
           name with .bmp, in the current directory). --width defaults to 640,
           --height to round(width / aspect_ratio); --samples overrides the
           scene's `point`; --float renders with the f32 reference instead of
           Q16.16.
  compare  renders a scene with Q16.16 and with the f32 reference (same size,
           same samples; sizes as for render), or reads two images (.bmp or
           .png), and prints PSNR, mean and max error, the share of pixels
           within 1, 2 and 8 levels, and the worst row and column. --diff
           writes the error as a heat map (.png or .bmp): black where equal,
           brighter where worse, white from 8 levels.";

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
            eprintln!("lensray: {msg}");
            ExitCode::from(2)
        }
    }
}

fn run(args: &[String]) -> Result<(), Fail> {
    match args.first().map(String::as_str) {
        Some("render") => cmd_render::run(&args[1..]),
        Some("compare") => cmd_compare::run(&args[1..]),
        Some("-h") | Some("--help") | Some("help") => {
            println!("{USAGE}");
            Ok(())
        }
        Some(other) => Err(Fail(format!("unknown command \"{other}\"\n{USAGE}"))),
        None => Err(Fail(USAGE.to_string())),
    }
}
