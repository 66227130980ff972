//! The malformed-scene corpus (`host-tests/corpus/malformed/`): one fault per
//! file, and what each must come to, written out here: the exact error (kind,
//! its details and line) or acceptance. Both number types must agree.

use std::path::{Path, PathBuf};

use lensray::{ErrorKind, ErrorKind::*, ParseError, Scene, I16F16, MAX_LIGHTS, MAX_OBJECTS};

const Q16: &str = "must be below 32768 in magnitude (the range of Q16.16)";
const GT0: &str = "must be greater than 0";
const GE0: &str = "must not be negative";
const POINT: &str = "must be between 1 and 65535";

/// What a file must come to.
enum Expect {
    /// Refused on this line with this error.
    Error(u32, ErrorKind),
    /// Accepted, parsing to the same scene as this text.
    SameAs(&'static [u8]),
}
use Expect::*;

/// The error's copy of a word (the parser's `Word`, a `heapless::String<32>`):
/// at most 29 bytes, then "...".
fn w(s: &str) -> heapless::String<32> {
    heapless::String::try_from(s).expect("short word")
}

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus/malformed")
}

const PROGRAM1: &[u8] = include_bytes!("../../scenes/paper-program1.scene");

fn expectations() -> Vec<(&'static str, Expect)> {
    let wrong = |keyword, expected, found| WrongCount {
        keyword,
        expected,
        found,
    };
    let range = |keyword, value: &str, rule| OutOfRange {
        keyword,
        value: w(value),
        rule,
    };
    let nan = |keyword, value: &str| NotANumber {
        keyword,
        value: w(value),
    };
    vec![
        ("unknown-keyword.scene", Error(2, UnknownKeyword(w("ligth_position")))),
        ("keyword-wrong-case.scene", Error(1, UnknownKeyword(w("Width")))),
        ("missing-value.scene", Error(1, wrong("lens_position", "3", 2))),
        ("extra-value.scene", Error(1, wrong("width", "1", 2))),
        ("object-without-shape.scene", Error(1, wrong("object", "1 or 2", 0))),
        ("rotate-without-angle.scene", Error(2, wrong("rotate", "2", 1))),
        ("not-a-number.scene", Error(1, nan("radius", "abc"))),
        ("nan.scene", Error(1, nan("width", "nan"))),
        ("inf.scene", Error(1, nan("light_position", "inf"))),
        ("exponent-1e30.scene", Error(1, nan("focal_length", "1e30"))),
        ("beyond-q16-range.scene", Error(2, range("translate", "32768", Q16))),
        (
            "huge-decimal.scene",
            Error(1, range("width", &format!("1{}...", "0".repeat(28)), Q16)),
        ),
        (
            "huge-integer.scene",
            Error(1, range("point", "99999999999999999999999", POINT)),
        ),
        ("point-0.scene", Error(1, range("point", "0", POINT))),
        ("point-4000000000.scene", Error(1, range("point", "4000000000", POINT))),
        (
            "point-fraction.scene",
            Error(
                1,
                NotAnInteger {
                    keyword: "point",
                    value: w("2.5"),
                },
            ),
        ),
        ("point-negative.scene", Error(1, range("point", "-3", POINT))),
        (
            "transformation-count-negative.scene",
            Error(2, range("total_transformation", "-1", "must be between 0 and 1000000")),
        ),
        (
            "focal-length-equals-image-distance.scene",
            Error(
                2,
                FocalLength {
                    focal_length: 8.0,
                    image_distance: 8.0,
                },
            ),
        ),
        (
            "focal-length-beyond-image-distance.scene",
            Error(
                2,
                FocalLength {
                    focal_length: 9.0,
                    image_distance: 8.0,
                },
            ),
        ),
        ("zero-width.scene", Error(1, range("width", "0", GT0))),
        ("zero-look.scene", Error(1, ZeroVector { keyword: "look" })),
        ("zero-up.scene", Error(1, ZeroVector { keyword: "up" })),
        ("up-parallel-to-look.scene", Error(2, UpParallelToLook)),
        ("negative-radius.scene", Error(1, range("radius", "-0.5", GE0))),
        ("negative-ka.scene", Error(2, range("Ka", "-1", GE0))),
        (
            "background-above-one.scene",
            Error(1, range("background", "2", "must be between 0 and 1")),
        ),
        ("shadows-maybe.scene", Error(1, NotASwitch("shadows", w("maybe")))),
        ("zero-scale.scene", Error(2, range("scale", "0", "must not be 0"))),
        // The object's line: its transformations as a whole are at fault.
        ("squeezed-flat.scene", Error(1, ObjectOutOfRange)),
        ("translated-beyond-range.scene", Error(1, ObjectOutOfRange)),
        (
            "transformation-count-short.scene",
            Error(
                4,
                TransformExpected {
                    count: 2,
                    seen: 1,
                    count_line: 2,
                },
            ),
        ),
        (
            "transformation-count-short-at-end.scene",
            Error(2, TransformsMissing { count: 2, seen: 1 }),
        ),
        (
            "transformation-count-long.scene",
            Error(4, TooManyTransforms { count: 1 }),
        ),
        ("property-before-object.scene", Error(1, NoObject { keyword: "Ka" })),
        (
            "transformation-before-object.scene",
            Error(1, NoObject { keyword: "translate" }),
        ),
        ("intensity-before-light.scene", Error(1, NoLight)),
        ("unknown-material.scene", Error(1, UnknownMaterial(w("unobtainium")))),
        ("unknown-shape.scene", Error(1, UnknownShape(w("torus")))),
        ("unknown-axis.scene", Error(2, UnknownAxis(w("w")))),
        // 17 objects of two lines each: the 17th `object` is line 33.
        (
            "too-many-objects.scene",
            Error(2 * MAX_OBJECTS as u32 + 1, TooManyObjects { limit: MAX_OBJECTS }),
        ),
        (
            "too-many-lights.scene",
            Error(MAX_LIGHTS as u32 + 1, TooManyLights { limit: MAX_LIGHTS }),
        ),
        ("binary-garbage.scene", Error(1, NotText { byte: 0x7F })),
        (
            "one-megabyte-line.scene",
            Error(1, range("width", &format!("1{}...", "0".repeat(28)), Q16)),
        ),
        ("bom-in-the-middle.scene", Error(2, NotText { byte: 0xEF })),
        ("carriage-return-mid-line.scene", Error(1, NotText { byte: b'\r' })),
        ("invalid-utf8-comment.scene", Error(1, NotText { byte: 0xE9 })),
        ("non-ascii-value.scene", Error(1, NotText { byte: 0xC2 })),
        // Accepted: a byte order mark, CRLF, tabs and trailing spaces change nothing.
        ("bom.scene", SameAs(PROGRAM1)),
        ("crlf.scene", SameAs(PROGRAM1)),
        ("tabs.scene", SameAs(PROGRAM1)),
        ("trailing-spaces.scene", SameAs(PROGRAM1)),
        ("empty.scene", SameAs(b"")),
        ("comments-only.scene", SameAs(b"")),
    ]
}

/// Parses in both number types, which must agree; the Q16.16 result.
fn parse(bytes: &[u8]) -> Result<Scene<I16F16>, ParseError> {
    let fixed = Scene::<I16F16>::parse_bytes(bytes);
    let float = Scene::<f32>::parse_bytes(bytes);
    assert_eq!(fixed.as_ref().err(), float.as_ref().err(), "Q16.16 and f32 disagree");
    fixed
}

#[test]
fn every_malformed_scene_gets_its_error_or_is_accepted() {
    let table = expectations();
    for (name, expect) in &table {
        let bytes = std::fs::read(corpus_dir().join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let got = parse(&bytes);
        match expect {
            Error(line, kind) => {
                let want = ParseError {
                    line: *line,
                    kind: kind.clone(),
                };
                assert_eq!(got.as_ref().err(), Some(&want), "{name}");
            }
            SameAs(text) => {
                let scene = got.unwrap_or_else(|e| panic!("{name}: refused: {e}"));
                let clean = Scene::<I16F16>::parse_bytes(text).expect("reference parses");
                // Debug shows every field, private ones included: the scenes are the same.
                assert_eq!(format!("{scene:?}"), format!("{clean:?}"), "{name}");
            }
        }
    }
}

/// The table and the directory hold the same files: none untested, none missing.
#[test]
fn the_corpus_is_all_in_the_table() {
    let table = expectations();
    let mut in_table: Vec<&str> = table.iter().map(|(n, _)| *n).collect();
    in_table.sort();
    let mut on_disk: Vec<String> = std::fs::read_dir(corpus_dir())
        .expect("corpus directory")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    assert_eq!(in_table, on_disk);
    let faults = table.iter().filter(|(_, e)| matches!(e, Error(..))).count();
    assert!(faults >= 30, "only {faults} malformed scenes");
}

/// Every error message names its line and fits on one line.
#[test]
fn error_messages_are_one_line_naming_the_line() {
    for (name, expect) in expectations() {
        if let Error(line, kind) = expect {
            let msg = ParseError { line, kind }.to_string();
            assert!(msg.starts_with(&format!("line {line}: ")), "{name}: {msg}");
            assert!(!msg.contains('\n') && msg.len() < 200, "{name}: {msg}");
        }
    }
}
