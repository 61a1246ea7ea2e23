//! diag
use crestline::extract::{ExtractOptions, Method, extract};
use crestline::lines::FeatureLines;
use crestline::{Vec3, shapes};

fn seg_d(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = b - a;
    let t = if ab.norm_squared() > 0.0 { ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (a + ab * t - p).norm()
}
fn dist(p: Vec3, lines: &FeatureLines) -> f64 {
    let mut best = f64::INFINITY;
    for l in &lines.lines {
        let n = l.points.len();
        let segs = if l.closed { n } else { n.saturating_sub(1) };
        for i in 0..segs { best = best.min(seg_d(p, l.points[i], l.points[(i + 1) % n])); }
        if n == 1 { best = best.min((l.points[0] - p).norm()); }
    }
    best
}
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rings: Vec<usize> = args.get(1).map(|s| s.split(',').map(|x| x.parse().unwrap()).collect()).unwrap_or(vec![1]);
    for sub in [4u32, 5] {
        let mesh = shapes::ellipsoid(3.0, 2.0, 1.0, sub);
        let diag = mesh.bounding_box().diagonal();
        for &r in &rings {
            let mut o = ExtractOptions::for_method(Method::Ybs);
            o.curvature = o.curvature.with_rings(r);
            if let Ok(s) = std::env::var("SMOOTH") { o.smoothing = crestline::smoothing::extremality::ExtremalitySmoothing { steps: s.parse().unwrap(), ..Default::default() }; }
            let res = extract(&mesh, &o).unwrap();
            let eq: Vec<Vec3> = (0..20000).map(|i| { let t = i as f64 * std::f64::consts::TAU / 20000.0; Vec3::new(3.0 * t.cos(), 2.0 * t.sin(), 0.0) }).collect();
            let mut worst: f64 = 0.0;
            for l in &res.lines.lines { for p in &l.points { worst = worst.max(eq.iter().map(|q| (q - p).norm()).fold(f64::INFINITY, f64::min)); } }
            let cov = eq.iter().step_by(10).filter(|q| dist(**q, &res.lines) <= 0.01 * diag).count() as f64 / 2000.0;
            println!("sub {sub} rings {r}: lines {} (traced {}, gaps {}) worst {:.4} (tol {:.4}) coverage {:.1}% closed {}", res.lines.lines.len(), res.stats.lines_traced, res.stats.gaps_jumped, worst, 0.01 * diag, 100.0 * cov, res.lines.lines.iter().filter(|l| l.closed).count());
        }
    }
    let mesh = shapes::torus(3.0, 1.0, 120, 40);
    for &r in &rings {
        let mut o = ExtractOptions::for_method(Method::Ybs);
        o.curvature = o.curvature.with_rings(r);
        if let Ok(s) = std::env::var("SMOOTH") { o.smoothing = crestline::smoothing::extremality::ExtremalitySmoothing { steps: s.parse().unwrap(), ..Default::default() }; }
        let res = extract(&mesh, &o).unwrap();
        println!("torus rings {r}: lines {} length {:.3} diag {:.3}", res.lines.lines.len(), res.lines.total_length(), mesh.bounding_box().diagonal());
    }
}
