//! diag
use crestline::curvature::{Curvature, CurvatureOptions, Estimator, estimate};
use crestline::lines::gap::GapJumping;
use crestline::lines::{trace_crest_lines, FeatureLines};
use crestline::shapes::{self, exact};

fn report(name: &str, mesh: &crestline::TriMesh, lines: &FeatureLines, joins: usize) {
    let diag = mesh.bounding_box().diagonal();
    let strong: Vec<_> = lines.lines.iter().filter(|l| l.strength >= 1.0 && l.length >= 0.01 * diag).collect();
    println!("{name}: lines {} joins {} strong {}", lines.lines.len(), joins, strong.len());
    for l in strong {
        let far = l.points.iter().map(|p| p.z.abs()).fold(0.0, f64::max);
        let p0 = l.points[0]; let p1 = *l.points.last().unwrap();
        println!("  {:?} n={} len={:.3} T={:.3} closed={} maxz={:.3} ({:.2},{:.2},{:.2}) -> ({:.2},{:.2},{:.2})", l.kind, l.points.len(), l.length, l.strength, l.closed, far, p0.x,p0.y,p0.z,p1.x,p1.y,p1.z);
    }
}

fn main() {
    let sub: u32 = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(5);
    let rings: usize = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(1);
    let mesh = shapes::ellipsoid(3.0, 2.0, 1.0, sub);
    let mut c = estimate(&mesh, &CurvatureOptions::default().with_estimator(Estimator::CubicFit).with_rings(rings)).unwrap();
    let g = GapJumping::default();
    for gaps in [None, Some(&g)] {
        let (l, j) = trace_crest_lines(&mesh, &c, gaps);
        report(&format!("fit gaps={}", gaps.is_some()), &mesh, &l, j);
    }
    for (v, p) in mesh.positions().iter().enumerate() {
        let x = exact::ellipsoid(3.0, 2.0, 1.0, *p);
        c.k_max[v] = x.k_max; c.k_min[v] = x.k_min; c.dir_max[v] = x.dir_max; c.dir_min[v] = x.dir_min;
        c.e_max[v] = x.e_max; c.e_min[v] = x.e_min;
    }
    for gaps in [None, Some(&g)] {
        let (l, j) = trace_crest_lines(&mesh, &c, gaps);
        report(&format!("exact gaps={}", gaps.is_some()), &mesh, &l, j);
    }
}
