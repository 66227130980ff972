//! Baked scenes (`lensray::baked`): a renderer baked on the host and loaded
//! back renders the same pixels, bit for bit, for every scene of `scenes/`
//! and for random valid scenes from the fuzzer's grammar, in Q16.16 and f32;
//! every corrupted, truncated, foreign or re-checksummed-but-invalid file
//! gives the right error and never a panic.

use std::path::{Path, PathBuf};

use lensray::baked::{bake, baked_len, BakeError, BakeScalar, Baked, FORMAT_VERSION, HEADER_LEN, MAGIC};
use lensray::{Renderer, Scene, I16F16};
use lensray_testkit::fuzz::{scene_from_grammar, Rng};

fn scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "scene"))
        .collect();
    v.sort();
    assert!(v.len() >= 10, "scenes/ went missing");
    v
}

fn baked_bytes<S: BakeScalar, P: std::borrow::Borrow<lensray::baked::Setup<S>>>(r: &Renderer<'_, S, P>) -> Vec<u8> {
    let mut v = vec![0u8; baked_len(r)];
    let n = bake(r, &mut v).unwrap();
    assert_eq!(n, v.len());
    v
}

/// Bakes the scene at this size and samples, loads it back and compares every pixel.
fn round_trip<S: BakeScalar>(scene: &Scene<S>, w: u32, h: u32, samples: u32, what: &str) {
    let renderer = Renderer::new(scene, w, h).with_samples(samples);
    let bytes = baked_bytes(&renderer);
    // Too small a buffer is refused with the size it needs.
    assert_eq!(
        bake(&renderer, &mut vec![0u8; bytes.len() - 1]),
        Err(BakeError::BufferTooSmall { needed: bytes.len() })
    );
    let mut loaded = Baked::<S>::empty();
    loaded.load(&bytes).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(loaded.size(), (w, h));
    let again = loaded.renderer();
    assert_eq!(again.rays_per_pixel(), renderer.rays_per_pixel(), "{what}");
    for row in 0..h {
        for col in 0..w {
            assert_eq!(
                again.pixel(col, row),
                renderer.pixel(col, row),
                "{what}: pixel ({col}, {row}) differs after baking"
            );
        }
    }
    // Baking the loaded renderer gives the same bytes: nothing was lost or added.
    assert_eq!(baked_bytes(&again), bytes, "{what}: re-baked bytes differ");
    // The firmware's way, the set-up lent rather than copied: the same
    // renderer, as often as asked, and again after a reload.
    assert_eq!(baked_bytes(&loaded.lend()), bytes, "{what}: lent renderer differs");
    assert_eq!(baked_bytes(&loaded.lend()), bytes, "{what}: lent twice");
    loaded.load(&bytes).unwrap();
    assert_eq!(baked_bytes(&loaded.lend()), bytes, "{what}: lent after a reload");
}

#[test]
fn every_scene_renders_bit_for_bit_after_baking() {
    for path in scenes() {
        let text = std::fs::read(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let q = Scene::<I16F16>::parse_bytes(&text).unwrap();
        let f = Scene::<f32>::parse_bytes(&text).unwrap();
        let samples = q.camera.samples.min(3);
        round_trip(&q, 40, 30, samples, &format!("{name} Q16.16"));
        round_trip(&f, 40, 30, samples, &format!("{name} f32"));
    }
}

#[test]
fn random_valid_scenes_render_bit_for_bit_after_baking() {
    let mut rng = Rng::new(0x15_BA4E);
    let mut tried = 0;
    let mut accepted = 0;
    while accepted < 150 {
        tried += 1;
        assert!(tried < 5000, "the grammar gave too few valid scenes");
        let text = scene_from_grammar(&mut rng);
        let (Ok(q), Ok(f)) = (Scene::<I16F16>::parse_bytes(&text), Scene::<f32>::parse_bytes(&text)) else {
            continue;
        };
        accepted += 1;
        let what = String::from_utf8_lossy(&text).into_owned();
        let (w, h) = (1 + rng.below(14) as u32, 1 + rng.below(10) as u32);
        round_trip(&q, w, h, 2, &what);
        round_trip(&f, w, h, 2, &what);
    }
}

/// Program 1-like pinhole scene with every shape, baked small.
fn sample_bake() -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/pinhole-shapes.scene");
    let scene = Scene::<I16F16>::parse_bytes(&std::fs::read(path).unwrap()).unwrap();
    baked_bytes(&Renderer::new(&scene, 16, 12))
}

fn load(bytes: &[u8]) -> Result<(), BakeError> {
    Baked::<I16F16>::empty().load(bytes)
}

#[test]
fn every_byte_flip_gives_the_error_of_its_field() {
    let good = sample_bake();
    assert!(load(&good).is_ok());
    let n = good.len();
    for i in 0..n {
        for mask in [1u8 << (i % 8), 0xFF] {
            let mut bad = good.clone();
            bad[i] ^= mask;
            let e = load(&bad).expect_err("a flipped byte loaded");
            let ok = match i {
                0..=3 => e == BakeError::ForeignMagic,
                4 | 5 => matches!(e, BakeError::Version { found } if found != FORMAT_VERSION),
                6 => matches!(e, BakeError::NumberType { expected: 0, .. }),
                7 => matches!(e, BakeError::OutOfRange(_)),
                8..=11 => matches!(e, BakeError::Truncated { .. } | BakeError::TrailingBytes { .. }),
                _ => e == BakeError::Checksum,
            };
            assert!(ok, "byte {i} ^ {mask:#04x}: {e:?}");
            // Every error reads as a sentence.
            assert!(!e.to_string().is_empty());
        }
    }
}

#[test]
fn truncated_extended_and_foreign_files_are_refused() {
    let good = sample_bake();
    for len in 0..good.len() {
        let e = load(&good[..len]).expect_err("a truncated file loaded");
        assert!(
            matches!(e, BakeError::Truncated { got, .. } if got == len),
            "{len}: {e:?}"
        );
    }
    let mut long = good.clone();
    long.push(0);
    assert!(matches!(load(&long), Err(BakeError::TrailingBytes { .. })));

    // Other files: a scene's text, a PNG's signature, zeros, another magic.
    for foreign in [
        &b"object sphere\ntranslate 0 0 -8\n"[..],
        &[0x89, b'P', b'N', b'G', 13, 10, 26, 10, 0, 0, 0, 13, 0, 0, 0, 0][..],
        &[0u8; 64][..],
        b"LRBX\x01\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00",
    ] {
        assert_eq!(load(foreign), Err(BakeError::ForeignMagic));
    }

    // A Q16.16 bake read by an f32 renderer, and the other way round.
    let e = Baked::<f32>::empty().load(&good).unwrap_err();
    assert_eq!(e, BakeError::NumberType { found: 0, expected: 1 });
    assert!(e.to_string().contains("Q16.16") && e.to_string().contains("f32"));
    let scene = Scene::<f32>::parse("object sphere\ntranslate 0 0 -8\n").unwrap();
    let f = baked_bytes(&Renderer::new(&scene, 4, 3));
    assert_eq!(load(&f), Err(BakeError::NumberType { found: 1, expected: 0 }));

    // A later version, checksummed as such, is refused by version.
    let mut next = good.clone();
    next[4..6].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    rechecksum(&mut next);
    assert_eq!(
        load(&next),
        Err(BakeError::Version {
            found: FORMAT_VERSION + 1
        })
    );
    assert_eq!(&good[..4], &MAGIC);
}

/// Rewrites the CRC-32 after an edit: the file is then intact but may hold nonsense.
fn rechecksum(bytes: &mut [u8]) {
    let n = bytes.len() - 4;
    let crc = lensray::baked::crc32(&bytes[..n]);
    bytes[n..].copy_from_slice(&crc.to_le_bytes());
}

/// Files with a valid checksum and random payload edits (a faulty or hostile
/// baker): each either loads and renders every pixel without a panic (in a
/// build with overflow checks), or is refused as out of range.
fn hostile_payloads<S: BakeScalar>(good: &[u8], seed: u64, rounds: usize) -> (usize, usize) {
    let mut rng = Rng::new(seed);
    let (mut refused, mut rendered) = (0, 0);
    let payload = HEADER_LEN..good.len() - 4;
    for _ in 0..rounds {
        let mut bad = good.to_vec();
        for _ in 0..1 + rng.below(4) {
            let i = payload.start + rng.below(payload.len());
            bad[i] = match rng.below(4) {
                0 => bad[i] ^ (1 << rng.below(8)),
                1 => 0xFF,
                2 => 0x80,
                _ => rng.next_u64() as u8,
            };
        }
        rechecksum(&mut bad);
        let mut loaded = Baked::<S>::empty();
        match loaded.load(&bad) {
            Ok(()) => {
                // A mutated sample count of thousands would only make the test slow.
                let r = loaded.renderer();
                let r = if r.rays_per_pixel() > 16 { r.with_samples(16) } else { r };
                let (w, h) = loaded.size();
                for row in 0..h.min(12) {
                    for col in 0..w.min(16) {
                        let _ = r.pixel(col, row);
                    }
                }
                rendered += 1;
            }
            Err(BakeError::OutOfRange(_) | BakeError::Payload) => refused += 1,
            Err(e) => panic!("unexpected error for an intact file: {e:?}"),
        }
    }
    (refused, rendered)
}

#[test]
fn intact_files_with_nonsense_values_never_panic() {
    let scene_text =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/paper-program1.scene")).unwrap();
    let q = Scene::<I16F16>::parse_bytes(&scene_text).unwrap();
    let f = Scene::<f32>::parse_bytes(&scene_text).unwrap();
    let (refused, rendered) =
        hostile_payloads::<I16F16>(&baked_bytes(&Renderer::new(&q, 16, 12).with_samples(2)), 1, 5000);
    assert!(
        refused > 0 && rendered > 0,
        "Q16.16: {refused} refused, {rendered} rendered"
    );
    let (refused, rendered) =
        hostile_payloads::<f32>(&baked_bytes(&Renderer::new(&f, 16, 12).with_samples(2)), 2, 5000);
    assert!(
        refused > 0 && rendered > 0,
        "f32: {refused} refused, {rendered} rendered"
    );
}

/// A refused file leaves the scene exactly as `Baked::empty()`, even after a
/// good load and a refusal halfway through the payload (`Baked::clear`).
#[test]
fn a_refused_file_leaves_an_empty_scene() {
    let good = sample_bake();
    let empty = format!("{:?}", Baked::<I16F16>::empty());
    let mut rng = Rng::new(15);
    let payload = HEADER_LEN..good.len() - 4;
    let mut refused = 0;
    for _ in 0..400 {
        let mut bad = good.clone();
        let i = payload.start + rng.below(payload.len());
        bad[i] = rng.next_u64() as u8;
        rechecksum(&mut bad);
        let mut loaded = Baked::<I16F16>::empty();
        loaded.load(&good).unwrap();
        assert_ne!(format!("{loaded:?}"), empty);
        if loaded.load(&bad).is_err() {
            refused += 1;
            assert_eq!(format!("{loaded:?}"), empty, "byte {i} = {:#04x}", bad[i]);
        }
    }
    // Enough refusals past the header that the reset is exercised.
    assert!(refused >= 20, "only {refused} refused");
}

#[test]
fn an_adaptive_frame_keeps_its_stop_rule_after_baking() {
    // Program 1 at 64x48 and 40 samples: adaptive, so the pre-pass in
    // `Renderer::new` sets a stop rule, which travels in the baked bytes
    // (the board never runs the pre-pass).
    let path = scenes()
        .into_iter()
        .find(|p| p.ends_with("paper-program1.scene"))
        .unwrap();
    let text = std::fs::read(&path).unwrap();
    let q = Scene::<I16F16>::parse_bytes(&text).unwrap();
    let f = Scene::<f32>::parse_bytes(&text).unwrap();
    for samples in [40, q.camera.samples] {
        let r = Renderer::new_with_samples(&q, 64, 48, Some(samples));
        let rule = r.stop_rule().expect("Program 1 is adaptive: a stop rule");
        assert!(rule.survey_rays > 0 && rule.pilot >= 4, "{rule:?}");
        round_trip(&q, 64, 48, samples, "Program 1 adaptive Q16.16");
        round_trip(&f, 64, 48, samples, "Program 1 adaptive f32");
        let mut loaded = Baked::<I16F16>::empty();
        loaded.load(&baked_bytes(&r)).unwrap();
        assert_eq!(loaded.renderer().stop_rule(), Some(rule));
        // The firmware's way: the renderer lent the loaded scene's set-up.
        let again = loaded.lend();
        assert_eq!(again.stop_rule(), Some(rule));
        // Rows and their rays the same after baking.
        let (mut a, mut b) = (vec![Default::default(); 64], vec![Default::default(); 64]);
        for row in 0..48 {
            assert_eq!(
                again.render_row(row, &mut a),
                r.render_row(row, &mut b),
                "row {row}'s rays"
            );
            assert_eq!(a, b, "row {row}");
        }
    }
}

/// A frame without a stop rule (one sample, or `adaptive off`) bakes none,
/// and every pixel casts all its samples; a frame with too few samples for
/// two pilots bakes plain samples within 40 % (no threshold), and every
/// pixel casts those.
#[test]
fn a_frame_without_a_stop_rule_bakes_none() {
    let path = scenes()
        .into_iter()
        .find(|p| p.ends_with("paper-program1.scene"))
        .unwrap();
    let text = String::from_utf8(std::fs::read(&path).unwrap()).unwrap();
    let q = Scene::<I16F16>::parse(&text).unwrap();
    let off = Scene::<I16F16>::parse(&format!("{text}\nadaptive off\n")).unwrap();
    for (scene, samples, cast) in [(&q, 1, 1), (&off, 40, 40), (&q, 7, 2), (&q, 15, 6)] {
        let r = Renderer::new_with_samples(scene, 24, 18, Some(samples));
        let plain = (cast < samples).then_some(lensray::StopRule {
            pilot: cast,
            threshold: u32::MAX,
            survey_rays: 0,
        });
        assert_eq!(r.stop_rule(), plain, "{samples} samples");
        let mut loaded = Baked::<I16F16>::empty();
        loaded.load(&baked_bytes(&r)).unwrap();
        let again = loaded.renderer();
        assert_eq!(again.stop_rule(), plain);
        assert_eq!(again.rays_per_pixel(), cast);
        let mut row = vec![Default::default(); 24];
        assert_eq!(again.render_row(9, &mut row), 24 * cast);
    }
}
