//! lensray's firmware for QEMU's `microbit` (Cortex-M0) and `mps2-an386`
//! (Cortex-M4F) machines.
//!
//! It parses a scene embedded in flash, renders it one scanline at a time into
//! a `DrawTarget` that sends each finished row to the host over semihosting
//! (the file `lensray-rows.rgb` in QEMU's working directory), reports the
//! instructions it took (run under `-icount shift=0`) and its memory use, and
//! exits with status 0. Any error exits non-zero: 1 for the host's file calls,
//! 2 for a bad scene, 3 for a HardFault, 4 for an unexpected interrupt, 101 for
//! a panic. It never waits for anything, so it never hangs.
//!
//! The scene, image size, sample count and number type are fixed at build
//! time (see build.rs); `lensray emulate` sets them for you.

#![no_std]
#![no_main]

mod instruction_count;
mod row_file;
mod semihosting;
mod stack_paint;

use core::fmt::Write;
use cortex_m_rt::{entry, exception, ExceptionFrame};
use lensray::{render_with, Renderer, Scalar, Scene};
use row_file::RowFile;
use semihosting::{exit, HostFile};

/// Build-time settings written by build.rs: `BOARD`, `SCENE`, `SCENE_NAME`,
/// `WIDTH`, `HEIGHT`, `SAMPLES`, `Number`, `FAULT`.
mod config {
    include!(concat!(env!("OUT_DIR"), "/config.rs"));
}
use config::*;

/// The file on the host that receives the rows.
const ROWS_FILE: &str = "lensray-rows.rgb";
/// Bytes of one row: 3 per pixel.
const ROW_BYTES: usize = WIDTH as usize * 3;
/// How the f32 renderer takes square roots, for the report.
const SQRT: &str = if cfg!(feature = "hw-sqrt") { "vsqrt.f32" } else { "libm" };
/// The square root, as the report's first line shows it for f32.
const SQRT_NOTE: &str = if cfg!(feature = "hw-sqrt") {
    " (sqrt: vsqrt.f32)"
} else {
    " (sqrt: libm)"
};
/// The core, for the report.
const CORE: &str = if cfg!(feature = "microbit") {
    "Cortex-M0"
} else {
    "Cortex-M4F"
};

#[entry]
fn main() -> ! {
    let paint = stack_paint::paint();
    let Ok(mut console) = HostFile::console() else { exit(1) };
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        exit(1)
    };
    match FAULT {
        "panic" => panic!("failing on purpose (LENSRAY_FAULT=panic)"),
        // SAFETY: an undefined instruction, to test the HardFault handler.
        "hardfault" => unsafe { core::arch::asm!("udf #0") },
        _ => {}
    }
    let counter = instruction_count::Counter::start(peripherals.SYST);

    let calibration = counter.calibrate();
    let t0 = counter.ticks();
    let scene = match Scene::<Number>::parse_bytes(SCENE) {
        Ok(s) => s,
        Err(e) => {
            let _ = writeln!(console, "{SCENE_NAME}:{}: {}", e.line, e.kind);
            exit(2)
        }
    };
    let mut renderer = Renderer::new(&scene, WIDTH, HEIGHT);
    if let Some(n) = SAMPLES {
        renderer = renderer.with_samples(n);
    }
    let t1 = counter.ticks();

    let mut rows = match RowFile::<ROW_BYTES>::create(ROWS_FILE, HEIGHT) {
        Ok(r) => r,
        Err(e) => {
            let _ = writeln!(console, "cannot create {ROWS_FILE} on the host: {e:?}");
            exit(1)
        }
    };
    let t2 = counter.ticks();
    let rendered = render_with(&renderer, &mut rows);
    let t3 = counter.ticks();
    let sent = rows.rows_sent();
    if let Err(e) = rendered.and_then(|()| rows.close()) {
        let _ = writeln!(console, "sending row {sent} failed: {e:?}");
        exit(1)
    }

    let setup = instruction_count::instructions(t1 - t0);
    let frame = instruction_count::instructions(t3 - t2);
    let pixels = WIDTH as u64 * HEIGHT as u64;
    let per_pixel = (frame + pixels / 2) / pixels;
    let rays = renderer.rays_per_pixel();
    let report = writeln!(
        console,
        "board {BOARD} ({CORE}), {}{}, scene {SCENE_NAME}, {WIDTH}x{HEIGHT}, {rays} rays per pixel\n\
         set-up: {setup} instructions\n\
         frame: {frame} instructions, {per_pixel} instructions per pixel\n\
         memory: flash {} bytes, static RAM {} bytes, peak stack {} bytes{}, RAM {} bytes\n\
         report board={BOARD} number={} f32_sqrt={SQRT} width={WIDTH} height={HEIGHT} rays={rays} setup={setup} frame={frame} \
         per_pixel={per_pixel} flash={} static_ram={} peak_stack={} stack_overflow={} ram={} \
         calibration={calibration}",
        Number::NAME,
        if Number::NAME == "f32" { SQRT_NOTE } else { "" },
        stack_paint::flash(),
        stack_paint::static_ram(),
        paint.peak_stack(),
        if paint.overflowed() { " (or more: the paint is gone)" } else { "" },
        stack_paint::ram(),
        Number::NAME,
        stack_paint::flash(),
        stack_paint::static_ram(),
        paint.peak_stack(),
        paint.overflowed() as u8,
        stack_paint::ram(),
    );
    exit(if report.is_ok() { 0 } else { 1 })
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    if let Ok(mut console) = HostFile::console() {
        let _ = writeln!(console, "HardFault at pc {:#010x}", frame.pc());
    }
    exit(3)
}

#[exception]
unsafe fn DefaultHandler(irq: i16) {
    if let Ok(mut console) = HostFile::console() {
        let _ = writeln!(console, "unexpected exception or interrupt {irq}");
    }
    exit(4)
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    if let Ok(mut console) = HostFile::console() {
        let _ = writeln!(console, "{info}");
    }
    exit(101)
}
