//! Tracing: the nearest hit along a ray, shadow rays and the Phong colour a
//! ray sees, over a scene's data ([`Scene`]); camera rays skip what the lens
//! cannot reach ([`LensCones`]).

use crate::geometry::ray::Ray;
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::render::cull::LensCones;
use crate::render::defocus::{Defocus, Pull};
use crate::scene::shape::Shape;
#[cfg(not(feature = "no-exact-retakes"))]
use crate::scene::ShadowStart;
use crate::scene::{Hit, Scene, ShadowFrom};

impl<S: Scalar> Scene<S> {
    /// The nearest object hit by the ray `o + t d` (unit `d`) with `t_min < t`.
    pub fn closest_hit(&self, o: Vec3<S>, d: Vec3<S>, t_min: S) -> Option<(usize, Hit<S>)> {
        self.closest_hit_dir(o, d, S::dir_from(d.to_array()), t_min)
    }

    /// As [`Scene::closest_hit`], with the ray's direction also held precisely.
    pub fn closest_hit_dir(&self, o: Vec3<S>, d: Vec3<S>, precise: S::Dir, t_min: S) -> Option<(usize, Hit<S>)> {
        self.closest_hit_culled(o, d, precise, t_min, None)
    }

    /// The nearest object hit by a camera ray (which leaves the lens: see
    /// [`LensCones`]): [`Scene::closest_hit_dir`] with the objects out of the
    /// ray's reach skipped. `cones` are the camera's own: a pinhole's hold
    /// its planes' terms for rays from its eye.
    pub fn closest_hit_camera_ray(&self, ray: &Ray<S>, cones: &LensCones<S>) -> Option<(usize, Hit<S>)> {
        self.closest_hit_culled(ray.origin, ray.dir, ray.precise, S::HIT_EPSILON, Some(cones))
    }

    /// As [`Scene::closest_hit_dir`], skipping the objects a ray from the
    /// lens cannot reach where `cones` is given. The micro:bit's (feature
    /// `no-exact-retakes`): the rounded order alone, the search as before
    /// fix 17 (the other's loop with its switch constant false still cost
    /// it 67 instructions a pixel and 76 bytes).
    #[cfg(feature = "no-exact-retakes")]
    fn closest_hit_culled(
        &self,
        o: Vec3<S>,
        d: Vec3<S>,
        precise: S::Dir,
        t_min: S,
        cones: Option<&LensCones<S>>,
    ) -> Option<(usize, Hit<S>)> {
        let mut best: Option<(usize, Hit<S>)> = None;
        for (i, obj) in self.objects.iter().enumerate() {
            if let Some(c) = cones {
                if !c.may_reach(i, d) {
                    continue;
                }
            }
            let t_max = best.map_or(S::MAX, |(_, h)| h.t);
            // Cones come with camera rays only: from the eye where the camera is a pinhole.
            let eye = match cones {
                Some(c) if obj.shape == Shape::Plane => c.plane_from_eye(i),
                _ => None,
            };
            if let Some(h) = obj.intersect_from(o, d, precise, t_min, t_max, eye) {
                best = Some((i, h));
            }
        }
        best
    }

    /// As [`Scene::closest_hit_dir`], skipping the objects a ray from the
    /// lens cannot reach where `cones` is given. With the exact retakes on
    /// (Q16.16; [`Scene::set_exact_retakes`]) an object met within 2⁻⁸ of
    /// the nearest hit so far is ordered against it on both hits' t taken
    /// again from the exact ray (`Scene::nearer_exact`); else (f32, or the
    /// switch off) on the rounded t.
    #[cfg(not(feature = "no-exact-retakes"))]
    fn closest_hit_culled(
        &self,
        o: Vec3<S>,
        d: Vec3<S>,
        precise: S::Dir,
        t_min: S,
        cones: Option<&LensCones<S>>,
    ) -> Option<(usize, Hit<S>)> {
        let exact = S::RECHECK && self.exact_retakes();
        let window = S::from_q15(128);
        let mut best: Option<(usize, Hit<S>)> = None;
        for (i, obj) in self.objects.iter().enumerate() {
            if let Some(c) = cones {
                if !c.may_reach(i, d) {
                    continue;
                }
            }
            let t_max = best.map_or(S::MAX, |(_, h)| h.t);
            // The exact order looks up to the window beyond the nearest so far.
            let t_max = if exact { t_max.add(window) } else { t_max };
            // Cones come with camera rays only: from the eye where the camera is a pinhole.
            let eye = match cones {
                Some(c) if obj.shape == Shape::Plane => c.plane_from_eye(i),
                _ => None,
            };
            if let Some(h) = obj.intersect_from(o, d, precise, t_min, t_max, eye) {
                if exact {
                    if let Some((j, b)) = best {
                        if h.t.add(window) > b.t && !self.nearer_exact((i, &h), (j, &b), o, &precise) {
                            continue;
                        }
                    }
                }
                best = Some((i, h));
            }
        }
        best
    }

    /// Whether hit `a` (object `a.0`'s) lies nearer along the ray `o + t d`
    /// than hit `b`, two hits within a few Q16.16 steps of each other: on
    /// their t taken again from the exact ray (`Object::exact_t`; seeds 9206,
    /// 13193, 17035: a cube's face and a plane, a sphere through a cube,
    /// rounded to 2⁻¹⁶ and ordered the other way than float64), else on
    /// the rounded t as before. Cold: the few rays a frame where two
    /// surfaces meet.
    #[cfg(not(feature = "no-exact-retakes"))]
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

    /// Whether anything but object `skip` (if given) lies on the shadow ray
    /// from `o` along `v` (`d` its unit direction, `dist` its length) within
    /// `t_min < t < dist` (see `Object::blocks`; `from` its start for the
    /// retakes).
    #[allow(clippy::too_many_arguments)]
    fn shadowed(
        &self,
        o: Vec3<S>,
        d: Vec3<S>,
        v: Vec3<S>,
        dist: S,
        t_min: S,
        skip: Option<usize>,
        from: ShadowFrom<'_, S>,
    ) -> bool {
        self.objects
            .iter()
            .enumerate()
            .any(|(i, obj)| Some(i) != skip && obj.blocks(o, d, v, dist, t_min, from))
    }

    /// [`Scene::shadowed`] on the segment from `o` (just above the hit) to
    /// `light` itself, `t_min` its start (docs/accuracy.md, fix 20): `light −
    /// o` is exact in Q16.16, so the segment ends at the light in every type.
    /// Out of line, and not on the micro:bit (`no-exact-retakes`, where
    /// `exact_retakes` is false: its flash has no room for the second
    /// normalising; it keeps P's own vector from `o`, whose segment ends at
    /// `light + n ε`).
    #[inline(never)]
    fn shadowed_to(&self, o: Vec3<S>, light: Vec3<S>, t_min: S, skip: Option<usize>, from: ShadowFrom<'_, S>) -> bool {
        let v = light - o;
        let (d, dist) = v.normalize_len();
        self.shadowed(o, d, v, dist, t_min, skip, from)
    }

    /// The colour seen along the ray `o + t d` (unit `d`), unclamped.
    ///
    /// # Panics
    ///
    /// Never: every operation saturates.
    pub fn trace(&self, o: Vec3<S>, d: Vec3<S>) -> Vec3<S> {
        self.trace_dir(o, d, S::dir_from(d.to_array()))
    }

    /// As [`Scene::trace`], with the ray's direction also held precisely
    /// (any length): the camera's rays, see [`Ray`].
    pub fn trace_dir(&self, o: Vec3<S>, d: Vec3<S>, precise: S::Dir) -> Vec3<S> {
        self.trace_culled(o, d, precise, None, None).0
    }

    /// The colour seen along a camera ray (which leaves the lens: see
    /// [`LensCones`]), unclamped: [`Scene::trace_dir`] with the objects out
    /// of the ray's reach skipped. `cones` are the camera's own: a pinhole's
    /// hold its planes' terms for rays from its eye.
    pub fn trace_camera_ray(&self, ray: &Ray<S>, cones: &LensCones<S>) -> Vec3<S> {
        self.trace_culled(ray.origin, ray.dir, ray.precise, Some(cones), None).0
    }

    /// As [`Scene::trace_camera_ray`], for a ray standing for a stratum of
    /// the lens where `footprint` is given (the camera's defocus, the
    /// stratum's radius from [`Defocus::stratum`] and the ray's pull, from
    /// `Camera::lens_offset`): a checker it meets is averaged over the
    /// stratum's footprint there, its centre pulled in (see [`Defocus`]). Also
    /// the object hit and its distance, `None` for a miss (the scanline filter's gate).
    pub fn trace_lens_ray(
        &self,
        ray: &Ray<S>,
        cones: &LensCones<S>,
        footprint: Option<(&Defocus<S>, S, Pull<'_, S>)>,
    ) -> (Vec3<S>, Option<(usize, S)>) {
        self.trace_culled(ray.origin, ray.dir, ray.precise, Some(cones), footprint)
    }

    fn trace_culled(
        &self,
        o: Vec3<S>,
        d: Vec3<S>,
        precise: S::Dir,
        cones: Option<&LensCones<S>>,
        footprint: Option<(&Defocus<S>, S, Pull<'_, S>)>,
    ) -> (Vec3<S>, Option<(usize, S)>) {
        let Some((i, hit)) = self.closest_hit_culled(o, d, precise, S::HIT_EPSILON, cones) else {
            return (self.background, None);
        };
        // Always there (the search's own index); `get` spares a panicking bounds check.
        let Some(obj) = self.objects.get(i) else {
            return (self.background, None);
        };
        // From the precise direction where the type has it (Q16.16: the rounded
        // d, 2⁻¹⁷ a component, put P 2e-4 off at t = 26 and its shadow ray
        // across a plane 1e-3 away: seed 15233).
        let p = S::along_dir(o.to_array(), &precise, hit.t).map_or_else(|| o + d.scale(hit.t), Vec3::from_array);
        let (n, outside, n_len) = obj.facing_normal_len(&hit, d);
        // Shadow rays' close decisions taken again from the exact hit (Q16.16,
        // retakes on); built only then (live across the lights, its parts
        // cost the Cortex-M3 31 instructions a pixel on Program 1).
        #[cfg(not(feature = "no-exact-retakes"))]
        let start;
        #[cfg(not(feature = "no-exact-retakes"))]
        let (p, from) = if self.shadows && S::RECHECK && self.exact_retakes() {
            // At grazing (a slope under 1/4) a bounded shape's rounded t is off
            // by its object-space rounding over the slope and moves P along the
            // ray (1e-4: a shadow ray's start past a tangent): P at the exact t.
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
        #[cfg(feature = "no-exact-retakes")]
        let from = core::marker::PhantomData;
        // Every shape is convex: a shadow ray leaving the lit side of its own
        // surface never meets it again, so it is not tested (at a large
        // object's magnitudes no fixed offset clears Q16.16's rounding). Seen
        // from inside, the ray crosses the object and the far wall counts.
        let own = (S::SHADOW_SKIPS_OWN_CONVEX && (outside || obj.shape == Shape::Plane)).then_some(i);
        let v = -d;
        let m = &obj.material;
        let filtered = match footprint {
            Some((defocus, stratum, pull)) if obj.texture > S::ZERO && stratum > S::ZERO => {
                let (width, shift) = defocus.checker_footprint(d, hit.t, stratum, pull);
                obj.checker_filtered(&hit, d, n, width, shift)
            }
            _ => None,
        };
        // A light's terminator on a curved surface, where the specular steps
        // from ks (r·v)^shine to 0, is box-filtered over the footprint: its
        // radius, 1/|N n| and 1/n·d (held off grazing, a slant of at most 16, as the
        // checker's). None without a footprint, on flat faces, or with the
        // filter off (always with the feature `no-terminator-filter`: then
        // the lights' loop is the sharp step's).
        let turn = match footprint {
            Some((defocus, stratum, _)) if stratum > S::ZERO && self.terminator_filtered() => {
                obj.curved_at(&hit, n_len).map(|inv_len| {
                    let n_dot_d = n.dot_inline(d);
                    let slant = S::ONE.div(n_dot_d.min(S::from_q15(-2048)));
                    (defocus.width(d, hit.t, stratum), inv_len, slant, n_dot_d)
                })
            }
            _ => None,
        };
        let (ka, kd) = if let Some(f) = filtered {
            (m.ka * f, m.kd * f)
        } else if if self.exact_retakes() {
            obj.in_dark_square_of(&hit, o, &precise)
        } else {
            obj.in_dark_square(&hit)
        } {
            let q = S::from_q15(8192);
            (m.ka * q, m.kd * q)
        } else {
            (m.ka, m.kd)
        };
        let mut colour = ka.hadamard(self.ambient);
        // Shadow rays leave from just above the surface, on the viewer's side.
        let p_shadow = if self.shadows { p + n * S::HIT_EPSILON } else { p };
        for light in &self.lights {
            let to_light = light.position - p;
            // A light behind the surface needs no normalising (in Program 1, the
            // lamp under the floor for every floor pixel).
            if turn.is_none() && !S::dot_positive(n.to_array(), to_light.to_array()) {
                continue;
            }
            let (l, dist) = to_light.normalize_len();
            let n_dot_l = n.dot_inline(l);
            // Within the footprint's band of the terminator: its lit share,
            // the step at n·l = 0 box-filtered.
            let lit = turn.and_then(|(w, inv_len, slant, n_dot_d)| {
                // n·l runs n·l ± |c_l| w across the footprint: filtered only
                // where that band holds the terminator (n·d's rate then too).
                let c_l = obj.footprint_gradient(inv_len, n, d, slant, l).scale(w);
                if n_dot_l.mul(n_dot_l) >= c_l.dot_inline(c_l) {
                    return None;
                }
                let band = S::length3(c_l.to_array());
                let c_d = obj.footprint_gradient(inv_len, n, d, slant, d).scale(w);
                Some(lit_share(n_dot_l, band, c_l.dot_inline(c_d).div(band), n_dot_d))
            });
            let lit = match lit {
                None if n_dot_l <= S::ZERO => continue,
                Some(share) if share <= S::ZERO => continue,
                Some(share) if share >= S::ONE => None,
                lit => lit,
            };
            // Below the terminator (only within the band gets here) P stands for
            // the lit part of its footprint, whose shadow rays leave the lit
            // side: its own convex surface is skipped in every type (f32 met it,
            // Q16.16 not).
            let own = if n_dot_l <= S::ZERO && outside { Some(i) } else { own };
            // The segment from just above P to the light itself (SPEC: "a light
            // whose segment from P is blocked"): along P's own vector from
            // p_shadow it ended at light + n ε, past a surface 5e-4 behind the
            // light in some pixels and not others (seed 29172). Every type
            // (f32, float64's reference) casts the same segment; the micro:bit
            // (no retakes, no flash) P's own vector from p_shadow, as before.
            let blocked = self.shadows
                && if self.exact_retakes() {
                    self.shadowed_to(p_shadow, light.position, S::HIT_EPSILON, own, from)
                } else {
                    self.shadowed(p_shadow, l, to_light, dist, S::HIT_EPSILON, own, from)
                };
            if blocked {
                continue;
            }
            let r = n.scale(n_dot_l.add(n_dot_l)) - l;
            let r_dot_v = r.dot_inline(v).max(S::ZERO);
            let diffuse = kd.scale(n_dot_l.max(S::ZERO));
            let highlight = r_dot_v.powf(m.shine);
            let specular = m.ks.scale(lit.map_or(highlight, |lit| highlight.mul(lit)));
            colour = colour + (diffuse + specular).hadamard(light.intensity);
        }
        (colour, Some((i, hit.t)))
    }
}

/// The lit share of a footprint across which n·l runs `n_dot_l` + u `band`
/// (`band` ≥ 0) and n·d runs `n_dot_d` + u `band_d` for u in [−1, 1]: the
/// step at n·l = 0 box-filtered over the part still facing the ray (n·d <
/// 0). Past the silhouette the footprint would be the hidden side, lit or
/// not (seed 10410: a dark cone lit from behind, +3.5 levels without it).
fn lit_share<S: Scalar>(n_dot_l: S, band: S, band_d: S, n_dot_d: S) -> S {
    if band <= S::ZERO {
        return if n_dot_l > S::ZERO { S::ONE } else { S::ZERO };
    }
    let u_lit = if n_dot_l.abs() < band {
        n_dot_l.neg().div(band)
    } else if n_dot_l > S::ZERO {
        S::ONE.neg()
    } else {
        S::ONE
    };
    // The facing window: n·d + u band_d < 0 (n·d ≤ 0).
    let far = n_dot_d.neg();
    let hi = if band_d > far { far.div(band_d) } else { S::ONE };
    let lo = if band_d.neg() > far {
        far.div(band_d)
    } else {
        S::ONE.neg()
    };
    hi.sub(u_lit.max(lo)).max(S::ZERO).div(hi.sub(lo))
}

#[cfg(test)]
mod tests {
    use super::lit_share;
    use crate::number::Scalar;
    use fixed::types::I16F16;

    /// The share against counting: u on a fine grid of [−1, 1], lit where
    /// n·l > 0, counted where n·d < 0; in f32 and Q16.16.
    #[test]
    fn lit_share_counts_the_lit_part_of_what_faces_the_ray() {
        fn share<S: Scalar>(v: [f64; 4]) -> f64 {
            lit_share(
                S::from_f64(v[0]),
                S::from_f64(v[1]),
                S::from_f64(v[2]),
                S::from_f64(v[3]),
            )
            .to_f64()
        }
        let mut u = crate::test_rng::unit_f64(0x11f5_4a2e);
        for case in 0..4000 {
            let (n_dot_l, band) = (2.0 * u() - 1.0, 2.0 * u() * u());
            let (band_d, n_dot_d) = (4.0 * u() - 2.0, -u());
            let steps = 20_000;
            let (mut seen, mut lit) = (0u32, 0u32);
            for k in 0..steps {
                let x = -1.0 + 2.0 * (k as f64 + 0.5) / steps as f64;
                if n_dot_d + x * band_d < 0.0 {
                    seen += 1;
                    lit += (n_dot_l + x * band > 0.0) as u32;
                }
            }
            let want = lit as f64 / seen as f64;
            let v = [n_dot_l, band, band_d, n_dot_d];
            let (a, b) = (share::<f32>(v), share::<I16F16>(v));
            assert!((a - want).abs() < 1e-3, "case {case} {v:?}: f32 {a}, counted {want}");
            assert!((b - want).abs() < 2e-3, "case {case} {v:?}: Q16.16 {b}, counted {want}");
        }
        // No band: the sharp step.
        assert_eq!(share::<f32>([0.2, 0.0, 0.5, -0.5]), 1.0);
        assert_eq!(share::<I16F16>([-0.2, 0.0, 0.5, -0.5]), 0.0);
    }
}
