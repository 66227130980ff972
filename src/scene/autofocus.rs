//! Autofocus on an object (`focus_on`), computed exactly at set-up.
//!
//! A camera focuses on what it is pointed at: the ray from the lens centre E
//! towards the object's centre C (the image of its object-space origin) is cast
//! at the object alone, and the plane in focus is put through the first point
//! where it meets the surface, or through C where the ray misses (a ring
//! seen through its hole, say). The distance of that plane is the point's depth
//! along the viewing direction, the distance the thin-lens equation takes.
//!
//! Everything here is `f64` and runs once per scene, so the Q16.16 renderer
//! and the f32 reference get the very same focal length.

use crate::camera::CameraParams;
use crate::scene::shape::Shape;
use crate::scene::ObjectDesc;

/// Rays parameters below this (in units of |C − E|) are not hits: the lens
/// centre itself touching a surface does not focus at distance 0.
const T_MIN: f64 = 1e-9;

/// Where the ray from the lens centre towards the object's centre first meets
/// the object (world space), or the centre itself where it misses.
///
/// A camera standing at the centre looks along `look` instead.
pub fn focus_point(params: &CameraParams, desc: &ObjectDesc) -> [f64; 3] {
    let e = params.lens_position;
    let c = desc.to_world.apply([0.0; 3], true);
    let mut d = [c[0] - e[0], c[1] - e[1], c[2] - e[2]];
    if d.iter().all(|x| x.abs() < 1e-12) {
        d = params.look;
    }
    let Some(inv) = desc.to_world.inverse() else {
        return c;
    };
    let lo = inv.apply(e, true);
    let ld = inv.apply(d, false);
    match first_hit(desc.shape, lo, ld) {
        Some(t) => [e[0] + t * d[0], e[1] + t * d[1], e[2] + t * d[2]],
        None => c,
    }
}

/// Depth of a world point in front of the camera: its distance from the lens
/// along the unit viewing direction (negative behind the lens).
pub fn depth(params: &CameraParams, p: [f64; 3]) -> f64 {
    let l = params.look;
    let len = libm::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if len == 0.0 {
        return 0.0;
    }
    let e = params.lens_position;
    ((p[0] - e[0]) * l[0] + (p[1] - e[1]) * l[1] + (p[2] - e[2]) * l[2]) / len
}

/// The distance of the plane in focus for `focus_on` this object: the depth of
/// [`focus_point`]. Not positive when the object lies behind the lens.
pub fn focus_distance(params: &CameraParams, desc: &ObjectDesc) -> f64 {
    depth(params, focus_point(params, desc))
}

/// Smallest `t > T_MIN` where the object-space ray `o + t d` meets the shape.
fn first_hit(shape: Shape, o: [f64; 3], d: [f64; 3]) -> Option<f64> {
    let mut best: Option<f64> = None;
    let mut take = |t: f64, ok: bool| {
        if ok && t > T_MIN && t.is_finite() && best.is_none_or(|b| t < b) {
            best = Some(t);
        }
    };
    let at = |t: f64| [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
    // Where the ray crosses the plane `axis = value`, if it is not parallel.
    let cross = |axis: usize, value: f64| (d[axis] != 0.0).then(|| (value - o[axis]) / d[axis]);
    match shape {
        Shape::Sphere => {
            for t in quadratic(dot(d, d), 2.0 * dot(o, d), dot(o, o) - 1.0) {
                take(t, true);
            }
        }
        Shape::Plane => {
            if let Some(t) = cross(2, 0.0) {
                take(t, true);
            }
        }
        Shape::Cube => {
            for axis in 0..3 {
                for side in [-1.0, 1.0] {
                    if let Some(t) = cross(axis, side) {
                        let p = at(t);
                        let inside = (0..3).all(|k| k == axis || p[k].abs() <= 1.0);
                        take(t, inside);
                    }
                }
            }
        }
        Shape::Cylinder => {
            let (a, b, c) = (
                d[0] * d[0] + d[2] * d[2],
                2.0 * (o[0] * d[0] + o[2] * d[2]),
                o[0] * o[0] + o[2] * o[2] - 1.0,
            );
            for t in quadratic(a, b, c) {
                take(t, at(t)[1].abs() <= 1.0);
            }
            for side in [-1.0, 1.0] {
                if let Some(t) = cross(1, side) {
                    let p = at(t);
                    take(t, p[0] * p[0] + p[2] * p[2] <= 1.0);
                }
            }
        }
        Shape::Cone => {
            // x² + z² = ((1 − y) / 2)², for −1 <= y <= 1.
            let k = [o[0], (1.0 - o[1]) / 2.0, o[2]];
            let kd = [d[0], -d[1] / 2.0, d[2]];
            let a = kd[0] * kd[0] + kd[2] * kd[2] - kd[1] * kd[1];
            let b = 2.0 * (k[0] * kd[0] + k[2] * kd[2] - k[1] * kd[1]);
            let c = k[0] * k[0] + k[2] * k[2] - k[1] * k[1];
            for t in quadratic(a, b, c) {
                take(t, at(t)[1].abs() <= 1.0);
            }
            if let Some(t) = cross(1, -1.0) {
                let p = at(t);
                take(t, p[0] * p[0] + p[2] * p[2] <= 1.0);
            }
        }
    }
    best
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Real roots of `a t² + b t + c = 0` (NaN where there is none; NaN is no hit).
fn quadratic(a: f64, b: f64, c: f64) -> [f64; 2] {
    if a == 0.0 {
        return [if b != 0.0 { -c / b } else { f64::NAN }, f64::NAN];
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return [f64::NAN; 2];
    }
    // The numerically stable pair: no cancellation between b and the root.
    let q = -0.5 * (b + libm::copysign(libm::sqrt(disc), b));
    if q == 0.0 {
        return [0.0, f64::NAN];
    }
    [q / a, c / q]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::transform::Mat34;

    fn desc(shape: Shape, to_world: Mat34) -> ObjectDesc {
        ObjectDesc {
            shape,
            ka: [0.0; 3],
            kd: [0.0; 3],
            ks: [0.0; 3],
            shine: 1.0,
            texture: 0.0,
            to_world,
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn sphere_focuses_on_its_near_surface() {
        let cam = CameraParams::default();
        let m = Mat34::translate([0.0, 0.0, -8.0]);
        assert!(close(focus_distance(&cam, &desc(Shape::Sphere, m)), 7.0));
        // Twice as large: the surface comes a unit nearer.
        let m = Mat34::translate([0.0, 0.0, -8.0]).after(&Mat34::scale([2.0; 3]));
        assert!(close(focus_distance(&cam, &desc(Shape::Sphere, m)), 6.0));
    }

    #[test]
    fn off_axis_objects_use_the_depth_not_the_range() {
        // Sphere at (6, 0, −8): range 10, near surface at range 9, depth 9 · 0.8.
        let cam = CameraParams::default();
        let m = Mat34::translate([6.0, 0.0, -8.0]);
        let p = focus_point(&cam, &desc(Shape::Sphere, m));
        assert!(close(p[0], 5.4) && close(p[2], -7.2), "{p:?}");
        assert!(close(focus_distance(&cam, &desc(Shape::Sphere, m)), 7.2));
    }

    #[test]
    fn each_shape_is_met_where_expected() {
        let cam = CameraParams::default();
        let at = |shape, m: Mat34| focus_distance(&cam, &desc(shape, m));
        let t = Mat34::translate([0.0, 0.0, -10.0]);
        assert!(close(at(Shape::Cube, t), 9.0));
        assert!(close(at(Shape::Cylinder, t), 9.0), "side wall");
        assert!(close(at(Shape::Cone, t), 9.5), "halfway up the side, radius 1/2");
        // A cube turned 45° about y shows an edge at distance √2 from its centre.
        let m = t.after(&Mat34::rotate(1, 45.0));
        assert!((at(Shape::Cube, m) - (10.0 - core::f64::consts::SQRT_2)).abs() < 1e-9);
        // A cylinder seen along its axis: the cap.
        let m = t.after(&Mat34::rotate(0, 90.0));
        assert!(close(at(Shape::Cylinder, m), 9.0));
        // A cone seen from below (base towards the camera): the base.
        let m = t.after(&Mat34::rotate(0, -90.0));
        assert!(close(at(Shape::Cone, m), 9.0));
    }

    #[test]
    fn plane_and_miss_use_the_centre() {
        let cam = CameraParams::default();
        // Program 1's floor: tilted plane through (0, −3, 0); the ray towards
        // that point meets the plane there.
        let m = Mat34::translate([0.0, -3.0, 0.0]).after(&Mat34::rotate(0, -80.0));
        let p = focus_point(&cam, &desc(Shape::Plane, m));
        assert!(close(p[1], -3.0) && close(p[2], 0.0), "{p:?}");
        // A plane seen edge-on: the ray runs inside it and never crosses it, a miss.
        let m = Mat34::translate([0.0, 0.0, -5.0]).after(&Mat34::rotate(1, 90.0));
        assert!(close(focus_distance(&cam, &desc(Shape::Plane, m)), 5.0));
    }

    #[test]
    fn behind_the_camera_is_negative() {
        let cam = CameraParams::default();
        let m = Mat34::translate([0.0, 0.0, 8.0]);
        assert!(close(focus_distance(&cam, &desc(Shape::Sphere, m)), -7.0));
    }
}
