//! Baked scenes: a renderer set up on the host, stored as bytes that a
//! microcontroller loads without a parser, without `f64` and without any
//! set-up arithmetic.
//!
//! [`Renderer::new`] parses nothing but does the set-up in `f64` (matrix
//! inverses, the camera basis, sines and cosines, the film map's scales);
//! [`bake`] writes the result of that set-up for one image size, and
//! [`Baked::load`] reads it back, checked, into the library's own types, so
//! that [`Baked::renderer`] renders exactly what the host's renderer renders.
//!
//! # Format (version [`FORMAT_VERSION`])
//!
//! Everything little-endian, no padding, no `#[repr]` of any Rust type:
//!
//! | bytes | field |
//! |---|---|
//! | 4 | magic `LRBK` ([`MAGIC`]) |
//! | 2 | format version |
//! | 1 | number type: 0 Q16.16, 1 f32 |
//! | 1 | 0 (reserved) |
//! | 4 | payload length n (stored bytes) |
//! | n | payload: the renderer's fields in declaration order (see below), zero runs compressed |
//! | 4 | CRC-32 (IEEE 802.3, reflected, as zlib's) of all the bytes before it |
//!
//! The payload is each struct's fields in the order its `baked_fields!` list
//! names them (next to each struct's definition): integers as themselves,
//! Q16.16 as its 32 bits, `f32` as its bits, `bool` as one byte 0 or 1, an
//! `Option` as a byte 0 or 1 then the value, a list as a `u16` count then the
//! items, an enum as one byte. Stored, each run of zero bytes (most of a
//! scene: the high bytes of small numbers) is the byte 0 and its length
//! (1 to 255); a 0 without a length, or with length 0, is a bad payload.
//! Adding a field to a baked struct is one change,
//! in its `baked_fields!` list (the compiler refuses a list that misses one),
//! plus a bump of [`FORMAT_VERSION`].
//!
//! # Checks
//!
//! [`Baked::load`] checks, in order: the magic, the version, the number type,
//! the length, the checksum, then every value's range (counts within the
//! scene's capacity, enum tags, shifts and magnitudes the integer kernels
//! need, finite `f32`s, one lens cone per object, image sides and sample
//! counts the renderer accepts) and that nothing is left over. Any failure is
//! a [`BakeError`] (the first one met, in that order); a loaded scene
//! renders without a panic and exactly as the renderer that was baked.
//!
//! ```
//! use lensray::{baked, I16F16, Renderer, Scene};
//!
//! let scene = Scene::<I16F16>::parse("object sphere\ntranslate 0 0 -8\n")?;
//! let renderer = Renderer::new(&scene, 32, 24);
//! let mut bytes = [0u8; 4096];
//! let n = baked::bake(&renderer, &mut bytes).unwrap();
//!
//! let mut loaded = baked::Baked::<I16F16>::empty();
//! loaded.load(&bytes[..n]).unwrap();
//! assert_eq!(loaded.renderer().pixel(16, 12), renderer.pixel(16, 12));
//!
//! bytes[20] ^= 1; // one flipped bit
//! assert_eq!(loaded.load(&bytes[..n]), Err(baked::BakeError::Checksum));
//! # Ok::<(), lensray::ParseError>(())
//! ```

use crate::camera::sampler::Sampler;
use crate::camera::{Camera, MAX_IMAGE_SIDE};
use crate::render::cull::LensCones;
use crate::render::Renderer;
use crate::scene::{Scene, MAX_OBJECTS};
use core::borrow::Borrow;

pub use crate::bytes::{crc32, BakeError, Field, Reader, Writer, FORMAT_VERSION, HEADER_LEN, MAGIC, TRAILER_LEN};
pub use crate::number::BakeScalar;
pub use crate::render::Setup;

/// The payload: the scene's rendering state (its camera statements are not
/// baked: the camera below is their set-up), the camera, the lens cones, the
/// samples and whether they are adaptive.
fn put_renderer<S: BakeScalar>(scene: &Scene<S>, setup: &Setup<S>, w: &mut Writer<'_>) {
    let Setup {
        camera,
        cones,
        defocus,
        samples,
        sampler,
        stop,
    } = setup;
    put_scene(scene, w);
    camera.put(w);
    cones.put(w);
    defocus.put(w);
    samples.put(w);
    sampler.put(w);
    stop.put(w);
}

fn put_scene<S: BakeScalar>(s: &Scene<S>, w: &mut Writer<'_>) {
    // `camera` (the f64 statements) is left out: the baked camera is their set-up.
    let Scene {
        camera: _,
        ambient,
        background,
        shadows,
        objects,
        lights,
        // Host-side switches (on when loaded), not part of the bake.
    } = s;
    ambient.put(w);
    background.put(w);
    shadows.put(w);
    objects.put(w);
    lights.put(w);
}

/// Bytes [`bake`] writes for this renderer.
pub fn baked_len<S: BakeScalar, P: Borrow<Setup<S>>>(renderer: &Renderer<'_, S, P>) -> usize {
    let mut w = Writer::new(None);
    put_renderer(renderer.scene, renderer.setup.borrow(), &mut w);
    w.flush();
    HEADER_LEN + w.pos + TRAILER_LEN
}

/// Writes the renderer's set-up (scene, camera for its image size, lens
/// cones, samples) into `out`; the number of bytes written.
///
/// # Errors
///
/// [`BakeError::BufferTooSmall`] if `out` is shorter than [`baked_len`]
/// (nothing useful is written then).
pub fn bake<S: BakeScalar, P: Borrow<Setup<S>>>(
    renderer: &Renderer<'_, S, P>,
    out: &mut [u8],
) -> Result<usize, BakeError> {
    let needed = baked_len(renderer);
    if out.len() < needed {
        return Err(BakeError::BufferTooSmall { needed });
    }
    let payload = needed - HEADER_LEN - TRAILER_LEN;
    let (header, rest) = out.split_at_mut(HEADER_LEN);
    header[..4].copy_from_slice(&MAGIC);
    header[4..6].copy_from_slice(&FORMAT_VERSION.to_le_bytes());
    header[6] = S::TAG;
    header[7] = 0;
    header[8..].copy_from_slice(&(payload as u32).to_le_bytes());
    let mut w = Writer::new(Some(&mut rest[..payload]));
    put_renderer(renderer.scene, renderer.setup.borrow(), &mut w);
    w.flush();
    let crc = crc32(&out[..needed - TRAILER_LEN]);
    out[needed - TRAILER_LEN..needed].copy_from_slice(&crc.to_le_bytes());
    Ok(needed)
}

/// A loaded baked scene: the renderer's state, owned. Load it once
/// ([`Baked::load`]), then render with [`Baked::renderer`] as often as needed.
#[derive(Clone, Debug)]
pub struct Baked<S: BakeScalar> {
    scene: Scene<S>,
    setup: Setup<S>,
}

impl<S: BakeScalar> Baked<S> {
    /// An empty scene (renders black), to load into.
    pub fn empty() -> Self {
        Baked {
            scene: Scene::default(),
            setup: Self::blank_setup(),
        }
    }

    /// The empty scene's set-up: one copy for [`Baked::empty`] and
    /// [`Baked::clear`].
    #[inline(never)]
    fn blank_setup() -> Setup<S> {
        Setup {
            camera: Camera::blank(),
            cones: LensCones::blank(),
            defocus: Field::blank(),
            samples: 1,
            sampler: Sampler::default(),
            stop: None,
        }
    }

    /// Checks `bytes` and loads them over `self`, in place (no second copy
    /// of the scene on the stack). On an error `self` is left empty.
    ///
    /// # Errors
    ///
    /// Any [`BakeError`] but `BufferTooSmall`; see the [module docs](self).
    ///
    /// # Panics
    ///
    /// Never, whatever the bytes.
    pub fn load(&mut self, bytes: &[u8]) -> Result<(), BakeError> {
        let result = self.load_checked(bytes);
        if result.is_err() {
            self.clear();
        }
        result
    }

    /// Empties `self` field by field: `*self = Baked::empty()` built a whole
    /// second scene on the Cortex-M0's stack before copying it over; out of
    /// line, so no caller's frame grows by it.
    #[inline(never)]
    fn clear(&mut self) {
        let scene = &mut self.scene;
        // Loading writes these three of the camera statements, no other
        // (`take_payload`): a whole default CameraParams cost 90 bytes more.
        let d = crate::camera::CameraParams::default();
        let cam = &mut scene.camera;
        (cam.samples, cam.adaptive, cam.sampler) = (d.samples, d.adaptive, d.sampler);
        scene.ambient = crate::geometry::vec3::Vec3::ZERO;
        scene.background = crate::geometry::vec3::Vec3::ZERO;
        scene.shadows = false;
        scene.objects.clear();
        scene.lights.clear();
        self.setup = Self::blank_setup();
    }

    fn load_checked(&mut self, bytes: &[u8]) -> Result<(), BakeError> {
        let got = bytes.len();
        if bytes.get(..4).is_some_and(|m| m != MAGIC) {
            return Err(BakeError::ForeignMagic);
        }
        if got < HEADER_LEN + TRAILER_LEN {
            return Err(BakeError::Truncated {
                needed: HEADER_LEN + TRAILER_LEN,
                got,
            });
        }
        let version = u16::from_le_bytes([bytes[4], bytes[5]]);
        if version != FORMAT_VERSION {
            return Err(BakeError::Version { found: version });
        }
        if bytes[6] != S::TAG {
            return Err(BakeError::NumberType {
                found: bytes[6],
                expected: S::TAG,
            });
        }
        if bytes[7] != 0 {
            return Err(BakeError::OutOfRange("reserved header byte is not 0"));
        }
        let payload = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize;
        let expected = HEADER_LEN.saturating_add(payload).saturating_add(TRAILER_LEN);
        if got < expected {
            return Err(BakeError::Truncated { needed: expected, got });
        }
        if got > expected {
            return Err(BakeError::TrailingBytes { expected, got });
        }
        let (body, crc) = bytes.split_at(got - TRAILER_LEN);
        if crc32(body) != u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]) {
            return Err(BakeError::Checksum);
        }
        let mut r = Reader::new(&body[HEADER_LEN..]);
        self.take_payload(&mut r);
        if r.ok() && !r.at_end() {
            r.fail(BakeError::Payload);
        }
        r.error.map_or(Ok(()), Err)
    }

    fn take_payload(&mut self, r: &mut Reader<'_>) {
        let Scene {
            camera: _,
            ambient,
            background,
            shadows,
            objects,
            lights,
        } = &mut self.scene;
        ambient.take(r);
        background.take(r);
        shadows.take(r);
        objects.take(r);
        lights.take(r);
        let setup = &mut self.setup;
        setup.camera.take(r);
        setup.cones.take(r);
        setup.defocus.take(r);
        setup.samples.take(r);
        setup.sampler.take(r);
        Field::take(&mut setup.stop, r);
        if !r.ok() {
            return;
        }
        // One cone per object: the cull looks an object's cone up by its index.
        if self.setup.cones.len() != self.scene.objects.len() {
            return r.out_of_range("lens cones do not match the objects");
        }
        if !(1..=65535).contains(&self.setup.samples) {
            return r.out_of_range("samples per pixel not in 1..=65535");
        }
        let (cols, rows) = (self.setup.camera.cols(), self.setup.camera.rows());
        if !(1..=MAX_IMAGE_SIDE).contains(&cols) || !(1..=MAX_IMAGE_SIDE).contains(&rows) {
            return r.out_of_range("image side not in 1..=8192");
        }
        // The statements the renderer still reads from the scene's camera.
        if let Some(rule) = self.setup.stop {
            // A threshold's checks come at powers of two; plain samples stop anywhere.
            let plain = rule.threshold == u32::MAX;
            if rule.pilot == 0 || rule.pilot > self.setup.samples || !(plain || rule.pilot.is_power_of_two()) {
                return r.out_of_range("stop rule's pilot is not within the samples");
            }
        }
        self.scene.camera.samples = self.setup.samples;
        self.scene.camera.adaptive = self.setup.stop.is_some();
        self.scene.camera.sampler = self.setup.sampler;
    }

    /// The renderer the bytes were baked from: the same pixels.
    pub fn renderer(&self) -> Renderer<'_, S> {
        Renderer {
            scene: &self.scene,
            setup: self.setup.clone(),
        }
    }

    /// The renderer the bytes were baked from, lent the set-up it renders
    /// with rather than given a copy: the same pixels as
    /// [`Baked::renderer`] with no second camera and lens cones in memory
    /// (a microcontroller's).
    pub fn lend(&self) -> Renderer<'_, S, &Setup<S>> {
        Renderer {
            scene: &self.scene,
            setup: &self.setup,
        }
    }

    /// The loaded scene (its `camera` statements are defaults: the baked
    /// camera is their set-up, see [`Baked::renderer`]).
    pub fn scene(&self) -> &Scene<S> {
        &self.scene
    }

    /// Image width and height the scene was baked for.
    pub fn size(&self) -> (u32, u32) {
        (self.setup.camera.cols(), self.setup.camera.rows())
    }
}

// Keeps MAX_OBJECTS in the docs' reach: the object list's capacity.
const _: () = assert!(MAX_OBJECTS <= u16::MAX as usize);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32_check_value() {
        // The catalogue's check value for CRC-32/ISO-HDLC.
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(crc32(b""), 0);
    }
}
