//! Accuracy of both curvature estimators on the analytic shapes, against the exact values of
//! `crestline::shapes::exact`, and the singular-triangle statistics (HPW Definition 1) of real
//! meshes next to HPW's Table 2, printed as the markdown tables of `BENCHMARKS.md`.
//!
//! ```sh
//! cargo run --release -p crestline --example curvature_accuracy
//! ```

use std::f64::consts::PI;

use crestline::curvature::{
    CubicFitOptions, Curvature, PrincipalSelection, ShapeOperatorOptions, cubic_fit, shape_operator,
};
use crestline::shapes::{self, GridPattern, exact};

const PATTERNS: [GridPattern; 2] = [GridPattern::Alternating, GridPattern::Uniform];

fn label(p: GridPattern) -> &'static str {
    match p {
        GridPattern::Alternating => "alternating (valence 4/8)",
        GridPattern::Uniform => "uniform (valence 6)",
    }
}
use crestline::{TriMesh, Vec3};

struct Case {
    name: String,
    mesh: TriMesh,
    exact: Box<dyn Fn(Vec3) -> exact::ExactCurvature>,
    /// Vertices at least this many rings from the boundary are compared.
    margin: u32,
    /// Directions (and the e they orient) are compared where k_max − k_min exceeds this.
    min_gap: f64,
}

/// One estimator configuration.
type Estimate = Box<dyn Fn(&TriMesh) -> crestline::Result<Curvature>>;

fn estimators() -> Vec<(&'static str, Estimate)> {
    vec![
        (
            "shape operator",
            Box::new(|m: &TriMesh| Ok(shape_operator(m, &ShapeOperatorOptions::DEFAULT))),
        ),
        (
            "shape operator (3×3 largest |λ|)",
            Box::new(|m: &TriMesh| {
                Ok(shape_operator(
                    m,
                    &ShapeOperatorOptions::DEFAULT
                        .with_direction_support(0.0)
                        .with_selection(PrincipalSelection::LargestMagnitude),
                ))
            }),
        ),
        (
            "cubic fit k=1",
            Box::new(|m: &TriMesh| cubic_fit(m, &CubicFitOptions::DEFAULT)),
        ),
        (
            "cubic fit k=1, no p→p'",
            Box::new(|m: &TriMesh| cubic_fit(m, &CubicFitOptions::DEFAULT.with_presmooth(false))),
        ),
        (
            "cubic fit k=2",
            Box::new(|m: &TriMesh| cubic_fit(m, &CubicFitOptions::DEFAULT.with_rings(2))),
        ),
    ]
}

fn cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for s in [3, 4] {
        let m = shapes::icosphere(2.0, s);
        cases.push(Case {
            name: format!("sphere r=2, icosphere({s}), {} v", m.num_vertices()),
            mesh: m,
            exact: Box::new(|p| exact::sphere(2.0, p)),
            margin: 0,
            min_gap: f64::INFINITY,
        });
    }
    for ((n, l), pattern) in [(32, 20), (64, 40)]
        .into_iter()
        .flat_map(|s| PATTERNS.map(|p| (s, p)))
    {
        let m = shapes::cylinder_with(1.0, 4.0, n, l, pattern);
        cases.push(Case {
            name: format!(
                "cylinder r=1, {n}×{l} {}, {} v",
                label(pattern),
                m.num_vertices()
            ),
            mesh: m,
            exact: Box::new(|p| exact::cylinder(1.0, p)),
            margin: 2,
            min_gap: 0.0,
        });
    }
    for s in [4, 5] {
        let m = shapes::ellipsoid(2.0, 1.5, 1.0, s);
        cases.push(Case {
            name: format!("ellipsoid 2,1.5,1, icosphere({s}), {} v", m.num_vertices()),
            mesh: m,
            exact: Box::new(|p| exact::ellipsoid(2.0, 1.5, 1.0, p)),
            margin: 0,
            min_gap: 0.05,
        });
    }
    for ((a, b), pattern) in [(48, 16), (96, 32)]
        .into_iter()
        .flat_map(|s| PATTERNS.map(|p| (s, p)))
    {
        let m = shapes::torus_with(3.0, 1.0, a, b, pattern);
        cases.push(Case {
            name: format!(
                "torus 3,1, {a}×{b} {}, {} v",
                label(pattern),
                m.num_vertices()
            ),
            mesh: m,
            exact: Box::new(|p| exact::torus(3.0, 1.0, p)),
            margin: 0,
            min_gap: 0.0,
        });
    }
    for (n, pattern) in [60, 120].into_iter().flat_map(|s| PATTERNS.map(|p| (s, p))) {
        let m = shapes::waving_surface_with(6.0, n, pattern);
        cases.push(Case {
            name: format!(
                "waving grid [-6,6]², {n}×{n} {}, {} v",
                label(pattern),
                m.num_vertices()
            ),
            mesh: m,
            exact: Box::new(exact::waving),
            margin: 3,
            min_gap: 0.05,
        });
    }
    for rings in [28, 56] {
        let m = shapes::waving_disk(3.0 * PI, rings);
        cases.push(Case {
            name: format!(
                "waving disk ρ≤3π, {rings} rings, {} v / {} f",
                m.num_vertices(),
                m.num_faces()
            ),
            mesh: m,
            exact: Box::new(exact::waving),
            margin: 3,
            min_gap: 0.05,
        });
    }
    cases
}

/// HPW Table 2: singular triangles of the raw and the smoothed bunny.
fn singular_triangles() -> crestline::Result<()> {
    use crestline::curvature::extremality::triangle_regularity;
    use crestline::smoothing::surface::{SurfaceSmoothing, smooth_surface};
    let dir =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes");
    println!("| mesh | faces | estimator | singular (max) | singular (min) | singular (either) |");
    println!("| --- | --- | --- | --- | --- | --- |");
    for name in ["stanford-bunny.obj", "igea.ply", "fandisk.obj"] {
        let mesh = match crestline::io::read_mesh(&dir.join(name), None) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("skipping {name}: {e}");
                continue;
            }
        };
        let mut variants = vec![(name.to_string(), mesh.clone())];
        if name == "stanford-bunny.obj" {
            for steps in [1, 3] {
                let options = SurfaceSmoothing {
                    steps,
                    ..Default::default()
                };
                if let Ok(m) = smooth_surface(&mesh, &options) {
                    variants.push((format!("{name}, {steps} mean-curvature-flow steps"), m));
                }
            }
        }
        for (label, m) in variants {
            let unsupported = ShapeOperatorOptions::DEFAULT.with_direction_support(0.0);
            let literal = unsupported.with_selection(PrincipalSelection::LargestMagnitude);
            for (estimator, c) in [
                (
                    "shape operator (default: direction support 0.5)",
                    shape_operator(&m, &ShapeOperatorOptions::DEFAULT),
                ),
                (
                    "shape operator, no direction support",
                    shape_operator(&m, &unsupported),
                ),
                (
                    "shape operator (3×3 largest |λ|)",
                    shape_operator(&m, &literal),
                ),
                ("cubic fit k=1", cubic_fit(&m, &CubicFitOptions::DEFAULT)?),
            ] {
                let r = triangle_regularity(&m, &c);
                println!(
                    "| {label} | {} | {estimator} | {} ({:.2}%) | {} ({:.2}%) | {} ({:.2}%) |",
                    m.num_faces(),
                    r.singular_max,
                    100.0 * r.singular_max_fraction(),
                    r.singular_min,
                    100.0 * r.singular_min_fraction(),
                    r.singular_either,
                    100.0 * r.singular_either_fraction()
                );
            }
        }
    }
    println!();
    Ok(())
}

fn main() -> crestline::Result<()> {
    singular_triangles()?;
    println!(
        "| shape | estimator | k_max max / rms | k_min max / rms | e_max max / rms | e_min max / rms | dir_max ° max / rms | dir_min ° max / rms | fallback |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for case in cases() {
        let dist = exact::rings_from_boundary(&case.mesh);
        for (name, estimate) in estimators() {
            let c = estimate(&case.mesh)?;
            let all = exact::compare(
                &case.mesh,
                &c,
                &case.exact,
                |v| dist[v] >= case.margin,
                case.min_gap,
            );
            let f = |s: exact::ErrorStat| {
                if s.count == 0 {
                    "–".to_string()
                } else {
                    format!("{:.3} / {:.3}", s.max, s.rms)
                }
            };
            let fd = |s: exact::ErrorStat| {
                if s.count == 0 {
                    "–".to_string()
                } else {
                    format!("{:.1} / {:.2}", s.max, s.rms)
                }
            };
            println!(
                "| {} | {name} | {} | {} | {} | {} | {} | {} | {} |",
                case.name,
                f(all.k_max),
                f(all.k_min),
                f(all.e_max),
                f(all.e_min),
                fd(all.dir_max_deg),
                fd(all.dir_min_deg),
                c.fallback_vertices
            );
            if case.min_gap.is_finite() && case.min_gap > 0.0 {
                // The same, away from umbilics (where e and directions are defined).
                let away = exact::compare(
                    &case.mesh,
                    &c,
                    &case.exact,
                    |v| {
                        let x = (case.exact)(case.mesh.positions()[v]);
                        dist[v] >= case.margin && x.k_max - x.k_min > case.min_gap
                    },
                    case.min_gap,
                );
                println!(
                    "| ↳ gap > {} | {name} | {} | {} | {} | {} | | | |",
                    case.min_gap,
                    f(away.k_max),
                    f(away.k_min),
                    f(away.e_max),
                    f(away.e_min),
                );
            }
        }
    }
    Ok(())
}
