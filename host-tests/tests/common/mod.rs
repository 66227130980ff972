//! Helpers shared by the host tests: scene files, renders in both number types.

#![allow(dead_code)]

use std::path::PathBuf;

use lensray::{Scene, I16F16};
use lensray_host::{render_image, Image};

/// The repository's `scenes/` directory.
pub fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

/// The text of `scenes/NAME`.
pub fn scene_text(name: &str) -> String {
    let p = scenes_dir().join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Renders scene text in Q16.16 (`samples` overrides the scene's `point`).
pub fn render_fixed(text: &str, w: u32, h: u32, samples: Option<u32>) -> Image {
    let scene = Scene::<I16F16>::parse(text).unwrap_or_else(|e| panic!("{e}"));
    render_image(&scene, w, h, samples, &|| {})
}

/// Renders scene text with the f32 reference.
pub fn render_float(text: &str, w: u32, h: u32, samples: Option<u32>) -> Image {
    let scene = Scene::<f32>::parse(text).unwrap_or_else(|e| panic!("{e}"));
    render_image(&scene, w, h, samples, &|| {})
}

/// `round(255 · clamp(v, 0, 1))`, SPEC section 4's pixel value, in f64.
pub fn level(v: f64) -> f64 {
    (255.0 * v.clamp(0.0, 1.0)).round()
}
