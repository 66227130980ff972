//! Checker borders, every shape and the plane: Q16.16's choice of square
//! against float64 (`lensray_host::reference64`) for the very ray Q16.16
//! holds, on rays whose origin sits a few Q16.16 steps from where f64's
//! square flips (small, turned, stretched objects: an object-space error
//! grows with the inverse scale). See docs/accuracy.md, fix 16.

use lensray::unstable::scene::{Object, ObjectDesc, DEFAULT_MATERIAL};
use lensray::{Scalar, Shape, Vec3, I16F16};
use lensray_host::reference64::{Object64, Scene64};

/// xorshift64*: the test's seeded random source, uniform in [0, 1).
fn rng(mut s: u64) -> impl FnMut() -> f64 {
    move || {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        (s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// One textured object in both forms, Q16.16 and f64, from the same scene
/// text: scaled 0.2 to 1.5 per axis (a plane 0.5 to 20), turned twice,
/// anywhere within 30, squares of 0.1 to 0.6 object units.
fn object(shape: Shape, r: &mut impl FnMut() -> f64) -> (Object<I16F16>, Object64) {
    let big = if shape == Shape::Plane { 15.0 } else { 1.3 };
    let s = [0, 1, 2].map(|_| 0.2 + big * r());
    let names = ["x", "y", "z"];
    let (ax, ang) = (names[(r() * 3.0) as usize], r() * 360.0);
    let (ax2, ang2) = (names[(r() * 3.0) as usize], r() * 360.0);
    let t = [0, 1, 2].map(|_| (r() - 0.5) * 60.0);
    let texture = 0.1 + 0.5 * r();
    let text = format!(
        "object {}\ntexture {texture:.5}\nscale {:.4} {:.4} {:.4}\nrotate {ax} {ang:.4}\nrotate {ax2} {ang2:.4}\ntranslate {:.4} {:.4} {:.4}\n",
        shape.name(),
        s[0],
        s[1],
        s[2],
        t[0],
        t[1],
        t[2]
    );
    let o64 = Scene64::parse(&text).objects.remove(0);
    let mut desc = ObjectDesc::new(shape, &DEFAULT_MATERIAL, o64.to_world);
    desc.texture = (texture * 1e5).round() / 1e5;
    (Object::new(&desc).expect("invertible"), o64)
}

/// (shape, rays, Q16.16 squares unlike f64's) over `cases` rays a shape
/// meets: the origin stepped by single Q16.16 steps across the place where
/// f64's square flips (its parity), 3 steps either side, where both hit the
/// same face or part. `retake`: Q16.16's decision with the exact retake
/// (`in_dark_square_along`), else the rounded point's alone.
fn disagreements(cases: usize, retake: bool) -> Vec<(Shape, usize, usize)> {
    let mut r = rng(0x5EED_C4EC_0B0A_4D16);
    let mut out = Vec::new();
    for shape in [Shape::Sphere, Shape::Cube, Shape::Cylinder, Shape::Cone, Shape::Plane] {
        let (mut rays, mut wrong) = (0, 0);
        for _ in 0..cases {
            let (obj, o64) = object(shape, &mut r);
            // Aim at a point near the centre (the plane: near its origin).
            let c = o64.to_world.apply([0, 1, 2].map(|_| (r() - 0.5) * 1.2), true);
            let dir: [f64; 3] = {
                let v = [r() - 0.5, r() - 0.5, r() - 0.5];
                let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                v.map(|x| x / l)
            };
            let dist = 20.0 + 100.0 * r();
            let d = Vec3::<I16F16>::from_f64(dir.map(|x| -x)).normalize();
            let df = d.to_f64();
            let axis = (r() * 3.0) as usize;
            let base = Vec3::<I16F16>::from_f64([0, 1, 2].map(|i| c[i] + dir[i] * dist)).to_array();
            let origin = |k: i64| {
                let mut o = base;
                o[axis] = I16F16::from_bits(o[axis].to_bits() + k as i32);
                o
            };
            // f64's hit: (part, dark).
            let f64_at = |k: i64| {
                let o = origin(k).map(|x| x.to_f64());
                o64.hit(o, df, 1.0 / 1024.0, f64::INFINITY)
                    .map(|h| (h.part, o64.dark(h.p)))
            };
            let Some(start) = f64_at(0) else { continue };
            // The first flip of the square within 2^14 steps, on the same part.
            let Some(far) = (1..=64)
                .map(|i| i * 256)
                .find(|&k| f64_at(k).is_none_or(|h| h != start))
            else {
                continue;
            };
            if f64_at(far).is_none_or(|h| h.0 != start.0) {
                continue;
            }
            let (mut lo, mut hi) = (far - 256, far);
            while hi - lo > 1 {
                let mid = (lo + hi) / 2;
                if f64_at(mid) == Some(start) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            for k in lo - 3..=hi + 3 {
                let Some((part, dark)) = f64_at(k) else { continue };
                if part != start.0 {
                    continue;
                }
                let o = Vec3::from_array(origin(k));
                let Some(hit) = obj.intersect(o, d, I16F16::HIT_EPSILON, I16F16::MAX) else {
                    continue;
                };
                let q = if retake {
                    obj.in_dark_square_along(&hit, o, d)
                } else {
                    obj.in_dark_square(&hit)
                };
                rays += 1;
                wrong += usize::from(q != dark);
            }
        }
        out.push((shape, rays, wrong));
    }
    out
}

#[test]
fn checker_border_decisions_agree_with_f64() {
    let before = disagreements(300, false);
    let counts = disagreements(300, true);
    println!("rounded point: {before:?}\nretaken: {counts:?}");
    for ((shape, rays, wrong), (_, _, was)) in counts.into_iter().zip(before) {
        assert!(rays > 800, "{shape:?}: {rays} rays");
        // Measured (docs/accuracy.md, fix 16): with the rounded point alone
        // 102 (plane) to 247 (sphere) went the other way; with the retake 6
        // (cube) to 58 (sphere). Not yet 0: see the docs' "What remains".
        assert!(
            wrong * 4 <= was,
            "{shape:?}: {wrong} of {rays} unlike f64 ({was} without the retake)"
        );
    }
}
