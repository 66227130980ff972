//! The firmware under QEMU, through `lensray emulate`: the rows each board
//! sends are bit for bit the host's own plain render (`render_image`) of the
//! same scene, size and samples, the micro:bit's included (one code path: no
//! feature changes an image), with adaptive sampling and its pre-pass at
//! work (the scenes' defaults),
//! the instruction counter is calibrated, the microbit's 16 KiB of RAM hold the
//! statics and the deepest stack, a panic or a HardFault ends the run with a
//! non-zero status instead of a hang, and a run past `--timeout` is stopped.
//!
//! The QEMU tests need qemu-system-arm and the thumbv6m/thumbv7em targets and
//! take a minute or two, so they are `#[ignore]`d in a plain `cargo test`;
//! `scripts/firmware-tests.sh` (run by `scripts/test-all.sh`) installs what is
//! missing and runs them with `--ignored`. Each board's test writes its
//! figures to `firmware-figures-BOARD.md` in cargo's target tmp directory and
//! prints them.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Instant;

use lensray::{Scalar, I16F16};
use lensray_host::{load_image, load_scene, render_image, Image};

const LENSRAY: &str = env!("CARGO_BIN_EXE_lensray");

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn scene(name: &str) -> PathBuf {
    repo().join("scenes").join(name)
}

fn tmp(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// One emulated render: its options, and the results.
struct Run {
    board: &'static str,
    /// A file of `scenes/`, or an absolute path.
    scene: &'static str,
    width: u32,
    height: u32,
    samples: Option<u32>,
    float: bool,
    soft_sqrt: bool,
}

/// What came back from a run.
struct Outcome {
    image: Image,
    report: BTreeMap<String, String>,
    stdout: String,
    seconds: f64,
}

impl Outcome {
    fn get(&self, key: &str) -> u64 {
        self.report
            .get(key)
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("report has no number {key}:\n{}", self.stdout))
    }
}

fn emulate_cmd(run: &Run, out: &Path) -> Command {
    let mut cmd = Command::new(LENSRAY);
    cmd.arg("emulate")
        .arg(scene(run.scene))
        .args(["--board", run.board])
        .args(["--width", &run.width.to_string(), "--height", &run.height.to_string()])
        .arg("-o")
        .arg(out)
        .env_remove("LENSRAY_FAULT")
        .env_remove("LENSRAY_CHECK");
    if let Some(n) = run.samples {
        cmd.args(["--samples", &n.to_string()]);
    }
    if run.float {
        cmd.arg("--float");
    }
    if run.soft_sqrt {
        cmd.arg("--soft-sqrt");
    }
    cmd
}

fn show(o: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// The host's plain render of `run`'s scene in `S`: what every board must send.
fn host_render<S: Scalar + Send + Sync>(path: &Path, run: &Run) -> Image {
    let scene = load_scene::<S>(path).unwrap();
    render_image(&scene, run.width, run.height, run.samples, &|| {})
}

/// The host renderer's [`Renderer::rays_per_pixel`](lensray::Renderer::rays_per_pixel) for `run`.
fn host_rays<S: Scalar>(path: &Path, run: &Run) -> u32 {
    let scene = load_scene::<S>(path).unwrap();
    lensray::Renderer::new_with_samples(&scene, run.width, run.height, run.samples).rays_per_pixel()
}

/// Runs `lensray emulate` and checks its image against the host's render.
fn emulate_and_compare(run: &Run) -> Outcome {
    let out = tmp(&format!(
        "{}-{}-{}x{}-{}{}.bmp",
        run.board,
        Path::new(run.scene).file_name().unwrap().to_string_lossy(),
        run.width,
        run.height,
        if run.float { "f32" } else { "q16" },
        if run.soft_sqrt { "-soft" } else { "" }
    ));
    let _ = std::fs::remove_file(&out);
    let start = Instant::now();
    let o = emulate_cmd(run, &out).output().expect("run lensray emulate");
    let seconds = start.elapsed().as_secs_f64();
    assert!(o.status.success(), "lensray emulate failed:\n{}", show(&o));
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    let report: BTreeMap<String, String> = stdout
        .lines()
        .find_map(|l| l.strip_prefix("report "))
        .unwrap_or_else(|| panic!("no report line:\n{stdout}"))
        .split_whitespace()
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let image = load_image(&out).expect("read the emulated image");

    // The host's own render of the same scene at the same size, in the same number type.
    let path = scene(run.scene);
    let host = if run.float {
        host_render::<f32>(&path, run)
    } else {
        host_render::<I16F16>(&path, run)
    };
    assert_eq!((image.width, image.height), (run.width, run.height));
    let differing: Vec<(usize, _, _)> = image
        .pixels
        .iter()
        .zip(&host.pixels)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(i, (a, b))| (i, *a, *b))
        .collect();
    assert!(
        differing.is_empty(),
        "{} of {} pixels differ from the host's render on {} ({}); first (index, board, host): {:?}",
        differing.len(),
        image.pixels.len(),
        run.board,
        run.scene,
        &differing[..differing.len().min(5)]
    );

    let outcome = Outcome {
        image,
        report,
        stdout,
        seconds,
    };
    check_report(run, &path, &outcome);
    outcome
}

/// The report of `run` (its scene at `path`) describes that very run, with
/// figures that agree with each other and with the board.
fn check_report(run: &Run, path: &Path, outcome: &Outcome) {
    // The report describes this very run.
    assert_eq!(outcome.report.get("board").map(String::as_str), Some(run.board));
    assert_eq!(outcome.get("width"), run.width as u64);
    assert_eq!(outcome.get("height"), run.height as u64);
    // The most rays a pixel casts, as the host's renderer has them (the
    // scene's `point` or `--samples`, 1 through a pinhole, fewer where the
    // pre-pass chose plain samples).
    let rays = if run.float {
        host_rays::<f32>(path, run)
    } else {
        host_rays::<I16F16>(path, run)
    };
    assert_eq!(outcome.get("rays"), rays as u64, "{}", outcome.stdout);
    let number = if run.float { f32::NAME } else { I16F16::NAME };
    assert_eq!(outcome.report.get("number").map(String::as_str), Some(number));
    // Instructions per pixel is the frame over the pixels, and the summary line says it.
    let pixels = (run.width * run.height) as u64;
    let per_pixel = outcome.get("per_pixel");
    assert_eq!(per_pixel, (outcome.get("frame") + pixels / 2) / pixels);
    let summary = format!("{per_pixel} instructions per pixel on {}", run.board);
    assert!(
        outcome.stdout.contains(&summary),
        "no line \"{summary}\":\n{}",
        outcome.stdout
    );
    // SysTick counts instructions: a loop of exactly 2,000,000 reads within one tick.
    let cal = outcome.get("calibration") as i64;
    assert!(
        (cal - 2_000_000).abs() <= 63,
        "calibration loop counted as {cal} instructions"
    );
    // No stack overflow into the statics, and everything fits the board's RAM.
    assert_eq!(outcome.get("stack_overflow"), 0, "{}", outcome.stdout);
    let used = outcome.get("static_ram") + outcome.get("peak_stack");
    assert!(
        used <= outcome.get("ram"),
        "statics + stack = {used} bytes > RAM\n{}",
        outcome.stdout
    );
    assert!(outcome.get("peak_stack") > 0 && outcome.get("flash") > 0);
}

/// A Markdown table of the runs, written beside the test's outputs (as
/// `firmware-figures-NAME.md`) and printed.
fn record(name: &str, rows: &[(&Run, &Outcome)]) {
    let mut md = String::from(
        "| board | scene | size | rays/pixel | number | instructions/pixel | pixels per million instructions | frame instructions | flash | static RAM | peak stack | wall s (build + run) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (run, o) in rows {
        let board = run.board;
        let number = match (run.float, run.soft_sqrt) {
            (false, _) => "Q16.16",
            (true, false) if board == "mps2-an386" => "f32, vsqrt.f32",
            (true, _) => "f32, libm sqrt",
        };
        md += &format!(
            "| {board} | {} | {}x{} | {} | {number} | {} | {:.1} | {} | {} | {} | {} | {:.1} |\n",
            run.scene,
            run.width,
            run.height,
            o.get("rays"),
            o.get("per_pixel"),
            (run.width * run.height) as f64 * 1e6 / o.get("frame") as f64,
            o.get("frame"),
            o.get("flash"),
            o.get("static_ram"),
            o.get("peak_stack"),
            o.seconds,
        );
    }
    let path = tmp(&format!("firmware-figures-{name}.md"));
    std::fs::write(&path, &md).expect("write the figures");
    println!("{md}(also in {})", path.display());
}

const PROGRAM1: &str = "paper-program1.scene";
const PINHOLE: &str = "pinhole-shapes.scene";

/// Program 1 through a pinhole (its text and a `radius 0` line): the speed floors.
fn program1_pinhole(board: &str) -> &'static str {
    let text = std::fs::read_to_string(scene(PROGRAM1)).unwrap();
    // One file a board: the boards' tests run side by side.
    let path = tmp(&format!("paper-program1-pinhole-{board}.scene"));
    std::fs::write(&path, format!("{text}\nradius 0\n")).unwrap();
    path.to_str().unwrap().to_string().leak()
}

/// The micro:bit's flash floor for the default build (Program 1 baked at
/// its defaults, 160x120): 40 KiB of .text + .rodata + .data.
const MICROBIT_FLASH: u64 = 40 * 1024;

/// The micro:bit's ceiling for Program 1 through a pinhole, instructions a
/// pixel at 160x120: 5,684 measured (BENCHMARKS.md) with a few percent for
/// toolchain drift. The build is for size (firmware/Cargo.toml's `microbit`
/// profile, the default build held to 40 KiB of flash), with the Cortex-M0's
/// products, bit counts, word reciprocal and square root in Thumb-1
/// (src/number/thumb1.rs) and its divisions in one out-of-line copy each
/// (src/number/wide.rs); the exact retakes of docs/fixed-point.md run on
/// every board.
const MICROBIT_PINHOLE: u64 = 6000;

/// Program 1's adaptive frame at `width` x `height` and `samples` on the
/// host: its stop rule (the pre-pass in `Renderer::new`), checked to be
/// at work (pixels stop at different counts).
fn program1_stop_rule(width: u32, height: u32, samples: Option<u32>) -> lensray::StopRule {
    let scene = load_scene::<I16F16>(&scene(PROGRAM1)).unwrap();
    let r = lensray::Renderer::new_with_samples(&scene, width, height, samples);
    let rule = r
        .stop_rule()
        .unwrap_or_else(|| panic!("Program 1 at {width}x{height}, {samples:?} samples: no stop rule"));
    let counts: std::collections::BTreeSet<u32> = (0..height)
        .step_by(3)
        .flat_map(|y| (0..width).step_by(3).map(move |x| (x, y)))
        .map(|(x, y)| r.pixel_rays(x, y).1)
        .collect();
    assert!(counts.len() > 1, "every pixel cast {counts:?} rays");
    rule
}

#[test]
#[ignore = "needs qemu-system-arm and thumbv6m-none-eabi; run by scripts/firmware-tests.sh"]
fn microbit_renders_bit_for_bit_in_16k_of_ram() {
    let program1_pinhole = program1_pinhole("microbit");
    let run = |scene, width, height, samples, float| Run {
        board: "microbit",
        scene,
        width,
        height,
        samples,
        float,
        soft_sqrt: false,
    };
    // The default build first: Program 1 at 160x120 and its own `point` 70,
    // stratified and adaptive, the stop rule baked in.
    program1_stop_rule(160, 120, None);
    let runs = [
        run(PROGRAM1, 160, 120, None, false),
        run(PINHOLE, 160, 120, None, false),
        // f32 in software (no FPU): the same image as the host's f32 render.
        run(PROGRAM1, 160, 120, Some(4), true),
        run(program1_pinhole, 160, 120, None, false),
        run(PROGRAM1, 160, 120, Some(4), false),
        // Too few samples for two pilots: no threshold, plain samples as the host has them.
        run(PROGRAM1, 64, 48, Some(2), false),
    ];
    let outcomes: Vec<Outcome> = runs.iter().map(emulate_and_compare).collect();
    for o in &outcomes {
        // The micro:bit's own 16 KiB, statics and stack together.
        assert_eq!(o.get("ram"), 16 * 1024);
        assert!(o.get("flash") <= 256 * 1024);
        assert_eq!(o.report.get("scene_form").map(String::as_str), Some("baked"));
    }
    // Baked Program 1 at its defaults: statics and the deepest stack in 8 KiB.
    let ram = outcomes[0].get("static_ram") + outcomes[0].get("peak_stack");
    assert!(ram <= 8 * 1024, "Program 1 baked needs {ram} bytes of RAM");
    // Baked Program 1 at its defaults (the default build), .text + .rodata +
    // .data (the report's `flash`): at most 40 KiB.
    let flash = outcomes[0].get("flash");
    assert!(
        flash <= MICROBIT_FLASH,
        "Program 1 baked needs {flash} bytes of flash (floor {MICROBIT_FLASH})"
    );
    // Program 1's pinhole count (exact under -icount, so no wall clock is
    // involved) at most MICROBIT_PINHOLE instructions a pixel.
    let pinhole = outcomes[3].get("per_pixel");
    assert!(
        pinhole <= MICROBIT_PINHOLE,
        "Program 1 pinhole takes {pinhole} instructions a pixel (floor {MICROBIT_PINHOLE})"
    );
    assert_eq!(outcomes[3].get("rays"), 1);
    assert_eq!(outcomes[1].get("rays"), 1);
    record("microbit", &runs.iter().zip(&outcomes).collect::<Vec<_>>());
}

/// Every board renders Program 1 at its defaults (`point` 70, stratified,
/// adaptive: the pre-pass's stop rule at work) exactly as the host does:
/// one code path, no board left out. The micro:bit's default build at
/// 160x120 is in its own test above; here 64x48, on every QEMU board, in
/// Q16.16, and in f32 on the FPU board.
#[test]
#[ignore = "needs qemu-system-arm, qemu-system-riscv32 and the four targets; run by scripts/firmware-tests.sh"]
fn every_board_renders_the_hosts_image_at_the_scenes_defaults() {
    let (w, h) = (64, 48);
    program1_stop_rule(w, h, None);
    let mut rows = Vec::new();
    for (board, float) in [
        ("microbit", false),
        ("mps2-an385", false),
        ("mps2-an386", false),
        ("mps2-an386", true),
        ("sifive-e", false),
    ] {
        let run = Run {
            board,
            scene: PROGRAM1,
            width: w,
            height: h,
            samples: None,
            float,
            soft_sqrt: false,
        };
        let o = emulate_and_compare(&run);
        rows.push((run, o));
    }
    record("defaults", &rows.iter().map(|(r, o)| (r, o)).collect::<Vec<_>>());
}

#[test]
#[ignore = "needs qemu-system-arm and thumbv7em-none-eabihf; run by scripts/firmware-tests.sh"]
fn mps2_an386_renders_bit_for_bit_in_q16_and_f32() {
    let run = |scene, samples, float, soft_sqrt| Run {
        board: "mps2-an386",
        scene,
        width: 160,
        height: 120,
        samples,
        float,
        soft_sqrt,
    };
    let runs = [
        run(PROGRAM1, Some(4), false, false),
        run(PINHOLE, None, false, false),
        run(PROGRAM1, Some(4), true, false),
        run(PROGRAM1, Some(4), true, true),
    ];
    let outcomes: Vec<Outcome> = runs.iter().map(emulate_and_compare).collect();
    // The FPU's square root is in use (not libm's, whose image is the same):
    // the frame takes fewer instructions with it.
    assert_eq!(
        outcomes[2].report.get("f32_sqrt").map(String::as_str),
        Some("vsqrt.f32")
    );
    assert_eq!(outcomes[3].report.get("f32_sqrt").map(String::as_str), Some("libm"));
    assert!(
        outcomes[2].get("frame") < outcomes[3].get("frame"),
        "vsqrt.f32 {} vs libm {} instructions",
        outcomes[2].get("frame"),
        outcomes[3].get("frame")
    );
    assert_eq!(outcomes[2].image, outcomes[3].image);
    record("mps2-an386", &runs.iter().zip(&outcomes).collect::<Vec<_>>());
}

/// Scenes from the fuzzer's grammar (seeded) that both number types accept
/// and that are not blank at 32x24: scenes no one picked by hand, written
/// to files for `lensray emulate`.
fn unseen_scenes(seed: u64, count: usize) -> Vec<&'static str> {
    use lensray::Scene;
    use lensray_testkit::fuzz::{scene_from_grammar, Rng};
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    while out.len() < count {
        let text = scene_from_grammar(&mut rng);
        let (Ok(q), Ok(_)) = (Scene::<I16F16>::parse_bytes(&text), Scene::<f32>::parse_bytes(&text)) else {
            continue;
        };
        let img = render_image(&q, 32, 24, Some(2), &|| {});
        if img.pixels.iter().all(|p| *p == img.pixels[0]) {
            continue;
        }
        let path = tmp(&format!("unseen-{seed}-{}.scene", out.len()));
        std::fs::write(&path, &text).unwrap();
        out.push(&*Box::leak(path.to_string_lossy().into_owned().into_boxed_str()));
    }
    out
}

/// Program 1 (4 rays) and pinhole-shapes at 160x120 in Q16.16 and f32,
/// Program 1 through a pinhole in Q16.16 (held to `pinhole_floor`
/// instructions a pixel, the board's floor), then `count` small
/// scenes never seen (from `seed`, 2 rays, alternating number types), all bit
/// for bit on `board`; the outcomes in that order, recorded.
fn bit_for_bit_on(board: &'static str, seed: u64, count: usize, pinhole_floor: u64) -> Vec<Outcome> {
    let run = |scene, width, height, samples, float| Run {
        board,
        scene,
        width,
        height,
        samples,
        float,
        soft_sqrt: false,
    };
    let mut runs = vec![
        run(PROGRAM1, 160, 120, Some(4), false),
        run(PINHOLE, 160, 120, None, false),
        run(PROGRAM1, 160, 120, Some(4), true),
        run(PINHOLE, 160, 120, None, true),
        run(program1_pinhole(board), 160, 120, None, false),
    ];
    for (k, s) in unseen_scenes(seed, count).into_iter().enumerate() {
        runs.push(run(s, 48, 36, Some(2), k % 2 == 1));
    }
    let outcomes: Vec<Outcome> = runs.iter().map(emulate_and_compare).collect();
    assert_eq!(outcomes[1].get("rays"), 1);
    // Exact under -icount, so no wall clock is involved.
    let pinhole = outcomes[4].get("per_pixel");
    assert!(
        pinhole <= pinhole_floor,
        "{board}: Program 1 pinhole takes {pinhole} instructions a pixel (floor {pinhole_floor})"
    );
    record(board, &runs.iter().zip(&outcomes).collect::<Vec<_>>());
    outcomes
}

#[test]
#[ignore = "needs qemu-system-arm and thumbv7m-none-eabi; run by scripts/firmware-tests.sh"]
fn mps2_an385_cortex_m3_renders_bit_for_bit_in_q16_and_f32() {
    // At most 3,000 instructions a pixel on the Cortex-M3, the speed
    // issue's floor (2,541 measured).
    bit_for_bit_on("mps2-an385", 15, 3, 3000);
}

#[test]
#[ignore = "needs qemu-system-riscv32 and riscv32imac-unknown-none-elf; run by scripts/firmware-tests.sh"]
fn sifive_e_rv32_renders_bit_for_bit_in_q16_and_f32() {
    // Scenes never seen from another seed than the Cortex-M3's.
    // At most 3,800 instructions a pixel on RV32, the speed issue's floor
    // (3,294 measured).
    for o in bit_for_bit_on("sifive-e", 32, 4, 3800) {
        // The FE310's own 16 KiB of data RAM, statics and stack together.
        assert_eq!(o.get("ram"), 16 * 1024);
        assert_eq!(o.report.get("scene_form").map(String::as_str), Some("baked"));
    }
}

/// Program 1 through a pinhole at 8x6 in Q16.16 on `board`: the quickest
/// run, for the tests of what happens around the render.
fn tiny_pinhole(board: &'static str) -> Run {
    Run {
        board,
        scene: PINHOLE,
        width: 8,
        height: 6,
        samples: None,
        float: false,
        soft_sqrt: false,
    }
}

/// `lensray emulate` with a deliberate failure built in (`LENSRAY_FAULT`).
fn emulate_fault(board: &str, fault: &str) -> Output {
    let board = match board {
        "microbit" => "microbit",
        "sifive-e" => "sifive-e",
        _ => "mps2-an386",
    };
    let run = tiny_pinhole(board);
    let out = tmp(&format!("fault-{board}-{fault}.bmp"));
    let _ = std::fs::remove_file(&out);
    let o = emulate_cmd(&run, &out)
        .env("LENSRAY_FAULT", fault)
        .args(["--timeout", "120"])
        .output()
        .expect("run lensray emulate");
    assert!(!out.exists(), "an image was written for a failed run");
    o
}

/// The Cortex-M0's Thumb-1 kernels (the library's `number::thumb1`) compute
/// what the portable Rust computes, on the board: edge values and 100,000
/// pseudo-random pairs of every magnitude (exit status 5 names the first
/// pair that differs).
#[test]
#[ignore = "needs qemu-system-arm and thumbv6m-none-eabi; run by scripts/firmware-tests.sh"]
fn microbit_thumb1_kernels_match_the_portable_rust() {
    let run = tiny_pinhole("microbit");
    let out = tmp("thumb1-kernels.bmp");
    let o = emulate_cmd(&run, &out)
        .env("LENSRAY_CHECK", "kernels")
        .output()
        .expect("run lensray emulate");
    assert!(o.status.success(), "{}", show(&o));
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(
        said.contains("kernels match the portable Rust on 100000 pairs"),
        "{}",
        show(&o)
    );
}

#[test]
#[ignore = "needs qemu-system-arm and both thumb targets; run by scripts/firmware-tests.sh"]
fn a_panic_or_a_hardfault_exits_non_zero_instead_of_hanging() {
    for (board, fault, status, says) in [
        (
            "microbit",
            "panic",
            "exit status 101",
            "failing on purpose (LENSRAY_FAULT=panic)",
        ),
        ("microbit", "hardfault", "exit status 3", "HardFault at pc"),
        ("mps2-an386", "hardfault", "exit status 3", "HardFault at pc"),
        // RISC-V: an illegal instruction traps to the start-up's handler.
        (
            "sifive-e",
            "hardfault",
            "exit status 3",
            "HardFault (trap, mcause 2) at pc",
        ),
        ("sifive-e", "panic", "exit status 101", "failing on purpose"),
    ] {
        let o = emulate_fault(board, fault);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{board} {fault}:\n{}", show(&o));
        assert!(
            err.contains(status) && err.contains(says),
            "{board} {fault}:\n{}",
            show(&o)
        );
    }
}

#[test]
#[ignore = "needs qemu-system-arm and thumbv6m-none-eabi; run by scripts/firmware-tests.sh"]
fn a_run_past_its_timeout_is_stopped() {
    // Program 1 with its own 70 rays a pixel: tens of seconds of QEMU, stopped after 1.
    let run = Run {
        board: "microbit",
        scene: PROGRAM1,
        width: 160,
        height: 120,
        samples: None,
        float: false,
        soft_sqrt: false,
    };
    let out = tmp("timeout.bmp");
    let _ = std::fs::remove_file(&out);
    let o = emulate_cmd(&run, &out).args(["--timeout", "1"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", show(&o));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("did not finish within 1 s"),
        "{}",
        show(&o)
    );
    assert!(!out.exists());
}

#[test]
fn a_bad_scene_fails_like_render_before_any_build() {
    let dir = tmp("emulate-bad-scene");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.scene");
    std::fs::write(&bad, "width 10\nfocal_length 9\nobject sphere\n").unwrap();
    let out = dir.join("bad.bmp");
    let render = Command::new(LENSRAY)
        .arg("render")
        .arg(&bad)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    // No firmware crate where it is looked for: a build attempt would fail differently.
    let emulate = Command::new(LENSRAY)
        .arg("emulate")
        .arg(&bad)
        .args(["--board", "microbit", "-o"])
        .arg(&out)
        .env("LENSRAY_FIRMWARE_DIR", dir.join("no-firmware-here"))
        .output()
        .unwrap();
    assert_eq!(emulate.status.code(), Some(2), "{}", show(&emulate));
    let (r, e) = (
        String::from_utf8_lossy(&render.stderr),
        String::from_utf8_lossy(&emulate.stderr),
    );
    assert!(e.starts_with(&format!("{}:2: ", bad.display())), "{}", show(&emulate));
    assert_eq!(r, e, "render and emulate report the bad scene differently");
    assert!(!out.exists());

    // Unknown boards and missing boards are refused too, also before any build.
    for args in [&["--board", "esp32"][..], &[][..]] {
        let o = Command::new(LENSRAY)
            .arg("emulate")
            .arg(scene(PINHOLE))
            .args(args)
            .env("LENSRAY_FIRMWARE_DIR", dir.join("no-firmware-here"))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{}", show(&o));
        assert!(String::from_utf8_lossy(&o.stderr).contains("--board"), "{}", show(&o));
    }
}

/// `camera-features` (a six-bladed aperture, its own `point` 320,
/// stratified and adaptive) at 40x30 on the Cortex-M3, in Q16.16 and f32:
/// each image the host's, bit for bit.
#[test]
#[ignore = "needs qemu-system-arm and thumbv7m-none-eabi; run by scripts/firmware-tests.sh"]
fn camera_features_at_its_defaults_runs_bit_for_bit_on_the_cortex_m3() {
    let (w, h) = (40, 30);
    let text = std::fs::read_to_string(scene("camera-features.scene")).unwrap();
    let parsed = lensray::Scene::<I16F16>::parse(&text).unwrap();
    assert!(lensray::Renderer::new(&parsed, w, h).stop_rule().is_some());
    m3_bit_for_bit_in_both_types("camera-features", &text, w, h);
}
/// Scene `text`, saved as `name`, rendered at `w`x`h` on the Cortex-M3 in
/// Q16.16 and in f32: each image the host's, bit for bit.
fn m3_bit_for_bit_in_both_types(name: &str, text: &str, w: u32, h: u32) {
    let path = tmp(&format!("{name}-mps2-an385.scene"));
    std::fs::write(&path, text).unwrap();
    let scene: &'static str = path.to_str().unwrap().to_string().leak();
    for float in [false, true] {
        emulate_and_compare(&Run {
            board: "mps2-an385",
            scene,
            width: w,
            height: h,
            samples: None,
            float,
            soft_sqrt: false,
        });
    }
}
