//! The checked byte form every baked value is written in and read back from
//! ([`Field`]), below every other module so that each type can say how it is
//! baked where it is defined; the baked renderer itself is [`crate::baked`].

use core::fmt;

use fixed::types::I16F16;

/// The first four bytes of every baked scene.
pub const MAGIC: [u8; 4] = *b"LRBK";
/// The format this library writes and reads. Bump it when any baked struct changes.
pub const FORMAT_VERSION: u16 = 4;
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
    pub(crate) out: Option<&'a mut [u8]>,
    pub(crate) pos: usize,
}

impl Writer<'_> {
    pub(crate) fn bytes(&mut self, b: &[u8]) {
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
    pub(crate) bytes: &'a [u8],
}

impl Reader<'_> {
    pub(crate) fn array<const N: usize>(&mut self) -> Result<[u8; N], BakeError> {
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
        fn put(&self, w: &mut $crate::bytes::Writer<'_>) {
            let $name { $($field),* } = self;
            $( $crate::bytes::Field::put($field, w); )*
        }
        fn take(&mut self, r: &mut $crate::bytes::Reader<'_>) -> Result<(), $crate::bytes::BakeError> {
            let $name { $($field),* } = self;
            $( $crate::bytes::Field::take($field, r)?; )*
            $( let $v = &*self; $check )?
            #[allow(unreachable_code)]
            Ok(())
        }
        fn blank() -> Self {
            $name { $($field: $crate::bytes::Field::blank()),* }
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
