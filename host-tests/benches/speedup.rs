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
//! Each round also measures the *ceiling*, the best speedup this machine gives
//! the same work at that moment: as many whole frames, each rendered row after
//! row by one thread, one after another on one thread or side by side, one a
//! core. Nothing is split or shared there, so what it falls short of the core
//! count is the machine's (vCPUs of unequal speed, neighbours on the host); a
//! render's *efficiency* in a round is its speedup over that round's ceiling,
//! what splitting a frame's rows costs. The four batches of a round run in an
//! order that reverses every round.
//!
//! Prints one line a render, for `scripts/bench.sh`:
//! `speedup NAME median=M q1=A q3=B best=F ceiling=C efficiency=E rounds=R
//! threads=T steal=S`, where `best` is the fastest one-thread batch over the
//! fastest all-cores batch, C and E are medians over the same rounds, and S is
//! the share of CPU time the hypervisor took (`/proc/stat`'s steal) during
//! them, or `n/a` where it cannot be read.

use std::time::{Duration, Instant};

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use lensray::{Renderer, Scalar, Scene, I16F16};
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

/// `jobs` whole frames, each rendered row after row by one thread, in `pool`:
/// one after another on a pool of one, side by side on a pool of all cores.
/// The same work with nothing split, so the best any split of it could do.
fn whole_frames<S: Scalar + Send + Sync>(pool: &ThreadPool, scene: &Scene<S>, samples: u32, jobs: usize) -> Duration {
    let start = Instant::now();
    pool.install(|| {
        (0..jobs).into_par_iter().with_max_len(1).for_each(|_| {
            let renderer = Renderer::new_with_samples(scene, W, H, Some(samples));
            let mut row = [Rgb888::BLACK; W as usize];
            for y in 0..H {
                renderer.render_row(y, &mut row);
            }
            std::hint::black_box(row);
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

/// One round's four times a frame: rows in parallel on one thread and on all;
/// whole frames on one thread and side by side on all.
#[derive(Clone, Copy)]
struct Round {
    render_one: f64,
    render_all: f64,
    whole_one: f64,
    whole_all: f64,
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
    // The ceiling's batch: as many frames as a render batch, one job a core.
    let ceiling_jobs = (n_frames as usize).div_ceil(threads) * threads;

    let before = cpu_jiffies();
    // Each batch's time a frame, in the order of Round's fields.
    let batches: [&dyn Fn() -> f64; 4] = [
        &|| frames(&one, &scene, samples, n_frames).as_secs_f64() / n_frames as f64,
        &|| frames(&all, &scene, samples, n_frames).as_secs_f64() / n_frames as f64,
        &|| whole_frames(&one, &scene, samples, ceiling_jobs).as_secs_f64() / ceiling_jobs as f64,
        &|| whole_frames(&all, &scene, samples, ceiling_jobs).as_secs_f64() / ceiling_jobs as f64,
    ];
    let rounds: Vec<Round> = (0..ROUNDS)
        .map(|round| {
            let mut t = [0.0; 4];
            for i in 0..4 {
                let i = if round % 2 == 1 { 3 - i } else { i };
                t[i] = batches[i]();
            }
            Round {
                render_one: t[0],
                render_all: t[1],
                whole_one: t[2],
                whole_all: t[3],
            }
        })
        .collect();
    let steal = steal_since(before);

    let speedup: Vec<f64> = rounds.iter().map(|r| r.render_one / r.render_all).collect();
    let ceiling: Vec<f64> = rounds.iter().map(|r| r.whole_one / r.whole_all).collect();
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
