//! What aperture blades cost: lens points per second on a round lens and on
//! polygons (the stratified sampler's map of the unit square onto the
//! aperture, `Aperture::map_q16`), and Program 1 with 16 rays a pixel through
//! a round and a six-bladed lens (Q16.16, one thread).
//! `cargo bench -p lensray-host --bench aperture`.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::RgbColor;
use lensray::{Aperture, Renderer, Scene, I16F16};

const PROGRAM1: &str = include_str!("../../scenes/paper-program1.scene");

fn samples(c: &mut Criterion) {
    let mut g = c.benchmark_group("lens-samples");
    g.sample_size(20);
    const N: u64 = 10_000;
    g.throughput(Throughput::Elements(N));
    for blades in [0u32, 3, 5, 6, 16] {
        let ap = Aperture::regular(blades, 0.0);
        g.bench_function(BenchmarkId::new("blades", blades), |b| {
            b.iter(|| {
                // Unit-square points from a xorshift, as 16-bit fractions.
                let mut s = 0x2545_F491u32;
                let mut acc = 0i64;
                for _ in 0..N {
                    s ^= s << 13;
                    s ^= s >> 17;
                    s ^= s << 5;
                    let (x, y) = ap.map_q16(s as u16, (s >> 16) as u16);
                    acc += (x ^ y) as i64;
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

fn render(c: &mut Criterion) {
    let (w, h, n) = (160u32, 120u32, 16u32);
    let mut g = c.benchmark_group("program1-160x120-lens16/Q16.16");
    g.sample_size(10);
    g.throughput(Throughput::Elements((w * h * n) as u64));
    for blades in [0u32, 6] {
        let scene = Scene::<I16F16>::parse(&format!("{PROGRAM1}\naperture_blades {blades}\n")).unwrap();
        g.bench_function(BenchmarkId::new("blades", blades), |b| {
            b.iter(|| {
                let r = Renderer::new_with_samples(&scene, w, h, Some(n));
                let mut row = [Rgb888::BLACK; 160];
                let mut sum = 0u64;
                for y in 0..h {
                    r.render_row(y, &mut row);
                    sum += row.iter().map(|p| p.g() as u64).sum::<u64>();
                }
                sum
            })
        });
    }
    g.finish();
}

criterion_group!(aperture, samples, render);
criterion_main!(aperture);
