//! The exact Q16.16 data the kernels share: matrix rows, precise directions
//! and rounding shifts and divisions. A leaf under the trait, the film map and
//! the plane, so none of them imports another's implementation.

use crate::number::wide::{bits_u64, isqrt_round_u64, mul_i32, mul_i64, sar64, Recip};
use fixed::types::I16F16;

/// The bit length of a checker side's Q16.16 bits (> 0 with a texture): the
/// `b` of the cell index `floor(x m / 2^(29 + b))`. Without a runtime call
/// on the M0.
#[inline(always)]
pub(crate) fn side_bits(side: I16F16) -> u32 {
    bits_u64(side.to_bits() as u32 as u64)
}

/// Q16.16 matrix row: entries `m[i] · 2^-shift` with `|m[i]| <= 2^30`, and the
/// translation at scale `2^(shift + 16)`, so `row · v` is an exact i64 sum.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct FixedRow {
    pub(crate) m: [i32; 3],
    pub(crate) t: i64,
    pub(crate) shift: u32,
}

impl crate::bytes::Field for FixedRow {
    crate::bytes::baked_fields!(FixedRow { m, t, shift }, check(row) {
        // The kernels' exact i64 sums need these bounds.
        if row.shift > 30 || row.m.iter().any(|x| x.unsigned_abs() > 1 << 30) || row.t.unsigned_abs() > 1 << 60 {
            return Err(crate::bytes::BakeError::OutOfRange("matrix row beyond its scale"));
        }
    });
}

impl FixedRow {
    /// `row · v` (plus the translation when `affine`), rounded to Q16.16:
    /// `Kernels::row_apply` for [`I16F16`], which the plane also calls.
    // Not `#[inline]` on the M0: each crate calling it compiled a copy of its own.
    #[cfg_attr(not(lensray_v6m), inline)]
    pub(crate) fn apply(&self, v: [I16F16; 3], affine: bool) -> I16F16 {
        let s = self.exact(v, affine);
        let q = if self.shift == 0 { s } else { shr_round(s, self.shift) };
        I16F16::from_bits(sat32(q))
    }

    /// `row · v` (plus the translation when `affine`) exactly, at scale `2^-(16 + shift)`.
    #[cfg_attr(lensray_v6m, inline(always))]
    #[cfg_attr(not(lensray_v6m), inline)]
    pub(crate) fn exact(&self, v: [I16F16; 3], affine: bool) -> i64 {
        let row = self;
        // Each product <= 2^61 and t <= 2^60: the sum stays below 2^63: no overflow.
        let s =
            mul_i32(row.m[0], v[0].to_bits()) + mul_i32(row.m[1], v[1].to_bits()) + mul_i32(row.m[2], v[2].to_bits());
        if affine {
            s + row.t
        } else {
            s
        }
    }
}

/// Q16.16's precise direction: `m[i] · 2^e`, with `|m[i]| < 2^31`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct FixedDir {
    pub(crate) m: [i64; 3],
    pub(crate) e: i8,
    /// Whether `|m|` is 2^-e within 2^-30 relative (the camera's rays): the
    /// plane then needs no square root for world distances.
    pub(crate) unit: bool,
    /// The ray origin's bits below Q16.16, at 2^-32 (a pinhole camera's eye:
    /// its rounding, 2^-17, was 1e-4 in a small object's space; 0 elsewhere).
    pub(crate) o_lo: [i16; 3],
}

impl FixedDir {
    /// Normalises exact components `w[i] · 2^s[i]` (`s[i] <= 32`) at scale
    /// `2^e` to 31-bit mantissas, rounded as one i128 shift would round them,
    /// in i64 (i128 shifts are expanded in place on the Cortex-M0).
    pub(crate) fn from_scaled(w: [i64; 3], s: [u32; 3], e: i32) -> FixedDir {
        let bits = |i: usize| {
            if w[i] == 0 {
                0
            } else {
                bits_u64(w[i].unsigned_abs()) + s[i]
            }
        };
        let k = bits(0).max(bits(1)).max(bits(2)).saturating_sub(31);
        let m = core::array::from_fn(|i| {
            let (x, s) = (w[i], s[i]);
            if s >= k {
                // Below 2^31 after the shift: bits(x) + s <= 31 + k.
                x << (s - k)
            } else {
                ((x >> (k - s - 1)) + 1) >> 1
            }
        });
        FixedDir {
            m,
            e: (e + k as i32) as i8,
            unit: false,
            o_lo: [0; 3],
        }
    }

    /// Normalises exact i64 components at scale `2^e` to 31-bit mantissas.
    #[inline]
    pub(crate) fn from_i64(w: [i64; 3], e: i32) -> FixedDir {
        let big = w.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
        let k = bits_u64(big).saturating_sub(31);
        let m = if k == 0 {
            w
        } else {
            w.map(|x| ((x >> (k - 1)) + 1) >> 1)
        };
        FixedDir {
            m,
            e: (e + k as i32) as i8,
            unit: false,
            o_lo: [0; 3],
        }
    }

    /// `rows · v` (+ the translation if `affine`) exactly, for `v` in Q16.16
    /// bits or mantissas below 2^31, as a direction at scale `2^(e - shift)`.
    /// Each product is below 2^61 and the translation below 2^60: an i64 sum
    /// holds a row; rows of different scales meet in i128.
    #[inline]
    pub(crate) fn exact_rows(rows: &[FixedRow; 3], v: [i64; 3], affine: bool, e: i32) -> FixedDir {
        let row = |r: &FixedRow| {
            mul_i64(r.m[0] as i64, v[0])
                + mul_i64(r.m[1] as i64, v[1])
                + mul_i64(r.m[2] as i64, v[2])
                + if affine { r.t } else { 0 }
        };
        let common = rows.iter().map(|r| r.shift).max().unwrap_or(0);
        if rows.iter().all(|r| r.shift == common) {
            return FixedDir::from_i64([row(&rows[0]), row(&rows[1]), row(&rows[2])], e - common as i32);
        }
        let w = [row(&rows[0]), row(&rows[1]), row(&rows[2])];
        let s = core::array::from_fn(|i| common - rows[i].shift);
        FixedDir::from_scaled(w, s, e - common as i32)
    }

    /// `|self|` as a mantissa below 2^32 at scale `2^e`.
    pub(crate) fn length(&self) -> u64 {
        let sq: u64 = self.m.iter().map(|&c| mul_i64(c, c) as u64).sum();
        isqrt_round_u64(sq)
    }
}

/// A shape's hit-or-miss decided exactly, with the cube's entry axis or the
/// cylinder's and cone's entry part ([`SIDE`], [`LOW_CAP`], [`HIGH_CAP`])
/// (`None`: not decided).
pub(crate) type Decided = Option<(bool, u8)>;

/// [`exact_point`]'s solids decided exactly from the point and direction
/// (the sphere by its rim, the others by none).
pub(crate) const CUBE: u8 = 1;
/// See [`CUBE`].
pub(crate) const CYLINDER: u8 = 2;
/// See [`CUBE`].
pub(crate) const CONE: u8 = 3;
/// A cylinder's or cone's entry part: its side.
pub(crate) const SIDE: u8 = 0;
/// The cap (the cone's base) at y = −1.
pub(crate) const LOW_CAP: u8 = 1;
/// The cylinder's cap at y = 1.
pub(crate) const HIGH_CAP: u8 = 2;

/// `rows · (o + s d)` rounded once to Q16.16 (`Kernels::exact_point`): the
/// world point, exact at scale 2^-(16 + g) with g = −d.e (`o 2^g + m s`,
/// each term below 2^62), split into its Q16.16 part and the g bits below,
/// each through the rows' exact sums. Against the usual re-origin (rounded
/// in the world, then each row's sum rounded) it drops the world rounding,
/// which the object's inverse scale multiplies. With `rim` (a unit
/// direction), also whether the line through the point along it meets the
/// unit sphere, from the point at 2^-30 (see [`within_rim`]); for `solid`
/// [`CUBE`], whether the ray meets the cube [-1, 1]³ and through which
/// axis's face (see [`cube_entry`]); for [`CYLINDER`] and [`CONE`], whether it
/// meets the solid and through which part (see [`side_entry`]).
#[cold]
#[inline(never)]
pub(crate) fn exact_point(
    rows: &[FixedRow; 3],
    o: [I16F16; 3],
    d: &FixedDir,
    s: I16F16,
    rim: Option<[I16F16; 3]>,
    solid: u8,
) -> Option<([I16F16; 3], Decided)> {
    let fine = fine_point(rows, o, d, s)?;
    let point = fine.map(round14);
    let exact = match solid {
        CUBE => cube_entry(fine, rows, d),
        CYLINDER | CONE => local_dir(rows, d).and_then(|dir| side_entry(fine, dir, solid == CONE)),
        _ => rim.and_then(|u| within_rim(fine, u)).map(|x| (x, 0)),
    };
    Some((point, exact))
}

/// [`exact_point`]'s point `rows · (o + s d)` at 2^-30, unrounded (31
/// significant bits of each part: 2^-31 of the point's size).
#[inline(never)]
fn fine_point(rows: &[FixedRow; 3], o: [I16F16; 3], d: &FixedDir, s: I16F16) -> Option<[i64; 3]> {
    let g = (d.e as i32).checked_neg().filter(|g| (1..=30).contains(g))? as u32;
    let (mut hi, mut lo) = ([0i64; 3], [0i64; 3]);
    for i in 0..3 {
        (hi[i], lo[i]) = split_at_g(o[i].to_bits(), d.m[i], s.to_bits() as i64, g, d.o_lo[i] as i64)?;
    }
    // Each part through the rows' exact sums, then added at 2^-30.
    let (a, b) = (
        FixedDir::exact_rows(rows, hi, true, -16),
        FixedDir::exact_rows(rows, lo, false, -16 - g as i32),
    );
    Some(core::array::from_fn(|j| {
        at30(a.m[j], a.e as i32) + at30(b.m[j], b.e as i32)
    }))
}

/// [`exact_cells`]' surfaces: a flat face (the hit's normal along one axis,
/// the point exactly on it), the unit sphere, the cylinder's side, the cone's side.
pub(crate) const FLAT: u8 = 0;
/// See [`FLAT`].
pub(crate) const ROUND: u8 = 1;

/// The checker's cells of a hit whose point lies close to a border
/// (`Kernels::exact_cells`), summed over the three axes, from the exact ray:
/// `q`, the object-space point of `o + s d` at 2^-30 (not rounded to
/// Q16.16: 2^-17 a component decided a border 6e-6 away the wrong way),
/// taken onto the surface along the exact local
/// direction `D` by one Newton step, `q − (f(q) / 2) D / (n · D)`, with `f`
/// the surface's implicit function (`surface`: [`FLAT`], [`ROUND`] for the
/// sphere, [`CYLINDER`], [`CONE`]; exact at 2^-60, or `n · (q − p)` on a
/// flat face) and `n` the hit's normal, half of f's gradient there. `q` lies
/// within the rounded t's error (2^-12 or so) of the surface, so the step's
/// own error is its square. A flat face's own axis keeps the hit's exact
/// coordinate. `None` (the rounded decision stands) where the point is not
/// near the surface or beyond the scales.
#[cold]
#[inline(never)]
pub(crate) fn exact_cells(
    rows: &[FixedRow; 3],
    o: [I16F16; 3],
    d: &FixedDir,
    s: I16F16,
    (p, n): ([I16F16; 3], [I16F16; 3]),
    surface: u8,
    (side, scale): (I16F16, I16F16),
) -> Option<i64> {
    let q = fine_point(rows, o, d, s)?;
    let dir = local_dir(rows, d)?.map(|x| x >> 11);
    let nb = n.map(|x| x.to_bits() as i64);
    // D to 20 bits; n · D at 2^-16 of D's scale (below 2^39).
    let slope = nb[0] * dir[0] + nb[1] * dir[1] + nb[2] * dir[2];
    let half_f = half_f(q, p, nb, surface)?;
    // Up to 2^-6 from the surface (the step's product below 2^60).
    if slope == 0 || half_f.unsigned_abs() >= 1 << 40 {
        return None;
    }
    let b = side_bits(side);
    let mut sum = 0;
    for j in 0..3 {
        sum += if surface == FLAT && nb[j] != 0 {
            // `Kernels::checker_cell` of the face's exact coordinate.
            mul_i32(p[j].to_bits(), scale.to_bits()) >> (29 + b).min(63)
        } else {
            let x = q[j] - div_round_i64(half_f * dir[j], slope);
            // floor(x m / 2^(43 + b)), x cut to 32 bits first (a far plane's);
            // a shift past 63 floors to 0 or -1 (a large side).
            let k = bits_u64(x.unsigned_abs()).saturating_sub(32);
            mul_once(x >> k, scale.to_bits() as i64) >> (43 + b - k).min(63)
        };
    }
    Some(sum)
}

/// Half the surface's implicit function at `q` (at 2^-30) at 2^-46 (see
/// [`exact_cells`]): `n · (q − p)` on a flat face, else `f(q) / 2`.
fn half_f(q: [i64; 3], p: [I16F16; 3], nb: [i64; 3], surface: u8) -> Option<i64> {
    Some(if surface == FLAT {
        // A point far off the face (a far plane's) may not fit: then no retake.
        let term = |i: usize| nb[i].checked_mul(q[i].checked_sub((p[i].to_bits() as i64) << 14)?);
        term(0)?.checked_add(term(1)?)?.checked_add(term(2)?)?
    } else {
        if q.iter().any(|x| x.unsigned_abs() >= 1 << 31) {
            return None;
        }
        // Exact modulo 2^64, and f itself is small: wrapping sums.
        let sq = |x: i64| mul_once(x, x);
        let f = sq(q[0]).wrapping_add(sq(q[2])).wrapping_sub(match surface {
            ROUND => (1i64 << 60).wrapping_sub(sq(q[1])),
            CYLINDER => 1 << 60,
            _ => sq((1 << 30) - q[1]) >> 2,
        });
        shr_round_call(f, 15)
    })
}

/// A hit's world distance taken again from the exact ray
/// (`Kernels::exact_t`), at 2^-30 world units: two surfaces met within a
/// few Q16.16 steps of each other along a camera ray (a cube's face and a
/// plane, a sphere through a cube) are ordered on
/// it, not on t rounded to 2^-16. As in [`exact_cells`], `q` is the exact
/// object-space point of `o + s d` (at 2^-30), and a Newton step along the
/// exact local direction `D` (local units a world unit, from the rows' and
/// `d`'s scales) takes its t onto the surface: `s − (f(q) / 2) / (n · D)`,
/// `n` the half gradient at `q` (a flat face's normal); then a second step
/// from that t rounded to Q16.16. `None` (the rounded order stands) where
/// the point is not near the surface, the ray runs along it, or the scales
/// do not fit.
#[cold]
#[inline(never)]
pub(crate) fn exact_t(
    rows: &[FixedRow; 3],
    o: [I16F16; 3],
    d: &FixedDir,
    s: I16F16,
    (p, n): ([I16F16; 3], [I16F16; 3]),
    surface: u8,
) -> Option<i64> {
    // D row by row at the finest rows' scale 2^(e − low), as `local_dir`,
    // then cut to 24 bits (2^(e − low + k)).
    let low = rows.iter().map(|r| r.shift).min()?;
    let mut v = [0i64; 3];
    for (x, r) in v.iter_mut().zip(rows) {
        let sum = (0..3).fold(0i64, |acc, k| acc + mul_once(r.m[k] as i64, d.m[k]));
        *x = sum >> (r.shift - low);
    }
    let big = v.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
    let k = bits_u64(big).saturating_sub(24);
    let dir = v.map(|x| x >> k);
    // δ = −half_f / (n · D) at 2^(−46 − (e − low + k − 16)) = 2^(−30 + sh).
    let sh = low as i32 - d.e as i32 - k as i32;
    let (mut s, mut t) = (s, 0);
    // Twice: the second step from the first's t rounded to Q16.16 (a hit
    // rounded 2e-4 off at grazing kept 5e-7 of the step's own error).
    for _ in 0..2 {
        let q = fine_point(rows, o, d, s)?;
        // The surface's half gradient at q itself (a curved one's), at 2^-16.
        let nb = if surface == FLAT {
            n.map(|x| x.to_bits() as i64)
        } else {
            let y = match surface {
                ROUND => q[1],
                CYLINDER => 0,
                _ => ((1i64 << 30) - q[1]) >> 2,
            };
            [q[0] >> 14, y >> 14, q[2] >> 14]
        };
        let half_f = half_f(q, p, nb, surface)?;
        // n · D at 2^(e − low + k − 16), below 2^43 (|n| below 4).
        let slope = nb[0] * dir[0] + nb[1] * dir[1] + nb[2] * dir[2];
        if slope == 0 || half_f.unsigned_abs() >= 1 << 40 {
            return None;
        }
        let step = if sh >= 0 {
            // half_f below 2^40: 22 bits of room, the rest off the slope.
            let up = sh.min(22) as u32;
            let down = (sh as u32 - up).min(63);
            let slope = slope >> down;
            if slope == 0 {
                return None;
            }
            div_round_i64(half_f << up, slope)
        } else {
            // The slope below 2^43: up to 19 bits of room.
            let down = (-sh) as u32;
            if down > 19 {
                return None;
            }
            div_round_i64(half_f, slope << down)
        };
        t = ((s.to_bits() as i64) << 14) - step;
        s = round14(t);
    }
    Some(t)
}

/// The point `o + t d` of a world ray (`d` held precisely, with the
/// origin's bits below Q16.16) at 2^-32, for `t` at 2^-30 (an exact
/// distance, from [`exact_t`]). `None` where the scales do not fit.
#[inline(never)]
fn exact_along(o: [I16F16; 3], d: &FixedDir, t: i64) -> Option<[i64; 3]> {
    // D t at 2^-32 is m t 2^(e + 2): t split at 2^-16 keeps each product below 2^62.
    let sh = -(d.e as i32) - 16;
    if !(0..=48).contains(&sh) || t.unsigned_abs() >= 1 << 45 || d.m.iter().any(|m| m.unsigned_abs() >= 1 << 31) {
        return None;
    }
    let (th, tl) = (t >> 14, t & ((1 << 14) - 1));
    Some(core::array::from_fn(|i| {
        let m = d.m[i];
        let far = if sh == 0 {
            mul_once(m, th)
        } else {
            shr_round_call(mul_once(m, th), sh as u32)
        };
        ((o[i].to_bits() as i64) << 16) + d.o_lo[i] as i64 + far + shr_round_call(mul_once(m, tl), sh as u32 + 14)
    }))
}

/// A point at 2^-32 as its nearest Q16.16 value and the rest below it
/// (-2^15 to 2^15 at 2^-32); `None` beyond the range.
fn split32(x: i64) -> Option<(I16F16, i16)> {
    let q = (x + (1 << 15)) >> 16;
    Some((I16F16::from_bits(i32::try_from(q).ok()?), (x - (q << 16)) as i16))
}

/// A hit's point `o + t d` from its exact distance (`Kernels::exact_hit_point`),
/// rounded once to Q16.16: at grazing the rounded t of a bounded shape is
/// off by its object-space rounding over the slope (1e-4 at a slope of
/// 0.1), which moved a shadow ray's start past its tangent.
#[cold]
#[inline(never)]
pub(crate) fn exact_hit_point(o: [I16F16; 3], d: &FixedDir, t: i64) -> Option<[I16F16; 3]> {
    let p = exact_along(o, d, t)?;
    Some([split32(p[0])?.0, split32(p[1])?.0, split32(p[2])?.0])
}

/// A shadow ray's line from the exact hit (`Kernels::shadow_line`): the hit
/// point `P = o + t d` of the world ray at 2^-32 ([`exact_along`]), the
/// start `P + n ε` (ε times the Q16.16 normal, exact at 2^-32) rounded to
/// Q16.16 with its bits below as the direction's `o_lo`, and the direction
/// the exact vector from that start to the light at 2^-30 (the segment ends
/// at the light itself): Q16.16's P, rounded to 2^-16 a
/// component, put a shadow ray 4.4e-6 from tangent to a cylinder on the
/// other side. `None` where the scales do not fit.
#[cold]
#[inline(never)]
pub(crate) fn shadow_line(
    o: [I16F16; 3],
    d: &FixedDir,
    t: i64,
    (n, eps): ([I16F16; 3], I16F16),
    light: [I16F16; 3],
) -> Option<([I16F16; 3], FixedDir)> {
    let p = exact_along(o, d, t)?;
    let (mut v, mut start, mut lo) = ([0i64; 3], [I16F16::ZERO; 3], [0i16; 3]);
    for i in 0..3 {
        let s = p[i] + mul_i32(n[i].to_bits(), eps.to_bits());
        v[i] = ((light[i].to_bits() as i64) << 16) - s;
        (start[i], lo[i]) = split32(s)?;
    }
    // At 2^-30 (|v| below 2 keeps g at 30, the finest `fine_point` takes).
    let mut dir = FixedDir::from_i64(v.map(|x| shr_round_call(x, 2)), -30);
    if dir.m == [0; 3] {
        return None;
    }
    dir.o_lo = lo;
    Some((start, dir))
}

/// One axis of `o 2^g + m s` (with `o`'s bits below Q16.16, `o_lo` at
/// 2^-32) as its part at 2^-16 and the g bits below (`None` past the i32
/// range); out of line: the M0's flash.
#[inline(never)]
fn split_at_g(o: i32, m: i64, s: i64, g: u32, o_lo: i64) -> Option<(i64, i64)> {
    if m.unsigned_abs() >= 1 << 31 {
        return None;
    }
    let lo = if g >= 16 {
        o_lo << (g - 16)
    } else {
        shr_round_call(o_lo, 16 - g)
    };
    let p = ((o as i64) << g) + mul_once(m, s) + lo;
    let hi = p >> g;
    if hi != hi as i32 as i64 {
        return None;
    }
    // 0 <= p − hi 2^g < 2^30.
    Some((hi, p - (hi << g)))
}

/// A mantissa at scale 2^e at 2^-30, rounded (out of line: the M0's flash).
#[inline(never)]
fn at30(m: i64, e: i32) -> i64 {
    let k = e + 30;
    if k >= 0 {
        m << k.min(32)
    } else if k > -62 {
        shr_round(m, (-k) as u32)
    } else {
        0
    }
}

/// A value at 2^-30 rounded to Q16.16, saturated (out of line: the M0's flash).
#[inline(never)]
fn round14(x: i64) -> I16F16 {
    I16F16::from_bits(sat32(shr_round(x, 14)))
}

/// `rows · d` (no translation) at one scale, cut to 31 bits: each row's
/// exact i64 sum (products below 2^61), the finer rows shifted to the
/// coarsest; a small frame (no i128), for the cube's test on the M0's stack.
fn local_dir(rows: &[FixedRow; 3], d: &FixedDir) -> Option<[i64; 3]> {
    let low = rows.iter().map(|r| r.shift).min()?;
    let mut v = [0i64; 3];
    for (x, r) in v.iter_mut().zip(rows) {
        let sum = (0..3).fold(0i64, |acc, k| acc + mul_once(r.m[k] as i64, d.m[k]));
        *x = sum >> (r.shift - low);
    }
    let big = v.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
    let k = crate::number::wide::bits_u64(big).saturating_sub(31);
    Some(v.map(|x| x >> k))
}

/// Whether the line `p + t D` (`p` at 2^-30, `D` the exact object-space
/// direction, any length) meets the cube [-1, 1]³, and the
/// axis of its entry face: the slabs' entry and exit times
/// `(∓1 − p_i) / |D_i|` compared by cross-multiplication (numerators at
/// 2^-27, below 2^31; mantissas below 2^31: exact in an i64). `None` where
/// |p| is 8 or more on an axis. i32 arrays: the M0's stack.
#[inline(never)]
fn cube_entry(p: [i64; 3], rows: &[FixedRow; 3], d: &FixedDir) -> Option<(bool, u8)> {
    let dir = local_dir(rows, d)?;
    let (mut a, mut b, mut m) = ([0i32; 3], [0i32; 3], [0i32; 3]);
    let mut k = 3;
    for i in 0..3 {
        if p[i].unsigned_abs() >= 1 << 33 {
            return None;
        }
        let pi = if dir[i] < 0 { -p[i] } else { p[i] };
        (a[i], b[i], m[i]) = (
            ((-(1i64 << 30) - pi) >> 3) as i32,
            (((1i64 << 30) - pi) >> 3) as i32,
            dir[i].unsigned_abs() as i32,
        );
        if m[i] == 0 {
            // Parallel to the slab: inside it or a miss.
            if p[i].unsigned_abs() > 1 << 30 {
                return Some((false, 0));
            }
        } else if k == 3 || mul_once(a[i] as i64, m[k] as i64) > mul_once(a[k] as i64, m[i] as i64) {
            k = i;
        }
    }
    if k == 3 {
        return None;
    }
    // Entering through axis k's face no later than leaving through any.
    let hit = (0..3).all(|j| m[j] == 0 || mul_once(a[k] as i64, m[j] as i64) <= mul_once(b[j] as i64, m[k] as i64));
    Some((hit, k as u8))
}

/// `m · 2^e` with `|m| < 2^62`: the cold exact decisions' one number type,
/// products of 31-bit mantissas and aligned sums (each within 2^-30 of its
/// terms, 2^-30 of the shape's size where its forms are evaluated).
#[derive(Copy, Clone)]
struct Wide {
    m: i64,
    e: i32,
}

impl Wide {
    /// The same value with exactly `bits` significant bits (0 stays 0),
    /// rounded where bits are dropped.
    #[inline(never)]
    fn fit(self, bits: u32) -> Wide {
        let n = bits_u64(self.m.unsigned_abs());
        if n == 0 || n == bits {
            self
        } else if n < bits {
            Wide {
                m: self.m << (bits - n),
                e: self.e - (bits - n) as i32,
            }
        } else {
            Wide {
                m: shr_round_call(self.m, n - bits),
                e: self.e + (n - bits) as i32,
            }
        }
    }

    /// `self · b` from 31-bit mantissas (below 2^62).
    #[inline(never)]
    fn mul(self, b: Wide) -> Wide {
        let (a, b) = (self.fit(31), b.fit(31));
        Wide {
            m: mul_once(a.m, b.m),
            e: a.e + b.e,
        }
    }

    /// `self + b`, both at 61 bits, the smaller shifted to the larger's scale.
    #[inline(never)]
    fn add(self, b: Wide) -> Wide {
        let (a, b) = (self.fit(61), b.fit(61));
        let (hi, lo) = if a.m == 0 || (b.m != 0 && b.e > a.e) {
            (b, a)
        } else {
            (a, b)
        };
        let k = (hi.e - lo.e) as u32;
        let lo = match k {
            0 => lo.m,
            1..=62 => shr_round_call(lo.m, k),
            _ => 0,
        };
        Wide { m: hi.m + lo, e: hi.e }
    }
}

/// [`side_entry`]'s forms, each up to 7 terms `c · v_i v_j` (as `(c, 8 i + j)`)
/// of `v = (q × D, D)`: the low and the high end's crossing within the unit
/// circle, the side's discriminant, y at the chord's middle above the low
/// end and below the high end, and the side's leading coefficient `a` (the
/// cone's times 4). `q` is the point about the apex for the cone, whose ends
/// are then at y = −2 and 0 and whose high end has no cap.
#[rustfmt::skip]
const SIDE_FORMS: [[[(i8, u8); 7]; 6]; 2] = [
    // The cylinder.
    [
        [(-1, 0), (-2, 5), (-1, 18), (2, 19), (-1, 27), (1, 36), (-1, 45)],
        [(-1, 0), (2, 5), (-1, 18), (-2, 19), (-1, 27), (1, 36), (-1, 45)],
        [(-1, 9), (1, 27), (1, 45), (0, 0), (0, 0), (0, 0), (0, 0)],
        [(1, 5), (-1, 19), (1, 27), (1, 45), (0, 0), (0, 0), (0, 0)],
        [(-1, 5), (1, 19), (1, 27), (1, 45), (0, 0), (0, 0), (0, 0)],
        [(1, 27), (1, 45), (0, 0), (0, 0), (0, 0), (0, 0), (0, 0)],
    ],
    // The cone.
    [
        [(-1, 0), (-4, 5), (-1, 18), (4, 19), (-4, 27), (1, 36), (-4, 45)],
        [(0, 0), (0, 0), (0, 0), (0, 0), (0, 0), (0, 0), (0, 0)],
        [(1, 0), (-4, 9), (1, 18), (0, 0), (0, 0), (0, 0), (0, 0)],
        [(4, 5), (-4, 19), (8, 27), (-2, 36), (8, 45), (0, 0), (0, 0)],
        [(-1, 5), (1, 19), (0, 0), (0, 0), (0, 0), (0, 0), (0, 0)],
        [(4, 27), (-1, 36), (4, 45), (0, 0), (0, 0), (0, 0), (0, 0)],
    ],
];

/// One of [`SIDE_FORMS`] at `v`, its sign (one loop for every form: the M0's flash).
#[inline(never)]
fn side_form(v: &[Wide; 8], terms: &[(i8, u8); 7]) -> i64 {
    let mut acc = Wide { m: 0, e: 0 };
    for &(c, ij) in terms {
        if c != 0 {
            let x = v[(ij >> 3) as usize & 7].mul(v[ij as usize & 7]);
            acc = acc.add(x.mul(Wide { m: c as i64, e: 0 }));
        }
    }
    acc.m
}

/// Whether the line `p + t D` (`p` at 2^-30, `D` the exact object-space
/// direction, any length) meets the cylinder (`cone` false) or the cone, and
/// through which part it enters ([`SIDE`], [`LOW_CAP`], [`HIGH_CAP`]). Every
/// test is the sign of a quadratic form in `q × D` and `D` (`q` the point, the
/// cone's about its apex), so `D`'s scale drops out and nothing cancels
/// beyond the test's own margin ([`SIDE_FORMS`]): a cap is entered where the
/// line crosses its plane within the unit circle; else the side's quadric must
/// be met (`b² − a c >= 0`, as `a − c_y²` for the cylinder and
/// `c_x² + c_z² − 4 c_y²` for the cone) with its chord's middle between the
/// ends. `None` where |p| is 2 or more on an axis (no line near the solid).
#[inline(never)]
fn side_entry(p: [i64; 3], dir: [i64; 3], cone: bool) -> Option<(bool, u8)> {
    if p.iter().any(|x| x.unsigned_abs() >= 1 << 31) {
        return None;
    }
    let mut q = p;
    q[1] -= if cone { 1 << 30 } else { 0 };
    // q × D exactly: |q| < 3 · 2^30 and D cut to 30 bits, each product below 2^62.
    let d = dir.map(|x| x >> 1);
    let mut v = [Wide { m: 0, e: 0 }; 8];
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        v[i] = Wide {
            m: mul_once(q[j], d[k]) - mul_once(q[k], d[j]),
            e: -30,
        };
        v[i + 3] = Wide { m: d[i], e: 0 };
    }
    let forms = &SIDE_FORMS[usize::from(cone)];
    let holds = |f: usize| side_form(&v, &forms[f]) >= 0;
    if dir[1] != 0 {
        let up = dir[1] > 0;
        // The end it enters by (the cone's base only from below), then the one it leaves by.
        if (!cone || up) && holds(usize::from(!up)) {
            return Some((true, if up { LOW_CAP } else { HIGH_CAP }));
        }
        if (!cone || !up) && holds(usize::from(up)) {
            return Some((true, SIDE));
        }
    } else if p[1].unsigned_abs() > 1 << 30 {
        return Some((false, SIDE));
    }
    // Along the axis or steeper than the cone's lines (a <= 0): the ends decided.
    let met = side_form(&v, &forms[5]) > 0 && holds(2) && holds(3) && holds(4);
    Some((met, SIDE))
}

/// [`mul_i64`] as one out-of-line copy for the cold kernels (the M0's flash).
#[inline(never)]
fn mul_once(a: i64, b: i64) -> i64 {
    mul_i64(a, b)
}

/// Whether the line through `p` (at 2^-30, near its closest approach to the
/// centre) along the unit `u` meets the unit sphere: 1 − |p|² + (p·u)² >= 0
/// at 2^-60. `u`'s rounding (2^-17) enters only through p·u, small there.
/// `None` where |p| is 2 or more on an axis (no rim in doubt).
#[inline(never)]
fn within_rim(p: [i64; 3], u: [I16F16; 3]) -> Option<bool> {
    let (mut pp, mut pu) = (0u64, 0i64);
    for i in 0..3 {
        if p[i].unsigned_abs() >= 1 << 31 {
            return None;
        }
        pp += mul_once(p[i], p[i]) as u64;
        pu += mul_once(p[i], u[i].to_bits() as i64);
    }
    // p·u at 2^-46, then at 2^-30 (at most 2^33 here).
    let pu = shr_round(pu, 16);
    if pu.unsigned_abs() >= 1 << 31 {
        return None;
    }
    Some(((1u64 << 60) + mul_once(pu, pu) as u64) >= pp)
}

/// `n / d` rounded to nearest (ties away from zero), for `d != 0`, in i64:
/// through [`Recip`] when `|d|` fits 32 bits.
#[inline]
pub(crate) fn div_round_i64(n: i64, d: i64) -> i64 {
    let du = d.unsigned_abs();
    // On the M0 `div_rem_u64` holds the one copy of the reciprocal division
    // (a second one here took 600 bytes for a rare path).
    #[cfg(not(lensray_v6m))]
    if du >> 32 == 0 {
        return div_round_i64_by(n, &Recip::new(du as u32), d < 0);
    }
    let nu = n.unsigned_abs();
    let (q, r) = crate::number::wide::div_rem_u64(nu, du);
    let q = (q + u64::from(r >= du - du / 2)) as i64;
    if (n < 0) != (d < 0) {
        -q
    } else {
        q
    }
}

/// `n / d` rounded to nearest (ties away from zero), exactly as
/// [`div_round_i64`], for the divisor `d = ±r.divisor()` with the sign
/// `d_neg`: several divisions by one `d` compute its reciprocal once.
// The M0 divides through `div_rem_u64` instead (one copy of the division).
#[cfg_attr(lensray_v6m, allow(dead_code))]
#[inline]
pub(crate) fn div_round_i64_by(n: i64, r: &Recip, d_neg: bool) -> i64 {
    let (q, rem) = r.div_rem(n.unsigned_abs());
    let d = r.divisor();
    let q = (q + u64::from(rem >= d - d / 2)) as i64;
    if (n < 0) != d_neg {
        -q
    } else {
        q
    }
}

/// Rounds `x / 2^s` to nearest (ties up), for `0 < s < 63`.
// Forced on the M0: at opt-level "s" a call per rounding cost 30 instructions a pixel.
#[cfg_attr(lensray_v6m, inline(always))]
#[cfg_attr(not(lensray_v6m), inline)]
pub(crate) fn shr_round(x: i64, s: u32) -> i64 {
    // One variable shift (a library call on the M0), then the last bit by hand.
    let r = sar64(x, s - 1);
    (r >> 1) + (r & 1)
}

/// [`shr_round`] as one out-of-line copy on the M0, for rare paths.
#[cfg_attr(lensray_v6m, inline(never))]
#[cfg_attr(not(lensray_v6m), inline)]
pub(crate) fn shr_round_call(x: i64, s: u32) -> i64 {
    shr_round(x, s)
}

/// Saturates an i64 to the i32 range.
#[inline]
pub(crate) fn sat32(x: i64) -> i32 {
    if x > i32::MAX as i64 {
        i32::MAX
    } else if x < i32::MIN as i64 {
        i32::MIN
    } else {
        x as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The i128 form `from_scaled` replaces: the reference.
    fn from_wide(w: [i128; 3], e: i32) -> FixedDir {
        let big = w.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
        let k = (128 - big.leading_zeros()).saturating_sub(31);
        let m = w.map(|x| {
            if k == 0 {
                x as i64
            } else {
                (((x >> (k - 1)) + 1) >> 1) as i64
            }
        });
        FixedDir {
            m,
            e: (e + k as i32) as i8,
            unit: false,
            o_lo: [0; 3],
        }
    }

    /// Whether the line `p + t d` meets the cylinder or cone, by sampling it
    /// densely in f64 (the definition, none of the forms).
    fn sampled(p: [f64; 3], d: [f64; 3], cone: bool) -> bool {
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let d = d.map(|x| x / len);
        (-60_000..=60_000).any(|k| {
            let t = k as f64 / 10_000.0;
            let x = [0, 1, 2].map(|i| p[i] + t * d[i]);
            let r = if cone { (1.0 - x[1]) / 2.0 } else { 1.0 };
            x[1].abs() <= 1.0 && x[0] * x[0] + x[2] * x[2] <= r * r
        })
    }

    #[test]
    fn side_entry_agrees_with_the_sampled_line() {
        let mut unit = crate::test_rng::unit_f64(0x5eed);
        let mut checked = 0;
        for i in 0..3000 {
            let cone = i % 2 == 0;
            let p = [0; 3].map(|_| unit() * 3.0 - 1.5);
            let mut d = [0; 3].map(|_| unit() * 2.0 - 1.0);
            if i % 5 == 0 {
                d[1] = 0.0;
            }
            let (pi, di) = (
                p.map(|x| (x * (1u64 << 30) as f64) as i64),
                d.map(|x| (x * (1u64 << 30) as f64) as i64),
            );
            let (pf, df) = (pi.map(|x| x as f64 / (1u64 << 30) as f64), di.map(|x| x as f64));
            let want = sampled(pf, df.map(|x| x / (1u64 << 30) as f64), cone);
            let got = side_entry(pi, di, cone).expect("in range").0;
            // The sampling's own step (1e-4 along the line) can miss a grazing hit.
            if got != want {
                let nudged = [-1e-3, 1e-3]
                    .map(|e| sampled(pf.map(|x| x * (1.0 + e)), df.map(|x| x / (1u64 << 30) as f64), cone));
                assert!(
                    nudged[0] != nudged[1] || nudged.contains(&got),
                    "{cone} {pf:?} {df:?}: {got}, sampled {want}"
                );
            }
            checked += 1;
        }
        assert_eq!(checked, 3000);
    }

    #[test]
    fn scaled_rows_normalise_as_in_i128() {
        let mut next = crate::test_rng::xorshift32(128);
        for i in 0..200_000u32 {
            let (a, b) = (next(), next());
            let mut w = [0i64; 3];
            let mut s = [0u32; 3];
            for j in 0..3 {
                let x = ((next() as u64) << 32 | next() as u64) as i64;
                // Sums of rows: below 2^62, any length down to 0.
                w[j] = if (a >> j) & 7 == 0 { 0 } else { x >> (2 + next() % 62) };
                s[j] = if i % 4 == 0 { 0 } else { (b >> (5 * j)) % 31 };
            }
            let wide = core::array::from_fn(|j| (w[j] as i128) << s[j]);
            let (got, want) = (FixedDir::from_scaled(w, s, 7), from_wide(wide, 7));
            assert_eq!((got.m, got.e), (want.m, want.e), "{w:?} << {s:?}");
        }
    }
}
