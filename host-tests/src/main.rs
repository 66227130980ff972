//! `lensray`: the host simulator.
//!
//! ```text
//! lensray render SCENE [-o OUT] [--width W] [--height H] [--samples N] [--float]
//! ```
//!
//! Exit status: 0 on success, 2 on any error (bad scene, bad arguments,
//! unwritable output). Errors are one line on stderr: a scene error reads
//! `SCENE:LINE: message` (as compilers print, for editors to jump to), any
//! other `lensray: message`.

use std::process::ExitCode;

mod cmd_render;
mod opts;

pub(crate) const USAGE: &str = "usage:
  lensray render SCENE [-o OUT] [--width W] [--height H] [--samples N] [--float]

  render   renders a scene file to OUT (.bmp or .png; default: the scene's
           name with .bmp, in the current directory). --width defaults to 640,
           --height to round(width / aspect_ratio); --samples overrides the
           scene's `point`; --float renders with the f32 reference instead of
           Q16.16.";

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
        Some("-h") | Some("--help") | Some("help") => {
            println!("{USAGE}");
            Ok(())
        }
        Some(other) => Err(Fail(format!("unknown command \"{other}\"\n{USAGE}"))),
        None => Err(Fail(USAGE.to_string())),
    }
}
