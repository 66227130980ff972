//! f32 and Q16.16 against float64 on generated pinhole scenes: whether a
//! change to a number type brings it closer to the truth or not.
//!
//! `cargo run --release -p lensray-host --example f32_truth -- [COUNT] [FIRST_SEED]`
//! or `-- FILE.scene...` (as pinholes; 160x120): per number type, the pixels more than 2 levels from
//! `reference64`, the PSNR against it over all scenes, and the scenes whose
//! f32 image has such pixels; with a hash of every f32 image.
use embedded_graphics::pixelcolor::RgbColor;

use lensray_host::reference64::Scene64;
use lensray_host::render_both;
use lensray_host::sweep::scene_text;
use lensray_testkit::scenegen::Camera;
use std::hash::{Hash, Hasher};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // Scene files (rendered as pinholes), or COUNT FIRST_SEED.
    let texts: Vec<(String, String)> = if args.first().is_some_and(|a| a.ends_with(".scene")) {
        let read = |f: &String| std::fs::read_to_string(f).expect("read") + "\nradius 0\n";
        args.iter().map(|f| (f.clone(), read(f))).collect()
    } else {
        let arg = |i: usize, d: u64| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
        let (count, first) = (arg(0, 300), arg(1, 0));
        (first..first + count)
            .map(|s| (s.to_string(), scene_text(s, Camera::Pinhole)))
            .collect()
    };
    let count = texts.len();
    let (w, h) = (160u32, 120u32);
    // [wrong pixels, squared error] for Q16.16 and f32.
    let mut tot = [[0f64; 2]; 2];
    let mut images = std::collections::hash_map::DefaultHasher::new();
    for (seed, text) in texts {
        let (fixed, float) = lensray_host::both_unadaptive(&text);
        let s64 = Scene64::parse(&text);
        let (a, b) = render_both(&fixed, &float, w, h, None);
        let mut per = [[0f64; 2]; 2];
        for i in 0..(w * h) as usize {
            let (c, r) = (i as u32 % w, i as u32 / w);
            let want = s64.pixel(c, r, w, h).rgb.map(|x| x.clamp(0.0, 255.0).round() as u8);
            for (k, p) in [a.pixels[i], b.pixels[i]].into_iter().enumerate() {
                let got = [p.r(), p.g(), p.b()];
                let e = (0..3).map(|j| got[j].abs_diff(want[j])).max().unwrap();
                per[k][0] += (e > 2) as u8 as f64;
                per[k][1] += (0..3).map(|j| (got[j] as f64 - want[j] as f64).powi(2)).sum::<f64>();
            }
            [b.pixels[i].r(), b.pixels[i].g(), b.pixels[i].b()].hash(&mut images);
        }
        if per[1][0] > 0.0 || std::env::var_os("ALL").is_some() {
            println!(
                "seed {seed}: f32 {} pixels off f64 (squared error {}), Q16.16 {}",
                per[1][0], per[1][1], per[0][0]
            );
        }
        for k in 0..2 {
            tot[k][0] += per[k][0];
            tot[k][1] += per[k][1];
        }
    }
    let n = count as f64 * (w * h) as f64 * 3.0;
    for (k, name) in ["Q16.16", "f32"].into_iter().enumerate() {
        let psnr = 10.0 * (255f64 * 255.0 / (tot[k][1] / n)).log10();
        println!(
            "{name} against f64: {} pixels more than 2 levels off, {psnr:.3} dB over all",
            tot[k][0]
        );
    }
    println!("f32 images hash {:016x}", images.finish());
}
