//! Options shared by the commands that render, and rendering with progress.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use lensray::{Scalar, Scene};
use lensray_host::panel::PanelFormat;
use lensray_host::{render_image_counted, Image, MAX_SIDE};

use crate::Fail;

/// Most lens samples a pixel the command line takes.
const MAX_SAMPLES: u32 = 65535;

/// Image size and lens samples: every command that renders.
#[derive(Args, Clone, Debug, Default)]
pub(crate) struct Size {
    /// Image width in pixels (1 to 8192)
    #[arg(long, value_name = "W", value_parser = whole(1, MAX_SIDE))]
    pub(crate) width: Option<u32>,
    /// Image height in pixels (1 to 8192) [default: width / the scene's aspect_ratio, rounded]
    #[arg(long, value_name = "H", value_parser = whole(1, MAX_SIDE))]
    pub(crate) height: Option<u32>,
    /// Lens samples a pixel (1 to 65535) [default: the scene's `point`]
    #[arg(long, value_name = "N", value_parser = whole(1, MAX_SAMPLES))]
    pub(crate) samples: Option<u32>,
}

/// What the command line may change in a loaded scene's camera.
#[derive(Args, Clone, Debug, Default)]
pub(crate) struct Sampling {
    /// Overrides the scene's `adaptive`: a pixel stops taking lens samples once its mean is settled
    #[arg(long, value_name = "on|off")]
    pub(crate) adaptive: Option<OnOff>,
    /// Overrides the scene's `sampler`
    #[arg(long, value_name = "SAMPLER")]
    pub(crate) sampler: Option<SamplerName>,
}

/// `on` or `off`, as the scene format spells a switch.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OnOff {
    On,
    Off,
}

/// The lens samplers, by their scene-format names.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SamplerName {
    /// Each lens sample drawn on its own
    Independent,
    /// Lens samples spread over strata of the aperture
    Stratified,
}

/// `--panel`: a panel format by name (`PanelFormat::parse`).
pub(crate) fn panel(name: &str) -> Result<PanelFormat, String> {
    PanelFormat::parse(name).ok_or_else(|| "unknown panel format; use rgb565".to_string())
}

/// A parser of whole numbers in `lo..=hi` whose messages name the limits:
/// "not a whole number", "must be between LO and HI" (for any whole number
/// out of range, however long or negative).
pub(crate) fn whole(lo: u32, hi: u32) -> impl Fn(&str) -> Result<u32, String> + Clone + Send + Sync + 'static {
    move |v: &str| {
        let digits = v.strip_prefix(['-', '+']).unwrap_or(v);
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err("not a whole number".into());
        }
        let n: u64 = if v.starts_with('-') {
            0
        } else {
            digits.parse().unwrap_or(u64::MAX)
        };
        if (v.starts_with('-') && digits.bytes().any(|b| b != b'0')) || n < lo as u64 || n > hi as u64 {
            return Err(format!("must be between {lo} and {hi}"));
        }
        Ok(n as u32)
    }
}

/// Applies the options that change a loaded scene (`--adaptive`, `--sampler`).
pub(crate) fn apply_to_scene<S: Scalar>(o: &Sampling, scene: &mut Scene<S>) {
    if let Some(a) = o.adaptive {
        scene.camera.adaptive = a == OnOff::On;
    }
    if let Some(s) = o.sampler {
        scene.camera.sampler = match s {
            SamplerName::Independent => lensray::Sampler::Independent,
            SamplerName::Stratified => lensray::Sampler::Stratified,
        };
    }
}

/// Image size: `--width` (`default_width`) and `--height` (width / aspect_ratio).
pub(crate) fn image_size(o: &Size, default_width: u32, aspect_ratio: f64) -> Result<(u32, u32), Fail> {
    let w = o.width.unwrap_or(default_width);
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

/// Progressive rendering as a display shows it (`render --passes`).
#[derive(Args, Clone, Debug)]
pub(crate) struct Passes {
    /// Renders progressively and saves the picture after each pass as DIR/pass-1.png ...: a
    /// preview of SxS blocks with P lens samples, then the same blocks and ever finer ones at the
    /// full samples; the last pass is the plain render, also written to the output
    #[arg(long, value_name = "DIR")]
    pub(crate) passes: Option<PathBuf>,
    /// Block side S of the first progressive pass (1 to 64)
    #[arg(long, value_name = "S", default_value_t = 8, value_parser = whole(1, lensray::progressive::MAX_STEP))]
    pub(crate) first_step: u32,
    /// Lens samples P of the progressive preview (0 to 65535; 0 for no preview)
    #[arg(long, value_name = "P", default_value_t = 1, value_parser = whole(0, MAX_SAMPLES))]
    pub(crate) preview_samples: u32,
}

/// Renders progressively (`--passes DIR`), saving the display after each pass
/// as `DIR/pass-K.png` (K from 1) as soon as it is done; returns the final image.
pub(crate) fn render_passes_to<S: Scalar + Send + Sync>(
    scene: &Scene<S>,
    w: u32,
    h: u32,
    samples: Option<u32>,
    o: &Passes,
    dir: &std::path::Path,
) -> Result<(Image, u64), Fail> {
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
    let out = lensray_host::passes::render_passes(scene, w, h, samples, o.first_step, o.preview_samples, &mut save);
    match failed {
        Some(e) => Err(e),
        None => Ok(out),
    }
}
