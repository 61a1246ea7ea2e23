//! No allocation from a header's word alone: files whose headers claim billions of elements
//! but hold a few bytes fail with an error naming the file and a position, and reading them
//! never holds more than 1 MiB at once. A counting global allocator measures the peak.
//!
//! Everything runs in one test, so that no other test's allocations share the counters.

// Test code: stopping loudly on the first surprise is the point. `unsafe` for the one
// `GlobalAlloc` implementation, which only forwards to the system allocator.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic, unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};

use crestline::io::lines::parse_lines_obj;
use crestline::io::mask::parse_diffusion_factors;
use crestline::io::{Format, read_mesh, read_mesh_bytes};
use crestline::{Error, Location};

/// The system allocator, counting the bytes held and their peak since the last reset.
struct Counting;

static HELD: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded unchanged to `System`; the counters are only arithmetic.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as `System::alloc`, with the caller's layout.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let held = HELD.fetch_add(layout.size(), SeqCst) + layout.size();
            PEAK.fetch_max(held, SeqCst);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `alloc` above with this layout.
        unsafe { System.dealloc(ptr, layout) };
        HELD.fetch_sub(layout.size(), SeqCst);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as `System::realloc`, with the caller's arguments.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            HELD.fetch_sub(layout.size(), SeqCst);
            let held = HELD.fetch_add(new_size, SeqCst) + new_size;
            PEAK.fetch_max(held, SeqCst);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

const MIB: usize = 1 << 20;

/// Runs `work` and returns its result and the most bytes it held at once beyond what was held
/// before.
fn peak_of<T>(work: impl FnOnce() -> T) -> (T, usize) {
    let before = HELD.load(SeqCst);
    PEAK.store(before, SeqCst);
    let result = work();
    (result, PEAK.load(SeqCst).saturating_sub(before))
}

/// A binary little-endian PLY header with `vertices` and `faces` declared, then `body`.
fn binary_ply(vertices: &str, faces: &str, list: &str, body: &[u8]) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\n\
         property float y\nproperty float z\nelement face {faces}\n\
         property list {list} int vertex_indices\nend_header\n"
    )
    .into_bytes();
    bytes.extend_from_slice(body);
    bytes
}

fn ascii_ply(vertices: &str, faces: &str, body: &str) -> Vec<u8> {
    format!(
        "ply\nformat ascii 1.0\nelement vertex {vertices}\nproperty float x\n\
         property float y\nproperty float z\nelement face {faces}\n\
         property list uchar int vertex_indices\nend_header\n{body}"
    )
    .into_bytes()
}

fn binary_stl(declared: u32, triangles: usize) -> Vec<u8> {
    let mut bytes = vec![b' '; 80];
    bytes.extend_from_slice(&declared.to_le_bytes());
    bytes.extend(std::iter::repeat_n(0u8, 50 * triangles));
    bytes
}

#[test]
fn headers_claiming_billions_of_elements_allocate_little() {
    let four_billion = "4000000000";
    let triangle = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect::<Vec<u8>>();
    let mut face = vec![3u8];
    for i in [0i32, 1, 2] {
        face.extend_from_slice(&i.to_le_bytes());
    }
    let cases: Vec<(&str, Vec<u8>)> = vec![
        (
            "vertices.ply",
            ascii_ply(four_billion, "1", "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        ),
        (
            "faces.ply",
            ascii_ply("3", four_billion, "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
        ),
        ("both.ply", ascii_ply(four_billion, four_billion, "0 0 0\n")),
        (
            "vertices-bin.ply",
            binary_ply(four_billion, "1", "uchar", &triangle),
        ),
        ("faces-bin.ply", {
            let mut body = triangle.clone();
            body.extend_from_slice(&face);
            binary_ply("3", four_billion, "uchar", &body)
        }),
        // One face whose list claims four billion corners.
        ("corners-bin.ply", {
            let mut body = triangle.clone();
            body.extend_from_slice(&u32::MAX.to_le_bytes());
            body.extend_from_slice(&[0u8; 12]);
            binary_ply("3", "1", "uint", &body)
        }),
        (
            "strips.ply",
            format!(
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                 property float z\nelement tristrips {four_billion}\n\
                 property list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n\
                 4000000000 0 1 2\n"
            )
            .into_bytes(),
        ),
        (
            "counts.off",
            format!("OFF\n{four_billion} {four_billion} 0\n0 0 0\n").into_bytes(),
        ),
        (
            "faces.off",
            format!("OFF\n3 {four_billion} 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes(),
        ),
        (
            "corners.off",
            b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n".to_vec(),
        ),
        ("binary.stl", binary_stl(u32::MAX, 1)),
        ("empty-binary.stl", binary_stl(u32::MAX, 0)),
        (
            "huge-index.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4000000000\n".to_vec(),
        ),
        (
            "negative-index.obj",
            b"v 0 0 0\nv 1 0 0\nf 1 2 -4000000000\n".to_vec(),
        ),
    ];
    let mut report = Vec::new();
    for (name, bytes) in &cases {
        assert!(bytes.len() < 300, "{name}: {} bytes", bytes.len());
        let format = Format::from_path(Path::new(name)).unwrap();
        let (result, peak) = peak_of(|| read_mesh_bytes(bytes, format, Path::new(name)));
        let (message, whole) = match result {
            Ok(m) => panic!("{name}: read as {} triangles", m.num_faces()),
            Err(e) => {
                let whole = matches!(
                    e,
                    Error::Parse {
                        location: Location::File,
                        ..
                    }
                );
                (e.to_string(), whole)
            }
        };
        assert!(message.starts_with(&format!("{name}: ")), "{message}");
        // A position, or none for the file as a whole.
        assert!(
            whole
                || ["line ", "byte "]
                    .iter()
                    .any(|w| message[name.len() + 2..].starts_with(w)),
            "{message}"
        );
        assert!(peak < MIB, "{name}: {peak} bytes held at once ({message})");
        report.push(format!("{name}: {peak} bytes: {message}"));
    }
    // The same through a file on disk, as the command line reads it.
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in &cases[..3] {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let (result, peak) = peak_of(|| read_mesh(&path, None));
        assert!(result.is_err(), "{name}");
        assert!(peak < MIB, "{name} on disk: {peak} bytes held at once");
    }
    // The feature-line and mask readers.
    let (result, peak) =
        peak_of(|| parse_lines_obj(b"v 0 0 0\nl 1 4000000000\n", Path::new("l.obj")));
    assert!(result.is_err());
    assert!(peak < MIB, "lines: {peak}");
    let (result, peak) =
        peak_of(|| parse_diffusion_factors(b"1\n0.5\n", 4_000_000_000, Path::new("m.txt")));
    assert!(result.is_err());
    assert!(peak < MIB, "mask: {peak}");
    println!("{}", report.join("\n"));
}
