//! The fuzzer as a test: parser and renderer together, any bytes in.
//!
//! `fuzz_parser_and_renderer` runs for `LENSRAY_FUZZ_SECS` seconds (default 60)
//! or `LENSRAY_FUZZ_INPUTS` inputs, whichever comes first, from seed
//! `LENSRAY_FUZZ_SEED` (default fixed, so a failure reproduces). Inputs that
//! break the property are written to `target/fuzz-crashes/` and fail the test;
//! each one found is then kept in `host-tests/corpus/regressions/`, which
//! `every_past_crash_stays_fixed` replays on every run.
//!
//! A campaign: `LENSRAY_FUZZ_SECS=3600 LENSRAY_FUZZ_SEED=7 cargo test -p lensray-host --test fuzz -- --nocapture`.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use lensray_testkit::fuzz::{check_input, escape, kind_name, seed_corpus, Fuzzer, Outcome};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn env_u64(name: &str) -> Option<u64> {
    let v = std::env::var(name).ok()?;
    Some(v.parse().unwrap_or_else(|_| panic!("{name}={v}: not a whole number")))
}

/// Writes `bytes` to `target/fuzz-crashes/NAME` and returns the path.
fn save_crash(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = workspace().join("target/fuzz-crashes");
    std::fs::create_dir_all(&dir).expect("create target/fuzz-crashes");
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write crash input");
    path
}

/// Aborts the process with the input at hand saved when one input takes
/// longer than `limit`: an endless loop is a crash too.
fn watchdog(progress: Arc<AtomicU64>, current: Arc<Mutex<Vec<u8>>>, limit: Duration) {
    std::thread::spawn(move || {
        let mut last = u64::MAX;
        let mut since = Instant::now();
        loop {
            std::thread::sleep(Duration::from_millis(500));
            let now = progress.load(Ordering::Relaxed);
            if now == u64::MAX {
                return;
            }
            if now != last {
                last = now;
                since = Instant::now();
            } else if since.elapsed() > limit {
                let input = current.lock().map(|g| g.clone()).unwrap_or_default();
                let path = save_crash(&format!("hang-{now}.scene"), &input);
                eprintln!("input {now} ran for over {limit:?}: saved to {}", path.display());
                std::process::abort();
            }
        }
    });
}

#[test]
fn fuzz_parser_and_renderer() {
    let secs = env_u64("LENSRAY_FUZZ_SECS").unwrap_or(60);
    let max_inputs = env_u64("LENSRAY_FUZZ_INPUTS").unwrap_or(u64::MAX);
    let seed = env_u64("LENSRAY_FUZZ_SEED").unwrap_or(0x6C65_6E73);
    let corpus = seed_corpus(&workspace());
    let scenes = corpus
        .iter()
        .filter(|(p, _)| p.starts_with(workspace().join("scenes")))
        .count();
    assert!(scenes >= 1, "no seed scenes found in scenes/");
    let mut fuzzer = Fuzzer::new(seed, corpus.into_iter().map(|(_, b)| b).collect());

    let progress = Arc::new(AtomicU64::new(0));
    let current = Arc::new(Mutex::new(Vec::new()));
    watchdog(progress.clone(), current.clone(), Duration::from_secs(30));
    // Panics are caught and reported below; their default message would only repeat them.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));

    let start = Instant::now();
    let deadline = start + Duration::from_secs(secs);
    let mut report_at = start + Duration::from_secs(300);
    while fuzzer.stats.inputs < max_inputs {
        // Reading the clock every 256 inputs keeps it off the profile.
        if fuzzer.stats.inputs.is_multiple_of(256) {
            let now = Instant::now();
            if now >= deadline {
                break;
            }
            if now >= report_at {
                report_at = now + Duration::from_secs(300);
                eprintln!(
                    "fuzz: {} inputs, {} rendered, {} failures, {:.0} s",
                    fuzzer.stats.inputs,
                    fuzzer.stats.rendered,
                    fuzzer.stats.failed,
                    start.elapsed().as_secs_f64()
                );
            }
        }
        let input = fuzzer.next_input();
        current.lock().unwrap().clone_from(&input);
        fuzzer.run_one(input);
        progress.store(fuzzer.stats.inputs, Ordering::Relaxed);
    }
    progress.store(u64::MAX, Ordering::Relaxed);
    std::panic::set_hook(hook);

    let s = &fuzzer.stats;
    let elapsed = start.elapsed().as_secs_f64();
    eprintln!(
        "fuzz: seed {seed}: {} inputs in {elapsed:.1} s ({:.0}/s), {} rendered, {} rejected, {} failures",
        s.inputs,
        s.inputs as f64 / elapsed,
        s.rendered,
        s.inputs - s.rendered - s.failed,
        s.failed
    );
    eprintln!("fuzz: rejections by kind: {:?}", s.kinds);
    let mut report = String::new();
    for (i, (input, msg)) in s.failures.iter().enumerate().take(20) {
        let path = save_crash(&format!("crash-{seed}-{i}.scene"), input);
        report.push_str(&format!(
            "\n{msg}\n  saved to {}\n  input: {}",
            path.display(),
            escape(input, 400)
        ));
    }
    assert!(
        s.failures.is_empty(),
        "{} inputs broke the property:{report}",
        s.failures.len()
    );

    // The fuzzer must reach both ends: the renderer and the parser's many refusals.
    if s.inputs >= 20_000 {
        assert!(
            s.rendered * 10 >= s.inputs,
            "only {} of {} inputs rendered: the fuzzer stays in the parser",
            s.rendered,
            s.inputs
        );
        assert!(
            s.kinds.len() >= 15,
            "only {} error kinds reached: {:?}",
            s.kinds.len(),
            s.kinds
        );
    }
}

/// Every input a fuzz run ever failed on, replayed: the property holds now.
#[test]
fn every_past_crash_stays_fixed() {
    let dir = workspace().join("host-tests/corpus/regressions");
    let mut n = 0;
    for (path, bytes) in seed_corpus(&workspace()) {
        if !path.starts_with(&dir) {
            continue;
        }
        n += 1;
        match check_input(&bytes) {
            Ok(Outcome::Rendered) => {}
            Ok(Outcome::Rejected(e)) => assert!(!kind_name(&e).is_empty()),
            Err(msg) => panic!("{}: {msg}", path.display()),
        }
    }
    assert!(n > 0, "no regression inputs in {}", dir.display());
}

#[test]
fn every_keyword_is_in_the_libfuzzer_dictionary_and_the_format_docs() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dict = std::fs::read_to_string(root.join("fuzz/parse_render.dict")).unwrap();
    let docs = std::fs::read_to_string(root.join("docs/scene-format.md")).unwrap();
    for k in lensray::parse::KEYWORDS {
        assert!(
            dict.contains(&format!("=\"{k}\"")),
            "{k} is missing from fuzz/parse_render.dict"
        );
        assert!(
            docs.contains(&format!("`{k}")),
            "{k} is missing from docs/scene-format.md"
        );
    }
    for w in ["independent", "stratified", "on", "off"] {
        assert!(
            dict.contains(&format!("=\"{w}\"")),
            "{w} is missing from fuzz/parse_render.dict"
        );
    }
}
