//! The micro:bit's runtime routines, small: compiler-builtins defines them
//! weak, and these take their place (same results, a little slower).
//!
//! * Memory copies and fills: the AEABI entry points LLVM calls for struct
//!   moves and zeroing, each a short word loop (and a byte loop for the odd
//!   ends), in place of six copies of compiler-builtins' (1.4 KB of Cortex-M0
//!   flash). Volatile accesses keep LLVM from turning the loops back into
//!   calls to themselves.
//! * `u64 / u64` and `u32 / u32` (`__aeabi_uldivmod`, `__aeabi_uidiv`,
//!   `__aeabi_uidivmod`): one shift-and-subtract routine over the
//!   quotient's bits only, in place of compiler-builtins' (1.3 KB).

use core::ptr::{read_volatile, write_volatile};

/// Copies `n` bytes, a word at a time while both pointers are aligned.
///
/// # Safety
///
/// As `memcpy`: `n` bytes readable at `src`, writable at `dst`, not overlapping.
#[inline(never)]
unsafe fn copy(dst: *mut u8, src: *const u8, n: usize) {
    let mut i = 0;
    if (dst as usize | src as usize) & 3 == 0 {
        while i + 4 <= n {
            // SAFETY: aligned and within the caller's n bytes.
            unsafe { write_volatile(dst.add(i) as *mut u32, read_volatile(src.add(i) as *const u32)) };
            i += 4;
        }
    }
    while i < n {
        // SAFETY: within the caller's n bytes.
        unsafe { write_volatile(dst.add(i), read_volatile(src.add(i))) };
        i += 1;
    }
}

/// Sets `n` bytes to `c`, a word at a time while aligned.
///
/// # Safety
///
/// As `memset`: `n` bytes writable at `dst`.
#[inline(never)]
unsafe fn fill(dst: *mut u8, n: usize, c: u8) {
    let mut i = 0;
    if dst as usize & 3 == 0 {
        let w = u32::from_ne_bytes([c; 4]);
        while i + 4 <= n {
            // SAFETY: aligned and within the caller's n bytes.
            unsafe { write_volatile(dst.add(i) as *mut u32, w) };
            i += 4;
        }
    }
    while i < n {
        // SAFETY: within the caller's n bytes.
        unsafe { write_volatile(dst.add(i), c) };
        i += 1;
    }
}

/// # Safety
///
/// As `memcpy`.
#[no_mangle]
pub unsafe extern "C" fn __aeabi_memcpy(dst: *mut u8, src: *const u8, n: usize) {
    // SAFETY: the caller's promise.
    unsafe { copy(dst, src, n) }
}

/// # Safety
///
/// As `memcpy`, both pointers 4-aligned.
#[no_mangle]
pub unsafe extern "C" fn __aeabi_memcpy4(dst: *mut u8, src: *const u8, n: usize) {
    // SAFETY: the caller's promise.
    unsafe { copy(dst, src, n) }
}

/// # Safety
///
/// As `memcpy`, both pointers 8-aligned.
#[no_mangle]
pub unsafe extern "C" fn __aeabi_memcpy8(dst: *mut u8, src: *const u8, n: usize) {
    // SAFETY: the caller's promise.
    unsafe { copy(dst, src, n) }
}

/// # Safety
///
/// As `memcpy`.
#[no_mangle]
pub unsafe extern "C" fn memcpy(dst: *mut u8, src: *const u8, n: usize) -> *mut u8 {
    // SAFETY: the caller's promise.
    unsafe { copy(dst, src, n) };
    dst
}

/// # Safety
///
/// `n` bytes writable at `dst`.
#[no_mangle]
pub unsafe extern "C" fn __aeabi_memclr(dst: *mut u8, n: usize) {
    // SAFETY: the caller's promise.
    unsafe { fill(dst, n, 0) }
}

/// # Safety
///
/// `n` bytes writable at `dst`, 4-aligned.
#[no_mangle]
pub unsafe extern "C" fn __aeabi_memclr4(dst: *mut u8, n: usize) {
    // SAFETY: the caller's promise.
    unsafe { fill(dst, n, 0) }
}

/// # Safety
///
/// `n` bytes writable at `dst`, 8-aligned.
#[no_mangle]
pub unsafe extern "C" fn __aeabi_memclr8(dst: *mut u8, n: usize) {
    // SAFETY: the caller's promise.
    unsafe { fill(dst, n, 0) }
}

/// # Safety
///
/// As `memset` (note the AEABI order: length before value).
#[no_mangle]
pub unsafe extern "C" fn __aeabi_memset(dst: *mut u8, n: usize, c: i32) {
    // SAFETY: the caller's promise.
    unsafe { fill(dst, n, c as u8) }
}

/// # Safety
///
/// As `memset`.
#[no_mangle]
pub unsafe extern "C" fn memset(dst: *mut u8, c: i32, n: usize) -> *mut u8 {
    // SAFETY: the caller's promise.
    unsafe { fill(dst, n, c as u8) };
    dst
}

/// `n / d` and `n % d` by shift and subtract, one step a quotient bit; for
/// `d == 0` (Rust checks before dividing) the quotient is all ones.
extern "C" fn udivmod(mut n: u64, mut d: u64, rem: &mut u64) -> u64 {
    let mut q = 0;
    if d != 0 && n >= d {
        // Align d's top bit with n's, then one step a bit back down.
        let shift = d.leading_zeros() - n.leading_zeros();
        d <<= shift;
        for _ in 0..=shift {
            q <<= 1;
            if n >= d {
                n -= d;
                q |= 1;
            }
            d >>= 1;
        }
    } else if d == 0 {
        q = u64::MAX;
    }
    *rem = n;
    q
}

/// `u64 / u64` as the AEABI has it: numerator in r0:r1, denominator in
/// r2:r3; quotient back in r0:r1, remainder in r2:r3.
#[unsafe(naked)]
#[no_mangle]
pub extern "C" fn __aeabi_uldivmod() {
    core::arch::naked_asm!(
        "push {{r4, lr}}",
        "sub sp, sp, #16",
        // The remainder's slot at sp + 8, its address the fifth argument at sp.
        "add r4, sp, #8",
        "str r4, [sp]",
        "bl {div}",
        "ldr r2, [sp, #8]",
        "ldr r3, [sp, #12]",
        "add sp, sp, #16",
        "pop {{r4, pc}}",
        div = sym udivmod,
    )
}

/// `u32 / u32`: the u64 routine's (one routine, not two: the few u32
/// divisions the firmware makes have short quotients).
#[no_mangle]
pub extern "C" fn __aeabi_uidiv(n: u32, d: u32) -> u32 {
    let mut rem = 0;
    udivmod(n as u64, d as u64, &mut rem) as u32
}

/// `u32 / u32` and `u32 % u32`: quotient in r0, remainder in r1 (a u64's
/// halves as AAPCS returns it).
#[no_mangle]
pub extern "C" fn __aeabi_uidivmod(n: u32, d: u32) -> u64 {
    let mut rem = 0;
    let q = udivmod(n as u64, d as u64, &mut rem);
    q as u32 as u64 | rem << 32
}
