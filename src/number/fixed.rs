//! [`Scalar`] for [`I16F16`]: Q16.16, integer instructions only on the per-ray
//! path, saturating at the ends of the range.

use crate::number::film::{FilmMapDesc, FixedFilmMap};
use crate::number::q16::{sat32, shr_round, side_bits, FixedDir, FixedRow};
use crate::number::scalar::{BakeScalar, Kernels, Scalar};
use crate::number::wide::{
    bits_u64, div_pow2_u32, div_rem_u64, div_rem_u64_u32, isqrt_round_u64, mul_i32, mul_i32_inline, mul_i64, mul_u32,
    mul_u64, sar64,
};
use fixed::types::I16F16;

/// `2^e` as f64, for `e < 64`.
fn pow2(e: u32) -> f64 {
    (1u64 << e) as f64
}

/// The Q16.16 product of raw values `a · b / 2^16`, rounded to nearest
/// (ties up) and saturated, through the exact 64-bit product (on the M0, the
/// Thumb-1 routine).
#[inline(always)]
fn mul_q16(a: i32, b: i32) -> i32 {
    #[cfg(lensray_v6m)]
    {
        crate::number::thumb1::mul_q16(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        sat32(shr_round(a as i64 * b as i64, 16))
    }
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
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self.saturating_add(o)
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self.saturating_sub(o)
    }
    #[inline]
    fn mul(self, o: Self) -> Self {
        // Colours, unit vectors and their dot products stay below 1: one MULS on the M0.
        self.mul_inline(o)
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
    #[inline(always)]
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
        d.e += cut as i8;
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
    let e = d.e as i32;
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
    // On the M0 a call to the Thumb-1 routine (in place at every `Vec3`
    // product the Rust took 3.3 KB of its flash, for some 3 % of its
    // instructions); elsewhere the compiler's choice, as for `mul`.
    #[cfg_attr(lensray_v6m, inline(always))]
    #[cfg_attr(not(lensray_v6m), inline)]
    fn mul_inline(self, o: Self) -> Self {
        I16F16::from_bits(mul_q16(self.to_bits(), o.to_bits()))
    }
    #[inline(always)]
    fn quarter(self) -> Self {
        // x · 2^14 / 2^16 rounded to nearest, ties up: floor((x + 2) / 4),
        // in two parts so that x + 2 cannot overflow; never saturates.
        let x = self.to_bits();
        I16F16::from_bits((x >> 2) + (((x & 3) + 2) >> 2))
    }
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
        // floor(x m / 2^(29 + b)), exactly: both factors below 2^31; the shift
        // by words (a runtime call on the M0).
        sar64(mul_i32(x.to_bits(), scale.to_bits()), 29 + side_bits(side))
    }
    // In place (the side's bit count shared by the three axes: no CLZ on the M0).
    #[inline(always)]
    fn checker_near(x: Self, side: Self, scale: Self, on_face: bool) -> (i64, bool) {
        let cell = Self::checker_cell(x, side, scale);
        // Where x lies in its cell, in 32-bit steps (one multiply on the M0):
        // the cell's start as `cell · side` drifts from the exact border by a
        // cell index times side's rounding, 2⁻¹⁷ a cell (under the band up
        // to 128 cells out; a far floor's squares are f32's doubt too).
        let (at, side) = (
            x.to_bits().wrapping_sub((cell as i32).wrapping_mul(side.to_bits())),
            side.to_bits(),
        );
        // Within 2⁻¹⁰ object units (64 steps) of either border, on either
        // side: the drift puts x a few steps below its cell's start as
        // computed (`at` < 0) or past its end (`at` > side) where it lies
        // just above or below a border (tested unsigned, those were missed:
        // most of the property test's wrong squares after the retake). A
        // flat face's own axis (`on_face`) is exact: nothing to retake.
        let near =
            !on_face && ((at.wrapping_add(64) as u32) <= 128 || (side.wrapping_sub(at).wrapping_add(64) as u32) <= 128);
        (cell, near)
    }
    #[inline]
    fn checker_pos(x: Self, side: Self, scale: Self) -> (i64, Self) {
        let p = mul_i32(x.to_bits(), scale.to_bits());
        let s = 29 + side_bits(side);
        // The 16 bits below the cell index: its Q16.16 fraction.
        let frac = ((p & ((1i64 << s) - 1)) >> (s - 16)) as i32;
        (sar64(p, s), I16F16::from_bits(frac))
    }
    type Row = FixedRow;
    type Acc = i64;
    type Dir = FixedDir;

    fn length3(v: [Self; 3]) -> Self {
        let s: u64 = v
            .iter()
            .map(|x| {
                let b = x.to_bits();
                mul_i32_inline(b, b) as u64
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
        let recip = div_pow2_u32(46, l as u32) as i64;
        let unit = v.map(|x| {
            let p = mul_i64(x.to_bits() as i64, recip);
            I16F16::from_bits(sat32(shr_round(p, 30)))
        });
        (unit, len)
    }
    #[inline]
    fn dot_positive(a: [Self; 3], b: [Self; 3]) -> bool {
        // Three exact products below 2^62 each: the i64 sum cannot overflow.
        // In place: once for each light at each hit.
        mul_i32_inline(a[0].to_bits(), b[0].to_bits())
            + mul_i32_inline(a[1].to_bits(), b[1].to_bits())
            + mul_i32_inline(a[2].to_bits(), b[2].to_bits())
            > 0
    }
    fn within(v: [Self; 3], r: Self) -> bool {
        let s: u64 = v
            .iter()
            .map(|x| {
                let b = x.to_bits();
                mul_i32_inline(b, b) as u64
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
    // Always: one copy of the body (in `FixedRow::apply`, which the plane calls too).
    #[inline(always)]
    fn row_apply(row: &FixedRow, v: [Self; 3], affine: bool) -> Self {
        row.apply(v, affine)
    }
    fn row_to_f64(row: &FixedRow) -> [f64; 4] {
        let scale = pow2(row.shift);
        let m = row.m.map(|x| x as f64 / scale);
        [m[0], m[1], m[2], row.t as f64 / (scale * pow2(16))]
    }
    // Out of line on the M0: rare (box-filtered checkers), one copy.
    #[cfg_attr(lensray_v6m, inline(never))]
    fn row_entry(row: &FixedRow, j: usize) -> Self {
        // Entries m 2^-shift: Q16.16 bits m 2^(16 - shift), in 32 bits.
        let m = row.m.get(j).copied().unwrap_or(0);
        let bits = match row.shift.checked_sub(16) {
            Some(0) => m,
            Some(s) => ((m >> (s - 1)) + 1) >> 1,
            None => {
                let up = 16 - row.shift;
                let x = m << up;
                if x >> up == m {
                    x
                } else if m < 0 {
                    i32::MIN
                } else {
                    i32::MAX
                }
            }
        };
        I16F16::from_bits(bits)
    }
    fn rows_apply_unit(rows: &[FixedRow; 3], v: [Self; 3]) -> ([Self; 3], Self, Self) {
        unit_of_exact(FixedDir::exact_rows(rows, v.map(|x| x.to_bits() as i64), false, 0))
    }
    fn rows_apply_dir(rows: &[FixedRow; 3], d: &FixedDir) -> Option<([Self; 3], Self, Self)> {
        // Mantissas at 2^e are Q16.16 bits at 2^(e + 16).
        d.unit
            .then(|| unit_of_exact(FixedDir::exact_rows(rows, d.m, false, d.e as i32 + 16)))
    }
    fn along_dir(o: [Self; 3], d: &FixedDir, t: Self) -> Option<[Self; 3]> {
        // D t in Q16.16 bits is m t 2^e: 31-bit factors, one rounding.
        let s = -(d.e as i32);
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
            o_lo: [0; 3],
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
    fn film_dir_right(map: &FixedFilmMap, film: &[i64; 3], _i: i32, _j: i32) -> [i64; 3] {
        map.right(film)
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
        checker: (Self, Self),
        eye: Option<[Self; 4]>,
        face: (usize, i8),
    ) -> Option<(Self, Self, Self)> {
        crate::number::plane::plane_hit(rows, o, d, t_min, t_max, checker, eye, face)
    }
    fn plane_from_eye(rows: &[FixedRow; 3], eye: [f64; 3]) -> Option<[Self; 4]> {
        // The eye rounded as the camera rounds it, and its bits below as the film map holds them.
        let (o, lo) = (
            eye.map(<Self as Scalar>::from_f64),
            eye.map(crate::number::plane::below_q16),
        );
        Some(crate::number::plane::plane_from_eye(rows, o, lo))
    }
    fn side_roots(o: [Self; 3], d: [Self; 3], cone: bool, close: &mut bool) -> Option<Option<(Self, Self)>> {
        // The exact sums fit an i64 for object-space values below 4096; only
        // nonsense inputs (a corrupt baked scene) go beyond: the generic quadratic.
        let small = |v: [Self; 3]| v.iter().all(|x| x.to_bits().unsigned_abs() < 1 << 28);
        (small(o) && small(d)).then(|| crate::number::quadric::side_roots(o, d, cone, close))
    }
    const RECHECK: bool = true;
    fn exact_point(
        rows: &[FixedRow; 3],
        o: [Self; 3],
        d: &FixedDir,
        s: Self,
        rim: Option<[Self; 3]>,
        solid: u8,
    ) -> Option<([Self; 3], crate::number::q16::Decided)> {
        crate::number::q16::exact_point(rows, o, d, s, rim, solid)
    }
    fn exact_cells(
        rows: &[FixedRow; 3],
        o: [Self; 3],
        d: &FixedDir,
        s: Self,
        hit: ([Self; 3], [Self; 3]),
        surface: u8,
        checker: (Self, Self),
    ) -> Option<i64> {
        crate::number::q16::exact_cells(rows, o, d, s, hit, surface, checker)
    }
    fn exact_t(
        rows: &[FixedRow; 3],
        o: [Self; 3],
        d: &FixedDir,
        s: Self,
        hit: ([Self; 3], [Self; 3]),
        surface: u8,
    ) -> Option<i64> {
        crate::number::q16::exact_t(rows, o, d, s, hit, surface)
    }
    fn exact_hit_point(o: [Self; 3], d: &FixedDir, t: i64) -> Option<[Self; 3]> {
        crate::number::q16::exact_hit_point(o, d, t)
    }
    fn shadow_line(
        o: [Self; 3],
        d: &FixedDir,
        t: i64,
        offset: ([Self; 3], Self),
        light: [Self; 3],
    ) -> Option<([Self; 3], FixedDir)> {
        crate::number::q16::shadow_line(o, d, t, offset, light)
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
        // Once a pixel: through div_rem_u64's one copy of the division on the M0.
        #[cfg(lensray_v6m)]
        let q = crate::number::wide::div_rem_u64(acc.unsigned_abs() + (n / 2) as u64, n as u64).0 as i64;
        #[cfg(not(lensray_v6m))]
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
    fn to_fine(self) -> u16 {
        // 255 · 2¹⁶ fits a u32; truncating 8 of the 16 bits to_u8 rounds
        // away cannot cross its rounding point.
        let b = self.to_bits().clamp(0, 1 << 16) as u32;
        ((b * 255) >> 8) as u16
    }
    #[inline]
    fn to_level(self) -> u32 {
        // v < 257 keeps 255 v below 65536: one 32-bit multiply, exact.
        let b = self.to_bits().clamp(0, 257 << 16) as u32;
        ((b * 255) >> 16).min(65535)
    }
}

impl BakeScalar for I16F16 {
    const TAG: u8 = 0;
    type BakedRow = FixedRow;
    type BakedFilmMap = crate::number::film::FixedFilmMap;
    #[inline]
    fn film_map_fits(map: &Self::BakedFilmMap, cols: u32, rows: u32) -> bool {
        map.fits(cols, rows)
    }
}

#[cfg(test)]
mod mul_tests {
    use super::*;

    /// Ties round up for both signs (-0.5 ulp to 0, +0.5 ulp to 1), and the
    /// ends saturate: the contract the M0's routine is checked against.
    #[test]
    fn products_round_ties_up_and_saturate() {
        for (a, b, q) in [
            (-0x8000, 1, 0),
            (0x8000, 1, 1),
            (-0x8001, 1, -1),
            (0x10000, -0x8000, -0x8000),
            (i32::MAX, i32::MAX, i32::MAX),
            (i32::MIN, i32::MAX, i32::MIN),
            (i32::MIN, i32::MIN, i32::MAX),
        ] {
            assert_eq!(mul_q16(a, b), q, "{a} * {b}");
        }
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
