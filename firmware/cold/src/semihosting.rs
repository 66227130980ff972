//! Semihosting calls (Arm: `bkpt 0xAB`; RISC-V: `ebreak` between two marker
//! instructions): files on the host, a console, and an exit status. QEMU
//! serves them with `-semihosting-config enable=on,target=native`.

use core::ffi::CStr;
use core::fmt;

const SYS_OPEN: u32 = 0x01;
const SYS_CLOSE: u32 = 0x02;
const SYS_WRITE: u32 = 0x05;
const SYS_EXIT_EXTENDED: u32 = 0x20;
/// `ADP_Stopped_ApplicationExit`: with SYS_EXIT_EXTENDED, the second word is the exit status.
const ADP_STOPPED_APPLICATION_EXIT: u32 = 0x20026;

/// `fopen` mode "wb" in semihosting's numbering.
const MODE_WRITE_BINARY: u32 = 5;
/// `fopen` mode "w": with the name ":tt", the host's console.
const MODE_WRITE: u32 = 4;

/// One semihosting call: operation `op`, argument block or value `arg`.
///
/// # Safety
///
/// `arg` must point to the argument block `op` expects (and what it points to
/// must stay valid for the call).
#[cfg(target_arch = "arm")]
#[inline(always)]
unsafe fn call(op: u32, arg: usize) -> i32 {
    let mut r0 = op;
    // The host reads and writes our memory during the call: no `nomem`.
    core::arch::asm!("bkpt #0xab", inout("r0") r0, in("r1") arg, options(nostack, preserves_flags));
    r0 as i32
}

/// One semihosting call (see the Arm version above).
///
/// # Safety
///
/// As for Arm: `arg` must point to the argument block `op` expects.
#[cfg(target_arch = "riscv32")]
#[inline(always)]
unsafe fn call(op: u32, arg: usize) -> i32 {
    let mut a0 = op;
    // The marked `ebreak`: three uncompressed instructions on one page.
    core::arch::asm!(
        ".balign 16",
        ".option push",
        ".option norvc",
        "slli x0, x0, 0x1f",
        "ebreak",
        "srai x0, x0, 0x7",
        ".option pop",
        inout("a0") a0,
        in("a1") arg,
        options(nostack, preserves_flags)
    );
    a0 as i32
}

/// Ends the emulation with `status` as QEMU's own exit status.
pub fn exit(status: u32) -> ! {
    let block = [ADP_STOPPED_APPLICATION_EXIT, status];
    loop {
        // SAFETY: a two-word block, as SYS_EXIT_EXTENDED expects.
        unsafe { call(SYS_EXIT_EXTENDED, block.as_ptr() as usize) };
    }
}

/// A file open on the host.
pub struct HostFile(u32);

/// A semihosting call failed (no host, or the host's file call failed).
#[derive(Copy, Clone, Debug)]
pub struct IoError;

impl HostFile {
    /// Creates (or truncates) `name`, relative to the host's working directory.
    pub fn create(name: &CStr) -> Result<HostFile, IoError> {
        Self::open(name, MODE_WRITE_BINARY)
    }

    /// The host's console (its standard output under QEMU).
    pub fn console() -> Result<HostFile, IoError> {
        Self::open(c":tt", MODE_WRITE)
    }

    fn open(name: &CStr, mode: u32) -> Result<HostFile, IoError> {
        // SYS_OPEN wants the NUL-terminated name and its length.
        let block = [name.as_ptr() as u32, mode, name.to_bytes().len() as u32];
        // SAFETY: name pointer, mode and length, as SYS_OPEN expects.
        let handle = unsafe { call(SYS_OPEN, block.as_ptr() as usize) };
        if handle < 0 {
            Err(IoError)
        } else {
            Ok(HostFile(handle as u32))
        }
    }

    /// Writes all of `bytes`.
    // Once, not inlined at each of the report's and the rows' call sites.
    #[inline(never)]
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<(), IoError> {
        if bytes.is_empty() {
            return Ok(());
        }
        let block = [self.0, bytes.as_ptr() as u32, bytes.len() as u32];
        // SAFETY: handle, pointer and length, as SYS_WRITE expects; it returns the bytes NOT written.
        match unsafe { call(SYS_WRITE, block.as_ptr() as usize) } {
            0 => Ok(()),
            _ => Err(IoError),
        }
    }

    /// Closes the file, so the host has all of it.
    pub fn close(self) -> Result<(), IoError> {
        let block = [self.0];
        // SAFETY: a one-word block holding the handle, as SYS_CLOSE expects.
        match unsafe { call(SYS_CLOSE, block.as_ptr() as usize) } {
            0 => Ok(()),
            _ => Err(IoError),
        }
    }
}

/// Text and numbers without `core::fmt`: its formatting machinery (some
/// 5 KiB of flash) stays out of the baked firmware.
impl HostFile {
    /// Writes `s` (errors are the caller's to ignore: there is no one to tell).
    // Once: inlined at the report's 50 call sites it took a kilobyte.
    #[inline(never)]
    pub fn text(&mut self, s: &str) -> &mut HostFile {
        let _ = self.write_all(s.as_bytes());
        self
    }

    /// Writes `n` in decimal.
    // Once, not at each of the report's call sites (opt-level 3 copied it).
    #[inline(never)]
    pub fn num(&mut self, n: u64) -> &mut HostFile {
        // Digits from the last (the micro:bit links a short u64 division:
        // the firmware's runtime.rs).
        let mut buf = [0u8; 20];
        let (mut n, mut i) = (n, buf.len());
        while i > 0 {
            let q = n / 10;
            i -= 1;
            buf[i] = b'0' + (n - q * 10) as u8;
            n = q;
            if n == 0 {
                break;
            }
        }
        let _ = self.write_all(&buf[i..]);
        self
    }

    /// Writes `n` as `0x` and eight hex digits.
    #[inline(never)]
    pub fn hex(&mut self, n: u32) -> &mut HostFile {
        let mut buf = *b"0x00000000";
        for (k, b) in buf[2..].iter_mut().enumerate() {
            let d = (n >> (28 - 4 * k)) & 0xF;
            *b = if d < 10 { b'0' + d as u8 } else { b'a' + d as u8 - 10 };
        }
        let _ = self.write_all(&buf);
        self
    }
}

impl fmt::Write for HostFile {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.write_all(s.as_bytes()).map_err(|_| fmt::Error)
    }
}
