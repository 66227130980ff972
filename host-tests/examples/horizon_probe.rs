//! Where f32's plane hit at the horizon goes wrong: `horizon_probe FILE COL ROW OBJECT`
//! (pinhole, 160x120) splits the f32 hit's error into the plane's height of
//! the eye and the direction's component along the plane's normal.
use lensray::{CameraSample, Scene};
use lensray_host::reference64::Scene64;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let text = std::fs::read_to_string(&a[0]).unwrap() + "\nradius 0\n";
    let (c, r, k): (u32, u32, usize) = (a[1].parse().unwrap(), a[2].parse().unwrap(), a[3].parse().unwrap());
    let s64 = Scene64::parse(&text);
    let float = Scene::<f32>::parse(&text).unwrap();
    let rg = lensray::Renderer::new(&float, 160, 120);
    let fr = rg.camera().generate_ray(&CameraSample {
        film: &rg.camera().film_point(c, r),
        lens: None,
    });
    let m = s64.objects[k].to_object.0;
    let o = s64.camera.lens_position;
    let d = s64.chief_dir(c, r, 160, 120);
    let dot = |r: [f64; 4], v: [f64; 3], aff: f64| r[0] * v[0] + r[1] * v[1] + r[2] * v[2] + r[3] * aff;
    let h = dot(m[2], o, 1.0);
    let dz = dot(m[2], d, 0.0);
    let n = (m[2][0] * m[2][0] + m[2][1] * m[2][1] + m[2][2] * m[2][2]).sqrt();
    println!("f64: h {h:.9} dz {dz:.6e} sin {:.6e} t {:.6}", dz / n, -h / dz);
    let r32 = m.map(|row| row.map(|x| x as f32 as f64));
    let fd = [fr.dir.x as f64, fr.dir.y as f64, fr.dir.z as f64];
    let h32 = dot(r32[2], o, 1.0);
    let dz32 = dot(r32[2], fd, 0.0);
    let dz_rows = dot(r32[2], d, 0.0);
    let dz_dir = dot(m[2], fd, 0.0);
    println!(
        "f32 parts: h {h32:.9} ({:+.3e}) dz {dz32:.6e} ({:+.3e} rel)",
        h32 - h,
        dz32 / dz - 1.0
    );
    println!(
        "  dz from rounded rows alone {:+.3e} rel, from the f32 direction alone {:+.3e} rel",
        dz_rows / dz - 1.0,
        dz_dir / dz - 1.0
    );
    println!(
        "  t with f32 h only {:.4}, with f32 dz only {:.4}, both {:.4}",
        -h32 / dz,
        -h / dz32,
        -h32 / dz32
    );
    let o_f = [fr.origin.x as f64, fr.origin.y as f64, fr.origin.z as f64];
    println!("  eye rounding {:?}", [0, 1, 2].map(|i| o_f[i] - o[i]));
}
