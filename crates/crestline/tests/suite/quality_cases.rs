//! Line quality on the exact-answer cases of `../shared/quality` (issue 19): analytic surfaces
//! meshed irregularly, by marching cubes and with scan-like noise, with their exact crest
//! lines. Each test runs `extract` with a method's default settings and scores the lines in
//! Rust against `truth_lines.obj`:
//!
//! - precision: the share of the detected length within 1% of the diagonal of an exact crest
//!   line of the same kind;
//! - recall: the share of the exact crest length within 1% of the diagonal of a detected line
//!   of that kind. Unlike `score.py`, which counts only the strong exact lines (their
//!   strengths are in `truth_lines.npz`), every exact line counts here, so recall and F1 are
//!   a little lower than the benchmark's (`bench/quality/run.sh`);
//! - on the torus, which has no crest lines, the detected length per diagonal.
//!
//! The bounds sit a little below what these measures gave when they were set (with the
//! recall counted over every exact line, the bumpy sphere's and the noisy ridge's weak
//! lines, which `score.py` leaves out, keep their F1 lower here than in the benchmark).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::PathBuf;

use crestline::extract::{ExtractOptions, Method, extract};
use crestline::lines::{FeatureLines, LineKind};
use crestline::spatial::PointGrid;
use crestline::{TriMesh, Vec3};

use crate::common;

fn cases_dir() -> PathBuf {
    common::shared_dir("quality/cases")
}

fn load(case: &str) -> TriMesh {
    let path = cases_dir().join(format!("{case}.obj"));
    let mesh = crestline::io::read_mesh(&path, None)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    crestline::mesh::orient_outward(mesh).unwrap().0
}

/// The exact crest lines of a surface as segments, by kind (`o ridge` / `o valley` groups).
fn truth(surface: &str) -> Vec<(LineKind, [Vec3; 2])> {
    let path = cases_dir().join(surface).join("truth_lines.obj");
    let text = std::fs::read_to_string(&path).unwrap();
    let (mut vertices, mut segments, mut kind) = (Vec::new(), Vec::new(), LineKind::Ridge);
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.first() {
            Some(&"v") => vertices.push(Vec3::new(
                words[1].parse().unwrap(),
                words[2].parse().unwrap(),
                words[3].parse().unwrap(),
            )),
            Some(&"o") | Some(&"g") => {
                kind = if words[1].contains("valley") {
                    LineKind::Valley
                } else {
                    LineKind::Ridge
                }
            }
            Some(&"l") => {
                // OBJ indices count from 1, or back from the last vertex when negative.
                let idx: Vec<usize> = words[1..]
                    .iter()
                    .map(|w| {
                        let i = w.parse::<i64>().unwrap();
                        if i < 0 {
                            (vertices.len() as i64 + i) as usize
                        } else {
                            i as usize - 1
                        }
                    })
                    .collect();
                for pair in idx.windows(2) {
                    segments.push((kind, [vertices[pair[0]], vertices[pair[1]]]));
                }
            }
            _ => {}
        }
    }
    segments
}

pub(super) fn line_segments(
    lines: &FeatureLines,
    kind: LineKind,
) -> impl Iterator<Item = [Vec3; 2]> + '_ {
    lines
        .of_kind(kind)
        .flat_map(|l| common::polyline_segments(&l.points, l.closed))
        .map(|(a, b)| [a, b])
}

/// The share of the length of `from` within `tau` of `to`.
pub(super) fn covered(from: &[(Vec3, f64)], to: &[(Vec3, f64)], tau: f64) -> (f64, f64) {
    let points: Vec<Vec3> = to.iter().map(|p| p.0).collect();
    let grid = PointGrid::new(&points, tau);
    let total: f64 = from.iter().map(|p| p.1).sum();
    let near: f64 = from
        .iter()
        .filter(|p| !points.is_empty() && grid.nearest_within(p.0, tau).is_some())
        .map(|p| p.1)
        .sum();
    (near, total)
}

/// Precision, recall and F1 of `lines` against the exact lines of `surface`.
fn score(mesh: &TriMesh, lines: &FeatureLines, surface: &str) -> (f64, f64, f64) {
    let tau = 0.01 * mesh.bounding_box().diagonal();
    let exact = truth(surface);
    let (mut p_near, mut p_total, mut r_near, mut r_total) = (0.0, 0.0, 0.0, 0.0);
    for kind in [LineKind::Ridge, LineKind::Valley] {
        let detected = common::weighted_samples(line_segments(lines, kind), tau / 4.0);
        let reference =
            common::weighted_samples(exact.iter().filter(|s| s.0 == kind).map(|s| s.1), tau / 4.0);
        let (n, t) = covered(&detected, &reference, tau);
        (p_near, p_total) = (p_near + n, p_total + t);
        let (n, t) = covered(&reference, &detected, tau);
        (r_near, r_total) = (r_near + n, r_total + t);
    }
    precision_recall_f1((p_near, p_total), (r_near, r_total))
}

/// Precision, recall and F1 from the (near, total) lengths of the detected and the exact lines.
pub(super) fn precision_recall_f1(
    (p_near, p_total): (f64, f64),
    (r_near, r_total): (f64, f64),
) -> (f64, f64, f64) {
    let precision = if p_total > 0.0 { p_near / p_total } else { 0.0 };
    let recall = if r_total > 0.0 { r_near / r_total } else { 0.0 };
    let f1 = if precision + recall > 0.0 {
        2.0 * precision * recall / (precision + recall)
    } else {
        0.0
    };
    (precision, recall, f1)
}

fn check_f1(method: Method, case: &str, min_f1: f64) {
    check_f1_with(&ExtractOptions::for_method(method), case, min_f1);
}

fn check_f1_with(options: &ExtractOptions, case: &str, min_f1: f64) {
    let method = options.method();
    let mesh = load(case);
    let result = extract(&mesh, options).unwrap();
    let surface = case.split('/').next().unwrap();
    let (p, r, f1) = score(&mesh, &result.lines, surface);
    eprintln!("{method:?} {case}: P {p:.3} R {r:.3} F1 {f1:.3}");
    assert!(
        f1 >= min_f1,
        "{method:?} on {case}: F1 {f1:.3} (P {p:.3}, R {r:.3}) below {min_f1}"
    );
}

fn check_spurious(method: Method, case: &str, max_diagonals: f64) {
    let mesh = load(case);
    let result = extract(&mesh, &ExtractOptions::for_method(method)).unwrap();
    let spurious = result.lines.total_length() / mesh.bounding_box().diagonal();
    eprintln!("{method:?} {case}: {spurious:.3} diagonals of spurious lines");
    assert!(
        spurious <= max_diagonals,
        "{method:?} on {case}: {spurious:.3} diagonals of lines on a torus (at most {max_diagonals})"
    );
}

#[test]
fn hpw_irregular_ellipsoid() {
    check_f1(Method::Hpw, "ovoid/irr20k", 0.98);
}

#[test]
fn hpw_marching_cubes_superquadric() {
    check_f1(Method::Hpw, "superquadric/mc", 0.97);
}

#[test]
fn hpw_irregular_bumpy_sphere() {
    check_f1(Method::Hpw, "bumpy/irr20k", 0.84);
}

#[test]
fn noisy_bumpy_sphere_and_ridge() {
    // The hardest public case: the bumps' crest lines are weak where noise is strong. Plain
    // extremality smoothing moved their zeros by about a spacing (score.py 0.400, here
    // 0.429); twiced (the smoothing's residual smoothed and added back,
    // `smoothing::extremality`) 0.466, here 0.468; moved back across by the jet fit's known
    // bias (`lines::debias`, `ExtractOptions::debias_lines`) HPW 0.710, YBS 0.739, here
    // (recall over every exact line, not only the strong ones) HPW 0.631, YBS 0.625; without
    // the lines the noise moves about and their wandering ends (`lines::located`) HPW 0.806,
    // YBS 0.811, here 0.632 and 0.636 (the lines dropped and the ends cut ran near weak
    // crests, which this recall counts: precision 0.669 → 0.859, recall 0.597 → 0.500). The
    // ridge is an open height field: the vertices within the fit radius of its boundary have
    // one-sided discs and are left out of the debias's profile fits; with them its valleys
    // were moved away from the exact ones (score.py 0.966 → 0.952, here 0.856; now 0.969,
    // here 0.872). Moved back by the extremality smoothing's drift as well (`lines::debias`,
    // *Smoothing drift*), the bumps' lines: score.py HPW 0.806 → 0.846, YBS 0.811 → 0.848,
    // here 0.632 → 0.655 and 0.636 → 0.657; the ridge 0.969 → 0.963 (here 0.866, 0.864).
    for (case, min_f1) in [("bumpy/noisy20k", 0.645), ("ridge/noisy20k", 0.86)] {
        for method in [Method::Hpw, Method::Ybs] {
            check_f1(method, case, min_f1);
        }
    }
}

#[test]
fn valleys_beside_a_ridge_under_other_noise() {
    // The ridge's clean mesh with noise of 0.1 mean edges along the normals, four draws other
    // than the public noisy20k's. The valleys at the foot of the ridge have T 2.7 on the
    // clean mesh. Before `lines::assemble::noise_free_share`, when the strength took both
    // families' noise out of the cyclideness at every point, they measured T 0.7 to 1.2
    // under such noise, and the threshold (1) dropped one in some draws. Measured (F1 here,
    // every exact line counted): seed 1 HPW and YBS 0.694 -> 0.832, seed 4 YBS 0.697 ->
    // 0.853; the other six 0.804 to 0.901, unchanged.
    let clean = load("ridge/reg20k");
    for seed in 1..=4 {
        let mesh = crestline::shapes::with_normal_noise(&clean, 0.1, seed).unwrap();
        for method in [Method::Hpw, Method::Ybs] {
            let result = extract(&mesh, &ExtractOptions::for_method(method)).unwrap();
            let (p, r, f1) = score(&mesh, &result.lines, "ridge");
            eprintln!("seed {seed} {method:?}: P {p:.3} R {r:.3} F1 {f1:.3}");
            assert!(
                f1 >= 0.75,
                "{method:?}, noise seed {seed}: F1 {f1:.3} (P {p:.3}, R {r:.3})"
            );
        }
    }
}

#[test]
fn the_noisy_disc_does_not_depend_on_the_triangulation() {
    // The same noise, a tenth of the sample spacing along the normals, on the regular and the
    // irregular meshes of a surface: the fit should widen its disc alike. Chosen by the fits'
    // residual, which is smaller where the weights are unequal, the irregular meshes' discs
    // were 4% narrower (radii 8.34 to 8.43 spacings against 8.67 to 8.79 here, the three
    // surfaces) and their lines noisier (the ellipsoid's F1 0.926 and 0.945); chosen by the
    // noise's standard deviation they agree within 0.6% (F1 0.943 and 0.957).
    for surface in ["ovoid", "ridge", "bumpy"] {
        let mut radii = Vec::new();
        for mesh in ["reg20k", "irr20k"] {
            let clean = load(&format!("{surface}/{mesh}"));
            let spacing = crestline::curvature::jet_fit::sample_spacing(&clean);
            let fraction = 0.1 * spacing / crestline::mesh::mean_edge_length(&clean);
            for seed in 1..=2 {
                let noisy = crestline::shapes::with_normal_noise(&clean, fraction, seed).unwrap();
                let result = extract(&noisy, &ExtractOptions::default()).unwrap();
                let fit = result.stats.jet_fit.unwrap();
                let (p, r, f1) = score(&noisy, &result.lines, surface);
                let case = format!("{surface}/{mesh}, noise seed {seed}");
                eprintln!(
                    "{case}: radius {:.3}, sigma {:.4}, P {p:.3} R {r:.3} F1 {f1:.3}",
                    fit.radius, fit.sigma
                );
                if surface == "ovoid" {
                    assert!(f1 >= 0.935, "{case}: F1 {f1:.3} (P {p:.3}, R {r:.3})");
                }
                radii.push(fit.radius);
            }
        }
        let widest = radii.iter().copied().fold(f64::MIN, f64::max);
        let narrowest = radii.iter().copied().fold(f64::MAX, f64::min);
        assert!(
            widest <= 1.015 * narrowest,
            "{surface}: radii {radii:.3?} under the same noise"
        );
    }
}

#[test]
fn noisy_bumps_without_debias() {
    // `debias_lines: false` leaves the lines where the widened fit put them, about a spacing
    // off the bumps' crests: here 0.468 against 0.631 with it. Both without the step that
    // drops the lines the noise moves about (`lines::located`, which came later; with it the
    // uncorrected path measures 0.446, the default 0.632), so that this measures the debias.
    let mesh = load("bumpy/noisy20k");
    let f1 = |debias_lines| {
        let options = ExtractOptions {
            debias_lines,
            drop_unlocated_lines: false,
            ..ExtractOptions::for_method(Method::Hpw)
        };
        let result = extract(&mesh, &options).unwrap();
        score(&mesh, &result.lines, "bumpy").2
    };
    let (with, without) = (f1(true), f1(false));
    eprintln!("bumpy/noisy20k: F1 {with:.3} with debias, {without:.3} without");
    // The uncorrected path keeps its own floor (the twiced smoothing's 0.468).
    assert!(without >= 0.45, "F1 {without:.3} without debias");
    assert!(
        with - without >= 0.1,
        "F1 {with:.3} with debias, {without:.3} without"
    );
}

#[test]
fn noisy_bumps_without_the_lines_the_noise_moves_about() {
    // The noise of the public bumps is white: the lines along weak crests whose extremality
    // crosses zero less than twice as steeply as its noise wander off them and are dropped,
    // and such ends of the others are cut (`lines::located`). Measured: precision
    // 0.715 → 0.910 (HPW), 0.749 → 0.917 (YBS).
    let mesh = load("bumpy/noisy20k");
    assert!(
        white_noise_found(&mesh),
        "the jet fit should find the noise of bumpy/noisy20k white"
    );
    for method in [Method::Hpw, Method::Ybs] {
        let run = |drop_unlocated_lines| {
            let options = ExtractOptions {
                drop_unlocated_lines,
                ..ExtractOptions::for_method(method)
            };
            let result = extract(&mesh, &options).unwrap();
            let (p, _, f1) = score(&mesh, &result.lines, "bumpy");
            let stats = &result.stats;
            (p, f1, stats.lines_unlocated, stats.lines_trimmed)
        };
        let ((p, f1, dropped, trimmed), (p_all, f1_all, none, untrimmed)) = (run(true), run(false));
        assert!(trimmed > 0 && untrimmed == 0, "{trimmed} / {untrimmed}");
        eprintln!(
            "{method:?}: {dropped} lines dropped, P {p_all:.3} -> {p:.3}, F1 {f1_all:.3} -> {f1:.3}"
        );
        assert!(dropped > 0 && none == 0, "{dropped} / {none}");
        assert!(
            p - p_all >= 0.1,
            "{method:?}: precision {p_all:.3} -> {p:.3}"
        );
        // Not at the cost of F1. Since the lines are also moved back by the smoothing's drift
        // (`lines::debias`), those along weak crests follow them a little better, and over
        // every exact line (this recall, weak crests included) dropping them costs HPW 0.003
        // (0.658 → 0.655); over the strong ones (score.py) F1 goes 0.753 → 0.846. Since the
        // fit keeps the curved heights on white noise (`jet_fit`, step 3) the lines kept
        // along weak crests follow them better (F1 with every line HPW 0.658 → 0.675), and
        // dropping them costs HPW 0.007 here (0.675 → 0.668; YBS gains, 0.651 → 0.668);
        // over the strong ones (score.py) HPW 0.776 → 0.867, YBS 0.784 → 0.866.
        assert!(f1 >= f1_all - 0.01, "{method:?}: F1 {f1_all:.3} -> {f1:.3}");
    }
}

#[test]
fn the_smoothing_drift_moves_lines_on_white_noise_only() {
    // The public noisy bumps: white noise, and their lines are moved back by the extremality
    // smoothing's drift as well as by the fit's bias (`lines::debias`, *Smoothing drift*).
    let bumps = extract(&load("bumpy/noisy20k"), &ExtractOptions::default()).unwrap();
    let report = bumps.stats.debias;
    eprintln!("bumpy/noisy20k: {report:?}");
    assert!(
        report.with_drift > 0 && report.with_drift <= report.moved,
        "{report:?}"
    );
    // The bunny, a scan whose residual is mostly surface the fit does not follow: its lines
    // are debiased without the drift (measured there, the drift is that detail).
    let bunny = common::load_shared("stanford-bunny.obj");
    assert!(!white_noise_found(&bunny));
    let report = extract(&bunny, &ExtractOptions::default())
        .unwrap()
        .stats
        .debias;
    eprintln!("stanford-bunny: {report:?}");
    assert!(report.moved > 0 && report.with_drift == 0, "{report:?}");
}

/// Whether the jet fit finds the noise of `mesh` white.
fn white_noise_found(mesh: &TriMesh) -> bool {
    let options = crestline::curvature::JetFitOptions::default();
    crestline::curvature::jet_fit_report(mesh, &options)
        .unwrap()
        .1
        .white_noise()
}

#[test]
fn hpw_noisy_ellipsoid() {
    check_f1(Method::Hpw, "ovoid/noisy20k", 0.97);
}

#[test]
fn white_noise_is_smoothed_along_the_lines() {
    // The noise the fit leaves in the extremalities is correlated over its disc, and the zeros
    // of weak crests wander with it (the noisy ridge's valleys, the ellipsoid's crests near
    // its umbilics). Smoothed up to three times faster along the lines than across, measured
    // here: ovoid/noisy20k 0.992 -> 1.000, ridge/noisy20k 0.865 -> 0.871 (score.py, whose
    // strong lines differ: 0.991 -> 1.000, 0.962 -> 0.966); the first numbers are HPW's
    // isotropic smoothing (`white_noise_along_lines` 1), which fails both bounds.
    check_f1(Method::Hpw, "ovoid/noisy20k", 0.997);
    check_f1(Method::Hpw, "ridge/noisy20k", 0.868);
}

#[test]
fn hpw_marching_cubes_torus_has_no_lines() {
    check_spurious(Method::Hpw, "ring/mc", 0.05);
}

#[test]
fn hpw_noisy_torus_has_no_lines() {
    // The disc (0.34) is as wide as the tube (0.3): the heights' series converges slowly and
    // its truncation left a ridge of T = 1.6 around the torus (0.64 diagonals) before the
    // curved heights (`jet_fit`). Measured (score.py): 0.000.
    check_spurious(Method::Hpw, "ring/noisy20k", 0.1);
}

#[test]
fn noisy_tori_under_other_noise_have_no_lines() {
    // The public torus's clean mesh with noise along the normals, draws other than the
    // public noisy20k's. e is zero on a torus, and the equators are planes of symmetry, where
    // a bias of e changes sign: a fit whose heights' series is truncated on the tube puts a
    // zero there. When the fit chose the heights or the curved heights at each vertex by the
    // residual (a choice the noise made, `jet_fit` step 3), four of these six draws kept a
    // ridge around the outer equator with HPW, 0.81 to 1.21 diagonals long, and five with
    // YBS (0.80 to 1.43); the curved heights, kept wherever they are made on white noise,
    // leave none.
    let clean = load("ring/reg20k");
    for (fraction, seed) in [(0.07, 4), (0.07, 6), (0.1, 4), (0.1, 5), (0.1, 6), (0.1, 1)] {
        check_noisy_torus_has_no_lines("public", &clean, fraction, seed, None);
    }
}

/// The torus `clean` with white noise of `fraction` mean edges along the normals (draw
/// `seed`): the fit finds it white (with a disc wider than `tube`, when given) and neither
/// HPW nor YBS traces more than 0.1 diagonals.
fn check_noisy_torus_has_no_lines(
    name: &str,
    clean: &TriMesh,
    fraction: f64,
    seed: u64,
    tube: Option<f64>,
) {
    let diagonal = clean.bounding_box().diagonal();
    let mesh = crestline::shapes::with_normal_noise(clean, fraction, seed).unwrap();
    for method in [Method::Hpw, Method::Ybs] {
        let result = extract(&mesh, &ExtractOptions::for_method(method)).unwrap();
        let case = format!("{name} torus, noise {fraction} seed {seed}, {method:?}");
        let fit = result.stats.jet_fit.expect("the jet fit's report");
        assert!(
            fit.white_noise(),
            "{case}: the fit should find the noise white"
        );
        let disc = fit.radius * fit.spacing;
        assert!(
            tube.is_none_or(|tube| disc > tube),
            "{case}: disc {disc:.3} not wider than the tube"
        );
        let spurious = result.lines.total_length() / diagonal;
        eprintln!("{case}: {spurious:.3} diagonals");
        assert!(spurious <= 0.1, "{case}: {spurious:.3} diagonals of lines");
    }
}

#[test]
fn noisy_tubes_narrower_than_the_disc_have_no_lines() {
    // Tori whose tube is narrower than the fit's disc, which widens with the noise: the
    // public torus (tube 0.3) under noise of 0.2 mean edges (disc 0.40) and a torus of tube
    // 0.2 under noise of 0.1 (disc 0.27). There the noise at the disc's rim put samples
    // beyond the sphere of the tube's curvature, the curved heights' fit was refused where
    // the fit was to keep it (`jet_fit`, step 3: at nearly every vertex) and the heights'
    // left ridges along the outer side of the tube in every one of these draws: 2.0 to 2.6
    // diagonals on the public torus, 0.7 to 2.6 on the thin one (HPW and YBS).
    let public = load("ring/reg20k");
    let thin = crestline::shapes::torus(1.0, 0.2, 200, 50);
    let cases = [
        ("public", &public, 0.3, 0.2, 22),
        ("public", &public, 0.3, 0.2, 23),
        ("thin", &thin, 0.2, 0.1, 1),
        ("thin", &thin, 0.2, 0.1, 2),
        ("thin", &thin, 0.2, 0.1, 3),
    ];
    for (name, clean, tube, fraction, seed) in cases {
        check_noisy_torus_has_no_lines(name, clean, fraction, seed, Some(tube));
    }
}

/// `mesh` with every 200th vertex moved three mean edges along its normal, outward and inward
/// in turn: the stray samples of a scan.
fn with_spikes(mesh: &TriMesh) -> (TriMesh, Vec<u32>) {
    let normals = crestline::mesh::vertex_normals_area(mesh);
    let edge = crestline::mesh::mean_edge_length(mesh);
    let mut positions = mesh.positions().to_vec();
    let spikes: Vec<u32> = (100..mesh.num_vertices() as u32).step_by(200).collect();
    for (i, &v) in spikes.iter().enumerate() {
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        positions[v as usize] += normals[v as usize] * (3.0 * sign * edge);
    }
    (mesh.with_positions(positions).unwrap(), spikes)
}

#[test]
fn spikes_are_put_back_before_anything_is_estimated() {
    // Stray vertices three edges off the surface (`mesh::outliers`), one in 200 here. Each was
    // ringed with creases and pulled every fit around it into crest lines: measured here with
    // them kept, the clean ellipsoid F1 0.248 and the noisy one 0.000; put back, 1.000 and
    // 1.000, and the noisy torus keeps no line (0.000 diagonals).
    for (case, min_f1) in [("ovoid/reg20k", 0.97), ("ovoid/noisy20k", 0.95)] {
        let (mesh, spikes) = with_spikes(&load(case));
        let mut options = ExtractOptions::for_method(Method::Hpw);
        let result = extract(&mesh, &options).unwrap();
        assert_eq!(result.stats.outliers.vertices, spikes, "{case}");
        assert_eq!(result.stats.creases, 0, "{case}");
        let (p, r, f1) = score(&mesh, &result.lines, "ovoid");
        eprintln!("{case} with spikes: P {p:.3} R {r:.3} F1 {f1:.3}");
        assert!(f1 >= min_f1, "{case} with spikes: F1 {f1:.3}");
        options.repair_outliers = false;
        let kept = extract(&mesh, &options).unwrap();
        let (p, r, f1) = score(&mesh, &kept.lines, "ovoid");
        eprintln!("{case} with spikes kept: P {p:.3} R {r:.3} F1 {f1:.3}");
        assert!(f1 < 0.5, "{case} with spikes kept: F1 {f1:.3}");
    }
    let (mesh, _) = with_spikes(&load("ring/noisy20k"));
    let result = extract(&mesh, &ExtractOptions::for_method(Method::Hpw)).unwrap();
    let spurious = result.lines.total_length() / mesh.bounding_box().diagonal();
    eprintln!("ring/noisy20k with spikes: {spurious:.3} diagonals");
    assert!(
        spurious <= 0.1,
        "{spurious:.3} diagonals of lines on the torus"
    );
}

#[test]
fn ybs_irregular_superquadric() {
    check_f1(Method::Ybs, "superquadric/irr20k", 0.97);
}

#[test]
fn ybs_marching_cubes_ellipsoid() {
    check_f1(Method::Ybs, "ovoid/mc", 0.98);
}

#[test]
fn ybs_noisy_superquadric() {
    check_f1(Method::Ybs, "superquadric/noisy20k", 0.97);
}

#[test]
fn ybs_noisy_torus_has_no_lines() {
    check_spurious(Method::Ybs, "ring/noisy20k", 0.1);
}

#[test]
fn saliency_irregular_ellipsoid() {
    // Measured (score.py): F1 1.000.
    check_f1(Method::Saliency, "ovoid/irr20k", 0.97);
}

#[test]
fn saliency_marching_cubes_superquadric() {
    // Measured (score.py): F1 0.989 (0.971 before the lines grew between crest points in one
    // triangle, 2026-11-28).
    check_f1(Method::Saliency, "superquadric/mc", 0.97);
}

/// The saliency method's lines grow from their salient stretches along the crest points
/// (`lines/link.rs`, *Whole lines*), also between crest points in one triangle whose carrying
/// vertices lie on either side of the line: the ridge's valleys cross the regular grid at an
/// angle and the bumps' rings cross the irregular triangles, and both were kept in pieces.
#[test]
fn saliency_lines_across_the_triangles_are_whole() {
    // Measured here (recall over every exact line): ridge/reg20k F1 0.773 → 0.875,
    // bumpy/irr20k 0.451 → 0.479 (score.py, strong lines only: 0.896 → 0.963, 0.850 → 0.894).
    check_f1(Method::Saliency, "ridge/reg20k", 0.85);
    check_f1(Method::Saliency, "bumpy/irr20k", 0.47);
}

#[test]
fn saliency_noisy_bumpy_sphere() {
    // The saliency method's lines are crest lines, moved back by the fit's bias as HPW's
    // (`lines::debias`): score.py 0.466 → 0.815, here (recall over every exact line, where
    // the saliency method keeps the strong ones only) 0.244 → 0.431.
    check_f1(Method::Saliency, "bumpy/noisy20k", 0.41);
}

/// The saliency's knee per family (`saliency::family`): the ridge surface's valleys bend less
/// than its ridge, and with one knee over all vertices they were kept or lost by a hair (the
/// irregular and the noisy mesh lost them).
#[test]
fn saliency_valleys_beside_a_ridge_have_a_knee_of_their_own() {
    // Measured here (recall over every exact line): irr20k F1 0.650 -> 0.919, noisy20k
    // 0.687 -> 0.822 (score.py, strong lines only: 0.753 -> 0.957, 0.788 -> 0.920).
    check_f1(Method::Saliency, "ridge/irr20k", 0.89);
    check_f1(Method::Saliency, "ridge/noisy20k", 0.78);
    for case in ["ridge/irr20k", "ridge/noisy20k"] {
        let result = extract(&load(case), &ExtractOptions::for_method(Method::Saliency)).unwrap();
        let s = &result.stats;
        let [ridge, valley] = s.family_thresholds.unwrap();
        assert!(
            ridge == s.threshold && valley < s.threshold,
            "{case}: {s:?}"
        );
    }
}

#[test]
fn saliency_noisy_torus_has_no_lines() {
    check_spurious(Method::Saliency, "ring/noisy20k", 0.1);
}

/// A saliency that rises without a knee is split in two (`threshold::NoKnee::Split`): on the
/// superquadric, whose rounded edges make its sorted saliency one ramp, with a knee search
/// that can find no knee (no step is steep enough), the saliency method still draws its
/// crest lines (measured: F1 1.000, split at 0.90; with the default search the knee is at
/// 0.63, F1 1.000; before the split, nothing: F1 0).
#[test]
fn saliency_without_a_knee_is_split() {
    use crestline::extract::Pipeline;
    use crestline::threshold::{KneeSearch, Threshold};
    let mut options = ExtractOptions::for_method(Method::Saliency);
    let Pipeline::Saliency(mwz) = &mut options.pipeline else {
        panic!("the saliency method's pipeline")
    };
    let Threshold::Knee { search, .. } = &mut mwz.threshold else {
        panic!("the saliency method's default threshold is a knee search")
    };
    *search = KneeSearch {
        steepness: f64::INFINITY,
        ..*search
    };
    let mesh = load("superquadric/reg20k");
    let result = extract(&mesh, &options).unwrap();
    assert!(result.stats.threshold_is_split, "{:?}", result.stats);
    let (p, r, f1) = score(&mesh, &result.lines, "superquadric");
    eprintln!(
        "saliency split at {:.3}: P {p:.3} R {r:.3} F1 {f1:.3}",
        result.stats.threshold
    );
    assert!(f1 >= 0.95, "F1 {f1:.3} (P {p:.3}, R {r:.3})");
}

/// Smooth surfaces have no creases, also between filtered normals (`lines::crease`, step 2b,
/// which runs on all of these: their angles have no gap and their faces turn by more than
/// `NOISE_ROUGHNESS`). The two ways the filter was seen to make them (2026-11-27): the
/// plain bilateral filter kept the normals of the irregular torus's slivers (0.5 diagonals
/// of creases); a guidance taken from any less spread patch broke the coarse torus into
/// facets (25 diagonals).
#[test]
fn smooth_surfaces_have_no_creases_between_filtered_normals() {
    use crestline::lines::crease::{CreaseOptions, NOISE_ROUGHNESS, find_creases, roughness};
    let noisy_irregular = |case: &str, seed| {
        let mesh = crestline::shapes::with_normal_noise(&load(case), 0.1, seed).unwrap();
        (format!("{case} + noise 0.1"), mesh)
    };
    let cases = [
        "ring/irr20k",
        "ring/reg5k",
        "bumpy/noisy20k",
        "ridge/noisy20k",
    ]
    .map(|case| (case.to_string(), load(case)))
    .into_iter()
    // Irregular and noisy, made here. (Spheres made alike with noise along the exact normals
    // got creases from a patch spacing taken as the median distance to the neighbours
    // instead of the mean; these do not show it.)
    .chain([
        noisy_irregular("ovoid/irr20k", 606),
        noisy_irregular("bumpy/irr20k", 505),
    ]);
    for (case, mesh) in cases {
        assert!(
            roughness(&mesh).to_degrees() >= NOISE_ROUGHNESS,
            "{case}: the filter would not run"
        );
        let raw = CreaseOptions {
            filter_noise: false,
            ..CreaseOptions::DEFAULT
        };
        assert!(
            find_creases(&mesh, &raw).unwrap().is_empty(),
            "{case}: no step 2b"
        );
        let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
        assert!(
            creases.is_empty(),
            "{case}: {} creases above {:?} degrees",
            creases.curves.len(),
            creases.threshold
        );
    }
}
