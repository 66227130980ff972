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

use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::scene::Scene;

/// The footprint's radius as a share of a stratum's radius a/√P: under 1, so
/// that the extra blur stays below the stratum's own scale.
pub const FOOTPRINT_GAIN: f64 = 1.0;

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
    /// shifts (no square root on the per-pixel path).
    #[inline]
    pub fn stratum(&self, strata: u32) -> S {
        let m = 31 - strata.max(1).leading_zeros();
        let r = self.radius.mul(S::from_q15(32768 >> (m / 2).min(15)));
        // 1/√2 in Q1.15 for an odd power.
        if m & 1 == 1 {
            r.mul(S::from_q15(23170))
        } else {
            r
        }
    }

    /// The footprint radius, world units, of a ray along unit `d` standing for
    /// a stratum of radius `stratum` (from [`Defocus::stratum`]) at distance `t`.
    #[inline]
    pub fn width(&self, d: Vec3<S>, t: S, stratum: S) -> S {
        stratum.mul(S::ONE.sub(self.depth_ratio(d, t)).abs())
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
