//! `lensray sheet`: several scenes rendered side by side with captions, in one PNG or BMP.

use std::path::PathBuf;

use clap::Args;
use lensray::{Scalar, Scene, I16F16};
use lensray_host::sheet::{camera_caption, contact_sheet, Tile};
use lensray_host::{encode, load_scene, write_atomic, Format};

use crate::cli::opts::{self, image_size, render_with_progress, whole};
use crate::Fail;

/// Tile width without `--width`.
const DEFAULT_WIDTH: u32 = 320;

/// Renders several scenes side by side, captioned, in one image
///
/// Renders each scene and lays them side by side, each captioned with its file name and camera,
/// under an optional title, in one PNG or BMP.
#[derive(Args, Debug)]
pub(crate) struct SheetArgs {
    /// The scene files
    #[arg(value_name = "SCENE", required = true)]
    scenes: Vec<PathBuf>,
    /// Output image, .png or .bmp
    #[arg(short = 'o', long = "output", value_name = "SHEET", default_value = "sheet.png")]
    out: PathBuf,
    /// Renders a row (1 to 64) [default: the number of scenes, up to 4]
    #[arg(long, value_name = "C", value_parser = whole(1, 64))]
    columns: Option<u32>,
    /// A title above the renders
    #[arg(long, value_name = "TEXT")]
    title: Option<String>,
    #[command(flatten)]
    size: opts::Size,
    /// Renders with the f32 reference instead of Q16.16
    #[arg(long)]
    float: bool,
    #[command(flatten)]
    sampling: opts::Sampling,
}

pub(crate) fn run(o: SheetArgs) -> Result<(), Fail> {
    let out = &o.out;
    let format = Format::of(out).ok_or_else(|| Fail(format!("{}: output must end in .bmp or .png", out.display())))?;
    if out.is_dir() {
        return Err(Fail(format!("{}: is a directory", out.display())));
    }
    let tiles = if o.float {
        tiles::<f32>(&o)?
    } else {
        tiles::<I16F16>(&o)?
    };
    let n = tiles.len() as u32;
    let sheet = contact_sheet(&tiles, o.columns.unwrap_or(n.min(4)), o.title.as_deref());
    let bytes = encode(&sheet.image, format)?;
    write_atomic(out, &bytes).map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())))?;
    eprintln!(
        "wrote {} ({}x{}, {n} renders)",
        out.display(),
        sheet.image.width,
        sheet.image.height
    );
    Ok(())
}

/// Parses every scene first (a bad one fails before any long render), then renders each.
fn tiles<S: Scalar + Send + Sync>(o: &SheetArgs) -> Result<Vec<Tile>, Fail> {
    let scenes: Vec<(String, Scene<S>)> = o
        .scenes
        .iter()
        .map(|path| {
            let name = path
                .file_stem()
                .map_or_else(|| path.display().to_string(), |s| s.to_string_lossy().into_owned());
            let mut scene = load_scene::<S>(path)?;
            opts::apply_to_scene(&o.sampling, &mut scene);
            Ok((name, scene))
        })
        .collect::<Result<_, Fail>>()?;
    let mut tiles = Vec::with_capacity(scenes.len());
    for (name, scene) in &scenes {
        let (w, h) = image_size(&o.size, DEFAULT_WIDTH, scene.camera.aspect_ratio)?;
        let image = render_with_progress(scene, w, h, o.size.samples).0;
        tiles.push(Tile {
            image,
            caption: vec![name.clone(), camera_caption(&scene.camera)],
        });
    }
    Ok(tiles)
}
