//! Options shared by the commands that render, and rendering with progress.

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};
use lensray::{Scalar, Scene};
use lensray_host::{render_image_counted, Image, MAX_SIDE};

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
    /// `--adaptive on|off`: overrides the scene's `adaptive` statement.
    pub(crate) adaptive: Option<bool>,
    /// `--sampler independent|stratified`: overrides the scene's `sampler` statement.
    pub(crate) sampler: Option<lensray::sampler::Sampler>,
    /// `--passes DIR`: save each progressive pass there.
    pub(crate) passes: Option<PathBuf>,
    /// `--first-step N`: block side of the first progressive pass.
    pub(crate) first_step: Option<u32>,
    /// `--preview-samples N`: samples of the progressive preview (0: none).
    pub(crate) preview_samples: Option<u32>,
    /// `--panel rgb565`: the image as a 16-bit panel shows it.
    pub(crate) panel: Option<lensray_host::panel::PanelFormat>,
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
            "--adaptive" => {
                o.adaptive = Some(match it.next().map(String::as_str) {
                    Some("on") => true,
                    Some("off") => false,
                    Some(v) => return Err(Fail(format!("--adaptive {v}: must be on or off"))),
                    None => return Err(Fail("--adaptive needs a value: on or off".into())),
                })
            }
            "--sampler" => {
                use lensray::sampler::Sampler;
                o.sampler = Some(match it.next().map(String::as_str) {
                    Some("independent") => Sampler::Independent,
                    Some("stratified") => Sampler::Stratified,
                    Some(v) => return Err(Fail(format!("--sampler {v}: must be independent or stratified"))),
                    None => return Err(Fail("--sampler needs a value: independent or stratified".into())),
                })
            }
            "--passes" => o.passes = Some(PathBuf::from(it.next().ok_or("--passes needs a directory")?)),
            "--first-step" => {
                o.first_step = Some(parse_u32("--first-step", it.next(), 1, lensray::progressive::MAX_STEP)?)
            }
            "--preview-samples" => o.preview_samples = Some(parse_u32("--preview-samples", it.next(), 0, 65535)?),
            "--panel" => {
                let v = it.next().ok_or("--panel needs a value: rgb565")?;
                o.panel = Some(
                    lensray_host::panel::PanelFormat::parse(v)
                        .ok_or_else(|| Fail(format!("--panel {v}: unknown panel format; use rgb565")))?,
                );
            }
            s if s.starts_with('-') && s.len() > 1 => return Err(Fail(format!("unknown option \"{s}\""))),
            _ => o.positional.push(a.clone()),
        }
    }
    Ok(o)
}

/// Applies the options that change a loaded scene (`--adaptive`, `--sampler`).
pub(crate) fn apply_to_scene<S: Scalar>(o: &RenderOpts, scene: &mut Scene<S>) {
    if let Some(a) = o.adaptive {
        scene.camera.adaptive = a;
    }
    if let Some(s) = o.sampler {
        scene.camera.sampler = s;
    }
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
) -> (Image, u64) {
    let bar = ProgressBar::new(h as u64);
    bar.set_style(
        ProgressStyle::with_template("{spinner} rendering [{bar:40}] {pos}/{len} rows, {eta} left")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let tick = || bar.inc(1);
    let out = render_image_counted(scene, w, h, samples, &tick);
    bar.finish_and_clear();
    out
}

/// Renders progressively (`--passes DIR`), saving the display after each pass
/// as `DIR/pass-K.png` (K from 1) as soon as it is done; returns the final image.
pub(crate) fn render_passes_to<S: Scalar + Send + Sync>(
    scene: &Scene<S>,
    w: u32,
    h: u32,
    o: &RenderOpts,
    dir: &std::path::Path,
) -> Result<Image, Fail> {
    std::fs::create_dir_all(dir).map_err(|e| Fail(format!("{}: cannot create: {e}", dir.display())))?;
    let mut failed: Option<Fail> = None;
    let mut save = |i: usize, pass: &lensray::progressive::Pass, img: &Image| {
        if failed.is_some() {
            return;
        }
        let path = dir.join(format!("pass-{}.png", i + 1));
        let result = lensray_host::encode(img, lensray_host::Format::Png)
            .map_err(Fail)
            .and_then(|bytes| {
                lensray_host::write_atomic(&path, &bytes)
                    .map_err(|e| Fail(format!("{}: cannot write: {e}", path.display())))
            });
        match result {
            Ok(()) => eprintln!(
                "wrote {} ({}x{} blocks, {} samples)",
                path.display(),
                pass.step,
                pass.step,
                pass.samples
            ),
            Err(e) => failed = Some(e),
        }
    };
    let img = lensray_host::passes::render_passes(
        scene,
        w,
        h,
        o.samples,
        o.first_step.unwrap_or(8),
        o.preview_samples.unwrap_or(1),
        &mut save,
    );
    match failed {
        Some(e) => Err(e),
        None => Ok(img),
    }
}
