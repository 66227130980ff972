//! The checked byte form every baked value is written in and read back from
//! ([`Field`]), below every other module so that each type can say how it is
//! baked where it is defined; the baked renderer itself is [`crate::baked`].

use core::fmt;

use fixed::types::I16F16;

/// The first four bytes of every baked scene.
pub const MAGIC: [u8; 4] = *b"LRBK";
/// The format this library writes and reads. Bump it when any baked struct changes.
pub const FORMAT_VERSION: u16 = 21;
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

/// Where baked bytes go: a buffer, or nowhere (counting only). Runs of
/// zero bytes are written as `0, n` (n = 1..=255 zeros): most of a baked
/// scene is the zero high bytes of small numbers.
pub struct Writer<'a> {
    pub(crate) out: Option<&'a mut [u8]>,
    pub(crate) pos: usize,
    /// Zeros not yet written (below 255).
    pub(crate) zeros: u8,
}

impl<'a> Writer<'a> {
    /// A writer into `out`, or counting only.
    pub(crate) fn new(out: Option<&'a mut [u8]>) -> Self {
        Writer { out, pos: 0, zeros: 0 }
    }

    pub(crate) fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            if x == 0 {
                self.zeros += 1;
                if self.zeros == u8::MAX {
                    self.flush();
                }
            } else {
                self.flush();
                self.raw(x);
            }
        }
    }

    /// Writes the pending zero run; call once after the last value.
    pub(crate) fn flush(&mut self) {
        if self.zeros > 0 {
            self.raw(0);
            self.raw(self.zeros);
            self.zeros = 0;
        }
    }

    fn raw(&mut self, x: u8) {
        if let Some(dst) = self.out.as_deref_mut().and_then(|o| o.get_mut(self.pos)) {
            *dst = x;
        }
        self.pos += 1;
    }
}

/// Baked bytes being read. A missing byte or a bad value is recorded (the
/// first one wins) and reading goes on with zeros, so that reading a field
/// is straight-line code, without a branch on an error after every value;
/// nothing read after an error is used.
pub struct Reader<'a> {
    pub(crate) bytes: &'a [u8],
    /// Zeros of the current run still to read.
    pub(crate) zeros: u8,
    pub(crate) error: Option<BakeError>,
}

impl<'a> Reader<'a> {
    /// A reader of a payload.
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Reader {
            bytes,
            zeros: 0,
            error: None,
        }
    }

    /// Whether nothing has gone wrong so far.
    pub fn ok(&self) -> bool {
        self.error.is_none()
    }

    /// Records `e` unless an earlier error is recorded.
    #[inline(never)]
    pub fn fail(&mut self, e: BakeError) {
        if self.error.is_none() {
            self.error = Some(e);
        }
    }

    /// Records a value out of range, named by `what`.
    pub fn out_of_range(&mut self, what: &'static str) {
        self.fail(BakeError::OutOfRange(what));
    }

    /// Whether every byte was read (no zero run left either).
    pub(crate) fn at_end(&self) -> bool {
        self.bytes.is_empty() && self.zeros == 0
    }

    /// The next byte, expanding zero runs; 0 past the end (recorded).
    #[inline(always)]
    fn byte(&mut self) -> u8 {
        if self.zeros > 0 {
            self.zeros -= 1;
            return 0;
        }
        match *self.bytes {
            [0, n, ref rest @ ..] if n > 0 => {
                self.zeros = n - 1;
                self.bytes = rest;
                0
            }
            [x, ref rest @ ..] if x != 0 => {
                self.bytes = rest;
                x
            }
            // The end, a run without its length, or a run of no zeros.
            _ => {
                self.fail(BakeError::Payload);
                0
            }
        }
    }

    /// The next `n` (at most 4) bytes as a little-endian number.
    // Once, called by every value: the loader's flash on a microcontroller.
    #[inline(never)]
    pub(crate) fn le(&mut self, n: u32) -> u32 {
        let mut v = 0;
        for i in 0..n.min(4) {
            v |= (self.byte() as u32) << (8 * i);
        }
        v
    }
}

/// A value with a baked form: written, read back in place, and blank (what
/// a value is before it is read). Implemented by every type a renderer holds.
pub trait Field {
    /// Appends the value's bytes.
    fn put(&self, w: &mut Writer<'_>);
    /// Reads the value over `self`, checking its range; a failure is
    /// recorded in `r` ([`Reader::fail`]), and what follows is read anyway.
    fn take(&mut self, r: &mut Reader<'_>);
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
        #[inline]
        fn put(&self, w: &mut $crate::bytes::Writer<'_>) {
            let $name { $($field),* } = self;
            $( $crate::bytes::Field::put($field, w); )*
        }
        #[inline]
        fn take(&mut self, r: &mut $crate::bytes::Reader<'_>) {
            let $name { $($field),* } = self;
            $( $crate::bytes::Field::take($field, r); )*
            // Checked only while all is well: a check may rely on the ones before it.
            $( if r.ok() {
                let $v = &*self;
                let checked = (|| -> Result<(), $crate::bytes::BakeError> {
                    $check
                    #[allow(unreachable_code)]
                    Ok(())
                })();
                if let Err(e) = checked {
                    r.fail(e);
                }
            } )?
        }
        fn blank() -> Self {
            $name { $($field: $crate::bytes::Field::blank()),* }
        }
    };
}
pub(crate) use baked_fields;

macro_rules! int_field {
    ($($t:ty: $n:literal),*) => {$(
        impl Field for $t {
            fn put(&self, w: &mut Writer<'_>) {
                w.bytes(&self.to_le_bytes());
            }
            #[inline]
            fn take(&mut self, r: &mut Reader<'_>) {
                // Truncated to the type's width, sign included.
                *self = r.le($n) as $t;
            }
            fn blank() -> Self {
                0
            }
        }
    )*};
}
int_field!(u8: 1, u16: 2, i32: 4, u32: 4);

impl Field for i16 {
    fn put(&self, w: &mut Writer<'_>) {
        w.bytes(&self.to_le_bytes());
    }
    #[inline]
    fn take(&mut self, r: &mut Reader<'_>) {
        *self = r.le(2) as u16 as i16;
    }
    fn blank() -> Self {
        0
    }
}

impl Field for i64 {
    fn put(&self, w: &mut Writer<'_>) {
        w.bytes(&self.to_le_bytes());
    }
    #[inline]
    fn take(&mut self, r: &mut Reader<'_>) {
        let lo = r.le(4) as u64;
        *self = (lo | (r.le(4) as u64) << 32) as i64;
    }
    fn blank() -> Self {
        0
    }
}

impl Field for bool {
    fn put(&self, w: &mut Writer<'_>) {
        w.bytes(&[*self as u8]);
    }
    #[inline]
    fn take(&mut self, r: &mut Reader<'_>) {
        let b = r.le(1);
        if b > 1 {
            r.out_of_range("a flag is neither 0 nor 1");
        }
        *self = b == 1;
    }
    fn blank() -> Self {
        false
    }
}

impl Field for I16F16 {
    fn put(&self, w: &mut Writer<'_>) {
        self.to_bits().put(w);
    }
    #[inline]
    fn take(&mut self, r: &mut Reader<'_>) {
        *self = I16F16::from_bits(r.le(4) as i32);
    }
    fn blank() -> Self {
        I16F16::ZERO
    }
}

impl Field for f32 {
    fn put(&self, w: &mut Writer<'_>) {
        self.to_bits().put(w);
    }
    #[inline]
    fn take(&mut self, r: &mut Reader<'_>) {
        *self = f32::from_bits(r.le(4));
        // Infinities and NaNs would paint a picture the host never made.
        if !self.is_finite() {
            r.out_of_range("an f32 is not finite");
        }
    }
    fn blank() -> Self {
        0.0
    }
}

// `Copy`: a blank array is one blank item repeated, smaller than
// `array::from_fn` in a microcontroller's loader.
impl<T: Field + Copy, const N: usize> Field for [T; N] {
    fn put(&self, w: &mut Writer<'_>) {
        self.iter().for_each(|x| x.put(w));
    }
    fn take(&mut self, r: &mut Reader<'_>) {
        self.iter_mut().for_each(|x| x.take(r))
    }
    fn blank() -> Self {
        [T::blank(); N]
    }
}

impl<A: Field, B: Field> Field for (A, B) {
    fn put(&self, w: &mut Writer<'_>) {
        self.0.put(w);
        self.1.put(w);
    }
    fn take(&mut self, r: &mut Reader<'_>) {
        self.0.take(r);
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
    fn take(&mut self, r: &mut Reader<'_>) {
        let mut some = false;
        some.take(r);
        if !some {
            *self = None;
            return;
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
    fn take(&mut self, r: &mut Reader<'_>) {
        let mut n = 0u16;
        n.take(r);
        if n as usize > N {
            r.out_of_range("more items than the scene's capacity");
        }
        self.clear();
        // Not past the first error: no item is read from nonsense.
        while r.ok() && self.len() < n as usize {
            // Pushed blank, then read where it lies: no second copy on the stack.
            if self.push(T::blank()).is_err() {
                break;
            }
            if let Some(x) = self.last_mut() {
                x.take(r);
            }
        }
    }
    fn blank() -> Self {
        heapless::Vec::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stored bytes of `values`, written as a baked payload is.
    fn stored<T: Field>(values: &T) -> std::vec::Vec<u8> {
        let mut count = Writer::new(None);
        values.put(&mut count);
        count.flush();
        let mut out = std::vec![0u8; count.pos];
        let mut w = Writer::new(Some(&mut out));
        values.put(&mut w);
        w.flush();
        assert_eq!(w.pos, out.len());
        out
    }

    fn read<T: Field>(bytes: &[u8]) -> (T, Option<BakeError>, bool) {
        let mut r = Reader::new(bytes);
        let mut v = T::blank();
        v.take(&mut r);
        let end = r.at_end();
        (v, r.error, end)
    }

    #[test]
    fn zero_runs_of_any_length_round_trip() {
        // Runs from none to past two full runs of 255, between non-zero bytes.
        for run in [0usize, 1, 2, 254, 255, 256, 509, 510, 511, 600] {
            let mut v = [0u8; 700];
            v[0] = 7;
            v[run + 1] = 9;
            let bytes = stored(&v);
            // Each zero run costs two bytes per 255 zeros or part of them.
            let runs = |n: usize| 2 * n.div_ceil(255);
            assert_eq!(bytes.len(), 2 + runs(run) + runs(700 - run - 2), "run {run}");
            let (back, error, end) = read::<[u8; 700]>(&bytes);
            assert_eq!((back, error, end), (v, None, true), "run {run}");
        }
    }

    #[test]
    fn a_bad_zero_run_or_a_short_payload_is_a_payload_error() {
        // A run of no zeros, a run without its length, nothing at all.
        for bytes in [&[0u8, 0, 5, 5][..], &[5, 5, 5, 0], &[]] {
            let (_, error, _) = read::<u32>(bytes);
            assert_eq!(error, Some(BakeError::Payload), "{bytes:?}");
        }
        // A run longer than the value: the value reads, the rest is left over.
        let (v, error, end) = read::<u16>(&[0, 3]);
        assert_eq!((v, error, end), (0, None, false));
    }

    #[test]
    fn the_first_error_is_the_one_reported() {
        // A flag of 2 (out of range), then a payload that ends early.
        let (_, error, _) = read::<(bool, u32)>(&[2, 1]);
        assert_eq!(error, Some(BakeError::OutOfRange("a flag is neither 0 nor 1")));
        // The other way round: the payload ends inside the first value.
        let (_, error, _) = read::<(u32, bool)>(&[1, 2]);
        assert_eq!(error, Some(BakeError::Payload));
    }

    #[test]
    fn a_list_longer_than_its_capacity_reads_no_item() {
        let mut bytes = stored(&17u16);
        bytes.extend_from_slice(&[1, 2, 3]);
        let (v, error, _) = read::<heapless::Vec<u8, 16>>(&bytes);
        assert!(v.is_empty());
        assert_eq!(
            error,
            Some(BakeError::OutOfRange("more items than the scene's capacity"))
        );
    }
}
