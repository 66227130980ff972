//! Tells the library whether it is built for Cortex-M0/M0+ (thumbv6m): that
//! core multiplies 32 by 32 bits into 32 only, and the library then forms
//! 64-bit products from 16-bit halves instead of calling a 64×64 routine.
//! Cores with a 32 / 32 divide and no 64-bit one (Cortex-M3/M4, RV32IM) get
//! `lensray_hwdiv`: divisions by a word use that instruction.

fn main() {
    println!("cargo:rustc-check-cfg=cfg(lensray_v6m)");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rustc-check-cfg=cfg(lensray_hwdiv)");
    let target = std::env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv6m") {
        println!("cargo:rustc-cfg=lensray_v6m");
    }
    // 32-bit cores with a 32 / 32 divide but no 64-bit one: Cortex-M3/M4/M7, RV32IM.
    let rv32m = target.starts_with("riscv32")
        && target["riscv32".len()..]
            .split('-')
            .next()
            .is_some_and(|e| e.contains('m'));
    if target.starts_with("thumbv7") || target.starts_with("thumbv8m.main") || rv32m {
        println!("cargo:rustc-cfg=lensray_hwdiv");
    }
}
