//! Random-scene sweeps: every generated scene (see [`lensray_testkit::scenegen`])
//! rendered in Q16.16 and in f32, and the distribution of their differences.
//!
//! The f32 renderer matches an independent float64 evaluation on most
//! pixels ([`truth_sides`] says where it does not), so a scene's PSNR here
//! is mostly the cost of fixed point. Lens scenes take a fixed number
//! of samples (16) and adaptive sampling off: the sweep measures the number
//! type, not the sampler's stopping rule.

use std::fmt;

use crate::{render_both, Diff, LineErrors};
use lensray_testkit::scenegen::{generate_with, Camera, Options};

/// Lens samples a pixel of a lens scene takes in a sweep.
pub const LENS_SAMPLES: u32 = 16;

/// One scene's Q16.16-against-f32 measures.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneResult {
    /// The generator's seed.
    pub seed: u64,
    /// Whether the camera has a lens.
    pub lens: bool,
    /// PSNR in dB (infinite for identical images).
    pub psnr: f64,
    /// Share of pixels with every channel within 2 levels.
    pub within2: f64,
    /// Largest mean error of any row or column, in levels.
    pub worst_line: f64,
}

impl SceneResult {
    /// Whether the scene meets the floors: `min_psnr` dB, `min_within2` of
    /// its pixels within 2 levels, no row or column worse than `max_line` levels.
    pub fn meets(&self, min_psnr: f64, min_within2: f64, max_line: f64) -> bool {
        self.psnr >= min_psnr && self.within2 >= min_within2 && self.worst_line <= max_line
    }

    /// The scene's name: `seed N` with its camera (`pinhole`/`lens`).
    pub fn name(&self) -> String {
        format!("seed {} ({})", self.seed, if self.lens { "lens" } else { "pinhole" })
    }
}

/// The scene text of a seed under the camera choice.
pub fn scene_text(seed: u64, camera: Camera) -> String {
    generate_with(
        seed,
        &Options {
            camera,
            ..Options::default()
        },
    )
}

/// Renders one scene text in both number types at `width` × `height`.
///
/// # Panics
///
/// If the text does not parse (the generator's scenes always do).
pub fn measure(text: &str, seed: u64, width: u32, height: u32) -> SceneResult {
    let (fixed, float) = crate::both_unadaptive(text);
    let lens = fixed.camera.radius > 0.0;
    let samples = lens.then_some(LENS_SAMPLES);
    let (a, b) = render_both(&fixed, &float, width, height, samples);
    let diff = Diff::of(&a, &b).expect("same size");
    let lines = LineErrors::of(&a, &b).expect("same size");
    SceneResult {
        seed,
        lens,
        psnr: diff.psnr,
        within2: diff.within[1],
        worst_line: lines.worst_row.1.max(lines.worst_col.1),
    }
}

/// Sweeps the seeds `seeds` under one camera choice.
pub fn run(seeds: impl IntoIterator<Item = u64>, camera: Camera, width: u32, height: u32) -> Vec<SceneResult> {
    seeds
        .into_iter()
        .map(|seed| measure(&scene_text(seed, camera), seed, width, height))
        .collect()
}

/// The distribution of a sweep's results.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Scenes measured.
    pub count: usize,
    /// Lowest, 10th percentile and median PSNR (dB).
    pub min: f64,
    /// 10th percentile PSNR.
    pub p10: f64,
    /// Median PSNR.
    pub median: f64,
    /// Smallest share of pixels within 2 levels of any scene, and the mean share.
    pub min_within2: f64,
    /// Mean share of pixels within 2 levels.
    pub mean_within2: f64,
    /// Largest row or column mean error of any scene (levels).
    pub worst_line: f64,
    /// The worst scenes by PSNR, worst first (at most 5).
    pub worst: Vec<SceneResult>,
}

impl Summary {
    /// Summarises results (at least one).
    pub fn of(results: &[SceneResult]) -> Summary {
        let mut by_psnr: Vec<&SceneResult> = results.iter().collect();
        by_psnr.sort_by(|a, b| a.psnr.total_cmp(&b.psnr));
        let n = by_psnr.len();
        let at = |q: f64| by_psnr[((n - 1) as f64 * q).round() as usize].psnr;
        Summary {
            count: n,
            min: at(0.0),
            p10: at(0.1),
            median: at(0.5),
            min_within2: results.iter().map(|r| r.within2).fold(1.0, f64::min),
            mean_within2: results.iter().map(|r| r.within2).sum::<f64>() / n as f64,
            worst_line: results.iter().map(|r| r.worst_line).fold(0.0, f64::max),
            worst: by_psnr.iter().take(5).map(|r| (*r).clone()).collect(),
        }
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} scenes: PSNR min {:.1} dB, p10 {:.1}, median {:.1}; within 2 levels min {:.3} %, mean {:.3} %; worst row/column {:.2} levels",
            self.count,
            self.min,
            self.p10,
            self.median,
            self.min_within2 * 100.0,
            self.mean_within2 * 100.0,
            self.worst_line
        )?;
        write!(f, "worst:")?;
        for r in &self.worst {
            write!(
                f,
                " {} {:.1} dB {:.2} % line {:.1};",
                r.name(),
                r.psnr,
                r.within2 * 100.0,
                r.worst_line
            )?;
        }
        Ok(())
    }
}

/// Which number type float64 (`crate::reference64`) sides with where a
/// pinhole scene's Q16.16 and f32 pixels differ by more than 2 levels at
/// `width` × `height`: (Q16.16 within 2 levels of f64 and f32 not, f32 and
/// not Q16.16, neither or both). A sweep's failure with most pixels on
/// Q16.16's side is the reference's error, not fixed point's.
///
/// # Panics
///
/// If the text does not parse.
pub fn truth_sides(text: &str, width: u32, height: u32) -> (u32, u32, u32) {
    use embedded_graphics::pixelcolor::RgbColor;
    let (fixed, float) = crate::both_unadaptive(text);
    let s64 = crate::reference64::Scene64::parse(text);
    let (a, b) = render_both(&fixed, &float, width, height, None);
    let rgb = |p: embedded_graphics::pixelcolor::Rgb888| [p.r(), p.g(), p.b()];
    let near = |x: [u8; 3], y: [u8; 3]| (0..3).all(|k| x[k].abs_diff(y[k]) <= 2);
    let mut sides = (0, 0, 0);
    for (i, (&pa, &pb)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        let (q, f) = (rgb(pa), rgb(pb));
        if near(q, f) {
            continue;
        }
        let (c, r) = (i as u32 % width, i as u32 / width);
        let want = s64
            .pixel(c, r, width, height)
            .rgb
            .map(|x| x.clamp(0.0, 255.0).round() as u8);
        match (near(q, want), near(f, want)) {
            (true, false) => sides.0 += 1,
            (false, true) => sides.1 += 1,
            _ => sides.2 += 1,
        }
    }
    sides
}
