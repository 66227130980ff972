//! What a 16-bit display shows of a render: each pixel through the panel's
//! RGB 5-6-5 format and back to 8 bits a channel, with embedded-graphics' own
//! conversions (the ones a `DrawTarget<Color = Rgb565>` applies to lensray's
//! `Rgb888` pixels, and the ones that widen a panel's words for a picture).

use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};

use crate::Image;

/// The panel formats a render can be shown in (`lensray render --panel`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PanelFormat {
    /// 16 bits a pixel: 5 red, 6 green, 5 blue (ST7789, ILI9341 ...).
    Rgb565,
}

impl PanelFormat {
    /// The format named on the command line.
    pub fn parse(name: &str) -> Option<PanelFormat> {
        match name {
            "rgb565" => Some(PanelFormat::Rgb565),
            _ => None,
        }
    }

    /// The image as the panel shows it: Rgb888 -> panel format -> Rgb888.
    pub fn quantise(self, img: &Image) -> Image {
        match self {
            PanelFormat::Rgb565 => Image {
                width: img.width,
                height: img.height,
                pixels: img.pixels.iter().map(|&p| Rgb888::from(Rgb565::from(p))).collect(),
            },
        }
    }
}

/// An image from RGB 5-6-5 words (red in the top bits), row by row, widened
/// to Rgb888 as embedded-graphics converts Rgb565; `None` if the count is not
/// `width * height`.
pub fn image_from_rgb565(words: &[u16], width: u32, height: u32) -> Option<Image> {
    if words.len() != width as usize * height as usize {
        return None;
    }
    Some(Image {
        width,
        height,
        pixels: words
            .iter()
            .map(|&w| Rgb888::from(Rgb565::from(RawU16::new(w))))
            .collect(),
    })
}

/// The RGB 5-6-5 word of a colour (red in the top bits), as a panel receives it.
pub fn rgb565_word(c: Rgb888) -> u16 {
    RawU16::from(Rgb565::from(c)).into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_graphics::pixelcolor::RgbColor;

    #[test]
    fn words_and_quantised_pixels_agree_for_every_channel_value() {
        // Each channel value through the word and back equals the quantised pixel.
        for v in 0..=255u8 {
            let c = Rgb888::new(v, 255 - v, v / 3);
            let img = Image {
                width: 1,
                height: 1,
                pixels: vec![c],
            };
            let shown = PanelFormat::Rgb565.quantise(&img);
            let from_word = image_from_rgb565(&[rgb565_word(c)], 1, 1).unwrap();
            assert_eq!(shown, from_word);
        }
        // Full scale stays full scale and the 5-bit channels keep their top bits.
        assert_eq!(rgb565_word(Rgb888::WHITE), 0xffff);
        assert_eq!(rgb565_word(Rgb888::new(0x80, 0, 0)), 0x8000);
        assert_eq!(rgb565_word(Rgb888::new(0, 0x04, 0)), 0x0020);
        assert!(image_from_rgb565(&[0; 3], 2, 2).is_none());
    }
}
