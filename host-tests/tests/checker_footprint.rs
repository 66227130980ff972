//! Lens rays' box-filtered checkers (issue 14): a ray standing for one
//! stratum of the lens averages the checker over its footprint. The average
//! is the exact mean of the darkening over the box, in both number types;
//! zero width is the plain checker; pinhole renders do not change.

use lensray::unstable::defocus::Defocus;
use lensray::unstable::scene::{Hit, Object, ObjectDesc};
use lensray::unstable::shape::{LocalHit, Shape};
use lensray::unstable::transform::Mat34;
use lensray::{Renderer, Scalar, Scene, Vec3, I16F16};

/// splitmix64, for reproducible random cases.
fn rng(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

fn textured_plane<S: Scalar>(side: f64) -> Object<S> {
    Object::new(&ObjectDesc {
        shape: Shape::Plane,
        ka: [0.2; 3],
        kd: [0.8; 3],
        ks: [0.0; 3],
        shine: 1.0,
        texture: side,
        to_world: Mat34::IDENTITY,
    })
    .unwrap()
}

/// The darkening at (x, y) of the plane z = 0: 1/4 on a dark square, else 1.
fn darkening(x: f64, y: f64, side: f64) -> f64 {
    let cells = (x / side).floor() as i64 + (y / side).floor() as i64;
    if cells & 1 == 1 {
        0.25
    } else {
        1.0
    }
}

/// The filtered darkening of `S` at (x, y) for half-width w, head-on.
fn filtered<S: Scalar>(obj: &Object<S>, x: f64, y: f64, w: f64) -> f64 {
    let p = Vec3::new(S::from_f64(x), S::from_f64(y), S::ZERO);
    let hit = Hit {
        t: S::ONE,
        local: LocalHit {
            t: S::ONE,
            p,
            n: Vec3::new(S::ZERO, S::ZERO, S::ONE),
        },
    };
    let d = Vec3::new(S::ZERO, S::ZERO, S::ONE.neg());
    match obj.checker_filtered(
        &hit,
        d,
        Vec3::new(S::ZERO, S::ZERO, S::ONE),
        S::from_f64(w),
        Vec3::new(S::ZERO, S::ZERO, S::ZERO),
    ) {
        Some(f) => f.to_f64(),
        None if obj.in_dark_square(&hit) => 0.25,
        None => 1.0,
    }
}

#[test]
fn the_filtered_checker_is_the_mean_over_the_footprint_in_both_number_types() {
    let mut s = 7u64;
    let mut worst: [f64; 2] = [0.0; 2];
    for _ in 0..300 {
        let side = 0.3 + 4.0 * rng(&mut s);
        let (x, y) = (40.0 * rng(&mut s) - 20.0, 40.0 * rng(&mut s) - 20.0);
        let w = side * 3.0 * rng(&mut s) * rng(&mut s);
        // The box's mean by a fine midpoint grid.
        let k = 300;
        let mut sum = 0.0;
        for i in 0..k {
            for j in 0..k {
                let u = x - w + 2.0 * w * (i as f64 + 0.5) / k as f64;
                let v = y - w + 2.0 * w * (j as f64 + 0.5) / k as f64;
                sum += darkening(u, v, side);
            }
        }
        let mean = sum / (k * k) as f64;
        let f = filtered(&textured_plane::<f32>(side), x, y, w);
        let q = filtered(&textured_plane::<I16F16>(side), x, y, w);
        worst[0] = worst[0].max((f - mean).abs());
        worst[1] = worst[1].max((q - mean).abs());
    }
    // The grid resolves the box to 1/300 of its side along each axis.
    assert!(worst[0] < 0.01, "f32: {}", worst[0]);
    assert!(worst[1] < 0.01, "Q16.16: {}", worst[1]);
}

/// The mean over [x − e, x + e] of the square wave +1 on even cells of
/// `side`, −1 on odd ones, by a fine midpoint grid.
fn wave_mean(x: f64, e: f64, side: f64) -> f64 {
    if e == 0.0 {
        return if (x / side).floor() as i64 & 1 == 0 { 1.0 } else { -1.0 };
    }
    let k = 4000;
    let sum: f64 = (0..k)
        .map(|i| {
            let u = x - e + 2.0 * e * (i as f64 + 0.5) / k as f64;
            if (u / side).floor() as i64 & 1 == 0 {
                1.0
            } else {
                -1.0
            }
        })
        .sum();
    sum / k as f64
}

#[test]
fn footprints_on_stretched_slanted_planes_span_what_the_lens_disc_covers() {
    // A plane squashed, stretched and turned (scales 0.3 to 3 per axis, so
    // one world unit is up to 10 times more object units along one axis than
    // another), seen slanted: the footprint, a disc of radius w across the
    // ray projected along it onto the plane, covers in object space a box
    // whose half-widths are found here by walking the disc's rim (f64), and
    // the filter must average the checker over that box. Seed 7019's floor
    // (scales 2.7, 2.3, 0.53) was blurred flat by a footprint sized by the
    // ray's own stretch on every axis.
    let mut s = 11u64;
    let mut worst: [f64; 2] = [0.0; 2];
    for case in 0..200 {
        let sc = [0, 1, 2].map(|_| 0.3 * 10f64.powf(rng(&mut s)));
        let to_world = Mat34::translate([rng(&mut s) * 10.0 - 5.0, rng(&mut s) * 4.0 - 2.0, -20.0])
            .after(&Mat34::rotate(0, 360.0 * rng(&mut s)))
            .after(&Mat34::rotate(1, 360.0 * rng(&mut s)))
            .after(&Mat34::scale(sc))
            .after(&Mat34::rotate(2, 360.0 * rng(&mut s)));
        let side = 0.3 + 2.0 * rng(&mut s);
        let b = to_world.inverse().unwrap().0;
        // World unit normal: row 2 of world → object (the plane is object z = 0).
        let nl = (b[2][0] * b[2][0] + b[2][1] * b[2][1] + b[2][2] * b[2][2]).sqrt();
        let mut n = [b[2][0] / nl, b[2][1] / nl, b[2][2] / nl];
        // A ray at least 25° off grazing, facing n's side.
        let d = loop {
            let v = [0, 1, 2].map(|_| rng(&mut s) * 2.0 - 1.0);
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if l > 0.2 && l < 1.0 {
                let d = v.map(|x| x / l);
                let c = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
                if c.abs() > 0.45 {
                    if c > 0.0 {
                        n = n.map(|x| -x);
                    }
                    break d;
                }
            }
        };
        let dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
        // Two unit vectors across the ray.
        let a = if d[0].abs() < 0.6 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let cross = |x: [f64; 3], y: [f64; 3]| {
            [
                x[1] * y[2] - x[2] * y[1],
                x[2] * y[0] - x[0] * y[2],
                x[0] * y[1] - x[1] * y[0],
            ]
        };
        let e1 = cross(d, a);
        let l1 = (e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]).sqrt();
        let e1 = e1.map(|x| x / l1);
        let e2 = cross(d, e1);
        let w = 0.05 + 1.5 * rng(&mut s);
        let mut half = [0.0f64; 2];
        for i in 0..720 {
            let th = i as f64 * std::f64::consts::PI / 360.0;
            let x = [0, 1, 2].map(|k| w * (th.cos() * e1[k] + th.sin() * e2[k]));
            let nx = x[0] * n[0] + x[1] * n[1] + x[2] * n[2];
            let y = [0, 1, 2].map(|k| x[k] - d[k] * nx / dn);
            for (k, h) in half.iter_mut().enumerate() {
                *h = h.max((b[k][0] * y[0] + b[k][1] * y[1] + b[k][2] * y[2]).abs());
            }
        }
        let p = [rng(&mut s) * 8.0 - 4.0, rng(&mut s) * 8.0 - 4.0];
        let truth = 0.625 + 0.375 * wave_mean(p[0], half[0], side) * wave_mean(p[1], half[1], side);
        fn got<S: Scalar>(to_world: &Mat34, side: f64, p: [f64; 2], d: [f64; 3], n: [f64; 3], w: f64) -> f64 {
            let obj = Object::<S>::new(&ObjectDesc {
                shape: Shape::Plane,
                ka: [0.2; 3],
                kd: [0.8; 3],
                ks: [0.0; 3],
                shine: 1.0,
                texture: side,
                to_world: *to_world,
            })
            .unwrap();
            let hit = Hit {
                t: S::ONE,
                local: LocalHit {
                    t: S::ONE,
                    p: Vec3::new(S::from_f64(p[0]), S::from_f64(p[1]), S::ZERO),
                    n: Vec3::new(S::ZERO, S::ZERO, S::ONE),
                },
            };
            match obj.checker_filtered(
                &hit,
                Vec3::from_f64(d),
                Vec3::from_f64(n),
                S::from_f64(w),
                Vec3::new(S::ZERO, S::ZERO, S::ZERO),
            ) {
                Some(f) => f.to_f64(),
                None if obj.in_dark_square(&hit) => 0.25,
                None => 1.0,
            }
        }
        let f = got::<f32>(&to_world, side, p, d, n, w);
        let q = got::<I16F16>(&to_world, side, p, d, n, w);
        let (ef, eq) = ((f - truth).abs(), (q - truth).abs());
        assert!(
            ef < 0.02 && eq < 0.02,
            "case {case}: truth {truth}, f32 {f}, Q16.16 {q} (scales {sc:?}, half {half:?})"
        );
        worst = [worst[0].max(ef), worst[1].max(eq)];
    }
    eprintln!(
        "worst error of the filtered darkening: f32 {:.4}, Q16.16 {:.4}",
        worst[0], worst[1]
    );
}

#[test]
fn a_footprint_inside_one_square_or_of_zero_width_is_the_plain_checker() {
    let obj = textured_plane::<I16F16>(2.0);
    let hit = |x: f64, y: f64| Hit {
        t: I16F16::ONE,
        local: LocalHit {
            t: I16F16::ONE,
            p: Vec3::new(I16F16::from_num(x), I16F16::from_num(y), I16F16::ZERO),
            n: Vec3::new(I16F16::ZERO, I16F16::ZERO, I16F16::ONE),
        },
    };
    let d = Vec3::new(I16F16::ZERO, I16F16::ZERO, -I16F16::ONE);
    let up = Vec3::new(I16F16::ZERO, I16F16::ZERO, I16F16::ONE);
    let zero = Vec3::new(I16F16::ZERO, I16F16::ZERO, I16F16::ZERO);
    assert_eq!(obj.checker_filtered(&hit(1.0, 1.0), d, up, I16F16::ZERO, zero), None);
    assert_eq!(
        obj.checker_filtered(&hit(1.0, 1.0), d, up, I16F16::from_num(0.9), zero),
        None
    );
    // Across a border, half and half: 5/8.
    let f = obj
        .checker_filtered(&hit(2.0, 1.0), d, up, I16F16::from_num(0.5), zero)
        .unwrap();
    assert!((f.to_num::<f64>() - 0.625).abs() < 1e-3, "{f}");
    // Untextured: never filtered.
    let plain = textured_plane::<I16F16>(0.0);
    assert_eq!(plain.checker_filtered(&hit(2.0, 1.0), d, up, I16F16::ONE, zero), None);
}

#[test]
fn stratum_radii_halve_with_four_times_the_strata() {
    let scene = Scene::<f32>::parse("radius 0.5\nfocus_distance 10\n").unwrap();
    let d = Defocus::new(&scene);
    for m in 0..12u32 {
        let r = d.stratum(1 << m).radius as f64;
        let exact = 0.5 / ((1u64 << m) as f64).sqrt();
        assert!((r - exact).abs() < 1e-4 * exact.max(1e-3), "{m}: {r} vs {exact}");
    }
    // A pinhole has no footprint.
    let pin = Scene::<f32>::parse("radius 0\n").unwrap();
    assert_eq!(Defocus::new(&pin).stratum(8).radius, 0.0);
}

#[test]
fn polygon_footprints_stand_for_a_stratum_of_the_polygons_area() {
    // The stratum's radius is that of the disc of 1/P of the aperture's area,
    // the area counted independently: the Q1.15 lattice points the aperture
    // contains (every 64th), against the round lens's. Sized by the circle, a
    // triangle's footprints were 1.56 times too wide (seed 8219's floor blurred flat).
    let count = |ap: &lensray::unstable::aperture::Aperture| {
        // Within Q1.15 (|x| < 2¹⁵), symmetric: x² + y² stays within an i32.
        let steps = (-32704..32768).step_by(64);
        steps
            .clone()
            .flat_map(|x| steps.clone().map(move |y| (x, y)))
            .filter(|&(x, y)| ap.contains_q15(x, y))
            .count() as f64
    };
    let round = count(&lensray::unstable::aperture::Aperture::ROUND);
    for blades in [0u32, 3, 4, 5, 6, 8, 16] {
        let text = format!("radius 0.5\nfocus_distance 10\naperture_blades {blades}\naperture_rotation 17\n");
        let d = Defocus::new(&Scene::<f32>::parse(&text).unwrap());
        let ap = lensray::unstable::aperture::Aperture::regular(blades, 17.0);
        let want = 0.5 * (count(&ap) / round).sqrt() / 4.0;
        let got = d.stratum(16).radius as f64;
        assert!((got - want).abs() < 2e-3 * want, "{blades} blades: {got} vs {want}");
    }
}

#[test]
fn pinhole_renders_are_unfiltered() {
    // A textured floor: with a pinhole, the stratified and independent
    // samplers give the same picture (one ray, no footprint).
    let text = "object plane\ntexture 0.7\nrotate x -90\ntranslate 0 -2 0\nlight_position 0 10 0\n";
    let pin = Scene::<I16F16>::parse(&format!("{text}radius 0\n")).unwrap();
    let a = Renderer::new(&pin, 40, 30);
    let mut ind = pin.clone();
    ind.camera.sampler = lensray::unstable::sampler::Sampler::Independent;
    let b = Renderer::new(&ind, 40, 30);
    for (x, y) in (0..30).flat_map(|y| (0..40).map(move |x| (x, y))) {
        assert_eq!(a.pixel(x, y), b.pixel(x, y));
    }
}

/// Over a grid of a frame's pixels whose every ray meets the checker, the
/// mean squared error of each pixel's checker darkening as its first `n`
/// stratified rays' footprints average it (their centres pulled in, or
/// not) against the pixel's truth, the mean of 1024 stratified rays' point
/// darkening; and the number of such pixels.
fn checker_error(text: &str, n: u32, pull: bool) -> (f64, usize) {
    use lensray::unstable::camera::{Camera, CameraSample};
    use lensray::unstable::cull::LensCones;
    use lensray::unstable::sampler::{PixelSamples, Sampler};
    let scene = Scene::<I16F16>::parse(text).unwrap();
    let (w, h) = (64, 48);
    let cam = Camera::new(&scene.camera, w, h);
    let cones = LensCones::new(&scene, scene.camera.lens_position, scene.camera.radius);
    let defocus = Defocus::new(&scene);
    let stratum = defocus.stratum(n);
    let share = if pull { stratum.pull } else { I16F16::ZERO };
    let (mut sum, mut pixels) = (0.0, 0);
    for y in (0..h).step_by(2) {
        for x in (0..w).step_by(2) {
            let film = cam.film_point(x, y);
            let mut lens = PixelSamples::new(Sampler::Stratified, x, y);
            let (mut truth, mut est, mut hits) = (0.0, 0.0, 0u32);
            for i in 0..1024 {
                let p_lens = lens.next(cam.aperture());
                let ray = cam.generate_ray(&CameraSample {
                    film: &film,
                    lens: Some(p_lens),
                });
                let Some((k, hit)) = scene.closest_hit_camera_ray(&ray, &cones) else {
                    continue;
                };
                let o = &scene.objects()[k];
                let point = if o.in_dark_square(&hit) { 0.25 } else { 1.0 };
                truth += point;
                hits += 1;
                if i < n {
                    let shift = defocus.shift(ray.dir, hit.t, cam.lens_offset(p_lens, share));
                    let wdt = defocus.width(ray.dir, hit.t, stratum.radius);
                    let nrm = o.normal(&hit, ray.dir);
                    est += o
                        .checker_filtered(&hit, ray.dir, nrm, wdt, shift)
                        .map_or(point, |f| f.to_f64());
                }
            }
            if hits == 1024 {
                let e = truth / 1024.0 - est / n as f64;
                sum += e * e;
                pixels += 1;
            }
        }
    }
    (sum / pixels.max(1) as f64, pixels)
}

#[test]
fn pulled_footprints_keep_a_blurred_checkers_contrast() {
    // Random checkered planes out of focus (a circle of confusion of 0.5 to
    // 3 squares), head-on to slanted, round lens and polygons, 4 and 8
    // strata: the box each stratum's ray averages over widens the lens's
    // blur by 4/(3P) of its variance and greys the checker (seed 12484:
    // blue -7.5 levels at 4 strata). Pulled in by `Stratum::pull`, the
    // spread is the lens's again: less error against the truth overall
    // (0.85 of it here), and never much more on one frame.
    let mut s = 12484u64;
    let (mut pulled, mut centred) = (0.0, 0.0);
    for case in 0..24 {
        let (n, blades) = ([4u32, 8][case % 2], [0u32, 0, 5, 6, 0, 3][case % 6]);
        let side = 0.2 + 0.6 * rng(&mut s);
        let tilt = -70.0 * rng(&mut s);
        let depth = 6.0 + 6.0 * rng(&mut s);
        let focus = depth * (0.45 + 0.2 * rng(&mut s));
        // The circle of confusion at the plane: radius (z/z_f − 1).
        let radius = (side * (0.5 + 2.5 * rng(&mut s)) / (depth / focus - 1.0)).min(1.5);
        let text = format!(
            "width 10\naspect_ratio 1.33\nimage_distance 8\nfocal_length 4\nlens_position 0 0 0\nlook 0 0 -1\nup 0 1 0\n\
             radius {radius}\nfocus_distance {focus}\naperture_blades {blades}\nambient_light 1 1 1\n\
             object plane\nKa 0.2 0.2 0.2\nKd 0.8 0.8 0.8\ntexture {side}\ntotal_transformation 2\nrotate x {tilt}\ntranslate 0 0 -{depth}\n"
        );
        let (p, pixels) = checker_error(&text, n, true);
        let (c, _) = checker_error(&text, n, false);
        assert!(pixels > 200, "case {case}: {pixels} pixels on the checker");
        assert!(
            p < 1.15 * c,
            "case {case} ({n} strata, {blades} blades): {p} against {c} centred"
        );
        eprintln!("case {case}: {n} strata, {blades} blades: {p:.6} pulled, {c:.6} centred");
        (pulled, centred) = (pulled + p, centred + c);
    }
    assert!(pulled < 0.9 * centred, "{pulled} pulled against {centred} centred");
}
