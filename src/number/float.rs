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
    type Row = [f32; 4];
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
    fn row_from_f64(r: [f64; 4]) -> [f32; 4] {
        r.map(|x| x as f32)
    }
    #[inline]
    fn row_apply(row: &[f32; 4], v: [Self; 3], affine: bool) -> Self {
        let s = row[0] * v[0] + row[1] * v[1] + row[2] * v[2];
        if affine {
            s + row[3]
        } else {
            s
        }
    }
    fn rows_apply_unit(rows: &[[f32; 4]; 3], v: [Self; 3]) -> ([Self; 3], Self, Self) {
        let w = rows.map(|r| Self::row_apply(&r, v, false));
        let (unit, len) = Self::normalize3(w);
        if len == 0.0 {
            return ([0.0; 3], 0.0, 0.0);
        }
        (unit, len, if len >= 1.0 { 0.0 } else { 1.0 / len })
    }
    fn dir_from(v: [Self; 3]) -> FloatDir {
        FloatDir { d: v, o_lo: [0.0; 3] }
    }
    #[inline]
    fn origin_low(d: &FloatDir) -> Option<[Self; 3]> {
        Some(d.o_lo)
    }
    type FilmMap = FloatFilmMap;
    type Film = [f32; 3];
    fn film_map(desc: &FilmMapDesc) -> FloatFilmMap {
        FloatFilmMap::new(desc)
    }
    #[inline]
    fn film_dir(map: &FloatFilmMap, i: i32, j: i32) -> [f32; 3] {
        map.film(i, j)
    }
    #[inline]
    fn film_ray_dir(map: &FloatFilmMap, film: &[f32; 3], lens: (i32, i32)) -> (FloatDir, [Self; 3]) {
        let u = map.ray_dir(film, lens);
        // A chief ray leaves from the eye itself: its bits below f32 ride along.
        let o_lo = if lens == (0, 0) { map.eye_lo } else { [0.0; 3] };
        (FloatDir { d: u, o_lo }, u)
    }
    fn plane_hit(
        rows: &[[f32; 4]; 3],
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
        let v = if self > 1.0 {
            1.0
        } else if self > 0.0 {
            self
        } else {
            0.0
        };
        (v * 255.0 + 0.5) as u8
    }
    #[inline]
    fn to_level(self) -> u32 {
        <f32 as Scalar>::mul(self, <f32 as Scalar>::from_i32(255))
            .floor_i32()
            .clamp(0, 65535) as u32
    }
}

impl BakeScalar for f32 {
    const TAG: u8 = 1;
    type BakedRow = [f32; 4];
    type BakedFilmMap = FloatFilmMap;
    fn film_map_fits(_: &Self::BakedFilmMap, _: u32, _: u32) -> bool {
        true
    }
}

/// f32's precise direction: the unit direction, with a chief ray's origin's
/// bits below f32 (the eye's, from the film map; 0 for other rays): the eye
/// rounded to f32 at 60 units is 2e-6 off, more than a grazing ray's margin
/// on an object scaled 0.3 (seed 14009).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FloatDir {
    d: [f32; 3],
    o_lo: [f32; 3],
}

/// f32's film map: the parts rounded to f32.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FloatFilmMap {
    a: [f32; 3],
    b: [f32; 3],
    c: [f32; 3],
    k_u: [f32; 3],
    k_v: [f32; 3],
    /// The eye less its f32 value (`FloatDir::o_lo` of chief rays).
    eye_lo: [f32; 3],
}

impl crate::bytes::Field for FloatFilmMap {
    crate::bytes::baked_fields!(FloatFilmMap {
        a,
        b,
        c,
        k_u,
        k_v,
        eye_lo
    });
}

impl FloatFilmMap {
    /// Rounds the parts. Set-up only.
    pub fn new(d: &FilmMapDesc) -> FloatFilmMap {
        let r = |v: [f64; 3]| v.map(|x| x as f32);
        FloatFilmMap {
            a: r(d.a),
            b: r(d.b),
            c: r(d.c),
            k_u: r(d.k_u),
            k_v: r(d.k_v),
            eye_lo: d.eye.map(|e| (e - e as f32 as f64) as f32),
        }
    }

    /// `D(i, j)`.
    #[inline]
    pub fn film(&self, i: i32, j: i32) -> [f32; 3] {
        let (i, j) = (i as f32, j as f32);
        [0, 1, 2].map(|k| self.a[k] * i + self.b[k] * j + self.c[k])
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

/// [`plane_hit`](crate::number::plane::plane_hit) in `f32`: the same plane through the same rows, with `d` of
/// any length.
fn plane_hit_f32(
    rows: &[[f32; 4]; 3],
    o: [f32; 3],
    d: &FloatDir,
    t_min: f32,
    t_max: f32,
    face: (usize, i8),
) -> Option<(f32, f32, f32)> {
    let (d, o_lo) = (d.d, d.o_lo);
    let ld = rows.map(|r| <f32 as Kernels>::row_apply(&r, d, false));
    let k = face.0.min(2);
    if ld[k] == 0.0 {
        return None;
    }
    let lo = rows.map(|r| <f32 as Kernels>::row_apply(&r, o, true) + <f32 as Kernels>::row_apply(&r, o_lo, false));
    // s in units of ld, t in world units.
    let s = -(lo[k] - face.1 as f32) / ld[k];
    let t = s * <f32 as Kernels>::length3(d);
    if !(t > t_min && t < t_max) {
        return None;
    }
    Some((t, lo[0] + ld[0] * s, lo[1] + ld[1] * s))
}
