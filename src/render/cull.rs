//! Which objects a ray from the lens can reach at all, decided per object by
//! one dot product.
//!
//! Every camera ray leaves the lens, within its radius a of the lens centre E.
//! A ray from there passes within r of a bounding sphere's centre c only if
//! the same direction from E passes within r + a of it (the ray moved by at
//! most a), which holds only for directions within the angle θ of the axis
//! towards c, where sin θ = (r + a) / |c − E|. So the test of an object's
//! bounding sphere, a dozen products, becomes `d · axis < cos θ` for the
//! objects the ray misses by a wide margin: most of them, for most rays.
//!
//! Each cone's directions, and each plane's half of the sky (a ray from the
//! lens running away from a plane never meets it), are boxed on the film
//! once per frame: a pixel out of an object's box skips it, and a pixel out
//! of every box sees the background without casting a ray (docs/speed.md).

use crate::camera::FilmFrame;
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::scene::{Object, Scene, MAX_OBJECTS};

/// The cone of directions from the lens that can reach one object.
#[derive(Copy, Clone, Debug, PartialEq)]
struct Cone<S> {
    /// Unit vector from E towards the bounding sphere's centre.
    axis: Vec3<S>,
    /// Directions with `d · axis` below this miss the object.
    cos_min: S,
    /// Every direction may reach it (the plane; a lens inside the sphere).
    always: bool,
    /// The pixels some of whose rays may pass `d · axis >= cos_min` (a
    /// plane's: may run towards it): columns `[0]..=[1]`, rows `[2]..=[3]`
    /// (every pixel where not known).
    pixels: [i16; 4],
}

impl<S: crate::bytes::Field> crate::bytes::Field for Cone<S> {
    crate::bytes::baked_fields!(Cone {
        axis,
        cos_min,
        always,
        pixels
    });
}

/// The lens's cones for every object of a scene, in the scene's order.
#[derive(Clone, Debug)]
pub struct LensCones<S: Scalar> {
    cones: heapless::Vec<Cone<S>, MAX_OBJECTS>,
    /// A pinhole's planes hold their chief rays' eye terms in their cones
    /// (`Kernels::plane_from_eye`: axis and `cos_min`, which a plane, never
    /// culled, has no use for).
    from_eye: bool,
}

impl<S: Scalar + crate::bytes::Field> crate::bytes::Field for LensCones<S> {
    crate::bytes::baked_fields!(LensCones { cones, from_eye });
}

/// Every pixel: a cone without a box on the film.
const ANY_PIXEL: [i16; 4] = [i16::MIN, i16::MAX, i16::MIN, i16::MAX];

/// Slack on `cos θ` for the rounding of the direction, the axis and their dot
/// product in Q16.16 (each within a few 2^-17): 2^-12.
const SLACK: f64 = 1.0 / 4096.0;

/// How far below `cos_min` a chief ray's exact `cos` may lie and still pass
/// the test in `S`: the rounded direction, axis and dot product are within
/// 7 · 2^-17 of exact; the pixel boxes are cut 2^-12 below.
const COS_ROUNDING: f64 = 1.0 / 4096.0;

impl<S: Scalar> LensCones<S> {
    /// The cones seen from a lens of radius `radius` (0 for a pinhole) centred
    /// at `eye`, in world space, and where the camera's `film` is given,
    /// each cone's box of pixels on it ([`LensCones::may_reach_pixel`]).
    /// Set-up only, in f64.
    pub fn new(scene: &Scene<S>, eye: [f64; 3], radius: f64, film: Option<&FilmFrame>) -> Self {
        // As the camera decides it: every camera ray then leaves from the eye.
        let pinhole = radius.is_nan() || radius <= 0.0;
        let mut from_eye = false;
        let radius = if radius.is_finite() && radius > 0.0 {
            radius
        } else {
            0.0
        };
        let every = Cone {
            axis: Vec3::ZERO,
            cos_min: S::ZERO,
            always: true,
            pixels: ANY_PIXEL,
        };
        let mut cones = heapless::Vec::new();
        for obj in &scene.objects {
            let plane = film.map_or(ANY_PIXEL, |f| plane_pixels(obj, f, eye, radius));
            let terms = if pinhole { obj.plane_from_eye(eye) } else { None };
            if let Some([a, b, c, d]) = terms {
                from_eye = true;
                let _ = cones.push(Cone {
                    axis: Vec3::new(a, b, c),
                    cos_min: d,
                    always: true,
                    pixels: plane,
                });
                continue;
            }
            let cone = obj.bound().map_or(Cone { pixels: plane, ..every }, |(centre, r)| {
                let w = [0, 1, 2].map(|k| centre.to_f64()[k] - eye[k]);
                let dist = libm::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
                let reach = r.to_f64() + radius;
                if dist <= reach * (1.0 + 1e-9) + 1e-6 {
                    return every;
                }
                let sin = reach / dist;
                let axis = w.map(|x| x / dist);
                let cos_min = libm::sqrt(1.0 - sin * sin) - SLACK;
                Cone {
                    axis: Vec3::from_f64(axis),
                    cos_min: S::from_f64(cos_min),
                    always: false,
                    pixels: film.map_or(ANY_PIXEL, |f| f.cone_pixels(axis, cos_min - COS_ROUNDING)),
                }
            });
            // One cone per object: the scene holds at most MAX_OBJECTS.
            let _ = cones.push(cone);
        }
        LensCones { cones, from_eye }
    }

    /// A pinhole's eye terms of plane `i` (`Kernels::plane_from_eye`), for
    /// its chief rays; `None` for a lens or a type without them.
    #[inline(always)]
    pub(crate) fn plane_from_eye(&self, i: usize) -> Option<[S; 4]> {
        if !self.from_eye {
            return None;
        }
        self.cones.get(i).map(|c| [c.axis.x, c.axis.y, c.axis.z, c.cos_min])
    }

    /// Number of cones: one per object.
    pub fn len(&self) -> usize {
        self.cones.len()
    }

    /// Whether a ray from the lens along the unit `d` can reach object `i`;
    /// for a camera ray of `pixel` (column, row) where given, pixels outside
    /// the cone's box on the film are out of reach without the dot product. The box holds every pixel
    /// whose chief ray passes the dot product's test, rounding included
    /// (docs/speed.md), so the answer is the same; a plane's box holds every
    /// pixel some of whose rays run towards it.
    #[inline(always)]
    pub(crate) fn may_reach_pixel(&self, i: usize, d: Vec3<S>, pixel: Option<(i16, i16)>) -> bool {
        match self.cones.get(i) {
            Some(c) => pixel.is_none_or(|p| in_box(c.pixels, p)) && (c.always || d.dot_inline(c.axis) >= c.cos_min),
            None => true,
        }
    }

    /// Whether no camera ray of `pixel` (column, row) can reach any object:
    /// the pixel lies outside every box, and sees the background.
    #[inline]
    pub(crate) fn reach_nothing(&self, pixel: (i16, i16)) -> bool {
        !self.cones.iter().any(|c| in_box(c.pixels, pixel))
    }
}

/// Whether `(x, y)` lies in the box `[c0, c1, r0, r1]`.
#[inline(always)]
fn in_box([c0, c1, r0, r1]: [i16; 4], (x, y): (i16, i16)) -> bool {
    c0 <= x && x <= c1 && r0 <= y && y <= r1
}

/// A plane's box on `film`: where the lens (`radius` about `eye`) lies
/// wholly on one side of it, 2^-10 to spare for rounding, the pixels some
/// of whose rays run towards it ([`FilmFrame::plane_pixels`]); otherwise,
/// and for other shapes, every pixel.
fn plane_pixels<S: Scalar>(obj: &Object<S>, film: &FilmFrame, eye: [f64; 3], radius: f64) -> [i16; 4] {
    let Some((n, k)) = obj.plane_f64() else {
        return ANY_PIXEL;
    };
    let height = n[0] * eye[0] + n[1] * eye[1] + n[2] * eye[2] + k;
    if height.is_nan() || height.abs() <= radius * (1.0 + 1e-9) + 1.0 / 1024.0 {
        return ANY_PIXEL;
    }
    // From the lens towards the plane.
    let toward = if height > 0.0 { n.map(|x| -x) } else { n };
    film.plane_pixels(toward)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixed::types::I16F16;

    /// Distance from `c` to the ray `o + t d` (t >= 0), in f64.
    fn ray_distance(o: [f64; 3], d: [f64; 3], c: [f64; 3]) -> f64 {
        let w = [0, 1, 2].map(|k| c[k] - o[k]);
        let t = (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]).max(0.0);
        let p = [0, 1, 2].map(|k| w[k] - t * d[k]);
        libm::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2])
    }

    fn check<S: Scalar>() {
        let text = "lens_position 0.5 -0.25 1\nlight_position 0 5 0\n\
                    object sphere\ntranslate 0 0 -8\n\
                    object cube\nscale 0.5 0.5 0.5\ntranslate -2 -1.5 -6\n\
                    object plane\ntranslate 0 -3 0\n\
                    object cone\nscale 2 2 2\ntranslate 4 0.5 -15\n\
                    object sphere\ntranslate 0.5 -0.25 1.5\n";
        let scene = Scene::<S>::parse(text).unwrap();
        let eye = [0.5, -0.25, 1.0];
        let radius = 0.4;
        let cones = LensCones::new(&scene, eye, radius, None);
        let mut bits = crate::test_rng::xorshift32(0x1234_5678);
        let mut next = move || (bits() >> 8) as f64 / (1u32 << 24) as f64 * 2.0 - 1.0;
        let (mut culled, mut near_misses) = (0, 0);
        for _ in 0..50_000 {
            // A lens point within the radius (in the lens plane z = 1) and a direction ahead.
            let (lx, ly) = (next() * radius * 0.7, next() * radius * 0.7);
            let o = [eye[0] + lx, eye[1] + ly, eye[2]];
            let d = [next() * 0.6, next() * 0.6, -1.0];
            let l = libm::sqrt(d[0] * d[0] + d[1] * d[1] + 1.0);
            let d = d.map(|x| x / l);
            let dv = Vec3::<S>::from_f64(d);
            for (i, obj) in scene.objects.iter().enumerate() {
                let reach = cones.may_reach_pixel(i, dv, None);
                let Some((c, r)) = obj.bound() else {
                    assert!(reach, "the plane is never culled");
                    continue;
                };
                let dist = ray_distance(o, d, c.to_f64());
                if !reach {
                    culled += 1;
                    // Culled only where the ray misses the bounding sphere.
                    assert!(dist > r.to_f64(), "object {i}: culled at distance {dist} within {r:?}");
                    // Tight: the same direction from the lens centre passes just outside r + a.
                    if ray_distance(eye, d, c.to_f64()) < (r.to_f64() + radius) * 1.05 {
                        near_misses += 1;
                    }
                }
                if i == 4 {
                    assert!(reach, "a lens inside the sphere culls nothing");
                }
            }
        }
        // Most of the three distant objects are out of reach, and the cone is
        // tight: some culled directions pass within 5 % of r + a from the centre.
        assert!(culled > 100_000, "{} culled {culled}", S::NAME);
        assert!(near_misses > 50, "{} near misses {near_misses}", S::NAME);
    }

    #[test]
    fn culls_only_rays_that_miss() {
        check::<I16F16>();
        check::<f32>();
    }

    /// A random camera's statements: film `big_n` from a lens of `radius`,
    /// placed, turned and tilted at random, wide or narrow.
    fn camera_text(r: &mut impl FnMut(f64, f64) -> f64, big_n: f64, radius: f64) -> std::string::String {
        std::format!(
            "width {}\nimage_distance {big_n}\nfocal_length {}\nradius {radius}\n\
             lens_position {} {} {}\nlook {} {} -1\nup {} 1 0\n",
            r(2.0, 20.0),
            r(0.2, 0.95) * big_n,
            r(-3.0, 3.0),
            r(-3.0, 3.0),
            r(-3.0, 3.0),
            r(-0.8, 0.8),
            r(-0.8, 0.8),
            r(-0.3, 0.3)
        )
    }

    /// The chief ray (`None`) and, for a lens, five random lens points in
    /// Q1.15, most near the rim.
    fn lens_points(r: &mut impl FnMut(f64, f64) -> f64, radius: f64) -> [Option<(i32, i32)>; 6] {
        let mut lens = [None; 6];
        for l in lens.iter_mut().skip(1).filter(|_| radius > 0.0) {
            let (a, m) = (r(0.0, core::f64::consts::TAU), libm::sqrt(r(0.0, 1.0)).max(r(0.9, 1.0)));
            *l = Some(((libm::cos(a) * m * 32767.0) as i32, (libm::sin(a) * m * 32767.0) as i32));
        }
        lens
    }

    /// The pixel boxes hold every pixel some of whose rays (the chief ray,
    /// or lens rays through random lens points) pass its cone's dot-product
    /// test, so skipping the others changes nothing, and they leave out most
    /// of the frame: random cameras (pinholes and lenses, tilted, wide and
    /// narrow), objects near and far, beside and behind the eye, both types.
    fn boxes_hold_every_passing_pixel<S: Scalar>() {
        let mut next = crate::test_rng::unit_f64(0x5EED_0B0C);
        let mut r = move |lo: f64, hi: f64| lo + (hi - lo) * next();
        let (mut passed, mut skipped, mut pairs) = (0u32, 0u32, 0u32);
        for k in 0..60 {
            let (cols, rows) = (r(8.0, 48.0) as u32, r(6.0, 36.0) as u32);
            let big_n = r(2.0, 12.0);
            let radius = if k % 2 == 0 { 0.0 } else { r(0.05, 2.5) };
            let mut text = camera_text(&mut r, big_n, radius);
            for _ in 0..6 {
                let shape = ["sphere", "cube", "cylinder", "cone"][(r(0.0, 3.99)) as usize];
                text += &std::format!(
                    "object {shape}\nscale {} {} {}\ntranslate {} {} {}\n",
                    r(0.05, 2.0),
                    r(0.05, 2.0),
                    r(0.05, 2.0),
                    r(-8.0, 8.0),
                    r(-8.0, 8.0),
                    r(-30.0, 6.0)
                );
            }
            let scene = Scene::<S>::parse(&text).unwrap();
            let renderer = crate::Renderer::new(&scene, cols, rows);
            let cones = &renderer.s().cones;
            for (col, row) in (0..rows).flat_map(|y| (0..cols).map(move |x| (x, y))) {
                let pixel = Some((col as i16, row as i16));
                // The chief ray and lens points out to the rim (Q1.15).
                let lens = lens_points(&mut r, radius);
                for p_lens in lens {
                    let d = renderer.camera_ray(col, row, p_lens).dir;
                    for i in 0..scene.objects.len() {
                        let reach = cones.may_reach_pixel(i, d, None);
                        assert_eq!(
                            reach,
                            cones.may_reach_pixel(i, d, pixel),
                            "{text}pixel ({col}, {row}) lens {p_lens:?}, object {i}"
                        );
                        passed += reach as u32;
                    }
                }
                for c in &cones.cones {
                    pairs += 1;
                    let [c0, c1, r0, r1] = c.pixels;
                    skipped += !((c0..=c1).contains(&(col as i16)) && (r0..=r1).contains(&(row as i16))) as u32;
                }
            }
        }
        // Most pixels are boxed out of most objects: the dot products they spare.
        assert!(
            passed > 1000 && skipped > pairs / 2,
            "{} passed {passed}, boxed out {skipped} of {pairs}",
            S::NAME
        );
    }

    /// Every ray of a pixel outside a plane's box misses the plane, and
    /// every ray of a pixel out of all boxes misses everything: random
    /// cameras (pinholes and lenses, tilted, wide and narrow) over planes
    /// turned every way, some scaled, with a sphere, both types. The boxes leave out a fair share.
    fn plane_boxes_hold_every_hit<S: Scalar>() {
        let mut next = crate::test_rng::unit_f64(0x9_1A4E);
        let mut r = move |lo: f64, hi: f64| lo + (hi - lo) * next();
        let (mut out, mut pairs, mut nothing, mut hits) = (0u32, 0u32, 0u32, 0u32);
        for k in 0..48 {
            let (cols, rows) = (r(8.0, 40.0) as u32, r(6.0, 30.0) as u32);
            let big_n = r(2.0, 12.0);
            let radius = if k % 2 == 0 { 0.0 } else { r(0.05, 2.0) };
            let mut text = camera_text(&mut r, big_n, radius);
            for _ in 0..2 {
                let s = if r(0.0, 1.0) < 0.3 { r(0.01, 50.0) } else { 1.0 };
                text += &std::format!(
                    "object plane\nscale {s} {s} {s}\nrotate x {}\nrotate y {}\ntranslate {} {} {}\n",
                    r(-180.0, 180.0),
                    r(-180.0, 180.0),
                    r(-6.0, 6.0),
                    r(-6.0, 6.0),
                    r(-6.0, 6.0)
                );
            }
            text += &std::format!(
                "object sphere\ntranslate {} {} {}\n",
                r(-8.0, 8.0),
                r(-8.0, 8.0),
                r(-30.0, -5.0)
            );
            let scene = Scene::<S>::parse(&text).unwrap();
            let renderer = crate::Renderer::new(&scene, cols, rows);
            let cones = &renderer.s().cones;
            for (col, row) in (0..rows).flat_map(|y| (0..cols).map(move |x| (x, y))) {
                let pixel = (col as i16, row as i16);
                let empty = cones.reach_nothing(pixel);
                nothing += empty as u32;
                let lens = lens_points(&mut r, radius);
                for p_lens in lens {
                    let ray = renderer.camera_ray(col, row, p_lens);
                    for (i, obj) in scene.objects.iter().enumerate() {
                        let eye = cones.plane_from_eye(i).filter(|_| p_lens.is_none());
                        let hit = obj.intersect_from(ray.origin, ray.dir, ray.precise, S::HIT_EPSILON, S::MAX, eye);
                        hits += hit.is_some() as u32;
                        let boxed = in_box(cones.cones[i].pixels, pixel);
                        assert!(
                            boxed || hit.is_none(),
                            "{text}pixel {pixel:?} lens {p_lens:?}: object {i} out of its box"
                        );
                        assert!(
                            !empty || hit.is_none(),
                            "{text}pixel {pixel:?} lens {p_lens:?}: object {i} met"
                        );
                    }
                }
                for (c, obj) in cones.cones.iter().zip(&scene.objects) {
                    if obj.shape == crate::scene::shape::Shape::Plane {
                        pairs += 1;
                        out += !in_box(c.pixels, pixel) as u32;
                    }
                }
            }
        }
        assert!(
            out > pairs / 5 && nothing > 1000 && hits > 10_000,
            "{}: {out} of {pairs} plane pairs boxed out, {nothing} empty pixels, {hits} hits",
            S::NAME
        );
    }

    #[test]
    fn plane_boxes_skip_only_rays_that_miss() {
        plane_boxes_hold_every_hit::<I16F16>();
        plane_boxes_hold_every_hit::<f32>();
    }

    #[test]
    fn pixel_boxes_skip_only_what_the_cones_skip() {
        boxes_hold_every_passing_pixel::<I16F16>();
        boxes_hold_every_passing_pixel::<f32>();
    }
}
