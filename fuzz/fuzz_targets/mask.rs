//! The diffusion-mask reader on arbitrary bytes (the first byte is the number of vertices).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| crestline_fuzz::read_mask(data));
