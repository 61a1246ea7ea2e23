use crestline::curvature::{CurvatureOptions, Estimator, estimate};
use crestline::io::read_mesh;
use crestline::saliency::{SaliencyOptions, mesh_saliency};
use std::io::Write;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = &args[1];
    let out = &args[2];
    let mesh = read_mesh(std::path::Path::new(path), None).unwrap();
    let c = estimate(&mesh, &CurvatureOptions::default().with_estimator(Estimator::CubicFit)).unwrap();
    let lambdas = [0.25, 0.5, 1.0, 2.0];
    let mut cols = Vec::new();
    for &l in &lambdas {
        let t = std::time::Instant::now();
        let s = mesh_saliency(&mesh, &c, &SaliencyOptions { lambda: l, ..Default::default() }).unwrap();
        eprintln!("lambda {l}: {:.3} s", t.elapsed().as_secs_f64());
        cols.push(s.saliency);
    }
    let mut f = std::io::BufWriter::new(std::fs::File::create(out).unwrap());
    writeln!(f, "l025,l05,l1,l2").unwrap();
    for v in 0..mesh.num_vertices() {
        writeln!(f, "{},{},{},{}", cols[0][v], cols[1][v], cols[2][v], cols[3][v]).unwrap();
    }
}
