//! Options shared by the commands that render, and rendering with progress.

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};
use lensray::{Scalar, Scene};
use lensray_host::{render_image, Image, MAX_SIDE};

use crate::Fail;

/// Options shared by the commands that render.
#[derive(Default)]
pub(crate) struct RenderOpts {
    pub(crate) positional: Vec<String>,
    pub(crate) out: Option<PathBuf>,
    pub(crate) width: Option<u32>,
    pub(crate) height: Option<u32>,
    pub(crate) samples: Option<u32>,
    pub(crate) float: bool,
}

pub(crate) fn parse_u32(flag: &str, v: Option<&String>, lo: u32, hi: u32) -> Result<u32, Fail> {
    let v = v.ok_or_else(|| Fail(format!("{flag} needs a value")))?;
    let digits = v.strip_prefix(['-', '+']).unwrap_or(v);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(Fail(format!("{flag} {v}: not a whole number")));
    }
    // Any whole number out of range, however long, gets the range message.
    let n: u64 = if v.starts_with('-') {
        0
    } else {
        digits.parse().unwrap_or(u64::MAX)
    };
    if (v.starts_with('-') && digits.bytes().any(|b| b != b'0')) || n < lo as u64 || n > hi as u64 {
        return Err(Fail(format!("{flag} {v}: must be between {lo} and {hi}")));
    }
    Ok(n as u32)
}

pub(crate) fn parse_opts(args: &[String]) -> Result<RenderOpts, Fail> {
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
pub(crate) fn image_size(o: &RenderOpts, aspect_ratio: f64) -> Result<(u32, u32), Fail> {
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
pub(crate) fn render_with_progress<S: Scalar + Send + Sync>(
    scene: &Scene<S>,
    w: u32,
    h: u32,
    samples: Option<u32>,
) -> Image {
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
