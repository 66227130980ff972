//! Rendering: a pixel, a scanline, or a whole image into a `DrawTarget`.
//!
//! There is no frame buffer anywhere: [`Renderer::render_row`] fills one row
//! of colours, and [`render`] streams each row into the target with one
//! `fill_contiguous` call, computing pixels as the target consumes them.

use crate::camera::Camera;
use crate::cull::LensCones;
use crate::lfsr::Lfsr;
use crate::scalar::Scalar;
use crate::scene::Scene;
use crate::vec3::Vec3;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

/// A scene and a camera set up for one image size: renders pixels.
///
/// Every pixel depends only on the scene, the image size and the pixel's own
/// position, so rows may be rendered in any order or in parallel.
#[derive(Clone, Debug)]
pub struct Renderer<'a, S: Scalar> {
    pub(crate) scene: &'a Scene<S>,
    pub(crate) camera: Camera<S>,
    /// The objects each lens ray can reach, precomputed for this camera.
    pub(crate) cones: LensCones<S>,
    pub(crate) samples: u32,
    pub(crate) adaptive: bool,
}

/// Lens samples an adaptive pixel takes before it first asks whether its
/// samples agree, and between later checks.
pub const ADAPTIVE_BATCH: u32 = 8;

/// The standard error of an adaptive pixel's mean, in 8-bit levels, below
/// which it stops: 1 level (the bound is on its square, in sixteenths).
const ADAPTIVE_SE2_SIXTEENTHS: u64 = 16;

/// Running sums of a pixel's samples in 8-bit levels (unclamped: a lamp
/// brighter than white weighs what it adds to the mean), per channel: what
/// the adaptive stop decides on, in integers.
#[derive(Default)]
struct LevelStats {
    sum: [u64; 3],
    sum_sq: [u64; 3],
}

impl LevelStats {
    fn add<S: Scalar>(&mut self, c: Vec3<S>) {
        let level = |x: S| x.mul(S::from_i32(255)).floor_i32().clamp(0, 65535) as u64;
        for (i, l) in [level(c.x), level(c.y), level(c.z)].into_iter().enumerate() {
            self.sum[i] += l;
            self.sum_sq[i] += l * l;
        }
    }

    /// Whether the mean of `n >= 2` samples is within the bound of the mean
    /// of all `full` samples, on every channel: the expected square of their
    /// difference, s² (1/n − 1/full) with s² the samples' variance, at most
    /// se². In integers, exactly: (n·Σx² − (Σx)²) · (full − n) · 16 <=
    /// se²·16 · n² · (n − 1) · full.
    fn settled(&self, n: u32, full: u32) -> bool {
        let (n, full) = (n as u128, full as u128);
        (0..3).all(|i| {
            let spread = n * self.sum_sq[i] as u128 - self.sum[i] as u128 * self.sum[i] as u128;
            spread * (full - n) * 16 <= ADAPTIVE_SE2_SIXTEENTHS as u128 * n * n * (n - 1) * full
        })
    }
}

impl<'a, S: Scalar> Renderer<'a, S> {
    /// A renderer for `cols` × `rows` pixels with the scene's own sample count.
    ///
    /// Each side is clamped to 1..=[`MAX_IMAGE_SIDE`](crate::camera::MAX_IMAGE_SIDE).
    ///
    /// # Panics
    ///
    /// Never: any scene [`Scene::parse`] accepts and any size.
    pub fn new(scene: &'a Scene<S>, cols: u32, rows: u32) -> Self {
        Renderer {
            scene,
            camera: Camera::new(&scene.camera, cols, rows),
            cones: LensCones::new(scene, scene.camera.lens_position, scene.camera.radius),
            samples: scene.camera.samples.max(1),
            adaptive: scene.camera.adaptive,
        }
    }

    /// Overrides the lens samples per pixel (clamped to 1..=65535).
    ///
    /// # Panics
    ///
    /// Never.
    pub fn with_samples(mut self, samples: u32) -> Self {
        self.samples = samples.clamp(1, 65535);
        self
    }

    /// Turns adaptive lens sampling on or off (the scene's `adaptive`
    /// statement sets the default; see [`Renderer::pixel_rays`]).
    pub fn with_adaptive(mut self, adaptive: bool) -> Self {
        self.adaptive = adaptive;
        self
    }

    /// Whether lens sampling is adaptive.
    pub fn is_adaptive(&self) -> bool {
        self.adaptive
    }

    /// The camera in use.
    pub fn camera(&self) -> &Camera<S> {
        &self.camera
    }

    /// The objects each of this camera's rays can reach (see [`LensCones`]).
    pub fn cones(&self) -> &LensCones<S> {
        &self.cones
    }

    /// Rays cast per pixel: 1 for a pinhole camera, else the sample count
    /// (with adaptive sampling, the most a pixel casts).
    pub fn rays_per_pixel(&self) -> u32 {
        if self.camera.is_pinhole() {
            1
        } else {
            self.samples
        }
    }

    /// The mean colour of pixel (`col`, `row`), unclamped.
    ///
    /// # Panics
    ///
    /// Never, for any `col` and `row` (beyond the image they stand for its last
    /// column and row, as the camera clamps them): all arithmetic saturates.
    pub fn pixel_colour(&self, col: u32, row: u32) -> Vec3<S> {
        self.pixel_rays(col, row).0
    }

    /// The mean colour of pixel (`col`, `row`), unclamped, and the rays it cast.
    ///
    /// With adaptive sampling a pixel takes [`ADAPTIVE_BATCH`] lens samples,
    /// then checks after every further batch whether the mean of its samples
    /// (in 8-bit levels) is within a level of the mean of all the samples
    /// (estimated from their spread); it stops there. Samples that agree (an
    /// in-focus pixel, or one whose rays all miss every object) stop after the
    /// first batch; samples that differ (a blurred edge) go on up to the full
    /// count. The samples taken are the first ones of the full render.
    pub fn pixel_rays(&self, col: u32, row: u32) -> (Vec3<S>, u32) {
        let film = self.camera.film_point(col, row);
        if self.camera.is_pinhole() {
            let ray = self.camera.chief_ray_from(&film);
            return (self.scene.trace_camera_ray(&ray, &self.cones), 1);
        }
        // The pixel's own register: samples independent of row order and threads.
        let mut lfsr = Lfsr::for_pixel(col, row, 0);
        let mut acc = [S::acc_zero(); 3];
        let mut stats = LevelStats::default();
        let mut n = 0;
        while n < self.samples {
            let ray = self.camera.lens_ray_from(&film, self.camera.lens_sample(&mut lfsr));
            let c = self.scene.trace_camera_ray(&ray, &self.cones);
            acc = [
                S::acc_add(acc[0], c.x),
                S::acc_add(acc[1], c.y),
                S::acc_add(acc[2], c.z),
            ];
            n += 1;
            if self.adaptive {
                stats.add(c);
                if n % ADAPTIVE_BATCH == 0 && n < self.samples && stats.settled(n, self.samples) {
                    break;
                }
            }
        }
        let colour = Vec3::new(S::acc_mean(acc[0], n), S::acc_mean(acc[1], n), S::acc_mean(acc[2], n));
        (colour, n)
    }

    /// Pixel (`col`, `row`) as 8-bit RGB: each channel clamped and `round(255 v)`.
    ///
    /// # Panics
    ///
    /// Never, as [`Renderer::pixel_colour`].
    pub fn pixel(&self, col: u32, row: u32) -> Rgb888 {
        let c = self.pixel_colour(col, row);
        Rgb888::new(c.x.to_u8(), c.y.to_u8(), c.z.to_u8())
    }

    /// Fills `out` with row `row`, from column 0 (`out.len()` pixels at most
    /// the image width; extra entries are left untouched).
    ///
    /// # Panics
    ///
    /// Never, for any `row` and any length of `out`.
    pub fn render_row(&self, row: u32, out: &mut [Rgb888]) {
        for (col, px) in out.iter_mut().take(self.camera.cols() as usize).enumerate() {
            *px = self.pixel(col as u32, row);
        }
    }
}

/// Renders `scene` into `target`, one `fill_contiguous` call per row.
///
/// The image is the target's bounding box (its size, from its top-left
/// corner); the target's colour type converts
/// from [`Rgb888`] (Rgb565 and others through embedded-graphics' own
/// conversions). An empty target draws nothing. A side longer than
/// [`MAX_IMAGE_SIDE`](crate::camera::MAX_IMAGE_SIDE) gets an image of that
/// many pixels, from the top-left corner; the rest of the target is untouched.
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
pub fn render_with<S, D>(renderer: &Renderer<'_, S>, target: &mut D) -> Result<(), D::Error>
where
    S: Scalar,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let origin = target.bounding_box().top_left;
    // Only pixels with an i32 address are drawn: a target near the edge of the
    // plane gets the part of the image that fits (`origin + row` would overflow).
    let cols = renderer.camera().cols().min(addressable(origin.x));
    let rows = renderer.camera().rows().min(addressable(origin.y));
    for row in 0..rows {
        // No overflow: row < addressable(origin.y).
        let top_left = Point::new(origin.x, origin.y + row as i32);
        let area = Rectangle::new(top_left, Size::new(cols, 1));
        target.fill_contiguous(&area, (0..cols).map(|col| D::Color::from(renderer.pixel(col, row))))?;
    }
    Ok(())
}

/// How many coordinates from `start` up fit in an i32: `i32::MAX - start + 1`, capped.
pub(crate) fn addressable(start: i32) -> u32 {
    u32::try_from(i32::MAX as i64 - start as i64 + 1).unwrap_or(u32::MAX)
}
