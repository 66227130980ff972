//! Affine 3×4 matrices in f64 for the independent evaluation
//! ([`crate::reference64`]): written apart from the library's own set-up,
//! so that a mistake there shows as a difference here.

/// An affine map: a 3×3 linear part and a translation, row-major.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Mat34(pub [[f64; 4]; 3]);

impl Mat34 {
    /// The identity map.
    pub const IDENTITY: Mat34 = Mat34([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]);

    /// Scaling by `s` along the axes.
    pub fn scale(s: [f64; 3]) -> Mat34 {
        let mut m = Mat34::IDENTITY;
        (0..3).for_each(|i| m.0[i][i] = s[i]);
        m
    }

    /// Translation by `t`.
    pub fn translate(t: [f64; 3]) -> Mat34 {
        let mut m = Mat34::IDENTITY;
        (0..3).for_each(|i| m.0[i][3] = t[i]);
        m
    }

    /// Rotation by `degrees` about axis 0 (x), 1 (y) or 2 (z), right-handed;
    /// quarter turns exact.
    pub fn rotate(axis: usize, degrees: f64) -> Mat34 {
        let d = degrees.rem_euclid(360.0);
        let (s, c) = if d % 90.0 == 0.0 {
            [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0)][(d / 90.0) as usize]
        } else {
            d.to_radians().sin_cos()
        };
        let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut m = Mat34::IDENTITY;
        m.0[i][i] = c;
        m.0[i][j] = -s;
        m.0[j][i] = s;
        m.0[j][j] = c;
        m
    }

    /// `self ∘ first`: `first` applied first.
    pub fn after(&self, first: &Mat34) -> Mat34 {
        let (a, b) = (&self.0, &first.0);
        Mat34(core::array::from_fn(|i| {
            core::array::from_fn(|j| {
                let t = if j == 3 { a[i][3] } else { 0.0 };
                (0..3).map(|k| a[i][k] * b[k][j]).sum::<f64>() + t
            })
        }))
    }

    /// The inverse map; `None` where the linear part is singular.
    pub fn inverse(&self) -> Option<Mat34> {
        let m = &self.0;
        let cof = |r: usize, c: usize| {
            let (r1, r2, c1, c2) = ((r + 1) % 3, (r + 2) % 3, (c + 1) % 3, (c + 2) % 3);
            m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
        };
        let det: f64 = (0..3).map(|c| m[0][c] * cof(0, c)).sum();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let mut inv = [[0.0; 4]; 3];
        for (i, row) in inv.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().take(3).enumerate() {
                *x = cof(j, i) / det;
            }
            row[3] = -(0..3).map(|k| row[k] * m[k][3]).sum::<f64>();
        }
        Some(Mat34(inv))
    }

    /// The transpose of the linear part (no translation): normals' map.
    pub fn linear_transpose(&self) -> Mat34 {
        let mut t = Mat34::IDENTITY;
        for i in 0..3 {
            for j in 0..3 {
                t.0[i][j] = self.0[j][i];
            }
        }
        t
    }

    /// `v` mapped: as a point (`affine`) or a vector.
    pub fn apply(&self, v: [f64; 3], affine: bool) -> [f64; 3] {
        let w = if affine { 1.0 } else { 0.0 };
        self.0.map(|r| r[0] * v[0] + r[1] * v[1] + r[2] * v[2] + r[3] * w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_map_after_its_inverse_is_the_identity() {
        let m = Mat34::translate([1.0, -2.0, 3.0])
            .after(&Mat34::rotate(1, 33.0))
            .after(&Mat34::scale([0.5, 2.0, 3.0]));
        let p = [0.3, -0.7, 1.1];
        let q = m.inverse().unwrap().apply(m.apply(p, true), true);
        assert!((0..3).all(|i| (p[i] - q[i]).abs() < 1e-12), "{q:?}");
        assert_eq!(Mat34::rotate(2, 90.0).apply([1.0, 0.0, 0.0], false), [0.0, 1.0, 0.0]);
    }
}
