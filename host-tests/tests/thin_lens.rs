//! The thin lens's circle of confusion, measured on the picture of a tiny
//! bright sphere at several depths (Q16.16 renders).
//!
//! Derivation (also in `docs/accuracy.md`): the camera of SPEC section 3 sends
//! each film point's rays from lens points L (|L| <= a) towards the point P
//! where its chief ray meets the plane in focus, depth z_f = f N / (N - f); a
//! film point x (film at distance N) has P = x z_f / N. At depth z the ray from
//! L is at the lateral position L + (P - L) z / z_f = x z / N + L (1 - z / z_f).
//! A point Q at depth z is therefore seen by the film points
//! x = (N / z) Q - N L (1 / z - 1 / z_f): as L runs over the lens disk, these
//! fill a disc around Q's pinhole image of radius
//!
//!     c = a N |1/z - 1/z_f|          (film units; / pixel pitch for pixels)
//!
//! the circle of confusion. A sphere of radius r at depth z images (pinhole)
//! as a disc of radius rho = N r / sqrt(z^2 - r^2); with the lens, each film
//! point sees it through the share of the lens for which the shifted disc
//! covers it, so the picture is the disc of radius rho spread by the disc of
//! radius c. For two uniform discs the second moments add:
//! <s^2> = c^2 / 2 + rho^2 / 2, so the measured radius sqrt(2 <s^2>) must be
//! sqrt(c^2 + rho^2); and no pixel lies farther than c + rho from the centre.

mod common;

use common::render_fixed;
use lensray_host::Image;
use lensray_testkit::measure::luma;

/// 81 pixels across a film 81/64 wide: pitch 1/64, the centre pixel on the axis.
const SIDE: u32 = 81;
const PITCH: f64 = 1.0 / 64.0;
const N: f64 = 8.0;
const F: f64 = 4.0;
const A: f64 = 0.3;

/// Focus depth f N / (N - f) = 8.
fn z_focus() -> f64 {
    F * N / (N - F)
}

/// The thin-lens circle of confusion at depth z, in pixels.
fn coc_pixels(z: f64) -> f64 {
    A * N * (1.0 / z - 1.0 / z_focus()).abs() / PITCH
}

/// Renders a white, flat-lit sphere of radius r at depth z on black;
/// `brightness` scales its colour (pixels are means, clamped after averaging).
/// Every pixel casts all its `samples` (`adaptive off`): the picture is the
/// lens's, not where adaptive sampling stops a pixel.
fn tiny_sphere(z: f64, r: f64, brightness: f64, samples: u32) -> Image {
    let text = format!(
        "width {}\naspect_ratio 1\nimage_distance {N}\nfocal_length {F}\nradius {A}\npoint {samples}\nadaptive off\n\
         ambient_light {brightness} {brightness} {brightness}\n\
         object sphere\nKa 1 1 1\nKd 0 0 0\nscale {r} {r} {r}\ntranslate 0 0 -{z}\n",
        SIDE as f64 * PITCH
    );
    render_fixed(&text, SIDE, SIDE, None)
}

/// (centroid, sqrt(2 <s^2>), farthest lit pixel's distance, lit pixels).
fn disc(img: &Image) -> ((f64, f64), f64, f64, usize) {
    let mut px = Vec::new();
    for y in 0..img.height {
        for x in 0..img.width {
            let l = luma(img, x, y);
            if l > 0.0 {
                px.push((x as f64, y as f64, l));
            }
        }
    }
    let s: f64 = px.iter().map(|p| p.2).sum();
    let cx = px.iter().map(|p| p.0 * p.2).sum::<f64>() / s;
    let cy = px.iter().map(|p| p.1 * p.2).sum::<f64>() / s;
    let d2 = |p: &(f64, f64, f64)| (p.0 - cx).powi(2) + (p.1 - cy).powi(2);
    let m2 = px.iter().map(|p| p.2 * d2(p)).sum::<f64>() / s;
    let far = px.iter().map(|p| d2(p).sqrt()).fold(0.0, f64::max);
    ((cx, cy), (2.0 * m2).sqrt(), far, px.len())
}

#[test]
fn a_tiny_sphere_off_focus_images_as_the_circle_of_confusion() {
    for z in [5.0, 6.0, 16.0] {
        // Radius for a one-pixel pinhole image: rho = N r / z = 1 pixel.
        let r = z * PITCH / N;
        let rho = N * r / (z * z - r * r).sqrt() / PITCH;
        let c = coc_pixels(z);
        // Peak share of the lens that sees the sphere: (rho / c)^2; scale it to
        // about 70 % of white so that nothing clamps.
        let img = tiny_sphere(z, r, 0.7 * (c / rho).powi(2), 1024);
        let (centre, radius, far, lit) = disc(&img);
        let want = (c * c + rho * rho).sqrt();
        eprintln!(
            "depth {z}: circle of confusion {c:.3} px, predicted radius {want:.3}, measured {radius:.3} \
             ({:+.1} %), farthest lit pixel {far:.2} px, {lit} pixels lit, centre {centre:.2?}",
            (radius / want - 1.0) * 100.0
        );
        assert!(
            (radius / want - 1.0).abs() < 0.10,
            "depth {z}: radius {radius:.3} px, predicted {want:.3}"
        );
        // A disc: nothing beyond its rim, and lit out to near it.
        assert!(
            far <= c + rho + 1.0,
            "depth {z}: a pixel lit {far:.2} px out, the rim is at {:.2}",
            c + rho
        );
        assert!(
            far >= c - 1.5,
            "depth {z}: lit only to {far:.2} px, the rim is at {:.2}",
            c + rho
        );
        assert!(
            (centre.0 - 40.0).abs() < 0.5 && (centre.1 - 40.0).abs() < 0.5,
            "{centre:?}"
        );
    }
}

#[test]
fn at_the_focus_depth_the_tiny_sphere_shrinks_to_a_pixel() {
    assert_eq!(coc_pixels(z_focus()), 0.0);
    // rho = 0.75 pixel: in focus, every lens sample meets the sphere at the same
    // film point, so the picture is the pinhole one.
    let z = z_focus();
    let img = tiny_sphere(z, 0.75 * z * PITCH / N, 1.0, 256);
    let (centre, radius, far, lit) = disc(&img);
    eprintln!("depth {z} (in focus): measured radius {radius:.3} px, farthest lit {far:.2}, {lit} pixel(s) lit");
    assert!(
        lit <= 5 && far <= 1.0 && radius <= 1.0,
        "{lit} pixels lit, radius {radius}"
    );
    assert_eq!(
        img.get(40, 40),
        embedded_graphics::pixelcolor::Rgb888::new(255, 255, 255)
    );
    assert!((centre.0 - 40.0).abs() < 0.5 && (centre.1 - 40.0).abs() < 0.5);
}
