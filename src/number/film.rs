//! The camera's exact map from a pixel to its rays' world directions.
//!
//! A pixel's chief ray runs along `D(i, j) = a i + b j + c` in world space,
//! with `(i, j) = (2c + 1, 2r + 1)` its doubled centre and a, b, c fixed by the
//! camera; a lens sample `(s_x, s_y)` tilts it to `D − s_x k_u − s_y k_v` (see
//! `crate::camera`). In Q16.16 the map is held as integers at one scale
//! chosen at set-up, so that a ray's direction costs six small products, one
//! square root and one reciprocal, and comes out a unit vector to 30 bits.

use crate::number::plane::{below_q16, round_f64, unit_mantissas};
use crate::number::q16::{shr_round, shr_round_call, FixedDir};
use crate::number::wide::{bits_u64, mul_i32_short};
use fixed::types::I16F16;

/// The map's exact parts, from the camera's set-up (world space).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FilmMapDesc {
    /// The lens centre (a pinhole's eye), whose bits below Q16.16 the chief
    /// rays carry.
    pub eye: [f64; 3],
    /// Change of direction per unit of the doubled column index.
    pub a: [f64; 3],
    /// Change of direction per unit of the doubled row index.
    pub b: [f64; 3],
    /// The direction at index (0, 0).
    pub c: [f64; 3],
    /// What a lens sample's x (in units of the lens radius) takes off the direction.
    pub k_u: [f64; 3],
    /// What a lens sample's y takes off the direction.
    pub k_v: [f64; 3],
    /// Largest doubled column index, `2 cols − 1`.
    pub i_max: f64,
    /// Largest doubled row index, `2 rows − 1`.
    pub j_max: f64,
}

impl FilmMapDesc {
    /// The film map of a camera at `eye` with basis `u, v, n` (n pointing
    /// back from the view), pixel pitch `p`, film half-width and half-height
    /// `half`, image distance `big_n`, lens tilt a/m (0 for a pinhole) and
    /// `cols` × `rows` pixels: the world direction of p_film = (p/2 · i − W,
    /// H − p/2 · j, −N), less the lens tilt,
    /// i (p/2) u + j (−p/2) v + (−W u + H v − N n) − s_x (a/m) u − s_y (a/m) v.
    /// Set-up only (f64).
    pub fn from_basis(
        eye: [f64; 3],
        [u, v, n]: [[f64; 3]; 3],
        p: f64,
        half: (f64, f64),
        big_n: f64,
        tilt: f64,
        (cols, rows): (u32, u32),
    ) -> Self {
        FilmMapDesc {
            eye,
            a: u.map(|x| x * p / 2.0),
            b: v.map(|x| -x * p / 2.0),
            c: [0, 1, 2].map(|k| -half.0 * u[k] + half.1 * v[k] - big_n * n[k]),
            k_u: u.map(|x| x * tilt),
            k_v: v.map(|x| x * tilt),
            i_max: (2 * cols - 1) as f64,
            j_max: (2 * rows - 1) as f64,
        }
    }
}

/// Q16.16's film map: `a`, `b`, `c` at scale `2^-(s + f)`, `k_u`, `k_v` at
/// `2^-s`, with s chosen so that every direction, lens term included, stays
/// below 2^31 at scale `2^-s`, and f (at most 15) so that a and b fit an i32.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct FixedFilmMap {
    a: [i32; 3],
    b: [i32; 3],
    c: [i64; 3],
    k_u: [i32; 3],
    k_v: [i32; 3],
    f: u32,
    /// The eye's bits below Q16.16 at 2^-32 (`FixedDir::o_lo` of chief rays).
    eye_lo: [i16; 3],
}

impl crate::bytes::Field for FixedFilmMap {
    crate::bytes::baked_fields!(FixedFilmMap { a, b, c, k_u, k_v, f, eye_lo }, check(m) {
        // Directions stay below 2^31 at scale 2^-s, so c below 2^46 at 2^-(s + f).
        if m.f > 15 || m.c.iter().any(|x| x.unsigned_abs() >= 1 << 46) || m.eye_lo.contains(&i16::MIN) {
            return Err(crate::bytes::BakeError::OutOfRange("film map beyond its scale"));
        }
    });
}

impl FixedFilmMap {
    /// Whether every direction of a `cols` × `rows` image, lens terms
    /// included, stays below 2^31 at scale 2^-s, as [`FixedFilmMap::new`]
    /// makes it (checked on a baked map, whose size comes with it).
    // Compiled where it is used: a firmware's loader compiles it for size.
    #[inline]
    pub(crate) fn fits(&self, cols: u32, rows: u32) -> bool {
        let (i_max, j_max) = (2 * cols as i64 - 1, 2 * rows as i64 - 1);
        (0..3).all(|k| {
            let lens = self.k_u[k].unsigned_abs() as u64 + self.k_v[k].unsigned_abs() as u64;
            [(1, 1), (i_max, 1), (1, j_max), (i_max, j_max)].iter().all(|&(i, j)| {
                let d = self.a[k] as i64 * i + self.b[k] as i64 * j + self.c[k];
                (d.unsigned_abs() >> self.f) + lens < 1 << 31
            })
        })
    }
}

impl FixedFilmMap {
    /// Chooses the scales and rounds the parts. Set-up only.
    pub fn new(d: &FilmMapDesc) -> FixedFilmMap {
        // The largest |component| over the image's corners, with the lens's
        // reach, and |a| and |b| themselves (one column leaves a unconstrained).
        let mut bound = 0.0f64;
        for k in 0..3 {
            let extra = libm::fabs(d.k_u[k]) + libm::fabs(d.k_v[k]);
            bound = bound.max(libm::fabs(d.a[k])).max(libm::fabs(d.b[k]));
            for (i, j) in [(1.0, 1.0), (d.i_max, 1.0), (1.0, d.j_max), (d.i_max, d.j_max)] {
                bound = bound.max(libm::fabs(d.a[k] * i + d.b[k] * j + d.c[k]) + extra);
            }
        }
        // 2^8 of headroom for the rounding of a, b and c.
        let limit = (1u64 << 31) as f64 - 256.0;
        let s = if bound > 0.0 && bound.is_finite() {
            libm::floor(libm::log2(limit / bound)) as i32
        } else {
            0
        };
        let s = if bound * libm::exp2(s as f64) >= limit {
            s - 1
        } else {
            s
        };
        let ab = (0..3)
            .map(|k| libm::fabs(d.a[k]).max(libm::fabs(d.b[k])))
            .fold(0.0, f64::max);
        let f = if ab > 0.0 {
            let room = libm::floor(libm::log2(((1u64 << 31) - 1) as f64 / (ab * libm::exp2(s as f64)))) as i32;
            room.clamp(0, 15) as u32
        } else {
            15
        };
        let scale = |x: f64, e: i32| round_f64(x * libm::exp2(e as f64));
        let sf = s + f as i32;
        FixedFilmMap {
            a: d.a.map(|x| scale(x, sf) as i32),
            b: d.b.map(|x| scale(x, sf) as i32),
            c: d.c.map(|x| scale(x, sf) as i64),
            k_u: d.k_u.map(|x| scale(x, s) as i32),
            k_v: d.k_v.map(|x| scale(x, s) as i32),
            f,
            // What rounding to Q16.16 (as `Scalar::from_f64`) leaves, at 2^-32; 0 out of range.
            eye_lo: d.eye.map(below_q16),
        }
    }

    /// `D(i + 2, j)` from `D(i, j)`: one step of `2 a`, exact as `film` is.
    #[inline]
    pub fn right(&self, film: &[i64; 3]) -> [i64; 3] {
        let a = &self.a;
        [
            film[0] + 2 * a[0] as i64,
            film[1] + 2 * a[1] as i64,
            film[2] + 2 * a[2] as i64,
        ]
    }

    /// `D(i, j)` exactly, at scale `2^-(s + f)`.
    #[inline]
    pub fn film(&self, i: i32, j: i32) -> [i64; 3] {
        // Constant indices, written out: no bounds check (and no panic path) at
        // any opt-level. Doubled indices are at most 2 MAX_IMAGE_SIDE + 1 < 2^15.
        let (a, b, c) = (&self.a, &self.b, &self.c);
        [
            mul_i32_short(a[0], i) + mul_i32_short(b[0], j) + c[0],
            mul_i32_short(a[1], i) + mul_i32_short(b[1], j) + c[1],
            mul_i32_short(a[2], i) + mul_i32_short(b[2], j) + c[2],
        ]
    }

    /// The unit direction along `D − s_x k_u − s_y k_v` for a film direction
    /// from [`FixedFilmMap::film`] and a lens sample in Q1.15 ((0, 0) for the
    /// chief ray): 30-bit mantissas marked unit, and rounded to Q16.16.
    #[inline]
    pub fn ray_dir(&self, film: &[i64; 3], lens: (i32, i32)) -> (FixedDir, [I16F16; 3]) {
        // The direction exactly, at scale 2^-(s + g).
        // A chief ray leaves from the eye itself: its bits below Q16.16 ride along.
        let (w, g, o_lo) = if lens == (0, 0) {
            (*film, self.f, self.eye_lo)
        } else {
            // Lens terms are exact at 2^-(s + 15): Q1.15 times the i32 parts.
            let up = 15 - self.f;
            let (u, v) = (&self.k_u, &self.k_v);
            let w = [
                (film[0] << up) - mul_i32_short(u[0], lens.0) - mul_i32_short(v[0], lens.1),
                (film[1] << up) - mul_i32_short(u[1], lens.0) - mul_i32_short(v[1], lens.1),
                (film[2] << up) - mul_i32_short(u[2], lens.0) - mul_i32_short(v[2], lens.1),
            ];
            (w, 15, [0; 3])
        };
        // Below 2^31 at scale 2^-s; a direction far shorter than the film's
        // largest (a very tall or wide film) keeps more of its bits.
        let mut d = if g == 0 { w } else { w.map(|x| shr_round(x, g)) };
        if d.iter().all(|x| x.unsigned_abs() < 1 << 29) && g > 0 {
            let big = w.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
            let keep = bits_u64(big).saturating_sub(31).min(g);
            // Rare: through one out-of-line copy of the rounding shift.
            d = if keep == 0 {
                w
            } else {
                w.map(|x| shr_round_call(x, keep))
            };
        }
        let Some(m) = unit_mantissas(d) else {
            let zero = FixedDir {
                m: [0; 3],
                e: -30,
                unit: false,
                o_lo: [0; 3],
            };
            return (zero, [I16F16::ZERO; 3]);
        };
        let rounded = m.map(|x| I16F16::from_bits(shr_round(x, 14) as i32));
        (
            FixedDir {
                m,
                e: -30,
                unit: true,
                o_lo,
            },
            rounded,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact unit direction of `D(i, j) − s_x k_u − s_y k_v`, in f64.
    fn exact(d: &FilmMapDesc, i: i32, j: i32, lens: (i32, i32)) -> [f64; 3] {
        let (sx, sy) = (lens.0 as f64 / 32768.0, lens.1 as f64 / 32768.0);
        let v: [f64; 3] =
            core::array::from_fn(|k| d.a[k] * i as f64 + d.b[k] * j as f64 + d.c[k] - sx * d.k_u[k] - sy * d.k_v[k]);
        let l = libm::sqrt(v.iter().map(|x| x * x).sum());
        v.map(|x| x / l)
    }

    /// Cameras from ordinary to extreme: a tilted basis, a lens whose reach
    /// dwarfs the film, one column or one row of the largest image, a film far
    /// wider than its distance.
    fn cameras() -> impl Iterator<Item = FilmMapDesc> {
        let s = libm::sqrt(0.5);
        let (u, v, n) = ([s, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, s]);
        let desc = move |width: f64, cols: u32, rows: u32, big_n: f64, tilt: f64| {
            let p = width / cols as f64;
            let (w, h) = (width / 2.0, p * rows as f64 / 2.0);
            FilmMapDesc {
                eye: [0.0; 3],
                a: u.map(|x| x * p / 2.0),
                b: v.map(|x| -x * p / 2.0),
                c: core::array::from_fn(|k| -w * u[k] + h * v[k] - big_n * n[k]),
                k_u: u.map(|x| x * tilt),
                k_v: v.map(|x| x * tilt),
                i_max: (2 * cols - 1) as f64,
                j_max: (2 * rows - 1) as f64,
            }
        };
        [
            desc(10.0, 160, 120, 8.0, 0.2),
            desc(10.0, 8192, 8192, 8.0, 0.0),
            desc(10.0, 1, 8192, 8.0, 0.1),
            desc(441.856, 8192, 1, 0.001, 3.0),
            desc(10.0, 1, 1, 8.0, 500.0),
            desc(32000.0, 640, 480, 0.01, 0.0),
        ]
        .into_iter()
    }

    /// The eye's low bits put back on its Q16.16 value give the eye within
    /// 2^-33, and only chief rays carry them.
    #[test]
    fn chief_rays_carry_the_eye_to_2_32() {
        use crate::number::Scalar;
        let mut unit = crate::test_rng::unit_f64(0xe7e);
        let base = cameras().next().expect("a camera");
        for _ in 0..10_000 {
            let eye = [0; 3].map(|_| (unit() - 0.5) * 60_000.0);
            let map = FixedFilmMap::new(&FilmMapDesc { eye, ..base });
            for (k, &e) in eye.iter().enumerate() {
                let q = <I16F16 as Scalar>::from_f64(e).to_bits() as f64 / 65536.0;
                let back = q + map.eye_lo[k] as f64 / 4_294_967_296.0;
                // 2^-33 and the f64 sum's own rounding at 30,000.
                assert!(
                    (back - eye[k]).abs() <= 2f64.powi(-33) + 1e-11,
                    "{} vs {}",
                    back,
                    eye[k]
                );
            }
            let film = map.film(3, 5);
            assert_eq!(map.ray_dir(&film, (0, 0)).0.o_lo, map.eye_lo);
            assert_eq!(map.ray_dir(&film, (100, -7)).0.o_lo, [0; 3]);
        }
    }

    #[test]
    fn unit_directions_match_the_exact_ones() {
        let mut next = crate::test_rng::xorshift32(0x9E37_79B9);
        for (c, d) in cameras().enumerate() {
            let ordinary = c == 0;
            let map = FixedFilmMap::new(&d);
            let float = crate::number::float::FloatFilmMap::new(&d);
            for n in 0..2000 {
                let i = 1 + 2 * (next() % (d.i_max as u32).div_ceil(2)) as i32;
                let j = 1 + 2 * (next() % (d.j_max as u32).div_ceil(2)) as i32;
                let lens = if n % 2 == 0 || d.k_u == [0.0; 3] {
                    (0, 0)
                } else {
                    ((next() >> 17) as i32 - 16384, (next() >> 17) as i32 - 16384)
                };
                let want = exact(&d, i, j, lens);
                let (precise, rounded) = map.ray_dir(&map.film(i, j), lens);
                assert!(precise.unit && precise.e == -30, "{d:?}");
                for k in 0..3 {
                    let m = precise.m[k] as f64 / (1u64 << 30) as f64;
                    // 30-bit mantissas: within 2^-27 for Program 1's camera, and 2^-21
                    // where a lens's reach or a film's size dwarfs the direction.
                    let tol = if ordinary { 1u32 << 27 } else { 1 << 21 };
                    assert!(
                        (m - want[k]).abs() < 1.0 / tol as f64,
                        "{d:?} ({i}, {j}) {lens:?}: {m} vs {want:?}"
                    );
                    let r = rounded[k].to_bits() as f64 / 65536.0;
                    assert!((r - want[k]).abs() <= 0.5 / 65536.0 + 1e-7, "{r} vs {want:?}");
                    // f32 has 24 bits for the sum a i + b j + c: the ordinary cameras only.
                    if d.c.iter().all(|x| x.abs() < 100.0) {
                        let f = float.ray_dir(&float.film(i, j), lens)[k] as f64;
                        assert!((f - want[k]).abs() < 1e-5, "f32 {f} vs {want:?}");
                    }
                }
            }
        }
    }
}
