//! The firmware's code that runs once per run: loading and checking the
//! baked scene, the report, the memory measures, the semihosting calls. A
//! crate of its own so that the release profile compiles it for size
//! (`opt-level = "z"`) while the per-pixel code, instantiated in the
//! firmware crate, stays at speed: per-crate opt-levels apply where generic
//! code is instantiated, so the loaders here are concrete per number type,
//! never generic. (The micro:bit's profile compiles everything at "s",
//! which came out smaller than "z" here too.)

#![no_std]

pub mod report;
pub mod semihosting;
pub mod stack_paint;

use lensray::baked::{BakeError, Baked};
use lensray::I16F16;
use semihosting::HostFile;

/// A number type whose baked scenes this crate loads: each method is
/// compiled here, once, for that type.
pub trait Load: lensray::baked::BakeScalar {
    /// An empty scene to load into (`Baked::empty`).
    fn empty() -> Baked<Self>;
    /// `Baked::load`: checks `bytes` and loads them over `loaded`.
    fn load(loaded: &mut Baked<Self>, bytes: &[u8]) -> Result<(), BakeError>;
}

macro_rules! load_for {
    ($($t:ty),*) => {$(
        impl Load for $t {
            #[inline(never)]
            fn empty() -> Baked<Self> {
                Baked::empty()
            }
            #[inline(never)]
            fn load(loaded: &mut Baked<Self>, bytes: &[u8]) -> Result<(), BakeError> {
                loaded.load(bytes)
            }
        }
    )*};
}
load_for!(I16F16, f32);

/// Loads the baked `bytes` into `loaded`, or says on `console` why not:
/// the field for a value out of range, one line for any other fault (the
/// bytes were baked by this build's own library; the host's `lensray bake`
/// names every fault, and seven phrases here cost the micro:bit's flash).
pub fn load_baked<S: Load>(loaded: &mut Baked<S>, bytes: &[u8], name: &str, console: &mut HostFile) -> bool {
    match S::load(loaded, bytes) {
        Ok(()) => true,
        Err(e) => {
            say_load_error(e, name, console);
            false
        }
    }
}

#[inline(never)]
fn say_load_error(e: BakeError, name: &str, console: &mut HostFile) {
    let what = match e {
        BakeError::OutOfRange(field) => field,
        _ => "corrupt, truncated or not this build's",
    };
    console.text(name).text(" (baked): ").text(what).text("\n");
}
