//! diag
use crestline::curvature::cubic_fit::{Sample, fit_cubic, presmoothed_positions};
use crestline::curvature::tangent_frame;
use crestline::mesh::vertex_normals_max;
use crestline::shapes::{self, exact};
use crestline::{TriMesh, Vec3};

fn run(mesh: &TriMesh, pos: &[Vec3], normals: &[Vec3], name: &str) {
    let (mut err, mut norm, mut wrong, mut n) = (0.0, 0.0, 0, 0);
    let mut maxerr: f64 = 0.0;
    for v in 0..mesh.num_vertices() {
        let p = mesh.position(v as u32);
        let x = exact::ellipsoid(3.0, 2.0, 1.0, p);
        if x.k_max - x.k_min < 0.3 { continue; }
        let (u, w, nn) = tangent_frame(normals[v]);
        let samples: Vec<Sample> = mesh.topology().neighbors(v as u32).map(|q| {
            let d = pos[q as usize] - pos[v];
            let m = normals[q as usize];
            Sample { position: Vec3::new(d.dot(&u), d.dot(&w), d.dot(&nn)), normal: Some(Vec3::new(m.dot(&u), m.dot(&w), m.dot(&nn))) }
        }).collect();
        let Some(cub) = fit_cubic(&samples) else { continue };
        let (_, _, t) = cub.principal();
        let e = cub.extremality(t);
        let dir = u * t[0] + w * t[1];
        let s = dir.dot(&x.dir_max).signum();
        let d = s * e - x.e_max;
        err += d * d; norm += x.e_max * x.e_max; maxerr = maxerr.max(d.abs()); n += 1;
        if x.e_max.abs() > 1.0 && s * e * x.e_max < 0.0 { wrong += 1; }
    }
    println!("{name}: rel rms {:.3} max {:.2} wrong-sign {wrong}/{n}", (err / norm).sqrt(), maxerr);
}

fn main() {
    for sub in [4u32, 5, 6] {
        let mesh = shapes::ellipsoid(3.0, 2.0, 1.0, sub);
        let p: Vec<Vec3> = mesh.positions().to_vec();
        let exact_n: Vec<Vec3> = p.iter().map(|&q| exact::ellipsoid(3.0, 2.0, 1.0, q).normal).collect();
        let max_n = vertex_normals_max(&mesh);
        println!("sub {sub}");
        run(&mesh, &p, &exact_n, "  raw pos, exact normals");
        run(&mesh, &p, &max_n, "  raw pos, max normals");
        let pp = presmoothed_positions(&mesh);
        let sm = TriMesh::from_arrays(pp.iter().map(|q| [q.x, q.y, q.z]).collect(), mesh.faces().to_vec()).unwrap();
        let sm_n = vertex_normals_max(&sm);
        run(&mesh, &pp, &sm_n, "  smoothed pos, max normals of M'");
    }
}
