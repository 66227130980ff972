//! How wide a lens ray's share of the lens is where it meets a surface: the
//! footprint over which a stratified ray box-filters a checker texture.
//!
//! A pixel's rays all pass through its point in focus F (depth z_f). Lens
//! points δ apart meet depth z δ·|1 − z/z_f| apart, so a ray standing for one
//! of P equal strata of a lens of radius a (about a/√P across) covers, at
//! depth z, a disc of radius about a/√P · |1 − z/z_f| (a the radius of the
//! disc of the aperture's area: a triangle inscribed in the lens's circle
//! has 0.64 of its radius; sized by the circle, footprints of seed 8219's
//! triangle blurred its checkered floor flat, 3.6 dB under the floor). Averaging the texture
//! over it is what the stratum's rays average: the estimate keeps its mean
//! (up to a blur of that size, which vanishes as P grows, and is zero in focus
//! and for a pinhole) and loses the noise of squares flipping across the lens.

#[cfg(not(feature = "no-rim-pull"))]
use crate::camera::Camera;
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::scene::Scene;

/// The footprint's radius as a share of a stratum's radius a/√P: under 1, so
/// that the extra blur stays below the stratum's own scale.
pub const FOOTPRINT_GAIN: f64 = 1.0;

/// 1 − √(1 − 4/(3·2^m)) in Q1.15, by m (strata 2^m): the share of its offset
/// from the lens centre by which a stratum's ray pulls its footprint's centre
/// in, so that the centres' spread (a lens of radius a' = a √(1 − 4/(3P)),
/// variance a'²/4 an axis) plus the box's (half-width a/√P, variance
/// a²/(3P)) is the lens's own, a²/4. Without it the box widened the blur of
/// a checker by 4/(3P) of its variance and moved its mean toward grey (seed
/// 12484 at 4 strata: blue −7.5 levels). Past the table, its last; at one
/// stratum (4/3 > 1) the centre is the lens centre's.
const PULL_Q15: [u16; 12] = [32768, 13849, 6013, 2855, 1395, 690, 343, 171, 85, 43, 21, 11];

/// What a lens ray carries to its trace for its footprint's pull: the
/// camera, its lens point and the share of its offset ([`Stratum::pull`]),
/// so that the offset is made only for a ray that meets a checker; nothing
/// on the micro:bit (feature `no-rim-pull`: its code as before).
#[cfg(not(feature = "no-rim-pull"))]
#[derive(Copy, Clone, Debug)]
pub struct Pull<'a, S: Scalar> {
    /// The camera whose lens the point is on.
    pub camera: &'a Camera<S>,
    /// The lens point, Q1.15 on the unit disk.
    pub p_lens: (i32, i32),
    /// The share of its offset from the lens centre; 0 with the pull off.
    pub share: S,
}
/// See above.
#[cfg(feature = "no-rim-pull")]
pub type Pull<'a, S> = core::marker::PhantomData<&'a S>;

/// A stratum's share of the lens, for its ray's footprint: from [`Defocus::stratum`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Stratum<S> {
    /// The footprint's radius per unit of |1 − z/z_f|, world units.
    pub radius: S,
    /// The share of the ray's offset from the lens centre by which its
    /// footprint's centre is pulled in (used where [`crate::Scene`]'s rim
    /// pull is on: not with the feature `no-rim-pull`).
    pub pull: S,
}

/// A camera's defocus, for the footprints of its lens rays.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Defocus<S> {
    /// The viewing direction over the depth in focus: t d · ahead is z/z_f.
    ahead: Vec3<S>,
    /// The lens radius times [`FOOTPRINT_GAIN`]; 0 for a pinhole.
    radius: S,
    /// K / T for the scanline filter (see [`crate::render::scanline`]): K the
    /// circle of confusion, in pixels, of a point at infinity; 0 for none.
    pub(crate) far: S,
}

impl<S: Scalar> Defocus<S> {
    /// The defocus of `scene`'s camera. Set-up only, in f64.
    pub fn new(scene: &Scene<S>) -> Self {
        let none = Defocus {
            ahead: Vec3::new(S::ZERO, S::ZERO, S::ZERO),
            radius: S::ZERO,
            far: S::ZERO,
        };
        let cam = &scene.camera;
        let z_f = cam.focus_depth();
        if !(cam.radius > 0.0 && z_f > 0.0 && z_f.is_finite()) {
            return none;
        }
        let Some([_, _, n]) = crate::camera::basis(cam) else {
            return none;
        };
        let aperture = crate::camera::aperture::Aperture::regular(cam.aperture_blades, cam.aperture_rotation);
        Defocus {
            ahead: Vec3::from_f64(n.map(|x| -x / z_f)),
            // A stratum is 1/P of the aperture's area: a polygon's is smaller than its circle's.
            radius: S::from_f64(cam.radius * FOOTPRINT_GAIN * aperture.equal_area_radius()),
            far: S::ZERO,
        }
    }

    /// The lens radius the footprints use; 0 for a pinhole.
    #[inline]
    pub fn radius(&self) -> S {
        self.radius
    }

    /// z/z_f of the point at distance `t` along unit `d`: its depth over the depth in focus.
    #[inline]
    pub fn depth_ratio(&self, d: Vec3<S>, t: S) -> S {
        t.mul(d.dot(self.ahead))
    }

    /// A ray's footprint radius per unit of |1 − z/z_f| when it stands for
    /// one of `strata` equal strata of the lens (rounded down to a power of
    /// two: a stratified set's full blocks): the radius over √strata, by
    /// shifts (no square root on the per-pixel path); and how far its texture
    /// centre is pulled toward the lens centre (see [`Stratum::pull`]).
    #[inline]
    pub fn stratum(&self, strata: u32) -> Stratum<S> {
        let m = 31 - strata.max(1).leading_zeros();
        let r = self.radius.mul(S::from_q15(32768 >> (m / 2).min(15)));
        // 1/√2 in Q1.15 for an odd power.
        let radius = if m & 1 == 1 { r.mul(S::from_q15(23170)) } else { r };
        let pull = if cfg!(feature = "no-rim-pull") {
            S::ZERO
        } else {
            S::from_q15(PULL_Q15[(m as usize).min(PULL_Q15.len() - 1)] as i32)
        };
        Stratum { radius, pull }
    }

    /// The footprint radius, world units, of a ray along unit `d` standing for
    /// a stratum of radius `stratum` (from [`Defocus::stratum`]) at distance `t`.
    #[inline]
    pub fn width(&self, d: Vec3<S>, t: S, stratum: S) -> S {
        stratum.mul(S::ONE.sub(self.depth_ratio(d, t)).abs())
    }

    /// Where the footprint's centre moves, world units across the ray, at
    /// distance `t` along unit `d`, for a ray whose lens point was pulled by
    /// `pull` (its offset from the lens centre times [`Stratum::pull`]):
    /// rays through the point in focus that leave the lens δ apart are δ (1
    /// − z/z_f) apart at depth z, and the pulled point is −`pull` away.
    #[inline]
    pub fn shift(&self, d: Vec3<S>, t: S, pull: Vec3<S>) -> Vec3<S> {
        pull.scale(self.depth_ratio(d, t).sub(S::ONE))
    }

    /// A checker footprint's radius ([`Defocus::width`]) and its centre's
    /// move ([`Defocus::shift`]) for the ray `pull` describes, from one
    /// depth ratio (its offset made here, for a ray that met a checker); no
    /// move on the micro:bit.
    #[inline]
    pub(crate) fn checker_footprint(&self, d: Vec3<S>, t: S, stratum: S, pull: Pull<'_, S>) -> (S, Vec3<S>) {
        #[cfg(not(feature = "no-rim-pull"))]
        {
            let off = S::ONE.sub(self.depth_ratio(d, t));
            let offset = pull.camera.lens_offset(pull.p_lens, pull.share);
            (stratum.mul(off.abs()), (-offset).scale(off))
        }
        #[cfg(feature = "no-rim-pull")]
        {
            let _ = pull;
            (self.width(d, t, stratum), Vec3::ZERO)
        }
    }
}

impl<S: crate::bytes::Field> crate::bytes::Field for Defocus<S> {
    crate::bytes::baked_fields!(Defocus { ahead, radius, far });
}

impl<S: Scalar + crate::bytes::Field> Defocus<S> {
    /// No defocus: what an empty baked scene holds.
    pub(crate) fn blank() -> Self {
        <Self as crate::bytes::Field>::blank()
    }
}
