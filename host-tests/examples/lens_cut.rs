//! Which generated lens scenes have a lens cut by an object (diagnosis):
//! `lens_cut FIRST COUNT` lists the seeds where some object crosses the
//! lens's disc (`Scene64::lens_cut_by`) and counts them; `lens_cut FILE...`
//! says it of scene files.
use lensray_host::reference64::Scene64;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().is_some_and(|a| a.parse::<u64>().is_err()) {
        for f in &args {
            let by = Scene64::parse(&std::fs::read_to_string(f).unwrap()).lens_cut_by();
            println!("{f}: cut by objects {by:?}");
        }
        return;
    }
    let a: Vec<u64> = args.iter().map(|s| s.parse().unwrap()).collect();
    let (first, count) = (a[0], a[1]);
    let mut cut = 0;
    for seed in first..first + count {
        let s = Scene64::parse(&lensray_testkit::scenegen::generate_lens(seed));
        let by = s.lens_cut_by();
        if !by.is_empty() {
            cut += 1;
            let shapes: Vec<_> = by.iter().map(|&i| s.objects[i].shape).collect();
            println!(
                "seed {seed}: point {} radius {:.3} cut by objects {by:?} {shapes:?}",
                s.camera.samples, s.camera.radius
            );
        }
    }
    println!("{cut} of {count} lens scenes have a cut lens");
}
