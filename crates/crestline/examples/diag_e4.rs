//! diag
use crestline::curvature::cubic_fit::{Sample, fit_cubic, presmoothed_positions};
use crestline::curvature::tangent_frame;
use crestline::mesh::vertex_normals_max;
use crestline::shapes::{self, exact};
use crestline::{TriMesh, Vec3};
use nalgebra::{DMatrix, DVector};

fn ring(mesh: &TriMesh, v: u32, k: usize) -> Vec<u32> {
    let mut seen = vec![v];
    let mut frontier = vec![v];
    for _ in 0..k {
        let mut next = Vec::new();
        for &f in &frontier { for q in mesh.topology().neighbors(f) { if !seen.contains(&q) { seen.push(q); next.push(q); } } }
        frontier = next;
    }
    seen.remove(0);
    seen
}

fn refine(mesh: &TriMesh, pos: &[Vec3], normals: &[Vec3], k: usize) -> Vec<Vec3> {
    (0..mesh.num_vertices()).map(|v| {
        let (u, w, n) = tangent_frame(normals[v]);
        let r = ring(mesh, v as u32, k);
        let mut a = DMatrix::zeros(r.len(), 5);
        let mut b = DVector::zeros(r.len());
        for (i, &q) in r.iter().enumerate() {
            let d = pos[q as usize] - pos[v];
            let (x, y, z) = (d.dot(&u), d.dot(&w), d.dot(&n));
            a.row_mut(i).copy_from_slice(&[x, y, 0.5 * x * x, x * y, 0.5 * y * y]);
            b[i] = z;
        }
        let sol = a.svd(true, true).solve(&b, 1e-12).unwrap();
        (n - u * sol[0] - w * sol[1]).normalize()
    }).collect()
}

fn run(mesh: &TriMesh, pos: &[Vec3], normals: &[Vec3], name: &str) {
    let (mut err, mut norm, mut wrong, mut n) = (0.0, 0.0, 0, 0);
    let mut maxerr: f64 = 0.0;
    let mut nerr: f64 = 0.0;
    for v in 0..mesh.num_vertices() {
        let p = mesh.position(v as u32);
        let x = exact::ellipsoid(3.0, 2.0, 1.0, p);
        nerr = nerr.max(normals[v].dot(&x.normal).min(1.0).acos().to_degrees());
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
    println!("{name}: rel rms {:.3} max {:.2} wrong-sign {wrong}/{n}  max normal err {nerr:.3} deg", (err / norm).sqrt(), maxerr);
}

fn main() {
    for sub in [4u32, 5, 6] {
        let mesh = shapes::ellipsoid(3.0, 2.0, 1.0, sub);
        println!("sub {sub}");
        let pp = presmoothed_positions(&mesh);
        let sm = TriMesh::from_arrays(pp.iter().map(|q| [q.x, q.y, q.z]).collect(), mesh.faces().to_vec()).unwrap();
        let sm_n = vertex_normals_max(&sm);
        run(&mesh, &pp, &sm_n, "  M' max normals");
        for k in [1, 2] {
            let r = refine(&mesh, &pp, &sm_n, k);
            run(&mesh, &pp, &r, &format!("  M' quadric-jet normals {k}-ring"));
        }
        let raw: Vec<Vec3> = mesh.positions().to_vec();
        let rn = vertex_normals_max(&mesh);
        for k in [1, 2] {
            let r = refine(&mesh, &raw, &rn, k);
            run(&mesh, &raw, &r, &format!("  raw quadric-jet normals {k}-ring"));
        }
    }
}
