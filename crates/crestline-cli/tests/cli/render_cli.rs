//! Pictures (issue 24, item 9): the optional wireframe on every command that draws PNG or
//! SVG pictures, and the up axis guessed from the mesh when `--up` is not given.

// Test code: stopping loudly on the first surprise is the point.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};

use crate::common::{crestline as run, fails, ok, s, stderr};
use crestline::io::{Format, WriteOptions, write_mesh};

const FANDISK: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fandisk.obj");

/// A 2 × 2 × 0.2 slab, thin along Z (a plate lying on the XY plane, as CAD parts are
/// drawn), as OBJ in `dir`.
fn z_up_plate(dir: &Path) -> PathBuf {
    let (cube, _) = crestline::shapes::pillow_box(0.5, 0.0, 1);
    let slab = cube
        .positions()
        .iter()
        .map(|p| p.component_mul(&crestline::Vec3::new(2.0, 2.0, 0.2)));
    let plate = cube.with_positions(slab.collect()).unwrap();
    let path = dir.join("plate.obj");
    write_mesh(&path, &plate, Format::Obj, &WriteOptions::default()).unwrap();
    path
}

/// Runs `args` with `-o PICTURE` added and returns the picture's bytes and stderr.
fn picture(dir: &Path, name: &str, args: &[&str]) -> (Vec<u8>, String) {
    let path = dir.join(name);
    let mut all = args.to_vec();
    all.extend(["-o", s(&path)]);
    let out = ok(run(&all));
    (std::fs::read(&path).unwrap(), stderr(&out))
}

#[test]
fn render_draws_the_wireframe_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let base = ["render", FANDISK, "--size", "160"];
    let (plain, _) = picture(d, "plain.png", &base);
    let (wired, _) = picture(d, "wired.png", &[&base[..], &["--wireframe"]].concat());
    assert!(plain != wired, "--wireframe changes nothing");
    // SVG embeds the raster mesh, wireframe included.
    let (plain_svg, _) = picture(d, "plain.svg", &base);
    let (wired_svg, _) = picture(d, "wired.svg", &[&base[..], &["--wireframe"]].concat());
    assert!(plain_svg != wired_svg);
    // The viewer has no wireframe: refused, not ignored.
    let html = d.join("v.html");
    let err = fails(run(&[&base[..], &["--wireframe", "-o", s(&html)]].concat()));
    assert!(err.contains("--wireframe"), "{err}");
}

#[test]
fn extract_draws_the_wireframe_on_its_pictures_and_refuses_it_without_one() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lines = d.join("lines.obj");
    let shot = |name: &str, extra: &[&str]| {
        let png = d.join(name);
        let mut args = vec!["extract", FANDISK, "-o", s(&lines), "--png", s(&png)];
        args.extend(extra);
        ok(run(&args));
        std::fs::read(&png).unwrap()
    };
    assert!(shot("plain.png", &[]) != shot("wired.png", &["--wireframe"]));
    let err = fails(run(&["extract", FANDISK, "-o", s(&lines), "--wireframe"]));
    assert!(err.contains("--png"), "{err}");
    let err = fails(run(&["extract", FANDISK, "-o", s(&lines), "--up", "z"]));
    assert!(err.contains("--png"), "{err}");
}

#[test]
fn the_up_axis_is_guessed_from_the_mesh_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A plate lying on its large face is drawn Z-up, as `--up z` draws it.
    let plate = z_up_plate(d);
    let (auto, note) = picture(d, "auto.png", &["render", s(&plate), "--size", "96"]);
    assert!(note.contains("up axis: z"), "{note}");
    let (z, note_z) = picture(
        d,
        "z.png",
        &["render", s(&plate), "--size", "96", "--up", "z"],
    );
    assert!(
        !note_z.contains("up axis"),
        "an axis given is not guessed: {note_z}"
    );
    let (y, _) = picture(
        d,
        "y.png",
        &["render", s(&plate), "--size", "96", "--up", "y"],
    );
    assert!(auto == z && auto != y, "the plate is not drawn Z-up");
    // Fandisk has no flat base: Y, as before.
    let (auto, note) = picture(d, "f.png", &["render", FANDISK, "--size", "96"]);
    assert!(note.contains("up axis: y"), "{note}");
    let (y, _) = picture(
        d,
        "fy.png",
        &["render", FANDISK, "--size", "96", "--up", "y"],
    );
    assert!(auto == y);
    // extract --png guesses too and says so.
    let lines = d.join("plate.obj.lines.obj");
    let png = d.join("extract.png");
    let out = ok(run(&[
        "extract",
        s(&plate),
        "-o",
        s(&lines),
        "--png",
        s(&png),
    ]));
    assert!(stderr(&out).contains("up axis: z"), "{}", stderr(&out));
}

#[test]
fn render_fields_put_spikes_back_as_curvature_does() {
    // A unit sphere with a vertex three edges off it: the field of `render` is the one
    // `crestline curvature` writes (the spike put back first, said on stderr) unless
    // --keep-outliers.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("spiky.obj");
    crate::common::write_spiky_sphere(&path, 3, &[100]);
    let base = ["render", s(&path), "--size", "160", "--field", "k_max"];
    let (_, said) = picture(dir.path(), "k.png", &base);
    assert!(said.contains("1 outlier vertex"), "{said}");
    let (_, kept) = picture(
        dir.path(),
        "kept.png",
        &[&base[..], &["--keep-outliers"]].concat(),
    );
    assert!(!kept.contains("outlier"), "{kept}");
}
