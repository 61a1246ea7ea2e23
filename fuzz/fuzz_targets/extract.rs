//! The whole pipeline, every method, on whatever small mesh a reader accepts (the first byte
//! picks the format).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| crestline_fuzz::run_pipeline(data));
