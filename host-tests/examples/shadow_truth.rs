//! A pinhole pixel's shadow rays against float64: `shadow_truth FILE COL ROW
//! [X Y Z]` (160x120). For each light and object, the shadow decision and
//! its margins (object units) and hit t in float64, once from Q16.16's start
//! point and once from the exact one: where they differ, the start point
//! decides. Q16.16's P is the exact eye plus the chief direction times its
//! rounded t, rounded to 2⁻¹⁶, or `X Y Z` where given (the renderer's own P
//! also rounds the eye: see docs/accuracy.md, fix 18).
use lensray::{CameraSample, Scalar, Scene, I16F16};
use lensray_host::reference64::Scene64;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let text = std::fs::read_to_string(&a[0]).expect("read");
    let (c, r): (u32, u32) = (a[1].parse().unwrap(), a[2].parse().unwrap());
    let (w, h) = (160, 120);
    let scene = Scene::<I16F16>::parse(&text).expect("parse");
    let s64 = Scene64::parse(&text);
    let rend = lensray::Renderer::new(&scene, w, h);
    let ray = rend.camera().generate_ray(&CameraSample {
        film: &rend.camera().film_point(c, r),
        lens: None,
    });
    let (i, hit) = scene.closest_hit_camera_ray(&ray, rend.cones()).expect("a hit");
    let eye = s64.camera.lens_position;
    let d = s64.chief_dir(c, r, w, h);
    let px = s64.pixel(c, r, w, h);
    let (j, h64) = px.hit.expect("an f64 hit");
    let t = hit.t.to_f64();
    let q16 = |x: f64| (x * 65536.0).round() / 65536.0;
    // Q16.16's P near as `along_dir` rounds it, or as given.
    let pq = if a.len() >= 6 {
        [3, 4, 5].map(|k| a[k].parse::<f64>().unwrap())
    } else {
        [0, 1, 2].map(|k| q16(eye[k] + d[k] * t))
    };
    let pe = [0, 1, 2].map(|k| eye[k] + d[k] * h64.t);
    let (n, _) = scene.objects()[i].facing_normal(&hit, ray.dir);
    let n = n.to_f64();
    println!(
        "object {i} (f64 {j}) t {t} (f64 {}) P {pq:?} exact {pe:?} off {:?}",
        h64.t,
        [0, 1, 2].map(|k| pq[k] - pe[k])
    );
    let eps = 1.0 / 1024.0;
    for (l, light) in scene.lights().iter().enumerate() {
        let lp = light.position.to_f64();
        for (name, p) in [("Q16.16's P", pq), ("exact P", pe)] {
            let ps = [0, 1, 2].map(|k| p[k] + n[k] * eps);
            if (0..3).map(|k| (lp[k] - p[k]) * n[k]).sum::<f64>() <= 0.0 {
                continue;
            }
            // The segment from just above P to the light itself (fix 20).
            let to = [0, 1, 2].map(|k| lp[k] - ps[k]);
            let dist = (to[0] * to[0] + to[1] * to[1] + to[2] * to[2]).sqrt();
            let u = to.map(|x| x / dist);
            for (k, ob) in s64.objects.iter().enumerate() {
                if k == i {
                    continue;
                }
                let m = ob.margin(ps, u);
                let hit = ob.hit(ps, u, f64::MIN, f64::MAX).map(|h| h.t);
                let blocked = ob.hit(ps, u, eps, dist).is_some();
                if blocked || m.hit.abs() < 1e-2 || m.face < 1e-2 {
                    println!(
                        "  light {l} from {name}: object {k} {:?} blocks {blocked} margin {:.3e} face {:.3e} first t {hit:?} dist {dist:.4}",
                        ob.shape, m.hit, m.face
                    );
                }
            }
        }
    }
}
