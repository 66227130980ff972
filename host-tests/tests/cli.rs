//! The `lensray render` command on bad input, run as a user would: the built
//! binary, in a fresh folder. Every error is one line on stderr, the exit
//! status is 2, nothing panics and no file is written (nor a good one replaced).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use lensray::{Scene, I16F16};

/// A fresh, empty working folder for one case, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("lensray-cli-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    /// The folder's entries with their contents, sorted.
    fn listing(&self) -> Vec<(String, Vec<u8>)> {
        let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(&self.0)
            .expect("read temp dir")
            .map(|e| {
                let e = e.expect("entry");
                let bytes = std::fs::read(e.path()).unwrap_or_default();
                (e.file_name().to_string_lossy().into_owned(), bytes)
            })
            .collect();
        out.sort();
        out
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn lensray(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .env_remove("RAYON_NUM_THREADS")
        .output()
        .expect("run lensray")
}

fn corpus(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("corpus/malformed")
        .join(name)
}

/// Runs `args` in `dir` and checks the failure: exit status 2, exactly one
/// line on stderr (returned), no panic, and the folder exactly as it was.
fn fails(dir: &TempDir, args: &[&str]) -> String {
    let before = dir.listing();
    let out = lensray(&dir.0, args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: not one line: {err:?}");
    assert!(err.ends_with('\n'));
    assert_eq!(dir.listing(), before, "{args:?} changed the folder");
    err.trim_end().to_string()
}

#[test]
fn every_malformed_scene_prints_file_line_message_and_exits_2() {
    let mut n = 0;
    let dir = TempDir::new("malformed");
    // A good image already in place must survive every failed render.
    std::fs::write(dir.0.join("out.bmp"), b"a good image").unwrap();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(corpus(""))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    paths.sort();
    for path in paths {
        let bytes = std::fs::read(&path).unwrap();
        let Err(e) = Scene::<I16F16>::parse_bytes(&bytes) else {
            continue;
        };
        let shown = path.to_str().unwrap();
        let err = fails(&dir, &["render", shown, "-o", "out.bmp", "--width", "8"]);
        assert_eq!(err, format!("{shown}:{}: {}", e.line, e.kind));
        n += 1;
    }
    assert!(n >= 30, "only {n} malformed scenes");
    assert_eq!(std::fs::read(dir.0.join("out.bmp")).unwrap(), b"a good image");
}

#[test]
fn a_missing_scene_file_is_one_line() {
    let dir = TempDir::new("missing");
    let err = fails(&dir, &["render", "no-such.scene"]);
    assert!(err.starts_with("lensray: no-such.scene: cannot read: "), "{err}");
}

#[test]
fn a_directory_as_the_scene_is_one_line() {
    let dir = TempDir::new("dir-scene");
    std::fs::create_dir(dir.0.join("scenes")).unwrap();
    let err = fails(&dir, &["render", "scenes"]);
    assert_eq!(err, "lensray: scenes: is a directory, not a scene file");
    let err = fails(&dir, &["render", "."]);
    assert_eq!(err, "lensray: .: is a directory, not a scene file");
}

#[test]
fn an_unwritable_output_is_refused_before_rendering() {
    let dir = TempDir::new("unwritable");
    std::fs::write(dir.0.join("a.scene"), b"object sphere\ntranslate 0 0 -5\n").unwrap();
    let err = fails(&dir, &["render", "a.scene", "-o", "no-such-dir/out.bmp"]);
    assert_eq!(
        err,
        "lensray: no-such-dir/out.bmp: cannot write: no-such-dir is not a directory"
    );
    // A file where a folder should be.
    let err = fails(&dir, &["render", "a.scene", "-o", "a.scene/out.bmp"]);
    assert_eq!(
        err,
        "lensray: a.scene/out.bmp: cannot write: a.scene is not a directory"
    );
    std::fs::create_dir(dir.0.join("taken.bmp")).unwrap();
    let err = fails(&dir, &["render", "a.scene", "-o", "taken.bmp"]);
    assert_eq!(err, "lensray: taken.bmp: is a directory");
    let err = fails(&dir, &["render", "a.scene", "-o", "out.jpg"]);
    assert_eq!(err, "lensray: out.jpg: output must end in .bmp or .png");
}

#[test]
fn out_of_range_sizes_are_refused_with_the_limit() {
    let dir = TempDir::new("sizes");
    std::fs::write(dir.0.join("a.scene"), b"object sphere\ntranslate 0 0 -5\n").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--width", "0"], "--width 0: must be between 1 and 8192"),
        (&["--width", "100000"], "--width 100000: must be between 1 and 8192"),
        (&["--width", "8193"], "--width 8193: must be between 1 and 8192"),
        (
            &["--width", "99999999999999999999999"],
            "--width 99999999999999999999999: must be between 1 and 8192",
        ),
        (&["--width", "-3"], "--width -3: must be between 1 and 8192"),
        (&["--width", "abc"], "--width abc: not a whole number"),
        (&["--width", "1.5"], "--width 1.5: not a whole number"),
        (&["--width"], "--width needs a value"),
        (&["--height", "0"], "--height 0: must be between 1 and 8192"),
        (&["--height", "100000"], "--height 100000: must be between 1 and 8192"),
        (&["--samples", "0"], "--samples 0: must be between 1 and 65535"),
        (&["--samples", "65536"], "--samples 65536: must be between 1 and 65535"),
    ];
    for (opts, want) in cases {
        let mut args = vec!["render", "a.scene"];
        args.extend_from_slice(opts);
        assert_eq!(fails(&dir, &args), format!("lensray: {want}"));
    }
    // A height from the scene's aspect ratio is checked before rendering too.
    std::fs::write(dir.0.join("tall.scene"), b"aspect_ratio 0.001\n").unwrap();
    let err = fails(&dir, &["render", "tall.scene", "--width", "100"]);
    assert_eq!(
        err,
        "lensray: height 100000 from width 100 / aspect_ratio 0.001 must be between 1 and 8192; give --height"
    );
}

#[test]
fn a_good_scene_still_renders() {
    let dir = TempDir::new("good");
    std::fs::write(dir.0.join("a.scene"), b"object sphere\ntranslate 0 0 -5\n").unwrap();
    let out = lensray(
        &dir.0,
        &["render", "a.scene", "--width", "8", "--height", "6", "--samples", "2"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let img = lensray_host::load_image(&dir.0.join("a.bmp")).expect("a.bmp written");
    assert_eq!((img.width, img.height), (8, 6));
    // Only the image: no probe or temporary file left behind.
    let names: Vec<String> = dir.listing().into_iter().map(|(n, _)| n).collect();
    assert_eq!(names, ["a.bmp", "a.scene"]);
}
