//! [`Scalar`] for `f32`: the reference that measures what fixed point costs.

use crate::number::film::FilmMapDesc;
use crate::number::scalar::{BakeScalar, Kernels, Scalar};

/// Correctly rounded `sqrt` of a positive f32: libm's, in software.
#[cfg(not(all(feature = "hw-sqrt", target_arch = "arm", target_abi = "eabihf")))]
#[inline]
fn sqrt_f32(x: f32) -> f32 {
    libm::sqrtf(x)
}

/// Correctly rounded `sqrt` of a positive f32: the FPU's `vsqrt.f32` (IEEE 754
/// requires it correctly rounded, so it equals libm's `sqrtf` bit for bit).
#[cfg(all(feature = "hw-sqrt", target_arch = "arm", target_abi = "eabihf"))]
#[inline]
fn sqrt_f32(x: f32) -> f32 {
    let r: u32;
    // Stable Rust refuses FPU register operands here (`vfp2` is an unstable
    // target feature), so the value goes through s0, which is saved and restored.
    // SAFETY: FPU register moves and one square root; s0 is left as it was.
    unsafe {
        core::arch::asm!(
            "vmov {save}, s0",
            "vmov s0, {x}",
            "vsqrt.f32 s0, s0",
            "vmov {r}, s0",
            "vmov s0, {save}",
            x = in(reg) x.to_bits(),
            r = lateout(reg) r,
            save = out(reg) _,
            options(pure, nomem, nostack, preserves_flags),
        );
    }
    f32::from_bits(r)
}

impl Scalar for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const MAX: Self = f32::MAX;
    const HIT_EPSILON: Self = 1.0 / 1024.0;
    const NAME: &'static str = "f32";
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn from_i32(i: i32) -> Self {
        i as f32
    }
    #[inline]
    fn from_q15(i: i32) -> Self {
        i as f32 * (1.0 / 32768.0)
    }
    #[inline]
    fn add(self, o: Self) -> Self {
        self + o
    }
    #[inline]
    fn sub(self, o: Self) -> Self {
        self - o
    }
    #[inline]
    fn mul(self, o: Self) -> Self {
        self * o
    }
    #[inline]
    fn div(self, o: Self) -> Self {
        if o == 0.0 {
            return if self == 0.0 {
                0.0
            } else if self > 0.0 {
                f32::MAX
            } else {
                -f32::MAX
            };
        }
        self / o
    }
    #[inline]
    fn neg(self) -> Self {
        -self
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabsf(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        if self <= 0.0 {
            0.0
        } else {
            sqrt_f32(self)
        }
    }
    fn powf(self, e: Self) -> Self {
        if e <= 0.0 {
            return 1.0;
        }
        if self <= 0.0 {
            return 0.0;
        }
        libm::powf(self, e)
    }
    #[inline]
    fn floor_i32(self) -> i32 {
        libm::floorf(self) as i32
    }
}

impl Kernels for f32 {
    #[inline(always)]
    fn mul_inline(self, o: Self) -> Self {
        self * o
    }
    #[inline(always)]
    fn quarter(self) -> Self {
        self * 0.25
    }
    const SHADOW_SKIPS_OWN_CONVEX: bool = false;
    const SHADOW_PRECISE_DIR: bool = false;
    const LOCAL_FROM_CENTRE: bool = true;
    fn checker_scale(side: f64) -> Self {
        <f32 as Scalar>::from_f64(1.0 / side)
    }
    #[inline]
    fn checker_cell(x: Self, _side: Self, scale: Self) -> i64 {
        <f32 as Scalar>::mul(x, scale).floor_i32() as i64
    }
    #[inline]
    fn checker_pos(x: Self, _side: Self, scale: Self) -> (i64, Self) {
        let u = <f32 as Scalar>::mul(x, scale);
        let cell = u.floor_i32();
        // At most just below 1: f32 rounding of u − floor(u) never reaches it but may.
        (cell as i64, (u - cell as f32).clamp(0.0, 1.0 - f32::EPSILON / 2.0))
    }
    type Row = FloatRow;
    /// f64, so that summing many samples adds no error of its own (the Q16.16
    /// sum is exact in i64): an f32 sum of seventy 0.1s lands below 7 and turns
    /// a colour of exactly 25.5 levels into 25 instead of 26.
    type Acc = f64;
    type Dir = FloatDir;

    fn length3(v: [Self; 3]) -> Self {
        Scalar::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    }
    fn normalize3(v: [Self; 3]) -> ([Self; 3], Self) {
        let len = Self::length3(v);
        if len == 0.0 {
            return ([0.0; 3], 0.0);
        }
        (v.map(|x| x / len), len)
    }
    fn within(v: [Self; 3], r: Self) -> bool {
        v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= r * r
    }
    #[inline]
    fn dot_positive(a: [Self; 3], b: [Self; 3]) -> bool {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0.0
    }
    fn row_from_f64(r: [f64; 4]) -> FloatRow {
        let hi = r.map(|x| x as f32);
        FloatRow {
            hi,
            lo: [0, 1, 2, 3].map(|k| (r[k] - hi[k] as f64) as f32),
            grazing2: GRAZING * GRAZING * (hi[0] * hi[0] + hi[1] * hi[1] + hi[2] * hi[2]),
        }
    }
    #[inline]
    fn row_apply(row: &FloatRow, v: [Self; 3], affine: bool) -> Self {
        let row = &row.hi;
        let s = row[0] * v[0] + row[1] * v[1] + row[2] * v[2];
        if affine {
            s + row[3]
        } else {
            s
        }
    }
    fn row_to_f64(row: &FloatRow) -> [f64; 4] {
        [0, 1, 2, 3].map(|k| row.hi[k] as f64 + row.lo[k] as f64)
    }
    fn row_entry(row: &FloatRow, j: usize) -> Self {
        row.hi[j % 3]
    }
    fn rows_apply_unit(rows: &[FloatRow; 3], v: [Self; 3]) -> ([Self; 3], Self, Self) {
        let w = [0, 1, 2].map(|k| Self::row_apply(&rows[k], v, false));
        let (unit, len) = Self::normalize3(w);
        if len == 0.0 {
            return ([0.0; 3], 0.0, 0.0);
        }
        (unit, len, if len >= 1.0 { 0.0 } else { 1.0 / len })
    }
    fn dir_from(v: [Self; 3]) -> FloatDir {
        FloatDir {
            d: v,
            o_lo: [0.0; 3],
            exact: [0; 3],
        }
    }
    #[inline]
    fn origin_low(d: &FloatDir) -> Option<[Self; 3]> {
        Some(d.o_lo)
    }
    type FilmMap = FloatFilmMap;
    type Film = FloatFilm;
    fn film_map(desc: &FilmMapDesc) -> FloatFilmMap {
        FloatFilmMap::new(desc)
    }
    #[inline]
    fn film_dir(map: &FloatFilmMap, i: i32, j: i32) -> FloatFilm {
        FloatFilm {
            d: map.film(i, j),
            exact: map.film_exact(i, j),
        }
    }
    #[inline]
    fn film_ray_dir(map: &FloatFilmMap, film: &FloatFilm, lens: (i32, i32)) -> (FloatDir, [Self; 3]) {
        let u = map.ray_dir(&film.d, lens);
        // A chief ray leaves from the eye itself: its bits below f32 ride along.
        let o_lo = if lens == (0, 0) { map.eye_lo } else { [0.0; 3] };
        let exact = map.lens_exact(&film.exact, lens);
        (FloatDir { d: u, o_lo, exact }, u)
    }
    #[inline(always)]
    fn plane_hit(
        rows: &[FloatRow; 3],
        o: [Self; 3],
        d: FloatDir,
        t_min: Self,
        t_max: Self,
        _checker: (Self, Self),
        _eye: Option<[Self; 4]>,
        face: (usize, i8),
    ) -> Option<(Self, Self, Self)> {
        // f32 holds far coordinates itself.
        plane_hit_f32(rows, o, &d, t_min, t_max, face)
    }
    #[inline]
    fn acc_zero() -> f64 {
        0.0
    }
    #[inline]
    fn acc_add(acc: f64, x: Self) -> f64 {
        acc + x as f64
    }
    fn acc_mean(acc: f64, n: u32) -> Self {
        (acc / n.max(1) as f64) as f32
    }
    #[inline]
    fn to_u8(self) -> u8 {
        half_up_levels(self) as u8
    }
    #[inline]
    fn to_fine(self) -> u16 {
        // The very sum to_u8 truncates (its own rounding: 0.5/255 gives 1),
        // times 256 (exact), less the half: (fine + 128) >> 8 is to_u8.
        ((half_up_levels(self) * 256.0) as u32 - 128) as u16
    }
    #[inline]
    fn to_level(self) -> u32 {
        <f32 as Scalar>::mul(self, <f32 as Scalar>::from_i32(255))
            .floor_i32()
            .clamp(0, 65535) as u32
    }
}

/// 255 v + ½ of a channel clamped to [0, 1] (NaN as 0), in f32: to_u8 truncates it.
#[inline]
fn half_up_levels(v: f32) -> f32 {
    let v = if v > 1.0 {
        1.0
    } else if v > 0.0 {
        v
    } else {
        0.0
    };
    v * 255.0 + 0.5
}

impl BakeScalar for f32 {
    const TAG: u8 = 1;
    type BakedRow = FloatRow;
    type BakedFilmMap = FloatFilmMap;
    fn film_map_fits(_: &Self::BakedFilmMap, _: u32, _: u32) -> bool {
        true
    }
}

/// f32's matrix row: the entries rounded to f32, with what rounding left
/// (`lo`, about 2⁻²⁴ of each), so that a plane met at grazing can be taken
/// again from its row to 48 bits (`plane_hit_f32`). The per-ray path reads `hi`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FloatRow {
    hi: [f32; 4],
    lo: [f32; 4],
    /// [`GRAZING`]² times the squared length of `hi`'s linear part: the
    /// grazing test's bound, from set-up rather than per ray.
    grazing2: f32,
}

impl crate::bytes::Field for FloatRow {
    crate::bytes::baked_fields!(FloatRow { hi, lo, grazing2 });
}

/// f32's precise direction: the unit direction, with a chief ray's origin's
/// bits below f32 (the eye's, from the film map; 0 for other rays): the eye
/// rounded to f32 at 60 units is 2e-6 off, more than a grazing ray's margin
/// on an object scaled 0.3; and a camera ray's direction exactly
/// (`FloatFilmMap::film_exact`; zero for other rays) for a plane met at grazing.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FloatDir {
    d: [f32; 3],
    o_lo: [f32; 3],
    exact: [i64; 3],
}

/// f32's film direction of a pixel: rounded, and exactly at the film map's
/// integer scale.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FloatFilm {
    d: [f32; 3],
    exact: [i64; 3],
}

/// f32's film map: the parts rounded to f32, and as integers at one scale
/// 2^-e (`exact_*`, chosen at set-up so that every direction of the image,
/// lens terms included, stays below 2^62): a camera ray's direction exactly,
/// to 2⁻⁴⁷ of the largest, in a few integer products.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FloatFilmMap {
    a: [f32; 3],
    b: [f32; 3],
    c: [f32; 3],
    k_u: [f32; 3],
    k_v: [f32; 3],
    /// The eye less its f32 value (`FloatDir::o_lo` of chief rays).
    eye_lo: [f32; 3],
    /// `a`, `b`, `c` times 2^e, rounded.
    exact_a: [i64; 3],
    exact_b: [i64; 3],
    exact_c: [i64; 3],
    /// `k_u`, `k_v` times 2^(e − 15), rounded: a Q1.15 lens sample times them is at 2^-e.
    exact_k_u: [i64; 3],
    exact_k_v: [i64; 3],
}

impl crate::bytes::Field for FloatFilmMap {
    crate::bytes::baked_fields!(FloatFilmMap {
        a,
        b,
        c,
        k_u,
        k_v,
        eye_lo,
        exact_a,
        exact_b,
        exact_c,
        exact_k_u,
        exact_k_v
    });
}

impl FloatFilmMap {
    /// Rounds the parts. Set-up only.
    pub fn new(d: &FilmMapDesc) -> FloatFilmMap {
        let r = |v: [f64; 3]| v.map(|x| x as f32);
        // The largest |component| of a direction (corners, lens reach) and of
        // each part: every product and sum below then stays under 2^63.
        let mut bound = 0.0f64;
        for k in 0..3 {
            let lens = libm::fabs(d.k_u[k]) + libm::fabs(d.k_v[k]);
            for x in [d.a[k], d.b[k], d.c[k], lens] {
                bound = bound.max(libm::fabs(x));
            }
            for (i, j) in [(1.0, 1.0), (d.i_max, 1.0), (1.0, d.j_max), (d.i_max, d.j_max)] {
                bound = bound.max(libm::fabs(d.a[k] * i + d.b[k] * j + d.c[k]) + lens);
            }
        }
        let e = if bound > 0.0 && bound.is_finite() {
            (libm::floor(libm::log2(4_611_686_018_427_387_904.0 / bound)) as i32).clamp(-900, 900)
        } else {
            0
        };
        let at = |v: [f64; 3], e: i32| v.map(|x| libm::round(x * libm::exp2(e as f64)) as i64);
        FloatFilmMap {
            a: r(d.a),
            b: r(d.b),
            c: r(d.c),
            k_u: r(d.k_u),
            k_v: r(d.k_v),
            eye_lo: d.eye.map(|e| (e - e as f32 as f64) as f32),
            exact_a: at(d.a, e),
            exact_b: at(d.b, e),
            exact_c: at(d.c, e),
            exact_k_u: at(d.k_u, e - 15),
            exact_k_v: at(d.k_v, e - 15),
        }
    }

    /// `D(i, j)`.
    #[inline]
    pub fn film(&self, i: i32, j: i32) -> [f32; 3] {
        let (i, j) = (i as f32, j as f32);
        [0, 1, 2].map(|k| self.a[k] * i + self.b[k] * j + self.c[k])
    }

    /// `D(i, j)` at scale 2^-e, exactly but for the parts' rounding (wrapping:
    /// only the result need fit, and it does for the image's pixels).
    #[inline]
    pub fn film_exact(&self, i: i32, j: i32) -> [i64; 3] {
        [0, 1, 2].map(|k| {
            self.exact_a[k]
                .wrapping_mul(i as i64)
                .wrapping_add(self.exact_b[k].wrapping_mul(j as i64))
                .wrapping_add(self.exact_c[k])
        })
    }

    /// [`FloatFilmMap::film_exact`] tilted by a lens sample (Q1.15).
    #[inline]
    pub fn lens_exact(&self, film: &[i64; 3], lens: (i32, i32)) -> [i64; 3] {
        if lens == (0, 0) {
            return *film;
        }
        [0, 1, 2].map(|k| {
            film[k]
                .wrapping_sub(self.exact_k_u[k].wrapping_mul(lens.0 as i64))
                .wrapping_sub(self.exact_k_v[k].wrapping_mul(lens.1 as i64))
        })
    }

    /// The unit direction along `D − s_x k_u − s_y k_v`.
    #[inline]
    pub fn ray_dir(&self, film: &[f32; 3], lens: (i32, i32)) -> [f32; 3] {
        let d = if lens == (0, 0) {
            *film
        } else {
            let (sx, sy) = (lens.0 as f32 / 32768.0, lens.1 as f32 / 32768.0);
            [0, 1, 2].map(|k| film[k] - sx * self.k_u[k] - sy * self.k_v[k])
        };
        <f32 as Kernels>::normalize3(d).0
    }
}

/// A plane is taken again in f64 where a camera ray meets it at a slope
/// (sine of the angle between ray and plane) under this: f32's hit there
/// moves by its direction's and rows' 2⁻²² divided by the slope, more than
/// 2⁻¹⁶ of its distance, enough to put a far checker row on the other colour.
const GRAZING: f32 = 1.0 / 64.0;

/// [`plane_hit`](crate::number::plane::plane_hit) in `f32`: the same plane through the same rows, with `d` of
/// any length.
#[inline(always)]
fn plane_hit_f32(
    rows: &[FloatRow; 3],
    o: [f32; 3],
    d: &FloatDir,
    t_min: f32,
    t_max: f32,
    face: (usize, i8),
) -> Option<(f32, f32, f32)> {
    let (dir, o_lo) = (d.d, d.o_lo);
    let ld = [0, 1, 2].map(|k| <f32 as Kernels>::row_apply(&rows[k], dir, false));
    let k = face.0.min(2);
    let lo = [0, 1, 2]
        .map(|k| <f32 as Kernels>::row_apply(&rows[k], o, true) + <f32 as Kernels>::row_apply(&rows[k], o_lo, false));
    // A camera ray (its exact direction known) at grazing: |ld_k| / |row_k| under GRAZING.
    // An OR, not `!= [0; 3]`: that is a call of memcmp (100 instructions on the M4F).
    if d.exact[0] | d.exact[1] | d.exact[2] != 0 && ld[k] * ld[k] < rows[k].grazing2 {
        return plane_hit_exact(rows, o, d, (lo[0], lo[1]), t_min, t_max, face);
    }
    if ld[k] == 0.0 {
        return None;
    }
    // s in units of ld, t in world units.
    let s = -(lo[k] - face.1 as f32) / ld[k];
    let t = s * <f32 as Kernels>::length3(dir);
    if !(t > t_min && t < t_max) {
        return None;
    }
    Some((t, lo[0] + ld[0] * s, lo[1] + ld[1] * s))
}

/// [`plane_hit_f32`] for a camera ray at grazing, in f64: the plane's height
/// of the origin from the row to 48 bits and the eye to 48 bits (chief
/// rays), and the point (x, y) along the film map's integer direction (2⁻⁴⁵),
/// so that the point lies where float64 puts it (the f32 direction's error
/// divided by the slope, 3e-5 at the horizon); t is
/// where the rounded direction meets the same plane, so that the shading
/// point `o + t d` lies on it (the exact distance along `d` put it 1e-3
/// under the plane 9,800 away, in its own shadow) and compares
/// with other objects' t along `d`. Cold: software f64 on the boards.
#[cold]
#[inline(never)]
fn plane_hit_exact(
    rows: &[FloatRow; 3],
    o: [f32; 3],
    d: &FloatDir,
    lo: (f32, f32),
    t_min: f32,
    t_max: f32,
    face: (usize, i8),
) -> Option<(f32, f32, f32)> {
    let lo = [lo.0, lo.1];
    let k = face.0.min(2);
    let row = |r: &FloatRow| -> [f64; 4] { core::array::from_fn(|c| r.hi[c] as f64 + r.lo[c] as f64) };
    let n = row(&rows[k]);
    let org: [f64; 3] = core::array::from_fn(|c| o[c] as f64 + d.o_lo[c] as f64);
    let dot = |a: &[f64; 4], v: &[f64; 3]| a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
    let h = dot(&n, &org) + n[3] - face.1 as f64;
    // Along the rounded unit direction, in its units.
    let s_d = -h / dot(&n, &d.d.map(|x| x as f64));
    let t = (s_d as f32) * <f32 as Kernels>::length3(d.d);
    if !(t > t_min && t < t_max) {
        return None;
    }
    // Along the exact direction, in its units: the point, from the origin's
    // x and y in f32 (their rows' entries hold them to 2⁻²⁴ anyway).
    let dd = d.exact.map(|x| x as f64);
    let s = (-h / dot(&n, &dd)) as f32;
    let df = d.exact.map(|x| x as f32);
    let at = |r: &FloatRow, lo: f32| {
        let m = &r.hi;
        lo + s * (m[0] * df[0] + m[1] * df[1] + m[2] * df[2])
    };
    Some((t, at(&rows[0], lo[0]), at(&rows[1], lo[1])))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::transform::Mat34;

    fn unit(v: [f64; 3]) -> [f64; 3] {
        let l = libm::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        v.map(|x| x / l)
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    /// A random camera's film map (any basis, eye within ±60, films from
    /// narrow to 40 times wider than deep, up to 2000 pixels a side, a lens
    /// or none), as `Camera::new` makes it.
    fn camera(next: &mut impl FnMut() -> f64) -> FilmMapDesc {
        let n = unit([0; 3].map(|_| next() * 2.0 - 1.0));
        let u = unit(cross([0; 3].map(|_| next() * 2.0 - 1.0), n));
        let v = cross(n, u);
        let (cols, rows) = (1 + (next() * 2000.0) as u32, 1 + (next() * 2000.0) as u32);
        let (width, big_n) = (0.5 + next() * 20.0, 0.5 + next() * 10.0);
        let p = width / cols as f64;
        let (w, h) = (width / 2.0, p * rows as f64 / 2.0);
        let tilt = if next() < 0.5 { 0.0 } else { next() * 3.0 };
        let eye = [0; 3].map(|_| next() * 120.0 - 60.0);
        FilmMapDesc::from_basis(eye, [u, v, n], p, (w, h), big_n, tilt, (cols, rows))
    }

    /// The film map's integer directions are the exact ones but for the
    /// parts' rounding: half a unit of 2^-e each, times the pixel's indices
    /// and the lens sample's 2^15, with 2^-e at most 2^-61 of the map's bound
    /// (its largest direction, lens reach included). At most 2^-45 of it.
    #[test]
    fn exact_film_directions_hold_45_bits() {
        let mut next = crate::test_rng::unit_f64(0x000F_113A);
        for _ in 0..2000 {
            let desc = camera(&mut next);
            let map = FloatFilmMap::new(&desc);
            let mut bound = 0f64;
            for k in 0..3 {
                let lens = libm::fabs(desc.k_u[k]) + libm::fabs(desc.k_v[k]);
                for (i, j) in [
                    (1.0, 1.0),
                    (desc.i_max, 1.0),
                    (1.0, desc.j_max),
                    (desc.i_max, desc.j_max),
                ] {
                    bound = bound.max(libm::fabs(desc.a[k] * i + desc.b[k] * j + desc.c[k]) + lens);
                }
            }
            let room = (desc.i_max + desc.j_max + 65537.0) * 2f64.powi(-62) * bound + bound * 1e-15;
            assert!(room <= bound * 2f64.powi(-45), "{desc:?}");
            for _ in 0..50 {
                let i = 1 + 2 * (next() * (desc.i_max - 1.0) / 2.0) as i32;
                let j = 1 + 2 * (next() * (desc.j_max - 1.0) / 2.0) as i32;
                let lens = if next() < 0.5 {
                    (0, 0)
                } else {
                    ((next() * 65535.0) as i32 - 32767, (next() * 65535.0) as i32 - 32767)
                };
                let exact = map.lens_exact(&map.film_exact(i, j), lens);
                assert!(exact.iter().all(|x| x.unsigned_abs() < 1 << 62), "{exact:?}");
                let (sx, sy) = (lens.0 as f64 / 32768.0, lens.1 as f64 / 32768.0);
                let want: [f64; 3] = core::array::from_fn(|k| {
                    desc.a[k] * i as f64 + desc.b[k] * j as f64 + desc.c[k] - sx * desc.k_u[k] - sy * desc.k_v[k]
                });
                // The scale, a power of two, from the largest component.
                let k = (0..3)
                    .max_by(|&p, &q| want[p].abs().total_cmp(&want[q].abs()))
                    .unwrap_or(0);
                let scale = libm::exp2(libm::round(libm::log2(exact[k] as f64 / want[k])));
                for k in 0..3 {
                    let off = libm::fabs(exact[k] as f64 / scale - want[k]);
                    assert!(off <= room, "{off:e} over {room:e}: {desc:?}");
                }
            }
        }
    }

    /// A camera ray (chief or lens) meeting a plane at a slope from 1e-5 to
    /// the grazing one: f32's point in the plane's space lies where float64
    /// puts it within the bound of the error analysis (the rows' f32 entries
    /// and f32's few roundings on the point, 2⁻²¹, and the cold path's 2⁻³⁶
    /// of distance over the slope), and its t where the rounded direction
    /// meets the plane. Without
    /// the cold path a slope of 1e-4 puts the point 1e-3 of the distance off.
    /// A plane of normal `normal` (and `w` in it) `h` ahead of `origin`,
    /// turned about its normal and scaled at random: its object → world map.
    fn plane_frame(normal: [f64; 3], w: [f64; 3], origin: [f64; 3], next: &mut impl FnMut() -> f64) -> Mat34 {
        let e1 = unit(cross(normal, w));
        let e2 = cross(normal, e1);
        let h = 0.5 + next() * 100.0;
        let p0: [f64; 3] = core::array::from_fn(|k| origin[k] + normal[k] * h);
        let frame = Mat34([0, 1, 2].map(|k| [e1[k], e2[k], normal[k], p0[k]]));
        let turn = Mat34::rotate(2, next() * 360.0);
        let scale = [0; 3].map(|_| 0.3 + next() * 5.0);
        frame.after(&turn).after(&Mat34::scale(scale))
    }

    #[test]
    fn grazing_plane_hits_agree_with_float64() {
        let mut next = crate::test_rng::unit_f64(0x06EA_021E);
        let (mut cold, mut checked) = (0, 0);
        for n in 0..20_000 {
            let desc = camera(&mut next);
            let map = FloatFilmMap::new(&desc);
            let i = 1 + 2 * (next() * (desc.i_max - 1.0) / 2.0) as i32;
            let j = 1 + 2 * (next() * (desc.j_max - 1.0) / 2.0) as i32;
            let chief = n % 2 == 0;
            let lens = if chief {
                (0, 0)
            } else {
                ((next() * 65535.0) as i32 - 32767, (next() * 65535.0) as i32 - 32767)
            };
            let film = <f32 as Kernels>::film_dir(&map, i, j);
            let (dir, _) = <f32 as Kernels>::film_ray_dir(&map, &film, lens);
            let (sx, sy) = (lens.0 as f64 / 32768.0, lens.1 as f64 / 32768.0);
            let d = unit(core::array::from_fn(|k| {
                desc.a[k] * i as f64 + desc.b[k] * j as f64 + desc.c[k] - sx * desc.k_u[k] - sy * desc.k_v[k]
            }));
            // A chief ray from the eye; a lens ray from a point exactly an f32's.
            let o = desc.eye.map(|x| x as f32);
            let origin = if chief { desc.eye } else { o.map(|x| x as f64) };
            // The plane: normal at `slope` to the ray, `h` ahead of the origin.
            let slope = libm::pow(10.0, -5.0 + 4.7 * next());
            let w = unit(cross(d, [0; 3].map(|_| next() * 2.0 - 1.0)));
            let normal = unit(core::array::from_fn(|k| {
                w[k] * libm::sqrt(1.0 - slope * slope) + d[k] * slope
            }));
            let inv = plane_frame(normal, w, origin, &mut next).inverse().unwrap();
            let rows = inv.0.map(<f32 as Kernels>::row_from_f64);
            // float64's hit.
            let (lo, ld) = (inv.apply(origin, true), inv.apply(d, false));
            let t64 = -lo[2] / ld[2];
            let (x64, y64) = (lo[0] + t64 * ld[0], lo[1] + t64 * ld[1]);
            let got = <f32 as Kernels>::plane_hit(&rows, o, dir, 0.0, f32::MAX, (0.0, 0.0), None, (2, 0));
            let Some((t, x, y)) = got else {
                panic!("no hit: slope {slope:e}, t {t64}");
            };
            checked += 1;
            // Above the grazing slope f32's own hit (unchanged) is all there is.
            if slope >= GRAZING as f64 * 0.99 {
                continue;
            }
            cold += 1;
            // The point's error relative to its distance: the cold path's (2⁻⁴⁵
            // of direction, 2⁻⁴⁶ of height, both over the slope).
            let rel = 2f64.powi(-36) / slope;
            // t: where the rounded direction meets the plane (the shading point on it).
            let dr = dir.d.map(|x| x as f64);
            let (ldr, lenr) = (inv.apply(dr, false), libm::sqrt(dot(dr, dr)));
            let t_d = -lo[2] / ldr[2] * lenr;
            assert!(
                libm::fabs(t as f64 - t_d) <= t_d * (2f64.powi(-36) / slope + 2f64.powi(-22)),
                "t {t} vs {t_d} (slope {slope:e}, chief {chief})"
            );
            for (r, got, want) in [(0, x, x64), (1, y, y64)] {
                let m = inv.0[r];
                let size = libm::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
                let along = libm::fabs(t64 * ld[r]);
                let room = 2f64.powi(-21) * (size * (dot(origin.map(libm::fabs), [1.0; 3]) + t64) + libm::fabs(m[3]))
                    + 2f64.powi(-24) * libm::fabs(want)
                    + along * rel;
                assert!(
                    libm::fabs(got as f64 - want) <= room,
                    "coordinate {r}: {got} vs {want} (slope {slope:e}, t {t64}, chief {chief})"
                );
            }
        }
        assert!(cold > 8_000 && checked == 20_000, "{cold} grazing of {checked}");
    }
}
