//! A lamp seen through part of the lens, made a part of its own.
//!
//! A pixel's rays all pass through its point in focus P (depth z_f). At a
//! lamp's depth d the ray from lens point L is at (1 − k) L + k P, k = d/z_f,
//! so it comes within ρ of the lamp's centre Q (its bounding sphere, radius
//! ρ) only if L lies in a disc of centre (Q − k P)/(1 − k) and radius about
//! ρ/|1 − k| on the lens: the lamp's *lens disc*, whose centre moves with the
//! pixel, linearly (P's u with the column, its v with the row). A lamp far
//! out of focus reaches the pixels of its bokeh through a small disc (seen
//! from `camera-features`' bokeh at `point` 33, a twentieth of the hexagon),
//! which a pilot of 8 or 16 stratified rays misses on many pixels; those
//! settle dark by up to 40 levels.
//!
//! So an adaptive pixel whose lens meets a lamp's disc, where its pilot
//! would put at most two rays in it on average, splits its lens in two: the
//! disc's *steps* in the stratified sampler's unit square, before the square
//! is mapped onto the aperture ([`STEPS`] ranges of `v`, the turn or the
//! place round a polygon's rim, between the tangents from the lens's centre,
//! each with the range of `u`, radius² over the rim's, that the disc spans
//! there), and the rest. The steps' share of the lens is their area in the
//! square, exactly (the map preserves area), so the two parts are weighed by
//! their shares as a cut lens's are ([`crate::render::parts::Shares`]):
//! post-stratification, which keeps the mean however the steps fit the lamp.
//! A pilot that put no ray in the steps casts one more there, uniform over
//! them ([`PixelLamp::point_at`]); where that ray moves the pixel's mean by a
//! level ([`spread`]) the pixel is not settled and goes on as far as the
//! frame's budget lets it, else the ray is left out.
//!
//! Per pixel in integers (the same parts in Q16.16 and f32, and on the
//! boards): the disc's centre from its linear coefficients, the steps from
//! integer square roots, the aperture's rim and its inverse
//! ([`Aperture::v_toward`]). Set-up (the coefficients) in f64.

// Without the parts (the micro:bit's build) only the baked form is read.
#![cfg_attr(feature = "no-lamp-parts", allow(dead_code, unused_imports))]

use crate::camera::aperture::Aperture;
use crate::camera::sampler::Sampler;
use crate::number::Scalar;
use crate::render::footprint::{BrightFootprints, MAX_BRIGHT};
use crate::render::parts::{Shares, FORCE_MIN_SHARE};
use crate::scene::Scene;

/// ⌊√x⌋ (the library's one 64-bit integer square root).
fn isqrt(x: u64) -> u64 {
    crate::number::wide::isqrt_rem_u64(x).0
}

/// The most lamps' discs a frame has: one a bright object.
pub const MAX_LAMPS: usize = MAX_BRIGHT;

/// Fixed-point fraction bits of a lens disc's centre coefficients.
const FRAC: u32 = 16;

/// The largest lens disc radius whose steps are laid as it is, in Q1.15
/// lens radii (their 64-bit products hold it).
const MAX_RADIUS: i64 = 2 * 32768;

/// The largest lens disc radius kept, in Q1.15 lens radii (512 lens radii):
/// a disc above [`MAX_RADIUS`] is a lamp near focus, which reaches the
/// pixels at its bokeh's rim through a sliver of the lens that a pilot
/// misses (mutant 96 of scripts/mutate-scenes.py, `point` 12, four lamps
/// 16 to 25 times white a few units before a focus at 24: -0.45 dB
/// against the floor at 320x240 without their parts, -0.12 with them).
/// There it stands for a disc of [`MAX_RADIUS`] that holds all the lens
/// holds of it ([`near_focus`]).
const MAX_BIG_RADIUS: i64 = 1 << 24;

/// A disc of centre (`x`, `y`) and radius `r` above [`MAX_RADIUS`] (Q1.15
/// lens radii) as one of [`MAX_RADIUS`] that holds the part of the lens
/// it covers: that part lies beyond the chord at h = |c| − r along its
/// centre's direction ê, whose ends are (h, ±√(1 − h²)); the disc of
/// radius 2 centred at (h + √(4 − (1 − h²)))ê holds both ends and the lens
/// between them. `None` where the disc holds the whole lens (h ≤ −1: one
/// part, none to stand for).
fn near_focus(x: i64, y: i64, r: i64) -> Option<(i64, i64)> {
    const ONE: i64 = 32768;
    // |x|, |y| < 2²⁵ here: the squares fit.
    let rho = isqrt((x * x + y * y) as u64) as i64;
    // ⌊ρ⌋: h low by a unit at most, the chord nearer the centre (more held).
    // Past this, ρ > r − 1 > 0 (r is over two lens radii): no zero divisor.
    let h = rho - r;
    if h <= -ONE {
        return None;
    }
    // 8 units inside the radius: its roots' roundings.
    let inner = MAX_RADIUS - 8;
    let xc = h + isqrt((inner * inner - (ONE * ONE - h * h)) as u64) as i64;
    // |x| xc < 2²⁵ · 2¹⁸; toward 0 by under a unit (the margin takes it),
    // by the shared exact division (no runtime `/`, no panic path).
    let scale = |a: i64| {
        let q = crate::number::wide::div_rem_u64(a.unsigned_abs() * xc as u64, rho as u64).0 as i64;
        if a < 0 {
            -q
        } else {
            q
        }
    };
    Some((scale(x), scale(y)))
}

/// The most rays a pixel's first block puts in a lamp's part on average, in
/// 65536ths: beyond two its stratified rays do not miss it (at most one,
/// `camera-features` at `point` 33 made 22.96 dB; two, 25.04).
const MAX_EXPECTED: u64 = 131072;

/// One lamp's lens disc: centre (`u0` + `du` (2 col + 1), `v0` + `dv` (2 row + 1))
/// in Q1.15 lens radii times 2¹⁶, radius `r` in Q1.15 lens radii.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct LensDisc {
    u: [i64; 2],
    v: [i64; 2],
    r: i32,
}

impl crate::bytes::Field for LensDisc {
    crate::bytes::baked_fields!(LensDisc { u, v, r }, check(d) {
        if !(0..=MAX_BIG_RADIUS as i32).contains(&d.r) {
            return Err(crate::bytes::BakeError::OutOfRange("lamp's lens disc radius not in 0..=2^24"));
        }
    });
}

/// The lens discs of a frame's lamps (the objects of [`BrightFootprints`]
/// with a bounding sphere wholly in front of the lens), for the stratified
/// sampler only; none with the feature `no-lamp-parts` (the micro:bit's).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LampParts {
    #[cfg(not(feature = "no-lamp-parts"))]
    discs: [LensDisc; MAX_BRIGHT],
    /// How many of `discs` are a lamp's.
    #[cfg(not(feature = "no-lamp-parts"))]
    count: u32,
    /// The discs (bits) of lamps that glow: bright by their ambient term
    /// alone, in every direction and under no light.
    #[cfg(not(feature = "no-lamp-parts"))]
    glowing: u32,
}

#[cfg(not(feature = "no-lamp-parts"))]
impl crate::bytes::Field for LampParts {
    crate::bytes::baked_fields!(LampParts { discs, count, glowing }, check(l) {
        if l.count as usize > MAX_BRIGHT {
            return Err(crate::bytes::BakeError::OutOfRange("more lamps' lens discs than bright objects"));
        }
        if l.glowing >> l.count != 0 {
            return Err(crate::bytes::BakeError::OutOfRange("a glowing lamp beyond the lamps' lens discs"));
        }
    });
}

// Without the parts the discs are read past (the format stays one):
// [`BAKED_WORDS`] words, one loop (the micro:bit's flash).
#[cfg(feature = "no-lamp-parts")]
crate::bytes::read_past_field!(LampParts, BAKED_WORDS);

/// The words baked lamps' discs take (see the `Field` impls): 9 a disc
/// (two i64 pairs and an i32), the count and the glowing ones.
const BAKED_WORDS: usize = 9 * MAX_BRIGHT + 2;
const _: () =
    assert!(BAKED_WORDS * 4 == MAX_BRIGHT * (2 * core::mem::size_of::<[i64; 2]>() + core::mem::size_of::<i32>()) + 8);

/// Steps of a lamp's part across the turn: each a range of `v` with its own
/// range of `u`, hugging the lens disc (one box held a hexagon's disc in
/// twice its area, and a ray drawn in it missed the lamp half the time:
/// `camera-features` at `point` 33 made 19.5 dB; 8 steps 21.9, 32 24.3, 64
/// 25.0 within 1.04 of the disc's area, the exact disc 25.8).
pub const STEPS: usize = 64;

/// A pixel's lamp part: [`STEPS`] steps of `step` in `v` from `v0` (round
/// the square), each a range of `u` (first and last; none where the first
/// is above the last), in 2⁻¹⁶ of the unit square, and the two parts' shares.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct PixelLamp {
    v0: u32,
    step: u32,
    u: [(u16, u16); STEPS],
    /// Outside the steps, inside them, and no third part.
    pub(crate) shares: Shares,
    /// Which of the frame's lamps' discs (in [`LampParts`]' order) it is.
    pub(crate) lamp: u8,
}

impl PixelLamp {
    /// The part of the unit-square point `(u, v)`: 1 in a step, else 0.
    #[inline]
    pub fn part(&self, (u, v): (u16, u16)) -> usize {
        let dv = v.wrapping_sub(self.v0 as u16) as u32;
        // Past the steps' turn (most rays): no division on the per-ray path.
        if dv >= self.step * STEPS as u32 {
            return 0;
        }
        match self.u.get((dv / self.step) as usize) {
            Some(&(lo, last)) => (lo <= u && u <= last) as usize,
            None => 0,
        }
    }

    /// The point of the steps at `at` of their area (a 32-bit fraction):
    /// uniform over them for `at` uniform.
    pub fn point_at(&self, at: u32) -> (u16, u16) {
        let step = self.step.max(1) as u64;
        let width = |(lo, last): (u16, u16)| (last as u64 + 1).saturating_sub(lo as u64);
        let area: u64 = self.u.iter().map(|&l| width(l) * step).sum();
        let mut left = (at as u64 * area) >> 32;
        for (j, &(lo, last)) in self.u.iter().enumerate() {
            let here = width((lo, last)) * step;
            if left < here {
                let (du, dv) = (left / step, left % step);
                let v = self.v0 as u64 + j as u64 * step + dv;
                return ((lo as u64 + du) as u16, v as u16);
            }
            left -= here;
        }
        (0, self.v0 as u16)
    }
}

impl LampParts {
    /// No lamp parts.
    #[cfg(not(feature = "no-lamp-parts"))]
    pub const NONE: LampParts = LampParts {
        discs: [LensDisc {
            u: [0; 2],
            v: [0; 2],
            r: 0,
        }; MAX_BRIGHT],
        count: 0,
        glowing: 0,
    };
    /// No lamp parts (the only ones without them).
    #[cfg(feature = "no-lamp-parts")]
    pub const NONE: LampParts = LampParts {};

    /// The lens discs of `scene`'s lamps: none without the parts.
    #[cfg(feature = "no-lamp-parts")]
    pub fn new<S: Scalar>(_scene: &Scene<S>, _bright: &BrightFootprints, _cols: u32, _rows: u32) -> Self {
        Self::NONE
    }

    /// Whether the frame has any lamp's lens disc: never without the parts.
    #[cfg(feature = "no-lamp-parts")]
    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        true
    }

    /// No lamp glows without them.
    #[cfg(feature = "no-lamp-parts")]
    #[inline(always)]
    pub fn glows(&self, _lamp: u8) -> bool {
        false
    }

    /// No lamp glows without them.
    #[cfg(feature = "no-lamp-parts")]
    #[inline(always)]
    pub fn any_glows(&self) -> bool {
        false
    }

    /// No pixel has a lamp part without them.
    #[cfg(feature = "no-lamp-parts")]
    #[inline(always)]
    pub fn pixel(&self, _col: u32, _row: u32, _aperture: &Aperture, _block: u32) -> Option<PixelLamp> {
        None
    }

    /// The lens discs of `scene`'s lamps (see `bright`) at `cols` × `rows`
    /// pixels. Set-up only, in f64.
    #[cfg(not(feature = "no-lamp-parts"))]
    pub fn new<S: Scalar>(scene: &Scene<S>, bright: &BrightFootprints, cols: u32, rows: u32) -> Self {
        let mut out = Self::NONE;
        let cam = &scene.camera;
        let a = cam.radius;
        if cam.sampler != Sampler::Stratified || a.is_nan() || a <= 0.0 {
            return out;
        }
        let Some([u, v, n]) = crate::camera::basis(cam) else {
            return out;
        };
        let z_f = cam.focus_depth();
        let big_n = cam.image_distance;
        if !(z_f > 0.0 && z_f.is_finite() && big_n > 0.0) {
            return out;
        }
        let p = cam.width / cols.max(1) as f64;
        let (half_w, half_h) = (cam.width / 2.0, p * rows.max(1) as f64 / 2.0);
        let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        for (i, obj) in scene.objects.iter().enumerate() {
            let Some((centre, rho)) = obj.bound().filter(|_| bright.is_bright(i)) else {
                continue;
            };
            let (c, rho) = (centre.to_f64(), rho.to_f64());
            let w = [0, 1, 2].map(|k| c[k] - cam.lens_position[k]);
            let (qu, qv, d) = (dot(w, u), dot(w, v), -dot(w, n));
            let k = d / z_f;
            // Straddling the lens plane or behind it (NaN too), or in focus.
            if d - rho <= 0.0 || d.is_nan() || (1.0 - k).abs() < 1e-3 {
                continue;
            }
            // Lens radii, Q1.15.
            let s = 32768.0 / a / (1.0 - k);
            // Lines at angle α to the axis pass within ρ of Q where their
            // depth plane's point is within ρ / cos α of it.
            let r = rho * libm::sqrt(dot(w, w)) / d * s.abs();
            // P = (z_f (x p − half_w) / N, z_f (half_h − y p) / N) at x = col + ½, y = row + ½.
            let g = k * z_f * p / (2.0 * big_n) * s;
            let fixed = |x: f64| x * (1u64 << FRAC) as f64;
            let coefficients = [
                (qu + k * z_f * half_w / big_n) * s,
                -g,
                (qv - k * z_f * half_h / big_n) * s,
                g,
            ];
            let fits = |x: f64| x.is_finite() && fixed(x.abs()) < (1u64 << 62) as f64;
            if !r.is_finite() || r >= MAX_BIG_RADIUS as f64 || !coefficients.iter().all(|&x| fits(x)) {
                continue;
            }
            let [u0, du, v0, dv] = coefficients.map(|x| libm::round(fixed(x)) as i64);
            let disc = LensDisc {
                u: [u0, du],
                v: [v0, dv],
                r: (libm::ceil(r) as i32).max(1),
            };
            match out.discs.get_mut(out.count as usize) {
                Some(slot) => *slot = disc,
                None => break,
            }
            let (ka, ambient) = (obj.material.ka.to_f64(), scene.ambient.to_f64());
            if (0..3).any(|k| ka[k] * ambient[k] > crate::render::footprint::BRIGHT) {
                out.glowing |= 1 << out.count;
            }
            out.count += 1;
        }
        out
    }

    /// Whether the frame has any lamp's lens disc.
    #[cfg(not(feature = "no-lamp-parts"))]
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Whether lamp `lamp` (its disc's index) glows: its ambient term alone
    /// is bright (see [`crate::render::footprint::BRIGHT`]).
    #[cfg(not(feature = "no-lamp-parts"))]
    #[inline]
    pub fn glows(&self, lamp: u8) -> bool {
        self.glowing >> lamp & 1 != 0
    }

    /// Whether any of the frame's lamps glows (see [`LampParts::glows`]).
    #[cfg(not(feature = "no-lamp-parts"))]
    #[inline]
    pub fn any_glows(&self) -> bool {
        self.glowing != 0
    }

    /// Pixel (`col`, `row`)'s lamp part on `aperture`: of the lamps whose
    /// lens disc reaches the lens, the smallest disc whose steps are at
    /// least [`FORCE_MIN_SHARE`] of the lens and where a first block of
    /// `block` rays puts at most two on average, if any.
    // Out of line: its steps' locals then stay out of the frame held under
    // every pixel (1.7 KB more of the Cortex-M3's stack inlined).
    #[cfg(not(feature = "no-lamp-parts"))]
    #[inline(never)]
    pub fn pixel(&self, col: u32, row: u32, aperture: &Aperture, block: u32) -> Option<PixelLamp> {
        if self.is_empty() {
            return None;
        }
        let (i, j) = (2 * col.min(1 << 16) as i64 + 1, 2 * row.min(1 << 16) as i64 + 1);
        // Far off the lens (beyond 2²⁵ lens radii): clamped.
        let at = |c: [i64; 2], t: i64| (c[0].saturating_add(c[1].saturating_mul(t)) >> FRAC).clamp(-1 << 40, 1 << 40);
        // The discs that reach the lens's circle, the smallest first (the
        // steps cost the Cortex-M3 thousands of instructions a disc: they
        // are laid for one disc a pixel, where one is taken).
        let mut near = [(0i64, 0i64, 0i64, 0u8); MAX_BRIGHT];
        let mut count = 0;
        for (index, d) in self.discs.iter().take(self.count as usize).enumerate() {
            let (mut x, mut y, mut r) = (at(d.u, i), at(d.v, j), d.r as i64);
            let reach = 32768 + r;
            if x.abs() < reach && y.abs() < reach && x * x + y * y < reach * reach {
                if r > MAX_RADIUS {
                    let Some(c) = near_focus(x, y, r) else {
                        continue;
                    };
                    (x, y, r) = (c.0, c.1, MAX_RADIUS);
                }
                let mut k = count;
                while k > 0 && near[k - 1].2 > r {
                    near[k] = near[k - 1];
                    k -= 1;
                }
                near[k] = (x, y, r, index as u8);
                count += 1;
            }
        }
        near.iter().take(count).find_map(|&(x, y, r, index)| {
            let lamp = lens_steps(x, y, r, aperture)?;
            let share = lamp.shares.0[1] as u64;
            (share >= FORCE_MIN_SHARE as u64 && share * block as u64 <= MAX_EXPECTED)
                .then_some(PixelLamp { lamp: index, ..lamp })
        })
    }
}

/// Where one ray in a lamp's part of the lens (a share `share` of it,
/// 65536ths), of levels `x`, moves a pixel's mean of levels `mean` by a
/// level or more on some channel if the part is what it saw: the spread of
/// a sample that the part sets (D √share, D the channels' summed
/// difference, in sixteenths of a level), at least 1; else `None`.
pub fn spread(mean: [u32; 3], x: [u32; 3], share: u32) -> Option<u32> {
    let (mut far, mut sum) = (false, 0u64);
    for (m, x) in mean.into_iter().zip(x) {
        let d = x.abs_diff(m) as u64;
        far |= d * share as u64 >= 1 << 16;
        sum += d;
    }
    far.then(|| ((sum * crate::camera::aperture::isqrt_u32(share) as u64) >> 4).clamp(1, u32::MAX as u64) as u32)
}

/// The steps of the unit square that hold the lens disc of centre (`x`,
/// `y`) and radius `r` (Q1.15 lens radii) as `aperture`'s map lays the
/// square on the lens, with their share; `None` where the disc misses the
/// lens's circle. Along a direction e the disc spans t± = c·ê ± √(r² −
/// (c×ê)²), t₋ growing and t₊ shrinking away from the centre's direction:
/// a step's extremes are at its edge nearer that direction, or ρ ∓ r where
/// the step holds it; u = (t / rim)², the rim bounded over the step.
fn lens_steps(x: i64, y: i64, r: i64, aperture: &Aperture) -> Option<PixelLamp> {
    const ONE: i64 = 32768;
    if x.abs() >= ONE + r || y.abs() >= ONE + r {
        return None;
    }
    let d2 = x * x + y * y;
    if d2 >= (ONE + r) * (ONE + r) {
        return None;
    }
    let rho = isqrt(d2 as u64) as i64;
    let holds_centre = d2 <= r * r;
    // The turn's range: the tangents from the lens's centre, turned by ± asin(r / ρ).
    let (v0, width) = if holds_centre {
        (0u32, 1u32 << 16)
    } else {
        let t = isqrt((d2 - r * r) as u64) as i64;
        let lo = aperture.v_toward(x * t + y * r, y * t - x * r);
        let hi = aperture.v_toward(x * t - y * r, y * t + x * r);
        // Margins of 2 units for the inverse rim's roundings (any range is a part).
        (
            lo.wrapping_sub(2) as u32 & 0xFFFF,
            (hi.wrapping_sub(lo) as u32 + 5).min(1 << 16),
        )
    };
    // Steps within one turn: no point counted twice.
    let step = width.div_ceil(STEPS as u32).min((1 << 16) / STEPS as u32);
    let v_centre = if d2 > 0 { aperture.v_toward(x, y) } else { 0 };
    let blades = aperture.blades();
    let m = aperture.inradius_q15().max(1) as i64;
    // The disk's rim is 1 to the sin table's 1.5 steps (the margins below
    // take it); a polygon's, by a 32-bit root. A divisor 1 is a shift: the
    // disk's steps take no division (the Cortex-M3 divides an i64 in software).
    let length = |e: (i64, i64)| match blades {
        0 => ONE,
        _ => crate::camera::aperture::isqrt_u32((e.0 * e.0 + e.1 * e.1) as u32) as i64,
    };
    // Else in 32 bits (|t| < 2³³ over a rim of at least 2¹⁴, both by 4: a
    // unit of t at most, for the margins; the M0 and M3 divide an i64 in
    // software, at many times the cost).
    let over = |t: i64, d: i64| {
        if d == ONE {
            t >> 15
        } else {
            ((t >> 2) as i32 / ((d >> 2) as i32).max(1)) as i64
        }
    };
    // A polygon's corners' and chords' middles' v, once.
    let mut corners = [(0u32, 0u32); crate::camera::aperture::MAX_BLADES as usize];
    for (k, c) in corners.iter_mut().enumerate().take(blades as usize) {
        *c = (((k as u32) << 16) / blades, ((2 * k as u32 + 1) << 15) / blades);
    }
    // Whether v = w lies in [a, a + step) round the square.
    let within = |w: u32, a: u32| (w.wrapping_sub(a) & 0xFFFF) < step;
    // A step's edge at `v`: its rim's length and the disc's span t± along it, if it meets the disc.
    let edge = |v: u32| {
        let (ex, ey) = aperture.rim((v & 0xFFFF) as u16);
        let (ex, ey) = (ex as i64, ey as i64);
        let el = length((ex, ey)).max(1);
        // |c| < 2¹⁷ and |e| <= 2¹⁵: |c × e| < 2³², its square a u64, as (r |e|)² <= 2⁶².
        let (along, across) = (x * ex + y * ey, (x * ey - y * ex).unsigned_abs());
        let (reach, across) = (((r * el) as u64).pow(2), across * across);
        let span = (reach >= across).then(|| {
            // √ to 2¹⁵ (a unit of t or two; the margins take it): a 32-bit
            // root, a sixth of a 64-bit one's instructions on the Cortex-M3.
            let s =
                (crate::camera::aperture::isqrt_u32(((reach - across) >> 30).min(u32::MAX as u64) as u32) as i64) << 15;
            (over(along - s, el), over(along + s, el))
        });
        (el, span)
    };
    // Empty steps: first above last.
    let mut u = [(1u16, 0u16); STEPS];
    let mut inside = 0u64;
    let mut a = edge(v0);
    for (j, out) in u.iter_mut().enumerate() {
        let va = (v0 + j as u32 * step) & 0xFFFF;
        let b = edge(va + step);
        let (mut rim_lo, mut rim_hi) = (a.0.min(b.0), a.0.max(b.0));
        // A corner within the step reaches the circle; a chord's middle, the inradius.
        if corners
            .iter()
            .take(blades as usize)
            .any(|&(corner, _)| within(corner, va))
        {
            rim_hi = ONE;
        }
        if corners
            .iter()
            .take(blades as usize)
            .any(|&(_, middle)| within(middle, va))
        {
            rim_lo = rim_lo.min(m);
        }
        let (mut t_lo, mut t_hi) = (i64::MAX, i64::MIN);
        if holds_centre {
            t_lo = 0;
        }
        if d2 == 0 || within(v_centre as u32, va) {
            (t_lo, t_hi) = (t_lo.min(rho - r), t_hi.max(rho + r));
        }
        for (lo, hi) in [a.1, b.1].into_iter().flatten() {
            (t_lo, t_hi) = (t_lo.min(lo), t_hi.max(hi));
        }
        a = b;
        if t_hi < t_lo {
            continue;
        }
        let u_of = |t: i64, rim: i64| {
            let q = over(t.max(0) << 15, rim);
            ((q * q) >> 14).min(1 << 16)
        };
        // Margins for the roundings (a unit of t is 4 of u at the rim, and
        // the root above is within two); within
        // 16 bits (any range is a part).
        let lo = (u_of(t_lo, rim_hi) - 16).clamp(0, 0xFFFF);
        let last = (u_of(t_hi, rim_lo) + 16).clamp(lo, 0xFFFF);
        *out = (lo as u16, last as u16);
        inside += (last - lo + 1) as u64 * step as u64;
    }
    // Its share of the lens, 65536ths: the steps' area in the square, rounded.
    let inside = ((inside + (1 << 15)) >> 16).min(1 << 16) as u32;
    Some(PixelLamp {
        v0,
        step,
        u,
        shares: Shares([(1 << 16) - inside, inside, 0]),
        lamp: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points of the unit square the aperture maps into a lens disc lie in
    /// the disc's box: the box holds the lamp (the weighing is right whatever
    /// it holds; a box that misses the lamp would not find it).
    #[test]
    fn the_box_holds_the_lens_disc() {
        let mut next = crate::test_rng::unit_f64(0x1a_3b_5c);
        for (blades, rot) in [(0u32, 0.0), (6, 15.0), (3, 90.0), (5, -30.0), (8, 7.0)] {
            let ap = Aperture::regular(blades, rot);
            for case in 0..1500 {
                let r = (0.02 + 0.6 * next()) * 32768.0;
                let (rho, th) = (1.3 * next() * 32768.0, 2.0 * core::f64::consts::PI * next());
                let (x, y) = ((rho * libm::cos(th)) as i64, (rho * libm::sin(th)) as i64);
                let Some(b) = lens_steps(x, y, r as i64, &ap) else {
                    continue;
                };
                let (mut inside, mut held) = (0u32, 0u32);
                for i in 0..20_000u32 {
                    let (u, v) = ((next() * 65536.0) as u16, (next() * 65536.0) as u16);
                    let _ = i;
                    let p = ap.map_q16(u, v);
                    let (dx, dy) = (p.0 as f64 - x as f64, p.1 as f64 - y as f64);
                    if dx * dx + dy * dy < r * r {
                        inside += 1;
                        held += b.part((u, v)) as u32;
                    }
                }
                assert_eq!(
                    held, inside,
                    "blades {blades} case {case}: disc ({x}, {y}) r {r:.0}: {b:?}"
                );
            }
        }
    }

    /// A lamp near focus (a lens disc above [`MAX_RADIUS`], up to
    /// [`MAX_BIG_RADIUS`]) crossing the lens: its stand-in's steps hold every
    /// lens point the disc holds (the part a pilot may miss is the lamp's),
    /// and on a sliver (the bokeh's rim: 1 to 20 % of the lens) they hold
    /// at most 3 times its area on the round lens, 8 on a polygon, where the
    /// stand-in's rim (radius 2) bulges past a flat side's sliver (6.0 seen).
    #[test]
    fn a_near_focus_disc_is_held_by_its_stand_in() {
        let mut next = crate::test_rng::unit_f64(0x0ea7_f0c5);
        for (blades, rot, most) in [(0u32, 0.0, 3.0), (6, 15.0, 8.0), (3, 90.0, 8.0), (9, 45.0, 8.0)] {
            let ap = Aperture::regular(blades, rot);
            let (mut slivers, mut worst) = (0, 0f64);
            for case in 0..400 {
                // 2 to 500 lens radii; its edge from 0.95 lens radii inside the centre to beyond the rim.
                let r = libm::exp(libm::log(2.0) + next() * libm::log(250.0)) * 32768.0;
                let h = (-0.95 + 2.0 * next()) * 32768.0;
                let th = 2.0 * core::f64::consts::PI * next();
                let rho = r + h;
                let (x, y) = ((rho * libm::cos(th)) as i64, (rho * libm::sin(th)) as i64);
                let (r, rr) = (r as i64, r);
                let stand_in = near_focus(x, y, r).and_then(|(sx, sy)| lens_steps(sx, sy, MAX_RADIUS, &ap));
                let (mut inside, mut held, mut part) = (0u32, 0u32, 0u32);
                for _ in 0..8_000 {
                    let (u, v) = ((next() * 65536.0) as u16, (next() * 65536.0) as u16);
                    let p = ap.map_q16(u, v);
                    let (dx, dy) = (p.0 as f64 - x as f64, p.1 as f64 - y as f64);
                    let within = dx * dx + dy * dy < rr * rr;
                    let in_part = stand_in.as_ref().is_some_and(|b| b.part((u, v)) == 1);
                    inside += within as u32;
                    held += (within && in_part) as u32;
                    part += in_part as u32;
                }
                assert_eq!(held, inside, "blades {blades} case {case}: disc ({x}, {y}) r {r}");
                if (80..1600).contains(&inside) {
                    slivers += 1;
                    worst = worst.max(part as f64 / inside as f64);
                }
            }
            assert!(
                slivers > 20 && worst <= most,
                "blades {blades}: {slivers} slivers, worst {worst:.2}"
            );
        }
    }

    /// The steps hug the disc (within a tenth of its area on the lens; one
    /// box held a hexagon's disc in twice its area), their share is their
    /// area in the unit square, and `point_at` draws in them, uniformly.
    #[test]
    fn the_steps_hug_the_disc_and_their_share_is_their_area() {
        let mut next = crate::test_rng::unit_f64(0x57e9_5a3e);
        for (blades, rot) in [(0u32, 0.0), (6, 15.0), (5, -30.0)] {
            let ap = Aperture::regular(blades, rot);
            for (rho, r) in [(0.6, 0.24), (0.3, 0.24), (0.9, 0.24), (0.6, 0.1), (0.1, 0.05)] {
                let (x, y) = ((rho * 32768.0 * 0.8) as i64, (rho * 32768.0 * 0.6) as i64);
                let rr = r * 32768.0;
                let steps = lens_steps(x, y, rr as i64, &ap).unwrap();
                let (mut disc, mut part, mut total) = (0u32, 0u32, 0u32);
                for u in (0..65536u32).step_by(97) {
                    for v in (0..65536u32).step_by(89) {
                        let p = ap.map_q16(u as u16, v as u16);
                        let (dx, dy) = (p.0 as f64 - x as f64, p.1 as f64 - y as f64);
                        disc += (dx * dx + dy * dy < rr * rr) as u32;
                        part += steps.part((u as u16, v as u16)) as u32;
                        total += 1;
                    }
                }
                let ratio = part as f64 / disc as f64;
                assert!(
                    (1.0..1.1).contains(&ratio),
                    "blades {blades}, ρ {rho}, r {r}: {ratio:.3}"
                );
                let share = steps.shares.0[1] as f64 / 65536.0;
                let seen = part as f64 / total as f64;
                assert!(
                    (share - seen).abs() < 4.0 * (share / total as f64).sqrt() + 2e-4,
                    "{share} {seen}"
                );
                // Drawn points: all in the steps, spread over them as their areas.
                let mut by_step = [0u32; STEPS];
                for _ in 0..20_000 {
                    let (u, v) = steps.point_at((next() * 4294967296.0) as u32);
                    assert_eq!(steps.part((u, v)), 1);
                    let j = (v.wrapping_sub(steps.v0 as u16) as u32 / steps.step) as usize;
                    by_step[j] += 1;
                }
                let area: u64 = steps
                    .u
                    .iter()
                    .map(|&(lo, last)| (last as u64 + 1).saturating_sub(lo as u64))
                    .sum();
                for (j, &(lo, last)) in steps.u.iter().enumerate() {
                    let want = 20_000.0 * (last as f64 + 1.0 - lo as f64).max(0.0) / area as f64;
                    assert!(
                        (by_step[j] as f64 - want).abs() <= 5.0 * want.sqrt() + 1.0,
                        "step {j}: {} vs {want:.1}",
                        by_step[j]
                    );
                }
            }
        }
    }
}
