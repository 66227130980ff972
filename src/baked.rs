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
//! | 4 | payload length n |
//! | n | payload: the renderer's fields in declaration order (see below) |
//! | 4 | CRC-32 (IEEE 802.3, reflected, as zlib's) of all the bytes before it |
//!
//! The payload is each struct's fields in the order its `baked_fields!` list
//! names them (next to each struct's definition): integers as themselves,
//! Q16.16 as its 32 bits, `f32` as its bits, `bool` as one byte 0 or 1, an
//! `Option` as a byte 0 or 1 then the value, a list as a `u16` count then the
//! items, an enum as one byte. Adding a field to a baked struct is one change,
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
//! a [`BakeError`]; a loaded scene renders without a panic and exactly as
//! the renderer that was baked.
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

use core::fmt;

use crate::camera::{Camera, MAX_IMAGE_SIDE};
use crate::cull::LensCones;
use crate::footprint::BrightFootprints;
use crate::render::Renderer;
use crate::sampler::Sampler;
use crate::scalar::Scalar;
use crate::scene::{Scene, MAX_OBJECTS};
use crate::shape::Shape;
use crate::vec3::Vec3;
use fixed::types::I16F16;

/// The first four bytes of every baked scene.
pub const MAGIC: [u8; 4] = *b"LRBK";
/// The format this library writes and reads. Bump it when any baked struct changes.
pub const FORMAT_VERSION: u16 = 2;
/// Bytes before the payload: magic, version, number type, reserved, length.
pub const HEADER_LEN: usize = 12;
/// Bytes after the payload: the CRC-32.
pub const TRAILER_LEN: usize = 4;

/// Why a baked scene cannot be written or loaded.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum BakeError {
    /// Fewer bytes than a header and a checksum, or than the header's length says.
    Truncated {
        /// Bytes the header (or the format) needs.
        needed: usize,
        /// Bytes there are.
        got: usize,
    },
    /// More bytes than the header's length says.
    TrailingBytes {
        /// Bytes the header says.
        expected: usize,
        /// Bytes there are.
        got: usize,
    },
    /// Not a baked scene: the first four bytes are not [`MAGIC`].
    ForeignMagic,
    /// A baked scene of another format version.
    Version {
        /// The file's version.
        found: u16,
    },
    /// Baked for the other number type (Q16.16 vs f32).
    NumberType {
        /// The file's number type tag (0 Q16.16, 1 f32).
        found: u8,
        /// The tag this renderer needs.
        expected: u8,
    },
    /// The bytes do not match their CRC-32: corrupted.
    Checksum,
    /// A value the renderer cannot take: the field named.
    OutOfRange(&'static str),
    /// The payload ends before its last field (or holds bytes past it).
    Payload,
    /// The output buffer is too small (writing): this many bytes are needed.
    BufferTooSmall {
        /// Bytes the baked scene takes.
        needed: usize,
    },
}

impl fmt::Display for BakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BakeError::Truncated { needed, got } => {
                write!(f, "truncated baked scene: {got} bytes, needs {needed}")
            }
            BakeError::TrailingBytes { expected, got } => {
                write!(f, "baked scene has {got} bytes, its header says {expected}")
            }
            BakeError::ForeignMagic => write!(f, "not a baked lensray scene (no LRBK magic)"),
            BakeError::Version { found } => {
                write!(
                    f,
                    "baked scene format version {found}; this build reads version {FORMAT_VERSION}"
                )
            }
            BakeError::NumberType { found, expected } => write!(
                f,
                "baked scene is for number type {} but the renderer uses {}",
                number_name(*found),
                number_name(*expected)
            ),
            BakeError::Checksum => write!(f, "baked scene is corrupt: its CRC-32 does not match"),
            BakeError::OutOfRange(what) => write!(f, "baked scene holds an invalid value: {what}"),
            BakeError::Payload => write!(f, "baked scene payload does not end where its last field does"),
            BakeError::BufferTooSmall { needed } => write!(f, "output buffer too small: needs {needed} bytes"),
        }
    }
}

/// Bad baked bytes are an error like any other (`?` into `Box<dyn Error>`).
impl core::error::Error for BakeError {}

fn number_name(tag: u8) -> &'static str {
    match tag {
        0 => "Q16.16",
        1 => "f32",
        _ => "unknown",
    }
}

/// CRC-32 (IEEE 802.3 polynomial, reflected, initial and final XOR all ones:
/// zlib's and PNG's), with a 16-entry table (64 bytes of flash).
pub fn crc32(bytes: &[u8]) -> u32 {
    const fn table() -> [u32; 16] {
        let mut t = [0u32; 16];
        let mut i = 0;
        while i < 16 {
            let mut c = i as u32;
            let mut k = 0;
            while k < 4 {
                c = if c & 1 != 0 { (c >> 1) ^ 0xEDB8_8320 } else { c >> 1 };
                k += 1;
            }
            t[i] = c;
            i += 1;
        }
        t
    }
    const T: [u32; 16] = table();
    let mut c = !0u32;
    for &b in bytes {
        c = (c >> 4) ^ T[((c ^ b as u32) & 15) as usize];
        c = (c >> 4) ^ T[((c ^ (b as u32 >> 4)) & 15) as usize];
    }
    !c
}

/// Where baked bytes go: a buffer, or nowhere (counting only).
pub struct Writer<'a> {
    out: Option<&'a mut [u8]>,
    pos: usize,
}

impl Writer<'_> {
    fn bytes(&mut self, b: &[u8]) {
        if let Some(out) = self.out.as_deref_mut() {
            if let Some(dst) = out.get_mut(self.pos..self.pos + b.len()) {
                dst.copy_from_slice(b);
            }
        }
        self.pos += b.len();
    }
}

/// Baked bytes being read.
pub struct Reader<'a> {
    bytes: &'a [u8],
}

impl Reader<'_> {
    fn array<const N: usize>(&mut self) -> Result<[u8; N], BakeError> {
        let (head, rest) = self.bytes.split_first_chunk::<N>().ok_or(BakeError::Payload)?;
        self.bytes = rest;
        Ok(*head)
    }
}

/// A value with a baked form: written, read back in place, and blank (what
/// a value is before it is read). Implemented by every type a renderer holds.
pub trait Field {
    /// Appends the value's bytes.
    fn put(&self, w: &mut Writer<'_>);
    /// Reads the value over `self`, checking its range.
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError>;
    /// A placeholder value, before reading.
    fn blank() -> Self
    where
        Self: Sized;
}

/// `Field` for a struct from the list of its fields, in their baked order,
/// and an optional range check run after reading. Every field must be listed
/// (the destructuring patterns refuse a list that misses one).
macro_rules! baked_fields {
    ($name:ident { $($field:ident),* $(,)? } $(, check($v:ident) $check:block)?) => {
        fn put(&self, w: &mut $crate::baked::Writer<'_>) {
            let $name { $($field),* } = self;
            $( $crate::baked::Field::put($field, w); )*
        }
        fn take(&mut self, r: &mut $crate::baked::Reader<'_>) -> Result<(), $crate::baked::BakeError> {
            let $name { $($field),* } = self;
            $( $crate::baked::Field::take($field, r)?; )*
            $( let $v = &*self; $check )?
            #[allow(unreachable_code)]
            Ok(())
        }
        fn blank() -> Self {
            $name { $($field: $crate::baked::Field::blank()),* }
        }
    };
}
pub(crate) use baked_fields;

macro_rules! int_field {
    ($($t:ty),*) => {$(
        impl Field for $t {
            fn put(&self, w: &mut Writer<'_>) {
                w.bytes(&self.to_le_bytes());
            }
            fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
                *self = <$t>::from_le_bytes(r.array()?);
                Ok(())
            }
            fn blank() -> Self {
                0
            }
        }
    )*};
}
int_field!(u8, i16, u16, i32, u32, i64);

impl Field for bool {
    fn put(&self, w: &mut Writer<'_>) {
        w.bytes(&[*self as u8]);
    }
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        *self = match r.array::<1>()?[0] {
            0 => false,
            1 => true,
            _ => return Err(BakeError::OutOfRange("a flag is neither 0 nor 1")),
        };
        Ok(())
    }
    fn blank() -> Self {
        false
    }
}

impl Field for I16F16 {
    fn put(&self, w: &mut Writer<'_>) {
        self.to_bits().put(w);
    }
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        *self = I16F16::from_bits(i32::from_le_bytes(r.array()?));
        Ok(())
    }
    fn blank() -> Self {
        I16F16::ZERO
    }
}

impl Field for f32 {
    fn put(&self, w: &mut Writer<'_>) {
        self.to_bits().put(w);
    }
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        *self = f32::from_bits(u32::from_le_bytes(r.array()?));
        // Infinities and NaNs would paint a picture the host never made.
        if !self.is_finite() {
            return Err(BakeError::OutOfRange("an f32 is not finite"));
        }
        Ok(())
    }
    fn blank() -> Self {
        0.0
    }
}

impl<T: Field, const N: usize> Field for [T; N] {
    fn put(&self, w: &mut Writer<'_>) {
        self.iter().for_each(|x| x.put(w));
    }
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        self.iter_mut().try_for_each(|x| x.take(r))
    }
    fn blank() -> Self {
        core::array::from_fn(|_| T::blank())
    }
}

impl<A: Field, B: Field> Field for (A, B) {
    fn put(&self, w: &mut Writer<'_>) {
        self.0.put(w);
        self.1.put(w);
    }
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        self.0.take(r)?;
        self.1.take(r)
    }
    fn blank() -> Self {
        (A::blank(), B::blank())
    }
}

impl<T: Field> Field for Option<T> {
    fn put(&self, w: &mut Writer<'_>) {
        self.is_some().put(w);
        if let Some(x) = self {
            x.put(w);
        }
    }
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        let mut some = false;
        some.take(r)?;
        if !some {
            *self = None;
            return Ok(());
        }
        self.get_or_insert_with(T::blank).take(r)
    }
    fn blank() -> Self {
        None
    }
}

impl<T: Field, const N: usize> Field for heapless::Vec<T, N> {
    fn put(&self, w: &mut Writer<'_>) {
        (self.len() as u16).put(w);
        self.iter().for_each(|x| x.put(w));
    }
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        let mut n = 0u16;
        n.take(r)?;
        if n as usize > N {
            return Err(BakeError::OutOfRange("more items than the scene's capacity"));
        }
        self.clear();
        for _ in 0..n {
            // Pushed blank, then read where it lies: no second copy on the stack.
            let _ = self.push(T::blank());
            if let Some(x) = self.last_mut() {
                x.take(r)?;
            }
        }
        Ok(())
    }
    fn blank() -> Self {
        heapless::Vec::new()
    }
}

impl<S: Field> Field for Vec3<S> {
    baked_fields!(Vec3 { x, y, z });
}

impl Field for Shape {
    fn put(&self, w: &mut Writer<'_>) {
        let tag: u8 = match self {
            Shape::Sphere => 0,
            Shape::Plane => 1,
            Shape::Cube => 2,
            Shape::Cylinder => 3,
            Shape::Cone => 4,
        };
        tag.put(w);
    }
    fn take(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        *self = match r.array::<1>()?[0] {
            0 => Shape::Sphere,
            1 => Shape::Plane,
            2 => Shape::Cube,
            3 => Shape::Cylinder,
            4 => Shape::Cone,
            _ => return Err(BakeError::OutOfRange("unknown shape")),
        };
        Ok(())
    }
    fn blank() -> Self {
        Shape::Sphere
    }
}

/// A number type whose renderers can be baked: [`I16F16`] and `f32`. Its
/// matrix rows and film map have baked forms too.
pub trait BakeScalar:
    Scalar<Row = <Self as BakeScalar>::BakedRow, FilmMap = <Self as BakeScalar>::BakedFilmMap> + Field
{
    /// The number type's tag in the header: 0 Q16.16, 1 f32.
    const TAG: u8;
    /// [`Scalar::Row`].
    type BakedRow: Field + Copy + fmt::Debug + Send + Sync;
    /// [`Scalar::FilmMap`].
    type BakedFilmMap: Field + Copy + fmt::Debug + Send + Sync;
    /// Whether the film map's integer kernels stay in range for this image size.
    fn film_map_fits(map: &Self::BakedFilmMap, cols: u32, rows: u32) -> bool;
}

impl BakeScalar for I16F16 {
    const TAG: u8 = 0;
    type BakedRow = crate::scalar::FixedRow;
    type BakedFilmMap = crate::film::FixedFilmMap;
    fn film_map_fits(map: &Self::BakedFilmMap, cols: u32, rows: u32) -> bool {
        map.fits(cols, rows)
    }
}

impl BakeScalar for f32 {
    const TAG: u8 = 1;
    type BakedRow = [f32; 4];
    type BakedFilmMap = crate::film::FloatFilmMap;
    fn film_map_fits(_: &Self::BakedFilmMap, _: u32, _: u32) -> bool {
        true
    }
}

/// The payload: the scene's rendering state (its camera statements are not
/// baked: the camera below is their set-up), the camera, the lens cones, the
/// samples and whether they are adaptive.
fn put_renderer<S: BakeScalar>(r: &Renderer<'_, S>, w: &mut Writer<'_>) {
    let Renderer {
        scene,
        camera,
        cones,
        samples,
        adaptive,
        sampler,
        bright,
    } = r;
    put_scene(scene, w);
    camera.put(w);
    cones.put(w);
    samples.put(w);
    adaptive.put(w);
    sampler.put(w);
    bright.put(w);
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
    } = s;
    ambient.put(w);
    background.put(w);
    shadows.put(w);
    objects.put(w);
    lights.put(w);
}

/// Bytes [`bake`] writes for this renderer.
pub fn baked_len<S: BakeScalar>(renderer: &Renderer<'_, S>) -> usize {
    let mut w = Writer { out: None, pos: 0 };
    put_renderer(renderer, &mut w);
    HEADER_LEN + w.pos + TRAILER_LEN
}

/// Writes the renderer's set-up (scene, camera for its image size, lens
/// cones, samples) into `out`; the number of bytes written.
///
/// # Errors
///
/// [`BakeError::BufferTooSmall`] if `out` is shorter than [`baked_len`]
/// (nothing useful is written then).
pub fn bake<S: BakeScalar>(renderer: &Renderer<'_, S>, out: &mut [u8]) -> Result<usize, BakeError> {
    let needed = baked_len(renderer);
    if out.len() < needed {
        return Err(BakeError::BufferTooSmall { needed });
    }
    let payload = needed - HEADER_LEN - TRAILER_LEN;
    let mut w = Writer {
        out: Some(&mut out[..needed]),
        pos: 0,
    };
    w.bytes(&MAGIC);
    FORMAT_VERSION.put(&mut w);
    S::TAG.put(&mut w);
    0u8.put(&mut w);
    (payload as u32).put(&mut w);
    put_renderer(renderer, &mut w);
    let crc = crc32(&out[..needed - TRAILER_LEN]);
    out[needed - TRAILER_LEN..needed].copy_from_slice(&crc.to_le_bytes());
    Ok(needed)
}

/// A loaded baked scene: the renderer's state, owned. Load it once
/// ([`Baked::load`]), then render with [`Baked::renderer`] as often as needed.
#[derive(Clone, Debug)]
pub struct Baked<S: BakeScalar> {
    scene: Scene<S>,
    camera: Camera<S>,
    cones: LensCones<S>,
    samples: u32,
    adaptive: bool,
    sampler: Sampler,
    bright: BrightFootprints,
}

impl<S: BakeScalar> Baked<S> {
    /// An empty scene (renders black), to load into.
    pub fn empty() -> Self {
        Baked {
            scene: Scene::default(),
            camera: Camera::blank(),
            cones: LensCones::blank(),
            samples: 1,
            adaptive: false,
            sampler: Sampler::default(),
            bright: BrightFootprints::blank(),
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
            *self = Baked::empty();
        }
        result
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
        let mut r = Reader {
            bytes: &body[HEADER_LEN..],
        };
        self.take_payload(&mut r)?;
        if !r.bytes.is_empty() {
            return Err(BakeError::Payload);
        }
        Ok(())
    }

    fn take_payload(&mut self, r: &mut Reader<'_>) -> Result<(), BakeError> {
        let Scene {
            camera: _,
            ambient,
            background,
            shadows,
            objects,
            lights,
        } = &mut self.scene;
        ambient.take(r)?;
        background.take(r)?;
        shadows.take(r)?;
        objects.take(r)?;
        lights.take(r)?;
        self.camera.take(r)?;
        self.cones.take(r)?;
        self.samples.take(r)?;
        self.adaptive.take(r)?;
        self.sampler.take(r)?;
        self.bright.take(r)?;
        // One cone per object: the cull looks an object's cone up by its index.
        if self.cones.len() != self.scene.objects.len() {
            return Err(BakeError::OutOfRange("lens cones do not match the objects"));
        }
        if !(1..=65535).contains(&self.samples) {
            return Err(BakeError::OutOfRange("samples per pixel not in 1..=65535"));
        }
        let (cols, rows) = (self.camera.cols(), self.camera.rows());
        if !(1..=MAX_IMAGE_SIDE).contains(&cols) || !(1..=MAX_IMAGE_SIDE).contains(&rows) {
            return Err(BakeError::OutOfRange("image side not in 1..=8192"));
        }
        // The statements the renderer still reads from the scene's camera.
        self.scene.camera.samples = self.samples;
        self.scene.camera.adaptive = self.adaptive;
        self.scene.camera.sampler = self.sampler;
        Ok(())
    }

    /// The renderer the bytes were baked from: the same pixels.
    pub fn renderer(&self) -> Renderer<'_, S> {
        Renderer {
            scene: &self.scene,
            camera: self.camera,
            cones: self.cones.clone(),
            samples: self.samples,
            adaptive: self.adaptive,
            sampler: self.sampler,
            bright: self.bright.clone(),
        }
    }

    /// The loaded scene (its `camera` statements are defaults: the baked
    /// camera is their set-up, see [`Baked::renderer`]).
    pub fn scene(&self) -> &Scene<S> {
        &self.scene
    }

    /// Image width and height the scene was baked for.
    pub fn size(&self) -> (u32, u32) {
        (self.camera.cols(), self.camera.rows())
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
