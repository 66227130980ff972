//! Every shape driven at the edge of what the parser accepts: objects 2000
//! units across whose far side reaches 32000, rays starting up to 32500 from
//! the origin and 2500 from the object. Hits must agree with the exact (f64)
//! value in both number types: the re-origining at the bounding sphere and
//! the 30-bit matrix rows are what keep Q16.16 in range and accurate here.

use crate::{Scalar, Scene, Vec3, I16F16};

/// Object size (uniform scale), its centre, and the ray's start distance.
const S: f64 = 2000.0;
const C: [f64; 3] = [30000.0, -30000.0, 30000.0];
const D: f64 = 2500.0;

/// The nearest hit of one ray on a one-object scene: (t, hit point in world).
fn hit<Sc: Scalar>(text: &str, o: [f64; 3], d: [f64; 3]) -> Option<(f64, [f64; 3])> {
    let scene = Scene::<Sc>::parse(text).unwrap_or_else(|e| panic!("{e}"));
    let (o, d) = (Vec3::<Sc>::from_f64(o), Vec3::<Sc>::from_f64(d));
    let (_, h) = scene.closest_hit(o, d, Sc::HIT_EPSILON)?;
    let p = (o + d * h.t).to_f64();
    Some((h.t.to_f64(), p))
}

/// Asserts both number types find the hit at `t_exact(d)` (to 1e-4 of the
/// size: 0.2 units here), from `C + offset` along `d`. `t_exact` gets the
/// direction as the number type holds it: a Q16.16 unit vector is within 2^-17
/// of the exact one per component, which at 20000 units along a slanted ray
/// moves the hit by a unit; what is tested here is the intersection itself.
fn check(shape: &str, offset: [f64; 3], d: [f64; 3], t_exact: impl Fn([f64; 3]) -> f64) {
    let text = format!(
        "object {shape}\nscale {S} {S} {S}\ntranslate {} {} {}\n",
        C[0], C[1], C[2]
    );
    let o = [C[0] + offset[0], C[1] + offset[1], C[2] + offset[2]];
    let tol = 1e-4 * S;
    let held = |name: &str| match name {
        "Q16.16" => Vec3::<I16F16>::from_f64(d).to_f64(),
        _ => Vec3::<f32>::from_f64(d).to_f64(),
    };
    for (name, got) in [("Q16.16", hit::<I16F16>(&text, o, d)), ("f32", hit::<f32>(&text, o, d))] {
        let (t, p) = got.unwrap_or_else(|| panic!("{shape} ({name}): no hit from {o:?} along {d:?}"));
        let d = held(name);
        let t_exact = t_exact(d);
        assert!((t - t_exact).abs() <= tol, "{shape} ({name}): t {t}, exact {t_exact}");
        for k in 0..3 {
            let want = o[k] + d[k] * t_exact;
            assert!(
                (p[k] - want).abs() <= tol,
                "{shape} ({name}): hit {p:?}, exact along the ray at {t_exact}"
            );
        }
    }
}

#[test]
fn sphere_at_the_edge_of_the_range() {
    // Along -z, half a radius off the axis: the surface at z = sqrt(3)/2 S.
    check("sphere", [S / 2.0, 0.0, D], [0.0, 0.0, -1.0], |_| {
        D - S * 3f64.sqrt() / 2.0
    });
    // Diagonally from the far corner towards the centre: t = D sqrt 3 - S for
    // the exact direction; for the held one, the nearer root of |o + t d| = S.
    let k = 1.0 / 3f64.sqrt();
    check("sphere", [-D, D, -D], [k, -k, k], |d| {
        let o = [-D, D, -D];
        let (a, b, c) = (
            d.iter().map(|x| x * x).sum::<f64>(),
            (0..3).map(|i| o[i] * d[i]).sum::<f64>(),
            o.iter().map(|x| x * x).sum::<f64>() - S * S,
        );
        (-b - (b * b - a * c).sqrt()) / a
    });
}

#[test]
fn plane_at_the_edge_of_the_range() {
    // The plane z = C_z (scale does not move it), from 2500 above, and from a
    // slant of 1 in 8 whose hit lies 20000 units along the ray.
    check("plane", [S / 3.0, -S / 7.0, D], [0.0, 0.0, -1.0], |_| D);
    let (a, b) = (1.0f64, 8.0f64);
    let l = (a * a + b * b).sqrt();
    check("plane", [-18000.0, 0.0, D], [b / l, 0.0, -a / l], |d| -D / d[2]);
}

#[test]
fn cube_at_the_edge_of_the_range() {
    check("cube", [S / 2.0, S / 3.0, D], [0.0, 0.0, -1.0], |_| D - S);
    check("cube", [-D, -S / 4.0, S / 5.0], [1.0, 0.0, 0.0], |_| D - S);
}

#[test]
fn cylinder_at_the_edge_of_the_range() {
    // The side, a third of a radius off the axis, and the top cap.
    check("cylinder", [D, S / 2.0, S / 3.0], [-1.0, 0.0, 0.0], |_| {
        D - S * (8.0f64 / 9.0).sqrt()
    });
    check("cylinder", [S / 4.0, D, -S / 5.0], [0.0, -1.0, 0.0], |_| D - S);
}

#[test]
fn cone_at_the_edge_of_the_range() {
    // Half-way up the radius is S / 2; the base from below.
    check("cone", [0.0, 0.0, D], [0.0, 0.0, -1.0], |_| D - S / 2.0);
    check("cone", [S / 3.0, -D, 0.0], [0.0, 1.0, 0.0], |_| D - S);
}

/// The parser's error for `text`, as displayed.
fn refusal(text: &str) -> String {
    match Scene::<I16F16>::parse(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_parser_refuses_what_q16_16_cannot_hold_and_names_the_line() {
    // A value beyond the range, on line 3.
    let e = refusal("width 10\nobject sphere\ntranslate 40000 0 0\n");
    assert_eq!(
        e,
        "line 3: translate 40000 must be below 32768 in magnitude (the range of Q16.16)"
    );
    assert!(refusal("lens_position 0 -32768 0\n").starts_with("line 1: lens_position -32768 must be below 32768"));
    // Values in range whose composition is not: named at the object's line.
    let beyond = "line 2: object: its transformations put it beyond the range of Q16.16 (coordinates below 32768)";
    assert_eq!(
        refusal("width 10\nobject cube\ntranslate 20000 0 0\ntranslate 20000 0 0\n"),
        beyond
    );
    // Centre in range, surface not: a sphere of radius 2000 centred at 31000.
    assert_eq!(
        refusal("width 10\nobject sphere\nscale 2000 2000 2000\ntranslate 31000 0 0\n"),
        beyond
    );
    // Squeezed so thin that the inverse needs entries beyond the range.
    assert_eq!(refusal("width 10\nobject cylinder\nscale 1 0.00001 1\n"), beyond);
    // Both ends of the range, each in it, but 40000 apart: a ray or light
    // vector between them cannot be held.
    let far = "lens_position -20000 0 0\nobject sphere\ntranslate 20000 0 0\n";
    assert_eq!(
        refusal(far),
        "line 2: object: part of it lies 32768 or more from the lens of line 1 along an axis, beyond the range of Q16.16"
    );
    let lit = "object cube\nscale 10 10 10\ntranslate 0 0 -30000\nlight_position 0 0 2760\n";
    assert_eq!(
        refusal(lit),
        "line 1: object: part of it lies 32768 or more from the light of line 4 along an axis, beyond the range of Q16.16"
    );
    assert!(refusal("object sphere\ntranslate 0 32000 0\nlens_position 0 -800 0\n").contains("from the lens of line 3"));
    assert!(
        Scene::<I16F16>::parse("object cube\nscale 10 10 10\ntranslate 0 0 -30000\nlight_position 0 0 2750\n").is_ok()
    );
    // The largest objects the range tests above use are accepted, and so is a
    // plane far out (it has no surface bound).
    let ok = format!(
        "object sphere\nscale {S} {S} {S}\ntranslate {} {} {}\n",
        C[0], C[1], C[2]
    );
    assert!(Scene::<I16F16>::parse(&ok).is_ok());
    assert!(Scene::<I16F16>::parse("object plane\ntranslate 0 0 -32000\n").is_ok());
}
