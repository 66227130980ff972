//! A `DrawTarget` with no frame buffer: each finished row goes to a file on
//! the host as packed RGB bytes (3 per pixel, rows top to bottom).

use crate::semihosting::{HostFile, IoError};
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Size};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics_core::primitives::Rectangle;
use embedded_graphics_core::Pixel;

/// What can go wrong sending rows.
#[derive(Copy, Clone, Debug)]
pub enum RowError {
    /// The host refused a write.
    Io,
    /// A pixel out of raster order: rows top to bottom, pixels left to right.
    OutOfOrder,
}

impl From<IoError> for RowError {
    fn from(_: IoError) -> Self {
        RowError::Io
    }
}

/// An image `W` pixels wide (`BYTES = 3 W`), `height` rows high, sent row by row.
pub struct RowFile<const BYTES: usize> {
    file: HostFile,
    /// Pixels waiting to be written: a row goes out in chunks, so the RAM
    /// this costs does not grow with the image width.
    chunk: [u8; CHUNK],
    filled: usize,
    /// The next pixel expected: rows top to bottom, pixels left to right.
    next_x: u32,
    next_row: u32,
    height: u32,
}

/// Bytes buffered before a write: 16 pixels (a row is `BYTES`).
const CHUNK: usize = 48;

impl<const BYTES: usize> RowFile<BYTES> {
    pub fn create(name: &core::ffi::CStr, height: u32) -> Result<Self, RowError> {
        Ok(RowFile {
            file: HostFile::create(name)?,
            chunk: [0; CHUNK],
            filled: 0,
            next_x: 0,
            next_row: 0,
            height,
        })
    }

    fn width(&self) -> u32 {
        (BYTES / 3) as u32
    }

    /// Appends the next pixel of the row; writes a full chunk, and the rest
    /// at the row's end.
    fn push(&mut self, c: Rgb888) -> Result<(), RowError> {
        // filled <= CHUNK - 3 here; `get_mut` spares a panicking bounds check.
        if let Some(dst) = self.chunk.get_mut(self.filled..self.filled + 3) {
            dst.copy_from_slice(&[c.r(), c.g(), c.b()]);
        }
        self.filled += 3;
        self.next_x += 1;
        let row_done = self.next_x == self.width();
        if self.filled == CHUNK || row_done {
            self.file.write_all(self.chunk.get(..self.filled).unwrap_or(&[]))?;
            self.filled = 0;
        }
        if row_done {
            self.next_x = 0;
            self.next_row += 1;
        }
        Ok(())
    }

    pub fn rows_sent(&self) -> u32 {
        self.next_row
    }

    pub fn close(self) -> Result<(), RowError> {
        Ok(self.file.close()?)
    }
}

impl<const BYTES: usize> OriginDimensions for RowFile<BYTES> {
    fn size(&self) -> Size {
        Size::new(self.width(), self.height)
    }
}

impl<const BYTES: usize> DrawTarget for RowFile<BYTES> {
    type Color = Rgb888;
    type Error = RowError;

    /// Pixels in raster order (left to right, rows top to bottom): they are
    /// streamed as they come, so anything else is refused.
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), RowError> {
        for Pixel(p, c) in pixels {
            if p.y != self.next_row as i32 || p.x != self.next_x as i32 {
                return Err(RowError::OutOfOrder);
            }
            self.push(c)?;
        }
        Ok(())
    }

    /// The fast path: one whole row, streamed in chunks.
    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(&mut self, area: &Rectangle, colors: I) -> Result<(), RowError> {
        let whole_row = self.next_x == 0
            && area.top_left.x == 0
            && area.top_left.y == self.next_row as i32
            && area.size == Size::new(self.width(), 1);
        if !whole_row {
            return Err(RowError::OutOfOrder);
        }
        for c in colors.into_iter().take(self.width() as usize) {
            self.push(c)?;
        }
        Ok(())
    }
}
