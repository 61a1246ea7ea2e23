//! The Stl reader on arbitrary bytes: a mesh or an error naming the file, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    crestline_fuzz::read_mesh(data, crestline::io::Format::Stl);
});
