//! Which lens points a pixel's rays go through: independent draws, or a
//! stratified low-discrepancy set, both from the pixel's LFSR and in integers.
//!
//! *Independent* samples ([`Sampler::Independent`]) are rejection draws from
//! the pixel's register ([`Aperture::sample`]): error falls as 1/√N.
//!
//! *Stratified* samples ([`Sampler::Stratified`]) are the points of a base-2
//! (0,2)-sequence (van der Corput for the first coordinate, Sobol's second
//! dimension for the other), scrambled per pixel by a random digital shift
//! (XOR with 16 bits from the pixel's register, the same for all its samples)
//! and jittered below the 10th bit by fresh register bits for each sample.
//! Any first 2ᵐ points (m ≤ 10) of a pixel then fall one in each of 2ᵐ
//! equal strata of the unit square, for every split of it into 2ᵃ × 2ᵇ
//! rectangles (a + b = m), and every point is still uniform. The square is
//! mapped onto the aperture by an area-preserving map ([`Aperture::map_q16`]),
//! so strata of the square are strata of equal area on the lens.
//!
//! Prefixes stay stratified: this is what adaptive sampling needs (a pixel's
//! first 16 samples cover all 16 strata of the lens). The state is the register,
//! two shift words and the sample index, a few words a pixel; a pixel's points
//! depend on that pixel alone, never on the order of the rows.

use crate::camera::aperture::Aperture;
use crate::camera::lfsr::Lfsr;

/// How a pixel's lens points are drawn (`sampler independent|stratified`).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
pub enum Sampler {
    /// Independent uniform draws (rejection from the square).
    Independent,
    /// A per-pixel scrambled, jittered (0,2)-sequence: stratified at every
    /// power-of-two prefix.
    #[default]
    Stratified,
}

/// Bits of the sequence kept exactly (2¹⁰ = 1024 strata); the bits below are
/// fresh jitter for each sample.
const NET_BITS: u32 = 10;
const NET_MASK: u16 = !((1u16 << (16 - NET_BITS)) - 1);

/// Sobol's second dimension: generator columns (Pascal's triangle mod 2),
/// column j for bit j of the index, most significant output bit first.
const SOBOL2: [u16; 16] = {
    let mut v = [0u16; 16];
    v[0] = 0x8000;
    let mut j = 1;
    while j < 16 {
        v[j] = v[j - 1] ^ (v[j - 1] >> 1);
        j += 1;
    }
    v
};

/// Point `i` of the base-2 (0,2)-sequence, as two 16-bit fractions of 1.
#[inline]
pub fn sequence_point(i: u32) -> (u16, u16) {
    let u = (i as u16).reverse_bits();
    let mut v = 0u16;
    let mut bits = i & 0xFFFF;
    let mut j = 0;
    while bits != 0 {
        if bits & 1 == 1 {
            // j < 16 (bits has 16): the mask only spares a panicking bounds check.
            v ^= SOBOL2[j & 15];
        }
        bits >>= 1;
        j += 1;
    }
    (u, v)
}

/// A pixel's lens points, one after another (see the module docs).
#[derive(Copy, Clone, Debug)]
pub struct PixelSamples {
    lfsr: Lfsr,
    sampler: Sampler,
    /// The pixel's digital shift of the sequence.
    shift: (u16, u16),
    /// Index of the next point.
    index: u32,
}

impl PixelSamples {
    /// The samples of pixel (`col`, `row`): its register is
    /// [`Lfsr::for_pixel`]`(col, row, 0)`, so the independent sampler draws
    /// exactly the points it always drew.
    pub fn new(sampler: Sampler, col: u32, row: u32) -> Self {
        let mut lfsr = Lfsr::for_pixel(col, row, 0);
        let shift = match sampler {
            Sampler::Independent => (0, 0),
            Sampler::Stratified => (lfsr.next_u16(), lfsr.next_u16()),
        };
        PixelSamples {
            lfsr,
            sampler,
            shift,
            index: 0,
        }
    }

    /// The next point of the unit square, as two 16-bit fractions (stratified
    /// sampler), or `None` for the independent sampler (which draws on the
    /// aperture directly).
    #[inline]
    pub fn next_unit(&mut self) -> Option<(u16, u16)> {
        match self.sampler {
            Sampler::Independent => None,
            Sampler::Stratified => {
                let (u, v) = sequence_point(self.index);
                self.index = self.index.wrapping_add(1);
                // One draw jitters both coordinates below the net's bits.
                let j = self.lfsr.next_u16();
                let (ju, jv) = (j & !NET_MASK, (j >> (16 - NET_BITS)) & !NET_MASK);
                Some((
                    ((u ^ self.shift.0) & NET_MASK) | ju,
                    ((v ^ self.shift.1) & NET_MASK) | jv,
                ))
            }
        }
    }

    /// The next lens point on `aperture`, Q1.15 (as [`Aperture::sample`]).
    // Not `next_point(..).0`: that cost the micro:bit's pixel loop 52 bytes of flash.
    #[inline]
    pub fn next(&mut self, aperture: &Aperture) -> (i32, i32) {
        match self.next_unit() {
            Some((u, v)) => aperture.map_q16(u, v),
            None => {
                self.index = self.index.wrapping_add(1);
                aperture.sample(&mut self.lfsr)
            }
        }
    }
}

impl crate::bytes::Field for Sampler {
    fn put(&self, w: &mut crate::bytes::Writer<'_>) {
        crate::bytes::Field::put(&(*self as u8), w);
    }
    #[inline]
    fn take(&mut self, r: &mut crate::bytes::Reader<'_>) {
        let mut tag = 0u8;
        crate::bytes::Field::take(&mut tag, r);
        *self = match tag {
            0 => Sampler::Independent,
            1 => Sampler::Stratified,
            _ => {
                r.out_of_range("unknown lens sampler");
                Sampler::Independent
            }
        };
    }
    fn blank() -> Self {
        Sampler::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sequence_is_a_net_at_every_power_of_two() {
        // The first 2^m points: one in each 2^a x 2^b box, for all a + b = m.
        for m in 0..=10u32 {
            for a in 0..=m {
                let b = m - a;
                let mut seen = std::vec![false; 1 << m];
                for i in 0..(1u32 << m) {
                    let (u, v) = sequence_point(i);
                    let cell = ((u as u32 >> (16 - a)) << b | (v as u32 >> (16 - b))) as usize;
                    let cell = if a == 0 && b == 0 { 0 } else { cell };
                    assert!(!seen[cell], "m {m}, {a}x{b}: point {i} shares a box");
                    seen[cell] = true;
                }
            }
        }
    }

    #[test]
    fn scrambled_jittered_points_keep_the_net_and_are_uniform() {
        // Any pixel's first 64 points: one in each 8x8, 4x16, 16x4 ... box.
        for (col, row) in [(0, 0), (17, 3), (319, 239)] {
            let mut s = PixelSamples::new(Sampler::Stratified, col, row);
            let pts: std::vec::Vec<(u16, u16)> = (0..64).map(|_| s.next_unit().unwrap()).collect();
            for a in 0..=6u32 {
                let b = 6 - a;
                let mut seen = [false; 64];
                for &(u, v) in &pts {
                    let cu = if a == 0 { 0 } else { (u as u32) >> (16 - a) };
                    let cv = if b == 0 { 0 } else { (v as u32) >> (16 - b) };
                    let cell = (cu << b | cv) as usize;
                    assert!(!seen[cell], "pixel ({col}, {row}) {a}x{b}");
                    seen[cell] = true;
                }
            }
        }
        // The first point of each pixel, over many pixels: uniform in 16x16 cells.
        let mut counts = [0u32; 256];
        for i in 0..102_400u32 {
            let (u, v) = PixelSamples::new(Sampler::Stratified, i % 320, i / 320)
                .next_unit()
                .unwrap();
            counts[((u >> 12) << 4 | (v >> 12)) as usize] += 1;
        }
        let e = 102_400.0 / 256.0;
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum();
        // 255 degrees of freedom: the 99.9th percentile is 330.5.
        assert!(chi2 < 330.5, "chi-square {chi2}");
    }

    #[test]
    fn independent_sampler_draws_the_lfsr_points_unchanged() {
        let ap = Aperture::regular(6, 15.0);
        let mut s = PixelSamples::new(Sampler::Independent, 5, 7);
        let mut r = Lfsr::for_pixel(5, 7, 0);
        for _ in 0..100 {
            assert_eq!(s.next(&ap), ap.sample(&mut r));
        }
    }

    /// The first `n` lens points of pixel (`col`, `row`), in units of the lens radius.
    fn lens_points(sampler: Sampler, ap: &Aperture, col: u32, row: u32, n: usize) -> std::vec::Vec<(f64, f64)> {
        let mut s = PixelSamples::new(sampler, col, row);
        (0..n)
            .map(|_| {
                let (x, y) = s.next(ap);
                (x as f64 / 32768.0, y as f64 / 32768.0)
            })
            .collect()
    }

    #[test]
    fn stratified_points_fill_equal_area_cells_of_the_lens_exactly() {
        // 64 points a pixel in 16 cells of equal area (4 rings x 4 sectors of
        // the disk; 4 rings x one triangle per side of a hexagon is 24 cells,
        // so the hexagon uses its 6 sectors x 2 rings = 12 cells of 64/12).
        // Chi-square of the counts, averaged over pixels: stratified points
        // come out near 0, independent ones near the degrees of freedom.
        let cells = |ap: &Aperture, p: (f64, f64)| -> usize {
            let r2 = p.0 * p.0 + p.1 * p.1;
            let turn = (p.1.atan2(p.0) / (2.0 * core::f64::consts::PI)).rem_euclid(1.0);
            if ap.blades() == 0 {
                ((r2 * 4.0) as usize).min(3) * 4 + ((turn * 4.0) as usize).min(3)
            } else {
                // Rings of the hexagon's gauge, sectors from corner to corner (rotation 0).
                let n = ap.blades() as f64;
                let k = ((turn * n) as usize).min(ap.blades() as usize - 1);
                let mid = (2.0 * k as f64 + 1.0) * core::f64::consts::PI / n;
                let g = (p.0 * mid.cos() + p.1 * mid.sin()) / (core::f64::consts::PI / n).cos();
                k * 2 + ((g * g * 2.0) as usize).min(1)
            }
        };
        for ap in [Aperture::ROUND, Aperture::regular(6, 0.0)] {
            let ncells = if ap.blades() == 0 { 16 } else { 12 };
            let chi2 = |sampler| {
                let mut total = 0.0;
                for px in 0..200u32 {
                    let mut counts = std::vec![0u32; ncells];
                    for p in lens_points(sampler, &ap, px % 20, px / 20, 64) {
                        counts[cells(&ap, p)] += 1;
                    }
                    let e = 64.0 / ncells as f64;
                    total += counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum::<f64>();
                }
                total / 200.0
            };
            let (ind, strat) = (chi2(Sampler::Independent), chi2(Sampler::Stratified));
            assert!(
                ind > 0.6 * (ncells - 1) as f64,
                "{} blades: independent chi-square {ind}",
                ap.blades()
            );
            assert!(
                strat < 0.1 * ind,
                "{} blades: stratified {strat}, independent {ind}",
                ap.blades()
            );
        }
    }

    #[test]
    fn stratified_estimates_of_a_blurred_edge_have_a_fraction_of_the_error() {
        // The share of the lens beyond an edge (a slanted half-plane): what a
        // pixel on a blurred edge integrates. Error of 64-point estimates over
        // many pixels, against the exact share from 10^6 independent points.
        let ap = Aperture::ROUND;
        let inside = |p: (f64, f64)| 0.8 * p.0 + 0.6 * p.1 > 0.3;
        let mut r = Lfsr::new(99);
        let truth = (0..1_000_000).filter(|_| inside(ap_sample(&ap, &mut r))).count() as f64 / 1e6;
        let mse = |sampler| {
            (0..400u32)
                .map(|px| {
                    let share = lens_points(sampler, &ap, px, 7, 64)
                        .into_iter()
                        .filter(|&p| inside(p))
                        .count() as f64
                        / 64.0;
                    (share - truth).powi(2)
                })
                .sum::<f64>()
                / 400.0
        };
        let (ind, strat) = (mse(Sampler::Independent), mse(Sampler::Stratified));
        // Independent: the binomial variance p (1 − p) / 64.
        assert!(
            (ind / (truth * (1.0 - truth) / 64.0) - 1.0).abs() < 0.25,
            "independent {ind}"
        );
        assert!(strat < ind / 4.0, "stratified {strat}, independent {ind}");
    }

    fn ap_sample(ap: &Aperture, r: &mut Lfsr) -> (f64, f64) {
        let (x, y) = ap.sample(r);
        (x as f64 / 32768.0, y as f64 / 32768.0)
    }
}
