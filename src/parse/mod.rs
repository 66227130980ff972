//! The scene-file parser (SPEC section 2; `docs/scene-format.md`).
//!
//! Parsing validates everything once, computes each object's matrices exactly
//! (`f64`) and rounds them to the number type; after that, rendering has no
//! fallible step. Any input gives either a [`Scene`] or a [`ParseError`] that
//! names the 1-based line, the statement and what is wrong. It never panics.

use core::fmt;

use crate::camera::sampler::Sampler;
use crate::camera::{self, aperture};
use crate::geometry::transform::Mat34;
use crate::geometry::vec3::Vec3;
use crate::number::Scalar;
use crate::scene::autofocus;
use crate::scene::shape::Shape;
use crate::scene::{Light, Object, ObjectDesc, Scene, DEFAULT_MATERIAL, MATERIALS, MAX_LIGHTS, MAX_OBJECTS};

/// Magnitudes a real value must stay below: the range of Q16.16.
pub const REAL_LIMIT: f64 = 32768.0;

/// A short copy of an offending word from the input (truncated to fit).
pub type Word = heapless::String<32>;

fn word(s: &str) -> Word {
    let mut w = Word::new();
    for ch in s.chars() {
        if w.len() + ch.len_utf8() > 29 {
            let _ = w.push_str("...");
            break;
        }
        let _ = w.push(ch);
    }
    w
}

/// What is wrong with a line. See [`ParseError`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// A byte that is not plain text: outside a comment, only printable ASCII,
    /// spaces and tabs; inside one, valid UTF-8.
    NotText {
        /// The offending byte.
        byte: u8,
    },
    /// The first word of a line is no keyword.
    UnknownKeyword(Word),
    /// A statement has the wrong number of values.
    WrongCount {
        /// The statement's keyword.
        keyword: &'static str,
        /// How many it takes, in words ("3", "1 or 2").
        expected: &'static str,
        /// How many it got.
        found: usize,
    },
    /// A value is not a decimal number (`nan`, `inf`, `1e5` included).
    NotANumber {
        /// The statement's keyword.
        keyword: &'static str,
        /// The value as written.
        value: Word,
    },
    /// A value is not a whole number.
    NotAnInteger {
        /// The statement's keyword.
        keyword: &'static str,
        /// The value as written.
        value: Word,
    },
    /// A value is outside what its statement allows.
    OutOfRange {
        /// The statement's keyword.
        keyword: &'static str,
        /// The value as written.
        value: Word,
        /// The rule it breaks ("must be greater than 0").
        rule: &'static str,
    },
    /// `look` (or `up`) is the zero vector.
    ZeroVector {
        /// `look` or `up`.
        keyword: &'static str,
    },
    /// `up` is parallel to `look`.
    UpParallelToLook,
    /// `focal_length` is not smaller than `image_distance`.
    FocalLength {
        /// f.
        focal_length: f64,
        /// N.
        image_distance: f64,
    },
    /// `object` names an unknown shape.
    UnknownShape(Word),
    /// `object` names an unknown material.
    UnknownMaterial(Word),
    /// `rotate` names an axis other than x, y, z.
    UnknownAxis(Word),
    /// `sampler` names neither `independent` nor `stratified`.
    UnknownSampler(Word),
    /// `shadows` and `adaptive` take `on` or `off`: the keyword and the word.
    NotASwitch(&'static str, Word),
    /// An object statement before any `object`.
    NoObject {
        /// The statement's keyword.
        keyword: &'static str,
    },
    /// `light_intensity` before any `light_position`.
    NoLight,
    /// A statement where a transformation line was announced.
    TransformExpected {
        /// The `total_transformation` count.
        count: u32,
        /// Transformation lines seen so far.
        seen: u32,
        /// Line of the `total_transformation` statement.
        count_line: u32,
    },
    /// The object ended before its announced transformation lines.
    TransformsMissing {
        /// The `total_transformation` count.
        count: u32,
        /// Transformation lines seen.
        seen: u32,
    },
    /// More transformation lines than the object's `total_transformation`.
    TooManyTransforms {
        /// The `total_transformation` count.
        count: u32,
    },
    /// More objects than the renderer holds.
    TooManyObjects {
        /// The capacity.
        limit: usize,
    },
    /// More lights than the renderer holds.
    TooManyLights {
        /// The capacity.
        limit: usize,
    },
    /// An object's transform puts it beyond Q16.16's range (±32768), or
    /// squeezes it flat.
    ObjectOutOfRange,
    /// `f_number` makes a lens radius beyond Q16.16's range.
    ApertureTooWide {
        /// The radius f / (2k).
        radius: f64,
    },
    /// `focus_on` names an object the scene does not have.
    NoSuchObject {
        /// The 1-based index given.
        index: u32,
        /// How many objects the scene has.
        count: usize,
    },
    /// `focus_on` names an object whose focus point is not in front of the lens.
    FocusBehindCamera {
        /// The 1-based index given.
        index: u32,
        /// The focus point's depth along the viewing direction.
        depth: f64,
    },
    /// Part of an object lies 32768 or more from the lens or a light along an
    /// axis: Q16.16 cannot hold the difference of their coordinates.
    TooFar {
        /// "the lens" or "the light".
        from: &'static str,
        /// The line of that lens or light (0: the default lens at the origin).
        line: u32,
    },
}

/// A scene that breaks the format: the 1-based line and what is wrong.
///
/// Displays as `line 12: unknown keyword "ligth_position"`.
#[derive(Clone, Debug, PartialEq)]
pub struct ParseError {
    /// 1-based line number.
    pub line: u32,
    /// What is wrong.
    pub kind: ErrorKind,
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ErrorKind::*;
        match self {
            NotText { byte } => write!(
                f,
                "byte 0x{byte:02X} is not allowed here (statements are plain ASCII; comments are UTF-8)"
            ),
            UnknownKeyword(w) => write!(f, "unknown keyword \"{w}\""),
            WrongCount { keyword, expected, found } => {
                write!(f, "{keyword} takes {expected} value(s), found {found}")
            }
            NotANumber { keyword, value } => write!(
                f,
                "{keyword}: \"{value}\" is not a number (decimal digits with an optional sign and point)"
            ),
            NotAnInteger { keyword, value } => write!(f, "{keyword}: \"{value}\" is not a whole number"),
            OutOfRange { keyword, value, rule } => write!(f, "{keyword} {value} {rule}"),
            ZeroVector { keyword } => write!(f, "{keyword} must not be the zero vector"),
            UpParallelToLook => write!(f, "up must not be parallel to look"),
            FocalLength {
                focal_length,
                image_distance,
            } => write!(
                f,
                "focal_length {focal_length} must be smaller than image_distance {image_distance}"
            ),
            UnknownShape(w) => write!(f, "object: unknown shape \"{w}\" (sphere, plane, cube, cylinder or cone)"),
            UnknownMaterial(w) => write!(f, "object: unknown material \"{w}\""),
            UnknownAxis(w) => write!(f, "rotate: unknown axis \"{w}\" (x, y or z)"),
            UnknownSampler(w) => write!(f, "sampler: unknown sampler \"{w}\" (independent or stratified)"),
            NotASwitch(k, w) => write!(f, "{k}: \"{w}\" must be on or off"),
            NoObject { keyword } => write!(f, "{keyword} before any object statement"),
            NoLight => write!(f, "light_intensity before any light_position"),
            TransformExpected {
                count,
                seen,
                count_line,
            } => write!(
                f,
                "expected a transformation line (scale, rotate, translate): total_transformation {count} on line {count_line} announced {count}, only {seen} given"
            ),
            TransformsMissing { count, seen } => write!(
                f,
                "total_transformation {count}: the object ended after {seen} transformation line(s)"
            ),
            TooManyTransforms { count } => write!(
                f,
                "more transformation lines than total_transformation {count} announced"
            ),
            TooManyObjects { limit } => write!(f, "too many objects: the renderer holds at most {limit}"),
            TooManyLights { limit } => write!(f, "too many lights: the renderer holds at most {limit}"),
            ObjectOutOfRange => write!(
                f,
                "object: its transformations put it beyond the range of Q16.16 (coordinates below 32768)"
            ),
            ApertureTooWide { radius } => write!(
                f,
                "f_number: the lens radius focal_length / (2 f_number) = {radius} must be below 32768"
            ),
            NoSuchObject { index, count } => {
                write!(f, "focus_on {index}: the scene has only {count} object(s)")
            }
            FocusBehindCamera { index, depth } => {
                // Rounded for reading; + 0.0 turns a rounded −0 into 0.
                let d = libm::round(depth * 1000.0) / 1000.0 + 0.0;
                write!(
                    f,
                    "focus_on {index}: the object is not in front of the camera (its focus point lies at depth {d})"
                )
            }
            TooFar { from, line: 0 } => write!(
                f,
                "object: part of it lies 32768 or more from {from} at the origin along an axis, beyond the range of Q16.16"
            ),
            TooFar { from, line } => write!(
                f,
                "object: part of it lies 32768 or more from {from} of line {line} along an axis, beyond the range of Q16.16"
            ),
        }
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.kind)
    }
}

/// A scene that does not parse is an error like any other (`?` into
/// `Box<dyn Error>` on the host, `defmt`-free reports on a board).
impl core::error::Error for ParseError {}

mod keyword;
pub use keyword::{Keyword, Section, AXES, KEYWORDS, SAMPLERS, SWITCH};

/// The most values any statement takes, plus one to detect extras.
const MAX_VALUES: usize = 4;

/// One statement: its keyword and values.
struct Statement<'a> {
    line: u32,
    keyword: Keyword,
    values: [&'a str; MAX_VALUES],
    count: usize,
}

impl<'a> Statement<'a> {
    fn err(&self, kind: ErrorKind) -> ParseError {
        ParseError { line: self.line, kind }
    }

    fn expect(&self, n: usize) -> Result<(), ParseError> {
        const NAMES: [&str; 4] = ["0", "1", "2", "3"];
        if self.count != n {
            return Err(self.err(ErrorKind::WrongCount {
                keyword: self.keyword.name(),
                expected: NAMES[n],
                found: self.count,
            }));
        }
        Ok(())
    }

    /// Value `i` as a real, checked against the format's grammar and range.
    fn real(&self, i: usize) -> Result<f64, ParseError> {
        let s = self.values[i];
        let x = parse_decimal(s).ok_or_else(|| {
            self.err(ErrorKind::NotANumber {
                keyword: self.keyword.name(),
                value: word(s),
            })
        })?;
        if x.is_nan() || x.abs() >= REAL_LIMIT {
            return Err(self.range(i, "must be below 32768 in magnitude (the range of Q16.16)"));
        }
        Ok(x)
    }

    fn range(&self, i: usize, rule: &'static str) -> ParseError {
        self.err(ErrorKind::OutOfRange {
            keyword: self.keyword.name(),
            value: word(self.values[i]),
            rule,
        })
    }

    /// The single real value, with `ok` as its rule.
    fn one_real(&self, ok: fn(f64) -> bool, rule: &'static str) -> Result<f64, ParseError> {
        self.expect(1)?;
        let x = self.real(0)?;
        if !ok(x) {
            return Err(self.range(0, rule));
        }
        Ok(x)
    }

    /// Three reals, each passing `ok`.
    fn three(&self, ok: fn(f64) -> bool, rule: &'static str) -> Result<[f64; 3], ParseError> {
        self.expect(3)?;
        let mut v = [0.0; 3];
        for (i, x) in v.iter_mut().enumerate() {
            *x = self.real(i)?;
            if !ok(*x) {
                return Err(self.range(i, rule));
            }
        }
        Ok(v)
    }

    /// The single whole number, within `lo..=hi`.
    fn integer(&self, lo: u64, hi: u64, rule: &'static str) -> Result<u32, ParseError> {
        self.expect(1)?;
        let s = self.values[0];
        let digits = s.strip_prefix('+').unwrap_or(s);
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            // A negative whole number is a range error, anything else not a number.
            if let Some(d) = s.strip_prefix('-') {
                if !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()) {
                    return Err(self.range(0, rule));
                }
            }
            return Err(self.err(ErrorKind::NotAnInteger {
                keyword: self.keyword.name(),
                value: word(s),
            }));
        }
        let mut n: u64 = 0;
        for b in digits.bytes() {
            n = n.saturating_mul(10).saturating_add((b - b'0') as u64);
        }
        if n < lo || n > hi {
            return Err(self.range(0, rule));
        }
        Ok(n as u32)
    }
}

/// Parses the format's decimal numbers: optional sign, digits, optional
/// fraction (`-80`, `0.5`, `.5`, `1.`); no exponent, `nan` or `inf`.
///
/// # Panics
///
/// Never.
pub fn parse_decimal(s: &str) -> Option<f64> {
    let b = s.as_bytes();
    let body = match b.first() {
        Some(b'+') | Some(b'-') => &b[1..],
        _ => b,
    };
    let mut digits = 0;
    let mut points = 0;
    for &c in body {
        match c {
            b'0'..=b'9' => digits += 1,
            b'.' => points += 1,
            _ => return None,
        }
    }
    if digits == 0 || points > 1 {
        return None;
    }
    // core's parser is correctly rounded; the grammar above keeps it to decimals.
    s.parse::<f64>().ok()
}

/// An object being read: its description so far and its transformation count.
struct Pending {
    line: u32,
    desc: ObjectDesc,
    /// `(count, line of the count)` when `total_transformation` was given.
    count: Option<(u32, u32)>,
    /// Transformation lines seen since the count.
    seen: u32,
}

/// Splits one raw line into its statement part, checking the bytes.
fn statement_text(raw: &[u8], line: u32) -> Result<&str, ParseError> {
    let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
    let (stmt, comment) = match raw.iter().position(|&b| b == b'#') {
        Some(i) => (&raw[..i], Some(&raw[i + 1..])),
        None => (raw, None),
    };
    if let Some(c) = comment {
        if let Err(e) = core::str::from_utf8(c) {
            let byte = c[e.valid_up_to()];
            return Err(ParseError {
                line,
                kind: ErrorKind::NotText { byte },
            });
        }
    }
    if let Some(&byte) = stmt.iter().find(|&&b| !(b == b'\t' || (0x20..0x7F).contains(&b))) {
        return Err(ParseError {
            line,
            kind: ErrorKind::NotText { byte },
        });
    }
    // Checked: printable ASCII, spaces and tabs only.
    Ok(core::str::from_utf8(stmt).unwrap_or(""))
}

impl<S: Scalar> Scene<S> {
    /// Parses a scene file's text.
    ///
    /// # Errors
    ///
    /// A [`ParseError`] naming the first line that breaks the format.
    ///
    /// # Panics
    ///
    /// Never, whatever the input.
    ///
    /// ```
    /// use lensray::{Scene, I16F16};
    /// let scene = Scene::<I16F16>::parse("object sphere gold\ntranslate 0 0 -5\n").unwrap();
    /// assert_eq!(scene.objects().len(), 1);
    /// let err = Scene::<I16F16>::parse("width 10\nligth_position 1 2 3\n").unwrap_err();
    /// assert_eq!(err.to_string(), "line 2: unknown keyword \"ligth_position\"");
    /// ```
    pub fn parse(text: &str) -> Result<Self, ParseError> {
        Self::parse_bytes(text.as_bytes())
    }

    /// Parses a scene file's bytes (a UTF-8 byte order mark at the start is skipped).
    ///
    /// # Errors
    ///
    /// As [`Scene::parse`].
    ///
    /// # Panics
    ///
    /// Never, whatever the bytes.
    pub fn parse_bytes(bytes: &[u8]) -> Result<Self, ParseError> {
        let mut scene = Scene::default();
        scene.parse_into(bytes)?;
        Ok(scene)
    }

    /// Parses a scene file's bytes into `self`, which it first resets to the
    /// empty scene: the way to parse on a small stack (a microcontroller's),
    /// as the scene is built where it stays instead of being returned by value.
    /// On an error `self` holds the scene up to the bad line.
    ///
    /// # Errors
    ///
    /// As [`Scene::parse`].
    ///
    /// # Panics
    ///
    /// Never, whatever the bytes.
    pub fn parse_into(&mut self, bytes: &[u8]) -> Result<(), ParseError> {
        *self = Scene::default();
        let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        let mut p = Parser::<S> {
            scene: self,
            object: None,
            lines: CameraLines::default(),
            focus: Focus::FocalLength,
            stop: Stop::Radius,
            focus_target: last_focus_on(bytes),
            focus_desc: None,
            placed: heapless::Vec::new(),
            light_at: heapless::Vec::new(),
        };
        for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
            let line = u32::try_from(i + 1).unwrap_or(u32::MAX);
            let text = statement_text(raw, line)?;
            let mut tokens = text.split([' ', '\t']).filter(|t| !t.is_empty());
            let Some(first) = tokens.next() else { continue };
            let keyword = Keyword::from_name(first).ok_or(ParseError {
                line,
                kind: ErrorKind::UnknownKeyword(word(first)),
            })?;
            let mut st = Statement {
                line,
                keyword,
                values: [""; MAX_VALUES],
                count: 0,
            };
            for t in tokens {
                if st.count < MAX_VALUES {
                    st.values[st.count] = t;
                }
                st.count += 1;
            }
            p.statement(&st)?;
        }
        p.finish_object()?;
        p.finish_camera()
    }
}

/// Lines of the camera statements the final checks refer to.
#[derive(Default)]
struct CameraLines {
    lens_position: u32,
    focal_length: u32,
    image_distance: u32,
    look: u32,
    up: u32,
}

/// The statement that sets the focus; the last one in the file stands.
#[derive(Copy, Clone)]
enum Focus {
    /// `focal_length` (or the default): as written.
    FocalLength,
    /// `focus_distance d`.
    Distance(f64),
    /// `focus_on I` on this line.
    Object { index: u32, line: u32 },
}

/// The statement that sets the aperture's size; the last one stands.
#[derive(Copy, Clone)]
enum Stop {
    /// `radius` (or the default).
    Radius,
    /// `f_number k` on this line, with the focal length in force at the end of the file.
    FNumber(f64, u32),
}

struct Parser<'a, S: Scalar> {
    scene: &'a mut Scene<S>,
    object: Option<Pending>,
    lines: CameraLines,
    focus: Focus,
    stop: Stop,
    /// The index of the file's last `focus_on`, found before parsing: the one
    /// object whose exact description is kept (no list of them all).
    focus_target: Option<u32>,
    focus_desc: Option<ObjectDesc>,
    /// Each bounded object's line, centre and reach along each axis.
    placed: heapless::Vec<(u32, [f64; 3], [f64; 3]), MAX_OBJECTS>,
    /// Each light's line and position.
    light_at: heapless::Vec<(u32, [f64; 3]), MAX_LIGHTS>,
}

/// The value of the last `focus_on` line with a whole number, if any: a quick
/// look ahead, so that an object can be kept for autofocus as it goes by
/// (the real parse checks every line).
fn last_focus_on(bytes: &[u8]) -> Option<u32> {
    let mut target = None;
    for raw in bytes.split(|&b| b == b'\n') {
        let stmt = raw.split(|&b| b == b'#').next().unwrap_or(raw);
        let mut tokens = stmt
            .split(|&b| b == b' ' || b == b'\t' || b == b'\r')
            .filter(|t| !t.is_empty());
        if tokens.next() != Some(b"focus_on".as_slice()) {
            continue;
        }
        if let Some(n) = tokens
            .next()
            .and_then(|t| core::str::from_utf8(t).ok())
            .and_then(|t| t.parse::<u32>().ok())
        {
            target = Some(n);
        }
    }
    target
}

fn positive(x: f64) -> bool {
    x > 0.0
}
fn non_negative(x: f64) -> bool {
    x >= 0.0
}
fn any(_: f64) -> bool {
    true
}
fn unit_interval(x: f64) -> bool {
    (0.0..=1.0).contains(&x)
}
fn non_zero(x: f64) -> bool {
    x != 0.0
}

const GT0: &str = "must be greater than 0";
const GE0: &str = "must not be negative";

impl<S: Scalar> Parser<'_, S> {
    fn statement(&mut self, st: &Statement<'_>) -> Result<(), ParseError> {
        let is_transform = st.keyword.section() == Section::Transform;
        if let Some(obj) = &self.object {
            if let Some((count, count_line)) = obj.count {
                if obj.seen < count && !is_transform {
                    return Err(st.err(ErrorKind::TransformExpected {
                        count,
                        seen: obj.seen,
                        count_line,
                    }));
                }
            }
        }
        if !self.camera_statement(st)? {
            self.scene_statement(st)?;
        }
        Ok(())
    }

    /// A camera statement; `false` for any other.
    fn camera_statement(&mut self, st: &Statement<'_>) -> Result<bool, ParseError> {
        let cam = &mut self.scene.camera;
        match st.keyword {
            Keyword::Width => cam.width = st.one_real(positive, GT0)?,
            Keyword::AspectRatio => cam.aspect_ratio = st.one_real(positive, GT0)?,
            Keyword::ImageDistance => {
                cam.image_distance = st.one_real(positive, GT0)?;
                self.lines.image_distance = st.line;
            }
            Keyword::LensPosition => {
                cam.lens_position = st.three(any, "")?;
                self.lines.lens_position = st.line;
            }
            Keyword::FocalLength => {
                cam.focal_length = st.one_real(positive, GT0)?;
                self.lines.focal_length = st.line;
                self.focus = Focus::FocalLength;
            }
            Keyword::FocusDistance => self.focus = Focus::Distance(st.one_real(positive, GT0)?),
            Keyword::FocusOn => {
                let index = st.integer(1, MAX_OBJECTS as u64, "must be an object's number, from 1 (file order)")?;
                self.focus = Focus::Object { index, line: st.line };
            }
            Keyword::FNumber => self.stop = Stop::FNumber(st.one_real(positive, GT0)?, st.line),
            Keyword::ApertureBlades => {
                const RULE: &str = "must be 0 (round) or between 3 and 16";
                let n = st.integer(0, aperture::MAX_BLADES as u64, RULE)?;
                if n == 1 || n == 2 {
                    return Err(st.range(0, RULE));
                }
                cam.aperture_blades = n;
            }
            Keyword::ApertureRotation => cam.aperture_rotation = st.one_real(any, "")?,
            Keyword::Look | Keyword::Up => {
                let v = st.three(any, "")?;
                if v == [0.0; 3] {
                    return Err(st.err(ErrorKind::ZeroVector {
                        keyword: st.keyword.name(),
                    }));
                }
                if st.keyword == Keyword::Look {
                    cam.look = v;
                    self.lines.look = st.line;
                } else {
                    cam.up = v;
                    self.lines.up = st.line;
                }
            }
            Keyword::Point => cam.samples = st.integer(1, 65535, "must be between 1 and 65535")?,
            Keyword::Radius => {
                cam.radius = st.one_real(non_negative, GE0)?;
                self.stop = Stop::Radius;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// A scene, light or object statement.
    fn scene_statement(&mut self, st: &Statement<'_>) -> Result<(), ParseError> {
        let cam = &mut self.scene.camera;
        match st.keyword {
            Keyword::AmbientLight => self.scene.ambient = Vec3::from_f64(st.three(non_negative, GE0)?),
            Keyword::Background => {
                self.scene.background = Vec3::from_f64(st.three(unit_interval, "must be between 0 and 1")?)
            }
            Keyword::Shadows => {
                st.expect(1)?;
                self.scene.shadows = match st.values[0] {
                    w if w == SWITCH[1] => true,
                    w if w == SWITCH[0] => false,
                    other => return Err(st.err(ErrorKind::NotASwitch("shadows", word(other)))),
                };
            }
            Keyword::Adaptive => {
                st.expect(1)?;
                cam.adaptive = match st.values[0] {
                    w if w == SWITCH[1] => true,
                    w if w == SWITCH[0] => false,
                    other => return Err(st.err(ErrorKind::NotASwitch("adaptive", word(other)))),
                };
            }
            Keyword::Sampler => {
                st.expect(1)?;
                cam.sampler = match st.values[0] {
                    w if w == SAMPLERS[0] => Sampler::Independent,
                    w if w == SAMPLERS[1] => Sampler::Stratified,
                    other => return Err(st.err(ErrorKind::UnknownSampler(word(other)))),
                };
            }
            Keyword::LightPosition => {
                let at = st.three(any, "")?;
                // Same capacity as the lights: a push that fails here fails below too.
                let _ = self.light_at.push((st.line, at));
                let position = Vec3::from_f64(at);
                let light = Light {
                    position,
                    intensity: Vec3::from_f64([1.0; 3]),
                };
                self.scene
                    .lights
                    .push(light)
                    .map_err(|_| st.err(ErrorKind::TooManyLights { limit: MAX_LIGHTS }))?;
            }
            Keyword::LightIntensity => {
                let v = Vec3::from_f64(st.three(non_negative, GE0)?);
                let light = self.scene.lights.last_mut().ok_or(st.err(ErrorKind::NoLight))?;
                light.intensity = v;
            }
            Keyword::Object => self.start_object(st)?,
            _ => self.object_statement(st)?,
        }
        Ok(())
    }

    fn start_object(&mut self, st: &Statement<'_>) -> Result<(), ParseError> {
        if st.count == 0 || st.count > 2 {
            return Err(st.err(ErrorKind::WrongCount {
                keyword: Keyword::Object.name(),
                expected: "1 or 2",
                found: st.count,
            }));
        }
        self.finish_object()?;
        if self.scene.objects.len() >= MAX_OBJECTS {
            return Err(st.err(ErrorKind::TooManyObjects { limit: MAX_OBJECTS }));
        }
        let shape = Shape::ALL
            .iter()
            .find(|(name, _)| *name == st.values[0])
            .map(|&(_, s)| s)
            .ok_or_else(|| st.err(ErrorKind::UnknownShape(word(st.values[0]))))?;
        let material = if st.count == 2 {
            MATERIALS
                .iter()
                .find(|m| m.0 == st.values[1])
                .ok_or_else(|| st.err(ErrorKind::UnknownMaterial(word(st.values[1]))))?
        } else {
            &DEFAULT_MATERIAL
        };
        self.object = Some(Pending {
            line: st.line,
            desc: ObjectDesc::new(shape, material, Mat34::IDENTITY),
            count: None,
            seen: 0,
        });
        Ok(())
    }

    fn object_statement(&mut self, st: &Statement<'_>) -> Result<(), ParseError> {
        let obj = self.object.as_mut().ok_or_else(|| {
            st.err(ErrorKind::NoObject {
                keyword: st.keyword.name(),
            })
        })?;
        let d = &mut obj.desc;
        let transform = match st.keyword {
            Keyword::Ka => {
                d.ka = st.three(non_negative, GE0)?;
                None
            }
            Keyword::Kd => {
                d.kd = st.three(non_negative, GE0)?;
                None
            }
            Keyword::Ks => {
                d.ks = st.three(non_negative, GE0)?;
                None
            }
            Keyword::Shine => {
                d.shine = st.one_real(non_negative, GE0)?;
                None
            }
            Keyword::Texture => {
                d.texture = st.one_real(non_negative, GE0)?;
                None
            }
            Keyword::TotalTransformation => {
                let n = st.integer(0, 1_000_000, "must be between 0 and 1000000")?;
                obj.count = Some((n, st.line));
                obj.seen = 0;
                None
            }
            Keyword::Scale => Some(Mat34::scale(st.three(non_zero, "must not be 0")?)),
            Keyword::Translate => Some(Mat34::translate(st.three(any, "")?)),
            Keyword::Rotate => {
                st.expect(2)?;
                let axis = AXES
                    .iter()
                    .position(|&a| a == st.values[0])
                    .ok_or_else(|| st.err(ErrorKind::UnknownAxis(word(st.values[0]))))?;
                Some(Mat34::rotate(axis, st.real(1)?))
            }
            _ => None,
        };
        if let Some(m) = transform {
            if let Some((count, _)) = obj.count {
                if obj.seen >= count {
                    return Err(st.err(ErrorKind::TooManyTransforms { count }));
                }
            }
            obj.seen += 1;
            d.to_world = m.after(&d.to_world);
        }
        Ok(())
    }

    fn finish_object(&mut self) -> Result<(), ParseError> {
        let Some(obj) = self.object.take() else {
            return Ok(());
        };
        if let Some((count, count_line)) = obj.count {
            if obj.seen < count {
                return Err(ParseError {
                    line: count_line,
                    kind: ErrorKind::TransformsMissing { count, seen: obj.seen },
                });
            }
        }
        let out_of_range = ParseError {
            line: obj.line,
            kind: ErrorKind::ObjectOutOfRange,
        };
        if !in_fixed_range(&obj.desc) {
            return Err(out_of_range);
        }
        let object = Object::new(&obj.desc).ok_or(out_of_range.clone())?;
        if self.focus_target == Some(self.scene.objects.len() as u32 + 1) {
            self.focus_desc = Some(obj.desc);
        }
        self.scene.objects.push(object).map_err(|_| out_of_range)?;
        if obj.desc.shape.bound_radius().is_some() {
            let m = &obj.desc.to_world.0;
            let _ = self.placed.push((
                obj.line,
                [m[0][3], m[1][3], m[2][3]],
                [0, 1, 2].map(|i| reach(obj.desc.shape, &m[i])),
            ));
        }
        Ok(())
    }

    fn finish_camera(&mut self) -> Result<(), ParseError> {
        let cam = &mut self.scene.camera;
        if matches!(self.focus, Focus::FocalLength) && cam.focal_length >= cam.image_distance {
            return Err(ParseError {
                line: self.lines.focal_length.max(self.lines.image_distance),
                kind: ErrorKind::FocalLength {
                    focal_length: cam.focal_length,
                    image_distance: cam.image_distance,
                },
            });
        }
        if camera::basis(cam).is_none() {
            return Err(ParseError {
                line: self.lines.look.max(self.lines.up),
                kind: ErrorKind::UpParallelToLook,
            });
        }
        // focus_distance and focus_on keep N and set f (1/f = 1/N + 1/d): f < N always.
        match self.focus {
            Focus::FocalLength => {}
            Focus::Distance(d) => cam.set_focus_distance(d),
            Focus::Object { index, line } => {
                let count = self.scene.objects.len();
                let desc = match self.focus_desc {
                    Some(desc) if index as usize <= count => desc,
                    _ => {
                        return Err(ParseError {
                            line,
                            kind: ErrorKind::NoSuchObject { index, count },
                        })
                    }
                };
                let depth = autofocus::focus_distance(cam, &desc);
                // NaN included: a degenerate view has no depth to focus at.
                if depth.is_nan() || depth <= 0.0 {
                    return Err(ParseError {
                        line,
                        kind: ErrorKind::FocusBehindCamera { index, depth },
                    });
                }
                cam.set_focus_distance(depth);
            }
        }
        // After the focus: the f-number takes the focal length in force at the end.
        if let Stop::FNumber(k, line) = self.stop {
            cam.set_f_number(k);
            if cam.radius >= REAL_LIMIT {
                return Err(ParseError {
                    line,
                    kind: ErrorKind::ApertureTooWide { radius: cam.radius },
                });
            }
        }
        // Rays and light vectors are differences of coordinates: each must fit.
        let points = core::iter::once(("the lens", self.lines.lens_position, cam.lens_position))
            .chain(self.light_at.iter().map(|&(line, at)| ("the light", line, at)));
        for (from, line, at) in points {
            for &(obj_line, centre, reach) in &self.placed {
                if (0..3).any(|i| libm::fabs(at[i] - centre[i]) + reach[i] >= REAL_LIMIT) {
                    return Err(ParseError {
                        line: obj_line,
                        kind: ErrorKind::TooFar { from, line },
                    });
                }
            }
        }
        Ok(())
    }
}

/// How far a bounded shape reaches from its centre along the world axis whose
/// matrix row is `row` (the plane: 0, it is not bounded).
fn reach(shape: Shape, row: &[f64; 4]) -> f64 {
    let [a, b, c, _] = *row;
    match shape {
        Shape::Plane => 0.0,
        Shape::Sphere => libm::sqrt(a * a + b * b + c * c),
        Shape::Cube => libm::fabs(a) + libm::fabs(b) + libm::fabs(c),
        // A unit disc in x, z swept along y from -1 to 1 (the cone within it).
        Shape::Cylinder | Shape::Cone => libm::sqrt(a * a + c * c) + libm::fabs(b),
    }
}

/// Whether an object fits Q16.16: its matrices' entries, the inverse's
/// (a shape squeezed to 1/32768 would need larger ones), and every point of
/// a bounded shape.
fn in_fixed_range(desc: &ObjectDesc) -> bool {
    let m = &desc.to_world.0;
    let fits = |x: f64| x.abs() < REAL_LIMIT;
    let Some(inv) = desc.to_world.inverse() else {
        return false;
    };
    let inside = m.iter().all(|row| fits(libm::fabs(row[3]) + reach(desc.shape, row)));
    inside
        && m.iter().all(|row| row.iter().all(|&x| fits(x)))
        && inv.0.iter().all(|row| row[..3].iter().all(|&x| fits(x)))
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod focus_tests;
