//! `lensray`: the host simulator.
//!
//! ```text
//! lensray render SCENE [-o OUT] [--width W] [--height H] [--samples N] [--float]
//! ```
//!
//! Exit status: 0 on success, 2 on any error (bad scene, bad arguments,
//! unwritable output). Errors are one line on stderr; a scene error reads
//! `SCENE:LINE: message`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use indicatif::{ProgressBar, ProgressStyle};
use lensray::{Scalar, Scene, I16F16};
use lensray_host::{encode, load_scene, render_image, write_atomic, Format, Image, MAX_SIDE};

const USAGE: &str = "usage:
  lensray render SCENE [-o OUT] [--width W] [--height H] [--samples N] [--float]

  render   renders a scene file to OUT (.bmp or .png; default: the scene's
           name with .bmp, in the current directory). --width defaults to 640,
           --height to round(width / aspect_ratio); --samples overrides the
           scene's `point`; --float renders with the f32 reference instead of
           Q16.16.";

/// A one-line error for the user; exit status 2.
struct Fail(String);

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
        Some("render") => cmd_render(&args[1..]),
        Some("-h") | Some("--help") | Some("help") => {
            println!("{USAGE}");
            Ok(())
        }
        Some(other) => Err(Fail(format!("unknown command \"{other}\"\n{USAGE}"))),
        None => Err(Fail(USAGE.to_string())),
    }
}

/// Options shared by the commands that render.
#[derive(Default)]
struct RenderOpts {
    positional: Vec<String>,
    out: Option<PathBuf>,
    width: Option<u32>,
    height: Option<u32>,
    samples: Option<u32>,
    float: bool,
}

fn parse_u32(flag: &str, v: Option<&String>, lo: u32, hi: u32) -> Result<u32, Fail> {
    let v = v.ok_or_else(|| Fail(format!("{flag} needs a value")))?;
    let n: u64 = v.parse().map_err(|_| Fail(format!("{flag} {v}: not a whole number")))?;
    if n < lo as u64 || n > hi as u64 {
        return Err(Fail(format!("{flag} {v}: must be between {lo} and {hi}")));
    }
    Ok(n as u32)
}

fn parse_opts(args: &[String]) -> Result<RenderOpts, Fail> {
    let mut o = RenderOpts::default();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "-o" | "--output" => o.out = Some(PathBuf::from(it.next().ok_or("-o needs a file name")?)),
            "--width" => o.width = Some(parse_u32("--width", it.next(), 1, MAX_SIDE)?),
            "--height" => o.height = Some(parse_u32("--height", it.next(), 1, MAX_SIDE)?),
            "--samples" => o.samples = Some(parse_u32("--samples", it.next(), 1, 65535)?),
            "--float" => o.float = true,
            s if s.starts_with('-') && s.len() > 1 => return Err(Fail(format!("unknown option \"{s}\""))),
            _ => o.positional.push(a.clone()),
        }
    }
    Ok(o)
}

/// Image size: `--width` (640) and `--height` (width / aspect_ratio).
fn image_size(o: &RenderOpts, aspect_ratio: f64) -> Result<(u32, u32), Fail> {
    let w = o.width.unwrap_or(640);
    let h = match o.height {
        Some(h) => h,
        None => {
            let h = (w as f64 / aspect_ratio).round();
            if !(1.0..=MAX_SIDE as f64).contains(&h) {
                return Err(Fail(format!(
                    "height {h} from width {w} / aspect_ratio {aspect_ratio} must be between 1 and {MAX_SIDE}; give --height"
                )));
            }
            h as u32
        }
    };
    Ok((w, h))
}

/// Renders with a progress bar on stderr (hidden when it is not a terminal).
fn render_with_progress<S: Scalar + Send + Sync>(scene: &Scene<S>, w: u32, h: u32, samples: Option<u32>) -> Image {
    let bar = ProgressBar::new(h as u64);
    bar.set_style(
        ProgressStyle::with_template("{spinner} rendering [{bar:40}] {pos}/{len} rows, {eta} left")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let tick = || bar.inc(1);
    let img = render_image(scene, w, h, samples, &tick);
    bar.finish_and_clear();
    img
}

fn cmd_render(args: &[String]) -> Result<(), Fail> {
    let o = parse_opts(args)?;
    let [scene_path] = o.positional.as_slice() else {
        return Err(Fail(format!("render takes one scene file\n{USAGE}")));
    };
    let scene_path = Path::new(scene_path);
    let out = match &o.out {
        Some(p) => p.clone(),
        None => {
            let stem = scene_path.file_stem().ok_or("the scene path has no file name")?;
            PathBuf::from(stem).with_extension("bmp")
        }
    };
    let format = Format::of(&out).ok_or_else(|| Fail(format!("{}: output must end in .bmp or .png", out.display())))?;
    if out.is_dir() {
        return Err(Fail(format!("{}: is a directory", out.display())));
    }
    let (img, kind) = if o.float {
        let scene = load_scene::<f32>(scene_path)?;
        let (w, h) = image_size(&o, scene.camera.aspect_ratio)?;
        (render_with_progress(&scene, w, h, o.samples), f32::NAME)
    } else {
        let scene = load_scene::<I16F16>(scene_path)?;
        let (w, h) = image_size(&o, scene.camera.aspect_ratio)?;
        (render_with_progress(&scene, w, h, o.samples), I16F16::NAME)
    };
    let bytes = encode(&img, format)?;
    write_atomic(&out, &bytes).map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())))?;
    eprintln!("wrote {} ({}x{}, {kind})", out.display(), img.width, img.height);
    Ok(())
}
