//! What `lensray emulate` needs besides the scene, and what it says when one
//! is missing: the firmware's sources (a checkout of lensray's repository),
//! the board's emulator (QEMU, or Node.js and the npm package rp2040js for
//! the Pico) and the board's Rust target. Each message names what is missing
//! and the command that gets it. Nothing here builds firmware or needs the
//! network: the checks come before the build.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const LENSRAY: &str = env!("CARGO_BIN_EXE_lensray");

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-fig8-pinhole.scene")
}

/// A fresh directory of its own under cargo's target tmp directory.
fn fresh(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A stand-in for a checkout: `root/firmware/` with the firmware's package
/// name and the Pico emulator's package.json, but nothing installed and no
/// sources (a build there would fail).
fn fake_checkout(root: &Path) -> PathBuf {
    let firmware = root.join("firmware");
    std::fs::create_dir_all(firmware.join("pico/emu")).unwrap();
    std::fs::write(
        firmware.join("Cargo.toml"),
        "[package]\nname = \"lensray-firmware\"\nversion = \"0.1.0\"\nedition = \"2021\"\n",
    )
    .unwrap();
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../firmware/pico/emu/package.json"),
        firmware.join("pico/emu/package.json"),
    )
    .unwrap();
    firmware
}

fn emulate(board: &str, cwd: &Path) -> Command {
    let mut cmd = Command::new(LENSRAY);
    cmd.arg("emulate")
        .arg(scene())
        .args(["--board", board, "-o"])
        .arg(cwd.join("out.bmp"))
        .current_dir(cwd)
        .env_remove("LENSRAY_FIRMWARE_DIR");
    cmd
}

/// Its stderr, after checking it failed with status 2 and wrote no image.
fn fails(o: Output, cwd: &Path) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(
        o.status.code(),
        Some(2),
        "stdout:\n{}\nstderr:\n{err}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(!cwd.join("out.bmp").exists(), "{err}");
    err
}

#[test]
fn a_firmware_dir_that_is_not_the_firmware_is_named_with_the_variable() {
    let dir = fresh("needs-bad-firmware-dir");
    let o = emulate("microbit", &dir)
        .env("LENSRAY_FIRMWARE_DIR", dir.join("nothing-here"))
        .output()
        .unwrap();
    let err = fails(o, &dir);
    assert!(err.starts_with("lensray: LENSRAY_FIRMWARE_DIR="), "{err}");
    assert!(err.contains(&dir.join("nothing-here").display().to_string()), "{err}");
    assert!(err.contains("firmware/ directory of a checkout"), "{err}");
}

#[test]
fn the_checkout_is_found_above_the_working_directory() {
    let root = fresh("needs-checkout-above");
    let firmware = fake_checkout(&root);
    let deep = root.join("scenes/mine");
    std::fs::create_dir_all(&deep).unwrap();
    // Whatever else happens (a tool missing, or the stand-in failing to
    // build), the firmware it names is the stand-in's, found from below.
    let err = fails(emulate("mps2-an385", &deep).output().unwrap(), &deep);
    assert!(err.contains(&firmware.display().to_string()), "{err}");
}

#[test]
fn without_an_emulator_on_the_path_it_names_the_package_to_install() {
    let dir = fresh("needs-empty-path");
    let empty = fresh("needs-empty-path-bin");
    for (board, program, package) in [
        ("microbit", "qemu-system-arm", "apt-get install qemu-system-arm"),
        ("sifive-e", "qemu-system-riscv32", "apt-get install qemu-system-misc"),
        ("pico", "node", "apt-get install nodejs npm"),
    ] {
        let o = emulate(board, &dir).env("PATH", &empty).output().unwrap();
        let err = fails(o, &dir);
        assert!(err.contains(&format!("{program} ")), "{board}: {err}");
        assert!(err.contains(package), "{board}: {err}");
        // Every line of the message is lensray's: one error, not a crash.
        assert!(err.starts_with("lensray: "), "{board}: {err}");
    }
}

#[test]
fn the_pico_without_its_npm_package_names_npm_ci_and_where() {
    let root = fresh("needs-pico-npm");
    let firmware = fake_checkout(&root);
    let o = emulate("pico", &root)
        .env("LENSRAY_FIRMWARE_DIR", &firmware)
        .output()
        .unwrap();
    let err = fails(o, &root);
    let emu = firmware.join("pico/emu");
    assert!(err.contains("rp2040js"), "{err}");
    assert!(err.contains(&format!("cd {} && npm ci", emu.display())), "{err}");
}
