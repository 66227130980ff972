//! `lensray bake`: sets a scene up on the host for one image size and writes
//! it as a baked scene (`lensray::baked`), the form firmware loads without a
//! parser or `f64`.

use std::path::{Path, PathBuf};

use clap::Args;
use lensray::baked::{bake, baked_len, BakeScalar};
use lensray::{Renderer, I16F16};
use lensray_host::{load_scene, write_atomic};

use crate::cli::opts::{self, apply_to_scene, image_size};
use crate::Fail;

/// Image width without `--width`: a small panel's, as `emulate` uses.
const DEFAULT_WIDTH: u32 = 160;

/// Writes a scene set up for one image size, as firmware loads it
///
/// Sets a scene up for one image size and writes it as a baked scene: little-endian, versioned,
/// CRC-32 checked, what the firmware loads without a parser (README, "Baked scenes").
#[derive(Args, Debug)]
pub(crate) struct BakeArgs {
    /// The scene file
    #[arg(value_name = "SCENE")]
    scene: PathBuf,
    /// Output file [default: the scene's name with .lrbk, in the current directory]
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    out: Option<PathBuf>,
    #[command(flatten)]
    size: opts::Size,
    /// Bakes the f32 renderer's set-up instead of Q16.16's
    #[arg(long)]
    float: bool,
    #[command(flatten)]
    sampling: opts::Sampling,
}

pub(crate) fn run(o: BakeArgs) -> Result<(), Fail> {
    let scene_path = o.scene.as_path();
    let out = match &o.out {
        Some(p) => p.clone(),
        None => {
            let stem = scene_path.file_stem().ok_or("the scene path has no file name")?;
            PathBuf::from(format!("{}.lrbk", stem.to_string_lossy()))
        }
    };
    if out.is_dir() {
        return Err(Fail(format!("{}: is a directory", out.display())));
    }
    let bytes = if o.float {
        bytes_of::<f32>(scene_path, &o)?
    } else {
        bytes_of::<I16F16>(scene_path, &o)?
    };
    write_atomic(&out, &bytes).map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())))?;
    Ok(())
}

fn bytes_of<S: BakeScalar>(scene_path: &Path, o: &BakeArgs) -> Result<Vec<u8>, Fail> {
    let mut scene = load_scene::<S>(scene_path)?;
    apply_to_scene(&o.sampling, &mut scene);
    let (w, h) = image_size(&o.size, DEFAULT_WIDTH, scene.camera.aspect_ratio)?;
    let renderer = Renderer::new_with_samples(&scene, w, h, o.size.samples);
    let mut bytes = vec![0u8; baked_len(&renderer)];
    bake(&renderer, &mut bytes)?;
    // The stop rule was set on the host, by the pre-pass in `Renderer::new`:
    // the board loads it and never runs the pre-pass.
    let stop = match renderer.stop_rule() {
        Some(r) => format!(
            "stop rule: pilot {}, threshold {} (pre-pass {} rays)",
            r.pilot, r.threshold, r.survey_rays
        ),
        None => "no stop rule".to_string(),
    };
    eprintln!(
        "baked {} for {w}x{h}, {}, at most {} rays a pixel, {stop}: {} bytes",
        scene_path.display(),
        S::NAME,
        renderer.rays_per_pixel(),
        bytes.len()
    );
    Ok(bytes)
}
