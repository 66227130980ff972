//! Lens rays' box-filtered checkers: a ray standing for one
//! stratum of the lens averages the checker over its footprint
//! (`Object::checker_filtered`). The average is the exact mean of the
//! darkening over the footprint's box, in both number types; a footprint
//! inside one square, or of zero width, is the plain checker; pinhole
//! renders do not change. The footprint's width is the library's own
//! business (`render/defocus.rs`); the polygon's part of it, the radius of
//! the disc of the aperture's area, is public and checked here.

use lensray::{Aperture, Renderer, Sampler, Scalar, Scene, Vec3, I16F16};
use lensray_host::reference64::Scene64;

/// splitmix64, for reproducible random cases.
fn rng(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// The plane z = 0 with checker squares of `side` (0: untextured) and the
/// statements `placement` after it, as the only object of its scene.
fn textured_plane<S: Scalar>(side: f64, placement: &str) -> Scene<S> {
    Scene::parse(&format!("object plane\ntexture {side}\n{placement}")).expect("a textured plane")
}

/// The plane's darkening along the ray from `o` (world) along unit `d` (the
/// number type's own), its checker averaged over a footprint of radius `w`
/// across the ray with the world normal `n` (facing the ray): the filtered
/// value, else the plain checker's (1/4 on a dark square, else 1); and the
/// hit's object point.
fn darkening_along<S: Scalar>(scene: &Scene<S>, o: [f64; 3], d: [f64; 3], n: [f64; 3], w: f64) -> (f64, [f64; 3]) {
    let obj = &scene.objects()[0];
    let d = Vec3::<S>::from_f64(d).normalize();
    let hit = obj
        .intersect(Vec3::from_f64(o), d, S::HIT_EPSILON, S::MAX)
        .expect("the ray meets the plane");
    let value = match obj.checker_filtered(&hit, d, Vec3::from_f64(n), S::from_f64(w)) {
        Some(f) => f.to_f64(),
        None if obj.in_dark_square(&hit) => 0.25,
        None => 1.0,
    };
    (value, hit.local.p.to_f64())
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

/// The filtered darkening of `S` at (x, y) of the plane z = 0 for a footprint
/// of radius `w`, head-on, and the hit's object point.
fn filtered<S: Scalar>(side: f64, x: f64, y: f64, w: f64) -> (f64, [f64; 3]) {
    darkening_along(
        &textured_plane::<S>(side, ""),
        [x, y, 10.0],
        [0.0, 0.0, -1.0],
        [0.0, 0.0, 1.0],
        w,
    )
}

#[test]
fn the_filtered_checker_is_the_mean_over_the_footprint_in_both_number_types() {
    let mut s = 7u64;
    let mut worst: [f64; 2] = [0.0; 2];
    for _ in 0..300 {
        let side = 0.3 + 4.0 * rng(&mut s);
        let (x, y) = (40.0 * rng(&mut s) - 20.0, 40.0 * rng(&mut s) - 20.0);
        let w = side * 3.0 * rng(&mut s) * rng(&mut s);
        // The box's mean about the type's own hit point, by a fine midpoint grid.
        let mean = |p: [f64; 3]| {
            let k = 300;
            let mut sum = 0.0;
            for i in 0..k {
                for j in 0..k {
                    let u = p[0] - w + 2.0 * w * (i as f64 + 0.5) / k as f64;
                    let v = p[1] - w + 2.0 * w * (j as f64 + 0.5) / k as f64;
                    sum += darkening(u, v, side);
                }
            }
            sum / (k * k) as f64
        };
        let (f, pf) = filtered::<f32>(side, x, y, w);
        let (q, pq) = filtered::<I16F16>(side, x, y, w);
        worst[0] = worst[0].max((f - mean(pf)).abs());
        worst[1] = worst[1].max((q - mean(pq)).abs());
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
        let t = [rng(&mut s) * 10.0 - 5.0, rng(&mut s) * 4.0 - 2.0, -20.0];
        let (ax, ay, az) = (360.0 * rng(&mut s), 360.0 * rng(&mut s), 360.0 * rng(&mut s));
        let placement = format!(
            "total_transformation 5\nrotate z {az:.6}\nscale {:.6} {:.6} {:.6}\nrotate y {ay:.6}\nrotate x {ax:.6}\ntranslate {:.6} {:.6} {:.6}\n",
            sc[0], sc[1], sc[2], t[0], t[1], t[2]
        );
        let side = 0.3 + 2.0 * rng(&mut s);
        // The plane's maps in f64, from the same text.
        let o64 = Scene64::parse(&format!("object plane\n{placement}")).objects.remove(0);
        let b = o64.to_object.0;
        // World unit normal: row 2 of world → object (the plane is object z = 0).
        let nl = (b[2][0] * b[2][0] + b[2][1] * b[2][1] + b[2][2] * b[2][2]).sqrt();
        let n = [b[2][0] / nl, b[2][1] / nl, b[2][2] / nl];
        // A ray at least 25° off grazing, facing n's side.
        let (d, n) = slanted_ray(&mut s, n);
        let w = 0.05 + 1.5 * rng(&mut s);
        let half = rim_half_widths(&b, d, n, w);
        // The ray from 10 before the plane's object point (p, 0).
        let p = [rng(&mut s) * 8.0 - 4.0, rng(&mut s) * 8.0 - 4.0];
        let at = o64.to_world.apply([p[0], p[1], 0.0], true);
        let o = [0, 1, 2].map(|k| at[k] - 10.0 * d[k]);
        // The truth about the type's own hit point.
        let truth = |q: [f64; 3]| 0.625 + 0.375 * wave_mean(q[0], half[0], side) * wave_mean(q[1], half[1], side);
        let (f, pf) = darkening_along(&textured_plane::<f32>(side, &placement), o, d, n, w);
        let (q, pq) = darkening_along(&textured_plane::<I16F16>(side, &placement), o, d, n, w);
        let (ef, eq) = ((f - truth(pf)).abs(), (q - truth(pq)).abs());
        assert!(
            ef < 0.02 && eq < 0.02,
            "case {case}: truth {} / {}, f32 {f}, Q16.16 {q} (scales {sc:?}, half {half:?})",
            truth(pf),
            truth(pq)
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
    let scene = textured_plane::<I16F16>(2.0, "");
    let obj = &scene.objects()[0];
    let d = Vec3::new(I16F16::ZERO, I16F16::ZERO, -I16F16::ONE);
    let up = Vec3::new(I16F16::ZERO, I16F16::ZERO, I16F16::ONE);
    let hit = |x: f64, y: f64| {
        let o = Vec3::from_f64([x, y, 10.0]);
        let h = obj.intersect(o, d, I16F16::HIT_EPSILON, I16F16::MAX).expect("a hit");
        assert_eq!(h.local.p.to_f64(), [x, y, 0.0]);
        h
    };
    assert_eq!(obj.checker_filtered(&hit(1.0, 1.0), d, up, I16F16::ZERO), None);
    assert_eq!(obj.checker_filtered(&hit(1.0, 1.0), d, up, I16F16::from_num(0.9)), None);
    // Across a border, half and half: 5/8.
    let f = obj
        .checker_filtered(&hit(2.0, 1.0), d, up, I16F16::from_num(0.5))
        .unwrap();
    assert!((f.to_num::<f64>() - 0.625).abs() < 1e-3, "{f}");
    // Untextured: never filtered.
    let plain = textured_plane::<I16F16>(0.0, "");
    let plain = &plain.objects()[0];
    let h = plain
        .intersect(Vec3::from_f64([2.0, 1.0, 10.0]), d, I16F16::HIT_EPSILON, I16F16::MAX)
        .unwrap();
    assert_eq!(plain.checker_filtered(&h, d, up, I16F16::ONE), None);
}

#[test]
fn a_polygons_equal_area_radius_is_that_of_the_disc_of_its_area() {
    // A footprint stands for 1/P of the aperture's area: the disc of that
    // area, the area counted independently here: the Q1.15 lattice points
    // the aperture contains (every 64th), against the round lens's. Sized by
    // the circle, a triangle's footprints were 1.56 times too wide (seed
    // 8219's floor blurred flat).
    let count = |ap: &Aperture| {
        // Within Q1.15 (|x| < 2¹⁵), symmetric: x² + y² stays within an i32.
        let steps = (-32704..32768).step_by(64);
        steps
            .clone()
            .flat_map(|x| steps.clone().map(move |y| (x, y)))
            .filter(|&(x, y)| ap.contains_q15(x, y))
            .count() as f64
    };
    let round = count(&Aperture::ROUND);
    for blades in [0u32, 3, 4, 5, 6, 8, 16] {
        let ap = Aperture::regular(blades, 17.0);
        let want = (count(&ap) / round).sqrt();
        let got = ap.equal_area_radius();
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
    ind.camera.sampler = Sampler::Independent;
    let b = Renderer::new(&ind, 40, 30);
    for (x, y) in (0..30).flat_map(|y| (0..40).map(move |x| (x, y))) {
        assert_eq!(a.pixel(x, y), b.pixel(x, y));
    }
}

/// A unit direction at least 25° off grazing the plane of unit normal `n`,
/// and `n` turned to face it (the side the ray comes from).
fn slanted_ray(s: &mut u64, mut n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    loop {
        let v = [0, 1, 2].map(|_| rng(s) * 2.0 - 1.0);
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if l > 0.2 && l < 1.0 {
            let d = v.map(|x| x / l);
            let c = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
            if c.abs() > 0.45 {
                if c > 0.0 {
                    n = n.map(|x| -x);
                }
                break (d, n);
            }
        }
    }
}

/// Half-widths in object x and y of a footprint: the disc of radius `w`
/// across the ray `d`, projected along it onto the plane of unit normal `n`
/// whose world → object rows are `b` (found by walking the disc's rim).
fn rim_half_widths(b: &[[f64; 4]; 3], d: [f64; 3], n: [f64; 3], w: f64) -> [f64; 2] {
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
    half
}
