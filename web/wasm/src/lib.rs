//! lensray's library in WebAssembly: the C ABI the web page's worker calls.
//!
//! No bindings generator: plain `extern "C"` functions over linear memory.
//! The page writes the scene text into a buffer this module hands out
//! ([`lr_text_buffer`]), parses it ([`lr_parse`]) with the library's own
//! parser into both number types, sets up a progressive schedule for an image
//! size ([`lr_setup`], the library's [`progressive::Schedule`]) and renders it
//! a few grid rows at a time ([`lr_render`], the library's
//! [`progressive::render_pass_row`]) into one RGBA buffer per number type,
//! which the page copies onto its canvas. [`lr_depth_at`] is the click-to-focus
//! query: the depth of what the pixel's chief ray meets first.
//!
//! [`lr_setup`] builds one renderer per number type and keeps it until the
//! next parse or set-up: its set-up (the adaptive pre-pass that sets the
//! frame's stop rule) costs as much as many rows, and the page calls in a
//! row or a pixel at a time. The frame's rays are what [`lr_render`] returns
//! plus that pre-pass's, [`lr_survey_rays`].
//!
//! Number types are selected by an integer: 0 is Q16.16, 1 is `f32`.
//! Every function is total: bad indices or a missing scene return 0, -1 or
//! NaN as documented, never a trap.

use std::cell::RefCell;
use std::ptr::NonNull;

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Size};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics_core::Pixel;
use lensray::progressive::{self, Pass, Schedule};
use lensray::{Renderer, Scalar, Scene, I16F16};

/// Q16.16, the fixed-point renderer.
pub const NUMBER_FIXED: u32 = 0;
/// `f32`, the reference.
pub const NUMBER_FLOAT: u32 = 1;

/// Everything the page has set: one scene text, parsed in both number types.
#[derive(Default)]
struct State {
    text: Vec<u8>,
    message: String,
    error_line: u32,
    fixed: Option<Loaded<I16F16>>,
    float: Option<Loaded<f32>>,
    width: u32,
    height: u32,
    passes: Vec<Pass>,
    /// RGBA, row-major, one image per number type.
    images: [Vec<u8>; 2],
}

/// A parsed scene and, after [`lr_setup`], its renderer for the set size,
/// which borrows the scene: the one self-reference, so the one `unsafe` here.
struct Loaded<S: Scalar + 'static> {
    /// Borrows `*scene`; cleared before the scene is freed (see `Drop`).
    renderer: Option<Renderer<'static, S>>,
    /// Owned (from `Box::leak`), never moved or mutated, freed in `Drop`.
    scene: NonNull<Scene<S>>,
}

impl<S: Scalar + 'static> Loaded<S> {
    fn new(scene: Scene<S>) -> Self {
        Loaded {
            renderer: None,
            scene: NonNull::from(Box::leak(Box::new(scene))),
        }
    }

    fn scene(&self) -> &Scene<S> {
        // SAFETY: the scene lives until `Drop` and is only ever shared.
        unsafe { self.scene.as_ref() }
    }

    /// Builds the renderer for a `width` × `height` image.
    fn set_size(&mut self, width: u32, height: u32) -> &Renderer<'_, S> {
        self.renderer = None;
        // SAFETY: the renderer never outlives the scene: `Drop` clears it
        // first, and it is only lent out for as long as `self` is borrowed.
        let scene: &'static Scene<S> = unsafe { self.scene.as_ref() };
        self.renderer.insert(Renderer::new(scene, width, height))
    }

    fn renderer(&self) -> Option<&Renderer<'_, S>> {
        self.renderer.as_ref()
    }
}

impl<S: Scalar + 'static> Drop for Loaded<S> {
    fn drop(&mut self) {
        self.renderer = None;
        // SAFETY: from `Box::leak` in `new`, freed once, nothing borrows it now.
        drop(unsafe { Box::from_raw(self.scene.as_ptr()) });
    }
}

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
}

fn with<R>(f: impl FnOnce(&mut State) -> R) -> R {
    STATE.with(|s| f(&mut s.borrow_mut()))
}

/// An RGBA buffer as an embedded-graphics display (alpha always 255).
pub struct RgbaTarget<'a> {
    /// `width * height * 4` bytes.
    pub rgba: &'a mut [u8],
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl OriginDimensions for RgbaTarget<'_> {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for RgbaTarget<'_> {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            if p.x >= 0 && p.y >= 0 && (p.x as u32) < self.width && (p.y as u32) < self.height {
                let i = (p.y as usize * self.width as usize + p.x as usize) * 4;
                self.rgba[i..i + 4].copy_from_slice(&[c.r(), c.g(), c.b(), 255]);
            }
        }
        Ok(())
    }
}

/// A buffer of `len` bytes for the scene text (UTF-8); the page writes the
/// text there, then calls [`lr_parse`]. The pointer is valid until the next call.
#[no_mangle]
pub extern "C" fn lr_text_buffer(len: u32) -> *mut u8 {
    with(|s| {
        s.text.clear();
        s.text.resize(len as usize, 0);
        s.text.as_mut_ptr()
    })
}

/// Parses the scene text in both number types. Returns 0 when it is a valid
/// scene, else the line of the first error (the message, `line N: ...`, from
/// [`lr_message`]). A failed parse keeps no scene: rendering draws nothing.
#[no_mangle]
pub extern "C" fn lr_parse() -> u32 {
    with(|s| {
        let fixed = Scene::<I16F16>::parse_bytes(&s.text);
        let float = Scene::<f32>::parse_bytes(&s.text);
        s.fixed = None;
        s.float = None;
        match (fixed, float) {
            (Ok(a), Ok(b)) => {
                s.fixed = Some(Loaded::new(a));
                s.float = Some(Loaded::new(b));
                s.message.clear();
                s.error_line = 0;
            }
            (Err(e), _) | (_, Err(e)) => {
                s.message = e.to_string();
                // Line 0 would read as success; errors always name a line from 1.
                s.error_line = e.line.max(1);
            }
        }
        s.error_line
    })
}

/// The last parse error's message (`line N: message`), UTF-8 at this pointer...
#[no_mangle]
pub extern "C" fn lr_message() -> *const u8 {
    with(|s| s.message.as_ptr())
}

/// ... of this many bytes (0 after a successful parse).
#[no_mangle]
pub extern "C" fn lr_message_len() -> u32 {
    with(|s| s.message.len() as u32)
}

/// Sets up a progressive render of `width` × `height` pixels of the parsed
/// scene: blocks of `first_step` first, a preview with `preview_samples` lens
/// samples (0: none). Returns the number of passes (0 without a valid scene).
/// Both images are cleared to black.
#[no_mangle]
pub extern "C" fn lr_setup(width: u32, height: u32, first_step: u32, preview_samples: u32) -> u32 {
    with(|s| {
        let w = width.clamp(1, lensray::MAX_IMAGE_SIDE);
        let h = height.clamp(1, lensray::MAX_IMAGE_SIDE);
        s.width = w;
        s.height = h;
        for img in s.images.iter_mut() {
            img.clear();
            img.resize(w as usize * h as usize * 4, 0);
            for px in img.chunks_exact_mut(4) {
                px[3] = 255;
            }
        }
        s.passes.clear();
        let (Some(fixed), Some(float)) = (s.fixed.as_mut(), s.float.as_mut()) else {
            return 0;
        };
        // Each number type's pre-pass sets its own stop rule, and the two may
        // differ (their colours are a rounding apart: one may choose plain
        // samples, the other a threshold). The passes take the larger of
        // their rays a pixel, so that neither takes a full pass for a
        // preview: a pass at least a renderer's rays is that renderer's own.
        let rays = fixed.set_size(w, h).rays_per_pixel();
        let rays = rays.max(float.set_size(w, h).rays_per_pixel());
        s.passes.extend(Schedule::new(first_step, preview_samples, rays));
        s.passes.len() as u32
    })
}

/// Block side of pass `i` (0 for no such pass).
#[no_mangle]
pub extern "C" fn lr_pass_step(i: u32) -> u32 {
    with(|s| s.passes.get(i as usize).map_or(0, |p| p.step))
}

/// Lens samples a pixel of pass `i` (0 for no such pass).
#[no_mangle]
pub extern "C" fn lr_pass_samples(i: u32) -> u32 {
    with(|s| s.passes.get(i as usize).map_or(0, |p| p.samples))
}

/// Grid rows of pass `i`: what [`lr_render`] counts in (0 for no such pass).
#[no_mangle]
pub extern "C" fn lr_pass_rows(i: u32) -> u32 {
    with(|s| s.passes.get(i as usize).map_or(0, |p| s.height.div_ceil(p.step.max(1))))
}

/// Rays the pre-pass of number type `number`'s renderer cast (set up by
/// [`lr_setup`]) to set the frame's adaptive stop rule: part of the frame's
/// rays, with what [`lr_render`] returns. 0 without a stop rule (adaptive
/// sampling off, a pinhole, too few samples), a bad number or no scene.
#[no_mangle]
pub extern "C" fn lr_survey_rays(number: u32) -> f64 {
    fn survey<S: Scalar>(loaded: Option<&Loaded<S>>) -> f64 {
        loaded
            .and_then(Loaded::renderer)
            .and_then(Renderer::stop_rule)
            .map_or(0.0, |s| s.survey_rays as f64)
    }
    with(|s| match number {
        NUMBER_FIXED => survey(s.fixed.as_ref()),
        NUMBER_FLOAT => survey(s.float.as_ref()),
        _ => 0.0,
    })
}

/// Renders grid rows `first .. end` of pass `i` in number type `number` into
/// its image. Returns the lens rays its pixels cast (with adaptive sampling,
/// what they took), 0 for an empty range, a bad pass or no scene.
#[no_mangle]
pub extern "C" fn lr_render(number: u32, i: u32, first: u32, end: u32) -> f64 {
    with(|s| {
        let Some(pass) = s.passes.get(i as usize).copied() else {
            return 0.0;
        };
        let (w, h) = (s.width, s.height);
        let Some(img) = s.images.get_mut(number as usize) else {
            return 0.0;
        };
        let mut target = RgbaTarget {
            rgba: img,
            width: w,
            height: h,
        };
        match number {
            NUMBER_FIXED => s
                .fixed
                .as_ref()
                .and_then(Loaded::renderer)
                .map_or(0.0, |r| rows(r, &mut target, &pass, first, end)),
            _ => s
                .float
                .as_ref()
                .and_then(Loaded::renderer)
                .map_or(0.0, |r| rows(r, &mut target, &pass, first, end)),
        }
    })
}

fn rows<S: Scalar>(renderer: &Renderer<'_, S>, target: &mut RgbaTarget<'_>, pass: &Pass, first: u32, end: u32) -> f64 {
    let step = pass.step.max(1);
    let mut rays = 0u64;
    for g in first..end.min(target.height.div_ceil(step)) {
        let Ok(n) = progressive::render_pass_row(renderer, target, pass, g * step);
        rays += n;
    }
    rays as f64
}

/// The RGBA image of number type `number` (`width * height * 4` bytes; null
/// for a bad number).
#[no_mangle]
pub extern "C" fn lr_image(number: u32) -> *const u8 {
    with(|s| s.images.get(number as usize).map_or(core::ptr::null(), |v| v.as_ptr()))
}

/// Depth (distance along the viewing direction) of the first surface the
/// chief ray of pixel (`col`, `row`) meets, in number type `number`: where
/// `focus_distance` puts that surface in focus. NaN where the ray meets
/// nothing (or no scene).
#[no_mangle]
pub extern "C" fn lr_depth_at(number: u32, col: u32, row: u32) -> f64 {
    with(|s| match number {
        NUMBER_FIXED => s.fixed.as_ref().map_or(f64::NAN, |l| hit_at(l, col, row).1),
        _ => s.float.as_ref().map_or(f64::NAN, |l| hit_at(l, col, row).1),
    })
}

/// The object (numbered from 1 in file order, as `focus_on` counts) the chief
/// ray of pixel (`col`, `row`) meets first; 0 for none.
#[no_mangle]
pub extern "C" fn lr_object_at(number: u32, col: u32, row: u32) -> u32 {
    with(|s| match number {
        NUMBER_FIXED => s.fixed.as_ref().map_or(0, |l| hit_at(l, col, row).0),
        _ => s.float.as_ref().map_or(0, |l| hit_at(l, col, row).0),
    })
}

/// The object (from 1; 0 for none) and depth (NaN for none) under a pixel's
/// chief ray, from the lens centre through the pixel's film point: the ray
/// every lens sample of that pixel converges with on the plane in focus.
fn hit_at<S: Scalar>(loaded: &Loaded<S>, col: u32, row: u32) -> (u32, f64) {
    let (scene, Some(renderer)) = (loaded.scene(), loaded.renderer()) else {
        return (0, f64::NAN);
    };
    let (cols, rows) = renderer.size();
    if col >= cols || row >= rows {
        return (0, f64::NAN);
    }
    let ray = renderer.camera_ray(col, row, None);
    let Some((i, t)) = renderer.hit(&ray) else {
        return (0, f64::NAN);
    };
    let (o, d, t) = (ray.origin.to_f64(), ray.dir.to_f64(), t.to_f64());
    let p = [0, 1, 2].map(|k| o[k] + t * d[k]);
    (i as u32 + 1, depth(&scene.camera, p))
}

/// Depth of world point `p`: its distance from the lens centre along the
/// unit viewing direction, `(p − lens_position) · look / |look|` (negative
/// behind the lens; 0 for a zero `look`). What `focus_distance` takes to put
/// `p` in focus, as the library's `focus_on` measures it.
fn depth(camera: &lensray::CameraParams, p: [f64; 3]) -> f64 {
    let (l, e) = (camera.look, camera.lens_position);
    let len = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    if len == 0.0 {
        return 0.0;
    }
    ((p[0] - e[0]) * l[0] + (p[1] - e[1]) * l[1] + (p[2] - e[2]) * l[2]) / len
}

/// The parsed scene's camera, for the page's controls: 0 focus distance
/// (depth of the plane in focus), 1 f-number, 2 lens radius, 3 aperture
/// blades, 4 aperture rotation, 5 samples (`point`), 6 aspect ratio,
/// 7 objects. NaN for another `what` or without a scene.
#[no_mangle]
pub extern "C" fn lr_camera(what: u32) -> f64 {
    with(|s| {
        let Some(sc) = s.float.as_ref().map(Loaded::scene) else {
            return f64::NAN;
        };
        let c = &sc.camera;
        match what {
            0 => c.focus_depth(),
            1 => c.f_number(),
            2 => c.radius,
            3 => c.aperture_blades as f64,
            4 => c.aperture_rotation,
            5 => c.samples as f64,
            6 => c.aspect_ratio,
            7 => sc.objects().len() as f64,
            _ => f64::NAN,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(text: &str) -> u32 {
        let p = lr_text_buffer(text.len() as u32);
        unsafe { core::ptr::copy_nonoverlapping(text.as_ptr(), p, text.len()) };
        lr_parse()
    }

    fn image(number: u32, w: u32, h: u32) -> Vec<u8> {
        let p = lr_image(number);
        unsafe { core::slice::from_raw_parts(p, (w * h * 4) as usize) }.to_vec()
    }

    fn program1() -> String {
        std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../scenes/paper-program1.scene"
        ))
        .unwrap()
    }

    #[test]
    fn passes_end_in_the_plain_render_of_both_number_types() {
        // Adaptive off: every pixel casts its samples, so the rays are known.
        let text = program1().replace("point 70", "point 5") + "adaptive off\n";
        assert_eq!(load(&text), 0);
        let (w, h) = (37, 23);
        let n = lr_setup(w, h, 8, 1);
        assert_eq!(n, 5, "preview, 8, 4, 2, 1");
        for number in [NUMBER_FIXED, NUMBER_FLOAT] {
            let mut rays = 0.0;
            for i in 0..n {
                // Odd chunks: rows may come in any grouping.
                let rows = lr_pass_rows(i);
                let mut g = 0;
                while g < rows {
                    rays += lr_render(number, i, g, g + 2);
                    g += 2;
                }
            }
            // Preview: 5 x 3 pixels at one sample; then every pixel at 5.
            assert_eq!(rays, 15.0 + (w * h * 5) as f64);
            let got = image(number, w, h);
            let plain: Vec<u8> = if number == NUMBER_FIXED {
                plain_render(&Scene::<I16F16>::parse(&text).unwrap(), w, h)
            } else {
                plain_render(&Scene::<f32>::parse(&text).unwrap(), w, h)
            };
            assert_eq!(got, plain, "number {number}");
        }
    }

    fn plain_render<S: Scalar>(scene: &Scene<S>, w: u32, h: u32) -> Vec<u8> {
        let renderer = Renderer::new(scene, w, h);
        let mut out = vec![Rgb888::BLACK; w as usize];
        let mut rgba = Vec::new();
        for row in 0..h {
            renderer.render_row(row, &mut out);
            for c in &out {
                rgba.extend_from_slice(&[c.r(), c.g(), c.b(), 255]);
            }
        }
        rgba
    }

    #[test]
    fn each_parse_and_set_up_renders_its_own_scene_and_size() {
        // The renderer is kept from set-up to set-up: a new scene or size must not see the old one.
        let text = program1().replace("point 70", "point 3") + "adaptive off\n";
        let (w, h) = (24, 18);
        assert_eq!(load(&text.replace("radius", "# radius")), 0);
        lr_setup(w, h, 1, 0);
        assert_eq!(load(&text), 0);
        assert_eq!(
            lr_object_at(NUMBER_FIXED, 0, 0),
            0,
            "parsed, not yet set up: nothing to ask"
        );
        for (w, h) in [(w, h), (w + 7, h - 5)] {
            assert_eq!(lr_setup(w, h, 1, 0), 1);
            assert_eq!(
                lr_render(NUMBER_FIXED, 0, 0, h),
                (w * h * 3) as f64,
                "the lens scene's samples"
            );
            assert_eq!(
                image(NUMBER_FIXED, w, h),
                plain_render(&Scene::<I16F16>::parse(&text).unwrap(), w, h)
            );
            let (col, row) = (w / 2, h - 1);
            assert_eq!(
                lr_object_at(NUMBER_FLOAT, col, row),
                1,
                "the floor under the bottom row's middle"
            );
            let want = hit_at(
                &{
                    let mut l = Loaded::new(Scene::<f32>::parse(&text).unwrap());
                    l.set_size(w, h);
                    l
                },
                col,
                row,
            );
            assert_eq!(lr_depth_at(NUMBER_FLOAT, col, row), want.1);
        }
    }

    #[test]
    fn adaptive_rays_are_what_the_pixels_took() {
        let text = program1().replace("point 70", "point 40");
        assert_eq!(load(&text), 0);
        let (w, h) = (40, 30);
        assert_eq!(lr_setup(w, h, 1, 0), 1, "one pass of single pixels");
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let r = Renderer::new(&scene, w, h);
        let mut row = vec![Rgb888::BLACK; w as usize];
        let plain: u32 = (0..h).map(|y| r.render_row(y, &mut row)).sum();
        assert_eq!(lr_render(NUMBER_FIXED, 0, 0, h), plain as f64);
        let survey = r.stop_rule().expect("a stop rule at 40 samples").survey_rays;
        assert!(survey > 0);
        assert_eq!(lr_survey_rays(NUMBER_FIXED), survey as f64, "the pre-pass's rays");
        let float = Scene::<f32>::parse(&text).unwrap();
        let f = Renderer::new(&float, w, h).stop_rule().unwrap().survey_rays;
        assert_eq!(lr_survey_rays(NUMBER_FLOAT), f as f64);
        assert!(
            plain + survey < w * h * 40,
            "{plain} + {survey} rays: fewer than `point` a pixel"
        );
        // Without adaptive sampling there is no pre-pass.
        assert_eq!(load(&(text + "adaptive off\n")), 0);
        lr_setup(w, h, 1, 0);
        assert_eq!(lr_survey_rays(NUMBER_FIXED), 0.0);
        assert_eq!(lr_survey_rays(2), 0.0, "no such number type");
    }

    #[test]
    fn errors_name_their_line() {
        assert_eq!(load("point 4\nradius 0.1\nligth_position 1 2 3\n"), 3);
        let msg = unsafe { core::slice::from_raw_parts(lr_message(), lr_message_len() as usize) };
        assert_eq!(
            std::str::from_utf8(msg).unwrap(),
            "line 3: unknown keyword \"ligth_position\""
        );
        assert_eq!(lr_setup(10, 10, 8, 1), 0, "no scene, no passes");
        assert_eq!(lr_render(0, 0, 0, 10), 0.0);
        assert!(lr_depth_at(0, 1, 1).is_nan());
    }

    #[test]
    fn every_preset_ends_in_the_plain_render_of_both_number_types() {
        // Adaptive sampling as each scene says: the two number types' stop
        // rules may differ, and each type's last pass must still be its own
        // plain render.
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes");
        let mut files: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        files.sort();
        assert!(files.len() >= 10, "{files:?}");
        let (w, h) = (48, 36);
        for path in files.iter().filter(|p| p.extension().is_some_and(|x| x == "scene")) {
            let text = std::fs::read_to_string(path).unwrap();
            assert_eq!(load(&text), 0, "{}", path.display());
            let n = lr_setup(w, h, 8, 1);
            for number in [NUMBER_FIXED, NUMBER_FLOAT] {
                for i in 0..n {
                    lr_render(number, i, 0, lr_pass_rows(i));
                }
                let plain: Vec<u8> = if number == NUMBER_FIXED {
                    plain_render(&Scene::<I16F16>::parse(&text).unwrap(), w, h)
                } else {
                    plain_render(&Scene::<f32>::parse(&text).unwrap(), w, h)
                };
                assert!(image(number, w, h) == plain, "{} number {number}", path.display());
            }
        }
    }

    #[test]
    fn depth_under_a_pixel_is_the_surface_focus_on_finds() {
        // Program 1's gold sphere (object 3): the centre pixel column through
        // its middle sees its front; focus_on 3 puts focus on the point
        // towards its centre, which a pixel near the image centre sees too.
        assert_eq!(load(&program1()), 0);
        let (w, h) = (320, 240);
        lr_setup(w, h, 8, 1);
        let sphere_centre_row = (h as f64 / 2.0 + 1.0 / 8.0 * 8.0 / (10.0 / w as f64)) as u32;
        for number in [NUMBER_FIXED, NUMBER_FLOAT] {
            assert_eq!(lr_object_at(number, w / 2, sphere_centre_row), 3);
            let d = lr_depth_at(number, w / 2, sphere_centre_row);
            let focus_on = 8.0 * (1.0 - 1.0 / 65f64.sqrt());
            assert!((d - focus_on).abs() < 0.01, "{number}: {d} vs {focus_on}");
            // The sky: nothing.
            assert_eq!(lr_object_at(number, w / 2, 0), 0);
            assert!(lr_depth_at(number, w / 2, 0).is_nan());
        }
    }
}
