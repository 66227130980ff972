//! Image measures for the tests of the paper's claims: focus and extent.

use embedded_graphics::pixelcolor::RgbColor;

use crate::Image;

/// An axis-aligned pixel box: columns `x0..x1`, rows `y0..y1`.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct PixelBox {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

/// Luma of a pixel (Rec. 601 weights), 0 to 255.
pub fn luma(img: &Image, x: u32, y: u32) -> f64 {
    let p = img.get(x, y);
    0.299 * p.r() as f64 + 0.587 * p.g() as f64 + 0.114 * p.b() as f64
}

/// Mean gradient energy (squared central differences of luma) in a box:
/// high for crisp edges, lower as they blur. Compare it between renders of
/// the same scene and box only.
pub fn gradient_energy(img: &Image, b: PixelBox) -> f64 {
    gradient_energy_where(img, b, |_, _| true)
}

/// Mean gradient energy over the pixels of a box for which `pred` holds
/// (e.g. a ring around a silhouette): as [`gradient_energy`], but
/// background texture outside the mask does not count.
pub fn gradient_energy_where(img: &Image, b: PixelBox, pred: impl Fn(u32, u32) -> bool) -> f64 {
    let (x0, y0) = (b.x0.max(1), b.y0.max(1));
    let (x1, y1) = (b.x1.min(img.width - 1), b.y1.min(img.height - 1));
    let mut sum = 0.0;
    let mut n = 0u64;
    for y in y0..y1 {
        for x in (x0..x1).filter(|&x| pred(x, y)) {
            let gx = (luma(img, x + 1, y) - luma(img, x - 1, y)) / 2.0;
            let gy = (luma(img, x, y + 1) - luma(img, x, y - 1)) / 2.0;
            sum += gx * gx + gy * gy;
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}

/// The smallest box holding every pixel for which `pred` holds, if any.
pub fn extent(img: &Image, pred: impl Fn(u32, u32) -> bool) -> Option<PixelBox> {
    let mut b: Option<PixelBox> = None;
    for y in 0..img.height {
        for x in 0..img.width {
            if pred(x, y) {
                let e = b.get_or_insert(PixelBox {
                    x0: x,
                    y0: y,
                    x1: x + 1,
                    y1: y + 1,
                });
                e.x0 = e.x0.min(x);
                e.y0 = e.y0.min(y);
                e.x1 = e.x1.max(x + 1);
                e.y1 = e.y1.max(y + 1);
            }
        }
    }
    b
}
