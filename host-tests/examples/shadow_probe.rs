//! A pinhole pixel's shadow rays, object by object, in both types:
//! `shadow_probe FILE COL ROW` (160x120): which object blocks which light.
//! P is `o + t d` from the rounded direction (as shading took it before
//! fix 13 of docs/accuracy.md).
use lensray::{CameraSample, Scalar, Scene, Vec3, I16F16};

fn probe<S: Scalar>(text: &str, c: u32, r: u32) {
    let scene = Scene::<S>::parse(text).expect("parse");
    let rend = lensray::Renderer::new(&scene, 160, 120);
    let ray = rend.camera().generate_ray(&CameraSample {
        film: &rend.camera().film_point(c, r),
        lens: None,
    });
    let Some((i, hit)) = scene.closest_hit_camera_ray(&ray, rend.cones()) else {
        println!("{}: no hit", S::NAME);
        return;
    };
    let obj = &scene.objects()[i];
    let p = ray.origin + ray.dir.scale(hit.t);
    let (n, outside) = obj.facing_normal(&hit, ray.dir);
    println!(
        "{}: object {i} outside {outside} p {:?} n {:?}",
        S::NAME,
        p.to_f64(),
        n.to_f64()
    );
    let ps = p + n.scale(S::HIT_EPSILON);
    for (k, light) in scene.lights().iter().enumerate() {
        let ndl = n.dot((light.position - p).normalize()).to_f64();
        // The segment from just above P to the light itself (docs/accuracy.md, fix 20).
        let (l, dist) = (light.position - ps).normalize_len();
        let blockers: Vec<(usize, f64)> = scene
            .objects()
            .iter()
            .enumerate()
            .filter_map(|(j, o)| o.intersect(ps, l, S::HIT_EPSILON, dist).map(|h| (j, h.t.to_f64())))
            .collect();
        println!(
            "  light {k}: n.l {ndl:.3e} dist {:.3} blockers {blockers:?}",
            dist.to_f64()
        );
        // The same ray, as f64 numbers, into the other type's objects.
        let f = Scene::<f32>::parse(text).expect("parse");
        let v = |x: Vec3<S>| Vec3::<f32>::from_f64(x.to_f64());
        let other: Vec<(usize, f64)> = f
            .objects()
            .iter()
            .enumerate()
            .filter_map(|(j, o)| {
                o.intersect(v(ps), v(l), 1.0 / 1024.0, dist.to_f64() as f32)
                    .map(|h| (j, h.t as f64))
            })
            .collect();
        println!("    the same ray in f32: {other:?}");
    }
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let text = std::fs::read_to_string(&a[0]).expect("read");
    let (c, r) = (a[1].parse().unwrap(), a[2].parse().unwrap());
    probe::<I16F16>(&text, c, r);
    probe::<f32>(&text, c, r);
}
