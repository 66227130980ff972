//! Prints a hash of the f32 render of each seed (pinhole and lens) and of
//! each file given: `f32_hashes COUNT FILE...`, to check that a change to the
//! fixed-point path leaves f32's images bit for bit.
use lensray::Scene;
use lensray_testkit::scenegen::Camera;
use std::hash::{Hash, Hasher};

fn hash(text: &str, name: &str) {
    let mut s = Scene::<f32>::parse(text).expect("parse");
    s.camera.adaptive = false;
    let lens = s.camera.radius > 0.0;
    let mut r = lensray::Renderer::new(&s, 160, 120);
    if lens {
        r = r.with_samples(16);
    }
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for row in 0..120 {
        let mut out = vec![embedded_graphics::pixelcolor::Rgb888::new(0, 0, 0); 160];
        r.render_row(row, &mut out);
        for p in out {
            use embedded_graphics::pixelcolor::RgbColor;
            (p.r(), p.g(), p.b()).hash(&mut h);
        }
    }
    println!("{name} {:016x}", h.finish());
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let count: u64 = args[0].parse().expect("count");
    for seed in 0..count {
        for camera in [Camera::Pinhole, Camera::Lens] {
            hash(
                &lensray_host::sweep::scene_text(seed, camera),
                &format!("{seed} {camera:?}"),
            );
        }
    }
    for f in &args[1..] {
        hash(&std::fs::read_to_string(f).expect("read"), f);
    }
}
