//! The fuzzer as a test: parser and renderer together, any bytes in.
//!
//! `fuzz_parser_and_renderer` checks `LENSRAY_FUZZ_INPUTS` inputs (default
//! 20,000, about a minute on two cores), or runs for `LENSRAY_FUZZ_SECS`
//! seconds when that is set (`bash scripts/test-all.sh` runs it for 20,
//! `bash scripts/campaigns.sh` for 600), from seed `LENSRAY_FUZZ_SEED` (default fixed, so a failure reproduces). It
//! is a campaign, left out of a plain `cargo test`: run it with `--ignored`.
//! Inputs that break the property are written to `target/fuzz-crashes/` and
//! fail the test; each one found is then kept in
//! `host-tests/corpus/regressions/` with the outcome it must have now, which
//! `every_past_crash_stays_fixed` replays on every run.
//!
//! An hour: `LENSRAY_FUZZ_SECS=3600 LENSRAY_FUZZ_SEED=7 cargo test -p lensray-host --test fuzz -- --ignored --nocapture`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use lensray::{Scene, I16F16};
use lensray_testkit::fuzz::{check_input, escape, kind_name, seed_corpus, Fuzzer, Outcome};

/// Inputs of a run without `LENSRAY_FUZZ_SECS`.
const DEFAULT_INPUTS: u64 = 20_000;

/// Error kinds every run of at least [`DEFAULT_INPUTS`] inputs must reach:
/// the default seed's run reaches all 26, the rarest (ApertureTooWide) once.
const KINDS_FLOOR: usize = 22;

/// The keywords that start a line of `input`.
fn statements(input: &[u8]) -> impl Iterator<Item = &[u8]> {
    input
        .split(|&b| b == b'\n')
        .filter_map(|line| line.split(|b| b.is_ascii_whitespace()).find(|w| !w.is_empty()))
}

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
#[ignore = "campaign: scripts/campaigns.sh (20 s of it in scripts/test-all.sh)"]
fn fuzz_parser_and_renderer() {
    let secs = env_u64("LENSRAY_FUZZ_SECS");
    let max_inputs = env_u64("LENSRAY_FUZZ_INPUTS").unwrap_or(if secs.is_some() { u64::MAX } else { DEFAULT_INPUTS });
    let secs = secs.unwrap_or(u64::MAX / 4);
    let seed = env_u64("LENSRAY_FUZZ_SEED").unwrap_or(0x6C65_6E73);
    let corpus = seed_corpus(&workspace());
    let scenes = corpus
        .iter()
        .filter(|(p, _)| p.starts_with(workspace().join("scenes")))
        .count();
    assert!(scenes >= 1, "no seed scenes found in scenes/");
    let mut fuzzer = Fuzzer::new(seed, corpus.into_iter().map(|(_, b)| b).collect());

    let start = Instant::now();
    let rendered_keywords = run_for(&mut fuzzer, max_inputs, secs);

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

    // The fuzzer must reach both ends, at any length of run: the renderer with
    // every statement of the format, and the parser's many refusals.
    assert!(s.inputs >= 1_000, "only {} inputs: too few to say anything", s.inputs);
    assert!(
        s.rendered * 10 >= s.inputs,
        "only {} of {} inputs rendered: the fuzzer stays in the parser",
        s.rendered,
        s.inputs
    );
    let unseen: Vec<&str> = lensray::KEYWORDS
        .iter()
        .filter(|k| !rendered_keywords.contains(k.as_bytes()))
        .copied()
        .collect();
    assert!(unseen.is_empty(), "no rendered input had these statements: {unseen:?}");
    // Fewer inputs reach fewer kinds: the floor scales down below the default run.
    let floor = (KINDS_FLOOR as u64 * s.inputs.min(DEFAULT_INPUTS) / DEFAULT_INPUTS) as usize;
    assert!(
        s.kinds.len() >= floor,
        "only {} error kinds reached in {} inputs (at least {floor}): {:?}",
        s.kinds.len(),
        s.inputs,
        s.kinds
    );
}

/// Runs `fuzzer` until `max_inputs` inputs or `secs` seconds, whichever is
/// first, under a watchdog, with panics caught quietly (the fuzzer reports
/// them); the keywords that began a statement of an input that rendered.
fn run_for(fuzzer: &mut Fuzzer, max_inputs: u64, secs: u64) -> BTreeSet<Vec<u8>> {
    let progress = Arc::new(AtomicU64::new(0));
    let current = Arc::new(Mutex::new(Vec::new()));
    watchdog(progress.clone(), current.clone(), Duration::from_secs(30));
    // Panics are caught and reported below; their default message would only repeat them.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));

    // Keywords that began a statement of an input that rendered: the renderer saw them.
    let mut rendered_keywords: BTreeSet<Vec<u8>> = BTreeSet::new();
    let start = Instant::now();
    let deadline = start
        .checked_add(Duration::from_secs(secs))
        .unwrap_or(start + Duration::from_secs(1 << 40));
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
        let rendered = fuzzer.stats.rendered;
        fuzzer.run_one(input);
        if fuzzer.stats.rendered > rendered {
            let input = current.lock().unwrap();
            rendered_keywords.extend(statements(&input).map(<[u8]>::to_vec));
        }
        progress.store(fuzzer.stats.inputs, Ordering::Relaxed);
    }
    progress.store(u64::MAX, Ordering::Relaxed);
    std::panic::set_hook(hook);
    rendered_keywords
}

/// What a regression input must come to now, from its `# expect: rendered`
/// or `# expect: rejected KIND` line: a fixed crash that is suddenly refused
/// earlier would no longer reach the code that crashed.
fn expected_outcome(bytes: &[u8]) -> Option<String> {
    let text = String::from_utf8_lossy(bytes);
    text.lines()
        .find_map(|l| l.strip_prefix("# expect:"))
        .map(|e| e.trim().to_string())
}

/// What an outcome is called in an `# expect:` line.
fn outcome_name(outcome: &Outcome) -> String {
    match outcome {
        Outcome::Rendered => "rendered".into(),
        Outcome::Rejected(e) => format!("rejected {}", kind_name(e)),
    }
}

/// Every input a fuzz run ever failed on, replayed: the property holds now,
/// and each comes to the outcome written in it.
#[test]
fn every_past_crash_stays_fixed() {
    let dir = workspace().join("host-tests/corpus/regressions");
    let mut n = 0;
    for (path, bytes) in seed_corpus(&workspace()) {
        if !path.starts_with(&dir) {
            continue;
        }
        n += 1;
        let want = expected_outcome(&bytes).unwrap_or_else(|| {
            panic!(
                "{}: no `# expect: rendered` or `# expect: rejected KIND` line",
                path.display()
            )
        });
        match check_input(&bytes) {
            Ok(outcome) => assert_eq!(outcome_name(&outcome), want, "{}", path.display()),
            Err(msg) => panic!("{}: {msg}", path.display()),
        }
    }
    assert!(n > 0, "no regression inputs in {}", dir.display());
}

/// `kind_name` is the error kind's variant name, the key of the fuzzer's
/// counts and of `# expect:` lines, for kinds with and without fields.
#[test]
fn kind_name_is_the_variant_name() {
    for (text, kind) in [
        ("bogus 1\n", "UnknownKeyword"),
        ("object torus\n", "UnknownShape"),
        ("width 1 2\n", "WrongCount"),
        ("width abc\n", "NotANumber"),
        ("shadows maybe\n", "NotASwitch"),
    ] {
        let e = Scene::<I16F16>::parse(text).expect_err(text);
        assert_eq!(kind_name(&e), kind, "{text:?}: {:?}", e.kind);
        // The name is the start of the Debug text and nothing more.
        let debug = format!("{:?}", e.kind);
        assert!(
            debug == kind || debug.starts_with(&format!("{kind} {{")) || debug.starts_with(&format!("{kind}(")),
            "{debug}"
        );
    }
}

#[test]
fn every_keyword_is_in_the_libfuzzer_dictionary_and_the_format_docs() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dict = std::fs::read_to_string(root.join("fuzz/parse_render.dict")).unwrap();
    let docs = std::fs::read_to_string(root.join("docs/scene-format.md")).unwrap();
    for k in lensray::KEYWORDS {
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

/// `fuzz/` (libFuzzer's crate) resolves to the library and the test kit
/// without the command's dependencies: its lock file (kept current by
/// `cargo check --locked` in the test command) names none of them.
#[test]
fn the_fuzz_crate_needs_none_of_the_commands_dependencies() {
    let lock = std::fs::read_to_string(workspace().join("fuzz/Cargo.lock")).unwrap();
    let packages: Vec<&str> = lock
        .lines()
        .filter_map(|l| l.strip_prefix("name = \"")?.strip_suffix('"'))
        .collect();
    assert!(packages.contains(&"lensray-testkit"), "{packages:?}");
    for heavy in ["lensray-host", "rayon", "image", "indicatif", "clap", "tinybmp"] {
        assert!(!packages.contains(&heavy), "fuzz/ depends on {heavy}");
    }
}
