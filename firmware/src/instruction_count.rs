//! Counting executed instructions: SysTick on the Cortex-M boards, the
//! `mcycle` counter on RISC-V.
//!
//! Under QEMU's `-icount shift=0` every instruction advances the virtual clock
//! by 1 ns, so SysTick, clocked by the core, ticks once per 1000 / f_MHz
//! instructions: 62.5 on the micro:bit (16 MHz), 40 on the MPS2 (25 MHz).
//! QEMU's RISC-V `mcycle` then reads the instruction count itself (one per tick).
//! Without `-icount` both follow the host's clock and the count means nothing.

#[cfg(target_arch = "riscv32")]
pub use riscv::*;
#[cfg(target_arch = "arm")]
pub use systick::*;

/// Instructions in [`Counter::calibrate`]'s loop.
pub const CALIBRATION: u32 = 2_000_000;

/// Ticks to instructions, rounded.
pub fn instructions(ticks: u64) -> u64 {
    let (num, den) = INSTRUCTIONS_PER_TICK;
    (ticks * num + den / 2) / den
}

#[cfg(target_arch = "riscv32")]
mod riscv {
    use super::CALIBRATION;

    /// One `mcycle` tick per instruction under `-icount shift=0`.
    pub const INSTRUCTIONS_PER_TICK: (u64, u64) = (1, 1);

    /// The machine cycle counter (nothing to set up: it always runs).
    pub struct Counter;

    impl Counter {
        /// The counter.
        pub fn start() -> Counter {
            Counter
        }

        /// Ticks since reset (64 bits read as two halves).
        pub fn ticks(&self) -> u64 {
            loop {
                let (hi, lo, hi2): (u32, u32, u32);
                // SAFETY: reads of machine-mode counter CSRs.
                unsafe {
                    core::arch::asm!("csrr {0}, mcycleh", "csrr {1}, mcycle", "csrr {2}, mcycleh",
                        out(reg) hi, out(reg) lo, out(reg) hi2, options(nomem, nostack));
                }
                // A carry between the halves shows as a changed high half: read again.
                if hi == hi2 {
                    return (hi as u64) << 32 | lo as u64;
                }
            }
        }

        /// Counts a loop of exactly [`CALIBRATION`] instructions.
        pub fn calibrate(&self) -> u64 {
            let start = self.ticks();
            // SAFETY: a register-only countdown loop: two instructions per turn.
            unsafe {
                core::arch::asm!("2:", "addi {n}, {n}, -1", "bnez {n}, 2b", n = inout(reg) CALIBRATION / 2 => _, options(nomem, nostack));
            }
            super::instructions(self.ticks() - start)
        }
    }
}

#[cfg(target_arch = "arm")]
mod systick {
    use super::CALIBRATION;

    use core::sync::atomic::{AtomicU32, Ordering};
    use cortex_m::peripheral::syst::SystClkSource;
    use cortex_m::peripheral::SYST;
    use cortex_m_rt::exception;

    /// SysTick's 24-bit reload: the longest period, fewest interrupts.
    const RELOAD: u32 = 0x00FF_FFFF;

    /// Completed SysTick periods (written only by the SysTick handler).
    static WRAPS: AtomicU32 = AtomicU32::new(0);

    /// Instructions per SysTick tick under `-icount shift=0`, as a fraction
    /// (numerator, denominator): 10^9 / the board's core clock.
    pub const INSTRUCTIONS_PER_TICK: (u64, u64) = if cfg!(feature = "microbit") { (125, 2) } else { (40, 1) };

    /// A running SysTick: ticks since [`Counter::start`].
    pub struct Counter {
        _syst: SYST,
    }

    impl Counter {
        /// Starts SysTick from the core clock, with its wrap interrupt.
        pub fn start(mut syst: SYST) -> Counter {
            syst.set_clock_source(SystClkSource::Core);
            syst.set_reload(RELOAD);
            syst.clear_current();
            syst.enable_interrupt();
            syst.enable_counter();
            let counter = Counter { _syst: syst };
            // The counter reads 0 until its first reload: start from a true count.
            while SYST::get_current() == 0 {}
            counter
        }

        /// Ticks since the start (64 bits: no wrap in practice).
        pub fn ticks(&self) -> u64 {
            loop {
                let before = WRAPS.load(Ordering::SeqCst);
                let current = SYST::get_current();
                // At 0 the wrap is pending or just counted: wait for the reload, one tick.
                if current == 0 {
                    continue;
                }
                // A wrap between the two reads shows as a changed count: read again.
                if WRAPS.load(Ordering::SeqCst) == before {
                    return before as u64 * (RELOAD as u64 + 1) + (RELOAD - current) as u64;
                }
            }
        }

        /// Counts a loop of exactly [`CALIBRATION`] instructions: the result
        /// checks [`INSTRUCTIONS_PER_TICK`] (to about one tick).
        pub fn calibrate(&self) -> u64 {
            let start = self.ticks();
            // SAFETY: a register-only countdown loop: two instructions per turn.
            unsafe {
                core::arch::asm!("2:", "subs {n}, #1", "bne 2b", n = inout(reg) CALIBRATION / 2 => _, options(nomem, nostack));
            }
            super::instructions(self.ticks() - start)
        }
    }

    #[exception]
    fn SysTick() {
        // The only writer, so a load and a store suffice (Cortex-M0 has no atomic add).
        WRAPS.store(WRAPS.load(Ordering::Relaxed).wrapping_add(1), Ordering::Relaxed);
    }
}
