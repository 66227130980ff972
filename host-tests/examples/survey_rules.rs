//! What a frame's set-up survey decided (diagnosis, no render):
//! `survey_rules SEED|SCENE WIDTH [POINT]`: the cap and the survey's rays,
//! the spare floor's rules as flags, and the lamps' parts. A survey alone
//! takes seconds, so a family of scenes can be sorted by what their frames
//! take before any of them is measured against a reference.
use lensray::{Renderer, Scene, I16F16};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 3 {
        eprintln!("usage: survey_rules SEED|SCENE WIDTH [POINT]");
        std::process::exit(2);
    }
    let (_, text, w, h) = lensray_host::convergence::seed_frame(&a);
    let scene = Scene::<I16F16>::parse(&text).unwrap_or_else(|e| panic!("{}: {e}", a[1]));
    let point = a.get(3).map(|p| p.parse().expect("POINT"));
    let r = Renderer::new_with_samples(&scene, w, h, point);
    let (cap, rays) = r.adaptive_cap();
    println!(
        "point {} cap {cap} survey rays {rays} lamp parts {} (off {:#b}) in place {} plain lamps {} raised pilots {} doubling {}",
        r.samples(),
        r.lamp_parts(),
        r.lamp_parts_off(),
        r.lamps_in_place(),
        r.plain_lamps(),
        r.raised_pilots(),
        r.doubling()
    );
}
