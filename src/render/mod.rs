//! Rendering: a pixel, a scanline, or a whole image into a `DrawTarget`.
//!
//! There is no frame buffer anywhere: [`Renderer::render_row`] fills one row
//! of colours, and [`render`] streams each row into the target with one
//! `fill_contiguous` call, computing pixels as the target consumes them.

use crate::camera::sampler::{PixelSamples, Sampler};
use crate::camera::{Camera, CameraSample};
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::render::cull::LensCones;
use crate::render::cut::LensCut;
use crate::render::defocus::Defocus;
use crate::render::footprint::BrightFootprints;
use crate::scene::Scene;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

pub mod cull;
pub mod cut;
pub mod defocus;
pub mod footprint;
pub mod lamps;
pub mod parts;
pub mod progressive;
pub mod scanline;
mod trace;

/// A scene and a camera set up for one image size: renders pixels.
///
/// Every pixel depends only on the scene, the image size and the pixel's own
/// position, so rows may be rendered in any order or in parallel.
#[derive(Clone, Debug)]
pub struct Renderer<'a, S: Scalar> {
    pub(crate) scene: &'a Scene<S>,
    pub(crate) camera: Camera<S>,
    /// The objects each lens ray can reach, precomputed for this camera.
    pub(crate) cones: LensCones<S>,
    pub(crate) samples: u32,
    pub(crate) adaptive: bool,
    pub(crate) sampler: Sampler,
    /// Pixels a bright object may reach through part of the lens: no early stop.
    pub(crate) bright: BrightFootprints,
    /// The lens rays' footprints, for box-filtered checkers (stratified sampler).
    pub(crate) defocus: Defocus<S>,
    /// The most samples an adaptive pixel that is not settled takes: the
    /// frame's ray budget spread over the pixels the survey found unsettled
    /// (see [`Renderer::pixel_rays`]), rounded down to whole rays (the
    /// shares take its fraction, [`Renderer::budget256`]).
    pub(crate) cap: u32,
    /// Lens rays the survey that set `cap` cast.
    pub(crate) survey_rays: u32,
    /// The mean spread (standard deviation of a sample, sixteenths of a
    /// level, summed over channels) of the survey's unsettled pixels at their
    /// pilot, raised by [`spread_margin`] (the micro:bit's: their sum over
    /// the unsettled count and its margin); 0 without a survey. An unsettled
    /// pixel's share of the budget beyond its pilot grows with its own
    /// spread over this one.
    pub(crate) spread: u32,
    /// The mean samples a pixel that settles at its plain pilot takes where
    /// the survey found budget to spare (rays left once the unsettled pixels
    /// take what the survey measured them to): such a pixel goes on to it (dithered
    /// to a power of two, [`dithered_cap`]) and stops there. 0: none.
    pub(crate) floor: u32,
    /// Below [`ADAPTIVE_MIN_POINT`] with gaps (see [`Renderer::gaps`]): the
    /// rays a pixel that casts any takes, in 256ths (dithered), from the gap
    /// survey: the budget the filled gaps leave. 0: 40 % of `point`. From
    /// it, with a survey: `cap` in 256ths before it was rounded down, which
    /// the unsettled pixels' shares take (see [`Renderer::share`]); 0: `cap`.
    pub(crate) budget256: u32,
    /// What the surveys chose, as bits. 0-7, below [`ADAPTIVE_MIN_POINT`]:
    /// anchors every this many columns (see [`scanline::fills`]; 0: no
    /// gaps); 8-15: the loose rule's levels the gaps fill by (0: the strict
    /// rule); 16, from [`ADAPTIVE_MIN_POINT`]: an unsettled pixel doubles its
    /// pilot at least (see [`Renderer::doubling`]); 17, below it with gaps:
    /// a pixel whose first rays are wide takes every sample (see [`Renderer::extends`]);
    /// 18, with a loose rule: it fills off checkers (see
    /// [`Renderer::gap_checkers`]; baked since format 15); 19: the doubling
    /// was measured; 20, from [`ADAPTIVE_MIN_POINT`]: pixels in lamps'
    /// footprints take [`adaptive_raised_pilot`] (see [`Renderer::raised_pilots`]);
    /// 21: adaptive pixels take lamps' parts of the lens (see [`lamps`]);
    /// 22: pixels in lamps' footprints take the plain pilot (see
    /// [`Renderer::plain_lamps`]); 23 to 30: lamp 0 to 7's part is off (see
    /// [`Renderer::lamp_parts_off`]); 31: the pilots being the whole
    /// budget, lamps' parts take the pilot's last ray (see
    /// [`Renderer::lamps_in_place`]); 23 to 31 baked since format 17.
    pub(crate) rules: u32,
    /// A plane that cuts the lens: a pixel's rays are weighed by their
    /// part's share of the lens (see [`cut`]).
    pub(crate) cut: LensCut,
    /// Lamps' discs on the lens: a pixel's rays are weighed by their part's
    /// share, and its pilot puts one in the lamp's (see [`lamps`]).
    pub(crate) lamps: lamps::LampParts,
}

/// The pilot of `point 48` to 95: one sample in each of 16 equal strata of
/// the lens (see [`crate::camera::sampler`]).
pub const ADAPTIVE_PILOT: u32 = 16;

/// The smallest pilot from `point` 20: 8 samples, two a quarter. A pilot of 4
/// (one sample a quarter) stops wrongly too often there: generated scenes of
/// `point` 28 to 31 fell up to 2.7 dB below `point` independent samples with it.
pub const ADAPTIVE_MIN_PILOT: u32 = 8;

/// The fewest samples for a pilot of [`ADAPTIVE_MIN_PILOT`]: below it 8 is
/// more than 40 % of them.
pub const ADAPTIVE_EIGHT_POINT: u32 = 5 * ADAPTIVE_MIN_PILOT / 2;

/// The pilot below [`ADAPTIVE_EIGHT_POINT`]: 4, one sample a quarter, the
/// only pilot within 40 % there (before, such pixels took every sample: 100 %).
/// Seeds 1000-1059, 3000-3059, 6000-6059 at 80x60 with `point` 10 to 19:
/// 27 of 33 meet both floors with it.
pub const ADAPTIVE_SMALL_PILOT: u32 = 4;

/// The fewest samples a pixel must have for adaptive sampling to start: below
/// it even the small pilot is more than 40 % of them (a pilot of 2 has no
/// quarters to compare).
pub const ADAPTIVE_MIN_POINT: u32 = 5 * ADAPTIVE_SMALL_PILOT / 2;

// Rows are filtered wherever there is a ray budget (a literal there: no import cycle).
const _: () = assert!(scanline::FILTER_MIN_POINT == ADAPTIVE_BUDGET_POINT);
const _: () = assert!(scanline::SMALL_PILOT_POINT == ADAPTIVE_EIGHT_POINT);

/// The fewest samples with a ray budget (adaptive on, below
/// [`ADAPTIVE_MIN_POINT`]: the pixels that cast rays share 40 % of `point`
/// a pixel, dithered between powers of two, and rows are filtered and have
/// gaps: see [`Renderer::gap_period`] and [`scanline::fills`]). Every
/// `point`: where some pixels cast no ray, 40 % of 1 or 2 is within reach.
/// Seeds 8600-8619, 8700-8719, 8800-8819 at 320×240 met both floors at
/// `point` 1 to 9 on 520 of 540 frames with gaps before extension (at 1 and 2 on 113 of 120,
/// where every pixel taking its samples meets none).
pub const ADAPTIVE_BUDGET_POINT: u32 = 1;

/// The pilot of a pixel with `samples` lens samples: the largest power of two
/// at most a third of them, and at least [`ADAPTIVE_MIN_PILOT`]; below
/// [`ADAPTIVE_EIGHT_POINT`], [`ADAPTIVE_SMALL_PILOT`]. A pixel
/// that stops after its pilot has seen the lens at a third to a sixth of
/// the full render's resolution: what reaches it through less of the lens
/// than one stratum is what the pilot may miss, an error at most √6 times
/// the standard error `samples` independent samples have on that pixel (a
/// share f < 1/P of the lens at brightness B: B f against B √(f/samples)).
/// A quarter (pilot 8 at `point 63`) missed such features on unseen scenes.
pub fn adaptive_pilot(samples: u32) -> u32 {
    if samples < ADAPTIVE_EIGHT_POINT {
        return ADAPTIVE_SMALL_PILOT;
    }
    let third = (samples / 3).max(1);
    (1u32 << (31 - third.leading_zeros())).max(ADAPTIVE_MIN_PILOT)
}

/// The pilot of a pixel a lamp may reach through part of the lens (see
/// [`BrightFootprints`]): twice [`adaptive_pilot`], so that it sees the lens
/// at half the full render's resolution, where that stays within 40 % of
/// `samples` (a pilot above the ray budget everywhere in a frame full of
/// lamps' footprints would spend more than the budget on every pixel).
pub fn adaptive_risk_pilot(samples: u32) -> u32 {
    let budget = (samples.saturating_mul(2) / 5).max(1);
    let budget = 1u32 << (31 - budget.leading_zeros());
    adaptive_raised_pilot(samples).min(budget.max(adaptive_pilot(samples)))
}

/// [`adaptive_risk_pilot`] before it is held within the ray budget: twice
/// [`adaptive_pilot`] (the pilot of twice the samples). A frame whose
/// survey finds these pilots within [`RAISED_PILOTS_SHARE`] of the budget
/// takes it (see [`Renderer::raised_pilots`]).
pub fn adaptive_raised_pilot(samples: u32) -> u32 {
    adaptive_pilot(samples.saturating_mul(2))
}

/// The most the pilots may cost, in fortieths of `point` a pixel, for a
/// frame's pixels in lamps' footprints to take [`adaptive_raised_pilot`]
/// (the budget, 16 fortieths, less room for the survey's rays): a lamp
/// through less than one stratum of a pilot is missed alike by every pixel
/// of its bokeh that misses it (`camera-features` at `point` 63: 9,650 such
/// pixels stopped at 16 rays, 40 levels dark on average, -2.10 dB against
/// the floor; raised, +1.07).
pub const RAISED_PILOTS_SHARE: u64 = 15;

/// The ray budget of an adaptive frame, a pixel: 40 % of `samples`; also
/// the cap of an unsettled pixel where no survey is taken (see [`survey_stride`]).
pub fn adaptive_limit(samples: u32) -> u32 {
    samples.saturating_mul(2) / 5
}

/// `cap` rounded to a power of two for pixel (`col`, `row`): the one below
/// it or twice that, the latter on a share of the pixels (an 8×8 ordered
/// dither, in 64ths, rounded down) that keeps their mean within `cap`.
/// Sixteenths (a 4×4 dither) left a budget of 2.61 rays at 2.5 (seed 9008).
/// Stratified samples gain at full blocks of the sequence: a pixel of 8
/// gained nothing from 3 samples more on generated scenes, one of 16 did.
pub fn dithered_cap(cap: u32, col: u32, row: u32) -> u32 {
    dithered_ratio(cap, 1, col, row)
}

/// The fixed budget of a pixel of `samples` from [`ADAPTIVE_BUDGET_POINT`]:
/// [`dithered_cap`] of 40 % of them exactly, not rounded down first (`point`
/// 7 took 2 rays, 29 %, where 40 % is 2.8).
pub fn dithered_budget(samples: u32, col: u32, row: u32) -> u32 {
    dithered_ratio(samples.saturating_mul(2), 5, col, row)
}

/// The range of a pixel's rays, in levels on some channel (the most less
/// the least, each clamped at white: rays all above it leave the pixel
/// white, and unclamped a blown-out frame counted most pixels wide), above which a pixel that casts with gaps goes on from its
/// budget to every sample (see [`Renderer::extends`]): at 2 or 4 rays a
/// pixel, such a pixel is where the frame's error is (a lamp or an edge
/// through part of the lens), and where its rays agree within 32 levels,
/// `point` independent samples are within a few levels too.
pub const EXTEND_LEVELS: u32 = 32;

/// The gap periods a frame may take (see [`Renderer::gap_period`]): anchors
/// every 2, 3 or 4 columns.
pub const GAP_PERIODS: core::ops::RangeInclusive<u32> = 2..=4;

/// The rays a pixel that casts should have where gaps can free them: a
/// stratified pair (the lens in halves), where one ray alone is no better
/// than an independent one. Seeds 8600-8619, 8700-8719, 8800-8819 at
/// 320x240 met both floors at `point` 2 on 57 of 60 frames with it, 48 with
/// one ray sought; at 3 to 9 on 3 more frames of 8600-8619 and 8800-8819.
pub const GAP_PAIR: u32 = 2;

/// A pixel as [`Renderer::pixel_far_wide`] renders it: its colour, rays,
/// class, and the powers of two at which its rays' range was wide.
type FarWide = (scanline::Fine, u32, u8, u32);

/// The share `filled` of `tested` less two binomial deviations (rounded
/// up), in 65536ths: what a survey may count on.
fn share_less_two_deviations(filled: u64, tested: u64) -> u64 {
    let var = (filled * (tested - filled)).div_ceil(tested);
    let sigma = crate::number::wide::isqrt_rem_u64(4 * var).0 + 1;
    (filled.saturating_sub(sigma) << 16) / tested
}

/// How far a gap filled is off its pixel as rendered, `mid`: the square of
/// the `line` between its anchors less `mid` on the channel where that is
/// most, in levels² (rounded down).
fn fill_error(line: scanline::Fine, mid: scanline::Fine) -> u64 {
    (0..3)
        .map(|i| (line.0[i] as u64).abs_diff(mid.0[i] as u64).pow(2) >> 16)
        .max()
        .unwrap_or(0)
}

/// Error, in levels² a fill, that the loose rule's fills on checkers may
/// have beyond twice its fills' off them (see [`Renderer::gap_checkers`]):
/// what a frame with no fill off checkers to compare may take.
pub const CHECKER_FILL_ERROR: u64 = 16;

/// The column of row `row`'s first anchor at `period`: a diagonal from row
/// to row, so that no column is a gap in every row.
#[inline]
pub fn gap_phase(row: u32, period: u32) -> u32 {
    row % period.max(1)
}

/// Pixel (`col`, `row`)'s rank, 0 to 63, in the 8×8 ordered (Bayer) dither:
/// each 2×2 level's digit from the bits of `col ^ row` and `row`, the
/// lowest bits the most significant (the 4×4 pattern is its rank / 4).
#[inline]
fn bayer_rank(col: u32, row: u32) -> u32 {
    let d = col ^ row;
    (0..3).fold(0, |r, k| 4 * r + 2 * (d >> k & 1) + (row >> k & 1))
}

/// [`dithered_cap`] of `num / den` (`den` 1, 5 or 256).
fn dithered_ratio(num: u32, den: u32, col: u32, row: u32) -> u32 {
    let whole = (num / den).max(1);
    let low = 1u32 << (31 - whole.leading_zeros());
    let rank = bayer_rank(col, row);
    // (num/den − low) / low of the pixels, in 64ths: low < 2^16, num < 2^24.
    if (rank + 1) * low * den <= 64 * num.saturating_sub(low * den) {
        2 * low
    } else {
        low
    }
}

/// The mean of the `seen` spreads (of the survey's unsettled pixels, see
/// [`Renderer::survey_spread`]) summing to `sum`, their squares to `squares`,
/// raised by [`SPREAD_MARGIN_SE`] standard errors of that mean: the frame's
/// unsettled pixels take shares P + (C − P) σ/σ̄ whose mean is C only where
/// their spreads' mean is the grid's, and a small grid's may be far off.
/// Rounded up; in integers.
pub fn spread_margin(seen: u64, sum: u64, squares: u128) -> u32 {
    let mean = sum.div_ceil(seen.max(1)) as u128;
    if seen < 2 || sum == 0 {
        return mean.min(u32::MAX as u128) as u32;
    }
    // SE / mean = √(D / seen) / sum, D = seen Σσ² − (Σσ)².
    let d = (seen as u128 * squares).saturating_sub(sum as u128 * sum as u128) / seen as u128;
    let root = crate::number::wide::isqrt_rem_u64(d.min(u64::MAX as u128) as u64).0 as u128 + 1;
    let raised = mean + (SPREAD_MARGIN_SE as u128 * mean * root).div_ceil(sum as u128);
    raised.min(u32::MAX as u128) as u32
}

/// How many standard errors of the survey's mean spread [`spread_margin`]
/// adds: the margin that the shares' rounding down to whole rays lent
/// before they took fractions (seed 6001 at `point` 18, 80x60, 70 grid
/// pixels: 41.3 % of `point` with fractions and no margin).
pub const SPREAD_MARGIN_SE: u64 = 3;

/// The unsettled pixels' cap from `cap256`, in 256ths: its whole rays, for
/// [`Renderer::cap`], and all of it, for [`Renderer::budget256`] (0 on the
/// micro:bit, whose shares take whole rays).
fn cap_parts(cap256: u32) -> (u32, u32) {
    (cap256 >> 8, if cfg!(feature = "no-spare-floor") { 0 } else { cap256 })
}

/// The fewest pixels a survey takes: below it (images under about 32×32)
/// its estimate of the frame's unsettled share is too coarse, and
/// unsettled pixels stop at [`adaptive_limit`].
pub const SURVEY_MIN_PIXELS: u32 = 64;

/// The most lens rays a survey's pilots may cast (2¹⁸): its cost stays a
/// set-up's, whatever the image size and `point` (8192×8192 at `point`
/// 65535 would otherwise survey a million pixels of 16,384 rays each; 640×480
/// at `point` 70 and 320×240 at 320 survey every 8th pixel as before).
pub const SURVEY_MAX_RAYS: u64 = 1 << 18;

/// The spacing of the survey's grid of pixels in an image of `cols` ×
/// `rows` at `samples` a pixel: 8 (a 1/64 of the pixels, each at its pilot:
/// at most a 64th of the frame's rays), or 4 where 8 gives fewer than
/// [`SURVEY_MIN_PIXELS`]; doubled from 8 while the grid's pilots could cast
/// more than [`SURVEY_MAX_RAYS`] (large images at a large `point`); `None`
/// where the grid would have fewer than [`SURVEY_MIN_PIXELS`].
pub fn survey_stride(cols: u32, rows: u32, samples: u32) -> Option<u32> {
    let count = |s: u32| (cols / s) as u64 * (rows / s) as u64;
    // A lamp's footprint doubles a pilot: the bound holds for any frame.
    let pilot = adaptive_risk_pilot(samples) as u64;
    if count(8) < SURVEY_MIN_PIXELS as u64 {
        return (count(4) >= SURVEY_MIN_PIXELS as u64 && count(4) * pilot <= SURVEY_MAX_RAYS).then_some(4);
    }
    let mut stride = 8u32;
    while count(stride) * pilot > SURVEY_MAX_RAYS {
        stride = stride.checked_mul(2)?;
        if count(stride) < SURVEY_MIN_PIXELS as u64 {
            return None;
        }
    }
    Some(stride)
}

/// The pixel a survey takes in cell (`j`, `k`) (row, column) of its grid of
/// spacing `s` (a power of two) on draw `draw` (0 but for the gap survey's
/// checks): at an offset hashed from the cell, not its centre, so that a
/// pattern periodic in the image (a far checker's moiré) cannot put every
/// spot on its bright or dark phase (seed 11260: the centres read 19.3 rays
/// a pixel where the frame casts 16.7).
pub fn survey_spot(j: u32, k: u32, s: u32, draw: u32) -> (u32, u32) {
    debug_assert!(s.is_power_of_two());
    let h = (j.wrapping_mul(0x9E37_79B9) ^ k.wrapping_mul(0x85EB_CA6B) ^ draw.wrapping_mul(0x27D4_EB2F))
        .wrapping_mul(0xC2B2_AE35);
    (k * s + (h >> 20 & (s - 1)), j * s + (h >> 8 & (s - 1)))
}

/// The variance of an adaptive pixel's mean, in 8-bit levels squared, below
/// which it stops whatever its samples, in sixteenths (1: a sixteenth of a
/// level²; at one level², pixels of faint noise stopped at the pilot summed
/// to more error than `point` independent samples leave, and at a quarter,
/// frames near 75 dB lost 1-level roundings to them: seed 8606, `point` 15,
/// -0.59 dB against `point` independent samples, -0.42 at a sixteenth).
const ADAPTIVE_VAR_SIXTEENTHS: u64 = 1;

/// The variance of an adaptive pixel's mean below which it stops, relative
/// to that of the independent full render (s²/`point`), in sixteenths (16:
/// the same; twice it let pilots of 8 stop at 1.5 times the independent
/// render's error on unseen scenes).
const ADAPTIVE_REL_SIXTEENTHS: u64 = 16;

/// How many times lower than the independent estimate s²/n the stratified
/// samples' variance is believed at most: the safety margin that makes a
/// pixel with much contrast among its samples go on even when its quarters
/// agree by chance.
const ADAPTIVE_MAX_GAIN: u64 = 8;

/// Bit 21 of [`Renderer::rules`]: adaptive pixels take lamps' parts of the
/// lens (see [`lamps`]), where the survey found room for their rays.
const LAMP_PARTS_RULE: u32 = 1 << 21;

/// Bit 22 of [`Renderer::rules`]: pixels in lamps' footprints take the
/// plain pilot, as others do, where the survey's rays in its lamps' parts of
/// the lens mostly showed what the pilots showed (see [`Renderer::surveyed`]).
const PLAIN_LAMPS_RULE: u32 = 1 << 22;

/// Bits 23 to 30 of [`Renderer::rules`]: lamp k's part of the lens (its
/// disc, k in the frame's order) is off at bit 23 + k.
const LAMP_OFF_SHIFT: u32 = 23;
/// Those bits, one a lamp.
const LAMP_OFF_RULES: u32 = ((1 << lamps::MAX_LAMPS) - 1) << LAMP_OFF_SHIFT;

/// Bit 31 of [`Renderer::rules`]: where the pilots are the whole budget
/// (no survey), a pixel's pilot draws its last ray in a lamp's part of the
/// lens if none of the others fell there (see [`Renderer::lamps_in_place`]).
const LAMP_IN_PLACE_RULE: u32 = 1 << 31;

/// `a · b` exactly, as its high and low 64-bit words (compared as a tuple).
fn mul_wide(a: u64, b: u64) -> (u64, u64) {
    let (a0, a1, b0, b1) = (a & 0xFFFF_FFFF, a >> 32, b & 0xFFFF_FFFF, b >> 32);
    let (p00, p01, p10) = (a0 * b0, a0 * b1, a1 * b0);
    // Below 3 · 2³²: no carry is lost.
    let mid = (p00 >> 32) + (p01 & 0xFFFF_FFFF) + (p10 & 0xFFFF_FFFF);
    (
        a1 * b1 + (p01 >> 32) + (p10 >> 32) + (mid >> 32),
        (p00 & 0xFFFF_FFFF) | (mid << 32),
    )
}

/// Running sums of a pixel's samples in 8-bit levels (unclamped: a lamp
/// brighter than white weighs what it adds to the mean), per channel, in
/// integers: the total square and the sums of four quarters of the samples
/// so far, each quarter a stratified set of its own (a block of 2ᵏ points of
/// the sequence).
#[derive(Default)]
struct LevelStats {
    /// At most 2¹⁵ samples below 2¹⁶ levels each: a u32 holds them (and
    /// leaves the Cortex-M0's stack room).
    quarter: [[u32; 3]; 4],
    sum_sq: [u64; 3],
}

impl LevelStats {
    /// Adds sample `k` (0-based) of a pixel whose next check is at `check` samples.
    fn add<S: Scalar>(&mut self, k: u32, check: u32, c: Vec3<S>) {
        let level = |x: S| x.to_level();
        // check is a power of two: k / (check / 4) by a shift (no divide on the M0).
        let shift = check.trailing_zeros().saturating_sub(2);
        let q = (k >> shift).min(3) as usize;
        let levels = [level(c.x), level(c.y), level(c.z)];
        for (i, l) in levels.into_iter().enumerate() {
            self.quarter[q][i] += l;
            // l < 2¹⁶: the square fits a u32 (no 64-bit multiply on the M0).
            self.sum_sq[i] += (l * l) as u64;
        }
    }

    /// `None` if the mean of the `n` samples so far (a power of two, at least
    /// 4) of a pixel of `full` samples is settled on every channel, else its
    /// samples' spread (at least 1). Its
    /// variance V is estimated from the spread of the four quarters' means,
    /// V_q = Σ(m_j − m)²/12, and taken as at least s²/(n G), s² the samples'
    /// variance and G = [`ADAPTIVE_MAX_GAIN`]; the pixel stops when V is at
    /// most one level² or at most twice s²/`full`, the variance of the
    /// independent full render. In integers, exactly, with h = n/4, Q the
    /// total and q_j the quarters' sums: 192 h² V_q = Σ(4 q_j − Q)² and
    /// n (n − 1) s² = n Σx² − Q².
    ///
    /// In u64 with one 128-bit comparison (u128 arithmetic inline took 2.4 KB
    /// of the Cortex-M0's flash): with Σq_j = Q, Σ(4 q_j − Q)² = 4 D,
    /// D = 4 Σq_j² − Q² <= 3 Q² (Q < 2³¹: n <= 2¹⁵ samples below 2¹⁶ levels).
    /// Not settled, it returns the samples' spread (see below).
    // Out of line: inlined into the firmware's `main` it grew the frame held
    // under every pixel (the Cortex-M0's stack).
    #[inline(never)]
    fn settled(&self, n: u32, full: u32) -> Option<u32> {
        const T: u64 = ADAPTIVE_VAR_SIXTEENTHS;
        const REL: u64 = ADAPTIVE_REL_SIXTEENTHS;
        const GAIN: u64 = ADAPTIVE_MAX_GAIN;
        // The divisions by 16 below are exact: n is a multiple of 4.
        let n32 = n;
        let (n, h, full) = (n as u64, (n / 4) as u64, full as u64);
        // n = 4h: 16 V_q <= T/16 · 192 h² reads D <= 3 T h², and 16 s²/(n G) <= T
        // reads spread <= G T n² (n − 1) / 16.
        let abs_d = 3 * T * h * h;
        let abs_s = GAIN * T * n * n * (n - 1) / 16;
        let rel_ok = full * 16 <= REL * n * GAIN;
        let (mut settled, mut var) = (true, 0u64);
        for i in 0..3 {
            let (mut total, mut squares) = (0u64, 0u64);
            for quarter in &self.quarter {
                let q = quarter[i] as u64;
                total += q;
                squares += q * q;
            }
            let d = 4 * squares - total * total;
            let spread = (n * self.sum_sq[i]).saturating_sub(total * total);
            var = var.saturating_add(spread);
            let absolute = d <= abs_d && spread <= abs_s;
            // 4 D · 16 full n (n − 1) <= REL spread · 192 h², over 64 h.
            settled &= absolute || (rel_ok && mul_wide(d, 4 * full * (4 * h - 1)) <= mul_wide(spread, 3 * REL * h));
        }
        // Not settled: the samples' spread √(Σ s²) over the channels, in
        // sixteenths of a level, 256 Σ s² = 256 Σ (n Σx² − Q²) / (n (n − 1))
        // (in u64, saturating: a 128-bit division and square root here cost
        // the M0 3.5 KB of flash; the shared integer square root).
        let var = if var >> 56 == 0 { var << 8 } else { u64::MAX };
        // n is 8 to 2¹⁶: n (n − 1) fits a u32.
        // The shared exact division: a plain u64 `/` brought the M0 runtime's 1 KB routine and a panic path.
        (!settled).then(|| {
            let per = crate::number::wide::div_rem_u64(var, (n32 * (n32 - 1)) as u64).0;
            (crate::number::wide::isqrt_rem_u64(per).0 as u32).max(1)
        })
    }

    /// Moves on to the next check at twice the samples: the four quarters
    /// become the first two, the next samples fill the other two.
    fn double(&mut self) {
        for i in 0..3 {
            self.quarter[0][i] += self.quarter[1][i];
            self.quarter[1][i] = self.quarter[2][i] + self.quarter[3][i];
            self.quarter[2][i] = 0;
            self.quarter[3][i] = 0;
        }
    }
}

impl<'a, S: Scalar> Renderer<'a, S> {
    /// A renderer for `cols` × `rows` pixels with the scene's own sample count.
    ///
    /// Each side is clamped to 1..=[`MAX_IMAGE_SIDE`](crate::camera::MAX_IMAGE_SIDE).
    ///
    /// # Panics
    ///
    /// Never: any scene [`Scene::parse`] accepts and any size.
    pub fn new(scene: &'a Scene<S>, cols: u32, rows: u32) -> Self {
        Self::unsurveyed(scene, cols, rows).surveyed()
    }

    /// [`Renderer::new`] with `samples` lens samples a pixel (clamped to
    /// 1..=65535) in place of the scene's where given: the same renderer as
    /// `Renderer::new(..).with_samples(n)`, with one set-up survey, not two.
    pub fn new_with_samples(scene: &'a Scene<S>, cols: u32, rows: u32, samples: Option<u32>) -> Self {
        let mut r = Self::unsurveyed(scene, cols, rows);
        if let Some(n) = samples {
            r.samples = n.clamp(1, 65535);
        }
        r.surveyed()
    }

    /// The renderer before its survey (see [`Renderer::surveyed`]).
    fn unsurveyed(scene: &'a Scene<S>, cols: u32, rows: u32) -> Self {
        let camera = Camera::new(&scene.camera, cols, rows);
        let bright = BrightFootprints::new(scene, camera.cols(), camera.rows());
        Renderer {
            scene,
            lamps: lamps::LampParts::new(scene, &bright, camera.cols(), camera.rows()),
            bright,
            camera,
            cones: LensCones::new(scene, scene.camera.lens_position, scene.camera.radius),
            samples: scene.camera.samples.max(1),
            adaptive: scene.camera.adaptive,
            sampler: scene.camera.sampler,
            defocus: Defocus::new(scene).with_far(&scene.camera, camera.cols()),
            cap: 0,
            survey_rays: 0,
            spread: 0,
            floor: 0,
            budget256: 0,
            rules: 0,
            cut: LensCut::new(scene, camera.aperture(), camera.cols(), camera.rows()),
        }
    }

    /// Sets [`Renderer::cap`] from a survey of the frame: a grid of pixels
    /// (see [`survey_stride`]) each takes its pilot and tells whether it
    /// settled there, else its spread. With S the pilots of the settled ones, U the
    /// unsettled ones among G surveyed of the frame's N pixels, and R the
    /// survey's rays, the cap C is the largest with N/G (S + U C) + R at
    /// most 40 % of `samples` a pixel (an unsettled pixel taking all of C
    /// bounds what it takes), at most `samples`: the budget settled pixels
    /// leave goes to the unsettled ones, also in lamps' footprints. Every
    /// pixel still depends only on its position (rows in any order, the
    /// progressive passes the same image). The unsettled pixels' mean spread
    /// sets how they share it (see [`Renderer::pixel_rays`]). Where the
    /// shares' sum leaves no room for [`Renderer::doubling`], the grid runs
    /// again under C with it and the rays it casts decide. Where C is
    /// `samples`, or at least two thirds of it on a grid of every 8th pixel
    /// or sparser where the pilot is 8 or more and the floor could rise by
    /// half of it, the grid runs again under C to measure what the
    /// unsettled pixels take, and what that leaves, with margins, sets
    /// [`Renderer::floor`] (capped, none left: the pass's rays lower C).
    /// Where the grid's rays in its lamps' parts of the lens mostly showed
    /// what the pilots showed, and the footprints' larger pilots are the
    /// whole budget there and leave a third of their pixels unsettled or
    /// more, the grid runs again with those pixels at the plain pilot
    /// ([`PLAIN_LAMPS_RULE`]; once: the second survey has no larger pilot).
    /// Else a lamp whose grid rays mostly showed what the pilots showed has
    /// its part off ([`LAMP_OFF_RULES`]), each lamp on its own.
    /// The grid takes a pixel of each cell at a hashed offset
    /// ([`survey_spot`]). Set-up only, in integers.
    fn surveyed(mut self) -> Self {
        self.clear_survey();
        self.survey_after(0)
    }

    /// [`Renderer::surveyed`]'s survey, after `prior` rays of an earlier one
    /// (counted in the budget; see [`PLAIN_LAMPS_RULE`]).
    fn survey_after(mut self, prior: u64) -> Self {
        let (cols, rows) = (self.camera.cols(), self.camera.rows());
        let stride = survey_stride(cols, rows, self.samples);
        if let (true, Some(s)) = (self.gaps(), stride) {
            return self.gap_surveyed(s);
        }
        let (true, Some(s), false) = (
            self.adaptive && self.samples >= ADAPTIVE_MIN_POINT,
            stride,
            self.camera.is_pinhole(),
        ) else {
            return self;
        };
        let grid = |s: u32| (0..rows / s).flat_map(move |j| (0..cols / s).map(move |k| survey_spot(j, k, s, 0)));
        // Pixels in lamps' footprints take the raised pilot where the grid's
        // pilots with it, the grid's share in footprints two binomial
        // deviations high, stay within RAISED_PILOTS_SHARE and SURVEY_MAX_RAYS.
        let (raised, risk) = (adaptive_raised_pilot(self.samples), adaptive_risk_pilot(self.samples));
        if !cfg!(feature = "no-spare-floor") && raised > risk && self.rules & PLAIN_LAMPS_RULE == 0 {
            let (risky, count) = grid(s).fold((0u64, 0u64), |(r, c), (x, y)| {
                (r + self.bright.at_risk(x, y) as u64, c + 1)
            });
            let var = (risky * (count - risky)).div_ceil(count.max(1));
            let high = (risky + 2 * crate::number::wide::isqrt_rem_u64(var).0 + 1).min(count);
            let pilots = high * raised as u64 + (count - high) * adaptive_pilot(self.samples) as u64;
            if risky > 0
                && 40 * pilots <= RAISED_PILOTS_SHARE * self.samples as u64 * count
                && pilots <= SURVEY_MAX_RAYS
            {
                self.rules = 1 << 20;
            }
        }
        let (bright, risk_pilot, plain_pilot) = (&self.bright, self.risk_pilot(), adaptive_pilot(self.samples));
        let pilot = |x, y| if bright.at_risk(x, y) { risk_pilot } else { plain_pilot };
        let (pilots, count) = grid(s).fold((0u64, 0u64), |(p, c), (x, y)| (p + pilot(x, y) as u64, c + 1));
        // Wherever the grid's pilots (no rays: lamps' footprints are known)
        // leave any of the budget: the survey costs a 64th of the pilots. Only
        // where they left a fifth, `point` 21 to 25 spent none of what the
        // pilots left (seed 9009, `point` 22: every pixel at 8, -0.56 dB
        // against `point` independent samples; surveyed, +2.37).
        // With the survey's own rays, the grid's pilots again over s² (a
        // frame of lamps' footprints whose pilot is 40 % of `point` cast 40.5 %).
        let survey = if cfg!(feature = "no-spare-floor") {
            0
        } else {
            pilots.div_ceil(s as u64 * s as u64)
        };
        let full = 5 * (pilots + survey) >= 2 * self.samples as u64 * count;
        if full {
            // No ray to spare for a glowing lamp's part: the pilot's last in it.
            if !cfg!(feature = "no-spare-floor") && self.lamps.any_glows() {
                self.rules |= LAMP_IN_PLACE_RULE;
            }
            return self;
        }
        #[cfg(test)]
        SURVEYS.with(|n| n.set(n.get() + 1));
        // Lamps' parts of the lens, measured with the rest (see [`lamps`]).
        if !self.lamps.is_empty() && self.rules & PLAIN_LAMPS_RULE == 0 {
            self.rules |= LAMP_PARTS_RULE;
        }
        let (mut settled_pilots, mut unsettled, mut rays, mut spreads) = (0u64, 0u64, prior, 0u64);
        // Their squares, for the margin on the shares (see [`spread_margin`]).
        let mut spreads_sq = 0u128;
        // Grid pixels at the footprints' larger pilot, all and unsettled.
        let (mut plain_settled, mut risky, mut risky_unsettled) = (0u64, 0u64, 0u64);
        // Grid pixels that cast a lamp's ray beyond their pilot, and that kept it, by lamp.
        let mut by_lamp = [(0u64, 0u64); lamps::MAX_LAMPS];
        // The unsettled pixels by spread, for the doubling they take (see [`Renderer::share`]).
        let mut by_spread = [[0u16; 64]; 2];
        for (x, y) in grid(s) {
            let pilot = pilot(x, y);
            risky += (pilot != plain_pilot) as u64;
            // Without a spread yet, the pixel stops at its pilot either way.
            let (_, n, spread, _, lamp) = self.pixel_rays_within(x, y, pilot);
            rays += n as u64;
            if let Some(l) = by_lamp.get_mut((lamp >> 2) as usize).filter(|_| lamp & 3 > 0) {
                *l = (l.0 + 1, l.1 + (lamp & 3 > 1) as u64);
            }
            if spread == 0 {
                settled_pilots += n as u64;
                plain_settled += (pilot == plain_pilot) as u64;
            } else {
                // A lamp's ray beyond the pilot (see [`lamps`]) comes on top of its share.
                settled_pilots += n.saturating_sub(pilot) as u64;
                unsettled += 1;
                risky_unsettled += (pilot != plain_pilot) as u64;
                spreads += spread as u64;
                spreads_sq += spread as u128 * spread as u128;
                if !cfg!(feature = "no-spare-floor") {
                    // Half-octaves of spread, plain and raised pilots apart.
                    let e = 31 - spread.leading_zeros();
                    let b = (2 * e + (e > 0 && spread >> (e - 1) & 1 == 1) as u32) as usize;
                    let k = (pilot != plain_pilot) as usize;
                    by_spread[k][b] = by_spread[k][b].saturating_add(1);
                }
            }
        }
        // A lamp whose grid rays mostly showed what the pilots showed is off:
        // the frame is better off without its rays (seed 11734, `point` 27,
        // a gilded sphere bright only by its bound: 1162 of 1200 grid pixels
        // cast one, none kept, -0.57 dB; 11754, 158 of 681 kept, -0.47 dB;
        // `camera-features` at 33, 56 of 61). Each lamp on its own: a
        // frame's false lamps outnumbered its bright ones, whose bokeh then
        // settled dark (host-tests/extra-scenes/mutant-lamps-judged-one-by-one.scene,
        // -0.71 dB against the floor with every part off). And by two
        // deviations: one unkept ray of one grid pixel turned a frame's every
        // part off (the mutant at `point` 10 of host-tests/extra-scenes/ at 23:
        // +0.27 -> +5.13 dB).
        let (mut off, mut on) = (0u32, false);
        let (mut lamps_cast, mut lamps_kept, mut dropped) = (0u64, 0u64, 0u64);
        for (k, &(cast, kept)) in by_lamp.iter().enumerate() {
            (lamps_cast, lamps_kept) = (lamps_cast + cast, lamps_kept + kept);
            // Fewer than half kept, by two binomial deviations at a half (√cast / 2 each).
            let short = cast.saturating_sub(2 * kept);
            if short * short > 4 * cast {
                off |= 1 << k;
                dropped += cast;
            } else {
                on |= cast > 0;
            }
        }
        // Nor are the frame's lamps' rays, mostly not kept, what the
        // footprints' larger pilots guard against where those pilots are
        // the whole budget there, the lamps' rays were cast on an eighth of
        // the footprints or more, and a third or more stayed unsettled: the
        // grid again with every pixel at the plain pilot, after the rays
        // cast so far (seed 11777, `point` 17 to 19 and 34 to 40: a sphere
        // bright only by its bound, -1.06 to -2.20 dB against the floor).
        // Where those pilots were within the budget, or settled their
        // pixels, they paid (without them seed 11734 at `point` 41 lost
        // 3.25 dB; 11835 at 36 to 40, 1 % unsettled, 3.0).
        if !cfg!(feature = "no-spare-floor")
            && 2 * lamps_kept < lamps_cast
            && risky > 0
            && 5 * risk_pilot >= 2 * self.samples
            && 8 * lamps_cast >= risky
            && 3 * risky_unsettled >= risky
        {
            self.clear_survey();
            self.rules = PLAIN_LAMPS_RULE;
            return self.survey_after(rays);
        }
        if on {
            self.rules |= off << LAMP_OFF_SHIFT;
        } else if off != 0 {
            self.rules &= !LAMP_PARTS_RULE;
        }
        // The rays of the lamps now off are not the frame's.
        (rays, settled_pilots) = (rays - dropped, settled_pilots - dropped);
        let seen = unsettled;
        // A margin of one binomial standard deviation of the count,
        // √(U (G − U) / G) rounded up, so that a frame with more unsettled
        // pixels than its survey saw stays within the budget.
        let var = (unsettled * (count - unsettled)).div_ceil(count.max(1));
        let root = crate::number::wide::isqrt_rem_u64(var).0;
        let sigma = root + (root * root < var) as u64;
        let pixels = cols as u128 * rows as u128;
        let unsettled = unsettled + sigma;
        // 5 (R + N/G (S + U C)) <= 2 samples N, times G: what R rays leave.
        let budget_after =
            |rays: u64| (2 * self.samples as u128 * pixels).saturating_sub(5 * rays as u128) * count as u128;
        let budget = budget_after(rays);
        let mut spent = 5 * settled_pilots as u128 * pixels;
        // An unsettled pixel takes at least its pilot: where C would fall
        // below the lamps' pilot, those pixels are spent at it and the others
        // share the rest under it (hand-near-focus at `point` 80, three
        // quarters of it in lamps' footprints, cast 40.5 %).
        let lamps_apart = !cfg!(feature = "no-spare-floor")
            && risky_unsettled > 0
            && budget.saturating_sub(spent) < 5 * unsettled as u128 * pixels * risk_pilot as u128;
        // The unsettled pixels that share C (margin included), those the survey saw, and C's most.
        let apart = if lamps_apart { risky_unsettled } else { 0 };
        let (sharing, seen_sharing) = (unsettled - apart, seen - apart);
        let most = if lamps_apart { risk_pilot - 1 } else { self.samples };
        spent += 5 * (apart * risk_pilot as u64) as u128 * pixels;
        // In 256ths: the shares take C's fraction (see [`Renderer::share`]).
        let cap_after = |rays: u64| match budget_after(rays).checked_sub(spent) {
            _ if sharing == 0 => most << 8,
            Some(left) => (256 * left / (5 * sharing as u128 * pixels)).min((most as u128) << 8) as u32,
            None => 0,
        };
        (self.cap, self.budget256) = cap_parts(cap_after(rays));
        if self.cap < plain_pilot {
            // No room for a lamp's ray beyond the pilot (seed 11679, `point`
            // 10, its pilots the whole budget: 40.3 % of `point` with them).
            self.rules &= !LAMP_PARTS_RULE;
        }
        self.survey_rays = rays as u32;
        self.spread = if cfg!(feature = "no-spare-floor") {
            spreads.div_ceil(unsettled.max(1)).min(u32::MAX as u64) as u32
        } else {
            spread_margin(seen, spreads, spreads_sq)
        };
        // Every share within `point` bounds what the unsettled pixels take.
        let mut doubling = self.cap == self.samples && !cfg!(feature = "no-spare-floor");
        if !cfg!(feature = "no-spare-floor") && self.cap < self.samples && seen > 0 {
            // An unsettled pixel doubles its pilot at least (see
            // [`Renderer::share`]) where the shares, spreads at their
            // half-octaves' middles and at most `point`, then sum to what the
            // survey gave them (C a pixel before rounding down): rays the
            // shares stopped at `point` leave (lamps' rims), not others'.
            let pilots = [plain_pilot, risk_pilot];
            let mut sum = 0u64;
            // Lamps' pixels spent at their pilot above are not summed again.
            let kinds = if lamps_apart { 1 } else { 2 };
            for (k, row) in by_spread.iter().enumerate().take(kinds) {
                for (b, &n) in row.iter().enumerate() {
                    // The half-octave's middle: 1.25 or 1.75 times 2^(b/2) (under 2^32).
                    let mid = ((1u64 << (b / 2)) * (5 + 2 * (b & 1) as u64) / 4) as u32;
                    sum += n as u64 * self.own_share256(self.cap, pilots[k], mid, true) as u64;
                }
            }
            // sum / (256 seen) <= left / (5 U N): the shares are in 256ths.
            let left = budget.saturating_sub(spent);
            doubling = sum as u128 * 5 * sharing as u128 * pixels <= 256 * left * seen_sharing as u128;
        }
        // The shares are each pixel's most: where their sum says no, the grid
        // rendered with the doubling says how many rays it takes, most pixels
        // settling before their share (seed 11260, `point` 46: 36.8 % of
        // `point` with it, -0.06 -> +0.28 dB against the floor). Where the cap
        // lets a pilot double, on grids of a 64th of the pixels or sparser:
        // the pass costs a pixel 1/s² of its rays.
        let doubles = self.cap >= 2 * plain_pilot && self.cap < self.samples;
        let measured = !cfg!(feature = "no-spare-floor") && !doubling && doubles && seen > 0 && s >= 8;
        let raised = self.rules & (1 << 20 | LAMP_PARTS_RULE | PLAIN_LAMPS_RULE | LAMP_OFF_RULES);
        if measured {
            self.rules = raised | 1 << 16;
            let (mut sum, mut squares) = (0u64, 0u64);
            for (x, y) in grid(s) {
                let n = self.pixel_rays_within(x, y, self.cap).1 as u64;
                sum += n;
                squares += n * n;
            }
            rays += sum;
            self.survey_rays = rays as u32;
            // Three deviations of the sum: √(G Σn² − (Σn)²) / √G.
            let var = (count * squares).saturating_sub(sum * sum).div_ceil(count);
            let dev = crate::number::wide::isqrt_rem_u64(var).0 + 1;
            // 5 (R + N/G (sum + 3 dev)) <= 2 samples N, times G.
            doubling = 5 * (sum + 3 * dev) as u128 * pixels <= budget_after(rays);
            if !doubling {
                // The pass's rays come out of the cap.
                (self.cap, self.budget256) = cap_parts(cap_after(rays));
            }
        }
        self.rules = raised | (doubling as u32) << 16 | (measured as u32) << 19;
        // Rays the unsettled pixels leave go to the pixels settled at the
        // plain pilot, as a floor (seeds 1042, 8232 cast 21 and 18 % of
        // `point` and missed by stopping early). Under a cap of two thirds
        // of `point` or more too, measured (seed 11557, `point` 43, cap 34:
        // 30.7 -> 35.8 % of `point`, +0.74 dB); under a lower cap the shares
        // spend the budget and the pass's rays came out of the cap (seed
        // 11568, cap 12 of 28: -0.26 dB), as they did under pilots of 4
        // (the stress scene `grazing`, `point` 16: Q16.16 lowered its cap
        // and f32 did not, a row 1.14 levels apart).
        let capped = self.cap < self.samples
            && 3 * self.cap >= 2 * self.samples
            && self.samples >= ADAPTIVE_EIGHT_POINT
            && s >= 8;
        if (self.cap == self.samples || capped) && plain_settled > 0 && !cfg!(feature = "no-spare-floor") {
            let plain = plain_pilot as u64;
            // Three deviations and three pixels more of those that take the floor.
            let var = (plain_settled * (count - plain_settled)).div_ceil(count);
            let takers = plain_settled + 3 * crate::number::wide::isqrt_rem_u64(var).0 + 3;
            let extra = |left: u128| left / (5 * takers as u128 * pixels);
            // The unsettled pixels' rays, high: every sample, three count
            // deviations and three pixels more (seed 8212: none of 70 surveyed,
            // 0.6 % of the frame, cast 40.3 %).
            let mut high = (unsettled + 2 * sigma + 3) * self.samples as u64;
            let mut rays = rays;
            // Or measured on the grid under the cap, where the budget holds
            // that pass at its most (pilots again, unsettled pixels at every
            // sample): most settle long before every sample (frames at 320x240
            // cast 26 to 35 % of `point`; seed 8714 32.2 % -> 37.2 %, +0.36 dB).
            let pass_most = settled_pilots + unsettled * self.samples as u64;
            // Capped, where the floor would rise by half a pilot even if every
            // unsettled pixel stopped at its pilot (a pass that found no floor
            // cost seeds 11579 and 11601 0.6 % of `point`).
            let worth = capped && {
                let best = budget_after(rays + pilots)
                    .saturating_sub(spent + 5 * ((unsettled + 2 * sigma + 3) * plain) as u128 * pixels);
                2 * extra(best) >= plain as u128
            };
            if unsettled > 0
                && (worth
                    || budget_after(rays + pass_most) >= spent + 5 * (unsettled * self.samples as u64) as u128 * pixels)
            {
                let (mut measured, mut sum, mut squares, mut seen) = (0u64, 0u64, 0u64, 0u64);
                for (x, y) in grid(s) {
                    let (_, n, _, _, _) = self.pixel_rays_within(x, y, self.cap);
                    measured += n as u64;
                    if n > pilot(x, y) {
                        sum += n as u64;
                        squares += n as u64 * n as u64;
                        seen += 1;
                    }
                }
                rays += measured;
                // Their sum, the same count margins at their mean, and three deviations of the sum.
                let mean = sum.div_ceil(seen.max(1)).max(plain);
                let var = (seen * squares).saturating_sub(sum * sum).div_ceil(seen.max(1));
                let dev = crate::number::wide::isqrt_rem_u64(var).0 + 1;
                let margin = unsettled - seen.min(unsettled) + 2 * sigma + 3;
                high = high.min(sum + margin * mean + 3 * dev);
            }
            if let Some(left) = budget_after(rays).checked_sub(spent + 5 * high as u128 * pixels) {
                self.floor = (plain as u128 + extra(left)).min(self.samples as u128) as u32;
            } else if worth {
                // No floor: the pass's rays come out of the cap.
                (self.cap, self.budget256) = cap_parts(cap_after(rays));
            }
            self.survey_rays = rays as u32;
        }
        self
    }

    /// Sets the gaps' bits of [`Renderer::rules`] (see [`Renderer::gap_period`]) and [`Renderer::budget256`] from a
    /// survey of gaps on a grid of spacing `s` (doubled while a pass's pairs
    /// could cast more than 1/32 of the frame's budget or are more than
    /// 512; no survey, and no
    /// gaps, under 16 pairs): for a period (one that could leave a ray a
    /// pixel if every gap filled), one pair of neighbouring anchors in each cell is rendered at 40 % of
    /// `point`, and the share F of pairs whose gaps [`scanline::fills`]
    /// fills, less two binomial deviations, frees F G pixels, G the frame's
    /// gaps between two anchors; the pixels that cast rays share what the
    /// frame's budget (40 % of `point` a pixel) leaves after the survey's
    /// rays. Above one sample, the pairs are rendered again at that budget
    /// and the lesser F sets it (more rays a pixel fill fewer gaps). The
    /// period is the shortest whose budget is [`GAP_PAIR`] rays a pixel that
    /// casts or more (periods that could not reach it are not surveyed),
    /// else the longest, surveyed again with the loose rule's rungs (see
    /// [`scanline::GAP_LOOSE_LEVELS`]), each off checkers and on them,
    /// counted on the same pairs: the strictest that reaches it, on
    /// checkers only where its fills there are sound (the middle pixel of
    /// each pair the loose rule may fill is rendered too, at most half as
    /// many rays again), else every gap filled off checkers where that
    /// leaves a ray a pixel, else on them (within 40 % of `point` 1). The
    /// choice is then checked as it renders ([`Renderer::gap_verified`]).
    /// Seeds 8600-8619, 8700-8719, 8800-8819 at 320x240
    /// met both floors at `point` 1 on 56 of 60 frames, at 2 on 57 of 60
    /// (one loose rule and one ray sought: 47 and 48). Set-up only, in integers.
    fn gap_surveyed(mut self, s: u32) -> Self {
        let (cols, rows) = (self.camera.cols(), self.camera.rows());
        let pixels = cols as u64 * rows as u64;
        let mut rays = 0u64;
        // Rays the frame's budget leaves after `rays`, times 5: 2 p N − 5 R.
        let left = |rays: u64| (2 * self.samples as u64 * pixels).saturating_sub(5 * rays);
        // A pass's pairs cast at most 1/32 of the frame's budget (two anchors
        // at 40 % of `point`, a ray at least), there are at most 512 of them
        // (large frames: a set-up's cost) and 16 or more.
        let per_pair = 2 * (2 * self.samples as u64).div_ceil(5);
        let mut s = s;
        let pairs = |s: u32| (cols / s) as u64 * (rows / s) as u64;
        while pairs(s) > 512 || pairs(s) * per_pair * 32 * 5 > 2 * self.samples as u64 * pixels {
            s = match s.checked_mul(2) {
                Some(s) => s,
                None => return self,
            };
        }
        if pairs(s) < 16 {
            return self;
        }
        // The longest period again with the loose rule where none leaves a
        // pair a pixel, its rungs counted on the same pairs.
        const RUNGS: usize = scanline::GAP_LOOSE_LEVELS.len();
        const VARIANTS: usize = 2 * RUNGS;
        // The budget sought, in 256ths: a stratified pair a pixel that casts (one at `point` 1).
        let want = 256 * self.samples.min(GAP_PAIR);
        // The share of pairs the chosen rung fills, as the budget assumed it,
        // and the rays set aside for the check of the choice.
        let (mut chosen, mut reserve) = (0, 0);
        for (period, loose) in GAP_PERIODS.map(|p| (p, false)).chain([(*GAP_PERIODS.end(), true)]) {
            let levels = if loose { scanline::GAP_LOOSE_LEVELS } else { [0; RUNGS] };
            self.budget256 = 0;
            self.rules = period | (levels[0] as u32) << 8;
            // A period whose every gap filled would leave less than sought
            // is not surveyed (`point` 1 at 2).
            if period < *GAP_PERIODS.end() && left(rays) * 256 < 5 * (pixels - self.fillable_gaps()) * want as u64 {
                continue;
            }
            // Variant v: rung v / 2, off checkers where v is even (see
            // [`Renderer::gap_checkers`]); the strict rule's are all one.
            let mut least = [u64::MAX; VARIANTS];
            // By rung: the error of the fills it makes only on checkers, and
            // of those off them, at the pairs' middle pixels (see
            // [`fill_error`]), and their counts, over the passes.
            let (mut on, mut off) = ([(0u64, 0u64); RUNGS], [(0u64, 0u64); RUNGS]);
            for pass in 0..2 {
                if pass == 1 && self.samples == 1 {
                    break;
                }
                // The second pass with pixels that extend, counted (see [`Renderer::extends`]).
                let extending = pass == 1 && self.samples >= 3 && !cfg!(feature = "no-spare-floor");
                self.rules |= (extending as u32) << 17;
                // By k (2^k up to 16 rays): anchors that cast 2^k rays or more,
                // and those whose first 2^k were wide; all of them, then those
                // of the pairs each variant leaves unfilled (their gaps cast: edges,
                // wide more often than anchors at large; seed 6019 at `point` 7
                // cast 40.1 % counted from all anchors alone).
                let (mut cast, mut wide) = ([[0u64; 5]; VARIANTS + 1], [[0u64; 5]; VARIANTS + 1]);
                let (mut tested, mut filled) = (0u64, [0u64; VARIANTS]);
                let mut anchor_rays = 0u64;
                self.survey_pairs(s, 0, |(l, nl, cl, wl), (r, nr, cr, wr), (x, y)| {
                    rays += (nl + nr) as u64;
                    anchor_rays += (nl + nr) as u64;
                    tested += 1;
                    // The pair's two anchors into group g's counts.
                    let mut count = |g: usize| {
                        for (n, w) in [(nl, wl), (nr, wr)] {
                            for k in 1..5 {
                                cast[g][k] += (n >> k != 0) as u64;
                                wide[g][k] += (w >> k & 1) as u64;
                            }
                        }
                    };
                    if extending {
                        count(0);
                    }
                    let fill = |v: usize| scanline::fills((l, cl), (r, cr), levels[v / 2], v % 2 == 1);
                    for (v, f) in filled.iter_mut().enumerate() {
                        let fills = fill(v);
                        *f += fills as u64;
                        if extending && !fills {
                            count(v + 1);
                        }
                    }
                    // The middle pixel of a pair the loose rule may fill.
                    if loose && fill(VARIANTS - 1) {
                        let (m, nm, _, _) = self.pixel_far_wide(x + period / 2, y);
                        rays += nm as u64;
                        let e = fill_error(scanline::interpolate((l, cl), (r, cr), period / 2, period).0, m);
                        for i in 0..RUNGS {
                            let tally = if fill(2 * i) {
                                &mut off[i]
                            } else if fill(2 * i + 1) {
                                &mut on[i]
                            } else {
                                continue;
                            };
                            *tally = (tally.0 + e, tally.1 + 1);
                        }
                    }
                });
                if tested == 0 {
                    return self.without_gaps();
                }
                // The share of variant v's pairs filled, less two binomial
                // deviations (rounded up), in 65536ths, the least of the passes.
                for (least, &filled) in least.iter_mut().zip(&filled) {
                    *least = (*least).min(share_less_two_deviations(filled, tested));
                }
                // The check's first draw ([`Renderer::gap_verified`]) renders
                // the anchors of half this pass's pairs at the budget chosen:
                // their rays at this pass's, a quarter over, come out of the
                // budget before the choice, not after it (10904 at `point` 5
                // chose a pair and extension, 2.008 rays, and the check left
                // 1.99: one pixel that casts in 16 with one ray). Not given
                // back where unspent: the check holds at the budget it saw.
                reserve = anchor_rays * 5 / 8;
                let budgets: [u32; VARIANTS] = core::array::from_fn(|v| self.budget_for(least[v], rays + reserve));
                // On checkers where its fills there are off their pixels by
                // at most twice as much as off them (noise, which casting
                // would have too), and CHECKER_FILL_ERROR more: a checker in
                // focus has no noise to hide a wrong fill in. At `point` 3,
                // 320x240, a fill on checkers was off by 1140 levels² against
                // 55 off them on seed 10835 (a checker finer than the pixels,
                // in focus), 243 against 1 on 10954 (receding squares' edges):
                // both missed the floor; 457 against 953 on 10637 and 120
                // against 149 on 10733: both met it only on checkers. The
                // rung that fills every gap is judged by the fills off
                // checkers of the rung below: its own cross every edge and
                // are no measure of noise (seed 8800 at `point` 4, 160x120:
                // 184 levels² a fill on checkers against 107 off them, 1 at
                // the rung below; filled on checkers, -11.6 dB).
                let sound = |v: usize| {
                    let ((e_on, n_on), (e_off, n_off)) = (on[v / 2], off[(v / 2).min(RUNGS - 2)]);
                    v.is_multiple_of(2) || e_on * n_off.max(1) <= (2 * e_off + CHECKER_FILL_ERROR * n_off.max(1)) * n_on
                };
                // The strictest sound variant that leaves a pair; else every
                // gap filled off checkers, where that is not sound on them and
                // leaves a ray a pixel (at `point` 2 it met the floor on 10603,
                // 10703 and 10945, 320x240, which missed by up to 6.8 dB on
                // them); else the strictest on checkers that leaves a pair,
                // else the loosest (the budget's: a checker finer than the
                // pixels at `point` 1 or 2 is not met).
                let v = (0..VARIANTS).find(|&v| sound(v) && budgets[v] >= want).unwrap_or(
                    if !sound(VARIANTS - 1) && budgets[VARIANTS - 2] >= 256 {
                        VARIANTS - 2
                    } else {
                        (0..VARIANTS)
                            .find(|&v| !v.is_multiple_of(2) && budgets[v] >= want)
                            .unwrap_or(VARIANTS - 1)
                    },
                );
                let rung = v / 2;
                let off_checkers = loose && v.is_multiple_of(2);
                self.rules = period | (levels[rung] as u32) << 8 | (off_checkers as u32) << 18;
                self.budget256 = budgets[v];
                chosen = least[v];
                if extending {
                    // The share of pixels wide at their first 2^k rays, two
                    // deviations high (all where none cast them), in 65536ths.
                    let share_of = |g: usize, k: usize| -> u64 {
                        let (c, w) = (cast[g][k], wide[g][k]);
                        if c == 0 {
                            return 1 << 16;
                        }
                        let var = (w * (c - w)).div_ceil(c);
                        let high = (w + crate::number::wide::isqrt_rem_u64(4 * var).0 + 1).min(c);
                        (high << 16).div_ceil(c)
                    };
                    // Over the pixels that cast: the frame's N − G outside gaps at
                    // all anchors' share, its (1 − F) G unfilled gaps at the
                    // unfilled pairs' (F the rung's share filled, as counted).
                    let (gaps, f) = (self.fillable_gaps(), (filled[v] << 16) / tested);
                    let unfilled = (gaps * ((1 << 16) - f)) >> 16;
                    let share = |k: usize| {
                        let (a, u) = (share_of(0, k), share_of(v + 1, k));
                        ((pixels - gaps) * a + unfilled * u).div_ceil((pixels - gaps + unfilled).max(1))
                    };
                    let (b, p) = (self.budget256 as u64, self.samples as u64);
                    // The most a pixel that casts may take before extending, B'
                    // between L and 2L (powers of two), with what extending then
                    // costs it at most: B' + cost <= B, the largest L first.
                    let mut k = 31 - self.samples.leading_zeros() as usize;
                    while k >= 1 {
                        let low = 1u64 << k;
                        let cost = |k: usize, n: u64| (256 * share(k) * p.saturating_sub(n)).div_ceil(1 << 16);
                        let most = cost(k, low).max(if 2 * low < p { cost(k + 1, 2 * low) } else { 0 });
                        let rest = b.saturating_sub(most).min(512 * low - 1);
                        // Where few are wide: extending all is no choice of the worst.
                        let few = share(k) <= 1 << 14;
                        if few && low < p && rest >= 256 * low && rest >= want as u64 {
                            self.budget256 = rest as u32;
                            self.rules |= 1 << 17;
                            break;
                        }
                        k -= 1;
                    }
                }
            }
            if self.budget256 >= want || loose {
                rays = self.gap_verified(s, rays, reserve, chosen);
                break;
            }
        }
        self.survey_rays = rays as u32;
        self
    }

    /// The anchor pairs of [`Renderer::gap_surveyed`]'s grid of spacing `s`
    /// at the current period: one in each cell, every phase of the dither,
    /// each anchor as [`Renderer::pixel_far_wide`] renders it; `draw` 0 for
    /// the choosing passes, others for spots drawn afresh in every other
    /// cell (half the rays: a check, not a choice).
    fn survey_pairs(&self, s: u32, draw: u32, mut pair: impl FnMut(FarWide, FarWide, (u32, u32))) {
        let (cols, rows, period) = (self.camera.cols(), self.camera.rows(), self.gap_period());
        for j in 0..rows / s {
            for k in 0..cols / s {
                if draw > 0 && (j + k + draw).is_multiple_of(2) {
                    continue;
                }
                let (x, y) = survey_spot(j, k, s, draw);
                // The anchor at or after x, and the next.
                let x = x + (gap_phase(y, period) + period - x % period) % period;
                if x + period < cols {
                    pair(self.pixel_far_wide(x, y), self.pixel_far_wide(x + period, y), (x, y));
                }
            }
        }
    }

    /// [`Renderer::gap_surveyed`]'s choice checked as the frame will render
    /// it: pairs at spots drawn afresh in every other cell, at the chosen
    /// budget, rung and extension; where the share they fill falls short
    /// of `least`, the share the choice assumed (65536ths, two deviations
    /// low), the budget drops to the draws' pooled share less two
    /// deviations, checked by the next draw, up to three. The passes that
    /// chose measured other budgets, or extension on: seed 10819 at `point`
    /// 6 filled 61 % of its pairs there and 43 % as rendered, 40.9 % of
    /// `point`. Fresh spots, not the choosing passes' again: a share those
    /// overstated by chance (seed 8662 at 9, 160x120, 70 pairs: 40.0 %) is
    /// not confirmed by them. Half the cells: at every cell the check's rays
    /// cost 9225 and 9209 (`point` 5 and 4, 160x120) their margins; at a
    /// quarter, too few pairs (14 on 8775 at 8) cut a third of a frame's rays.
    /// A first draw short of `least` is pooled with a second at the same
    /// budget before the budget drops: one draw's two deviations are wide.
    /// `reserve`, the rays the choice set aside for the check, is spent first.
    /// Returns `rays` with the draws' rays added.
    fn gap_verified(&mut self, s: u32, mut rays: u64, reserve: u64, mut least: u64) -> u64 {
        let (level, checkers) = (self.gap_loose(), self.gap_checkers());
        let mut assumed = self.budget_for(least, rays + reserve);
        // The pairs of every draw, and of the draws at the current budget, filled and tested.
        let (mut tested, mut filled, mut tested_now, mut filled_now) = (0u64, 0u64, 0u64, 0u64);
        for draw in 1..4 {
            self.survey_pairs(s, draw, |(l, nl, cl, _), (r, nr, cr, _), _| {
                rays += (nl + nr) as u64;
                let fills = scanline::fills((l, cl), (r, cr), level, checkers) as u64;
                (tested, filled, tested_now, filled_now) =
                    (tested + 1, filled + fills, tested_now + 1, filled_now + fills);
            });
            // The share assumed (already two deviations low) holds where the
            // draws at this budget, pooled, fill it or more; the first draw
            // short of it is pooled with a second before the budget drops
            // (one of 149 pairs cost 9008 at `point` 5 a tenth of its gaps).
            let holds = (filled_now << 16) >= least * tested_now.max(1);
            if !holds && draw == 1 {
                continue;
            }
            // Else every draw's pooled share less two deviations, checked by the next.
            let share = if holds {
                least
            } else {
                least.min(share_less_two_deviations(filled, tested.max(1)))
            };
            // The draws' rays beyond those set aside come out of the budget, and so does a shortfall.
            let measured = self.budget_for(share, rays);
            self.budget256 = self.budget256.saturating_sub(assumed.saturating_sub(measured)).max(1);
            if holds {
                break;
            }
            (least, assumed, tested_now, filled_now) = (share, measured, 0, 0);
        }
        rays
    }

    /// Rays a pixel that casts has, in 256ths, where the share `least`
    /// (65536ths) of the gaps of the current period fill and `rays` are
    /// spent: what the frame's budget (40 % of `point` a pixel) leaves over
    /// its pixels that cast, N − F G, at most `point`.
    fn budget_for(&self, least: u64, rays: u64) -> u32 {
        let pixels = self.camera.cols() as u64 * self.camera.rows() as u64;
        let left = (2 * self.samples as u64 * pixels).saturating_sub(5 * rays);
        let casting = 5 * ((pixels << 16) - least * self.fillable_gaps());
        let b256 = (left * 256 * (1 << 16) / casting.max(1)).min(256 * self.samples as u64);
        (b256 as u32).max(1)
    }

    /// How many pixels of the frame are gaps between two anchors (see [`gap_phase`]).
    fn fillable_gaps(&self) -> u64 {
        let (cols, rows, period) = (
            self.camera.cols() as u64,
            self.camera.rows() as u64,
            self.gap_period() as u64,
        );
        (0..period.min(rows))
            .map(|phase| {
                // Rows of this phase, and the anchors of each: phase, phase + period ... < cols.
                let rows_of = (rows - phase).div_ceil(period);
                let anchors = if phase < cols {
                    (cols - phase).div_ceil(period)
                } else {
                    0
                };
                rows_of * anchors.saturating_sub(1) * (period - 1)
            })
            .sum()
    }

    /// The rays a pixel that casts any takes below [`ADAPTIVE_MIN_POINT`]
    /// with gaps, in 256ths, before its dither (0: none set, 40 % of `point`).
    pub fn gap_budget(&self) -> u32 {
        self.budget256
    }

    /// Anchors every this many columns below [`ADAPTIVE_MIN_POINT`] (see
    /// [`scanline::fills`]), from the gap survey; 0: no gaps.
    pub fn gap_period(&self) -> u32 {
        self.rules & 0xFF
    }

    /// Whether an unsettled pixel doubles its pilot at least (see
    /// [`Renderer::pixel_rays`]): where the survey found the rays for it.
    pub fn doubling(&self) -> bool {
        self.rules >> 16 & 1 != 0
    }

    /// Whether pixels in lamps' footprints take [`adaptive_raised_pilot`],
    /// not [`adaptive_risk_pilot`]: where the survey found the frame's
    /// pilots with it within [`RAISED_PILOTS_SHARE`] fortieths of `point`. Not on the
    /// micro:bit (feature `no-spare-floor`).
    pub fn raised_pilots(&self) -> bool {
        !cfg!(feature = "no-spare-floor") && self.rules >> 20 & 1 != 0
    }

    /// Whether pixels in lamps' footprints take the plain pilot: where the
    /// survey's rays in its lamps' parts of the lens mostly showed what the
    /// pilots showed, and the footprints' larger pilots were the whole
    /// budget there and left a third of their pixels unsettled or more (the
    /// survey then ran again with every pixel at the plain pilot). Not on
    /// the micro:bit (feature `no-spare-floor`).
    pub fn plain_lamps(&self) -> bool {
        !cfg!(feature = "no-spare-floor") && self.rules & PLAIN_LAMPS_RULE != 0
    }

    /// The pilot of a pixel in a lamp's footprint (see [`BrightFootprints`]).
    fn risk_pilot(&self) -> u32 {
        if self.plain_lamps() {
            return adaptive_pilot(self.samples);
        }
        if self.raised_pilots() {
            adaptive_raised_pilot(self.samples)
        } else {
            adaptive_risk_pilot(self.samples)
        }
    }

    /// The pilot of pixel (`col`, `row`) in an adaptive frame.
    pub fn pilot(&self, col: u32, row: u32) -> u32 {
        if self.bright.at_risk(col, row) {
            self.risk_pilot()
        } else {
            adaptive_pilot(self.samples)
        }
    }

    /// Whether the survey rendered its grid again with the doubling to
    /// decide it, the shares' sum having said no (diagnosis and tests).
    #[doc(hidden)]
    pub fn doubling_measured(&self) -> bool {
        self.rules >> 19 & 1 != 0
    }

    /// Whether a pixel that casts with gaps (`point` 3 to 9) goes on from
    /// its budget ([`Renderer::fixed_budget`], a power of two) to every
    /// sample where its rays so far are wider than [`EXTEND_LEVELS`]. The
    /// gap survey's second pass renders its anchors with it and counts, for
    /// each power of two L, the anchors that cast L rays and those whose
    /// first L were wide, all of them and those of the pairs left unfilled
    /// (standing for the gaps that cast); the budget B then drops to the
    /// largest B' (between some L and 2L) with B' plus what extending costs
    /// at most (the wide share of the pixels that cast, two deviations high,
    /// times `point` − L, and the same at 2L) within B, at least a pair,
    /// where at most a quarter are wide (where most are, extending them all
    /// picks none out: seed 9109 at `point` 9 lost 3.2 dB).
    /// Not on the micro:bit (feature `no-spare-floor`).
    pub fn extends(&self) -> bool {
        !cfg!(feature = "no-spare-floor") && self.rules >> 17 & 1 != 0
    }

    /// The levels of [`scanline::fills`]' loose rule the gaps fill by (a
    /// rung of [`scanline::GAP_LOOSE_LEVELS`]), 0: the strict rule (see [`Renderer::gap_period`]).
    pub fn gap_loose(&self) -> u8 {
        (self.rules >> 8) as u8
    }

    /// Whether the loose rule fills between anchors that met a checker (see
    /// [`scanline::fills`]): unless the gap survey found it filling wrong
    /// there, a checker finer than the gaps whose moiré the line misses.
    pub fn gap_checkers(&self) -> bool {
        self.rules >> 18 & 1 == 0
    }

    /// Whether rows have gaps (see [`scanline::fills`]): rows are
    /// filtered and the frame is below [`ADAPTIVE_MIN_POINT`] (a ray budget).
    #[inline]
    pub fn gaps(&self) -> bool {
        self.filters() && self.samples < ADAPTIVE_MIN_POINT
    }

    /// The most samples an adaptive pixel that is not settled takes (from
    /// the survey, see [`Renderer::new`]'s set-up), and the rays the survey cast.
    pub fn adaptive_cap(&self) -> (u32, u32) {
        (self.cap, self.survey_rays)
    }

    /// Overrides the lens samples per pixel (clamped to 1..=65535). The
    /// survey runs again only if the count changes (a progressive pass at
    /// the renderer's own count, band after band, costs none).
    ///
    /// # Panics
    ///
    /// Never.
    pub fn with_samples(mut self, samples: u32) -> Self {
        let samples = samples.clamp(1, 65535);
        if samples == self.samples {
            return self;
        }
        self.samples = samples;
        self.surveyed()
    }

    /// [`Renderer::with_samples`] without a survey where the count changes:
    /// the cap is 40 % of `samples` and rows have no gaps. For a progressive
    /// preview (its blocks are single pixels): a survey a band would cost
    /// more than the preview.
    pub(crate) fn with_samples_unsurveyed(mut self, samples: u32) -> Self {
        let samples = samples.clamp(1, 65535);
        if samples != self.samples {
            self.samples = samples;
            self.clear_survey();
        }
        self
    }

    /// What a survey sets, as a renderer without one has it: the cap 40 % of
    /// `point`, no spare floor, no gaps.
    fn clear_survey(&mut self) {
        self.cap = adaptive_limit(self.samples);
        (self.survey_rays, self.spread, self.floor) = (0, 0, 0);
        (self.budget256, self.rules) = (0, 0);
    }

    /// Whether adaptive pixels take lamps' parts of the lens (see [`lamps`]):
    /// the survey found room for their rays.
    pub fn lamp_parts(&self) -> bool {
        self.rules & LAMP_PARTS_RULE != 0 && !self.lamps.is_empty()
    }

    /// Whether, the pilots being the whole budget (no survey), an adaptive
    /// pixel whose pilot put no ray in the part of the lens of a lamp that
    /// glows (its ambient term alone bright; see [`lamps`]) draws its
    /// pilot's last ray there, in place of the sequence's, and weighs its
    /// parts by their shares. Set only where some lamp glows.
    pub fn lamps_in_place(&self) -> bool {
        self.rules & LAMP_IN_PLACE_RULE != 0
    }

    /// The lamps whose parts of the lens are off where the others' are on,
    /// as bits in the frame's order of its bright objects (see [`lamps`]):
    /// the survey's grid mostly kept none of their rays.
    pub fn lamp_parts_off(&self) -> u32 {
        (self.rules & LAMP_OFF_RULES) >> LAMP_OFF_SHIFT
    }

    /// This renderer without lamps' parts of the lens (see [`lamps`]), its
    /// survey as it was: what they change (tests, diagnosis).
    #[doc(hidden)]
    pub fn without_lamp_parts(mut self) -> Self {
        self.rules &= !LAMP_PARTS_RULE;
        self
    }

    /// This renderer without gaps (see [`Renderer::gap_period`]): its
    /// pixels as a build without the scanline filter (the micro:bit's, which
    /// takes no gap survey) renders them, 40 % of `point` each.
    pub fn without_gaps(mut self) -> Self {
        self.budget256 = 0;
        self.rules &= !0x6_FFFF;
        self
    }

    /// Turns adaptive lens sampling on or off (the scene's `adaptive`
    /// statement sets the default; see [`Renderer::pixel_rays`]); surveys
    /// again only on a change.
    pub fn with_adaptive(mut self, adaptive: bool) -> Self {
        if adaptive == self.adaptive {
            return self;
        }
        self.adaptive = adaptive;
        self.surveyed()
    }

    /// Chooses how lens points are drawn (the scene's `sampler` statement
    /// sets the default); surveys again only on a change.
    pub fn with_sampler(mut self, sampler: Sampler) -> Self {
        if sampler == self.sampler {
            return self;
        }
        self.sampler = sampler;
        self.surveyed()
    }

    /// How lens points are drawn.
    pub fn sampler(&self) -> Sampler {
        self.sampler
    }

    /// The lens samples a pixel (`point`, or [`Renderer::with_samples`]'): the
    /// most an adaptive pixel takes.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Whether lens sampling is adaptive.
    pub fn is_adaptive(&self) -> bool {
        self.adaptive
    }

    /// The camera in use.
    pub fn camera(&self) -> &Camera<S> {
        &self.camera
    }

    /// The pixels where adaptive sampling takes every sample (see [`BrightFootprints`]).
    pub fn bright_footprints(&self) -> &BrightFootprints {
        &self.bright
    }

    /// The objects each of this camera's rays can reach (see [`LensCones`]).
    pub fn cones(&self) -> &LensCones<S> {
        &self.cones
    }

    /// Rays cast per pixel: 1 for a pinhole camera, else the sample count
    /// (with adaptive sampling, the most a pixel casts).
    pub fn rays_per_pixel(&self) -> u32 {
        if self.camera.is_pinhole() {
            1
        } else {
            self.samples
        }
    }

    /// The mean colour of pixel (`col`, `row`), unclamped.
    ///
    /// # Panics
    ///
    /// Never, for any `col` and `row` (beyond the image they stand for its last
    /// column and row, as the camera clamps them): all arithmetic saturates.
    pub fn pixel_colour(&self, col: u32, row: u32) -> Vec3<S> {
        self.pixel_rays(col, row).0
    }

    /// The mean colour of pixel (`col`, `row`), unclamped, and the rays it cast.
    ///
    /// With adaptive sampling and [`ADAPTIVE_BUDGET_POINT`] to
    /// [`ADAPTIVE_MIN_POINT`] − 1 samples a pixel takes 40 % of them,
    /// dithered between powers of two ([`dithered_budget`]). With adaptive sampling
    /// (and at least [`ADAPTIVE_MIN_POINT`] samples) a
    /// pixel takes a pilot of [`adaptive_pilot`] lens samples (twice that in
    /// a lamp's footprint, see [`BrightFootprints`] and
    /// [`adaptive_risk_pilot`]), then at every power of two asks whether its
    /// mean is settled (see the scene format's "Adaptive lens sampling"), and
    /// stops there; else it goes on, up to its share of the frame's budget
    /// (the survey's cap C: its pilot P plus (C − P) times its samples'
    /// spread over the survey's mean, at least 2P where C is and the survey
    /// found the rays for it, [`Renderer::doubling`], dithered to a power of two). The
    /// samples taken are the first ones of the full render. With the
    /// stratified sampler, a ray that meets a checker averages it over its
    /// stratum's footprint (see [`Defocus`]): one of `check` strata while the
    /// pixel is adaptive, else of the largest power of two within the samples.
    pub fn pixel_rays(&self, col: u32, row: u32) -> (Vec3<S>, u32) {
        let (c, n, _, _, _) = self.pixel_rays_within(col, row, self.cap);
        (c, n)
    }

    /// Pixel (`col`, `row`) as 8-bit RGB, the rays it cast, and its class
    /// for the scanline filter (see [`scanline::Scanline`]; 0 where the
    /// renderer does not filter).
    fn pixel_far(&self, col: u32, row: u32) -> (scanline::Fine, u32, u8) {
        let (c, n, far, _) = self.pixel_far_wide(col, row);
        (c, n, far)
    }

    /// [`Renderer::pixel_far`] and, with extension on, the powers of two at
    /// which its rays' range was wide (see [`Renderer::extends`]).
    fn pixel_far_wide(&self, col: u32, row: u32) -> FarWide {
        let (c, n, wide_at, far, _) = self.pixel_rays_within(col, row, self.cap);
        (scanline::Fine::of(c), n, far, wide_at)
    }

    /// The first `cols` pixels (at most the image width) of row `row` as the
    /// picture has them: filtered where far out of focus, with gaps below
    /// [`ADAPTIVE_MIN_POINT`] (see [`scanline`]).
    pub fn scanline(
        &self,
        row: u32,
        cols: u32,
    ) -> scanline::Scanline<impl FnMut(u32) -> (scanline::Fine, u32, u8) + '_> {
        scanline::Scanline::new(move |col| self.pixel_far(col, row), cols.min(self.camera.cols()))
            .with_filter(self.filters())
            .with_gaps(self.gaps().then(|| {
                let period = self.gap_period();
                (period, gap_phase(row, period), self.gap_loose(), self.gap_checkers())
            }))
    }

    /// What a lens ray through `p_lens` carries for its footprint's pull
    /// (share `share` of its offset: [`defocus::Stratum::pull`]): none
    /// with the scene's rim pull off; nothing on the micro:bit (`no-rim-pull`).
    #[inline(always)]
    fn pull(&self, p_lens: (i32, i32), share: S) -> defocus::Pull<'_, S> {
        #[cfg(not(feature = "no-rim-pull"))]
        return defocus::Pull {
            camera: &self.camera,
            p_lens,
            share: if self.scene.rim_pulled() { share } else { S::ZERO },
        };
        #[cfg(feature = "no-rim-pull")]
        {
            let _ = (p_lens, share);
            core::marker::PhantomData
        }
    }

    /// Whether rows are filtered where far out of focus (see [`scanline`]):
    /// a lens camera with stratified, adaptive sampling of at least
    /// [`scanline::FILTER_MIN_POINT`] samples; never with `sampler independent` or
    /// `adaptive off`, nor with the feature `no-scanline-filter` (the micro:bit's).
    #[inline]
    pub fn filters(&self) -> bool {
        !cfg!(feature = "no-scanline-filter")
            && self.adaptive
            && self.sampler == Sampler::Stratified
            && self.samples >= scanline::FILTER_MIN_POINT
            && !self.camera.is_pinhole()
    }

    /// The survey's mean spread, margin included (see [`spread_margin`];
    /// diagnosis): the σ̄ of the unsettled pixels' shares.
    #[doc(hidden)]
    pub fn survey_spread(&self) -> u32 {
        self.spread
    }

    /// [`Renderer::pixel_rays`] and the pixel's spread at its last check if
    /// it was not settled there, else 0; below [`ADAPTIVE_MIN_POINT`] with
    /// extension on (see [`Renderer::extends`]), the powers of two n, as
    /// bits, at which its first n rays were wide (diagnosis).
    #[doc(hidden)]
    pub fn pixel_rays_spread(&self, col: u32, row: u32) -> (Vec3<S>, u32, u32) {
        let (c, n, spread, _, _) = self.pixel_rays_within(col, row, self.cap);
        (c, n, spread)
    }

    /// The rays pixel (`col`, `row`) casts below [`ADAPTIVE_MIN_POINT`]
    /// (adaptive on; a gap casts none), before it extends (see
    /// [`Renderer::extends`]): the frame's budget a pixel that casts
    /// (40 % of `point` without gaps) dithered between powers of two, at
    /// most `point`.
    #[doc(hidden)]
    #[inline(always)]
    pub fn fixed_budget(&self, col: u32, row: u32) -> u32 {
        // No gaps without the filter (the micro:bit's flash).
        let budget = if cfg!(feature = "no-scanline-filter") {
            0
        } else {
            self.budget256
        };
        match budget {
            0 => dithered_budget(self.samples, col, row),
            // Anchors every `gap_period` columns: their own full dither.
            b => dithered_ratio(b, 256, col / self.gap_period().max(1), row).min(self.samples),
        }
    }

    /// [`Renderer::pixel_rays`] with a cap of `most` samples for an adaptive
    /// pixel that is not settled (at least its pilot), and the pixel's spread
    /// at its last check if it was not settled there (at least 1), else 0,
    /// and its class for the scanline filter (see [`scanline::Scanline`]),
    /// and its lamp's ray beyond the pilot: bits 0-1 none 0, cast 1, kept 2;
    /// bits 2-4 the lamp's index, where cast.
    fn pixel_rays_within(&self, col: u32, row: u32, most: u32) -> (Vec3<S>, u32, u32, u8, u8) {
        let film = self.camera.film_point(col, row);
        if self.camera.is_pinhole() {
            let ray = self.camera.generate_ray(&CameraSample {
                film: &film,
                lens: None,
            });
            return (self.scene.trace_lens_ray(&ray, &self.cones, None).0, 1, 0, 0, 0);
        }
        // The pixel's own samples: independent of row order and threads.
        let mut lens = PixelSamples::new(self.sampler, col, row);
        // Sums and counts of the rays by part of the lens: one part but
        // where a plane cuts the lens (see [`cut`]).
        let mut sums = [[S::acc_zero(); 3]; 3];
        let mut counts = [0u32; 3];
        let pixel_cut = self.cut.is_cut().then(|| self.cut.pixel(col, row));
        let mut stats = LevelStats::default();
        let adaptive = self.adaptive && self.samples >= ADAPTIVE_MIN_POINT;
        // Where a lamp may shine through part of the lens, a pilot at half the
        // full render's resolution of the lens.
        let risk = self.bright.at_risk(col, row);
        let mut check = if risk {
            self.risk_pilot()
        } else {
            adaptive_pilot(self.samples)
        };
        // A pixel that is not settled stops at the frame's cap (the survey's),
        // dithered between the powers of two around it: a partial block of
        // the (0,2)-sequence is badly stratified.
        // (Set at its first check, which comes first: one call site.)
        let mut limit = if adaptive {
            most.max(check)
        } else if self.adaptive && self.samples >= ADAPTIVE_BUDGET_POINT {
            self.fixed_budget(col, row)
        } else {
            self.samples
        };
        let pilot = check;
        // The rays of a pixel's first block: its pilot, else all it takes.
        let first_block = if adaptive { pilot } else { limit };
        // Else, for an adaptive pixel where the survey found room, a lamp's
        // disc on the lens that its pilot may miss (stratified sampler only).
        let mut lamp = match pixel_cut {
            None if !self.lamps.is_empty() && adaptive && self.rules & (LAMP_PARTS_RULE | LAMP_IN_PLACE_RULE) != 0 => {
                self.lamps
                    .pixel(col, row, self.camera.aperture(), first_block)
                    .filter(|l| self.rules >> LAMP_OFF_SHIFT >> l.lamp & 1 == 0)
                    // In the pilot's place, only a lamp that glows (false lamps'
                    // rays cost a stratum: seed 12048 at `point` 10, -5.9 dB).
                    .filter(|l| self.rules & LAMP_IN_PLACE_RULE == 0 || self.lamps.glows(l.lamp))
            }
            _ => None,
        };
        let mut parts = pixel_cut.map(|q| q.shares).or(lamp.as_ref().map(|l| l.shares));
        let mut spread = 0;
        let mut n = 0;
        // Stratified rays stand for a stratum each: with adaptive sampling,
        // one of the `check` strata the samples so far divide the lens into;
        // else one of the largest power of two within the samples it takes
        // (the check of a pixel that is not adaptive; no more locals: the M0's stack).
        let full = 1u32 << (31 - if adaptive { self.samples } else { limit }.leading_zeros());
        if !adaptive {
            check = full;
        }
        // The stratum's footprint changes with `check` only: set per doubling, not per ray.
        let stratified = self.sampler == Sampler::Stratified;
        // The scanline filter's gate: true while every ray met something far
        // out of focus; what they met: bit 0 a lamp, bit 1 anything else.
        let mut far = self.filters();
        let gate = self.defocus.gated(self.samples);
        // And while every ray met something twice as far out of focus (the 5-tap).
        let mut wide = far;
        // And while every lamp's ray met it spread over its brightness times the gate.
        let mut lamp_far = far;
        // And while everything else met is spread over that too; with the
        // nearest lamp's and the farthest other hit's depth ratios.
        let mut occluder_far = far;
        let (mut lamp_near, mut occluder_back) = (S::MAX, S::ZERO);
        let mut lamps = 0u8;
        let mut stratum = self.defocus.stratum(check.min(full));
        // With gaps: whether some ray met a checker (see [`scanline::fills`]).
        let gaps = self.gaps();
        // With extension on: its rays' levels' range, and the powers of two
        // n at which the first n rays' range was above [`EXTEND_LEVELS`].
        let track = !adaptive && gaps && self.extends();
        let (mut lo, mut hi, mut wide_at) = ([u32::MAX; 3], [0u32; 3], 0u32);
        let mut textured = false;
        // A ray drawn in a lamp's part beyond the sequence's (see [`lamps`]):
        // due, cast, and the spread it sets where it moves the mean by a level.
        let (mut lamp_due, mut lamp_cast, mut lamp_spread, mut lamp_index) = (false, 0u32, None, 0u8);
        // (Compiled out on the micro:bit: its flash.)
        let lamps_on = !cfg!(feature = "no-lamp-parts");
        let in_place = lamps_on && self.rules & LAMP_IN_PLACE_RULE != 0;
        while n < limit || (lamps_on && lamp_due) {
            let extra = lamps_on && core::mem::take(&mut lamp_due);
            // By reference: a pixel's steps are 270 bytes, and copies of them
            // per ray cost the Cortex-M3 5 % of Program 1's instructions.
            let (mut p_lens, unit) = match lamp.as_ref().filter(|_| extra) {
                Some(l) => {
                    let unit = l.point_at(lens.draw_u32());
                    (self.camera.aperture().map_q16(unit.0, unit.1), Some(unit))
                }
                None if lamps_on => lens.next_point(self.camera.aperture()),
                None => (lens.next(self.camera.aperture()), None),
            };
            let mut part = match (&pixel_cut, &lamp, unit) {
                (Some(q), _, _) => q.part(self.cut.sigma(p_lens)),
                (None, Some(l), Some(unit)) => l.part(unit),
                _ => 0,
            };
            // The first block's last ray where a part of a cut lens has none
            // of it: one from that part in its place, so that it has a mean.
            let mut forced = false;
            if let Some(q) = parts.filter(|_| n + 1 == first_block && first_block >= parts::FORCE_MIN_BLOCK) {
                let mut after = counts;
                after[part] += 1;
                if let (Some(k), Some(c)) = (q.starved(&after), pixel_cut) {
                    let keep = |p| c.part(self.cut.sigma(p)) == k;
                    if let Some(p) = lens.draw_where(self.camera.aperture(), cut::FORCE_TRIES, keep) {
                        (p_lens, part, forced) = (p, k, true);
                    }
                }
            }
            // The pilots being the whole budget, the pilot's last ray in the
            // lamp's part where none of the others fell (the mutant at
            // `point` 20 of host-tests/extra-scenes/: -1.16 -> +1.57 dB).
            if in_place && n + 1 == first_block && counts[1] == 0 && part == 0 {
                if let Some(l) = lamp.as_ref() {
                    let unit = l.point_at(lens.draw_u32());
                    (p_lens, part, forced) = (self.camera.aperture().map_q16(unit.0, unit.1), 1, true);
                }
            }
            let ray = self.camera.generate_ray(&CameraSample {
                film: &film,
                lens: Some(p_lens),
            });
            // One call site for both samplers: two inlined copies of the trace
            // took 4 KiB more stack on the Cortex-M0.
            let footprint = stratified.then(|| (&self.defocus, stratum.radius, self.pull(p_lens, stratum.pull)));
            let (c, t) = self.scene.trace_lens_ray(&ray, &self.cones, footprint);
            if gaps {
                textured |= t.is_some_and(|(i, _)| self.scene.objects.get(i).is_some_and(|o| o.texture != S::ZERO));
            }
            if far {
                far = match t {
                    Some((i, t)) => {
                        let bright = self.bright.is_bright(i);
                        let (f, w, l, u) = gate.far_hits(ray.dir, t, self.bright.lamp());
                        lamps |= if bright { 1 } else { 2 };
                        if bright {
                            // Only a lamp's own hits decide its gate.
                            lamp_far &= l;
                            if u < lamp_near {
                                lamp_near = u;
                            }
                        } else {
                            occluder_far &= l;
                            if u > occluder_back {
                                occluder_back = u;
                            }
                        }
                        wide &= w;
                        f
                    }
                    None => {
                        lamps |= 2;
                        // A miss is behind every lamp: no occluder.
                        occluder_far = false;
                        wide &= gate.wide_miss();
                        gate.far_miss()
                    }
                };
            }
            let sum = &mut sums[part];
            *sum = [
                S::acc_add(sum[0], c.x),
                S::acc_add(sum[1], c.y),
                S::acc_add(sum[2], c.z),
            ];
            counts[part] += 1;
            if extra {
                lamp_cast = 1;
                lamp_index = lamp.as_ref().map_or(0, |l| l.lamp);
                let level = |k: usize| S::acc_mean(sums[0][k], counts[0]).to_level();
                let x = [c.x.to_level(), c.y.to_level(), c.z.to_level()];
                lamp_spread = lamp
                    .as_ref()
                    .and_then(|l| lamps::spread([level(0), level(1), level(2)], x, l.shares.0[1]));
                if lamp_spread.is_none() {
                    // It shows what the block's rays show: left out, and the
                    // rays weighed alike (its noise cost near-exact frames:
                    // seed 11734 -0.37 dB).
                    (sums[1], counts[1], parts, lamp) = ([S::acc_zero(); 3], 0, None, None);
                }
            } else {
                if adaptive {
                    stats.add(n, check, c);
                }
                n += 1;
            }
            if track {
                // Clamped at white: rays all above it leave the pixel white.
                let levels = [c.x, c.y, c.z].map(|v| v.to_level().min(255));
                // A forced ray is from another part of the lens by design: no
                // sign that the block's own rays disagree (seed 8919 took every
                // sample on most pixels, 44.7 % of `point`).
                for i in (0..3).filter(|_| !forced) {
                    lo[i] = lo[i].min(levels[i]);
                    hi[i] = hi[i].max(levels[i]);
                }
                if n >= 2 && n.is_power_of_two() && (0..3).any(|i| hi[i] - lo[i] > EXTEND_LEVELS) {
                    wide_at |= n;
                    // At its budget (a power of two below `point`): on to every sample.
                    if n == limit {
                        limit = self.samples;
                        stratum = self.defocus.stratum(self.samples);
                    }
                }
            }
            // The first block put no ray in the lamp's part: one more, there,
            // before the check (in place of one of the block's, it cost
            // near-exact frames their stratification: seed 11734 -3.9 dB).
            if lamps_on
                && !extra
                && n == first_block
                && first_block >= parts::FORCE_MIN_BLOCK
                && lamp.is_some()
                && counts[1] == 0
            {
                lamp_due = true;
                continue;
            }
            if adaptive && n == check && n < self.samples {
                // Its share beyond the pilot: the frame's, times its spread
                // over the survey's mean (samples ∝ the standard deviation:
                // the least total variance for the rays). Settled, it still
                // goes on where the lamp's ray, weighed by its part's share,
                // moves the mean by a level.
                let settled = stats.settled(n, self.samples).or(lamp_spread.filter(|_| n == pilot));
                let Some(own) = settled else {
                    // Settled at the plain pilot in a frame with rays to
                    // spare: on to the floor without further checks, then stop.
                    if !cfg!(feature = "no-spare-floor") && n == pilot && !risk && self.floor > n {
                        limit = dithered_cap(self.floor, col, row).min(self.samples);
                        check = u32::MAX;
                        stratum = self.defocus.stratum(limit.min(full));
                        continue;
                    }
                    spread = 0;
                    break;
                };
                spread = own;
                // Its share is set once, from the pilot's spread as the survey
                // saw it: a later, larger spread would spend rays the survey
                // did not count (seed 6009: 53 % of `point`).
                if n == pilot {
                    limit = self.share(most, pilot, spread, col, row);
                }
                stats.double();
                check = check.saturating_mul(2);
                stratum = self.defocus.stratum(check.min(full));
            }
        }
        // Each part of a cut lens by its share; else the plain mean.
        let colour = match parts {
            Some(q) => q.mean(&sums, &counts),
            None => Vec3::new(
                S::acc_mean(sums[0][0], n),
                S::acc_mean(sums[0][1], n),
                S::acc_mean(sums[0][2], n),
            ),
        };
        // A pixel that saw a lamp through part of the lens is on its bokeh's rim:
        // filtered only where every lamp it met is spread over its brightness
        // times the gate (the rim then changes no faster than an object's edge
        // at the gate), and then with anything of the same blur.
        // Or where all else it met is in front of every lamp and spread as far:
        // the rim is that occluder's silhouette, as soft, and the pixel may be
        // mixed with a lamp's pixels or with the others' (class 3, both bits).
        let lamps = match lamps {
            3 if lamp_far => 2,
            3 if occluder_far && occluder_back < lamp_near => 3,
            3 => 0,
            _ => lamps,
        };
        let class = if far && lamps != 0 {
            lamps | if wide { scanline::WIDE } else { 0 }
        } else {
            0
        } | if textured { scanline::TEXTURED } else { 0 };
        let lamp = (lamp_cast as u8 + lamp_spread.is_some() as u8) | (lamp_index << 2);
        (colour, n + lamp_cast, if track { wide_at } else { spread }, class, lamp)
    }

    /// The cap of an unsettled pixel of pilot `pilot` and spread `spread`
    /// where the frame's is `most`, dithered to a power of two.
    fn share(&self, most: u32, pilot: u32, spread: u32, col: u32, row: u32) -> u32 {
        if cfg!(feature = "no-spare-floor") {
            return dithered_cap(self.own_share(most, pilot, spread), col, row).min(self.samples);
        }
        dithered_ratio(self.own_share256(most, pilot, spread, self.doubling()), 256, col, row).min(self.samples)
    }

    /// [`Renderer::share`] before its dither, in whole rays (rounded down):
    /// the micro:bit's, whose flash has no room for [`Renderer::own_share256`].
    fn own_share(&self, most: u32, pilot: u32, spread: u32) -> u32 {
        // In u32, saturating (lamps' spreads). No survey spread: the frame's cap.
        match most
            .saturating_sub(pilot)
            .saturating_mul(spread)
            .checked_div(self.spread)
        {
            Some(extra) => pilot.saturating_add(extra).min(self.samples),
            None => most.max(pilot),
        }
    }

    /// [`Renderer::share`] before its dither, doubling or not, in 256ths of
    /// a ray: P + (C − P) σ/σ̄ with C the frame's cap before it was rounded
    /// down where `most` is it (the survey sums it to decide
    /// [`Renderer::doubling`]). Whole rays rounded every share down, and C
    /// to the pilot where it was under one ray above it: a frame's unsettled
    /// pixels then all stopped at their pilot (seed 11777 at `point` 21 and
    /// 22, -2.66 and -2.83 dB against the floor); the margin that rounding
    /// lent is now σ̄'s (see [`spread_margin`]).
    fn own_share256(&self, most: u32, pilot: u32, spread: u32, doubling: bool) -> u32 {
        let most256 = match self.budget256 {
            c if c > 0 && most == self.cap && c >> 8 == most => c as u64,
            _ => (most as u64) << 8,
        };
        let pilot256 = (pilot as u64) << 8;
        let own = match (most256.saturating_sub(pilot256) * spread as u64).checked_div(self.spread as u64) {
            Some(extra) => (pilot256 + extra).min((self.samples as u64) << 8),
            None => most256.max(pilot256),
        };
        // At least one doubling where the cap allows: a spread far under the
        // frame's mean (lamps' rims raise it) is no sign of a settled mean
        // (seed 9027: such pixels stopped at 4 of 14 with 7 times the error).
        let own = if doubling && most >= 2 * pilot {
            own.max(2 * pilot256)
        } else {
            own
        };
        own.min(u32::MAX as u64) as u32
    }

    /// The plane that cuts this lens, if one does (see [`cut`]).
    pub fn lens_cut(&self) -> &LensCut {
        &self.cut
    }

    /// Pixel (`col`, `row`) as 8-bit RGB: each channel clamped and `round(255 v)`;
    /// before the scanline filter (see [`scanline`]), which rows carry.
    ///
    /// # Panics
    ///
    /// Never, as [`Renderer::pixel_colour`].
    pub fn pixel(&self, col: u32, row: u32) -> Rgb888 {
        rgb(self.pixel_colour(col, row))
    }

    /// Pixel (`col`, `row`) in 256ths of a level a channel, as rows carry it
    /// to the scanline filter and gaps ([`scanline::Fine`]; its
    /// [`scanline::Fine::rgb`] is [`Renderer::pixel`]).
    pub fn pixel_fine(&self, col: u32, row: u32) -> scanline::Fine {
        scanline::Fine::of(self.pixel_colour(col, row))
    }

    /// Fills `out` with row `row`, from column 0 (`out.len()` pixels at most
    /// the image width; extra entries are left untouched), filtered where far
    /// out of focus (see [`scanline`]; a shorter `out` ends the row), and returns the
    /// rays the row cast (a row of 8192 pixels at 65535 rays fits a u32).
    ///
    /// # Panics
    ///
    /// Never, for any `row` and any length of `out`.
    pub fn render_row(&self, row: u32, out: &mut [Rgb888]) -> u32 {
        let cols = out.len().min(self.camera.cols() as usize) as u32;
        let mut pixels = self.scanline(row, cols);
        for (px, c) in out.iter_mut().zip(&mut pixels) {
            *px = c;
        }
        pixels.rays()
    }
}

/// A mean colour as 8-bit RGB, each channel clamped and rounded ([`Renderer::pixel`]'s).
#[inline]
pub(crate) fn rgb<S: Scalar>(c: Vec3<S>) -> Rgb888 {
    Rgb888::new(c.x.to_u8(), c.y.to_u8(), c.z.to_u8())
}

/// Renders `scene` into `target`, one `fill_contiguous` call per row.
///
/// The image is the target's bounding box (its size, from its top-left
/// corner); the target's colour type converts
/// from [`Rgb888`] (Rgb565 and others through embedded-graphics' own
/// conversions). An empty target draws nothing. A side longer than
/// [`MAX_IMAGE_SIDE`](crate::camera::MAX_IMAGE_SIDE) gets an image of that
/// many pixels, from the top-left corner; the rest of the target is untouched.
///
/// # Errors
///
/// Only the target's own errors.
///
/// # Panics
///
/// Never.
pub fn render<S, D>(scene: &Scene<S>, target: &mut D) -> Result<(), D::Error>
where
    S: Scalar,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let area = target.bounding_box();
    if area.size.width == 0 || area.size.height == 0 {
        return Ok(());
    }
    let renderer = Renderer::new(scene, area.size.width, area.size.height);
    render_with(&renderer, target)
}

/// Renders with a prepared [`Renderer`] (e.g. with a sample override) into
/// `target`, one `fill_contiguous` per row: the renderer's image size, placed
/// at the top-left corner of the target's bounding box. Pixels that would lie
/// beyond `i32::MAX` in x or y (a target at the very edge of the plane) are
/// not drawn.
///
/// # Errors
///
/// Only the target's own errors.
///
/// # Panics
///
/// Never.
pub fn render_with<S, D>(renderer: &Renderer<'_, S>, target: &mut D) -> Result<(), D::Error>
where
    S: Scalar,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let (origin, cols, rows) = addressable_area(renderer, target);
    for row in 0..rows {
        // No overflow: row < addressable(origin.y).
        let top_left = Point::new(origin.x, origin.y + row as i32);
        let area = Rectangle::new(top_left, Size::new(cols, 1));
        target.fill_contiguous(&area, renderer.scanline(row, cols).map(D::Color::from))?;
    }
    Ok(())
}

/// The target's top-left corner and the image's columns and rows drawn there.
/// Only pixels with an i32 address are drawn: a target near the edge of the
/// plane gets the part of the image that fits (`origin + row` would overflow).
#[inline]
pub(crate) fn addressable_area<S: Scalar, D: DrawTarget>(renderer: &Renderer<'_, S>, target: &D) -> (Point, u32, u32) {
    let origin = target.bounding_box().top_left;
    let cols = renderer.camera().cols().min(addressable(origin.x));
    let rows = renderer.camera().rows().min(addressable(origin.y));
    (origin, cols, rows)
}

/// How many coordinates from `start` up fit in an i32: `i32::MAX - start + 1`, capped.
pub(crate) fn addressable(start: i32) -> u32 {
    u32::try_from(i32::MAX as i64 - start as i64 + 1).unwrap_or(u32::MAX)
}

#[cfg(test)]
std::thread_local! {
    /// Surveys that cast rays on this thread (tests: set-up work done once).
    static SURVEYS: core::cell::Cell<u32> = const { core::cell::Cell::new(0) };
}

#[cfg(test)]
mod survey_tests {
    use super::*;
    use crate::I16F16;

    fn surveys_in<T>(f: impl FnOnce() -> T) -> (T, u32) {
        let before = SURVEYS.with(|n| n.get());
        let t = f();
        (t, SURVEYS.with(|n| n.get()) - before)
    }

    /// A builder that changes nothing surveys nothing more, one that changes
    /// the count surveys again, and `new_with_samples` surveys once for the
    /// same renderer (cap, survey and pixels) as `new` then `with_samples`.
    #[test]
    fn the_survey_runs_once_a_setting() {
        let scene = Scene::<I16F16>::parse(include_str!("../../scenes/paper-program1.scene")).unwrap();
        let point = scene.camera.samples;
        let (r, n) = surveys_in(|| Renderer::new(&scene, 64, 48));
        assert_eq!(n, 1);
        let (r, n) = surveys_in(|| {
            r.with_samples(point)
                .with_adaptive(true)
                .with_sampler(Sampler::Stratified)
        });
        assert_eq!((n, r.samples), (0, point));
        for samples in [Some(40), Some(point), None] {
            let (once, n) = surveys_in(|| Renderer::new_with_samples(&scene, 64, 48, samples));
            assert_eq!(n, 1);
            let (twice, n) = surveys_in(|| Renderer::new(&scene, 64, 48).with_samples(samples.unwrap_or(point)));
            assert_eq!(n, if samples == Some(40) { 2 } else { 1 });
            assert_eq!(once.adaptive_cap(), twice.adaptive_cap());
            for (x, y) in [(0, 0), (17, 23), (63, 47)] {
                assert_eq!(once.pixel_rays(x, y), twice.pixel_rays(x, y));
            }
        }
    }

    /// An adaptive frame is surveyed wherever its pilots, with the survey's
    /// own rays (the pilots again over the cell's area), leave any of the
    /// budget (40 % of `point`), however little: at 128×96 (cells of 8)
    /// `point` 21 to 25 too, whose pilots of 8 leave under a fifth; at 64×48
    /// (cells of 4, the survey a sixteenth of the pilots) not 21, where
    /// pilots and survey together would take 40.5 %.
    #[test]
    fn a_survey_wherever_the_pilots_leave_rays() {
        let scene = Scene::<I16F16>::parse(include_str!("../../scenes/paper-program1.scene")).unwrap();
        for (cols, rows, stride, expected) in [(128, 96, 8, 5), (64, 48, 4, 4)] {
            let mut surveyed = 0;
            for samples in ADAPTIVE_MIN_POINT..=40 {
                let (r, n) = surveys_in(|| Renderer::new_with_samples(&scene, cols, rows, Some(samples)));
                // Program 1 has no lamp in view: every pixel's pilot is the plain one.
                assert!(!r.bright_footprints().at_risk(cols / 2, rows / 2));
                assert_eq!(survey_stride(cols, rows, samples), Some(stride));
                // pilot (1 + 1/s²) < 40 % of `point`.
                let leaves = 5 * adaptive_pilot(samples) * (stride * stride + 1) < 2 * samples * stride * stride;
                assert_eq!(n == 1, leaves, "{cols}x{rows} at point {samples}: {n} surveys");
                surveyed += (21..=25).contains(&samples) as u32 * n;
            }
            assert_eq!(surveyed, expected, "{cols}x{rows}");
        }
    }

    /// Each survey spot lies in its own cell, and over a 320×240 grid
    /// (40×30 cells of 8) a pattern of period 8 in either direction, on for
    /// half of it, holds half of the spots, 45 to 55 % at any phase (the
    /// cells' centres put them all on one side), every offset taken.
    #[test]
    fn the_survey_spots_are_spread_over_every_phase_of_their_cells() {
        for s in [4, 8, 16] {
            let mut offsets = [[0u32; 16]; 2];
            for j in 0..30 {
                for k in 0..40 {
                    let (x, y) = survey_spot(j, k, s, 0);
                    assert_eq!((x / s, y / s), (k, j), "stride {s}");
                    offsets[0][(x % s) as usize] += 1;
                    offsets[1][(y % s) as usize] += 1;
                }
            }
            for (axis, counts) in offsets.iter().enumerate() {
                assert!(
                    counts[..s as usize].iter().all(|&n| n > 0),
                    "stride {s} axis {axis}: {counts:?}"
                );
                for phase in 0..s {
                    let on: u32 = (0..s / 2).map(|i| counts[((phase + i) % s) as usize]).sum();
                    assert!(
                        (540..=660).contains(&on),
                        "stride {s} axis {axis} phase {phase}: {on} of 1200"
                    );
                }
            }
        }
    }
}

#[cfg(test)]
mod dither_tests {
    use super::*;

    /// The 8×8 ordered dither built by doubling the 2×2 one, as Bayer
    /// defines it (M₂ₙ = 4 Mₙ plus the 2×2 rank of the quadrant): the
    /// reference for [`bayer_rank`].
    fn bayer_doubled(col: u32, row: u32, size: u32) -> u32 {
        if size == 1 {
            return 0;
        }
        let half = size / 2;
        let quadrant = [[0, 2], [3, 1]][(row / half % 2) as usize][(col / half % 2) as usize];
        4 * bayer_doubled(col % half, row % half, half) + quadrant
    }

    #[test]
    fn the_dither_ranks_are_bayers_8x8_matrix_and_every_2x2_block_takes_each_quarter() {
        for row in 0..24 {
            for col in 0..24 {
                assert_eq!(
                    bayer_rank(col, row),
                    bayer_doubled(col % 8, row % 8, 8),
                    "({col}, {row})"
                );
            }
        }
        for (c0, r0) in [(0, 0), (2, 6), (6, 4)] {
            let mut quarters: [u32; 4] =
                core::array::from_fn(|i| bayer_rank(c0 + i as u32 % 2, r0 + i as u32 / 2) / 16);
            quarters.sort_unstable();
            assert_eq!(quarters, [0, 1, 2, 3], "block at ({c0}, {r0})");
        }
    }
}

#[cfg(test)]
mod settled_tests {
    use super::*;

    /// The samples' spread in 128-bit integers as first written: the reference.
    fn spread_u128(s: &LevelStats, n: u32) -> u32 {
        let n = n as u128;
        let var: u128 = (0..3)
            .map(|i| {
                let total: u128 = s.quarter.iter().map(|q| q[i] as u128).sum();
                (n * s.sum_sq[i] as u128).saturating_sub(total * total)
            })
            .sum();
        let scaled = (var << 8) / (n * (n - 1));
        (scaled.isqrt() as u32).max(1)
    }

    /// The test in 128-bit integers as first written: the reference.
    fn settled_u128(s: &LevelStats, n: u32, full: u32) -> bool {
        let (n, h, full) = (n as u128, (n / 4) as u128, full as u128);
        let (t, rel, gain) = (
            ADAPTIVE_VAR_SIXTEENTHS as u128,
            ADAPTIVE_REL_SIXTEENTHS as u128,
            ADAPTIVE_MAX_GAIN as u128,
        );
        let quarters_bound = 192 * h * h;
        let abs_q = quarters_bound * t;
        let abs_s = gain * t * n * n * (n - 1);
        let rel_q = full * 16 * n * (n - 1);
        let rel_ok = full * 16 <= rel * n * gain;
        (0..3).all(|i| {
            let q: [u128; 4] = core::array::from_fn(|j| s.quarter[j][i] as u128);
            let total = q[0] + q[1] + q[2] + q[3];
            let spread_q: u128 = q.iter().map(|&x| (4 * x).abs_diff(total).pow(2)).sum();
            let spread = (n * s.sum_sq[i] as u128).saturating_sub(total * total);
            let absolute = spread_q * 16 <= abs_q && spread * 16 <= abs_s;
            absolute || (rel_ok && spread_q * rel_q <= rel * spread * quarters_bound)
        })
    }

    #[test]
    fn mul_wide_is_the_u128_product() {
        let mut next = crate::test_rng::xorshift32(7);
        for _ in 0..20_000 {
            let a = ((next() as u64) << 32 | next() as u64) >> (next() % 64);
            let b = ((next() as u64) << 32 | next() as u64) >> (next() % 64);
            let p = a as u128 * b as u128;
            assert_eq!(mul_wide(a, b), ((p >> 64) as u64, p as u64), "{a} * {b}");
        }
        assert_eq!(mul_wide(u64::MAX, u64::MAX), (u64::MAX - 1, 1));
    }

    /// Pixels of samples around a mean with a spread from none to the whole
    /// range (lamps up to 2¹⁶ levels among them), checked at every power of
    /// two up to 2¹⁵ samples against a `full` of up to 65535: both tests
    /// agree on every one, and both answers occur.
    #[test]
    fn settled_in_u64_is_the_u128_test() {
        let mut next = crate::test_rng::xorshift32(0x05e7_71ed);
        let (mut yes, mut no) = (0, 0);
        for pixel in 0..400 {
            let mean = next() % 70_000;
            let spread = [0, 1, 3, 20, 300, 65_535][pixel % 6];
            let full = [16, 25, 64, 100, 1000, 65_535][(next() % 6) as usize];
            let top = if pixel % 3 == 0 { 1 << 15 } else { 1 << 10 };
            let mut s = LevelStats::default();
            let mut check = 4;
            for k in 0..top {
                let level = |r: u32| (mean + r % (2 * spread + 1)).saturating_sub(spread).min(65_535);
                // Only the level sums matter here: one colour channel each.
                for i in 0..3 {
                    let l = level(next());
                    let q = (k / (check / 4)).min(3) as usize;
                    s.quarter[q][i] += l;
                    s.sum_sq[i] += (l * l) as u64;
                }
                if k + 1 == check {
                    let spread = s.settled(check, full);
                    let got = spread.is_none();
                    assert_eq!(
                        got,
                        settled_u128(&s, check, full),
                        "n {check} full {full} pixel {pixel}"
                    );
                    if let Some(spread) = spread {
                        assert_eq!(spread, spread_u128(&s, check), "n {check} pixel {pixel}");
                    }
                    if got {
                        yes += 1;
                    } else {
                        no += 1;
                    }
                    s.double();
                    check *= 2;
                }
            }
        }
        assert!(yes > 100 && no > 100, "{yes} settled, {no} not");
    }
}
