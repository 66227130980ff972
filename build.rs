//! Tells the library whether it is built for Cortex-M0/M0+ (thumbv6m): that
//! core multiplies 32 by 32 bits into 32 only, and the library then forms
//! 64-bit products from 16-bit halves instead of calling a 64×64 routine.

fn main() {
    println!("cargo:rustc-check-cfg=cfg(lensray_v6m)");
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var("TARGET").is_ok_and(|t| t.starts_with("thumbv6m")) {
        println!("cargo:rustc-cfg=lensray_v6m");
    }
}
