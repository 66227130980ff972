//! Lens sample patterns compared (experiment): PSNR against a converged
//! reference at N samples a pixel, adaptive off, for each pattern.
//! `lens_pattern WIDTH REF N1,N2,.. PATTERNS ITEM...` (ITEM: a seed of the
//! generator's lens scenes or a scene file; PATTERNS e.g. 0,1,3).
use lensray::unstable::sampler::{Sampler, PATTERN};
use lensray_host::convergence::{measure, reference, Setting};
use std::sync::atomic::Ordering;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let w: u32 = a[1].parse().unwrap();
    let ref_n: u32 = a[2].parse().unwrap();
    let ns: Vec<u32> = a[3].split(',').map(|x| x.parse().unwrap()).collect();
    let pats: Vec<u8> = a[4].split(',').map(|x| x.parse().unwrap()).collect();
    let h = w * 3 / 4;
    let mut gain = vec![vec![0.0f64; ns.len()]; pats.len()];
    let mut items = 0;
    for item in &a[5..] {
        let text = match item.parse::<u64>() {
            Ok(seed) => lensray_testkit::scenegen::generate_lens(seed),
            Err(_) => std::fs::read_to_string(item).unwrap(),
        };
        PATTERN.store(0, Ordering::Relaxed);
        let truth = reference(&text, w, h, ref_n, Sampler::Stratified).unwrap();
        let ind: Vec<f64> = ns
            .iter()
            .map(|&n| measure(&text, &truth, Setting::independent(n)).unwrap().psnr)
            .collect();
        if !ind.iter().all(|p| p.is_finite()) {
            continue;
        }
        items += 1;
        println!("{item}: independent {}", fmt(&ind));
        for (pi, &p) in pats.iter().enumerate() {
            PATTERN.store(p, Ordering::Relaxed);
            let got: Vec<f64> = ns
                .iter()
                .map(|&n| {
                    measure(&text, &truth, Setting { samples: n, sampler: Sampler::Stratified, adaptive: false })
                        .unwrap()
                        .psnr
                })
                .collect();
            for (k, g) in got.iter().enumerate() {
                gain[pi][k] += g - ind[k];
            }
            println!("  pattern {p}: {}", fmt(&got));
        }
    }
    println!("mean gain over independent (dB), {items} scenes, N = {ns:?}");
    for (pi, &p) in pats.iter().enumerate() {
        let g: Vec<f64> = gain[pi].iter().map(|g| g / items as f64).collect();
        println!("  pattern {p}: {}", fmt(&g));
    }
}

fn fmt(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:6.2}")).collect::<Vec<_>>().join(" ")
}
