//! The firmware's closing report: one `report key=value ...` line, written
//! without `core::fmt` (the host's `lensray emulate` puts it in words).

use crate::semihosting::HostFile;

/// The report's keys after its head, in the order [`Report::measured`]
/// writes their values: one string walked key by key (a table of string
/// slices, or a call per key, cost the micro:bit's flash more).
const KEYS: &str = " rays= setup= frame= per_pixel= flash= static_ram= peak_stack= stack_overflow= ram= calibration=";

/// What a run measured, and what it ran.
pub struct Report;

impl Report {
    /// Writes the report of a run whose memory `paint` measured; the exit
    /// status: 0 written, 1 not. `head` is the line's fixed start, `report
    /// board=... scene_form=...` (board, number type, f32 square root,
    /// width, height and scene form, set at build time); `setup` and
    /// `frame` are instructions; `calibration` the instructions counted for
    /// a loop of 2,000,000. Here rather than in the firmware crate: run
    /// once, compiled for size (the micro:bit's flash).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub fn measured(
        head: &str,
        (width, height): (u32, u32),
        rays: u32,
        setup: u64,
        frame: u64,
        paint: &crate::stack_paint::Paint,
        calibration: u64,
        console: &mut HostFile,
    ) -> u32 {
        use crate::stack_paint as sp;
        let pixels = width as u64 * height as u64;
        // Instructions a pixel, rounded.
        let per_pixel = (frame + pixels / 2) / pixels.max(1);
        let values = [
            rays as u64,
            setup,
            frame,
            per_pixel,
            sp::flash() as u64,
            sp::static_ram() as u64,
            paint.peak_stack() as u64,
            // The stack ran past its paint: the peak is a lower bound.
            paint.overflowed() as u64,
            sp::ram() as u64,
            calibration,
        ];
        console.text(head);
        let mut keys = KEYS.as_bytes();
        for v in values {
            // Each key runs to its `=`.
            let end = keys.iter().position(|&b| b == b'=').map_or(keys.len(), |i| i + 1);
            let (key, rest) = keys.split_at_checked(end).unwrap_or((keys, &[]));
            let _ = console.write_all(key);
            console.num(v);
            keys = rest;
        }
        console.write_all(b"\n").is_err() as u32
    }
}
