//! Contact sheets: renders side by side on a grid, each with a caption under
//! it, drawn with embedded-graphics' built-in 6×10 font.

use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyle};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::text::{Baseline, Text};
use lensray::CameraParams;

use crate::Image;

/// Sheet background.
pub const BACKGROUND: Rgb888 = Rgb888::new(24, 24, 24);
/// Caption and title colour.
pub const INK: Rgb888 = Rgb888::new(235, 235, 235);
/// Space around and between tiles, in pixels.
pub const GAP: u32 = 8;
/// Height of a caption line (the font is 10 pixels high).
pub const LINE: u32 = 12;
/// Width of a character of the font.
const CHAR_W: u32 = 6;

/// One picture of a sheet and its caption lines.
#[derive(Clone, Debug)]
pub struct Tile {
    /// The picture.
    pub image: Image,
    /// Caption lines, shown under the picture (cut to its width).
    pub caption: Vec<String>,
}

/// A laid-out sheet: the image and where each tile's top-left corner went.
#[derive(Clone, Debug)]
pub struct Sheet {
    /// The whole sheet.
    pub image: Image,
    /// Top-left corner of each tile's picture, in tile order.
    pub origins: Vec<(u32, u32)>,
}

/// Lays `tiles` out left to right, `columns` a row (at least 1), under an
/// optional title line. Columns are as wide as the widest tile; a row is as
/// high as its highest picture plus the most caption lines in it.
pub fn contact_sheet(tiles: &[Tile], columns: u32, title: Option<&str>) -> Sheet {
    let columns = columns.max(1) as usize;
    let col_w = tiles.iter().map(|t| t.image.width).max().unwrap_or(0);
    let rows: Vec<&[Tile]> = tiles.chunks(columns).collect();
    let row_h: Vec<u32> = rows
        .iter()
        .map(|r| {
            let pic = r.iter().map(|t| t.image.height).max().unwrap_or(0);
            let lines = r.iter().map(|t| t.caption.len() as u32).max().unwrap_or(0);
            pic + if lines > 0 { 2 + lines * LINE } else { 0 }
        })
        .collect();
    let top = GAP + if title.is_some() { LINE + GAP / 2 } else { 0 };
    let used_cols = columns.min(tiles.len()) as u32;
    let width = (GAP + used_cols * (col_w + GAP)).max(GAP * 2);
    let height = top + row_h.iter().map(|h| h + GAP).sum::<u32>();
    let mut image = Image::filled(width, height.max(GAP * 2), BACKGROUND);
    let style = MonoTextStyle::new(&FONT_6X10, INK);
    let max_chars = |w: u32| (w / CHAR_W) as usize;
    if let Some(t) = title {
        draw_text(&mut image, t, GAP, GAP, max_chars(width - 2 * GAP), style);
    }
    let mut origins = Vec::with_capacity(tiles.len());
    let mut y = top;
    for (r, row) in rows.iter().enumerate() {
        let pic_h = row.iter().map(|t| t.image.height).max().unwrap_or(0);
        for (c, tile) in row.iter().enumerate() {
            let x = GAP + c as u32 * (col_w + GAP);
            image.blit(&tile.image, x, y);
            origins.push((x, y));
            for (k, line) in tile.caption.iter().enumerate() {
                let ty = y + pic_h + 2 + k as u32 * LINE;
                draw_text(&mut image, line, x, ty, max_chars(tile.image.width.max(col_w)), style);
            }
        }
        y += row_h[r] + GAP;
    }
    Sheet { image, origins }
}

fn draw_text(image: &mut Image, text: &str, x: u32, y: u32, max_chars: usize, style: MonoTextStyle<'_, Rgb888>) {
    // The font covers ASCII; anything else shows as '?'.
    let shown: String = text
        .chars()
        .take(max_chars)
        .map(|c| if c.is_ascii() && !c.is_ascii_control() { c } else { '?' })
        .collect();
    let _ = Text::with_baseline(&shown, Point::new(x as i32, y as i32), style, Baseline::Top).draw(image);
}

/// A one-line summary of a camera for a caption: the pinhole, or the focal
/// length, the distance in focus, the lens radius with its f-number, and the
/// blades (`f 4  focus 8  r 0.2 f/10  6 blades`).
pub fn camera_caption(c: &CameraParams) -> String {
    let num = |x: f64| {
        let s = format!("{x:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    if c.radius <= 0.0 {
        return format!("pinhole  f {}  N {}", num(c.focal_length), num(c.image_distance));
    }
    let mut s = format!(
        "f {}  focus {}  r {} f/{}",
        num(c.focal_length),
        num(c.focus_depth()),
        num(c.radius),
        num(c.f_number())
    );
    if c.aperture_blades > 0 {
        s += &format!("  {} blades", c.aperture_blades);
    }
    s
}
