//! lensray's firmware for QEMU's `microbit` (Cortex-M0), `mps2-an385`
//! (Cortex-M3), `mps2-an386` (Cortex-M4F) and `sifive_e` (RV32IMAC) machines.
//!
//! It loads a scene baked at build time into flash (`lensray::baked`; with
//! the feature `parse-on-device` it parses the scene's text instead), renders it one scanline at a time into
//! a `DrawTarget` that sends each finished row to the host over semihosting
//! (the file `lensray-rows.rgb` in QEMU's working directory), reports the
//! instructions it took (run under `-icount shift=0`) and its memory use, and
//! exits with status 0. Any error exits non-zero: 1 for the host's file calls,
//! 2 for a bad scene, 3 for a HardFault, 4 for an unexpected interrupt, 5 for a
//! Thumb-1 kernel that differs from the portable Rust (`LENSRAY_CHECK`), 101 for
//! a panic. It never waits for anything, so it never hangs.
//!
//! The scene, image size, sample count and number type are fixed at build
//! time (see build.rs); `lensray emulate` sets them for you. Every board
//! renders through the library's one code path, exactly what the host
//! renders; the micro:bit is built with its own profile, for size, and its
//! own short runtime routines (runtime.rs), to keep its default build within
//! 40 KiB of flash.

#![no_std]
#![no_main]

mod instruction_count;
#[cfg(feature = "profile")]
mod profile;
#[cfg(target_arch = "riscv32")]
mod riscv_start;
mod row_file;
#[cfg(feature = "microbit")]
mod runtime;

#[cfg(feature = "parse-on-device")]
use core::fmt::Write;
#[cfg(target_arch = "arm")]
use cortex_m_rt::{entry, exception, ExceptionFrame};
#[cfg(feature = "profile")]
use lensray::Scalar;
#[cfg(feature = "parse-on-device")]
use lensray::Scene;
use lensray::{render_with, Renderer};
use lensray_firmware_cold::report::Report;
use lensray_firmware_cold::semihosting::{self, exit, HostFile};
use lensray_firmware_cold::stack_paint;
use row_file::RowFile;

/// Build-time settings written by build.rs: `BOARD`, `SCENE`, `SCENE_NAME`,
/// `WIDTH`, `HEIGHT`, `SAMPLES`, `Number`, `FAULT`, `REPORT_HEAD`.
#[allow(dead_code)] // SAMPLES is baked in unless the scene is parsed on the device; BOARD is the profile's.
mod config {
    include!(concat!(env!("OUT_DIR"), "/config.rs"));
}
use config::*;

/// The file on the host that receives the rows.
const ROWS_FILE: &core::ffi::CStr = c"lensray-rows.rgb";
/// Bytes of one row: 3 per pixel.
const ROW_BYTES: usize = WIDTH as usize * 3;
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
    lensray_firmware_cold::load_baked(loaded, SCENE, SCENE_NAME, console)
}

/// The renderer of a loaded scene, with the build's sample override.
#[cfg(feature = "parse-on-device")]
fn renderer(loaded: &Loaded) -> Renderer<'_, Number> {
    Renderer::new_with_samples(loaded, WIDTH, HEIGHT, SAMPLES)
}

/// The renderer of a loaded scene (size and samples were baked in), lent
/// its camera and lens cones: no second copy of them on the stack.
#[cfg(not(feature = "parse-on-device"))]
fn renderer(loaded: &mut Loaded) -> Renderer<'_, Number, &lensray::baked::Setup<Number>> {
    loaded.lend()
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
    if CHECK_KERNELS {
        check_kernels(&mut console);
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
            console.text("cannot create lensray-rows.rgb on the host\n");
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

    let rays = renderer.rays_per_pixel();
    report(&paint, &mut console, rays, [t0, t1, t2, t3], calibration)
}

/// Runs the library's Thumb-1 kernels against its portable Rust on the
/// board (`LENSRAY_CHECK=kernels`); exits 5 at the first pair that differs.
#[inline(never)]
fn check_kernels(console: &mut HostFile) {
    const PAIRS: u32 = 100_000;
    if let Some((kernel, a, b)) = lensray::check_thumb1_kernels(PAIRS) {
        console.text(kernel).text(" differs from the portable Rust at ");
        let sign = |x: i64| if x < 0 { "-" } else { "" };
        console.text(sign(a)).num(a.unsigned_abs()).text(", ");
        console.text(sign(b)).num(b.unsigned_abs()).text("\n");
        exit(5)
    }
    console
        .text("kernels match the portable Rust on ")
        .num(PAIRS as u64)
        .text(" pairs\n");
}

/// Writes the report and exits; out of line, so that the report's values
/// are not held in `main`'s frame under the whole render.
#[inline(never)]
fn report(paint: &stack_paint::Paint, console: &mut HostFile, rays: u32, ticks: [u64; 4], calibration: u64) -> ! {
    let [t0, t1, t2, t3] = ticks;
    let setup = instruction_count::instructions(t1 - t0);
    let frame = instruction_count::instructions(t3 - t2);
    exit(Report::measured(
        REPORT_HEAD,
        (WIDTH, HEIGHT),
        rays,
        setup,
        frame,
        paint,
        calibration,
        console,
    ))
}

#[cfg(feature = "parse-on-device")]
fn new_loaded() -> Loaded {
    Scene::default()
}

#[cfg(not(feature = "parse-on-device"))]
fn new_loaded() -> Loaded {
    <Number as lensray_firmware_cold::Load>::empty()
}

#[cfg(target_arch = "arm")]
#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    if let Ok(mut console) = HostFile::console() {
        console.text("HardFault at pc ").hex(frame.pc()).text("\n");
    }
    exit(3)
}

/// The interrupt vectors after the exceptions': one, the fewest cortex-m-rt's
/// link.x accepts. The firmware enables no interrupt (only the SysTick
/// exception), and the 31 more a Cortex-M0 may have cost 124 bytes of flash.
#[cfg(target_arch = "arm")]
#[link_section = ".vector_table.interrupts"]
#[no_mangle]
static __INTERRUPTS: [unsafe extern "C" fn(); 1] = [DefaultHandler];

#[cfg(target_arch = "arm")]
extern "C" {
    /// The handler `#[exception] DefaultHandler` below defines.
    fn DefaultHandler();
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
