//! Sampler quality against the truth: renders measured against converged
//! references (the same scene at many lens samples, f32), with the rays
//! each render cast.
//!
//! References are expensive, so they are rendered once and cached as PNG
//! under `target/converged/`, named by a hash of the scene text, the size,
//! the sample count and the sampler (a changed scene gets a new reference).

use std::path::{Path, PathBuf};

use lensray::Sampler;
use lensray::{Scalar, Scene, I16F16};

use crate::{decode_image, encode, render_image_counted, write_atomic, Diff, Format, Image};

/// Bumped when the renderer's converged image changes meaning (invalidates the cache).
const CACHE_VERSION: u32 = 1;

/// One render's quality: PSNR against the reference and mean lens rays a pixel.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Point {
    /// PSNR against the reference, dB.
    pub psnr: f64,
    /// Mean lens rays cast a pixel.
    pub rays: f64,
}

/// How to render a scene for a measurement.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Setting {
    /// Lens samples a pixel (the most, with adaptive sampling).
    pub samples: u32,
    /// The lens sampler.
    pub sampler: Sampler,
    /// Adaptive sampling on or off.
    pub adaptive: bool,
}

impl Setting {
    /// What a scene renders with by default: stratified, adaptive, `point` at most.
    pub fn default_render(point: u32) -> Self {
        Setting {
            samples: point,
            sampler: Sampler::Stratified,
            adaptive: true,
        }
    }

    /// The floor's yardstick: `samples` independent samples in every pixel.
    pub fn independent(samples: u32) -> Self {
        Setting {
            samples,
            sampler: Sampler::Independent,
            adaptive: false,
        }
    }
}

/// Renders `text` (Q16.16 unless `float`) at `w`×`h` with `setting`; the
/// image and the mean rays a pixel.
pub fn render_text(text: &str, w: u32, h: u32, setting: Setting, float: bool) -> Result<(Image, f64), String> {
    fn go<S: Scalar + Send + Sync>(text: &str, w: u32, h: u32, s: Setting) -> Result<(Image, f64), String> {
        let mut scene = Scene::<S>::parse(text).map_err(|e| e.to_string())?;
        scene.camera.sampler = s.sampler;
        scene.camera.adaptive = s.adaptive;
        let (img, rays) = render_image_counted(&scene, w, h, Some(s.samples), &|| {});
        Ok((img, rays as f64 / (w as f64 * h as f64)))
    }
    if float {
        go::<f32>(text, w, h, setting)
    } else {
        go::<I16F16>(text, w, h, setting)
    }
}

/// FNV-1a, for cache names.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    })
}

/// The workspace's `target/converged/`.
pub fn cache_dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
    target.join("converged")
}

/// The converged reference of `text` at `w`×`h`: f32, `samples` lens samples
/// of `sampler`, not adaptive; from the cache when it is there.
pub fn reference(text: &str, w: u32, h: u32, samples: u32, sampler: Sampler) -> Result<Image, String> {
    // `point` and `adaptive` do not change a reference (its samples are
    // given, every one cast): left out of the key, so variants share it.
    let stripped: String = text
        .lines()
        .filter(|l| !matches!(l.split_whitespace().next(), Some("point" | "adaptive")))
        .collect::<Vec<_>>()
        .join("\n");
    let key = format!("{CACHE_VERSION}|{w}x{h}|{samples}|{sampler:?}|{stripped}");
    let path = cache_dir().join(format!(
        "{:016x}-{w}x{h}-{samples}-{sampler:?}.png",
        fnv(key.as_bytes())
    ));
    if let Ok(bytes) = std::fs::read(&path) {
        if let Ok(img) = decode_image(&bytes) {
            return Ok(img);
        }
    }
    let setting = Setting {
        samples,
        sampler,
        adaptive: false,
    };
    let (img, _) = render_text(text, w, h, setting, true)?;
    std::fs::create_dir_all(cache_dir()).map_err(|e| e.to_string())?;
    write_atomic(&path, &encode(&img, Format::Png)?).map_err(|e| e.to_string())?;
    Ok(img)
}

/// PSNR of a render of `text` with `setting` (Q16.16) against `reference`, and its rays.
pub fn measure(text: &str, reference: &Image, setting: Setting) -> Result<Point, String> {
    let (img, rays) = render_text(text, reference.width, reference.height, setting, false)?;
    let psnr = Diff::of(&img, reference).ok_or("sizes differ")?.psnr;
    Ok(Point { psnr, rays })
}

/// A plot's PSNR axis, from the least finite value to the largest, each
/// rounded out to 5 dB; `None` where every render is exact (infinite PSNR,
/// nothing to scale). Exact renders are left out of the range, so that one
/// does not stretch the axis to infinity (a plot draws them at its top).
pub fn psnr_axis(psnrs: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = psnrs
        .into_iter()
        .filter(|p| p.is_finite())
        .fold(None, |acc: Option<(f64, f64)>, p| {
            Some(acc.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))))
        })?;
    let (lo, hi) = ((lo / 5.0).floor() * 5.0, (hi / 5.0).ceil() * 5.0);
    // A flat curve still gets a 5 dB axis.
    Some((lo, if hi > lo { hi } else { lo + 5.0 }))
}

/// `text` with its `point` statement replaced by `point N` (first): the same
/// scene at another sample count (campaigns at every `point`).
pub fn with_point(text: &str, point: u32) -> String {
    std::iter::once(format!("point {point}"))
        .chain(
            text.lines()
                .filter(|l| l.split_whitespace().next() != Some("point"))
                .map(str::to_string),
        )
        .collect::<Vec<_>>()
        .join("\n")
}

/// A diagnosis example's first arguments SEED WIDTH (`args` as
/// `std::env::args` gives them): SEED, the generated lens scene of SEED, and
/// the frame's width and height (WIDTH × 3/4 WIDTH). SEED may be a scene
/// file's path instead (a mutant, a still life): its text, and seed 0.
///
/// # Panics
///
/// Where SEED is neither a number nor a readable file, or WIDTH is missing
/// or not a number (a diagnosis tool's usage).
pub fn seed_frame(args: &[String]) -> (u64, String, u32, u32) {
    let w: u32 = args[2].parse().expect("WIDTH");
    let Ok(seed) = args[1].parse::<u64>() else {
        let text = std::fs::read_to_string(&args[1]).expect("SEED or a scene file");
        return (0, text, w, w * 3 / 4);
    };
    (seed, lensray_testkit::scenegen::generate_lens(seed), w, w * 3 / 4)
}

#[cfg(test)]
mod tests {
    use super::psnr_axis;

    #[test]
    fn the_psnr_axis_spans_the_finite_values_rounded_out_to_5_db() {
        assert_eq!(psnr_axis([31.2, 44.9, 38.0]), Some((30.0, 45.0)));
        // An exact render (infinite PSNR) does not stretch the axis.
        assert_eq!(psnr_axis([f64::INFINITY, 52.1, 47.3]), Some((45.0, 55.0)));
        // One value, or values on a 5 dB mark, still give an axis 5 dB tall.
        assert_eq!(psnr_axis([40.0]), Some((40.0, 45.0)));
        // Every render exact: nothing to scale.
        assert_eq!(psnr_axis([f64::INFINITY; 3]), None);
        assert_eq!(psnr_axis([]), None);
    }
}
