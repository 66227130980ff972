//! lensray's host side: whole-image rendering on all cores, BMP and PNG files,
//! and image comparison. The `lensray` command (`src/main.rs`) and the host
//! tests (`tests/`) are built on it.

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use lensray::{Renderer, Scalar, Scene};
use rayon::prelude::*;

pub mod canvas;
pub mod convergence;
pub mod fuzz;
pub mod panel;
pub mod passes;
pub mod scenegen;
pub mod sheet;
pub mod sweep;

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

/// Largest image side the simulator accepts (the camera's limit).
pub const MAX_SIDE: u32 = lensray::camera::MAX_IMAGE_SIDE;

/// Renders a whole image, rows in parallel on rayon's pool (all cores unless
/// the pool is limited). The pixels do not depend on the order or the threads.
///
/// `on_row` is called once per finished row (for a progress bar).
pub fn render_image<S: Scalar + Send + Sync>(
    scene: &Scene<S>,
    width: u32,
    height: u32,
    samples: Option<u32>,
    on_row: &(dyn Fn() + Sync),
) -> Image {
    render_image_counted(scene, width, height, samples, on_row).0
}

/// [`render_image`], and the lens rays it cast in all (one a pixel for a pinhole).
pub fn render_image_counted<S: Scalar + Send + Sync>(
    scene: &Scene<S>,
    width: u32,
    height: u32,
    samples: Option<u32>,
    on_row: &(dyn Fn() + Sync),
) -> (Image, u64) {
    let mut renderer = Renderer::new(scene, width, height);
    if let Some(n) = samples {
        renderer = renderer.with_samples(n);
    }
    // Rows straight into the image: no per-row allocation, no copy at the end.
    let mut pixels = vec![Rgb888::BLACK; width as usize * height as usize];
    let mut rays = 0;
    if width > 0 {
        // One row a task: rayon otherwise stops splitting at a few chunks of
        // many rows, and a small frame ends with one core finishing the last chunk.
        rays = pixels
            .par_chunks_mut(width as usize)
            .with_max_len(1)
            .enumerate()
            .map(|(row, out)| {
                let n = renderer.render_row(row as u32, out);
                on_row();
                n as u64
            })
            .sum();
    }
    (Image { width, height, pixels }, rays)
}

/// Encodes a 24-bit uncompressed BMP (bottom-up rows, padded to 4 bytes).
pub fn encode_bmp(img: &Image) -> Vec<u8> {
    let row_bytes = (img.width as usize * 3).div_ceil(4) * 4;
    let data_len = row_bytes * img.height as usize;
    let file_len = 54 + data_len;
    let mut out = Vec::with_capacity(file_len);
    out.extend_from_slice(b"BM");
    out.extend_from_slice(&(file_len as u32).to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&54u32.to_le_bytes());
    // BITMAPINFOHEADER.
    out.extend_from_slice(&40u32.to_le_bytes());
    out.extend_from_slice(&(img.width as i32).to_le_bytes());
    out.extend_from_slice(&(img.height as i32).to_le_bytes());
    out.extend_from_slice(&1u16.to_le_bytes());
    out.extend_from_slice(&24u16.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&(data_len as u32).to_le_bytes());
    out.extend_from_slice(&2835u32.to_le_bytes());
    out.extend_from_slice(&2835u32.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    for y in (0..img.height).rev() {
        let start = out.len();
        for x in 0..img.width {
            let p = img.get(x, y);
            out.extend_from_slice(&[p.b(), p.g(), p.r()]);
        }
        out.resize(start + row_bytes, 0);
    }
    out
}

/// The output formats, by file extension.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Format {
    /// 24-bit BMP.
    Bmp,
    /// 8-bit RGB PNG.
    Png,
}

impl Format {
    /// The format a path's extension names (`.bmp`, `.png`, any case).
    pub fn of(path: &Path) -> Option<Format> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "bmp" => Some(Format::Bmp),
            "png" => Some(Format::Png),
            _ => None,
        }
    }
}

/// Encodes an image in a format.
pub fn encode(img: &Image, format: Format) -> Result<Vec<u8>, String> {
    match format {
        Format::Bmp => Ok(encode_bmp(img)),
        Format::Png => {
            let mut out = Vec::new();
            let buf = image::RgbImage::from_raw(img.width, img.height, img.to_rgb_bytes())
                .ok_or("image buffer has the wrong size")?;
            buf.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
                .map_err(|e| e.to_string())?;
            Ok(out)
        }
    }
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, then a
/// rename, so an error or an interrupt never leaves a half-written file in
/// place of a good one.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Reads a BMP (through tinybmp) or PNG file back into an [`Image`].
pub fn load_image(path: &Path) -> Result<Image, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    decode_image(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Decodes BMP (tinybmp) or PNG bytes.
pub fn decode_image(bytes: &[u8]) -> Result<Image, String> {
    if bytes.starts_with(b"BM") {
        use embedded_graphics::prelude::*;
        let bmp = tinybmp::Bmp::<Rgb888>::from_slice(bytes).map_err(|e| format!("not a readable BMP: {e:?}"))?;
        let size = bmp.size();
        let mut pixels = vec![Rgb888::BLACK; (size.width * size.height) as usize];
        for Pixel(p, c) in bmp.pixels() {
            pixels[(p.y as u32 * size.width + p.x as u32) as usize] = c;
        }
        return Ok(Image {
            width: size.width,
            height: size.height,
            pixels,
        });
    }
    let img = image::load_from_memory(bytes)
        .map_err(|e| format!("not a readable image: {e}"))?
        .to_rgb8();
    Ok(Image {
        width: img.width(),
        height: img.height(),
        pixels: img.pixels().map(|p| Rgb888::new(p[0], p[1], p[2])).collect(),
    })
}

/// A scene file that could not be used: its message is `FILE:LINE: message`
/// for a format error, `FILE: message` when the file cannot be read.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError(pub String);

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Reads and parses a scene file in the number type `S`.
pub fn load_scene<S: Scalar>(path: &Path) -> Result<Scene<S>, SceneError> {
    let shown = path.display();
    if path.is_dir() {
        return Err(SceneError(format!("{shown}: is a directory, not a scene file")));
    }
    let bytes = std::fs::read(path).map_err(|e| SceneError(format!("{shown}: cannot read: {e}")))?;
    Scene::<S>::parse_bytes(&bytes).map_err(|e| SceneError(format!("{shown}:{}: {}", e.line, e.kind)))
}

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

/// A scene rendered in both number types at the same size and samples:
/// Q16.16 first, the f32 reference second.
pub fn render_both(
    fixed: &Scene<lensray::I16F16>,
    float: &Scene<f32>,
    width: u32,
    height: u32,
    samples: Option<u32>,
) -> (Image, Image) {
    let none = || {};
    (
        render_image(fixed, width, height, samples, &none),
        render_image(float, width, height, samples, &none),
    )
}

/// Image measures for the tests of the paper's claims: focus and extent.
pub mod measure {
    use super::Image;
    use embedded_graphics::pixelcolor::RgbColor;

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
}
