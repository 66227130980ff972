//! Lens sampling against converged references: the adaptive sampler's
//! floors as distributions, and PSNR against mean rays a pixel.
//!
//! ```sh
//! cargo bench -p lensray-host --bench sampling
//! ```
//!
//! The set: every lens scene in `scenes/` and `host-tests/extra-scenes/`,
//! and `LENSRAY_SAMPLING_GENERATED` (40) lens scenes of the scene generator
//! from seed `LENSRAY_SAMPLING_FIRST_SEED` (1) on. For each, at
//! `LENSRAY_SAMPLING_WIDTH` (320; height 3/4 of it), in Q16.16, against a
//! converged reference (`LENSRAY_SAMPLING_REFERENCE`, 2048 stratified f32
//! samples, cached under `target/converged/`):
//!
//! * the default render (stratified, adaptive): PSNR and mean rays a pixel,
//!   the pre-pass's included;
//! * `point` independent samples in every pixel;
//! * plain stratified samples at the default's mean rays in every pixel
//!   (its PSNR interpolated between the whole counts on either side).
//!
//! Writes Markdown to `target/sampling.md` (or `LENSRAY_SAMPLING_OUT`) and,
//! for the scenes of `scenes/`, the curves to `docs/sampling.png` (or
//! `LENSRAY_SAMPLING_PLOT`; `LENSRAY_SAMPLING_PLOT=` skips them).

use std::path::{Path, PathBuf};

use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyle};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{Circle, Line, PrimitiveStyle, Rectangle};
use embedded_graphics::text::Text;
use lensray::{Sampler, Scene};
use lensray_host::convergence::{measure, psnr_axis, reference, Point as Quality, Setting};
use lensray_host::{encode, write_atomic, Diff, Format, Image};
use rayon::prelude::*;

/// Sample counts of the curves (each scene's own `point` is added).
const COUNTS: [u32; 7] = [4, 8, 16, 32, 64, 128, 256];

struct Row {
    name: String,
    point: u32,
    default: Quality,
    independent: Quality,
    stratified: Quality,
    converged: f64,
    curves: Option<[Vec<(u32, Quality)>; 2]>,
}

impl Row {
    fn share(&self) -> f64 {
        self.default.rays / self.point as f64
    }
    /// Default minus `other`, dB; 0 where both are exact.
    fn margin(&self, other: Quality) -> f64 {
        if self.default.psnr.is_infinite() && other.psnr.is_infinite() {
            0.0
        } else {
            self.default.psnr - other.psnr
        }
    }
}

fn env_u32(key: &str, default: u32) -> u32 {
    std::env::var(key).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn lens_scenes(dir: &Path) -> Vec<(String, String)> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| Some(e.ok()?.path())).collect())
        .unwrap_or_default();
    v.retain(|p| p.extension().is_some_and(|e| e == "scene"));
    v.sort();
    v.into_iter()
        .filter_map(|p| {
            let text = std::fs::read_to_string(&p).ok()?;
            let lens = Scene::<f32>::parse(&text).ok()?.camera.radius > 0.0;
            lens.then(|| (p.file_name().unwrap().to_string_lossy().into_owned(), text))
        })
        .collect()
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let w = env_u32("LENSRAY_SAMPLING_WIDTH", 320);
    let h = w * 3 / 4;
    let ref_n = env_u32("LENSRAY_SAMPLING_REFERENCE", 2048);
    let mut named = lens_scenes(&root.join("scenes"));
    let curved = named.len();
    named.extend(lens_scenes(&root.join("host-tests/extra-scenes")));
    let first = env_u32("LENSRAY_SAMPLING_FIRST_SEED", 1) as u64;
    for seed in first..first + env_u32("LENSRAY_SAMPLING_GENERATED", 40) as u64 {
        named.push((
            format!("generated-lens-{seed}"),
            lensray_testkit::scenegen::generate_lens(seed),
        ));
    }
    let rows: Vec<Row> = named
        .iter()
        .enumerate()
        .map(|(i, (name, text))| row(name, text, (w, h), ref_n, i < curved))
        .collect();
    let md = markdown(&rows, w, h, ref_n);
    println!("{md}");
    let out = std::env::var_os("LENSRAY_SAMPLING_OUT").map_or_else(|| root.join("target/sampling.md"), PathBuf::from);
    write_atomic(&out, md.as_bytes()).unwrap();
    let plot_path =
        std::env::var_os("LENSRAY_SAMPLING_PLOT").map_or_else(|| root.join("docs/sampling.png"), PathBuf::from);
    if !plot_path.as_os_str().is_empty() {
        let with: Vec<&Row> = rows.iter().filter(|r| r.curves.is_some()).collect();
        write_atomic(&plot_path, &encode(&plot(&with, w, h), Format::Png).unwrap()).unwrap();
        eprintln!("wrote {}", plot_path.display());
    }
    eprintln!("wrote {}", out.display());
}

/// One scene's measurements (and its curves where `curves`).
fn row(name: &str, text: &str, (w, h): (u32, u32), ref_n: u32, curves: bool) -> Row {
    let point = Scene::<f32>::parse(text).unwrap().camera.samples;
    let truth = reference(text, w, h, ref_n, Sampler::Stratified).unwrap();
    let quarter = reference(text, w, h, ref_n / 4, Sampler::Stratified).unwrap();
    let converged = Diff::of(&truth, &quarter).unwrap().psnr;
    let default = measure(text, &truth, Setting::default_render(point)).unwrap();
    let independent = measure(text, &truth, Setting::independent(point)).unwrap();
    // Plain stratified at the default's mean rays: PSNR interpolated in
    // rays between the whole counts around it.
    let plain = |samples: u32| {
        let s = Setting {
            samples: samples.clamp(1, point),
            sampler: Sampler::Stratified,
            adaptive: false,
        };
        measure(text, &truth, s).unwrap()
    };
    let (lo, hi) = (default.rays.floor() as u32, default.rays.ceil() as u32);
    let (a, b) = (plain(lo), plain(hi));
    let f = default.rays - lo as f64;
    let psnr = if hi == lo || a.psnr == b.psnr {
        b.psnr
    } else {
        a.psnr + f * (b.psnr - a.psnr)
    };
    let stratified = Quality {
        psnr,
        rays: default.rays,
    };
    let curves = curves.then(|| {
        let mut counts: Vec<u32> = COUNTS.iter().copied().filter(|&c| c < point).collect();
        counts.push(point);
        [Sampler::Independent, Sampler::Stratified].map(|sampler| {
            counts
                .par_iter()
                .map(|&samples| {
                    let s = Setting {
                        samples,
                        sampler,
                        adaptive: false,
                    };
                    (samples, measure(text, &truth, s).unwrap())
                })
                .collect()
        })
    });
    let r = Row {
        name: name.to_string(),
        point,
        default,
        independent,
        stratified,
        converged,
        curves,
    };
    eprintln!(
        "{name} (point {point}): default {:.2} dB at {:.1} rays ({:.1} %), independent {:+.2} dB, stratified {:+.2} dB",
        default.psnr,
        default.rays,
        100.0 * r.share(),
        r.margin(independent),
        r.margin(stratified)
    );
    r
}

/// Min, median and max.
fn spread(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let mid = if v.len() % 2 == 1 {
        v[v.len() / 2]
    } else {
        (v[v.len() / 2 - 1] + v[v.len() / 2]) / 2.0
    };
    (v[0], mid, v[v.len() - 1])
}

fn markdown(rows: &[Row], w: u32, h: u32, ref_n: u32) -> String {
    let mut s = format!(
        "Against converged references ({ref_n} stratified f32 samples, {w}x{h}); renders in Q16.16.\n\
         *Rays*: the default render's mean rays a pixel (the pre-pass's included) and their share\n\
         of `point`. *vs independent*: its PSNR less that of `point` independent samples.\n\
         *vs stratified*: less that of plain stratified samples at its mean rays (interpolated\n\
         between the whole counts on either side).\n\n\
         | scene (point) | default PSNR | rays (share) | vs independent | vs stratified | converged |\n\
         |---|---|---|---|---|---|\n"
    );
    for r in rows {
        s += &format!(
            "| `{}` ({}) | {:.2} dB | {:.1} ({:.1} %) | {:+.2} dB | {:+.2} dB | {:.0} dB |\n",
            r.name,
            r.point,
            r.default.psnr,
            r.default.rays,
            100.0 * r.share(),
            r.margin(r.independent),
            r.margin(r.stratified),
            r.converged
        );
    }
    let dist = |f: &dyn Fn(&Row) -> f64| spread(rows.iter().map(f).collect());
    let share = dist(&|r| 100.0 * r.share());
    let ind = dist(&|r| r.margin(r.independent));
    let strat = dist(&|r| r.margin(r.stratified));
    s += &format!(
        "\nOver the {} scenes (min / median / max):\n\n\
         | measure | min | median | max | floor |\n|---|---|---|---|---|\n\
         | rays, share of `point` | {:.1} % | {:.1} % | {:.1} % | median at most 40 % |\n\
         | PSNR less `point` independent samples | {:+.2} dB | {:+.2} dB | {:+.2} dB | median at least 0 |\n\
         | PSNR less plain stratified at the same rays | {:+.2} dB | {:+.2} dB | {:+.2} dB | median at least +2.0, min at least -0.5 |\n",
        rows.len(),
        share.0,
        share.1,
        share.2,
        ind.0,
        ind.1,
        ind.2,
        strat.0,
        strat.1,
        strat.2
    );
    let own: Vec<&Row> = rows.iter().filter(|r| r.curves.is_some()).collect();
    let met = own
        .iter()
        .filter(|r| r.share() <= 0.4 && r.margin(r.independent) >= 0.0)
        .count();
    s += &format!(
        "\nScenes of `scenes/` within 40 % of `point` and at least `point` independent samples: {met} of {}.\n",
        own.len()
    );
    s
}

/// One panel a scene: PSNR against log2 of mean rays a pixel.
fn plot(rows: &[&Row], w: u32, h: u32) -> Image {
    const PW: u32 = 300;
    const PH: u32 = 200;
    let per_row = 3u32;
    let nrows = (rows.len() as u32).div_ceil(per_row).max(1);
    let mut img = Image::filled(PW * per_row, PH * nrows + 30, Rgb888::WHITE);
    let ink = MonoTextStyle::new(&FONT_6X10, Rgb888::BLACK);
    let (grey, blue, red) = (
        Rgb888::new(150, 150, 150),
        Rgb888::new(20, 80, 220),
        Rgb888::new(220, 30, 30),
    );
    let title = format!("PSNR (dB) against converged references vs mean rays a pixel (log scale), {w}x{h}, Q16.16");
    let _ = Text::new(&title, Point::new(8, 12), ink).draw(&mut img);
    let legend = "grey: independent, blue: stratified, red dot: default (stratified, adaptive)";
    let _ = Text::new(legend, Point::new(8, 24), ink).draw(&mut img);
    for (i, r) in rows.iter().enumerate() {
        let Some(curves) = &r.curves else { continue };
        let (ox, oy) = ((i as u32 % per_row * PW) as i32, (30 + i as u32 / per_row * PH) as i32);
        let (l, t, pw, ph) = (ox + 34, oy + 18, PW as i32 - 46, PH as i32 - 44);
        let psnrs: Vec<f64> = curves
            .iter()
            .flatten()
            .map(|x| x.1.psnr)
            .chain([r.default.psnr])
            .collect();
        let axis = psnr_axis(psnrs.iter().copied());
        let x_lo = r.default.rays.max(1.0).log2().floor().min(2.0);
        let x_hi = (r.point.max(4) as f64).log2().ceil();
        // An exact render (infinite PSNR) sits on the top edge.
        let at = |p: Quality| {
            let x = l + ((p.rays.log2() - x_lo) / (x_hi - x_lo) * pw as f64) as i32;
            let y = match axis {
                Some((lo, hi)) if p.psnr.is_finite() => t + ph - ((p.psnr - lo) / (hi - lo) * ph as f64) as i32,
                _ => t,
            };
            Point::new(x, y)
        };
        let frame = PrimitiveStyle::with_stroke(Rgb888::BLACK, 1);
        let _ = Rectangle::new(Point::new(l, t), Size::new(pw as u32, ph as u32))
            .into_styled(frame)
            .draw(&mut img);
        let label = format!("{} ({})", r.name.trim_end_matches(".scene"), r.point);
        let _ = Text::new(&label, Point::new(ox + 6, oy + 12), ink).draw(&mut img);
        if let Some((lo, hi)) = axis {
            let _ = Text::new(&format!("{hi:.0}"), Point::new(ox + 4, t + 8), ink).draw(&mut img);
            let _ = Text::new(&format!("{lo:.0}"), Point::new(ox + 4, t + ph), ink).draw(&mut img);
        }
        let mut k = x_lo as u32;
        while k as f64 <= x_hi {
            let x = l + ((k as f64 - x_lo) / (x_hi - x_lo) * pw as f64) as i32;
            let _ = Text::new(&format!("{}", 1u32 << k), Point::new(x - 6, t + ph + 12), ink).draw(&mut img);
            k += 1;
        }
        for (curve, colour) in curves.iter().zip([grey, blue]) {
            for pair in curve.windows(2) {
                let _ = Line::new(at(pair[0].1), at(pair[1].1))
                    .into_styled(PrimitiveStyle::with_stroke(colour, 2))
                    .draw(&mut img);
            }
            for p in curve {
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
