//! The scanline filter (issue 14, `src/render/scanline.rs`): a row's pixel
//! differs from the pixel rendered alone only where it, both its neighbours
//! and every ray they cast see what is spread over at least the gate,
//! `FAR_COC_PIXELS` or below `point` 20 `SMALL_PILOT_COC_PIXELS` (circles of confusion recomputed here in f64 from each
//! ray's own hit) and their rays all met lamps or all met none (a pixel
//! whose rays met both counts as meeting none where every lamp it met is
//! spread over the brightest lamp's bound times the gate, and as either
//! where all else it met is in front of every lamp and spread as far), and then it
//! is exactly (1, 2, 1)/4 of the three, or (1, 4, 6, 4, 1)/16 of five where
//! it and its four neighbours see only what is spread over twice that (of
//! their own values, in 256ths of a level, rounded once); never
//! with `sampler independent` or `adaptive off`; the progressive passes end
//! on the same picture.

use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use lensray::unstable::render::scanline::{far_coc_pixels, far_ratio, Fine, FAR_COC_PIXELS, WIDE_COC_FACTOR};
use lensray::unstable::sampler::{PixelSamples, Sampler};
use lensray::{progressive, CameraSample, Renderer, Scalar, Scene, I16F16};

/// The smallest circle of confusion, in pixels, over the hits of the rays
/// pixel (`col`, `row`) casts (a miss: a point at infinity), and what they
/// met: bit 0 a lamp (a bright object), bit 1 anything else; a pixel that
/// met both is 2 where every lamp's hit is spread over the brightest lamp's
/// bound times the gate, else 5 (a soft rim: mixed with either class) where
/// every other hit is in front of every lamp's and spread as far, else 3,
/// and 4 within 2 % of a gate or depth (either may hold: Q16.16's depths
/// against f64's).
fn smallest_coc<S: Scalar>(r: &Renderer<'_, S>, scene: &Scene<S>, col: u32, row: u32) -> (f64, u8) {
    let (coc, met, _) = coc_and_lamps(r, scene, col, row);
    (coc, met)
}

/// [`smallest_coc`], and whether the pixel met a lamp and something else
/// and is class 2 by the lamp's gate or class 1 by its occluder's (a rim the
/// filter may mix across): where all else it met is in front of every lamp
/// and spread over that gate too, it counts as a lamp's (within 2 % of the
/// gate or of the lamp's depth, 4: either may hold).
fn coc_and_lamps<S: Scalar>(r: &Renderer<'_, S>, scene: &Scene<S>, col: u32, row: u32) -> (f64, u8, bool) {
    let cam = &scene.camera;
    let z_f = cam.focus_depth();
    let n = lensray::unstable::camera::basis(cam).unwrap()[2];
    let k = far_ratio(cam, r.camera().cols()) * FAR_COC_PIXELS;
    let (_, count) = r.pixel_rays(col, row);
    let camera = r.camera();
    let film = camera.film_point(col, row);
    let mut lens = PixelSamples::new(r.sampler(), col, row);
    let (mut coc, mut met, mut lamp_coc) = (f64::INFINITY, 0, f64::INFINITY);
    // The others' least circle of confusion (a miss: none in front), the
    // lamps' nearest depth and the others' farthest.
    let (mut other_coc, mut lamp_z, mut other_z) = (f64::INFINITY, f64::INFINITY, 0.0f64);
    for _ in 0..count {
        let ray = camera.generate_ray(&CameraSample {
            film: &film,
            lens: Some(lens.next(camera.aperture())),
        });
        let c = match scene.closest_hit_camera_ray(&ray, r.cones()) {
            Some((i, hit)) => {
                let lamp = r.bright_footprints().is_bright(i);
                met |= if lamp { 1 } else { 2 };
                let d = ray.dir.to_array().map(|x| x.to_f64());
                let z = -hit.t.to_f64() * (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
                let c = if z > 0.0 { k * (1.0 - z_f / z).abs() } else { 0.0 };
                if lamp {
                    lamp_coc = lamp_coc.min(c);
                    lamp_z = lamp_z.min(z);
                } else {
                    other_coc = other_coc.min(c);
                    other_z = other_z.max(z);
                }
                c
            }
            None => {
                met |= 2;
                other_coc = 0.0;
                k
            }
        };
        coc = coc.min(c);
    }
    let both = met == 3;
    if both {
        let gate = far_coc_pixels(r.samples()) * r.bright_footprints().lamp() as f64;
        // The occluder's rule: every other hit in front of every lamp hit and spread past the gate.
        let (occluded, unsure) = (
            other_coc >= 1.02 * gate && other_z < 0.98 * lamp_z,
            other_coc >= 0.98 * gate && other_z < 1.02 * lamp_z,
        );
        met = if lamp_coc >= 1.02 * gate {
            2
        } else if lamp_coc >= 0.98 * gate {
            4
        } else if occluded {
            5
        } else if unsure {
            4
        } else {
            3
        };
    }
    (coc, met, both && (met == 5 || met == 2))
}

/// Whether every pixel of `window` holds one lamp class, 1 or 2: a soft rim
/// (5) holds both, a sharp one (3) none.
fn alike(window: &[(f64, u8)]) -> bool {
    [1u8, 2].iter().any(|&k| window.iter().all(|x| x.1 == k || x.1 == 5))
}

/// (1, 4, 6, 4, 1)/16 of five pixels' own values (256ths of a level),
/// rounded once, half up.
fn mix5(p: &[Fine]) -> Rgb888 {
    let m = |i: usize| {
        let v: f64 = [1.0, 4.0, 6.0, 4.0, 1.0]
            .iter()
            .zip(p)
            .map(|(w, c)| w * c.0[i] as f64)
            .sum();
        (v / 16.0 / 256.0 + 0.5).floor() as u8
    };
    Rgb888::new(m(0), m(1), m(2))
}

/// (1, 2, 1)/4 of three pixels' own values, rounded once, half up.
fn mix(a: Fine, b: Fine, c: Fine) -> Rgb888 {
    let m = |i: usize| ((a.0[i] as f64 + 2.0 * b.0[i] as f64 + c.0[i] as f64) / 4.0 / 256.0 + 0.5).floor() as u8;
    Rgb888::new(m(0), m(1), m(2))
}

/// Every row of `scene` at `w`×`h`: (pixels filtered, pixels the gate held back).
fn check<S: Scalar>(scene: &Scene<S>, w: u32, h: u32, label: &str) -> (u32, u32) {
    let r = Renderer::new(scene, w, h);
    assert!(r.filters(), "{label}: the default render filters");
    let (mut filtered, mut held) = (0, 0);
    for row in 0..h {
        let mut out = vec![Rgb888::BLACK; w as usize];
        r.render_row(row, &mut out);
        let fine: Vec<Fine> = (0..w).map(|c| r.pixel_fine(c, row)).collect();
        let alone: Vec<Rgb888> = (0..w).map(|c| r.pixel(c, row)).collect();
        let info: Vec<(f64, u8)> = (0..w).map(|c| smallest_coc(&r, scene, c, row)).collect();
        // The frame's gate: 4 pixels, 2 below `point` 20.
        let gate = far_coc_pixels(r.samples());
        let wide_coc = WIDE_COC_FACTOR as f64 * gate;
        for c in 0..w as usize {
            // A lamp's hit within the slack of its gate: either class may hold.
            if info[c.saturating_sub(2)..(c + 3).min(w as usize)]
                .iter()
                .any(|x| x.1 == 4)
            {
                continue;
            }
            // Five alike, all spread over twice the gate: the 5-tap (2 % of slack as below).
            if c > 1 && c + 2 < w as usize {
                let five = &info[c - 2..=c + 2];
                let least5 = five.iter().map(|x| x.0).fold(f64::INFINITY, f64::min);
                let alike5 = alike(five);
                if alike5 && least5 >= 1.02 * wide_coc {
                    assert_eq!(out[c], mix5(&fine[c - 2..=c + 2]), "{label} ({c}, {row}) 5-tap");
                    filtered += 1;
                    continue;
                }
                // Within the slack either filter may hold.
                if alike5 && least5 >= 0.98 * wide_coc && out[c] == mix5(&fine[c - 2..=c + 2]) {
                    continue;
                }
            }
            let inner = c > 0 && c + 1 < w as usize;
            let window = if inner { &info[c - 1..=c + 1] } else { &info[c..=c] };
            let least = window.iter().map(|x| x.0).fold(f64::INFINITY, f64::min);
            // All lamps or none, alike in the three: else the rim of a lamp's bokeh.
            let alike = inner && alike(window);
            if out[c] != alone[c] {
                // Q16.16's depths against f64's: 2 % of slack.
                assert!(
                    alike && least >= 0.98 * gate,
                    "{label} ({c}, {row}) filtered at a circle of confusion of {least:.2} pixels, {window:?}"
                );
                assert_eq!(out[c], mix(fine[c - 1], fine[c], fine[c + 1]), "{label} ({c}, {row})");
            }
            if alike && least >= 1.02 * gate {
                // The gate is open here: the row holds the mix (equal to the pixel where smooth).
                assert_eq!(out[c], mix(fine[c - 1], fine[c], fine[c + 1]), "{label} ({c}, {row})");
                filtered += 1;
            } else if !alike || least < 0.98 * gate {
                assert_eq!(out[c], alone[c], "{label} ({c}, {row})");
                held += 1;
            }
        }
    }
    (filtered, held)
}

/// The generator's lens scenes in both number types: the filter acts exactly
/// where the circles of confusion say, and both cases occur.
#[test]
fn the_filter_acts_only_where_everything_is_far_out_of_focus() {
    let (mut filtered, mut held) = (0, 0);
    for seed in 7000..7024 {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        let mut q = Scene::<I16F16>::parse(&text).unwrap();
        if q.camera.radius <= 0.0 {
            continue;
        }
        // The default render whatever the scene says; at least the adaptive
        // minimum (below it rows have gaps: their pixels are not the pixel alone,
        // see the scanline module's gap test).
        let point = q.camera.samples.max(lensray::unstable::render::ADAPTIVE_MIN_POINT);
        q.camera.sampler = Sampler::Stratified;
        q.camera.adaptive = true;
        q.camera.samples = point;
        let mut f = Scene::<f32>::parse(&text).unwrap();
        f.camera.sampler = Sampler::Stratified;
        f.camera.adaptive = true;
        f.camera.samples = point;
        for (a, b) in [
            check(&q, 40, 30, &format!("seed {seed} Q16.16")),
            check(&f, 40, 30, &format!("seed {seed} f32")),
        ] {
            filtered += a;
            held += b;
        }
    }
    assert!(filtered > 1000 && held > 1000, "{filtered} filtered, {held} held back");
}

/// Pixels whose rays met a lamp and something else, and of them those the
/// row mixed, over every row of `scene` at `w`×`h` (after [`check`]'s checks).
fn rims<S: Scalar>(scene: &Scene<S>, w: u32, h: u32) -> (u32, u32) {
    let r = Renderer::new(scene, w, h);
    let (mut both, mut mixed) = (0, 0);
    for row in 0..h {
        let mut out = vec![Rgb888::BLACK; w as usize];
        r.render_row(row, &mut out);
        for c in 0..w {
            let (_, met, converted) = coc_and_lamps(&r, scene, c, row);
            if met == 3 || converted {
                both += 1;
                mixed += (out[c as usize] != r.pixel(c, row)) as u32;
            }
        }
    }
    (both, mixed)
}

/// A lamp (a sphere lit to about 7 times white) far behind a dim sphere,
/// both far out of focus: pixels that see both through the lens are mixed
/// where the lamp is spread over 7 times the gate, and never where a
/// brighter light puts the lamp's gate past its blur (the rim stays sharp).
#[test]
fn a_lamp_far_enough_out_of_focus_is_mixed_across_its_rim() {
    for (intensity, mixes) in [(3.0, true), (40.0, false)] {
        let text = format!(
            "point 40\nradius 1.5\nfocal_length 4\nimage_distance 8\nwidth 2\n\
             light_position 0 0 10\nlight_intensity {intensity} {intensity} {intensity}\nambient_light 0.2 0.2 0.2\n\
             object sphere\nKa 0.2 0.2 0.2\nKd 1 1 1\nKs 1 1 1\nscale 40 40 40\ntranslate 30 0 -200\n\
             object sphere\nKa 0.3 0.3 0.3\nKd 0.05 0.05 0.05\nKs 0 0 0\nscale 12 12 12\ntranslate -8 0 -60\n"
        );
        rims_mixed(&text, &format!("intensity {intensity}"), 4, mixes);
    }
}

/// `text` at 48x36 in both number types, its lamp's bound above
/// `least_lamp`: [`check`]'s checks on every row, more than 50 pixels that
/// see the lamp and something else, and of them more than a quarter mixed
/// where `mixes`, else none.
fn rims_mixed(text: &str, label: &str, least_lamp: u16, mixes: bool) {
    let q = Scene::<I16F16>::parse(text).unwrap();
    let f = Scene::<f32>::parse(text).unwrap();
    let lamp = Renderer::new(&q, 48, 36).bright_footprints().lamp();
    assert!(lamp > least_lamp, "{label}: the far sphere is a lamp ({lamp})");
    check(&q, 48, 36, &format!("{label} Q16.16"));
    check(&f, 48, 36, &format!("{label} f32"));
    for (both, mixed) in [rims(&q, 48, 36), rims(&f, 48, 36)] {
        assert!(both > 50, "{label}: {both} pixels see the lamp and the sphere");
        if mixes {
            assert!(mixed > both / 4, "{label}: {mixed} of {both} mixed");
        } else {
            assert_eq!(mixed, 0, "{label}: rims mixed");
        }
    }
}

/// A dim sphere just before the lens, in front of a lamp lit past its gate:
/// the rim it makes through part of every pixel's lens is its own
/// silhouette, spread over far more than the lamp's bound times the gate, so
/// the pixels that see both are mixed with their neighbours of either class
/// (seed 12194: a near sphere in a tenth of each pixel's lens, -2.88 ->
/// +0.10 dB against the floor at `point` 8); a larger one farther off,
/// still in front but too near focus to pass that gate, is never mixed across.
#[test]
fn a_lamps_rim_behind_a_near_occluder_is_mixed_with_either_side() {
    for (z, mixes) in [(-1.2, true), (-40.0, false)] {
        let size = if mixes { 0.4 } else { 8.0 };
        // A light behind the lamp makes its bound (29 times white); the one
        // before it shows it dim, so that a mix is seen.
        let text = format!(
            "point 40\nradius 1.5\nfocal_length 4\nimage_distance 8\nwidth 2\n\
             light_position 0 0 10\nlight_intensity 0.8 0.8 0.8\nambient_light 0.2 0.2 0.2\n\
             light_position 0 0 -400\nlight_intensity 40 40 40\n\
             object sphere\nKa 0.2 0.2 0.2\nKd 0.5 0.5 0.5\nKs 0.2 0.2 0.2\nscale 60 60 60\ntranslate 0 0 -120\n\
             object sphere\nKa 0.3 0.3 0.3\nKd 0.05 0.05 0.05\nKs 0 0 0\nscale {size} {size} {size}\ntranslate 0.1 0 {z}\n"
        );
        rims_mixed(&text, &format!("z {z}"), 20, mixes);
    }
}

/// A sphere in focus before a wall far out of focus: every pixel whose rays
/// or whose neighbours' rays meet the sphere keeps its own value (its edge
/// stays exact), and the wall's pixels away from it are filtered.
#[test]
fn an_edge_in_focus_stays_exact() {
    let text = "point 40\nradius 1.5\nfocal_length 4\nimage_distance 8\n\
                light_position 0 0 10\nlight_intensity 1 1 1\nambient_light 0.3 0.3 0.3\n\
                object sphere\nKd 0.8 0.2 0.2\nscale 1.5 1.5 1.5\ntranslate 0 0 -8\n\
                object plane\ntexture 1\nKa 0.3 0.3 0.3\nKd 0.5 0.5 0.9\ntranslate 0 0 -30\n";
    let scene = Scene::<I16F16>::parse(text).unwrap();
    let (w, h) = (48, 36);
    let r = Renderer::new(&scene, w, h);
    assert!(r.filters());
    let (mut edge, mut wall) = (0, 0);
    for row in 0..h {
        let mut out = vec![Rgb888::BLACK; w as usize];
        r.render_row(row, &mut out);
        let near: Vec<bool> = (0..w)
            .map(|c| smallest_coc(&r, &scene, c, row).0 < far_coc_pixels(r.samples()))
            .collect();
        for c in 0..w as usize {
            let touches = near[c] || (c > 0 && near[c - 1]) || (c + 1 < w as usize && near[c + 1]);
            if touches {
                assert_eq!(out[c], r.pixel(c as u32, row), "({c}, {row})");
                edge += 1;
            } else if c > 0 && c + 1 < w as usize && out[c] != r.pixel(c as u32, row) {
                wall += 1;
            }
        }
    }
    assert!(
        edge > 100 && wall > 100,
        "{edge} pixels at the sphere, {wall} wall pixels filtered"
    );
}

/// Rows are the pixels alone with the independent sampler or adaptive
/// sampling off (the converged references and the floors' yardstick).
#[test]
fn independent_and_non_adaptive_renders_are_not_filtered() {
    let text = lensray_testkit::scenegen::generate_lens(6014);
    for (sampler, adaptive) in [(Sampler::Independent, true), (Sampler::Stratified, false)] {
        let mut scene = Scene::<I16F16>::parse(&text).unwrap();
        scene.camera.sampler = sampler;
        scene.camera.adaptive = adaptive;
        scene.camera.samples = 24;
        let r = Renderer::new(&scene, 32, 24);
        assert!(!r.filters());
        for row in 0..24 {
            let mut out = vec![Rgb888::BLACK; 32];
            r.render_row(row, &mut out);
            let alone: Vec<Rgb888> = (0..32).map(|c| r.pixel(c, row)).collect();
            assert_eq!(out, alone, "{sampler:?} adaptive {adaptive} row {row}");
        }
    }
}

/// The progressive passes end on the plain render where rows are filtered
/// (the last pass redraws the coarser grids' rows), in both number types.
#[test]
fn progressive_passes_end_on_the_filtered_picture() {
    fn go<S: Scalar>(text: &str) {
        let scene = Scene::<S>::parse(text).unwrap();
        let r = Renderer::new(&scene, 40, 30);
        assert!(r.filters());
        let mut display = MockDisplay::<Rgb888>::new();
        display.set_allow_overdraw(true);
        for pass in progressive::Schedule::new(8, 1, r.rays_per_pixel()) {
            progressive::render_pass(&r, &mut display, &pass).unwrap();
        }
        let mut plain = MockDisplay::<Rgb888>::new();
        lensray::render_with(&r, &mut plain).unwrap();
        display.assert_eq(&plain);
        let mut unfiltered = 0;
        for row in 0..30 {
            let mut out = vec![Rgb888::BLACK; 40];
            r.render_row(row, &mut out);
            unfiltered += (0..40).filter(|&c| out[c as usize] != r.pixel(c, row)).count();
        }
        assert!(unfiltered > 50, "the scene is filtered: {unfiltered} pixels");
    }
    let text = lensray_testkit::scenegen::generate_lens(6014).replace("adaptive off", "adaptive on")
        + "\nsampler stratified\nadaptive on\n";
    go::<I16F16>(&text);
    go::<f32>(&text);
}
