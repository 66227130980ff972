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

    /// Whether nothing was recorded (a band all of whose blocks it skipped).
    #[allow(dead_code)] // the host tests ask
    pub fn is_empty(&self) -> bool {
        self.block_count == 0 && self.run.is_none()
    }

    /// Forgets what was recorded.
    pub fn clear(&mut self) {
        self.block_count = 0;
        self.run = None;
    }

    /// Draws what was recorded on `target`, whose even pixels (both
    /// coordinates even) `shadow` holds, and keeps `shadow` up to date.
    ///
    /// A band of blocks goes out as one window over the whole band, rows of
    /// the image's width: a block the band skipped (it keeps a coarser
    /// pass's colour, which its even top-left pixel shows) is sent again in
    /// that colour from `shadow`. One window where a block each took one:
    /// setting a window costs the panel's bus more than a small block's
    /// pixels. Anything else is drawn as it was recorded.
    pub fn replay<D: DrawTarget<Color = Rgb565>>(&self, target: &mut D, shadow: &mut Shadow) -> Result<(), D::Error> {
        if let Some((area, row)) = self.whole_band(shadow) {
            // The band is its one row again on each of its rows.
            let width = area.size.width as usize;
            let pixels = row[..width]
                .iter()
                .copied()
                .cycle()
                .take(width * area.size.height as usize);
            target.fill_contiguous(&area, pixels)?;
            for y in (area.top_left.y..area.top_left.y + area.size.height as i32).filter(|y| y % 2 == 0) {
                shadow.paint_row(y, &row[..width]);
            }
            return Ok(());
        }
        for (area, colour) in &self.blocks[..self.block_count] {
            target.fill_solid(area, *colour)?;
            shadow.paint_blocks(area, area.size.width as usize, &[*colour]);
        }
        if let Some(area) = self.run {
            let n = area.size.width as usize;
            target.fill_contiguous(&area, self.run_pixels[..n].iter().copied())?;
            shadow.paint_blocks(&area, 1, &self.run_pixels[..n]);
        }
        Ok(())
    }

    /// The band's whole area and one row of it, each block's colour over its
    /// width (from `shadow` where the band skipped one), where the recording
    /// is a band of blocks in order along one grid row, of one width and
    /// height, each skipped one at an even pixel; `None` otherwise.
    fn whole_band(&self, shadow: &Shadow) -> Option<(Rectangle, [Rgb565; MAX_COLS])> {
        let blocks = &self.blocks[..self.block_count];
        let first = blocks.first()?.0;
        let (y, height, step) = (first.top_left.y, first.size.height, first.size.width as usize);
        let width = self.size.width as usize;
        if self.run.is_some() || step == 0 || y < 0 || width > MAX_COLS {
            return None;
        }
        let mut row = [Rgb565::new(0, 0, 0); MAX_COLS];
        // The next block starts at pixel `at` of the row.
        let mut at = 0;
        let mut fill = |at: usize, c: Rgb565| row[at..(at + step).min(width)].fill(c);
        for (area, colour) in blocks {
            let x = usize::try_from(area.top_left.x).ok()?;
            while at < x && at < width {
                fill(at, shadow.get(at, y)?);
                at += step;
            }
            let fits = at == x && x < width && area.top_left.y == y && area.size.height == height;
            if !fits || area.size.width as usize != step.min(width - x) {
                return None;
            }
            fill(at, *colour);
            at += step;
        }
        while at < width {
            fill(at, shadow.get(at, y)?);
            at += step;
        }
        let area = Rectangle::new(Point::new(0, y), Size::new(width as u32, height));
        Some((area, row))
    }
}

/// Even pixels of the panel (both coordinates even): what core 0 last drew
/// there. A band that skips a block (it keeps a coarser pass's colour, and
/// blocks start at even pixels) is sent whole with that block's colour from
/// here. One entry per 2x2 pixels of the largest image, 51 KB.
pub struct Shadow {
    cols: usize,
    colours: [Rgb565; SHADOW_LEN],
}

/// The shadow's entries: a quarter of a [`MAX_COLS`] x [`MAX_COLS`] image.
pub const SHADOW_LEN: usize = (MAX_COLS / 2) * (MAX_COLS / 2);

impl Shadow {
    /// An all-black shadow for an image `width` pixels wide.
    pub const fn new(width: u32) -> Self {
        Shadow {
            cols: (width as usize).div_ceil(2),
            colours: [Rgb565::new(0, 0, 0); SHADOW_LEN],
        }
    }

    /// The colour at even pixel (x, y); `None` for another pixel or one off the shadow.
    fn get(&self, x: usize, y: i32) -> Option<Rgb565> {
        self.index(x, y).map(|i| self.colours[i])
    }

    fn index(&self, x: usize, y: i32) -> Option<usize> {
        if y < 0 || !x.is_multiple_of(2) || y % 2 != 0 || x / 2 >= self.cols {
            return None;
        }
        let i = (y as usize / 2) * self.cols + x / 2;
        (i < SHADOW_LEN).then_some(i)
    }

    /// Records row `y` of the panel, `pixels` from its left edge.
    fn paint_row(&mut self, y: i32, pixels: &[Rgb565]) {
        let Some(start) = self.index(0, y) else {
            return;
        };
        let end = (start + self.cols).min(SHADOW_LEN);
        for (entry, c) in self.colours[start..end].iter_mut().zip(pixels.iter().step_by(2)) {
            *entry = *c;
        }
    }

    /// Records what was drawn over `area`: blocks `step` wide from its left
    /// edge, block `j` in `colours[j]` (the same colour down each column).
    fn paint_blocks(&mut self, area: &Rectangle, step: usize, colours: &[Rgb565]) {
        let (Ok(x0), y0) = (usize::try_from(area.top_left.x), area.top_left.y) else {
            return;
        };
        if step == 0 {
            return;
        }
        for y in (y0..y0 + area.size.height as i32).filter(|y| y % 2 == 0) {
            // Block j spans pixels x0 + j step .. x0 + (j + 1) step.
            let (mut j, mut end) = (0, x0 + step);
            for x in (x0..x0 + area.size.width as usize).filter(|x| x.is_multiple_of(2)) {
                while x >= end {
                    (j, end) = (j + 1, end + step);
                }
                if let (Some(i), Some(c)) = (self.index(x, y), colours.get(j)) {
                    self.colours[i] = *c;
                }
            }
        }
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
