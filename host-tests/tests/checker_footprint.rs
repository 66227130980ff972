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
    match obj.checker_filtered(&hit, d, Vec3::new(S::ZERO, S::ZERO, S::ONE), S::from_f64(w)) {
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
            match obj.checker_filtered(&hit, Vec3::from_f64(d), Vec3::from_f64(n), S::from_f64(w)) {
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
    assert_eq!(obj.checker_filtered(&hit(1.0, 1.0), d, up, I16F16::ZERO), None);
    assert_eq!(obj.checker_filtered(&hit(1.0, 1.0), d, up, I16F16::from_num(0.9)), None);
    // Across a border, half and half: 5/8.
    let f = obj
        .checker_filtered(&hit(2.0, 1.0), d, up, I16F16::from_num(0.5))
        .unwrap();
    assert!((f.to_num::<f64>() - 0.625).abs() < 1e-3, "{f}");
    // Untextured: never filtered.
    let plain = textured_plane::<I16F16>(0.0);
    assert_eq!(plain.checker_filtered(&hit(2.0, 1.0), d, up, I16F16::ONE), None);
}

#[test]
fn stratum_radii_halve_with_four_times_the_strata() {
    let scene = Scene::<f32>::parse("radius 0.5\nfocus_distance 10\n").unwrap();
    let d = Defocus::new(&scene);
    for m in 0..12u32 {
        let r = d.stratum(1 << m) as f64;
        let exact = 0.5 / ((1u64 << m) as f64).sqrt();
        assert!((r - exact).abs() < 1e-4 * exact.max(1e-3), "{m}: {r} vs {exact}");
    }
    // A pinhole has no footprint.
    let pin = Scene::<f32>::parse("radius 0\n").unwrap();
    assert_eq!(Defocus::new(&pin).stratum(8), 0.0);
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
        let got = d.stratum(16) as f64;
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
