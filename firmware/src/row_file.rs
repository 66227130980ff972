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
    /// A pixel outside the next row: rows must arrive in order, one at a time.
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
    row: [u8; BYTES],
    next_row: u32,
    height: u32,
}

impl<const BYTES: usize> RowFile<BYTES> {
    /// Creates `name` on the host for an image `height` rows high.
    pub fn create(name: &str, height: u32) -> Result<Self, RowError> {
        Ok(RowFile {
            file: HostFile::create(name)?,
            row: [0; BYTES],
            next_row: 0,
            height,
        })
    }

    fn width(&self) -> u32 {
        (BYTES / 3) as u32
    }

    fn put(&mut self, x: usize, c: Rgb888) {
        self.row[3 * x..3 * x + 3].copy_from_slice(&[c.r(), c.g(), c.b()]);
    }

    fn send_row(&mut self) -> Result<(), RowError> {
        self.file.write_all(&self.row)?;
        self.next_row += 1;
        Ok(())
    }

    /// Rows sent so far.
    pub fn rows_sent(&self) -> u32 {
        self.next_row
    }

    /// Closes the file.
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

    /// Pixels of the next row, in any order; the row is sent when its last
    /// pixel (the rightmost) arrives.
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), RowError> {
        for Pixel(p, c) in pixels {
            if p.y != self.next_row as i32 || p.x < 0 || p.x >= self.width() as i32 {
                return Err(RowError::OutOfOrder);
            }
            self.put(p.x as usize, c);
            if p.x == self.width() as i32 - 1 {
                self.send_row()?;
            }
        }
        Ok(())
    }

    /// The fast path: one whole row, sent in one write.
    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(&mut self, area: &Rectangle, colors: I) -> Result<(), RowError> {
        let whole_row =
            area.top_left.x == 0 && area.top_left.y == self.next_row as i32 && area.size == Size::new(self.width(), 1);
        if !whole_row {
            return Err(RowError::OutOfOrder);
        }
        for (x, c) in colors.into_iter().take(self.width() as usize).enumerate() {
            self.put(x, c);
        }
        self.send_row()
    }
}
