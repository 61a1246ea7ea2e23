//! diag
use crestline::extract::{ExtractOptions, Method, extract};
use std::path::Path;

fn main() {
    let path = std::env::args().nth(1).unwrap();
    let png = std::env::args().nth(2);
    let t: f64 = std::env::args().nth(3).map(|s| s.parse().unwrap()).unwrap_or(1.0);
    let mesh = crestline::io::read_mesh(Path::new(&path), None).unwrap();
    let mut o = ExtractOptions::for_method(Method::Ybs);
    o.filter.threshold = t;
    let r = extract(&mesh, &o).unwrap();
    println!("traced {} kept {} gaps {} times {:?}", r.stats.lines_traced, r.stats.lines, r.stats.gaps_jumped, r.stats.stage_times);
    if let Some(p) = png { crestline::render::write_png(Path::new(&p), &mesh, Some(&r.lines), None, &Default::default()).unwrap(); }
}
