//! Q16.16's ray–plane intersection, from a unit direction held to 30 bits.
//!
//! The plane is the object-space z = 0 of an object whose world → object rows
//! are given. Along the world ray `o + t D` with D a unit vector, the object's
//! z is `oz + t (row_z · D)`, so the world distance is `t = −oz / (row_z · D)`:
//! one exact dot product and one division. The object-space x and y, which
//! only the texture needs, follow from t by two more products, and only for a
//! hit within range. Every product of the 30-bit rows and mantissas is exact
//! in an i64; grazing hits far away keep their precision.

use crate::number::q16::{shr_round, FixedDir, FixedRow};
use crate::number::wide::{bits_u64, div_rem_u64, div_rem_u64_u32, isqrt_rem_u64, mul_i32, mul_i64, mul_u64};
use fixed::types::I16F16;

/// Bits needed for `x` (0 for 0).
// In place on the M0 (a call costs more than the body there); a hint elsewhere.
#[cfg_attr(lensray_v6m, inline(always))]
#[cfg_attr(not(lensray_v6m), inline)]
fn bits(x: u64) -> u32 {
    bits_u64(x)
}

/// `row · m` exactly, at scale `2^-(30 + row.shift)` for mantissas at `2^-30`.
// In place on the M0 (a call costs more than the body there); a hint elsewhere.
#[cfg_attr(lensray_v6m, inline(always))]
#[cfg_attr(not(lensray_v6m), inline)]
fn dot(row: &FixedRow, m: &[i64; 3]) -> i64 {
    // 30-bit entries times 30-bit mantissas: i32 factors, each product below 2^60.
    mul_i32(row.m[0], m[0] as i32) + mul_i32(row.m[1], m[1] as i32) + mul_i32(row.m[2], m[2] as i32)
}

/// `x` cut to at most 31 bits: `(x', k)` with `x ≈ x' · 2^k`, rounded.
// In place on the M0 (a call costs more than the body there); a hint elsewhere.
#[cfg_attr(lensray_v6m, inline(always))]
#[cfg_attr(not(lensray_v6m), inline)]
fn cut31(x: i64) -> (i64, u32) {
    let k = bits(x.unsigned_abs()).saturating_sub(31);
    if k == 0 {
        (x, 0)
    } else {
        (shr_round(x, k), k)
    }
}

/// `n · 2^e / den` rounded to nearest, saturated to the i32 range, for
/// `|n| < 2^32`, `den != 0` and `e <= 62`.
fn ratio(n: i64, den: i64, e: u32) -> i64 {
    let (den, k) = cut31(den);
    let neg = (n < 0) != (den < 0);
    let (nu, mut du) = (n.unsigned_abs(), den.unsigned_abs());
    if nu == 0 {
        return 0;
    }
    // The quotient's scale after the cut: 2^(e - k), with e - k >= -1.
    let e = e as i32 - k as i32;
    if e < 0 {
        du <<= 1;
    }
    let e = e.max(0) as u32;
    // A numerator of 2^62 or more over a divisor below 2^32 saturates.
    let q = if bits(nu) + e > 62 {
        i32::MAX as u64 + 1
    } else {
        let num = nu << e;
        // du is at most 2^32 after the cut: the reciprocal division on the M0.
        div_rem_u64(num + du / 2, du).0
    };
    let q = q.min(i32::MAX as u64 + 1) as i64;
    if neg {
        -q
    } else {
        q
    }
}

/// `t · l / 2^e` rounded to nearest, for `|t| < 2^31`, `|l| < 2^62`, `e <= 62`.
fn scaled(t: i64, l: i64, e: u32) -> i64 {
    let (l, k) = cut31(l);
    // Both factors within 31 bits: the product fits an i64.
    let p = mul_i64(t, l);
    let e = e as i32 - k as i32;
    if e > 0 {
        shr_round(p, e as u32)
    } else if e == 0 {
        p
    } else {
        p.saturating_mul(2)
    }
}

/// Saturates to the Q16.16 range.
#[inline]
fn q16(x: i64) -> I16F16 {
    I16F16::from_bits(x.clamp(i32::MIN as i64, i32::MAX as i64) as i32)
}

/// Unit mantissas at 2^-30 of a direction whose largest component is below
/// 2^31: one square root and one reciprocal. `None` for the zero vector.
pub(crate) fn unit_mantissas(d: [i64; 3]) -> Option<[i64; 3]> {
    // Each square of an i32 is below 2^62: the sum fits a u64.
    let sq: u64 = d.iter().map(|&x| mul_i32(x as i32, x as i32) as u64).sum();
    let l = isqrt_rem_u64(sq).0;
    if l == 0 {
        return None;
    }
    // |x| <= l keeps each component within 2^30; the reciprocal 2^61 / l fits
    // 32 bits where l > 2^29 (callers scale their vectors up to make it so).
    Some(if l > 1 << 29 {
        // l < 2^32 (sq < 2^64) and the quotient fits 32 bits: the fast division.
        let recip = div_rem_u64_u32(1 << 61, l as u32).0;
        d.map(|x| {
            let q = ((mul_u64(x.unsigned_abs(), recip) + (1 << 30)) >> 31) as i64;
            if x < 0 {
                -q
            } else {
                q
            }
        })
    } else {
        d.map(|x| crate::number::q16::div_round_i64(x << 30, l as i64))
    })
}

/// A precise direction of any length as a unit one (mantissas at 2^-30).
pub(crate) fn to_unit(d: FixedDir) -> Option<FixedDir> {
    let big = d.m.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
    if big == 0 {
        return None;
    }
    // Largest component into [2^30, 2^31): the length is then above 2^29.
    let b = bits(big);
    let m = if b > 31 {
        d.m.map(|x| shr_round(x, b - 31))
    } else {
        d.m.map(|x| x << (31 - b))
    };
    Some(FixedDir {
        m: unit_mantissas(m)?,
        e: -30,
        unit: true,
    })
}

/// Where the world ray `o + t D` meets the object-space plane z = 0, for
/// `t_min < t < t_max`: `(t, x, y)`, t the world distance along D (taken as a
/// unit vector; see [`to_unit`]) and (x, y, 0) the object-space point.
pub(crate) fn plane_hit(
    rows: &[FixedRow; 3],
    o: [I16F16; 3],
    d: FixedDir,
    t_min: I16F16,
    t_max: I16F16,
) -> Option<(I16F16, I16F16, I16F16)> {
    let d = if d.unit && d.e == -30 { d } else { to_unit(d)? };
    // How fast the object's z changes per unit of world distance.
    let dz = dot(&rows[2], &d.m);
    if dz == 0 {
        return None;
    }
    let oz = rows[2].apply(o, true).to_bits() as i64;
    // t = −oz / (row_z · D): Q16.16 bits −oz · 2^(30 + shift) / dz.
    // A hit beyond Q16.16's range is drawn at its edge, not dropped: f32
    // draws it, and only the direction of a point that far matters.
    let t = ratio(-oz, dz, 30 + rows[2].shift).min(i32::MAX as i64 - 1);
    if t <= t_min.to_bits() as i64 || t >= t_max.to_bits() as i64 {
        return None;
    }
    // Object-space x and y: o + t (row · D), in range only.
    let along = |i: usize| {
        let start = rows[i].apply(o, true).to_bits() as i64;
        q16(start + scaled(t, dot(&rows[i], &d.m), 30 + rows[i].shift))
    };
    Some((q16(t), along(0), along(1)))
}
