//! `lensray render`: a scene file to a BMP or PNG image.

use std::path::{Path, PathBuf};

use lensray::{Scalar, I16F16};
use lensray_host::{encode, load_scene, write_atomic, Format};

use crate::cli::opts::{apply_to_scene, image_size, parse_opts, render_passes_to, render_with_progress};
use crate::{Fail, USAGE};

pub(crate) fn run(args: &[String]) -> Result<(), Fail> {
    let o = parse_opts(args)?;
    let [scene_path] = o.positional.as_slice() else {
        return Err(Fail(format!("render takes one scene file\n{USAGE}")));
    };
    let scene_path = Path::new(scene_path);
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
    // Rays are counted by the plain render; progressive passes cast the same.
    let (img, kind, rays) = if o.float {
        let mut scene = load_scene::<f32>(scene_path)?;
        apply_to_scene(&o, &mut scene);
        let (w, h) = image_size(&o, scene.camera.aspect_ratio)?;
        match &o.passes {
            Some(dir) => (render_passes_to(&scene, w, h, &o, dir)?, f32::NAME, None),
            None => {
                let (img, rays) = render_with_progress(&scene, w, h, o.samples);
                (img, f32::NAME, Some(rays))
            }
        }
    } else {
        let mut scene = load_scene::<I16F16>(scene_path)?;
        apply_to_scene(&o, &mut scene);
        let (w, h) = image_size(&o, scene.camera.aspect_ratio)?;
        match &o.passes {
            Some(dir) => (render_passes_to(&scene, w, h, &o, dir)?, I16F16::NAME, None),
            None => {
                let (img, rays) = render_with_progress(&scene, w, h, o.samples);
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
