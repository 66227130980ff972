//! Near-tangent rays, every bounded shape: Q16.16's hit-or-miss decision
//! against float64 (`lensray_host::reference64`) for the very ray Q16.16
//! holds, on rays whose origin sits a few Q16.16 steps from where the
//! decision flips (small, turned, stretched objects: an object-space error
//! grows with the inverse scale). See docs/fixed-point.md, section 4.

mod common;
use common::{random_placement, rng, SteppedRay};
use lensray::{Scalar, Scene, Shape, Vec3, I16F16};
use lensray_host::reference64::{Object64, Scene64};

/// One object in both forms, Q16.16 (the only object of its scene) and f64,
/// from the same scene text: scaled 0.2 to 1.5 per axis, turned twice,
/// anywhere within 30.
fn object(shape: Shape, r: &mut impl FnMut() -> f64) -> (Scene<I16F16>, Object64) {
    let text = format!("object {}\n{}", shape.name(), random_placement(r, 1.3));
    let o64 = Scene64::parse(&text).objects.remove(0);
    (Scene::parse(&text).expect("a valid placement"), o64)
}

/// (shape, rays, Q16.16 decisions unlike f64's) over `cases` silhouettes of
/// each bounded shape: the origin stepped by single Q16.16 steps across the
/// place where f64's decision flips, 3 steps either side.
fn disagreements(cases: usize) -> Vec<(Shape, usize, usize)> {
    let mut r = rng(0x9E37_79B9_7F4A_7C15);
    let mut out = Vec::new();
    for shape in [Shape::Sphere, Shape::Cube, Shape::Cylinder, Shape::Cone] {
        let (mut rays, mut wrong) = (0, 0);
        for _ in 0..cases {
            let (scene, o64) = object(shape, &mut r);
            let obj = &scene.objects()[0];
            let c = o64.to_world.apply([0.0; 3], true);
            // An origin 20 to 120 away, the direction at the centre, rounded;
            // slid along an axis: f64 hits on the centre line and misses 4
            // units aside; bisect to the two neighbouring steps.
            let ray = SteppedRay::new(c, &mut r);
            let (d, df) = (ray.d, ray.df);
            let origin = |k: i64| ray.origin(k);
            let hits64 = |k: i64| {
                let o = origin(k).map(|x| x.to_f64());
                o64.hit(o, df, 1.0 / 1024.0, f64::INFINITY).is_some()
            };
            let (mut lo, mut hi) = (0i64, 4 << 16);
            if !hits64(lo) || hits64(hi) {
                continue;
            }
            while hi - lo > 1 {
                let mid = (lo + hi) / 2;
                if hits64(mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            for k in lo - 3..=hi + 3 {
                let o = Vec3::from_array(origin(k));
                let q = obj.intersect(o, d, I16F16::HIT_EPSILON, I16F16::MAX).is_some();
                rays += 1;
                wrong += usize::from(q != hits64(k));
            }
        }
        out.push((shape, rays, wrong));
    }
    out
}

#[test]
fn near_tangent_decisions_agree_with_f64() {
    let counts = disagreements(400);
    println!("{counts:?}");
    for (shape, rays, wrong) in counts {
        assert!(rays > 2000, "{shape:?}: {rays} rays");
        // Rays 0 to 4 Q16.16 steps (up to 6e-5 world units, 3e-4 object
        // units) from the flip. Measured on these 400 silhouettes a shape:
        // without the recheck 9.4 % (sphere) to 13.1 % (cube) went the other
        // way; with the exact decisions none, for every shape (the cylinder's
        // and the cone's with their second pass exact; 4.6 % and 7.7 % with it
        // rounded to 2^-17: docs/fixed-point.md, section 4).
        assert_eq!(wrong, 0, "{shape:?}: {wrong} of {rays} unlike f64");
    }
}
