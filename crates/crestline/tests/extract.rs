//! End-to-end properties of `extract` on analytic surfaces and real meshes (HPW; the YBS
//! counterparts are in `extract_ybs.rs`). The exact crest line of the test ellipsoid is
//! derived at [`common::ELLIPSOID`].

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{ELLIPSOID, check_deterministic_and_simple, check_ellipsoid, check_torus_is_empty};
use crestline::extract::{ExtractOptions, Method};
use crestline::shapes;

const A: f64 = ELLIPSOID[0];
const B: f64 = ELLIPSOID[1];
const C: f64 = ELLIPSOID[2];

#[test]
fn hpw_finds_the_ellipsoid_crest_line_at_5k_and_20k_faces() {
    for subdivisions in [4, 5] {
        let mesh = shapes::ellipsoid(A, B, C, subdivisions);
        check_ellipsoid(&mesh, &ExtractOptions::for_method(Method::Hpw), "HPW");
    }
}

#[test]
fn torus_has_no_crest_lines_by_default() {
    check_torus_is_empty(&ExtractOptions::for_method(Method::Hpw), "HPW");
}

#[test]
fn output_is_deterministic_and_polylines_are_simple() {
    let mesh = shapes::ellipsoid(A, B, C, 4);
    let options = ExtractOptions {
        filter: crestline::lines::filter::LineFilter {
            threshold: 0.0,
            min_length: 0.0,
            ..Default::default()
        },
        ..ExtractOptions::default()
    };
    check_deterministic_and_simple(&mesh, &options, "HPW");
}
