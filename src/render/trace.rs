//! Tracing: the nearest hit along a ray, shadow rays and the Phong colour a
//! ray sees, over a scene's data ([`Scene`]); camera rays skip what the lens
//! cannot reach ([`LensCones`]).

use crate::geometry::ray::Ray;
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::render::cull::LensCones;
use crate::render::defocus::Defocus;
use crate::scene::shape::Shape;
use crate::scene::{Hit, Object, Scene, ShadowFrom, ShadowStart};

impl<S: Scalar> Scene<S> {
    /// An object's ambient and diffuse colours at a hit (normal `n`) of the
    /// ray `o + t d`: dark squares of its checker at a quarter, the checker
    /// averaged over the ray's footprint where `footprint` is given.
    fn textured(
        obj: &Object<S>,
        (hit, n): (&Hit<S>, Vec3<S>),
        (o, d, precise): (Vec3<S>, Vec3<S>, &S::Dir),
        footprint: Option<(&Defocus<S>, S)>,
    ) -> (Vec3<S>, Vec3<S>) {
        let m = &obj.material;
        let filtered = match footprint {
            Some((defocus, stratum)) if obj.texture > S::ZERO && stratum > S::ZERO => {
                obj.checker_filtered(hit, d, n, defocus.width(d, hit.t, stratum))
            }
            _ => None,
        };
        if let Some(f) = filtered {
            (m.ka * f, m.kd * f)
        } else if obj.in_dark_square_of(hit, o, precise) {
            (m.ka.quarter(), m.kd.quarter())
        } else {
            (m.ka, m.kd)
        }
    }

    /// The nearest object hit by the ray `o + t d` (unit `d`) with `t_min < t`.
    pub fn closest_hit(&self, o: Vec3<S>, d: Vec3<S>, t_min: S) -> Option<(usize, Hit<S>)> {
        self.closest_hit_culled(o, d, S::dir_from(d.to_array()), t_min, None, None)
    }

    /// The nearest object hit by a camera ray (which leaves the lens: see
    /// [`LensCones`]), skipping the objects out of the ray's reach. `cones`
    /// are the camera's own: a pinhole's hold its planes' terms for rays
    /// from its eye.
    pub(crate) fn closest_hit_camera_ray(&self, ray: &Ray<S>, cones: &LensCones<S>) -> Option<(usize, Hit<S>)> {
        self.closest_hit_culled(ray.origin, ray.dir, ray.precise, S::HIT_EPSILON, Some(cones), None)
    }

    /// The nearest hit, skipping the objects a ray from the lens cannot
    /// reach where `cones` is given. In Q16.16 an object met within 2⁻⁸ of
    /// the nearest hit so far is ordered against it on both hits' t taken
    /// again from the exact ray (`Scene::nearer_exact`); f32 orders on t.
    fn closest_hit_culled(
        &self,
        o: Vec3<S>,
        d: Vec3<S>,
        precise: S::Dir,
        t_min: S,
        cones: Option<&LensCones<S>>,
        pixel: Option<(i16, i16)>,
    ) -> Option<(usize, Hit<S>)> {
        let window = S::from_q15(128);
        let mut best: Option<(usize, Hit<S>)> = None;
        for (i, obj) in self.objects.iter().enumerate() {
            if cones.is_some_and(|c| !c.may_reach_pixel(i, d, pixel)) {
                continue;
            }
            let t_max = best.map_or(S::MAX, |(_, h)| h.t);
            // The exact order looks up to the window beyond the nearest so far.
            let t_max = if S::RECHECK { t_max.add(window) } else { t_max };
            // Cones come with camera rays only: from the eye where the camera is a pinhole.
            let eye = match cones {
                Some(c) if obj.shape == Shape::Plane => c.plane_from_eye(i),
                _ => None,
            };
            if let Some(h) = obj.intersect_from(o, d, precise, t_min, t_max, eye) {
                if let Some((j, b)) = best.filter(|_| S::RECHECK) {
                    if h.t.add(window) > b.t && !self.nearer_exact((i, &h), (j, &b), o, &precise) {
                        continue;
                    }
                }
                best = Some((i, h));
            }
        }
        best
    }

    /// Whether hit `a` (object `a.0`'s) lies nearer along the ray `o + t d`
    /// than hit `b`, two hits within a few Q16.16 steps of each other: on
    /// their t taken again from the exact ray (`Object::exact_t`), else on
    /// the rounded t. Cold: the few rays a frame where two surfaces meet.
    #[cold]
    #[inline(never)]
    fn nearer_exact(&self, a: (usize, &Hit<S>), b: (usize, &Hit<S>), o: Vec3<S>, d: &S::Dir) -> bool {
        let exact = |(i, h): (usize, &Hit<S>)| self.objects.get(i).and_then(|obj| obj.exact_t(h, o, d));
        match (exact(a), exact(b)) {
            (Some(ta), Some(tb)) if ta != tb => ta < tb,
            _ => a.1.t < b.1.t,
        }
    }

    /// Whether anything lies on the ray within `t_min < t < t_max`
    /// (stops at the first hit: shadow rays).
    pub fn any_hit(&self, o: Vec3<S>, d: Vec3<S>, t_min: S, t_max: S) -> bool {
        self.objects
            .iter()
            .any(|obj| obj.intersect(o, d, t_min, t_max).is_some())
    }

    /// Whether anything but object `skip` (if given) lies on the segment
    /// from `o` (just above the hit) to `light` itself, `t_min` its start
    /// (see `Object::blocks`; `from` its start for the retakes). `light − o`
    /// is exact in Q16.16, so the segment ends at the light in every type.
    #[inline(never)]
    fn shadowed_to(&self, o: Vec3<S>, light: Vec3<S>, t_min: S, skip: Option<usize>, from: ShadowFrom<'_, S>) -> bool {
        let v = light - o;
        let (d, dist) = v.normalize_len();
        self.objects
            .iter()
            .enumerate()
            .any(|(i, obj)| Some(i) != skip && obj.blocks(o, d, v, dist, t_min, from))
    }

    /// The colour seen along the ray `o + t d` (unit `d`), unclamped.
    ///
    /// # Panics
    ///
    /// Never: every operation saturates.
    pub fn trace(&self, o: Vec3<S>, d: Vec3<S>) -> Vec3<S> {
        let ray = Ray {
            origin: o,
            dir: d,
            precise: S::dir_from(d.to_array()),
        };
        self.trace_ray(&ray, None, None, None)
    }

    /// The colour seen along `ray`, unclamped, skipping the objects out of
    /// a camera ray's reach where `cones` is given. Where `footprint` is
    /// given (the camera's defocus and the radius of the ray's cell of the
    /// lens, [`Defocus::stratum`]) a checker it meets is averaged over the
    /// ray's footprint there (see [`Defocus`]).
    pub(crate) fn trace_ray(
        &self,
        ray: &Ray<S>,
        cones: Option<&LensCones<S>>,
        footprint: Option<(&Defocus<S>, S)>,
        pixel: Option<(i16, i16)>,
    ) -> Vec3<S> {
        let (o, d, precise) = (ray.origin, ray.dir, ray.precise);
        let Some((i, hit)) = self.closest_hit_culled(o, d, precise, S::HIT_EPSILON, cones, pixel) else {
            return self.background;
        };
        // Always there (the search's own index); `get` spares a panicking bounds check.
        let Some(obj) = self.objects.get(i) else {
            return self.background;
        };
        // From the precise direction where the type has it (Q16.16: the
        // rounded d, 2⁻¹⁷ a component, puts P off by 2e-4 at t = 26).
        let p = S::along_dir(o.to_array(), &precise, hit.t).map_or_else(|| o + d.scale(hit.t), Vec3::from_array);
        let (n, outside, _) = obj.facing_normal_len(&hit, d);
        // Shadow rays' close decisions are taken again from the exact hit (Q16.16).
        let start;
        let (p, from) = if self.shadows && S::RECHECK {
            // At grazing (a slope under 1/4) a bounded shape's rounded t is off
            // by its object-space rounding over the slope: P at the exact t.
            let p = if obj.shape != Shape::Plane && n.dot_inline(d) > S::from_q15(-8192) {
                obj.exact_hit_point(&hit, o, &precise).unwrap_or(p)
            } else {
                p
            };
            start = ShadowStart {
                obj,
                hit: &hit,
                o,
                d: &precise,
                p,
                n,
            };
            (p, Some(&start))
        } else {
            (p, None)
        };
        let m = &obj.material;
        let (ka, kd) = Self::textured(obj, (&hit, n), (o, d, &precise), footprint);
        // Every shape is convex: a shadow ray leaving the lit side of its own
        // surface never meets it again, so it is not tested. Seen from
        // inside, the ray crosses the object and the far wall counts.
        let own = (S::SHADOW_SKIPS_OWN_CONVEX && (outside || obj.shape == Shape::Plane)).then_some(i);
        let v = -d;
        let mut colour = ka.tinted(self.ambient);
        // Shadow rays leave from just above the surface, on the viewer's side.
        let p_shadow = if self.shadows { p + n * S::HIT_EPSILON } else { p };
        for light in &self.lights {
            let to_light = light.position - p;
            // A light behind the surface needs no normalising.
            if !S::dot_positive(n.to_array(), to_light.to_array()) {
                continue;
            }
            let (l, _) = to_light.normalize_len();
            let n_dot_l = n.dot_inline(l);
            if n_dot_l <= S::ZERO {
                continue;
            }
            if self.shadows && self.shadowed_to(p_shadow, light.position, S::HIT_EPSILON, own, from) {
                continue;
            }
            let r = n.scale(n_dot_l.add(n_dot_l)) - l;
            let r_dot_v = r.dot_inline(v).max(S::ZERO);
            let diffuse = kd.scale(n_dot_l);
            let power = r_dot_v.powf(m.shine);
            // No highlight (the reflection turned away) adds nothing: ks · 0 is 0.
            let lit = if power == S::ZERO {
                diffuse
            } else {
                diffuse + m.ks.scale(power)
            };
            colour = colour + lit.tinted(light.intensity);
        }
        colour
    }
}
