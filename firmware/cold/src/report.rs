//! The firmware's closing report: one `report key=value ...` line, written
//! without `core::fmt` (the host's `lensray emulate` puts it in words).

use crate::semihosting::{HostFile, IoError};

/// What a run measured, and what it ran.
pub struct Report<'a> {
    /// The line's fixed start, `report board=... scene_form=...`: board,
    /// number type, f32 square root, width, height and scene form, set at
    /// build time.
    pub head: &'a str,
    pub width: u32,
    pub height: u32,
    pub rays: u32,
    /// Instructions of the set-up and of the frame.
    pub setup: u64,
    pub frame: u64,
    /// Bytes.
    pub flash: u64,
    pub static_ram: u64,
    pub peak_stack: u64,
    /// The stack ran past its paint: the peak is a lower bound.
    pub overflowed: bool,
    pub ram: u64,
    /// Instructions counted for a loop of 2,000,000.
    pub calibration: u64,
}

impl<'a> Report<'a> {
    /// Writes the report of a run whose memory `paint` measured; the exit
    /// status: 0 written, 1 not. Here rather than in the firmware crate: run
    /// once, compiled for size (the micro:bit's flash).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub fn measured(
        head: &'a str,
        size: (u32, u32),
        rays: u32,
        setup: u64,
        frame: u64,
        paint: &crate::stack_paint::Paint,
        calibration: u64,
        console: &mut HostFile,
    ) -> u32 {
        use crate::stack_paint as sp;
        let report = Report {
            head,
            width: size.0,
            height: size.1,
            rays,
            setup,
            frame,
            flash: sp::flash() as u64,
            static_ram: sp::static_ram() as u64,
            peak_stack: paint.peak_stack() as u64,
            overflowed: paint.overflowed(),
            ram: sp::ram() as u64,
            calibration,
        };
        report.write(console).is_err() as u32
    }

    /// Instructions a pixel, rounded.
    pub fn per_pixel(&self) -> u64 {
        let pixels = self.width as u64 * self.height as u64;
        (self.frame + pixels / 2) / pixels.max(1)
    }

    /// Writes the report to `c`.
    pub fn write(&self, c: &mut HostFile) -> Result<(), IoError> {
        let per_pixel = self.per_pixel();
        c.text(self.head).text(" rays=").num(self.rays as u64);
        c.text(" setup=").num(self.setup).text(" frame=").num(self.frame);
        c.text(" per_pixel=")
            .num(per_pixel)
            .text(" flash=")
            .num(self.flash)
            .text(" static_ram=")
            .num(self.static_ram);
        c.text(" peak_stack=")
            .num(self.peak_stack)
            .text(" stack_overflow=")
            .num(self.overflowed as u64)
            .text(" ram=")
            .num(self.ram);
        c.text(" calibration=").num(self.calibration).write_all(b"\n")
    }
}
