//! Damaged files never make a reader panic: valid files in every format, cut short at a
//! random byte and with random bytes overwritten, give either a mesh or an error that names
//! the file.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;

use crestline::io::{Format, PlyEncoding, WriteOptions, read_mesh_bytes, write_mesh_to};
use proptest::prelude::*;
use proptest::sample::Index;

const VARIANTS: [(Format, PlyEncoding); 6] = [
    (Format::Obj, PlyEncoding::Ascii),
    (Format::Off, PlyEncoding::Ascii),
    (Format::Stl, PlyEncoding::Ascii),
    (Format::Ply, PlyEncoding::Ascii),
    (Format::Ply, PlyEncoding::BinaryLittleEndian),
    (Format::Ply, PlyEncoding::BinaryBigEndian),
];

/// Bytes that make text formats interesting: digits, signs, separators, line breaks,
/// comment and corner syntax, letters of nan/inf, and the extremes.
const NASTY: &[u8] = b"0123456789-+. \t\r\n#/eEnaifNAIF\x00\xff";

fn damaged_file() -> impl Strategy<Value = (Format, Vec<u8>)> {
    (
        0..VARIANTS.len(),
        1u32..3,
        any::<Index>(),
        prop::collection::vec((any::<Index>(), any::<Index>(), any::<u8>()), 0..6),
    )
        .prop_map(|(variant, subdivisions, cut, edits)| {
            let (format, encoding) = VARIANTS[variant];
            let mesh = crestline::shapes::icosphere(1.0, subdivisions - 1);
            let mut bytes = Vec::new();
            let options = WriteOptions::default().with_ply_encoding(encoding);
            write_mesh_to(&mut bytes, &mesh, format, &options).unwrap();
            bytes.truncate(cut.index(bytes.len() + 1));
            for (at, pick, raw) in edits {
                if bytes.is_empty() {
                    break;
                }
                let i = at.index(bytes.len());
                // Half the edits use a "nasty" text byte, half any byte.
                bytes[i] = if raw % 2 == 0 {
                    NASTY[pick.index(NASTY.len())]
                } else {
                    raw
                };
            }
            (format, bytes)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn damaged_files_never_panic((format, bytes) in damaged_file()) {
        if let Err(e) = read_mesh_bytes(&bytes, format, Path::new("damaged")) {
            let message = e.to_string();
            prop_assert!(message.starts_with("damaged: "), "{}", message);
        }
    }

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400), f in 0..4usize) {
        let format = Format::ALL[f];
        if let Err(e) = read_mesh_bytes(&bytes, format, Path::new("noise")) {
            prop_assert!(e.to_string().starts_with("noise: "), "{}", e);
        }
    }
}

#[test]
fn header_prefixes_never_panic() {
    // Every prefix of a PLY header with lists of every kind.
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                element tristrips 1\nproperty list int int vertex_indices\nend_header\n\
                0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n4 0 1 2 -1\n";
    for end in 0..=text.len() {
        let _ = read_mesh_bytes(&text.as_bytes()[..end], Format::Ply, Path::new("p.ply"));
    }
}
