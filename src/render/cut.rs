//! A lens cut by a plane: parts of the aperture see the plane's two sides,
//! or past it, and a part's share of a pixel's stratified rays is not its
//! share of the lens.
//!
//! A plane within the lens's reach of its centre crosses the lens's disc
//! along a chord. With D the signed distance from the plane, a lens point
//! L's ray to the pixel's point in focus P meets the plane unless D(L) lies
//! between 0 and D(P): two lines across the lens, the chord D(L) = 0 (the
//! same for every pixel) and D(L) = D(P) (the pixel's own, within the lens
//! near the plane's horizon on the film), cut it into at most three parts
//! of shares known at set-up. A pilot of P stratified rays puts 0, 1 or 2
//! of them in a part of share f where fP is under 1, so the mean is off by
//! f times what the part sees, per ray too many or too few (seed 10123: a
//! floor 0.48 below a tilted lens of radius 1.16, 9 % of it beyond: pixels
//! at 8 rays 20 levels under or 36 over; seed 10014: a lamp plane through
//! the lens, its horizon's pixels up to 150 levels off). Each part's mean
//! weighed by its share (post-stratification) takes that count out of the
//! estimate; it changes nothing as the samples grow (the same mean in the
//! limit). A pixel whose first block of rays (its pilot, or every ray it
//! takes, at least 4) leaves a part of 1/256 of the lens or more without a
//! ray draws the block's last ray there instead (uniform over it, by
//! rejection from the pixel's register), for no ray more; a part left
//! without rays all the same drops out, the others weighed by their shares
//! of what was seen.
//!
//! D is σ here, in the lens sampler's own Q1.15 coordinates, tested in
//! integers from the plane taken on Q16.16's grid in both types (the same
//! decisions in Q16.16 and f32, and on the boards); the shares come from a table
//! of 64 bins across the chord's direction, counted on 65536 of the
//! sampler's own points.

use crate::camera::aperture::Aperture;
#[cfg(not(feature = "no-lens-cut"))]
use crate::camera::sampler::{PixelSamples, Sampler};
#[cfg(not(feature = "no-lens-cut"))]
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::render::parts::Shares;
#[cfg(not(feature = "no-lens-cut"))]
use crate::scene::shape::Shape;
use crate::scene::Scene;

/// Points of the sampler's sequence that measure the aperture's shares.
const SHARE_POINTS: u32 = 65536;

/// Bins of [`LensCut`]'s table of shares across the chord's direction.
pub const SHARE_BINS: usize = 64;

/// σ, the signed distance from the plane in 2⁻²⁹ of the lens's reach
/// across it, spans (−2³⁰, 2³⁰) over the aperture (the centre within
/// reach): each bin is 2²⁵ wide (64: the share across a disc is smooth,
/// linear within a bin to about 10⁻⁴; 256 bins cost the Cortex-M3 2 KB
/// more stack, the renderer being moved and copied whole).
#[cfg(not(feature = "no-lens-cut"))]
const BIN_SHIFT: u32 = 25;
const SIGMA_SPAN: i64 = 1 << 30;

/// Draws of the pixel's register that look for a point in a part of the
/// lens (a share f of the aperture: all miss with probability (1 − f)^128,
/// under 3 % from f = 1/36).
pub const FORCE_TRIES: u32 = 128;

/// The cut of a lens by a plane, as the renderer tests its rays against it.
///
/// A lens point L's ray to the pixel's point in focus P meets the plane
/// where L and P lie on its two sides, or on one side with L the farther
/// from it (the ray crosses after P): with D the signed distance from the
/// plane, where D(L) is not between 0 and D(P). So two lines across the
/// lens, D(L) = 0 (the chord) and D(L) = D(P) (the pixel's own, moving
/// across the frame), split it into at most three parts, each of which
/// sees its own side of the plane, or past it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LensCut {
    /// σ(x, y) = `line[0] x + line[1] y + line[2]` for a lens point (Q1.15):
    /// D(L) in 2⁻²⁹ of the lens's reach across the plane, positive beyond
    /// the chord (the side away from the centre).
    #[cfg(not(feature = "no-lens-cut"))]
    line: [i32; 3],
    /// σ of pixel (c, r)'s point in focus: `focus[0] + focus[1] (2c + 1) +
    /// focus[2] (2r + 1)`, saturating.
    #[cfg(not(feature = "no-lens-cut"))]
    focus: [i64; 3],
    /// The aperture's share (65536ths) where σ is below bin i's lower
    /// edge, −2³⁰ + i·2²⁵; all zero: no cut.
    #[cfg(not(feature = "no-lens-cut"))]
    table: [u32; SHARE_BINS + 1],
}

/// A pixel's parts of a cut lens: below both lines, between, above both.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct PixelCut {
    /// The lines' σ, the lesser first.
    bounds: [i32; 2],
    /// Each part's share of the aperture.
    pub(crate) shares: Shares,
}

impl LensCut {
    /// No cut.
    #[cfg(not(feature = "no-lens-cut"))]
    pub const NONE: LensCut = LensCut {
        line: [0; 3],
        focus: [0; 3],
        table: [0; SHARE_BINS + 1],
    };
    /// No cut (the only one without the weighing).
    #[cfg(feature = "no-lens-cut")]
    pub const NONE: LensCut = LensCut {};

    /// The cut of `scene`'s lens by its first plane that crosses the
    /// aperture, at `cols` × `rows` pixels, for the stratified sampler only
    /// (the independent one stays as it always was, the measure the floors
    /// compare with). Set-up only, in f64.
    #[cfg(feature = "no-lens-cut")]
    pub fn new<S: Scalar>(_scene: &Scene<S>, _aperture: &Aperture, _cols: u32, _rows: u32) -> Self {
        Self::NONE
    }

    /// See above.
    #[cfg(not(feature = "no-lens-cut"))]
    pub fn new<S: Scalar>(scene: &Scene<S>, aperture: &Aperture, cols: u32, rows: u32) -> Self {
        let cam = &scene.camera;
        if cam.sampler != Sampler::Stratified || cam.radius.is_nan() || cam.radius <= 0.0 || cols == 0 || rows == 0 {
            return Self::NONE;
        }
        let Some([u, v, n]) = crate::camera::basis(cam) else {
            return Self::NONE;
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for o in scene.objects.iter().filter(|o| o.shape == Shape::Plane) {
            // The plane is z = 0 in object space: D(X) = row · X + z0 of world → object.
            let t = o.world_to_object();
            // On Q16.16's grid, 2⁻¹⁶, whatever the type: Q16.16 and f32 then take
            // the same plane (but where the exact value lies within f32's
            // rounding of a half step) and so make the same decisions.
            let grid = |x: S| libm::round(x.to_f64() * 65536.0) / 65536.0;
            let row = [0, 1, 2].map(|j| grid(t.entry(2, j)));
            let z0 = grid(t.point_coord(2, Vec3::new(S::ZERO, S::ZERO, S::ZERO)));
            // At the lens point E + r (x u + y v), x and y on the unit disc.
            let centre = dot(row, cam.lens_position) + z0;
            let (along_u, along_v) = (cam.radius * dot(row, u), cam.radius * dot(row, v));
            let reach = libm::sqrt(along_u * along_u + along_v * along_v);
            if !(reach > 0.0 && libm::fabs(centre) < reach) {
                continue;
            }
            // σ = k D: positive beyond the chord; x, y in Q1.15.
            let k = if centre > 0.0 { -1.0 } else { 1.0 } * (1u64 << 29) as f64 / reach;
            let line = [
                libm::round(k * along_u / 32768.0) as i32,
                libm::round(k * along_v / 32768.0) as i32,
                libm::round(k * centre) as i32,
            ];
            // D(P) = D(E) + (z_f/N) row · (−N n + u_c u + v_r v), with
            // u_c = −W + (p/2)(2c + 1) and v_r = H − (p/2)(2r + 1).
            let z_f = cam.focus_depth();
            let focus = if z_f.is_finite() && z_f > 0.0 {
                let m = z_f / cam.image_distance;
                let half = cam.width / cols as f64 / 2.0;
                let (w, h) = (cam.width / 2.0, half * rows as f64);
                let (ru, rv) = (dot(row, u), dot(row, v));
                let held = |x: f64, most: f64| libm::round(x.clamp(-most, most)) as i64;
                [
                    held(
                        k * (centre - z_f * dot(row, n) + m * (-w * ru + h * rv)),
                        (1u64 << 61) as f64,
                    ),
                    held(k * m * half * ru, (1u64 << 45) as f64),
                    held(-k * m * half * rv, (1u64 << 45) as f64),
                ]
            } else {
                // No plane in focus: the pixel's line lies off the lens.
                [4 * SIGMA_SPAN, 0, 0]
            };
            let mut cut = LensCut {
                line,
                focus,
                table: [0; SHARE_BINS + 1],
            };
            let mut counts = [0u32; SHARE_BINS];
            let mut points = PixelSamples::new(Sampler::Stratified, 0, 0);
            for _ in 0..SHARE_POINTS {
                let bin = (cut.sigma(points.next(aperture)) as i64 + SIGMA_SPAN) >> BIN_SHIFT;
                counts[bin.clamp(0, SHARE_BINS as i64 - 1) as usize] += 1;
            }
            for (i, count) in counts.iter().enumerate() {
                cut.table[i + 1] = cut.table[i] + count;
            }
            let beyond = SHARE_POINTS - cut.below(0);
            if beyond > 0 && beyond < SHARE_POINTS {
                return cut;
            }
        }
        Self::NONE
    }

    /// Whether this lens has a cut.
    #[inline]
    pub fn is_cut(&self) -> bool {
        #[cfg(feature = "no-lens-cut")]
        return false;
        #[cfg(not(feature = "no-lens-cut"))]
        (self.table[SHARE_BINS] != 0)
    }

    /// The aperture's share beyond the chord, in 65536ths (0: no cut).
    pub fn share(&self) -> u32 {
        if self.is_cut() {
            SHARE_POINTS - self.below(0)
        } else {
            0
        }
    }

    /// σ of the lens point `p_lens` (Q1.15).
    #[inline]
    pub fn sigma(&self, p_lens: (i32, i32)) -> i32 {
        #[cfg(feature = "no-lens-cut")]
        let [a, b, c] = [0i32, 0, 0];
        #[cfg(not(feature = "no-lens-cut"))]
        let [a, b, c] = self.line;
        a.wrapping_mul(p_lens.0)
            .wrapping_add(b.wrapping_mul(p_lens.1))
            .wrapping_add(c)
    }

    /// The aperture's share (65536ths) where σ is at most `sigma`, from the
    /// table (linear within a bin).
    fn below(&self, sigma: i64) -> u32 {
        #[cfg(feature = "no-lens-cut")]
        return {
            let _ = sigma;
            0
        };
        #[cfg(not(feature = "no-lens-cut"))]
        {
            let t = (sigma + SIGMA_SPAN).clamp(0, 2 * SIGMA_SPAN - 1) as u64;
            let (i, frac) = ((t >> BIN_SHIFT) as usize, t & ((1 << BIN_SHIFT) - 1));
            let (lo, hi) = (self.table[i] as u64, self.table[i + 1] as u64);
            (lo + (((hi - lo) * frac) >> BIN_SHIFT)) as u32
        }
    }

    /// Pixel (`col`, `row`)'s parts of the lens.
    #[inline]
    pub fn pixel(&self, col: u32, row: u32) -> PixelCut {
        #[cfg(feature = "no-lens-cut")]
        let [f0, f1, f2] = [0i64; 3];
        #[cfg(not(feature = "no-lens-cut"))]
        let [f0, f1, f2] = self.focus;
        let (i, j) = (2 * col.min(1 << 14) as i64 + 1, 2 * row.min(1 << 14) as i64 + 1);
        let p = f0
            .saturating_add(f1.saturating_mul(i))
            .saturating_add(f2.saturating_mul(j))
            .clamp(-2 * SIGMA_SPAN + 1, 2 * SIGMA_SPAN - 1);
        let (lo, hi) = (p.min(0), p.max(0));
        let (a, b) = (self.below(lo), self.below(hi));
        PixelCut {
            bounds: [lo as i32, hi as i32],
            shares: Shares([a, b - a, SHARE_POINTS - b]),
        }
    }
}

impl PixelCut {
    /// The part of the lens point whose σ is `sigma`: 0, 1 or 2.
    #[inline]
    pub fn part(&self, sigma: i32) -> usize {
        (sigma > self.bounds[0]) as usize + (sigma > self.bounds[1]) as usize
    }
}

#[cfg(not(feature = "no-lens-cut"))]
impl crate::bytes::Field for LensCut {
    crate::bytes::baked_fields!(LensCut { line, focus, table }, check(cut) {
        // Shares that only grow, to 65536 or none at all.
        let end = cut.table[SHARE_BINS];
        if cut.table[0] != 0 || !(end == 0 || end == SHARE_POINTS) || cut.table.windows(2).any(|w| w[0] > w[1]) {
            return Err(crate::bytes::BakeError::OutOfRange("lens cut shares not rising from 0 to 65536"));
        }
    });
}

// Without the weighing the cut is read past (the format stays one): its
// bytes are 74 words (3 of the line, 6 of the focus's three i64, 65 of
// the table), read as such (one loop: the micro:bit's flash).
#[cfg(feature = "no-lens-cut")]
crate::bytes::read_past_field!(LensCut, BAKED_WORDS);

/// The words a baked cut takes (see the `Field` impls).
const BAKED_WORDS: usize = 3 + 6 + SHARE_BINS + 1;
#[cfg(not(feature = "no-lens-cut"))]
const _: () = assert!(
    BAKED_WORDS * 4
        == core::mem::size_of::<[i32; 3]>()
            + core::mem::size_of::<[i64; 3]>()
            + core::mem::size_of::<[u32; SHARE_BINS + 1]>()
);

#[cfg(test)]
mod tests {
    // Without the weighing there is no cut to test.
    #[cfg(not(feature = "no-lens-cut"))]
    mod weighed {
        use crate::camera::aperture::Aperture;
        use crate::camera::sampler::Sampler;
        use crate::render::cut::*;
        use crate::Scene;

        fn scene(extra: &str) -> Scene<f32> {
            let text = format!("radius 1\npoint 16\nlook 0 0 -1\nup 0 1 0\n{extra}");
            Scene::parse(&text).unwrap()
        }

        /// A unit lens in the z = 0 plane, cut by the plane y = d: the share
        /// beyond is the circular segment's, (acos d − d √(1 − d²)) / π.
        #[test]
        fn a_floor_through_the_lens_cuts_the_segment_beyond_it() {
            for d in [-0.7, -0.2, 0.0, 0.3, 0.9] {
                let s = scene(&format!("object plane\nrotate x -90\ntranslate 0 {d} 0\n"));
                let cut = LensCut::new(&s, &Aperture::ROUND, 64, 48);
                let ad = f64::abs(d);
                let want = (libm::acos(ad) - ad * libm::sqrt(1.0 - ad * ad)) / core::f64::consts::PI;
                let got = cut.share() as f64 / 65536.0;
                assert!((got - want).abs() < 2e-3, "d {d}: share {got} against {want}");
                // Beyond is the side away from the lens's centre (v is +y here).
                if d != 0.0 {
                    let far = if d > 0.0 { 32000 } else { -32000 };
                    assert!(cut.sigma((0, far)) > 0 && cut.sigma((0, -far)) <= 0, "d {d}");
                }
            }
        }

        #[test]
        fn planes_clear_of_the_lens_and_other_shapes_do_not_cut() {
            for extra in [
                "object plane\nrotate x -90\ntranslate 0 -1.01 0\n",
                // Parallel to the lens, behind it.
                "object plane\ntranslate 0 0 2\n",
                "object sphere\nscale 3 3 3\n",
            ] {
                assert!(
                    !LensCut::new(&scene(extra), &Aperture::ROUND, 64, 48).is_cut(),
                    "{extra}"
                );
            }
            // The independent sampler is left as it was.
            let mut s = scene("object plane\nrotate x -90\ntranslate 0 0.5 0\n");
            assert!(LensCut::new(&s, &Aperture::ROUND, 64, 48).is_cut());
            s.camera.sampler = Sampler::Independent;
            assert!(!LensCut::new(&s, &Aperture::ROUND, 64, 48).is_cut());
        }

        /// The middle part is exactly the lens points whose ray to the
        /// pixel's point in focus does not meet the plane (f64 geometry: a
        /// tilted plane through the lens, a tilted camera, every 7th pixel).
        #[test]
        fn the_middle_part_is_where_rays_miss_the_plane() {
            let text = "radius 0.8\npoint 16\nlook 0.2 -0.3 -1\nup 0 1 0\nfocal_length 3\nimage_distance 4\n\
                        object plane\nrotate x -70\nrotate y 20\ntranslate 0 -0.3 0\n";
            let s: Scene<f32> = Scene::parse(text).unwrap();
            let (cols, rows) = (64, 48);
            let cut = LensCut::new(&s, &Aperture::ROUND, cols, rows);
            assert!(cut.is_cut());
            let cam = &s.camera;
            let [u, v, n] = crate::camera::basis(cam).unwrap();
            // The plane in f64: the rotated z = 0 through (0, -0.3, 0).
            let (rx, ry) = ((-70f64).to_radians(), 20f64.to_radians());
            let normal = [ry.sin() * rx.cos(), -rx.sin(), ry.cos() * rx.cos()];
            let dist = |p: [f64; 3]| normal[0] * p[0] + normal[1] * (p[1] + 0.3) + normal[2] * p[2];
            let z_f = cam.focus_depth();
            let pitch = cam.width / cols as f64;
            let (mut checked, mut middle) = (0, 0);
            for r in (0..rows).step_by(7) {
                for c in (0..cols).step_by(7) {
                    let (uc, vr) = (
                        -cam.width / 2.0 + pitch * (c as f64 + 0.5),
                        pitch * rows as f64 / 2.0 - pitch * (r as f64 + 0.5),
                    );
                    let dir: [f64; 3] = core::array::from_fn(|m| -cam.image_distance * n[m] + uc * u[m] + vr * v[m]);
                    let p_focus: [f64; 3] = core::array::from_fn(|m| dir[m] * z_f / cam.image_distance);
                    let q = cut.pixel(c, r);
                    for k in 0..400 {
                        let (x, y) = ((k % 20) as f64 / 10.0 - 0.95, (k / 20) as f64 / 10.0 - 0.95);
                        if x * x + y * y > 0.99 {
                            continue;
                        }
                        let p_lens: [f64; 3] = core::array::from_fn(|m| cam.radius * (x * u[m] + y * v[m]));
                        let (dl, dp) = (dist(p_lens), dist(p_focus));
                        // Clear of either line by a little (the plane is rounded to f32).
                        if dl.abs() < 1e-3 || (dl - dp).abs() < 1e-3 {
                            continue;
                        }
                        let misses = dl * (dp - dl) > 0.0;
                        let sample = ((x * 32768.0) as i32, (y * 32768.0) as i32);
                        assert_eq!(
                            q.part(cut.sigma(sample)) == 1,
                            misses,
                            "pixel ({c}, {r}) lens ({x}, {y}): dl {dl} dp {dp} sigma {} {:?} {:?}",
                            cut.sigma(sample),
                            q,
                            cut.line
                        );
                        checked += 1;
                        middle += misses as u32;
                    }
                }
            }
            // Both kinds seen, many times.
            assert!(
                checked > 5000 && middle > 500 && checked - middle > 500,
                "{checked} {middle}"
            );
        }
    }
}
