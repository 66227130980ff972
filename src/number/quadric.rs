//! Q16.16's roots of the cylinder's and the cone's side quadric, exactly.
//!
//! The side is `x² + z² = 1` (cylinder) or `x² + z² = ((1 − y) / 2)²` (cone).
//! Along `o + t d` that is `A t² + 2 B t + C = 0`, whose coefficients are sums
//! of products of Q16.16 values: exact in an i64 at scale 2⁻³² (the cone's
//! times 4, so that its quarter is exact too), and the discriminant
//! `B² − A C` exact in an i128. The roots then come from the stable pair
//! `q / A`, `C / q` with `q = −(B + sign(B) √disc)`: no cancellation between
//! `B` and the root, and a ray nearly along a cone's line (A near 0) keeps
//! its one finite root, where rounding each product to 2⁻¹⁶ moved hits near
//! a cone's apex by 0.01 of its size.

use crate::number::q16::div_round_i64;
use crate::number::wide::{div_rem_u64, isqrt_round_u64, mul_i32, mul_u32};
use fixed::types::I16F16;

/// `n / d` as Q16.16 bits, rounded and saturated, for `d != 0`.
fn ratio_q16(n: i64, d: i64) -> I16F16 {
    let q = if n.unsigned_abs() < 1 << 46 {
        div_round_i64(n << 16, d)
    } else {
        // Rare (object-space origins far along a squashed axis).
        wide_ratio_trunc(n, d)
    };
    I16F16::from_bits(q.clamp(i32::MIN as i64, i32::MAX as i64) as i32)
}

/// `n · 2^16 / d` truncated towards zero, for `d != 0`, exactly where it lies
/// within ±2^32 (beyond, ±2^32: the caller saturates to 32 bits anyway). A
/// u64 division and 16 steps of long division: an i128 division is expanded
/// in place on the Cortex-M0 (900 bytes of its flash).
fn wide_ratio_trunc(n: i64, d: i64) -> i64 {
    let (nu, du) = (n.unsigned_abs(), d.unsigned_abs().max(1));
    let (q1, mut r) = div_rem_u64(nu, du);
    let q = if q1 >> 16 != 0 {
        1 << 32
    } else {
        let mut q = q1;
        for _ in 0..16 {
            // r < du <= 2^63: doubling it never wraps.
            r <<= 1;
            q <<= 1;
            if r >= du {
                r -= du;
                q |= 1;
            }
        }
        q
    } as i64;
    if (n < 0) != (d < 0) {
        -q
    } else {
        q
    }
}

/// `a · b` exactly, from four 32 × 32-bit products: no i128 multiply (a
/// library call, and stack, on the Cortex-M0).
fn mul_wide(a: i64, b: i64) -> i128 {
    let (ua, ub) = (a.unsigned_abs(), b.unsigned_abs());
    let (a0, a1, b0, b1) = (ua as u32, (ua >> 32) as u32, ub as u32, (ub >> 32) as u32);
    let mid = mul_u32(a0, b1) as u128 + mul_u32(a1, b0) as u128;
    let p = mul_u32(a0, b0) as u128 + (mid << 32) + ((mul_u32(a1, b1) as u128) << 64);
    if (a < 0) != (b < 0) {
        -(p as i128)
    } else {
        p as i128
    }
}

/// The rounded square root of an i128 `x >= 0`, as an i64: scaled into a u64
/// by constant two-bit shifts where needed (the root then keeps 31 bits).
fn sqrt_wide(x: i128) -> i64 {
    let mut x = x as u128;
    let mut k = 0;
    while x >> 62 != 0 {
        x >>= 2;
        k += 1;
    }
    (isqrt_round_u64(x as u64) << k) as i64
}

/// The side roots `(t0, t1)`, `t0 <= t1`, of the ray `o + t d` (object space,
/// Q16.16), or `None` where the ray misses the side's surface (or, for the
/// cylinder, runs along its axis). A cone's ray along one of its lines has one
/// root, returned twice. Sets `close` where the ray is within about 2⁻⁹ of
/// tangent (the chord's half length √disc / A below it, or a miss as near).
// Not inlined: its wide locals stay out of the callers' frames (the M0's 8 KiB of stack).
#[inline(never)]
pub(crate) fn side_roots(o: [I16F16; 3], d: [I16F16; 3], cone: bool, close: &mut bool) -> Option<(I16F16, I16F16)> {
    let [ox, oy, oz] = o.map(I16F16::to_bits);
    let [dx, dy, dz] = d.map(I16F16::to_bits);
    let radial_a = mul_i32(dx, dx) + mul_i32(dz, dz);
    let radial_b = mul_i32(ox, dx) + mul_i32(oz, dz);
    let radial_c = mul_i32(ox, ox) + mul_i32(oz, oz);
    let (a, b, c) = if cone {
        // w = 1 − y: |oy| stays far below 2^15 in object space, so w fits an i32.
        let w0 = (1i32 << 16) - oy;
        (
            4 * radial_a - mul_i32(dy, dy),
            4 * radial_b + mul_i32(w0, dy),
            4 * radial_c - mul_i32(w0, w0),
        )
    } else {
        (radial_a, radial_b, radial_c - (1i64 << 32))
    };
    if a == 0 {
        // Along a line of the cone: 2 B t + C = 0 (the cylinder's axis: no root).
        if !cone || b == 0 {
            return None;
        }
        let t = ratio_q16(-c, 2 * b);
        return Some((t, t));
    }
    let disc = mul_wide(b, b) - mul_wide(a, c);
    // |disc| below 2⁻¹² at scale 2⁻⁶⁴ (the cone's at its own scale, times
    // 16): a line within about 2⁻¹³ / A of tangent, above Q16.16's error
    // (the cone's at 2⁻¹⁴ of the cylinder's left most of its tangents undecided).
    *close |= disc.unsigned_abs() < if cone { 1 << 56 } else { 1 << 52 };
    if disc < 0 {
        return None;
    }
    let h = sqrt_wide(disc);
    let q = if b >= 0 { -(b + h) } else { h - b };
    if q == 0 {
        // b = 0 and a double root: t = 0.
        return Some((I16F16::ZERO, I16F16::ZERO));
    }
    let (r1, r2) = (ratio_q16(q, a), ratio_q16(c, q));
    Some(if r1 <= r2 { (r1, r2) } else { (r2, r1) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wide_ratio_is_the_i128_quotient() {
        let mut next = crate::test_rng::xorshift32(46);
        for i in 0..100_000usize {
            let (w1, w2, w3, sh) = (next(), next(), next(), next());
            let word = ((w1 as u64) << 32 | w2 as u64) as i64;
            let n = match i % 3 {
                0 => word | (1 << 46),
                1 => -(word >> 1 | 1 << 46),
                _ => [i64::MIN, i64::MAX, 1 << 46, -(1 << 46)][i / 3 % 4],
            };
            let dw = ((w3 as u64) << 32 | w1 as u64) as i64;
            let d = match i % 5 {
                0 => [1, -1, i64::MIN, i64::MAX, 3][i / 5 % 5],
                _ => ((dw >> (sh % 63)) & i64::MAX).max(1) * if i % 2 == 0 { 1 } else { -1 },
            };
            let want = (((n as i128) << 16) / d as i128).clamp(-(1 << 32), 1 << 32) as i64;
            assert_eq!(wide_ratio_trunc(n, d), want, "{n} / {d}");
            let clamp = |x: i64| x.clamp(i32::MIN as i64, i32::MAX as i64);
            assert_eq!(ratio_q16(n, d).to_bits() as i64, clamp(want), "{n} / {d}");
        }
    }

    /// Against the roots in f64 of the same Q16.16 ray, over rays through the
    /// cone near its apex, nearly along its lines, and through the cylinder:
    /// each root within 2⁻¹⁵ (the Q16.16 rounding of the result, and slack).
    #[test]
    fn any_input_gives_an_answer_without_overflow() {
        // Corrupt baked scenes reach here with any bits: no overflow (a panic in
        // a debug build), at the exact path's bound and beyond it.
        use crate::number::scalar::Kernels;
        let edge = (1 << 28) - 1;
        let values = [0, 1, -1, 1 << 16, edge, -edge, 1 << 28, i32::MAX, i32::MIN];
        for &a in &values {
            for &b in &values {
                for cone in [false, true] {
                    let (o, d) = (
                        [a, b, a].map(I16F16::from_bits),
                        [b, a, b.wrapping_neg()].map(I16F16::from_bits),
                    );
                    let exact = <I16F16 as Kernels>::side_roots(o, d, cone, &mut false);
                    assert_eq!(
                        exact.is_some(),
                        a.unsigned_abs() < 1 << 28 && b.unsigned_abs() < 1 << 28
                    );
                }
            }
        }
    }

    #[test]
    fn side_roots_match_f64() {
        let mut unit = crate::test_rng::unit_f64(0x1234_5678);
        let mut rnd = || unit() * 2.0 - 1.0;
        let q = |x: f64| I16F16::from_num(x);
        let mut checked = 0;
        for i in 0..20000 {
            let cone = i % 2 == 0;
            let o = [rnd() * 1.5, rnd() * 1.5, rnd() * 1.5];
            // Aim at a point near the apex (or the axis) so near-tangent rays are common.
            let target = [rnd() * 0.05, 1.0 - rnd().abs() * 0.1, rnd() * 0.05];
            let mut d = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
            let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            d = d.map(|x| x / n);
            let (oq, dq) = (o.map(q), d.map(q));
            let (of, df) = (oq.map(|x| x.to_num::<f64>()), dq.map(|x| x.to_num::<f64>()));
            let k = if cone { 0.25 } else { 0.0 };
            let w0 = 1.0 - of[1];
            let a = df[0] * df[0] + df[2] * df[2] - k * df[1] * df[1];
            let b = of[0] * df[0] + of[2] * df[2] + k * w0 * df[1];
            let c = of[0] * of[0] + of[2] * of[2] - if cone { k * w0 * w0 } else { 1.0 };
            let disc = b * b - a * c;
            let got = side_roots(oq, dq, cone, &mut false);
            if a.abs() < 1e-3 || disc.abs() < 1e-9 {
                continue;
            }
            checked += 1;
            if disc < 0.0 {
                assert!(got.is_none(), "{o:?} {d:?}");
                continue;
            }
            let h = disc.sqrt();
            let (mut r1, mut r2) = ((-b - h) / a, (-b + h) / a);
            if r1 > r2 {
                core::mem::swap(&mut r1, &mut r2);
            }
            let (g1, g2) = got.expect("roots");
            for (g, r) in [(g1, r1), (g2, r2)] {
                if r.abs() > 30000.0 {
                    continue;
                }
                // One Q16.16 rounding of the result, and slack for the root's own.
                assert!(
                    (g.to_num::<f64>() - r).abs() <= 2f64.powi(-15),
                    "{o:?} {d:?}: {g} vs {r}"
                );
            }
        }
        assert!(checked > 10000);
    }
}
