//! [`Image`] as an embedded-graphics `DrawTarget`: the library's display
//! functions (progressive passes) and text (contact-sheet captions) draw into it
//! as into a panel.

use std::convert::Infallible;

use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;

use crate::Image;

impl Image {
    /// A `width` × `height` image of one colour.
    pub fn filled(width: u32, height: u32, colour: Rgb888) -> Image {
        Image {
            width,
            height,
            pixels: vec![colour; (width * height) as usize],
        }
    }

    /// Copies `src` with its top-left corner at (`x`, `y`), clipped to this image.
    pub fn blit(&mut self, src: &Image, x: u32, y: u32) {
        for sy in 0..src.height.min(self.height.saturating_sub(y)) {
            for sx in 0..src.width.min(self.width.saturating_sub(x)) {
                self.pixels[((y + sy) * self.width + x + sx) as usize] = src.get(sx, sy);
            }
        }
    }
}

impl OriginDimensions for Image {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for Image {
    type Color = Rgb888;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<Rgb888>>,
    {
        for Pixel(p, c) in pixels {
            // Outside the image: clipped, as a panel ignores it.
            if p.x >= 0 && p.y >= 0 && (p.x as u32) < self.width && (p.y as u32) < self.height {
                self.pixels[(p.y as u32 * self.width + p.x as u32) as usize] = c;
            }
        }
        Ok(())
    }
}

/// A horizontal band of a larger image (rows `y0 .. y0 + band.height`) that
/// presents itself as the whole image: drawing anywhere else is dropped. Lets
/// threads draw disjoint bands of one picture with the library's functions.
pub struct Band {
    /// The band's rows.
    pub band: Image,
    /// First row of the band in the whole image.
    pub y0: u32,
    /// Height of the whole image.
    pub full_height: u32,
}

impl OriginDimensions for Band {
    fn size(&self) -> Size {
        Size::new(self.band.width, self.full_height)
    }
}

impl DrawTarget for Band {
    type Color = Rgb888;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<Rgb888>>,
    {
        let y0 = self.y0 as i32;
        self.band.draw_iter(
            pixels
                .into_iter()
                .map(|Pixel(p, c)| Pixel(Point::new(p.x, p.y - y0), c)),
        )
    }
}
