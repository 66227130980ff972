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

/// `a · b` exactly, as i64: on the M0 a call to the Thumb-1 routine (in
/// place at its some fifty sites it took 2 KB of its flash); the per-ray
/// kernels that exist once (square root, division, normalisation) keep
/// [`mul_i32_inline`] in place.
#[inline(always)]
pub(crate) fn mul_i32(a: i32, b: i32) -> i64 {
    #[cfg(lensray_v6m)]
    {
        super::thumb1::mul_i32(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        a as i64 * b as i64
    }
}

/// `a · b` exactly, as i64, in place.
#[inline(always)]
pub(crate) fn mul_i32_inline(a: i32, b: i32) -> i64 {
    #[cfg(lensray_v6m)]
    {
        mul_i32_halves(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        a as i64 * b as i64
    }
}

/// `a · k` exactly, as i64, for `|k| <= 2^15` (a pixel index, a lens
/// sample in Q1.15): two 32-bit products on the M0 instead of four.
#[inline(always)]
pub(crate) fn mul_i32_short(a: i32, k: i32) -> i64 {
    #[cfg(lensray_v6m)]
    {
        // |a >> 16| <= 2^15 and |a & 0xFFFF| < 2^16: each product fits an i32.
        let hi = (a >> 16) * k;
        let lo = (a & 0xFFFF) * k;
        ((hi as i64) << 16) + lo as i64
    }
    #[cfg(not(lensray_v6m))]
    {
        a as i64 * k as i64
    }
}

/// `a · b` exactly, as u64: one out-of-line copy on the M0, as [`mul_i32`].
#[cfg_attr(lensray_v6m, inline(never))]
#[cfg_attr(not(lensray_v6m), inline(always))]
pub(crate) fn mul_u32(a: u32, b: u32) -> u64 {
    mul_u32_inline(a, b)
}

/// `a · b` exactly, as u64, in place.
#[inline(always)]
pub(crate) fn mul_u32_inline(a: u32, b: u32) -> u64 {
    #[cfg(lensray_v6m)]
    {
        mul_u32_halves(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        a as u64 * b as u64
    }
}

/// `a · b` for u64 factors whose product fits a u64 (the caller's promise,
/// as for `*`): with one factor of 32 bits, two products from halves.
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

/// `a · b` for i64 factors whose product fits an i64: on the M0 a call to
/// the Thumb-1 routine.
#[inline(always)]
pub(crate) fn mul_i64(a: i64, b: i64) -> i64 {
    #[cfg(lensray_v6m)]
    {
        super::thumb1::mul_i64(a, b)
    }
    #[cfg(not(lensray_v6m))]
    {
        a * b
    }
}

/// `a · b` for u64 factors whose product fits a u64.
// One copy on the M0: in place at its dozen sites it took 470 bytes of its flash.
#[cfg_attr(lensray_v6m, inline(never))]
#[cfg_attr(not(lensray_v6m), inline(always))]
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

/// Bits needed for a u64 (0 for 0): `64 - leading_zeros`, without a library
/// call on the Cortex-M0.
#[inline(always)]
pub(crate) fn bits_u64(x: u64) -> u32 {
    let hi = (x >> 32) as u32;
    if hi != 0 {
        64 - clz32(hi)
    } else {
        32 - clz32(x as u32)
    }
}

/// `x >> s` (arithmetic) for `s < 64` from 32-bit shifts, inline: on a
/// Cortex-M0 a variable 64-bit shift is a call to `__aeabi_lasr`.
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
pub(crate) fn sar64_words(x: i64, s: u32) -> i64 {
    let (lo, hi) = (x as u32, (x >> 32) as i32);
    if s >= 32 {
        (hi >> (s - 32)) as i64
    } else if s == 0 {
        x
    } else {
        let lo = (lo >> s) | ((hi as u32) << (32 - s));
        (((hi >> s) as i64) << 32) | lo as i64
    }
}

/// `x >> s` (arithmetic) for `s < 64`.
#[inline(always)]
pub(crate) fn sar64(x: i64, s: u32) -> i64 {
    #[cfg(lensray_v6m)]
    {
        sar64_words(x, s)
    }
    #[cfg(not(lensray_v6m))]
    {
        x >> s
    }
}

/// Leading zeros of a u32: on the M0 (no `CLZ`) a call to the Thumb-1
/// routine, where `leading_zeros` calls `__clzsi2`, some 30 instructions.
#[inline(always)]
fn clz32(x: u32) -> u32 {
    #[cfg(lensray_v6m)]
    {
        super::thumb1::clz32(x)
    }
    #[cfg(not(lensray_v6m))]
    {
        x.leading_zeros()
    }
}

/// Rounded `1 / sqrt(x)` in Q1.15 at the middle of each interval
/// `[i, i + 1) / 512` of x in [1/4, 1), i in 128..512: `round(sqrt(2^40 / (2i + 1)))`,
/// at most 65408, at index `i - 128` ([`rsqrt_start`]).
static RSQRT_T: [u16; 384] = {
    let mut t = [0u16; 384];
    let mut i = 128;
    while i < 512 {
        let q = (1u64 << 42) / (2 * i as u64 + 1);
        // round(sqrt(q / 4)) from the floor of sqrt(q).
        t[i - 128] = q.isqrt().div_ceil(2) as u16;
        i += 1;
    }
    t
};

/// [`RSQRT_T`]'s entry for the top word `w` of a value normalised to
/// [2^30, 2^32) (or [2^62, 2^64)): `w >> 23` is in 128..512; held there, so
/// that no bounds check (and no panic path) is needed.
#[inline(always)]
fn rsqrt_start(w: u32) -> u32 {
    RSQRT_T[((w >> 23).saturating_sub(128) as usize).min(383)] as u32
}

/// Rounded `2^47 / d` at the middle of each of the 256 intervals
/// `[256 + j, 257 + j) · 2^23` of a normalised divisor d: `round(2^24 / (256.5 + j))`.
static RECIP_T: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut j = 0;
    while j < 256 {
        let m = 513 + 2 * j as u32;
        t[j] = (((1u32 << 25) + m / 2) / m) as u16;
        j += 1;
    }
    t
};

/// `floor(sqrt(n))` and `n - floor(sqrt(n))^2` from an estimate `r` of the root
/// within a few units (any `r` is exact, only slower).
#[inline(always)]
fn isqrt_fix_u32(n: u32, r: u32) -> (u32, u32) {
    // The root of a u32 is below 2^16, so r · r never wraps.
    let mut r = r.min(0xFFFF);
    let mut sq = r * r;
    while sq > n {
        r -= 1;
        sq -= 2 * r + 1;
    }
    let mut rem = n - sq;
    while rem > 2 * r {
        rem -= 2 * r + 1;
        r += 1;
    }
    (r, rem)
}

/// `floor(sqrt(n))` and the remainder for u64, from an estimate within a few units.
#[inline(always)]
fn isqrt_fix_u64(n: u64, r: u64) -> (u64, u64) {
    let mut r = r.min(0xFFFF_FFFF);
    let mut sq = mul_u32_inline(r as u32, r as u32);
    while sq > n {
        r -= 1;
        sq -= 2 * r + 1;
    }
    let mut rem = n - sq;
    while rem > 2 * r {
        rem -= 2 * r + 1;
        r += 1;
    }
    (r, rem)
}

/// An estimate of `floor(sqrt(n))` for `n > 0`, within 2 units.
///
/// Table start for `1/sqrt` of n scaled to [2^30, 2^32) and one Newton step
/// for the root, with 32-bit products only.
#[inline(always)]
fn isqrt_estimate_u32(n: u32) -> u32 {
    let k = clz32(n) / 2;
    let nn = n << (2 * k);
    // y0 ≈ 2^15 / sqrt(nn / 2^32), relative error below 2^-9.
    let y0 = rsqrt_start(nn);
    // s0 ≈ sqrt(nn), within 2^-8.9; (nn >> 16) · y0 < 2^32.
    let s0 = ((nn >> 16) * y0) >> 15;
    // |nn - s0^2| < 2^24.1 even when s0^2 wraps a u32.
    let res = nn.wrapping_sub(s0.wrapping_mul(s0)) as i32;
    // Newton: s1 = s0 + res / (2 s0) ≈ s0 + res · y0 / 2^32, |(res >> 10) · y0| < 2^30.1.
    let s1 = s0 as i32 + (((res >> 10) * y0 as i32) >> 22);
    (s1.max(0) as u32) >> k
}

/// `(floor(sqrt(n)), n - floor(sqrt(n))^2)` for a u32, exact for every n:
/// [`isqrt_estimate_u32`] corrected by squares.
#[inline]
fn isqrt_rem_u32(n: u32) -> (u32, u32) {
    if n == 0 {
        return (0, 0);
    }
    isqrt_fix_u32(n, isqrt_estimate_u32(n))
}

/// An estimate of `floor(sqrt(n))` for `n >= 2^32`, within 2 units.
///
/// n scaled to [2^62, 2^64): a table start for `1/sqrt`, one Newton step for
/// it, the root `n · (1/sqrt n)` and one Newton step for the root: four
/// 32 × 32 → 64-bit products (from halves on a Cortex-M0), 32-bit shifts only.
#[inline(always)]
fn isqrt_estimate_u64(n: u64) -> u32 {
    let (hi, lo) = ((n >> 32) as u32, n as u32);
    debug_assert!(hi != 0);
    let k = clz32(hi) / 2;
    // nn = n << 2k in 32-bit words (a variable u64 shift is a library call on the M0).
    let (nh, nl) = if k == 0 {
        (hi, lo)
    } else {
        ((hi << (2 * k)) | (lo >> (32 - 2 * k)), lo << (2 * k))
    };
    let nn = ((nh as u64) << 32) | nl as u64;
    // y0 ≈ 2^15 / sqrt(x), x = nn / 2^64 in [1/4, 1); relative error below 2^-9.
    let y0 = rsqrt_start(nh);
    // Newton for 1/sqrt: y1 = y0 (3 - x y0^2) / 2, in Q1.31; t = x y0^2 in Q2.30.
    let t = (mul_u32_inline(nh, y0 * y0) >> 32) as u32;
    let h = 3 * (1u32 << 30) - t;
    // y0 · h / 2^15 exactly, from two 16 × 16-bit products; below 2^32 (y1 < 2).
    let y1 = ((y0 * (h >> 16)) << 1) + ((y0 * (h & 0xFFFF)) >> 15);
    // s1 = x · y1 · 2^32 ≈ sqrt(nn), relative error about 2^-17.4, below 2^32.
    let s1 = (mul_u32_inline(nh, y1) >> 31) as u32;
    // Newton for the root with 1/sqrt(nn) = y1 / 2^63: s2 = s1 + res · y1 / 2^64.
    let res = nn.wrapping_sub(mul_u32_inline(s1, s1)) as i64;
    // |res| < 2^47.6, so |res| >> 16 fits a u32.
    let c = (mul_u32_inline((res.unsigned_abs() >> 16) as u32, y1) >> 48) as u32;
    let s2 = if res < 0 { s1 - c } else { s1.saturating_add(c) };
    s2 >> k
}

/// `(floor(sqrt(n)), n - floor(sqrt(n))^2)` for a u64, exact for every n.
///
/// Table start and Newton steps by products only (see
/// [`isqrt_estimate_u64`]), then an exact correction by squares: some 150
/// instructions on a Cortex-M0 where the bit-by-bit method took 500 or more.
/// The other targets' square root, and the reference the M0's Thumb-1
/// routine is checked against.
#[cfg_attr(lensray_v6m, allow(dead_code))]
#[inline]
pub(crate) fn isqrt_rem_u64(n: u64) -> (u64, u64) {
    if n >> 32 == 0 {
        let (r, rem) = isqrt_rem_u32(n as u32);
        return (r as u64, rem as u64);
    }
    isqrt_fix_u64(n, isqrt_estimate_u64(n) as u64)
}

/// `floor(sqrt(n))`, exact for every n: on the M0 the Thumb-1 routine.
#[inline(always)]
pub(crate) fn isqrt_floor_u64(n: u64) -> u64 {
    #[cfg(lensray_v6m)]
    {
        super::thumb1::isqrt(n, &RSQRT_T) as u32 as u64
    }
    #[cfg(not(lensray_v6m))]
    {
        isqrt_rem_u64(n).0
    }
}

/// `sqrt(n)` rounded to nearest (no ties are possible), exact for every n.
#[inline(always)]
pub(crate) fn isqrt_round_u64(n: u64) -> u64 {
    #[cfg(lensray_v6m)]
    {
        // The root in the low word, 1 in the high word where it rounds up.
        let r = super::thumb1::isqrt(n, &RSQRT_T);
        (r & 0xFFFF_FFFF) + (r >> 32)
    }
    #[cfg(not(lensray_v6m))]
    {
        let (r, rem) = isqrt_rem_u64(n);
        // sqrt(n) > r + 1/2 exactly when n > r^2 + r.
        if rem > r {
            r + 1
        } else {
            r
        }
    }
}

/// An estimate of [`recip_word`]`(d)` from below, by at most 3, for `d >= 2^31`.
///
/// A table start (9 bits), a Newton step in 32-bit products and a
/// full-width Newton step. Every rounding is downwards (Newton's step for a
/// reciprocal never overshoots), so the estimate never exceeds the reciprocal.
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
fn recip_word_estimate(d: u32) -> u32 {
    debug_assert!(d >> 31 == 1);
    // x0 ≈ 2^47 / d, relative error below 2^-9; d >> 23 is in 256..512.
    let x0 = RECIP_T[((d >> 23) & 0xFF) as usize] as u32;
    // e = (2^47 - d · x0) / 2^24, |e| < 2^14.1, from two 16 × 16-bit products;
    // the floors make it at most 2 too large.
    let p = (((d >> 16) * x0) >> 8) + (((d & 0xFFFF) * x0) >> 24);
    let e = (1i32 << 23) - p as i32;
    // Newton: 2^64 / d ≈ x0 · 2^17 + x0 · e / 2^6, |e · x0| < 2^30.1; less 2^12
    // (more than e's 2 · x0 / 2^6) to stay below the reciprocal.
    let v1 = ((x0 as i64) << 17) + ((e * x0 as i32) >> 6) as i64 - (1i64 << 32) - (1 << 12);
    let v1 = v1.max(0) as u32;
    // e2 = 2^64 - d (2^32 + v1) in (0, 2^47); Newton: v += e2 / 2^32 + v1 · e2 / 2^64.
    let e2 = ((d as u64) << 32).wrapping_neg() - mul_u32_inline(d, v1);
    let m = (e2 >> 32) as u32;
    // v1 · m / 2^32 from two 16 × 16-bit products (m < 2^15).
    let t = ((v1 >> 16) * m + (((v1 & 0xFFFF) * m) >> 16)) >> 16;
    v1 + m + t
}

/// `floor((2^64 - 1) / d) - 2^32` for a normalised divisor `d >= 2^31`,
/// exactly: the reciprocal of the 2-by-1 word division of Möller and
/// Granlund (2011), from [`recip_word_estimate`] corrected by the remainder.
// On the M0 one copy in Thumb-1, shared by the divisions and the powers of
// two' reciprocals.
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
fn recip_word(d: u32) -> u32 {
    #[cfg(lensray_v6m)]
    {
        super::thumb1::recip_word(d, &RECIP_T)
    }
    #[cfg(not(lensray_v6m))]
    {
        recip_word_portable(d)
    }
}

/// [`recip_word`] in Rust: the other targets' (inline), and the reference
/// the M0's Thumb-1 routine is checked against.
#[inline(always)]
fn recip_word_portable(d: u32) -> u32 {
    let mut v = recip_word_estimate(d);
    // e = 2^64 - 1 - d (2^32 + v) >= 0 must drop below d.
    let mut e = !((d as u64) << 32) - mul_u32_inline(d, v);
    while e >= d as u64 {
        v += 1;
        e -= d as u64;
    }
    v
}

/// `(u1 · 2^32 + u0) / d` and its remainder, for `d >= 2^31`, `u1 < d` and
/// `v = recip_word(d)`: one 32 × 32 → 64-bit product and at most two
/// corrections (Möller and Granlund 2011, algorithm 4).
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
fn div_2by1(u1: u32, u0: u32, d: u32, v: u32) -> (u32, u32) {
    let q = mul_u32_inline(v, u1).wrapping_add(((u1 as u64) << 32) | u0 as u64);
    let mut q1 = ((q >> 32) as u32).wrapping_add(1);
    let q0 = q as u32;
    let mut r = u0.wrapping_sub(q1.wrapping_mul(d));
    // q1 is one too large at most, or (rarely) one too small.
    if r > q0 {
        q1 = q1.wrapping_sub(1);
        r = r.wrapping_add(d);
    }
    if r >= d {
        q1 += 1;
        r -= d;
    }
    (q1, r)
}

/// Exact division by a u32 through a precomputed reciprocal (multiplies
/// only; the Cortex-M0 path of [`Recip`]). Several divisions by the same
/// divisor pay for the reciprocal (some 100 instructions) once; each then
/// costs one or two 32 × 32 → 64-bit products.
#[derive(Copy, Clone, Debug)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
pub(crate) struct RecipMul {
    /// The divisor (read by `div_round_i64_by`, which the M0 leaves to `div_rem_u64`).
    #[cfg_attr(lensray_v6m, allow(dead_code))]
    d: u32,
    /// `d << s`, at least 2^31.
    dn: u32,
    /// `recip_word(dn)`.
    v: u32,
    /// Leading zeros of d.
    s: u32,
}

#[cfg_attr(not(lensray_v6m), allow(dead_code))]
impl RecipMul {
    /// The reciprocal of `d`, for `d > 0`.
    // Forced on the M0: at opt-level "s" the call cost 79 instructions a pixel, inlined 84 bytes.
    #[cfg_attr(lensray_v6m, inline(always))]
    #[cfg_attr(not(lensray_v6m), inline)]
    pub(crate) fn new(d: u32) -> RecipMul {
        debug_assert!(d != 0, "division by zero");
        let s = clz32(d);
        let dn = d << s;
        RecipMul {
            d,
            dn,
            v: recip_word(dn),
            s,
        }
    }

    /// The divisor.
    #[inline(always)]
    #[cfg_attr(lensray_v6m, allow(dead_code))]
    pub(crate) fn divisor(&self) -> u32 {
        self.d
    }

    /// `(n / d, n % d)` exactly, for every n (quotients of 32 bits or less
    /// take one word step, larger ones two).
    #[inline(always)]
    pub(crate) fn div_rem(&self, n: u64) -> (u64, u32) {
        let (dn, v, s) = (self.dn, self.v, self.s);
        let (hi, lo) = ((n >> 32) as u32, n as u32);
        // n << s as three words n2:n1:n0; n2 < 2^s <= dn.
        let (n2, n1, n0) = if s == 0 {
            (0, hi, lo)
        } else {
            (hi >> (32 - s), (hi << s) | (lo >> (32 - s)), lo << s)
        };
        let (q1, r) = if n2 == 0 && n1 < dn {
            (0, n1)
        } else {
            div_2by1(n2, n1, dn, v)
        };
        let (q0, r) = div_2by1(r, n0, dn, v);
        (((q1 as u64) << 32) | q0 as u64, r >> s)
    }
}

/// Division by a u32 with the hardware's or the runtime's `/` (targets with
/// a divide instruction or fast 64-bit products); the API of [`RecipMul`].
#[derive(Copy, Clone, Debug)]
#[cfg_attr(any(lensray_v6m, lensray_hwdiv), allow(dead_code))]
pub(crate) struct RecipDiv {
    d: u32,
}

#[cfg_attr(any(lensray_v6m, lensray_hwdiv), allow(dead_code))]
impl RecipDiv {
    /// The divisor `d`, for `d > 0`.
    #[inline(always)]
    pub(crate) fn new(d: u32) -> RecipDiv {
        RecipDiv { d }
    }

    /// The divisor.
    #[inline(always)]
    pub(crate) fn divisor(&self) -> u32 {
        self.d
    }

    /// `(n / d, n % d)` exactly.
    #[inline(always)]
    pub(crate) fn div_rem(&self, n: u64) -> (u64, u32) {
        let d = self.d as u64;
        (n / d, (n % d) as u32)
    }
}

/// Division by a u32 on 32-bit cores with a 32 / 32 divide instruction but
/// no 64-bit one (Cortex-M3/M4 `UDIV`, RV32IM `divu`): the runtime's
/// `u64 / u64` routine costs some 200 instructions there, while this takes
/// one hardware divide for a dividend of one word and three otherwise: the
/// top word's, then base-2^16 long division of the rest by the normalised
/// divisor (Knuth's algorithm D).
#[derive(Copy, Clone, Debug)]
#[cfg_attr(not(lensray_hwdiv), allow(dead_code))]
pub(crate) struct RecipHw {
    d: u32,
}

#[cfg_attr(not(lensray_hwdiv), allow(dead_code))]
impl RecipHw {
    /// The divisor `d`, for `d > 0`.
    #[inline(always)]
    pub(crate) fn new(d: u32) -> RecipHw {
        RecipHw { d }
    }

    /// The divisor.
    #[inline(always)]
    pub(crate) fn divisor(&self) -> u32 {
        self.d
    }

    /// `(n / d, n % d)` exactly.
    #[inline(always)]
    pub(crate) fn div_rem(&self, n: u64) -> (u64, u32) {
        let d = self.d;
        let (hi, lo) = ((n >> 32) as u32, n as u32);
        if hi == 0 {
            return ((lo / d) as u64, lo % d);
        }
        let (q1, r) = (hi / d, hi % d);
        let (q0, r) = div_2by1_digits(r, lo, d);
        (((q1 as u64) << 32) | q0 as u64, r)
    }
}

/// `(u1 · 2^32 + u0) / d` and its remainder for `0 < d` and `u1 < d` (the
/// quotient fits a word), by two base-2^16 digits of the divisor shifted
/// until its top bit is set, each digit from one word divide by the
/// divisor's top half and corrected at most twice (Knuth's algorithm D).
#[inline(always)]
#[cfg_attr(not(lensray_hwdiv), allow(dead_code))]
fn div_2by1_digits(u1: u32, u0: u32, d: u32) -> (u32, u32) {
    let s = d.leading_zeros();
    let dn = d << s;
    let (dh, dl) = (dn >> 16, dn & 0xFFFF);
    // u1:u0 << s as u32 (top, below d << s) and two 16-bit digits.
    let top = if s == 0 { u1 } else { (u1 << s) | (u0 >> (32 - s)) };
    let low = u0 << s;
    // One digit of (rest · 2^16 + next) / dn, rest < dn: at most 2^16 - 1.
    let digit = |rest: u32, next: u32| {
        let (mut q, mut r) = (rest / dh, rest % dh);
        // q overshoots by at most 2; once r reaches 2^16 the test below cannot hold.
        while q >> 16 != 0 || q * dl > (r << 16 | next) {
            q -= 1;
            r += dh;
            if r >> 16 != 0 {
                break;
            }
        }
        // rest · 2^16 + next - q · dn lies in [0, dn): exact in wrapping words.
        (q, (rest << 16 | next).wrapping_sub(q.wrapping_mul(dn)))
    };
    let (q1, rest) = digit(top, low >> 16);
    let (q0, rest) = digit(rest, low & 0xFFFF);
    (q1 << 16 | q0, rest >> s)
}

/// A divisor prepared for exact division: [`RecipMul`] on a Cortex-M0,
/// where a `u64 / u64` costs some 350 instructions; [`RecipHw`] on 32-bit
/// cores with a word divide; plain `/` elsewhere.
#[cfg(lensray_v6m)]
pub(crate) type Recip = RecipMul;
/// See the Cortex-M0's [`Recip`].
#[cfg(all(lensray_hwdiv, not(lensray_v6m)))]
pub(crate) type Recip = RecipHw;
/// See the Cortex-M0's [`Recip`].
#[cfg(not(any(lensray_v6m, lensray_hwdiv)))]
pub(crate) type Recip = RecipDiv;

/// `(n / d, n % d)` exactly, for `d > 0`.
// One copy on the M0 (its four copies in place took 750 bytes of its flash,
// for some 95 instructions a pixel).
#[cfg_attr(lensray_v6m, inline(never))]
#[cfg_attr(not(lensray_v6m), inline)]
pub(crate) fn div_rem_u64_u32(n: u64, d: u32) -> (u64, u32) {
    Recip::new(d).div_rem(n)
}

/// `floor(2^k / l)` for `l > 0` from the word reciprocal alone, where
/// `2^k / l` is `2^64 / (l << s)` shifted right (`s` the leading zeros of l);
/// `None` for other `k`.
#[inline(always)]
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
fn div_pow2_by_recip(k: u32, l: u32) -> Option<u64> {
    let s = clz32(l);
    if s + k <= 32 || s + k > 64 {
        return None;
    }
    let dn = l << s;
    // floor(2^64 / dn) = 2^32 + recip_word(dn), but 2^33 for dn = 2^31.
    let (hi, lo) = if dn == 1 << 31 {
        (2u32, 0u32)
    } else {
        (1, recip_word(dn))
    };
    // floor(floor(x) / 2^sh) = floor(x / 2^sh), with sh < 32.
    let sh = 64 - k - s;
    if sh == 0 {
        return Some(((hi as u64) << 32) | lo as u64);
    }
    Some((((hi >> sh) as u64) << 32) | ((lo >> sh) | (hi << (32 - sh))) as u64)
}

/// `floor(2^k / l)` for `l > 0`, `k < 64`: on the M0 without the division's
/// multiply-and-correct steps where [`div_pow2_by_recip`] applies.
#[cfg_attr(lensray_v6m, inline(never))]
#[cfg_attr(not(lensray_v6m), inline)]
pub(crate) fn div_pow2_u32(k: u32, l: u32) -> u64 {
    #[cfg(lensray_v6m)]
    if let Some(q) = div_pow2_by_recip(k, l) {
        return q;
    }
    div_rem_u64_u32(1 << k, l).0
}

/// `(n / d, n % d)` exactly, for `d > 0`: through [`Recip`] when d fits 32 bits.
#[inline]
pub(crate) fn div_rem_u64(n: u64, d: u64) -> (u64, u64) {
    if d >> 32 == 0 {
        let (q, r) = div_rem_u64_u32(n, d as u32);
        (q, r as u64)
    } else {
        #[cfg(lensray_v6m)]
        {
            div_rem_u64_big(n, d)
        }
        #[cfg(not(lensray_v6m))]
        {
            (n / d, n % d)
        }
    }
}

/// `(n / d, n % d)` exactly for `d >= 2^32` (the quotient fits 32 bits),
/// from one `u64 / u32` division by d's top word (Warren, Hacker's Delight,
/// `divlu`): on the Cortex-M0 it keeps the runtime's 1 KB `u64 / u64` out.
#[cfg_attr(not(lensray_v6m), allow(dead_code))]
#[inline(never)]
pub(crate) fn div_rem_u64_big(n: u64, d: u64) -> (u64, u64) {
    debug_assert!(d >> 32 != 0);
    let s = clz32((d >> 32) as u32);
    // d's top 32 bits once normalised (at least 2^31), and n halved so that
    // the quotient fits 32 bits.
    let d1 = ((d << s) >> 32) as u32;
    // Through `div_rem_u64`'s own copy of the reciprocal division (one copy, not two).
    let q1 = div_rem_u64(n >> 1, d1 as u64).0;
    // q or q + 1 (Warren): one less, then at most one correction.
    let q = ((q1 << s) >> 31).saturating_sub(1);
    let r = n - mul_u64(q, d);
    if r >= d {
        (q + 1, r - d)
    } else {
        (q, r)
    }
}

/// Runs each of the M0's Thumb-1 kernels (`thumb1`) against the portable
/// Rust on the edge values and on `n` pseudo-random pairs of every
/// magnitude: the first pair that differs, as the kernel's name and its
/// operands. For the board (tests/firmware.rs runs it under QEMU); the host
/// has no Thumb-1 to run.
#[cfg(lensray_v6m)]
pub(crate) fn check_thumb1(n: u32) -> Option<(&'static str, i64, i64)> {
    const EDGES: [i32; 14] = [
        0,
        1,
        -1,
        0x7FFF,
        0x8000,
        0xFFFF,
        0x1_0000,
        -0x1_0000,
        0x1_0001,
        -0xFFFF,
        0x7FFF_FFFF,
        i32::MIN,
        i32::MIN + 1,
        0x4000_0000,
    ];
    let mut state = 0x2545_F491u32;
    let mut next = move || {
        // xorshift32: cheap, full period, no table.
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state
    };
    let edges = EDGES.iter().flat_map(|&a| EDGES.map(|b| (a, b)));
    // Magnitudes from 1 bit to 32, either sign.
    let random = (0..n).map(|_| {
        let (ra, rb, shifts) = (next(), next(), next());
        ((ra as i32) >> (shifts & 31), (rb as i32) >> ((shifts >> 5) & 31))
    });
    edges.chain(random).find_map(|(a, b)| thumb1_differs(a, b))
}

/// The first Thumb-1 kernel that differs from the portable Rust on operands
/// drawn from `a` and `b`, with those operands.
#[cfg(lensray_v6m)]
fn thumb1_differs(a: i32, b: i32) -> Option<(&'static str, i64, i64)> {
    use super::thumb1::{clz32, mul_i32, mul_i64, mul_q16};
    let exact = a as i64 * b as i64;
    if mul_i32(a, b) != exact {
        return Some(("mul_i32", a as i64, b as i64));
    }
    // Factors within an i32, and one beyond it whose product still fits.
    let (a64, b64) = (a as i64 >> (b as u32 & 31), (b as i64) << (a as u32 % 30));
    if mul_i64(a as i64, b as i64) != exact || a64.checked_mul(b64).is_some_and(|p| p != mul_i64(a64, b64)) {
        return Some(("mul_i64", a as i64, b as i64));
    }
    let q16 = ((exact + 0x8000) >> 16).clamp(i32::MIN as i64, i32::MAX as i64) as i32;
    if mul_q16(a, b) != q16 {
        return Some(("mul_q16", a as i64, b as i64));
    }
    if clz32(a as u32) != (a as u32).leading_zeros() {
        return Some(("clz32", a as i64, 0));
    }
    // A normalised divisor from either factor.
    let d = (a as u32 | 1 << 31) ^ (b as u32 & 0x7FFF_FFFF);
    if recip_word(d) != recip_word_portable(d) {
        return Some(("recip_word", d as i64, 0));
    }
    // A radicand of both; every other one a square, one below, or where the rounding turns.
    let n = ((a as u64) << 32 | b as u32 as u64) >> (b as u32 & 63);
    let m = n as u32 as u64;
    let n = if a & 1 == 0 {
        n
    } else {
        (m * m).wrapping_add([u64::MAX, 0, 1, m, m + 1, 2 * m][b.rem_euclid(6) as usize])
    };
    let (r, rem) = isqrt_rem_u64(n);
    if isqrt_floor_u64(n) != r || isqrt_round_u64(n) != r + u64::from(rem > r) {
        return Some(("isqrt", n as i64, 0));
    }
    None
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
    fn big_divisors_divide_exactly() {
        let mut r = rng(15);
        let edges = [
            1u64 << 32,
            (1 << 32) + 1,
            u64::MAX,
            u64::MAX - 1,
            1 << 63,
            (1 << 63) - 1,
            3 << 32,
        ];
        for i in 0..200_000 {
            let d = match i % 4 {
                0 => edges[(r() % edges.len() as u64) as usize],
                _ => (r() >> (r() % 32)) | 1 << 32,
            };
            let n = match i % 3 {
                0 => u64::MAX - r() % 4,
                1 => r() >> (r() % 64),
                _ => r(),
            };
            assert_eq!(div_rem_u64_big(n, d), (n / d, n % d), "{n} / {d}");
            assert_eq!(div_rem_u64(n, d), (n / d, n % d), "{n} / {d}");
        }
    }

    #[test]
    fn shifts_from_words() {
        let mut r = rng(9);
        for _ in 0..100_000 {
            let x = r() as i64;
            for s in 0..64 {
                assert_eq!(sar64_words(x, s), x >> s, "{x} >> {s}");
            }
        }
        assert_eq!(sar64_words(i64::MIN, 63), -1);
        assert_eq!(sar64_words(-1, 5), -1);
    }

    #[test]
    fn bits_of_u64() {
        for x in [0u64, 1, 2, 3, 0xFFFF_FFFF, 1 << 32, (1 << 32) + 1, u64::MAX, 1 << 63] {
            assert_eq!(bits_u64(x), 64 - x.leading_zeros(), "{x:#x}");
        }
        let mut r = rng(5);
        for _ in 0..100_000 {
            let x = r() >> (r() % 64);
            assert_eq!(bits_u64(x), 64 - x.leading_zeros(), "{x:#x}");
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
            // The u64 form: products that fit 64 bits, with one factor beyond 32 bits or not.
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

    /// Every result of `isqrt_rem_u64` against the oracle, with its remainder.
    fn check_sqrt(n: u64) {
        let r = isqrt_reference(n);
        assert_eq!(isqrt_rem_u64(n), (r, n - r * r), "{n}");
        let round = if n - r * r > r { r + 1 } else { r };
        assert_eq!(isqrt_round_u64(n), round, "{n}");
        if n >> 32 == 0 {
            assert_eq!(isqrt_rem_u32(n as u32), (r as u32, (n - r * r) as u32), "{n}");
        }
    }

    #[test]
    fn square_root_is_exact() {
        for n in 0..300_000u64 {
            check_sqrt(n);
        }
        // Around every square and at every width.
        let mut r = rng(11);
        for _ in 0..300_000 {
            let x = r() >> (r() % 64);
            check_sqrt(x);
            let root = (r() >> (32 + r() % 32)).max(1);
            for n in [root * root - 1, root * root, root * root + 1] {
                check_sqrt(n);
            }
        }
        // Around every power of two and every table interval's ends.
        for b in 0..64 {
            let p = 1u64 << b;
            for n in [p - 1, p, p + 1, p.wrapping_mul(3) / 2] {
                check_sqrt(n);
            }
        }
        for i in 128u64..=512 {
            for shift in [0, 7, 23, 30, 33, 55] {
                let edge = i << shift;
                for n in [edge.wrapping_sub(1), edge, edge + 1] {
                    check_sqrt(n);
                }
            }
        }
        let big = 0xFFFF_FFFFu64 * 0xFFFF_FFFF;
        for n in [
            0,
            1,
            2,
            3,
            4,
            u64::MAX,
            u64::MAX - 1,
            1 << 32,
            (1 << 32) - 1,
            big - 1,
            big,
            big + 1,
        ] {
            check_sqrt(n);
        }
        assert_eq!(isqrt_rem_u64(u64::MAX), (0xFFFF_FFFF, 0x1_FFFF_FFFE));
        assert_eq!(isqrt_rem_u64(1 << 32), (1 << 16, 0));
    }

    /// The estimates before the correction stay within their stated bounds
    /// (the corrections are exact from any start, only slower).
    #[test]
    fn estimates_are_close() {
        let mut r = rng(23);
        for _ in 0..1_000_000 {
            let n = r() >> (r() % 32);
            let n = n.max(1 << 32);
            let e = isqrt_estimate_u64(n) as i64 - isqrt_reference(n) as i64;
            assert!(e.abs() <= 2, "{n}: {e}");
            let n32 = ((r() >> 32) as u32 >> (r() % 32)).max(1);
            let e = isqrt_estimate_u32(n32) as i64 - isqrt_reference(n32 as u64) as i64;
            assert!(e.abs() <= 2, "{n32}: {e}");
            let d = (r() as u32) | (1 << 31);
            let v = (u64::MAX as u128 / d as u128 - (1u128 << 32)) as u32;
            assert!((0..=3).contains(&(v - recip_word_estimate(d))), "{d}");
        }
        for n in [
            u64::MAX,
            u64::MAX - 1,
            1 << 32,
            (1 << 62) - 1,
            1 << 62,
            0xFFFF_FFFE_0000_0001,
        ] {
            let e = isqrt_estimate_u64(n) as i64 - isqrt_reference(n) as i64;
            assert!(e.abs() <= 2, "{n}: {e}");
        }
    }

    /// The 32-bit square root and its estimate, for every u32 (some four
    /// billion; run with --ignored).
    #[test]
    #[ignore]
    fn square_root_u32_exhaustive() {
        let mut root = 0u32;
        for n in 0..=u32::MAX {
            if (root as u64 + 1) * (root as u64 + 1) <= n as u64 {
                root += 1;
            }
            assert_eq!(isqrt_rem_u32(n), (root, n - root * root), "{n}");
            if n > 0 {
                assert!(isqrt_estimate_u32(n).abs_diff(root) <= 2, "{n}");
            }
        }
    }
    /// The word reciprocal's definition: `(2^32 + v) · d <= 2^64 - 1 < (2^32 + v + 1) · d`.
    fn check_recip_word(d: u32) {
        let v = recip_word(d);
        let want = (u64::MAX as u128 / d as u128 - (1u128 << 32)) as u32;
        assert_eq!(v, want, "d = {d:#x}");
    }

    #[test]
    fn word_reciprocal_is_exact() {
        for d in (1u32 << 31)..(1u32 << 31) + 100_000 {
            check_recip_word(d);
        }
        for d in (u32::MAX - 100_000)..=u32::MAX {
            check_recip_word(d);
        }
        // Each table interval's ends, and a stride through the whole range.
        for j in 256u32..512 {
            for d in [(j << 23), (j << 23) + 1, (j << 23).wrapping_add((1 << 23) - 1)] {
                check_recip_word(d.max(1 << 31));
            }
        }
        let mut d = 1u32 << 31;
        while let Some(next) = d.checked_add(4099) {
            check_recip_word(d);
            d = next;
        }
        let mut r = rng(13);
        for _ in 0..200_000 {
            check_recip_word((r() as u32) | (1 << 31));
        }
    }

    /// Every normalised divisor (some two billion; run with --ignored).
    #[test]
    #[ignore]
    fn word_reciprocal_exhaustive() {
        for d in (1u32 << 31)..=u32::MAX {
            check_recip_word(d);
            assert!(recip_word(d) - recip_word_estimate(d) <= 3, "{d}");
        }
    }

    /// `RecipMul`, `Recip`, `RecipHw`, `div_rem_u64_u32` and `div_rem_u64` against `/` and `%`.
    fn check_div(n: u64, d: u32) {
        let want = (n / d as u64, (n % d as u64) as u32);
        let r = RecipMul::new(d);
        assert_eq!(r.div_rem(n), want, "{n} / {d}");
        assert_eq!(r.divisor(), d);
        assert_eq!(Recip::new(d).div_rem(n), want, "{n} / {d}");
        // The word-divide kernel of the Cortex-M3 and RV32, checked here on every host.
        assert_eq!(RecipHw::new(d).div_rem(n), want, "{n} / {d}");
        assert_eq!(div_rem_u64_u32(n, d), want, "{n} / {d}");
        assert_eq!(div_rem_u64(n, d as u64), (want.0, want.1 as u64), "{n} / {d}");
    }

    #[test]
    fn division_is_exact() {
        // Exhaustive small ranges.
        for d in 1u32..300 {
            for n in 0u64..2000 {
                check_div(n, d);
            }
        }
        let mut r = rng(17);
        // Every divisor width, with random and edge numerators.
        for bits in 1..=32u32 {
            let lo = 1u64 << (bits - 1);
            for _ in 0..3000 {
                let d = (lo + r() % lo) as u32;
                let d = if r() & 7 == 0 { lo as u32 } else { d };
                let d = if r() & 7 == 0 { ((lo << 1) - 1) as u32 } else { d };
                let dd = d as u64;
                let below = (dd << 32) - 1;
                for n in [
                    0,
                    1,
                    dd - 1,
                    dd,
                    dd + 1,
                    below,
                    below - dd,
                    dd << 31,
                    u64::MAX,
                    u64::MAX - 1,
                ] {
                    check_div(n, d);
                }
                // Quotients of every width, up to 64 bits.
                check_div(r() >> (r() % 64), d);
                check_div(r() % (below + 1), d);
                // Exact multiples and their neighbours.
                let q = r() % (1 << 32);
                let m = q * dd;
                for n in [m.wrapping_sub(1), m, m + 1, m + dd - 1] {
                    check_div(n, d);
                }
            }
        }
        // Powers of two.
        for a in 0..32 {
            for b in 0..64 {
                let d = 1u32 << a;
                for n in [(1u64 << b) - 1, 1 << b, (1u64 << b) + 1] {
                    check_div(n, d);
                }
            }
        }
        for _ in 0..1_000_000 {
            let d = ((r() >> 32) as u32 >> (r() % 32)).max(1);
            check_div(r() >> (r() % 64), d);
        }
        // Wide divisors go through `/`.
        for _ in 0..10_000 {
            let (n, d) = (r(), (r() >> (r() % 32)).max(1 << 32));
            assert_eq!(div_rem_u64(n, d), (n / d, n % d));
        }
    }

    /// One reciprocal, many dividends.
    #[test]
    fn powers_of_two_divide_by_the_reciprocal() {
        let mut next = rng(0x5EED_2F0C);
        let mut ls: Vec<u32> = (1..=4096)
            .chain((0..32).flat_map(|b| [1u32 << b, (1u32 << b).wrapping_sub(1), (1u32 << b) + 1]))
            .collect();
        ls.extend((0..50_000).map(|_| (next() as u32) >> (next() % 32)));
        ls.push(u32::MAX);
        let (mut cases, mut by_recip) = (0, 0);
        for l in ls.into_iter().filter(|&l| l != 0) {
            for k in [0, 31, 32, 33, 40, 46, 50, 61, 62, 63] {
                let want = (1u64 << k) / l as u64;
                cases += 1;
                if let Some(q) = div_pow2_by_recip(k, l) {
                    by_recip += 1;
                    assert_eq!(q, want, "2^{k} / {l}");
                }
                assert_eq!(div_pow2_u32(k, l), want, "2^{k} / {l}");
            }
        }
        // The reciprocal's path (leading zeros of l plus k in 33..=64): about half of these.
        assert!(by_recip * 3 > cases, "{by_recip} of {cases} by the reciprocal");
    }

    #[test]
    fn reciprocal_reused() {
        let mut r = rng(19);
        for _ in 0..2000 {
            let d = ((r() >> 32) as u32 >> (r() % 32)).max(1);
            let (m, p, h) = (RecipMul::new(d), Recip::new(d), RecipHw::new(d));
            for _ in 0..100 {
                let n = r() >> (r() % 64);
                let want = (n / d as u64, (n % d as u64) as u32);
                assert_eq!(m.div_rem(n), want, "{n} / {d}");
                assert_eq!(p.div_rem(n), want, "{n} / {d}");
                // The word-divide kernel of the Cortex-M3 and RV32, checked here on every host.
                assert_eq!(h.div_rem(n), want, "{n} / {d}");
            }
        }
    }
}
