//! The same scene renders to the same bytes with one thread and with all of
//! them, and on every run: in the library's parallel renderer and through the
//! `lensray` command.

use std::path::{Path, PathBuf};
use std::process::Command;

use lensray::{Scalar, Scene, I16F16};
use lensray_host::{encode_bmp, render_image};

const PROGRAM1: &str = include_str!("../../scenes/paper-program1.scene");

/// Program 1 at 48×36 with 6 lens samples a pixel, on a pool of `threads`.
fn bmp<S: Scalar + Send + Sync>(scene: &Scene<S>, threads: usize) -> Vec<u8> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let img = pool.install(|| render_image(scene, 48, 36, Some(6), &|| {}));
    encode_bmp(&img)
}

fn same_bytes_on_any_pool<S: Scalar + Send + Sync>() {
    let scene = Scene::<S>::parse(PROGRAM1).expect("Program 1 parses");
    let all = std::thread::available_parallelism().map_or(2, |n| n.get());
    let one = bmp(&scene, 1);
    // More threads than cores interleave rows in ever new orders.
    for threads in [all, 1, 5, all] {
        assert!(
            bmp(&scene, threads) == one,
            "{}: {threads} threads differ from 1",
            S::NAME
        );
    }
    // Not a blank image: the comparison sees the scene.
    let distinct: std::collections::BTreeSet<&[u8]> = one[54..].chunks(3).collect();
    assert!(distinct.len() > 50, "{} colours only", distinct.len());
}

#[test]
fn library_render_is_the_same_on_any_pool_q16() {
    same_bytes_on_any_pool::<I16F16>();
}

#[test]
fn library_render_is_the_same_on_any_pool_f32() {
    same_bytes_on_any_pool::<f32>();
}

#[test]
fn the_command_writes_the_same_bytes_with_1_thread_and_all() {
    let dir = std::env::temp_dir().join(format!("lensray-determinism-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene");
    let run = |threads: Option<&str>, out: &str, extra: &[&str]| -> Vec<u8> {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_lensray"));
        cmd.arg("render")
            .arg(&scene)
            .args(["-o", out, "--width", "64", "--height", "48", "--samples", "6"])
            .args(extra)
            .current_dir(&dir);
        match threads {
            Some(n) => cmd.env("RAYON_NUM_THREADS", n),
            None => cmd.env_remove("RAYON_NUM_THREADS"),
        };
        let o = cmd.output().expect("run lensray");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(dir.join(out)).expect("output written")
    };
    for (extra, name) in [(&[][..], "q16"), (&["--float"][..], "f32")] {
        let one = run(Some("1"), &format!("{name}-1.bmp"), extra);
        let all = run(None, &format!("{name}-all.bmp"), extra);
        let again = run(None, &format!("{name}-again.bmp"), extra);
        let many = run(Some("7"), &format!("{name}-7.bmp"), extra);
        assert!(one == all && all == again && again == many, "{name}: outputs differ");
    }
    let _ = std::fs::remove_dir_all(PathBuf::from(&dir));
}
