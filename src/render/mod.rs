//! Rendering: a pixel, a scanline, or a whole image into a `DrawTarget`.
//!
//! There is no frame buffer anywhere: [`Renderer::render_row`] fills one row
//! of colours, and [`render`] streams each row into the target with one
//! `fill_contiguous` call, computing pixels as the target consumes them.
//!
//! A pixel's lens rays, and when it stops taking them, are [`adaptive`]'s;
//! what a ray sees is `trace`'s; which objects a lens ray can reach is
//! `cull`'s; a stratified ray's checker footprint is `defocus`'s.

use crate::camera::sampler::{PixelSamples, Sampler};
use crate::camera::{Camera, CameraSample, FilmFrame, FilmPoint, MAX_IMAGE_SIDE};
use crate::geometry::ray::Ray;
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::render::cull::LensCones;
use crate::render::defocus::Defocus;
use crate::scene::Scene;
use core::borrow::Borrow;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

pub mod adaptive;
pub(crate) mod cull;
pub(crate) mod defocus;
pub mod progressive;
mod trace;

pub use adaptive::StopRule;
use adaptive::Sums;

/// A scene and a camera set up for one image size: renders pixels.
///
/// Every pixel depends only on the scene, the image size, the frame's
/// [`StopRule`] (set once, by [`Renderer::new`]) and the pixel's own
/// position, so rows may be rendered in any order or in parallel.
///
/// The set-up beside the scene ([`Setup`]) is its own (`P` = [`Setup`]), or
/// lent by a loaded baked scene (`P` = `&Setup`, [`Baked::lend`]): a
/// microcontroller then holds one copy of it, not two.
///
/// [`Baked::lend`]: crate::baked::Baked::lend
///
/// ```
/// use lensray::{Renderer, Scene, I16F16};
/// use embedded_graphics_core::pixelcolor::Rgb888;
///
/// let scene = Scene::<I16F16>::parse("ambient_light 1 1 1\nobject sphere\nKa 0 0 1\ntranslate 0 0 -5\n")?;
/// let renderer = Renderer::new(&scene, 32, 24);
/// let mut row = [Rgb888::new(0, 0, 0); 32];
/// let rays = renderer.render_row(12, &mut row);
/// assert_eq!(rays, 32); // a pinhole camera: one ray a pixel
/// assert_eq!(row[16], Rgb888::new(0, 0, 255));
/// # Ok::<(), lensray::ParseError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Renderer<'a, S: Scalar, P = Setup<S>> {
    pub(crate) scene: &'a Scene<S>,
    pub(crate) setup: P,
}

/// What a [`Renderer`] holds besides its scene: the camera set up for one
/// image size, what the lens rays can reach, their footprints, the
/// samples and the stop rule.
#[derive(Clone, Debug)]
pub struct Setup<S: Scalar> {
    pub(crate) camera: Camera<S>,
    /// The objects each lens ray can reach, precomputed for this camera.
    pub(crate) cones: LensCones<S>,
    /// The lens rays' footprints, for box-filtered checkers (stratified sampler).
    pub(crate) defocus: Defocus<S>,
    /// Lens samples a pixel: all it casts without a stop rule, the most with one.
    pub(crate) samples: u32,
    pub(crate) sampler: Sampler,
    /// When a pixel stops early: none without adaptive sampling.
    pub(crate) stop: Option<StopRule>,
}

impl<'a, S: Scalar> Renderer<'a, S> {
    /// A renderer for `cols` × `rows` pixels with the scene's own camera,
    /// sample count (`point`), `sampler` and `adaptive` statements.
    ///
    /// Each side is clamped to 1..=[`MAX_IMAGE_SIDE`](crate::MAX_IMAGE_SIDE).
    /// With adaptive sampling on a lens camera this runs the frame's
    /// pre-pass: a grid of pixels renders every sample once to set the
    /// [`StopRule`] (about 1/32 of the frame's pixels, at most 256), so it
    /// costs as much as that many pixels.
    ///
    /// # Panics
    ///
    /// Never: any scene [`Scene::parse`] accepts and any size.
    pub fn new(scene: &'a Scene<S>, cols: u32, rows: u32) -> Self {
        Self::new_with_samples(scene, cols, rows, None)
    }

    /// [`Renderer::new`] with `samples` lens samples a pixel (clamped to
    /// 1..=65535) in place of the scene's `point` where given: one pre-pass,
    /// where `Renderer::new(..).with_samples(n)` runs two.
    pub fn new_with_samples(scene: &'a Scene<S>, cols: u32, rows: u32, samples: Option<u32>) -> Self {
        let camera = Camera::new(&scene.camera, cols, rows);
        let setup = Setup {
            camera,
            cones: LensCones::new(
                scene,
                scene.camera.lens_position,
                scene.camera.radius,
                Some(&FilmFrame::new(&scene.camera, cols, rows)),
            ),
            defocus: Defocus::new(scene),
            samples: samples.unwrap_or(scene.camera.samples).clamp(1, 65535),
            sampler: scene.camera.sampler,
            stop: None,
        };
        Renderer { scene, setup }.surveyed()
    }

    /// The same renderer with `samples` lens samples a pixel (clamped to
    /// 1..=65535) in place of the scene's `point`; the stop rule is set again.
    pub fn with_samples(mut self, samples: u32) -> Self {
        self.setup.samples = samples.clamp(1, 65535);
        self.surveyed()
    }

    /// Sets the stop rule from the pre-pass where the scene asks for
    /// adaptive sampling ([`adaptive::survey`]); none otherwise.
    fn surveyed(mut self) -> Self {
        self.setup.stop = None;
        if self.scene.camera.adaptive && !self.setup.camera.is_pinhole() {
            let run = |x, y, pilot, record: &mut dyn FnMut(u32, &Sums<S>) -> bool| {
                self.lens_pixel((x, y), Some(pilot), record).0
            };
            let stop = adaptive::survey(self.setup.samples, self.size(), run);
            self.setup.stop = stop;
        }
        self
    }
}

impl<'a, S: Scalar, P: Borrow<Setup<S>>> Renderer<'a, S, P> {
    /// The set-up, owned or lent.
    #[inline(always)]
    pub(crate) fn s(&self) -> &Setup<S> {
        self.setup.borrow()
    }

    /// A lens pixel's mean colour and rays ([`adaptive::pixel`]): its
    /// sampler's points in order, each ray's checker footprint its cell of
    /// the lens where the sampler is stratified.
    fn lens_pixel(
        &self,
        (col, row): (u32, u32),
        pilot: Option<u32>,
        stop: impl FnMut(u32, &Sums<S>) -> bool,
    ) -> (Vec3<S>, u32) {
        let s = self.s();
        let film = s.camera.film_point(col, row);
        let pixel = Some((col.min(MAX_IMAGE_SIDE) as i16, row.min(MAX_IMAGE_SIDE) as i16));
        let mut lens = PixelSamples::new(s.sampler, col, row);
        let stratified = s.sampler == Sampler::Stratified;
        // Out of every object's box, each ray sees the background (the
        // samples are the pixel's own: skipping them changes no other pixel).
        let nothing = pixel.is_some_and(|p| s.cones.reach_nothing(p));
        // A cell's radius changes at the pixel's checks only.
        let mut cell = (0, S::ZERO);
        let cast = |strata: u32| {
            if nothing {
                return self.scene.background;
            }
            let ray = s.camera.generate_ray(&CameraSample {
                film: &film,
                lens: Some(lens.next(s.camera.aperture())),
            });
            if cell.0 != strata {
                cell = (strata, s.defocus.stratum(strata));
            }
            let footprint = stratified.then_some((&s.defocus, cell.1));
            self.scene.trace_ray(&ray, Some(&s.cones), footprint, pixel)
        };
        adaptive::pixel(s.samples, pilot, cast, stop)
    }

    /// The image size in pixels: columns, rows.
    pub fn size(&self) -> (u32, u32) {
        (self.s().camera.cols(), self.s().camera.rows())
    }

    /// The most rays a pixel casts: 1 for a pinhole camera; where the stop
    /// rule is plain samples within the budget, those; else the sample count.
    pub fn rays_per_pixel(&self) -> u32 {
        match self.s().stop {
            _ if self.s().camera.is_pinhole() => 1,
            // Plain samples within the budget: every pixel stops at the pilot.
            Some(rule) if rule.threshold == u32::MAX => rule.pilot.min(self.s().samples),
            _ => self.s().samples,
        }
    }

    /// The frame's stop rule, if pixels stop early (adaptive sampling on a
    /// lens camera with room for it): its pilot, threshold and the rays its
    /// pre-pass cast.
    pub fn stop_rule(&self) -> Option<StopRule> {
        self.s().stop
    }

    /// The scene this renderer draws.
    pub fn scene(&self) -> &'a Scene<S> {
        self.scene
    }

    /// The mean colour of pixel (`col`, `row`), unclamped, and the rays it cast.
    ///
    /// Beyond the image, `col` and `row` stand for its last column and row.
    ///
    /// # Panics
    ///
    /// Never: all arithmetic saturates.
    pub fn pixel_rays(&self, col: u32, row: u32) -> (Vec3<S>, u32) {
        self.pixel_rays_along(col, row, &mut None)
    }

    /// [`Renderer::pixel_rays`] for a row's pixels in order: a pinhole's chief
    /// direction steps from the pixel to the left (`film`, carried from call
    /// to call, `None` at a row's start or after an empty pixel), one
    /// addition where it took six products.
    #[inline]
    fn pixel_rays_along(&self, col: u32, row: u32, film: &mut Option<FilmPoint<S>>) -> (Vec3<S>, u32) {
        let s = self.s();
        if !s.camera.is_pinhole() {
            return self.lens_pixel_rays(col, row);
        }
        // The pixel's own: the cones' boxes skip what its chief ray cannot
        // reach, and a pixel out of them all its chief ray and film point
        // (the next pixel's is then made afresh).
        let pixel = (col.min(MAX_IMAGE_SIDE) as i16, row.min(MAX_IMAGE_SIDE) as i16);
        if s.cones.reach_nothing(pixel) {
            *film = None;
            return (self.scene.background, 1);
        }
        let f = match film {
            Some(left) => s.camera.film_point_right_of(left, col, row),
            None => s.camera.film_point(col, row),
        };
        *film = Some(f);
        let ray = s.camera.generate_ray(&CameraSample { film: &f, lens: None });
        (self.scene.trace_ray(&ray, Some(&s.cones), None, Some(pixel)), 1)
    }

    /// [`Renderer::pixel_rays`] of a lens camera.
    fn lens_pixel_rays(&self, col: u32, row: u32) -> (Vec3<S>, u32) {
        let Some(rule) = self.s().stop else {
            return self.lens_pixel((col, row), None, |_, _| false);
        };
        // Checks at the pilot and at each power of two past it.
        let stop = |n: u32, sums: &Sums<S>| {
            (n == rule.pilot || n.is_power_of_two()) && (rule.threshold == u32::MAX || rule.stops(n, sums.estimate(n)))
        };
        self.lens_pixel((col, row), Some(rule.pilot), stop)
    }

    /// Pixel (`col`, `row`) as 8-bit RGB: [`Renderer::pixel_rays`]'s mean,
    /// each channel clamped to [0, 1] and rounded.
    pub fn pixel(&self, col: u32, row: u32) -> Rgb888 {
        rgb(self.pixel_rays(col, row).0)
    }

    /// Fills `out` with row `row`, from column 0 (`out.len()` pixels, at most
    /// the image width; extra entries are left untouched), and returns the
    /// rays the row cast (a row of 8192 pixels at 65535 rays fits a u32).
    ///
    /// # Panics
    ///
    /// Never, for any `row` and any length of `out`.
    pub fn render_row(&self, row: u32, out: &mut [Rgb888]) -> u32 {
        let mut rays = 0u32;
        let mut film = None;
        for (col, px) in (0..self.s().camera.cols()).zip(out.iter_mut()) {
            let (c, n) = self.pixel_rays_along(col, row, &mut film);
            *px = rgb(c);
            rays = rays.saturating_add(n);
        }
        rays
    }

    /// The ray of pixel (`col`, `row`) through lens point `p_lens` (Q1.15
    /// on the unit disc, as [`CameraSample::lens`]), or its chief ray for
    /// `None`: what [`Renderer::trace`] and [`Renderer::hit`] take.
    pub fn camera_ray(&self, col: u32, row: u32, p_lens: Option<(i32, i32)>) -> Ray<S> {
        let film = self.s().camera.film_point(col, row);
        self.s().camera.generate_ray(&CameraSample {
            film: &film,
            lens: p_lens,
        })
    }

    /// The colour a camera ray sees (section 4 of the scene format), with
    /// no checker footprint: a point sample.
    pub fn trace(&self, ray: &Ray<S>) -> Vec3<S> {
        self.scene.trace_ray(ray, Some(&self.s().cones), None, None)
    }

    /// The nearest object a camera ray meets, as its index in the scene's
    /// objects and its distance along the ray; `None` for a miss.
    pub fn hit(&self, ray: &Ray<S>) -> Option<(usize, S)> {
        self.scene
            .closest_hit_camera_ray(ray, &self.s().cones)
            .map(|(i, h)| (i, h.t))
    }
}

/// A mean colour as 8-bit RGB, each channel clamped and rounded ([`Renderer::pixel`]'s).
#[inline]
pub(crate) fn rgb<S: Scalar>(c: Vec3<S>) -> Rgb888 {
    Rgb888::new(c.x.to_u8(), c.y.to_u8(), c.z.to_u8())
}

/// Renders `scene` into `target`, one `fill_contiguous` call per row.
///
/// The image is the target's bounding box (its size, from its top-left
/// corner); the target's colour type converts from [`Rgb888`] (Rgb565 and
/// others through embedded-graphics' own conversions). An empty target
/// draws nothing. A side longer than [`MAX_IMAGE_SIDE`](crate::MAX_IMAGE_SIDE)
/// gets an image of that many pixels, from the top-left corner; the rest of
/// the target is untouched.
///
/// # Errors
///
/// Only the target's own errors.
///
/// # Panics
///
/// Never.
pub fn render<S, D>(scene: &Scene<S>, target: &mut D) -> Result<(), D::Error>
where
    S: Scalar,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let area = target.bounding_box();
    if area.size.width == 0 || area.size.height == 0 {
        return Ok(());
    }
    let renderer = Renderer::new(scene, area.size.width, area.size.height);
    render_with(&renderer, target)
}

/// Renders with a prepared [`Renderer`] (e.g. with a sample override) into
/// `target`, one `fill_contiguous` per row: the renderer's image size, placed
/// at the top-left corner of the target's bounding box. Pixels that would lie
/// beyond `i32::MAX` in x or y (a target at the very edge of the plane) are
/// not drawn.
///
/// # Errors
///
/// Only the target's own errors.
///
/// # Panics
///
/// Never.
pub fn render_with<S, P, D>(renderer: &Renderer<'_, S, P>, target: &mut D) -> Result<(), D::Error>
where
    S: Scalar,
    P: Borrow<Setup<S>>,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let (origin, cols, rows) = addressable_area(renderer, target);
    for row in 0..rows {
        // No overflow: row < addressable(origin.y).
        let top_left = Point::new(origin.x, origin.y + row as i32);
        let area = Rectangle::new(top_left, Size::new(cols, 1));
        let mut film = None;
        let pixels = (0..cols).map(|col| D::Color::from(rgb(renderer.pixel_rays_along(col, row, &mut film).0)));
        target.fill_contiguous(&area, pixels)?;
    }
    Ok(())
}

/// The target's top-left corner and the image's columns and rows drawn there.
/// Only pixels with an i32 address are drawn: a target near the edge of the
/// plane gets the part of the image that fits (`origin + row` would overflow).
#[inline]
pub(crate) fn addressable_area<S: Scalar, P: Borrow<Setup<S>>, D: DrawTarget>(
    renderer: &Renderer<'_, S, P>,
    target: &D,
) -> (Point, u32, u32) {
    let origin = target.bounding_box().top_left;
    let (cols, rows) = renderer.size();
    let cols = cols.min(addressable(origin.x));
    let rows = rows.min(addressable(origin.y));
    (origin, cols, rows)
}

/// How many coordinates from `start` up fit in an i32: `i32::MAX - start + 1`, capped.
pub(crate) fn addressable(start: i32) -> u32 {
    u32::try_from(i32::MAX as i64 - start as i64 + 1).unwrap_or(u32::MAX)
}
