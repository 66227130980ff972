//! Lens sampling against converged references: PSNR as a function of mean
//! rays a pixel, independent against stratified samples, and the default
//! render (stratified, adaptive), for every lens scene in `scenes/` (and the
//! generator's lens scenes in `LENSRAY_SAMPLING_EXTRA`, a folder of `.scene`
//! files, when set).
//!
//! ```sh
//! cargo bench -p lensray-host --bench sampling
//! ```
//!
//! Writes a Markdown section to `target/sampling.md` (or `LENSRAY_SAMPLING_OUT`)
//! and the plot to `docs/sampling.png` (or `LENSRAY_SAMPLING_PLOT`). Size
//! `LENSRAY_SAMPLING_WIDTH` (320; height from 4:3), reference samples
//! `LENSRAY_SAMPLING_GENERATED` (4): how many of the scene generator's lens
//! scenes (seeds 1..), each also at `point 70`; `LENSRAY_SAMPLING_SCENES`: the
//! folder instead of `scenes/`. `LENSRAY_SAMPLING_REFERENCE` (2048, stratified f32; cached under
//! `target/converged/`), checked against a reference of a quarter the samples.

use std::path::{Path, PathBuf};

use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyle};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{Circle, Line, PrimitiveStyle, Rectangle};
use embedded_graphics::text::Text;
use lensray::unstable::sampler::Sampler;
use lensray::Scene;
use lensray_host::convergence::{measure, psnr_axis, reference, Point as Quality, Setting};
use lensray_host::{encode, write_atomic, Diff, Format, Image};

/// Sample counts of the curves (each scene's own `point` is added).
const COUNTS: [u32; 7] = [4, 8, 16, 32, 64, 128, 256];

struct Row {
    name: String,
    point: u32,
    independent: Vec<(u32, Quality)>,
    stratified: Vec<(u32, Quality)>,
    default: Quality,
    converged: f64,
}

fn env_u32(key: &str, default: u32) -> u32 {
    std::env::var(key).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn lens_scenes(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| Some(e.ok()?.path())).collect())
        .unwrap_or_default();
    v.retain(|p| p.extension().is_some_and(|e| e == "scene"));
    v.sort();
    v.retain(|p| {
        std::fs::read_to_string(p)
            .ok()
            .and_then(|t| Scene::<f32>::parse(&t).ok())
            .is_some_and(|s| s.camera.radius > 0.0)
    });
    v
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let w = env_u32("LENSRAY_SAMPLING_WIDTH", 320);
    let h = w * 3 / 4;
    let ref_n = env_u32("LENSRAY_SAMPLING_REFERENCE", 2048);
    let dir = std::env::var_os("LENSRAY_SAMPLING_SCENES").map_or(root.join("scenes"), PathBuf::from);
    let mut scenes = lens_scenes(&dir);
    // Lens scenes kept out of the web page's presets (host-tests/extra-scenes/).
    scenes.extend(lens_scenes(&root.join("host-tests/extra-scenes")));
    if let Some(extra) = std::env::var_os("LENSRAY_SAMPLING_EXTRA") {
        scenes.extend(lens_scenes(Path::new(&extra)));
    }
    let mut named: Vec<(String, String)> = scenes
        .iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(p).unwrap())
        })
        .collect();
    // The random scene generator's lens scenes (host-tests/testkit/src/scenegen.rs), as
    // generated (their `point` is 1 to 64) and at `point 70`.
    for seed in 1..=env_u32("LENSRAY_SAMPLING_GENERATED", 4) as u64 {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        named.push((format!("generated-lens-{seed}"), text.clone()));
        named.push((format!("generated-lens-{seed}@70"), text + "\npoint 70\n"));
    }
    let mut rows = Vec::new();
    for (name, text) in named {
        let point = Scene::<f32>::parse(&text).unwrap().camera.samples;
        eprintln!("{name}: references ({ref_n} and {} samples, f32, {w}x{h})", ref_n / 4);
        let truth = reference(&text, w, h, ref_n, Sampler::Stratified).unwrap();
        let quarter = reference(&text, w, h, ref_n / 4, Sampler::Stratified).unwrap();
        let converged = Diff::of(&truth, &quarter).unwrap().psnr;
        let mut counts: Vec<u32> = COUNTS.iter().copied().filter(|&c| c < point).collect();
        counts.push(point);
        let curve = |sampler| -> Vec<(u32, Quality)> {
            counts
                .iter()
                .map(|&samples| {
                    let s = Setting {
                        samples,
                        sampler,
                        adaptive: false,
                    };
                    (samples, measure(&text, &truth, s).unwrap())
                })
                .collect()
        };
        let independent = curve(Sampler::Independent);
        let stratified = curve(Sampler::Stratified);
        let default = measure(&text, &truth, Setting::default_render(point)).unwrap();
        eprintln!(
            "{name}: independent {point}: {:.2} dB, stratified {point}: {:.2} dB, default {:.2} dB at {:.1} rays",
            independent.last().unwrap().1.psnr,
            stratified.last().unwrap().1.psnr,
            default.psnr,
            default.rays
        );
        rows.push(Row {
            name,
            point,
            independent,
            stratified,
            default,
            converged,
        });
    }
    let md = markdown(&rows, w, h, ref_n);
    println!("{md}");
    let out = std::env::var_os("LENSRAY_SAMPLING_OUT")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target/sampling.md"));
    write_atomic(&out, md.as_bytes()).unwrap();
    let plot_path = std::env::var_os("LENSRAY_SAMPLING_PLOT")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("docs/sampling.png"));
    write_atomic(&plot_path, &encode(&plot(&rows, w, h), Format::Png).unwrap()).unwrap();
    eprintln!("wrote {} and {}", out.display(), plot_path.display());
}

fn markdown(rows: &[Row], w: u32, h: u32, ref_n: u32) -> String {
    let mut s = String::new();
    let cols: Vec<String> = COUNTS.iter().map(|c| format!("{c}")).collect();
    s += &format!(
        "PSNR (dB) of the Q16.16 render against a converged reference (the same scene\n\
         at {ref_n} stratified lens samples, f32, {w}x{h}), by lens samples a pixel\n\
         (every pixel casts them all: adaptive sampling off); *point* is the scene's\n\
         own `point`. *Default* is the render as the scene is written (stratified,\n\
         adaptive): its PSNR and mean rays a pixel. *Converged* is the reference\n\
         against one of a quarter the samples: far above every render, so the\n\
         reference's own noise does not limit the figures.\n\n"
    );
    s += &format!(
        "| scene (point) | sampler | {} | point | default: PSNR, rays (share of point) | floor: PSNR >= independent at point, rays <= 40 % | converged |\n",
        cols.join(" | ")
    );
    s += &format!("|---|---|{}---|---|---|---|\n", "---|".repeat(COUNTS.len()));
    for r in rows {
        let cell = |curve: &[(u32, Quality)], c: u32| {
            curve
                .iter()
                .find(|(n, _)| *n == c)
                .map_or("".to_string(), |(_, p)| format!("{:.1}", p.psnr))
        };
        let ind_point = r.independent.last().unwrap().1.psnr;
        let share = r.default.rays / r.point as f64;
        let met = r.default.psnr >= ind_point && share <= 0.4;
        for (label, curve) in [("independent", &r.independent), ("stratified", &r.stratified)] {
            let counts: Vec<String> = COUNTS.iter().map(|&c| cell(curve, c)).collect();
            let first = label == "independent";
            s += &format!(
                "| {} | {label} | {} | {:.1} | {} | {} | {} |\n",
                if first {
                    format!("`{}` ({})", r.name, r.point)
                } else {
                    String::new()
                },
                counts.join(" | "),
                curve.last().unwrap().1.psnr,
                if first {
                    format!(
                        "{:.1} dB, {:.1} ({:.1} %)",
                        r.default.psnr,
                        r.default.rays,
                        100.0 * share
                    )
                } else {
                    String::new()
                },
                if first {
                    // Both exact: inf - inf would print NaN.
                    let margin = if r.default.psnr.is_infinite() && ind_point.is_infinite() {
                        "both exact".to_string()
                    } else {
                        format!("{:+.1} dB", r.default.psnr - ind_point)
                    };
                    format!("{} ({margin})", if met { "**met**" } else { "**NOT met**" })
                } else {
                    String::new()
                },
                if first {
                    format!("{:.1} dB", r.converged)
                } else {
                    String::new()
                },
            );
        }
    }
    // Rays for the same picture: the stratified count that first matches independent at point.
    s += "\nRays for today's picture: the fewest stratified samples of the table whose PSNR reaches\n\
          that of `point` independent samples, and the default render's mean rays:\n\n\
          | scene | independent at point | stratified, same PSNR | default (adaptive) |\n|---|---|---|---|\n";
    for r in rows {
        let target = r.independent.last().unwrap().1.psnr;
        let same = r
            .stratified
            .iter()
            .find(|(_, p)| p.psnr >= target)
            .map_or("-".to_string(), |(n, _)| format!("{n}"));
        s += &format!("| `{}` | {} | {} | {:.1} |\n", r.name, r.point, same, r.default.rays);
    }
    s
}

/// One panel a scene: PSNR against log2 of mean rays a pixel.
fn plot(rows: &[Row], w: u32, h: u32) -> Image {
    const PW: u32 = 300;
    const PH: u32 = 200;
    let per_row = 3u32;
    let nrows = (rows.len() as u32).div_ceil(per_row).max(1);
    let mut img = Image::filled(PW * per_row, PH * nrows + 30, Rgb888::WHITE);
    let ink = MonoTextStyle::new(&FONT_6X10, Rgb888::BLACK);
    let grey = Rgb888::new(150, 150, 150);
    let blue = Rgb888::new(20, 80, 220);
    let red = Rgb888::new(220, 30, 30);
    let _ = Text::new(
        &format!("PSNR (dB) against converged references vs mean rays a pixel (log scale), {w}x{h}, Q16.16"),
        Point::new(8, 12),
        ink,
    )
    .draw(&mut img);
    let _ = Text::new(
        "grey: independent, blue: stratified, red dot: default (stratified, adaptive)",
        Point::new(8, 24),
        ink,
    )
    .draw(&mut img);
    for (i, r) in rows.iter().enumerate() {
        let (ox, oy) = ((i as u32 % per_row * PW) as i32, (30 + i as u32 / per_row * PH) as i32);
        let (l, t, pw, ph) = (ox + 34, oy + 18, PW as i32 - 46, PH as i32 - 44);
        let psnrs: Vec<f64> = r
            .independent
            .iter()
            .chain(&r.stratified)
            .map(|x| x.1.psnr)
            .chain([r.default.psnr])
            .collect();
        let axis = psnr_axis(psnrs.iter().copied());
        // From 4 rays, or fewer where the default cast fewer (`point` 6 casts 2.2):
        // a dot left of the axis was drawn in the panel beside.
        let x_lo = r.default.rays.max(1.0).log2().floor().min(2.0);
        let x_hi = (r.point.max(4) as f64).log2().ceil();
        // An exact render (infinite PSNR) sits on the top edge, labelled "exact".
        let at = |p: Quality| {
            let x = l + ((p.rays.log2() - x_lo) / (x_hi - x_lo) * pw as f64) as i32;
            let y = match axis {
                Some((lo, hi)) if p.psnr.is_finite() => t + ph - ((p.psnr - lo) / (hi - lo) * ph as f64) as i32,
                _ => t,
            };
            Point::new(x, y)
        };
        let _ = Rectangle::new(Point::new(l, t), Size::new(pw as u32, ph as u32))
            .into_styled(PrimitiveStyle::with_stroke(Rgb888::BLACK, 1))
            .draw(&mut img);
        let _ = Text::new(
            &format!("{} ({})", r.name.trim_end_matches(".scene"), r.point),
            Point::new(ox + 6, oy + 12),
            ink,
        )
        .draw(&mut img);
        match axis {
            Some((lo, hi)) => {
                let _ = Text::new(&format!("{hi:.0}"), Point::new(ox + 4, t + 8), ink).draw(&mut img);
                let _ = Text::new(&format!("{lo:.0}"), Point::new(ox + 4, t + ph), ink).draw(&mut img);
            }
            None => {
                let note = "every render exact (infinite PSNR)";
                let _ = Text::new(note, Point::new(l + 8, t + ph / 2), ink).draw(&mut img);
            }
        }
        if psnrs.iter().any(|p| p.is_infinite()) {
            let _ = Text::new("exact", Point::new(l + pw - 34, t + 10), ink).draw(&mut img);
        }
        let mut k = x_lo as u32;
        while k as f64 <= x_hi {
            let x = l + ((k as f64 - x_lo) / (x_hi - x_lo) * pw as f64) as i32;
            let _ = Text::new(&format!("{}", 1u32 << k), Point::new(x - 6, t + ph + 12), ink).draw(&mut img);
            k += 1;
        }
        for (curve, colour) in [(&r.independent, grey), (&r.stratified, blue)] {
            for pair in curve.windows(2) {
                let _ = Line::new(at(pair[0].1), at(pair[1].1))
                    .into_styled(PrimitiveStyle::with_stroke(colour, 2))
                    .draw(&mut img);
            }
            for p in curve.iter() {
                let _ = Circle::with_center(at(p.1), 5)
                    .into_styled(PrimitiveStyle::with_fill(colour))
                    .draw(&mut img);
            }
        }
        let _ = Circle::with_center(at(r.default), 9)
            .into_styled(PrimitiveStyle::with_fill(red))
            .draw(&mut img);
    }
    img
}
