//! How wide a lens ray's share of the lens is where it meets a surface: the
//! footprint over which a stratified ray box-filters a checker texture.
//!
//! A pixel's rays all pass through its point in focus F (depth z_f). Lens
//! points δ apart meet depth z δ·|1 − z/z_f| apart, so a ray standing for one
//! of P equal cells of a lens of radius a (about a/√P across) covers, at
//! depth z, a disc of radius about a/√P · |1 − z/z_f| (a the radius of the
//! disc of the aperture's area). Averaging the texture over it is what the
//! cell's rays would average: the estimate keeps its mean, up to a blur of
//! that size, which vanishes as P grows and is zero in focus and for a
//! pinhole, and loses the noise of squares flipping across the lens
//! (docs/sampling.md).

use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::scene::Scene;

/// A scene's lens, for its rays' footprints.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Defocus<S> {
    /// −n / z_f: a point's depth ratio z/z_f is `t d · ahead` for a ray of unit `d`.
    ahead: Vec3<S>,
    /// The radius of the disc of the aperture's area; 0 for none.
    radius: S,
}

impl<S: Scalar> Defocus<S> {
    /// The footprints of `scene`'s lens; all of zero width for a pinhole or
    /// a plane in focus at infinity. Set-up only.
    pub fn new(scene: &Scene<S>) -> Self {
        let none = Defocus {
            ahead: Vec3::ZERO,
            radius: S::ZERO,
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
            radius: S::from_f64(cam.radius * aperture.equal_area_radius()),
        }
    }

    /// The radius a/√P of one of `strata` equal cells of the lens (a power
    /// of two): halved every two doublings, times √½ in between.
    #[inline]
    pub fn stratum(&self, strata: u32) -> S {
        let m = 31 - strata.max(1).leading_zeros();
        let r = self.radius.mul(S::from_q15(32768 >> (m / 2).min(15)));
        if m & 1 == 1 {
            r.mul(S::from_q15(23170))
        } else {
            r
        }
    }

    /// The footprint's radius across a ray of unit direction `d` at distance
    /// `t`, for a cell of radius `stratum`: `stratum · |1 − z/z_f|`.
    #[inline]
    pub fn width(&self, d: Vec3<S>, t: S, stratum: S) -> S {
        stratum.mul(S::ONE.sub(t.mul(d.dot(self.ahead))).abs())
    }
}

impl<S: crate::bytes::Field> crate::bytes::Field for Defocus<S> {
    crate::bytes::baked_fields!(Defocus { ahead, radius });
}
