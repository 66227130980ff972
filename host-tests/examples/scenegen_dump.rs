//! Writes generated scenes to files: `scenegen_dump DIR pinhole|lens SEED...`
//! (how host-tests/corpus/sweep-regressions/ was filled from a sweep's failures).
use lensray_testkit::scenegen::Camera;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let camera = if args[1] == "lens" {
        Camera::Lens
    } else {
        Camera::Pinhole
    };
    for seed in args[2..].iter().filter_map(|s| s.parse::<u64>().ok()) {
        let path = format!("{}/seed-{seed}-{}.scene", args[0], args[1]);
        std::fs::write(&path, lensray_host::sweep::scene_text(seed, camera)).expect("write");
    }
}
