//! Whether the intersection or the ray is at fault: `intersect_probe FILE COL ROW OBJECT` feeds the
//! Q16.16 camera ray of one pixel (pinhole) to the f32 intersection of one object.
use lensray::CameraSample;
use lensray::Vec3;
use lensray::{Scene, I16F16};

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let text = std::fs::read_to_string(&a[0]).unwrap();
    let (c, r, k): (u32, u32, usize) = (a[1].parse().unwrap(), a[2].parse().unwrap(), a[3].parse().unwrap());
    let fixed = Scene::<I16F16>::parse(&text).unwrap();
    let float = Scene::<f32>::parse(&text).unwrap();
    let rf = lensray::Renderer::new(&fixed, 160, 120);
    let rg = lensray::Renderer::new(&float, 160, 120);
    let qr = rf.camera().generate_ray(&CameraSample {
        film: &rf.camera().film_point(c, r),
        lens: None,
    });
    let fr = rg.camera().generate_ray(&CameraSample {
        film: &rg.camera().film_point(c, r),
        lens: None,
    });
    let cv = |v: Vec3<I16F16>| Vec3::new(v.x.to_num::<f32>(), v.y.to_num::<f32>(), v.z.to_num::<f32>());
    let (qo, qd) = (cv(qr.origin), cv(qr.dir));
    println!("q ray {:?} {:?}\nf ray {:?} {:?}", qo, qd, fr.origin, fr.dir);
    let of = &float.objects()[k];
    let oq = &fixed.objects()[k];
    println!(
        "f32 native: {:?}",
        of.intersect(fr.origin, fr.dir, 1e-3, f32::MAX).map(|h| h.t)
    );
    println!(
        "f32 with q ray: {:?}",
        of.intersect(qo, qd, 1e-3, f32::MAX).map(|h| h.t)
    );
    println!(
        "q native: {:?}",
        oq.intersect_dir(qr.origin, qr.dir, qr.precise, I16F16::from_bits(64), I16F16::MAX)
            .map(|h| h.t.to_num::<f64>())
    );
}
