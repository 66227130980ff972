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
    match obj.checker_filtered(&hit, d, S::from_f64(w)) {
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
    assert_eq!(obj.checker_filtered(&hit(1.0, 1.0), d, I16F16::ZERO), None);
    assert_eq!(obj.checker_filtered(&hit(1.0, 1.0), d, I16F16::from_num(0.9)), None);
    // Across a border, half and half: 5/8.
    let f = obj.checker_filtered(&hit(2.0, 1.0), d, I16F16::from_num(0.5)).unwrap();
    assert!((f.to_num::<f64>() - 0.625).abs() < 1e-3, "{f}");
    // Untextured: never filtered.
    let plain = textured_plane::<I16F16>(0.0);
    assert_eq!(plain.checker_filtered(&hit(2.0, 1.0), d, I16F16::ONE), None);
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
