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

/// `lensray --help` and `lensray COMMAND --help` (and `help COMMAND`): each
/// on stdout with status 0, naming the command's own options and no other's.
#[test]
fn help_lists_each_commands_own_options() {
    let dir = TempDir::new("help");
    let cases: &[(&str, &[&str], &[&str])] = &[
        (
            "render",
            &[
                "--output",
                "--width",
                "--height",
                "--samples",
                "--float",
                "--adaptive",
                "--sampler",
                "--passes",
                "--first-step",
                "--preview-samples",
                "--panel",
            ],
            &["--board", "--diff", "--columns"],
        ),
        (
            "sheet",
            &["--columns", "--title", "--width", "--float"],
            &["--passes", "--board", "--panel"],
        ),
        (
            "emulate",
            &["--board", "--timeout", "--soft-sqrt", "--parse-on-device", "--width"],
            &["--passes", "--diff"],
        ),
        (
            "compare",
            &["--diff", "--width", "--height", "--samples"],
            &["--float", "--output", "--board"],
        ),
        (
            "bake",
            &["--output", "--width", "--float", "--adaptive"],
            &["--passes", "--board", "--diff"],
        ),
    ];
    for &(command, has, lacks) in cases {
        for args in [vec![command, "--help"], vec!["help", command], vec![command, "-h"]] {
            let out = lensray(&dir.0, &args);
            let text = String::from_utf8_lossy(&out.stdout);
            assert_eq!(
                out.status.code(),
                Some(0),
                "{args:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            assert!(text.contains(&format!("Usage: lensray {command}")), "{args:?}:\n{text}");
            for flag in has {
                assert!(text.contains(flag), "{args:?} does not mention {flag}:\n{text}");
            }
            for flag in lacks {
                assert!(
                    !text.contains(flag),
                    "{args:?} mentions {flag}, another command's:\n{text}"
                );
            }
        }
    }
    let out = lensray(&dir.0, &["--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0));
    for command in ["render", "sheet", "emulate", "compare", "bake"] {
        assert!(
            text.contains(command),
            "lensray --help does not list {command}:\n{text}"
        );
    }
    // Nothing asked: the overview on stderr, and a failure.
    let out = lensray(&dir.0, &[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("render"));
    assert_eq!(dir.listing(), []);
}

#[test]
fn version_is_the_packages() {
    let dir = TempDir::new("version");
    for flag in ["--version", "-V"] {
        let out = lensray(&dir.0, &[flag]);
        assert_eq!(out.status.code(), Some(0));
        assert_eq!(
            String::from_utf8_lossy(&out.stdout),
            format!("lensray {}\n", env!("CARGO_PKG_VERSION"))
        );
    }
}

/// A mistyped option or command: one line naming it and the nearest right one.
#[test]
fn a_mistyped_option_or_command_gets_a_suggestion() {
    let dir = TempDir::new("typos");
    std::fs::write(dir.0.join("a.scene"), b"object sphere\ntranslate 0 0 -5\n").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &["render", "a.scene", "--widht", "8"],
            "lensray: unknown option \"--widht\"; did you mean \"--width\"?; see lensray render --help",
        ),
        (
            &["render", "a.scene", "--samplse", "8"],
            "lensray: unknown option \"--samplse\"; did you mean \"--samples\"?; see lensray render --help",
        ),
        (
            &["compare", "a.scene", "--dif", "x.png"],
            "lensray: unknown option \"--dif\"; did you mean \"--diff\"?; see lensray compare --help",
        ),
        (
            &["rendr", "a.scene"],
            "lensray: unknown command \"rendr\"; did you mean \"render\"?; see lensray --help",
        ),
        // Another command's option is refused, not ignored.
        (
            &["render", "a.scene", "--board", "microbit"],
            "lensray: unknown option \"--board\"; see lensray render --help",
        ),
        (
            &["render", "a.scene", "b.scene"],
            "lensray: render takes one scene file: \"b.scene\" is one too many",
        ),
        (
            &["render"],
            "lensray: render takes one scene file; see lensray render --help",
        ),
        (
            &["sampler-typo"],
            "lensray: unknown command \"sampler-typo\"; see lensray --help",
        ),
        (
            &["render", "a.scene", "--sampler", "stratifed"],
            "lensray: --sampler stratifed: must be independent or stratified",
        ),
        (
            &["render", "a.scene", "--adaptive"],
            "lensray: --adaptive needs a value: on or off",
        ),
        (
            &["emulate", "a.scene"],
            "lensray: emulate needs --board <BOARD>; see lensray emulate --help",
        ),
        (
            &["emulate", "a.scene", "--board", "esp32"],
            "lensray: --board esp32: must be microbit, mps2-an385, mps2-an386, sifive-e or pico",
        ),
    ];
    for (args, want) in cases {
        assert_eq!(fails(&dir, args), *want);
    }
}

/// Options keep working as before clap: last one wins, in any order.
#[test]
fn a_repeated_option_takes_its_last_value() {
    let dir = TempDir::new("repeat");
    std::fs::write(dir.0.join("a.scene"), b"object sphere\ntranslate 0 0 -5\n").unwrap();
    let out = lensray(
        &dir.0,
        &[
            "render",
            "--width",
            "3",
            "a.scene",
            "--height",
            "5",
            "--width",
            "7",
            "-o",
            "x.bmp",
            "--samples",
            "1",
        ],
    );
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let img = lensray_host::load_image(&dir.0.join("x.bmp")).unwrap();
    assert_eq!((img.width, img.height), (7, 5));
}
