//! `lensray emulate`: builds the firmware with a scene embedded, runs it under
//! QEMU, writes the image the board rendered and says what it cost.
//!
//! The scene is checked on the host first, so a bad scene fails with the same
//! `FILE:LINE: message` as `render`, before anything is built. The firmware is
//! built from a checkout of lensray's repository ([`firmware_dir`]: its
//! `firmware/` directory); its build.rs reads the scene, size, samples and
//! number type from `LENSRAY_*` variables, which this command sets. What the
//! run needs besides (the board's Rust target, its emulator, the Pico's npm
//! package) is checked before the build, and whatever is missing is named
//! with the command that installs it ([`missing_tools`]).

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use clap::builder::PossibleValuesParser;
use clap::Args;

use embedded_graphics::pixelcolor::Rgb888;
use lensray::{Scalar, I16F16};
use lensray_host::{encode, load_scene, write_atomic, Format, Image};

use crate::cli::opts::{self, image_size, whole};
use crate::Fail;

/// A board QEMU emulates: its name, Rust target, cargo features and
/// profile, QEMU program and machine arguments. A new board is one more
/// entry in [`BOARDS`].
struct Board {
    name: &'static str,
    /// The core, for the report in words.
    core: &'static str,
    target: &'static str,
    features: &'static str,
    /// The firmware's cargo profile (firmware/Cargo.toml): `microbit`, the
    /// release build compiled for size, for the micro:bit's flash.
    profile: &'static str,
    qemu_program: &'static str,
    qemu: &'static [&'static str],
}

const BOARDS: [Board; 4] = [
    Board {
        name: "microbit",
        core: "Cortex-M0",
        target: "thumbv6m-none-eabi",
        features: "microbit",
        profile: "microbit",
        qemu_program: "qemu-system-arm",
        qemu: &["-machine", "microbit"],
    },
    Board {
        name: "mps2-an385",
        core: "Cortex-M3",
        target: "thumbv7m-none-eabi",
        features: "mps2-an385",
        profile: "release",
        qemu_program: "qemu-system-arm",
        qemu: &["-machine", "mps2-an385", "-cpu", "cortex-m3"],
    },
    Board {
        name: "mps2-an386",
        core: "Cortex-M4F",
        target: "thumbv7em-none-eabihf",
        features: "mps2-an386,hw-sqrt",
        profile: "release",
        qemu_program: "qemu-system-arm",
        qemu: &["-machine", "mps2-an386", "-cpu", "cortex-m4"],
    },
    // 32-bit RISC-V without an FPU (SiFive FE310, rv32imac): the ESP32-C3 / CH32V class.
    Board {
        name: "sifive-e",
        core: "RV32IMAC",
        target: "riscv32imac-unknown-none-elf",
        features: "sifive-e",
        profile: "release",
        qemu_program: "qemu-system-riscv32",
        qemu: &["-machine", "sifive_e"],
    },
];

/// The boards' names: the QEMU boards, then the Pico (rp2040js).
const BOARD_NAMES: [&str; BOARDS.len() + 1] = {
    let mut names = [PICO; BOARDS.len() + 1];
    let mut i = 0;
    while i < BOARDS.len() {
        names[i] = BOARDS[i].name;
        i += 1;
    }
    names
};

/// The board under rp2040js instead of QEMU.
const PICO: &str = "pico";

/// The file the firmware writes its rows to, in QEMU's working directory.
const ROWS_FILE: &str = "lensray-rows.rgb";

/// Image width without `--width`: a small panel's, as a microcontroller renders slowly.
pub(crate) const DEFAULT_WIDTH: u32 = 160;

/// Longest QEMU run before it counts as hung (`--timeout`), in seconds.
const DEFAULT_TIMEOUT: u32 = 3600;

/// Renders a scene on an emulated board and says what it cost
///
/// Builds the firmware with the scene embedded, runs it under QEMU on the board (instruction
/// counting on), writes the image the board rendered and prints its instructions per pixel and
/// memory use. Boards: microbit (Cortex-M0), mps2-an385 (Cortex-M3), mps2-an386 (Cortex-M4F),
/// sifive-e (RV32IMAC, no FPU); pico builds firmware/pico and runs it under rp2040js (Node) with a model of its ST7789 panel,
/// writes what the panel shows (equal to `render --panel rgb565`) and prints cycles a pixel and
/// the frame's seconds at 125 MHz.
///
/// Needs a checkout of lensray's repository (the firmware's sources: its firmware/ directory, found
/// from the working directory upward, else where this lensray was built from, or given by
/// LENSRAY_FIRMWARE_DIR), the board's Rust target (rustup target add), and its emulator:
/// qemu-system-arm, qemu-system-riscv32 for sifive-e, or Node.js and `npm ci` in firmware/pico/emu
/// for pico. Whatever is missing is named, with the command that installs it, before anything is
/// built.
#[derive(Args, Debug)]
pub(crate) struct EmulateArgs {
    /// The scene file (rendered as it is: put `adaptive on` in it for an adaptive render)
    #[arg(value_name = "SCENE")]
    pub(crate) scene: PathBuf,
    /// The board
    #[arg(long, value_name = "BOARD", required = true, value_parser = PossibleValuesParser::new(BOARD_NAMES))]
    board: String,
    /// Output image, .bmp or .png [default: the scene's name, -BOARD.bmp]
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub(crate) out: Option<PathBuf>,
    #[command(flatten)]
    pub(crate) size: opts::Size,
    /// Renders with the f32 reference instead of Q16.16 (QEMU boards)
    #[arg(long)]
    pub(crate) float: bool,
    /// Takes f32 square roots in software even on the FPU board
    #[arg(long)]
    soft_sqrt: bool,
    /// Embeds the scene's text and parses it on the board instead of the scene baked at build time
    #[arg(long)]
    parse_on_device: bool,
    /// Longest run in seconds before it counts as hung (1 to 86400)
    #[arg(long, value_name = "SECONDS", default_value_t = DEFAULT_TIMEOUT, value_parser = whole(1, 86_400))]
    timeout: u32,
}

pub(crate) fn run(o: EmulateArgs) -> Result<(), Fail> {
    let timeout = o.timeout;
    let scene_path = o.scene.as_path();
    if o.board == PICO {
        return crate::cli::emulate_pico::run(&o, scene_path, o.soft_sqrt, Duration::from_secs(timeout as u64));
    }
    let board = BOARDS
        .iter()
        .find(|b| b.name == o.board)
        .ok_or_else(|| Fail(format!("--board {}: unknown board", o.board)))?;
    let (soft_sqrt, parse_on_device) = (o.soft_sqrt, o.parse_on_device);

    // The scene first: a bad one fails here, exactly as `render` reports it.
    let aspect = if o.float {
        load_scene::<f32>(scene_path)?.camera.aspect_ratio
    } else {
        load_scene::<I16F16>(scene_path)?.camera.aspect_ratio
    };
    let (width, height) = image_size(&o.size, DEFAULT_WIDTH, aspect)?;
    let (out, format) = output_path(o.out.as_deref(), scene_path, board.name)?;
    let scene_abs = std::fs::canonicalize(scene_path).map_err(|e| Fail(format!("{}: {e}", scene_path.display())))?;
    let firmware = firmware_dir()?;
    missing_tools(&firmware, board.target, &[Tool::Qemu(board.qemu_program)])?;

    let work = WorkDir::new()?;
    let build = Build {
        firmware: &firmware,
        board,
        scene: &scene_abs,
        width,
        height,
        samples: o.size.samples,
        float: o.float,
        soft_sqrt,
        parse_on_device,
    };
    let elf = build.run(&work.0)?;

    eprintln!("running on {} under QEMU", board.name);
    let output = run_qemu(board, &elf, &work.0, Duration::from_secs(timeout as u64))?;
    let report = checked_report(board, &output)?;
    let rows = std::fs::read(work.0.join(ROWS_FILE))
        .map_err(|e| Fail(format!("the firmware's rows ({ROWS_FILE}) cannot be read: {e}")))?;
    let img = image_from_rows(&rows, width, height)?;

    let scene_name = scene_path.file_name().unwrap_or_default().to_string_lossy();
    print!("{}", describe(board, &scene_name, &report)?);
    for line in output.lines() {
        println!("{line}");
    }
    let frame: u64 = report_value(&report, "frame")?;
    let per_pixel: u64 = report_value(&report, "per_pixel")?;
    let pixels = width as u64 * height as u64;
    println!(
        "{per_pixel} instructions per pixel on {} ({} instructions a frame of {width}x{height}; {:.2} pixels per million instructions)",
        board.name,
        frame,
        pixels as f64 * 1e6 / frame.max(1) as f64
    );
    let bytes = encode(&img, format)?;
    write_atomic(&out, &bytes).map_err(|e| Fail(format!("{}: cannot write: {e}", out.display())))?;
    let kind = if o.float { f32::NAME } else { I16F16::NAME };
    eprintln!(
        "wrote {} ({width}x{height}, {kind}, rendered on {})",
        out.display(),
        board.name
    );
    Ok(())
}

/// The output image's path (`out`, else SCENE-BOARD.bmp here) and format,
/// refused if it names neither BMP nor PNG, or a directory.
pub(crate) fn output_path(out: Option<&Path>, scene_path: &Path, board: &str) -> Result<(PathBuf, Format), Fail> {
    let out = match out {
        Some(p) => p.to_path_buf(),
        None => {
            let stem = scene_path.file_stem().ok_or("the scene path has no file name")?;
            PathBuf::from(format!("{}-{board}.bmp", stem.to_string_lossy()))
        }
    };
    let format = Format::of(&out).ok_or_else(|| Fail(format!("{}: output must end in .bmp or .png", out.display())))?;
    if out.is_dir() {
        return Err(Fail(format!("{}: is a directory", out.display())));
    }
    Ok((out, format))
}

/// The firmware's report from what it said on `board`; an error if there is
/// none, or if its stack ran into the statics.
fn checked_report(board: &Board, output: &str) -> Result<BTreeMap<String, String>, Fail> {
    let report = parse_report(output).ok_or_else(|| {
        Fail(format!(
            "the firmware on {} finished without its report; it said:\n{output}",
            board.name
        ))
    })?;
    if report_value::<u32>(&report, "stack_overflow")? != 0 {
        return Err(Fail(format!(
            "the stack on {} ran into the statics, so the image may be wrong; a smaller --width needs less. It said:\n{output}",
            board.name
        )));
    }
    Ok(report)
}

/// A private directory for one run: the firmware's copy and QEMU's working
/// directory (the rows file lands there). Removed when dropped.
pub(crate) struct WorkDir(pub(crate) PathBuf);

impl WorkDir {
    pub(crate) fn new() -> Result<WorkDir, Fail> {
        static N: AtomicU32 = AtomicU32::new(0);
        let dir = std::env::temp_dir().join(format!(
            "lensray-emulate-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir).map_err(|e| Fail(format!("{}: {e}", dir.display())))?;
        Ok(WorkDir(dir))
    }
}

impl Drop for WorkDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// What to build the firmware with.
struct Build<'a> {
    firmware: &'a Path,
    board: &'a Board,
    scene: &'a Path,
    width: u32,
    height: u32,
    samples: Option<u32>,
    float: bool,
    soft_sqrt: bool,
    parse_on_device: bool,
}

impl Build<'_> {
    /// Builds the firmware and copies its ELF into `dir`, under a lock: runs
    /// of this command in parallel share one target directory.
    fn run(&self, dir: &Path) -> Result<PathBuf, Fail> {
        let firmware = self.firmware;
        let (target_dir, lock) = lock_target_dir(firmware)?;

        let mut features = if self.soft_sqrt {
            self.board.features.replace(",hw-sqrt", "")
        } else {
            self.board.features.to_string()
        };
        if self.parse_on_device {
            features += ",parse-on-device";
        }
        eprintln!(
            "building the firmware for {} ({}) in {}",
            self.board.name,
            self.board.target,
            firmware.display()
        );
        let mut cmd = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
        cmd.current_dir(firmware)
            .args([
                "build",
                "--profile",
                self.board.profile,
                "--target",
                self.board.target,
                "--features",
                &features,
            ])
            .arg("--target-dir")
            .arg(&target_dir)
            .env("LENSRAY_SCENE", self.scene)
            .env("LENSRAY_WIDTH", self.width.to_string())
            .env("LENSRAY_HEIGHT", self.height.to_string())
            .env("LENSRAY_FLOAT", if self.float { "1" } else { "0" })
            // These would replace the firmware's own flags and targets.
            .env_remove("RUSTFLAGS")
            .env_remove("CARGO_ENCODED_RUSTFLAGS")
            .env_remove("CARGO_BUILD_RUSTFLAGS")
            .env_remove("CARGO_BUILD_TARGET")
            .stdin(Stdio::null());
        match self.samples {
            Some(n) => cmd.env("LENSRAY_SAMPLES", n.to_string()),
            None => cmd.env_remove("LENSRAY_SAMPLES"),
        };
        let built = cmd
            .output()
            .map_err(|e| Fail(format!("cannot run cargo to build the firmware: {e}")))?;
        if !built.status.success() {
            return Err(Fail(format!(
                "building the firmware failed:\n{}",
                String::from_utf8_lossy(&built.stderr).trim_end()
            )));
        }
        let elf = target_dir
            .join(self.board.target)
            .join(self.board.profile)
            .join("lensray-firmware");
        let copy = dir.join("lensray-firmware.elf");
        std::fs::copy(&elf, &copy).map_err(|e| Fail(format!("{}: {e}", elf.display())))?;
        drop(lock);
        Ok(copy)
    }
}

/// The firmware's target directory, created where missing, and a lock on it
/// held until the file is dropped: runs in parallel build one at a time.
pub(crate) fn lock_target_dir(firmware: &Path) -> Result<(PathBuf, std::fs::File), Fail> {
    let target_dir = firmware.join("target");
    std::fs::create_dir_all(&target_dir).map_err(|e| Fail(format!("{}: {e}", target_dir.display())))?;
    let lock_path = target_dir.join("lensray-emulate.lock");
    let lock = std::fs::File::create(&lock_path).map_err(|e| Fail(format!("{}: {e}", lock_path.display())))?;
    lock.lock()
        .map_err(|e| Fail(format!("{}: cannot lock: {e}", lock_path.display())))?;
    Ok((target_dir, lock))
}

/// The firmware crate (the `firmware/` directory of a checkout of lensray's
/// repository), the first of: `$LENSRAY_FIRMWARE_DIR`; the `firmware/` of
/// the working directory or of the nearest directory above it that has one
/// (running inside a checkout); the `firmware/` of the checkout this program
/// was built from, while it is still there (`cargo install --path host-tests`
/// builds from one).
pub(crate) fn firmware_dir() -> Result<PathBuf, Fail> {
    if let Some(dir) = std::env::var_os("LENSRAY_FIRMWARE_DIR") {
        let dir = PathBuf::from(dir);
        if is_firmware(&dir) {
            return Ok(dir);
        }
        return Err(Fail(format!(
            "LENSRAY_FIRMWARE_DIR={}: not lensray's firmware/ directory (it has no Cargo.toml of lensray-firmware); \
             point it at the firmware/ directory of a checkout of lensray's repository",
            dir.display()
        )));
    }
    let cwd = std::env::current_dir().ok();
    if let Some(dir) = cwd
        .iter()
        .flat_map(|c| c.ancestors())
        .map(|d| d.join("firmware"))
        .find(|d| is_firmware(d))
    {
        return Ok(dir);
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../firmware");
    if is_firmware(&built) {
        return Ok(std::fs::canonicalize(&built).unwrap_or(built));
    }
    Err(Fail(format!(
        "emulate builds the firmware from a checkout of lensray's repository, and there is none here \
         ({} and the directories above it have no firmware/ of lensray's) nor where this lensray was built \
         ({}): run it inside a checkout, or set LENSRAY_FIRMWARE_DIR to a checkout's firmware/ directory",
        cwd.as_deref()
            .map_or_else(|| "the working directory".into(), |c| c.display().to_string()),
        built.display()
    )))
}

/// Whether `dir` holds the firmware crate.
fn is_firmware(dir: &Path) -> bool {
    std::fs::read_to_string(dir.join("Cargo.toml"))
        .is_ok_and(|t| t.lines().any(|l| l.replace(' ', "") == "name=\"lensray-firmware\""))
}

/// What a board's run needs besides Cargo and the Rust target.
pub(crate) enum Tool<'a> {
    /// A QEMU program.
    Qemu(&'a str),
    /// Node.js, and rp2040js installed by npm in this directory (the Pico's emulator).
    Rp2040js(&'a Path),
}

/// Checks what building the firmware for `target` and running it need: the
/// Rust target (as the toolchain building in `firmware` sees it) and each of
/// `tools`. An error lists everything missing, each with the command that
/// installs it.
pub(crate) fn missing_tools(firmware: &Path, target: &str, tools: &[Tool]) -> Result<(), Fail> {
    let mut missing = Vec::new();
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let sysroot = Command::new(&rustc)
        .args(["--print", "sysroot"])
        .current_dir(firmware)
        .stdin(Stdio::null())
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()));
    match sysroot {
        None => missing.push("rustc does not run: install Rust (https://rustup.rs)".to_string()),
        Some(root) if !root.join("lib/rustlib").join(target).is_dir() => missing.push(format!(
            "the Rust target {target} is not installed: rustup target add {target}"
        )),
        Some(_) => {}
    }
    for tool in tools {
        match tool {
            Tool::Qemu(program) => {
                if !runs(program) {
                    // Debian puts qemu-system-riscv32 in qemu-system-misc.
                    let package = if *program == "qemu-system-arm" {
                        "qemu-system-arm"
                    } else {
                        "qemu-system-misc"
                    };
                    missing.push(format!(
                        "{program} (QEMU) is missing: sudo apt-get install {package} on Debian or Ubuntu, \
                         brew install qemu on macOS"
                    ));
                }
            }
            Tool::Rp2040js(emu) => {
                if !runs("node") {
                    missing.push(
                        "node (Node.js 18 or later, for the Pico's emulator) is missing: \
                         sudo apt-get install nodejs npm on Debian or Ubuntu, brew install node on macOS"
                            .to_string(),
                    );
                }
                if !emu.join("node_modules/rp2040js/package.json").is_file() {
                    missing.push(format!(
                        "rp2040js (the Pico's emulator, an npm package) is not installed: cd {} && npm ci",
                        emu.display()
                    ));
                }
            }
        }
    }
    if missing.is_empty() {
        Ok(())
    } else {
        Err(Fail(format!(
            "building and running the firmware of {} needs what is missing here: {}",
            firmware.display(),
            missing.join("; ")
        )))
    }
}

/// Whether `program --version` runs.
fn runs(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok()
}

/// Runs `cmd` with its output piped, killed after `timeout`: its exit status
/// (`None` when it was killed), its stdout, and all it printed (stdout then
/// stderr) for an error message.
pub(crate) fn run_bounded(
    cmd: &mut Command,
    program: &str,
    timeout: Duration,
) -> Result<(Option<ExitStatus>, String, String), Fail> {
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| Fail(format!("cannot run {program}: {e}")))?;
    let mut stdout = child.stdout.take().ok_or("no stdout from the emulator")?;
    let mut stderr = child.stderr.take().ok_or("no stderr from the emulator")?;
    // Pipes drained on their own threads, so a chatty emulator never blocks.
    let out_reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stdout.read_to_string(&mut s);
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child
            .try_wait()
            .map_err(|e| Fail(format!("waiting for {program}: {e}")))?
        {
            break Some(status);
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let out = out_reader.join().unwrap_or_default();
    let err = err_reader.join().unwrap_or_default();
    let said = format!("{out}{err}").trim_end().to_string();
    Ok((status, out, said))
}

/// Runs the ELF under QEMU in `dir` with instruction counting; its console
/// output, or an error if it fails, exits non-zero or outlives `timeout`.
fn run_qemu(board: &Board, elf: &Path, dir: &Path, timeout: Duration) -> Result<String, Fail> {
    let mut cmd = Command::new(board.qemu_program);
    cmd.args(board.qemu)
        .args(["-nographic", "-monitor", "none", "-serial", "null"])
        .args(["-semihosting-config", "enable=on,target=native", "-icount", "shift=0"])
        .arg("-kernel")
        .arg(elf)
        .current_dir(dir);
    let (status, out, said) = run_bounded(&mut cmd, board.qemu_program, timeout)?;
    match status {
        None => Err(Fail(format!(
            "the firmware on {} did not finish within {} s (--timeout); it said:\n{said}",
            board.name,
            timeout.as_secs()
        ))),
        Some(s) if !s.success() => {
            // A stack overflow faults, and its fault handler faults again (a lockup).
            let hint = if said.contains("HardFault") || said.contains("Lockup") {
                "\n(a stack overflow ends like this; a smaller --width needs less stack)"
            } else {
                ""
            };
            Err(Fail(format!(
                "the firmware on {} failed ({}); it said:\n{said}{hint}",
                board.name,
                match s.code() {
                    Some(c) => format!("exit status {c}"),
                    None => "killed by a signal".to_string(),
                }
            )))
        }
        Some(_) => Ok(out),
    }
}

/// The firmware's `report key=value ...` line, as a map.
fn parse_report(output: &str) -> Option<BTreeMap<String, String>> {
    let line = output.lines().find_map(|l| l.strip_prefix("report "))?;
    Some(
        line.split_whitespace()
            .filter_map(|kv| kv.split_once('='))
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
    )
}

/// The report in words (the firmware writes only its `report` line: the
/// micro:bit's flash is dearer than the host's).
fn describe(board: &Board, scene_name: &str, r: &BTreeMap<String, String>) -> Result<String, Fail> {
    let text = |key: &str| r.get(key).map(String::as_str).unwrap_or("?");
    let num = |key: &str| report_value::<u64>(r, key);
    let number = text("number");
    let sqrt = if number == "f32" {
        format!(" (sqrt: {})", text("f32_sqrt"))
    } else {
        String::new()
    };
    let overflow = if num("stack_overflow")? != 0 {
        " (or more: the paint is gone)"
    } else {
        ""
    };
    Ok(format!(
        "board {} ({}), {number}{sqrt}, scene {scene_name} ({}), {}x{}, {} rays per pixel\n\
         set-up: {} instructions\n\
         frame: {} instructions, {} instructions per pixel\n\
         memory: flash {} bytes, static RAM {} bytes, peak stack {} bytes{overflow}, RAM {} bytes\n",
        board.name,
        board.core,
        text("scene_form"),
        num("width")?,
        num("height")?,
        num("rays")?,
        num("setup")?,
        num("frame")?,
        num("per_pixel")?,
        num("flash")?,
        num("static_ram")?,
        num("peak_stack")?,
        num("ram")?,
    ))
}

fn report_value<T: std::str::FromStr>(report: &BTreeMap<String, String>, key: &str) -> Result<T, Fail> {
    report
        .get(key)
        .and_then(|v| v.parse().ok())
        .ok_or_else(|| Fail(format!("the firmware's report has no valid {key}")))
}

/// Packed RGB rows, top to bottom, as an image of the expected size.
fn image_from_rows(rows: &[u8], width: u32, height: u32) -> Result<Image, Fail> {
    let want = width as usize * height as usize * 3;
    if rows.len() != want {
        return Err(Fail(format!(
            "the firmware sent {} bytes of rows, not {want} ({width}x{height} RGB)",
            rows.len()
        )));
    }
    Ok(Image {
        width,
        height,
        pixels: rows.chunks_exact(3).map(|p| Rgb888::new(p[0], p[1], p[2])).collect(),
    })
}
