//! Both cores render: bands (see `bands.rs`) are taken in order from one
//! counter under SIO spinlock 0 (the M0+ has no compare-and-swap), by core 1
//! while it runs and by core 0 always; core 1 records each band in the next
//! of [`SLOTS`] recorders in shared RAM and goes on to the next band while
//! core 0 has not drawn it yet, and core 0 alone draws on the panel, keeping
//! the passes in order. If core 1 does not start (rp2040js emulates one
//! core), core 0 takes every band: the picture is the same either way.

use core::sync::atomic::{compiler_fence, AtomicPtr, AtomicU32, Ordering};

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::Size;
use embedded_graphics_core::pixelcolor::Rgb565;
use lensray::progressive::render_pass_row;
use lensray::{Renderer, I16F16};
use rp2040_hal::pac;
use rp2040_hal::sio::Spinlock0;

use crate::bands::{Bands, Recorder, Shadow};

/// What both cores render: set once by core 0 before core 1 starts.
pub struct Work<'a> {
    pub renderer: Renderer<'a, I16F16>,
    pub bands: Bands,
    pub size: Size,
}

/// Core 1's recorders, used in turn: with two, core 1 renders its next band
/// while core 0, busy with a band of its own, has not drawn the last one
/// (with one it waited there, and two cores took 64 % of one core's time).
pub const SLOTS: usize = 2;

/// The next band to take.
static NEXT: AtomicU32 = AtomicU32::new(0);
/// Per slot: 1 + the band core 1 is rendering into it or has not yet handed
/// over; 0 for a free slot.
static SLOT_BAND: [AtomicU32; SLOTS] = [const { AtomicU32::new(0) }; SLOTS];
/// Per slot: 1 when its recorder holds its band, ready to draw.
static SLOT_READY: [AtomicU32; SLOTS] = [const { AtomicU32::new(0) }; SLOTS];
/// The work, for core 1 (a `Work` that outlives `main`, which never returns).
static WORK: AtomicPtr<()> = AtomicPtr::new(core::ptr::null_mut());
/// Core 1's bands, recorded for core 0 to draw.
static mut CORE1_RECORDERS: [Recorder; SLOTS] = [const { Recorder::new(Size::zero()) }; SLOTS];
/// Core 1's stack: rendering needs a few KiB.
static mut CORE1_STACK: [u64; 2048] = [0; 2048];

/// Takes the next band; `slot`, where given, marks it as core 1's in that
/// slot under the same lock, so that core 0 never takes a later band
/// without seeing it.
fn take(bands: &Bands, slot: Option<usize>) -> Option<u32> {
    let _lock = Spinlock0::claim();
    let k = NEXT.load(Ordering::Relaxed);
    if k >= bands.len() {
        return None;
    }
    NEXT.store(k + 1, Ordering::Relaxed);
    if let Some(band) = slot.and_then(|i| SLOT_BAND.get(i)) {
        band.store(k + 1, Ordering::Relaxed);
    }
    Some(k)
}

/// Core 1: takes bands while there are any, into its slots in turn, each
/// slot free (drawn by core 0) before it is used again.
extern "C" fn core1_main() -> ! {
    // SAFETY: core 0 stored a `Work` that lives for ever before starting this core.
    let work = unsafe { &*(WORK.load(Ordering::Acquire) as *const Work<'static>) };
    let mut slot = 0;
    loop {
        while SLOT_BAND[slot].load(Ordering::Acquire) != 0 {
            cortex_m::asm::nop();
        }
        let Some(k) = take(&work.bands, Some(slot)) else { break };
        // SAFETY: core 0 reads a slot's recorder only while its SLOT_READY is
        // 1, and this core writes it only between taking the slot (its
        // SLOT_BAND was 0) and setting SLOT_READY.
        let recorder = unsafe { &mut (*core::ptr::addr_of_mut!(CORE1_RECORDERS))[slot] };
        if let Some(band) = work.bands.get(k) {
            recorder.clear();
            // A band too large for the recorder is drawn short; bands.rs's tests rule that out.
            let _ = render_pass_row(&work.renderer, recorder, &band.pass, band.row);
        }
        SLOT_READY[slot].store(1, Ordering::Release);
        slot = (slot + 1) % SLOTS;
    }
    loop {
        cortex_m::asm::wfe();
    }
}

/// Draws core 1's bands in the order it took them (from slot `*next`): each
/// of a pass before `pass_index` (waiting for it to be recorded), and each
/// already recorded and not of a later pass.
fn take_over_core1<D: DrawTarget<Color = Rgb565>>(
    work: &Work,
    (display, shadow): (&mut D, &mut Shadow),
    pass_index: usize,
    next: &mut usize,
) -> Result<(), D::Error> {
    loop {
        let b = SLOT_BAND[*next].load(Ordering::Acquire);
        if b == 0 {
            return Ok(());
        }
        let its_pass = work.bands.get(b - 1).map_or(0, |band| band.pass_index);
        let ready = SLOT_READY[*next].load(Ordering::Acquire) == 1;
        if its_pass > pass_index || (its_pass == pass_index && !ready) {
            return Ok(());
        }
        if ready {
            // SAFETY: SLOT_READY is 1: core 1 is done writing this slot and
            // will not touch it before its SLOT_BAND clears.
            let recorder = unsafe { &(*core::ptr::addr_of!(CORE1_RECORDERS))[*next] };
            let drawn = recorder.replay(display, shadow);
            SLOT_READY[*next].store(0, Ordering::Relaxed);
            SLOT_BAND[*next].store(0, Ordering::Release);
            *next = (*next + 1) % SLOTS;
            drawn?;
        }
    }
}

/// Renders every band on this core and on core 1 if it runs, drawing all on
/// `display`, whose even pixels `shadow` keeps (`Recorder::replay`).
/// `marker` toggles at each band this core starts, for the harness's per-band timing.
pub fn render<D: DrawTarget<Color = Rgb565>>(
    work: &'static Work<'static>,
    display: &mut D,
    own: &mut Recorder,
    shadow: &mut Shadow,
    mut marker: impl FnMut(),
) -> Result<(), D::Error> {
    let mut next = 0;
    while let Some(k) = take(&work.bands, None) {
        marker();
        let Some(band) = work.bands.get(k) else { break };
        own.clear();
        let _ = render_pass_row(&work.renderer, own, &band.pass, band.row);
        // Every band of an earlier pass is drawn before this one.
        take_over_core1(work, (display, shadow), band.pass_index, &mut next)?;
        own.replay(display, shadow)?;
    }
    marker();
    // Core 1's last bands, whatever their pass.
    take_over_core1(work, (display, shadow), usize::MAX, &mut next)
}

/// Starts core 1 on `work` through the boot ROM's handshake (RP2040 datasheet
/// 2.8.2), each step bounded: true if core 1 answered, false if no core 1
/// did (as under rp2040js), and then core 0 renders alone.
pub fn start_core1(work: &'static Work<'static>, psm: &pac::PSM, ppb: &pac::PPB) -> bool {
    // SAFETY: only the FIFO registers, which nothing else on core 0 uses.
    let sio = unsafe { &*pac::SIO::ptr() };
    // SAFETY: core 1 is not running yet.
    for recorder in unsafe { &mut *core::ptr::addr_of_mut!(CORE1_RECORDERS) } {
        *recorder = Recorder::new(work.size);
    }
    WORK.store(work as *const Work as *mut (), Ordering::Release);
    psm.frce_off().modify(|_, w| w.proc1().set_bit());
    while !psm.frce_off().read().proc1().bit_is_set() {
        cortex_m::asm::nop();
    }
    psm.frce_off().modify(|_, w| w.proc1().clear_bit());
    let stack = core::ptr::addr_of_mut!(CORE1_STACK);
    // SAFETY: one past the end of the stack array, its top (8-byte aligned: u64s).
    let stack_top = unsafe { (stack as *mut u64).add(2048) } as u32;
    compiler_fence(Ordering::Release);
    let commands = [
        0,
        0,
        1,
        ppb.vtor().read().bits(),
        stack_top,
        core1_main as *const () as usize as u32,
    ];
    let mut seq = 0;
    let mut fails = 0;
    while seq < commands.len() {
        let cmd = commands[seq];
        if cmd == 0 {
            while sio.fifo_st().read().vld().bit_is_set() {
                let _ = sio.fifo_rd().read();
            }
            cortex_m::asm::sev();
        }
        if !wait(|| sio.fifo_st().read().rdy().bit_is_set()) {
            return false;
        }
        // SAFETY: any word may be written to the FIFO.
        sio.fifo_wr().write(|w| unsafe { w.bits(cmd) });
        cortex_m::asm::sev();
        if !wait(|| sio.fifo_st().read().vld().bit_is_set()) {
            return false;
        }
        if sio.fifo_rd().read().bits() == cmd {
            seq += 1;
        } else {
            seq = 0;
            fails += 1;
            if fails > 8 {
                return false;
            }
        }
    }
    true
}

/// Polls `ready` for about a millisecond at 125 MHz: the boot ROM on core 1 answers within microseconds.
fn wait(mut ready: impl FnMut() -> bool) -> bool {
    for _ in 0..20_000 {
        if ready() {
            return true;
        }
    }
    false
}
