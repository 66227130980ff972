//! A pixel's lens in parts, each weighed by its share of the aperture
//! (post-stratification): a lens cut by a plane ([`crate::render::cut`]),
//! or a lamp's disc on it and the rest ([`crate::render::lamps`]).
//!
//! A pixel's stratified rays put a count in each part that is not its
//! share; each part's mean weighed by its share takes that count's noise
//! out of the estimate and changes nothing in the limit.

use crate::geometry::vec3::Vec3;
use crate::number::Scalar;

/// The fewest rays in a pixel's first block (its pilot, or all it takes)
/// for a ray to be drawn in a part of the lens none of them fell in: with
/// fewer, the other parts would lose too much of their stratification.
pub const FORCE_MIN_BLOCK: u32 = 4;

/// The smallest share of the aperture (65536ths) a part must have for a
/// ray to be drawn there: 1/256.
pub const FORCE_MIN_SHARE: u32 = 256;

/// Each of a pixel's (at most three) parts of the lens by its share of the
/// aperture, 65536ths.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Shares(pub [u32; 3]);

impl Shares {
    /// The part of at least [`FORCE_MIN_SHARE`] of the lens with the largest
    /// share among those `counts` says have no ray yet, if any.
    #[inline]
    pub fn starved(&self, counts: &[u32; 3]) -> Option<usize> {
        (0..3)
            .filter(|&k| counts[k] == 0 && self.0[k] >= FORCE_MIN_SHARE)
            .max_by_key(|&k| self.0[k])
    }

    /// The pixel's colour from each part's sum and count of rays: each
    /// part's mean weighed by its share of the lens, over the parts that
    /// have rays (`n` rays in all, at least one).
    #[inline]
    pub fn mean<S: Scalar>(&self, sums: &[[S::Acc; 3]; 3], counts: &[u32; 3]) -> Vec3<S> {
        let seen: u32 = (0..3).filter(|&k| counts[k] > 0).map(|k| self.0[k]).sum();
        let mut out = [S::ZERO; 3];
        for k in (0..3).filter(|&k| counts[k] > 0) {
            // Its share of the parts seen, Q1.15 (seen > 0: a part with rays has lens).
            let w = S::from_q15(
                ((self.0[k] as u64) << 15)
                    .checked_div(seen as u64)
                    .unwrap_or(0)
                    .min(32768) as i32,
            );
            for (c, o) in out.iter_mut().enumerate() {
                *o = o.add(S::acc_mean(sums[k][c], counts[k]).mul(w));
            }
        }
        Vec3::new(out[0], out[1], out[2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each part's mean weighs its share of the parts that have rays.
    #[test]
    fn each_part_weighs_its_share() {
        let q = Shares([16384, 0, 49152]);
        let sums = [[2.0f64; 3], [0.0; 3], [1.2; 3]];
        // Two rays of 1, six of 0.2: a quarter and three quarters of the lens.
        let m = q.mean::<f32>(&sums, &[2, 0, 6]);
        assert!((m.x - (0.25 + 0.75 * 0.2)).abs() < 1e-4, "{}", m.x);
        let q = Shares([6554, 32768, 26214]);
        // The middle part unseen: the others by their shares of what is seen.
        let m = q.mean::<f32>(&sums, &[2, 0, 6]);
        let w = 6554.0 / (6554.0 + 26214.0);
        assert!((m.x - (w + (1.0 - w) * 0.2)).abs() < 1e-4, "{}", m.x);
        assert_eq!(q.starved(&[2, 0, 6]), Some(1));
        assert_eq!(q.starved(&[2, 1, 6]), None);
    }
}
