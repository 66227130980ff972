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
use lensray::{Renderer, I16F16};
use semihosting::HostFile;

/// A number type whose baked scenes this crate loads: each method is
/// compiled here, once, for that type.
pub trait Load: lensray::baked::BakeScalar {
    /// An empty scene to load into (`Baked::empty`).
    fn empty() -> Baked<Self>;
    /// `Baked::load`: checks `bytes` and loads them over `loaded`.
    fn load(loaded: &mut Baked<Self>, bytes: &[u8]) -> Result<(), BakeError>;
    /// `Baked::take_renderer`.
    fn take_renderer(loaded: &mut Baked<Self>) -> Renderer<'_, Self>;
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
            #[inline(never)]
            fn take_renderer(loaded: &mut Baked<Self>) -> Renderer<'_, Self> {
                loaded.take_renderer()
            }
        }
    )*};
}
load_for!(I16F16, f32);

/// Loads the baked `bytes` into `loaded`, or says on `console` why not
/// (named without `core::fmt`: the host's `lensray bake` gives the details).
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
    use BakeError as E;
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
    console.text(name).text(" (baked): ").text(what).text("\n");
}
