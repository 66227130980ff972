//! The host's parallel speedup, measured in pairs: `cargo bench -p lensray-host
//! --bench speedup`.
//!
//! criterion (`benches/render.rs`) measures one thread and all cores minutes
//! apart, so on a shared machine their ratio also measures how the neighbours'
//! load drifted in between. Here each round renders Program 1 at 160x120 for
//! about 40 ms on a rayon pool of one thread and for as long on a pool of all
//! cores, back to back (the order alternating), and the speedup is the median
//! of the rounds' ratios: drift that spans a round cancels out.
//!
//! Prints one line a render, for `scripts/bench.sh`:
//! `speedup NAME median=M q1=A q3=B rounds=R threads=T steal=S`, where S is the
//! share of CPU time the hypervisor took (`/proc/stat`'s steal) during that
//! render's rounds, or `n/a` where it cannot be read.

use std::time::{Duration, Instant};

use lensray::{Scalar, Scene, I16F16};
use lensray_host::render_image;

const PROGRAM1: &str = include_str!("../../scenes/paper-program1.scene");
const W: u32 = 160;
const H: u32 = 120;
const ROUNDS: usize = 101;
const BATCH_TIME: Duration = Duration::from_millis(40);

/// Frames rendered in `pool`, `n` of them, and the time they took.
fn frames<S: Scalar + Send + Sync>(pool: &rayon::ThreadPool, scene: &Scene<S>, samples: u32, n: u32) -> Duration {
    let start = Instant::now();
    for _ in 0..n {
        std::hint::black_box(pool.install(|| render_image(scene, W, H, Some(samples), &|| {})));
    }
    start.elapsed()
}

/// (steal, total) jiffies of all CPUs so far, on Linux.
fn cpu_jiffies() -> Option<(u64, u64)> {
    let stat = std::fs::read_to_string("/proc/stat").ok()?;
    let fields: Vec<u64> = stat
        .lines()
        .next()?
        .split_whitespace()
        .skip(1)
        .map(|f| f.parse().ok())
        .collect::<Option<_>>()?;
    // user nice system idle iowait irq softirq steal ...; guest time is already in user.
    Some((*fields.get(7)?, fields.iter().take(8).sum()))
}

/// The share of CPU time stolen since `before`, as text.
fn steal_since(before: Option<(u64, u64)>) -> String {
    match (before, cpu_jiffies()) {
        (Some((s0, t0)), Some((s1, t1))) if t1 > t0 => format!("{:.1}%", 100.0 * (s1 - s0) as f64 / (t1 - t0) as f64),
        _ => "n/a".into(),
    }
}

/// The value at quantile `q` of sorted `v` (nearest rank).
fn quantile(v: &[f64], q: f64) -> f64 {
    v[((v.len() - 1) as f64 * q).round() as usize]
}

fn measure<S: Scalar + Send + Sync>(label: &str, radius: &str, samples: u32) {
    let scene = Scene::<S>::parse(&format!("{PROGRAM1}\n{radius}\n")).unwrap();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let all = rayon::ThreadPoolBuilder::new().build().unwrap();
    // Warm both pools and size a batch to about BATCH_TIME on one thread.
    frames(&all, &scene, samples, 3);
    let per_frame = frames(&one, &scene, samples, 3) / 3;
    let n = (BATCH_TIME.as_secs_f64() / per_frame.as_secs_f64()).ceil().max(1.0) as u32;
    let before = cpu_jiffies();
    let mut ratios: Vec<f64> = (0..ROUNDS)
        .map(|round| {
            let (t_one, t_all) = if round % 2 == 0 {
                let t_one = frames(&one, &scene, samples, n);
                (t_one, frames(&all, &scene, samples, n))
            } else {
                let t_all = frames(&all, &scene, samples, n);
                (frames(&one, &scene, samples, n), t_all)
            };
            t_one.as_secs_f64() / t_all.as_secs_f64()
        })
        .collect();
    let steal = steal_since(before);
    ratios.sort_by(f64::total_cmp);
    println!(
        "speedup program1-{W}x{H}/{}/{label} median={:.3} q1={:.3} q3={:.3} rounds={ROUNDS} threads={} steal={steal}",
        S::NAME,
        quantile(&ratios, 0.5),
        quantile(&ratios, 0.25),
        quantile(&ratios, 0.75),
        all.current_num_threads(),
    );
}

/// The same paired rounds for work with nothing shared: `threads` equal spins
/// of arithmetic, one after another on one thread, or side by side on all of them.
fn ceiling(threads: usize) {
    fn spin(n: u64) -> u64 {
        let mut x = 1u64;
        for i in 0..n {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(i) ^ (x >> 13);
        }
        x
    }
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let all = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let run = |pool: &rayon::ThreadPool, n: u64| {
        let start = Instant::now();
        pool.install(|| {
            use rayon::prelude::*;
            (0..threads).into_par_iter().with_max_len(1).for_each(|_| {
                std::hint::black_box(spin(std::hint::black_box(n)));
            })
        });
        start.elapsed()
    };
    let probe = 1_000_000;
    let n = (probe as f64 * BATCH_TIME.as_secs_f64() / run(&one, probe).as_secs_f64()) as u64;
    let before = cpu_jiffies();
    let mut ratios: Vec<f64> = (0..ROUNDS)
        .map(|_| run(&one, n).as_secs_f64() / run(&all, n).as_secs_f64())
        .collect();
    ratios.sort_by(f64::total_cmp);
    println!(
        "speedup machine-ceiling median={:.3} q1={:.3} q3={:.3} rounds={ROUNDS} threads={threads} steal={}",
        quantile(&ratios, 0.5),
        quantile(&ratios, 0.25),
        quantile(&ratios, 0.75),
        steal_since(before),
    );
}

fn main() {
    // cargo bench passes --bench; `cargo test --benches` does not, and gets no measurement.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    ceiling(rayon::current_num_threads());
    for (label, radius, samples) in [("pinhole", "radius 0", 1u32), ("lens16", "radius 0.2", 16)] {
        measure::<I16F16>(label, radius, samples);
        measure::<f32>(label, radius, samples);
    }
}
