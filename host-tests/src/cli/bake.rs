//! `lensray bake`: sets a scene up on the host for one image size and writes
//! it as a baked scene (`lensray::baked`), the form firmware loads without a
//! parser or `f64`.

use std::path::{Path, PathBuf};

use lensray::baked::{bake, baked_len, BakeScalar};
use lensray::{Renderer, I16F16};
use lensray_host::{load_scene, write_atomic};

use crate::cli::opts::{apply_to_scene, image_size, parse_opts, RenderOpts};
use crate::{Fail, USAGE};

/// Image width without `--width`: a small panel's, as `emulate` uses.
const DEFAULT_WIDTH: u32 = 160;

pub(crate) fn run(args: &[String]) -> Result<(), Fail> {
    let mut o = parse_opts(args)?;
    if o.passes.is_some() || o.first_step.is_some() || o.preview_samples.is_some() {
        return Err(Fail("bake takes no --passes, --first-step or --preview-samples".into()));
    }
    o.width = o.width.or(Some(DEFAULT_WIDTH));
    let [scene_path] = o.positional.as_slice() else {
        return Err(Fail(format!("bake takes one scene file\n{USAGE}")));
    };
    let scene_path = Path::new(scene_path);
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

fn bytes_of<S: BakeScalar>(scene_path: &Path, o: &RenderOpts) -> Result<Vec<u8>, Fail> {
    let mut scene = load_scene::<S>(scene_path)?;
    apply_to_scene(o, &mut scene);
    let (w, h) = image_size(o, scene.camera.aspect_ratio)?;
    let mut renderer = Renderer::new(&scene, w, h);
    if let Some(n) = o.samples {
        renderer = renderer.with_samples(n);
    }
    let mut bytes = vec![0u8; baked_len(&renderer)];
    bake(&renderer, &mut bytes)?;
    eprintln!(
        "baked {} for {w}x{h}, {}, {} rays a pixel: {} bytes",
        scene_path.display(),
        S::NAME,
        renderer.rays_per_pixel(),
        bytes.len()
    );
    Ok(bytes)
}
