use lensray::lfsr::Lfsr;
use lensray::{Renderer, Scalar, Scene, Vec3, I16F16};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let text = std::fs::read_to_string(&args[1]).unwrap();
    let row: u32 = args[2].parse().unwrap();
    let sx = Scene::<I16F16>::parse(&text).unwrap();
    let sf = Scene::<f32>::parse(&text).unwrap();
    let rx = Renderer::new(&sx, 320, 240);
    let rf = Renderer::new(&sf, 320, 240);
    let n = sx.camera.samples;
    let (mut flips_xf, mut flips_xray, mut total, mut flips_ray) = (0, 0, 0, 0);
    for col in 0..320 {
        let mut l = Lfsr::for_pixel(col, row, 0);
        for _ in 0..n {
            let s = l.disk_q15();
            let ax = rx.camera().lens_ray(rx.camera().p_film(col, row), s);
            let af = rf.camera().lens_ray(rf.camera().p_film(col, row), s);
            let cx = sx.trace(ax.origin, ax.dir).to_f64();
            let cf = sf.trace(af.origin, af.dir).to_f64();
            // f32 scene fed the fixed ray.
            let o = Vec3::<f32>::from_f64(ax.origin.to_f64());
            let d = Vec3::<f32>::from_f64(ax.dir.to_f64());
            let cxr = sf.trace(o, d).to_f64();
            let big = |a: [f64; 3], b: [f64; 3]| (0..3).any(|i| (a[i] - b[i]).abs() > 0.02);
            total += 1;
            if big(cx, cf) {
                flips_xf += 1;
            }
            if big(cx, cxr) {
                flips_xray += 1;
            }
            if big(cf, cxr) {
                flips_ray += 1;
            }
        }
    }
    println!("row {row}: samples {total}, fixed vs f32 differ {flips_xf}, fixed vs f32-on-fixed-ray differ {flips_xray}, f32 own ray vs f32 on fixed ray {flips_ray}");
}
