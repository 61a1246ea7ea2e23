//! The feature-line OBJ reader on arbitrary bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| crestline_fuzz::read_lines(data));
