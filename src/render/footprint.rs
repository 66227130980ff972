//! Where on the film a bright object can be seen through *some* part of the
//! lens: the pixels whose adaptive pilot may miss it.
//!
//! A pixel's lens rays all pass through its point in focus F; at depth z they
//! fill a disc of radius |1 − z/z_f|·a around (z/z_f)·F, a the lens radius
//! (a polygonal opening lies inside that circle). An object's bounding sphere
//! (centre C at depth d, radius ρ) can be reached only if, at some depth in
//! d ± ρ, that disc comes within ρ of C. For every pixel this is a disc on
//! the film around C's pinhole image, of radius R·N/d with
//! R = ρ + |1 − d/z_f|·a + (ρ/z_f)(|F|max + a): computed once at set-up
//! (f64), tested per pixel in integers.
//!
//! A stratified pilot of P samples sees the lens in P cells of equal area:
//! an object reaching the pixel through a smaller part may be missed by all
//! of them, and if it is brighter than white the miss is a large error (a
//! lamp 15 times white through 1/32 of the lens is 120 levels). So a pixel
//! in the footprint of an object that can shine more than [`BRIGHT`] times
//! white takes all its samples.

use crate::number::Scalar;
use crate::scene::Scene;

/// Objects whose brightest possible colour (ambient plus every light at full
/// diffuse and specular strength; for a plane, only the lights on the lens's
/// side of it, as shading skips a light behind the surface) exceeds this
/// many times white are bright:
/// lamps. Lit surfaces of ordinary materials stay below it (Program 1's gold
/// sphere bounds at 3.7 under its three lights, its floor at 2.6), and a
/// pilot that misses one through less than 1/16 of the lens errs by less than
/// 4 · 255 / 16 levels there: the variance rule handles them.
pub const BRIGHT: f64 = 4.0;

/// Most bright objects tracked; with more, every pixel counts as at risk.
pub const MAX_BRIGHT: usize = 8;

/// A bright object's footprint: a disc of pixels, in half-pixel units
/// (pixel (c, r) is at (2c + 1, 2r + 1)).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
struct Spot {
    col2: i32,
    row2: i32,
    radius2: i32,
}

/// The footprints of a scene's bright objects for one camera and image size.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BrightFootprints {
    spots: heapless::Vec<Spot, MAX_BRIGHT>,
    /// A bright object straddles the lens plane, or there are too many.
    everywhere: bool,
    /// Bit i: object i is bright (see the scanline filter, [`crate::render::scanline`]).
    objects: u32,
    /// The brightest bright object's bound, in times white, rounded up (at
    /// most `u16::MAX`; 0 with none): how much farther out of focus than
    /// anything else a lamp must be for the scanline filter to mix across
    /// its bokeh's rim ([`crate::render::scanline`]).
    lamp: u16,
}

/// Coordinates are clamped here (half pixels): far beyond any image side.
const FAR: f64 = (1 << 20) as f64;

impl BrightFootprints {
    /// The footprints of `scene`'s bright objects at `cols` × `rows` pixels.
    /// Set-up only, in f64; none for a pinhole camera.
    pub fn new<S: Scalar>(scene: &Scene<S>, cols: u32, rows: u32) -> Self {
        let mut out = BrightFootprints {
            spots: heapless::Vec::new(),
            everywhere: false,
            objects: 0,
            lamp: 0,
        };
        let cam = &scene.camera;
        let a = cam.radius;
        if a.is_nan() || a <= 0.0 {
            return out;
        }
        let Some([u, v, n]) = crate::camera::basis(cam) else {
            return out;
        };
        let (cols, rows) = (cols.max(1) as f64, rows.max(1) as f64);
        let p = cam.width / cols;
        let (half_w, half_h) = (cam.width / 2.0, p * rows / 2.0);
        let big_n = cam.image_distance;
        let z_f = cam.focus_depth();
        let f_max = z_f / big_n * libm::sqrt(half_w * half_w + half_h * half_h);
        let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        let ambient = scene.ambient.to_f64();
        for (i, obj) in scene.objects.iter().enumerate() {
            let m = &obj.material;
            let (ka, kd, ks) = (m.ka.to_f64(), m.kd.to_f64(), m.ks.to_f64());
            // A plane is lit only by the lights on the lens's side of it (shading
            // skips a light behind the surface, and the surface faces the ray).
            let side = if obj.bound().is_none() {
                lens_side(scene, obj, [u, v], a)
            } else {
                None
            };
            let brightest = (0..3)
                .map(|k| {
                    let lights: f64 = scene
                        .lights
                        .iter()
                        .filter(|l| side.is_none_or(|s| obj.plane_height(l.position).to_f64() * s > 0.0))
                        .map(|l| l.intensity.to_f64()[k])
                        .sum();
                    ka[k] * ambient[k] + (kd[k] + ks[k]) * lights
                })
                .fold(0.0, f64::max);
            if brightest.is_nan() || brightest > BRIGHT {
                out.objects |= 1u32.checked_shl(i as u32).unwrap_or(0);
                // NaN and anything past u16 saturate: the filter never mixes across such a rim.
                let up = if brightest.is_nan() {
                    f64::INFINITY
                } else {
                    libm::ceil(brightest)
                };
                out.lamp = out.lamp.max(up.min(u16::MAX as f64) as u16);
                let Some((centre, rho)) = obj.bound() else {
                    // A bright plane is everywhere.
                    out.everywhere = true;
                    continue;
                };
                let (c, rho) = (centre.to_f64(), rho.to_f64());
                let w = [0, 1, 2].map(|k| c[k] - cam.lens_position[k]);
                let (cx, cy, d) = (dot(w, u), dot(w, v), -dot(w, n));
                if d + rho <= 0.0 {
                    continue; // Wholly behind the lens.
                }
                if d - rho <= 1e-6 * (1.0 + rho) || z_f.is_nan() || z_f <= 0.0 {
                    out.everywhere = true;
                    continue;
                }
                let r = rho + (1.0 - d / z_f).abs() * a + rho / z_f * (f_max + a);
                let k = big_n / d;
                let clamp = |x: f64| if x.is_finite() { x.clamp(-FAR, FAR) } else { FAR };
                let spot = Spot {
                    col2: clamp(2.0 * (cx * k + half_w) / p) as i32,
                    row2: clamp(2.0 * (half_h - cy * k) / p) as i32,
                    // Plus a pixel for the rounding of the centre.
                    radius2: clamp(2.0 * r * k / p + 2.0).abs() as i32,
                };
                if out.spots.push(spot).is_err() {
                    out.everywhere = true;
                }
            }
        }
        out
    }

    /// Whether a bright object may reach pixel (`col`, `row`) through part of the lens.
    #[inline]
    pub fn at_risk(&self, col: u32, row: u32) -> bool {
        if self.everywhere {
            return true;
        }
        let (c, r) = (2 * col.min(1 << 16) as i64 + 1, 2 * row.min(1 << 16) as i64 + 1);
        self.spots.iter().any(|s| {
            let (dc, dr) = (c - s.col2 as i64, r - s.row2 as i64);
            dc * dc + dr * dr <= s.radius2 as i64 * s.radius2 as i64
        })
    }

    /// The brightest lamp's bound in times white, rounded up (0 with no lamp).
    #[inline]
    pub fn lamp(&self) -> u16 {
        self.lamp
    }

    /// Whether object `i` is bright (a lamp: its brightest colour exceeds [`BRIGHT`]).
    #[inline]
    pub fn is_bright(&self, i: usize) -> bool {
        (self.objects >> (i & 31)) & 1 == 1
    }

    /// Whether the scene has no bright object in front of the lens.
    pub fn is_empty(&self) -> bool {
        self.spots.is_empty() && !self.everywhere
    }
}

/// The sign of plane `obj`'s height over the whole lens (the disc of radius
/// `a` across `uv` around the lens centre), or `None` where it straddles it.
fn lens_side<S: Scalar>(scene: &Scene<S>, obj: &crate::scene::Object<S>, uv: [[f64; 3]; 2], a: f64) -> Option<f64> {
    let e = scene.camera.lens_position;
    let mut sign = None;
    // The corners of the square around the disc: a height (affine) that keeps
    // its sign on them keeps it on the disc.
    for (su, sv) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        let p = [0, 1, 2].map(|k| e[k] + a * (su * uv[0][k] + sv * uv[1][k]));
        let h = obj
            .plane_height(crate::geometry::vec3::Vec3::new(
                S::from_f64(p[0]),
                S::from_f64(p[1]),
                S::from_f64(p[2]),
            ))
            .to_f64();
        let s = if h > 0.0 {
            1.0
        } else if h < 0.0 {
            -1.0
        } else {
            return None;
        };
        if sign.is_some_and(|x| x != s) {
            return None;
        }
        sign = Some(s);
    }
    sign
}

impl crate::bytes::Field for Spot {
    crate::bytes::baked_fields!(Spot { col2, row2, radius2 }, check(spot) {
        if spot.radius2 < 0 {
            return Err(crate::bytes::BakeError::OutOfRange("a bright footprint's radius is negative"));
        }
    });
}

impl crate::bytes::Field for BrightFootprints {
    crate::bytes::baked_fields!(BrightFootprints {
        spots,
        everywhere,
        objects,
        lamp
    });
}

impl BrightFootprints {
    /// No bright object: what an empty baked scene holds.
    pub(crate) fn blank() -> Self {
        <Self as crate::bytes::Field>::blank()
    }
}
