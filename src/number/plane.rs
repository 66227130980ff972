//! Q16.16's ray–plane intersection, from a unit direction held to 30 bits.
//!
//! The plane is the object-space z = 0 of an object whose world → object rows
//! are given. Along the world ray `o + t D` with D a unit vector, the object's
//! z is `oz + t (row_z · D)`, so the world distance is `t = −oz / (row_z · D)`:
//! one exact dot product and one division. The object-space x and y, which
//! only the texture needs, follow from t by two more products, and only for a
//! hit within range. Every product of the 30-bit rows and mantissas is exact
//! in an i64; grazing hits far away keep their precision.

use crate::number::q16::{shr_round, side_bits, FixedDir, FixedRow};
use crate::number::wide::{
    bits_u64, div_pow2_u32, div_rem_u64, isqrt_floor_u64, mul_i32, mul_i32_inline, mul_i64, mul_u32_inline, sar64,
};
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
    let q = if saturates(nu, e) {
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

/// Whether `nu · 2^e` reaches 2^62 (`bits(nu) + e > 62`), without a bit
/// count (a binary search on the M0): `nu >= 2^(62 - e)`.
#[inline(always)]
fn saturates(nu: u64, e: u32) -> bool {
    e > 62 || sar64(nu as i64, 62 - e) != 0
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
    let sq: u64 = d.iter().map(|&x| mul_i32_inline(x as i32, x as i32) as u64).sum();
    let l = isqrt_floor_u64(sq);
    if l == 0 {
        return None;
    }
    // |x| <= l keeps each component within 2^30; the reciprocal 2^61 / l fits
    // 32 bits where l > 2^29 (callers scale their vectors up to make it so).
    Some(if l > 1 << 29 {
        // l < 2^32 (sq < 2^64) and the quotient fits 32 bits: the fast division.
        let recip = div_pow2_u32(61, l as u32) as u32;
        d.map(|x| {
            // |x| <= l < 2^32: one 32 x 32-bit product.
            let q = ((mul_u32_inline(x.unsigned_abs() as u32, recip) + (1 << 30)) >> 31) as i64;
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
    let b = bits_u64(big);
    let m = if b > 31 {
        d.m.map(|x| shr_round(x, b - 31))
    } else {
        d.m.map(|x| x << (31 - b))
    };
    Some(FixedDir {
        m: unit_mantissas(m)?,
        e: -30,
        unit: true,
        o_lo: d.o_lo,
    })
}

/// Where the world ray `o + t D` meets the object-space plane z = 0, for
/// `t_min < t < t_max`: `(t, x, y)`, t the world distance along D (taken as a
/// unit vector; see [`to_unit`]) and (x, y, 0) the object-space point.
/// `checker` is the plane's (side, scale) as `Kernels::checker_cell` takes
/// them (side 0: none): for a hit beyond the range, x and y come back as a
/// point of the true hit's checker parity (see [`far_xy`]). `face` is
/// `Kernels::plane_hit`'s: `(2, 0)` for the plane.
#[allow(clippy::too_many_arguments)]
pub(crate) fn plane_hit(
    rows: &[FixedRow; 3],
    o: [I16F16; 3],
    d: FixedDir,
    t_min: I16F16,
    t_max: I16F16,
    checker: (I16F16, I16F16),
    eye: Option<[I16F16; 4]>,
    face: (usize, i8),
) -> Option<(I16F16, I16F16, I16F16)> {
    let d = if d.unit && d.e == -30 { d } else { to_unit(d)? };
    // A cube's face: its row, the plane where it is ±1.
    let row = match face.0 {
        0 => &rows[0],
        1 => &rows[1],
        _ => &rows[2],
    };
    // How fast the object's z changes per unit of world distance.
    let dz = dot(row, &d.m);
    if dz == 0 {
        return None;
    }
    // t = −oz / (row_z · D) = −oz' 2^30 / dz for oz' the exact object z at
    // scale 2^-(16 + shift), cut to 32 bits (2^-32 relative): oz rounded to
    // Q16.16 moved a grazing hit by 2^-17 / (row_z · D), 1e-3 at 33 (
    // the seam of two planes a pixel off).
    let z = match eye {
        // A chief ray: the same origin terms for every pixel, from set-up.
        Some(e) => ((e[3].to_bits() as i64) << 32) | e[2].to_bits() as u32 as i64,
        None => {
            let z = origin_z(row, o, &d.o_lo);
            if face.1 == 0 {
                z
            } else {
                z - ((face.1 as i64) << (row.shift + 16))
            }
        }
    };
    // Most origins fit 32 bits: no bit count then (a binary search on the M0).
    let (oz, k) = if z.unsigned_abs() >> 32 == 0 {
        (z, 0)
    } else {
        let k = bits(z.unsigned_abs()) - 32;
        (shr_round(z, k), k)
    };
    // A plane behind the ray (or through its origin) gives t <= 0, which no
    // t_min >= 0 takes: no division for it (the sky, half the rays away).
    if t_min >= I16F16::ZERO && (oz == 0 || (oz > 0) == (dz > 0)) {
        return None;
    }
    // A hit beyond Q16.16's range is drawn at its edge, not dropped: f32
    // draws it, and only the direction of a point that far matters (and its
    // texture: see [`far_xy`]).
    let t = ratio(-oz, dz, 30 + k);
    let far = t > FAR_T;
    let t = t.min(FAR_T);
    if t <= t_min.to_bits() as i64 || t >= t_max.to_bits() as i64 {
        return None;
    }
    if far {
        let (x, y) = far_xy(rows, o, &d, (oz, k, dz), checker);
        return Some((q16(t), x, y));
    }
    // Object-space x and y: o + t (row · D). Beyond Q16.16's range (a hit
    // in range on a plane scaled down: one at 31,777 read 59,958 of
    // its object y), the middle of a square of its true parity, as `far_xy`.
    let along = |i: usize| {
        let start = match eye {
            Some(e) => e[i],
            None => rows[i].apply(o, true),
        }
        .to_bits() as i64;
        let x = start + scaled(t, dot(&rows[i], &d.m), 30 + rows[i].shift);
        if x == x as i32 as i64 {
            I16F16::from_bits(x as i32)
        } else {
            far_coord(&rows[i], o, &d, t, 0, checker)
        }
    };
    Some((q16(t), along(0), along(1)))
}

/// The origin's exact object-space z at the row's scale 2^-(16 + shift),
/// with its bits below Q16.16 where it has any.
#[inline]
fn origin_z(row: &FixedRow, o: [I16F16; 3], o_lo: &[i16; 3]) -> i64 {
    let z = row.exact(o, true);
    // An origin on the Q16.16 grid (every ray but a chief ray from an eye off it) has nothing below.
    if *o_lo != [0; 3] {
        z + origin_low(row, o_lo)
    } else {
        z
    }
}

/// Rounds `x` to the nearest integer, away from zero on ties. Set-up only.
pub(crate) fn round_f64(x: f64) -> f64 {
    let r = libm::floor(libm::fabs(x) + 0.5);
    if x < 0.0 {
        -r
    } else {
        r
    }
}

/// What rounding `x` to Q16.16 (as `Scalar::from_f64`) leaves, at 2^-32; 0
/// out of range (set-up only).
pub(crate) fn below_q16(x: f64) -> i16 {
    let q = libm::floor(x * 65536.0 + 0.5);
    if libm::fabs(q) < (1u64 << 31) as f64 {
        round_f64((x * 65536.0 - q) * 65536.0).clamp(-32767.0, 32767.0) as i16
    } else {
        0
    }
}

/// [`plane_hit`]'s terms of a pinhole's chief rays that depend on the eye
/// alone: `rows[0]` and `rows[1]` applied to it (Q16.16) and its exact z
/// (`origin_z`, low word then high word), from the eye `o` and its bits
/// below, `o_lo`. Set-up only.
pub(crate) fn plane_from_eye(rows: &[FixedRow; 3], o: [I16F16; 3], o_lo: [i16; 3]) -> [I16F16; 4] {
    let z = origin_z(&rows[2], o, &o_lo);
    [
        rows[0].apply(o, true),
        rows[1].apply(o, true),
        I16F16::from_bits(z as i32),
        I16F16::from_bits((z >> 32) as i32),
    ]
}

/// `row · o_lo` (the origin's bits below Q16.16, at 2^-32) at the row's exact
/// scale 2^-(16 + shift): the eye's height over a floor 0.4 below it was
/// 2e-5 off with the eye rounded, its hit 4 away 8e-5.
#[inline]
fn origin_low(row: &FixedRow, o_lo: &[i16; 3]) -> i64 {
    // 32-bit products (one instruction on the M0): m's top 15 bits times a
    // value below 2^15, at 2^-(17 + shift); m's dropped bits weigh 2^-32.
    let s: i64 = (0..3).map(|i| ((row.m[i] >> 15) * o_lo[i] as i32) as i64).sum();
    (s + 1) >> 1
}

/// The distance (Q16.16 bits) [`plane_hit`] gives a hit beyond the range.
pub(crate) const FAR_T: i64 = i32::MAX as i64 - 1;

/// Object-space x and y of a plane hit beyond the range (`t = −oz 2^(30 + k)
/// / dz` Q16.16 bits), for the plane's checker (side, scale): each the middle
/// of a square of the true hit's checker parity. At the clamped distance the texture took the square 32767
/// along the ray, unrelated to the true one (a lens: half the
/// samples on a far plane took a random square, where f32 took the right
/// one 84 % of the time); a plane's x and y serve only its texture. Without
/// a texture, or where 31 bits cannot tell the square, 0.
#[inline(never)]
fn far_xy(
    rows: &[FixedRow; 3],
    o: [I16F16; 3],
    d: &FixedDir,
    (oz, k, dz): (i64, u32, i64),
    checker: (I16F16, I16F16),
) -> (I16F16, I16F16) {
    // t in units of 2^g bits, g so that it fits 31 bits again (30 significant).
    let g = (bits_u64(oz.unsigned_abs()) + k + 1)
        .saturating_sub(bits_u64(dz.unsigned_abs()))
        .min(30 + k);
    let t = ratio(-oz, dz, 30 + k - g);
    let along = |i: usize| far_coord(&rows[i], o, d, t, g, checker);
    (along(0), along(1))
}

/// [`far_xy`]'s one coordinate `row · o + t (row · D)`, `t` in units of 2^g
/// Q16.16 bits. Out of line: one copy of its wide products.
#[inline(never)]
fn far_coord(row: &FixedRow, o: [I16F16; 3], d: &FixedDir, t: i64, g: u32, checker: (I16F16, I16F16)) -> I16F16 {
    let (side, m) = (checker.0.to_bits(), checker.1.to_bits());
    let sb = side_bits(checker.0);
    let (dot, shift) = (dot(row, &d.m), 30 + row.shift);
    // In units of 2^(g + up) bits, up for a row that stretches (|row · D| up to 2^up).
    let gi = g + (bits(dot.unsigned_abs()) + 1).saturating_sub(shift);
    let x = sar64(row.apply(o, true).to_bits() as i64, gi) + scaled(sar64(t, gi - g), dot, shift);
    if sb == 0 || gi > 29 + sb || x != x as i32 as i64 {
        return I16F16::ZERO;
    }
    // Kernels::checker_cell of x 2^gi: floor(x 2^gi m / 2^(29 + b)).
    let cell = mul_i32(x as i32, m) >> (29 + sb - gi);
    // The middle of square 0 or of square −1: in range, its cell beyond doubt.
    let half = side / 2;
    I16F16::from_bits(if cell & 1 == 0 { half } else { half - side })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::transform::Mat34;
    use crate::number::{Kernels, Scalar};

    /// The kernel's face argument for the plane itself.
    const PLANE: (usize, i8) = (2, 0);

    /// [`saturates`] agrees with the bit count it replaces, at every exponent
    /// and around every power of two as well as at random.
    #[test]
    fn saturation_test_is_the_bit_count() {
        let mut next = crate::test_rng::xorshift32(0x5EED_0062);
        for e in 0..=70u32 {
            for b in 0..64u32 {
                let p = 1u64 << b;
                let r = ((next() as u64) << 32 | next() as u64) >> (63 - b);
                for nu in [p - 1, p, p + 1, r, u64::MAX >> (63 - b)] {
                    assert_eq!(saturates(nu, e), bits(nu) + e > 62, "nu {nu} e {e}");
                }
            }
        }
    }

    /// [`unit_mantissas`]' 32 x 32-bit products lose nothing: each component
    /// against the same rounding of |x| 2^61 / l in u128, l the exact integer
    /// square root, for directions whose largest component is in [2^30, 2^31)
    /// (its callers' promise), random and at the extremes.
    #[test]
    fn unit_mantissas_match_wide_arithmetic() {
        let mut next = crate::test_rng::xorshift32(0x0417_2026);
        let mut cases: Vec<[i64; 3]> = vec![
            [(1 << 31) - 1, (1 << 31) - 1, (1 << 31) - 1],
            [-(1 << 31) + 1, (1 << 31) - 1, -(1 << 31) + 1],
            [1 << 30, 0, 0],
            [0, -(1 << 30), 1],
        ];
        for _ in 0..20_000 {
            let big = ((1i64 << 30) + (next() as i64 & ((1 << 30) - 1))) * if next() & 1 == 0 { 1 } else { -1 };
            let other = |n: u32| (n as i32 >> (n & 31)) as i64 % (1 << 31);
            let mut d = [big, other(next()), other(next())];
            d.rotate_left((next() % 3) as usize);
            cases.push(d);
        }
        for d in cases {
            let sq: u64 = d.iter().map(|&x| (x * x) as u64).sum();
            let l = sq.isqrt();
            assert!(l > 1 << 29, "{d:?}");
            let recip = (1u128 << 61) / l as u128;
            let want = d.map(|x| {
                let q = ((x.unsigned_abs() as u128 * recip + (1 << 30)) >> 31) as i64;
                if x < 0 {
                    -q
                } else {
                    q
                }
            });
            assert_eq!(unit_mantissas(d), Some(want), "{d:?}");
        }
    }

    /// A chief ray's plane hit from the eye terms of set-up
    /// ([`plane_from_eye`]) is the hit computed from the eye itself, bit for
    /// bit: random planes, eyes off the Q16.16 grid (and on it), directions.
    #[test]
    fn eye_terms_from_set_up_give_the_same_hit() {
        let mut next = crate::test_rng::unit_f64(0x0E7E_7E2D);
        let mut hits = 0;
        for n in 0..20_000 {
            let to_world = Mat34::translate([0, 1, 2].map(|_| next() * 60.0 - 30.0))
                .after(&Mat34::rotate(1, next() * 360.0))
                .after(&Mat34::rotate(0, next() * 360.0))
                .after(&Mat34::scale([
                    0.2 + next() * 5.0,
                    0.2 + next() * 5.0,
                    0.2 + next() * 5.0,
                ]));
            let rows = to_world.inverse().unwrap().0.map(<I16F16 as Kernels>::row_from_f64);
            let eye = [0, 1, 2].map(|_| {
                let x = next() * 200.0 - 100.0;
                if n % 4 == 0 {
                    libm::round(x)
                } else {
                    x
                }
            });
            let (o, o_lo) = (eye.map(I16F16::from_f64), eye.map(below_q16));
            let v = [0, 1, 2].map(|_| next() * 2.0 - 1.0);
            let l = libm::sqrt(v.iter().map(|x| x * x).sum());
            let d = FixedDir {
                m: v.map(|x| libm::round(x / l * (1u64 << 30) as f64) as i64),
                e: -30,
                unit: true,
                o_lo,
            };
            let checker = (I16F16::from_f64(0.5), <I16F16 as Kernels>::checker_scale(0.5));
            let from = |eye| plane_hit(&rows, o, d, I16F16::from_bits(64), I16F16::MAX, checker, eye, PLANE);
            let want = from(None);
            hits += want.is_some() as u32;
            assert_eq!(
                from(Some(plane_from_eye(&rows, o, o_lo))),
                want,
                "eye {eye:?} dir {v:?}"
            );
        }
        assert!(hits > 5_000, "{hits} hits");
    }

    /// Rays from random origins to a checkered floor at a distance of `near`
    /// to 10 `near`, turned about y and scaled in its own plane by 0.3 to 4.3
    /// times `shrink`: of the hits `keep` takes (by f64's t and object x, y),
    /// how many, and how many whose parity of [`plane_hit`]'s (x, y) under
    /// `Kernels::checker_cell` is that of the same hit computed in f64 from
    /// the kernel's own inputs (rows, rounded origin terms, direction mantissas).
    fn checker_parity(seed: u32, near: f64, shrink: f64, keep: fn(f64, f64, f64) -> bool) -> (u32, u32) {
        let mut next = crate::test_rng::unit_f64(seed);
        let (mut kept, mut right) = (0, 0);
        for _ in 0..4000 {
            // A floor at height h, turned about y and scaled in its own plane.
            let (h, turn, s) = (next() * 100.0 - 50.0, next() * 360.0, (0.3 + next() * 4.0) * shrink);
            let to_world = Mat34::translate([0.0, h, 0.0])
                .after(&Mat34::rotate(1, turn))
                .after(&Mat34::rotate(0, -90.0))
                .after(&Mat34::scale([s, s, 1.0]));
            let inv = to_world.inverse().unwrap();
            let rows = inv.0.map(<I16F16 as Kernels>::row_from_f64);
            let side = I16F16::from_f64(0.3 + next() * 9.0);
            let scale = <I16F16 as Kernels>::checker_scale(side.to_f64());
            let o = [0, 1, 2].map(|_| I16F16::from_f64(next() * 200.0 - 100.0));
            // Towards the floor at a distance of `near` to 10 `near`.
            let reach = near * libm::exp(next() * libm::log(10.0));
            let dy = h - o[1].to_f64();
            let phi = next() * core::f64::consts::TAU;
            let c = libm::sqrt(1.0 - (dy / reach) * (dy / reach));
            let unit = [c * libm::cos(phi), dy / reach, c * libm::sin(phi)];
            let m = unit.map(|x| libm::round(x * (1u64 << 30) as f64) as i64);
            let d = FixedDir {
                m,
                e: -30,
                unit: true,
                o_lo: [0; 3],
            };
            let Some((_, x, y)) = plane_hit(
                &rows,
                o,
                d,
                I16F16::from_bits(64),
                I16F16::MAX,
                (side, scale),
                None,
                PLANE,
            ) else {
                continue;
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
            if !keep(t, fx, fy) || fx.abs().max(fy.abs()) > (1u64 << 29) as f64 {
                continue;
            }
            // Kernels::checker_cell on the exact value: floor(x 2^16 m / 2^(29 + b)).
            let b = 32 - side.to_bits().leading_zeros();
            let cell = |v: f64| libm::floor(v * 65536.0 * scale.to_bits() as f64 / libm::exp2((29 + b) as f64)) as i64;
            let want = (cell(fx) + cell(fy)) & 1;
            let cells = |v: I16F16| <I16F16 as Kernels>::checker_cell(v, side, scale);
            let got = (cells(x) + cells(y)) & 1;
            kept += 1;
            right += (got == want) as u32;
        }
        (kept, right)
    }

    /// A checkered plane's hits beyond Q16.16's range keep their true square
    /// ([`checker_parity`]). Clamping the distance at 32767 gives the square
    /// there: right half the time.
    #[test]
    fn far_hits_keep_their_checker_parity() {
        let (far, right) = checker_parity(0x2545_F491, 40_000.0, 1.0, |t, _, _| t >= 32768.0);
        // Borders within 2^-30 of a hit's size may go either way: a few.
        assert!(right as f64 >= 0.995 * far as f64, "{right} of {far}");
        assert!(far > 1000, "{far}");
    }

    /// Hits in range on a plane scaled down, whose object x or y is beyond
    /// Q16.16's range, keep their true square too ([`checker_parity`];
    /// the coordinate clamped at 32768, a column of squares flipped).
    #[test]
    fn hits_in_range_beyond_the_objects_range_keep_their_parity() {
        let (kept, right) = checker_parity(0x3225_4001, 3_000.0, 0.05, |t, x, y| {
            t < 32768.0 && x.abs().max(y.abs()) >= 32768.0
        });
        assert!(right as f64 >= 0.995 * kept as f64, "{right} of {kept}");
        assert!(kept > 500, "{kept}");
    }

    /// Grazing hits in range: t within 2^-16 plus 2^-28 relative of its value
    /// computed in f64 from the kernel's own inputs (rows, origin, direction
    /// mantissas). The origin's object z rounded to Q16.16 first was off by
    /// 2^-17 / (row_z · D): 1e-3 at a slope of 0.004.
    #[test]
    fn grazing_hits_take_the_exact_origin() {
        let mut next = crate::test_rng::unit_f64(0x1234_5678);
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
            let d = FixedDir {
                m,
                e: -30,
                unit: true,
                o_lo: [0; 3],
            };
            let r = &rows[2];
            let dz: f64 = (0..3).map(|k| r.m[k] as f64 * m[k] as f64).sum::<f64>() / libm::exp2(30.0 + r.shift as f64);
            let oz = r.exact(o, true) as f64 / libm::exp2(16.0 + r.shift as f64);
            let want = -oz / dz;
            if !(0.01..30000.0).contains(&want) {
                continue;
            }
            let (t, _, _) = plane_hit(
                &rows,
                o,
                d,
                I16F16::from_bits(64),
                I16F16::MAX,
                (I16F16::ZERO, I16F16::ZERO),
                None,
                PLANE,
            )
            .expect("a hit");
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
