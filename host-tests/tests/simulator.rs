//! The `lensray render` command end to end: files it writes, read back.

use std::path::{Path, PathBuf};
use std::process::Command;

use lensray::{Scene, I16F16};
use lensray_host::{decode_image, encode_bmp, load_image, render_image, Diff, Image};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

fn program1() -> PathBuf {
    root().join("scenes/paper-program1.scene")
}

fn lensray(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lensray-sim-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn host_render(w: u32, h: u32, samples: Option<u32>) -> Image {
    let scene = Scene::<I16F16>::parse(&std::fs::read_to_string(program1()).unwrap()).unwrap();
    render_image(&scene, w, h, samples, &|| {})
}

#[test]
fn bmp_is_24_bit_and_reads_back_through_tinybmp_as_rendered() {
    let img = host_render(61, 37, Some(3));
    let bytes = encode_bmp(&img);
    // 24 bits per pixel, rows padded to 4 bytes (61 * 3 = 183 -> 184).
    assert_eq!(u16::from_le_bytes([bytes[28], bytes[29]]), 24);
    assert_eq!(bytes.len(), 54 + 184 * 37);
    assert_eq!(decode_image(&bytes).unwrap(), img);
}

#[test]
fn render_command_writes_the_rendered_pixels_as_bmp_and_png() {
    let dir = temp_dir("formats");
    let want = host_render(80, 60, Some(2));
    for name in ["out.bmp", "out.png"] {
        let out = lensray(
            &dir,
            &[
                "render",
                program1().to_str().unwrap(),
                "-o",
                name,
                "--width",
                "80",
                "--samples",
                "2",
            ],
        );
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        // --height defaults to round(80 / 1.33) = 60.
        assert_eq!(load_image(&dir.join(name)).unwrap(), want, "{name}");
    }
    // No temporary files are left behind.
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 2, "{left:?}");
}

#[test]
fn default_output_is_the_scene_name_in_the_current_directory() {
    let dir = temp_dir("default");
    let out = lensray(
        &dir,
        &[
            "render",
            program1().to_str().unwrap(),
            "--width",
            "32",
            "--samples",
            "1",
        ],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let img = load_image(&dir.join("paper-program1.bmp")).unwrap();
    assert_eq!((img.width, img.height), (32, 24));
}

#[test]
fn float_flag_renders_the_f32_reference() {
    let dir = temp_dir("float");
    let scene_path = program1();
    let size = ["--width", "64", "--height", "48", "--samples", "4"];
    for (name, float) in [("x.bmp", false), ("f.bmp", true)] {
        let mut args = vec!["render", scene_path.to_str().unwrap(), "-o", name];
        args.extend(size);
        if float {
            args.push("--float");
        }
        assert!(lensray(&dir, &args).status.success());
    }
    let (x, f) = (
        load_image(&dir.join("x.bmp")).unwrap(),
        load_image(&dir.join("f.bmp")).unwrap(),
    );
    let scene = Scene::<f32>::parse(&std::fs::read_to_string(program1()).unwrap()).unwrap();
    assert_eq!(f, render_image(&scene, 64, 48, Some(4), &|| {}));
    assert_eq!(x, host_render(64, 48, Some(4)));
    // Different arithmetic, the same picture.
    assert_ne!(x, f);
    assert!(Diff::of(&x, &f).unwrap().psnr > 35.0);
}

#[test]
fn samples_flag_overrides_the_scenes_point() {
    let scene_point = host_render(40, 30, None);
    assert_eq!(scene_point, host_render(40, 30, Some(70)));
    assert_ne!(scene_point, host_render(40, 30, Some(5)));
}
