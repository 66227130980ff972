//! A deterministic, seeded mutation fuzzer for the parser and the renderer together.
//!
//! [`check_input`] is the property: any bytes either give a [`ParseError`]
//! (a 1-based line inside the input, one line of text, the same in both number
//! types) or a scene that renders tiny images in Q16.16 and f32, each pixel
//! delivered once inside the target, without a panic. [`Fuzzer`] feeds it inputs
//! made from a corpus (the files of `scenes/`, the malformed corpus and every
//! past crash) by byte, token and line mutations and by writing scenes from the
//! grammar, so that most inputs get past the parser into the renderer.
//!
//! Everything is driven by one 64-bit seed: the same seed gives the same inputs.
//! The tests (`tests/fuzz.rs`) run it for about a minute; a campaign runs it
//! for longer (see README, "Robustness").

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{Dimensions, Point, Size};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use lensray::{render_with, ErrorKind, ParseError, Renderer, Scalar, Scene, I16F16};
use lensray::{Keyword, Section, KEYWORDS};

/// Image size of the tiny renders: 8 × 6 pixels, 2 lens samples each.
pub const TINY: (u32, u32, u32) = (8, 6, 2);

/// What an input came to.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Refused with this error.
    Rejected(ParseError),
    /// Parsed and rendered.
    Rendered,
}

/// A `DrawTarget` that records every pixel and refuses any outside it or
/// delivered twice: it checks that a render paints its image exactly once.
/// It may be placed anywhere in the i32 plane, up to its edges.
pub struct Canvas {
    area: Rectangle,
    /// The pixels, row-major from the top-left corner; `None` where nothing was drawn.
    pub pixels: Vec<Option<Rgb888>>,
    /// What went wrong, if anything (a pixel out of bounds or drawn twice).
    pub fault: Option<String>,
}

impl Canvas {
    /// An empty canvas of `width` × `height` at the origin.
    pub fn new(width: u32, height: u32) -> Self {
        Canvas::at(Point::zero(), width, height)
    }

    /// An empty canvas of `width` × `height` whose top-left corner is `top_left`.
    pub fn at(top_left: Point, width: u32, height: u32) -> Self {
        Canvas {
            area: Rectangle::new(top_left, Size::new(width, height)),
            pixels: vec![None; width as usize * height as usize],
            fault: None,
        }
    }

    /// Records a pixel at absolute (`x`, `y`).
    fn put(&mut self, x: i64, y: i64, c: Rgb888) {
        let (l, t) = (self.area.top_left.x as i64, self.area.top_left.y as i64);
        let (w, h) = (self.area.size.width as i64, self.area.size.height as i64);
        let (dx, dy) = (x - l, y - t);
        if dx < 0 || dy < 0 || dx >= w || dy >= h || x > i32::MAX as i64 || y > i32::MAX as i64 {
            self.fault
                .get_or_insert(format!("pixel ({x}, {y}) outside {w}x{h} at ({l}, {t})"));
            return;
        }
        let slot = &mut self.pixels[(dy * w + dx) as usize];
        if slot.is_some() {
            self.fault.get_or_insert(format!("pixel ({x}, {y}) drawn twice"));
        }
        *slot = Some(c);
    }

    /// Whether pixel (`col`, `row`) from the corner has an i32 address.
    pub fn addressable(&self, col: u32, row: u32) -> bool {
        self.area.top_left.x as i64 + col as i64 <= i32::MAX as i64
            && self.area.top_left.y as i64 + row as i64 <= i32::MAX as i64
    }

    /// Whether exactly the addressable pixels were drawn, each once, of an
    /// image of `cols` × `rows` from the corner.
    pub fn complete(&self, cols: u32, rows: u32) -> bool {
        let w = self.area.size.width;
        self.fault.is_none()
            && self.pixels.iter().enumerate().all(|(i, p)| {
                let (c, r) = (i as u32 % w, i as u32 / w);
                p.is_some() == (c < cols && r < rows && self.addressable(c, r))
            })
    }
}

impl Dimensions for Canvas {
    fn bounding_box(&self) -> Rectangle {
        self.area
    }
}

impl DrawTarget for Canvas {
    type Color = Rgb888;
    type Error = core::convert::Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, pixels: I) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            self.put(p.x as i64, p.y as i64, c);
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Self::Error> {
        // Walks the area in i64 so that no area, however placed, overflows here.
        let (x0, y0) = (area.top_left.x as i64, area.top_left.y as i64);
        let (w, h) = (area.size.width as i64, area.size.height as i64);
        let mut colors = colors.into_iter();
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                let Some(c) = colors.next() else {
                    self.fault
                        .get_or_insert(format!("fill_contiguous ran out of colours at ({x}, {y})"));
                    return Ok(());
                };
                self.put(x, y, c);
            }
        }
        Ok(())
    }
}

/// Number of lines of an input as the parser counts them (split at `\n`).
pub fn line_count(bytes: &[u8]) -> usize {
    bytes.iter().filter(|&&b| b == b'\n').count() + 1
}

/// Renders `scene` at `w` × `h` with `samples` into a [`Canvas`] at the
/// origin and into one at the far corner of the i32 plane; `Err` when a pixel
/// is missing, outside or drawn twice.
fn render_tiny<S: Scalar>(scene: &Scene<S>, w: u32, h: u32, samples: u32) -> Result<(), String> {
    let renderer = Renderer::new(scene, w, h).with_samples(samples);
    let corner = Point::new(i32::MAX - (w as i32 / 2 - 1), i32::MAX - (h as i32 / 2 - 1));
    for top_left in [Point::zero(), corner] {
        let mut canvas = Canvas::at(top_left, w, h);
        let Ok(()) = render_with(&renderer, &mut canvas);
        if !canvas.complete(w, h) {
            return Err(format!(
                "{} render {w}x{h} at {top_left:?}: {}",
                S::NAME,
                canvas.fault.clone().unwrap_or_else(|| "a pixel was missed".into())
            ));
        }
        // The same pixel asked alone gives the same colour: nothing depends
        // on the order of rows or pixels.
        if top_left == Point::zero()
            && canvas.pixels[(h / 2 * w + w / 2) as usize] != Some(renderer.pixel(w / 2, h / 2))
        {
            return Err(format!(
                "{} pixel ({}, {}) differs between render and its row alone",
                S::NAME,
                w / 2,
                h / 2
            ));
        }
    }
    Ok(())
}

/// The far corners of the largest image the camera takes: pixel indices and
/// film sizes at their extremes.
fn render_extremes<S: Scalar>(scene: &Scene<S>) {
    let max = lensray::MAX_IMAGE_SIDE;
    for (w, h) in [(max, max), (max, 1), (1, max), (1, 1)] {
        let renderer = Renderer::new(scene, w, h).with_samples(2);
        for (c, r) in [(0, 0), (w - 1, h - 1), (w / 2, h / 2)] {
            let _ = renderer.pixel(c, r);
        }
    }
}

/// The property every input must have. `Ok` says what the input came to;
/// `Err` describes a broken promise. A panic is a crash.
pub fn check_input(bytes: &[u8]) -> Result<Outcome, String> {
    let fixed = Scene::<I16F16>::parse_bytes(bytes);
    let float = Scene::<f32>::parse_bytes(bytes);
    check_equivalents(bytes, &fixed)?;
    match (fixed, float) {
        (Err(e), Err(e32)) => {
            // Compared as shown: an error may carry a NaN (FocusBehindCamera's depth).
            if format!("{e:?}") != format!("{e32:?}") {
                return Err(format!("Q16.16 and f32 parsers disagree: {e} / {e32}"));
            }
            let lines = line_count(bytes);
            if e.line == 0 || e.line as usize > lines {
                return Err(format!("error names line {} of a {lines}-line input: {e}", e.line));
            }
            let msg = e.to_string();
            if !msg.starts_with(&format!("line {}: ", e.line)) || msg.contains(['\n', '\r']) || msg.len() > 300 {
                return Err(format!("error message is not one short line: {msg:?}"));
            }
            check_first_fault(bytes, &e)?;
            Ok(Outcome::Rejected(e))
        }
        (Ok(a), Ok(b)) => {
            let (w, h, n) = TINY;
            render_tiny(&a, w, h, n)?;
            render_tiny(&b, w, h, n)?;
            render_extremes(&a);
            render_extremes(&b);
            Ok(Outcome::Rendered)
        }
        (Ok(_), Err(e)) => Err(format!("only the f32 parser refuses: {e}")),
        (Err(e), Ok(_)) => Err(format!("only the Q16.16 parser refuses: {e}")),
    }
}

/// Error kinds found only once the object or the file has ended: they may
/// name an earlier line than the one that revealed them.
fn deferred(e: &ParseError) -> bool {
    matches!(
        e.kind,
        ErrorKind::TransformsMissing { .. }
            | ErrorKind::ObjectOutOfRange
            | ErrorKind::FocalLength { .. }
            | ErrorKind::UpParallelToLook
            | ErrorKind::ApertureTooWide { .. }
            | ErrorKind::NoSuchObject { .. }
            | ErrorKind::FocusBehindCamera { .. }
            | ErrorKind::TooFar { .. }
    )
}

/// The error names the first faulty line: the input cut after that line
/// gives the very same error (for errors a line shows by itself).
fn check_first_fault(bytes: &[u8], e: &ParseError) -> Result<(), String> {
    if deferred(e) {
        return Ok(());
    }
    let end = bytes
        .iter()
        .enumerate()
        .filter(|&(_, &b)| b == b'\n')
        .nth(e.line as usize - 1)
        .map_or(bytes.len(), |(i, _)| i);
    let cut = Scene::<I16F16>::parse_bytes(&bytes[..end]);
    if format!("{:?}", cut.as_ref().err()) != format!("{:?}", Some(e)) {
        return Err(format!(
            "error {e} is not the first fault: lines 1..={} alone give {:?}",
            e.line,
            cut.err()
        ));
    }
    Ok(())
}

/// What the format accepts as equivalent parses the same: CRLF line ends,
/// trailing spaces and tabs, a byte order mark in front.
fn check_equivalents(bytes: &[u8], parsed: &Result<Scene<I16F16>, ParseError>) -> Result<(), String> {
    let summary = |r: &Result<Scene<I16F16>, ParseError>| match r {
        Ok(s) => Ok((
            s.camera,
            s.objects().len(),
            s.lights().len(),
            s.ambient,
            s.background,
            s.shadows,
        )),
        // Debug text: an error may carry a NaN, which equals nothing.
        Err(e) => Err(format!("{e:?}")),
    };
    let want = summary(parsed);
    let mut variants: Vec<(&str, Vec<u8>)> = Vec::new();
    if !bytes.contains(&b'\r') {
        let mut crlf = Vec::with_capacity(bytes.len() + 64);
        for &b in bytes {
            if b == b'\n' {
                crlf.push(b'\r');
            }
            crlf.push(b);
        }
        variants.push(("CRLF", crlf));
    }
    let mut spaced = Vec::with_capacity(bytes.len() + 64);
    for &b in bytes {
        if b == b'\n' {
            // Before the line end, CR included.
            let cr = spaced.last() == Some(&b'\r');
            if cr {
                spaced.pop();
            }
            spaced.extend_from_slice(if cr { b" \t \r" } else { b" \t " });
        }
        spaced.push(b);
    }
    variants.push(("trailing spaces", spaced));
    if !bytes.starts_with(b"\xEF\xBB\xBF") {
        variants.push(("a BOM", [b"\xEF\xBB\xBF", bytes].concat()));
    }
    for (what, v) in variants {
        let got = summary(&Scene::<I16F16>::parse_bytes(&v));
        if got != want {
            return Err(format!("with {what} the input parses differently: {got:?} vs {want:?}"));
        }
    }
    Ok(())
}

/// splitmix64: small, fast, and the same on every machine.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// True with probability `num / den`.
    pub fn chance(&mut self, num: u64, den: u64) -> bool {
        self.next_u64() % den < num
    }

    /// One element of a non-empty slice.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Numbers at the edges of what the format and Q16.16 allow, and beyond.
const EDGE_NUMBERS: &[&str] = &[
    "0",
    "-0",
    "+0",
    "1",
    "-1",
    "2",
    "0.5",
    ".5",
    "1.",
    "-.5",
    "0.00001",
    "-0.00001",
    "0.0000152587890625",
    "0.000007",
    "0.0001",
    "0.001",
    "0.999999",
    "1.000001",
    "7.99999",
    "8",
    "8.00001",
    "45",
    "90",
    "-90",
    "180",
    "270",
    "360",
    "720.5",
    "181.02",
    "255",
    "1000",
    "16383.99",
    "16384",
    "23170.475",
    "32767",
    "32767.99998",
    "-32767.99998",
    "32768",
    "-32768",
    "65535",
    "65536",
    "1000000",
    "1000001",
    "4000000000",
    "4294967296",
    "18446744073709551616",
    "99999999999999999999999999999999999999999",
    "1e30",
    "1e-30",
    "1E5",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "infinity",
    "0x10",
    "--1",
    "+-1",
    "1..2",
    ".",
    "-",
    "+",
    "1,5",
    "½",
];

/// Words the format knows besides its keywords, and near misses.
const WORDS: &[&str] = &[
    "sphere",
    "plane",
    "cube",
    "cylinder",
    "cone",
    "gold",
    "copper",
    "silver",
    "brass",
    "bronze",
    "chrome",
    "pewter",
    "emerald",
    "jade",
    "ruby",
    "pearl",
    "obsidian",
    "x",
    "y",
    "z",
    "w",
    "on",
    "off",
    "Sphere",
    "GOLD",
    "X",
    "yes",
    "#",
    "#x",
    "object",
    "Ka",
    "ka",
    "KA",
    "point",
    "",
    "independent",
    "stratified",
    "Stratified",
];

/// Bytes that matter to the parser's splitting and checking.
const EDGE_BYTES: &[u8] = &[
    b'\n', b'\r', b'\t', b' ', b'#', b'.', b'-', b'+', b'0', b'9', 0, 0x7F, 0x80, 0xC3, 0xEF, 0xBB, 0xBF, 0xFF, 0x0B,
    0x0C,
];

/// How many values a statement takes (a shape or axis word counts as one):
/// the library's keyword table's.
fn arity(keyword: &str) -> usize {
    Keyword::from_name(keyword).map_or(3, Keyword::arity)
}

/// A number, mostly well-formed and within range, sometimes not.
fn number(rng: &mut Rng) -> String {
    match rng.below(10) {
        0..=2 => (*rng.pick(EDGE_NUMBERS)).to_string(),
        3..=5 => {
            // Small plausible values: most scenes live here.
            let v = (rng.below(2001) as f64 - 1000.0) / 100.0;
            format!("{v}")
        }
        6..=7 => {
            // Log-uniform magnitudes from 2^-20 to 2^15, either sign.
            let e = rng.below(36) as i32 - 20;
            let m = 1.0 + rng.below(1000) as f64 / 1000.0;
            let v = m * 2f64.powi(e) * if rng.chance(1, 2) { -1.0 } else { 1.0 };
            let digits = rng.below(10);
            format!("{v:.digits$}")
        }
        8 => format!("{}", rng.below(70000)),
        _ => {
            // Any decimal string: sign, digits, point, digits.
            let mut s = String::new();
            if rng.chance(1, 3) {
                s.push(*rng.pick(&['-', '+']));
            }
            for _ in 0..rng.below(8) {
                s.push((b'0' + rng.below(10) as u8) as char);
            }
            if rng.chance(1, 2) {
                s.push('.');
                for _ in 0..rng.below(12) {
                    s.push((b'0' + rng.below(10) as u8) as char);
                }
            }
            s
        }
    }
}

/// In-range values at the edges: what a valid scene may hold.
const EDGE_VALID: &[&str] = &[
    "0",
    "1",
    "-1",
    "0.00002",
    "0.0001",
    "0.001",
    "0.999",
    "1.001",
    "3.99999",
    "4.00001",
    "7.9999",
    "90",
    "180",
    "-270",
    "359.99",
    "1000",
    "16384",
    "23170.47",
    "32767.99",
    "-32767.99",
];

/// A number inside Q16.16's range, from everyday sizes to the extremes.
fn plausible(rng: &mut Rng) -> String {
    match rng.below(10) {
        0..=4 => format!("{}", (rng.below(2001) as f64 - 1000.0) / 100.0),
        5..=7 => {
            let e = rng.below(31) as i32 - 16;
            let v = (1.0 + rng.below(1000) as f64 / 1000.0) * 2f64.powi(e);
            let v = if rng.chance(1, 2) { -v } else { v };
            format!("{v:.6}")
        }
        _ => (*rng.pick(EDGE_VALID)).to_string(),
    }
}

/// Whether a statement's values must be positive (or non-negative).
fn wants_positive(keyword: &str) -> bool {
    matches!(
        keyword,
        "width"
            | "aspect_ratio"
            | "image_distance"
            | "focal_length"
            | "radius"
            | "shine"
            | "texture"
            | "Ka"
            | "Kd"
            | "Ks"
            | "ambient_light"
            | "light_intensity"
            | "focus_distance"
            | "f_number"
    )
}

/// One statement from the grammar, with the right number of values most of the time.
fn statement(rng: &mut Rng) -> String {
    // Object and transformation statements are the ones that reach the renderer's depths.
    let keyword = match rng.below(4) {
        0 => *rng.pick(&["object", "scale", "rotate", "translate", "total_transformation"]),
        _ => *rng.pick(&KEYWORDS),
    };
    let mut n = arity(keyword);
    if rng.chance(1, 12) {
        n = rng.below(6);
    }
    let mut s = keyword.to_string();
    for i in 0..n {
        s.push(if rng.chance(1, 16) { '\t' } else { ' ' });
        let v = match (keyword, i) {
            ("object", 0) => (*rng.pick(&WORDS[..5])).to_string(),
            ("object", _) => (*rng.pick(&WORDS[5..17])).to_string(),
            ("rotate", 0) => (*rng.pick(&WORDS[17..20])).to_string(),
            ("shadows" | "adaptive", _) => (*rng.pick(&WORDS[21..23])).to_string(),
            ("sampler", _) => (*rng.pick(&WORDS[35..38])).to_string(),
            ("point" | "total_transformation", _) if rng.chance(3, 4) => format!("{}", rng.below(6)),
            _ if rng.chance(1, 20) => (*rng.pick(WORDS)).to_string(),
            _ => number(rng),
        };
        s.push_str(&v);
    }
    s
}

/// A whole scene from the grammar: camera lines, lights, then objects with
/// their properties and transformations.
pub fn scene_from_grammar(rng: &mut Rng) -> Vec<u8> {
    let mut lines: Vec<String> = Vec::new();
    // The camera section's keywords, from the library's keyword table.
    let camera: Vec<&str> = Keyword::ALL
        .iter()
        .filter(|k| k.section() == Section::Camera)
        .map(|k| k.name())
        .collect();
    for _ in 0..rng.below(6) {
        let k = *rng.pick(&camera);
        lines.push(statement_for(rng, k));
    }
    for _ in 0..rng.below(4) {
        lines.push(statement_for(rng, "light_position"));
        if rng.chance(2, 3) {
            lines.push(statement_for(rng, "light_intensity"));
        }
    }
    if rng.chance(1, 2) {
        lines.push("radius 0.2".into());
    }
    for _ in 0..1 + rng.below(5) {
        lines.push(statement_for(rng, "object"));
        for _ in 0..rng.below(4) {
            let k = *rng.pick(&["Ka", "Kd", "Ks", "shine", "texture"]);
            lines.push(statement_for(rng, k));
        }
        let n = rng.below(5);
        // Most objects in front of the camera, or nothing renders.
        let in_front = rng.chance(2, 3);
        if rng.chance(1, 2) {
            lines.push(format!("total_transformation {}", n + in_front as usize));
        }
        for _ in 0..n {
            let k = *rng.pick(&["scale", "rotate", "translate"]);
            lines.push(statement_for(rng, k));
        }
        if in_front {
            lines.push(format!("translate 0 0 -{}", 2 + rng.below(30)));
        }
    }
    if rng.chance(1, 20) {
        lines.push(statement(rng));
    }
    let mut text = lines.join("\n");
    text.push('\n');
    text.into_bytes()
}

/// A statement for a given keyword, right arity, values from [`number`].
fn statement_for(rng: &mut Rng, keyword: &str) -> String {
    let mut s = keyword.to_string();
    for i in 0..arity(keyword) {
        s.push(' ');
        let v = match (keyword, i) {
            ("object", 0) => (*rng.pick(&WORDS[..5])).to_string(),
            ("object", _) if rng.chance(1, 2) => continue,
            ("object", _) => (*rng.pick(&WORDS[5..17])).to_string(),
            ("rotate", 0) => (*rng.pick(&WORDS[17..20])).to_string(),
            ("shadows" | "adaptive", _) => (*rng.pick(&WORDS[21..23])).to_string(),
            ("sampler", _) => (*rng.pick(&WORDS[35..37])).to_string(),
            ("point" | "focus_on", _) => format!("{}", 1 + rng.below(4)),
            ("aperture_blades", _) => format!("{}", rng.pick(&[0, 3, 5, 6, 16, 1, 2, 17])),
            ("Ka" | "Kd" | "Ks" | "ambient_light" | "background" | "light_intensity", _) if rng.chance(3, 4) => {
                format!("{}", rng.below(101) as f64 / 100.0)
            }
            _ if rng.chance(1, 10) => number(rng),
            (k, _) if wants_positive(k) => plausible(rng).trim_start_matches('-').to_string(),
            _ => plausible(rng),
        };
        s.push_str(&v);
    }
    s
}

/// Splits into lines, keeping each line's `\n`.
fn split_lines(bytes: &[u8]) -> Vec<Vec<u8>> {
    bytes.split_inclusive(|&b| b == b'\n').map(<[u8]>::to_vec).collect()
}

/// Byte ranges of the space-separated tokens of `bytes`.
fn tokens(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, &b) in bytes.iter().enumerate() {
        let sep = matches!(b, b' ' | b'\t' | b'\n' | b'\r');
        match (start, sep) {
            (None, false) => start = Some(i),
            (Some(s), true) => {
                out.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, bytes.len()));
    }
    out
}

/// One mutation of `input` in place; `other` is another corpus entry to splice from.
fn mutate_once(rng: &mut Rng, input: &mut Vec<u8>, other: &[u8]) {
    let len = input.len();
    match rng.below(14) {
        // Byte level.
        0 if len > 0 => {
            let i = rng.below(len);
            input[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            input[i] = *rng.pick(EDGE_BYTES);
        }
        2 => {
            let i = rng.below(len + 1);
            let b = if rng.chance(1, 2) {
                *rng.pick(EDGE_BYTES)
            } else {
                rng.below(256) as u8
            };
            input.insert(i, b);
        }
        3 if len > 0 => {
            let i = rng.below(len);
            let n = 1 + rng.below((len - i).min(16));
            input.drain(i..i + n);
        }
        // Token level: the parser's words.
        4..=6 => {
            let toks = tokens(input);
            if toks.is_empty() {
                input.extend_from_slice(number(rng).as_bytes());
                return;
            }
            let (s, e) = *rng.pick(&toks);
            let new = match rng.below(4) {
                0 => (*rng.pick(&KEYWORDS)).to_string(),
                1 => (*rng.pick(WORDS)).to_string(),
                _ => number(rng),
            };
            input.splice(s..e, new.into_bytes());
        }
        7 => {
            // Insert or delete one token.
            let toks = tokens(input);
            if !toks.is_empty() && rng.chance(1, 2) {
                let (s, e) = *rng.pick(&toks);
                input.drain(s..e);
            } else {
                let i = toks.get(rng.below(toks.len() + 1)).map_or(input.len(), |t| t.1);
                let mut w = b" ".to_vec();
                w.extend_from_slice(number(rng).as_bytes());
                input.splice(i..i, w);
            }
        }
        // Line level.
        8..=10 => {
            let mut lines = split_lines(input);
            let i = rng.below(lines.len() + 1);
            match rng.below(5) {
                0 if !lines.is_empty() => {
                    let l = lines[rng.below(lines.len())].clone();
                    lines.insert(i, l);
                }
                1 if i < lines.len() => {
                    lines.remove(i);
                }
                2 if lines.len() > 1 => {
                    let j = rng.below(lines.len());
                    let i = i.min(lines.len() - 1);
                    lines.swap(i, j);
                }
                _ => {
                    let mut l = statement(rng).into_bytes();
                    l.push(b'\n');
                    lines.insert(i, l);
                }
            }
            *input = lines.concat();
        }
        11 => {
            // Splice a run of lines from another input.
            let theirs = split_lines(other);
            if theirs.is_empty() {
                return;
            }
            let a = rng.below(theirs.len());
            let b = a + 1 + rng.below((theirs.len() - a).min(8));
            let mut lines = split_lines(input);
            let i = rng.below(lines.len() + 1);
            for (k, l) in theirs[a..b].iter().enumerate() {
                lines.insert(i + k, l.clone());
            }
            *input = lines.concat();
        }
        12 => {
            // Line endings and spacing the format accepts.
            let mut out = Vec::with_capacity(input.len() + 8);
            let kind = rng.below(4);
            for &b in input.iter() {
                match (kind, b) {
                    (0, b'\n') => out.extend_from_slice(b"\r\n"),
                    (1, b' ') => out.push(b'\t'),
                    (2, b'\n') => out.extend_from_slice(b"  \t\n"),
                    _ => out.push(b),
                }
            }
            if kind == 3 {
                out.splice(0..0, *b"\xEF\xBB\xBF");
            }
            *input = out;
        }
        _ => {
            // Repeat a chunk: long lines, many objects, many lights.
            if len == 0 {
                return;
            }
            let i = rng.below(len);
            let n = 1 + rng.below((len - i).min(64));
            let chunk = input[i..i + n].to_vec();
            let times = 1 + rng.below(40);
            for _ in 0..times {
                input.splice(i..i, chunk.iter().copied());
            }
        }
    }
}

/// Inputs above this size are cut: the parser is linear, and long inputs slow the run.
const MAX_INPUT: usize = 64 * 1024;

/// Counts of one run.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Inputs checked.
    pub inputs: u64,
    /// Inputs that parsed and rendered.
    pub rendered: u64,
    /// Rejections by error kind (the variant's name).
    pub kinds: BTreeMap<String, u64>,
    /// Inputs that broke the property or panicked.
    pub failed: u64,
    /// The first 100 of them, with what happened.
    pub failures: Vec<(Vec<u8>, String)>,
}

/// The variant name of an error kind (`"UnknownKeyword"`).
pub fn kind_name(e: &ParseError) -> String {
    let s = format!("{:?}", e.kind);
    s.split(|c: char| !c.is_alphanumeric())
        .next()
        .unwrap_or_default()
        .to_string()
}

/// The fuzzer: a corpus, a generator and a record of what it found.
pub struct Fuzzer {
    rng: Rng,
    corpus: Vec<Vec<u8>>,
    /// Inputs that rendered, kept to mutate further (the renderer is where the depth is).
    rendered: Vec<Vec<u8>>,
    /// Counts so far.
    pub stats: Stats,
}

impl Fuzzer {
    /// A fuzzer over `corpus` (at least the empty input is added).
    pub fn new(seed: u64, mut corpus: Vec<Vec<u8>>) -> Self {
        corpus.push(Vec::new());
        Fuzzer {
            rng: Rng::new(seed),
            corpus,
            rendered: Vec::new(),
            stats: Stats::default(),
        }
    }

    /// The next input.
    pub fn next_input(&mut self) -> Vec<u8> {
        let rng = &mut self.rng;
        let choice = rng.below(10);
        let mut input = match choice {
            0..=3 => scene_from_grammar(rng),
            4..=6 if !self.rendered.is_empty() => rng.pick(&self.rendered).clone(),
            _ => rng.pick(&self.corpus).clone(),
        };
        let other = rng.pick(&self.corpus).clone();
        let n = match rng.below(4) {
            // Half the written scenes go in as they are, to reach the renderer.
            0 | 1 if choice <= 3 => 0,
            0 => 0,
            1 | 2 => 1 + rng.below(3),
            _ => 1 + rng.below(12),
        };
        for _ in 0..n {
            mutate_once(rng, &mut input, &other);
        }
        input.truncate(MAX_INPUT);
        input
    }

    /// Checks one input, catching a panic; records the outcome.
    pub fn run_one(&mut self, input: Vec<u8>) {
        self.stats.inputs += 1;
        let result = std::panic::catch_unwind(|| check_input(&input));
        match result {
            Ok(Ok(Outcome::Rendered)) => {
                self.stats.rendered += 1;
                if self.rendered.len() < 4096 {
                    self.rendered.push(input);
                } else {
                    let i = self.rng.below(self.rendered.len());
                    self.rendered[i] = input;
                }
            }
            Ok(Ok(Outcome::Rejected(e))) => *self.stats.kinds.entry(kind_name(&e)).or_default() += 1,
            Ok(Err(msg)) => self.fail(input, msg),
            Err(panic) => {
                let msg = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "panic".into());
                self.fail(input, format!("panic: {msg}"));
            }
        }
    }

    fn fail(&mut self, input: Vec<u8>, msg: String) {
        self.stats.failed += 1;
        if self.stats.failures.len() < 100 {
            self.stats.failures.push((input, msg));
        }
    }
}

/// The seed corpus: every file in `scenes/`, the malformed corpus and the
/// crash regressions (`host-tests/corpus/malformed/`, `host-tests/corpus/regressions/`),
/// each cut to 64 KiB.
pub fn seed_corpus(workspace: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for dir in ["scenes", "host-tests/corpus/malformed", "host-tests/corpus/regressions"] {
        let Ok(entries) = std::fs::read_dir(workspace.join(dir)) else {
            continue;
        };
        let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        paths.sort();
        for p in paths {
            if p.is_file() {
                if let Ok(mut bytes) = std::fs::read(&p) {
                    bytes.truncate(MAX_INPUT);
                    out.push((p, bytes));
                }
            }
        }
    }
    out
}

/// Shows an input as an escaped string, cut after `max` bytes.
pub fn escape(bytes: &[u8], max: usize) -> String {
    let mut s: String = bytes[..bytes.len().min(max)].escape_ascii().to_string();
    if bytes.len() > max {
        s.push_str(&format!("... ({} bytes)", bytes.len()));
    }
    s
}
