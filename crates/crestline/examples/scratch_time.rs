use crestline::curvature::{CurvatureOptions, Estimator, estimate};
use crestline::io::read_mesh;
use crestline::saliency::{SaliencyOptions, mesh_saliency};
fn cpu() -> f64 {
    let s = std::fs::read_to_string("/proc/self/stat").unwrap();
    let f: Vec<&str> = s.rsplit(')').next().unwrap().split_whitespace().collect();
    (f[11].parse::<f64>().unwrap() + f[12].parse::<f64>().unwrap()) / 100.0
}
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mesh = read_mesh(std::path::Path::new(&args[1]), None).unwrap();
    let reps: usize = args.get(2).map_or(10, |s| s.parse().unwrap());
    let c = estimate(&mesh, &CurvatureOptions::default().with_estimator(Estimator::CubicFit)).unwrap();
    let sigma = crestline::mesh::mean_edge_length(&mesh);
    for f in [1.0, 2.0, 3.0] {
        let g = crestline::spatial::PointGrid::new(mesh.positions(), 8.0 * sigma / f);
        let (mut cand, mut runs, mut inr) = (0usize, 0usize, 0usize);
        for p in mesh.positions().iter().step_by(10) {
            g.for_each_run_near(*p, 8.0 * sigma, |r| { cand += r.len(); runs += 1; });
            g.for_each_within(*p, 8.0 * sigma, |_, _| inr += 1);
        }
        let q = (mesh.num_vertices() / 10) as f64;
        println!("cell r/{f}: candidates {:.1}, runs {:.1}, within {:.1}", cand as f64 / q, runs as f64 / q, inr as f64 / q);
    }
    let mut walls = Vec::new();
    let c0 = cpu();
    let mut sum = 0.0;
    for _ in 0..reps {
        let t = std::time::Instant::now();
        let s = mesh_saliency(&mesh, &c, &SaliencyOptions::default()).unwrap();
        walls.push(t.elapsed().as_secs_f64());
        sum += s.saliency.iter().sum::<f64>();
    }
    walls.sort_by(f64::total_cmp);
    println!("median wall {:.3} s, min {:.3}, cpu per run {:.3} s (checksum {sum:.6e})", walls[reps / 2], walls[0], (cpu() - c0) / reps as f64);
}
#[allow(dead_code)]
fn count() {}
