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
use crate::number::wide::{bits_u64, div_rem_u64, div_rem_u64_u32, isqrt_rem_u64, mul_i32, mul_i64, mul_u64, Recip};
use fixed::types::I16F16;

/// Bits needed for `x` (0 for 0).
#[inline]
fn bits(x: u64) -> u32 {
    bits_u64(x)
}

/// `row · m` exactly, at scale `2^-(30 + row.shift)` for mantissas at `2^-30`.
#[inline]
fn dot(row: &FixedRow, m: &[i64; 3]) -> i64 {
    // 30-bit entries times 30-bit mantissas: i32 factors, each product below 2^60.
    mul_i32(row.m[0], m[0] as i32) + mul_i32(row.m[1], m[1] as i32) + mul_i32(row.m[2], m[2] as i32)
}

/// `x` cut to at most 31 bits: `(x', k)` with `x ≈ x' · 2^k`, rounded.
#[inline]
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
    // t = −oz / (row_z · D) = −oz' 2^30 / dz for oz' the exact object z at
    // scale 2^-(16 + shift), cut to 32 bits (2^-32 relative): oz rounded to
    // Q16.16 moved a grazing hit by 2^-17 / (row_z · D), 1e-3 at 33 (seed
    // 3162: the seam of two planes a pixel off).
    let (oz, k) = origin_z(rows, o);
    // A hit beyond Q16.16's range is drawn at its edge, not dropped: f32
    // draws it, and only the direction of a point that far matters (its
    // texture: see [`far_checker`]).
    let t = ratio(-oz, dz, 30 + k).min(FAR_T);
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

/// The object-space z of the world point `o`, exactly, as `(z', k)` with
/// `z = z' 2^(k - 16 - shift)` and `|z'| <= 2^32`.
#[inline]
fn origin_z(rows: &[FixedRow; 3], o: [I16F16; 3]) -> (i64, u32) {
    let z = rows[2].exact(o, true);
    let k = bits(z.unsigned_abs()).saturating_sub(32);
    if k == 0 {
        (z, 0)
    } else {
        (shr_round(z, k), k)
    }
}

/// The distance (Q16.16 bits) [`plane_hit`] gives a hit beyond the range.
pub(crate) const FAR_T: i64 = i32::MAX as i64 - 1;

/// For a hit of [`plane_hit`] at [`FAR_T`] (beyond the range) on a plane
/// checkered with `side` and `scale` (as `Kernels::checker_cell` takes
/// them): object-space x and y with the checker parity of the true hit. At
/// the clamped distance the texture took the square 32767 along the ray,
/// unrelated to the true one (seed 3086, lens: half the samples on a far
/// plane took a random square where f32 took the right one 84 % of the
/// time). The coordinates come from the exact ratio without t, to 30 bits,
/// each as the middle of a square of its true cell's parity (a plane's x and
/// y serve only its texture). Rare: kept out of line.
#[inline(never)]
pub(crate) fn far_checker(
    rows: &[FixedRow; 3],
    o: [I16F16; 3],
    d: FixedDir,
    side: I16F16,
    scale: I16F16,
) -> Option<(I16F16, I16F16)> {
    let d = if d.unit && d.e == -30 { d } else { to_unit(d)? };
    let dz = dot(&rows[2], &d.m);
    let (oz, k) = origin_z(rows, o);
    let coord = |i: usize| {
        let start = rows[i].apply(o, true).to_bits() as i64;
        // x − start = t (row_x · D) / 2^(30 + shift_x), t = −oz 2^(30 + k) / dz.
        let e = k as i32 - rows[i].shift as i32;
        far_coord(
            start,
            -oz,
            dot(&rows[i], &d.m),
            dz,
            e,
            side.to_bits() as i64,
            scale.to_bits() as i64,
        )
    };
    (dz != 0 && side.to_bits() > 0).then(|| (coord(0), coord(1)))
}

/// Bits of `|x|` past which a far hit's checker cell is not worth computing:
/// 2^30 object units, where f32's own rounding is whole squares.
const FAR_LIMIT_BITS: u32 = 46;

/// The object-space coordinate `start + n · dot / dz · 2^e` (Q16.16 bits, for
/// `dz != 0`) as the middle of a square (side `side`, scale `scale`, both
/// Q16.16 bits, side > 0) of its cell's parity; saturated past [`FAR_LIMIT_BITS`].
#[inline(never)]
fn far_coord(start: i64, n: i64, dot: i64, dz: i64, e: i32, side: i64, scale: i64) -> I16F16 {
    let (dot, kd) = cut31(dot);
    let (dz, kz) = cut31(dz);
    // |n| < 2^32 and |dot| < 2^31: the product, then shifted up to 62 bits for
    // a quotient of at least 30 bits.
    let num = mul_i64(n, dot);
    let b = bits(num.unsigned_abs());
    let up = 62u32.saturating_sub(b);
    // dz below 2^32 after the cut: the reciprocal division (the M0's fast one).
    let q = crate::number::q16::div_round_i64_by(num << up, &Recip::new(dz.unsigned_abs() as u32), dz < 0);
    let e = e + kd as i32 - kz as i32 - up as i32;
    let off = if num == 0 {
        0
    } else if e >= 0 {
        if bits(q.unsigned_abs()) + e as u32 >= FAR_LIMIT_BITS {
            return q16(start + q.signum() * (1 << FAR_LIMIT_BITS));
        }
        q << e
    } else if -e >= 63 {
        0
    } else {
        shr_round(q, (-e) as u32)
    };
    let x = start + off;
    if x.unsigned_abs() >> FAR_LIMIT_BITS != 0 {
        return q16(x);
    }
    // floor(x m / 2^(29 + b)) as `Kernels::checker_cell`, for |x| < 2^46: x's
    // top and low 16 bits times the 30-bit mantissa, each within an i64.
    let sb = 64 - side.leading_zeros();
    let (hi, lo) = (x >> 16, x & 0xFFFF);
    let cell = (hi * scale + ((lo * scale) >> 16)) >> (13 + sb);
    // The middle of square 0 or of square −1: in range, and its cell beyond doubt.
    let half = side / 2;
    I16F16::from_bits(if cell & 1 == 0 { half } else { -(side - half) } as i32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::transform::Mat34;
    use crate::number::{Kernels, Scalar};

    /// A checkered plane's hits beyond Q16.16's range keep their true square:
    /// the parity of [`plane_hit`]'s (x, y) under `Kernels::checker_cell`
    /// against the parity of the same hit computed in f64 from the kernel's
    /// own inputs (rows, rounded origin terms, direction mantissas). Clamping
    /// the distance at 32767 gives the square there: right half the time.
    #[test]
    fn far_hits_keep_their_checker_parity() {
        let mut seed = 0x2545_F491u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f64 / u32::MAX as f64
        };
        let (mut far, mut right) = (0, 0);
        for _ in 0..4000 {
            // A floor at height h, turned about y and scaled in its own plane.
            let (h, turn, s) = (next() * 100.0 - 50.0, next() * 360.0, 0.3 + next() * 4.0);
            let to_world = Mat34::translate([0.0, h, 0.0])
                .after(&Mat34::rotate(1, turn))
                .after(&Mat34::rotate(0, -90.0))
                .after(&Mat34::scale([s, s, 1.0]));
            let inv = to_world.inverse().unwrap();
            let rows = inv.0.map(<I16F16 as Kernels>::row_from_f64);
            let side = I16F16::from_f64(0.3 + next() * 9.0);
            let scale = <I16F16 as Kernels>::checker_scale(side.to_f64());
            let o = [0, 1, 2].map(|_| I16F16::from_f64(next() * 200.0 - 100.0));
            // Towards the floor at a distance of 40,000 to 400,000.
            let reach = 40_000.0 * libm::exp(next() * libm::log(10.0));
            let dy = h - o[1].to_f64();
            let phi = next() * core::f64::consts::TAU;
            let c = libm::sqrt(1.0 - (dy / reach) * (dy / reach));
            let unit = [c * libm::cos(phi), dy / reach, c * libm::sin(phi)];
            let m = unit.map(|x| libm::round(x * (1u64 << 30) as f64) as i64);
            let d = FixedDir { m, e: -30, unit: true };
            let Some((t, x, y)) = plane_hit(&rows, o, d, I16F16::from_bits(64), I16F16::MAX) else {
                continue;
            };
            let (x, y) = if t.to_bits() as i64 == FAR_T {
                far_checker(&rows, o, d, side, scale).unwrap()
            } else {
                (x, y)
            };
            // The same hit in f64 from the kernel's inputs: the row products
            // and the origin's z exactly, its x and y as the kernel rounds them.
            let row = |r: &FixedRow| {
                let dot: f64 = (0..3).map(|k| r.m[k] as f64 * m[k] as f64).sum();
                (r.apply(o, true).to_f64(), dot / libm::exp2(30.0 + r.shift as f64))
            };
            let oz = rows[2].exact(o, true) as f64 / libm::exp2(16.0 + rows[2].shift as f64);
            let dz = row(&rows[2]).1;
            let t = -oz / dz;
            let coord = |r: &FixedRow| {
                let (start, dot) = row(r);
                start + t * dot
            };
            let (fx, fy) = (coord(&rows[0]), coord(&rows[1]));
            if t < 32768.0 || fx.abs().max(fy.abs()) > (1u64 << 29) as f64 {
                continue;
            }
            // Kernels::checker_cell on the exact value: floor(x 2^16 m / 2^(29 + b)).
            let b = 32 - side.to_bits().leading_zeros();
            let cell = |v: f64| libm::floor(v * 65536.0 * scale.to_bits() as f64 / libm::exp2((29 + b) as f64)) as i64;
            let want = (cell(fx) + cell(fy)) & 1;
            let cells = |v: I16F16| <I16F16 as Kernels>::checker_cell(v, side, scale);
            let got = (cells(x) + cells(y)) & 1;
            far += 1;
            right += (got == want) as u32;
        }
        // Borders within 2^-30 of a hit's size may go either way: a few.
        assert!(right as f64 >= 0.995 * far as f64, "{right} of {far}");
        assert!(far > 1000, "{far}");
    }

    /// Grazing hits in range: t within 2^-16 plus 2^-28 relative of its value
    /// computed in f64 from the kernel's own inputs (rows, origin, direction
    /// mantissas). The origin's object z rounded to Q16.16 first was off by
    /// 2^-17 / (row_z · D): 1e-3 at a slope of 0.004 (seed 3162).
    #[test]
    fn grazing_hits_take_the_exact_origin() {
        let mut seed = 0x1234_5678u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f64 / u32::MAX as f64
        };
        let mut tested = 0;
        for _ in 0..4000 {
            let (h, s) = (next() * 60.0 - 30.0, 0.3 + next() * 4.0);
            let to_world = Mat34::translate([next() * 10.0, h, next() * 10.0])
                .after(&Mat34::rotate(2, next() * 360.0))
                .after(&Mat34::rotate(0, -90.0 + next() * 20.0 - 10.0))
                .after(&Mat34::scale([s, 1.0 / s, s]));
            let rows = to_world.inverse().unwrap().0.map(<I16F16 as Kernels>::row_from_f64);
            let o = [0, 1, 2].map(|_| I16F16::from_f64(next() * 20.0 - 10.0));
            // Slopes of 1e-4 to 1e-1 against the floor.
            let slope = -libm::exp(libm::log(1e-4) + next() * libm::log(1e3));
            let phi = next() * core::f64::consts::TAU;
            let c = libm::sqrt(1.0 - slope * slope);
            let unit = [c * libm::cos(phi), slope, c * libm::sin(phi)];
            let m = unit.map(|x| libm::round(x * (1u64 << 30) as f64) as i64);
            let d = FixedDir { m, e: -30, unit: true };
            let r = &rows[2];
            let dz: f64 = (0..3).map(|k| r.m[k] as f64 * m[k] as f64).sum::<f64>() / libm::exp2(30.0 + r.shift as f64);
            let oz = r.exact(o, true) as f64 / libm::exp2(16.0 + r.shift as f64);
            let want = -oz / dz;
            if !(0.01..30000.0).contains(&want) {
                continue;
            }
            let (t, _, _) = plane_hit(&rows, o, d, I16F16::from_bits(64), I16F16::MAX).expect("a hit");
            let err = (t.to_f64() - want).abs();
            assert!(
                err <= 1.0 / 65536.0 + want / (1u64 << 28) as f64,
                "t {} vs {want}",
                t.to_f64()
            );
            tested += 1;
        }
        assert!(tested > 1000, "{tested}");
    }
}
