//! Lens samples from a linear-feedback shift register, in integers.
//!
//! The Q16.16 renderer and the f32 reference must draw the very same lens
//! points, and a pixel's points must depend on that pixel alone (so rows can be
//! rendered in any order, on any number of threads or machines). So sampling
//! is pure integer work: a 32-bit Galois LFSR seeded from the pixel's
//! coordinates, and rejection sampling of the unit disk in Q1.15.
//!
//! # The shifted-copy pitfall
//!
//! Successive states of a shift register are shifted copies of each other: take
//! x from one state and y from the next, and the points fall on a few lines.
//! [`Lfsr::next_u16`] therefore clocks the register 32 times per draw, so every
//! coordinate is made of bits no earlier coordinate contained. The tests measure
//! the result: correlation of x and y near 0, and equal counts in equal-area cells.

/// Feedback taps of x³² + x²² + x² + x + 1 for a right-shifting Galois register
/// (maximal: period 2³² − 1).
pub const TAPS: u32 = 0x8020_0003;

/// Four clocks of the register started at each nibble value: the register is
/// linear and its upper bits only shift for four clocks, so four clocks of
/// any state are `(state >> 4) ^ NIBBLE_CLOCKS[state & 0xF]` (the CRC table
/// trick; 64 bytes where a byte's table took a kilobyte of the M0's flash).
const NIBBLE_CLOCKS: [u32; 16] = {
    let mut t = [0u32; 16];
    let mut v = 0;
    while v < 16 {
        let mut s = v as u32;
        let mut k = 0;
        while k < 4 {
            let lsb = s & 1;
            s >>= 1;
            s ^= lsb.wrapping_neg() & TAPS;
            k += 1;
        }
        t[v] = s;
        v += 1;
    }
    t
};

/// A 32-bit Galois LFSR. Its state is never 0.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Lfsr {
    state: u32,
}

impl Lfsr {
    /// A register started at `seed` (0 is replaced by 1: 0 is the one fixed point).
    pub const fn new(seed: u32) -> Self {
        Lfsr {
            state: if seed == 0 { 1 } else { seed },
        }
    }

    /// The register seeded for pixel (`col`, `row`) and `pass` (0 for a
    /// plain render): a fixed integer hash, so every pixel starts elsewhere in
    /// the sequence.
    pub fn for_pixel(col: u32, row: u32, pass: u32) -> Self {
        // A murmur3-style finaliser spreads neighbouring pixels far apart.
        let mut h = col.wrapping_mul(0x9E37_79B1) ^ row.wrapping_mul(0x85EB_CA77) ^ pass.wrapping_mul(0xC2B2_AE3D);
        h ^= h >> 16;
        h = h.wrapping_mul(0x7FEB_352D);
        h ^= h >> 15;
        h = h.wrapping_mul(0x846C_A68B);
        h ^= h >> 16;
        Lfsr::new(h)
    }

    /// The current state.
    pub const fn state(&self) -> u32 {
        self.state
    }

    /// Clocks the register once and returns the new state.
    #[inline]
    pub fn step(&mut self) -> u32 {
        let lsb = self.state & 1;
        self.state >>= 1;
        // Branch-free feedback: all-ones mask when the bit shifted out was 1.
        self.state ^= lsb.wrapping_neg() & TAPS;
        self.state
    }

    /// Clocks the register eight times, by table.
    #[inline]
    pub fn step8(&mut self) -> u32 {
        for _ in 0..2 {
            self.state = (self.state >> 4) ^ NIBBLE_CLOCKS[(self.state & 0xF) as usize];
        }
        self.state
    }

    /// 16 fresh bits: clocks 32 times so the draw shares no bit with the last one.
    // Once: its eight table steps inlined at each draw took 450 bytes of the M0's flash.
    #[inline(never)]
    pub fn next_u16(&mut self) -> u16 {
        // Four table steps of eight clocks each: about a quarter of the instructions of
        // 32 single clocks on a Cortex-M0, the same states.
        for _ in 0..4 {
            self.step8();
        }
        (self.state >> 16) as u16
    }

    /// A point uniform on the unit disk, in Q1.15 (`(x, y)` with
    /// `x² + y² < 2³⁰`), by rejection from the square.
    ///
    /// After 64 rejections in a row (probability 0.215⁶⁴) it returns the
    /// centre, so the call always ends.
    pub fn disk_q15(&mut self) -> (i32, i32) {
        for _ in 0..64 {
            let x = self.next_u16() as i16 as i32;
            let y = self.next_u16() as i16 as i32;
            if x * x + y * y < 1 << 30 {
                return (x, y);
            }
        }
        (0, 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_clocks_by_table_equal_eight_single_clocks() {
        let mut seed = 0x1234_5678u32;
        for n in 0..100_000u32 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let start = if n < 256 { n.max(1) } else { seed | 1 };
            let (mut a, mut b) = (Lfsr::new(start), Lfsr::new(start));
            for _ in 0..8 {
                a.step();
            }
            assert_eq!(b.step8(), a.state(), "from {start:#x}");
            // And a draw is 32 single clocks.
            let (mut c, mut d) = (Lfsr::new(start), Lfsr::new(start));
            for _ in 0..32 {
                c.step();
            }
            assert_eq!(d.next_u16(), (c.state() >> 16) as u16, "from {start:#x}");
            assert_eq!(d, c);
        }
    }

    #[test]
    fn period_is_maximal() {
        // A maximal 32-bit register returns to its start after 2^32 - 1 steps and
        // not before: check it doesn't return within the first 2^20 steps, and
        // that 2^32 - 1 steps is a multiple of the period by checking the
        // polynomial's order with fast exponentiation of the step map.
        let mut r = Lfsr::new(1);
        for _ in 0..(1u32 << 20) {
            assert_ne!(r.step(), 1);
        }
        // The step is linear over GF(2): represent it as a 32x32 bit matrix (columns
        // = images of basis vectors) and raise it to 2^32 - 1 and to (2^32-1)/p for
        // each prime p of 2^32 - 1 = 3 * 5 * 17 * 257 * 65537.
        let step_col = |v: u32| {
            let mut r = Lfsr { state: v };
            r.step()
        };
        let m: [u32; 32] = core::array::from_fn(|i| step_col(1 << i));
        let mul = |a: &[u32; 32], b: &[u32; 32]| -> [u32; 32] {
            core::array::from_fn(|i| {
                let col = b[i];
                let mut out = 0;
                for (j, aj) in a.iter().enumerate() {
                    if col >> j & 1 == 1 {
                        out ^= aj;
                    }
                }
                out
            })
        };
        let pow = |e: u64| {
            let mut result: [u32; 32] = core::array::from_fn(|i| 1 << i);
            let mut base = m;
            let mut e = e;
            while e > 0 {
                if e & 1 == 1 {
                    result = mul(&result, &base);
                }
                base = mul(&base, &base);
                e >>= 1;
            }
            result
        };
        let identity: [u32; 32] = core::array::from_fn(|i| 1 << i);
        let n = (1u64 << 32) - 1;
        assert_eq!(pow(n), identity);
        for p in [3u64, 5, 17, 257, 65537] {
            assert_ne!(pow(n / p), identity, "period divides (2^32-1)/{p}");
        }
    }

    #[test]
    fn never_zero_and_zero_seed_is_replaced() {
        let mut r = Lfsr::new(0);
        assert_eq!(r.state(), 1);
        for _ in 0..10_000 {
            assert_ne!(r.step(), 0);
        }
    }

    /// 10^5 samples from consecutive pixels' registers.
    fn samples() -> impl Iterator<Item = (f64, f64)> {
        (0..100_000u32).map(|i| {
            let mut r = Lfsr::for_pixel(i % 320, i / 320, 0);
            let (x, y) = r.disk_q15();
            (x as f64 / 32768.0, y as f64 / 32768.0)
        })
    }

    #[test]
    fn disk_samples_are_uncorrelated() {
        let points: std::vec::Vec<(f64, f64)> = samples().collect();
        assert!(points.iter().all(|(x, y)| x * x + y * y < 1.0));
        let corr = correlation(&points);
        assert!(corr.abs() < 0.02, "correlation {corr}");
        // Also within one pixel's stream: successive draws of the same register.
        let mut r = Lfsr::for_pixel(7, 9, 0);
        let pts: std::vec::Vec<(f64, f64)> = (0..100_000)
            .map(|_| {
                let (x, y) = r.disk_q15();
                (x as f64, y as f64)
            })
            .collect();
        let c = correlation(&pts);
        assert!(c.abs() < 0.02, "within-stream correlation {c}");
    }

    #[test]
    fn disk_samples_fill_equal_area_cells_evenly() {
        // 4 rings of equal area times 8 sectors: 32 cells of 3125 expected each.
        let mut counts = [0u32; 32];
        for (x, y) in samples() {
            let r2 = x * x + y * y;
            let ring = ((r2 * 4.0) as usize).min(3);
            let a = y.atan2(x) + core::f64::consts::PI;
            let sector = ((a / (2.0 * core::f64::consts::PI) * 8.0) as usize).min(7);
            counts[ring * 8 + sector] += 1;
        }
        let e = 100_000.0 / 32.0;
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum();
        // 31 degrees of freedom: the 99.9th percentile is 61.1.
        assert!(chi2 < 61.1, "chi-square {chi2}, counts {counts:?}");
    }

    #[test]
    fn naive_successive_states_would_fail_the_correlation_test() {
        // The pitfall the docs warn of, shown: x and y from two successive states
        // (one clock apart) are strongly correlated, so the test above has teeth.
        let mut r = Lfsr::new(12345);
        let naive: std::vec::Vec<(f64, f64)> = (0..100_000)
            .map(|_| {
                let x = (r.step() >> 16) as i16 as f64;
                (x, (r.step() >> 16) as i16 as f64)
            })
            .collect();
        let corr = correlation(&naive);
        assert!(corr.abs() > 0.1, "naive correlation only {corr}");
    }

    /// Pearson's correlation of the pairs' two coordinates.
    fn correlation(points: &[(f64, f64)]) -> f64 {
        let n = points.len() as f64;
        let (mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for &(x, y) in points {
            sx += x;
            sy += y;
            sxx += x * x;
            syy += y * y;
            sxy += x * y;
        }
        let cov = sxy / n - sx / n * sy / n;
        cov / ((sxx / n - (sx / n).powi(2)).sqrt() * (syy / n - (sy / n).powi(2)).sqrt())
    }
}
