//! Exact 64-bit products and square roots, fast on a Cortex-M0.
//!
//! The Cortex-M0 (thumbv6m) has one multiply, `MULS`, 32 × 32 bits into the
//! low 32. LLVM turns every i64 product there into a call to `__aeabi_lmul`, a
//! general 64 × 64 multiply of about 50 instructions, even when both factors
//! fit 32 bits, as they do in Q16.16. Four 16 × 16-bit products and a few adds
//! form the 32 × 32 → 64 product inline in about 20. Every function here is
//! exact, so results are the same bit for bit on every target; elsewhere the
//! plain 64-bit product is used (one instruction on an x86-64 or a Cortex-M4).

/// `a · b` for u32 factors, from four 16 × 16-bit products (exact).
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
pub(crate) fn mul_u32_halves(a: u32, b: u32) -> u64 {
    let (a0, a1) = (a & 0xFFFF, a >> 16);
    let (b0, b1) = (b & 0xFFFF, b >> 16);
    // Each partial product fits 32 bits; their middle sum needs 33.
    let mid = (a0 * b1) as u64 + (a1 * b0) as u64;
    (((a1 * b1) as u64) << 32) + (mid << 16) + (a0 * b0) as u64
}

/// `a · b` for i32 factors, from 16-bit halves (exact).
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
pub(crate) fn mul_i32_halves(a: i32, b: i32) -> i64 {
    // High halves signed, low halves unsigned: a = a1·2^16 + a0.
    let (a0, a1) = ((a & 0xFFFF) as u32, a >> 16);
    let (b0, b1) = ((b & 0xFFFF) as u32, b >> 16);
    // |a0·b1| < 2^31 and a1·b1 <= 2^30: each fits an i32.
    let mid = (a0 as i32 * b1) as i64 + (a1 * b0 as i32) as i64;
    (((a1 * b1) as i64) << 32) + (mid << 16) + (a0 * b0) as i64
}

/// `a · b` exactly, as i64.
#[inline(always)]
pub(crate) fn mul_i32(a: i32, b: i32) -> i64 {
    #[cfg(lensray_v6m)]
    {
        mul_i32_halves(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        a as i64 * b as i64
    }
}

/// `a · b` exactly, as u64.
#[inline(always)]
pub(crate) fn mul_u32(a: u32, b: u32) -> u64 {
    #[cfg(lensray_v6m)]
    {
        mul_u32_halves(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        a as u64 * b as u64
    }
}

/// `a · b` for i64 factors whose product fits an i64 (the caller's promise,
/// as for `*`): through [`mul_u32_halves`] when both magnitudes fit 32 bits.
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
pub(crate) fn mul_i64_halves(a: i64, b: i64) -> i64 {
    let (ua, ub) = (a.unsigned_abs(), b.unsigned_abs());
    if (ua | ub) >> 32 == 0 {
        let p = mul_u32_halves(ua as u32, ub as u32) as i64;
        return if (a ^ b) < 0 { -p } else { p };
    }
    a.wrapping_mul(b)
}

/// `a · b` for u64 factors whose product fits a u64, as [`mul_i64_halves`];
/// with one factor of 32 bits, two products.
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
pub(crate) fn mul_u64_halves(a: u64, b: u64) -> u64 {
    let (a, b) = if a >> 32 == 0 { (b, a) } else { (a, b) };
    if b >> 32 == 0 {
        // a · b = (a_hi · b) · 2^32 + a_lo · b; the promise keeps a_hi · b < 2^32.
        return mul_u32_halves(a as u32, b as u32).wrapping_add(mul_u32_halves((a >> 32) as u32, b as u32) << 32);
    }
    a.wrapping_mul(b)
}

/// `a · b` for i64 factors whose product fits an i64.
#[inline(always)]
pub(crate) fn mul_i64(a: i64, b: i64) -> i64 {
    #[cfg(lensray_v6m)]
    {
        mul_i64_halves(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        a * b
    }
}

/// `a · b` for u64 factors whose product fits a u64.
#[inline(always)]
pub(crate) fn mul_u64(a: u64, b: u64) -> u64 {
    #[cfg(lensray_v6m)]
    {
        mul_u64_halves(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        a * b
    }
}

/// Integer square root of a u32 (floor), one result bit per step.
#[inline]
fn isqrt_u32(n: u32) -> u32 {
    let mut rem = n;
    let mut root = 0u32;
    let mut bit = if n == 0 {
        0
    } else {
        1u32 << ((31 - n.leading_zeros()) & !1)
    };
    while bit != 0 {
        if rem >= root + bit {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// Integer square root of a u64 (floor), exact.
///
/// The top bits go through the 32-bit method (32-bit operations only); the
/// rest, one bit a step, by squaring the candidate with [`mul_u32`]: far
/// fewer 64-bit operations than the 64-bit digit-by-digit method.
pub(crate) fn isqrt_u64(n: u64) -> u64 {
    if n >> 32 == 0 {
        return isqrt_u32(n as u32) as u64;
    }
    // An even shift s that leaves n >> s below 2^32: isqrt(n) then lies in
    // [r·2^h, (r + 1)·2^h) for r = isqrt(n >> s), h = s / 2.
    let bits = 64 - n.leading_zeros();
    let s = (bits - 31) & !1;
    let h = s / 2;
    let mut root = (isqrt_u32((n >> s) as u32) as u64) << h;
    let mut j = h;
    while j > 0 {
        j -= 1;
        let cand = root | (1 << j);
        // cand < 2^32: its square is exact in a u64.
        if mul_u32(cand as u32, cand as u32) <= n {
            root = cand;
        }
    }
    root
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift64*), for wide coverage.
    fn rng(seed: u64) -> impl FnMut() -> u64 {
        let mut s = seed;
        move || {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            s.wrapping_mul(0x2545_F491_4F6C_DD1D)
        }
    }

    #[test]
    fn halves_multiply_exactly() {
        let edges = [
            0u32,
            1,
            2,
            0xFFFF,
            0x1_0000,
            0x7FFF_FFFF,
            0x8000_0000,
            0xFFFF_FFFF,
            12345,
        ];
        for &a in &edges {
            for &b in &edges {
                assert_eq!(mul_u32_halves(a, b), a as u64 * b as u64, "{a} * {b}");
                let (x, y) = (a as i32, b as i32);
                assert_eq!(mul_i32_halves(x, y), x as i64 * y as i64, "{x} * {y}");
            }
        }
        let mut r = rng(7);
        for _ in 0..200_000 {
            let (a, b) = (r() as u32, r() as u32);
            assert_eq!(mul_u32_halves(a, b), a as u64 * b as u64);
            assert_eq!(mul_i32_halves(a as i32, b as i32), a as i32 as i64 * b as i32 as i64);
            // The i64 and u64 forms, with small and large factors.
            // Products that fit 63 bits, with one factor beyond 32 bits or not.
            let (x, y) = ((r() as i64) >> (20 + r() % 40), (r() as i64) >> 44);
            assert_eq!(mul_i64_halves(x, y), x * y);
            assert_eq!(mul_i64_halves(y, x), x * y);
            let (x, y) = (r() >> (21 + r() % 40), r() >> 45);
            assert_eq!(mul_u64_halves(x, y), x * y);
            assert_eq!(mul_u64_halves(y, x), x * y);
            let (x, y) = (r() >> 31, r() >> 34);
            assert_eq!(mul_u64_halves(x, y), x * y);
        }
    }

    /// The 64-bit digit-by-digit square root the fast one replaces.
    /// An independent oracle: a float estimate corrected with exact u128 squares.
    fn isqrt_reference(n: u64) -> u64 {
        let mut r = (n as f64).sqrt() as u64;
        while (r as u128) * (r as u128) > n as u128 {
            r -= 1;
        }
        while ((r + 1) as u128) * ((r + 1) as u128) <= n as u128 {
            r += 1;
        }
        r
    }

    #[test]
    fn square_root_is_exact() {
        for n in 0..100_000u64 {
            assert_eq!(isqrt_u64(n), isqrt_reference(n), "{n}");
        }
        // Around every square and at every width.
        let mut r = rng(11);
        for _ in 0..200_000 {
            let x = r() >> (r() % 64);
            assert_eq!(isqrt_u64(x), isqrt_reference(x), "{x}");
            let root = (r() >> 32).max(1);
            for n in [root * root - 1, root * root, root * root + 1] {
                assert_eq!(isqrt_u64(n), isqrt_reference(n), "{n}");
            }
        }
        assert_eq!(isqrt_u64(u64::MAX), 0xFFFF_FFFF);
        assert_eq!(isqrt_u64(1 << 32), 1 << 16);
    }
}
