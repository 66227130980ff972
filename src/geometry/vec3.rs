//! 3-vectors over a [`Scalar`], with the arithmetic operators.
//!
//! The operators follow the [`Scalar`] rules: they saturate in Q16.16 and never
//! panic.

use crate::number::Scalar;
use core::ops::{Add, Mul, Neg, Sub};

/// A point, direction, normal or colour with three components.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Vec3<S> {
    /// x, or red.
    pub x: S,
    /// y, or green.
    pub y: S,
    /// z, or blue.
    pub z: S,
}

impl<S: Scalar> Vec3<S> {
    /// The zero vector.
    pub const ZERO: Self = Vec3 {
        x: S::ZERO,
        y: S::ZERO,
        z: S::ZERO,
    };

    /// A vector from its components.
    #[inline]
    pub const fn new(x: S, y: S, z: S) -> Self {
        Vec3 { x, y, z }
    }

    /// Rounds exact `f64` components (set-up only).
    pub fn from_f64(v: [f64; 3]) -> Self {
        Vec3::new(S::from_f64(v[0]), S::from_f64(v[1]), S::from_f64(v[2]))
    }

    /// The components as `f64` (tests and reports).
    pub fn to_f64(self) -> [f64; 3] {
        [self.x.to_f64(), self.y.to_f64(), self.z.to_f64()]
    }

    /// The components as an array.
    #[inline]
    pub fn to_array(self) -> [S; 3] {
        [self.x, self.y, self.z]
    }

    /// From an array.
    #[inline]
    pub fn from_array(a: [S; 3]) -> Self {
        Vec3::new(a[0], a[1], a[2])
    }

    /// Dot product (saturating).
    // One copy on the M0 (inlined at every site it took 2 KB of its flash);
    // the per-ray sites call `dot_inline`.
    #[cfg_attr(lensray_v6m, inline(never))]
    #[cfg_attr(not(lensray_v6m), inline(always))]
    pub fn dot(self, o: Self) -> S {
        self.dot_inline(o)
    }

    /// [`Vec3::dot`] in place, for the per-ray sites.
    #[inline(always)]
    pub fn dot_inline(self, o: Self) -> S {
        self.x
            .mul_inline(o.x)
            .add(self.y.mul_inline(o.y))
            .add(self.z.mul_inline(o.z))
    }

    /// `self * k` in place, for the per-ray sites (`*` is a call on the M0).
    #[inline(always)]
    pub fn scale(self, k: S) -> Self {
        Vec3::new(self.x.mul_inline(k), self.y.mul_inline(k), self.z.mul_inline(k))
    }

    /// Component-wise product (colours).
    #[inline(always)]
    pub fn hadamard(self, o: Self) -> Self {
        Vec3::new(self.x.mul_inline(o.x), self.y.mul_inline(o.y), self.z.mul_inline(o.z))
    }

    /// `self * 1/4`, component by component, without the products.
    #[inline(always)]
    pub fn quarter(self) -> Self {
        Vec3::new(self.x.quarter(), self.y.quarter(), self.z.quarter())
    }

    /// [`Vec3::hadamard`] by a light's colour: white (every component 1)
    /// leaves `self` as it is, which is each type's product by 1, for free.
    #[inline(always)]
    pub fn tinted(self, light: Self) -> Self {
        if light.x == S::ONE && light.y == S::ONE && light.z == S::ONE {
            self
        } else {
            self.hadamard(light)
        }
    }

    /// Unit vector along `self` and the length of `self`; zero stays zero.
    #[inline]
    pub fn normalize_len(self) -> (Self, S) {
        let (u, l) = S::normalize3(self.to_array());
        (Vec3::from_array(u), l)
    }

    /// Unit vector along `self`; zero stays zero.
    #[inline]
    pub fn normalize(self) -> Self {
        self.normalize_len().0
    }

    /// Length, without intermediate overflow.
    #[inline]
    pub fn length(self) -> S {
        S::length3(self.to_array())
    }
}

impl<S: Scalar> Add for Vec3<S> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Vec3::new(self.x.add(o.x), self.y.add(o.y), self.z.add(o.z))
    }
}

impl<S: Scalar> Sub for Vec3<S> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Vec3::new(self.x.sub(o.x), self.y.sub(o.y), self.z.sub(o.z))
    }
}

impl<S: Scalar> Neg for Vec3<S> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Vec3::new(self.x.neg(), self.y.neg(), self.z.neg())
    }
}

impl<S: Scalar> Mul<S> for Vec3<S> {
    type Output = Self;
    // One copy on the M0 (18 inlined copies took 3.9 KB of its flash); the
    // per-ray sites call `scale` instead.
    #[cfg_attr(lensray_v6m, inline(never))]
    #[cfg_attr(not(lensray_v6m), inline)]
    fn mul(self, k: S) -> Self {
        self.scale(k)
    }
}

impl<S: crate::bytes::Field> crate::bytes::Field for Vec3<S> {
    crate::bytes::baked_fields!(Vec3 { x, y, z });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::number::Kernels;
    use fixed::types::I16F16;

    /// A quarter is the product by 1/4 in both types: every Q16.16 value's
    /// low bits and sign, and the extremes.
    #[test]
    fn quarter_is_the_product_by_a_quarter() {
        let q = I16F16::from_q15(8192);
        let edges = [
            i32::MIN,
            i32::MIN + 1,
            i32::MIN + 2,
            i32::MAX - 2,
            i32::MAX - 1,
            i32::MAX,
        ];
        for bits in (-70_000..70_000)
            .chain((0..1 << 16).map(|k: i32| k.wrapping_mul(32_771)))
            .chain(edges)
        {
            let x = I16F16::from_bits(bits);
            assert_eq!(x.quarter(), x.mul_inline(q), "{bits}");
        }
        for x in [f32::MIN, -1.5, -0.0, 0.0, 1e-40, 0.3, 1.0, f32::MAX, f32::INFINITY] {
            assert_eq!(x.quarter().to_bits(), x.mul_inline(f32::from_q15(8192)).to_bits());
        }
    }

    /// A white light's `tinted` is the product by 1 it skips, bit for bit,
    /// in both types and at the extremes.
    #[test]
    fn white_tint_is_the_product_by_one() {
        let white = Vec3::new(I16F16::ONE, I16F16::ONE, I16F16::ONE);
        for bits in [
            i32::MIN,
            i32::MIN + 1,
            -65537,
            -65536,
            -1,
            0,
            1,
            32768,
            65535,
            65536,
            65537,
            i32::MAX,
        ] {
            let v = Vec3::new(
                I16F16::from_bits(bits),
                I16F16::from_bits(!bits),
                I16F16::from_bits(bits),
            );
            assert_eq!(v.tinted(white), v.hadamard(white), "{bits}");
        }
        let white = Vec3::new(1.0f32, 1.0, 1.0);
        for x in [f32::MIN, -1.5, -0.0, 0.0, 1e-40, 0.3, 1.0, f32::MAX, f32::INFINITY] {
            let v = Vec3::new(x, -x, x);
            assert_eq!(
                v.tinted(white).to_array().map(f32::to_bits),
                v.hadamard(white).to_array().map(f32::to_bits)
            );
        }
    }
}
