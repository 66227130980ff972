//! libFuzzer target: any bytes through the parser and, if accepted, the
//! renderer, with every promise of `lensray_testkit::fuzz::check_input`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(msg) = lensray_testkit::fuzz::check_input(data) {
        panic!("{msg}");
    }
});
