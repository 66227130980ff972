//! The number trait the whole renderer is written over.
//!
//! [`Scalar`] is implemented for [`I16F16`] (Q16.16, the renderer that runs on
//! microcontrollers without an FPU) and for `f32` (the reference that measures
//! what fixed point costs). Everything from the camera to shading is written once
//! over it, so the two renderers differ in their arithmetic and nothing else.
//!
//! The trait is sealed: its contract (saturation, rounding, which operations are
//! exact) is part of the renderer's accuracy analysis, and a third type would
//! need that analysis too.
//!
//! # Rules every implementation follows
//!
//! * No operation panics and none wraps. The Q16.16 operations saturate at the
//!   ends of the range (±32768); a debug build with overflow checks never trips.
//! * Division by zero gives the saturated value of the dividend's sign (0 / 0 is 0).
//! * `sqrt` of a negative number is 0.
//! * Set-up conversions (`from_f64`) round to nearest; they run once per scene.
//! * The Q16.16 per-ray operations use only integer instructions.
//!
//! Files, each importing only those before it (a unit test checks that no
//! file of `src/` imports one that imports it back): `wide` (exact wide
//! integer arithmetic), `q16` (exact Q16.16 rows, directions, rounding),
//! `film` and `plane` (the Q16.16 film map and plane kernels), `scalar` (the
//! trait and its sealed machinery), `fixed` and `float` (the implementations).

pub mod film;
mod fixed;
mod float;
pub(crate) mod plane;
mod q16;
pub(crate) mod quadric;
mod scalar;
#[cfg(lensray_v6m)]
pub(crate) mod thumb1;
pub(crate) mod wide;

pub(crate) use q16::{Decided, CONE, CUBE, CYLINDER, FLAT, HIGH_CAP, LOW_CAP, ROUND, SIDE};
pub use scalar::{BakeScalar, Scalar};
// The unit tests check kernels directly.
#[cfg(test)]
pub(crate) use scalar::Kernels;
