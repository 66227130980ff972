//! Classifies a failing sweep scene: `sweep_diag FILE...` (PIXELS=1 lists the
//! worst pixels with both types' hits) prints its PSNR as
//! is, with shadows off, and the pixels one number type draws as background
//! where the other draws an object (the missing-horizon class).
use embedded_graphics::pixelcolor::RgbColor;
use lensray::Scene;
use lensray_host::{render_both, Diff, LineErrors};

fn main() {
    for path in std::env::args().skip(1) {
        let text = std::fs::read_to_string(&path).expect("read");
        let (mut fixed, mut float) = lensray_host::both_unadaptive(&text);
        let samples = (fixed.camera.radius > 0.0).then_some(lensray_host::sweep::LENS_SAMPLES);
        let (w, h) = (160, 120);
        let (a, b) = render_both(&fixed, &float, w, h, samples);
        let d = Diff::of(&a, &b).unwrap();
        let l = LineErrors::of(&a, &b).unwrap();
        let bg = |s: &Scene<f32>| {
            [s.background.x, s.background.y, s.background.z].map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8)
        };
        let bgc = bg(&float);
        let px = |img: &lensray_host::Image, i: usize| img.pixels[i];
        let mut only_fixed_bg = 0;
        let mut only_float_bg = 0;
        for i in 0..(w * h) as usize {
            let (pa, pb) = (px(&a, i), px(&b, i));
            let ia = [pa.r(), pa.g(), pa.b()] == bgc;
            let ib = [pb.r(), pb.g(), pb.b()] == bgc;
            only_fixed_bg += (ia && !ib) as u32;
            only_float_bg += (ib && !ia) as u32;
        }
        if std::env::var("PIXELS").is_ok() && samples.is_none() {
            let rf = lensray::Renderer::new(&fixed, w, h);
            let rg = lensray::Renderer::new(&float, w, h);
            let mut shown = 0;
            for i in 0..(w * h) as usize {
                let (pa, pb) = (px(&a, i), px(&b, i));
                let e = [
                    pa.r().abs_diff(pb.r()),
                    pa.g().abs_diff(pb.g()),
                    pa.b().abs_diff(pb.b()),
                ];
                if e.iter().copied().max().unwrap() > 20 && shown < 12 {
                    shown += 1;
                    let (c, r) = (i as u32 % w, i as u32 / w);
                    let hf = rf.hit(&rf.camera_ray(c, r, None));
                    let hg = rg.hit(&rg.camera_ray(c, r, None));
                    let fmt_f = hf.map(|(k, t)| (k, t.to_num::<f64>()));
                    println!("  ({c},{r}) {:?} vs {:?}: Q {fmt_f:?} f32 {hg:?}", pa, pb);
                }
            }
        }
        fixed.shadows = false;
        float.shadows = false;
        let (a2, b2) = render_both(&fixed, &float, w, h, samples);
        let d2 = Diff::of(&a2, &b2).unwrap();
        println!(
            "{path}: {:.1} dB {:.2} % rows {:?} cols {:?}; shadows off {:.1} dB {:.2} %; bg only in Q16.16 {only_fixed_bg}, only in f32 {only_float_bg}",
            d.psnr, d.within[1] * 100.0, l.worst_row, l.worst_col, d2.psnr, d2.within[1] * 100.0
        );
    }
}
