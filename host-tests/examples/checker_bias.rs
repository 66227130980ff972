//! Whether the checker filter over lens footprints is biased on a frame
//! (diagnosis): `checker_bias SEED WIDTH N` casts the first N stratified lens
//! rays of every third pixel each way of the generated lens scene SEED and
//! compares the mean checker darkening the filter gives them with the mean
//! of the point samples (the square each hit lies in), overall and by the
//! footprint's radius in cells. Unbiased, the two agree as N grows; seed 9438
//! (a checker 0.36 below the lens, every pixel's lens footprint about one
//! square wide) reads 0.336 filtered against 0.310 at 16 rays, and the
//! excess falls as 1/N (+0.092 at 4, +0.027 at 16, +0.007 at 64, +0.002 at
//! 256), as it would if the boxes of strata at the lens's rim (a share 1/√N
//! of them, each reaching 1/√N of the lens) took in squares past the lens's
//! footprint.
use lensray::unstable::camera::{Camera, CameraSample};
use lensray::unstable::cull::LensCones;
use lensray::unstable::defocus::Defocus;
use lensray::unstable::number::Scalar;
use lensray::unstable::sampler::{PixelSamples, Sampler};
use lensray::{Scene, I16F16};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let (_, text, w, h) = lensray_host::convergence::seed_frame(&a);
    let n: u32 = a[3].parse().unwrap();
    let scene = Scene::<I16F16>::parse(&text).unwrap();
    let cam = Camera::new(&scene.camera, w, h);
    let cones = LensCones::new(&scene, scene.camera.lens_position, scene.camera.radius);
    let defocus = Defocus::new(&scene);
    let stratum = defocus.stratum(n);
    let (mut sf, mut sp, mut cnt, mut nf) = (0f64, 0f64, 0u64, 0u64);
    let mut by_e = [[0f64; 3]; 8];
    for y in (0..h).step_by(3) {
        for x in (0..w).step_by(3) {
            let film = cam.film_point(x, y);
            let mut lens = PixelSamples::new(Sampler::Stratified, x, y);
            for _ in 0..n {
                let p_lens = lens.next(cam.aperture());
                let ray = cam.generate_ray(&CameraSample {
                    film: &film,
                    lens: Some(p_lens),
                });
                let Some((i, hit)) = scene.closest_hit_camera_ray(&ray, &cones) else {
                    continue;
                };
                let o = &scene.objects()[i];
                if o.texture == I16F16::ZERO {
                    continue;
                }
                let nrm = o.normal(&hit, ray.dir);
                let wdt = defocus.width(ray.dir, hit.t, stratum.radius);
                let shift = defocus.shift(ray.dir, hit.t, cam.lens_offset(p_lens, stratum.pull));
                let point = if o.in_dark_square(&hit) { 0.25 } else { 1.0 };
                let f = o.checker_filtered(&hit, ray.dir, nrm, wdt, shift);
                let fv = f.map_or(point, |v| v.to_f64());
                sf += fv;
                sp += point;
                cnt += 1;
                if f.is_some() {
                    nf += 1;
                    let b = ((wdt.to_f64() / o.texture.to_f64()) * 8.0) as usize;
                    let b = b.min(7);
                    by_e[b][0] += 1.0;
                    by_e[b][1] += fv;
                    by_e[b][2] += point;
                }
            }
        }
    }
    println!(
        "rays {cnt}, filtered {nf}: mean filtered {:.4}, point {:.4}",
        sf / cnt as f64,
        sp / cnt as f64
    );
    for (b, v) in by_e.iter().enumerate() {
        if v[0] > 0.0 {
            println!(
                "  w/cell {:.3}..: {} rays, filtered mean {:.4}, point mean {:.4}",
                b as f64 / 8.0,
                v[0],
                v[1] / v[0],
                v[2] / v[0]
            );
        }
    }
}
