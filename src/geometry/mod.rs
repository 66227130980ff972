//! Geometry over a number type: vectors, affine transforms and rays.

pub mod ray;
pub mod transform;
pub mod vec3;
