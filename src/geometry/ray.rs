//! A ray in world space.

use crate::geometry::vec3::Vec3;
use crate::number::Scalar;

/// A primary ray in world space, with a unit direction.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Ray<S: Scalar> {
    /// Origin: the lens point.
    pub origin: Vec3<S>,
    /// Unit direction.
    pub dir: Vec3<S>,
    /// The same unit direction held more precisely (for the plane).
    pub(crate) precise: S::Dir,
}
