//! The five analytic shapes, intersected in object space.
//!
//! Bounded shapes (sphere, cube, cylinder, cone) are intersected by a ray whose
//! direction is a unit vector and whose origin lies within a few units of the
//! object's centre: the caller re-origins the ray at its object's bounding
//! sphere first (see `Object::intersect` in `crate::scene`). Every square and
//! product then stays small, which is what keeps Q16.16 accurate and in range.
//! The plane is unbounded and takes any origin. Every shape's `t` is a
//! distance along the unit direction.

use crate::geometry::vec3::Vec3;
use crate::number::{Scalar, HIGH_CAP, LOW_CAP, SIDE};

/// A shape of the scene format, in its object space.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Shape {
    /// x² + y² + z² = 1.
    Sphere,
    /// z = 0, unbounded, normal +z.
    Plane,
    /// The box [-1, 1]³.
    Cube,
    /// x² + z² = 1 for -1 <= y <= 1, closed by two caps.
    Cylinder,
    /// Apex (0, 1, 0), base of radius 1 at y = -1, closed by the base.
    Cone,
}

/// Where a ray meets a shape, in object space.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct LocalHit<S> {
    /// Ray parameter of the hit (in units of the ray's direction).
    pub t: S,
    /// The hit point, put exactly on the face it hit where the face is flat.
    pub p: Vec3<S>,
    /// Outward surface normal (not necessarily unit length).
    pub n: Vec3<S>,
}

impl Shape {
    /// Every shape by its scene-file name.
    pub const ALL: [(&'static str, Shape); 5] = [
        ("sphere", Shape::Sphere),
        ("plane", Shape::Plane),
        ("cube", Shape::Cube),
        ("cylinder", Shape::Cylinder),
        ("cone", Shape::Cone),
    ];

    /// The shape's scene-file name.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Sphere => "sphere",
            Shape::Plane => "plane",
            Shape::Cube => "cube",
            Shape::Cylinder => "cylinder",
            Shape::Cone => "cone",
        }
    }

    /// Radius of the smallest origin-centred ball holding the shape
    /// (`None` for the unbounded plane).
    pub fn bound_radius(self) -> Option<f64> {
        match self {
            Shape::Sphere => Some(1.0),
            Shape::Plane => None,
            Shape::Cube => Some(1.732_050_807_568_877_2),
            Shape::Cylinder | Shape::Cone => Some(core::f64::consts::SQRT_2),
        }
    }

    /// The nearest hit with `t_min < t < t_max` of the ray `o + t d`.
    ///
    /// For bounded shapes `d` must be a unit vector and `o` near the shape (see
    /// the module docs); the plane takes any `o`.
    pub fn intersect<S: Scalar>(self, o: Vec3<S>, d: Vec3<S>, t_min: S, t_max: S) -> Option<LocalHit<S>> {
        match self {
            Shape::Plane => plane(o, d, t_min, t_max),
            _ => self.intersect_bounded(o, d, t_min, t_max, &mut false, None),
        }
    }

    /// [`Shape::intersect`] for the bounded shapes, `None` for the plane: what
    /// an object past its bounding sphere calls (it meets planes through their
    /// world rows), so the renderer carries no second way into the plane.
    /// Sets `close` where a decision (a rim, an edge, a side's end, a cap's
    /// rim, a tangent) fell within [`close_band`] of its boundary: Q16.16's
    /// object-space ray may be on the wrong side there (`Kernels::RECHECK`).
    /// `exact`, where given, decides whether the shape is met and the cube's
    /// entry face or the cylinder's and cone's entry part (from the exact
    /// ray: `Kernels::exact_point`); a grazing ray then takes the tangent
    /// point, that face's slab time or that part's hit.
    pub(crate) fn intersect_bounded<S: Scalar>(
        self,
        o: Vec3<S>,
        d: Vec3<S>,
        t_min: S,
        t_max: S,
        close: &mut bool,
        exact: Option<(bool, u8)>,
    ) -> Option<LocalHit<S>> {
        match self {
            Shape::Sphere => sphere(o, d, t_min, t_max, close, exact.map(|e| e.0)),
            Shape::Plane => None,
            Shape::Cube => cube(o, d, t_min, t_max, close, exact),
            Shape::Cylinder => cylinder(o, d, t_min, t_max, close, exact),
            Shape::Cone => cone(o, d, t_min, t_max, close, exact),
        }
    }
}

/// The nearer of two candidate hits.
fn nearer<S: Scalar>(a: Option<LocalHit<S>>, b: Option<LocalHit<S>>) -> Option<LocalHit<S>> {
    match (a, b) {
        (Some(x), Some(y)) => Some(if y.t < x.t { y } else { x }),
        (x, None) => x,
        (None, y) => y,
    }
}

/// 2⁻⁹ object units: well above the error of Q16.16's object-space ray
/// (2⁻¹⁷ a component, from the origin and from the direction over the
/// shape's width), so a decision closer than this to its boundary is
/// decided again from the exact ray (`Object::intersect_dir`).
#[inline(always)]
fn close_band<S: Scalar>() -> S {
    S::from_q15(64)
}

/// `t_min < t < t_max`.
#[inline]
fn inside<S: Scalar>(t: S, t_min: S, t_max: S) -> bool {
    t > t_min && t < t_max
}

fn sphere<S: Scalar>(
    o: Vec3<S>,
    d: Vec3<S>,
    t_min: S,
    t_max: S,
    close: &mut bool,
    rim: Option<bool>,
) -> Option<LocalHit<S>> {
    // Closest approach along the (unit) ray, and the perpendicular offset there.
    let tc = o.dot(d).neg();
    let perp = o + d * tc;
    // Discriminant from the perpendicular distance (not b² − 4ac): small terms.
    let h2 = S::ONE.sub(perp.dot(perp));
    // 1 − |perp|² moves by twice the offset's error: near the rim.
    *close |= h2.abs() < close_band::<S>().add(close_band());
    let h2 = match rim {
        Some(false) => return None,
        Some(true) => h2.max(S::ZERO),
        None if h2 < S::ZERO => return None,
        None => h2,
    };
    let h = h2.sqrt();
    let t = [tc.sub(h), tc.add(h)].into_iter().find(|&t| inside(t, t_min, t_max))?;
    let p = o + d * t;
    Some(LocalHit { t, p, n: p })
}

/// The plane z = 0 through the number type's one plane intersection
/// (`Kernels::plane_hit`, which rendering reaches through the object's rows),
/// here with identity rows.
fn plane<S: Scalar>(o: Vec3<S>, d: Vec3<S>, t_min: S, t_max: S) -> Option<LocalHit<S>> {
    let rows = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]].map(S::row_from_f64);
    let (t, x, y) = S::plane_hit(
        &rows,
        o.to_array(),
        S::dir_from(d.to_array()),
        t_min,
        t_max,
        (S::ZERO, S::ZERO),
        None,
        (2, 0),
    )?;
    Some(LocalHit {
        t,
        p: Vec3::new(x, y, S::ZERO),
        n: Vec3::new(S::ZERO, S::ZERO, S::ONE),
    })
}

fn cube<S: Scalar>(
    o: Vec3<S>,
    d: Vec3<S>,
    t_min: S,
    t_max: S,
    close: &mut bool,
    exact: Option<(bool, u8)>,
) -> Option<LocalHit<S>> {
    let (o, d) = (o.to_array(), d.to_array());
    let (mut t_near, mut t_far) = (S::MAX.neg(), S::MAX);
    let (mut near_axis, mut far_axis) = (0usize, 0usize);
    for i in 0..3 {
        // Slab i: the ray is between the faces x_i = ±1 for t in [t1, t2].
        let inv = S::ONE.div(d[i]);
        let ta = S::ONE.neg().sub(o[i]).mul(inv);
        let tb = S::ONE.sub(o[i]).mul(inv);
        let (t1, t2) = if ta < tb { (ta, tb) } else { (tb, ta) };
        if t1 > t_near {
            t_near = t1;
            near_axis = i;
        }
        if t2 < t_far {
            t_far = t2;
            far_axis = i;
        }
    }
    match exact {
        Some((false, _)) => return None,
        // The exact entry face (at an edge both faces' times agree within
        // the band; the far end no earlier).
        Some((true, k)) => {
            near_axis = k as usize;
            t_far = t_far.max(t_near);
        }
        None => {}
    }
    if t_near > t_far {
        // Passing just beyond an edge or a corner.
        *close |= t_near.sub(t_far) < close_band();
        return None;
    }
    // Entering face if it is ahead, else the exit face (ray from inside).
    let (t, axis, entering) = if inside(t_near, t_min, t_max) {
        (t_near, near_axis, true)
    } else if inside(t_far, t_min, t_max) {
        (t_far, far_axis, false)
    } else {
        return None;
    };
    // Always 0..=2 (k from `Kernels::exact_point` too): keeps bounds checks and their panic path out.
    let axis = axis.min(2);
    let outward = (d[axis] < S::ZERO) == entering;
    let mut p = [o[0].add(d[0].mul(t)), o[1].add(d[1].mul(t)), o[2].add(d[2].mul(t))];
    // Near an edge: which face (or whether the cube at all) is in doubt.
    let edge = S::ONE.sub(close_band());
    *close |= (0..3).any(|i| i != axis && p[i].abs() > edge);
    let sign = if outward { S::ONE } else { S::ONE.neg() };
    // Put the point exactly on its face: the face lies on a checker boundary.
    p[axis] = sign;
    let mut n = [S::ZERO; 3];
    n[axis] = sign;
    Some(LocalHit {
        t,
        p: Vec3::from_array(p),
        n: Vec3::from_array(n),
    })
}

/// Whether a cube's meeting or missing the ray `o + t d` (`d` a unit
/// vector) is in doubt where a face is crossed slowly: the entry and exit
/// slab times within the band over the slower of their two slopes. A slab
/// time carries the rounded ray's error over its slope (`d`'s component),
/// which [`cube`]'s flag in object units does not scale with (a shadow ray
/// at a slope of 5e-3 to a face: 5e-3 of t). Cold: a shadow ray's retakes
/// only (`Object::blocks`), never on the micro:bit.
#[cold]
#[inline(never)]
pub(crate) fn cube_crossed_slowly<S: Scalar>(o: Vec3<S>, d: Vec3<S>) -> bool {
    let (o, d) = (o.to_array(), d.to_array());
    let (mut near, mut far) = ((S::MAX.neg(), S::ONE), (S::MAX, S::ONE));
    for i in 0..3 {
        let inv = S::ONE.div(d[i]);
        let ta = S::ONE.neg().sub(o[i]).mul(inv);
        let tb = S::ONE.sub(o[i]).mul(inv);
        let (t1, t2) = if ta < tb { (ta, tb) } else { (tb, ta) };
        if t1 > near.0 {
            near = (t1, d[i].abs());
        }
        if t2 < far.0 {
            far = (t2, d[i].abs());
        }
    }
    // The gap's error is the object-space error over each slope: at most twice it over the slower.
    near.0.sub(far.0).abs().mul(near.1.min(far.1)) < close_band()
}

/// Hit on the cap `y = y_cap` (±1, `code` its `LOW_CAP` or `HIGH_CAP`) of
/// radius 1, if any. With the exact entry `part`: that cap is met whatever
/// its rounded radius; the side entered, the cap facing the ray is not.
#[allow(clippy::too_many_arguments)]
fn cap<S: Scalar>(
    o: Vec3<S>,
    d: Vec3<S>,
    (y_cap, code): (S, u8),
    t_min: S,
    t_max: S,
    close: &mut bool,
    part: Option<u8>,
) -> Option<LocalHit<S>> {
    let facing = (d.y > S::ZERO) == (code == LOW_CAP);
    if d.y == S::ZERO || (part == Some(SIDE) && facing) {
        return None;
    }
    let t = y_cap.sub(o.y).div(d.y);
    if !inside(t, t_min, t_max) {
        return None;
    }
    let (x, z) = (o.x.add(d.x.mul(t)), o.z.add(d.z.mul(t)));
    let r2 = x.mul(x).add(z.mul(z));
    *close |= r2.sub(S::ONE).abs() < close_band::<S>().add(close_band());
    if r2 > S::ONE && part != Some(code) {
        return None;
    }
    Some(LocalHit {
        t,
        p: Vec3::new(x, y_cap, z),
        n: Vec3::new(S::ZERO, y_cap, S::ZERO),
    })
}

/// Roots of `a t² + 2 b t + c = 0` in increasing order (`a != 0` assumed
/// non-negligible by the caller), or `None` for no real root.
fn roots<S: Scalar>(a: S, b: S, c: S) -> Option<(S, S)> {
    let disc = b.mul(b).sub(a.mul(c));
    if disc < S::ZERO {
        return None;
    }
    let h = disc.sqrt();
    let (r1, r2) = (b.neg().sub(h).div(a), b.neg().add(h).div(a));
    Some(if r1 < r2 { (r1, r2) } else { (r2, r1) })
}

/// A root of the side surface, if its point lies within `-1 <= y <= 1`.
/// With the exact entry `part`: the side entered, a root up to the band
/// beyond an end counts (put on it); a cap entered, a root within the band
/// of that cap's end does not.
#[allow(clippy::too_many_arguments)]
fn side_hit<S: Scalar>(
    o: Vec3<S>,
    d: Vec3<S>,
    t: S,
    t_min: S,
    t_max: S,
    close: &mut bool,
    normal: impl Fn(Vec3<S>) -> Vec3<S>,
    part: Option<u8>,
) -> Option<LocalHit<S>> {
    if !inside(t, t_min, t_max) {
        return None;
    }
    let mut p = o + d * t;
    // At a side's end (a cylinder's rim, a cone's apex or base rim).
    let end = S::ONE.sub(p.y.abs()).abs() < close_band();
    *close |= end;
    let high = p.y > S::ZERO;
    let limit = if part == Some(SIDE) && end {
        S::ONE.add(close_band())
    } else {
        S::ONE
    };
    if p.y < limit.neg() || p.y > limit || (end && part == Some(if high { HIGH_CAP } else { LOW_CAP })) {
        return None;
    }
    p.y = p.y.max(S::ONE.neg()).min(S::ONE);
    Some(LocalHit { t, p, n: normal(p) })
}

/// `|a|` below about 2⁻¹²: treated as zero for a quadratic's leading term.
fn negligible<S: Scalar>(a: S) -> bool {
    a.abs() < S::HIT_EPSILON.mul(S::from_q15(2048))
}

/// The side's roots, or where the exact `part` is the side and the rounded
/// roots miss it (a grazing line), its tangent point `−b / a`.
fn tangent<S: Scalar>(side: Option<(S, S)>, part: Option<u8>, a: S, b: S) -> Option<(S, S)> {
    match side {
        None if part == Some(SIDE) && a > S::ZERO => {
            let t = b.neg().div(a);
            Some((t, t))
        }
        side => side,
    }
}

/// The exact re-decision's part, if one was taken; `None` where it says the
/// line misses the shape.
fn exact_part(exact: Option<(bool, u8)>) -> Option<Option<u8>> {
    match exact {
        Some((false, _)) => None,
        e => Some(e.map(|e| e.1)),
    }
}

fn cylinder<S: Scalar>(
    o: Vec3<S>,
    d: Vec3<S>,
    t_min: S,
    t_max: S,
    close: &mut bool,
    exact: Option<(bool, u8)>,
) -> Option<LocalHit<S>> {
    let part = exact_part(exact)?;
    // Side: (ox + t dx)² + (oz + t dz)² = 1.
    let a = d.x.mul(d.x).add(d.z.mul(d.z));
    let b = o.x.mul(d.x).add(o.z.mul(d.z));
    let c = o.x.mul(o.x).add(o.z.mul(o.z)).sub(S::ONE);
    let normal = |p: Vec3<S>| Vec3::new(p.x, S::ZERO, p.z);
    let mut best = None;
    // Q16.16's exact roots where it has them; else the quadratic in S.
    let side = S::side_roots(o.to_array(), d.to_array(), false, close).unwrap_or_else(|| {
        if negligible(a) {
            None
        } else {
            roots(a, b, c)
        }
    });
    if let Some((t0, t1)) = tangent(side, part, a, b) {
        best = side_hit(o, d, t0, t_min, t_max, close, normal, part)
            .or_else(|| side_hit(o, d, t1, t_min, t_max, close, normal, part));
    }
    best = nearer(best, cap(o, d, (S::ONE, HIGH_CAP), t_min, t_max, close, part));
    nearer(best, cap(o, d, (S::ONE.neg(), LOW_CAP), t_min, t_max, close, part))
}

fn cone<S: Scalar>(
    o: Vec3<S>,
    d: Vec3<S>,
    t_min: S,
    t_max: S,
    close: &mut bool,
    exact: Option<(bool, u8)>,
) -> Option<LocalHit<S>> {
    let part = exact_part(exact)?;
    // Side: x² + z² = ((1 - y) / 2)², with w = 1 - y falling by dy per unit t.
    let quarter = S::from_q15(8192);
    let w0 = S::ONE.sub(o.y);
    let a = d.x.mul(d.x).add(d.z.mul(d.z)).sub(quarter.mul(d.y.mul(d.y)));
    let b = o.x.mul(d.x).add(o.z.mul(d.z)).add(quarter.mul(w0.mul(d.y)));
    let c = o.x.mul(o.x).add(o.z.mul(o.z)).sub(quarter.mul(w0.mul(w0)));
    // Gradient of x² + z² − (1 − y)²/4, halved; straight up at the apex.
    let normal = |p: Vec3<S>| {
        let n = Vec3::new(p.x, quarter.mul(S::ONE.sub(p.y)), p.z);
        if n == Vec3::ZERO {
            Vec3::new(S::ZERO, S::ONE, S::ZERO)
        } else {
            n
        }
    };
    let mut best = None;
    if let Some(side) = S::side_roots(o.to_array(), d.to_array(), true, close) {
        // Q16.16: exact coefficients and stable roots (a near-apex hit moved by 1 % of the size).
        if let Some((t0, t1)) = tangent(side, part, a, b) {
            best = nearer(
                side_hit(o, d, t0, t_min, t_max, close, normal, part),
                side_hit(o, d, t1, t_min, t_max, close, normal, part),
            );
        }
    } else if negligible(a) {
        // Ray parallel to a line of the cone: one root, −c / 2b.
        if b != S::ZERO {
            let t = c.neg().div(b.add(b));
            best = side_hit(o, d, t, t_min, t_max, close, normal, part);
        }
    } else if let Some((t0, t1)) = roots(a, b, c) {
        // The lower root may lie on the upper nappe (y > 1): side_hit rejects it.
        best = nearer(
            side_hit(o, d, t0, t_min, t_max, close, normal, part),
            side_hit(o, d, t1, t_min, t_max, close, normal, part),
        );
    }
    nearer(best, cap(o, d, (S::ONE.neg(), LOW_CAP), t_min, t_max, close, part))
}

impl crate::bytes::Field for Shape {
    fn put(&self, w: &mut crate::bytes::Writer<'_>) {
        let tag: u8 = match self {
            Shape::Sphere => 0,
            Shape::Plane => 1,
            Shape::Cube => 2,
            Shape::Cylinder => 3,
            Shape::Cone => 4,
        };
        tag.put(w);
    }
    #[inline]
    fn take(&mut self, r: &mut crate::bytes::Reader<'_>) {
        *self = match r.le(1) {
            0 => Shape::Sphere,
            1 => Shape::Plane,
            2 => Shape::Cube,
            3 => Shape::Cylinder,
            4 => Shape::Cone,
            _ => {
                r.out_of_range("unknown shape");
                Shape::Sphere
            }
        };
    }
    fn blank() -> Self {
        Shape::Sphere
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixed::types::I16F16;

    fn v<S: Scalar>(x: f64, y: f64, z: f64) -> Vec3<S> {
        Vec3::from_f64([x, y, z])
    }

    /// Runs a ray in both number types and returns (t, p, n) as f64.
    fn hit_both(shape: Shape, o: [f64; 3], d: [f64; 3]) -> Option<(f64, [f64; 3], [f64; 3])> {
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let d = d.map(|x| x / len);
        let hf = shape.intersect::<f32>(
            v(o[0], o[1], o[2]),
            v(d[0], d[1], d[2]),
            <f32 as Scalar>::HIT_EPSILON,
            f32::MAX,
        );
        let hx = shape.intersect::<I16F16>(
            v(o[0], o[1], o[2]),
            v(d[0], d[1], d[2]),
            I16F16::HIT_EPSILON,
            I16F16::MAX,
        );
        assert_eq!(
            hf.is_some(),
            hx.is_some(),
            "{shape:?} from {o:?} along {d:?}: f32 and Q16.16 disagree"
        );
        let (hf, hx) = (hf?, hx?);
        assert!((hf.t.to_f64() - hx.t.to_f64()).abs() < 1e-3, "t {hf:?} vs {hx:?}");
        for (a, b) in hf.p.to_f64().iter().zip(hx.p.to_f64()) {
            assert!((a - b).abs() < 1e-3, "p {hf:?} vs {hx:?}");
        }
        Some((hf.t.to_f64(), hf.p.to_f64(), hf.n.to_f64()))
    }

    fn unit(n: [f64; 3]) -> [f64; 3] {
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        n.map(|x| x / l)
    }

    fn near(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < tol)
    }

    #[test]
    fn sphere_head_on_from_outside_and_inside() {
        let (t, p, n) = hit_both(Shape::Sphere, [0.0, 0.0, 3.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - 2.0).abs() < 1e-4);
        assert!(near(p, [0.0, 0.0, 1.0], 1e-4));
        assert!(near(unit(n), [0.0, 0.0, 1.0], 1e-4));
        // From the centre: the far side, at distance 1.
        let (t, p, _) = hit_both(Shape::Sphere, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert!((t - 1.0).abs() < 1e-4 && near(p, [1.0, 0.0, 0.0], 1e-4));
        // Pointing away: no hit.
        assert!(hit_both(Shape::Sphere, [0.0, 0.0, 3.0], [0.0, 0.0, 1.0]).is_none());
    }

    #[test]
    fn sphere_grazing_and_missing() {
        // Passing 0.999 from the centre hits; 1.001 misses.
        assert!(hit_both(Shape::Sphere, [0.999, 0.0, 2.0], [0.0, 0.0, -1.0]).is_some());
        assert!(hit_both(Shape::Sphere, [1.001, 0.0, 2.0], [0.0, 0.0, -1.0]).is_none());
    }

    #[test]
    fn plane_hits_from_both_sides_and_misses_parallel() {
        let (t, p, n) = hit_both(Shape::Plane, [0.5, 0.25, 2.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - 2.0).abs() < 1e-4 && p[2] == 0.0 && n == [0.0, 0.0, 1.0]);
        let (t, _, _) = hit_both(Shape::Plane, [0.0, 0.0, -4.0], [0.0, 0.0, 2.0]).unwrap();
        assert!((t - 4.0).abs() < 1e-4, "t is a distance along the unit direction");
        assert!(hit_both(Shape::Plane, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]).is_none());
        // Grazing: almost parallel (values exact in Q16.16), still hits on z = 0.
        let (t, p, _) = hit_both(Shape::Plane, [0.0, 0.0, 1.0 / 128.0], [1.0, 0.0, -1.0 / 1024.0]).unwrap();
        assert!((t - 8.0).abs() < 1e-3 && p[2] == 0.0);
    }

    #[test]
    fn cube_faces_edges_and_inside() {
        let (t, p, n) = hit_both(Shape::Cube, [0.2, 0.3, 3.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - 2.0).abs() < 1e-4);
        assert_eq!(p[2], 1.0, "snapped onto the face");
        assert_eq!(n, [0.0, 0.0, 1.0]);
        let (_, p, n) = hit_both(Shape::Cube, [-3.0, 0.1, 0.1], [1.0, 0.0, 0.0]).unwrap();
        assert_eq!((p[0], n), (-1.0, [-1.0, 0.0, 0.0]));
        // From inside: the exit face, outward normal.
        let (t, p, n) = hit_both(Shape::Cube, [0.0, 0.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        assert!((t - 1.0).abs() < 1e-4 && p[1] == -1.0 && n == [0.0, -1.0, 0.0]);
        // Diagonal towards a corner, and a miss just past an edge.
        assert!(hit_both(Shape::Cube, [2.0, 2.0, 2.0], [-1.0, -1.0, -1.0]).is_some());
        assert!(hit_both(Shape::Cube, [1.01, 0.0, 3.0], [0.0, 0.0, -1.0]).is_none());
    }

    #[test]
    fn cylinder_side_caps_and_inside() {
        let (t, p, n) = hit_both(Shape::Cylinder, [0.0, 0.5, 3.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - 2.0).abs() < 1e-4 && near(p, [0.0, 0.5, 1.0], 1e-4));
        assert!(near(unit(n), [0.0, 0.0, 1.0], 1e-4));
        let (t, p, n) = hit_both(Shape::Cylinder, [0.3, 3.0, 0.2], [0.0, -1.0, 0.0]).unwrap();
        assert!((t - 2.0).abs() < 1e-4 && p[1] == 1.0 && n == [0.0, 1.0, 0.0]);
        // Above the top, the side's infinite extension must not count.
        assert!(hit_both(Shape::Cylinder, [0.0, 1.5, 3.0], [0.0, 0.0, -1.0]).is_none());
        // From inside, downwards: the bottom cap.
        let (t, p, _) = hit_both(Shape::Cylinder, [0.0, 0.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        assert!((t - 1.0).abs() < 1e-4 && p[1] == -1.0);
        // Grazing the side.
        assert!(hit_both(Shape::Cylinder, [0.999, 0.0, 3.0], [0.0, 0.0, -1.0]).is_some());
        assert!(hit_both(Shape::Cylinder, [1.001, 0.0, 3.0], [0.0, 0.0, -1.0]).is_none());
    }

    #[test]
    fn cone_side_base_apex_and_inside() {
        // At y = 0 the radius is 1/2.
        let (t, p, n) = hit_both(Shape::Cone, [0.0, 0.0, 3.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - 2.5).abs() < 1e-4 && near(p, [0.0, 0.0, 0.5], 1e-4));
        // Outward normal tilts up by atan(1/2).
        assert!(near(unit(n), unit([0.0, 0.25, 0.5]), 1e-3), "{n:?}");
        // Base from below.
        let (_, p, n) = hit_both(Shape::Cone, [0.2, -3.0, 0.1], [0.0, 1.0, 0.0]).unwrap();
        assert!(p[1] == -1.0 && n == [0.0, -1.0, 0.0]);
        // Straight down onto the apex.
        let (t, _, _) = hit_both(Shape::Cone, [0.0, 3.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        assert!((t - 2.0).abs() < 1e-3);
        // At y = 0.5 the radius is 1/4: 0.3 off the axis misses the cone, and
        // the mirror nappe above the apex never counts.
        assert!(hit_both(Shape::Cone, [0.3, 0.5, 3.0], [0.0, 0.0, -1.0]).is_none());
        assert!(hit_both(Shape::Cone, [0.0, 1.5, 3.0], [0.0, 0.0, -1.0]).is_none());
        // From inside, sideways.
        let (t, _, _) = hit_both(Shape::Cone, [0.0, -0.5, 0.0], [1.0, 0.0, 0.0]).unwrap();
        assert!((t - 0.75).abs() < 1e-3);
        // Parallel to a generator line (a = 0): one root.
        let d = [0.0, -2.0, 1.0];
        assert!(hit_both(Shape::Cone, [0.0, 1.2, -0.5], d).is_some());
    }
}
