//! The host's parallel speedup, measured in pairs: `cargo bench -p lensray-host
//! --bench speedup`.
//!
//! criterion (`benches/render.rs`) measures one thread and all cores minutes
//! apart, so on a shared machine their ratio also measures how the neighbours'
//! load drifted in between. Here each round renders Program 1 at 160x120 for
//! about 40 ms on a rayon pool of one thread and for as long on a pool of all
//! cores, back to back, and the speedup is the median of the rounds' ratios:
//! drift that spans a round cancels out.
//!
//! Each round also measures the machine's *ceiling* the same way: equal spins
//! of arithmetic that share nothing, one after another on one thread or one a
//! core on all of them. Perfectly parallel work gets the ceiling; a render's
//! *efficiency* in a round is its speedup over that round's ceiling. The four
//! batches of a round run in an order that reverses every round.
//!
//! Prints one line a render, for `scripts/bench.sh`:
//! `speedup NAME median=M q1=A q3=B best=F ceiling=C efficiency=E rounds=R
//! threads=T steal=S`, where `best` is the fastest one-thread batch over the
//! fastest all-cores batch, C and E are medians over the same rounds, and S is
//! the share of CPU time the hypervisor took (`/proc/stat`'s steal) during
//! them, or `n/a` where it cannot be read.

use std::time::{Duration, Instant};

use lensray::{Scalar, Scene, I16F16};
use lensray_host::render_image;
use rayon::prelude::*;
use rayon::ThreadPool;

const PROGRAM1: &str = include_str!("../../scenes/paper-program1.scene");
const W: u32 = 160;
const H: u32 = 120;
const ROUNDS: usize = 101;
const BATCH_TIME: Duration = Duration::from_millis(40);

/// Frames rendered in `pool`, `n` of them, and the time they took.
fn frames<S: Scalar + Send + Sync>(pool: &ThreadPool, scene: &Scene<S>, samples: u32, n: u32) -> Duration {
    let start = Instant::now();
    for _ in 0..n {
        std::hint::black_box(pool.install(|| render_image(scene, W, H, Some(samples), &|| {})));
    }
    start.elapsed()
}

/// `spins` equal spins of `n` steps of arithmetic in `pool`, and the time they took.
fn spins(pool: &ThreadPool, spins: usize, n: u64) -> Duration {
    fn spin(n: u64) -> u64 {
        let mut x = 1u64;
        for i in 0..n {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(i) ^ (x >> 13);
        }
        x
    }
    let start = Instant::now();
    pool.install(|| {
        (0..spins).into_par_iter().with_max_len(1).for_each(|_| {
            std::hint::black_box(spin(std::hint::black_box(n)));
        })
    });
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

/// The value at quantile `q` of `v` (nearest rank).
fn quantile(v: &[f64], q: f64) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// One round's four batch times: render on one thread, on all; spins on one, on all.
#[derive(Clone, Copy)]
struct Round {
    render_one: f64,
    render_all: f64,
    spin_one: f64,
    spin_all: f64,
}

fn measure<S: Scalar + Send + Sync>(label: &str, radius: &str, samples: u32) {
    let scene = Scene::<S>::parse(&format!("{PROGRAM1}\n{radius}\n")).unwrap();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let all = rayon::ThreadPoolBuilder::new().build().unwrap();
    let threads = all.current_num_threads();
    // Warm both pools and size each batch to about BATCH_TIME on one thread.
    frames(&all, &scene, samples, 3);
    let per_frame = frames(&one, &scene, samples, 3).as_secs_f64() / 3.0;
    let n_frames = (BATCH_TIME.as_secs_f64() / per_frame).ceil().max(1.0) as u32;
    let probe = 1_000_000;
    let per_step = spins(&one, threads, probe).as_secs_f64() / probe as f64;
    let n_steps = (BATCH_TIME.as_secs_f64() / per_step) as u64;

    let before = cpu_jiffies();
    let rounds: Vec<Round> = (0..ROUNDS)
        .map(|round| {
            let mut r = Round {
                render_one: 0.0,
                render_all: 0.0,
                spin_one: 0.0,
                spin_all: 0.0,
            };
            let mut batches: [&mut dyn FnMut(); 4] = [
                &mut || r.render_one = frames(&one, &scene, samples, n_frames).as_secs_f64(),
                &mut || r.render_all = frames(&all, &scene, samples, n_frames).as_secs_f64(),
                &mut || r.spin_one = spins(&one, threads, n_steps).as_secs_f64(),
                &mut || r.spin_all = spins(&all, threads, n_steps).as_secs_f64(),
            ];
            if round % 2 == 1 {
                batches.reverse();
            }
            batches.iter_mut().for_each(|batch| batch());
            r
        })
        .collect();
    let steal = steal_since(before);

    let speedup: Vec<f64> = rounds.iter().map(|r| r.render_one / r.render_all).collect();
    let ceiling: Vec<f64> = rounds.iter().map(|r| r.spin_one / r.spin_all).collect();
    let efficiency: Vec<f64> = speedup.iter().zip(&ceiling).map(|(s, c)| s / c).collect();
    let fastest = |f: fn(&Round) -> f64| rounds.iter().map(f).fold(f64::INFINITY, f64::min);
    let best = fastest(|r| r.render_one) / fastest(|r| r.render_all);
    println!(
        "speedup program1-{W}x{H}/{}/{label} median={:.3} q1={:.3} q3={:.3} best={best:.3} ceiling={:.3} \
         efficiency={:.3} rounds={ROUNDS} threads={threads} steal={steal}",
        S::NAME,
        quantile(&speedup, 0.5),
        quantile(&speedup, 0.25),
        quantile(&speedup, 0.75),
        quantile(&ceiling, 0.5),
        quantile(&efficiency, 0.5),
    );
}

fn main() {
    // cargo bench passes --bench; `cargo test --benches` does not, and gets no measurement.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    for (label, radius, samples) in [("pinhole", "radius 0", 1u32), ("lens16", "radius 0.2", 16)] {
        measure::<I16F16>(label, radius, samples);
        measure::<f32>(label, radius, samples);
    }
}
