//! The paper's thin-lens camera (SPEC section 3), precomputed for one image size.
//!
//! Frames: *camera* coordinates have the lens centre at the origin, x along the
//! paper's u (right), y along v (up) and z along n (backwards: the camera looks
//! down −z). The film point of a pixel is `p_film = (u_c, v_r, −N)`.
//!
//! A thin lens of radius a and focal length f sends every ray from `p_lens` on
//! the lens towards `p_focus`, where the chief ray (through the lens centre)
//! meets the plane in focus at depth z_f = f·N / (N − f). Since
//! `p_focus = p_film · m` with m = z_f / N = f / (N − f), the direction
//! `p_focus − p_lens` is parallel to `p_film − p_lens / m`, which keeps every
//! number near the film's size however far the focus lies: what Q16.16 needs.
//!
//! The lens samples arrive from outside (see [`crate::camera::lfsr`]), so the camera
//! itself is deterministic.

use crate::camera::aperture::Aperture;
use crate::camera::sampler::Sampler;
pub use crate::geometry::ray::Ray;
use crate::geometry::vec3::Vec3;
use crate::number::film::FilmMapDesc;
use crate::number::Scalar;

pub mod aperture;
pub mod lfsr;
pub mod sampler;

/// Largest image side the camera accepts (pixel indices enter Q16.16 as
/// `2c + 1`, which must stay below 32768).
pub const MAX_IMAGE_SIDE: u32 = 8192;

/// A camera set up for one image size, in the number type `S`.
#[derive(Copy, Clone, Debug)]
pub struct Camera<S: Scalar> {
    /// Pixel → world direction of its rays, exactly (see [`crate::number::film`]).
    map: S::FilmMap,
    /// The lens centre E in world space: the chief rays' common origin.
    eye: Vec3<S>,
    /// a u and a v: where the lens sample's x and y move a ray's origin, world space.
    lens_u: Vec3<S>,
    lens_v: Vec3<S>,
    /// Pinhole (a = 0): one ray per pixel.
    pinhole: bool,
    /// Shape of the lens opening the samples are drawn on.
    aperture: Aperture,
    cols: u32,
    rows: u32,
}

impl<S: crate::number::BakeScalar> crate::bytes::Field for Camera<S> {
    crate::bytes::baked_fields!(Camera { map, eye, lens_u, lens_v, pinhole, aperture, cols, rows }, check(cam) {
        if !(1..=MAX_IMAGE_SIDE).contains(&cam.cols) || !(1..=MAX_IMAGE_SIDE).contains(&cam.rows) {
            return Err(crate::bytes::BakeError::OutOfRange("image side not in 1..=8192"));
        }
        if !S::film_map_fits(&cam.map, cam.cols, cam.rows) {
            return Err(crate::bytes::BakeError::OutOfRange("film map too large for the image"));
        }
    });
}

/// The camera statements of a scene, exactly as written (defaults filled in).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct CameraParams {
    /// Film width in world units (`width`).
    pub width: f64,
    /// Film width / height (`aspect_ratio`): the host's default image height.
    pub aspect_ratio: f64,
    /// Lens-to-film distance N (`image_distance`).
    pub image_distance: f64,
    /// Lens centre E (`lens_position`).
    pub lens_position: [f64; 3],
    /// Focal length f, 0 < f < N (`focal_length`).
    pub focal_length: f64,
    /// Viewing direction (`look`), not zero.
    pub look: [f64; 3],
    /// Up direction (`up`), not parallel to `look`.
    pub up: [f64; 3],
    /// Lens samples per pixel (`point`), 1..=65535.
    pub samples: u32,
    /// Lens radius a (`radius`); 0 is a pinhole.
    pub radius: f64,
    /// Blades of the aperture (`aperture_blades`): 0 is a round aperture, else
    /// the lens is a regular polygon of that many sides (3 to
    /// 16) inscribed in the circle of radius a.
    pub aperture_blades: u32,
    /// Rotation of the aperture polygon in degrees (`aperture_rotation`): at 0
    /// a corner points along the camera's u (right); positive turns towards v (up).
    pub aperture_rotation: f64,
    /// Adaptive lens sampling (`adaptive on|off`): a pixel stops taking lens
    /// samples once their mean is settled (see [`crate::Renderer::pixel_rays`]).
    pub adaptive: bool,
    /// How lens points are drawn (`sampler independent|stratified`).
    pub sampler: Sampler,
}

impl Default for CameraParams {
    fn default() -> Self {
        CameraParams {
            width: 10.0,
            aspect_ratio: 1.33,
            image_distance: 8.0,
            lens_position: [0.0; 3],
            focal_length: 4.0,
            look: [0.0, 0.0, -1.0],
            up: [0.0, 1.0, 0.0],
            samples: 1,
            radius: 0.0,
            aperture_blades: 0,
            aperture_rotation: 0.0,
            adaptive: true,
            sampler: Sampler::Stratified,
        }
    }
}

impl CameraParams {
    /// Distance of the plane in focus from the lens: f·N / (N − f).
    pub fn focus_depth(&self) -> f64 {
        self.focal_length * self.image_distance / (self.image_distance - self.focal_length)
    }

    /// The focal length that puts the plane in focus at distance `d > 0` with
    /// the image distance N kept (thin lens: 1/f = 1/N + 1/d), so the framing
    /// stays as it is: N d / (N + d), always between 0 and N.
    pub fn focal_length_for_distance(&self, d: f64) -> f64 {
        self.image_distance * d / (self.image_distance + d)
    }

    /// Refocuses at distance `d > 0` (`focus_distance`): sets the focal length
    /// by [`CameraParams::focal_length_for_distance`].
    pub fn set_focus_distance(&mut self, d: f64) {
        self.focal_length = self.focal_length_for_distance(d);
    }

    /// The f-number f / (2a); infinite for a pinhole.
    pub fn f_number(&self) -> f64 {
        self.focal_length / (2.0 * self.radius)
    }

    /// Sets the lens radius from an f-number `k > 0` (`f_number`) and the
    /// current focal length: a = f / (2k). Call it after any refocus.
    pub fn set_f_number(&mut self, k: f64) {
        self.radius = self.focal_length / (2.0 * k);
    }
}

/// The camera's orthonormal basis u, v, n in `f64` (n = −look, u = up × n).
///
/// `None` when `look` is zero or `up` is parallel to it.
pub fn basis(params: &CameraParams) -> Option<[[f64; 3]; 3]> {
    let unit = |v: [f64; 3]| {
        let l = libm::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if l > 0.0 && l.is_finite() {
            Some(v.map(|x| x / l))
        } else {
            None
        }
    };
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let n = unit(params.look.map(|x| -x))?;
    let up = unit(params.up)?;
    let c = cross(up, n);
    // Parallel, or so nearly that the basis would be noise.
    let s = libm::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if s < 1e-9 {
        return None;
    }
    let u = c.map(|x| x / s);
    let v = cross(n, u);
    Some([u, v, n])
}

/// Where a camera's film lies, in f64, for set-up: the basis (u, v, n),
/// the image distance N, the film's half sides W and H and the pixel pitch.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FilmFrame {
    basis: [[f64; 3]; 3],
    big_n: f64,
    half: (f64, f64),
    pitch: f64,
    size: (u32, u32),
    /// How far a lens ray's direction may turn from its pixel's chief ray:
    /// `asin(a / z_f)`, the lens radius over the focus distance; 0 for a pinhole.
    spread: f64,
}

impl FilmFrame {
    /// The film of `cols` × `rows` pixels (each clamped to 1..=[`MAX_IMAGE_SIDE`]).
    pub fn new(params: &CameraParams, cols: u32, rows: u32) -> Self {
        let cols = cols.clamp(1, MAX_IMAGE_SIDE);
        let rows = rows.clamp(1, MAX_IMAGE_SIDE);
        // Pixel pitch p, film half-width W and half-height H.
        let pitch = params.width / cols as f64;
        let (a, big_n, f) = (params.radius, params.image_distance, params.focal_length);
        // A lens ray runs from a lens point to the pixel's point in focus, at
        // depth z_f = N f / (N - f) or farther: a / z_f off its chief ray at most.
        let spread = if a > 0.0 && big_n > f && f > 0.0 {
            libm::asin((a * (big_n - f) / (big_n * f)).min(1.0))
        } else if a > 0.0 {
            core::f64::consts::FRAC_PI_2
        } else {
            0.0
        };
        FilmFrame {
            basis: basis(params).unwrap_or([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
            big_n: params.image_distance,
            half: (params.width / 2.0, pitch * rows as f64 / 2.0),
            pitch,
            size: (cols, rows),
            spread,
        }
    }

    /// The pixels any of whose rays (through any lens point) run within the
    /// angle `acos(cos)` of the unit world direction `axis`: columns
    /// `[0]..=[1]` and rows `[2]..=[3]`, a pixel wider on each side; every
    /// pixel where that cone reaches the film's plane or behind it.
    pub fn cone_pixels(&self, axis: [f64; 3], cos: f64) -> [i16; 4] {
        let any = [i16::MIN, i16::MAX, i16::MIN, i16::MAX];
        // A chief ray within the spread of that cone: the cone widened by it.
        let angle = libm::acos(cos.clamp(-1.0, 1.0)) + self.spread;
        if angle >= core::f64::consts::FRAC_PI_2 {
            return any;
        }
        let cos = libm::cos(angle);
        let [u, v, n] = self.basis;
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        // The axis in camera space: x along u, y along v, z forward (-n).
        let (ax, ay, az) = (dot(axis, u), dot(axis, v), -dot(axis, n));
        // The cone is the one tangent to a sphere of radius sin θ at the axis's tip.
        let rho = libm::sqrt((1.0 - cos * cos).max(0.0));
        if !(cos > 0.0 && az > rho * (1.0 + 1e-9) + 1e-12) {
            return any;
        }
        // The slopes m of the two planes through the eye tangent to it: x = m z (or y = m z).
        let den = az * az - rho * rho;
        let slopes = |a: f64| {
            let root = rho * libm::sqrt((a * a + den).max(0.0));
            ((a * az - root) / den, (a * az + root) / den)
        };
        let ((x0, x1), (y0, y1)) = (slopes(ax), slopes(ay));
        let big_n = self.big_n;
        self.film_box((big_n * x0, big_n * x1), (big_n * y0, big_n * y1))
    }

    /// The pixels some of whose rays (through any lens point) may run
    /// towards a plane: those whose chief ray is not turned away from the
    /// unit world direction `toward` by more than the spread and a margin
    /// for rounding (2^-10), the spread being how far a lens ray turns from
    /// its chief ray. A ray from the plane's side of the lens running away
    /// from it never meets it. Columns `[0]..=[1]` and rows `[2]..=[3]`, a
    /// pixel wider on each side; none where no chief ray comes near.
    pub fn plane_pixels(&self, toward: [f64; 3]) -> [i16; 4] {
        let angle = self.spread + 1.0 / 1024.0;
        if angle >= core::f64::consts::FRAC_PI_2 {
            return [i16::MIN, i16::MAX, i16::MIN, i16::MAX];
        }
        let [u, v, n] = self.basis;
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let ((w, h), big_n) = (self.half, self.big_n);
        // The chief ray of film point (x, y) is x u + y v - N n, no longer
        // than `longest`: it may reach the plane only where
        // x (u · τ) + y (v · τ) > N (n · τ) - sin(angle) longest.
        let longest = libm::sqrt(w * w + h * h + big_n * big_n);
        let (a, b) = (dot(u, toward), dot(v, toward));
        let c = big_n * dot(n, toward) - libm::sin(angle) * longest;
        // The film rectangle cut by that line spans its corners inside and
        // the points where the line crosses its edges.
        let corners = [(-w, -h), (w, -h), (w, h), (-w, h)]
            .into_iter()
            .filter(|&(x, y)| a * x + b * y >= c);
        let across = [-h, h]
            .map(|y| ((c - b * y) / a, y))
            .into_iter()
            .filter(|p| (-w..=w).contains(&p.0));
        let down = [-w, w]
            .map(|x| (x, (c - a * x) / b))
            .into_iter()
            .filter(|p| (-h..=h).contains(&p.1));
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for (x, y) in corners.chain(across).chain(down) {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if x0 > x1 {
            return [i16::MAX, i16::MIN, i16::MAX, i16::MIN];
        }
        self.film_box((x0, x1), (y0, y1))
    }

    /// The pixels whose centres lie within film x in `xs` and y in `ys`
    /// (film units, x right and y up from the film's centre), a pixel wider
    /// on each side.
    fn film_box(&self, xs: (f64, f64), ys: (f64, f64)) -> [i16; 4] {
        // x_c = -W + p (c + 1/2) and y_r = H - p (r + 1/2).
        let (p, (w, h)) = (self.pitch, self.half);
        let col = |x: f64| (x + w) / p - 0.5;
        let row = |y: f64| (h - y) / p - 0.5;
        let side = |lo: f64, hi: f64| {
            let clamp = |x: f64| x.clamp(-2.0, (MAX_IMAGE_SIDE + 2) as f64) as i16;
            (clamp(libm::floor(lo) - 1.0), clamp(libm::ceil(hi) + 1.0))
        };
        let (c0, c1) = side(col(xs.0), col(xs.1));
        let (r0, r1) = side(row(ys.1), row(ys.0));
        [c0, c1, r0, r1]
    }
}

impl<S: Scalar> Camera<S> {
    /// Sets the camera up for `cols` × `rows` pixels (square pixels: the film's
    /// height follows from its width and the row count).
    ///
    /// Sizes are clamped to 1..=[`MAX_IMAGE_SIDE`]; parameters are assumed
    /// validated by the parser (a degenerate basis falls back to the default view).
    pub fn new(params: &CameraParams, cols: u32, rows: u32) -> Self {
        let frame = FilmFrame::new(params, cols, rows);
        let (cols, rows) = frame.size;
        let [u, v, n] = frame.basis;
        let e = params.lens_position;
        let (p, half_w, half_h, big_n) = (frame.pitch, frame.half.0, frame.half.1, frame.big_n);
        // u_c = −W + p (c + ½) = (p/2)(2c + 1) − W; v_r = H − (p/2)(2r + 1).
        let f = params.focal_length;
        let pinhole = params.radius.is_nan() || params.radius <= 0.0;
        // m = z_f / N = f / (N − f); the tilt is a / m.
        let lens_tilt = if pinhole { 0.0 } else { params.radius * (big_n - f) / f };
        let radius = if pinhole { 0.0 } else { params.radius };
        let desc = FilmMapDesc::from_basis(e, [u, v, n], p, (half_w, half_h), big_n, lens_tilt, (cols, rows));
        Camera {
            map: S::film_map(&desc),
            eye: Vec3::from_f64(e),
            lens_u: Vec3::from_f64(u.map(|x| x * radius)),
            lens_v: Vec3::from_f64(v.map(|x| x * radius)),
            pinhole,
            aperture: Aperture::regular(params.aperture_blades, params.aperture_rotation),
            cols,
            rows,
        }
    }

    /// Image width in pixels.
    pub fn cols(&self) -> u32 {
        self.cols
    }

    /// Image height in pixels.
    pub fn rows(&self) -> u32 {
        self.rows
    }

    /// Whether this is a pinhole camera (radius 0): one ray per pixel.
    pub fn is_pinhole(&self) -> bool {
        self.pinhole
    }

    /// The shape of the lens opening (`aperture_blades`, `aperture_rotation`).
    pub fn aperture(&self) -> &Aperture {
        &self.aperture
    }

    /// `(2c + 1, 2r + 1)`: the pixel centre in half-pixel units.
    #[inline]
    fn doubled(col: u32, row: u32) -> (i32, i32) {
        (
            2 * col.min(MAX_IMAGE_SIDE) as i32 + 1,
            2 * row.min(MAX_IMAGE_SIDE) as i32 + 1,
        )
    }

    /// The world direction of pixel (`col`, `row`)'s chief ray, exactly:
    /// what [`CameraSample::film`] takes.
    #[inline]
    pub fn film_point(&self, col: u32, row: u32) -> FilmPoint<S> {
        let (i, j) = Self::doubled(col, row);
        FilmPoint {
            film: S::film_dir(&self.map, i, j),
        }
    }

    /// [`Camera::film_point`] of (`col`, `row`) from `left`, that of
    /// (`col - 1`, `row`): the same point, stepped along the row where the
    /// number type can.
    #[inline]
    pub fn film_point_right_of(&self, left: &FilmPoint<S>, col: u32, row: u32) -> FilmPoint<S> {
        if col == 0 || col > MAX_IMAGE_SIDE {
            return self.film_point(col, row);
        }
        let (i, j) = Self::doubled(col - 1, row);
        FilmPoint {
            film: S::film_dir_right(&self.map, &left.film, i, j),
        }
    }

    /// The camera's one ray-making entry: the ray of `sample`, whose lens
    /// point was drawn outside (by the renderer's sampler), so the camera
    /// holds no random state.
    #[inline]
    pub fn generate_ray(&self, sample: &CameraSample<'_, S>) -> Ray<S> {
        match sample.lens {
            None => self.chief_ray_from(sample.film),
            Some(lens) => self.lens_ray_from(sample.film, lens),
        }
    }

    /// The chief ray of a pixel: from the lens centre E through its film point
    /// (`−N n + u_c u + v_r v`), normalised.
    #[inline]
    fn chief_ray_from(&self, f: &FilmPoint<S>) -> Ray<S> {
        // The lens centre adds nothing: sample (0, 0).
        let (precise, dir) = S::film_ray_dir(&self.map, &f.film, (0, 0));
        Ray {
            origin: self.eye,
            dir: Vec3::from_array(dir),
            precise,
        }
    }

    /// The ray from the lens point `lens = (s_x, s_y)` (Q1.15, on the unit disk)
    /// towards the pixel's point in focus.
    #[inline]
    fn lens_ray_from(&self, f: &FilmPoint<S>, lens: (i32, i32)) -> Ray<S> {
        let (sx, sy) = (S::from_q15(lens.0), S::from_q15(lens.1));
        // p_focus − p_lens, divided by m: p_film − p_lens / m, in world space.
        let (precise, dir) = S::film_ray_dir(&self.map, &f.film, lens);
        Ray {
            // The lens point E + s_x a u + s_y a v.
            origin: self.eye + self.lens_u * sx + self.lens_v * sy,
            dir: Vec3::from_array(dir),
            precise,
        }
    }
}

/// What one camera ray is made from: a pixel's film point and where on the
/// lens the ray leaves.
#[derive(Copy, Clone, Debug)]
pub struct CameraSample<'a, S: Scalar> {
    /// The pixel's film point (the camera's film point), shared by its rays.
    pub film: &'a FilmPoint<S>,
    /// The lens point `(s_x, s_y)` (Q1.15, on the unit disk; see
    /// the renderer's sampler), or `None` for the chief ray through the lens
    /// centre (a pinhole's only ray).
    pub lens: Option<(i32, i32)>,
}

/// A pixel's chief-ray direction in world space, exact (see [`crate::number::film`]):
/// computed once per pixel and shared by its lens samples.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FilmPoint<S: Scalar> {
    film: S::Film,
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixed::types::I16F16;

    #[test]
    fn centre_pixel_chief_ray_looks_down_the_axis() {
        let params = CameraParams::default();
        // An odd size has a pixel whose centre is the film's centre.
        let cam = Camera::<I16F16>::new(&params, 641, 481);
        let ray = cam.generate_ray(&CameraSample {
            film: &cam.film_point(320, 240),
            lens: None,
        });
        let d = ray.dir.to_f64();
        assert!(
            d[0].abs() < 1e-4 && d[1].abs() < 1e-4 && (d[2] + 1.0).abs() < 1e-4,
            "{d:?}"
        );
        assert_eq!(ray.origin.to_f64(), [0.0; 3]);
    }

    /// Film points stepped along a row are the film points themselves, in
    /// both types, for a few sizes and views.
    #[test]
    fn stepped_film_points_are_the_film_points() {
        fn check<S: Scalar>(params: &CameraParams, cols: u32, rows: u32) {
            let cam = Camera::<S>::new(params, cols, rows);
            for row in [0, rows / 2, rows - 1] {
                let mut left = cam.film_point(0, row);
                for col in 1..cols {
                    let f = cam.film_point_right_of(&left, col, row);
                    assert_eq!(f, cam.film_point(col, row), "({col}, {row}) of {cols}x{rows}");
                    left = f;
                }
            }
        }
        let tilted = CameraParams {
            look: [0.3, -0.2, -1.0],
            up: [0.1, 1.0, 0.2],
            lens_position: [1.25, -0.3, 2.0],
            ..CameraParams::default()
        };
        for params in [CameraParams::default(), tilted] {
            for (cols, rows) in [(1, 1), (160, 120), (641, 481), (1000, 7)] {
                check::<I16F16>(&params, cols, rows);
                check::<f32>(&params, cols, rows);
            }
        }
    }

    #[test]
    fn corner_film_points_follow_the_spec() {
        let params = CameraParams::default();
        let cam = Camera::<f32>::new(&params, 640, 480);
        // Pixel (0, 0): u = −W + p/2, v = H − p/2, with p = 10/640, H = p·480/2.
        let p = 10.0 / 640.0;
        // The chief ray from the eye (the origin) runs along (u, v, −N).
        let d = cam
            .generate_ray(&CameraSample {
                film: &cam.film_point(0, 0),
                lens: None,
            })
            .dir
            .to_f64();
        let f = [d[0] * -8.0 / d[2], d[1] * -8.0 / d[2]];
        assert!((f[0] - (-5.0 + p / 2.0)).abs() < 1e-5, "{f:?}");
        assert!((f[1] - (p * 240.0 - p / 2.0)).abs() < 1e-5, "{f:?}");
        // The picture is upright: row 0 looks up, column 0 looks left.
        assert!(d[0] < 0.0 && d[1] > 0.0 && d[2] < 0.0);
    }

    #[test]
    fn all_lens_rays_of_a_pixel_meet_at_the_focus_depth() {
        // N = 8, f = 4: the plane in focus lies at depth 8.
        let params = CameraParams {
            radius: 0.4,
            ..CameraParams::default()
        };
        assert_eq!(params.focus_depth(), 8.0);
        let cam = Camera::<I16F16>::new(&params, 160, 120);
        let film = cam.film_point(30, 100);
        let chief = cam.generate_ray(&CameraSample {
            film: &film,
            lens: None,
        });
        // Where the chief ray reaches z = −8.
        let at_focus = |r: Ray<I16F16>| {
            let (o, d) = (r.origin.to_f64(), r.dir.to_f64());
            let t = (-8.0 - o[2]) / d[2];
            [o[0] + t * d[0], o[1] + t * d[1]]
        };
        let target = at_focus(chief);
        for lens in [(32767, 0), (-20000, 20000), (0, -32000), (1000, 2000)] {
            let r = cam.generate_ray(&CameraSample {
                film: &film,
                lens: Some(lens),
            });
            let o = r.origin.to_f64();
            assert!((o[0] * o[0] + o[1] * o[1]).sqrt() <= 0.4 + 1e-4);
            let hit = at_focus(r);
            assert!(
                (hit[0] - target[0]).abs() < 2e-3 && (hit[1] - target[1]).abs() < 2e-3,
                "{hit:?} vs {target:?}"
            );
        }
        // And they do not meet at another depth: at z = −4 they spread out.
        let r = cam.generate_ray(&CameraSample {
            film: &film,
            lens: Some((32767, 0)),
        });
        let (o, d) = (r.origin.to_f64(), r.dir.to_f64());
        let t = (-4.0 - o[2]) / d[2];
        let (c, cd) = (chief.origin.to_f64(), chief.dir.to_f64());
        let tc = (-4.0 - c[2]) / cd[2];
        assert!(((o[0] + t * d[0]) - (c[0] + tc * cd[0])).abs() > 0.1);
    }

    #[test]
    fn basis_rejects_degenerate_views() {
        let mut p = CameraParams {
            look: [0.0; 3],
            ..CameraParams::default()
        };
        assert!(basis(&p).is_none());
        p.look = [0.0, 2.0, 0.0];
        assert!(basis(&p).is_none(), "up parallel to look");
        p.look = [1.0, 0.0, 0.0];
        let [u, v, n] = basis(&p).unwrap();
        assert_eq!(n, [-1.0, 0.0, 0.0]);
        assert_eq!(v, [0.0, 1.0, 0.0]);
        assert_eq!(u, [0.0, 0.0, 1.0], "looking along +x, right is +z");
    }
}
