//! Host rendering speed: rays per second for Q16.16 and f32, on one thread and
//! on all cores (rows in parallel), both through `render_image` (one thread is a
//! rayon pool of one). `cargo bench -p lensray-host --bench render`;
//! `scripts/bench.sh` turns the medians into BENCHMARKS.md.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use lensray::{Scalar, Scene, I16F16};
use lensray_host::render_image;

const PROGRAM1: &str = include_str!("../../scenes/paper-program1.scene");
const W: u32 = 160;
const H: u32 = 120;

fn scene<S: Scalar>(radius: &str) -> Scene<S> {
    Scene::<S>::parse(&format!("{PROGRAM1}\n{radius}\n")).unwrap()
}

fn bench_type<S: Scalar + Send + Sync>(c: &mut Criterion) {
    // The same code on one worker and on all of them, so the ratio is the speedup of
    // rendering rows in parallel and nothing else.
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let mut g = c.benchmark_group(format!("program1-160x120/{}", S::NAME));
    g.sample_size(20);
    for (label, radius, samples) in [("pinhole", "radius 0", 1u32), ("lens16", "radius 0.2", 16)] {
        let s = scene::<S>(radius);
        g.throughput(Throughput::Elements((W * H * samples) as u64));
        g.bench_function(BenchmarkId::new("1-thread", label), |b| {
            b.iter(|| one.install(|| render_image(&s, W, H, Some(samples), &|| {})))
        });
        g.bench_function(BenchmarkId::new("all-cores", label), |b| {
            b.iter(|| render_image(&s, W, H, Some(samples), &|| {}))
        });
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
    bench_type::<I16F16>(c);
    bench_type::<f32>(c);
}

criterion_group!(render, benches);
criterion_main!(render);
