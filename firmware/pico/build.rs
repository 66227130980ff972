//! Puts the Pico's memory map (memory.x, beside this file) on the linker's
//! search path and links with cortex-m-rt's link.x. Link arguments set here
//! survive a RUSTFLAGS variable, unlike those of .cargo/config.toml.

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let map = manifest.join("memory.x");
    fs::copy(&map, out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rerun-if-changed={}", map.display());
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
}
