//! Runs the fuzz check on saved inputs: `fuzz_recheck FILE...` prints each outcome.
fn main() {
    for f in std::env::args().skip(1) {
        let bytes = std::fs::read(&f).unwrap();
        let r = std::panic::catch_unwind(|| lensray_testkit::fuzz::check_input(&bytes));
        match r {
            Ok(Ok(_)) => println!("{f}: ok"),
            Ok(Err(m)) => println!("{f}: {m}"),
            Err(_) => println!("{f}: panic"),
        }
    }
}
