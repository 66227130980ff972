//! lensray on a Raspberry Pi Pico (RP2040, Cortex-M0+ at 125 MHz) with a
//! 240×320 ST7789 SPI panel, driven through `mipidsi`: the paper's Program 1
//! (`scenes/paper-program1.scene`, embedded in flash) is rendered in Q16.16
//! straight to the panel, one scanline at a time, in landscape (320×240).
//! No frame buffer. Progressive display: a preview of 8×8 blocks at one ray
//! each appears within about a second (1/(64 × 8) of the frame's rays), then
//! the library's `progressive::Schedule` refines it in place, block size by
//! block size, down to single pixels at full samples: the last pass leaves
//! exactly what a plain `render_with` would draw. Both cores render: the
//! passes are cut into bands of rows that core 1 takes while it runs and core
//! 0 always; core 0 alone draws on the panel (`two_cores.rs`, `bands.rs`).
//! `emu/` runs this firmware under rp2040js with a model of the panel
//! (`lensray emulate --board pico`).
//!
//! Wiring (Pico pin number, GPIO → panel):
//!
//! ```text
//!   Raspberry Pi Pico                      ST7789 240x320 SPI panel
//!  +--------------------+
//!  | 36  3V3(OUT)       |------------------ VCC
//!  | 38  GND            |------------------ GND
//!  | 24  GP18 SPI0 SCK  |------------------ SCL (SCK, CLK)
//!  | 25  GP19 SPI0 TX   |------------------ SDA (MOSI, DIN)
//!  | 22  GP17           |------------------ CS
//!  | 21  GP16           |------------------ DC  (RS, data/command)
//!  | 26  GP20           |------------------ RES (RST, reset)
//!  | 27  GP21           |------------------ BLK (BL, backlight; high = on)
//!  +--------------------+
//! ```
//!
//! GP22 (pin 29) toggles as core 0 starts each band: a test point for timing.
//! The on-board LED (GP25) is lit while rendering and goes out when the frame
//! is done (the emulator harness, `emu/`, times the frame between the two);
//! it blinks if anything fails. A panic leaves its message in RAM and stops
//! at `bkpt #0x50` with the message's address and length in r0 and r1, which
//! the harness reports (on a board without a debugger the breakpoint becomes
//! a HardFault, which blinks). Build: `cargo build --release` in
//! this directory (target thumbv6m-none-eabi); flash: see README "Flashing the
//! Pico". At 8 rays a pixel the frame takes on the order of a minute (about
//! 0.12 M instructions a pixel, measured on the Cortex-M0 under QEMU).
//!
//! For an ILI9341 panel, use `mipidsi::models::ILI9341Rgb565` in place of
//! `ST7789` (same wiring; drop `invert_colors`).

#![no_std]
#![no_main]

mod bands;
mod two_cores;

use embedded_graphics_core::geometry::Size;
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::OutputPin;
use embedded_hal::digital::StatefulOutputPin;
use embedded_hal_bus::spi::ExclusiveDevice;
use lensray::progressive::Schedule;
use lensray::{Renderer, Scene, I16F16};
use mipidsi::interface::SpiInterface;
use mipidsi::models::ST7789;
use mipidsi::options::{ColorInversion, Orientation, Rotation};
use rp2040_hal::clocks::{init_clocks_and_plls, Clock};
use rp2040_hal::fugit::RateExtU32;
use rp2040_hal::gpio::{FunctionSpi, Pins};
use rp2040_hal::{pac, Sio, Spi, Timer, Watchdog};

/// The second-stage bootloader for the Pico's W25Q080 flash, at the start of flash.
#[link_section = ".boot2"]
#[used]
pub static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_W25Q080;

/// Build-time settings written by build.rs: `SCENE`, `WIDTH`, `HEIGHT`,
/// `SAMPLES` (8 by default: fewer than Program 1's 70, so the frame takes
/// about a minute), `FAULT`.
mod config {
    include!(concat!(env!("OUT_DIR"), "/config.rs"));
}
use config::*;

/// The breakpoint a panic stops at, for the emulator harness ("P").
const PANIC_BKPT: u8 = 0x50;
/// The Pico's crystal.
const XTAL_HZ: u32 = 12_000_000;
/// The ST7789's SPI clock ceiling (its write cycle is 16 ns).
const SPI_HZ: u32 = 62_500_000;

#[rp2040_hal::entry]
fn main() -> ! {
    let Some(mut pac) = pac::Peripherals::take() else {
        halt()
    };
    match FAULT {
        "panic" => panic!("failing on purpose (LENSRAY_FAULT=panic)"),
        // SAFETY: an undefined instruction, to test how a HardFault is reported.
        "hardfault" => unsafe { core::arch::asm!("udf #0") },
        _ => {}
    }
    let mut watchdog = Watchdog::new(pac.WATCHDOG);
    let Ok(clocks) = init_clocks_and_plls(
        XTAL_HZ,
        pac.XOSC,
        pac.CLOCKS,
        pac.PLL_SYS,
        pac.PLL_USB,
        &mut pac.RESETS,
        &mut watchdog,
    ) else {
        halt()
    };
    let sio = Sio::new(pac.SIO);
    let pins = Pins::new(pac.IO_BANK0, pac.PADS_BANK0, sio.gpio_bank0, &mut pac.RESETS);
    let mut timer = Timer::new(pac.TIMER, &mut pac.RESETS, &clocks);
    let mut led = pins.gpio25.into_push_pull_output();

    // SPI0 on GP18 (SCK) and GP19 (TX); the panel only listens.
    let sck = pins.gpio18.into_function::<FunctionSpi>();
    let mosi = pins.gpio19.into_function::<FunctionSpi>();
    let spi = Spi::<_, _, _, 8>::new(pac.SPI0, (mosi, sck)).init(
        &mut pac.RESETS,
        clocks.peripheral_clock.freq(),
        SPI_HZ.Hz(),
        embedded_hal::spi::MODE_3,
    );
    let cs = pins.gpio17.into_push_pull_output();
    let dc = pins.gpio16.into_push_pull_output();
    let rst = pins.gpio20.into_push_pull_output();
    let mut backlight = pins.gpio21.into_push_pull_output();
    // The GPIO chip select cannot fail (its error type is Infallible).
    let Ok(spi) = ExclusiveDevice::new(spi, cs, timer);
    // mipidsi gathers pixels here before each SPI transfer: a row of Rgb565.
    let mut buffer = [0u8; 320 * 2];
    let interface = SpiInterface::new(spi, dc, &mut buffer);
    let Ok(mut display) = mipidsi::Builder::new(ST7789, interface)
        .display_size(240, 320)
        .orientation(Orientation::new().rotate(Rotation::Deg90))
        // Most ST7789 modules need inverted colours to show true ones.
        .invert_colors(ColorInversion::Inverted)
        .reset_pin(rst)
        .init(&mut timer)
    else {
        blink(&mut led, &mut timer)
    };
    let _ = backlight.set_high();

    let (work, own, shadow) = frame_work();
    let _core1 = two_cores::start_core1(work, &pac.PSM, &pac.PPB);
    // GP22 toggles as core 0 starts each band: a test point for timing bands.
    let mut band_marker = pins.gpio22.into_push_pull_output();
    let _ = led.set_high();
    if two_cores::render(work, &mut display, own, shadow, || {
        let _ = band_marker.toggle();
    })
    .is_err()
    {
        blink(&mut led, &mut timer)
    }
    let _ = led.set_low();
    loop {
        cortex_m::asm::wfi();
    }
}

/// The scene parsed in place, the renderer and its bands in statics for both
/// cores, core 0's recorder, and its record of the panel's even pixels.
fn frame_work() -> (
    &'static two_cores::Work<'static>,
    &'static mut bands::Recorder,
    &'static mut bands::Shadow,
) {
    // In a static, for both cores; parsed in place: no second copy of the scene.
    let Some(scene) = cortex_m::singleton!(: Scene<I16F16> = Scene::default()) else {
        halt()
    };
    if let Err(e) = scene.parse_into(SCENE) {
        // build.rs parsed the same bytes, so this cannot happen.
        panic!("scene line {}: {}", e.line, e.kind)
    }
    let scene: &'static Scene<I16F16> = scene;
    // The image in the panel's top-left corner (all of it by default: 320×240).
    let renderer = Renderer::new_with_samples(scene, WIDTH, HEIGHT, Some(SAMPLES));
    // Coarse pass first, then refinements in place (see the module docs), cut
    // into bands that both cores take (two_cores.rs).
    let bands = bands::Bands::new(Schedule::new(8, 1, renderer.rays_per_pixel()), HEIGHT);
    let size = Size::new(WIDTH, HEIGHT);
    let Some(work) = cortex_m::singleton!(: two_cores::Work<'static> = two_cores::Work { renderer, bands, size })
    else {
        halt()
    };
    let work: &'static two_cores::Work<'static> = work;
    let Some(own) = cortex_m::singleton!(: bands::Recorder = bands::Recorder::new(size)) else {
        halt()
    };
    // Core 0's record of the panel's even pixels, for bands sent whole (bands.rs).
    let Some(shadow) = cortex_m::singleton!(: bands::Shadow = bands::Shadow::new(WIDTH)) else {
        halt()
    };
    (work, own, shadow)
}

/// Blinks the LED forever: something failed.
fn blink(led: &mut impl OutputPin, timer: &mut Timer) -> ! {
    loop {
        let _ = led.set_high();
        timer.delay_ms(100);
        let _ = led.set_low();
        timer.delay_ms(100);
    }
}

/// Stops: nothing is set up to show an error with.
fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

/// The last failure's message, for the harness or a debugger to read.
static mut FAILURE: Message = Message { buf: [0; 200], len: 0 };

/// A message that is cut short rather than fail to be written.
struct Message {
    buf: [u8; 200],
    len: usize,
}

impl core::fmt::Write for Message {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let room = self.buf.len() - self.len;
        let n = s.len().min(room);
        self.buf[self.len..self.len + n].copy_from_slice(&s.as_bytes()[..n]);
        self.len += n;
        Ok(())
    }
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    cortex_m::interrupt::disable();
    // SAFETY: interrupts are off and nothing runs after a panic but this.
    let msg = unsafe { &mut *core::ptr::addr_of_mut!(FAILURE) };
    msg.len = 0;
    let _ = core::fmt::write(msg, format_args!("{info}"));
    // SAFETY: a breakpoint; the harness reads r0/r1, a bare board HardFaults.
    unsafe {
        core::arch::asm!("bkpt #{n}", n = const PANIC_BKPT, in("r0") msg.buf.as_ptr(), in("r1") msg.len);
    }
    halt()
}

#[cortex_m_rt::exception]
unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
    // SAFETY: a fault ends the program; nothing else touches the message now.
    let msg = unsafe { &mut *core::ptr::addr_of_mut!(FAILURE) };
    if msg.len == 0 {
        let _ = core::fmt::write(msg, format_args!("HardFault at pc {:#010x}", frame.pc()));
    }
    // The LED on GP25 toggles about twice a second at 125 MHz (no timer needed).
    loop {
        // SAFETY: SIO's XOR alias of GPIO_OUT touches the LED's bit alone.
        unsafe { (*pac::SIO::ptr()).gpio_out_xor().write(|w| w.bits(1 << 25)) };
        cortex_m::asm::delay(30_000_000);
    }
}
