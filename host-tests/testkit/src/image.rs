//! An RGB image in memory: what renders produce and tests compare.

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};

/// An RGB image in memory, row-major from the top-left.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, row by row.
    pub pixels: Vec<Rgb888>,
}

impl Image {
    /// The pixel at (`x`, `y`).
    pub fn get(&self, x: u32, y: u32) -> Rgb888 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// The pixels as packed RGB bytes.
    pub fn to_rgb_bytes(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|p| [p.r(), p.g(), p.b()]).collect()
    }
}
