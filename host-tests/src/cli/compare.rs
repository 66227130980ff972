//! `lensray compare`: what fixed point costs, in numbers and as a heat map.
//!
//! `compare SCENE` renders the scene in Q16.16 and with the f32 reference at the
//! same size and samples; `compare A B` compares two image files. Both print
//! PSNR, mean and max error, the share of pixels within 1, 2 and 8 levels and
//! the worst row and column; `--diff OUT` writes the error as a heat map.

use std::path::{Path, PathBuf};

use clap::Args;
use lensray::{Renderer, I16F16};
use lensray_host::{encode, load_image, load_scene, write_atomic, Diff, Format, Image, LineErrors};

use crate::cli::opts::{self, image_size, render_with_progress};
use crate::Fail;

/// Image width without `--width`, as for `render`.
const DEFAULT_WIDTH: u32 = 640;

/// Prints how two renders differ: Q16.16 against f32, or two images
///
/// Renders a scene in Q16.16 and with the f32 reference (same size, same samples), or reads two
/// images (.bmp or .png), and prints PSNR, mean and max error, the share of pixels within 1, 2
/// and 8 levels, and the worst row and column.
#[derive(Args, Debug)]
pub(crate) struct CompareArgs {
    /// One scene file, or two images
    #[arg(value_name = "SCENE | A B", required = true, num_args = 1..=2)]
    files: Vec<PathBuf>,
    /// Writes the error as a heat map (.png or .bmp): black where equal, brighter where worse, white from 8 levels
    #[arg(long, value_name = "OUT")]
    diff: Option<PathBuf>,
    #[command(flatten)]
    size: opts::Size,
}

pub(crate) fn run(o: CompareArgs) -> Result<(), Fail> {
    // Check the heat map's name before minutes of rendering, not after.
    let diff_format = match &o.diff {
        Some(p) => {
            if p.is_dir() {
                return Err(Fail(format!("{}: is a directory", p.display())));
            }
            Some(Format::of(p).ok_or_else(|| Fail(format!("{}: --diff must end in .bmp or .png", p.display())))?)
        }
        None => None,
    };
    let (a, b) = match o.files.as_slice() {
        [scene] => compare_scene(scene, &o.size)?,
        [first, second] => {
            if o.size.width.is_some() || o.size.height.is_some() || o.size.samples.is_some() {
                return Err(Fail(
                    "--width, --height and --samples apply to a scene, not to two images".into(),
                ));
            }
            let (a, b) = (load_image(first)?, load_image(second)?);
            say(format_args!("{} against {}", first.display(), second.display()));
            (a, b)
        }
        _ => return Err(Fail("compare takes one scene file or two images".into())),
    };
    let mismatch = || {
        Fail(format!(
            "the images differ in size: {}x{} and {}x{}",
            a.width, a.height, b.width, b.height
        ))
    };
    let diff = Diff::of(&a, &b).ok_or_else(mismatch)?;
    say(format_args!("{diff}"));
    if let Some(lines) = LineErrors::of(&a, &b) {
        say(format_args!("{lines}"));
    }
    if let (Some(path), Some(format)) = (&o.diff, diff_format) {
        let heat = Diff::heat_map(&a, &b).ok_or_else(mismatch)?;
        let bytes = encode(&heat, format)?;
        write_atomic(path, &bytes).map_err(|e| Fail(format!("{}: cannot write: {e}", path.display())))?;
        eprintln!(
            "wrote {} (black: equal; dark red 1 level, up to yellow 7, white 8 or more)",
            path.display()
        );
    }
    Ok(())
}

/// Prints a line to stdout; a closed pipe (`| head`) is not an error worth a panic.
fn say(args: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let _ = writeln!(std::io::stdout().lock(), "{args}");
}

/// Renders a scene with Q16.16 and with f32: (Q16.16 image, f32 image).
fn compare_scene(path: &Path, o: &opts::Size) -> Result<(Image, Image), Fail> {
    let fixed = load_scene::<I16F16>(path)?;
    let float = load_scene::<f32>(path)?;
    let (w, h) = image_size(o, DEFAULT_WIDTH, fixed.camera.aspect_ratio)?;
    let probe = Renderer::new_with_samples(&fixed, w, h, o.samples);
    say(format_args!(
        "{}: Q16.16 against f32, {w}x{h}, {} ray(s) a pixel",
        path.display(),
        probe.rays_per_pixel()
    ));
    let a = render_with_progress(&fixed, w, h, o.samples).0;
    let b = render_with_progress(&float, w, h, o.samples).0;
    Ok((a, b))
}
