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
//! * Lens samples from an integer LFSR, identical for both number
//!   types and dependent only on the pixel.
//! * Scenes in the paper's plain-text format ([`Scene::parse`]); bad input gives
//!   a [`ParseError`] naming the line, never a panic.
//! * No entry point panics, whatever the input, scene or target size: the
//!   parser, [`render()`], [`render_with`] and [`Renderer`] document
//!   `# Panics: Never`, and the repository's host tests fuzz them and sweep
//!   target sizes.
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
//! ## API
//!
//! The items at the crate root are the whole API, the one the firmware, the
//! web page, the CLI and the host tests call: [`Scene`] (its camera
//! [`CameraParams`], [`Sampler`] and [`Aperture`]) and its parser's
//! [`ParseError`]; [`render()`], [`render_with`] and [`Renderer`] (with
//! [`Ray`] and [`CameraSample`] for one camera ray, and the [`adaptive`]
//! sampler's [`StopRule`]); [`progressive`] rendering; the [`baked`] loader;
//! the number trait [`Scalar`] with [`I16F16`]; and [`Vec3`], [`Shape`], the
//! material table and the limits. Everything else is private.
//!
//! Inside, each module uses only those before it, and no file of `src/`
//! imports one that imports it back (a unit test checks both): `bytes` (the
//! checked byte form of every baked value); `number` (the trait, its Q16.16
//! and `f32` implementations and their exact kernels); `geometry`; `camera`
//! (statements, lens, the one ray-making entry); `scene` (data, shapes,
//! autofocus); `parse`; `render` (adaptive sampling, tracing, culling,
//! checker footprints, progressive rendering); `baked`.

#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

// Dependencies point one way, each layer using only the ones above it:
// bytes, number, geometry, camera, scene, parse, render, baked.
pub mod baked;
mod bytes;
mod camera;
mod geometry;
mod number;
mod parse;
mod render;
mod scene;

pub use camera::aperture::Aperture;
pub use camera::sampler::Sampler;
pub use camera::{CameraParams, CameraSample, MAX_IMAGE_SIDE};
pub use fixed::types::I16F16;
pub use geometry::ray::Ray;
pub use geometry::vec3::Vec3;
pub use number::Scalar;
pub use parse::{ErrorKind, Keyword, ParseError, Section, KEYWORDS};
pub use render::adaptive::{self, StopRule};
pub use render::progressive;
pub use render::{render, render_with, Renderer};
pub use scene::shape::Shape;
pub use scene::{NamedMaterial, Scene, DEFAULT_MATERIAL, MATERIALS, MAX_LIGHTS, MAX_OBJECTS};

#[cfg(test)]
mod layout_tests;
#[cfg(test)]
mod range_tests;
#[cfg(test)]
mod test_rng;
#[cfg(test)]
mod tests;

/// On a Cortex-M0 build, runs its Thumb-1 kernels against the portable Rust
/// on the edge values and `pairs` pseudo-random pairs: the first kernel that
/// differs, with its operands. Elsewhere there are no
/// such kernels: `None`. For the firmware's own test (`LENSRAY_CHECK=kernels`).
#[doc(hidden)]
pub fn check_thumb1_kernels(pairs: u32) -> Option<(&'static str, i64, i64)> {
    #[cfg(lensray_v6m)]
    {
        number::wide::check_thumb1(pairs)
    }
    #[cfg(not(lensray_v6m))]
    {
        let _ = pairs;
        None
    }
}
