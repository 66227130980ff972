//! Helpers shared by the host tests: scene files, renders in both number types.

#![allow(dead_code)]

use std::path::PathBuf;

use lensray::{Scene, Shape, I16F16};
use lensray_host::{render_image, Image};

/// The repository's `scenes/` directory.
pub fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

/// The text of `scenes/NAME`.
pub fn scene_text(name: &str) -> String {
    let p = scenes_dir().join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Renders scene text in Q16.16 (`samples` overrides the scene's `point`).
pub fn render_fixed(text: &str, w: u32, h: u32, samples: Option<u32>) -> Image {
    let scene = Scene::<I16F16>::parse(text).unwrap_or_else(|e| panic!("{e}"));
    render_image(&scene, w, h, samples, &|| {})
}

/// Renders scene text with the f32 reference.
pub fn render_float(text: &str, w: u32, h: u32, samples: Option<u32>) -> Image {
    let scene = Scene::<f32>::parse(text).unwrap_or_else(|e| panic!("{e}"));
    render_image(&scene, w, h, samples, &|| {})
}

/// `round(255 · clamp(v, 0, 1))`, SPEC section 4's pixel value, in f64.
pub fn level(v: f64) -> f64 {
    (255.0 * v.clamp(0.0, 1.0)).round()
}

/// A seeded xorshift generator of uniform f64 in [0, 1) (the property tests').
pub fn rng(mut s: u64) -> impl FnMut() -> f64 {
    move || {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        (s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A ray aimed at a point from 20 to 120 away in a random direction, its
/// origin in Q16.16, to be slid one Q16.16 step at a time along a random
/// axis across a boundary near that point (the property tests' rays).
pub struct SteppedRay {
    /// The unit direction from the point back to the origin, in f64.
    pub back: [f64; 3],
    /// The ray's direction, rounded to Q16.16 and normalised.
    pub d: lensray::Vec3<I16F16>,
    /// `d` in f64.
    pub df: [f64; 3],
    base: [I16F16; 3],
    axis: usize,
}

impl SteppedRay {
    /// Draws the direction (three numbers), the distance and the axis, in that order.
    pub fn new(at: [f64; 3], r: &mut impl FnMut() -> f64) -> Self {
        let v = [r() - 0.5, r() - 0.5, r() - 0.5];
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let back = v.map(|x| x / l);
        let dist = 20.0 + 100.0 * r();
        let d = lensray::Vec3::<I16F16>::from_f64(back.map(|x| -x)).normalize();
        let df = d.to_f64();
        let axis = (r() * 3.0) as usize;
        let base = lensray::Vec3::<I16F16>::from_f64([0, 1, 2].map(|i| at[i] + back[i] * dist)).to_array();
        SteppedRay {
            back,
            d,
            df,
            base,
            axis,
        }
    }

    /// The origin moved `k` Q16.16 steps along the axis.
    pub fn origin(&self, k: i64) -> [I16F16; 3] {
        let mut o = self.base;
        o[self.axis] = I16F16::from_bits(o[self.axis].to_bits() + k as i32);
        o
    }
}

/// How far the object's stored rows put the world point `w` from where
/// f64's map puts it, per object axis: each row holds its entries to
/// 2^-shift and its translation to 2^-(shift + 16), `shift` the largest up
/// to 30 that keeps the entries within 2^30 and the translation within 2^60
/// (`Kernels::row_from_f64`: 30 significant bits).
pub fn stored_rows_delta(o64: &lensray_host::reference64::Object64, w: [f64; 3]) -> [f64; 3] {
    o64.to_object.0.map(|r| {
        let big = r[..3].iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let mut shift = 30;
        while shift > 0
            && (big * 2f64.powi(shift) > 2f64.powi(30) || r[3].abs() * 2f64.powi(shift + 16) > 2f64.powi(60))
        {
            shift -= 1;
        }
        let stored = |x: f64, s: i32| (x * 2f64.powi(s)).round() / 2f64.powi(s) - x;
        (0..3).map(|k| stored(r[k], shift) * w[k]).sum::<f64>() + stored(r[3], shift + 16)
    })
}

/// A random placement as scene lines: scaled 0.2 to 0.2 + `big` per axis,
/// turned twice about random axes, anywhere within 30 (draws nine numbers).
pub fn random_placement(r: &mut impl FnMut() -> f64, big: f64) -> String {
    let s = [0, 1, 2].map(|_| 0.2 + big * r());
    let names = ["x", "y", "z"];
    let (ax, ang) = (names[(r() * 3.0) as usize], r() * 360.0);
    let (ax2, ang2) = (names[(r() * 3.0) as usize], r() * 360.0);
    let t = [0, 1, 2].map(|_| (r() - 0.5) * 60.0);
    format!(
        "scale {:.4} {:.4} {:.4}\nrotate {ax} {ang:.4}\nrotate {ax2} {ang2:.4}\ntranslate {:.4} {:.4} {:.4}\n",
        s[0], s[1], s[2], t[0], t[1], t[2]
    )
}

/// Every shape, for the property tests' random pairs.
pub const SHAPES: [Shape; 5] = [Shape::Sphere, Shape::Cube, Shape::Cylinder, Shape::Cone, Shape::Plane];

/// An object's statements: scaled 0.2 to 1.5 per axis, turned twice, moved by `t`.
pub fn object_text(shape: Shape, (s, turns): ([f64; 3], [(usize, f64); 2]), t: [f64; 3]) -> String {
    let names = ["x", "y", "z"];
    format!(
        "object {}\ntotal_transformation 4\nscale {} {} {}\nrotate {} {}\nrotate {} {}\ntranslate {} {} {}\n",
        shape.name(),
        s[0],
        s[1],
        s[2],
        names[turns[0].0],
        turns[0].1,
        names[turns[1].0],
        turns[1].1,
        t[0],
        t[1],
        t[2]
    )
}

/// `v` over its length.
pub fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / l)
}

/// A point on the surface of the scene's only object: the hit of a ray from
/// 10 away aimed within 0.3 of its centre `c` (`None` for a miss).
pub fn surface_point(
    s64: &lensray_host::reference64::Scene64,
    c: [f64; 3],
    r: &mut impl FnMut() -> f64,
) -> Option<[f64; 3]> {
    let u = unit([r() - 0.5, r() - 0.5, r() - 0.5]);
    let aim = [0, 1, 2].map(|i| c[i] + 0.3 * (r() - 0.5));
    let o = [0, 1, 2].map(|i| aim[i] + 10.0 * u[i]);
    let d = unit([0, 1, 2].map(|i| aim[i] - o[i]));
    let h = s64.objects[0].hit(o, d, 1e-9, f64::INFINITY)?;
    Some([0, 1, 2].map(|i| o[i] + h.t * d[i]))
}

/// Pixel (`col`, `row`)'s first `n` stratified lens points on `aperture`
/// (Q1.15), as the renderer draws them, written out from the sampler's
/// documentation (src/camera/sampler.rs, src/camera/lfsr.rs; the library
/// keeps its sampler private): the base-2 (0,2)-sequence (van der Corput,
/// and Sobol's second dimension), shifted by two 16-bit draws of the
/// pixel's register and jittered below its 10th bit by one fresh draw a
/// point, mapped onto the aperture by [`lensray::Aperture::map_q16`].
pub fn stratified_lens_points(col: u32, row: u32, n: u32, aperture: &lensray::Aperture) -> Vec<(i32, i32)> {
    // The pixel's 32-bit Galois register (x³² + x²² + x² + x + 1), seeded by a
    // murmur3-style hash of the pixel (its pass 0); 16 fresh bits a draw
    // after 32 clocks.
    let mut h = col.wrapping_mul(0x9E37_79B1) ^ row.wrapping_mul(0x85EB_CA77);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7FEB_352D);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846C_A68B);
    h ^= h >> 16;
    let mut state = h.max(1);
    let mut draw = || {
        for _ in 0..32 {
            let lsb = state & 1;
            state = (state >> 1) ^ (lsb.wrapping_neg() & 0x8020_0003);
        }
        (state >> 16) as u16
    };
    let shift = (draw(), draw());
    // The sequence's top 10 bits are kept; the 6 below are jitter.
    const NET: u16 = 0xFFC0;
    (0..n)
        .map(|i| {
            let u = (i as u16).reverse_bits();
            let (mut v, mut column) = (0u16, 0x8000u16);
            for bit in 0..16 {
                if (i >> bit) & 1 == 1 {
                    v ^= column;
                }
                column ^= column >> 1;
            }
            let j = draw();
            let (ju, jv) = (j & !NET, (j >> 6) & !NET);
            aperture.map_q16(((u ^ shift.0) & NET) | ju, ((v ^ shift.1) & NET) | jv)
        })
        .collect()
}
