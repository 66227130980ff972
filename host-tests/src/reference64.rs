//! An independent float64 evaluation of a scene's pinhole pixels: SPEC's
//! camera, shapes, checker, shadows and Phong shading from the exact scene
//! description, written apart from the renderer (no `Scalar`, no re-origin,
//! no precise directions). It tells which number type is right where
//! Q16.16 and f32 disagree, and by how much the pixel's decisions clear
//! their boundaries (the `margin`s, in object-space units).

use crate::mat34::Mat34;
use lensray::{CameraParams, DEFAULT_MATERIAL, MATERIALS};
use lensray::{Scene, Shape};

type V = [f64; 3];

fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: V, k: f64) -> V {
    a.map(|x| x * k)
}
fn unit(a: V) -> V {
    scale(a, 1.0 / dot(a, a).sqrt())
}

/// One object of the scene, exactly as written.
#[derive(Clone, Debug)]
pub struct Object64 {
    /// The shape.
    pub shape: Shape,
    /// Object → world.
    pub to_world: Mat34,
    /// World → object.
    pub to_object: Mat34,
    ka: V,
    kd: V,
    ks: V,
    shine: f64,
    texture: f64,
}

/// A hit in f64: world distance, object-space point and normal, and the
/// margin of the decision that made it (object units; see [`Object64::hit`]).
#[derive(Copy, Clone, Debug)]
pub struct Hit64 {
    /// World distance along the unit ray.
    pub t: f64,
    /// Object-space point (on the face for flat faces).
    pub p: V,
    /// Object-space outward normal.
    pub n: V,
    /// Which face or part: 0..=2 cube axis, 3 side, 4 cap, 5 sphere, 6 plane.
    pub part: u8,
}

/// How close a ray passes to changing its decision on one object: the
/// smallest object-space distance, over the boundaries that decide whether
/// and where it hits (a sphere's rim, a cube's edges, a side's ends, a cap's
/// rim). Positive: hits; negative: misses.
#[derive(Copy, Clone, Debug)]
pub struct Margin {
    /// Signed distance of the hit/miss decision from its boundary.
    pub hit: f64,
    /// Distance of the choice of face (cube: between the two nearest slabs;
    /// cylinder/cone: side against cap), `INFINITY` where there is none.
    pub face: f64,
}

impl Object64 {
    /// The nearest hit of `o + t d` (unit `d`, world) with `t_min < t < t_max`.
    pub fn hit(&self, o: V, d: V, t_min: f64, t_max: f64) -> Option<Hit64> {
        let (lo, ld) = (self.to_object.apply(o, true), self.to_object.apply(d, false));
        let ok = |t: f64| t > t_min && t < t_max;
        let at = |t: f64| add(lo, scale(ld, t));
        match self.shape {
            Shape::Plane => {
                let t = -lo[2] / ld[2];
                (ld[2] != 0.0 && ok(t)).then(|| {
                    let p = at(t);
                    Hit64 {
                        t,
                        p: [p[0], p[1], 0.0],
                        n: [0.0, 0.0, 1.0],
                        part: 6,
                    }
                })
            }
            Shape::Sphere => {
                let (a, b, c) = (dot(ld, ld), dot(lo, ld), dot(lo, lo) - 1.0);
                let disc = b * b - a * c;
                if disc < 0.0 {
                    return None;
                }
                let h = disc.sqrt();
                [(-b - h) / a, (-b + h) / a]
                    .into_iter()
                    .find(|&t| ok(t))
                    .map(|t| Hit64 {
                        t,
                        p: at(t),
                        n: at(t),
                        part: 5,
                    })
            }
            Shape::Cube => {
                let (near, far, axis_n, axis_f) = slabs(lo, ld)?;
                if near > far {
                    return None;
                }
                let (t, axis, out) = if ok(near) {
                    (near, axis_n, ld[axis_n] < 0.0)
                } else if ok(far) {
                    (far, axis_f, ld[axis_f] >= 0.0)
                } else {
                    return None;
                };
                let mut p = at(t);
                let s = if out { 1.0 } else { -1.0 };
                p[axis] = s;
                let mut n = [0.0; 3];
                n[axis] = s;
                Some(Hit64 {
                    t,
                    p,
                    n,
                    part: axis as u8,
                })
            }
            Shape::Cylinder | Shape::Cone => {
                let cone = self.shape == Shape::Cone;
                let mut best: Option<Hit64> = None;
                let mut take = |h: Hit64| {
                    if best.is_none_or(|b| h.t < b.t) {
                        best = Some(h);
                    }
                };
                for t in side_roots(lo, ld, cone) {
                    let p = at(t);
                    if ok(t) && (-1.0..=1.0).contains(&p[1]) {
                        let n = if cone {
                            [p[0], 0.25 * (1.0 - p[1]), p[2]]
                        } else {
                            [p[0], 0.0, p[2]]
                        };
                        take(Hit64 { t, p, n, part: 3 });
                    }
                }
                let caps: &[f64] = if cone { &[-1.0] } else { &[1.0, -1.0] };
                for &y in caps {
                    let t = (y - lo[1]) / ld[1];
                    let p = at(t);
                    if ld[1] != 0.0 && ok(t) && p[0] * p[0] + p[2] * p[2] <= 1.0 {
                        take(Hit64 {
                            t,
                            p: [p[0], y, p[2]],
                            n: [0.0, y, 0.0],
                            part: 4,
                        });
                    }
                }
                best
            }
        }
    }

    /// The margins of the ray `o + t d` (unit `d`) on this object (bounded
    /// shapes; the plane's is its distance along z at t_max, never near).
    pub fn margin(&self, o: V, d: V) -> Margin {
        let (lo, ld) = (self.to_object.apply(o, true), self.to_object.apply(d, false));
        let len = dot(ld, ld).sqrt();
        let du = scale(ld, 1.0 / len);
        // The ray's closest approach to the origin's axis lines, in object units.
        let perp = |mask: V| {
            let (o2, d2) = (
                [lo[0] * mask[0], lo[1] * mask[1], lo[2] * mask[2]],
                [du[0] * mask[0], du[1] * mask[1], du[2] * mask[2]],
            );
            let dd = dot(d2, d2);
            let tc = if dd > 0.0 { -dot(o2, d2) / dd } else { 0.0 };
            (dot(add(o2, scale(d2, tc)), add(o2, scale(d2, tc))).sqrt(), tc)
        };
        match self.shape {
            Shape::Plane => Margin {
                hit: f64::INFINITY,
                face: f64::INFINITY,
            },
            Shape::Sphere => Margin {
                hit: 1.0 - perp([1.0; 3]).0,
                face: f64::INFINITY,
            },
            Shape::Cube => {
                let Some((near, far, _, _)) = slabs(lo, du) else {
                    return Margin {
                        hit: -1.0,
                        face: f64::INFINITY,
                    };
                };
                // Entry times per axis: the gap between the largest two.
                let mut entry: Vec<f64> = (0..3)
                    .filter(|&i| du[i] != 0.0)
                    .map(|i| {
                        let (a, b) = ((-1.0 - lo[i]) / du[i], (1.0 - lo[i]) / du[i]);
                        a.min(b)
                    })
                    .collect();
                entry.sort_by(f64::total_cmp);
                let face = if entry.len() >= 2 {
                    entry[entry.len() - 1] - entry[entry.len() - 2]
                } else {
                    f64::INFINITY
                };
                Margin { hit: far - near, face }
            }
            Shape::Cylinder | Shape::Cone => {
                let cone = self.shape == Shape::Cone;
                // Side tangency (cylinder: distance from the axis), and each
                // root's and cap hit's distance from the rim y = ±1 or r = 1.
                let mut hit = if cone {
                    f64::INFINITY
                } else {
                    1.0 - perp([1.0, 0.0, 1.0]).0
                };
                let mut face = f64::INFINITY;
                for t in side_roots(lo, du, cone) {
                    let y = lo[1] + du[1] * t;
                    face = face.min((1.0 - y.abs()).abs());
                }
                for y in [1.0, -1.0] {
                    if du[1] != 0.0 {
                        let t = (y - lo[1]) / du[1];
                        let (x, z) = (lo[0] + du[0] * t, lo[2] + du[2] * t);
                        face = face.min((1.0 - (x * x + z * z).sqrt()).abs());
                    }
                }
                if cone {
                    let (a, b, c) = cone_abc(lo, du);
                    hit = (b * b - a * c) / (b.abs() + 1.0);
                }
                Margin { hit, face }
            }
        }
    }

    fn world_normal(&self, n: V) -> V {
        unit(self.to_object.linear_transpose().apply(n, false))
    }

    /// Whether the checker darkens the object-space point `p`'s square.
    pub fn dark(&self, p: V) -> bool {
        self.texture > 0.0 && p.iter().map(|x| (x / self.texture).floor() as i64).sum::<i64>() & 1 == 1
    }
}

/// A cube's slabs along `o + t d`: (entry, exit, entry axis, exit axis), or
/// `None` when the ray runs parallel outside a slab.
fn slabs(o: V, d: V) -> Option<(f64, f64, usize, usize)> {
    let (mut near, mut far, mut an, mut af) = (f64::NEG_INFINITY, f64::INFINITY, 0, 0);
    for i in 0..3 {
        if d[i] == 0.0 {
            if o[i].abs() > 1.0 {
                return None;
            }
            continue;
        }
        let (a, b) = ((-1.0 - o[i]) / d[i], (1.0 - o[i]) / d[i]);
        let (t1, t2) = (a.min(b), a.max(b));
        if t1 > near {
            near = t1;
            an = i;
        }
        if t2 < far {
            far = t2;
            af = i;
        }
    }
    Some((near, far, an, af))
}

fn cone_abc(o: V, d: V) -> (f64, f64, f64) {
    let w0 = 1.0 - o[1];
    (
        d[0] * d[0] + d[2] * d[2] - 0.25 * d[1] * d[1],
        o[0] * d[0] + o[2] * d[2] + 0.25 * w0 * d[1],
        o[0] * o[0] + o[2] * o[2] - 0.25 * w0 * w0,
    )
}

/// The side quadric's real roots along `o + t d`.
fn side_roots(o: V, d: V, cone: bool) -> Vec<f64> {
    let (a, b, c) = if cone {
        cone_abc(o, d)
    } else {
        (
            d[0] * d[0] + d[2] * d[2],
            o[0] * d[0] + o[2] * d[2],
            o[0] * o[0] + o[2] * o[2] - 1.0,
        )
    };
    if a == 0.0 {
        return if b != 0.0 { vec![-c / (2.0 * b)] } else { vec![] };
    }
    let disc = b * b - a * c;
    if disc < 0.0 {
        return vec![];
    }
    let h = disc.sqrt();
    let q = if b >= 0.0 { -(b + h) } else { h - b };
    if q == 0.0 {
        return vec![0.0];
    }
    vec![q / a, c / q]
}

/// A scene in f64.
#[derive(Clone, Debug)]
pub struct Scene64 {
    /// The camera statements.
    pub camera: CameraParams,
    /// The objects, in file order.
    pub objects: Vec<Object64>,
    lights: Vec<(V, V)>,
    ambient: V,
    background: V,
    /// Whether shadow rays are cast.
    pub shadows: bool,
}

/// What one light does at a pixel's hit in f64.
#[derive(Clone, Debug)]
pub struct LightUse {
    /// Whether the light is behind the surface.
    pub behind: bool,
    /// The objects on the shadow ray, with their margins (the blocker's
    /// positive; a near miss's negative and small).
    pub blockers: Vec<(usize, Margin, bool)>,
}

/// A pinhole pixel in f64: its colour (0..=255, unrounded) and hit.
#[derive(Clone, Debug)]
pub struct Pixel64 {
    /// Colour in levels, unrounded and unclamped above.
    pub rgb: V,
    /// The object hit and the hit.
    pub hit: Option<(usize, Hit64)>,
    /// Each object's margins along the camera ray.
    pub margins: Vec<Margin>,
    /// Each light's use.
    pub lights: Vec<LightUse>,
}

impl Scene64 {
    /// Reads a scene's text (valid: it must parse).
    ///
    /// # Panics
    ///
    /// If the text does not parse.
    pub fn parse(text: &str) -> Scene64 {
        let parsed = Scene::<f32>::parse(text).expect("the scene parses");
        let mut s = Scene64 {
            camera: parsed.camera,
            objects: Vec::new(),
            lights: Vec::new(),
            ambient: [0.0; 3],
            background: [0.0; 3],
            shadows: false,
        };
        let num = |x: &str| x.parse::<f64>().expect("a number");
        for line in text.lines() {
            let line = line.split('#').next().unwrap_or("");
            let w: Vec<&str> = line.split_whitespace().collect();
            let Some(&k) = w.first() else { continue };
            let three = || [num(w[1]), num(w[2]), num(w[3])];
            let obj = s.objects.last_mut();
            match k {
                "object" => {
                    let shape = Shape::ALL.iter().find(|x| x.0 == w[1]).expect("shape").1;
                    let (_, ka, kd, ks, shine) = if w.len() > 2 {
                        *MATERIALS.iter().find(|m| m.0 == w[2]).expect("material")
                    } else {
                        DEFAULT_MATERIAL
                    };
                    s.objects.push(Object64 {
                        shape,
                        to_world: Mat34::IDENTITY,
                        to_object: Mat34::IDENTITY,
                        ka,
                        kd,
                        ks,
                        shine,
                        texture: 0.0,
                    });
                }
                "Ka" => obj.expect("object").ka = three(),
                "Kd" => obj.expect("object").kd = three(),
                "Ks" => obj.expect("object").ks = three(),
                "shine" => obj.expect("object").shine = num(w[1]),
                "texture" => obj.expect("object").texture = num(w[1]),
                "scale" | "translate" | "rotate" => {
                    let m = match k {
                        "scale" => Mat34::scale(three()),
                        "translate" => Mat34::translate(three()),
                        _ => Mat34::rotate(
                            ["x", "y", "z"].iter().position(|&a| a == w[1]).expect("axis"),
                            num(w[2]),
                        ),
                    };
                    let o = obj.expect("object");
                    o.to_world = m.after(&o.to_world);
                }
                "light_position" => s.lights.push((three(), [1.0; 3])),
                "light_intensity" => s.lights.last_mut().expect("light").1 = three(),
                "ambient_light" => s.ambient = three(),
                "background" => s.background = three(),
                "shadows" => s.shadows = w[1] == "on",
                _ => {}
            }
        }
        for o in &mut s.objects {
            o.to_object = o.to_world.inverse().expect("invertible");
        }
        s
    }

    /// The camera's frame (u, v, n) of the scene format's section 3, in f64:
    /// n = −look/|look|, u = up × n normalised, v = n × u; `None` where `look`
    /// is zero or parallel to `up`.
    fn basis(p: &CameraParams) -> Option<[[f64; 3]; 3]> {
        let norm = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let l = norm(p.look);
        if l == 0.0 {
            return None;
        }
        let n = p.look.map(|x| -x / l);
        let c = cross(p.up, n);
        let lc = norm(c);
        if lc < 1e-9 * norm(p.up) {
            return None;
        }
        let u = c.map(|x| x / lc);
        Some([u, cross(n, u), n])
    }

    /// The unit direction of pixel (`col`, `row`)'s chief ray at `cols` × `rows`.
    pub fn chief_dir(&self, col: u32, row: u32, cols: u32, rows: u32) -> V {
        let p = &self.camera;
        let [u, v, n] = Self::basis(p).expect("basis");
        let pitch = p.width / cols as f64;
        let (hw, hh) = (p.width / 2.0, pitch * rows as f64 / 2.0);
        let (ci, cj) = ((2 * col + 1) as f64, (2 * row + 1) as f64);
        unit(core::array::from_fn(|m| {
            ci * u[m] * pitch / 2.0 - cj * v[m] * pitch / 2.0 + (-hw * u[m] + hh * v[m] - p.image_distance * n[m])
        }))
    }

    /// The nearest hit along `o + t d`.
    pub fn closest(&self, o: V, d: V, t_min: f64) -> Option<(usize, Hit64)> {
        let mut best: Option<(usize, Hit64)> = None;
        for (i, obj) in self.objects.iter().enumerate() {
            let t_max = best.map_or(f64::INFINITY, |b| b.1.t);
            if let Some(h) = obj.hit(o, d, t_min, t_max) {
                best = Some((i, h));
            }
        }
        best
    }

    /// Pinhole pixel (`col`, `row`) at `cols` × `rows`.
    pub fn pixel(&self, col: u32, row: u32, cols: u32, rows: u32) -> Pixel64 {
        let eps = 1.0 / 1024.0;
        let o = self.camera.lens_position;
        let d = self.chief_dir(col, row, cols, rows);
        let margins = self.objects.iter().map(|obj| obj.margin(o, d)).collect();
        let Some((i, h)) = self.closest(o, d, eps) else {
            return Pixel64 {
                rgb: scale(self.background, 255.0),
                hit: None,
                margins,
                lights: Vec::new(),
            };
        };
        let obj = &self.objects[i];
        let p = add(o, scale(d, h.t));
        let mut n = obj.world_normal(h.n);
        if dot(n, d) > 0.0 {
            n = scale(n, -1.0);
        }
        let q = if obj.dark(h.p) { 0.25 } else { 1.0 };
        let (ka, kd) = (scale(obj.ka, q), scale(obj.kd, q));
        let mut c: V = core::array::from_fn(|k| ka[k] * self.ambient[k]);
        let ps = if self.shadows { add(p, scale(n, eps)) } else { p };
        let mut lights = Vec::new();
        for &(lp, li) in &self.lights {
            let to = sub(lp, p);
            let mut use_ = LightUse {
                behind: dot(n, to) <= 0.0,
                blockers: Vec::new(),
            };
            if use_.behind {
                lights.push(use_);
                continue;
            }
            let dist = dot(to, to).sqrt();
            let l = scale(to, 1.0 / dist);
            let mut blocked = false;
            if self.shadows {
                // SPEC's segment from P to the light, its start lifted to just above P.
                let to_s = sub(lp, ps);
                let dist_s = dot(to_s, to_s).sqrt();
                let ls = scale(to_s, 1.0 / dist_s);
                for (j, other) in self.objects.iter().enumerate() {
                    if other.shape == Shape::Plane && j == i {
                        continue;
                    }
                    let b = other.hit(ps, ls, eps, dist_s).is_some();
                    let m = other.margin(ps, ls);
                    if b || (m.hit.abs() < 1e-3 && other.shape != Shape::Plane) {
                        use_.blockers.push((j, m, b));
                    }
                    blocked |= b;
                }
            }
            lights.push(use_);
            if blocked {
                continue;
            }
            let ndl = dot(n, l);
            let r = sub(scale(n, 2.0 * ndl), l);
            let rv = dot(r, scale(d, -1.0)).max(0.0);
            let spec = if obj.shine == 0.0 { 1.0 } else { rv.powf(obj.shine) };
            for k in 0..3 {
                c[k] += (kd[k] * ndl + obj.ks[k] * spec) * li[k];
            }
        }
        Pixel64 {
            rgb: scale(c, 255.0),
            hit: Some((i, h)),
            margins,
            lights,
        }
    }
}
