//! lensray's firmware for QEMU's `microbit` (Cortex-M0), `mps2-an385`
//! (Cortex-M3), `mps2-an386` (Cortex-M4F) and `sifive_e` (RV32IMAC) machines.
//!
//! It loads a scene baked at build time into flash (`lensray::baked`; with
//! the feature `parse-on-device` it parses the scene's text instead), renders it one scanline at a time into
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
#[cfg(feature = "profile")]
mod profile;
#[cfg(target_arch = "riscv32")]
mod riscv_start;
mod row_file;
mod semihosting;
mod stack_paint;

#[cfg(feature = "parse-on-device")]
use core::fmt::Write;
#[cfg(target_arch = "arm")]
use cortex_m_rt::{entry, exception, ExceptionFrame};
#[cfg(feature = "parse-on-device")]
use lensray::Scene;
use lensray::{render_with, Renderer, Scalar};
use row_file::RowFile;
use semihosting::{exit, HostFile};

/// Build-time settings written by build.rs: `BOARD`, `SCENE`, `SCENE_NAME`,
/// `WIDTH`, `HEIGHT`, `SAMPLES`, `Number`, `FAULT`.
#[allow(dead_code)] // SAMPLES is baked in unless the scene is parsed on the device.
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
} else if cfg!(feature = "mps2-an385") {
    "Cortex-M3"
} else if cfg!(feature = "sifive-e") {
    "RV32IMAC"
} else {
    "Cortex-M4F"
};
/// How the scene reached the renderer, for the report.
const SCENE_FORM: &str = if cfg!(feature = "parse-on-device") {
    "parsed"
} else {
    "baked"
};

/// The scene, ready to render: parsed on the device from its text.
#[cfg(feature = "parse-on-device")]
type Loaded = Scene<Number>;
/// The scene, ready to render: loaded from its baked form.
#[cfg(not(feature = "parse-on-device"))]
type Loaded = lensray::baked::Baked<Number>;

/// Fills `loaded` from the embedded scene, in place; a message on failure.
#[cfg(feature = "parse-on-device")]
fn load(loaded: &mut Loaded, console: &mut HostFile) -> bool {
    match loaded.parse_into(SCENE) {
        Ok(()) => true,
        Err(e) => {
            let _ = writeln!(console, "{SCENE_NAME}:{}: {}", e.line, e.kind);
            false
        }
    }
}

/// Fills `loaded` from the embedded scene, in place; a message on failure.
#[cfg(not(feature = "parse-on-device"))]
fn load(loaded: &mut Loaded, console: &mut HostFile) -> bool {
    use lensray::baked::BakeError as E;
    match loaded.load(SCENE) {
        Ok(()) => true,
        Err(e) => {
            // Named without `core::fmt` (the host's `lensray bake` gives the details).
            let what = match e {
                E::Truncated { .. } => "truncated",
                E::TrailingBytes { .. } => "bytes past its length",
                E::ForeignMagic => "not a baked lensray scene",
                E::Version { .. } => "another format version",
                E::NumberType { .. } => "baked for the other number type",
                E::Checksum => "checksum mismatch: corrupted",
                E::OutOfRange(field) => field,
                _ => "bad payload",
            };
            console.text(SCENE_NAME).text(" (baked): ").text(what).text("\n");
            false
        }
    }
}

/// The renderer of a loaded scene, with the build's sample override.
#[cfg(feature = "parse-on-device")]
fn renderer(loaded: &Loaded) -> Renderer<'_, Number> {
    Renderer::new_with_samples(loaded, WIDTH, HEIGHT, SAMPLES)
}

/// The renderer of a loaded scene (size and samples were baked in), moving
/// its cones and footprints out rather than copying them.
#[cfg(not(feature = "parse-on-device"))]
fn renderer(loaded: &mut Loaded) -> Renderer<'_, Number> {
    loaded.take_renderer()
}

/// The instruction counter: SysTick on Arm.
#[cfg(target_arch = "arm")]
fn counter() -> instruction_count::Counter {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        exit(1)
    };
    instruction_count::Counter::start(peripherals.SYST)
}

/// The instruction counter: `mcycle` on RISC-V.
#[cfg(target_arch = "riscv32")]
fn counter() -> instruction_count::Counter {
    instruction_count::Counter::start()
}

/// Executes an undefined instruction, to test the fault handler.
fn fault() {
    // SAFETY: faults on purpose; the handler exits.
    #[cfg(target_arch = "arm")]
    unsafe {
        core::arch::asm!("udf #0")
    };
    // SAFETY: as above.
    #[cfg(target_arch = "riscv32")]
    unsafe {
        core::arch::asm!("unimp")
    };
}

#[cfg_attr(target_arch = "arm", entry)]
fn main() -> ! {
    let paint = stack_paint::paint();
    let Ok(mut console) = HostFile::console() else { exit(1) };
    match FAULT {
        "panic" => panic!("failing on purpose (LENSRAY_FAULT=panic)"),
        "hardfault" => fault(),
        _ => {}
    }
    let counter = counter();

    #[cfg(feature = "profile")]
    {
        let mut scene = Scene::<Number>::default();
        if scene.parse_into(SCENE).is_err() {
            exit(2)
        }
        let _ = writeln!(
            console,
            "profile board={BOARD} number={} scene={SCENE_NAME} width={WIDTH} height={HEIGHT}",
            Number::NAME
        );
        profile::run(&mut scene, WIDTH, HEIGHT, SAMPLES, &counter, &mut console);
        let _ = writeln!(console, "profile-stack peak_stack={}", paint.peak_stack());
        exit(0)
    }
    #[allow(unreachable_code)]
    let calibration = counter.calibrate();
    let t0 = counter.ticks();
    // Loaded in place: returning a scene by value would need a second copy on the stack.
    let mut loaded = new_loaded();
    if !load(&mut loaded, &mut console) {
        exit(2)
    }
    #[cfg_attr(feature = "parse-on-device", allow(clippy::unnecessary_mut_passed))]
    let renderer = renderer(&mut loaded);
    let t1 = counter.ticks();

    let mut rows = match RowFile::<ROW_BYTES>::create(ROWS_FILE, HEIGHT) {
        Ok(r) => r,
        Err(_) => {
            console.text("cannot create ").text(ROWS_FILE).text(" on the host\n");
            exit(1)
        }
    };
    let t2 = counter.ticks();
    let rendered = render_with(&renderer, &mut rows);
    let t3 = counter.ticks();
    let sent = rows.rows_sent();
    if rendered.and_then(|()| rows.close()).is_err() {
        console.text("sending row ").num(sent as u64).text(" failed\n");
        exit(1)
    }

    let setup = instruction_count::instructions(t1 - t0);
    let frame = instruction_count::instructions(t3 - t2);
    let pixels = WIDTH as u64 * HEIGHT as u64;
    let per_pixel = div_u64(frame + pixels / 2, pixels);
    let rays = renderer.rays_per_pixel();
    let (flash, static_ram, peak, ram) = (
        stack_paint::flash() as u64,
        stack_paint::static_ram() as u64,
        paint.peak_stack() as u64,
        stack_paint::ram() as u64,
    );
    let f32_note = if Number::NAME == "f32" { SQRT_NOTE } else { "" };
    let overflow_note = if paint.overflowed() {
        " (or more: the paint is gone)"
    } else {
        ""
    };
    // Written piece by piece, without `core::fmt` (see HostFile::text).
    let c = &mut console;
    c.text("board ")
        .text(BOARD)
        .text(" (")
        .text(CORE)
        .text("), ")
        .text(Number::NAME)
        .text(f32_note);
    c.text(", scene ")
        .text(SCENE_NAME)
        .text(" (")
        .text(SCENE_FORM)
        .text("), ");
    c.num(WIDTH as u64)
        .text("x")
        .num(HEIGHT as u64)
        .text(", ")
        .num(rays as u64)
        .text(" rays per pixel\n");
    c.text("set-up: ").num(setup).text(" instructions\n");
    c.text("frame: ")
        .num(frame)
        .text(" instructions, ")
        .num(per_pixel)
        .text(" instructions per pixel\n");
    c.text("memory: flash ")
        .num(flash)
        .text(" bytes, static RAM ")
        .num(static_ram);
    c.text(" bytes, peak stack ")
        .num(peak)
        .text(" bytes")
        .text(overflow_note)
        .text(", RAM ")
        .num(ram)
        .text(" bytes\n");
    c.text("report board=")
        .text(BOARD)
        .text(" number=")
        .text(Number::NAME)
        .text(" f32_sqrt=")
        .text(SQRT);
    c.text(" width=")
        .num(WIDTH as u64)
        .text(" height=")
        .num(HEIGHT as u64)
        .text(" rays=")
        .num(rays as u64);
    c.text(" scene_form=")
        .text(SCENE_FORM)
        .text(" setup=")
        .num(setup)
        .text(" frame=")
        .num(frame);
    c.text(" per_pixel=")
        .num(per_pixel)
        .text(" flash=")
        .num(flash)
        .text(" static_ram=")
        .num(static_ram);
    c.text(" peak_stack=")
        .num(peak)
        .text(" stack_overflow=")
        .num(paint.overflowed() as u64)
        .text(" ram=")
        .num(ram);
    let report = c.text(" calibration=").num(calibration).write_all(b"\n");
    exit(if report.is_ok() { 0 } else { 1 })
}

/// `n / d` for `d > 0`, bit by bit: the runtime's `u64 / u64` is a kilobyte
/// of the Cortex-M0's flash, for one division in the report.
fn div_u64(n: u64, d: u64) -> u64 {
    let (mut n, mut q, mut r) = (n, 0u64, 0u64);
    // Shifts by one only (a variable u64 shift is a call on the M0).
    for _ in 0..64 {
        // r < d before the shift: no bit is lost while d < 2^63.
        r = (r << 1) | (n >> 63);
        n <<= 1;
        q <<= 1;
        if r >= d {
            r -= d;
            q |= 1;
        }
    }
    q
}

#[cfg(feature = "parse-on-device")]
fn new_loaded() -> Loaded {
    Scene::default()
}

#[cfg(not(feature = "parse-on-device"))]
fn new_loaded() -> Loaded {
    Loaded::empty()
}

#[cfg(target_arch = "arm")]
#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    if let Ok(mut console) = HostFile::console() {
        console.text("HardFault at pc ").hex(frame.pc()).text("\n");
    }
    exit(3)
}

#[cfg(target_arch = "arm")]
#[exception]
unsafe fn DefaultHandler(irq: i16) {
    if let Ok(mut console) = HostFile::console() {
        console
            .text("unexpected exception or interrupt ")
            .num(irq as u64)
            .text("\n");
    }
    exit(4)
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    // The location and a literal message, without `core::fmt` (a formatted
    // message shows its template only).
    if let Ok(mut console) = HostFile::console() {
        console.text("panicked");
        if let Some(l) = info.location() {
            console.text(" at ").text(l.file()).text(":").num(l.line() as u64);
        }
        let m = info.message();
        console
            .text(": ")
            .text(m.as_str().unwrap_or("(formatted message)"))
            .text("\n");
    }
    exit(101)
}
