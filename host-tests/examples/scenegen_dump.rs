//! Writes generated scenes to files: `scenegen_dump DIR pinhole|lens SEED...`
//! writes `DIR/seed-SEED-pinhole.scene` (or `-lens`) for each seed, the
//! scene the sweep renders for it: how a seed a sweep reports under a floor
//! joins `host-tests/corpus/sweep-regressions/`.
use lensray_testkit::scenegen::Camera;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let camera = match args.get(1).map(String::as_str) {
        Some("pinhole") => Camera::Pinhole,
        Some("lens") => Camera::Lens,
        _ => {
            eprintln!("usage: scenegen_dump DIR pinhole|lens SEED...");
            std::process::exit(2);
        }
    };
    for seed in args[2..].iter().filter_map(|s| s.parse::<u64>().ok()) {
        let path = format!("{}/seed-{seed}-{}.scene", args[0], args[1]);
        std::fs::write(&path, lensray_host::sweep::scene_text(seed, camera)).expect("write");
    }
}
