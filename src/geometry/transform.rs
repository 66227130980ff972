//! Affine transforms: exact `f64` matrices at set-up, precise [`Scalar`] rows
//! on the per-ray path.

use crate::geometry::vec3::Vec3;
use crate::number::Scalar;

/// A 3×4 affine matrix in `f64`, built once per scene (parser, camera).
///
/// Column 3 is the translation. Products and inverses are exact to f64
/// rounding, so set-up adds no error of its own before rounding to `S`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Mat34(pub [[f64; 4]; 3]);

impl Mat34 {
    /// The identity.
    pub const IDENTITY: Mat34 = Mat34([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]);

    /// Scaling by `s`.
    pub fn scale(s: [f64; 3]) -> Mat34 {
        Mat34([[s[0], 0.0, 0.0, 0.0], [0.0, s[1], 0.0, 0.0], [0.0, 0.0, s[2], 0.0]])
    }

    /// Translation by `t`.
    pub fn translate(t: [f64; 3]) -> Mat34 {
        Mat34([[1.0, 0.0, 0.0, t[0]], [0.0, 1.0, 0.0, t[1]], [0.0, 0.0, 1.0, t[2]]])
    }

    /// Rotation by `degrees` about axis 0 (x), 1 (y) or 2 (z), right-handed.
    pub fn rotate(axis: usize, degrees: f64) -> Mat34 {
        let (s, c) = sin_cos_degrees(degrees);
        let mut m = Mat34::IDENTITY;
        // The two axes the rotation mixes, in cyclic order (y,z), (z,x), (x,y).
        let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
        m.0[i][i] = c;
        m.0[i][j] = -s;
        m.0[j][i] = s;
        m.0[j][j] = c;
        m
    }

    /// `self ∘ first`: applies `first`, then `self`.
    pub fn after(&self, first: &Mat34) -> Mat34 {
        let (a, b) = (&self.0, &first.0);
        let mut r = [[0.0; 4]; 3];
        for (i, row) in r.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
                if j == 3 {
                    *x += a[i][3];
                }
            }
        }
        Mat34(r)
    }

    /// Determinant of the linear part.
    pub fn det(&self) -> f64 {
        let m = &self.0;
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    }

    /// The inverse, or `None` when the linear part is singular.
    pub fn inverse(&self) -> Option<Mat34> {
        let m = &self.0;
        let d = self.det();
        if d == 0.0 || !d.is_finite() {
            return None;
        }
        let inv_d = 1.0 / d;
        let mut r = [[0.0; 4]; 3];
        // Adjugate / determinant for the linear part.
        for (i, row) in r.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().take(3).enumerate() {
                let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
                let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
                *x = (m[j1][i1] * m[j2][i2] - m[j1][i2] * m[j2][i1]) * inv_d;
            }
        }
        // Translation: -A⁻¹ t.
        for row in r.iter_mut() {
            row[3] = -(row[0] * m[0][3] + row[1] * m[1][3] + row[2] * m[2][3]);
        }
        Some(Mat34(r))
    }

    /// The transpose of the linear part, without translation (for normals).
    pub fn linear_transpose(&self) -> Mat34 {
        let m = &self.0;
        let mut r = [[0.0; 4]; 3];
        for (i, row) in r.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().take(3).enumerate() {
                *x = m[j][i];
            }
        }
        Mat34(r)
    }

    /// Applies to a point (`affine`) or a direction.
    pub fn apply(&self, v: [f64; 3], affine: bool) -> [f64; 3] {
        let m = &self.0;
        let t = if affine { 1.0 } else { 0.0 };
        [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] + m[i][3] * t)
    }
}

/// `(sin, cos)` of an angle in degrees, exact at multiples of 90°.
pub fn sin_cos_degrees(degrees: f64) -> (f64, f64) {
    // Reduce to [0, 360) so that quarter turns give exact 0 and ±1.
    let mut d = degrees % 360.0;
    if d < 0.0 {
        d += 360.0;
    }
    match d {
        0.0 => (0.0, 1.0),
        90.0 => (1.0, 0.0),
        180.0 => (0.0, -1.0),
        270.0 => (-1.0, 0.0),
        _ => {
            let r = d * (core::f64::consts::PI / 180.0);
            (libm::sin(r), libm::cos(r))
        }
    }
}

/// An affine transform rounded to `S`: three precise rows.
#[derive(Copy, Clone, Debug)]
pub struct Affine<S: Scalar> {
    rows: [S::Row; 3],
}

impl<S: crate::number::BakeScalar> crate::bytes::Field for Affine<S> {
    crate::bytes::baked_fields!(Affine { rows });
}

impl<S: Scalar> Affine<S> {
    /// Rounds an exact matrix to `S`'s row format.
    pub fn from_mat(m: &Mat34) -> Self {
        Affine {
            rows: [0, 1, 2].map(|i| S::row_from_f64(m.0[i])),
        }
    }

    /// Transforms a point (with translation).
    #[inline]
    pub fn point(&self, p: Vec3<S>) -> Vec3<S> {
        let a = p.to_array();
        Vec3::new(
            S::row_apply(&self.rows[0], a, true),
            S::row_apply(&self.rows[1], a, true),
            S::row_apply(&self.rows[2], a, true),
        )
    }

    /// Transforms a direction (no translation).
    #[inline]
    pub fn vector(&self, v: Vec3<S>) -> Vec3<S> {
        let a = v.to_array();
        Vec3::new(
            S::row_apply(&self.rows[0], a, false),
            S::row_apply(&self.rows[1], a, false),
            S::row_apply(&self.rows[2], a, false),
        )
    }

    /// Transforms a direction to a unit vector, with the transformed length
    /// and its reciprocal, at full precision (see `Kernels::rows_apply_unit`).
    #[inline]
    pub fn vector_unit(&self, v: Vec3<S>) -> (Vec3<S>, S, S) {
        let (u, len, inv) = S::rows_apply_unit(&self.rows, v.to_array());
        (Vec3::from_array(u), len, inv)
    }

    /// [`Transform::vector_unit`] of a precise direction where the number type
    /// has one (`Kernels::rows_apply_dir`: a camera ray's in Q16.16).
    #[inline]
    pub fn dir_unit(&self, d: &S::Dir) -> Option<(Vec3<S>, S, S)> {
        S::rows_apply_dir(&self.rows, d).map(|(u, len, inv)| (Vec3::from_array(u), len, inv))
    }

    /// Where the world ray `o + t d` meets this object's plane z = 0 (see
    /// `Kernels::plane_hit`), for `t_min < t < t_max`, with its texture's
    /// (side, scale) for hits beyond the range.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn plane_hit(
        &self,
        o: Vec3<S>,
        d: S::Dir,
        t_min: S,
        t_max: S,
        checker: (S, S),
        eye: Option<[S; 4]>,
        face: (usize, i8),
    ) -> Option<(S, S, S)> {
        S::plane_hit(&self.rows, o.to_array(), d, t_min, t_max, checker, eye, face)
    }

    /// `Kernels::plane_from_eye` of this object's rows. Set-up only.
    pub(crate) fn plane_from_eye(&self, eye: [f64; 3]) -> Option<[S; 4]> {
        S::plane_from_eye(&self.rows, eye)
    }

    /// The object-space point of the world ray `o + s d` (`d` held
    /// precisely), exactly and rounded once, and with `rim` (or `solid`) whether the line
    /// along it through the exact point meets the unit sphere, where the
    /// type has the kernel (`Kernels::exact_point`).
    #[inline]
    pub fn exact_point(
        &self,
        o: Vec3<S>,
        d: &S::Dir,
        s: S,
        rim: Option<Vec3<S>>,
        solid: u8,
    ) -> Option<(Vec3<S>, crate::number::Decided)> {
        S::exact_point(&self.rows, o.to_array(), d, s, rim.map(Vec3::to_array), solid)
            .map(|(p, r)| (Vec3::from_array(p), r))
    }

    /// The checker's cells of a hit retaken from the exact ray, where the
    /// type has the kernel (`Kernels::exact_cells`).
    #[inline]
    pub fn exact_cells(
        &self,
        o: Vec3<S>,
        d: &S::Dir,
        s: S,
        hit: (Vec3<S>, Vec3<S>),
        surface: u8,
        checker: (S, S),
    ) -> Option<i64> {
        S::exact_cells(
            &self.rows,
            o.to_array(),
            d,
            s,
            (hit.0.to_array(), hit.1.to_array()),
            surface,
            checker,
        )
    }

    /// A hit's world distance retaken from the exact ray, at 2^-30, where
    /// the type has the kernel (`Kernels::exact_t`).
    #[inline]
    pub fn exact_t(&self, o: Vec3<S>, d: &S::Dir, s: S, hit: (Vec3<S>, Vec3<S>), surface: u8) -> Option<i64> {
        S::exact_t(
            &self.rows,
            o.to_array(),
            d,
            s,
            (hit.0.to_array(), hit.1.to_array()),
            surface,
        )
    }

    /// Row `i` (0 to 2) as held, `(a, b, c, t)` in `f64`. Set-up only.
    pub(crate) fn row_f64(&self, i: usize) -> [f64; 4] {
        S::row_to_f64(&self.rows[i.min(2)])
    }

    /// Entry (`i`, `j`) of the linear part (rounded to `S`; `j` 0 to 2).
    #[inline]
    pub fn entry(&self, i: usize, j: usize) -> S {
        S::row_entry(&self.rows[i], j)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12)
    }

    #[test]
    fn rotations_are_right_handed() {
        // +90° about z takes x to y; about x takes y to z; about y takes z to x.
        assert!(close(
            Mat34::rotate(2, 90.0).apply([1.0, 0.0, 0.0], false),
            [0.0, 1.0, 0.0]
        ));
        assert!(close(
            Mat34::rotate(0, 90.0).apply([0.0, 1.0, 0.0], false),
            [0.0, 0.0, 1.0]
        ));
        assert!(close(
            Mat34::rotate(1, 90.0).apply([0.0, 0.0, 1.0], false),
            [1.0, 0.0, 0.0]
        ));
    }

    #[test]
    fn inverse_undoes_a_composite() {
        let m = Mat34::translate([1.0, -2.0, 3.0])
            .after(&Mat34::rotate(1, 37.0))
            .after(&Mat34::scale([0.5, 2.0, 3.0]));
        let inv = m.inverse().unwrap();
        let p = [0.3, -0.7, 2.5];
        assert!(close(inv.apply(m.apply(p, true), true), p));
        assert!(Mat34::scale([1.0, 0.0, 1.0]).inverse().is_none());
    }

    #[test]
    fn fixed_rows_keep_thirty_fraction_bits() {
        use fixed::types::I16F16;
        let m = Mat34::rotate(0, -80.0);
        let a = Affine::<I16F16>::from_mat(&m);
        // A point at depth 100 transforms with an error far below one Q16.16 step
        // times the coordinate, which plain Q16.16 entries would give.
        let p = [3.0, -3.0, -100.0];
        let exact = m.apply(p, true);
        let got = a.point(Vec3::from_f64(p)).to_f64();
        for i in 0..3 {
            assert!((got[i] - exact[i]).abs() <= 2.0 / 65536.0, "{got:?} vs {exact:?}");
        }
    }
}
