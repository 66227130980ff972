//! A lens cut by a plane: the part of the aperture beyond the plane sees
//! something else (the plane's far side, or what lies past it) for every
//! pixel, and its share of a pixel's stratified rays is not its share of
//! the lens.
//!
//! A plane within the lens's radius of its centre crosses the lens's disc
//! along a chord. Beyond the chord, a share f of the aperture (known at
//! set-up) sees what the rest cannot. A pilot of P stratified rays puts 0,
//! 1 or 2 of them there where fP is under 1, so the mean is off by about
//! 255 f per ray too many or too few (seed 10123: a floor 0.48 below a lens
//! of radius 1.16, tilted, f = 9 %: pixels at 8 rays 20 levels under or 36
//! over). Weighing the rays beyond the chord by f and the others by 1 − f
//! (post-stratification) takes that count out of the estimate; it changes
//! nothing as the samples grow (both converge on the same mean).
//!
//! The chord is a line in the lens sampler's own Q1.15 coordinates, tested
//! in integers (the same decision in Q16.16 and f32, on the boards too), and
//! f is the share of 65536 of the sampler's own points beyond it.
//!
//! A pixel whose first block of rays (its pilot, or every ray it takes) has
//! none beyond the chord would fall back on the plain mean, off by f times
//! the difference (seed 10014: a lamp beyond the chord, 150 levels); its
//! block's last ray is then drawn beyond the chord instead (uniform there,
//! by rejection from the pixel's register), for no ray more: the other side
//! keeps the block's other points.

use crate::camera::aperture::Aperture;
#[cfg(not(feature = "no-lens-cut"))]
use crate::camera::sampler::{PixelSamples, Sampler};
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
#[cfg(not(feature = "no-lens-cut"))]
use crate::scene::shape::Shape;
use crate::scene::Scene;

/// The line's normal in units of 2⁻¹⁴: `a x + b y + c` stays within i32 for
/// any Q1.15 point (|a x| and |b y| under 2²⁹, |c| under 2²⁹ for a chord).
#[cfg(not(feature = "no-lens-cut"))]
const UNIT: f64 = 16384.0;

/// Points of the sampler's sequence that measure the share beyond a chord
/// (stratified: the share is off by a few 65536ths at most).
const SHARE_POINTS: u32 = 65536;

/// The fewest rays in a pixel's first block (its pilot, or all it takes)
/// for its last ray to be drawn beyond the cut where none of the others
/// fell there: with fewer, the lens's other side would lose too much of
/// its stratification.
pub const FORCE_MIN_BLOCK: u32 = 4;

/// Draws of the pixel's register that look for a point beyond the cut
/// (a share f of the aperture: all miss with probability (1 − f)^128,
/// under 3 % from f = 1/36).
pub const FORCE_TRIES: u32 = 128;

/// The cut of a lens by a plane, as the renderer tests its rays against it.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct LensCut {
    /// A lens point (Q1.15) `(x, y)` is beyond the chord where
    /// `line[0] x + line[1] y + line[2] > 0`.
    #[cfg(not(feature = "no-lens-cut"))]
    line: [i32; 3],
    /// The aperture's share beyond the chord, in 65536ths; 0: no cut.
    #[cfg(not(feature = "no-lens-cut"))]
    share: u32,
}

impl LensCut {
    /// No cut.
    #[cfg(not(feature = "no-lens-cut"))]
    pub const NONE: LensCut = LensCut { line: [0; 3], share: 0 };
    /// No cut (the only one without the weighing).
    #[cfg(feature = "no-lens-cut")]
    pub const NONE: LensCut = LensCut {};

    /// The cut of `scene`'s lens by its first plane that crosses the
    /// aperture (both sides holding some of the sampler's points), for the
    /// stratified sampler only (the independent one stays as it always was,
    /// the measure the floors compare with). Set-up only, in f64.
    #[cfg(feature = "no-lens-cut")]
    pub fn new<S: Scalar>(_scene: &Scene<S>, _aperture: &Aperture) -> Self {
        Self::NONE
    }

    /// See above.
    #[cfg(not(feature = "no-lens-cut"))]
    pub fn new<S: Scalar>(scene: &Scene<S>, aperture: &Aperture) -> Self {
        let cam = &scene.camera;
        if cam.sampler != Sampler::Stratified || cam.radius.is_nan() || cam.radius <= 0.0 {
            return Self::NONE;
        }
        let Some([u, v, _]) = crate::camera::basis(cam) else {
            return Self::NONE;
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for o in scene.objects.iter().filter(|o| o.shape == Shape::Plane) {
            // The plane is z = 0 in object space: z(X) = row · X + z0 of world → object.
            let t = o.world_to_object();
            let row = [0, 1, 2].map(|j| t.entry(2, j).to_f64());
            let z0 = t.point_coord(2, Vec3::new(S::ZERO, S::ZERO, S::ZERO)).to_f64();
            // At the lens point E + r (x u + y v), x and y on the unit disc.
            let centre = dot(row, cam.lens_position) + z0;
            let (along_u, along_v) = (cam.radius * dot(row, u), cam.radius * dot(row, v));
            let slope = libm::sqrt(along_u * along_u + along_v * along_v);
            if !(slope > 0.0 && libm::fabs(centre) < slope) {
                continue;
            }
            // Beyond: the side away from the centre; Q1.15 coordinates.
            let k = if centre > 0.0 { -UNIT } else { UNIT } / slope;
            let line = [
                libm::round(k * along_u) as i32,
                libm::round(k * along_v) as i32,
                libm::round(k * centre * 32768.0) as i32,
            ];
            let mut cut = LensCut { line, share: 0 };
            let mut points = PixelSamples::new(Sampler::Stratified, 0, 0);
            cut.share = (0..SHARE_POINTS)
                .map(|_| cut.beyond(points.next(aperture)) as u32)
                .sum();
            if cut.share > 0 && cut.share < SHARE_POINTS {
                return cut;
            }
        }
        Self::NONE
    }

    /// Whether this lens has a cut.
    #[inline]
    pub fn is_cut(&self) -> bool {
        self.share() != 0
    }

    /// The aperture's share beyond the chord, in 65536ths (0: no cut).
    #[inline]
    pub fn share(&self) -> u32 {
        #[cfg(feature = "no-lens-cut")]
        return 0;
        #[cfg(not(feature = "no-lens-cut"))]
        self.share
    }

    /// Whether the lens point `p_lens` (Q1.15) lies beyond the chord.
    #[inline]
    pub fn beyond(&self, p_lens: (i32, i32)) -> bool {
        #[cfg(feature = "no-lens-cut")]
        let [a, b, c] = [0, 0, (p_lens.0 & 0).wrapping_sub(1)];
        #[cfg(not(feature = "no-lens-cut"))]
        let [a, b, c] = self.line;
        a.wrapping_mul(p_lens.0)
            .wrapping_add(b.wrapping_mul(p_lens.1))
            .wrapping_add(c)
            > 0
    }

    /// The pixel's colour from the sums of its `n_beyond` rays beyond the
    /// chord and its `n_rest` others, each side weighed by its share of the
    /// lens; `None` where a side has no ray (the plain mean stands).
    #[inline]
    pub fn mean<S: Scalar>(
        &self,
        beyond: &[S::Acc; 3],
        n_beyond: u32,
        rest: &[S::Acc; 3],
        n_rest: u32,
    ) -> Option<Vec3<S>> {
        if n_beyond == 0 || n_rest == 0 {
            return None;
        }
        // 65536ths to Q1.15, held under 1 whatever a baked file said.
        let f = S::from_q15((self.share().min(SHARE_POINTS - 1) >> 1) as i32);
        let g = S::ONE.sub(f);
        let m = |i: usize| {
            S::acc_mean(beyond[i], n_beyond)
                .mul(f)
                .add(S::acc_mean(rest[i], n_rest).mul(g))
        };
        Some(Vec3::new(m(0), m(1), m(2)))
    }
}

// No range check: any share reads as under 65536 (see [`LensCut::mean`]).
#[cfg(not(feature = "no-lens-cut"))]
impl crate::bytes::Field for LensCut {
    crate::bytes::baked_fields!(LensCut { line, share });
}

/// Without the weighing the cut is read past (the format stays one).
#[cfg(feature = "no-lens-cut")]
impl crate::bytes::Field for LensCut {
    fn put(&self, w: &mut crate::bytes::Writer<'_>) {
        [0i32; 4].put(w);
    }
    fn take(&mut self, r: &mut crate::bytes::Reader<'_>) {
        [0i32; 4].take(r);
    }
    fn blank() -> Self {
        Self::NONE
    }
}

#[cfg(test)]
mod tests {
    // Without the weighing there is no cut to test.
    #[cfg(not(feature = "no-lens-cut"))]
    mod weighed {
        use crate::render::cut::*;

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
                let cut = LensCut::new(&s, &Aperture::ROUND);
                let ad = f64::abs(d);
                let want = (libm::acos(ad) - ad * libm::sqrt(1.0 - ad * ad)) / core::f64::consts::PI;
                let got = cut.share() as f64 / 65536.0;
                assert!((got - want).abs() < 2e-3, "d {d}: share {got} against {want}");
                // Beyond is the side away from the lens's centre (v is +y here).
                if d != 0.0 {
                    let far = if d > 0.0 { 32000 } else { -32000 };
                    assert!(cut.beyond((0, far)) && !cut.beyond((0, -far)), "d {d}");
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
                assert!(!LensCut::new(&scene(extra), &Aperture::ROUND).is_cut(), "{extra}");
            }
            // The independent sampler is left as it was.
            let mut s = scene("object plane\nrotate x -90\ntranslate 0 0.5 0\n");
            assert!(LensCut::new(&s, &Aperture::ROUND).is_cut());
            s.camera.sampler = Sampler::Independent;
            assert!(!LensCut::new(&s, &Aperture::ROUND).is_cut());
        }

        /// The weighed mean: each side's mean times its share.
        #[test]
        fn each_side_weighs_its_share() {
            let cut = LensCut {
                line: [0, 1, 0],
                share: 16384,
            };
            let acc = |v: f64| [v; 3];
            // Beyond: two rays of 1; the rest: six of 0.2. Plain mean 0.4; weighed 0.25 + 0.15.
            let m = cut.mean::<f32>(&acc(2.0), 2, &acc(1.2), 6).unwrap();
            assert!((m.x - 0.4).abs() < 1e-6 && (m.y - 0.4).abs() < 1e-6);
            let cut = LensCut {
                line: [0, 1, 0],
                share: 6554,
            };
            let m = cut.mean::<f32>(&acc(2.0), 2, &acc(1.2), 6).unwrap();
            assert!((m.x - (0.1 + 0.9 * 0.2)).abs() < 1e-4, "{}", m.x);
            assert!(cut.mean::<f32>(&acc(0.0), 0, &acc(1.2), 6).is_none());
        }
    }
}
