//! `lensray sheet`: several scenes rendered side by side with captions, in one PNG or BMP.

use std::path::{Path, PathBuf};

use lensray::{Scalar, Scene, I16F16};
use lensray_host::sheet::{camera_caption, contact_sheet, Tile};
use lensray_host::{encode, load_scene, write_atomic, Format};

use crate::cli::opts::{image_size, parse_opts, parse_u32, render_with_progress, RenderOpts};
use crate::{Fail, USAGE};

pub(crate) fn run(args: &[String]) -> Result<(), Fail> {
    // The sheet's own options first; the rest are render's.
    let (mut columns, mut title, mut rest) = (None, None, Vec::new());
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--columns" => columns = Some(parse_u32("--columns", it.next(), 1, 64)?),
            "--title" => title = Some(it.next().ok_or("--title needs a text")?.clone()),
            _ => rest.push(a.clone()),
        }
    }
    let mut o = parse_opts(&rest)?;
    if o.passes.is_some() {
        return Err(Fail("sheet does not take --passes".into()));
    }
    if o.panel.is_some() {
        return Err(Fail("sheet does not take --panel".into()));
    }
    if o.positional.is_empty() {
        return Err(Fail(format!("sheet takes one or more scene files\n{USAGE}")));
    }
    if o.width.is_none() {
        o.width = Some(320);
    }
    let out = o.out.clone().unwrap_or_else(|| PathBuf::from("sheet.png"));
    let format = Format::of(&out).ok_or_else(|| Fail(format!("{}: output must end in .bmp or .png", out.display())))?;
    if out.is_dir() {
        return Err(Fail(format!("{}: is a directory", out.display())));
    }
    let tiles = if o.float {
        tiles::<f32>(&o)?
    } else {
        tiles::<I16F16>(&o)?
    };
    let n = tiles.len() as u32;
    let sheet = contact_sheet(&tiles, columns.unwrap_or(n.min(4)), title.as_deref());
    let bytes = encode(&sheet.image, format)?;
    write_atomic(&out, &bytes).map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())))?;
    eprintln!(
        "wrote {} ({}x{}, {n} renders)",
        out.display(),
        sheet.image.width,
        sheet.image.height
    );
    Ok(())
}

/// Parses every scene first (a bad one fails before any long render), then renders each.
fn tiles<S: Scalar + Send + Sync>(o: &RenderOpts) -> Result<Vec<Tile>, Fail> {
    let scenes: Vec<(String, Scene<S>)> = o
        .positional
        .iter()
        .map(|p| {
            let path = Path::new(p);
            let name = path
                .file_stem()
                .map_or_else(|| p.clone(), |s| s.to_string_lossy().into_owned());
            let mut scene = load_scene::<S>(path)?;
            crate::cli::opts::apply_to_scene(o, &mut scene);
            Ok((name, scene))
        })
        .collect::<Result<_, Fail>>()?;
    let mut tiles = Vec::with_capacity(scenes.len());
    for (name, scene) in &scenes {
        let (w, h) = image_size(o, scene.camera.aspect_ratio)?;
        let image = render_with_progress(scene, w, h, o.samples).0;
        tiles.push(Tile {
            image,
            caption: vec![name.clone(), camera_caption(&scene.camera)],
        });
    }
    Ok(tiles)
}
