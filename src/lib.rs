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
//! The items at the crate root ([`Scene`], [`render()`], [`render_with`],
//! [`Renderer`], [`ParseError`], [`Scalar`], [`I16F16`], [`Vec3`], [`Shape`],
//! [`baked`]'s loader) are the API a firmware or the CLI calls. The modules
//! below also open their parts to the host tests, the firmware's profiler and
//! the tools: those paths are unstable and may change.
//!
//! Each uses only those before it (a host test checks that `src/` has no
//! import cycle):
//!
//! * [`bytes`]: the checked byte form of every baked value;
//! * [`number`]: the number trait [`Scalar`], its Q16.16 and `f32`
//!   implementations and their exact kernels (wide integers, the film map,
//!   the plane);
//! * [`geometry`]: vectors, affine transforms, rays;
//! * [`camera`]: the camera statements, the lens (aperture, LFSR, lens
//!   sampler) and the one ray-making entry;
//! * [`scene`]: the scene data, shapes and autofocus;
//! * [`parse`]: the scene format;
//! * [`mod@render`]: tracing, culling, bright footprints, progressive
//!   rendering;
//! * [`baked`]: a renderer set up on the host, as checked bytes for flash.

#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

// Dependencies point one way, each layer using only the ones above it:
// bytes, number, geometry, camera, scene, parse, render, baked.
pub mod baked;
pub mod bytes;
pub mod camera;
pub mod geometry;
pub mod number;
pub mod parse;
pub mod render;
pub mod scene;

pub use fixed::types::I16F16;
pub use geometry::vec3::Vec3;
pub use number::Scalar;
pub use parse::{ErrorKind, ParseError};
pub use render::{render, render_with, Renderer};
pub use scene::shape::Shape;
pub use scene::{Scene, MAX_LIGHTS, MAX_OBJECTS};

// The modules' former paths, kept for the host tests and tools: unstable.
#[doc(hidden)]
pub use camera::{aperture, lfsr, sampler};
#[doc(hidden)]
pub use geometry::{transform, vec3};
#[doc(hidden)]
pub use number as scalar;
#[doc(hidden)]
pub use number::film;
#[doc(hidden)]
pub use render::{cull, footprint, progressive};
#[doc(hidden)]
pub use scene::{autofocus, shape};

#[cfg(test)]
mod layout_tests;
#[cfg(test)]
mod range_tests;
#[cfg(test)]
mod tests;
