//! lensray's host side: whole-image rendering on all cores, BMP and PNG files,
//! scene files, progressive passes, panels and contact sheets, and the studies
//! that render many whole images (sweeps, convergence). The `lensray` command
//! (`src/main.rs`, `src/cli/`) and the host tests (`tests/`) are built on it;
//! images, their differences and the fuzzer are the test kit's (`testkit/`).

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use lensray::{Renderer, Scalar, Scene};
use rayon::prelude::*;

pub mod convergence;
pub mod mat34;
pub mod panel;
pub mod passes;
pub mod reference64;
pub mod sheet;
pub mod sweep;

pub use lensray_testkit::{Diff, Image, LineErrors};

/// Largest image side the simulator accepts (the camera's limit).
pub const MAX_SIDE: u32 = lensray::MAX_IMAGE_SIDE;

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
    let renderer = Renderer::new_with_samples(scene, width, height, samples);
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
    // The adaptive survey's rays (set-up) count too.
    let survey = renderer.stop_rule().map_or(0, |s| s.survey_rays as u64);
    (Image { width, height, pixels }, rays + survey)
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

/// `text` parsed in Q16.16 and f32 with adaptive sampling off: every pixel
/// casts its samples, as the accuracy comparisons need. Panics on a bad scene
/// (generated or corpus text: a bug, not input).
pub fn both_unadaptive(text: &str) -> (Scene<lensray::I16F16>, Scene<f32>) {
    let mut fixed = Scene::<lensray::I16F16>::parse(text).unwrap_or_else(|e| panic!("{e}"));
    let mut float = Scene::<f32>::parse(text).unwrap_or_else(|e| panic!("{e}"));
    fixed.camera.adaptive = false;
    float.camera.adaptive = false;
    (fixed, float)
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
