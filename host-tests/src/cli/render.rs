//! `lensray render`: a scene file to a BMP or PNG image.

use std::path::{Path, PathBuf};

use clap::Args;
use lensray::{Scalar, I16F16};
use lensray_host::panel::PanelFormat;
use lensray_host::{encode, load_scene, write_atomic, Format};

use crate::cli::opts::{self, apply_to_scene, image_size, render_passes_to, render_with_progress};
use crate::Fail;

/// Image width without `--width`.
const DEFAULT_WIDTH: u32 = 640;

/// Renders a scene file to a BMP or PNG image
///
/// Renders in Q16.16 (or f32 with --float) on all cores and prints the mean lens rays cast a pixel.
#[derive(Args, Debug)]
pub(crate) struct RenderArgs {
    /// The scene file
    #[arg(value_name = "SCENE")]
    scene: PathBuf,
    /// Output image, .bmp or .png [default: the scene's name with .bmp, in the current directory]
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    out: Option<PathBuf>,
    #[command(flatten)]
    size: opts::Size,
    /// Renders with the f32 reference instead of Q16.16
    #[arg(long)]
    float: bool,
    #[command(flatten)]
    sampling: opts::Sampling,
    #[command(flatten)]
    passes: opts::Passes,
    /// Writes the image as a 16-bit panel shows it (each pixel to RGB 5-6-5 and back, by embedded-graphics' conversions)
    #[arg(long, value_name = "FORMAT", value_parser = opts::panel)]
    panel: Option<PanelFormat>,
}

pub(crate) fn run(o: RenderArgs) -> Result<(), Fail> {
    let scene_path = o.scene.as_path();
    if scene_path.is_dir() {
        return Err(Fail(format!(
            "{}: is a directory, not a scene file",
            scene_path.display()
        )));
    }
    let out = match &o.out {
        Some(p) => p.clone(),
        None => {
            let stem = scene_path.file_stem().ok_or("the scene path has no file name")?;
            PathBuf::from(stem).with_extension("bmp")
        }
    };
    let format = Format::of(&out).ok_or_else(|| Fail(format!("{}: output must end in .bmp or .png", out.display())))?;
    if out.is_dir() {
        return Err(Fail(format!("{}: is a directory", out.display())));
    }
    check_writable(&out)?;
    // Rays: what the pixels and the survey cast (with --passes, every pass's: the preview's too).
    let (img, kind, rays) = if o.float {
        let mut scene = load_scene::<f32>(scene_path)?;
        apply_to_scene(&o.sampling, &mut scene);
        let (w, h) = image_size(&o.size, DEFAULT_WIDTH, scene.camera.aspect_ratio)?;
        match &o.passes.passes {
            Some(dir) => {
                let (img, rays) = render_passes_to(&scene, w, h, o.size.samples, &o.passes, dir)?;
                (img, f32::NAME, Some(rays))
            }
            None => {
                let (img, rays) = render_with_progress(&scene, w, h, o.size.samples);
                (img, f32::NAME, Some(rays))
            }
        }
    } else {
        let mut scene = load_scene::<I16F16>(scene_path)?;
        apply_to_scene(&o.sampling, &mut scene);
        let (w, h) = image_size(&o.size, DEFAULT_WIDTH, scene.camera.aspect_ratio)?;
        match &o.passes.passes {
            Some(dir) => {
                let (img, rays) = render_passes_to(&scene, w, h, o.size.samples, &o.passes, dir)?;
                (img, I16F16::NAME, Some(rays))
            }
            None => {
                let (img, rays) = render_with_progress(&scene, w, h, o.size.samples);
                (img, I16F16::NAME, Some(rays))
            }
        }
    };
    // A panel's format is applied last, so --passes saves the full-depth passes.
    let img = match o.panel {
        Some(panel) => panel.quantise(&img),
        None => img,
    };
    let bytes = encode(&img, format)?;
    write_atomic(&out, &bytes).map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())))?;
    eprintln!("wrote {} ({}x{}, {kind})", out.display(), img.width, img.height);
    if let Some(rays) = rays {
        let pixels = img.width as f64 * img.height as f64;
        println!("rays per pixel: {:.2}", rays as f64 / pixels);
    }
    Ok(())
}

/// Refuses an output that cannot be written before any rendering: its folder
/// must exist and take a new file (tried with a probe file, removed at once).
fn check_writable(out: &Path) -> Result<(), Fail> {
    let dir = match out.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(Fail(format!(
            "{}: cannot write: {} is not a directory",
            out.display(),
            dir.display()
        )));
    }
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let probe = dir.join(format!(".{name}.{}.probe", std::process::id()));
    match std::fs::OpenOptions::new().write(true).create_new(true).open(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(Fail(format!("{}: cannot write: {e}", out.display()))),
    }
}
