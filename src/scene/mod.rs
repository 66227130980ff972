//! A validated scene: camera parameters, objects and lights, ready to render.
//!
//! A [`Scene`] is built by the parser ([`Scene::parse`]) and holds everything in
//! the number type `S` the renderer will use, except the camera's parameters,
//! which stay exact (`f64`) until the image size is known (see
//! [`crate::camera::Camera::new`]).

pub use crate::camera::CameraParams;
use crate::geometry::transform::{Affine, Mat34};
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::scene::shape::{LocalHit, Shape};

pub mod autofocus;
pub mod shape;

/// Most objects a scene can hold (fixed capacity: no allocator).
pub const MAX_OBJECTS: usize = 16;
/// Most point lights a scene can hold.
pub const MAX_LIGHTS: usize = 8;

/// Reflectances and Phong exponent of a surface.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Material<S> {
    /// Ambient reflectance `Ka`.
    pub ka: Vec3<S>,
    /// Diffuse reflectance `Kd`.
    pub kd: Vec3<S>,
    /// Specular reflectance `Ks`.
    pub ks: Vec3<S>,
    /// Phong exponent `shine`.
    pub shine: S,
}

impl<S: crate::bytes::Field> crate::bytes::Field for Material<S> {
    crate::bytes::baked_fields!(Material { ka, kd, ks, shine });
}

/// A named material of the classic OpenGL table: Ka, Kd, Ks, shine (f64).
pub type NamedMaterial = (&'static str, [f64; 3], [f64; 3], [f64; 3], f64);

/// The named materials (`object sphere gold`); shine is 128 × the table's shininess.
pub const MATERIALS: [NamedMaterial; 12] = [
    (
        "gold",
        [0.24725, 0.1995, 0.0745],
        [0.75164, 0.60648, 0.22648],
        [0.628281, 0.555802, 0.366065],
        51.2,
    ),
    (
        "copper",
        [0.19125, 0.0735, 0.0225],
        [0.7038, 0.27048, 0.0828],
        [0.256777, 0.137622, 0.086014],
        12.8,
    ),
    (
        "silver",
        [0.19225, 0.19225, 0.19225],
        [0.50754, 0.50754, 0.50754],
        [0.508273, 0.508273, 0.508273],
        51.2,
    ),
    (
        "brass",
        [0.329412, 0.223529, 0.027451],
        [0.780392, 0.568627, 0.113725],
        [0.992157, 0.941176, 0.807843],
        27.897,
    ),
    (
        "bronze",
        [0.2125, 0.1275, 0.054],
        [0.714, 0.4284, 0.18144],
        [0.393548, 0.271906, 0.166721],
        25.6,
    ),
    (
        "chrome",
        [0.25, 0.25, 0.25],
        [0.4, 0.4, 0.4],
        [0.774597, 0.774597, 0.774597],
        76.8,
    ),
    (
        "pewter",
        [0.105882, 0.058824, 0.113725],
        [0.427451, 0.470588, 0.541176],
        [0.333333, 0.333333, 0.521569],
        9.84615,
    ),
    (
        "emerald",
        [0.0215, 0.1745, 0.0215],
        [0.07568, 0.61424, 0.07568],
        [0.633, 0.727811, 0.633],
        76.8,
    ),
    (
        "jade",
        [0.135, 0.2225, 0.1575],
        [0.54, 0.89, 0.63],
        [0.316228, 0.316228, 0.316228],
        12.8,
    ),
    (
        "ruby",
        [0.1745, 0.01175, 0.01175],
        [0.61424, 0.04136, 0.04136],
        [0.727811, 0.626959, 0.626959],
        76.8,
    ),
    (
        "pearl",
        [0.25, 0.20725, 0.20725],
        [1.0, 0.829, 0.829],
        [0.296648, 0.296648, 0.296648],
        11.264,
    ),
    (
        "obsidian",
        [0.05375, 0.05, 0.06625],
        [0.18275, 0.17, 0.22525],
        [0.332741, 0.328634, 0.346435],
        38.4,
    ),
];

/// The default surface: Ka 0.2, Kd 0.8, Ks 0, shine 1.
pub const DEFAULT_MATERIAL: NamedMaterial = ("default", [0.2; 3], [0.8; 3], [0.0; 3], 1.0);

/// A shape placed in the world, with its surface.
#[derive(Copy, Clone, Debug)]
pub struct Object<S: Scalar> {
    /// The shape in object space.
    pub shape: Shape,
    /// Surface reflectances.
    pub material: Material<S>,
    /// Checker square side in object space; 0 is no texture.
    pub texture: S,
    /// 1 / texture (0 without texture) as `Kernels::checker_scale` holds it.
    inv_texture: S,
    /// World → object.
    to_object: Affine<S>,
    /// Object normal → world normal: the inverse transpose of object → world.
    normal_to_world: Affine<S>,
    /// World-space bounding sphere (centre, radius); the plane has none.
    bound: Option<(Vec3<S>, S)>,
    /// What the shape needs per hit, computed once. The plane: its world
    /// unit normal, the same for every hit, exactly as [`Object::normal`]
    /// would compute it per hit. Zero otherwise.
    per_shape: Vec3<S>,
}

impl<S: crate::number::BakeScalar> crate::bytes::Field for Object<S> {
    crate::bytes::baked_fields!(Object {
        shape,
        material,
        texture,
        inv_texture,
        to_object,
        normal_to_world,
        bound,
        per_shape,
    }, check(obj) {
        // The plane is the one shape without a bounding sphere; intersect relies on it.
        if (obj.shape == Shape::Plane) != obj.bound.is_none() {
            return Err(crate::bytes::BakeError::OutOfRange("bounding sphere does not match the shape"));
        }
    });
}

/// What the exact set-up of an object is built from (the parser's output).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ObjectDesc {
    /// The shape.
    pub shape: Shape,
    /// Ka, Kd, Ks, shine.
    pub ka: [f64; 3],
    /// Diffuse reflectance.
    pub kd: [f64; 3],
    /// Specular reflectance.
    pub ks: [f64; 3],
    /// Phong exponent.
    pub shine: f64,
    /// Checker square side, 0 for none.
    pub texture: f64,
    /// Object → world, the transformation lines composed in order.
    pub to_world: Mat34,
}

impl ObjectDesc {
    /// A `shape` of `material`, untextured, placed by `to_world`.
    pub fn new(shape: Shape, material: &NamedMaterial, to_world: Mat34) -> Self {
        let &(_, ka, kd, ks, shine) = material;
        ObjectDesc {
            shape,
            ka,
            kd,
            ks,
            shine,
            texture: 0.0,
            to_world,
        }
    }
}

impl<S: Scalar> Object<S> {
    /// Rounds an exact description to `S`. `None` if the transform is singular.
    pub fn new(desc: &ObjectDesc) -> Option<Self> {
        let inv = desc.to_world.inverse()?;
        let bound = desc.shape.bound_radius().map(|r| {
            let c = desc.to_world.apply([0.0; 3], true);
            // The ball's image lies within the largest stretch of the linear part.
            (
                Vec3::from_f64(c),
                S::from_f64(r * max_stretch(&desc.to_world) * (1.0 + 1e-6) + 1e-4),
            )
        });
        let normal_to_world = Affine::from_mat(&inv.linear_transpose());
        let to_object = Affine::from_mat(&match bound {
            // f32 applies it to a ray's offset from the rounded centre (`LOCAL_FROM_CENTRE`).
            Some((c, _)) if S::LOCAL_FROM_CENTRE => inv.after(&Mat34::translate(c.to_f64())),
            _ => inv,
        });
        let per_shape = match desc.shape {
            Shape::Plane => normal_to_world.vector_unit(Vec3::new(S::ZERO, S::ZERO, S::ONE)).0,
            _ => Vec3::ZERO,
        };
        Some(Object {
            shape: desc.shape,
            material: Material {
                ka: Vec3::from_f64(desc.ka),
                kd: Vec3::from_f64(desc.kd),
                ks: Vec3::from_f64(desc.ks),
                shine: S::from_f64(desc.shine),
            },
            texture: S::from_f64(desc.texture),
            inv_texture: if desc.texture > 0.0 {
                S::checker_scale(desc.texture)
            } else {
                S::ZERO
            },
            to_object,
            normal_to_world,
            bound,
            per_shape,
        })
    }

    /// The world-space bounding sphere (centre, radius), if the shape is bounded.
    pub fn bound(&self) -> Option<(Vec3<S>, S)> {
        self.bound
    }

    /// The nearest hit of the world ray `o + t d` (unit `d`) with
    /// `t_min < t < t_max`.
    pub fn intersect(&self, o: Vec3<S>, d: Vec3<S>, t_min: S, t_max: S) -> Option<Hit<S>> {
        self.intersect_dir(o, d, S::dir_from(d.to_array()), t_min, t_max)
    }

    /// As [`Object::intersect`], with `precise` the ray's direction held more
    /// precisely (any length; see `Kernels::Dir`), which the plane uses.
    #[inline]
    pub fn intersect_dir(&self, o: Vec3<S>, d: Vec3<S>, precise: S::Dir, t_min: S, t_max: S) -> Option<Hit<S>> {
        self.intersect_from(o, d, precise, t_min, t_max, None)
    }

    /// A plane's [`Kernels::plane_from_eye`](crate::number::Scalar) for a
    /// pinhole at `eye`; `None` for other shapes. Set-up only.
    pub(crate) fn plane_from_eye(&self, eye: [f64; 3]) -> Option<[S; 4]> {
        (self.shape == Shape::Plane)
            .then(|| self.to_object.plane_from_eye(eye))
            .flatten()
    }

    /// A plane's world unit normal `n` and offset `k` as its rows hold them:
    /// `n · p + k` is the signed distance of `p` (positive on the side the
    /// object's z grows). `None` for other shapes or a degenerate row. Set-up only.
    pub(crate) fn plane_f64(&self) -> Option<([f64; 3], f64)> {
        let [a, b, c, t] = self.to_object.row_f64(2);
        let len = libm::sqrt(a * a + b * b + c * c);
        (self.shape == Shape::Plane && len > 0.0 && len.is_finite()).then(|| ([a / len, b / len, c / len], t / len))
    }

    /// [`Object::intersect_dir`], with a plane's `eye` terms where the ray
    /// leaves from the pinhole they were computed for (a chief ray).
    pub(crate) fn intersect_from(
        &self,
        o: Vec3<S>,
        d: Vec3<S>,
        precise: S::Dir,
        t_min: S,
        t_max: S,
        eye: Option<[S; 4]>,
    ) -> Option<Hit<S>> {
        // One call of the plane kernel (the M0's flash): the plane's, or a
        // cube's face met at grazing (Q16.16, `bounded_from`).
        let (face, hit, limits, checker) = if self.shape == Shape::Plane {
            ((2, 0), None, (t_min, t_max), (self.texture, self.inv_texture))
        } else {
            let (hit, face) = self.bounded_from(o, d, &precise, t_min, t_max)?;
            if face.1 == 0 {
                return Some(hit);
            }
            (face, Some(hit), (S::ZERO, S::MAX), (S::ZERO, S::ZERO))
        };
        // Unbounded plane: from the ray's own origin, with the precise
        // direction (a grazing hit 100 away moves by 100² times its error).
        let plane = self
            .to_object
            .plane_hit(o, precise, limits.0, limits.1, checker, eye, face);
        match hit {
            None => {
                let (t, x, y) = plane?;
                let local = LocalHit {
                    t,
                    p: Vec3::new(x, y, S::ZERO),
                    n: Vec3::new(S::ZERO, S::ZERO, S::ONE),
                };
                Some(Hit { t, local })
            }
            Some(mut hit) => {
                // The face's t from the exact ray (5e-4 late, behind a plane).
                hit.t = plane.map_or(hit.t, |p| p.0);
                (hit.t > t_min && hit.t < t_max).then_some(hit)
            }
        }
    }

    /// [`Object::intersect_from`] for the bounded shapes: the hit (its world
    /// t in the range widened for a grazing cube face), with `(axis, ±1)`
    /// for a cube's face met at a slope under 1/8 in Q16.16 (the rounded
    /// object-space ray's 2⁻¹⁷ divided by it: its t is taken again from the
    /// face's plane), else `(2, 0)`.
    #[inline(always)]
    fn bounded_from(
        &self,
        o: Vec3<S>,
        d: Vec3<S>,
        precise: &S::Dir,
        t_min: S,
        t_max: S,
    ) -> Option<(Hit<S>, (usize, i8))> {
        let precise = *precise;
        // Every other shape has a bounding sphere (checked when it is made).
        let (center, radius) = self.bound?;
        // Cheap reject against the world bounding sphere.
        let oc = center - o;
        let tc = oc.dot_inline(d);
        if tc.add(radius) <= t_min || tc.sub(radius) >= t_max {
            return None;
        }
        if !S::within((oc - d * tc).to_array(), radius) {
            return None;
        }
        // Past the reject only: the object-space unit direction and |A d|
        // (or its reciprocal below 1: Q16.16 keeps its bits), the ray
        // re-origined at the sphere's edge so object-space numbers stay small.
        let t_off = tc.sub(radius).max(S::ZERO);
        let (lo, ld, len, inv_len) = if S::LOCAL_FROM_CENTRE {
            // f32: the start's offset from the centre, `t_off d − oc`,
            // through rows made for that offset (`Object::new`).
            let (ld, len, inv_len) = self.to_object.vector_unit(d);
            let o_lo = S::origin_low(&precise).map_or(Vec3::new(S::ZERO, S::ZERO, S::ZERO), Vec3::from_array);
            (self.to_object.point(d * t_off - (oc - o_lo)), ld, len, inv_len)
        } else {
            self.local_ray(o, d, &precise, t_off)
        };
        if len == S::ZERO && inv_len == S::ZERO {
            return None;
        }
        let by_len = len >= S::ONE;
        let to_local = |t: S| if by_len { t.mul(len) } else { t.div(inv_len) };
        let to_world = |t: S| if by_len { t.div(len) } else { t.mul(inv_len) };
        let (mut lo, mut base, mut again, mut rim) = (lo, t_off, S::RECHECK, None);
        let grazing = S::RECHECK && self.shape == Shape::Cube;
        // One call site of the shapes (the M0's flash): a second pass only
        // for a decision close to its boundary.
        let h = loop {
            let mut close = false;
            let (lt_min, lt_max) = (to_local(t_min.sub(base)), to_local(t_max.sub(base)));
            // A cube's face at grazing may round late by up to this (taken again).
            let lt_max = if grazing { lt_max.add(S::from_q15(512)) } else { lt_max };
            let h = self.shape.intersect_bounded(lo, ld, lt_min, lt_max, &mut close, rim);
            if !(again && close) {
                break h?;
            }
            again = false;
            // Near a rim, an edge or a tangent: a silhouette pixel.
            let k = if by_len { len } else { inv_len };
            match self.closest_origin(o, &precise, S::ONE, (lo, ld, base), by_len, k) {
                Some(p) => (lo, base, rim) = p,
                None => break h?,
            }
        };
        let t = base.add(to_world(h.t));
        if grazing {
            let (p, dl) = (h.p.to_array(), ld.to_array());
            // Constant indices: no bounds check (and no panic code) on the M0.
            let on = |i: usize, x: S, y: S| (x.abs() == S::ONE && y.abs() < S::from_q15(4096)).then_some((i, x));
            if let Some((i, x)) = on(0, p[0], dl[0])
                .or_else(|| on(1, p[1], dl[1]))
                .or_else(|| on(2, p[2], dl[2]))
            {
                return Some((Hit { t, local: h }, (i, if x > S::ZERO { 1 } else { -1 })));
            }
        }
        if t <= t_min || t >= t_max {
            return None;
        }
        Some((Hit { t, local: h }, (2, 0)))
    }

    /// The object-space ray re-origined at `o + t_off d`, its unit direction
    /// and `|A d|` with its reciprocal (see `intersect_dir`). A camera ray's
    /// precise direction where the type has it (Q16.16): the rounded `d`,
    /// 2⁻¹⁷ a component, moved a silhouette 50 away by 4e-4. Not inlined: its
    /// locals stay out of the frame below the shapes (the M0's 8 KiB of stack).
    #[inline(never)]
    fn local_ray(&self, o: Vec3<S>, d: Vec3<S>, precise: &S::Dir, t_off: S) -> (Vec3<S>, Vec3<S>, S, S) {
        let (ld, len, inv_len) = self
            .to_object
            .dir_unit(precise)
            .unwrap_or_else(|| self.to_object.vector_unit(d));
        let start = S::along_dir(o.to_array(), precise, t_off).map_or_else(|| o + d * t_off, Vec3::from_array);
        (self.to_object.point(start), ld, len, inv_len)
    }

    /// Whether the shadow ray from `o` along `v` (the exact vector from the
    /// ray's start to the light, `d` its unit direction, `dist` its length) meets
    /// this object with `t_min < t < dist`. With `Kernels::SHADOW_PRECISE_DIR`, a bounded shape
    /// takes its object-space direction and re-origin from `v` itself: the
    /// rounded `d` (2⁻¹⁷ a component) put a blocker 150 units on 1e-3 aside.
    /// A close decision (`Kernels::RECHECK`) is taken again on the exact
    /// line: from `from`'s exact hit where given (`ShadowStart`), else from `o`.
    // Not inlined: its locals stay out of the shading frame (the M0's 8 KiB of stack).
    #[inline(never)]
    pub(crate) fn blocks(
        &self,
        o: Vec3<S>,
        d: Vec3<S>,
        v: Vec3<S>,
        dist: S,
        t_min: S,
        from: ShadowFrom<'_, S>,
    ) -> bool {
        if !S::SHADOW_PRECISE_DIR || self.shape == Shape::Plane {
            return self.intersect(o, d, t_min, dist).is_some();
        }
        let Some((center, radius)) = self.bound else {
            return false;
        };
        // The bounding-sphere reject as in `intersect_dir` (coarse: d suffices).
        let oc = center - o;
        let tc = oc.dot(d);
        if tc.add(radius) <= t_min || tc.sub(radius) >= dist || !S::within((oc - d * tc).to_array(), radius) {
            return false;
        }
        // Local distance per unit of the segment's parameter s = t / dist: |A v|.
        let (ld, len, inv_len) = self.to_object.vector_unit(v);
        if len == S::ZERO && inv_len == S::ZERO {
            return false;
        }
        // Local per world distance, |A l|, as `intersect_dir` holds it.
        let (by_len, k) = if len >= S::ONE {
            (true, len.div(dist))
        } else {
            (false, inv_len.mul(dist))
        };
        let to_local = |t: S| if by_len { t.mul(k) } else { t.div(k) };
        // Re-origin on the exact line o + s v (an error along it only shifts t).
        let t_off = tc.sub(radius).max(S::ZERO);
        let lo = self.to_object.point(o + v * t_off.div(dist));
        let (mut lo, mut base, mut again, mut rim) = (lo, t_off, S::RECHECK, None);
        loop {
            let mut close = false;
            let (lt_min, lt_max) = (to_local(t_min.sub(base)), to_local(dist.sub(base)));
            let h = self.shape.intersect_bounded(lo, ld, lt_min, lt_max, &mut close, rim);
            // A cube's face crossed under a slope of 1/16: its slab times' error over the slope may pass the band.
            if S::RECHECK
                && again
                && !close
                && from.is_some()
                && self.shape == Shape::Cube
                && ld.to_array().iter().any(|x| x.abs() < S::from_q15(2048))
            {
                close = shape::cube_crossed_slowly(lo, ld);
            }
            if !(again && close) {
                return h.is_some();
            }
            again = false;
            // From the exact hit where the retakes are on (
            // Q16.16's start, rounded to 2⁻¹⁶, was on the other side of a tangent).
            let (o, line) = retake_line(from, o, v);
            match self.closest_origin(o, &line, dist, (lo, ld, base), by_len, k) {
                Some(p) => (lo, base, rim) = p,
                None => return h.is_some(),
            }
        }
    }

    /// A close decision's second pass (`Kernels::RECHECK`): the object-space
    /// point where the ray `o + s d` (`len` the length of `d`: 1 for a unit
    /// direction) passes closest to the centre, exactly and rounded once,
    /// with its world distance, and for a sphere or a cube whether the ray
    /// meets it (and the cube's face), decided from the exact point and
    /// direction: at a sphere's rim or a cube's edge a point rounded to
    /// 2⁻¹⁷ still leaves 1e-5 of doubt. `local` is the first pass's ray (origin,
    /// unit direction, world distance of the origin); local distances are
    /// world ones times `k` (`by_len`) or over it. Cold, out of line: taken
    /// by a few rays an object.
    #[cold]
    #[inline(never)]
    fn closest_origin(
        &self,
        o: Vec3<S>,
        d: &S::Dir,
        len: S,
        local: (Vec3<S>, Vec3<S>, S),
        by_len: bool,
        k: S,
    ) -> Option<(Vec3<S>, S, crate::number::Decided)> {
        let (lo, ld, base) = local;
        let l = lo.dot(ld).neg();
        let s = base.add(if by_len { l.div(k) } else { l.mul(k) }).div(len);
        let rim = (self.shape == Shape::Sphere).then_some(ld);
        use crate::number::{CONE, CUBE, CYLINDER};
        let solid = match self.shape {
            Shape::Cube => CUBE,
            Shape::Cylinder => CYLINDER,
            Shape::Cone => CONE,
            _ => 0,
        };
        let (p, inside) = self.to_object.exact_point(o, d, s, rim, solid)?;
        Some((p, s.mul(len), inside))
    }

    /// The world-space unit normal at a hit, turned to face against `d`.
    pub fn normal(&self, hit: &Hit<S>, d: Vec3<S>) -> Vec3<S> {
        self.facing_normal(hit, d).0
    }

    /// [`Object::normal`], and whether it is the outward normal (the ray
    /// came from outside the object) rather than its opposite.
    pub fn facing_normal(&self, hit: &Hit<S>, d: Vec3<S>) -> (Vec3<S>, bool) {
        let (n, outside, _) = self.facing_normal_len(hit, d);
        (n, outside)
    }

    /// [`Object::facing_normal`], and |N n| of the object-space normal n
    /// (N: normal to world; 0 on the plane), for [`Object::curved_at`].
    pub fn facing_normal_len(&self, hit: &Hit<S>, d: Vec3<S>) -> (Vec3<S>, bool, S) {
        // From the exact product: a large object's inverse transpose has entries of
        // 1/500, which rounded first would leave the normal a few bits.
        let (n, len) = if self.shape == Shape::Plane {
            (self.per_shape, S::ZERO)
        } else {
            let (n, len, _) = self.normal_to_world.vector_unit(hit.local.n);
            (n, len)
        };
        if n.dot_inline(d) > S::ZERO {
            (-n, false, len)
        } else {
            (n, true, len)
        }
    }

    /// Whether the checkerboard darkens this hit's square.
    pub fn in_dark_square(&self, hit: &Hit<S>) -> bool {
        if self.inv_texture == S::ZERO {
            return false;
        }
        let p = hit.local.p;
        let k = self.inv_texture;
        let cell = |x: S| S::checker_cell(x, self.texture, k);
        let sum = cell(p.x) + cell(p.y) + cell(p.z);
        sum & 1 == 1
    }

    /// [`Object::in_dark_square`] for a hit of the world ray `o + t d` (`d`
    /// held precisely): where the rounded point lies within 2⁻¹⁰ (object
    /// units) of a border, the type may take the cells again from the exact
    /// ray (`Kernels::exact_cells`; Q16.16's point, rounded to 2⁻¹⁶ a
    /// component after a re-origin and a transform, decided borders 6e-6
    /// away the wrong way).
    pub fn in_dark_square_of(&self, hit: &Hit<S>, o: Vec3<S>, d: &S::Dir) -> bool {
        if self.inv_texture == S::ZERO {
            return false;
        }
        let (p, n) = (hit.local.p, hit.local.n);
        let (side, k) = (self.texture, self.inv_texture);
        // A flat face's own axis (the normal along it) holds the face's exact
        // coordinate, never in doubt; a curved surface's point is in doubt
        // on every axis.
        let flat = self.surface(hit) == crate::number::FLAT;
        let cell = |x: S, nx: S| S::checker_near(x, side, k, flat && nx != S::ZERO);
        let (a, b, c) = (cell(p.x, n.x), cell(p.y, n.y), cell(p.z, n.z));
        let mut sum = a.0 + b.0 + c.0;
        if a.1 || b.1 || c.1 {
            sum = self.exact_cells(hit, o, d).unwrap_or(sum);
        }
        sum & 1 == 1
    }

    /// [`Object::in_dark_square_of`] for a hit of [`Object::intersect`]'s ray
    /// `o + t d` (`d` as rounded: the property test's).
    pub fn in_dark_square_along(&self, hit: &Hit<S>, o: Vec3<S>, d: Vec3<S>) -> bool {
        self.in_dark_square_of(hit, o, &S::dir_from(d.to_array()))
    }

    /// [`Object::in_dark_square_of`]'s retake (cold: a few hits a frame).
    #[cold]
    #[inline(never)]
    fn exact_cells(&self, hit: &Hit<S>, o: Vec3<S>, d: &S::Dir) -> Option<i64> {
        self.to_object.exact_cells(
            o,
            d,
            hit.t,
            (hit.local.p, hit.local.n),
            self.surface(hit),
            (self.texture, self.inv_texture),
        )
    }

    /// The surface a hit lies on, for the exact kernels (`q16::FLAT`,
    /// `ROUND`, `CYLINDER`, `CONE`): a side's normal has an x or z part, a
    /// cap's, a cube's face's and the plane's are flat.
    fn surface(&self, hit: &Hit<S>) -> u8 {
        use crate::number::{CONE, CYLINDER, FLAT, ROUND};
        let n = hit.local.n;
        let side_of = |code| if n.x == S::ZERO && n.z == S::ZERO { FLAT } else { code };
        match self.shape {
            Shape::Sphere => ROUND,
            Shape::Cylinder => side_of(CYLINDER),
            Shape::Cone => side_of(CONE),
            _ => FLAT,
        }
    }

    /// A hit's world distance along the world ray `o + t d` (`d` held
    /// precisely) taken again from the exact ray, at 2^-30 world units
    /// (`Kernels::exact_t`): `None` where the type has no such kernel
    /// (f32) or the scales do not fit.
    pub fn exact_t(&self, hit: &Hit<S>, o: Vec3<S>, d: &S::Dir) -> Option<i64> {
        self.to_object
            .exact_t(o, d, hit.t, (hit.local.p, hit.local.n), self.surface(hit))
    }

    /// A hit's point on the world ray `o + t d` (`d` held precisely) at its
    /// t taken again from the exact ray (`Kernels::exact_hit_point`),
    /// rounded once; `None` where the type has no such kernel (f32).
    #[cold]
    #[inline(never)]
    pub(crate) fn exact_hit_point(&self, hit: &Hit<S>, o: Vec3<S>, d: &S::Dir) -> Option<Vec3<S>> {
        let t = self.exact_t(hit, o, d)?;
        S::exact_hit_point(o.to_array(), d, t).map(Vec3::from_array)
    }

    /// [`Object::exact_t`] for a hit of [`Object::intersect`]'s ray `o + t d`
    /// (`d` as rounded: the property test's).
    pub fn exact_t_along(&self, hit: &Hit<S>, o: Vec3<S>, d: Vec3<S>) -> Option<i64> {
        self.exact_t(hit, o, &S::dir_from(d.to_array()))
    }

    /// The checker's darkening (1 on a light square, 1/4 on a dark one)
    /// averaged over a lens ray's footprint: a disc of radius `w` world units
    /// across the ray (unit `d`) projected along it onto the surface, whose
    /// unit world normal at the hit is `n_world` (either side). `None` where
    /// the footprint lies inside the hit's own square (then [`Object::in_dark_square`]
    /// decides, bit for bit as without a footprint), or without texture. The
    /// checker is a product of square waves along the object axes, so the
    /// average over the footprint's bounding box is the product of each
    /// wave's average: the difference of its integral (a triangle wave) at
    /// the box's ends over the box's width (docs/sampling.md).
    // Out of line: inlined into the trace it cost 4 KiB of Cortex-M0 flash.
    #[inline(never)]
    pub fn checker_filtered(&self, hit: &Hit<S>, d: Vec3<S>, n_world: Vec3<S>, w: S) -> Option<S> {
        if self.inv_texture == S::ZERO || w <= S::ZERO {
            return None;
        }
        let n = hit.local.n.to_array();
        // Object coordinate k of a world offset y is B_k·y (B_k row k of
        // world → object). Projected along d onto the tangent plane, y moves
        // by −d (n_w·y)/(n_w·d): coordinate k then reads c_k·y with
        // c_k = B_k − (B_k·d / n_w·d) n_w, so the footprint spans w |c_k| of
        // axis k, exactly for any affine map.
        let v = self.to_object.vector(d).to_array();
        // n_w faces the ray (n_w·d < 0): the footprint's 1/cos, held to 16.
        let slant = S::ONE.div(d.dot(n_world).neg().max(S::from_q15(2048)));
        let w_cells = w.div(self.texture);
        let p = hit.local.p.to_array();
        let mut product = S::ONE;
        let mut blurred = false;
        for k in 0..3 {
            let (cell, frac) = S::checker_pos(p[k], self.texture, self.inv_texture);
            let (mean, b) = axis_mean(self, k, frac, n[k], v[k].mul(slant), n_world, w_cells);
            blurred |= b;
            product = if cell & 1 == 1 {
                product.mul(mean).neg()
            } else {
                product.mul(mean)
            };
        }
        // Dark share (1 − product)/2 at 1/4: 5/8 + 3/8 product.
        blurred.then(|| S::from_q15(20480).add(S::from_q15(12288).mul(product)))
    }
}

/// A ray's hit on an object.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Hit<S> {
    /// World-space distance along the (unit) ray.
    pub t: S,
    /// The object-space hit.
    pub local: crate::scene::shape::LocalHit<S>,
}

/// Where a shadow ray leaves from, for its close decisions to be taken
/// again from the exact hit (`Object::blocks`): the hit `hit` on `obj` of
/// the world ray `o + t d` (`d` held precisely), its rounded point `p` and
/// the normal `n` the start is offset along.
#[derive(Copy, Clone, Debug)]
pub(crate) struct ShadowStart<'a, S: Scalar> {
    pub(crate) obj: &'a Object<S>,
    pub(crate) hit: &'a Hit<S>,
    pub(crate) o: Vec3<S>,
    pub(crate) d: &'a S::Dir,
    pub(crate) p: Vec3<S>,
    pub(crate) n: Vec3<S>,
}

/// What a shadow ray carries for its retakes: the start (Q16.16), else none.
pub(crate) type ShadowFrom<'a, S> = Option<&'a ShadowStart<'a, S>>;

impl<S: Scalar> ShadowStart<'_, S> {
    /// The shadow ray toward `p + n ε + v` (the light) from the exact hit: its
    /// start rounded with the bits below carried, and its direction
    /// (`Kernels::shadow_line`); `None` where the kernels have no answer.
    #[cold]
    #[inline(never)]
    fn exact_line(&self, v: Vec3<S>) -> Option<(Vec3<S>, S::Dir)> {
        let t = self.obj.exact_t(self.hit, self.o, self.d)?;
        // The start as `trace_culled` rounds it: start + v is the light.
        let light = (self.p + self.n * S::HIT_EPSILON + v).to_array();
        S::shadow_line(self.o.to_array(), self.d, t, (self.n.to_array(), S::HIT_EPSILON), light)
            .map(|(s, d)| (Vec3::from_array(s), d))
    }
}

/// The line a shadow ray's close decision is taken again on: the exact
/// one from `from`'s hit where it is given and has one, else the ray's
/// own, from `o` along `v`.
#[inline(always)]
fn retake_line<S: Scalar>(from: ShadowFrom<'_, S>, o: Vec3<S>, v: Vec3<S>) -> (Vec3<S>, S::Dir) {
    if let Some(line) = from.and_then(|s| s.exact_line(v)) {
        return line;
    }
    (o, S::dir_from(v.to_array()))
}

/// Largest factor by which the linear part stretches a vector (its top
/// singular value): the square root of AᵀA's largest eigenvalue, by the
/// closed form for symmetric 3×3 matrices. Set-up only.
fn max_stretch(m: &Mat34) -> f64 {
    let a = &m.0;
    let mut g = [[0.0f64; 3]; 3];
    for (i, gi) in g.iter_mut().enumerate() {
        for (j, x) in gi.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[k][i] * a[k][j]).sum();
        }
    }
    let off = g[0][1] * g[0][1] + g[0][2] * g[0][2] + g[1][2] * g[1][2];
    let lambda = if off == 0.0 {
        g[0][0].max(g[1][1]).max(g[2][2])
    } else {
        let q = (g[0][0] + g[1][1] + g[2][2]) / 3.0;
        let sq = |x: f64| x * x;
        let p2 = sq(g[0][0] - q) + sq(g[1][1] - q) + sq(g[2][2] - q) + 2.0 * off;
        let p = libm::sqrt(p2 / 6.0);
        let b = |i: usize, j: usize| (g[i][j] - if i == j { q } else { 0.0 }) / p;
        let det = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1)) - b(0, 1) * (b(1, 0) * b(2, 2) - b(1, 2) * b(2, 0))
            + b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0));
        let r = (det / 2.0).clamp(-1.0, 1.0);
        q + 2.0 * p * libm::cos(libm::acos(r) / 3.0)
    };
    libm::sqrt(lambda.max(0.0))
}

/// A point light.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Light<S> {
    /// World position.
    pub position: Vec3<S>,
    /// Intensity per channel.
    pub intensity: Vec3<S>,
}

impl<S: crate::bytes::Field> crate::bytes::Field for Light<S> {
    crate::bytes::baked_fields!(Light { position, intensity });
}

/// A parsed, validated scene in the number type `S`.
#[derive(Clone, Debug)]
pub struct Scene<S: Scalar> {
    /// The camera statements.
    pub camera: CameraParams,
    /// Ambient light intensity.
    pub ambient: Vec3<S>,
    /// Colour of rays that hit nothing.
    pub background: Vec3<S>,
    /// Whether shadow rays are cast.
    pub shadows: bool,
    /// The objects, in file order (see [`Scene::objects`]).
    pub(crate) objects: heapless::Vec<Object<S>, MAX_OBJECTS>,
    /// The point lights, in file order (see [`Scene::lights`]).
    pub(crate) lights: heapless::Vec<Light<S>, MAX_LIGHTS>,
}

impl<S: Scalar> Scene<S> {
    /// The objects, in file order (at most [`MAX_OBJECTS`]).
    pub fn objects(&self) -> &[Object<S>] {
        &self.objects
    }

    /// The point lights, in file order (at most [`MAX_LIGHTS`]).
    pub fn lights(&self) -> &[Light<S>] {
        &self.lights
    }

    /// Keeps only the first `n` lights (a profile measures the cost of each).
    pub fn truncate_lights(&mut self, n: usize) {
        self.lights.truncate(n);
    }
}

impl<S: Scalar> Default for Scene<S> {
    /// The empty scene: default camera, no objects, no lights, black.
    fn default() -> Self {
        Scene {
            camera: CameraParams::default(),
            ambient: Vec3::ZERO,
            background: Vec3::ZERO,
            shadows: false,
            objects: heapless::Vec::new(),
            lights: heapless::Vec::new(),
        }
    }
}

/// The mean over [frac − e, frac + e] of the square wave that is 1 on its
/// cell [0, 1) and −1 on the next: the difference of its integral, a
/// triangle wave of period 2 and peak 1, at the ends over the width (e > 0).
#[inline(never)]
fn box_mean<S: Scalar>(frac: S, e: S) -> S {
    let two = S::from_i32(2);
    let tri = |v: S| {
        let m = v.sub(two.mul(S::from_i32(v.mul(S::from_q15(16384)).floor_i32())));
        if m <= S::ONE {
            m
        } else {
            two.sub(m)
        }
    };
    tri(frac.add(e)).sub(tri(frac.sub(e))).div(e.add(e))
}

/// The checker's square wave along object axis `k` of `obj` averaged over a
/// lens ray's footprint, relative to the hit's cell (1 where the footprint
/// lies inside it), and whether it crossed a border. `frac` is the hit's
/// place in its cell, `n_k` the local normal's component, `r` the ray's
/// object coordinate k per world unit over −n_w·d, `n_world` the world normal
/// facing the ray, `w_cells` the footprint's radius over the square's side
/// (see [`Object::checker_filtered`]). Out of line: one copy, not three, in
/// the Cortex-M0's flash.
#[inline(never)]
fn axis_mean<S: Scalar>(obj: &Object<S>, k: usize, frac: S, n_k: S, r: S, n_world: Vec3<S>, w_cells: S) -> (S, bool) {
    // A flat face's normal axis: the face lies in one plane of it.
    if n_k.abs() == S::ONE {
        return (S::ONE, false);
    }
    let n_world = n_world.to_array();
    // c_k = B_k + r n_w.
    let c: [S; 3] = core::array::from_fn(|j| obj.to_object.entry(k, j).add(n_world[j].mul(r)));
    let e = w_cells.mul(S::length3(c));
    if e <= frac.min(S::ONE.sub(frac)) {
        (S::ONE, false)
    } else {
        (box_mean(frac, e), true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixed::types::I16F16;

    fn object<S: Scalar>(shape: Shape, to_world: Mat34) -> Object<S> {
        Object::new(&ObjectDesc::new(shape, &DEFAULT_MATERIAL, to_world)).unwrap()
    }

    /// World-space hit distance and unit normal (facing the ray), in f64.
    fn hit<S: Scalar>(obj: &Object<S>, o: [f64; 3], d: [f64; 3]) -> Option<(f64, [f64; 3])> {
        let (o, d) = (Vec3::<S>::from_f64(o), Vec3::<S>::from_f64(d).normalize());
        let h = obj.intersect(o, d, S::HIT_EPSILON, S::MAX)?;
        Some((h.t.to_f64(), obj.normal(&h, d).to_f64()))
    }

    fn both(shape: Shape, m: Mat34, o: [f64; 3], d: [f64; 3]) -> Option<(f64, [f64; 3])> {
        let a = hit(&object::<f32>(shape, m), o, d);
        let b = hit(&object::<I16F16>(shape, m), o, d);
        assert_eq!(a.is_some(), b.is_some(), "{shape:?}: f32 {a:?} vs Q16.16 {b:?}");
        if let (Some(x), Some(y)) = (a, b) {
            assert!((x.0 - y.0).abs() < 2e-3, "t {x:?} vs {y:?}");
            assert!((0..3).all(|i| (x.1[i] - y.1[i]).abs() < 2e-3), "n {x:?} vs {y:?}");
        }
        a
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 2e-3)
    }

    #[test]
    fn scaled_and_moved_sphere() {
        // Radius 2 at (1, 0, -10): the ray down -z from (1, 0, 0) hits at depth 8.
        let m = Mat34::translate([1.0, 0.0, -10.0]).after(&Mat34::scale([2.0; 3]));
        let (t, n) = both(Shape::Sphere, m, [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - 8.0).abs() < 2e-3 && close(n, [0.0, 0.0, 1.0]), "{t} {n:?}");
        // An ellipsoid squashed in z: semi-axis 0.5 along z.
        let m = Mat34::translate([0.0, 0.0, -5.0]).after(&Mat34::scale([1.0, 1.0, 0.5]));
        let (t, _) = both(Shape::Sphere, m, [0.0, 0.0, 0.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - 4.5).abs() < 2e-3);
        // Normals of a non-uniformly scaled shape need the inverse transpose:
        // at 45° around an ellipse x²/4 + y² = 1 the normal is not radial.
        let m = Mat34::scale([2.0, 1.0, 1.0]);
        let p = [2.0f64.sqrt(), 0.5f64.sqrt(), 0.0];
        let (_, n) = both(Shape::Sphere, m, [p[0] * 3.0, p[1] * 3.0, 0.0], [-p[0], -p[1], 0.0]).unwrap();
        let want = [p[0] / 4.0, p[1], 0.0];
        let l = (want[0] * want[0] + want[1] * want[1]).sqrt();
        assert!(close(n, want.map(|x| x / l)), "{n:?}");
    }

    #[test]
    fn rotated_cube_and_floor() {
        // Program 1's cube: rotated 45° about y, its edge faces the camera.
        let m = Mat34::translate([0.0, 0.0, -6.0]).after(&Mat34::rotate(1, 45.0));
        let (t, n) = both(Shape::Cube, m, [0.0, 0.0, 0.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - (6.0 - 2.0f64.sqrt())).abs() < 2e-3, "{t}");
        let s = 0.5f64.sqrt();
        assert!(close(n, [s, 0.0, s]) || close(n, [-s, 0.0, s]), "{n:?}");
        // Program 1's floor: plane rotated -80° about x and lowered to y = -3.
        let m = Mat34::translate([0.0, -3.0, 0.0]).after(&Mat34::rotate(0, -80.0));
        let (t, n) = both(Shape::Plane, m, [0.0, 0.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        // Straight down from the origin: the plane holds (0, -3, 0), so t = 3,
        // and its normal is +z turned by -80° about x (tipped up towards +y).
        let normal = Mat34::rotate(0, -80.0).apply([0.0, 0.0, 1.0], false);
        assert!(normal[1] > 0.98 && close(n, normal), "{n:?} vs {normal:?}");
        assert!((t - 3.0).abs() < 2e-3, "{t}");
        // A ray parallel to a level floor, just above it, never meets it (exact
        // values: a rounded direction may cross a tilted floor far away).
        let level = Mat34::translate([0.0, -3.0, 0.0]).after(&Mat34::rotate(0, -90.0));
        assert!(both(Shape::Plane, level, [0.0, -2.99, 0.0], [1.0, 0.0, -1.0]).is_none());
        assert!(both(Shape::Plane, level, [0.0, -2.99, 0.0], [1.0, -0.01, -1.0]).is_some());
    }

    #[test]
    fn rays_from_inside_and_behind() {
        let m = Mat34::translate([0.0, 0.0, -5.0]).after(&Mat34::scale([3.0; 3]));
        // From the centre of a big cylinder: the side at distance 3, normal facing back.
        let (t, n) = both(Shape::Cylinder, m, [0.0, 0.0, -5.0], [1.0, 0.0, 0.0]).unwrap();
        assert!((t - 3.0).abs() < 2e-3 && close(n, [-1.0, 0.0, 0.0]), "{t} {n:?}");
        // Behind the ray: nothing.
        assert!(both(Shape::Cone, m, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]).is_none());
        // Grazing the bounding sphere but missing the cube inside it.
        assert!(both(Shape::Cube, m, [3.5, 3.5, 0.0], [0.0, 0.0, -1.0]).is_none());
    }
}
