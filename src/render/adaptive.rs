//! A pixel's lens rays, and when it stops taking them (docs/sampling.md).
//!
//! Three mechanisms, each on that page with its reasoning:
//!
//! 1. **An error estimate at every doubling.** Every block of 2^m
//!    consecutive points of the stratified sampler is a (0,2)-net. Past a
//!    pilot, at each power of two n a pixel splits its rays into
//!    [`BLOCKS`] blocks of n/8 and takes the standard error of their means
//!    (Cycles' adaptive sampling compares two halves: one degree of
//!    freedom where eight blocks give seven).
//! 2. **A stop rule that spends rays where they lower the error most.**
//!    Doubling from n rays lowers the squared error by about half of it for
//!    n more rays. A pixel goes on while that gain per ray is above the
//!    frame's price, that is while its estimate is above a threshold times
//!    √(n / pilot) ([`StopRule::stops`]).
//! 3. **A pre-pass that sets the threshold.** A grid of pixels renders
//!    every sample and records its estimates and means; the rule is the
//!    threshold of least predicted squared error whose predicted rays, the
//!    pre-pass's included, stay within [`BUDGET_EIGHTHS`] eighths of
//!    `point` a pixel, or plain samples within 40 % where they predict less
//!    error (the pre-pass, `survey`).
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

/// The smallest pilot (a quality knob): 8 rays, one a block, the fewest
/// whose estimate has the blocks' seven degrees of freedom.
pub const MIN_PILOT: u32 = 8;

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
    /// Rays every pixel casts before its first check: a power of two, or,
    /// with a threshold of `u32::MAX`, the rays every pixel casts.
    pub pilot: u32,
    /// The error a pixel may keep at its pilot: its estimated standard
    /// error in sixteenths of an 8-bit level, red, green and blue in
    /// quadrature; √(n / pilot) times it at n rays. `u32::MAX`: plain
    /// samples, every pixel stops at the pilot.
    pub threshold: u32,
    /// Rays the pre-pass cast to choose the rule.
    pub survey_rays: u32,
}

impl StopRule {
    /// Whether a pixel whose estimate at `n` rays is `estimate` (in the
    /// threshold's units) stops there: `estimate ≤ threshold · √(n / pilot)`,
    /// squared into integers (saturating).
    pub fn stops(&self, n: u32, estimate: u32) -> bool {
        if self.threshold == u32::MAX {
            return true;
        }
        let (e, t) = (estimate as u64, self.threshold as u64);
        (e * e).saturating_mul(self.pilot as u64) <= (t * t).saturating_mul(n as u64)
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

/// The pilot for `samples` rays a pixel: `samples / 4` rounded down to a
/// power of two, at least [`MIN_PILOT`].
pub fn pilot(samples: u32) -> u32 {
    floor_pow2(samples / PILOT_DIVISOR).max(MIN_PILOT)
}

/// Blocks a pixel's rays are split into for the error estimate (a
/// quality knob): G − 1 = 7 degrees of freedom.
pub const BLOCKS: usize = 8;

/// A pixel's running sums: the mean's accumulators in the number type,
/// and each channel's displayed value (clamped to [0, 1], in sixteenths of
/// a level) summed over each of [`BLOCKS`] blocks of consecutive rays.
pub(crate) struct Sums<S: Scalar> {
    colour: [S::Acc; 3],
    blocks: [[u32; 3]; BLOCKS],
    /// Rays a block holds, as a power of two: its log.
    shift: u32,
}

impl<S: Scalar> Sums<S> {
    fn new() -> Self {
        Sums {
            colour: [S::acc_zero(); 3],
            blocks: [[0; 3]; BLOCKS],
            shift: 0,
        }
    }

    /// Adds ray `i` (from 0, in order), of colour `c`.
    fn add(&mut self, i: u32, c: Vec3<S>) {
        let block = &mut self.blocks[(i >> self.shift) as usize % BLOCKS];
        for (k, v) in [c.x, c.y, c.z].into_iter().enumerate() {
            self.colour[k] = S::acc_add(self.colour[k], v);
            block[k] += (v.to_fine() >> 4) as u32;
        }
    }

    /// The estimated error of the mean of the first `n` rays, a power of
    /// two ≥ 2: the spread of its blocks' means (each block a (0,2)-net of
    /// n/G points), as the standard error of their mean, summed in
    /// quadrature over channels, in sixteenths of a level, rounded down.
    pub(crate) fn estimate(&self, n: u32) -> u32 {
        if n < 2 {
            return 0;
        }
        let g = n.min(BLOCKS as u32) as u64;
        let size = (n as u64) / g;
        let spread: u64 = (0..3)
            .map(|k| {
                let (sum, squares) = self.blocks[..g as usize].iter().fold((0u64, 0u64), |(s, q), b| {
                    (s + b[k] as u64, q + b[k] as u64 * b[k] as u64)
                });
                (g * squares).saturating_sub(sum * sum)
            })
            .sum();
        // Never 0 (g ≥ 2, size ≥ 1): `checked_div` spares a panicking check.
        let mean_square = spread.checked_div(g * g * (g - 1) * size * size).unwrap_or(0);
        crate::number::wide::isqrt_floor_u64(mean_square) as u32
    }

    /// After a check at `n` rays: from [`BLOCKS`] rays on, pairs of blocks
    /// merge, and the next n rays fill the freed half.
    fn double(&mut self, n: u32) {
        if n < BLOCKS as u32 {
            return;
        }
        for k in 0..BLOCKS / 2 {
            let (a, b) = (self.blocks[2 * k], self.blocks[2 * k + 1]);
            self.blocks[k] = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        }
        self.blocks[BLOCKS / 2..].fill([0; 3]);
        self.shift += 1;
    }

    fn mean(&self, n: u32) -> Vec3<S> {
        let [r, g, b] = self.colour.map(|a| S::acc_mean(a, n));
        Vec3::new(r, g, b)
    }

    /// The mean of the first `n` rays as shown ([`shown`]).
    fn shown(&self, n: u32) -> [u32; 3] {
        shown(self.mean(n))
    }
}

/// A lens pixel's mean colour and the rays it cast: `cast(strata)` casts
/// its sampler's next ray, whose checker footprint is one of `strata` equal
/// cells of the lens (a power of two). With a `pilot`, after each ray from
/// the pilot's on (below `samples`) the pixel asks `stop(n, sums)` and
/// stops if told; a ray's cell is one of the rays the pixel has at its
/// next power of two. Without a pilot it casts every sample, each one of
/// `samples` rounded down to a power of two.
pub(crate) fn pixel<S: Scalar>(
    samples: u32,
    pilot: Option<u32>,
    mut cast: impl FnMut(u32) -> Vec3<S>,
    mut stop: impl FnMut(u32, &Sums<S>) -> bool,
) -> (Vec3<S>, u32) {
    let finest = floor_pow2(samples);
    let mut strata = pilot.map_or(finest, |p| floor_pow2(p).min(finest));
    let mut sums = Sums::<S>::new();
    let mut n = 0;
    while n < samples {
        sums.add(n, cast(strata));
        n += 1;
        let asks = pilot.is_some_and(|p| n >= p);
        if asks && n < samples && stop(n, &sums) {
            break;
        }
        if n.is_power_of_two() {
            sums.double(n);
            if asks {
                strata = (2 * n).min(finest);
            }
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

/// What the pre-pass records of one of its pixels: at each check from the
/// pilot (k for 2^k times the pilot) the estimate and the shown mean, the
/// shown mean at the plain render's rays, and at all of them.
struct Record {
    estimates: [u32; 16],
    means: [[u32; 3]; 16],
    checks: usize,
    plain: [u32; 3],
    all: [u32; 3],
}

/// Squared distance of two shown colours (sixteenths of a level).
fn squared(a: [u32; 3], b: [u32; 3]) -> u64 {
    (0..3).map(|k| (a[k].abs_diff(b[k]) as u64).pow(2)).sum()
}

/// The frame's stop rule for `samples` rays a pixel on `cols` × `rows`
/// pixels, from a pre-pass over a grid of them: `run(x, y, pilot, record)`
/// renders pixel (x, y) as [`pixel`] does with that pilot, calling
/// `record(n, sums)` after each ray from the pilot's on and never
/// stopping, and returns its mean; `None` where `samples` leaves no room
/// past two pilots.
///
/// Each grid pixel renders every sample. For each candidate threshold,
/// its rays and its squared distance to its own every-sample mean predict
/// the frame's rays and squared error (up to a constant: the every-sample
/// render's own error). The rule is the candidate of least predicted error
/// among those whose frame, with the pre-pass's own rays, stays within
/// [`BUDGET_EIGHTHS`] of `samples` a pixel; or, where plain stratified
/// samples in every pixel within 40 % of `samples` (their rays are exact)
/// predict less error, that: a pilot of those rays and no threshold (every
/// pixel stops there).
pub(crate) fn survey<S: Scalar>(
    samples: u32,
    (cols, rows): (u32, u32),
    mut run: impl FnMut(u32, u32, u32, &mut dyn FnMut(u32, &Sums<S>) -> bool) -> Vec3<S>,
) -> Option<StopRule> {
    let pilot = pilot(samples);
    let pixels = cols as u64 * rows as u64;
    if samples < 2 * pilot {
        // No room to adapt: plain samples within the promise, no pre-pass.
        let plain = (samples * 2 / 5).max(1);
        return (plain < samples).then_some(StopRule {
            pilot: plain,
            threshold: u32::MAX,
            survey_rays: 0,
        });
    }
    let wanted = (pixels / SURVEY_SHARE).clamp(1, SURVEY_MAX);
    // The smallest stride whose grid has at most `wanted` cells.
    let mut stride = 1u32;
    while (stride as u64 * stride as u64) * wanted < pixels {
        stride += 1;
    }
    let grid = (cols as u64).div_ceil(stride as u64) * (rows as u64).div_ceil(stride as u64);
    // Plain stratified samples, every pixel alike: their rays are known
    // exactly, so they take all of the promised 40 % but the pre-pass's.
    let promise = (pixels * samples as u64 * 2 / 5).saturating_sub(grid * samples as u64);
    let plain = ((promise / pixels) as u32).clamp(1, samples);
    let mut tally = Tally {
        rays: [0; CANDIDATES],
        errors: [0; CANDIDATES],
        plain_error: 0,
        count: 0,
    };
    for (j, y0) in (0..rows).step_by(stride as usize).enumerate() {
        for (i, x0) in (0..cols).step_by(stride as usize).enumerate() {
            // A point of each cell, hashed: a regular grid aliases with
            // regular scenes (a checkerboard).
            let h = cell_hash(i as u32, j as u32);
            let (x, y) = (x0 + h % stride, y0 + (h >> 16) % stride);
            if x < cols && y < rows {
                tally.add(&record(&mut run, (x, y), (pilot, plain, samples)), pilot, samples);
            }
        }
    }
    let survey_rays = tally.count * samples as u64;
    let budget = (pixels * samples as u64 * BUDGET_EIGHTHS / 8).saturating_sub(survey_rays);
    let best = (0..CANDIDATES)
        .filter(|&k| tally.rays[k] * pixels <= budget * tally.count)
        .min_by_key(|&k| tally.errors[k]);
    let survey_rays = survey_rays as u32;
    Some(match best {
        Some(k) if tally.errors[k] <= tally.plain_error => StopRule {
            pilot,
            threshold: candidate(k),
            survey_rays,
        },
        _ => StopRule {
            pilot: plain,
            threshold: u32::MAX,
            survey_rays,
        },
    })
}

/// Pre-pass pixel (x, y) rendered with every sample by `run`, recorded at
/// each check from `pilot` and at `plain` rays.
fn record<S: Scalar>(
    run: &mut impl FnMut(u32, u32, u32, &mut dyn FnMut(u32, &Sums<S>) -> bool) -> Vec3<S>,
    (x, y): (u32, u32),
    (pilot, plain, samples): (u32, u32, u32),
) -> Record {
    let mut r = Record {
        estimates: [0; 16],
        means: [[0; 3]; 16],
        checks: 0,
        plain: [0; 3],
        all: [0; 3],
    };
    let mean = run(x, y, pilot.min(plain), &mut |n, sums| {
        if n == plain {
            r.plain = sums.shown(n);
        }
        if n >= pilot && n.is_power_of_two() && r.checks < 16 {
            (r.estimates[r.checks], r.means[r.checks]) = (sums.estimate(n), sums.shown(n));
            r.checks += 1;
        }
        false
    });
    r.all = shown(mean);
    if plain == samples {
        r.plain = r.all;
    }
    r
}

/// The pre-pass's predictions: for each candidate threshold, its pixels'
/// rays and squared distance to their every-sample means; the same
/// distance for plain samples; and how many pixels.
struct Tally {
    rays: [u64; CANDIDATES],
    errors: [u64; CANDIDATES],
    plain_error: u64,
    count: u64,
}

impl Tally {
    fn add(&mut self, r: &Record, pilot: u32, samples: u32) {
        self.count += 1;
        self.plain_error += squared(r.plain, r.all);
        for (k, (total, error)) in self.rays.iter_mut().zip(self.errors.iter_mut()).enumerate() {
            let rule = StopRule {
                pilot,
                threshold: candidate(k),
                survey_rays: 0,
            };
            let at = (0..r.checks).find(|&c| rule.stops(pilot << c, r.estimates[c]));
            *total += at.map_or(samples, |c| pilot << c) as u64;
            *error += at.map_or(0, |c| squared(r.means[c], r.all));
        }
    }
}

/// A colour as shown: each channel clamped to [0, 1], in sixteenths of a level.
fn shown<S: Scalar>(c: Vec3<S>) -> [u32; 3] {
    [c.x, c.y, c.z].map(|v| (v.to_fine() >> 4) as u32)
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
        // Three channels of 255 levels in sixteenths, in quadrature: every
        // estimate stops at the last.
        assert!(candidate(CANDIDATES - 1) as f64 > 3f64.sqrt() * 255.0 * 16.0);
    }

    /// A generated lens integrand: a base value, up to two edges (half
    /// planes of another value) and up to two discs (spots, some bright),
    /// on the unit disc; the value at a lens point, clamped as displayed.
    struct Integrand {
        base: f64,
        edges: std::vec::Vec<(f64, f64, f64, f64)>,
        discs: std::vec::Vec<(f64, f64, f64, f64)>,
    }

    impl Integrand {
        fn new(u: &mut impl FnMut() -> f64) -> Self {
            let mut pick = |k: usize| {
                let count = (u() * k as f64) as usize;
                (0..count).map(|_| (u(), u(), u(), u())).collect()
            };
            let (edges, discs) = (pick(3), pick(3));
            Integrand {
                base: u(),
                edges,
                discs,
            }
        }

        fn at(&self, x: f64, y: f64) -> f64 {
            let mut v = self.base;
            for &(th, d, val, _) in &self.edges {
                let th = th * core::f64::consts::TAU;
                if x * th.cos() + y * th.sin() > 2.0 * d - 1.0 {
                    v = val;
                }
            }
            for &(cx, cy, r, val) in &self.discs {
                let (dx, dy) = (x - (2.0 * cx - 1.0), y - (2.0 * cy - 1.0));
                if dx * dx + dy * dy < 0.25 * r * r {
                    v = 4.0 * val;
                }
            }
            v.clamp(0.0, 1.0)
        }

        /// The mean over the unit disc, on a fine grid.
        fn mean(&self) -> f64 {
            let k = 400;
            let (mut sum, mut count) = (0.0, 0u32);
            for i in 0..k {
                for j in 0..k {
                    let (x, y) = ((2 * i + 1) as f64 / k as f64 - 1.0, (2 * j + 1) as f64 / k as f64 - 1.0);
                    if x * x + y * y < 1.0 {
                        sum += self.at(x, y);
                        count += 1;
                    }
                }
            }
            sum / count as f64
        }
    }

    /// On generated lens integrands through the stratified sampler, the
    /// mean's true error falls under the estimate (a standard error) at
    /// least as often as a normal error falls under one standard deviation
    /// (68 %), more often as rays grow (stratified samples beat independent
    /// ones, whose error the standard error describes). Beyond three
    /// estimates lie the pixels whose rays all missed a spot or an edge
    /// (the estimate is then 0): fewer as rays grow, as a feature every
    /// ray misses covers less of the lens (docs/sampling.md).
    #[test]
    fn the_error_estimate_is_calibrated_on_generated_lens_integrands() {
        use crate::camera::aperture::Aperture;
        use crate::camera::sampler::{PixelSamples, Sampler};
        let mut u = crate::test_rng::unit_f64(0x5eed_ca1b);
        let cases: std::vec::Vec<(Integrand, f64)> = (0..300)
            .map(|_| {
                let f = Integrand::new(&mut u);
                let m = f.mean();
                (f, m)
            })
            .collect();
        let mut misses = 1.0;
        for n in [8u32, 16, 32, 64] {
            let (mut within, mut within3, mut total) = (0u32, 0u32, 0u32);
            for (k, (f, truth)) in cases.iter().enumerate() {
                let mut lens = PixelSamples::new(Sampler::Stratified, k as u32 % 37, k as u32 / 37);
                let cast = |_| {
                    let (x, y) = lens.next(&Aperture::ROUND);
                    let v = f.at(x as f64 / 32768.0, y as f64 / 32768.0) as f32;
                    Vec3::new(v, v, v)
                };
                let mut estimate = 0;
                let (mean, _) = pixel::<f32>(n + 1, Some(n), cast, |m, sums| {
                    estimate = sums.estimate(m);
                    m == n
                });
                // Sixteenths of a level, three equal channels in quadrature.
                let err = (mean.x as f64 - truth).abs() * 255.0 * 16.0 * 3f64.sqrt();
                total += 1;
                within += (err <= estimate as f64 + 1.0) as u32;
                within3 += (err <= 3.0 * estimate as f64 + 1.0) as u32;
            }
            let (p1, p3) = (within as f64 / total as f64, within3 as f64 / total as f64);
            assert!(
                p1 >= 0.68,
                "{n} rays: the error fell within the estimate in {p1:.3} of pixels"
            );
            assert!(1.0 - p3 < misses, "{n} rays: beyond three estimates in {:.3}", 1.0 - p3);
            misses = 1.0 - p3;
        }
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
    fn the_pilot_is_a_quarter_of_point_as_a_power_of_two() {
        assert_eq!(pilot(1), MIN_PILOT);
        assert_eq!(pilot(70), 16);
        assert_eq!(pilot(128), 32);
        assert_eq!(pilot(65535), 8192);
        for s in 1..2000 {
            assert!(pilot(s).is_power_of_two());
        }
    }
}
