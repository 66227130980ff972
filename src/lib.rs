//! # lensray
//!
//! A ray tracer with a real camera lens, for microcontroller display boards.
//!
//! lensray implements the thin-lens model of Hartanto and Rosalina's paper
//! "Simulating the effect of camera lens in computer generated picture": every
//! pixel's film point sends several rays through random points of the lens,
//! all aimed at the point where its chief ray meets the plane in focus, and
//! averages them. Objects on that plane come out sharp, the others blurred.
//!
//! * `no_std`, no allocator: fixed-capacity scenes ([`MAX_OBJECTS`],
//!   [`MAX_LIGHTS`]), rendering one scanline at a time with no frame buffer.
//! * One algorithm over the [`Scalar`] trait, in two number types: Q16.16
//!   ([`I16F16`], integer instructions only on the per-ray path) and `f32`
//!   (the reference that measures what fixed point costs).
//! * Lens samples from an integer LFSR ([`lfsr`]), identical for both number
//!   types and dependent only on the pixel.
//! * Scenes in the paper's plain-text format ([`Scene::parse`]); bad input gives
//!   a [`ParseError`] naming the line, never a panic.
//! * No entry point panics, whatever the input, scene or target size: the
//!   parser, [`render()`], [`render_with`] and [`Renderer`] document
//!   `# Panics: Never`, and the host tests fuzz them and sweep target sizes
//!   (README, "Robustness").
//!
//! ## Rendering into a display
//!
//! Any `DrawTarget` whose colour converts from `Rgb888` will do; the image
//! is the target's bounding box. Here embedded-graphics' 64×64 `MockDisplay`
//! of Rgb565 stands in for a panel:
//!
//! ```
//! use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565, prelude::*};
//! use lensray::{render, I16F16, Scene};
//!
//! // A red sphere lit by white ambient light, seen head-on by a pinhole camera.
//! let scene = Scene::<I16F16>::parse(
//!     "ambient_light 1 1 1\nobject sphere\nKa 1 0 0\ntranslate 0 0 -8\n",
//! )?;
//! let mut display = MockDisplay::<Rgb565>::new();
//! render(&scene, &mut display).unwrap();
//! assert_eq!(display.get_pixel(Point::new(32, 32)), Some(Rgb565::RED));
//! assert_eq!(display.get_pixel(Point::new(0, 0)), Some(Rgb565::BLACK));
//! # Ok::<(), lensray::ParseError>(())
//! ```
//!
//! ## Modules
//!
//! [`scalar`] (the number trait), [`vec3`], [`transform`], [`lfsr`],
//! [`aperture`], [`camera`], [`film`] (a pixel's exact ray directions),
//! [`cull`] (which objects a lens ray can reach), [`footprint`] (where bright objects' bokeh can fall), [`autofocus`],
//! [`sampler`] (independent or stratified lens points), [`progressive`], [`shape`], [`scene`], [`parse`], [`mod@render`],
//! [`baked`] (a renderer set up on the host, as checked bytes for flash).

#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

pub mod aperture;
pub mod autofocus;
pub mod baked;
pub mod camera;
pub mod cull;
pub mod film;
pub mod footprint;
pub mod lfsr;
pub mod parse;
mod plane;
pub mod progressive;
pub mod render;
pub mod sampler;
pub mod scalar;
pub mod scene;
pub mod shape;
pub mod transform;
pub mod vec3;
mod wide;

pub use fixed::types::I16F16;
pub use parse::{ErrorKind, ParseError};
pub use render::{render, render_with, Renderer};
pub use scalar::Scalar;
pub use scene::{Scene, MAX_LIGHTS, MAX_OBJECTS};
pub use shape::Shape;
pub use vec3::Vec3;

#[cfg(test)]
mod range_tests;
#[cfg(test)]
mod tests;
