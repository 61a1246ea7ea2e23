//! diag
use crestline::curvature::{CurvatureOptions, Estimator, estimate};
use crestline::shapes::{self, exact};

fn main() {
    let sub: u32 = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(5);
    let rings: usize = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(1);
    let lo: f64 = std::env::args().nth(3).map(|s| s.parse().unwrap()).unwrap_or(120.0);
    let hi: f64 = std::env::args().nth(4).map(|s| s.parse().unwrap()).unwrap_or(140.0);
    let mesh = shapes::ellipsoid(3.0, 2.0, 1.0, sub);
    let c = estimate(&mesh, &CurvatureOptions::default().with_estimator(Estimator::CubicFit).with_rings(rings)).unwrap();
    let mut rows = Vec::new();
    for (v, p) in mesh.positions().iter().enumerate() {
        let t = (p.y / 2.0).atan2(p.x / 3.0).to_degrees();
        if p.z.abs() > 0.3 || t < lo || t > hi { continue; }
        let x = exact::ellipsoid(3.0, 2.0, 1.0, *p);
        let s = c.dir_max[v].dot(&x.dir_max).signum();
        let ang = c.dir_max[v].dot(&x.dir_max).abs().min(1.0).acos().to_degrees();
        rows.push((p.z, t, x.e_max, s * c.e_max[v], x.k_max, c.k_max[v], ang, mesh.topology().neighbors(v as u32).count()));
    }
    rows.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    for r in rows { println!("z={:+.3} t={:.1} e={:+.3} fit={:+.3} k={:.3} fit={:.3} dir_err={:.1} val={}", r.0, r.1, r.2, r.3, r.4, r.5, r.6, r.7); }
}
