//! Where a low-`point` render's error is, beside `point` independent samples':
//! `gap_errors SEED POINT WIDTH OUT_PREFIX` writes OUT_PREFIX-{ours,ind,ref}.png
//! (errors ×8) and prints the error by row-band.
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use lensray::unstable::sampler::Sampler;
use lensray_host::convergence::{reference, render_text, Setting};
use lensray_host::{encode, Format, Image};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let (seed, p, w): (u64, u32, u32) = (a[1].parse().unwrap(), a[2].parse().unwrap(), a[3].parse().unwrap());
    let h = w * 3 / 4;
    let g = lensray_testkit::scenegen::generate_lens(seed);
    let text = lensray_host::convergence::with_point(&g, p);
    let truth = reference(&text, w, h, 1024, Sampler::Stratified).unwrap();
    let (ours, _) = render_text(&text, w, h, Setting::default_render(p), false).unwrap();
    let (ind, _) = render_text(&text, w, h, Setting::independent(p), false).unwrap();
    let err = |img: &Image| -> (Image, Vec<f64>) {
        let mut rows = vec![0.0; h as usize];
        let px = img
            .pixels
            .iter()
            .zip(&truth.pixels)
            .enumerate()
            .map(|(i, (c, t))| {
                let d = |x: u8, y: u8| x as f64 - y as f64;
                let e = [d(c.r(), t.r()), d(c.g(), t.g()), d(c.b(), t.b())];
                rows[i / w as usize] += e.iter().map(|x| x * x).sum::<f64>() / 3.0;
                let s = |x: f64| (x.abs() * 8.0).min(255.0) as u8;
                Rgb888::new(s(e[0]), s(e[1]), s(e[2]))
            })
            .collect();
        (
            Image {
                width: w,
                height: h,
                pixels: px,
            },
            rows,
        )
    };
    let (eo, ro) = err(&ours);
    let (ei, ri) = err(&ind);
    std::fs::write(format!("{}-ours.png", a[4]), encode(&eo, Format::Png).unwrap()).unwrap();
    std::fs::write(format!("{}-ind.png", a[4]), encode(&ei, Format::Png).unwrap()).unwrap();
    std::fs::write(format!("{}-ref.png", a[4]), encode(&truth, Format::Png).unwrap()).unwrap();
    std::fs::write(format!("{}-img.png", a[4]), encode(&ours, Format::Png).unwrap()).unwrap();
    let band = h as usize / 12;
    for b in 0..12 {
        let s = |r: &Vec<f64>| r[b * band..(b + 1) * band].iter().sum::<f64>() / (band as f64 * w as f64);
        println!(
            "rows {:3}-{:3}: ours mse {:8.2}  ind mse {:8.2}",
            b * band,
            (b + 1) * band - 1,
            s(&ro),
            s(&ri)
        );
    }
    let t = |r: &Vec<f64>| r.iter().sum::<f64>() / (w * h) as f64;
    println!("total: ours {:.3} ind {:.3}", t(&ro), t(&ri));
}
