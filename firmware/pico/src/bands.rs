//! The progressive passes cut into bands that either core can render, and a
//! recorder that holds one band's drawing until core 0 puts it on the panel.
//!
//! A band is one grid row of one pass (`lensray::progressive::render_pass_row`):
//! image rows `row .. row + step`. Bands of one pass cover disjoint rows, so
//! they may reach the panel in any order; a pass's blocks must reach it before
//! any band of a later pass, which paints finer blocks over them. Bands are
//! numbered in schedule order, pass by pass, and taken in that order by
//! whichever core is free, so the only bands that can be missing when core 0
//! wants to draw one are the one core 1 is working on.
//!
//! No hardware here, so the host tests compile this file as it is
//! (`host-tests/tests/pico_bands.rs`).

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Dimensions, Point, Size};
use embedded_graphics_core::pixelcolor::Rgb565;
use embedded_graphics_core::primitives::Rectangle;
use embedded_graphics_core::Pixel;
use lensray::progressive::{Pass, Schedule};

/// Most passes a schedule has (steps 64 down to 1, and a preview).
pub const MAX_PASSES: usize = 8;

/// One band of a schedule: its pass (index and parameters) and first image row.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Band {
    pub pass_index: usize,
    pub pass: Pass,
    pub row: u32,
}

/// The bands of a schedule over an image of `rows` rows, numbered from 0.
#[derive(Clone, Debug)]
pub struct Bands {
    passes: [Option<Pass>; MAX_PASSES],
    rows: u32,
    count: u32,
}

impl Bands {
    pub fn new(schedule: Schedule, rows: u32) -> Self {
        let mut passes = [None; MAX_PASSES];
        let mut count = 0;
        for (slot, pass) in passes.iter_mut().zip(schedule) {
            count += rows.div_ceil(pass.step.max(1));
            *slot = Some(pass);
        }
        Bands { passes, rows, count }
    }

    /// How many bands there are.
    pub fn len(&self) -> u32 {
        self.count
    }

    /// Whether there are none (an image of no rows).
    #[allow(dead_code)] // the host tests use it; the firmware asks len
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Band `k`, or `None` past the last.
    pub fn get(&self, mut k: u32) -> Option<Band> {
        for (pass_index, pass) in self.passes.iter().enumerate() {
            let pass = (*pass)?;
            let step = pass.step.max(1);
            let n = self.rows.div_ceil(step);
            if k < n {
                return Some(Band {
                    pass_index,
                    pass,
                    row: k * step,
                });
            }
            k -= n;
        }
        None
    }
}

/// Widest image a recorder holds (the panel's landscape width).
pub const MAX_COLS: usize = 320;

/// A draw target that records one band's drawing (blocks of one colour, or
/// one run of pixels along a row, as `render_pass_row` draws) for replay on
/// the panel with the same calls. Drawing it cannot express (single pixels)
/// or more than it holds is refused with [`Overflow`].
pub struct Recorder {
    size: Size,
    blocks: [(Rectangle, Rgb565); MAX_COLS],
    block_count: usize,
    run: Option<Rectangle>,
    run_pixels: [Rgb565; MAX_COLS],
}

/// A band drew more than a [`Recorder`] holds, or drew single pixels.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Overflow;

impl Recorder {
    /// A recorder for an image of `size` (its bounding box, as the panel's).
    pub const fn new(size: Size) -> Self {
        Recorder {
            size,
            blocks: [(Rectangle::zero(), Rgb565::new(0, 0, 0)); MAX_COLS],
            block_count: 0,
            run: None,
            run_pixels: [Rgb565::new(0, 0, 0); MAX_COLS],
        }
    }

    /// Forgets what was recorded.
    pub fn clear(&mut self) {
        self.block_count = 0;
        self.run = None;
    }

    /// Draws what was recorded, in the order it was drawn (blocks, then the run).
    pub fn replay<D: DrawTarget<Color = Rgb565>>(&self, target: &mut D) -> Result<(), D::Error> {
        for (area, colour) in &self.blocks[..self.block_count] {
            target.fill_solid(area, *colour)?;
        }
        if let Some(area) = self.run {
            let n = area.size.width as usize;
            target.fill_contiguous(&area, self.run_pixels[..n].iter().copied())?;
        }
        Ok(())
    }
}

impl Dimensions for Recorder {
    fn bounding_box(&self) -> Rectangle {
        Rectangle::new(Point::zero(), self.size)
    }
}

impl DrawTarget for Recorder {
    type Color = Rgb565;
    type Error = Overflow;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, _: I) -> Result<(), Overflow> {
        Err(Overflow)
    }

    fn fill_solid(&mut self, area: &Rectangle, colour: Rgb565) -> Result<(), Overflow> {
        let slot = self.blocks.get_mut(self.block_count).ok_or(Overflow)?;
        *slot = (*area, colour);
        self.block_count += 1;
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
        &mut self,
        area: &Rectangle,
        colours: I,
    ) -> Result<(), Overflow> {
        if self.run.is_some() || area.size.height != 1 || area.size.width as usize > MAX_COLS {
            return Err(Overflow);
        }
        let n = area.size.width as usize;
        let mut got = 0;
        for (slot, c) in self.run_pixels[..n].iter_mut().zip(colours) {
            *slot = c;
            got += 1;
        }
        if got != n {
            return Err(Overflow);
        }
        self.run = Some(*area);
        Ok(())
    }
}
