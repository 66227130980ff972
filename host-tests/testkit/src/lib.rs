//! lensray's test kit: what the host tests, the fuzz targets and the `lensray`
//! command measure and check with. Images and how two differ, image measures,
//! the `Canvas` double of a display, the random scene generator and the
//! seeded fuzzer. It needs only the library and embedded-graphics (no threads,
//! no image codecs), so `fuzz/` builds on it alone.

mod canvas;
mod diff;
mod image;

pub mod fuzz;
pub mod measure;
pub mod scenegen;

pub use canvas::Band;
pub use diff::{Diff, LineErrors};
pub use image::Image;
