//! Progressive display: a coarse picture first, refined in place on the
//! display itself, with no frame buffer.
//!
//! A render of the paper's Program 1 takes minutes to hours on a
//! microcontroller. Progressive rendering puts a rough picture on the panel
//! within a fraction of that and then sharpens it, pass by pass, until it is
//! exactly the picture [`crate::render()`] draws.
//!
//! # How, without a frame buffer
//!
//! The passes interlace on a grid of blocks (as Adam7 does in PNG, in square
//! blocks). A [`Pass`] of spacing `step` computes the pixels whose column and
//! row are multiples of `step` and paints each as a `step` × `step` block. The
//! next pass halves the spacing and computes only the new pixels of the finer
//! grid: every pixel computed before keeps the top-left corner of its old
//! block, which the new blocks leave untouched, so the display itself holds the
//! picture and nothing needs to be stored or read back. Each pixel is computed
//! once with its full sample count (with adaptive sampling, the same samples
//! the plain render takes, stopping where it stops): the refinement passes
//! together cost exactly one plain render, as a pixel depends on itself alone.
//!
//! On top of that an optional *preview* pass draws the coarsest grid with few
//! lens samples (1 by default): for Program 1 at 8 × 8 blocks and 70 rays a
//! pixel, 1/4480 of the work of the whole picture. The coarsest grid is then
//! computed again with its full sample count, so the preview adds that little
//! and no more.
//!
//! # The trade-off
//!
//! Refining by *sample count* instead (every pixel at 1 sample, then 4, then
//! 16 ...) shows a full-resolution, noisy picture first. But averaging a pass
//! into the last needs each pixel's running sums (three 32-bit sums a pixel,
//! 900 KiB at 320 × 240 in f32 or Q16.16 accumulators: more RAM than such a
//! board has), or reading the panel back (many cannot, and 5-6 bits a channel
//! would round the sums away). Without them every pass starts again from
//! nothing and the whole sequence costs about 4/3 of a plain render, and its
//! first picture costs 1/70 of it for Program 1, not 1/4480. Rendering
//! *every 4th row* first (each row drawn 4 high) is the one-dimensional case
//! of the blocks here: its first picture comes 4 times sooner than the whole,
//! where 4 × 4 blocks bring it 16 times sooner. So lensray refines by
//! resolution at the full sample count: the total work stays one render, no
//! memory is needed beyond the pixel being computed, and the last pass leaves
//! exactly the final image. The price: until the last pass, fine detail
//! (thin edges, the far checkerboard) is shown blocky, not noisy.
//!
//! ```
//! use embedded_graphics::{mock_display::MockDisplay, pixelcolor::Rgb565, prelude::*};
//! use lensray::{progressive, I16F16, Renderer, Scene};
//!
//! let scene = Scene::<I16F16>::parse("ambient_light 1 1 1\nradius 0.3\npoint 9\nobject sphere\nKa 1 0 0\ntranslate 0 0 -8\n")?;
//! let mut display = MockDisplay::<Rgb565>::new();
//! display.set_allow_overdraw(true);
//! let renderer = Renderer::new(&scene, 64, 64);
//! for pass in progressive::Schedule::new(8, 1, renderer.rays_per_pixel()) {
//!     progressive::render_pass(&renderer, &mut display, &pass).unwrap();
//!     // The display now shows the picture so far; the last pass completes it.
//! }
//! let mut plain = MockDisplay::<Rgb565>::new();
//! lensray::render_with(&renderer, &mut plain).unwrap();
//! display.assert_eq(&plain);
//! # Ok::<(), lensray::ParseError>(())
//! ```

use crate::number::Scalar;
use crate::render::{addressable_area, rgb, Renderer};
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

/// Largest block side of a schedule.
pub const MAX_STEP: u32 = 64;

/// One pass of a progressive render.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Pass {
    /// Grid spacing, a power of two from 1 to [`MAX_STEP`]: the pass computes the
    /// pixels whose column and row are multiples of `step`, each painted as a
    /// `step` × `step` block (clipped at the image's right and bottom edges).
    pub step: u32,
    /// Leave out the pixels on the grid of spacing `2 · step`: an earlier pass
    /// computed them with the same samples and its blocks still show them.
    pub skip_coarser: bool,
    /// Lens samples per pixel (clamped to 1..=65535; a pinhole casts one ray).
    /// A pixel's first `samples` lens points are those of the full render.
    pub samples: u32,
}

impl Pass {
    /// Whether this pass computes pixel (`col`, `row`).
    pub fn computes(&self, col: u32, row: u32) -> bool {
        let s = self.step.max(1);
        if !col.is_multiple_of(s) || !row.is_multiple_of(s) {
            return false;
        }
        // Saturating: a hand-made pass may hold any step.
        let s2 = s.saturating_mul(2);
        !(self.skip_coarser && col.is_multiple_of(s2) && row.is_multiple_of(s2))
    }

    /// How many pixels of a `cols` × `rows` image this pass computes.
    pub fn pixel_count(&self, cols: u32, rows: u32) -> u64 {
        let s = self.step.max(1) as u64;
        let grid = |n: u32, s: u64| (n as u64).div_ceil(s);
        let all = grid(cols, s) * grid(rows, s);
        if self.skip_coarser {
            all - grid(cols, 2 * s) * grid(rows, 2 * s)
        } else {
            all
        }
    }
}

/// The passes of a progressive render, coarse to fine: an optional preview
/// with few samples, then the grid of `first_step` with the full samples, then
/// each finer grid's new pixels down to single pixels.
///
/// After the last pass the display holds exactly the image of a plain render
/// with `samples` lens samples a pixel.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Schedule {
    next: Option<Pass>,
    samples: u32,
}

impl Schedule {
    /// Passes from blocks of `first_step` (rounded down to a power of two,
    /// 1..=[`MAX_STEP`]) to single pixels, all with `samples` lens samples, after
    /// a preview of the first grid with `preview_samples` (0, or not fewer
    /// than `samples`, for no preview).
    pub fn new(first_step: u32, preview_samples: u32, samples: u32) -> Self {
        let step = prev_power_of_two(first_step.clamp(1, MAX_STEP));
        let samples = samples.clamp(1, 65535);
        let first = Pass {
            step,
            skip_coarser: false,
            samples: if preview_samples > 0 && preview_samples < samples {
                preview_samples
            } else {
                samples
            },
        };
        Schedule {
            next: Some(first),
            samples,
        }
    }

    /// How many passes a schedule has in all.
    pub fn len(&self) -> usize {
        (*self).count()
    }

    /// Whether the schedule has no passes left.
    pub fn is_empty(&self) -> bool {
        self.next.is_none()
    }
}

impl Iterator for Schedule {
    type Item = Pass;

    fn next(&mut self) -> Option<Pass> {
        let pass = self.next?;
        self.next = if pass.samples < self.samples {
            // After the preview: the same grid again at full samples.
            Some(Pass {
                samples: self.samples,
                ..pass
            })
        } else if pass.step > 1 {
            Some(Pass {
                step: pass.step / 2,
                skip_coarser: true,
                samples: self.samples,
            })
        } else {
            None
        };
        Some(pass)
    }
}

fn prev_power_of_two(n: u32) -> u32 {
    1 << (31 - n.max(1).leading_zeros())
}

/// Draws one pass into `target`: the renderer's image at the top-left corner
/// of the target's bounding box, as [`crate::render_with`] places it.
/// Returns the lens rays its pixels cast (with adaptive sampling, what they
/// took: fewer than the pass's samples a pixel).
///
/// # Errors
///
/// Only the target's own errors.
///
/// # Panics
///
/// Never.
pub fn render_pass<S, D>(renderer: &Renderer<'_, S>, target: &mut D, pass: &Pass) -> Result<u64, D::Error>
where
    S: Scalar,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let renderer = pass_renderer(renderer, pass);
    let step = pass.step.max(1);
    let mut rays = 0;
    for row in (0..renderer.size().1).step_by(step as usize) {
        rays += draw_band(&renderer, target, pass, row)?;
    }
    Ok(rays)
}

/// Draws the blocks of one grid row of a pass: image rows `row .. row + step`.
/// `row` is a multiple of `pass.step` (other rows draw nothing). Rows may be
/// drawn in any order, e.g. between other work on a device. Returns the
/// lens rays the band's pixels cast.
///
/// # Errors
///
/// Only the target's own errors.
///
/// # Panics
///
/// Never.
pub fn render_pass_row<S, D>(renderer: &Renderer<'_, S>, target: &mut D, pass: &Pass, row: u32) -> Result<u64, D::Error>
where
    S: Scalar,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    draw_band(&pass_renderer(renderer, pass), target, pass, row)
}

/// The renderer of `pass`: `renderer` itself at its own samples, else (a
/// preview) at the pass's without a set-up survey, which a band at a time
/// would repeat for every band.
fn pass_renderer<'a, S: Scalar>(renderer: &Renderer<'a, S>, pass: &Pass) -> Renderer<'a, S> {
    let mut r = renderer.clone();
    if pass.samples < r.rays_per_pixel() {
        // A preview: every pixel its few samples, no stop rule.
        r.setup.samples = pass.samples.max(1);
        r.setup.stop = None;
    }
    r
}

/// The work of [`render_pass_row`], with the pass's sample count already set.
fn draw_band<S, D>(renderer: &Renderer<'_, S>, target: &mut D, pass: &Pass, row: u32) -> Result<u64, D::Error>
where
    S: Scalar,
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    // Only pixels with an i32 address, as render_with: no coordinate overflows.
    let (origin, cols, rows) = addressable_area(renderer, target);
    let step = pass.step.max(1);
    if !row.is_multiple_of(step) || row >= rows {
        return Ok(0);
    }
    let height = step.min(rows - row);
    let skip_in_row = pass.skip_coarser && row.is_multiple_of(step.saturating_mul(2));
    // No overflow below: row < addressable(origin.y) and col < addressable(origin.x).
    let at = |col: u32| Point::new(origin.x + col as i32, origin.y + row as i32);
    if step == 1 && !skip_in_row {
        // Single pixels: stream the row as a plain render does.
        let area = Rectangle::new(at(0), Size::new(cols, 1));
        let mut rays = 0u64;
        // A pinhole's film point stepped along the row, as a plain render does.
        let mut film = None;
        let pixels = (0..cols).map(|col| {
            let (c, n) = renderer.pixel_rays_along(col, row, &mut film);
            rays += n as u64;
            D::Color::from(rgb(c))
        });
        target.fill_contiguous(&area, pixels)?;
        return Ok(rays);
    }
    let mut rays = 0;
    // Block j starts at column j step: the coarser pass drew the even ones of a skipping row.
    for (j, col) in (0..cols).step_by(step as usize).enumerate() {
        if skip_in_row && j % 2 == 0 {
            continue;
        }
        let (c, n) = renderer.pixel_rays(col, row);
        rays += n as u64;
        let colour = D::Color::from(rgb(c));
        let size = Size::new(step.min(cols - col), height);
        target.fill_solid(&Rectangle::new(at(col), size), colour)?;
    }
    Ok(rays)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedule_goes_from_preview_to_single_pixels() {
        let s: std::vec::Vec<Pass> = Schedule::new(8, 1, 70).collect();
        let p = |step, skip_coarser, samples| Pass {
            step,
            skip_coarser,
            samples,
        };
        assert_eq!(
            s,
            [
                p(8, false, 1),
                p(8, false, 70),
                p(4, true, 70),
                p(2, true, 70),
                p(1, true, 70)
            ]
        );
        assert_eq!(Schedule::new(8, 1, 70).len(), 5);
        // No preview when it would not be cheaper; odd first steps round down.
        assert_eq!(Schedule::new(6, 0, 70).next(), Some(p(4, false, 70)));
        assert_eq!(Schedule::new(4, 70, 70).len(), 3);
        assert_eq!(Schedule::new(1, 1, 1).collect::<std::vec::Vec<_>>(), [p(1, false, 1)]);
    }

    #[test]
    fn full_sample_passes_compute_every_pixel_exactly_once() {
        for (cols, rows) in [(37u32, 23u32), (64, 64), (1, 9)] {
            let passes: std::vec::Vec<Pass> = Schedule::new(16, 2, 5).filter(|p| p.samples == 5).collect();
            let mut total = 0;
            for r in 0..rows {
                for c in 0..cols {
                    let n = passes.iter().filter(|p| p.computes(c, r)).count();
                    assert_eq!(n, 1, "pixel ({c}, {r}) of {cols}x{rows}");
                }
            }
            for p in &passes {
                total += p.pixel_count(cols, rows);
            }
            assert_eq!(total, cols as u64 * rows as u64);
        }
    }
}
