//! diag
use crestline::extract::{ExtractOptions, Method, extract};
use crestline::lines::filter::LineFilter;
use crestline::shapes;

fn main() {
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(96);
    let cap: f64 = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(1.5);
    let (mesh, rims) = shapes::tablet(1.0, 2.0, cap, n);
    let diag = mesh.bounding_box().diagonal();
    println!("faces {} diag {diag:.3}", mesh.num_faces());
    for rings in [1usize, 3] {
        for steps in [0usize, 2, 3] {
            let mut o = ExtractOptions::for_method(Method::Ybs);
            o.curvature = o.curvature.with_rings(rings);
            o.smoothing.steps = steps;
            o.filter = LineFilter { threshold: 0.0, min_length: 0.0, ..o.filter };
            let r = extract(&mesh, &o).unwrap();
            // classify lines: near rim (all points within tol of z=±1, radius 1) or not
            let tol = 0.01 * diag;
            let near_rim = |p: &crestline::Vec3| ((p.z.abs() - 1.0).powi(2) + (p.x.hypot(p.y) - 1.0).powi(2)).sqrt() <= tol;
            let mut ts: Vec<(f64, f64, bool, usize)> = r.lines.lines.iter().map(|l| (l.strength, l.length, l.points.iter().all(near_rim), l.points.iter().filter(|p| !near_rim(p)).count())).collect();
            ts.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap());
            let rim: Vec<String> = ts.iter().filter(|t| t.2).take(6).map(|t| format!("{:.2}/{:.2}", t.0, t.1)).collect();
            let off: Vec<String> = ts.iter().filter(|t| !t.2).take(8).map(|t| format!("{:.3}/{:.2}({})", t.0, t.1, t.3)).collect();
            println!("rings {rings} steps {steps}: {} lines; rim lines (T/len) {:?}; top off-rim (T/len(offpts)) {:?} ; n off {}", ts.len(), rim, off, ts.iter().filter(|t| !t.2).count());
        }
    }
    let _ = rims;
}
