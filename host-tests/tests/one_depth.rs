//! Two surfaces at one depth, every pair of shapes: which object Q16.16's
//! nearest-hit search reports against float64 (`lensray_host::reference64`)
//! for the very ray Q16.16 holds, on rays whose origin sits a few Q16.16
//! steps from where the two surfaces cross (the nearer of the two flips
//! there). Random pairs (the plane included), each small, turned and
//! stretched, the second moved so that it passes through a point of the
//! first's surface. See docs/fixed-point.md, section 5.

mod common;
use common::{object_text, rng, stored_rows_delta, surface_point, SteppedRay, SHAPES};
use lensray::{Scalar, Scene, Shape, Vec3, I16F16};
use lensray_host::reference64::{Hit64, Object64, Scene64};

const CAMERA: &str = "image_distance 8\nlens_position 0 0 0\nwidth 1\naspect_ratio 1\nlook 0 0 -1\nup 0 1 0\n";

/// The world distance by which the exact kernel's t (`q16::exact_t`) may
/// lie off f64's for the hit `h` of the ray `o + t d` on `o64`: the object's
/// rows keep 30 significant bits an entry (`Kernels::row_from_f64`, as
/// `checker_border.rs`'s `row_error`), which puts the exact object-space
/// point `q` of the world point `w` off f64's by `δ = (M̃ − M) w + (t̃ − t)`;
/// along the ray that is `(n · δ) / (n · D)` of t, `D` the local direction a
/// world unit; the kernel's own rounding (2^-30 a component) adds a few
/// 2^-30 over the same slope.
fn t_error(o64: &Object64, o: [f64; 3], d: [f64; 3], h: &Hit64) -> f64 {
    let w = [0, 1, 2].map(|i| o[i] + h.t * d[i]);
    let delta = stored_rows_delta(o64, w);
    let dd = o64.to_object.apply(d, false);
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let nd = dot(h.n, dd).abs();
    let n_len = dot(h.n, h.n).sqrt();
    (dot(h.n, delta).abs() + 8.0 * n_len * 2f64.powi(-30)) / nd
}

/// The object Q16.16 would call nearest on the rounded t alone (each
/// object's own `intersect`, the first of equal t), as the search did
/// before the exact order: what shows that the rays are close enough to
/// test it.
fn nearest_on_rounded_t(scene: &Scene<I16F16>, o: Vec3<I16F16>, d: Vec3<I16F16>) -> Option<usize> {
    let hits = scene.objects().iter().enumerate();
    hits.filter_map(|(i, obj)| Some((obj.intersect(o, d, I16F16::HIT_EPSILON, I16F16::MAX)?.t, i)))
        .min()
        .map(|(_, i)| i)
}

/// A random pair of shapes, each small, turned and stretched, the second
/// moved so that it passes through a point `p` of the first's surface: the
/// scene's text and `p`; `None` where a surface point was not found.
fn pair_through_a_point<R: FnMut() -> f64>(r: &mut R) -> Option<(Shape, Shape, String, [f64; 3])> {
    let (a, b) = (SHAPES[(r() * 5.0) as usize], SHAPES[(r() * 5.0) as usize]);
    let mut form = || {
        let s = [0, 1, 2]
            .map(|_| (0.2 + 1.3 * r()) * 10_000.0)
            .map(|x| x.round() / 10_000.0);
        let turn = |r: &mut dyn FnMut() -> f64| ((r() * 3.0) as usize, ((r() * 360.0) * 10_000.0).round() / 10_000.0);
        (s, [turn(&mut *r), turn(&mut *r)])
    };
    let (fa, fb) = (form(), form());
    let ta = [0, 1, 2].map(|_| ((r() - 0.5) * 60.0 * 10_000.0).round() / 10_000.0);
    // A point on A's surface; B at the origin, a point on its surface.
    let a_text = object_text(a, fa, ta);
    let p = surface_point(&Scene64::parse(&format!("{CAMERA}{a_text}")), ta, &mut *r)?;
    let w = surface_point(
        &Scene64::parse(&format!("{CAMERA}{}", object_text(b, fb, [0.0; 3]))),
        [0.0; 3],
        &mut *r,
    )?;
    // B moved so that it passes through p (to the text's 4 decimals: near it).
    let tb = [0, 1, 2].map(|i| ((p[i] - w[i]) * 10_000.0).round() / 10_000.0);
    Some((a, b, format!("{CAMERA}{a_text}{}", object_text(b, fb, tb)), p))
}

/// The two neighbouring steps between which f64's nearest object flips
/// (within 0.02 either side of step 0), by bisection; `None` where it is
/// the same at both ends or missing at one.
fn flip(nearest64: impl Fn(i64) -> Option<usize>) -> Option<(i64, i64)> {
    let (mut lo, mut hi) = (-1310i64, 1310i64);
    let (first, last) = (nearest64(lo), nearest64(hi));
    if first == last || first.is_none() || last.is_none() {
        return None;
    }
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if nearest64(mid) == first {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some((lo, hi))
}

/// Why Q16.16's nearest object on the ray `o + t d` differs from f64's:
/// whether the two f64 hits lie further apart than the rows' error (the
/// difference is then beyond what the stored rows explain), and a line that
/// shows both hits in both types.
fn diagnosis(s64: &Scene64, on: &Scene<I16F16>, (o, d): (Vec3<I16F16>, Vec3<I16F16>), df: [f64; 3]) -> (bool, String) {
    let of = o.to_array().map(|x| x.to_f64());
    let h64 = [0, 1].map(|i| s64.objects[i].hit(of, df, 1e-3, f64::INFINITY));
    let t64 = h64.map(|h| h.map(|h| h.t));
    // Closer than the rows hold either hit: not decidable here.
    let (gap, bound) = match h64 {
        [Some(x), Some(y)] => (
            (x.t - y.t).abs(),
            t_error(&s64.objects[0], of, df, &x) + t_error(&s64.objects[1], of, df, &y),
        ),
        _ => (f64::INFINITY, 0.0),
    };
    let tq = [0, 1].map(|i| {
        let obj = &on.objects()[i];
        obj.intersect(o, d, I16F16::HIT_EPSILON, I16F16::MAX).map(|h| {
            let e = obj.exact_t_along(&h, o, d);
            (h.t.to_f64(), e.map(|e| e as f64 / (1u64 << 30) as f64))
        })
    });
    (
        gap >= bound,
        format!("f64 {t64:?} ({gap:.1e} apart, rows' error {bound:.1e}), Q16.16 (t, exact t) {tq:?}"),
    )
}

/// Rays, and Q16.16's nearest object unlike f64's with the exact order and
/// on the rounded t alone, over `cases` random pairs: the origin stepped one Q16.16 step at
/// a time across the place where f64's nearest object flips between the two
/// (both hit, their f64 t within 1e-3 there: a crossing, not a
/// silhouette), 3 steps either side.
fn disagreements(cases: usize) -> (usize, usize, usize, usize, Vec<String>) {
    let mut r = rng(0x5DEE_CE66_D1CE_4E5B);
    let (mut rays, mut wrong_on, mut wrong_off, mut beyond) = (0, 0, 0, 0);
    let mut cases_wrong = Vec::new();
    for case in 0..cases {
        let Some((a, b, text, p)) = pair_through_a_point(&mut r) else {
            continue;
        };
        let s64 = Scene64::parse(&text);
        let on = Scene::<I16F16>::parse(&text).expect("parse");
        // An origin 20 to 120 away, the direction at p, rounded.
        let ray = SteppedRay::new(p, &mut r);
        let (d, df) = (ray.d, ray.df);
        let origin = |k: i64| ray.origin(k);
        let nearest64 = |k: i64| s64.closest(origin(k).map(|x| x.to_f64()), df, 1e-3).map(|h| h.0);
        let Some((lo, hi)) = flip(nearest64) else {
            continue;
        };
        // A crossing: both objects met there, at nearly one t.
        let o = origin(lo).map(|x| x.to_f64());
        let (h0, h1) = (
            s64.objects[0].hit(o, df, 1e-3, f64::INFINITY),
            s64.objects[1].hit(o, df, 1e-3, f64::INFINITY),
        );
        match (h0, h1) {
            (Some(x), Some(y)) if (x.t - y.t).abs() < 1e-3 => {}
            _ => continue,
        }
        for k in lo - 3..=hi + 3 {
            let o = Vec3::from_array(origin(k));
            let truth = nearest64(k);
            let q_on = on.closest_hit(o, d, I16F16::HIT_EPSILON).map(|h| h.0);
            let q_off = nearest_on_rounded_t(&on, o, d);
            rays += 1;
            wrong_off += usize::from(q_off != truth);
            if q_on != truth {
                wrong_on += 1;
                let (far_apart, line) = diagnosis(&s64, &on, (o, d), df);
                beyond += usize::from(far_apart);
                cases_wrong.push(format!("case {case}: {a:?} and {b:?}, step {k} of {lo}..{hi}: {line}"));
            }
        }
    }
    (rays, wrong_on, wrong_off, beyond, cases_wrong)
}

/// Measured on these 2,000 pairs (5,536 rays a Q16.16 step or a few from
/// a crossing): on the rounded t alone 1,435 went the other way than f64; with the exact order 2, their two f64
/// hits 1e-10 and 7e-9 apart, within what the object's stored rows (30
/// significant bits an entry) hold the exact point to (3e-8 and 1e-7 at 75
/// to 110 world units from the origin). The test asserts that every ray
/// unlike f64 is one of those, and at most one ray in 1,000.
#[test]
fn two_surfaces_at_one_depth_are_ordered_as_f64_orders_them() {
    let (rays, on, off, beyond, cases) = disagreements(2000);
    println!(
        "{rays} rays: {on} unlike f64 with the exact order ({beyond} beyond the rows' error), {off} on the rounded t"
    );
    for c in &cases {
        println!("{c}");
    }
    assert!(rays > 5000, "{rays} rays");
    assert!(
        off * 10 > rays,
        "the rounded order went wrong on {off} of {rays}: the test tests nothing"
    );
    assert_eq!(
        beyond, 0,
        "{beyond} of {rays} unlike f64 farther apart than the rows' error"
    );
    assert!(on * 1000 <= rays, "{on} of {rays} unlike f64 with the exact order");
}
