//! The parser: every keyword, the defaults, and every error kind with its line.

use super::*;
use crate::scene::CameraParams;
use fixed::types::I16F16;

type Sc = Scene<f32>;

fn parse(text: &str) -> Result<Sc, ParseError> {
    Sc::parse(text)
}

fn err(text: &str) -> ParseError {
    match parse(text) {
        Ok(_) => panic!("accepted: {text:?}"),
        Err(e) => e,
    }
}

fn v3(v: Vec3<f32>) -> [f32; 3] {
    [v.x, v.y, v.z]
}

const PROGRAM1: &str = include_str!("../../scenes/paper-program1.scene");

#[test]
fn program1_parses_as_the_paper_wrote_it() {
    let s = parse(PROGRAM1).unwrap();
    let c = &s.camera;
    assert_eq!(
        (c.width, c.aspect_ratio, c.image_distance, c.focal_length),
        (10.0, 1.33, 8.0, 4.0)
    );
    assert_eq!(
        (c.lens_position, c.look, c.up),
        ([0.0; 3], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0])
    );
    assert_eq!((c.samples, c.radius), (70, 0.2));
    assert_eq!(v3(s.ambient), [1.0; 3]);
    assert_eq!(s.lights.len(), 3);
    assert_eq!(v3(s.lights[2].position), [0.0, -6.0, 0.0]);
    assert_eq!(v3(s.lights[2].intensity), [0.5, 0.0, 0.3]);
    let shapes: std::vec::Vec<Shape> = s.objects.iter().map(|o| o.shape).collect();
    assert_eq!(shapes, [Shape::Plane, Shape::Cube, Shape::Sphere, Shape::Cone]);
    // The gold sphere keeps the table's values; the plane its own.
    assert_eq!(v3(s.objects[2].material.kd), [0.75164, 0.60648, 0.22648]);
    assert_eq!(s.objects[2].material.shine, 51.2);
    assert_eq!(v3(s.objects[0].material.ks), [0.0, 0.5, 0.0]);
    assert_eq!(s.objects[0].texture, 0.5);
    // The sphere was moved to (0, -1, -8): its bound is centred there.
    let (c, r) = s.objects[2].bound().unwrap();
    assert_eq!(v3(c), [0.0, -1.0, -8.0]);
    assert!((r - 1.0).abs() < 1e-3);
    // Q16.16 parses it too.
    assert_eq!(Scene::<I16F16>::parse(PROGRAM1).unwrap().objects.len(), 4);
}

#[test]
fn empty_file_is_the_default_scene() {
    for text in ["", "\n\n", "# only a comment\n", "\u{feff}", "   \t  \r\n"] {
        let s = parse(text).unwrap();
        assert_eq!(s.camera, CameraParams::default());
        assert!(s.objects.is_empty() && s.lights.is_empty() && !s.shadows);
        assert_eq!(v3(s.ambient), [0.0; 3]);
        assert_eq!(v3(s.background), [0.0; 3]);
    }
}

#[test]
fn every_camera_and_light_keyword() {
    let s = parse(
        "width 12\naspect_ratio 2\nimage_distance 9\nlens_position 1 2 3\nfocal_length 3\nlook 1 0 0\nup 0 0 1\n\
         point 5\nradius 0.5\nambient_light 0.1 0.2 0.3\nlight_position 4 5 6\nlight_intensity 0.7 0.8 0.9\n\
         background 0 0.5 1\nshadows on\n",
    )
    .unwrap();
    let c = &s.camera;
    assert_eq!(
        (c.width, c.aspect_ratio, c.image_distance, c.focal_length),
        (12.0, 2.0, 9.0, 3.0)
    );
    assert_eq!(
        (c.lens_position, c.look, c.up),
        ([1.0, 2.0, 3.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    );
    assert_eq!((c.samples, c.radius), (5, 0.5));
    assert_eq!(v3(s.ambient), [0.1, 0.2, 0.3]);
    assert_eq!(v3(s.lights[0].position), [4.0, 5.0, 6.0]);
    assert_eq!(v3(s.lights[0].intensity), [0.7, 0.8, 0.9]);
    assert_eq!(v3(s.background), [0.0, 0.5, 1.0]);
    assert!(s.shadows);
    assert!(!parse("shadows on\nshadows off\n").unwrap().shadows);
    // A light without light_intensity shines 1 1 1.
    assert_eq!(
        v3(parse("light_position 0 0 0\n").unwrap().lights[0].intensity),
        [1.0; 3]
    );
}

#[test]
fn every_object_keyword_and_material_overrides() {
    let s = parse(
        "object cylinder copper\nKa 0.1 0.2 0.3\nKd 0.4 0.5 0.6\nKs 0.7 0.8 0.9\nshine 3.5\ntexture 0.25\n\
         total_transformation 3\nscale 1 2 3\nrotate z 90\ntranslate 1 0 0\n",
    )
    .unwrap();
    let o = &s.objects[0];
    assert_eq!(o.shape, Shape::Cylinder);
    assert_eq!(v3(o.material.ka), [0.1, 0.2, 0.3]);
    assert_eq!(v3(o.material.kd), [0.4, 0.5, 0.6]);
    assert_eq!(v3(o.material.ks), [0.7, 0.8, 0.9]);
    assert_eq!((o.material.shine, o.texture), (3.5, 0.25));
    // A material name alone gives the table's values; no name, the defaults.
    let s = parse("object cone copper\nobject cube\nobject sphere chrome\nshine 2\n").unwrap();
    assert_eq!(v3(s.objects[0].material.ka), [0.19125, 0.0735, 0.0225]);
    assert_eq!(s.objects[0].material.shine, 12.8);
    assert_eq!(v3(s.objects[1].material.ka), [0.2; 3]);
    assert_eq!(v3(s.objects[1].material.kd), [0.8; 3]);
    assert_eq!(
        (v3(s.objects[1].material.ks), s.objects[1].material.shine),
        ([0.0; 3], 1.0)
    );
    assert_eq!(v3(s.objects[2].material.kd), [0.4; 3]);
    assert_eq!(s.objects[2].material.shine, 2.0);
    for (name, ..) in MATERIALS {
        assert!(parse(&format!("object sphere {name}\n")).is_ok(), "{name}");
    }
    for (name, shape) in Shape::ALL {
        assert_eq!(parse(&format!("object {name}\n")).unwrap().objects[0].shape, shape);
    }
}

#[test]
fn transformations_apply_in_the_order_written() {
    // Scale first, then translate: centre at the translation, radius 2.
    let a = parse("object sphere\nscale 2 2 2\ntranslate 1 0 0\n").unwrap();
    let (c, r) = a.objects[0].bound().unwrap();
    assert_eq!(v3(c), [1.0, 0.0, 0.0]);
    assert!((r - 2.0).abs() < 1e-3);
    // Translate first, then scale: the translation is scaled too.
    let b = parse("object sphere\ntranslate 1 0 0\nscale 2 2 2\n").unwrap();
    assert_eq!(v3(b.objects[0].bound().unwrap().0), [2.0, 0.0, 0.0]);
    // Rotate after translate swings the centre around the axis.
    let c = parse("object sphere\ntranslate 1 0 0\nrotate z 90\n").unwrap();
    let centre = v3(c.objects[0].bound().unwrap().0);
    assert!(centre[0].abs() < 1e-6 && (centre[1] - 1.0).abs() < 1e-6);
    // Transformations without a count are fine, as is a count of 0 with none;
    // a count, once given, must match the object's transformation lines.
    assert!(parse("object cube\nKd 1 1 1\nscale 1 1 1\nKs 1 1 1\nrotate x 3\n").is_ok());
    assert!(parse("object cube\ntotal_transformation 0\nKd 1 1 1\n").is_ok());
    assert_eq!(
        err("object cube\ntotal_transformation 0\nKd 1 1 1\nscale 1 1 1\n"),
        ParseError {
            line: 4,
            kind: ErrorKind::TooManyTransforms { count: 0 }
        }
    );
}

#[test]
fn last_camera_statement_stands() {
    let s = parse("radius 0.1\nwidth 3\nradius 0.3\npoint 4\npoint 6\nfocal_length 2\nfocal_length 5\n").unwrap();
    assert_eq!(
        (s.camera.radius, s.camera.width, s.camera.samples, s.camera.focal_length),
        (0.3, 3.0, 6, 5.0)
    );
    // An out-of-order pair is judged on the final values only.
    assert!(parse("focal_length 9\nimage_distance 10\n").is_ok());
}

#[test]
fn comments_line_ends_tabs_bom_and_numbers() {
    let s =
        parse("\u{feff}width 7 # the film, in metres? ünïcödé ✓\r\nradius\t0.25  \t\r\n\r\n# x\npoint +3\n").unwrap();
    assert_eq!((s.camera.width, s.camera.radius, s.camera.samples), (7.0, 0.25, 3));
    for (text, want) in [
        ("-80", -80.0),
        ("0.5", 0.5),
        (".5", 0.5),
        ("1.", 1.0),
        ("+2", 2.0),
        ("-0", 0.0),
    ] {
        assert_eq!(parse_decimal(text), Some(want), "{text}");
    }
    for text in [
        "1e3", "nan", "inf", "-inf", "0x10", ",5", ".", "-", "1.2.3", "", "١", "5f",
    ] {
        assert_eq!(parse_decimal(text), None, "{text}");
    }
}

/// `(input, line, kind)` for every error kind.
#[test]
fn every_error_kind_names_its_line() {
    let cases = [error_cases_1(), error_cases_2(), error_cases_3(), error_cases_4()].concat();
    for (text, line, kind) in cases {
        let got = match Sc::parse_bytes(text) {
            Ok(_) => panic!("accepted {:?}", std::string::String::from_utf8_lossy(text)),
            Err(e) => e,
        };
        assert_eq!(
            got,
            ParseError { line, kind },
            "{:?}",
            std::string::String::from_utf8_lossy(text)
        );
    }
}

/// Bad scenes, their line and their error (part 1 of 4).
fn error_cases_1() -> std::vec::Vec<(&'static [u8], u32, ErrorKind)> {
    use ErrorKind::*;
    let w = word;
    vec![
        (
            b"width 10\nligth_position 1 2 3\n",
            2,
            UnknownKeyword(w("ligth_position")),
        ),
        (b"ka 1 1 1\n", 1, UnknownKeyword(w("ka"))),
        (
            b"\nlight_position 1 2\n",
            2,
            WrongCount {
                keyword: "light_position",
                expected: "3",
                found: 2,
            },
        ),
        (
            b"width 1 2\n",
            1,
            WrongCount {
                keyword: "width",
                expected: "1",
                found: 2,
            },
        ),
        (
            b"object\n",
            1,
            WrongCount {
                keyword: "object",
                expected: "1 or 2",
                found: 0,
            },
        ),
        (
            b"object sphere gold shiny\n",
            1,
            WrongCount {
                keyword: "object",
                expected: "1 or 2",
                found: 3,
            },
        ),
        (
            b"radius abc\n",
            1,
            NotANumber {
                keyword: "radius",
                value: w("abc"),
            },
        ),
        (
            b"width nan\n",
            1,
            NotANumber {
                keyword: "width",
                value: w("nan"),
            },
        ),
    ]
}

/// Bad scenes, their line and their error (part 2 of 4).
fn error_cases_2() -> std::vec::Vec<(&'static [u8], u32, ErrorKind)> {
    use ErrorKind::*;
    let w = word;
    vec![
        (
            b"width 1e3\n",
            1,
            NotANumber {
                keyword: "width",
                value: w("1e3"),
            },
        ),
        (
            b"point 2.5\n",
            1,
            NotAnInteger {
                keyword: "point",
                value: w("2.5"),
            },
        ),
        (
            b"point 0\n",
            1,
            OutOfRange {
                keyword: "point",
                value: w("0"),
                rule: "must be between 1 and 65535",
            },
        ),
        (
            b"point -3\n",
            1,
            OutOfRange {
                keyword: "point",
                value: w("-3"),
                rule: "must be between 1 and 65535",
            },
        ),
        (
            b"point 4000000000\n",
            1,
            OutOfRange {
                keyword: "point",
                value: w("4000000000"),
                rule: "must be between 1 and 65535",
            },
        ),
        (
            b"radius -1\n",
            1,
            OutOfRange {
                keyword: "radius",
                value: w("-1"),
                rule: GE0,
            },
        ),
    ]
}

/// Bad scenes, their line and their error (part 3 of 4).
fn error_cases_3() -> std::vec::Vec<(&'static [u8], u32, ErrorKind)> {
    use ErrorKind::*;
    let w = word;
    vec![
        (
            b"width 0\n",
            1,
            OutOfRange {
                keyword: "width",
                value: w("0"),
                rule: GT0,
            },
        ),
        (
            b"lens_position 40000 0 0\n",
            1,
            OutOfRange {
                keyword: "lens_position",
                value: w("40000"),
                rule: "must be below 32768 in magnitude (the range of Q16.16)",
            },
        ),
        (
            b"background 0 2 0\n",
            1,
            OutOfRange {
                keyword: "background",
                value: w("2"),
                rule: "must be between 0 and 1",
            },
        ),
        (
            b"object cube\nscale 1 0 1\n",
            2,
            OutOfRange {
                keyword: "scale",
                value: w("0"),
                rule: "must not be 0",
            },
        ),
        (b"look 0 0 0\n", 1, ZeroVector { keyword: "look" }),
        (b"up 0 0 0\n", 1, ZeroVector { keyword: "up" }),
        (b"look 0 1 0\n# c\n", 1, UpParallelToLook),
        (b"look 0 0 -1\nup 0 0 5\n", 2, UpParallelToLook),
        (
            b"image_distance 8\n\nfocal_length 9\n",
            3,
            FocalLength {
                focal_length: 9.0,
                image_distance: 8.0,
            },
        ),
        (
            b"focal_length 8\n",
            1,
            FocalLength {
                focal_length: 8.0,
                image_distance: 8.0,
            },
        ),
        (b"object torus\n", 1, UnknownShape(w("torus"))),
        (b"object sphere unobtainium\n", 1, UnknownMaterial(w("unobtainium"))),
        (b"object cube\nrotate w 45\n", 2, UnknownAxis(w("w"))),
        (b"shadows yes\n", 1, NotASwitch("shadows", w("yes"))),
    ]
}

/// Bad scenes, their line and their error (part 4 of 4).
fn error_cases_4() -> std::vec::Vec<(&'static [u8], u32, ErrorKind)> {
    use ErrorKind::*;
    let w = word;
    vec![
        (b"point 70\nadaptive 1\n", 2, NotASwitch("adaptive", w("1"))),
        (b"point 70\nsampler halton\n", 2, UnknownSampler(w("halton"))),
        (b"Kd 1 1 1\n", 1, NoObject { keyword: "Kd" }),
        (b"scale 1 1 1\n", 1, NoObject { keyword: "scale" }),
        (b"light_intensity 1 1 1\n", 1, NoLight),
        (
            b"object cube\ntotal_transformation 2\nscale 1 1 1\nKd 1 1 1\n",
            4,
            TransformExpected {
                count: 2,
                seen: 1,
                count_line: 2,
            },
        ),
        (
            b"object cube\ntotal_transformation 2\nscale 1 1 1\n",
            2,
            TransformsMissing { count: 2, seen: 1 },
        ),
        (
            b"object cube\ntotal_transformation 2\nscale 1 1 1\nobject sphere\n",
            4,
            TransformExpected {
                count: 2,
                seen: 1,
                count_line: 2,
            },
        ),
        (
            b"object cube\ntotal_transformation 1\nscale 1 1 1\ntranslate 0 0 1\n",
            4,
            TooManyTransforms { count: 1 },
        ),
        (b"object cube\nscale 0.00001 1 1\n", 1, ObjectOutOfRange),
        (
            b"object cube\ntranslate 30000 0 0\ntranslate 30000 0 0\n",
            1,
            ObjectOutOfRange,
        ),
        (b"width 10\nwidth 1\xC3\x28\n", 2, NotText { byte: 0xC3 }),
        (b"width 10 # bad \xFF utf-8\n", 1, NotText { byte: 0xFF }),
        (b"width\x0b10\n", 1, NotText { byte: 0x0B }),
        (b"width 1\rwidth 2\n", 1, NotText { byte: b'\r' }),
    ]
}

#[test]
fn capacity_errors_name_the_limit() {
    let mut text = std::string::String::new();
    for _ in 0..MAX_OBJECTS {
        text.push_str("object sphere\n");
    }
    assert_eq!(parse(&text).unwrap().objects.len(), MAX_OBJECTS);
    text.push_str("object cube\n");
    let e = err(&text);
    assert_eq!(
        e,
        ParseError {
            line: MAX_OBJECTS as u32 + 1,
            kind: ErrorKind::TooManyObjects { limit: MAX_OBJECTS }
        }
    );
    assert_eq!(
        e.to_string(),
        format!("line 17: too many objects: the renderer holds at most {MAX_OBJECTS}")
    );
    let lights = "light_position 0 0 0\n".repeat(MAX_LIGHTS + 1);
    assert_eq!(err(&lights).kind, ErrorKind::TooManyLights { limit: MAX_LIGHTS });
    assert_eq!(err(&lights).line, MAX_LIGHTS as u32 + 1);
}

#[test]
fn messages_read_as_the_spec_shows() {
    assert_eq!(
        err("width 10\nligth_position 1 2 3\n").to_string(),
        "line 2: unknown keyword \"ligth_position\""
    );
    assert_eq!(
        err("\n\nfocal_length 9\n").to_string(),
        "line 3: focal_length 9 must be smaller than image_distance 8"
    );
    // Long words are cut short in the message, not the error.
    let long = "x".repeat(5000);
    let e = err(&format!("{long} 1\n"));
    assert!(e.to_string().len() < 80, "{e}");
}

#[test]
fn never_panics_on_odd_bytes() {
    // A cheap sweep here; the fuzz harness goes much further.
    let mut seed = 0x1234_5678u32;
    let alphabet = b"width point radius object sphere cube 0123456789.-+ \t\n#\r\xC3\xA9\x00xyz";
    for _ in 0..2000 {
        let mut buf = std::vec::Vec::new();
        for _ in 0..(seed % 200) {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            buf.push(alphabet[(seed as usize) % alphabet.len()]);
        }
        let _ = Sc::parse_bytes(&buf);
        let _ = Scene::<I16F16>::parse_bytes(&buf);
    }
}

#[test]
fn parse_into_resets_and_matches_parse() {
    use crate::Scene;
    use fixed::types::I16F16;
    let text = b"point 4\nlight_position 1 2 3\nobject sphere gold\ntranslate 0 0 -5\n";
    let mut s = Scene::<I16F16>::parse("object cube\nobject cube\nshadows on\n").unwrap();
    s.parse_into(text).unwrap();
    let p = Scene::<I16F16>::parse_bytes(text).unwrap();
    assert_eq!((s.objects.len(), s.lights.len(), s.shadows), (1, 1, false));
    assert_eq!(s.camera, p.camera);
    assert_eq!(s.lights, p.lights);
    assert_eq!(s.objects[0].material, p.objects[0].material);
    let err = s.parse_into(b"width 10\nwidth -1\n").unwrap_err();
    assert_eq!(err.line, 2);
}
