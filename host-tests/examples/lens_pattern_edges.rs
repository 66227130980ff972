//! Lens sample patterns on synthetic integrands (experiment): the error of
//! N-point estimates of the share of the aperture beyond a random edge
//! (half-plane) or inside a random disk, over many pixels' scrambles.
//! `lens_pattern_edges BLADES PATTERNS N1,N2,..`
use lensray::unstable::aperture::Aperture;
use lensray::unstable::sampler::{PixelSamples, Sampler, PATTERN};
use std::sync::atomic::Ordering;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let blades: u32 = a[1].parse().unwrap();
    let pats: Vec<u8> = a[2].split(',').map(|x| x.parse().unwrap()).collect();
    let ns: Vec<u32> = a[3].split(',').map(|x| x.parse().unwrap()).collect();
    let ap = Aperture::regular(blades, 10.0);
    // Integrands: half-planes and disks from a fixed generator.
    let mut s = 0x1234_5678u64;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut shapes = vec![];
    for k in 0..400 {
        let t = rnd() * std::f64::consts::TAU;
        if k % 2 == 0 {
            shapes.push((0u8, t.cos(), t.sin(), rnd() * 1.6 - 0.8));
        } else {
            shapes.push((1u8, (rnd() * 2.0 - 1.0) * 1.2, (rnd() * 2.0 - 1.0) * 1.2, 0.2 + rnd() * 1.0));
        }
    }
    let inside = |sh: &(u8, f64, f64, f64), x: f64, y: f64| match sh.0 {
        0 => sh.1 * x + sh.2 * y > sh.3,
        _ => (x - sh.1).powi(2) + (y - sh.2).powi(2) < sh.3 * sh.3,
    };
    // Truth from 65536 stratified points of one pixel (pattern 0), per shape.
    PATTERN.store(0, Ordering::Relaxed);
    let mut big = PixelSamples::new(Sampler::Stratified, 3, 3);
    let pts: Vec<(f64, f64)> = (0..65536)
        .map(|_| {
            let (x, y) = big.next(&ap);
            (x as f64 / 32768.0, y as f64 / 32768.0)
        })
        .collect();
    let truth: Vec<f64> =
        shapes.iter().map(|sh| pts.iter().filter(|p| inside(sh, p.0, p.1)).count() as f64 / 65536.0).collect();
    let pixels = 300u32;
    print!("{:>10}", "N");
    for n in &ns {
        print!(" {n:>8}");
    }
    println!();
    let mut rows = vec![];
    for sampler in [Some(255u8)].into_iter().chain(pats.iter().map(|&p| Some(p))) {
        let p = sampler.unwrap();
        let mut row = vec![];
        for &n in &ns {
            let mut mse = 0.0;
            for px in 0..pixels {
                let pts: Vec<(f64, f64)> = if (4..=5).contains(&p) {
                    let g = korobov(n);
                    let mut r = lensray::unstable::lfsr::Lfsr::for_pixel(px % 40, px / 40 + 100, 0);
                    let (su, sv) = (r.next_u16() as u64, r.next_u16() as u64);
                    (0..n as u64)
                        .map(|i| {
                            let u = ((i << 16) / n as u64 + su) as u16;
                            let v = (((i * g as u64) % n as u64 * 65536) / n as u64 + sv) as u16;
                            let (x, y) = if p == 4 { ap.map_q16(u, v) } else { ap.map_concentric_q16(u, v) };
                            (x as f64 / 32768.0, y as f64 / 32768.0)
                        })
                        .collect()
                } else {
                    let (smp, pat) = if p == 255 { (Sampler::Independent, 0) } else { (Sampler::Stratified, p) };
                    PATTERN.store(pat, Ordering::Relaxed);
                    let mut ps = PixelSamples::new(smp, px % 40, px / 40 + 100);
                    (0..n)
                        .map(|_| {
                            let (x, y) = ps.next(&ap);
                            (x as f64 / 32768.0, y as f64 / 32768.0)
                        })
                        .collect()
                };
                for (sh, t) in shapes.iter().zip(&truth) {
                    let est = pts.iter().filter(|q| inside(sh, q.0, q.1)).count() as f64 / n as f64;
                    mse += (est - t).powi(2);
                }
            }
            row.push(mse / (pixels as f64 * shapes.len() as f64));
        }
        rows.push((p, row));
    }
    let ind = rows[0].1.clone();
    for (p, row) in rows {
        let name = if p == 255 { "indep".to_string() } else { format!("pattern {p}") };
        print!("{name:>10}");
        for (m, i) in row.iter().zip(&ind) {
            print!(" {:8.2}", i / m);
        }
        println!("   (variance gain over independent)");
    }
}

/// The generator g of the N-point rank-1 lattice (i/N, i g/N) with the
/// largest least toroidal distance between points.
fn korobov(n: u32) -> u32 {
    let mut best = (0.0, 1);
    for g in 1..n.max(2) {
        let mut d = f64::INFINITY;
        for i in 1..n {
            let du = (i as f64 / n as f64).min(1.0 - i as f64 / n as f64);
            let f = ((i * g) % n) as f64 / n as f64;
            let dv = f.min(1.0 - f);
            d = d.min(du * du + dv * dv);
        }
        if d > best.0 {
            best = (d, g);
        }
    }
    best.1
}
