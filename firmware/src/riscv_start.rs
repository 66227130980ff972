//! Start-up of the RISC-V board (no runtime crate): set the global and
//! stack pointers, copy `.data`, clear `.bss`, install the trap handler and
//! call [`main`](crate::main). Sections and symbols: boards/sifive-e/link.x.

use crate::semihosting::{exit, HostFile};

core::arch::global_asm!(
    ".section .init, \"ax\"",
    ".global _start",
    "_start:",
    ".option push",
    ".option norelax",
    "la gp, __global_pointer$",
    ".option pop",
    "la sp, _stack_start",
    "la t0, __sdata",
    "la t1, __edata",
    "la t2, __sidata",
    "1: bgeu t0, t1, 2f",
    "lw t3, 0(t2)",
    "sw t3, 0(t0)",
    "addi t0, t0, 4",
    "addi t2, t2, 4",
    "j 1b",
    "2: la t0, __sbss",
    "la t1, __ebss",
    "3: bgeu t0, t1, 4f",
    "sw zero, 0(t0)",
    "addi t0, t0, 4",
    "j 3b",
    "4: la t0, 6f",
    "csrw mtvec, t0",
    "call {main}",
    "5: j 5b",
    // mtvec wants a 4-byte aligned handler; a Rust function may be 2-aligned.
    ".balign 4",
    "6: j {trap}",
    trap = sym trap,
    main = sym crate::main,
);

/// Any trap (an illegal instruction, a bad address): no interrupt is ever
/// enabled, so a trap is a fault. Says where and exits with status 3.
extern "C" fn trap() -> ! {
    let (cause, pc): (usize, usize);
    // SAFETY: reads of two machine-mode CSRs.
    unsafe {
        core::arch::asm!("csrr {0}, mcause", "csrr {1}, mepc", out(reg) cause, out(reg) pc, options(nomem, nostack));
    }
    if let Ok(mut console) = HostFile::console() {
        console
            .text("HardFault (trap, mcause ")
            .num(cause as u64)
            .text(") at pc ")
            .hex(pc as u32)
            .text("\n");
    }
    exit(3)
}
