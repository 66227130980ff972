//! The number trait the whole renderer is written over.
//!
//! [`Scalar`] is implemented for [`I16F16`] (Q16.16, the renderer that runs on
//! microcontrollers without an FPU) and for `f32` (the reference that measures
//! what fixed point costs). Everything from the camera to shading is written once
//! over it, so the two renderers differ in their arithmetic and nothing else.
//!
//! The trait is sealed: its contract (saturation, rounding, which operations are
//! exact) is part of the renderer's accuracy analysis, and a third type would
//! need that analysis too.
//!
//! # Rules every implementation follows
//!
//! * No operation panics and none wraps. The Q16.16 operations saturate at the
//!   ends of the range (±32768); a debug build with overflow checks never trips.
//! * Division by zero gives the saturated value of the dividend's sign (0 / 0 is 0).
//! * `sqrt` of a negative number is 0.
//! * Set-up conversions (`from_f64`) round to nearest; they run once per scene.
//! * The Q16.16 per-ray operations use only integer instructions.

use crate::number::film::{FilmMapDesc, FixedFilmMap, FloatFilmMap};
use crate::number::wide::{
    bits_u64, div_rem_u64, div_rem_u64_u32, isqrt_round_u64, mul_i32, mul_i64, mul_u32, mul_u64, sar64, Recip,
};
use fixed::types::I16F16;

pub mod film;
pub(crate) mod plane;
pub(crate) mod quadric;
pub(crate) mod wide;

mod sealed {
    pub trait Sealed {}
    impl Sealed for fixed::types::I16F16 {}
    impl Sealed for f32 {}
}

/// The number type of a renderer: Q16.16 [`I16F16`] or `f32`.
///
/// See the [module docs](self) for the rules all implementations follow.
pub trait Scalar: Copy + PartialOrd + core::fmt::Debug + Send + Sync + sealed::Sealed + Kernels + 'static {
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// The largest finite value; "no hit yet" and saturated results.
    const MAX: Self;
    /// Smallest ray parameter that counts as a hit (about 2⁻¹⁰ world units):
    /// keeps a reflected or shadow ray from hitting the surface it left.
    const HIT_EPSILON: Self;
    /// Short human name of the number type ("Q16.16", "f32").
    const NAME: &'static str;
    /// Rounds an `f64` to the nearest value of this type, saturating. Set-up only.
    fn from_f64(x: f64) -> Self;
    /// The exact value as `f64` (for tests and reports; never on the per-ray path).
    fn to_f64(self) -> f64;
    /// Converts a small integer exactly (|i| < 32768 for Q16.16; saturates beyond).
    fn from_i32(i: i32) -> Self;
    /// Converts a Q1.15 lens-sample coordinate `i / 32768` exactly.
    fn from_q15(i: i32) -> Self;

    /// `self + o`, saturating.
    fn add(self, o: Self) -> Self;
    /// `self - o`, saturating.
    fn sub(self, o: Self) -> Self;
    /// `self * o`, rounded to nearest, saturating.
    fn mul(self, o: Self) -> Self;
    /// `self / o`, saturating; division by zero saturates (0 / 0 = 0).
    fn div(self, o: Self) -> Self;
    /// `-self`, saturating.
    fn neg(self) -> Self;
    /// `|self|`, saturating.
    fn abs(self) -> Self;
    /// Square root; 0 for negative input. Correctly rounded for `f32`,
    /// within one unit in the last place for Q16.16.
    fn sqrt(self) -> Self;
    /// `self ^ e` for a base in [0, 1] and an exponent `e >= 0`
    /// (the Phong power); `0 ^ 0 = 1`.
    fn powf(self, e: Self) -> Self;
    /// The largest integer not above `self`.
    fn floor_i32(self) -> i32;

    /// `min(self, o)`.
    #[inline]
    fn min(self, o: Self) -> Self {
        if o < self {
            o
        } else {
            self
        }
    }
    /// `max(self, o)`.
    #[inline]
    fn max(self, o: Self) -> Self {
        if o > self {
            o
        } else {
            self
        }
    }
}

/// Sealed: `Kernels` is public in a private module, so outside the crate it
/// can be neither named nor implemented (heapless's `LenType` pattern).
mod kernels {
    use super::*;

    /// The machinery behind [`Scalar`]: exact matrix rows, precise directions,
    /// the film map and the plane, accumulators. Sealed (its module is private),
    /// so it can change without breaking the public trait.
    pub trait Kernels: Copy + Sized {
        /// Whether a shadow ray leaving the lit side of a convex object skips
        /// that object: Q16.16's absolute rounding at a large object's magnitude
        /// outgrows any fixed offset (f32's relative rounding does not; its
        /// images stay as they were).
        const SHADOW_SKIPS_OWN_CONVEX: bool;
        /// Whether a shadow ray meets bounded shapes along its exact vector to
        /// the light rather than its rounded unit direction (Q16.16: 2⁻¹⁷ of
        /// direction, 150 units on, moved a small blocker's shadow edge by a
        /// pixel). f32 keeps the unit direction; its images stay as they were.
        const SHADOW_PRECISE_DIR: bool;

        /// The checker's scale for a square side `side` (> 0), as
        /// [`Kernels::checker_cell`] takes it: `1 / side` by default. Set-up only.
        fn checker_scale(side: f64) -> Self;

        /// The checker cell index along one axis, `floor(x / side)`, with `side`
        /// the square side in `Self` and `scale` from [`Kernels::checker_scale`].
        fn checker_cell(x: Self, side: Self, scale: Self) -> i64;

        /// One row of an affine matrix, stored more precisely than `Self`
        /// (Q16.16 keeps up to 30 fraction bits; see `Kernels::row_from_f64`).
        type Row: Copy + core::fmt::Debug + Send + Sync;
        /// Accumulator for sums of many colours (a pixel's samples).
        type Acc: Copy + core::fmt::Debug + Send + Sync;

        /// Length of a 3-vector, computed without intermediate overflow.
        fn length3(v: [Self; 3]) -> Self;
        /// Unit vector along `v`, and the length of `v`. A zero vector gives zero.
        fn normalize3(v: [Self; 3]) -> ([Self; 3], Self);
        /// `|v|² <= r²`, decided exactly (no intermediate overflow).
        fn within(v: [Self; 3], r: Self) -> bool;
        /// `a · b > 0`, decided exactly for Q16.16 (no rounding, no saturation).
        fn dot_positive(a: [Self; 3], b: [Self; 3]) -> bool;

        /// Builds a matrix row `(a, b, c, t)` from its exact `f64` entries.
        fn row_from_f64(r: [f64; 4]) -> Self::Row;
        /// `a·x + b·y + c·z (+ t if affine)`, with one rounding at the end.
        fn row_apply(row: &Self::Row, v: [Self; 3], affine: bool) -> Self;

        /// The direction `M v` for the three rows of a matrix, as a unit vector
        /// with its length `|M v|` and, where that is below 1, the reciprocal
        /// `1 / |M v|` (0 otherwise), all from the exact product: a large scale
        /// (rows of 1/2000) keeps its precision, where rounding `M v` to `Self`
        /// first would leave it a few bits. A zero result gives zeros.
        fn rows_apply_unit(rows: &[Self::Row; 3], v: [Self; 3]) -> ([Self; 3], Self, Self);

        /// A ray direction held more precisely than three `Self` values (Q16.16:
        /// 31-bit mantissas with a shared power of two), for the unbounded plane,
        /// whose hits along a grazing ray move by the ray's direction error times
        /// the square of the distance.
        type Dir: Copy + core::fmt::Debug + PartialEq + Send + Sync;
        /// A vector as a precise direction, exactly.
        fn dir_from(v: [Self; 3]) -> Self::Dir;
        /// A camera's exact map from pixels to its rays' directions (see [`crate::number::film`]).
        type FilmMap: Copy + core::fmt::Debug + Send + Sync;
        /// A pixel's chief direction as the film map gives it, before the lens.
        type Film: Copy + core::fmt::Debug + PartialEq + Send + Sync;
        /// Rounds a film map's exact parts. Set-up only.
        fn film_map(desc: &FilmMapDesc) -> Self::FilmMap;
        /// The chief direction `D(i, j)` of the doubled pixel centre (i, j).
        fn film_dir(map: &Self::FilmMap, i: i32, j: i32) -> Self::Film;
        /// The unit direction along the film direction tilted by a lens sample
        /// (Q1.15; (0, 0) for the chief ray): precise, marked unit, and rounded.
        fn film_ray_dir(map: &Self::FilmMap, film: &Self::Film, lens: (i32, i32)) -> (Self::Dir, [Self; 3]);
        /// Where the world ray `o + t d` meets the object-space plane z = 0 of an
        /// object whose world → object matrix has these rows, for `t_min < t < t_max`:
        /// `(t, x, y)`, t the world distance in units of |d| (a unit direction
        /// marked so needs no square root) and (x, y, 0) the object-space point.
        fn plane_hit(
            rows: &[Self::Row; 3],
            o: [Self; 3],
            d: Self::Dir,
            t_min: Self,
            t_max: Self,
        ) -> Option<(Self, Self, Self)>;

        /// [`Kernels::rows_apply_unit`] for a precise direction marked unit (a
        /// camera ray's), from its mantissas: `None` where the type keeps the
        /// rounded unit direction (f32; a direction not marked unit).
        fn rows_apply_dir(_rows: &[Self::Row; 3], _d: &Self::Dir) -> Option<([Self; 3], Self, Self)> {
            None
        }
        /// The point `o + t D` for a precise direction marked unit, from its
        /// mantissas (one rounding): `None` as for [`Kernels::rows_apply_dir`].
        fn along_dir(_o: [Self; 3], _d: &Self::Dir, _t: Self) -> Option<[Self; 3]> {
            None
        }

        /// The roots `(t0, t1)` of the cylinder's (`cone` false) or the cone's
        /// side quadric along the object-space ray `o + t d`, where the type
        /// computes them exactly (Q16.16: `number::quadric`): `Some(None)` for
        /// no root. `None`: the shape's generic quadratic (f32, unchanged).
        fn side_roots(_o: [Self; 3], _d: [Self; 3], _cone: bool) -> Option<Option<(Self, Self)>> {
            None
        }

        /// The empty accumulator.
        fn acc_zero() -> Self::Acc;
        /// `acc + x`.
        fn acc_add(acc: Self::Acc, x: Self) -> Self::Acc;
        /// `acc / n`, saturating (n > 0).
        fn acc_mean(acc: Self::Acc, n: u32) -> Self;

        /// A colour channel clamped to [0, 1] and rounded to 8 bits: `round(255 v)`.
        fn to_u8(self) -> u8;

        /// A colour channel in 8-bit levels, unclamped above white: `⌊255 v⌋`
        /// clamped to 0..=65535 (what adaptive sampling's statistics count).
        fn to_level(self) -> u32;
    }
}
pub(crate) use kernels::Kernels;

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

/// Q16.16's precise direction: `m[i] · 2^e`, with `|m[i]| < 2^31`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct FixedDir {
    pub(crate) m: [i64; 3],
    pub(crate) e: i32,
    /// Whether `|m|` is 2^-e within 2^-30 relative (the camera's rays): the
    /// plane then needs no square root for world distances.
    pub(crate) unit: bool,
}

impl FixedDir {
    /// Normalises exact i128 components at scale `2^e` to 31-bit mantissas.
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
            e: e + k as i32,
            unit: false,
        }
    }

    /// Normalises exact i64 components at scale `2^e` to 31-bit mantissas.
    #[inline]
    fn from_i64(w: [i64; 3], e: i32) -> FixedDir {
        let big = w.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
        let k = bits_u64(big).saturating_sub(31);
        let m = if k == 0 {
            w
        } else {
            w.map(|x| ((x >> (k - 1)) + 1) >> 1)
        };
        FixedDir {
            m,
            e: e + k as i32,
            unit: false,
        }
    }

    /// `rows · v` (+ the translation if `affine`) exactly, for `v` in Q16.16
    /// bits or mantissas below 2^31, as a direction at scale `2^(e - shift)`.
    /// Each product is below 2^61 and the translation below 2^60: an i64 sum
    /// holds a row; rows of different scales meet in i128.
    #[inline]
    fn exact_rows(rows: &[FixedRow; 3], v: [i64; 3], affine: bool, e: i32) -> FixedDir {
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
        let w: [i128; 3] = core::array::from_fn(|i| (row(&rows[i]) as i128) << (common - rows[i].shift));
        FixedDir::from_wide(w, e - common as i32)
    }

    /// `|self|` as a mantissa below 2^32 at scale `2^e`.
    fn length(&self) -> u64 {
        let sq: u64 = self.m.iter().map(|&c| mul_i64(c, c) as u64).sum();
        isqrt_round_u64(sq)
    }
}

/// `n / d` rounded to nearest (ties away from zero), for `d != 0`, in i64:
/// through [`Recip`] when `|d|` fits 32 bits.
#[inline]
pub(crate) fn div_round_i64(n: i64, d: i64) -> i64 {
    let du = d.unsigned_abs();
    if du >> 32 == 0 {
        return div_round_i64_by(n, &Recip::new(du as u32), d < 0);
    }
    let nu = n.unsigned_abs();
    let q = (nu / du + u64::from(nu % du >= du - du / 2)) as i64;
    if (n < 0) != (d < 0) {
        -q
    } else {
        q
    }
}

/// `n / d` rounded to nearest (ties away from zero), exactly as
/// [`div_round_i64`], for the divisor `d = ±r.divisor()` with the sign
/// `d_neg`: several divisions by one `d` compute its reciprocal once.
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

/// Saturates an i64 to the i32 range.
#[inline]
fn sat32(x: i64) -> i32 {
    if x > i32::MAX as i64 {
        i32::MAX
    } else if x < i32::MIN as i64 {
        i32::MIN
    } else {
        x as i32
    }
}

/// The Q16.16 product of raw values `a · b / 2^16`, rounded to nearest
/// (ties up) and saturated, through the exact 64-bit product.
#[inline]
fn mul_q16_wide(a: i32, b: i32) -> i32 {
    sat32(shr_round(mul_i32(a, b), 16))
}

/// [`mul_q16_wide`] in 32-bit arithmetic when both magnitudes are at most
/// 2^16 (values up to 1: colours, unit vectors): the magnitudes' product then
/// fits a u32 unless both are 1. `None` otherwise.
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
fn mul_q16_small(a: i32, b: i32) -> Option<i32> {
    let (ua, ub) = (a.unsigned_abs(), b.unsigned_abs());
    if ua > 1 << 16 || ub > 1 << 16 {
        return None;
    }
    // Times exactly 1 (white light, a unit axis): the other factor.
    if ua == 1 << 16 {
        return Some(if a < 0 { -b } else { b });
    }
    let m = ua * ub;
    // floor(p / 2^16 + 1/2) for p = ±m: ties go up, towards +∞, for both signs.
    Some(if (a ^ b) < 0 {
        -(((m + 0x7FFF) >> 16) as i32)
    } else {
        ((m + 0x8000) >> 16) as i32
    })
}

/// Rounds `x / 2^s` to nearest (ties up), for `0 < s < 63`.
#[inline]
pub(crate) fn shr_round(x: i64, s: u32) -> i64 {
    // One variable shift (a library call on the M0), then the last bit by hand.
    let r = sar64(x, s - 1);
    (r >> 1) + (r & 1)
}

/// `log2(x)` of a Q16.16 raw value `x > 0`, in Q16.16.
fn fixed_log2(raw: i32) -> i64 {
    let raw = raw as u32;
    let msb = 31 - raw.leading_zeros();
    // Mantissa in Q1.31: value in [1, 2).
    let mut m: u64 = ((raw as u64) << (31 - msb)) & 0xFFFF_FFFF;
    let mut frac: i64 = 0;
    for i in (0..16).rev() {
        // Squaring doubles the log; a value >= 2 means the next bit is 1.
        m = mul_u32(m as u32, m as u32) >> 31;
        if m >= 1 << 32 {
            m >>= 1;
            frac |= 1 << i;
        }
    }
    ((msb as i64 - 16) << 16) + frac
}

/// `x^n` for `x = b / 2^16` in (0, 1) and a whole `n >= 1`, as Q16.16 bits:
/// powers by squaring in Q0.32, rounded once more at the end (a few
/// multiplies where the logarithm and exponential take some forty).
fn pow_whole(b: u32, mut n: u32) -> i32 {
    // Q0.32 products, rounded to nearest; below 2^-32 the result rounds to 0 anyway.
    let mul = |a: u32, c: u32| ((mul_u32(a, c) + (1 << 31)) >> 32) as u32;
    let mut base = b << 16;
    let mut acc: Option<u32> = None;
    loop {
        if n & 1 != 0 {
            acc = Some(acc.map_or(base, |a| mul(a, base)));
        }
        n >>= 1;
        if n == 0 {
            break;
        }
        base = mul(base, base);
    }
    acc.map_or(0, |a| ((a as u64 + (1 << 15)) >> 16) as i32)
}

/// `2^(-2^-j)` for j = 1..=16 in Q2.30, rounded: the factors of `2^-f` for
/// each set bit of a 16-bit fraction f.
const EXP2_NEG: [u32; 16] = [
    759250125,  // 2^(-1/2)
    902905651,  // 2^(-1/4)
    984625594,  // 2^(-1/8)
    1028218693, // 2^(-1/16)
    1050733751, // 2^(-1/32)
    1062175491, // 2^(-1/64)
    1067942999, // 2^(-1/128)
    1070838486, // 2^(-1/256)
    1072289173, // 2^(-1/512)
    1073015252, // 2^(-1/1024)
    1073378477, // 2^(-1/2048)
    1073560135, // 2^(-1/4096)
    1073650976, // 2^(-1/8192)
    1073696399, // 2^(-1/16384)
    1073719111, // 2^(-1/32768)
    1073730468, // 2^(-1/65536)
];

/// `2^(-y)` for `y >= 0` in Q16.16 raw (i64), result as Q16.16 raw.
fn fixed_exp2_neg(y: i64) -> i32 {
    let int = y >> 16;
    if int >= 17 {
        return 0;
    }
    let frac = (y & 0xFFFF) as u32;
    // Product of 2^(-2^-j) over the set bits of the fraction, in Q2.30.
    let mut acc: u64 = 1 << 30;
    for (j, &c) in EXP2_NEG.iter().enumerate() {
        if frac & (1 << (15 - j)) != 0 {
            acc = (mul_u32(acc as u32, c) + (1 << 29)) >> 30;
        }
    }
    // Q2.30 -> Q16.16 with the integer part as a further shift, rounded.
    let s = 14 + int as u32;
    ((acc + (1 << (s - 1))) >> s) as i32
}

impl Scalar for I16F16 {
    const ZERO: Self = I16F16::ZERO;
    const ONE: Self = I16F16::ONE;
    const MAX: Self = I16F16::MAX;
    const HIT_EPSILON: Self = I16F16::from_bits(64);
    const NAME: &'static str = "Q16.16";
    fn from_f64(x: f64) -> Self {
        let r = x * 65536.0;
        // NaN maps to 0; everything else rounds to nearest and saturates.
        let bits = if r.is_nan() {
            0
        } else if r >= i32::MAX as f64 {
            i32::MAX
        } else if r <= i32::MIN as f64 {
            i32::MIN
        } else {
            let f = r + 0.5;
            let t = f as i64;
            (if (t as f64) > f { t - 1 } else { t }) as i32
        };
        I16F16::from_bits(bits)
    }
    fn to_f64(self) -> f64 {
        self.to_bits() as f64 / 65536.0
    }
    #[inline]
    fn from_i32(i: i32) -> Self {
        I16F16::from_bits(sat32((i as i64) << 16))
    }
    #[inline]
    fn from_q15(i: i32) -> Self {
        I16F16::from_bits(sat32((i as i64) << 1))
    }
    #[inline]
    fn add(self, o: Self) -> Self {
        self.saturating_add(o)
    }
    #[inline]
    fn sub(self, o: Self) -> Self {
        self.saturating_sub(o)
    }
    #[inline]
    fn mul(self, o: Self) -> Self {
        let (a, b) = (self.to_bits(), o.to_bits());
        // Colours, unit vectors and their dot products stay below 1: one MULS on the M0.
        #[cfg(lensray_v6m)]
        if let Some(q) = mul_q16_small(a, b) {
            return I16F16::from_bits(q);
        }
        I16F16::from_bits(mul_q16_wide(a, b))
    }
    #[inline]
    fn div(self, o: Self) -> Self {
        let (a, b) = (self.to_bits() as i64, o.to_bits() as i64);
        if b == 0 {
            return match a {
                0 => I16F16::ZERO,
                a if a > 0 => I16F16::MAX,
                _ => I16F16::MIN,
            };
        }
        // Round to nearest on magnitudes, then restore the sign.
        let (n, d) = ((a << 16).unsigned_abs(), b.unsigned_abs());
        // d <= 2^31 fits the 32-bit divisor.
        let q = div_rem_u64_u32(n + d / 2, d as u32).0 as i64;
        let q = if (a < 0) != (b < 0) { -q } else { q };
        I16F16::from_bits(sat32(q))
    }
    #[inline]
    fn neg(self) -> Self {
        self.saturating_neg()
    }
    #[inline]
    fn abs(self) -> Self {
        self.saturating_abs()
    }
    #[inline]
    fn sqrt(self) -> Self {
        let b = self.to_bits();
        if b <= 0 {
            return I16F16::ZERO;
        }
        // sqrt(b / 2^16) * 2^16 = sqrt(b * 2^16), rounded to nearest.
        let r = isqrt_round_u64((b as u64) << 16);
        I16F16::from_bits(r as i32)
    }
    fn powf(self, e: Self) -> Self {
        if e.to_bits() <= 0 {
            return I16F16::ONE;
        }
        let b = self.to_bits();
        if b <= 0 {
            return I16F16::ZERO;
        }
        if b >= 1 << 16 {
            return I16F16::ONE;
        }
        if e.to_bits() & 0xFFFF == 0 {
            return I16F16::from_bits(pow_whole(b as u32, (e.to_bits() >> 16) as u32));
        }
        // x^e = 2^(e·log2 x); log2 x < 0 here.
        let l = -fixed_log2(b);
        let y = mul_i64(l, e.to_bits() as i64) >> 16;
        I16F16::from_bits(fixed_exp2_neg(y))
    }
    #[inline]
    fn floor_i32(self) -> i32 {
        self.to_bits() >> 16
    }
}

/// The unit vector, length and reciprocal length (below 1) of an exact
/// product at Q16.16 scale: [`Kernels::rows_apply_unit`]'s rounding.
fn unit_of_exact(mut d: FixedDir) -> ([I16F16; 3], I16F16, I16F16) {
    let zero = ([I16F16::ZERO; 3], I16F16::ZERO, I16F16::ZERO);
    // The exact product as mantissas x at scale 2^e, cut to 21 bits: the
    // unit vector needs 17, and the square root's cost grows with the width.
    let cut = bits_u64(d.m.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0)).saturating_sub(21);
    if cut > 0 {
        d.m = d.m.map(|x| ((x >> (cut - 1)) + 1) >> 1);
        d.e += cut as i32;
    }
    let l = d.length();
    if l == 0 {
        return zero;
    }
    // Unit components in Q16.16, rounded: x · 2^16 / l, through one
    // reciprocal 2^62 / l; |x| <= l keeps x · recip below 2^62.
    let recip = div_rem_u64(1 << 62, l).0;
    let unit = d.m.map(|c| {
        let q = ((mul_u64(c.unsigned_abs(), recip) + (1 << 45)) >> 46) as i64;
        I16F16::from_bits(sat32(if c < 0 { -q } else { q }))
    });
    // The product's value is x · 2^(e - 16): |M v| is l · 2^e in Q16.16 bits.
    let e = d.e;
    let shifted = |x: u64, s: i32| -> u64 {
        if s >= 0 {
            if s >= 32 || x >> (63 - s) != 0 {
                u64::MAX
            } else {
                x << s
            }
        } else if s <= -64 {
            0
        } else {
            (x + (1 << (-s - 1))) >> -s
        }
    };
    let len_bits = shifted(l, e);
    let len = I16F16::from_bits(len_bits.min(i32::MAX as u64) as i32);
    // 1 / |M v| in Q16.16 bits, 2^32 / (l · 2^e): needed only below 1.
    let inv = if len_bits >= 1 << 16 {
        I16F16::ZERO
    } else {
        I16F16::from_bits(shifted(recip, -30 - e).min(i32::MAX as u64) as i32)
    };
    (unit, len, inv)
}

impl Kernels for I16F16 {
    const SHADOW_SKIPS_OWN_CONVEX: bool = true;
    const SHADOW_PRECISE_DIR: bool = true;
    fn checker_scale(side: f64) -> Self {
        // 1 / side as a mantissa m = 2^(29 + b) / (side 2^16) in (2^29, 2^30],
        // b the bit length of the side's Q16.16 bits (exact for a power of
        // two, which a face snapped onto a border needs): a Q16.16 reciprocal keeps
        // only 2^-17 absolute, and moved a border 45 away by 2e-3 (whole rows
        // of squares flipped).
        let bits = Self::from_f64(side).to_bits();
        if bits <= 0 {
            return Self::ZERO;
        }
        let b = 32 - bits.leading_zeros() as i32;
        let m = libm::round(libm::exp2((13 + b) as f64) / side);
        I16F16::from_bits(m.min((1u32 << 30) as f64) as i32)
    }
    #[inline]
    fn checker_cell(x: Self, side: Self, scale: Self) -> i64 {
        // floor(x m / 2^(29 + b)), exactly: both factors below 2^31.
        let b = 32 - side.to_bits().leading_zeros();
        mul_i32(x.to_bits(), scale.to_bits()) >> (29 + b)
    }
    type Row = FixedRow;
    type Acc = i64;
    type Dir = FixedDir;

    fn length3(v: [Self; 3]) -> Self {
        let s: u64 = v
            .iter()
            .map(|x| {
                let b = x.to_bits();
                mul_i32(b, b) as u64
            })
            .sum();
        // sqrt of a Q32.32 sum is the Q16.16 length; rounded.
        let r = isqrt_round_u64(s);
        I16F16::from_bits(sat32(r as i64))
    }
    fn normalize3(v: [Self; 3]) -> ([Self; 3], Self) {
        let len = Self::length3(v);
        let l = len.to_bits() as i64;
        if l == 0 {
            return ([I16F16::ZERO; 3], I16F16::ZERO);
        }
        // One division for a Q2.46-ish reciprocal, then three exact-enough multiplies.
        // 0 < l < 2^31 fits the 32-bit divisor.
        let recip = div_rem_u64_u32(1 << 46, l as u32).0 as i64;
        let unit = v.map(|x| {
            let p = mul_i64(x.to_bits() as i64, recip);
            I16F16::from_bits(sat32(shr_round(p, 30)))
        });
        (unit, len)
    }
    #[inline]
    fn dot_positive(a: [Self; 3], b: [Self; 3]) -> bool {
        // Three exact products below 2^62 each: the i64 sum cannot overflow.
        mul_i32(a[0].to_bits(), b[0].to_bits())
            + mul_i32(a[1].to_bits(), b[1].to_bits())
            + mul_i32(a[2].to_bits(), b[2].to_bits())
            > 0
    }
    fn within(v: [Self; 3], r: Self) -> bool {
        let s: u64 = v
            .iter()
            .map(|x| {
                let b = x.to_bits();
                mul_i32(b, b) as u64
            })
            .sum();
        let rb = r.to_bits().max(0);
        s <= mul_i32(rb, rb) as u64
    }
    fn row_from_f64(r: [f64; 4]) -> FixedRow {
        let mut big = 0.0f64;
        for x in &r[..3] {
            let a = if *x < 0.0 { -*x } else { *x };
            if a > big {
                big = a;
            }
        }
        let t_abs = if r[3] < 0.0 { -r[3] } else { r[3] };
        // The largest shift (at most 30) that keeps entries within 2^30 and the
        // translation within 2^60 at scale 2^(shift+16).
        let mut shift = 30u32;
        while shift > 0 && (big * pow2(shift) > (1u64 << 30) as f64 || t_abs * pow2(shift + 16) > (1u64 << 60) as f64) {
            shift -= 1;
        }
        let scale = pow2(shift);
        let round = |x: f64| -> f64 {
            let f = x + 0.5;
            let t = f as i64 as f64;
            if t > f {
                t - 1.0
            } else {
                t
            }
        };
        let clamp = |x: f64, lim: f64| {
            if x > lim {
                lim
            } else if x < -lim {
                -lim
            } else {
                x
            }
        };
        FixedRow {
            m: [
                clamp(round(r[0] * scale), (1u64 << 30) as f64) as i32,
                clamp(round(r[1] * scale), (1u64 << 30) as f64) as i32,
                clamp(round(r[2] * scale), (1u64 << 30) as f64) as i32,
            ],
            t: clamp(round(r[3] * pow2(shift + 16)), (1u64 << 60) as f64) as i64,
            shift,
        }
    }
    #[inline]
    fn row_apply(row: &FixedRow, v: [Self; 3], affine: bool) -> Self {
        // Each product <= 2^61 and t <= 2^60: the sum stays below 2^63: no overflow.
        let mut s =
            mul_i32(row.m[0], v[0].to_bits()) + mul_i32(row.m[1], v[1].to_bits()) + mul_i32(row.m[2], v[2].to_bits());
        if affine {
            s += row.t;
        }
        let q = if row.shift == 0 { s } else { shr_round(s, row.shift) };
        I16F16::from_bits(sat32(q))
    }
    fn rows_apply_unit(rows: &[FixedRow; 3], v: [Self; 3]) -> ([Self; 3], Self, Self) {
        unit_of_exact(FixedDir::exact_rows(rows, v.map(|x| x.to_bits() as i64), false, 0))
    }
    fn rows_apply_dir(rows: &[FixedRow; 3], d: &FixedDir) -> Option<([Self; 3], Self, Self)> {
        // Mantissas at 2^e are Q16.16 bits at 2^(e + 16).
        d.unit
            .then(|| unit_of_exact(FixedDir::exact_rows(rows, d.m, false, d.e + 16)))
    }
    fn along_dir(o: [Self; 3], d: &FixedDir, t: Self) -> Option<[Self; 3]> {
        // D t in Q16.16 bits is m t 2^e: 31-bit factors, one rounding.
        let s = -d.e;
        if !d.unit || !(1..62).contains(&s) {
            return None;
        }
        Some(core::array::from_fn(|i| {
            let step = shr_round(mul_i64(d.m[i], t.to_bits() as i64), s as u32);
            I16F16::from_bits(sat32(o[i].to_bits() as i64 + step))
        }))
    }
    fn dir_from(v: [Self; 3]) -> FixedDir {
        FixedDir {
            m: v.map(|x| x.to_bits() as i64),
            e: -16,
            unit: false,
        }
    }
    type FilmMap = FixedFilmMap;
    type Film = [i64; 3];
    fn film_map(desc: &FilmMapDesc) -> FixedFilmMap {
        FixedFilmMap::new(desc)
    }
    #[inline]
    fn film_dir(map: &FixedFilmMap, i: i32, j: i32) -> [i64; 3] {
        map.film(i, j)
    }
    #[inline]
    fn film_ray_dir(map: &FixedFilmMap, film: &[i64; 3], lens: (i32, i32)) -> (FixedDir, [Self; 3]) {
        map.ray_dir(film, lens)
    }
    fn plane_hit(
        rows: &[FixedRow; 3],
        o: [Self; 3],
        d: FixedDir,
        t_min: Self,
        t_max: Self,
    ) -> Option<(Self, Self, Self)> {
        crate::number::plane::plane_hit(rows, o, d, t_min, t_max)
    }
    fn side_roots(o: [Self; 3], d: [Self; 3], cone: bool) -> Option<Option<(Self, Self)>> {
        Some(crate::number::quadric::side_roots(o, d, cone))
    }
    #[inline]
    fn acc_zero() -> i64 {
        0
    }
    #[inline]
    fn acc_add(acc: i64, x: Self) -> i64 {
        acc + x.to_bits() as i64
    }
    fn acc_mean(acc: i64, n: u32) -> Self {
        let n = n.max(1);
        // Rounded on the magnitude: (acc - n/2) / n truncates towards zero.
        let q = div_rem_u64_u32(acc.unsigned_abs() + (n / 2) as u64, n).0 as i64;
        let q = if acc < 0 { -q } else { q };
        I16F16::from_bits(sat32(q))
    }
    #[inline]
    fn to_u8(self) -> u8 {
        let b = self.to_bits().clamp(0, 1 << 16) as u32;
        ((b * 255 + (1 << 15)) >> 16) as u8
    }
    #[inline]
    fn to_level(self) -> u32 {
        // v < 257 keeps 255 v below 65536: one 32-bit multiply, exact.
        let b = self.to_bits().clamp(0, 257 << 16) as u32;
        ((b * 255) >> 16).min(65535)
    }
}

/// `2^e` as f64, for `e < 64`.
fn pow2(e: u32) -> f64 {
    (1u64 << e) as f64
}

/// Correctly rounded `sqrt` of a positive f32: libm's, in software.
#[cfg(not(all(feature = "hw-sqrt", target_arch = "arm", target_abi = "eabihf")))]
#[inline]
fn sqrt_f32(x: f32) -> f32 {
    libm::sqrtf(x)
}

/// Correctly rounded `sqrt` of a positive f32: the FPU's `vsqrt.f32` (IEEE 754
/// requires it correctly rounded, so it equals libm's `sqrtf` bit for bit).
#[cfg(all(feature = "hw-sqrt", target_arch = "arm", target_abi = "eabihf"))]
#[inline]
fn sqrt_f32(x: f32) -> f32 {
    let r: u32;
    // Stable Rust refuses FPU register operands here (`vfp2` is an unstable
    // target feature), so the value goes through s0, which is saved and restored.
    // SAFETY: FPU register moves and one square root; s0 is left as it was.
    unsafe {
        core::arch::asm!(
            "vmov {save}, s0",
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {r}, s0",
            "vmov s0, {save}",
            x = in(reg) x.to_bits(),
            r = lateout(reg) r,
            save = out(reg) _,
            options(pure, nomem, nostack, preserves_flags),
        );
    }
    f32::from_bits(r)
}

impl Scalar for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const MAX: Self = f32::MAX;
    const HIT_EPSILON: Self = 1.0 / 1024.0;
    const NAME: &'static str = "f32";
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn from_i32(i: i32) -> Self {
        i as f32
    }
    #[inline]
    fn from_q15(i: i32) -> Self {
        i as f32 * (1.0 / 32768.0)
    }
    #[inline]
    fn add(self, o: Self) -> Self {
        self + o
    }
    #[inline]
    fn sub(self, o: Self) -> Self {
        self - o
    }
    #[inline]
    fn mul(self, o: Self) -> Self {
        self * o
    }
    #[inline]
    fn div(self, o: Self) -> Self {
        if o == 0.0 {
            return if self == 0.0 {
                0.0
            } else if self > 0.0 {
                f32::MAX
            } else {
                -f32::MAX
            };
        }
        self / o
    }
    #[inline]
    fn neg(self) -> Self {
        -self
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabsf(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        if self <= 0.0 {
            0.0
        } else {
            sqrt_f32(self)
        }
    }
    fn powf(self, e: Self) -> Self {
        if e <= 0.0 {
            return 1.0;
        }
        if self <= 0.0 {
            return 0.0;
        }
        libm::powf(self, e)
    }
    #[inline]
    fn floor_i32(self) -> i32 {
        libm::floorf(self) as i32
    }
}

impl Kernels for f32 {
    const SHADOW_SKIPS_OWN_CONVEX: bool = false;
    const SHADOW_PRECISE_DIR: bool = false;
    fn checker_scale(side: f64) -> Self {
        <f32 as Scalar>::from_f64(1.0 / side)
    }
    #[inline]
    fn checker_cell(x: Self, _side: Self, scale: Self) -> i64 {
        <f32 as Scalar>::mul(x, scale).floor_i32() as i64
    }
    type Row = [f32; 4];
    /// f64, so that summing many samples adds no error of its own (the Q16.16
    /// sum is exact in i64): an f32 sum of seventy 0.1s lands below 7 and turns
    /// a colour of exactly 25.5 levels into 25 instead of 26.
    type Acc = f64;
    type Dir = [f32; 3];

    fn length3(v: [Self; 3]) -> Self {
        Scalar::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    }
    fn normalize3(v: [Self; 3]) -> ([Self; 3], Self) {
        let len = Self::length3(v);
        if len == 0.0 {
            return ([0.0; 3], 0.0);
        }
        (v.map(|x| x / len), len)
    }
    fn within(v: [Self; 3], r: Self) -> bool {
        v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= r * r
    }
    #[inline]
    fn dot_positive(a: [Self; 3], b: [Self; 3]) -> bool {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0.0
    }
    fn row_from_f64(r: [f64; 4]) -> [f32; 4] {
        r.map(|x| x as f32)
    }
    #[inline]
    fn row_apply(row: &[f32; 4], v: [Self; 3], affine: bool) -> Self {
        let s = row[0] * v[0] + row[1] * v[1] + row[2] * v[2];
        if affine {
            s + row[3]
        } else {
            s
        }
    }
    fn rows_apply_unit(rows: &[[f32; 4]; 3], v: [Self; 3]) -> ([Self; 3], Self, Self) {
        let w = rows.map(|r| Self::row_apply(&r, v, false));
        let (unit, len) = Self::normalize3(w);
        if len == 0.0 {
            return ([0.0; 3], 0.0, 0.0);
        }
        (unit, len, if len >= 1.0 { 0.0 } else { 1.0 / len })
    }
    fn dir_from(v: [Self; 3]) -> [f32; 3] {
        v
    }
    type FilmMap = FloatFilmMap;
    type Film = [f32; 3];
    fn film_map(desc: &FilmMapDesc) -> FloatFilmMap {
        FloatFilmMap::new(desc)
    }
    #[inline]
    fn film_dir(map: &FloatFilmMap, i: i32, j: i32) -> [f32; 3] {
        map.film(i, j)
    }
    #[inline]
    fn film_ray_dir(map: &FloatFilmMap, film: &[f32; 3], lens: (i32, i32)) -> ([f32; 3], [Self; 3]) {
        let u = map.ray_dir(film, lens);
        (u, u)
    }
    fn plane_hit(
        rows: &[[f32; 4]; 3],
        o: [Self; 3],
        d: [f32; 3],
        t_min: Self,
        t_max: Self,
    ) -> Option<(Self, Self, Self)> {
        crate::number::plane::plane_hit_f32(rows, o, d, t_min, t_max)
    }
    #[inline]
    fn acc_zero() -> f64 {
        0.0
    }
    #[inline]
    fn acc_add(acc: f64, x: Self) -> f64 {
        acc + x as f64
    }
    fn acc_mean(acc: f64, n: u32) -> Self {
        (acc / n.max(1) as f64) as f32
    }
    #[inline]
    fn to_u8(self) -> u8 {
        let v = if self > 1.0 {
            1.0
        } else if self > 0.0 {
            self
        } else {
            0.0
        };
        (v * 255.0 + 0.5) as u8
    }
    #[inline]
    fn to_level(self) -> u32 {
        <f32 as Scalar>::mul(self, <f32 as Scalar>::from_i32(255))
            .floor_i32()
            .clamp(0, 65535) as u32
    }
}

/// A number type whose renderers can be baked: [`I16F16`] and `f32`. Its
/// matrix rows and film map have baked forms too.
pub trait BakeScalar:
    Scalar<Row = <Self as BakeScalar>::BakedRow, FilmMap = <Self as BakeScalar>::BakedFilmMap> + crate::bytes::Field
{
    /// The number type's tag in the header: 0 Q16.16, 1 f32.
    const TAG: u8;
    /// `Kernels::Row`.
    type BakedRow: crate::bytes::Field + Copy + core::fmt::Debug + Send + Sync;
    /// `Kernels::FilmMap`.
    type BakedFilmMap: crate::bytes::Field + Copy + core::fmt::Debug + Send + Sync;
    /// Whether the film map's integer kernels stay in range for this image size.
    fn film_map_fits(map: &Self::BakedFilmMap, cols: u32, rows: u32) -> bool;
}

impl BakeScalar for I16F16 {
    const TAG: u8 = 0;
    type BakedRow = crate::number::FixedRow;
    type BakedFilmMap = crate::number::film::FixedFilmMap;
    fn film_map_fits(map: &Self::BakedFilmMap, cols: u32, rows: u32) -> bool {
        map.fits(cols, rows)
    }
}

impl BakeScalar for f32 {
    const TAG: u8 = 1;
    type BakedRow = [f32; 4];
    type BakedFilmMap = crate::number::film::FloatFilmMap;
    fn film_map_fits(_: &Self::BakedFilmMap, _: u32, _: u32) -> bool {
        true
    }
}

#[cfg(test)]
mod mul_tests {
    use super::*;

    /// The M0's 32-bit product of small values equals the exact 64-bit one.
    #[test]
    fn small_products_equal_wide_ones() {
        let edges = [
            0,
            1,
            2,
            0x7FFF,
            0x8000,
            0x8001,
            0xFFFF,
            0x1_0000,
            0x1_0001,
            0x2_0000,
            i32::MAX,
        ];
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let mut small = 0;
        let values = edges
            .iter()
            .flat_map(|&e| [e, -e])
            .chain((0..200_000).map(|_| (next() as i32) >> (next() % 32)))
            .collect::<Vec<i32>>();
        for (i, &a) in values.iter().enumerate() {
            for &b in values[i..].iter().take(40).chain(&edges) {
                if let Some(q) = mul_q16_small(a, b) {
                    small += 1;
                    assert_eq!(q, mul_q16_wide(a, b), "{a} * {b}");
                } else {
                    assert!(a.unsigned_abs() > 0x10000 || b.unsigned_abs() > 0x10000, "{a} * {b}");
                }
            }
        }
        // Ties round up for both signs: -0.5 ulp goes to 0, +0.5 ulp to 1.
        assert_eq!(mul_q16_small(-0x8000, 1), Some(0));
        assert_eq!(mul_q16_small(0x8000, 1), Some(1));
        assert_eq!(mul_q16_small(-0x8001, 1), Some(-1));
        // Exactly 1 times anything up to 1, either way round and with signs.
        for (a, b) in [
            (0x10000, 0x10000),
            (-0x10000, 0x10000),
            (0x10000, -0x8000),
            (-0x10000, -0xFFFF),
            (0x1234, -0x10000),
        ] {
            assert_eq!(mul_q16_small(a, b), Some(mul_q16_wide(a, b)), "{a} * {b}");
        }
        assert!(small > 100_000, "the small path was taken {small} times");
    }
}

#[cfg(test)]
mod shift_tests {
    use super::*;

    #[test]
    fn rounding_shift_is_nearest_with_ties_up() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = (x as i64) >> (x % 64);
            for s in [1u32, 2, 14, 16, 30, 31, 32, 45, 62] {
                let want = ((v as i128 + (1i128 << (s - 1))) >> s) as i64;
                assert_eq!(shr_round(v, s), want, "{v} >> {s}");
            }
        }
        assert_eq!(shr_round(-3, 1), -1, "-1.5 goes up to -1");
        assert_eq!(shr_round(3, 1), 2, "1.5 goes up to 2");
        assert_eq!(shr_round(i64::MAX, 62), 2);
        assert_eq!(shr_round(i64::MIN, 62), -2);
    }
}

#[cfg(test)]
mod dot_sign_tests {
    use super::*;

    /// The sign of a dot product, exactly: where the rounded products would
    /// cancel to zero or flip it, and at the ends of the range.
    #[test]
    fn dot_sign_is_exact() {
        let q = |x: i32| I16F16::from_bits(x);
        let cases = [
            // 1·2^-16 · 2^-16 survives although each rounded product is 0.
            ([1, 0, 0], [1, 0, 0], true),
            ([1, 0, 0], [-1, 0, 0], false),
            ([0; 3], [5, 6, 7], false),
            // 3·2^-32 − 2·2^-32 > 0, with rounded products 0 − 0.
            ([3, 2, 0], [1, -1, 0], true),
            ([2, 3, 0], [1, -1, 0], false),
            // Saturating sums would clip both to the same value.
            ([i32::MAX, i32::MIN, 0], [i32::MAX, i32::MAX, 0], false),
            ([i32::MAX, i32::MIN + 1, 0], [i32::MAX, i32::MAX, 0], false),
            ([i32::MAX, i32::MIN + 2, 0], [i32::MAX, i32::MAX, 0], true),
        ];
        for (a, b, want) in cases {
            let exact: i128 = (0..3).map(|i| a[i] as i128 * b[i] as i128).sum();
            assert_eq!(exact > 0, want, "{a:?} · {b:?}");
            assert_eq!(
                <I16F16 as Kernels>::dot_positive(a.map(q), b.map(q)),
                want,
                "{a:?} · {b:?}"
            );
        }
        let mut s = 0x2545_F491u32;
        for _ in 0..100_000 {
            let mut next = || {
                s ^= s << 13;
                s ^= s >> 17;
                s ^= s << 5;
                (s as i32) >> (s % 31)
            };
            let (a, b) = ([next(), next(), next()], [next(), next(), next()]);
            let exact: i128 = (0..3).map(|i| a[i] as i128 * b[i] as i128).sum();
            assert_eq!(
                <I16F16 as Kernels>::dot_positive(a.map(q), b.map(q)),
                exact > 0,
                "{a:?} · {b:?}"
            );
        }
    }
}

#[cfg(test)]
mod pow_tests {
    use super::*;

    /// Whole Phong powers by squaring: within half a unit (plus the Q0.32
    /// roundings) of the exact power, and never further from it than the
    /// logarithm-and-exponential path they replace.
    #[test]
    fn whole_powers_are_nearly_exact() {
        for n in [1u32, 2, 3, 5, 7, 10, 16, 51, 128, 1000] {
            for b in (1..65536).step_by(7).chain([1, 2, 255, 32768, 65535]) {
                let x = I16F16::from_bits(b);
                let e = I16F16::from_num(n);
                let got = x.powf(e).to_bits();
                let exact = (b as f64 / 65536.0).powi(n as i32) * 65536.0;
                let err = (got as f64 - exact).abs();
                assert!(err <= 0.5 + 1e-3, "{b}^{n}: {got} vs {exact}");
                let l = -fixed_log2(b);
                let old = fixed_exp2_neg(mul_i64(l, e.to_bits() as i64) >> 16);
                assert!(
                    err <= (old as f64 - exact).abs() + 1e-9,
                    "{b}^{n}: {got}, was {old}, exact {exact}"
                );
            }
        }
        // The ends: 0^n = 0, 1^n = 1, x^0 = 1.
        assert_eq!(I16F16::ZERO.powf(I16F16::from_num(5)), I16F16::ZERO);
        assert_eq!(I16F16::ONE.powf(I16F16::from_num(5)), I16F16::ONE);
        assert_eq!(I16F16::from_bits(30000).powf(I16F16::ZERO), I16F16::ONE);
    }
}
