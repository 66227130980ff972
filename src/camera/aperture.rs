//! The shape of the lens opening: round, or a regular polygon of aperture blades.
//!
//! A real iris is made of blades, and an out-of-focus point of light images as
//! the shape of the opening (the "bokeh"). [`Aperture`] draws lens samples
//! uniform on that shape in integers, like the register's disc draws: Q1.15 points
//! from the square by rejection, kept when they lie inside every edge's
//! half-plane. The edges' integer coefficients are computed once at set-up, so
//! the draw itself is a few integer multiply-adds, the same for the Q16.16
//! renderer and the f32 reference.
//!
//! The polygon is inscribed in the unit circle: its corners lie on the rim of
//! the round lens of the same radius, as a photographer's aperture is measured.
//!
//! Cost: a draw is two 16-bit numbers (64 register clocks) and at most n
//! multiply-add-compare steps. The square keeps a share of draws equal to the
//! shape's area over 4: 79 % for the disk, 65 % for a hexagon, 59 % for a
//! pentagon, 32 % for a triangle, so a triangle needs 2.4 times the disk's
//! draws per sample; next to tracing the sample's ray, that is small.

use crate::camera::lfsr::Lfsr;
use crate::geometry::transform::sin_cos_degrees;

/// Most aperture blades (`aperture_blades`): beyond this a polygon is round to
/// the eye, and the edges live in a fixed array.
pub const MAX_BLADES: u32 = 16;

/// Scale of an edge normal's coefficients: Q1.14 (|a|, |b| <= 2¹⁴).
const NORMAL_ONE: f64 = 16384.0;

/// Where lens samples fall: the unit disk or a regular polygon inscribed in it.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Aperture {
    /// 0 for round, else the number of sides (3..=`MAX_BLADES` (16)).
    blades: u8,
    /// Edge `i` keeps the Q1.15 points with `a x + b y <= c`: (a, b) the
    /// outward unit normal in Q1.14, c = `inradius`.
    /// `|a x + b y| <= 2 · 2¹⁴ · 2¹⁵ = 2³⁰`: no i32 overflow.
    edges: [(i16, i16); MAX_BLADES as usize],
    /// The polygon's inradius cos(π/n) in Q2.29, the same for every edge.
    inradius: i32,
    /// Corner `k` in Q1.15 (on the unit circle, rounded towards the centre):
    /// what [`Aperture::map_q16`] interpolates along the rim.
    corners: [(i16, i16); MAX_BLADES as usize],
}

impl crate::bytes::Field for Aperture {
    crate::bytes::baked_fields!(Aperture { blades, edges, inradius, corners }, check(ap) {
        if ap.blades != 0 && !(3..=MAX_BLADES as u8).contains(&ap.blades) {
            return Err(crate::bytes::BakeError::OutOfRange("aperture blades not 0 or 3..=16"));
        }
        // |a x + b y| <= 2^30 needs unit normals in Q1.14, and c within that range.
        if ap.edges.iter().any(|&(a, b)| a.unsigned_abs() > 1 << 14 || b.unsigned_abs() > 1 << 14)
            || ap.inradius.unsigned_abs() > 1 << 30
        {
            return Err(crate::bytes::BakeError::OutOfRange("aperture edge beyond Q1.14"));
        }
    });
}

impl Default for Aperture {
    fn default() -> Self {
        Aperture::ROUND
    }
}

impl Aperture {
    /// The round lens: samples from the register's disc draws.
    pub const ROUND: Aperture = Aperture {
        blades: 0,
        edges: [(0, 0); MAX_BLADES as usize],
        inradius: 0,
        corners: [(0, 0); MAX_BLADES as usize],
    };

    /// A regular polygon of `blades` sides inscribed in the unit circle, with a
    /// corner at `rotation_degrees` from the u axis (counter-clockwise, towards v).
    ///
    /// `blades` 0 (and 1 or 2, which make no polygon) gives [`Aperture::ROUND`];
    /// more than `MAX_BLADES` (16) is clamped to it. Set-up only (f64 sin and cos).
    pub fn regular(blades: u32, rotation_degrees: f64) -> Self {
        if blades < 3 {
            return Aperture::ROUND;
        }
        let n = blades.min(MAX_BLADES);
        let (_, inradius) = sin_cos_degrees(180.0 / n as f64);
        let mut ap = Aperture {
            blades: n as u8,
            inradius: libm::round(inradius * NORMAL_ONE * 32768.0) as i32,
            ..Aperture::ROUND
        };
        for (k, e) in ap.edges.iter_mut().take(n as usize).enumerate() {
            // Edge k joins corners k and k + 1; its normal points halfway between.
            let angle = rotation_degrees + 180.0 * (2 * k + 1) as f64 / n as f64;
            let (s, co) = sin_cos_degrees(angle);
            *e = (libm::round(co * NORMAL_ONE) as i16, libm::round(s * NORMAL_ONE) as i16);
        }
        for (k, c) in ap.corners.iter_mut().take(n as usize).enumerate() {
            let (s, co) = sin_cos_degrees(rotation_degrees + 360.0 * k as f64 / n as f64);
            // Truncated towards 0: the corner stays within the unit circle.
            *c = ((co * 32767.0) as i16, (s * 32767.0) as i16);
        }
        ap
    }

    /// The point of the aperture that the unit-square point (`u`, `v`) (16-bit
    /// fractions) maps to, Q1.15: an area-preserving map, so uniform points
    /// of the square give uniform points of the aperture and equal strata of
    /// the square give strata of equal area.
    ///
    /// Polar: the distance from the centre is √u of the rim's, and `v` goes
    /// once round the rim (a full turn for the disk; for a polygon, sector
    /// `⌊v n⌋` from corner to corner, linearly). Integers only: a 16-step
    /// square root and, for the disk, a quarter-wave table of sines.
    #[inline]
    pub fn map_q16(&self, u: u16, v: u16) -> (i32, i32) {
        // Q0.15 radius: √((u + ½) / 2¹⁶), below 1 (the sample at the stratum's middle bit).
        let r = isqrt_u32((((u as u32) << 1) | 1) << 13) as i32;
        let (rim_x, rim_y) = self.rim(v);
        // Truncated towards 0: |point| <= r |rim| < 1.
        ((r * rim_x) / 32768, (r * rim_y) / 32768)
    }

    /// The rim point [`Aperture::map_q16`] scales for `v`, Q1.15.
    #[inline]
    pub fn rim(&self, v: u16) -> (i32, i32) {
        if self.blades == 0 {
            (sin_q15(v.wrapping_add(0x4000)), sin_q15(v))
        } else {
            let n = self.blades as u32;
            let t = v as u32 * n;
            let k = (t >> 16) as usize;
            // Q0.15: (b − a) f stays within an i32.
            let f = ((t & 0xFFFF) >> 1) as i32;
            // k < n <= MAX_BLADES; no modulo and no panicking index (the
            // firmware then links no panic formatting).
            let next = if k + 1 == n as usize { 0 } else { k + 1 };
            let corner = |i: usize| self.corners.get(i).copied().unwrap_or_default();
            let (a, b) = (corner(k), corner(next));
            // a + f (b − a), the chord: inside the polygon, within the circle.
            let lerp = |a: i16, b: i16| a as i32 + (((b as i32 - a as i32) * f) >> 15);
            (lerp(a.0, b.0), lerp(a.1, b.1))
        }
    }

    /// The radius of the disc of this aperture's area, the unit circle's
    /// radius 1: √(n sin(2π/n) / 2π) for n blades (a triangle's 0.64), 1 for
    /// round. Set-up only (f64).
    pub fn equal_area_radius(&self) -> f64 {
        if self.blades == 0 {
            return 1.0;
        }
        let n = self.blades as f64;
        let (s, _) = sin_cos_degrees(360.0 / n);
        libm::sqrt(n * s / (2.0 * core::f64::consts::PI))
    }

    /// Number of sides; 0 for round.
    pub fn blades(&self) -> u32 {
        self.blades as u32
    }

    /// Whether the Q1.15 point (`x`, `y`) lies inside the aperture (strictly
    /// inside the disk for the round one).
    #[inline]
    pub fn contains_q15(&self, x: i32, y: i32) -> bool {
        if self.blades == 0 {
            return x * x + y * y < 1 << 30;
        }
        let c = self.inradius;
        self.edges
            .iter()
            .take(self.blades as usize)
            .all(|&(a, b)| a as i32 * x + b as i32 * y <= c)
    }

    /// A lens point uniform on the aperture, in Q1.15, by rejection from the
    /// square. The round aperture draws exactly as the register's disc draws.
    ///
    /// After 64 rejections in a row (below 10⁻¹⁰ even for a triangle, which
    /// keeps 32 % of draws) it returns the centre, so the call always ends.
    #[inline]
    pub fn sample(&self, lfsr: &mut Lfsr) -> (i32, i32) {
        if self.blades == 0 {
            return lfsr.disk_q15();
        }
        for _ in 0..64 {
            let x = lfsr.next_u16() as i16 as i32;
            let y = lfsr.next_u16() as i16 as i32;
            if self.contains_q15(x, y) {
                return (x, y);
            }
        }
        (0, 0)
    }
}

/// ⌊√x⌋, bit by bit (16 steps of shifts and compares: no multiply, no divide).
#[inline]
pub fn isqrt_u32(x: u32) -> u32 {
    let (mut x, mut root) = (x, 0u32);
    let mut bit = 1u32 << 30;
    while bit > x {
        bit >>= 2;
    }
    while bit != 0 {
        if x >= root + bit {
            x -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// sin(2π k / 1024) · 32767 rounded, k = 0..=256: a quarter wave (514 bytes of flash).
const QUARTER_SINE: [i16; 257] = {
    let mut t = [0i16; 257];
    let mut k = 0;
    while k <= 256 {
        // Taylor series to x^23 (|x| <= π/2: error below 1e-15).
        let x = core::f64::consts::PI / 2.0 * k as f64 / 256.0;
        let (mut term, mut sum, mut n) = (x, x, 1.0);
        while n < 23.0 {
            term = -term * x * x / ((n + 1.0) * (n + 2.0));
            sum += term;
            n += 2.0;
        }
        let y = sum * 32767.0 + 0.5;
        t[k] = y as i16;
        k += 1;
    }
    t
};

/// sin of `turn` / 2¹⁶ of a full turn, Q1.15 (at most 32767), by the table,
/// interpolated linearly (error at most 1.5 Q1.15 steps: two roundings).
#[inline]
pub fn sin_q15(turn: u16) -> i32 {
    let p = (turn & 0x3FFF) as u32;
    // Odd quadrants run the quarter wave backwards.
    let p = if turn & 0x4000 != 0 { 0x4000 - p } else { p };
    let (i, f) = ((p >> 6) as usize, (p & 63) as i32);
    let m = if i >= 256 {
        QUARTER_SINE[256] as i32
    } else {
        let (a, b) = (QUARTER_SINE[i] as i32, QUARTER_SINE[i + 1] as i32);
        a + (((b - a) * f + 32) >> 6)
    };
    if turn & 0x8000 != 0 {
        -m
    } else {
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    /// 10⁵ samples from consecutive pixels' registers, as the renderer draws them.
    fn samples(ap: &Aperture) -> std::vec::Vec<(f64, f64)> {
        (0..100_000u32)
            .map(|i| {
                let mut r = Lfsr::for_pixel(i % 320, i / 320, 0);
                let (x, y) = ap.sample(&mut r);
                (x as f64 / 32768.0, y as f64 / 32768.0)
            })
            .collect()
    }

    /// The exact polygon's gauge: 1 on the boundary, and which edge is nearest.
    fn gauge(n: u32, rot: f64, (x, y): (f64, f64)) -> (f64, usize) {
        (0..n as usize)
            .map(|k| {
                let a = (rot + 180.0 * (2 * k + 1) as f64 / n as f64).to_radians();
                ((x * a.cos() + y * a.sin()) / (PI / n as f64).cos(), k)
            })
            .fold((f64::MIN, 0), |m, g| if g.0 > m.0 { g } else { m })
    }

    #[test]
    fn polygon_samples_are_inside_and_uniform() {
        for (n, rot) in [(3, 90.0), (5, 0.0), (6, 15.0), (16, 7.0)] {
            let ap = Aperture::regular(n, rot);
            assert_eq!(ap.blades(), n);
            // Cells of equal area: one triangle per edge, cut into 4 rings of
            // equal area by the gauge (the area within gauge g grows as g²).
            assert_inside_and_uniform(n, rot, samples(&ap));
        }
    }

    /// 100,000 points of an `n`-bladed aperture turned by `rot`: all inside,
    /// and uniform over cells of equal area (one triangle per edge, cut into
    /// 4 rings of equal area by the gauge: the area within gauge g grows as g²).
    fn assert_inside_and_uniform(n: u32, rot: f64, points: impl IntoIterator<Item = (f64, f64)>) {
        let mut counts = vec![0u32; n as usize * 4];
        for p in points {
            let (g, k) = gauge(n, rot, p);
            assert!(g < 1.0 + 1e-4, "{n} blades: {p:?} outside, gauge {g}");
            counts[k * 4 + ((g * g * 4.0) as usize).min(3)] += 1;
        }
        let e = 100_000.0 / counts.len() as f64;
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum();
        // 99.9th percentiles of chi-square with 4n − 1 degrees of freedom.
        let limit = match n {
            3 => 31.3,
            5 => 43.8,
            6 => 49.7,
            _ => 103.4,
        };
        assert!(chi2 < limit, "{n} blades: chi-square {chi2}, counts {counts:?}");
    }

    #[test]
    fn corners_are_reached_where_the_rotation_puts_them() {
        // A triangle with a corner straight up (90°): samples come within 3 %
        // of the rim at 90°, 210° and 330°, and nowhere near it halfway between.
        let ap = Aperture::regular(3, 90.0);
        let pts = samples(&ap);
        let reach = |deg: f64| {
            let (c, s) = (deg.to_radians().cos(), deg.to_radians().sin());
            pts.iter().map(|&(x, y)| x * c + y * s).fold(f64::MIN, f64::max)
        };
        for corner in [90.0, 210.0, 330.0] {
            assert!(reach(corner) > 0.97, "corner {corner}: {}", reach(corner));
        }
        for side in [30.0, 150.0, 270.0] {
            // The inradius of a triangle is 1/2.
            assert!((reach(side) - 0.5).abs() < 0.01, "side {side}: {}", reach(side));
        }
    }

    #[test]
    fn round_aperture_draws_the_disk_samples_unchanged() {
        let mut a = Lfsr::for_pixel(3, 4, 0);
        let mut b = a;
        for _ in 0..1000 {
            assert_eq!(Aperture::ROUND.sample(&mut a), b.disk_q15());
        }
        assert_eq!(Aperture::regular(0, 30.0), Aperture::ROUND);
        assert_eq!(Aperture::regular(2, 0.0), Aperture::ROUND);
        assert_eq!(Aperture::regular(99, 0.0).blades(), MAX_BLADES);
    }

    #[test]
    fn polygon_samples_are_uncorrelated() {
        // Pentagon turned off any symmetry axis of the square: x and y uncorrelated.
        let pts = samples(&Aperture::regular(5, 10.0));
        let n = pts.len() as f64;
        let (mx, my) = (
            pts.iter().map(|p| p.0).sum::<f64>() / n,
            pts.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let cov = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / n;
        let vx = pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>() / n;
        let vy = pts.iter().map(|p| (p.1 - my).powi(2)).sum::<f64>() / n;
        let corr = cov / (vx * vy).sqrt();
        assert!(corr.abs() < 0.02, "correlation {corr}");
        assert!(mx.abs() < 0.01 && my.abs() < 0.01, "mean ({mx}, {my})");
    }

    #[test]
    fn the_table_sine_is_within_one_and_a_half_steps() {
        for t in (0..=u16::MAX).step_by(7) {
            let exact = (t as f64 / 65536.0 * 2.0 * PI).sin() * 32767.0;
            assert!(
                (sin_q15(t) as f64 - exact).abs() <= 1.5,
                "turn {t}: {} vs {exact}",
                sin_q15(t)
            );
        }
        assert_eq!(sin_q15(0x4000), 32767);
        assert_eq!(sin_q15(0xC000), -32767);
        for x in [0u32, 1, 2, 3, 4, 99, 1 << 20, (1 << 30) - 1, u32::MAX] {
            let r = isqrt_u32(x) as u64;
            assert!(r * r <= x as u64 && (r + 1) * (r + 1) > x as u64, "{x}");
        }
    }

    /// 10⁵ uniform points of the square from an LCG, mapped onto the aperture.
    fn mapped(ap: &Aperture) -> std::vec::Vec<(f64, f64)> {
        let mut s = 12345u64;
        (0..100_000)
            .map(|_| {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let (u, v) = ((s >> 48) as u16, (s >> 32) as u16);
                let (x, y) = ap.map_q16(u, v);
                assert!(ap.contains_q15(x, y) || ap.blades() > 0, "({x}, {y}) outside the disk");
                (x as f64 / 32768.0, y as f64 / 32768.0)
            })
            .collect()
    }

    #[test]
    fn the_square_maps_onto_the_aperture_uniformly() {
        // The disk: 4 rings x 8 sectors of equal area.
        let mut counts = [0u32; 32];
        for (x, y) in mapped(&Aperture::ROUND) {
            let ring = ((((x * x + y * y) * 4.0) as usize).min(3)) * 8;
            let a = y.atan2(x) + PI;
            counts[ring + ((a / (2.0 * PI) * 8.0) as usize).min(7)] += 1;
        }
        let e = 100_000.0 / 32.0;
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum();
        assert!(chi2 < 61.1, "disk: chi-square {chi2}");
        // Polygons: inside, and uniform over the cells of the rejection test above.
        for (n, rot) in [(3, 90.0), (5, 0.0), (6, 15.0), (16, 7.0)] {
            assert_inside_and_uniform(n, rot, mapped(&Aperture::regular(n, rot)));
        }
    }
}
