//! The Cortex-M0's hottest exact integer kernels, written in Thumb-1.
//!
//! On thumbv6m every Rust function keeps a frame pointer (`push {r7, lr}`,
//! `add r7, sp`) and LLVM spills a register around the 16-bit halves of a
//! product; these leaf routines use r0–r6 and no stack beyond three saved
//! registers. Together they are called some 55 times a pixel. Each computes
//! exactly what the portable Rust computes on every other target (`*` on
//! i64, `leading_zeros`, the Q16.16 product's rounding and saturation): the
//! board's renders are compared bit for bit with the host's, and
//! `wide::check_thumb1` runs each against the portable Rust on the board.

use core::arch::naked_asm;

/// Leading zeros of each byte value (8 for 0): [`clz32`]'s last step.
static CLZ8: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = (i as u8).leading_zeros() as u8;
        i += 1;
    }
    t
};

/// The 32 × 32 → 64-bit product of registers `a` and `b` from four
/// 16 × 16-bit `MULS`: their halves into `a0`, `a1`, `b0`, `b1` (`a1` and `b1`
/// may be `a` and `b` themselves), the product's high word into `a1` and its
/// low word into `lo`. `shr` is `asrs` for signed factors (high halves
/// signed, the two middle products then below 2^31 in magnitude) or `lsrs`
/// for unsigned ones. The shifts set C; each `adds` sets it again for its
/// `adcs`.
#[rustfmt::skip]
macro_rules! mul32 {
    ($shr:literal, $a:literal, $b:literal => $a0:literal, $a1:literal, $b0:literal, $b1:literal, $lo:literal) => {
        concat!(
            "uxth ", $a0, ", ", $a, "\n",
            $shr, " ", $a1, ", ", $a, ", #16\n",
            "uxth ", $b0, ", ", $b, "\n",
            $shr, " ", $b1, ", ", $b, ", #16\n",
            "movs ", $lo, ", ", $a0, "\n",
            "muls ", $lo, ", ", $b0, "\n", // a0 b0
            "muls ", $b0, ", ", $a1, "\n", // a1 b0
            "muls ", $a1, ", ", $b1, "\n", // a1 b1: the high word's start
            "muls ", $b1, ", ", $a0, "\n", // a0 b1
            "lsls ", $a0, ", ", $b1, ", #16\n",
            $shr, " ", $b1, ", ", $b1, ", #16\n",
            "adds ", $lo, ", ", $lo, ", ", $a0, "\n",
            "adcs ", $a1, ", ", $b1, "\n",
            "lsls ", $a0, ", ", $b0, ", #16\n",
            $shr, " ", $b0, ", ", $b0, ", #16\n",
            "adds ", $lo, ", ", $lo, ", ", $a0, "\n",
            "adcs ", $a1, ", ", $b0, "\n",
        )
    };
}

/// The signed product of r0 and r1 into r1 (high) and r0 (low), with r2–r4.
macro_rules! mul_i32_body {
    () => {
        concat!(mul32!("asrs", "r0", "r1" => "r2", "r0", "r3", "r1", "r4"), "movs r1, r0\n", "movs r0, r4\n")
    };
}

/// The unsigned product of r0 and r1 (both kept) into r3 (high) and r6
/// (low), with r2, r4 and r5.
macro_rules! mul_u32_body {
    () => {
        mul32!("lsrs", "r0", "r1" => "r2", "r3", "r4", "r5", "r6")
    };
}

/// Leading zeros of `x` (32 for 0): two halving steps and the byte table.
#[unsafe(naked)]
pub(crate) extern "C" fn clz32(x: u32) -> u32 {
    naked_asm!(
        "movs r1, #0",
        "lsrs r2, r0, #16",
        "bne 1f",
        "lsls r0, r0, #16",
        "movs r1, #16",
        "1:",
        "lsrs r2, r0, #24",
        "bne 2f",
        "lsls r0, r0, #8",
        "adds r1, #8",
        "2:",
        "lsrs r0, r0, #24",
        "ldr r2, 3f",
        "ldrb r0, [r2, r0]",
        "adds r0, r0, r1",
        "bx lr",
        ".p2align 2",
        "3:",
        ".word {table}",
        table = sym CLZ8,
    )
}

/// `a · b` exactly.
#[unsafe(naked)]
pub(crate) extern "C" fn mul_i32(a: i32, b: i32) -> i64 {
    naked_asm!("push {{r4}}", mul_i32_body!(), "pop {{r4}}", "bx lr")
}

/// `a · b` for a product that fits an i64: the 32-bit product when both
/// factors fit an i32 (nearly always), else the runtime's 64-bit multiply
/// (whose low 64 bits are the product, as the caller promises it fits).
#[unsafe(naked)]
pub(crate) extern "C" fn mul_i64(a: i64, b: i64) -> i64 {
    naked_asm!(
        "push {{r4}}",
        // Each factor fits an i32 when its high word is its low word's sign.
        "asrs r4, r0, #31",
        "cmp r4, r1",
        "bne 1f",
        "asrs r4, r2, #31",
        "cmp r4, r3",
        "bne 1f",
        "movs r1, r2",
        mul_i32_body!(),
        "pop {{r4}}",
        "bx lr",
        // All four argument registers are taken: the address goes through ip.
        "1:",
        "ldr r4, 2f",
        "mov ip, r4",
        "pop {{r4}}",
        "bx ip",
        ".p2align 2",
        "2:",
        ".word __aeabi_lmul",
    )
}

/// The Q16.16 product `a · b / 2^16`, rounded to nearest (ties up) and
/// saturated: when both magnitudes are below 2^16 (colours, unit vectors)
/// their product fits a u32 and one `MULS` does; else the full product.
#[unsafe(naked)]
pub(crate) extern "C" fn mul_q16(a: i32, b: i32) -> i32 {
    naked_asm!(
        "push {{r4, r5}}",
        "movs r2, r0",
        "eors r2, r1", // the product's sign in bit 31
        "movs r3, r0",
        "bpl 1f",
        "negs r3, r3",
        "1:",
        "movs r4, r1",
        "bpl 2f",
        "negs r4, r4",
        "2:",
        "movs r5, r3",
        "orrs r5, r4",
        "lsrs r5, r5, #16",
        "bne 4f",
        "muls r3, r4", // m = |a| |b| <= (2^16 - 1)^2: m + 2^15 cannot carry
        "ldr r0, 5f",
        "cmp r2, #0",
        "blt 3f",
        // floor(m / 2^16 + 1/2)
        "adds r0, r3, r0",
        "lsrs r0, r0, #16",
        "pop {{r4, r5}}",
        "bx lr",
        // -m: -floor((m + 2^15 - 1) / 2^16), ties towards +∞ as for +m.
        "3:",
        "subs r0, #1",
        "adds r0, r3, r0",
        "lsrs r0, r0, #16",
        "negs r0, r0",
        "pop {{r4, r5}}",
        "bx lr",
        // The full product, plus 2^15, shifted down 16 and saturated.
        "4:",
        mul_i32_body!(),
        "ldr r2, 5f",
        "adds r0, r0, r2",
        "movs r2, #0", // MOVS keeps C
        "adcs r1, r2",
        "lsrs r0, r0, #16",
        "lsls r2, r1, #16",
        "orrs r0, r2",
        "asrs r1, r1, #16",
        // It fits an i32 when the high word is the low word's sign.
        "asrs r2, r0, #31",
        "cmp r1, r2",
        "bne 6f",
        "pop {{r4, r5}}",
        "bx lr",
        "6:",
        "ldr r0, 7f",
        "asrs r1, r1, #31",
        "eors r0, r1", // i32::MAX, or i32::MIN below 0
        "pop {{r4, r5}}",
        "bx lr",
        ".p2align 2",
        "5:",
        ".word 0x8000",
        "7:",
        ".word 0x7FFFFFFF",
    )
}

/// `floor((2^64 - 1) / d) - 2^32` for `d >= 2^31`, the word reciprocal of
/// `wide::recip_word`, by its steps: `table`'s 9-bit start, a Newton step in
/// 16 × 16-bit products, a full-width Newton step (both from below), then
/// the remainder's correction, at most three steps.
#[unsafe(naked)]
pub(crate) extern "C" fn recip_word(d: u32, table: &[u16; 256]) -> u32 {
    naked_asm!(
        "push {{r4, r5, r6}}",
        // x0 = table[(d >> 23) & 0xFF] ≈ 2^47 / d
        "lsls r2, r0, #1",
        "lsrs r2, r2, #24",
        "lsls r2, r2, #1",
        "ldrh r1, [r1, r2]",
        // e = 2^23 - ((d >> 16) x0 >> 8) - ((d & 0xFFFF) x0 >> 24), |e| < 2^14.1
        "lsrs r2, r0, #16",
        "muls r2, r1",
        "lsrs r2, r2, #8",
        "uxth r3, r0",
        "muls r3, r1",
        "lsrs r3, r3, #24",
        "adds r2, r2, r3",
        "movs r3, #1",
        "lsls r3, r3, #23",
        "subs r3, r3, r2",
        // v1 = (x0 << 17) + (e x0 >> 6) - 2^32 - 2^12 in (r2, r1), then max(0, v1)
        "muls r3, r1",
        "asrs r3, r3, #6",
        "lsrs r2, r1, #15",
        "lsls r1, r1, #17",
        "asrs r4, r3, #31",
        "adds r1, r1, r3",
        "adcs r2, r4",
        "movs r3, #1",
        "lsls r3, r3, #12",
        "movs r4, #1", // MOVS keeps C
        "subs r1, r1, r3",
        "sbcs r2, r4",
        "bpl 1f",
        "movs r1, #0",
        "1:",
        // m = the high word of 2^64 - d (2^32 + v1), below 2^15
        mul_u32_body!(),
        "negs r4, r0",
        "negs r2, r6", // C: no borrow out of the low word
        "sbcs r4, r3",
        // v = v1 + m + v1 m / 2^32, the last from two 16 × 16-bit products
        "lsrs r5, r1, #16",
        "muls r5, r4",
        "uxth r6, r1",
        "muls r6, r4",
        "lsrs r6, r6, #16",
        "adds r5, r5, r6",
        "lsrs r5, r5, #16",
        "adds r1, r1, r4",
        "adds r1, r1, r5",
        // e = 2^64 - 1 - d (2^32 + v) in (r4, r2): while e >= d, v += 1 and e -= d
        mul_u32_body!(),
        "mvns r2, r6",
        "mvns r4, r0",
        "subs r4, r4, r3",
        "2:",
        "cmp r4, #0",
        "bne 3f",
        "cmp r2, r0",
        "blo 4f",
        "3:",
        "adds r1, #1",
        "subs r2, r2, r0",
        "movs r3, #0", // MOVS keeps C
        "sbcs r4, r3",
        "b 2b",
        "4:",
        "movs r0, r1",
        "pop {{r4, r5, r6}}",
        "bx lr",
    )
}

/// `floor(sqrt(n))` in r0 and whether `sqrt(n)` rounds up (1 or 0) in r1,
/// for any u64 `n`: `wide::isqrt_rem_u64`'s estimate (n shifted by an even
/// count into [2^62, 2^64), `table`'s start for `1/sqrt`, a Newton step for
/// it and one for the root, 32-bit products only), then the remainder's
/// correction. The root rounds up when `n - r^2 > r`.
#[unsafe(naked)]
pub(crate) extern "C" fn isqrt(n: u64, table: &[u16; 384]) -> u64 {
    naked_asm!(
        // Stack: n's low and high words, k, then nn's low word (later the
        // sign of n - s1^2), then s1.
        "push {{r4, r5, r6}}",
        "sub sp, #20",
        "str r0, [sp, #0]",
        "str r1, [sp, #4]",
        "movs r3, r0",
        "orrs r3, r1",
        "bne 1f",
        "movs r1, #0",
        "b 15f",
        // k = leading zeros of n, halved; r5 counts them.
        "1:",
        "movs r5, #0",
        "movs r4, r1",
        "cmp r1, #0",
        "bne 2f",
        "movs r4, r0",
        "movs r5, #32",
        "2:",
        "lsrs r3, r4, #16",
        "bne 3f",
        "lsls r4, r4, #16",
        "adds r5, #16",
        "3:",
        "lsrs r3, r4, #24",
        "bne 4f",
        "lsls r4, r4, #8",
        "adds r5, #8",
        "4:",
        "lsrs r4, r4, #24",
        "ldr r3, 16f",
        "ldrb r4, [r3, r4]",
        "adds r5, r5, r4",
        "lsrs r5, r5, #1",
        "str r5, [sp, #8]",
        "lsls r4, r5, #1",
        // nn = n << 2k in (r1, r0); a register shift by 32 or more gives 0.
        "cmp r4, #32",
        "bhs 5f",
        "lsls r1, r4",
        "movs r3, #32",
        "subs r3, r3, r4",
        "movs r6, r0",
        "lsrs r6, r3",
        "orrs r1, r6",
        "lsls r0, r4",
        "b 6f",
        "5:",
        "subs r4, #32",
        "movs r1, r0",
        "lsls r1, r4",
        "movs r0, #0",
        // y0 = table[(nh >> 23) - 128] ≈ 2^15 / sqrt(nh / 2^32)
        "6:",
        "str r0, [sp, #12]",
        "lsrs r3, r1, #23",
        "subs r3, #128",
        "lsls r3, r3, #1",
        "ldrh r2, [r2, r3]",
        // t = nh y0^2 / 2^32, h = 3 · 2^30 - t, y1 = y0 h / 2^15
        "movs r3, r2",
        "muls r3, r2",
        mul32!("lsrs", "r1", "r3" => "r0", "r4", "r5", "r3", "r6"),
        "movs r3, #3",
        "lsls r3, r3, #30",
        "subs r3, r3, r4",
        "lsrs r4, r3, #16",
        "muls r4, r2",
        "lsls r4, r4, #1",
        "uxth r3, r3",
        "muls r3, r2",
        "lsrs r3, r3, #15",
        "adds r2, r4, r3",
        // s1 = nh y1 / 2^31
        mul32!("lsrs", "r1", "r2" => "r0", "r3", "r4", "r5", "r6"),
        "lsls r3, r3, #1",
        "lsrs r6, r6, #31",
        "orrs r3, r6",
        "str r3, [sp, #16]",
        // n - s1^2 (signed) in (r1, r5)
        mul32!("lsrs", "r3", "r3" => "r0", "r4", "r5", "r3", "r6"),
        "ldr r5, [sp, #12]",
        "subs r5, r5, r6",
        "sbcs r1, r4",
        "str r1, [sp, #12]",
        "bpl 7f",
        "movs r0, #0",
        "negs r5, r5",
        "sbcs r0, r1",
        "movs r1, r0",
        // c = (|n - s1^2| / 2^16) y1 / 2^48
        "7:",
        "lsls r1, r1, #16",
        "lsrs r5, r5, #16",
        "orrs r1, r5",
        mul32!("lsrs", "r1", "r2" => "r0", "r3", "r4", "r5", "r6"),
        "lsrs r3, r3, #16",
        // s2 = s1 - c below, s1 + c (saturated) above; the estimate s2 >> k
        "ldr r0, [sp, #16]",
        "ldr r4, [sp, #12]",
        "cmp r4, #0",
        "blt 8f",
        "adds r0, r0, r3",
        "bcc 9f",
        "movs r0, #0",
        "mvns r0, r0",
        "b 9f",
        "8:",
        "subs r0, r0, r3",
        "9:",
        "ldr r4, [sp, #8]",
        "lsrs r0, r4",
        // rem = n - r^2 in (r4, r3)
        mul32!("lsrs", "r0", "r0" => "r1", "r2", "r3", "r4", "r5"),
        "ldr r3, [sp, #0]",
        "ldr r4, [sp, #4]",
        "subs r3, r3, r5",
        "sbcs r4, r2",
        // While rem < 0: r -= 1, rem += 2r + 1.
        "10:",
        "cmp r4, #0",
        "bge 11f",
        "subs r0, #1",
        "lsls r1, r0, #1",
        "adds r1, #1",
        "lsrs r2, r0, #31",
        "adds r3, r3, r1",
        "adcs r4, r2",
        "b 10b",
        // While rem > 2r: rem -= 2r + 1, r += 1.
        "11:",
        "lsls r1, r0, #1",
        "lsrs r2, r0, #31",
        "cmp r4, r2",
        "bhi 12f",
        "bne 13f",
        "cmp r3, r1",
        "bls 13f",
        "12:",
        "adds r1, #1",
        "subs r3, r3, r1",
        "sbcs r4, r2",
        "adds r0, #1",
        "b 11b",
        // Rounds up when rem > r.
        "13:",
        "movs r1, #1",
        "cmp r4, #0",
        "bne 15f",
        "cmp r3, r0",
        "bhi 15f",
        "movs r1, #0",
        "15:",
        "add sp, #20",
        "pop {{r4, r5, r6}}",
        "bx lr",
        ".p2align 2",
        "16:",
        ".word {clz8}",
        clz8 = sym CLZ8,
    )
}
