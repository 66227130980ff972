//! `lensray compare`, run as a user runs it.

use std::process::Command;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use lensray_host::{encode_bmp, load_image, Image};

fn lensray(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .output()
        .expect("run lensray");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn tmp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("lensray-compare-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn two_images_give_the_figures_and_a_heat_map() {
    // 10x10 grey; the second has one pixel 3 levels brighter in red.
    let a = Image {
        width: 10,
        height: 10,
        pixels: vec![Rgb888::new(100, 100, 100); 100],
    };
    let mut b = a.clone();
    b.pixels[23] = Rgb888::new(103, 100, 100);
    let (pa, pb, heat) = (tmp("a.bmp"), tmp("b.bmp"), tmp("heat.png"));
    std::fs::write(&pa, encode_bmp(&a)).unwrap();
    std::fs::write(&pb, encode_bmp(&b)).unwrap();
    let (code, out, err) = lensray(&[
        "compare",
        pa.to_str().unwrap(),
        pb.to_str().unwrap(),
        "--diff",
        heat.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // MSE = 9 / 300 per channel: PSNR = 10 log10(255² · 300 / 9) = 63.35 dB.
    let psnr = 10.0 * (255.0f64 * 255.0 * 300.0 / 9.0).log10();
    assert!(out.contains(&format!("PSNR        {psnr:.2} dB")), "{out}");
    assert!(out.contains("mean error  0.0100 levels"), "{out}");
    assert!(out.contains("max error   3 levels"), "{out}");
    assert!(
        out.contains("within 1    99.000 %") && out.contains("within 2    99.000 %"),
        "{out}"
    );
    assert!(out.contains("within 8    100.000 %"), "{out}");
    assert!(
        out.contains("row 2") && out.contains("column 3"),
        "the worst line is row 2, column 3: {out}"
    );
    let h = load_image(&heat).unwrap();
    assert_eq!((h.width, h.height), (10, 10));
    for (i, p) in h.pixels.iter().enumerate() {
        assert_eq!(*p == Rgb888::BLACK, i != 23, "heat map pixel {i}: {p:?}");
    }
}

#[test]
fn a_scene_is_rendered_both_ways() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/paper-program1.scene");
    let (code, out, err) = lensray(&["compare", scene, "--width", "32", "--height", "24", "--samples", "4"]);
    assert_eq!(code, 0, "{err}");
    // The most rays a pixel casts at `--samples 4`, as the renderer says.
    let text = std::fs::read_to_string(scene).unwrap();
    let fixed = lensray::Scene::<lensray::I16F16>::parse(&text).unwrap();
    let rays = lensray::Renderer::new_with_samples(&fixed, 32, 24, Some(4)).rays_per_pixel();
    assert!(
        out.contains(&format!("Q16.16 against f32, 32x24, {rays} ray(s) a pixel")),
        "{out}"
    );
    let psnr: f64 = out
        .lines()
        .find_map(|l| l.strip_prefix("PSNR")?.trim().strip_suffix(" dB")?.parse().ok())
        .unwrap_or_else(|| panic!("no PSNR in {out}"));
    assert!(psnr > 40.0, "{out}");
}

#[test]
fn bad_uses_are_one_line_errors() {
    let a = Image {
        width: 4,
        height: 4,
        pixels: vec![Rgb888::BLACK; 16],
    };
    let b = Image {
        width: 4,
        height: 3,
        pixels: vec![Rgb888::BLACK; 12],
    };
    let (pa, pb) = (tmp("x.bmp"), tmp("y.bmp"));
    std::fs::write(&pa, encode_bmp(&a)).unwrap();
    std::fs::write(&pb, encode_bmp(&b)).unwrap();
    let (pa, pb) = (pa.to_str().unwrap(), pb.to_str().unwrap());
    let (code, _, err) = lensray(&["compare", pa, pb]);
    assert_eq!(code, 2);
    assert!(err.contains("the images differ in size: 4x4 and 4x3"), "{err}");
    let (code, _, err) = lensray(&["compare", pa, pa, "--width", "8"]);
    assert_eq!(code, 2);
    assert!(err.contains("apply to a scene"), "{err}");
    let (code, _, err) = lensray(&["compare", pa, pa, "--diff", "heat.txt"]);
    assert_eq!(code, 2);
    assert!(err.contains("--diff must end in .bmp or .png"), "{err}");
    let (code, _, _) = lensray(&["compare"]);
    assert_eq!(code, 2);
}
