//! The photographer's camera, checked on rendered pictures: bokeh
//! shaped by aperture blades, autofocus on each of Program 1's solids, and
//! progressive passes that end in exactly the plain render.

use embedded_graphics::pixelcolor::RgbColor;
use lensray::progressive::{render_pass, Schedule};
use lensray::{Renderer, Scalar, Scene, I16F16};
use lensray_host::passes::render_passes;
use lensray_host::{render_image, Image};
use lensray_testkit::measure::{gradient_energy, PixelBox};

fn program1() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/paper-program1.scene")).unwrap()
}

/// A bright sphere out of focus (the plane in focus is at depth 8), seen
/// through a lens with the given blades. One ray in 256 that hits it saturates
/// its pixel, so the lit pixels are the blur spot. Far: radius 0.75 at depth
/// 24, lens radius 2.25: the aperture's shape scaled by 2/3, widened by a
/// quarter unit. Near: radius 0.125 at depth 4, lens radius 1.5: the aperture's
/// shape turned upside down, widened by a quarter unit. Both spots: corners
/// 1.5 units from the centre.
/// `point 256`, `adaptive off`: every pixel casts all its rays, one in each
/// of 256 equal strata of the lens, so a pixel whose lens sees the sphere
/// through a 256th of its area is lit (adaptive sampling stops a pixel whose
/// first rays all miss it, which moves the spot's rim: not the question here).
fn bokeh_scene(blades: u32, rotation: f64, near: bool) -> String {
    let (lens, size, depth) = if near { (1.5, 0.125, 4) } else { (2.25, 0.75, 24) };
    format!(
        "width 4\nambient_light 1 1 1\nradius {lens}\npoint 256\nadaptive off\naperture_blades {blades}\naperture_rotation {rotation}\n\
         object sphere\nKa 300 300 300\nKd 0 0 0\nscale {size} {size} {size}\ntranslate 0 0 -{depth}\n"
    )
}

fn lit_mask(img: &Image) -> Vec<(f64, f64)> {
    let mut pts = Vec::new();
    for y in 0..img.height {
        for x in 0..img.width {
            if img.get(x, y).r() > 128 {
                pts.push((x as f64, y as f64));
            }
        }
    }
    pts
}

/// The spot's support function h(θ) = max over lit pixels of their offset from
/// the spot's centre along θ (degrees, counter-clockwise with y up), every half degree.
fn support(pts: &[(f64, f64)]) -> Vec<f64> {
    let n = pts.len() as f64;
    let (cx, cy) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    (0..720)
        .map(|i| {
            let t = (i as f64 / 2.0).to_radians();
            pts.iter()
                .map(|p| (p.0 - cx) * t.cos() - (p.1 - cy) * t.sin())
                .fold(f64::MIN, f64::max)
        })
        .collect()
}

/// Corners of the spot, as (direction in degrees, distance from the centre in
/// pixels). The support function of a polygon has a sharp V-shaped minimum at
/// each side's normal, where h is the side's distance from the centre; two
/// neighbouring sides' lines meet at a corner. A side is a minimum of h over
/// ±20° lying at least 3 pixels below the highest h within ±40°: a disk's rim
/// has none.
fn corners(h: &[f64]) -> Vec<(f64, f64)> {
    let at = |i: isize| h[i.rem_euclid(720) as usize];
    let mut sides = Vec::new();
    for i in 0..720isize {
        let low = (-40..=40).all(|k| at(i + k) >= at(i) && (k <= 0 || at(i + k) > at(i)));
        let high = (-80..=80).map(|k| at(i + k)).fold(f64::MIN, f64::max);
        if low && high - at(i) > 3.0 {
            sides.push(((i as f64 / 2.0).to_radians(), at(i)));
        }
    }
    (0..sides.len())
        .map(|k| {
            // x cos a + y sin a = ha and x cos b + y sin b = hb.
            let ((a, ha), (b, hb)) = (sides[k], sides[(k + 1) % sides.len()]);
            let det = (b - a).sin();
            let x = (ha * b.sin() - hb * a.sin()) / det;
            let y = (hb * a.cos() - ha * b.cos()) / det;
            (y.atan2(x).to_degrees().rem_euclid(360.0), x.hypot(y))
        })
        .collect()
}

fn angle_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

fn bokeh<S: Scalar + Send + Sync>(blades: u32, rotation: f64, near: bool) -> Image {
    let scene = Scene::<S>::parse(&bokeh_scene(blades, rotation, near)).unwrap();
    render_image(&scene, 160, 160, None, &|| {})
}

#[test]
fn out_of_focus_point_images_as_the_aperture_polygon() {
    for (blades, rotation, near) in [(5u32, 90.0, false), (6, 0.0, false), (3, -90.0, false), (5, 90.0, true)] {
        let img = bokeh::<I16F16>(blades, rotation, near);
        let pts = lit_mask(&img);
        let found = corners(&support(&pts));
        // Behind the plane in focus the spot keeps the aperture's orientation
        // (the picture is upright): corners at rotation + k·360°/n; in front
        // of it, the rays cross before the plane and the spot is upside down.
        // Corners at 1.5 units (60 pixels) widened by the sphere's own blur
        // of 1/4 unit (10 pixels), which moves a corner out by 10 / cos(180°/n).
        let turn = if near { 180.0 } else { 0.0 };
        let expected: Vec<f64> = (0..blades)
            .map(|k| rotation + turn + 360.0 * k as f64 / blades as f64)
            .collect();
        let reach = 60.0 + 10.0 / (180.0 / blades as f64).to_radians().cos();
        eprintln!("{blades} blades, near {near}: corners {found:?}");
        assert_eq!(
            found.len(),
            blades as usize,
            "{blades} blades: corners {found:?}, expected at {expected:?}"
        );
        for e in &expected {
            let (angle, r) = found
                .iter()
                .cloned()
                .min_by(|p, q| angle_gap(p.0, *e).total_cmp(&angle_gap(q.0, *e)))
                .unwrap();
            assert!(
                angle_gap(angle, *e) <= 2.0,
                "{blades} blades: no corner near {e}°: {found:?}"
            );
            assert!(
                (r - reach).abs() < 3.0,
                "{blades} blades: corner at {angle}° reaches {r}, not {reach}"
            );
        }
        // The f32 reference draws the same lens points: the same spot.
        if blades == 5 && !near {
            let f = bokeh::<f32>(blades, rotation, near);
            let differ = img
                .pixels
                .iter()
                .zip(&f.pixels)
                .filter(|(a, b)| (a.r() > 128) != (b.r() > 128))
                .count();
            assert!(differ * 1000 < pts.len(), "{differ} of {} lit pixels differ", pts.len());
        }
    }
    // A round lens: a round spot, no corners anywhere.
    let round = lit_mask(&bokeh::<I16F16>(0, 0.0, false));
    let found = corners(&support(&round));
    assert!(found.is_empty(), "round aperture has corners at {found:?}");
}

/// The boxes (widened by 3 pixels) of the pixels whose chief ray first meets
/// object `i`: where its edges are.
fn object_box(scene: &Scene<I16F16>, w: u32, h: u32, i: usize) -> PixelBox {
    let r = Renderer::new(scene, w, h);
    let b = lensray_testkit::measure::extent(
        &Image::filled(w, h, embedded_graphics::pixelcolor::Rgb888::BLACK),
        |x, y| r.hit(&r.camera_ray(x, y, None)).map(|(k, _)| k) == Some(i),
    )
    .unwrap();
    PixelBox {
        x0: b.x0.saturating_sub(3),
        y0: b.y0.saturating_sub(3),
        x1: (b.x1 + 3).min(w),
        y1: (b.y1 + 3).min(h),
    }
}

#[test]
fn focus_on_makes_the_chosen_solid_the_sharpest() {
    // Program 1 with a wider lens (f/2.5) so depth of field is shallow, then
    // `focus_on` appended: 2 the cube, 3 the sphere, 4 the cone.
    let (w, h) = (200, 150);
    let base = format!("{}\nf_number 2.5\n", program1());
    let solids = [2usize, 3, 4];
    let plain = Scene::<I16F16>::parse(&base).unwrap();
    let boxes: Vec<PixelBox> = solids.iter().map(|&k| object_box(&plain, w, h, k - 1)).collect();
    let energy: Vec<Vec<f64>> = solids
        .iter()
        .map(|&k| {
            let scene = Scene::<I16F16>::parse(&format!("{base}focus_on {k}\n")).unwrap();
            let img = render_image(&scene, w, h, Some(48), &|| {});
            boxes.iter().map(|b| gradient_energy(&img, *b)).collect()
        })
        .collect();
    eprintln!("gradient energy, focus on 2, 3, 4 (rows) in the boxes of 2, 3, 4 (columns): {energy:.1?}");
    for (j, &k) in solids.iter().enumerate() {
        let chosen = energy[j][j];
        for (i, other) in solids.iter().enumerate().filter(|(i, _)| *i != j) {
            assert!(
                chosen > 1.25 * energy[i][j],
                "object {k}: focused on it {chosen:.1}, focused on {other} {:.1} (all: {energy:?})",
                energy[i][j]
            );
        }
    }
}

#[test]
fn progressive_passes_refine_in_place_to_the_plain_render() {
    let scene = Scene::<I16F16>::parse(&program1()).unwrap();
    // Enough samples for adaptive sampling (the default) to stop some pixels early.
    let (w, h, samples) = (75, 53, 40);
    // One renderer: its set-up surveys the frame.
    let r = Renderer::new(&scene, w, h).with_samples(samples);
    let stopped = (0..w * h).filter(|i| r.pixel_rays(i % w, i / w).1 < samples).count();
    assert!(stopped > 0, "no pixel stopped early");
    let plain = render_image(&scene, w, h, Some(samples), &|| {});
    // The preview: every pixel its one sample.
    let one = Renderer::new(&scene, w, h).with_samples(1);
    let preview = lensray_host::Image {
        width: w,
        height: h,
        pixels: (0..w * h).map(|i| one.pixel(i % w, i / w)).collect(),
    };
    let mut shown = Vec::new();
    let (last, _) = render_passes(&scene, w, h, Some(samples), 8, 1, &mut |_, pass, img| {
        shown.push((*pass, img.clone()))
    });
    assert_eq!(last, plain, "the last pass is the plain render, pixel for pixel");
    assert_eq!(shown.len(), 5);
    for (pass, img) in &shown {
        // Every pixel shows the pixel at the top-left corner of its block so far.
        let truth = if pass.samples == 1 { &preview } else { &plain };
        let s = pass.step;
        for y in 0..h {
            for x in 0..w {
                assert_eq!(
                    img.get(x, y),
                    truth.get(x / s * s, y / s * s),
                    "after the {s}x{s} pass with {} samples, pixel ({x}, {y})",
                    pass.samples
                );
            }
        }
    }
    // The library's own single-threaded loop draws the same pictures.
    let renderer = Renderer::new(&scene, w, h).with_samples(samples);
    let mut display = Image::filled(w, h, embedded_graphics::pixelcolor::Rgb888::BLACK);
    for (k, pass) in Schedule::new(8, 1, samples).enumerate() {
        render_pass(&renderer, &mut display, &pass).unwrap();
        assert_eq!(display, shown[k].1, "pass {k}");
    }
}
