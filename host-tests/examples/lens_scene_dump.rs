//! Prints the generator's lens scene of a seed: `lens_scene_dump SEED`.
fn main() {
    let seed: u64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    print!("{}", lensray_testkit::scenegen::generate_lens(seed));
}
