//! Host rendering speed: rays per second for Q16.16 and f32, on one thread and
//! on all cores (rows in parallel). `cargo bench -p lensray-host --bench render`;
//! `scripts/bench.sh` turns the medians into BENCHMARKS.md.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::RgbColor;
use lensray::{Renderer, Scalar, Scene, I16F16};
use lensray_host::render_image;

const PROGRAM1: &str = include_str!("../../scenes/paper-program1.scene");
const W: u32 = 160;
const H: u32 = 120;

fn scene<S: Scalar>(radius: &str) -> Scene<S> {
    Scene::<S>::parse(&format!("{PROGRAM1}\n{radius}\n")).unwrap()
}

/// Renders row after row on the calling thread.
fn single<S: Scalar>(scene: &Scene<S>, samples: u32) -> u64 {
    let r = Renderer::new(scene, W, H).with_samples(samples);
    let mut row = [Rgb888::BLACK; W as usize];
    let mut sum = 0u64;
    for y in 0..H {
        r.render_row(y, &mut row);
        sum += row.iter().map(|p| p.g() as u64).sum::<u64>();
    }
    sum
}

fn bench_type<S: Scalar + Send + Sync>(c: &mut Criterion) {
    let mut g = c.benchmark_group(format!("program1-160x120/{}", S::NAME));
    g.sample_size(10);
    for (label, radius, samples) in [("pinhole", "radius 0", 1u32), ("lens16", "radius 0.2", 16)] {
        let s = scene::<S>(radius);
        g.throughput(Throughput::Elements((W * H * samples) as u64));
        g.bench_function(BenchmarkId::new("1-thread", label), |b| b.iter(|| single(&s, samples)));
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
