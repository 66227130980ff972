//! How two images differ: error figures, a heat map, and where the error lines up.

use std::fmt;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};

use crate::Image;

/// How two images differ, channel by channel (8-bit levels).
#[derive(Clone, Debug, PartialEq)]
pub struct Diff {
    /// Peak signal-to-noise ratio in dB (infinite for identical images).
    pub psnr: f64,
    /// Mean absolute error per channel.
    pub mean: f64,
    /// Largest absolute error of any channel.
    pub max: u8,
    /// Share of pixels whose channels are all within 1, 2 and 8 levels.
    pub within: [f64; 3],
}

impl Diff {
    /// Compares two images of the same size (`None` when sizes differ).
    pub fn of(a: &Image, b: &Image) -> Option<Diff> {
        if (a.width, a.height) != (b.width, b.height) {
            return None;
        }
        let n = a.pixels.len().max(1) as f64;
        let (mut se, mut ae, mut max) = (0.0f64, 0.0f64, 0u8);
        let mut within = [0usize; 3];
        for (p, q) in a.pixels.iter().zip(&b.pixels) {
            let d = [p.r().abs_diff(q.r()), p.g().abs_diff(q.g()), p.b().abs_diff(q.b())];
            let m = *d.iter().max().unwrap_or(&0);
            for (k, lim) in [1u8, 2, 8].iter().enumerate() {
                if m <= *lim {
                    within[k] += 1;
                }
            }
            max = max.max(m);
            for x in d {
                se += (x as f64).powi(2);
                ae += x as f64;
            }
        }
        let mse = se / (3.0 * n);
        Some(Diff {
            psnr: if mse == 0.0 {
                f64::INFINITY
            } else {
                10.0 * (255.0f64 * 255.0 / mse).log10()
            },
            mean: ae / (3.0 * n),
            max,
            within: within.map(|w| w as f64 / n),
        })
    }

    /// A heat map of the error: black where equal, brighter where worse
    /// (the largest channel error, scaled so 8 levels or more is white).
    pub fn heat_map(a: &Image, b: &Image) -> Option<Image> {
        if (a.width, a.height) != (b.width, b.height) {
            return None;
        }
        let pixels = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(p, q)| {
                let m = p
                    .r()
                    .abs_diff(q.r())
                    .max(p.g().abs_diff(q.g()))
                    .max(p.b().abs_diff(q.b()));
                // 1 level shows dark red, 2-7 orange to yellow, 8+ white.
                let v = (m as u32 * 32).min(255) as u8;
                match m {
                    0 => Rgb888::BLACK,
                    1..=7 => Rgb888::new(v.max(96), v / 2, 0),
                    _ => Rgb888::WHITE,
                }
            })
            .collect();
        Some(Image {
            width: a.width,
            height: a.height,
            pixels,
        })
    }
}

impl fmt::Display for Diff {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "PSNR        {:.2} dB", self.psnr)?;
        writeln!(f, "mean error  {:.4} levels", self.mean)?;
        writeln!(f, "max error   {} levels", self.max)?;
        writeln!(f, "within 1    {:.3} %", self.within[0] * 100.0)?;
        writeln!(f, "within 2    {:.3} %", self.within[1] * 100.0)?;
        write!(f, "within 8    {:.3} %", self.within[2] * 100.0)
    }
}

/// Where the error between two images lines up, row by row and column by
/// column (levels of 255).
///
/// A render whose error is noise keeps these near the image's own mean error;
/// a systematic fault (a row of pixels shifted, a band of flipped checker
/// squares, a colour rounded the wrong way over a whole face) shows up as one
/// line far above it. Two measures per line: the mean of each pixel's worst
/// channel error (noise counts), and the bias, the largest mean signed error
/// `a − b` of any channel (noise cancels, a consistent shift does not).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct LineErrors {
    /// The row with the largest mean error: (row, mean).
    pub worst_row: (u32, f64),
    /// The column with the largest mean error: (column, mean).
    pub worst_col: (u32, f64),
    /// The row with the largest bias: (row, |mean signed error|).
    pub worst_row_bias: (u32, f64),
    /// The column with the largest bias: (column, |mean signed error|).
    pub worst_col_bias: (u32, f64),
}

impl LineErrors {
    /// Row and column errors of two images of the same size (`None` when
    /// sizes differ or an image is empty).
    pub fn of(a: &Image, b: &Image) -> Option<LineErrors> {
        if (a.width, a.height) != (b.width, b.height) || a.pixels.is_empty() {
            return None;
        }
        let (w, h) = (a.width as usize, a.height as usize);
        // Per line: sum of worst-channel errors, and signed sums per channel.
        let mut rows = vec![(0i64, [0i64; 3]); h];
        let mut cols = vec![(0i64, [0i64; 3]); w];
        for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
            let d = [
                p.r() as i64 - q.r() as i64,
                p.g() as i64 - q.g() as i64,
                p.b() as i64 - q.b() as i64,
            ];
            let m = d.iter().map(|x| x.abs()).max().unwrap_or(0);
            for line in [&mut rows[i / w], &mut cols[i % w]] {
                line.0 += m;
                for (sum, x) in line.1.iter_mut().zip(d) {
                    *sum += x;
                }
            }
        }
        let worst = |lines: &[(i64, [i64; 3])], n: usize, f: fn(&(i64, [i64; 3])) -> i64| {
            let (i, s) = lines
                .iter()
                .enumerate()
                .map(|(i, l)| (i, f(l)))
                .max_by_key(|(_, s)| *s)
                .unwrap_or((0, 0));
            (i as u32, s as f64 / n as f64)
        };
        let abs = |l: &(i64, [i64; 3])| l.0;
        let bias = |l: &(i64, [i64; 3])| l.1.iter().map(|x| x.abs()).max().unwrap_or(0);
        Some(LineErrors {
            worst_row: worst(&rows, w, abs),
            worst_col: worst(&cols, h, abs),
            worst_row_bias: worst(&rows, w, bias),
            worst_col_bias: worst(&cols, h, bias),
        })
    }
}

impl fmt::Display for LineErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (r, c, rb, cb) = (self.worst_row, self.worst_col, self.worst_row_bias, self.worst_col_bias);
        writeln!(f, "worst row   {:.4} levels mean, row {}", r.1, r.0)?;
        writeln!(f, "worst col   {:.4} levels mean, column {}", c.1, c.0)?;
        writeln!(f, "row bias    {:.4} levels, row {}", rb.1, rb.0)?;
        write!(f, "col bias    {:.4} levels, column {}", cb.1, cb.0)
    }
}
