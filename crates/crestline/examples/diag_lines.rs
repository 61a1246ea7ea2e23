//! diag
use crestline::curvature::{CurvatureOptions, Estimator, estimate};
use crestline::lines::gap::GapJumping;
use crestline::lines::trace_crest_lines;
use crestline::smoothing::extremality::{ExtremalitySmoothing, smooth_extremalities};
use crestline::shapes;

fn main() {
    let sub: u32 = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(5);
    let rings: usize = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(1);
    let steps: usize = std::env::args().nth(3).map(|s| s.parse().unwrap()).unwrap_or(0);
    let gaps = std::env::args().nth(4).is_some();
    let mesh = shapes::ellipsoid(3.0, 2.0, 1.0, sub);
    let mut c = estimate(&mesh, &CurvatureOptions::default().with_estimator(Estimator::CubicFit).with_rings(rings)).unwrap();
    if steps > 0 { smooth_extremalities(&mesh, &mut c, &ExtremalitySmoothing { steps, ..Default::default() }).unwrap(); }
    let g = GapJumping::default();
    let (lines, j) = trace_crest_lines(&mesh, &c, gaps.then_some(&g));
    println!("joins {j}");
    for (i, l) in lines.lines.iter().enumerate() {
        let pts: Vec<(f64, f64)> = l.points.iter().map(|p| ((p.y / 2.0).atan2(p.x / 3.0).to_degrees(), p.z)).collect();
        println!("line {i} T={:.3} len={:.3} n={} closed={}", l.strength, l.length, pts.len(), l.closed);
        let s: Vec<String> = pts.iter().map(|(t, z)| format!("({t:.1},{z:+.3})")).collect();
        if pts.len() < 40 { println!("   {}", s.join(" ")); } else { println!("   {} ... {}", s[..5].join(" "), s[s.len()-5..].join(" ")); }
    }
}
