//! The photographer's camera statements: focus_distance, f_number, focus_on,
//! aperture_blades, aperture_rotation, and "the last one stands".

use crate::parse::ErrorKind;
use crate::scene::CameraParams;
use crate::{Scene, I16F16};

fn cam(text: &str) -> CameraParams {
    let a = Scene::<I16F16>::parse(text)
        .unwrap_or_else(|e| panic!("{text:?}: {e}"))
        .camera;
    // Set-up is exact f64 and independent of the number type.
    assert_eq!(a, Scene::<f32>::parse(text).unwrap().camera);
    a
}

fn err(text: &str) -> (u32, ErrorKind, String) {
    let e = Scene::<I16F16>::parse(text).unwrap_err();
    (e.line, e.kind.clone(), e.to_string())
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12 * b.abs().max(1.0)
}

#[test]
fn focus_distance_keeps_the_image_distance() {
    let c = cam("focus_distance 12\n");
    assert!(close(c.focal_length, 8.0 * 12.0 / 20.0), "{}", c.focal_length);
    assert!(close(c.focus_depth(), 12.0));
    assert_eq!(c.image_distance, 8.0, "framing unchanged");
    // The image distance in force at the end of the file is the one kept.
    let c = cam("focus_distance 12\nimage_distance 6\n");
    assert!(close(c.focal_length, 4.0) && close(c.focus_depth(), 12.0));
    // Figure 10's refocus, written as distances: f = 5 and f = 6 with N = 8.
    assert!(close(cam("focus_distance 13.333333333333334\n").focal_length, 5.0));
    assert!(close(cam("focus_distance 24\n").focal_length, 6.0));
}

#[test]
fn the_last_focus_statement_stands() {
    assert_eq!(cam("focus_distance 12\nfocal_length 5\n").focal_length, 5.0);
    assert!(close(cam("focal_length 5\nfocus_distance 12\n").focal_length, 4.8));
    // A focal length overridden later is not checked against N.
    assert!(close(cam("focal_length 9\nfocus_distance 12\n").focal_length, 4.8));
    let (line, kind, _) = err("focus_distance 12\nfocal_length 9\n");
    assert_eq!(line, 2);
    assert!(matches!(kind, ErrorKind::FocalLength { .. }));
    let sphere = "object sphere\ntranslate 0 0 -8\n";
    let c = cam(&format!("{sphere}focus_on 1\nfocal_length 5\n"));
    assert_eq!(c.focal_length, 5.0);
    let c = cam(&format!("focal_length 5\n{sphere}focus_on 1\n"));
    assert!(close(c.focus_depth(), 7.0));
}

#[test]
fn f_number_takes_the_final_focal_length() {
    assert!(close(cam("focal_length 5\nf_number 2\n").radius, 1.25));
    assert!(close(cam("f_number 2\nfocal_length 5\n").radius, 1.25));
    assert!(close(cam("f_number 2\nfocus_distance 12\n").radius, 4.8 / 4.0));
    // radius and f_number: the last one stands.
    assert_eq!(cam("f_number 2\nradius 0.3\n").radius, 0.3);
    assert!(close(cam("radius 0.3\nf_number 2\n").radius, 1.0));
    assert!(close(cam("f_number 2.8\n").f_number(), 2.8));
    let (line, kind, msg) = err("width 10\nf_number 0.00001\n");
    assert_eq!(line, 2);
    assert!(matches!(kind, ErrorKind::ApertureTooWide { .. }), "{msg}");
    assert_eq!(err("f_number 0\n").0, 1);
    assert_eq!(err("f_number -2\n").0, 1);
}

#[test]
fn focus_on_focuses_on_the_near_surface_of_program_1s_sphere() {
    let text = include_str!("../../scenes/paper-program1.scene");
    let plain = cam(text);
    assert_eq!((plain.focal_length, plain.radius, plain.aperture_blades), (4.0, 0.2, 0));
    // Object 3, the gold sphere at (0, −1, −8): the ray from the lens towards
    // its centre meets it one unit short of the centre.
    let c = cam(&format!("{text}\nfocus_on 3\n"));
    let expected = 8.0 * (1.0 - 1.0 / 65f64.sqrt());
    assert!(close(c.focus_depth(), expected), "{} vs {expected}", c.focus_depth());
    assert_eq!((c.image_distance, c.radius), (8.0, 0.2), "framing and aperture kept");
    // Object 1 is the floor: the ray meets it at its centre (0, −3, 0), depth 0.
    let (line, kind, msg) = err(&format!("{text}\nfocus_on 1\n"));
    assert_eq!(line, text.lines().count() as u32 + 2);
    assert!(matches!(kind, ErrorKind::FocusBehindCamera { index: 1, .. }), "{msg}");
    assert!(
        msg.ends_with("focus_on 1: the object is not in front of the camera (its focus point lies at depth 0)"),
        "{msg}"
    );
    // Cube (2) nearer, cone (4) farther.
    let cube = cam(&format!("{text}\nfocus_on 2\n")).focus_depth();
    let cone = cam(&format!("{text}\nfocus_on 4\n")).focus_depth();
    assert!(cube > 4.5 && cube < 6.0 && cone > 12.0 && cone < 15.0, "{cube} {cone}");
}

#[test]
fn focus_on_may_come_before_its_object_and_the_last_one_stands() {
    let two = "object sphere\ntranslate 0 0 -8\nobject sphere\ntranslate 0 0 -20\n";
    assert!(close(cam(&format!("focus_on 2\n{two}")).focus_depth(), 19.0));
    assert!(close(cam(&format!("focus_on 2\n{two}focus_on 1\n")).focus_depth(), 7.0));
    assert!(close(
        cam(&format!("focus_on 1\n{two}focus_on 2\n")).focus_depth(),
        19.0
    ));
    // With a comment and odd spacing the look-ahead still finds it.
    assert!(close(
        cam(&format!("{two}\t focus_on   2  # the far one\r\n")).focus_depth(),
        19.0
    ));
}

#[test]
fn focus_on_errors_name_the_line() {
    let (line, kind, msg) = err("object sphere\ntranslate 0 0 -8\nfocus_on 2\n");
    assert_eq!((line, kind), (3, ErrorKind::NoSuchObject { index: 2, count: 1 }));
    assert_eq!(msg, "line 3: focus_on 2: the scene has only 1 object(s)");
    assert_eq!(err("focus_on 1\n").1, ErrorKind::NoSuchObject { index: 1, count: 0 });
    for bad in ["focus_on 0\n", "focus_on 17\n", "focus_on -1\n"] {
        assert!(matches!(err(bad).1, ErrorKind::OutOfRange { .. }), "{bad}");
    }
    assert!(matches!(err("focus_on 1.5\n").1, ErrorKind::NotAnInteger { .. }));
    let (line, kind, _) = err("object sphere\ntranslate 0 0 8\nfocus_on 1\n");
    assert_eq!(line, 3);
    assert!(matches!(kind, ErrorKind::FocusBehindCamera { index: 1, depth } if depth < 0.0));
    // A look that turns the camera round puts the same sphere in front.
    assert!(close(
        cam("look 0 0 1\nobject sphere\ntranslate 0 0 8\nfocus_on 1\n").focus_depth(),
        7.0
    ));
}

#[test]
fn aperture_blades_and_rotation() {
    let c = cam("aperture_blades 6\naperture_rotation -15.5\n");
    assert_eq!((c.aperture_blades, c.aperture_rotation), (6, -15.5));
    assert_eq!(cam("aperture_blades 6\naperture_blades 0\n").aperture_blades, 0);
    assert_eq!(cam("aperture_blades 16\n").aperture_blades, 16);
    for bad in [
        "aperture_blades 1\n",
        "aperture_blades 2\n",
        "aperture_blades 17\n",
        "aperture_blades -3\n",
    ] {
        let (line, kind, msg) = err(bad);
        assert_eq!(line, 1);
        assert!(matches!(kind, ErrorKind::OutOfRange { .. }), "{bad}: {msg}");
        assert!(msg.contains("must be 0 (round) or between 3 and 16"), "{msg}");
    }
    assert!(matches!(err("aperture_rotation x\n").1, ErrorKind::NotANumber { .. }));
    assert!(matches!(err("aperture_rotation 1 2\n").1, ErrorKind::WrongCount { .. }));
}

#[test]
fn camera_params_api_matches_the_keywords() {
    let mut p = CameraParams::default();
    p.set_focus_distance(24.0);
    assert!(close(p.focal_length, 6.0));
    p.set_f_number(1.5);
    assert!(close(p.radius, 2.0) && close(p.f_number(), 1.5));
    assert_eq!(p.focal_length_for_distance(8.0), 4.0);
}

#[test]
fn the_features_scene_uses_each_feature() {
    let text = include_str!("../../scenes/camera-features.scene");
    let c = cam(text);
    // focus_on 2 (the gold sphere at (0.6, −1, −9)) replaced focus_distance 20.
    let centre = [0.6f64, -1.0, -9.0];
    let range = (centre[0] * centre[0] + centre[1] * centre[1] + centre[2] * centre[2]).sqrt();
    let look = [0.0f64, -0.08, -1.0];
    let look_len = (look[0] * look[0] + look[1] * look[1] + look[2] * look[2]).sqrt();
    let hit = centre.map(|x| x * (range - 1.0) / range);
    let depth = (hit[0] * look[0] + hit[1] * look[1] + hit[2] * look[2]) / look_len;
    assert!((c.focus_depth() - depth).abs() < 1e-9, "{} vs {depth}", c.focus_depth());
    assert!(close(c.f_number(), 1.8));
    assert_eq!((c.aperture_blades, c.aperture_rotation), (6, 15.0));
}
