//! The contact sheet (`lensray sheet`) and progressive passes
//! (`lensray render --passes`), as a user runs them.

use std::path::{Path, PathBuf};
use std::process::Command;

use embedded_graphics::pixelcolor::Rgb888;
use lensray_host::sheet::{camera_caption, contact_sheet, Tile, BACKGROUND, GAP, INK, LINE};
use lensray_host::{load_image, Image};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lensray-sheet-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn lensray(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lensray")).args(args).output().unwrap();
    (out.status.success(), String::from_utf8_lossy(&out.stderr).into_owned())
}

fn gradient(w: u32, h: u32, seed: u8) -> Image {
    let pixels = (0..w * h)
        .map(|i| Rgb888::new((i % w * 7) as u8 ^ seed, (i / w * 5) as u8, seed))
        .collect();
    Image {
        width: w,
        height: h,
        pixels,
    }
}

#[test]
fn sheet_places_each_tile_whole_with_its_caption_under_it() {
    let tiles = vec![
        Tile {
            image: gradient(40, 30, 1),
            caption: vec!["first".into(), "f 4".into()],
        },
        Tile {
            image: gradient(30, 20, 2),
            caption: vec!["second".into()],
        },
        Tile {
            image: gradient(40, 25, 3),
            caption: vec![],
        },
    ];
    let sheet = contact_sheet(&tiles, 2, Some("title"));
    // Two columns of the widest tile; two rows.
    assert_eq!(sheet.image.width, GAP + 2 * (40 + GAP));
    let top = GAP + LINE + GAP / 2;
    assert_eq!(
        sheet.origins,
        [(GAP, top), (GAP + 40 + GAP, top), (GAP, top + 30 + 2 + 2 * LINE + GAP)]
    );
    for (tile, &(x0, y0)) in tiles.iter().zip(&sheet.origins) {
        for y in 0..tile.image.height {
            for x in 0..tile.image.width {
                assert_eq!(sheet.image.get(x0 + x, y0 + y), tile.image.get(x, y));
            }
        }
        // Ink in each caption line's strip under the picture, none where there is no line.
        let ink_in = |y: u32| (x0..x0 + 40).filter(|&x| sheet.image.get(x, y) == INK).count();
        // Captions start under the row's highest picture (30 in the first row).
        let under = y0 + if y0 == top { 30 } else { 25 } + 2;
        for k in 0..2u32 {
            if under + (k + 1) * LINE > sheet.image.height {
                continue;
            }
            let strip: usize = (0..LINE).map(|d| ink_in(under + k * LINE + d)).sum();
            if (k as usize) < tile.caption.len() {
                assert!(strip > 10, "caption line {k} of tile at ({x0}, {y0}) is empty");
            } else {
                assert_eq!(strip, 0, "ink under tile at ({x0}, {y0}) line {k}");
            }
        }
    }
    // The title is drawn, and the gaps between tiles are background.
    assert!((0..sheet.image.width).any(|x| (GAP..GAP + LINE).any(|y| sheet.image.get(x, y) == INK)));
    assert_eq!(sheet.image.get(GAP + 40 + GAP / 2, top + 5), BACKGROUND);
    let empty = contact_sheet(&[], 3, None);
    assert!(empty.origins.is_empty() && empty.image.width >= 1);
}

#[test]
fn camera_caption_reads_like_a_photographers_notes() {
    let mut c = lensray::CameraParams::default();
    assert_eq!(camera_caption(&c), "pinhole  f 4  N 8");
    c.radius = 0.2;
    assert_eq!(camera_caption(&c), "f 4  focus 8  r 0.2 f/10");
    c.set_focus_distance(24.0);
    c.set_f_number(2.0);
    c.aperture_blades = 6;
    assert_eq!(camera_caption(&c), "f 6  focus 24  r 1.5 f/2  6 blades");
}

const SMALL: &str = "ambient_light 1 1 1\nradius 0.3\npoint 4\nobject sphere gold\ntranslate 0 0 -8\n";

#[test]
fn sheet_command_renders_every_scene_and_refuses_bad_ones_whole() {
    let d = tmp("cmd");
    let a = d.join("a.scene");
    let b = d.join("b.scene");
    std::fs::write(&a, SMALL).unwrap();
    std::fs::write(&b, format!("{SMALL}aperture_blades 5\nf_number 2\n")).unwrap();
    let out = d.join("sheet.png");
    let (ok, err) = lensray(&[
        "sheet",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "30",
    ]);
    assert!(ok, "{err}");
    let img = load_image(&out).unwrap();
    assert_eq!(
        (img.width, img.height),
        (GAP + 2 * (40 + GAP), GAP + 30 + 2 + 2 * LINE + GAP)
    );
    // Each tile is the scene's own render.
    let single = d.join("b.png");
    let (ok, err) = lensray(&[
        "render",
        b.to_str().unwrap(),
        "-o",
        single.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "30",
    ]);
    assert!(ok, "{err}");
    let tile = load_image(&single).unwrap();
    for y in 0..30 {
        for x in 0..40 {
            assert_eq!(img.get(GAP + 40 + GAP + x, GAP + y), tile.get(x, y));
        }
    }
    // A bad scene among good ones: an error naming its line, the old sheet kept.
    let bad = d.join("bad.scene");
    std::fs::write(&bad, "width 10\naperture_blades 2\n").unwrap();
    let before = std::fs::read(&out).unwrap();
    let (ok, err) = lensray(&[
        "sheet",
        a.to_str().unwrap(),
        bad.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains("bad.scene:2: aperture_blades 2 must be 0 (round) or between 3 and 16"),
        "{err}"
    );
    assert_eq!(std::fs::read(&out).unwrap(), before);
    let (ok, err) = lensray(&["sheet", "-o", out.to_str().unwrap()]);
    assert!(!ok && err.contains("one or more scene files"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn render_passes_saves_each_pass_and_ends_with_the_plain_render() {
    let d = tmp("passes");
    let scene = d.join("s.scene");
    // Every pixel its 4 samples: adaptive sampling would render so few
    // plain samples that no preview pass is left to tell from the others.
    std::fs::write(&scene, format!("{SMALL}adaptive off\n")).unwrap();
    let plain = d.join("plain.png");
    let progressive = d.join("progressive.png");
    let dir = d.join("passes");
    let s = scene.to_str().unwrap();
    assert!(lensray(&["render", s, "-o", plain.to_str().unwrap(), "--width", "50"]).0);
    let (ok, err) = lensray(&[
        "render",
        s,
        "-o",
        progressive.to_str().unwrap(),
        "--width",
        "50",
        "--passes",
        dir.to_str().unwrap(),
        "--first-step",
        "4",
    ]);
    assert!(ok, "{err}");
    // Preview at 4x4 with 1 sample, then 4x4, 2x2, 1x1 at 4 samples.
    let passes: Vec<Image> = (1..=4)
        .map(|k| load_image(&dir.join(format!("pass-{k}.png"))).unwrap())
        .collect();
    assert!(!dir.join("pass-5.png").exists());
    let plain = load_image(&plain).unwrap();
    assert_eq!(passes[3], plain);
    assert_eq!(load_image(&progressive).unwrap(), plain);
    // The 4x4 pass shows 4x4 blocks; the preview differs from it (1 sample, not 4).
    for y in 0..passes[1].height {
        for x in 0..50 {
            assert_eq!(passes[1].get(x, y), plain.get(x / 4 * 4, y / 4 * 4));
        }
    }
    // The preview shows the 1-sample render's grid pixels.
    let one = d.join("one.png");
    assert!(
        lensray(&[
            "render",
            s,
            "-o",
            one.to_str().unwrap(),
            "--width",
            "50",
            "--samples",
            "1"
        ])
        .0
    );
    let one = load_image(&one).unwrap();
    for y in 0..passes[0].height {
        for x in 0..50 {
            assert_eq!(passes[0].get(x, y), one.get(x / 4 * 4, y / 4 * 4));
        }
    }
    let (ok, err) = lensray(&["render", s, "--passes", dir.to_str().unwrap(), "--first-step", "65"]);
    assert!(
        !ok && err.contains("--first-step 65: must be between 1 and 64"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(Path::new(&d));
}
