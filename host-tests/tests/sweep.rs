//! Random-scene sweeps: Q16.16 against f32 on generated scenes and on every
//! scene a sweep ever failed (host-tests/corpus/sweep-regressions/).

use lensray_host::sweep::{measure, run, Summary};
use lensray_testkit::scenegen::Camera;

/// Floors of issue 12: PSNR (dB) and share of pixels within 2 levels.
const MIN_PSNR: f64 = 40.0;
const MIN_WITHIN2: f64 = 0.995;
/// Largest row or column mean error in levels: the floor (seed 59's
/// silhouette pixel, 2.13 before, is decided exactly since fix 10).
const MAX_LINE_160: f64 = 2.0;

/// PSNR floor at 64x48: one pixel of full contrast in one channel alone is
/// 39.6 dB there (a grazing silhouette that a sub-ULP error moves; see
/// docs/accuracy.md), so the small sweep allows one such pixel.
const MIN_PSNR_64: f64 = 35.0;

#[test]
fn small_generated_scenes_meet_the_floors() {
    // 150 seeds of each camera at 64x48 (a single pixel weighs 6 times what it
    // does at 160x120): PSNR, the share within 2 levels and the median.
    let mut all = Vec::new();
    for camera in [Camera::Pinhole, Camera::Lens] {
        all.extend(run(1000..1150, camera, 64, 48));
    }
    let summary = Summary::of(&all);
    println!("{summary}");
    let bad: Vec<String> = all
        .iter()
        .filter(|r| !r.meets(MIN_PSNR_64, MIN_WITHIN2, f64::INFINITY))
        .map(|r| format!("{} {:.1} dB {:.3}", r.name(), r.psnr, r.within2))
        .collect();
    assert!(bad.is_empty(), "under the floors: {bad:?}");
    assert!(summary.median >= 55.0, "median {:.1} dB", summary.median);
}

/// The `.scene` files of a corpus folder, sorted.
fn corpus(sub: &str) -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("corpus")
        .join(sub);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("corpus")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "scene"))
        .collect();
    files.sort();
    files
}

/// The corpus files under the given floors at 160x120, described.
fn under(files: &[std::path::PathBuf], psnr: f64, within2: f64, line: f64) -> Vec<String> {
    files
        .iter()
        .map(|f| (f, measure(&std::fs::read_to_string(f).unwrap(), 0, 160, 120)))
        .filter(|(_, r)| !r.meets(psnr, within2, line))
        .map(|(f, r)| {
            format!(
                "{}: {:.1} dB {:.3} line {:.2}",
                f.display(),
                r.psnr,
                r.within2,
                r.worst_line
            )
        })
        .collect()
}

#[test]
fn every_regression_scene_meets_the_floors() {
    let files = corpus("sweep-regressions");
    assert!(files.len() >= 63, "the corpus lost scenes");
    let bad = under(&files, MIN_PSNR, MIN_WITHIN2, MAX_LINE_160);
    assert!(bad.is_empty(), "under the floors: {bad:?}");
}

/// Scenes still under a floor after the fixes (docs/accuracy.md, "What
/// remains"): each held where it is (PSNR, share within 2 levels, worst line,
/// measured when filed, with a small margin), so that none can get worse unseen.
#[test]
fn open_regression_scenes_get_no_worse() {
    const HELD: [(&str, f64, f64, f64); 10] = [
        ("seed-5116-pinhole", 47.0, 0.999, 2.2),
        ("seed-9206-pinhole", 46.4, 0.999, 3.4),
        ("seed-12124-pinhole", 45.7, 0.999, 2.15),
        ("seed-13193-pinhole", 38.6, 0.999, 2.2),
        ("seed-14296-pinhole", 54.0, 0.997, 3.1),
        ("seed-16044-pinhole", 43.0, 0.999, 2.25),
        ("seed-16119-pinhole", 45.6, 0.996, 11.5),
        ("seed-17035-pinhole", 43.3, 0.999, 2.2),
        ("seed-19249-pinhole", 49.2, 0.999, 2.4),
        ("seed-19271-pinhole", 50.3, 0.998, 3.6),
    ];
    let files = corpus("sweep-regressions/open");
    assert_eq!(files.len(), HELD.len(), "a file without its limits, or a lost one");
    let bad: Vec<String> = files
        .iter()
        .flat_map(|f| {
            let stem = f.file_stem().unwrap().to_str().unwrap();
            let &(_, psnr, within2, line) = HELD.iter().find(|h| h.0 == stem).expect("limits for every open scene");
            under(std::slice::from_ref(f), psnr, within2, line)
        })
        .collect();
    assert!(bad.is_empty(), "worse than when filed: {bad:?}");
}
