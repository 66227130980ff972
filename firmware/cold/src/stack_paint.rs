//! Memory use: static RAM and flash from the linker's symbols, and the peak
//! stack by painting: free RAM below the stack is filled with a pattern at
//! start-up, and the lowest word no longer holding it marks the deepest stack.

use core::ptr::{addr_of, read_volatile, write_volatile};

/// The paint: unlikely as data, and odd as an address.
const PAINT: u32 = 0xC0FF_EE5D;
/// Most bytes painted below the stack (the MPS2's 4 MiB need not all be).
const MAX_PAINT: usize = 64 * 1024;
/// Bytes under the stack pointer left unpainted: `paint`'s own frame may be
/// pushed there after the stack pointer is read (LLVM's shrink-wrapping does).
const MARGIN: usize = 64;

extern "C" {
    static __vector_table: u32;
    static __sidata: u32;
    static __sdata: u32;
    static __edata: u32;
    static __sheap: u32;
    static _ram_start: u32;
    static _ram_end: u32;
    static _stack_start: u32;
}

/// A linker symbol's address (taking it is safe; reading it is not).
fn sym(p: *const u32) -> usize {
    p as usize
}

/// The painted window: `[low, high)`.
pub struct Paint {
    low: usize,
    high: usize,
}

/// Paints the free RAM below the current stack pointer.
///
/// Call it first thing in `main`, before interrupts are enabled: nothing may
/// use the stack below this function's frame while it paints.
#[inline(never)]
pub fn paint() -> Paint {
    let sp = stack_pointer();
    let heap = sym(addr_of!(__sheap));
    let high = (sp - MARGIN) & !3;
    let low = heap.max(high.saturating_sub(MAX_PAINT));
    let mut a = low;
    while a < high {
        // SAFETY: free RAM between the end of the statics and the stack pointer.
        unsafe { write_volatile(a as *mut u32, PAINT) };
        a += 4;
    }
    Paint { low, high }
}

/// The current stack pointer.
#[inline(always)]
fn stack_pointer() -> usize {
    #[cfg(target_arch = "arm")]
    {
        let sp: usize;
        // SAFETY: reads a register.
        unsafe { core::arch::asm!("mov {0}, sp", out(reg) sp, options(nomem, nostack, preserves_flags)) };
        sp
    }
    #[cfg(target_arch = "riscv32")]
    {
        let sp: usize;
        // SAFETY: reads a register.
        unsafe { core::arch::asm!("mv {0}, sp", out(reg) sp, options(nomem, nostack)) };
        sp
    }
}

impl Paint {
    /// The deepest the stack has been since [`paint`], in bytes from its top.
    pub fn peak_stack(&self) -> usize {
        let mut a = self.low;
        // SAFETY: reads of the painted window only.
        while a < self.high && unsafe { read_volatile(a as *const u32) } == PAINT {
            a += 4;
        }
        stack_top() - a
    }

    /// Whether the stack reached the bottom of the painted window (so the
    /// figure is a lower bound, or the stack ran into the statics).
    pub fn overflowed(&self) -> bool {
        // SAFETY: a read of the painted window's first word.
        self.low >= self.high || unsafe { read_volatile(self.low as *const u32) } != PAINT
    }
}

/// The initial stack pointer: the stack's top.
pub fn stack_top() -> usize {
    sym(addr_of!(_stack_start))
}

/// Bytes of RAM used by statics (`.data`, `.bss`, `.uninit`).
pub fn static_ram() -> usize {
    sym(addr_of!(__sheap)) - sym(addr_of!(_ram_start))
}

/// Bytes of RAM on the board (the memory map's RAM).
pub fn ram() -> usize {
    sym(addr_of!(_ram_end)) - sym(addr_of!(_ram_start))
}

/// Bytes of flash the program occupies: code, constants and `.data`'s image.
pub fn flash() -> usize {
    sym(addr_of!(__sidata)) + (sym(addr_of!(__edata)) - sym(addr_of!(__sdata))) - sym(addr_of!(__vector_table))
}
