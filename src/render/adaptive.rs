//! A pixel's lens rays, and when it stops taking them (docs/sampling.md).
//!
//! Three mechanisms, each on that page with its reasoning:
//!
//! 1. **An error estimate at every doubling.** The stratified sampler's
//!    first n points are a (0,2)-net for every power of two n, and so are
//!    its first n/2. Past a pilot, at each power of two n a pixel compares
//!    the mean of its first n/2 rays with the mean of all n (Cycles'
//!    adaptive sampling): half their difference estimates the error of the
//!    mean of n.
//! 2. **A stop rule that spends rays where they lower the error most.**
//!    Doubling from n rays lowers the squared error by about half of it for
//!    n more rays. A pixel goes on while that gain per ray is above the
//!    frame's price, that is while its estimate is above a threshold times
//!    √(n / pilot) ([`StopRule::stops`]).
//! 3. **A pre-pass that sets the threshold.** A grid of pixels renders
//!    every sample and records its estimates; the threshold is the lowest
//!    whose predicted rays, with the pre-pass's own, stay within
//!    [`BUDGET_EIGHTHS`] eighths of `point` a pixel ([`survey`]).
//!
//! Everything is integer arithmetic on the number type's own colours: the
//! Q16.16 renderer decides in Q16.16, the f32 one in f32, each bit for bit
//! on every machine.

use crate::geometry::vec3::Vec3;
use crate::number::Scalar;

/// The frame's rays, the pre-pass's included, as eighths of `point` a
/// pixel (a quality knob): 3/8, under the 40 % the adaptive render
/// promises by the pre-pass's own sampling error (docs/sampling.md).
pub const BUDGET_EIGHTHS: u64 = 3;

/// The pilot is about `point` over this (a quality knob): after it, a
/// pixel has seen the lens at a quarter of the full render's resolution.
pub const PILOT_DIVISOR: u32 = 4;

/// The smallest pilot: two halves of 2 rays to compare.
pub const MIN_PILOT: u32 = 4;

/// The largest pilot (a quality knob): 32 rays, one in each of 32 equal
/// cells of the lens, find what covers a thirty-second of it.
pub const MAX_PILOT: u32 = 32;

/// Pre-pass pixels: about one in this many of the frame's.
const SURVEY_SHARE: u64 = 32;

/// Pre-pass pixels at most: the threshold's sampling error is then a few
/// per cent of the frame's rays.
const SURVEY_MAX: u64 = 256;

/// Thresholds the pre-pass tries: 0, then 2^(k/4) for k = 0..55
/// (sixteenths of a level), past the largest possible estimate (√3 · 4080).
const CANDIDATES: usize = 57;

/// When a pixel stops taking lens rays: set once a frame by the pre-pass.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct StopRule {
    /// Rays every pixel casts before its first check: a power of two.
    pub pilot: u32,
    /// The error a pixel may keep at its pilot, in 256ths of an 8-bit level
    /// summed over red, green and blue; √(n / pilot) times it at n rays.
    pub threshold: u32,
    /// Rays the pre-pass cast to choose the threshold.
    pub survey_rays: u32,
}

impl StopRule {
    /// Whether a pixel whose estimate at `n` rays is `estimate` (256ths of a
    /// level, summed over channels) stops there: `estimate ≤ threshold ·
    /// √(n / pilot)`, squared into integers.
    pub fn stops(&self, n: u32, estimate: u32) -> bool {
        let e = estimate as u64;
        let t = self.threshold as u64;
        e * e * self.pilot as u64 <= t * t * n as u64
    }
}

impl crate::bytes::Field for StopRule {
    crate::bytes::baked_fields!(StopRule {
        pilot,
        threshold,
        survey_rays
    });
}

/// The largest power of two at most `n` (1 for 0).
fn floor_pow2(n: u32) -> u32 {
    1 << (31 - n.max(1).leading_zeros())
}

/// The pilot for `samples` rays a pixel: `samples / 8` rounded down to a
/// power of two, held within [`MIN_PILOT`]..=[`MAX_PILOT`].
pub fn pilot(samples: u32) -> u32 {
    floor_pow2(samples / PILOT_DIVISOR).clamp(MIN_PILOT, MAX_PILOT)
}

/// A pixel's running sums: the mean's accumulators in the number type,
/// and each channel's displayed value (clamped to [0, 1], in sixteenths of
/// an 8-bit level) summed and squared, for the error estimate.
struct Sums<S: Scalar> {
    colour: [S::Acc; 3],
    linear: [u64; 3],
    squares: [u64; 3],
}

impl<S: Scalar> Sums<S> {
    fn add(&mut self, c: Vec3<S>) {
        for (k, v) in [c.x, c.y, c.z].into_iter().enumerate() {
            self.colour[k] = S::acc_add(self.colour[k], v);
            let f = (v.to_fine() >> 4) as u64;
            self.linear[k] += f;
            self.squares[k] += f * f;
        }
    }

    /// The estimated error of the mean of `n` ≥ 2 rays: the standard error
    /// √(s²/n) of each channel (s² the rays' sample variance) summed in
    /// quadrature over channels, in sixteenths of a level, rounded down.
    fn estimate(&self, n: u32) -> u32 {
        let n = n as u64;
        // n Σf² − (Σf)² = n (n − 1) s²: below 2⁶³ for 65535 rays of 4080.
        let spread: u64 = (0..3)
            .map(|k| (n * self.squares[k]).saturating_sub(self.linear[k] * self.linear[k]))
            .sum();
        isqrt(spread / (n * n * (n - 1))) as u32
    }

    fn mean(&self, n: u32) -> Vec3<S> {
        let [r, g, b] = self.colour.map(|a| S::acc_mean(a, n));
        Vec3::new(r, g, b)
    }
}

/// ⌊√v⌋, bit by bit.
fn isqrt(mut v: u64) -> u64 {
    let (mut root, mut bit) = (0u64, 1u64 << 62);
    while bit > v {
        bit >>= 2;
    }
    while bit != 0 {
        if v >= root + bit {
            v -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// A lens pixel's mean colour and the rays it cast: `cast(strata)` casts
/// its sampler's next ray, whose checker footprint is one of `strata` equal
/// cells of the lens (a power of two). With a `pilot`, at every power of
/// two n from it below `samples` the pixel asks `stop(n, estimate)` and
/// stops if told; a ray's cell is then one of the rays it has at its next
/// check. Without a pilot it casts every sample, each one of `samples`
/// rounded down to a power of two.
pub(crate) fn pixel<S: Scalar>(
    samples: u32,
    pilot: Option<u32>,
    mut cast: impl FnMut(u32) -> Vec3<S>,
    mut stop: impl FnMut(u32, u32) -> bool,
) -> (Vec3<S>, u32) {
    let finest = floor_pow2(samples);
    let mut strata = pilot.map_or(finest, |p| p.min(finest));
    let mut sums = Sums::<S> {
        colour: [S::acc_zero(); 3],
        linear: [0; 3],
        squares: [0; 3],
    };
    let mut n = 0;
    while n < samples {
        sums.add(cast(strata));
        n += 1;
        if n.is_power_of_two() && pilot.is_some_and(|p| n >= p) && n < samples {
            if stop(n, sums.estimate(n)) {
                break;
            }
            strata = (2 * n).min(finest);
        }
    }
    (sums.mean(n), n)
}

/// A well-mixed 32-bit hash of a grid cell (a multiply-xorshift).
fn cell_hash(i: u32, j: u32) -> u32 {
    let mut h = i.wrapping_mul(0x9E37_79B1) ^ j.wrapping_mul(0x85EB_CA77);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^ (h >> 13)
}

/// 2^(k/4) for candidate k + 1, rounded; 0 for candidate 0.
fn candidate(j: usize) -> u32 {
    const QUARTERS: [u32; 4] = [256, 304, 362, 431];
    match j {
        0 => 0,
        j => (QUARTERS[(j - 1) % 4] << ((j - 1) / 4)) >> 8,
    }
}

/// The frame's stop rule for `samples` rays a pixel on `cols` × `rows`
/// pixels, from a pre-pass over a grid of them: `run(x, y, pilot, record)`
/// renders pixel (x, y) as [`pixel`] does with that pilot, calling
/// `record(n, estimate)` at each check and never stopping, and returns its
/// rays. `None` where `samples` leaves no room past two pilots.
///
/// For each candidate threshold the grid's rays predict the frame's; the
/// rule takes the lowest threshold whose frame, with the pre-pass's own
/// rays, stays within [`BUDGET_EIGHTHS`] of `samples` a pixel.
pub(crate) fn survey(
    samples: u32,
    (cols, rows): (u32, u32),
    mut run: impl FnMut(u32, u32, u32, &mut dyn FnMut(u32, u32) -> bool) -> u32,
) -> Option<StopRule> {
    let pilot = pilot(samples);
    if samples < 2 * pilot {
        return None;
    }
    let pixels = cols as u64 * rows as u64;
    let wanted = (pixels / SURVEY_SHARE).clamp(1, SURVEY_MAX);
    // The smallest stride whose grid has at most `wanted` cells.
    let mut stride = 1u32;
    while (stride as u64 * stride as u64) * wanted < pixels {
        stride += 1;
    }
    let mut rays = [0u64; CANDIDATES];
    let (mut count, mut survey_rays) = (0u64, 0u64);
    for (j, y0) in (0..rows).step_by(stride as usize).enumerate() {
        for (i, x0) in (0..cols).step_by(stride as usize).enumerate() {
            // A point of each cell, hashed: a regular grid aliases with
            // regular scenes (a checkerboard).
            let h = cell_hash(i as u32, j as u32);
            let (x, y) = (x0 + h % stride, y0 + (h >> 16) % stride);
            if x >= cols || y >= rows {
                continue;
            }
            // At most 15 checks: pilot 4 · 2^14 reaches 65535 samples.
            let mut found = [0u32; 16];
            let mut checks = 0;
            let n = run(x, y, pilot, &mut |_, e| {
                found[checks.min(15)] = e;
                checks += 1;
                false
            });
            survey_rays += n as u64;
            count += 1;
            for (j, total) in rays.iter_mut().enumerate() {
                let rule = StopRule {
                    pilot,
                    threshold: candidate(j),
                    survey_rays: 0,
                };
                let at = (0..checks.min(16)).find(|&i| rule.stops(pilot << i, found[i]));
                *total += at.map_or(samples, |i| pilot << i) as u64;
            }
        }
    }
    let budget = (pixels * samples as u64 * BUDGET_EIGHTHS / 8).saturating_sub(survey_rays);
    let j = (0..CANDIDATES)
        .find(|&j| rays[j] * pixels <= budget * count)
        .unwrap_or(CANDIDATES - 1);
    Some(StopRule {
        pilot,
        threshold: candidate(j),
        survey_rays: survey_rays as u32,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_rise_by_quarter_octaves_past_the_largest_estimate() {
        assert_eq!(candidate(0), 0);
        assert_eq!(candidate(1), 1);
        assert_eq!(candidate(5), 2);
        for j in 1..CANDIDATES - 1 {
            assert!(candidate(j + 1) >= candidate(j));
            let ratio = candidate(j + 1) as f64 / candidate(j).max(1) as f64;
            assert!(ratio <= 2.0 + 1e-9, "{j}");
        }
        // Three channels of 255 levels in 256ths: every estimate stops at the last.
        assert!(candidate(CANDIDATES - 1) as u64 > 3 * 255 * 256);
    }

    #[test]
    fn the_threshold_grows_with_the_root_of_the_rays() {
        let rule = StopRule {
            pilot: 8,
            threshold: 100,
            survey_rays: 0,
        };
        assert!(rule.stops(8, 100) && !rule.stops(8, 101));
        // √4 = 2 at four times the pilot.
        assert!(rule.stops(32, 200) && !rule.stops(32, 201));
        assert!(rule.stops(16, 141) && !rule.stops(16, 142));
    }

    #[test]
    fn the_pilot_is_an_eighth_of_point_within_its_bounds() {
        assert_eq!(pilot(1), MIN_PILOT);
        assert_eq!(pilot(70), 8);
        assert_eq!(pilot(128), 16);
        assert_eq!(pilot(65535), MAX_PILOT);
        for s in 1..2000 {
            assert!(pilot(s).is_power_of_two());
        }
    }
}
