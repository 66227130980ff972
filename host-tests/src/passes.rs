//! Progressive rendering on the host: the library's passes
//! ([`lensray::progressive`]), each drawn on all cores and handed over as an
//! image of the display after that pass.

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use lensray::progressive::{render_pass_row, Pass, Schedule};
use lensray::{Renderer, Scalar, Scene};
use rayon::prelude::*;

use crate::Image;
use lensray_testkit::Band;

/// Renders `scene` pass by pass as a display would show it, calling
/// `on_pass(index, pass, picture so far)` after each, and returns the final
/// image, the same pixels as [`crate::render_image`] with the same samples,
/// and the lens rays the passes and the adaptive survey cast.
///
/// `first_step` and `preview_samples` are [`Schedule::new`]'s; the display
/// starts black. Each pass draws its grid rows in parallel, each into its own
/// band, through the library's [`render_pass_row`].
pub fn render_passes<S: Scalar + Send + Sync>(
    scene: &Scene<S>,
    width: u32,
    height: u32,
    samples: Option<u32>,
    first_step: u32,
    preview_samples: u32,
    on_pass: &mut dyn FnMut(usize, &Pass, &Image),
) -> (Image, u64) {
    let renderer = Renderer::new_with_samples(scene, width, height, samples);
    let mut img = Image::filled(width, height, Rgb888::BLACK);
    let mut rays = renderer.stop_rule().map_or(0, |s| s.survey_rays as u64);
    for (i, pass) in Schedule::new(first_step, preview_samples, renderer.rays_per_pixel()).enumerate() {
        let step = pass.step.max(1);
        let bands: Vec<(Band, u64)> = (0..height)
            .step_by(step as usize)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|y0| {
                let rows = step.min(height - y0);
                let start = (y0 * width) as usize;
                let mut band = Band {
                    band: Image {
                        width,
                        height: rows,
                        pixels: img.pixels[start..start + (rows * width) as usize].to_vec(),
                    },
                    y0,
                    full_height: height,
                };
                let Ok(n) = render_pass_row(&renderer, &mut band, &pass, y0);
                (band, n)
            })
            .collect();
        for (b, n) in bands {
            rays += n;
            let start = (b.y0 * width) as usize;
            img.pixels[start..start + b.band.pixels.len()].copy_from_slice(&b.band.pixels);
        }
        on_pass(i, &pass, &img);
    }
    (img, rays)
}
