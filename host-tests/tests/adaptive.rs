//! Adaptive lens sampling on the stratified sampler, against converged
//! references: the default render (stratified, adaptive) of lens scenes
//! reaches at least the PSNR that `point` independent samples reach, with at
//! most 40 % of their rays (the issue-14 floors, scaled down to small frames;
//! the full-size figures are `cargo bench -p lensray-host --bench sampling`,
//! the generated-scene campaign `cargo run --release -p lensray-host
//! --example adaptive_campaign`).

use lensray::unstable::render::{
    adaptive_limit, adaptive_pilot, adaptive_raised_pilot, adaptive_risk_pilot, dithered_budget, dithered_cap,
    spread_margin, survey_stride, ADAPTIVE_BUDGET_POINT, ADAPTIVE_EIGHT_POINT, ADAPTIVE_MIN_PILOT, ADAPTIVE_MIN_POINT,
    ADAPTIVE_PILOT, ADAPTIVE_SMALL_PILOT, GAP_PAIR, SPREAD_MARGIN_SE, SURVEY_MAX_RAYS, SURVEY_MIN_PIXELS,
};
use lensray::unstable::sampler::Sampler;
use lensray::{Renderer, Scene, I16F16};
use lensray_host::convergence::{measure, reference, Setting};
use lensray_host::{load_scene, Diff};

fn scene_text(name: &str) -> String {
    std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../scenes")
            .join(name),
    )
    .unwrap()
}

/// The floors on one scene at `w`×`h`, against a stratified f32 reference of
/// 2048 samples (cached under target/converged/).
fn floors_hold(name: &str, w: u32, h: u32) {
    floors_hold_on(name, &scene_text(name), w, h);
}

fn floors_hold_on(name: &str, text: &str, w: u32, h: u32) {
    let text = text.to_string();
    let point = Scene::<f32>::parse(&text).unwrap().camera.samples;
    let truth = reference(&text, w, h, 2048, Sampler::Stratified).unwrap();
    let independent = measure(&text, &truth, Setting::independent(point)).unwrap();
    // The default render: the scene as written (stratified, adaptive).
    let scene = Scene::<I16F16>::parse(&text).unwrap();
    assert!(scene.camera.adaptive && scene.camera.sampler == Sampler::Stratified);
    let default = measure(&text, &truth, Setting::default_render(point)).unwrap();
    println!(
        "{name} {w}x{h}: independent {point}: {:.2} dB; default: {:.2} dB at {:.1} rays a pixel ({:.1} %)",
        independent.psnr,
        default.psnr,
        default.rays,
        100.0 * default.rays / point as f64
    );
    assert!(
        default.psnr >= independent.psnr,
        "{name}: {:.2} dB < {:.2} dB",
        default.psnr,
        independent.psnr
    );
    assert!(
        default.rays <= 0.4 * point as f64,
        "{name}: {:.1} rays a pixel",
        default.rays
    );
}

/// A camera resting on a floor that cuts its lens (host-tests/extra-scenes/):
/// both floors, the lens's parts weighed (`src/render/cut.rs`).
#[test]
fn a_camera_on_the_floor_meets_both_floors() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("extra-scenes/camera-on-the-floor.scene");
    let text = std::fs::read_to_string(path).unwrap();
    assert!(Renderer::new(&Scene::<I16F16>::parse(&text).unwrap(), 96, 72)
        .lens_cut()
        .is_cut());
    floors_hold_on("camera-on-the-floor.scene", &text, 96, 72);
}

/// Scenes written by hand outside the generator's range (host-tests/extra-scenes/hand-*:
/// a macro lens with lamps behind, a tilted camera with shadows and a hexagon,
/// a dark foreground on a bright background, 6 rays through a wide
/// pentagon, focus very near, a row of lamps, a grazing floor, `point` 300):
/// both floors on each.
#[test]
fn the_hand_written_scenes_meet_both_floors() {
    floors_hold_on_extra_scenes("hand-", 8);
}

/// Both floors at 96x72 on each of the `count` scenes of
/// host-tests/extra-scenes/ whose names start with `prefix`.
fn floors_hold_on_extra_scenes(prefix: &str, count: usize) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("extra-scenes");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(prefix) && n.ends_with(".scene"))
        .collect();
    names.sort();
    assert_eq!(names.len(), count, "{names:?}");
    for name in names {
        let text = std::fs::read_to_string(dir.join(&name)).unwrap();
        floors_hold_on(&name, &text, 96, 72);
    }
}

/// Still lifes, a family of scenes written from the scene format alone
/// (scripts/still-lifes.py; host-tests/extra-scenes/still-life-*): the four
/// of still lifes 1-40 with the least margin at 320x240 or the widest lens
/// (a hexagon at f/8 focused at 28.8 with shadows, `point` 24; a wide
/// nonagon over lamps' footprints, 21; `focus_on` through a hexagon, 16;
/// f/1.4, 33): both floors on each.
#[test]
fn the_still_lifes_meet_both_floors() {
    floors_hold_on_extra_scenes("still-life-", 4);
}

#[test]
fn program1_default_render_beats_independent_with_40_percent_of_the_rays() {
    floors_hold("paper-program1.scene", 96, 72);
}

#[test]
fn fig9b_default_render_beats_independent_with_40_percent_of_the_rays() {
    floors_hold("paper-fig9b.scene", 96, 72);
}

#[test]
fn bright_bokeh_default_render_beats_independent_with_40_percent_of_the_rays() {
    // Lamps 15 times brighter than white, far out of focus, seen through part
    // of a hexagonal lens: what a pilot that stops early gets wrong.
    floors_hold("camera-features.scene", 96, 72);
}

/// `camera-features` flashed at a smaller `point` than its 320: at 63 and 73
/// the risk pilot held within the budget (16) sees its lamps' footprints
/// (about a twentieth of the lens) in under one stratum, and the bokeh's
/// pixels that miss them all stop dark at their pilot (-2.1 and -2.6 dB
/// against the floor at 320x240). A fifth of the frame in footprints leaves
/// the room for the raised pilot (32): both floors on each.
#[test]
fn camera_features_at_a_smaller_point_takes_the_raised_pilot_and_meets_both_floors() {
    for point in [63, 73] {
        let text = lensray_host::convergence::with_point(&scene_text("camera-features.scene"), point);
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let r = Renderer::new(&scene, 96, 72);
        assert!(r.raised_pilots(), "point {point}");
        let lamp = (0..72)
            .flat_map(|y| (0..96).map(move |x| (x, y)))
            .find(|&(x, y)| r.bright_footprints().at_risk(x, y))
            .unwrap();
        assert_eq!(r.pilot(lamp.0, lamp.1), adaptive_raised_pilot(point));
        assert!(adaptive_raised_pilot(point) > adaptive_risk_pilot(point));
        floors_hold_on(&format!("camera-features at point {point}"), &text, 96, 72);
    }
}

/// `camera-features`' lamps, far behind the focused sphere, reach the pixels
/// of their bokeh through a twentieth of its hexagon: at `point` 23 to 53 a
/// pilot of 8 or 16 misses them on many of those pixels, which settled dark
/// (-1.1 to -1.8 dB against the floor at 320x240). Each such pixel now puts
/// a ray in the lamp's disc on the lens and weighs its rays by their parts'
/// shares (`src/render/lamps.rs`): both floors on each, and far more than
/// the same renderer without the parts.
#[test]
fn lamps_parts_of_the_lens_find_the_bokeh_a_pilot_misses() {
    let (w, h) = (96, 72);
    for point in [23, 33, 43, 53] {
        let text = lensray_host::convergence::with_point(&scene_text("camera-features.scene"), point);
        floors_hold_on(&format!("camera-features at point {point}"), &text, w, h);
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let truth = reference(&text, w, h, 2048, Sampler::Stratified).unwrap();
        let psnr = |r: &Renderer<'_, I16F16>| {
            let mut pixels = vec![embedded_graphics_core::pixelcolor::Rgb888::new(0, 0, 0); (w * h) as usize];
            for (row, out) in pixels.chunks_mut(w as usize).enumerate() {
                r.render_row(row as u32, out);
            }
            let img = lensray_host::Image {
                width: w,
                height: h,
                pixels,
            };
            lensray_host::Diff::of(&img, &truth).unwrap().psnr
        };
        let with = Renderer::new(&scene, w, h);
        assert!(with.lamp_parts(), "point {point}");
        let (on, off) = (psnr(&with), psnr(&with.clone().without_lamp_parts()));
        println!("point {point}: {on:.2} dB with lamps' parts, {off:.2} without");
        assert!(
            on >= off + 3.0,
            "point {point}: {on:.2} dB with lamps' parts, {off:.2} without"
        );
    }
}

/// Where the survey's rays in its lamps' parts of the lens mostly showed
/// what the pilots showed, the lamps' footprints take the plain pilot, after
/// a second survey (seed 11777: a sphere bright only by its bound; at
/// `point` 17 to 19 its footprints' raised pilots of 8 were the frame's
/// budget, and its fireflies, a highlight through a 400th of the lens, kept
/// their weight: -1.6 to -2.1 dB against the floor at 160x120). Both floors
/// there; `camera-features`' lamps keep their pilots.
#[test]
fn false_lamps_footprints_take_the_plain_pilot() {
    let (w, h) = (160, 120);
    // As it renders by default: stratified (its own line says independent).
    let generated = lensray_testkit::scenegen::generate_lens(11777) + "\nsampler stratified\n";
    for point in [17, 18, 19] {
        let text = lensray_host::convergence::with_point(&generated, point);
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let r = Renderer::new(&scene, w, h);
        assert!(r.plain_lamps(), "point {point}");
        let at_risk = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .find(|&(x, y)| r.bright_footprints().at_risk(x, y));
        let (x, y) = at_risk.expect("a pixel in a lamp's footprint");
        assert_eq!(
            r.pilot(x, y),
            lensray::unstable::render::adaptive_pilot(point),
            "point {point}"
        );
        floors_hold_on(&format!("seed 11777 at point {point}"), &text, w, h);
    }
    let text = lensray_host::convergence::with_point(&scene_text("camera-features.scene"), 33);
    let scene = Scene::<I16F16>::parse(&text).unwrap();
    assert!(!Renderer::new(&scene, w, h).plain_lamps());
}

/// Seed 12194 (`point` 8, the gaps' regime) at 320x240, the floors' own
/// size: a dim sphere 1.6 units from the lens, in a tenth of every pixel's
/// lens, before a lamp 2 to 4 pixels out of focus. Its pixels are the lamp's
/// for the scanline filter (the occluder's silhouette is the rim, see
/// `src/render/scanline.rs`): both floors, -2.88 dB against the PSNR floor
/// without that rule (at 96x72 and 160x120 the lamp is within the gate, and
/// the frame still misses there).
#[test]
fn a_lamp_behind_a_near_occluder_meets_both_floors_at_320x240() {
    let text = lensray_testkit::scenegen::generate_lens(12194);
    floors_hold_on("seed 12194", &text, 320, 240);
}

/// Seed 12484 (`point` 13) at 320x240: a checkered cube just before the
/// lens, far out of focus, nearly the same footprint on every pixel. Each
/// stratum's box, centred on its ray, widened the lens's blur and greyed the
/// checker over the whole frame (blue -7.5 levels at 4 rays; -0.89 dB
/// against the PSNR floor). Its centre pulled in (`Stratum::pull`): both
/// floors, and a dB over the same render with the pull off.
#[test]
fn a_checkered_solid_before_the_lens_meets_both_floors_with_its_footprints_pulled_in() {
    let text = lensray_testkit::scenegen::generate_lens(12484) + "\nsampler stratified\nadaptive on\n";
    let (w, h) = (320, 240);
    floors_hold_on("seed 12484", &text, w, h);
    let truth = reference(&text, w, h, 2048, Sampler::Stratified).unwrap();
    let mut scene = Scene::<I16F16>::parse(&text).unwrap();
    let pulled = lensray_host::render_image(&scene, w, h, None, &|| {});
    scene.set_rim_pull(false);
    let centred = lensray_host::render_image(&scene, w, h, None, &|| {});
    let psnr = |img: &lensray_host::Image| lensray_host::Diff::of(img, &truth).unwrap().psnr;
    let (on, off) = (psnr(&pulled), psnr(&centred));
    println!("seed 12484: {on:.2} dB pulled, {off:.2} dB centred");
    assert!(on >= off + 1.0, "{on:.2} dB pulled, {off:.2} dB centred");
}

/// Seed 12559 forced to `point` 6: lamps far above white on nearly every
/// pixel, its reference white almost everywhere. Its rays' ranges unclamped
/// made most pixels wide, which left extension off, and a pixel whose 2 rays
/// took in a dark one fell below white (-12.8 dB against the PSNR floor).
/// Clamped at white, only the pixels whose rays straddle it are wide and
/// extend: both floors. (At 160x120 and `point` 4 they are too many for the
/// budget, and it still misses: see BENCHMARKS.md.)
#[test]
fn a_blown_out_frame_at_a_small_point_extends_only_the_pixels_whose_rays_straddle_white() {
    let generated = lensray_testkit::scenegen::generate_lens(12559) + "\nsampler stratified\nadaptive on\n";
    let text = lensray_host::convergence::with_point(&generated, 6);
    let (w, h) = (320, 240);
    assert!(Renderer::new(&Scene::<I16F16>::parse(&text).unwrap(), w, h).extends());
    floors_hold_on("seed 12559 at point 6", &text, w, h);
}

/// Seed 11777 at `point` 20 and 21, where the pilots are the whole budget
/// or nearly: a lamp sphere's highlight reaches its pixels through slivers
/// of the lens beside a cylinder just before it. Those pixels are soft rims
/// (the cylinder's silhouette, far out of focus) and mix with their
/// neighbours, which met the cylinder alone: both floors at 160x120
/// (-2.27 and -1.66 dB against the PSNR floor before soft rims).
#[test]
fn a_lamps_highlight_beside_a_near_occluder_meets_both_floors_where_the_pilots_are_the_budget() {
    let generated = lensray_testkit::scenegen::generate_lens(11777) + "\nsampler stratified\n";
    for point in [20, 21] {
        let text = lensray_host::convergence::with_point(&generated, point);
        floors_hold_on(&format!("seed 11777 at point {point}"), &text, 160, 120);
    }
}

/// Progressive display with lamps' parts: the last pass is the plain render,
/// pixel for pixel (the parts, like the rest, depend on the pixel alone).
#[test]
fn progressive_passes_end_on_the_plain_render_with_lamps_parts() {
    let text = lensray_host::convergence::with_point(&scene_text("camera-features.scene"), 33);
    let scene = Scene::<I16F16>::parse(&text).unwrap();
    let (w, h) = (64, 48);
    assert!(Renderer::new(&scene, w, h).lamp_parts());
    let plain = lensray_host::render_image(&scene, w, h, None, &|| {});
    let (last, _) = lensray_host::passes::render_passes(&scene, w, h, None, 8, 1, &mut |_, _, _| {});
    assert_eq!(last, plain);
}

/// Where most of the survey's lamps' rays show what the pilots showed (a
/// generated gilded sphere, a "lamp" only by its bound under four lights:
/// seed 11734 lost 0.57 dB to them), the parts are off and the frame is what
/// it was without them; `camera-features`' lamps keep them.
#[test]
fn lamps_parts_are_off_where_the_survey_finds_nothing_behind_them() {
    for (w, h) in [(96, 72), (320, 240)] {
        let text = lensray_testkit::scenegen::generate_lens(11734);
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let r = Renderer::new(&scene, w, h);
        assert!(!r.bright_footprints().is_empty(), "{w}x{h}");
        assert!(!r.lamp_parts(), "{w}x{h}");
        let text = lensray_host::convergence::with_point(&scene_text("camera-features.scene"), 33);
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        assert!(Renderer::new(&scene, w, h).lamp_parts(), "{w}x{h}");
    }
}

/// Each lamp's part is judged on its own: in a frame of four lamps through a
/// wide octagon (host-tests/extra-scenes/mutant-lamps-judged-one-by-one.scene),
/// the survey's grid kept few of one lamp's rays, and with every lamp's
/// part off the bright bokeh of the others settled dark (-1.23 dB against
/// the floor at 160x120). At 320x240 that one lamp is off and the others
/// keep their parts; at 160x120 its unkept rays are too few to tell (two
/// binomial deviations) and every part is on; both floors hold. A frame
/// whose lamps are all kept has none off.
#[test]
fn each_lamps_part_is_off_or_on_by_its_own_rays() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("extra-scenes/mutant-lamps-judged-one-by-one.scene");
    let text = std::fs::read_to_string(path).unwrap();
    let scene = Scene::<I16F16>::parse(&text).unwrap();
    let r = Renderer::new(&scene, 320, 240);
    assert!(r.lamp_parts());
    assert_eq!(r.lamp_parts_off().count_ones(), 1);
    assert!(Renderer::new(&scene, 160, 120).lamp_parts());
    floors_hold_on("mutant-lamps-judged-one-by-one.scene", &text, 160, 120);
    let text = lensray_host::convergence::with_point(&scene_text("camera-features.scene"), 33);
    let scene = Scene::<I16F16>::parse(&text).unwrap();
    let r = Renderer::new(&scene, 160, 120);
    assert!(r.lamp_parts());
    assert_eq!(r.lamp_parts_off(), 0);
}

/// Where every pixel's pilot is the whole budget (`point` 10 and 20: no
/// survey, no ray to spare), a lamp seen through part of the lens still
/// has its part: the pilot's last ray is drawn there where none of the
/// others fell in it. Two random mutants of the paper's figure 10
/// (host-tests/extra-scenes/mutant-*-at-point-*.scene) missed the floor
/// on their lamps' rims by 3.46 and 1.04 dB at 96x72 without it; both
/// floors hold on each, at exactly 40 % of `point`.
#[test]
fn lamps_take_the_pilots_last_ray_where_the_pilot_is_the_whole_budget() {
    for (name, point) in [
        ("mutant-lamp-rims-at-point-10.scene", 10),
        ("mutant-near-lamp-at-point-20.scene", 20),
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("extra-scenes")
            .join(name);
        let text = std::fs::read_to_string(path).unwrap();
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        assert_eq!(scene.camera.samples, point);
        let r = Renderer::new(&scene, 96, 72);
        assert!(r.lamps_in_place(), "{name}");
        assert!(!r.lamp_parts(), "{name}: no survey, no ray beyond the pilot");
        floors_hold_on(name, &text, 96, 72);
    }
}

/// Seeds of generated lens scenes: `LENSRAY_SEEDS` (comma-separated), else
/// `count` seeds drawn from the clock, so that every run sees new scenes.
fn run_time_seeds(count: u64) -> Vec<u64> {
    if let Ok(v) = std::env::var("LENSRAY_SEEDS") {
        return v.split(',').filter_map(|s| s.trim().parse().ok()).collect();
    }
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_nanos() as u64;
    (0..count).map(|i| (t ^ (i << 40)) % 1_000_000).collect()
}

/// The default render of `text` at `point` against `truth`, beside `point`
/// independent samples: asserts the ray floor (40 %, survey included) and
/// returns how many dB short of the PSNR floor it is, if it is. Above 60 dB
/// (a mean square error under 0.07 level²) both renders differ from the
/// reference by a few pixels' rounding: not judged.
fn judged_short(text: &str, truth: &lensray_host::Image, seed: u64, point: u32) -> Option<f64> {
    let ind = measure(text, truth, Setting::independent(point)).unwrap();
    let def = measure(text, truth, Setting::default_render(point)).unwrap();
    println!(
        "seed {seed} point {point}: independent {:.2} dB, default {:.2} dB at {:.1} %",
        ind.psnr,
        def.psnr,
        100.0 * def.rays / point as f64
    );
    assert!(
        def.rays <= 0.4 * point as f64,
        "seed {seed} point {point}: {:.2} rays",
        def.rays
    );
    (def.psnr < ind.psnr && def.psnr < 60.0).then_some(ind.psnr - def.psnr)
}

/// The floors on generated lens scenes, at 80x60 against references of 512
/// samples (the campaign example measures many more, larger): seeds 400 to
/// 411 (`LENSRAY_SEEDS` for others), a block never tuned on, taken whole
/// before it was measured. Each judged scene must meet both floors. Fixed
/// seeds, not drawn from the clock: the PSNR floor is not met on every
/// generated scene (BENCHMARKS.md, "The scene generator's lens scenes": about
/// one in twenty-five, noise-like frames where 40 % of `point` stratified
/// stays under `point` independent), so a run-time draw would fail now and
/// then; the campaign command is where new seeds are tried.
#[test]
fn generated_lens_scenes_meet_the_floors() {
    let mut short = Vec::new();
    let seeds = match std::env::var("LENSRAY_SEEDS") {
        Ok(_) => run_time_seeds(0),
        Err(_) => (400..412).collect(),
    };
    let mut judged = 0;
    for seed in seeds {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        let point = Scene::<f32>::parse(&text).unwrap().camera.samples;
        if point < ADAPTIVE_MIN_POINT {
            continue; // Gaps: see generated_lens_scenes_meet_the_floors_below_point_ten.
        }
        let truth = reference(&text, 80, 60, 512, Sampler::Stratified).unwrap();
        if let Some(db) = judged_short(&text, &truth, seed, point) {
            short.push((seed, db));
        }
        judged += 1;
    }
    assert!(judged >= 5, "only {judged} scenes with point >= {ADAPTIVE_MIN_POINT}");
    assert!(short.is_empty(), "PSNR floor missed (seed, dB short): {short:?}");
}

/// The floors below `point` 10 (gaps: pixels that cast no ray), at 160x120
/// (at 80x60 `point` 1 and 2 cannot afford a gap survey) against references
/// of 512 samples: seeds 400 to 409 at `point` 1, 2, 3, 5 and 8, a block
/// never tuned on. Every frame within 40 %, survey included; the PSNR floor
/// on 43 of 50 (frames of sharp detail, seed 405, and of fine checkers near
/// focus still miss: BENCHMARKS.md). Seeking one ray a pixel that casts, not
/// [`GAP_PAIR`], 40 of 50 met it.
#[test]
fn generated_lens_scenes_meet_the_floors_below_point_ten() {
    let (mut judged, mut short) = (0, Vec::new());
    for seed in 400..410u64 {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        if Scene::<f32>::parse(&text).unwrap().camera.radius == 0.0 {
            continue;
        }
        let truth = reference(&text, 160, 120, 512, Sampler::Stratified).unwrap();
        for point in [1u32, 2, 3, 5, 8] {
            let text = lensray_host::convergence::with_point(&text, point);
            if let Some(db) = judged_short(&text, &truth, seed, point) {
                short.push((seed, point, db));
            }
            judged += 1;
        }
    }
    println!("short: {short:?}");
    // The count below is GAP_PAIR's (2): seeking one ray, 10 of 50 missed.
    assert_eq!(GAP_PAIR, 2);
    assert!(judged >= 40, "only {judged} frames");
    assert!(
        short.len() * 50 <= judged * 7,
        "PSNR floor missed on {} of {judged}: {short:?}",
        short.len()
    );
}

#[test]
fn generated_lens_scenes_stop_at_powers_of_two_or_the_limit_on_the_full_renders_samples() {
    // On scenes never seen: every pixel casts its pilot, a power of two above
    // it up to the frame's cap dithered to a power of two, or `point`; and
    // its colour is the render without adaptive sampling at that many
    // samples (the same samples and footprints).
    for seed in run_time_seeds(3) {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let point = scene.camera.samples;
        let r = Renderer::new(&scene, 24, 18);
        let pilot = adaptive_pilot(point);
        // No survey at 24x18: the cap is 40 % of point.
        assert_eq!(r.adaptive_cap(), (adaptive_limit(point), 0));
        let cap = adaptive_limit(point).max(pilot);
        let limit = (2 << (31 - cap.leading_zeros())).min(point);
        for (x, y) in (0..18).flat_map(|y| (0..24).map(move |x| (x, y))) {
            let (c, n) = r.pixel_rays(x, y);
            if point < ADAPTIVE_BUDGET_POINT || scene.camera.radius == 0.0 || !scene.camera.adaptive {
                assert!(n == point || n == 1, "seed {seed}: {n} of {point}");
                continue;
            }
            if point < ADAPTIVE_MIN_POINT {
                // The fixed budget: 40 % of point, dithered to a power of two.
                assert_eq!(n, dithered_budget(point, x, y), "seed {seed}: {n} of {point}");
                continue;
            }
            assert!(n <= limit, "seed {seed}: {n} rays of {point} (limit {limit})");
            assert_eq!(n.max(pilot), n, "seed {seed}: below the pilot");
            assert!(
                n == point || n.is_power_of_two(),
                "seed {seed}: {n} rays of {point} (pilot {pilot})"
            );
            if n == pilot {
                // A pixel that stopped at its pilot drew its footprints for n
                // strata, as the plain render of n samples does (later samples
                // of a pixel that goes on stand for finer strata).
                let (d, _) = r.clone().with_adaptive(false).with_samples(n).pixel_rays(x, y);
                assert_eq!(c, d, "seed {seed} pixel ({x}, {y})");
            }
        }
    }
}

#[test]
fn the_pilot_grows_with_point() {
    // A third of point, rounded down to a power of two, at least 8; 4 below 20.
    assert_eq!(ADAPTIVE_EIGHT_POINT, 20);
    assert_eq!(adaptive_pilot(20), ADAPTIVE_MIN_PILOT);
    assert_eq!(adaptive_pilot(19), ADAPTIVE_SMALL_PILOT);
    assert_eq!(adaptive_pilot(ADAPTIVE_MIN_POINT), 4);
    // The small pilot is 40 % of the least adaptive point.
    assert_eq!(5 * adaptive_pilot(ADAPTIVE_MIN_POINT), 2 * ADAPTIVE_MIN_POINT);
    assert_eq!(adaptive_pilot(33), 8);
    assert_eq!(adaptive_pilot(47), 8);
    assert_eq!(adaptive_pilot(48), 16);
    assert_eq!(adaptive_pilot(63), 16);
    assert_eq!(adaptive_pilot(70), 16);
    assert_eq!(adaptive_pilot(320), 64);
    // At most 40 % of point, never below the pilot.
    assert_eq!(adaptive_limit(20), 8);
    assert_eq!(adaptive_limit(70), 28);
    assert_eq!(adaptive_limit(320), 128);
    // A lens looking at nothing: every sample agrees, each pixel stops at its
    // pilot; below the small pilot's point, 40 % of point dithered (3.6 at
    // 9: 2 or 4), at least one ray (no gap survey at 8x6).
    for (point, rays) in [
        (1, 1),
        (2, dithered_budget(2, 3, 2)),
        (ADAPTIVE_MIN_POINT - 1, dithered_budget(9, 3, 2)),
        (ADAPTIVE_BUDGET_POINT, dithered_budget(3, 3, 2)),
        (ADAPTIVE_MIN_POINT, 4),
        (19, 4),
        (33, 8),
        (64, 16),
        (320, 64),
    ] {
        let empty = Scene::<I16F16>::parse(&format!("radius 0.3\npoint {point}\n")).unwrap();
        assert_eq!(Renderer::new(&empty, 8, 6).pixel_rays(3, 2).1, rays, "point {point}");
    }
}

#[test]
fn a_bright_plane_is_a_lamp_only_lit_from_the_lens_side() {
    // A floor 2 below the lens, white Kd: a light of 10 under it never lights
    // what the lens sees; the same light above it does (a footprint everywhere).
    for (y, lamp) in [(-5.0, false), (5.0, true)] {
        let text = format!(
            "radius 0.5\npoint 64\nlight_position 0 {y} -10\nlight_intensity 10 10 10\n\
             object plane\nKd 1 1 1\nrotate x -90\ntranslate 0 -2 0\n"
        );
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let r = Renderer::new(&scene, 16, 12);
        assert_eq!(!r.bright_footprints().is_empty(), lamp, "light at y {y}");
        assert_eq!(r.bright_footprints().at_risk(3, 3), lamp, "light at y {y}");
    }
}

/// The brightest lamp's bound, rounded up, is what the scanline filter's
/// lamp gate scales by: ambient plus every light at full diffuse and
/// specular strength, in its brightest channel, over random materials and
/// lights (recomputed here in f64), 0 with no lamp.
#[test]
fn the_lamp_gate_is_the_brightest_lamps_bound_rounded_up() {
    let mut next = {
        let mut x = 0x1a3f_u64;
        move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        }
    };
    let (mut lamps, mut none) = (0, 0);
    for _ in 0..200 {
        let amb = [next(), next(), next()];
        let lights: Vec<[f64; 3]> = (0..1 + (next() * 4.0) as usize)
            .map(|_| [next() * 2.0, next() * 2.0, next() * 2.0])
            .collect();
        let mut text = format!("radius 0.5\npoint 64\nambient_light {} {} {}\n", amb[0], amb[1], amb[2]);
        for (i, l) in lights.iter().enumerate() {
            text += &format!(
                "light_position {} 5 {}\nlight_intensity {} {} {}\n",
                i,
                -(i as f64),
                l[0],
                l[1],
                l[2]
            );
        }
        let mut want: f64 = 0.0;
        for i in 0..3 {
            let m: [[f64; 3]; 3] = core::array::from_fn(|_| [next(), next(), next()]);
            text += &format!(
                "object sphere\nKa {} {} {}\nKd {} {} {}\nKs {} {} {}\ntranslate {} 0 -10\n",
                m[0][0],
                m[0][1],
                m[0][2],
                m[1][0],
                m[1][1],
                m[1][2],
                m[2][0],
                m[2][1],
                m[2][2],
                3 * i
            );
            // The library holds the values in Q16.16: bound them from what it holds.
            let scene = Scene::<I16F16>::parse(&text).unwrap();
            let (o, amb_q) = (&scene.objects()[i].material, scene.ambient.to_f64());
            let (ka, kd, ks) = (o.ka.to_f64(), o.kd.to_f64(), o.ks.to_f64());
            let b = (0..3)
                .map(|k| {
                    ka[k] * amb_q[k]
                        + (kd[k] + ks[k]) * scene.lights().iter().map(|l| l.intensity.to_f64()[k]).sum::<f64>()
                })
                .fold(0.0, f64::max);
            if b > lensray::unstable::render::footprint::BRIGHT {
                want = want.max(b.ceil());
            }
        }
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let got = Renderer::new(&scene, 16, 12).bright_footprints().lamp();
        assert_eq!(got as f64, want, "{text}");
        if got == 0 {
            none += 1;
        } else {
            lamps += 1;
        }
    }
    assert!(lamps > 20 && none > 20, "{lamps} frames with lamps, {none} without");
}

#[test]
fn samples_that_agree_stop_after_the_pilot_and_others_go_on() {
    assert_eq!(adaptive_pilot(70), ADAPTIVE_PILOT);
    assert_eq!(adaptive_pilot(320), 64);
    // A lens camera looking at nothing: every sample misses, all agree.
    let empty = Scene::<I16F16>::parse("radius 0.3\npoint 64\n").unwrap();
    let r = Renderer::new(&empty, 8, 6);
    assert_eq!(r.pixel_rays(3, 2).1, ADAPTIVE_PILOT);
    assert_eq!(
        r.clone().with_adaptive(false).pixel_rays(3, 2).1,
        64,
        "off: every sample"
    );
    // Program 1's blurred cube edge: samples differ, so that pixel goes on
    // past the pilot, to the survey's cap dithered to 32 or 64.
    let p1 =
        load_scene::<I16F16>(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene"))
            .unwrap();
    let r = Renderer::new(&p1, 80, 60);
    let counts: Vec<u32> = (0..60)
        .flat_map(|y| (0..80).map(move |x| (x, y)))
        .map(|(x, y)| r.pixel_rays(x, y).1)
        .collect();
    let (cap, survey) = r.adaptive_cap();
    assert!(
        survey > 0 && cap > adaptive_limit(70),
        "cap {cap}: the budget settled pixels leave"
    );
    assert!(counts.contains(&32));
    assert!(counts.contains(&ADAPTIVE_PILOT));
    assert!(
        counts.iter().all(|&n| [16, 32, 64, 70].contains(&n)),
        "the pilot or a power of two"
    );
    // The frame's mean within the budget, the survey's rays included.
    let total: u64 = counts.iter().map(|&n| n as u64).sum::<u64>() + survey as u64;
    assert!(total * 5 <= 2 * 70 * 4800, "{total} rays");
    // A stopped pixel's samples are the first ones of the full render: with
    // as many samples as it took, adaptive off gives the same colour.
    let (x, y) = (0..4800)
        .map(|i| (i % 80, i / 80))
        .find(|&(x, y)| r.pixel_rays(x, y).1 == 16)
        .unwrap();
    let (c, _) = r.pixel_rays(x, y);
    let (d, _) = r.clone().with_adaptive(false).with_samples(16).pixel_rays(x, y);
    assert_eq!(c, d);
}

#[test]
fn stratified_and_independent_references_agree() {
    // The converged reference is unbiased: the stratified sampler's and the
    // independent sampler's f32 renders at 2048 samples come within what the
    // independent one's noise allows (it is the noisier).
    let text = scene_text("paper-fig9b.scene");
    let a = reference(&text, 96, 72, 2048, Sampler::Stratified).unwrap();
    let b = reference(&text, 96, 72, 2048, Sampler::Independent).unwrap();
    let c = reference(&text, 96, 72, 512, Sampler::Stratified).unwrap();
    let (ab, ac) = (Diff::of(&a, &b).unwrap().psnr, Diff::of(&a, &c).unwrap().psnr);
    println!("fig9b 96x72: stratified 2048 vs independent 2048 {ab:.2} dB, vs stratified 512 {ac:.2} dB");
    // Independent at 70 reaches about 40 dB; 2048 is 29 times the samples (+14.7 dB).
    assert!(ab > 52.0, "{ab:.2} dB");
    assert!(ac > 55.0, "{ac:.2} dB");
}

#[test]
fn the_scene_keyword_and_the_cli_flag_turn_it_on() {
    let s = Scene::<I16F16>::parse("adaptive on\n").unwrap();
    assert!(s.camera.adaptive && Renderer::new(&s, 4, 3).is_adaptive());
    let s = Scene::<I16F16>::parse("adaptive on\nadaptive off\n").unwrap();
    assert!(!s.camera.adaptive);
    let s = Scene::<I16F16>::parse("sampler independent\n").unwrap();
    assert_eq!(Renderer::new(&s, 4, 3).sampler(), Sampler::Independent);
    let s = Scene::<I16F16>::parse("sampler independent\nsampler stratified\n").unwrap();
    assert_eq!(s.camera.sampler, Sampler::Stratified);
    let err = Scene::<I16F16>::parse("adaptive maybe\n").unwrap_err();
    assert_eq!(err.to_string(), "line 1: adaptive: \"maybe\" must be on or off");
}

#[test]
fn the_render_flag_overrides_the_scene() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("adaptive-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene");
    let run = |flag: &str, out: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_lensray"))
            .arg("render")
            .arg(&scene)
            .args(["--width", "40", "--samples", "24", "--adaptive", flag, "-o"])
            .arg(dir.join(out))
            .output()
            .unwrap()
    };
    assert!(run("on", "on.bmp").status.success());
    assert!(run("off", "off.bmp").status.success());
    let on = lensray_host::load_image(&dir.join("on.bmp")).unwrap();
    let off = lensray_host::load_image(&dir.join("off.bmp")).unwrap();
    // On is the default render; off is every sample; they differ somewhere but stay close.
    let mut scene = load_scene::<I16F16>(&scene).unwrap();
    assert!(on.pixels == lensray_host::render_image(&scene, 40, 30, Some(24), &|| {}).pixels);
    scene.camera.adaptive = false;
    assert!(off.pixels == lensray_host::render_image(&scene, 40, 30, Some(24), &|| {}).pixels);
    let diff = Diff::of(&on, &off).unwrap();
    assert!(diff.psnr.is_finite() && diff.psnr > 30.0, "{:.1} dB", diff.psnr);
    let bad = run("maybe", "bad.bmp");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--adaptive maybe: must be on or off"));
    // --sampler: the independent render differs, and the command prints its rays.
    let ind = std::process::Command::new(env!("CARGO_BIN_EXE_lensray"))
        .arg("render")
        .arg(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene"))
        .args([
            "--width",
            "40",
            "--samples",
            "24",
            "--adaptive",
            "off",
            "--sampler",
            "independent",
            "-o",
        ])
        .arg(dir.join("ind.bmp"))
        .output()
        .unwrap();
    assert!(ind.status.success());
    assert_eq!(String::from_utf8_lossy(&ind.stdout), "rays per pixel: 24.00\n");
    assert!(lensray_host::load_image(&dir.join("ind.bmp")).unwrap().pixels != off.pixels);
    let on_out = String::from_utf8_lossy(&run("on", "on.bmp").stdout).into_owned();
    let rays: f64 = on_out.trim().strip_prefix("rays per pixel: ").unwrap().parse().unwrap();
    assert!((adaptive_pilot(24) as f64..24.0).contains(&rays), "{on_out}");
}

/// `render --passes` prints its rays too: the plain render's and more (the
/// preview, and the last pass's redraw of the coarser grids' filtered rows).
#[test]
fn render_with_passes_prints_the_rays_its_passes_cast() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("adaptive-passes-cli");
    std::fs::create_dir_all(&dir).unwrap();
    let rays = |extra: &[&str]| -> f64 {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_lensray"))
            .arg("render")
            .arg(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene"))
            .args(["--width", "64", "--samples", "24", "-o"])
            .arg(dir.join("out.png"))
            .args(extra)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        text.trim().strip_prefix("rays per pixel: ").unwrap().parse().unwrap()
    };
    let plain = rays(&[]);
    let passes_dir = dir.join("passes");
    let passes = rays(&["--passes", passes_dir.to_str().unwrap()]);
    assert!(plain < 24.0, "adaptive: {plain}");
    // The redraw is a quarter of the pixels again (their rays, about a quarter of the plain render's).
    assert!(passes > plain && passes < 1.5 * plain, "{passes} against {plain}");
}

#[test]
fn a_lamps_footprint_holds_every_pixel_it_reaches() {
    // Lamps 300 times white, behind and in front of the plane in focus, on a
    // round and a hexagonal lens, one off the axis: every pixel any of 1024
    // lens rays carries the lamp to lies in its footprint, and the footprint
    // is not the whole picture.
    for (lens, depth, x, blades) in [(2.25, 24, 0.0, 0), (1.5, 4, 0.3, 6), (1.0, 16, -3.0, 0)] {
        let text = format!(
            "width 4\nambient_light 1 1 1\nradius {lens}\npoint 1024\naperture_blades {blades}\nadaptive off\n\
             object sphere\nKa 300 300 300\nKd 0 0 0\nscale 0.3 0.3 0.3\ntranslate {x} 0 -{depth}\n"
        );
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        let r = Renderer::new(&scene, 48, 48);
        let (mut lit, mut risky) = (0, 0);
        for row in 0..48 {
            for col in 0..48 {
                let at_risk = r.bright_footprints().at_risk(col, row);
                risky += at_risk as u32;
                if r.pixel(col, row) != embedded_graphics::pixelcolor::Rgb888::new(0, 0, 0) {
                    lit += 1;
                    assert!(
                        at_risk,
                        "lens {lens}, depth {depth}: pixel ({col}, {row}) is lit outside the footprint"
                    );
                }
            }
        }
        assert!(lit > 0 && risky < 48 * 48, "lens {lens}: {lit} lit, {risky} at risk");
    }
}

#[test]
fn the_dithered_cap_is_a_power_of_two_and_keeps_the_mean_within_the_cap() {
    // Over each 8x8 tile: the power of two below the cap or twice it, with a
    // mean at most the cap and within a 64th of that power below it.
    for cap in 1..=300u32 {
        let low = 1u32 << (31 - cap.leading_zeros());
        for (c0, r0) in [(0, 0), (5, 2), (3, 7)] {
            let takes: Vec<u32> = (0..64).map(|i| dithered_cap(cap, c0 + i % 8, r0 + i / 8)).collect();
            assert!(takes.iter().all(|&n| n == low || n == 2 * low), "cap {cap}: {takes:?}");
            let sum: u32 = takes.iter().sum();
            assert!(sum <= 64 * cap, "cap {cap}: mean {} above", sum as f64 / 64.0);
            assert!(sum + low > 64 * cap, "cap {cap}: mean {} too low", sum as f64 / 64.0);
        }
    }
}

#[test]
fn the_spread_margin_is_the_mean_and_its_standard_errors() {
    // Random sets of spreads, 2 to 2000 of them, narrow and heavy-tailed
    // (lamps' spreads reach 2^24): the margin is the mean plus
    // SPREAD_MARGIN_SE standard errors, rounded up, to within 2 and a part
    // in 10^6 (the integer root's).
    let mut state = 14u64;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    for case in 0..400 {
        let n = 2 + next() % 2000;
        let top = 1u64 << (2 + next() % 23);
        let spreads: Vec<u64> = (0..n)
            .map(|_| match case % 3 {
                0 => 1 + next() % top,
                1 => top / 2 + next() % 8,
                _ => 1 + (next() % top) * (next() % top) / top,
            })
            .collect();
        let sum: u64 = spreads.iter().sum();
        let squares: u128 = spreads.iter().map(|&x| x as u128 * x as u128).sum();
        let got = spread_margin(n, sum, squares) as f64;
        let mean = sum as f64 / n as f64;
        let var = spreads.iter().map(|&x| (x as f64 - mean).powi(2)).sum::<f64>() / n as f64;
        let want = mean + SPREAD_MARGIN_SE as f64 * (var / n as f64).sqrt();
        assert!(
            got >= want * (1.0 - 1e-6)
                && got <= want * (1.0 + 1e-6) + 2.0 + SPREAD_MARGIN_SE as f64 * mean / sum as f64,
            "case {case}: {n} spreads up to {top}: {got} for {want}"
        );
    }
    // One spread, or none: its mean, no margin to measure.
    assert_eq!(spread_margin(1, 700, 490_000), 700);
    assert_eq!(spread_margin(0, 0, 0), 0);
}

/// A frame whose cap C is under one ray above its pilot: the shares take
/// C's fraction, so the unsettled pixels of most spread go on past the
/// pilot. Seed 11777 at `point` 22 has C = 8.65 over a pilot of 8; with C
/// rounded down to 8, every pixel stopped at 8 (-2.83 dB against the PSNR
/// floor at 320x240; +0.83 with the fraction).
#[test]
fn a_cap_under_a_ray_above_the_pilot_still_spends_its_fraction() {
    let (w, h) = (320, 240);
    let scene = Scene::<I16F16>::parse(&lensray_testkit::scenegen::generate_lens(11777)).unwrap();
    let r = Renderer::new_with_samples(&scene, w, h, Some(22));
    assert_eq!(r.adaptive_cap().0, adaptive_pilot(22), "the cap is the pilot");
    let rows = frame_rays(&r, w, h) - r.adaptive_cap().1 as u64;
    let pixels = (w * h) as u64;
    assert!(
        100 * rows >= 825 * pixels,
        "{:.3} rays a pixel: the fraction was not spent",
        rows as f64 / pixels as f64
    );
    assert_within_budget(&r, 11777, w, h);
}

#[test]
fn the_dithered_budget_is_forty_percent_of_point_in_powers_of_two() {
    // Over each 8x8 tile: the power of two below 40 % of `samples` or twice
    // it, a mean at most 40 % and within a 64th of that power below it
    // (rounding 40 % down first left `point` 7 at 2 rays, 29 %).
    for samples in 3..=300u32 {
        let low = 1u32 << (31 - (2 * samples / 5).leading_zeros());
        let takes: Vec<u32> = (0..64)
            .map(|i| dithered_budget(samples, 1 + i % 8, 6 + i / 8))
            .collect();
        assert!(takes.iter().all(|&n| n == low || n == 2 * low), "{samples}: {takes:?}");
        let sum: u32 = takes.iter().sum();
        assert!(
            5 * sum <= 128 * samples,
            "{samples}: mean {} above 40 %",
            sum as f64 / 64.0
        );
        assert!(
            5 * (sum + low) > 128 * samples,
            "{samples}: mean {} too low",
            sum as f64 / 64.0
        );
    }
}

/// An unsettled pixel doubles its pilot at least, where the frame's cap
/// allows it and the survey found the rays ([`Renderer::doubling`]; seed
/// 9027 at `point` 14 stopped such pixels at 4 of 14 rays with 7 times the
/// error of 14 independent samples, -0.15 dB under the floor; +2.63 dB with
/// it): over generated frames at 80x60, no pixel stops at its pilot
/// unsettled there, some do double, some frames have no room for it, and
/// each frame stays within 40 %, survey included.
#[test]
fn an_unsettled_pixel_doubles_its_pilot_where_the_cap_allows() {
    let (mut frames, mut doubled, mut without) = (0, 0u64, 0);
    for seed in 6000..6040u64 {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        let mut scene = Scene::<I16F16>::parse(&text).unwrap();
        if scene.camera.radius == 0.0 || scene.camera.samples < ADAPTIVE_MIN_POINT {
            continue;
        }
        scene.camera.sampler = Sampler::Stratified;
        scene.camera.adaptive = true;
        let r = Renderer::new(&scene, 80, 60);
        let (cap, survey) = r.adaptive_cap();
        if survey == 0 || cap >= scene.camera.samples {
            continue;
        }
        frames += 1;
        without += !r.doubling() as u32;
        for y in 0..60 {
            for x in 0..80 {
                let pilot = r.pilot(x, y);
                let (_, n, spread) = r.pixel_rays_spread(x, y);
                if spread != 0 && cap >= 2 * pilot && r.doubling() {
                    assert!(
                        n >= 2 * pilot,
                        "seed {seed} ({x}, {y}): {n} rays, pilot {pilot}, cap {cap}"
                    );
                    doubled += (n == 2 * pilot) as u64;
                }
            }
        }
        let total = frame_rays(&r, 80, 60);
        assert!(
            total * 5 <= 2 * scene.camera.samples as u64 * 4800,
            "seed {seed}: {:.2} rays of {}",
            total as f64 / 4800.0,
            scene.camera.samples
        );
    }
    assert!(
        frames >= 5 && doubled > 0 && without > 0,
        "{frames} frames ({without} without room), {doubled} pixels at twice the pilot"
    );
}

/// Where the shares' sum leaves no room for the doubling (each share is a
/// pixel's most), the survey renders its grid again with it and doubles if
/// the frame then holds within 40 %, three deviations of the sum included:
/// most unsettled pixels settle before their share. Seed 11260 at 320x240
/// (`point` 46, a far checker's moiré) stopped unsettled pixels at the pilot
/// of 8 with 4.7 times the error of 46 independent samples and missed the
/// floor by 0.06 dB; it doubles by the measure and meets it. Over generated
/// frames at 160x120 every measured frame stays within 40 %, survey
/// included, and the measure goes both ways.
#[test]
fn the_doubling_is_measured_on_the_grid_where_the_shares_leave_no_room() {
    let text = lensray_testkit::scenegen::generate_lens(11260);
    let scene = Scene::<I16F16>::parse(&text).unwrap();
    let r = Renderer::new(&scene, 320, 240);
    assert!(r.doubling_measured() && r.doubling());
    let truth = reference(&text, 320, 240, 1024, Sampler::Stratified).unwrap();
    assert_eq!(judged_short(&text, &truth, 11260, scene.camera.samples), None);
    let (mut doubled, mut not) = (0, 0);
    // 6000-6079: with shares in 256ths the sum says yes more often (of
    // 6000-6039 one frame is measured, and does not double; 6076 does).
    for seed in 6000..6080u64 {
        let scene = Scene::<I16F16>::parse(&lensray_testkit::scenegen::generate_lens(seed)).unwrap();
        if scene.camera.radius == 0.0 || !scene.camera.adaptive || scene.camera.samples < ADAPTIVE_MIN_POINT {
            continue;
        }
        let r = Renderer::new(&scene, 160, 120);
        if !r.doubling_measured() {
            continue;
        }
        (doubled, not) = (doubled + r.doubling() as u32, not + !r.doubling() as u32);
        assert_within_budget(&r, seed, 160, 120);
    }
    assert!(doubled > 0 && not > 0, "measured: {doubled} doubled, {not} not");
}

#[test]
fn the_survey_sets_the_cap_from_the_frames_settled_share() {
    // A lens looking at nothing: every surveyed pixel settles at its pilot,
    // so an unsettled pixel may take every sample; below the survey's size
    // the cap is 40 % of point.
    let empty = Scene::<I16F16>::parse("radius 0.3\npoint 64\n").unwrap();
    assert_eq!(survey_stride(80, 60, 70), Some(8));
    assert_eq!(survey_stride(40, 30, 70), Some(4));
    assert_eq!(survey_stride(24, 18, 70), None);
    // Large frames at a large `point`: a sparser grid, its pilots within the
    // bound, still enough pixels; else none.
    for (cols, rows, samples, stride) in [
        (8192, 8192, 65535, None),
        (4096, 3072, 4096, Some(256)),
        (640, 480, 1000, Some(32)),
        (640, 480, 70, Some(8)),
        (320, 240, 320, Some(8)),
        (160, 120, 65535, None),
    ] {
        assert_eq!(survey_stride(cols, rows, samples), stride, "{cols}x{rows} at {samples}");
        if let Some(s) = stride {
            let count = (cols / s) as u64 * (rows / s) as u64;
            assert!(
                count * adaptive_risk_pilot(samples) as u64 <= SURVEY_MAX_RAYS,
                "{cols}x{rows} at {samples}"
            );
            assert!(count >= SURVEY_MIN_PIXELS as u64, "{cols}x{rows} at {samples}");
            assert!(
                (cols / (s / 2)) as u64 * (rows / (s / 2)) as u64 * adaptive_risk_pilot(samples) as u64
                    > SURVEY_MAX_RAYS
                    || s == 8
            );
        }
    }
    let r = Renderer::new(&empty, 80, 60);
    assert_eq!(r.adaptive_cap(), (64, 70 * ADAPTIVE_PILOT));
    assert_eq!(Renderer::new(&empty, 24, 18).adaptive_cap(), (adaptive_limit(64), 0));
    // Adaptive off or a sample override: surveyed again.
    assert_eq!(r.clone().with_adaptive(false).adaptive_cap(), (adaptive_limit(64), 0));
    assert_eq!(r.clone().with_samples(320).adaptive_cap().0, 320);
    // The frame's rays with the survey's stay within 40 % of point on
    // Program 1 at three sizes and three counts.
    let p1 =
        load_scene::<I16F16>(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene"))
            .unwrap();
    for (w, h, point) in [(40, 30, 40), (64, 48, 70), (96, 72, 33)] {
        let r = Renderer::new(&p1, w, h).with_samples(point);
        let total = frame_rays(&r, w, h);
        assert!(
            total * 5 <= 2 * point as u64 * (w * h) as u64,
            "{w}x{h} point {point}: {:.1} rays",
            total as f64 / (w * h) as f64
        );
    }
}

#[test]
fn a_frame_with_rays_to_spare_spends_them_on_its_settled_pixels() {
    // A lens looking at nothing at 80x60: every pixel settles at its pilot (16
    // of 64: 25 % of `point`, before); the survey finds no unsettled pixel, so
    // the settled ones go on to a floor dithered between 16 and 32, within 40 %.
    let empty = Scene::<I16F16>::parse("radius 0.3\npoint 64\n").unwrap();
    let r = Renderer::new(&empty, 80, 60);
    let per = frame_rays(&r, 80, 60) as f64 / 4800.0;
    assert!(per > 0.3 * 64.0 && per <= 0.4 * 64.0, "{per} rays a pixel");
    for (x, y) in (0..60).flat_map(|y| (0..80).map(move |x| (x, y))) {
        let n = r.pixel_rays(x, y).1;
        assert!(n == 16 || n == 32, "pixel ({x}, {y}): {n}");
    }
    // Generated frames that stopped early with rays to spare (18 and 21 % of
    // `point`) and missed the PSNR floor by 0.5 and 1.1 dB at 80x60: met now.
    for seed in [8232u64, 1042] {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        let point = Scene::<f32>::parse(&text).unwrap().camera.samples;
        let truth = reference(&text, 80, 60, 1024, Sampler::Stratified).unwrap();
        let ind = measure(&text, &truth, Setting::independent(point)).unwrap();
        let def = measure(&text, &truth, Setting::default_render(point)).unwrap();
        assert!(
            def.rays <= 0.4 * point as f64,
            "seed {seed}: {:.2} rays of {point}",
            def.rays
        );
        assert!(
            def.psnr >= ind.psnr,
            "seed {seed}: {:.2} dB against {:.2} independent",
            def.psnr,
            ind.psnr
        );
    }
}

/// Frames at the floors' size whose cap is two thirds of `point` or more
/// and whose unsettled pixels mostly settle long before it: the grid
/// measured under the cap leaves rays, and the pixels settled at their
/// pilot take them as a floor (seeds 11557 and 11690 cast 30.7 and 27.6 %
/// of `point` without it, and stayed 7.8 and 10.9 dB above the PSNR floor;
/// 35.8 and 35.5 % with it, +0.74 and +0.29 dB). Still within 40 %, as
/// every frame of a block at that size is.
#[test]
fn a_capped_frame_whose_unsettled_pixels_settle_early_spends_the_rest_on_a_floor() {
    let (w, h) = (320, 240);
    for seed in [11557u64, 11690] {
        let scene = Scene::<I16F16>::parse(&lensray_testkit::scenegen::generate_lens(seed)).unwrap();
        let r = Renderer::new(&scene, w, h);
        let (point, cap) = (r.samples() as u64, r.adaptive_cap().0 as u64);
        assert!(cap < point && 3 * cap >= 2 * point, "seed {seed}: cap {cap} of {point}");
        let rays = frame_rays(&r, w, h);
        assert!(
            100 * rays >= 34 * point * (w * h) as u64,
            "seed {seed}: {:.2} rays of {point}",
            rays as f64 / (w * h) as f64
        );
        assert_within_budget(&r, seed, w, h);
    }
    for seed in 11700..11712u64 {
        let scene = Scene::<I16F16>::parse(&lensray_testkit::scenegen::generate_lens(seed)).unwrap();
        if scene.camera.radius != 0.0 && scene.camera.adaptive {
            assert_within_budget(&Renderer::new(&scene, w, h), seed, w, h);
        }
    }
}

/// Every ray a frame casts: its rows' (gaps cast none) and its set-up survey's.
fn frame_rays(r: &Renderer<'_, I16F16>, w: u32, h: u32) -> u64 {
    let mut row = vec![Default::default(); w as usize];
    (0..h).map(|y| r.render_row(y, &mut row) as u64).sum::<u64>() + r.adaptive_cap().1 as u64
}

/// Asserts that frame `r` of seed `seed` at `w`×`h` casts at most 40 % of
/// its `point`, survey included.
fn assert_within_budget(r: &Renderer<'_, I16F16>, seed: u64, w: u32, h: u32) {
    let rays = frame_rays(r, w, h);
    assert!(
        rays * 5 <= 2 * r.samples() as u64 * (w * h) as u64,
        "seed {seed}: {:.2} rays of {} (gap period {}, loose {})",
        rays as f64 / (w * h) as f64,
        r.samples(),
        r.gap_period(),
        r.gap_loose()
    );
}

#[test]
fn generated_lens_frames_stay_within_the_ray_budget_survey_included() {
    // The ray floor alone (no reference needed, so many frames): seeds 500
    // to 539 at 64x48 (surveyed every 4th pixel), lamps' footprints and all.
    // The rule before the survey let a pixel that saw a lamp take every
    // sample: such frames cast up to 79 % of `point`. Seeds 6000 to 6059 at
    // 80x60: a share set again at each doubling cast 53 % (seed 6009).
    let blocks = (500..540u64)
        .map(|s| (s, 64, 48))
        .chain((6000..6060u64).map(|s| (s, 80, 60)));
    // Below `point` 20 (pilot 4 from 10, a fixed budget from 5) the rule
    // before cast every sample: 100 % on every such frame.
    let (mut judged, mut small) = (0, 0);
    for (seed, w, h) in blocks {
        let scene = Scene::<I16F16>::parse(&lensray_testkit::scenegen::generate_lens(seed)).unwrap();
        let point = scene.camera.samples;
        // From 3, where 40 % of `point` is 1.2 rays (a literal: before, 3 and 4
        // took every sample and would fail here).
        if point < 3 || scene.camera.radius == 0.0 || !scene.camera.adaptive {
            continue;
        }
        judged += 1;
        small += (point < ADAPTIVE_EIGHT_POINT) as u32;
        assert_within_budget(&Renderer::new(&scene, w, h), seed, w, h);
    }
    assert!(
        judged >= 70 && small >= 12,
        "only {judged} adaptive lens frames, {small} below point 20"
    );
}

/// Asserts that the generated adaptive lens scenes `seeds`, each rendered at
/// every `point` of `points` at `w`×`h`, cast at most 40 % of `point`,
/// survey included; returns how many frames it rendered.
fn frames_within_budget(seeds: std::ops::Range<u64>, points: std::ops::RangeInclusive<u32>, w: u32, h: u32) -> u32 {
    let mut frames = 0;
    for seed in seeds {
        let scene = Scene::<I16F16>::parse(&lensray_testkit::scenegen::generate_lens(seed)).unwrap();
        if scene.camera.radius == 0.0 || !scene.camera.adaptive {
            continue;
        }
        for point in points.clone() {
            assert_within_budget(&Renderer::new_with_samples(&scene, w, h, Some(point)), seed, w, h);
            frames += 1;
        }
    }
    frames
}

#[test]
fn small_point_frames_stay_within_the_ray_budget_at_every_point() {
    // Seeds 6000 to 6019 at 80x60 rendered at every `point` from 3 to 19
    // (and 20, where the pilot of 8 starts): every frame casts at most 40 %
    // of `point`, survey included; the rule before cast 100 % below 20.
    let frames = frames_within_budget(6000..6020, 3..=20, 80, 60);
    assert!(frames >= 15 * 18, "only {frames} frames");
}

/// Frames mostly in lamps' footprints, at `point`s where the lamps' pilot
/// is 40 % of `point` or half the plain one's budget (20, 40, 80, 160) and
/// between: the pilots with the survey's rays, and the unsettled lamps'
/// pixels at their pilot above the cap, stay within 40 %. `hand-near-focus`
/// at 80 (three quarters of it in footprints, pilot 32) cast 40.5 %: the
/// survey counted its pilots alone against the budget, then added its own
/// rays, and gave the unsettled pixels a cap below the lamps' pilot that
/// those pixels did not keep to.
#[test]
fn frames_full_of_lamps_footprints_stay_within_the_ray_budget() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("extra-scenes");
    let mut texts: Vec<(&str, String)> = [
        "hand-near-focus.scene",
        "hand-lamp-grid.scene",
        "hand-macro-bokeh.scene",
    ]
    .into_iter()
    .map(|name| (name, std::fs::read_to_string(dir.join(name)).unwrap()))
    .collect();
    texts.push(("camera-features.scene", scene_text("camera-features.scene")));
    let mut frames = 0;
    for (name, text) in &texts {
        let scene = Scene::<I16F16>::parse(text).unwrap();
        for point in [20, 40, 63, 80, 100, 160] {
            // The helper names a seed: here the scene and its `point`.
            println!("{name} at point {point}");
            assert_within_budget(
                &Renderer::new_with_samples(&scene, 96, 72, Some(point)),
                point as u64,
                96,
                72,
            );
            frames += 1;
        }
    }
    // Generated frames at the same `point`s (lamps' footprints or not).
    frames += frames_within_budget(500..520, 40..=40, 64, 48) + frames_within_budget(500..520, 80..=80, 64, 48);
    assert!(frames >= 40, "only {frames} frames");
}

#[test]
fn a_checker_finer_than_the_gaps_is_not_filled_by_its_moire() {
    // Seed 10835 (`point` 3): a checker finer than the pixels, in focus. The
    // loose rung of 24 levels filled the gaps between anchors that met one
    // colour of it: -4.4 dB against `point` independent samples at 160x120.
    // The survey renders the middle of the pairs the loose rule may fill and
    // finds its fills on checkers far worse than those off them: it fills
    // off checkers. Seed 10730 at 3, whose fills on checkers are as good as
    // the rest, still fills on them. (10733, the example here before the
    // 8x8 dither moved its anchors' rays, now finds its fills on checkers
    // unsound by a hair and fills off them: -0.58 dB at 160x120, +3.37 at
    // 320x240.)
    for (seed, on_checkers) in [(10835u64, false), (10730, true)] {
        let (text, scene) = gap_frame(seed, 3);
        let r = Renderer::new(&scene, 160, 120);
        assert!(r.gap_loose() > 0, "seed {seed}: the strict rule");
        assert_eq!(r.gap_checkers(), on_checkers, "seed {seed}");
        let truth = reference(&text, 160, 120, 512, Sampler::Stratified).unwrap();
        assert_eq!(judged_short(&text, &truth, seed, 3), None, "seed {seed}");
    }
    // Seed 10703 at `point` 2, 320x240: no rung leaves a pair a pixel, and
    // fills on checkers are not sound, so every gap fills off them (a ray a
    // pixel that casts): +1.9 dB where filling on them all was -6.8.
    let (text, scene) = gap_frame(10703, 2);
    let r = Renderer::new(&scene, 320, 240);
    assert_eq!((r.gap_loose(), r.gap_checkers()), (255, false));
    let truth = reference(&text, 320, 240, 512, Sampler::Stratified).unwrap();
    assert_eq!(judged_short(&text, &truth, 10703, 2), None);
    // Seed 8800 at `point` 4, 160x120: the rung that fills every gap was
    // judged sound on checkers against its own fills off them, which cross
    // every edge (107 levels² a fill; 1 at the rung below), and filled the
    // checker's moiré at 4 rays an anchor: -11.6 dB. Judged by the rung
    // below, it fills off checkers (-3.0 dB, still short at this size).
    let (_, scene) = gap_frame(8800, 4);
    let r = Renderer::new(&scene, 160, 120);
    assert!(r.gap_loose() > 0 && !r.gap_checkers(), "seed 8800 fills on checkers");
}

#[test]
fn a_gap_frame_stays_within_the_ray_budget_as_it_renders_not_as_surveyed() {
    // The gap survey chose its budget from passes at other budgets (and with
    // extension on): seed 10819 at `point` 6 filled 61 % of its pairs there,
    // 43 % as rendered, and cast 40.9 % of `point` at 320x240. Now the choice
    // is checked as the frame renders it. Seeds 10810 to 10829 at `point` 4
    // to 7, 320x240 (the survey's grid is sized by the frame), every frame
    // within 40 %, survey included.
    let frames = frames_within_budget(10810..10830, 4..=7, 320, 240);
    assert!(frames >= 48, "only {frames} frames");
    // The check draws its pairs afresh: on the choosing passes' own pairs it
    // confirmed a share they had overstated by chance (seed 8662 at `point`
    // 9, 160x120, 70 pairs), and the frame cast 40.0 %, over by a hair.
    let (_, scene) = gap_frame(8662, 9);
    let r = Renderer::new(&scene, 160, 120);
    assert_eq!(r.gap_period(), 2);
    assert_within_budget(&r, 8662, 160, 120);
}

/// Generated scene `seed` at `point` as the campaign renders it (stratified,
/// adaptive): its text, with that `point`, and the scene.
fn gap_frame(seed: u64, point: u32) -> (String, Scene<I16F16>) {
    let text = lensray_host::convergence::with_point(&lensray_testkit::scenegen::generate_lens(seed), point);
    let mut scene = Scene::<I16F16>::parse(&text).unwrap();
    (scene.camera.adaptive, scene.camera.sampler) = (true, Sampler::Stratified);
    (text, scene)
}

#[test]
fn the_gap_check_takes_no_pair_for_its_own_rays_nor_drops_on_one_short_draw() {
    // The check of the survey's choice charged its rays after the choice:
    // seed 10904 at `point` 5, 160x120, chose a pair and extension (2.008
    // rays) and the check left 1.99, one pixel that casts in 16 with a single
    // ray (-0.03 dB). Its rays are now set aside before the choice. Over seeds
    // 8600 to 8899 at `point` 3 to 9, 160x120, 25 of the 2100 frames with the
    // strict rule ended under a pair; now only those whose check found a
    // shortfall do (2).
    let r = |seed: u64, point: u32, w: u32, h: u32| {
        let (_, scene) = gap_frame(seed, point);
        let r = Renderer::new(&scene, w, h);
        (r.gap_period(), r.gap_loose(), r.gap_budget())
    };
    let (period, loose, budget) = r(10904, 5, 160, 120);
    assert!(
        period > 0 && loose == 0 && budget >= 512,
        "seed 10904: {budget}/256 rays"
    );
    let (mut frames, mut below) = (0u32, 0u32);
    for seed in 8600..8900u64 {
        for point in 3..=9 {
            let (period, loose, budget) = r(seed, point, 160, 120);
            if period > 0 && loose == 0 {
                frames += 1;
                below += (budget < 512) as u32;
            }
        }
    }
    assert!(
        frames >= 2000 && below * 200 <= frames,
        "{below} of {frames} strict gap frames under a pair"
    );
    // A first draw short of the share assumed is pooled with a second before
    // the budget drops: seed 9008 at `point` 5, 320x240, drew 77 of 149 pairs
    // filled against 53 % assumed and fell to 43 % (2.40 rays a pixel that
    // casts); with the second draw, 160 of 296 hold it (2.61).
    let (_, _, budget) = r(9008, 5, 320, 240);
    assert!(budget >= 640, "seed 9008: {budget}/256 rays");
}

#[test]
fn gaps_bring_one_and_two_samples_within_the_ray_budget_on_every_frame() {
    // At `point` 1 and 2, 40 % is under the one ray a pixel casts: only
    // pixels that cast none (gaps) bring a frame within it. Seeds 6000 to
    // 6039 at 160x120: before gaps every such frame cast 100 %; with them 44
    // of 52 were within 40 %, survey included; with the loose rule's rungs
    // (up to filling every gap at period 4) every one is.
    let (mut frames, mut loose) = (0, 0);
    for seed in 6000..6040u64 {
        let scene = Scene::<I16F16>::parse(&lensray_testkit::scenegen::generate_lens(seed)).unwrap();
        if scene.camera.radius == 0.0 || !scene.camera.adaptive {
            continue;
        }
        for point in 1..=2u32 {
            let r = Renderer::new_with_samples(&scene, 160, 120, Some(point));
            if !r.filters() {
                // `sampler independent`: no filter, no gaps.
                continue;
            }
            assert!((2..=4).contains(&r.gap_period()), "seed {seed} point {point}: no gaps");
            assert_within_budget(&r, seed, 160, 120);
            loose += (r.gap_loose() > 0) as u32;
            frames += 1;
        }
    }
    assert_eq!(ADAPTIVE_BUDGET_POINT, 1);
    // The rungs are climbed: some frames need the loose rule, most not.
    assert!(
        frames >= 50 && loose > 0 && loose * 2 < frames,
        "{loose} of {frames} frames loose"
    );
}

/// `point` 3 to 9 with gaps: a pixel that casts stops at its budget unless
/// its rays there are wider than `EXTEND_LEVELS`, and then takes every
/// sample, where the gap survey found the rays for it; frames stay within
/// 40 % of `point`, survey included. Seeds 420 to 439 at 80x60.
#[test]
fn a_pixel_whose_rays_are_wide_at_its_budget_takes_every_sample() {
    let (mut frames, mut extending, mut extended) = (0, 0, 0u64);
    for seed in 420..440u64 {
        let text = lensray_testkit::scenegen::generate_lens(seed);
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        if scene.camera.radius == 0.0 || !scene.camera.adaptive || scene.camera.sampler != Sampler::Stratified {
            continue;
        }
        for point in 3..=9u32 {
            let r = Renderer::new_with_samples(&scene, 80, 60, Some(point));
            if !r.gaps() {
                continue;
            }
            frames += 1;
            assert_within_budget(&r, seed, 80, 60);
            if !r.extends() {
                continue;
            }
            extending += 1;
            for (x, y) in (0..60).flat_map(|y| (0..80).map(move |x| (x, y))) {
                let (_, n, wide_at) = r.pixel_rays_spread(x, y);
                let budget = r.fixed_budget(x, y);
                if budget < point && wide_at & budget != 0 {
                    assert_eq!(n, point, "seed {seed} point {point} ({x}, {y}): wide at {budget}");
                    extended += 1;
                } else {
                    assert_eq!(n, budget, "seed {seed} point {point} ({x}, {y}): not wide at {budget}");
                }
            }
        }
    }
    // Some frames extend, not all; some pixels extend, few.
    assert!(frames >= 60, "{frames} frames");
    assert!(
        extending > 0 && extending < frames,
        "{extending} of {frames} frames extend"
    );
    assert!(
        extended > 0 && extended * 4 < extending as u64 * 4800,
        "{extended} pixels"
    );
}

/// Seed 9209 at `point` 4 and 5, at the floors' size (320x240): edges in
/// focus and a lamp's bokeh at 2 rays a pixel that casts. Without extension
/// it met the PSNR floor by 0.62 and 0.27 dB (at 160x120 it missed it by
/// 1.05 and 0.43); extending the pixels whose rays are wide buys 2 dB more.
#[test]
fn wide_pixels_extended_gain_where_two_rays_barely_met_the_floor() {
    beats_independent_samples(9209, 320, [4, 5], 1.5, |r, point| {
        assert!(r.extends(), "point {point}: extends")
    });
}

/// Seed 9118 at `point` 4 and 7, 160x120: smooth shading near exact, half
/// the pixels gaps between anchors a level apart. Interpolated from the
/// anchors' rounded levels, a gap came out a level off in about one case in
/// four, and the frame missed the PSNR of `point` independent samples by
/// 1.9 dB at 4 here (1.8 and 4.9 at 4 and 7 in the campaign, against 1024
/// samples); from their own values (`scanline::Fine`), rounded once, it
/// meets it by 5.3 and 5.6.
#[test]
fn gaps_between_near_exact_anchors_round_once() {
    beats_independent_samples(9118, 160, [4, 7], 2.0, |r, point| {
        assert!(r.gap_period() >= 2, "point {point}: gaps")
    });
}

/// Generated lens scene `seed` at `width` (4:3), against a 512-sample
/// reference: at each of `points`, where `setup` holds of its renderer,
/// the default render casts at most 40 % of `point` rays a pixel and beats
/// `point` independent samples by `margin` dB.
/// Seed 8703 (`point` 32): a plane crosses the lens's disc, and the part
/// of the lens beyond it sees something else for every pixel. Rays weighed
/// by their part's share of the lens (`src/render/cut.rs`): +13.2 dB over
/// 32 independent samples at 160x120; +4.0 with every ray weighed alike,
/// as before.
#[test]
fn a_lens_cut_by_a_plane_weighs_each_side_by_its_share() {
    beats_independent_samples(8703, 160, [32, 32], 9.0, |r, _| {
        let share = r.lens_cut().share();
        assert!(share > 0 && share < 65536, "share {share}");
    });
}

/// A pixel whose first block has no ray beyond a cut draws its last one
/// there (`src/render/cut.rs`). Seed 10123 (`point` 24: a floor 0.48 under
/// a tilted lens of radius 1.16, 9 % of it beyond) at 160x120: -2.24 dB
/// against 24 independent samples before the cut was weighed, +0.04 with
/// the chord's two sides weighed, +10.06 with the draw; seed 10013 (`point`
/// 8, gaps and extension): +4.75, +5.71, +18.05.
#[test]
fn a_pixel_with_no_ray_beyond_a_cut_draws_one_there() {
    beats_independent_samples(10123, 160, [24, 24], 5.0, |r, _| assert!(r.lens_cut().is_cut()));
    // (Its text asks for the independent sampler; the default render is stratified.)
    beats_independent_samples(10013, 160, [8, 8], 8.5, |_, _| {});
}

/// Seed 10014 (`point` 45): a lamp plane through the lens. Near its horizon
/// on the film a pixel's rays meet it only from a strip of the lens between
/// the chord and the pixel's own line D(L) = D(P) (`src/render/cut.rs`): at
/// 160x120 -5.13 dB against 45 independent samples before, -4.44 with the
/// chord alone, -4.24 with the drawn ray too, +3.84 with the pixel's line.
#[test]
fn a_pixels_own_line_across_a_cut_lens_splits_off_what_meets_the_plane() {
    beats_independent_samples(10014, 160, [45, 45], 2.0, |r, _| assert!(r.lens_cut().is_cut()));
}

/// A light's terminator box-filtered over a lens ray's footprint on a
/// curved surface (`src/render/trace.rs`, `lit_share`): n·l's rate across
/// the footprint from the shape operator, and only the part still facing
/// the ray. Seed 10410 (`point` 22): a cone two units from the lens, lit
/// from behind, whose footprints run past its silhouette onto the lit back:
/// -7.8 dB against 22 independent samples at 160x120 with a band of the
/// footprint times the largest curvature. Seed 10608 (`point` 17): a
/// squashed sphere, whose curvature that band took for the largest
/// everywhere: -1.5 dB. Seed 9133 (`point` 57), the filter's first frame,
/// a bright strip across every pixel's lens: +1.1 dB.
#[test]
fn a_terminator_is_filtered_over_the_footprints_facing_part() {
    beats_independent_samples(10410, 160, [22, 22], 4.0, |_, _| {});
    beats_independent_samples(10608, 160, [17, 17], 4.0, |_, _| {});
    beats_independent_samples(9133, 160, [57, 57], 1.5, |_, _| {});
}

fn beats_independent_samples(
    seed: u64,
    width: u32,
    points: [u32; 2],
    margin: f64,
    setup: impl Fn(&Renderer<'_, I16F16>, u32),
) {
    let (w, h) = (width, width * 3 / 4);
    let text = lensray_testkit::scenegen::generate_lens(seed);
    let truth = reference(&text, w, h, 512, Sampler::Stratified).unwrap();
    for point in points {
        let text = lensray_host::convergence::with_point(&text, point);
        let scene = Scene::<I16F16>::parse(&text).unwrap();
        setup(&Renderer::new(&scene, w, h), point);
        let ind = measure(&text, &truth, Setting::independent(point)).unwrap();
        let def = measure(&text, &truth, Setting::default_render(point)).unwrap();
        println!(
            "seed {seed} point {point}: independent {:.2} dB, default {:.2} dB at {:.1} %",
            ind.psnr,
            def.psnr,
            100.0 * def.rays / point as f64
        );
        assert!(def.rays <= 0.4 * point as f64, "point {point}: {:.2} rays", def.rays);
        assert!(
            def.psnr >= ind.psnr + margin,
            "seed {seed} point {point}: {:.2} dB against {:.2}",
            def.psnr,
            ind.psnr
        );
    }
}
