//! Throwaway: per-stage time and peak RSS of the HPW pipeline (not committed).
use std::path::Path;
use std::time::Instant;

use crestline::curvature::{self, CurvatureOptions, Estimator};
use crestline::io::{Format, PlyEncoding};
use crestline::lines::filter::{LineFilter, StrengthMeasure, filter_lines};
use crestline::lines::trace_lines;
use crestline::smoothing::extremality::{ExtremalitySmoother, ExtremalitySmoothing};
use crestline::smoothing::{ConjugateGradientOptions, LinearSolver};
use crestline::{TriMesh, Vec3};

fn hwm_kb() -> u64 {
    let s = std::fs::read_to_string("/proc/self/status").unwrap();
    for l in s.lines() {
        if let Some(r) = l.strip_prefix("VmHWM:") {
            return r.trim().trim_end_matches("kB").trim().parse().unwrap();
        }
    }
    0
}
fn rss_kb() -> u64 {
    let s = std::fs::read_to_string("/proc/self/status").unwrap();
    for l in s.lines() {
        if let Some(r) = l.strip_prefix("VmRSS:") {
            return r.trim().trim_end_matches("kB").trim().parse().unwrap();
        }
    }
    0
}
fn cpu_s() -> f64 {
    let s = std::fs::read_to_string("/proc/self/stat").unwrap();
    let rest = &s[s.rfind(')').unwrap() + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    (f[11].parse::<f64>().unwrap() + f[12].parse::<f64>().unwrap()) / 100.0
}
fn reset() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

struct Report {
    faces: f64,
    t0: Instant,
    c0: f64,
}
impl Report {
    fn stage(&mut self, name: &str) {
        let t = self.t0.elapsed().as_secs_f64();
        let peak = hwm_kb();
        let c = cpu_s();
        println!(
            "{name:<24} {:>8.3} s  cpu {:>6.2} s  peak {:>8.1} MB ({:>6.1} B/face)   now {:>8.1} MB",
            t,
            c - self.c0,
            peak as f64 / 1024.0,
            peak as f64 * 1024.0 / self.faces,
            rss_kb() as f64 / 1024.0
        );
        reset();
        self.t0 = Instant::now();
        self.c0 = cpu_s();
    }
}

fn loop_subdivide(m: &TriMesh) -> TriMesh {
    let topo = m.topology();
    let faces = m.faces();
    let pos = m.positions();
    let nv = m.num_vertices();
    let mut out: Vec<[f64; 3]> = Vec::with_capacity(nv + topo.num_edges());
    for v in 0..nv as u32 {
        let p = pos[v as usize];
        let nb: Vec<u32> = topo.neighbors(v).collect();
        let boundary = topo.is_boundary_vertex(v);
        let q = if boundary || nb.len() < 3 {
            p
        } else {
            let n = nb.len() as f64;
            let beta = if nb.len() == 3 {
                3.0 / 16.0
            } else {
                3.0 / (8.0 * n)
            };
            let s: Vec3 = nb.iter().map(|&u| pos[u as usize]).sum();
            p * (1.0 - n * beta) + s * beta
        };
        out.push([q.x, q.y, q.z]);
    }
    for e in 0..topo.num_edges() as u32 {
        let [a, b] = topo.edge(e);
        let (pa, pb) = (pos[a as usize], pos[b as usize]);
        let ef = topo.edge_faces(e);
        let q = if ef.len() == 2 {
            let opp = |f: u32| {
                let t = faces[f as usize];
                *t.iter().find(|&&x| x != a && x != b).unwrap()
            };
            (pa + pb) * 0.375 + (pos[opp(ef[0]) as usize] + pos[opp(ef[1]) as usize]) * 0.125
        } else {
            (pa + pb) * 0.5
        };
        out.push([q.x, q.y, q.z]);
    }
    let mut nf = Vec::with_capacity(faces.len() * 4);
    for (f, t) in faces.iter().enumerate() {
        let fe = topo.face_edges(f as u32);
        let m = fe.map(|e| nv as u32 + e); // m[s] midpoint of edge t[s]-t[s+1]
        nf.push([t[0], m[0], m[2]]);
        nf.push([t[1], m[1], m[0]]);
        nf.push([t[2], m[2], m[1]]);
        nf.push([m[0], m[1], m[2]]);
    }
    TriMesh::from_arrays(out, nf).unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args[1] == "subdivide" {
        let mut m = crestline::io::read_mesh(Path::new(&args[2]), None).unwrap();
        let levels: usize = args[4].parse().unwrap();
        for _ in 0..levels {
            m = loop_subdivide(&m);
        }
        println!("{} faces", m.num_faces());
        crestline::io::write_mesh(
            Path::new(&args[3]),
            &m,
            Format::Ply,
            &crestline::io::WriteOptions::DEFAULT,
        )
        .unwrap();
        return;
    }
    if args[1] == "cgtrace" {
        let mesh = crestline::io::read_mesh(Path::new(&args[2]), None).unwrap();
        let c0 = curvature::estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(Estimator::ShapeOperator),
        )
        .unwrap();
        let mut c = c0.clone();
        let opts = ExtremalitySmoothing {
            solver: LinearSolver::Cholesky,
            ..Default::default()
        };
        let sm = ExtremalitySmoother::new(&mesh, &c, &opts).unwrap();
        sm.step(&mut c.e_max, &mut c.e_min).unwrap();
        let csr = build_csr(&mesh, &c0, 1.0);
        let mut x: Vec<[f64; 2]> = c0
            .e_max
            .iter()
            .zip(&c0.e_min)
            .map(|(a, b)| [*a, *b])
            .collect();
        if args.len() > 3 {
            let omega: f64 = args[3].parse().unwrap();
            let mut x: Vec<f64> = c0.e_max.clone();
            let t = Instant::now();
            let it = csr.solve_sgs(&mut x, 0, 1e-10, omega, Some(&c.e_max));
            println!(
                "sgs omega {omega}: {it} its {:.3} s",
                t.elapsed().as_secs_f64()
            );
            return;
        }
        csr.solve_traced(&mut x, 1e-10, Some(&c.e_max));
        return;
    }
    if args[1] == "spectrum" {
        let mesh = crestline::io::read_mesh(Path::new(&args[2]), None).unwrap();
        let c0 = curvature::estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(Estimator::ShapeOperator),
        )
        .unwrap();
        let csr = build_csr(&mesh, &c0, 1.0);
        let mut md: Vec<f64> = csr.mass.iter().zip(&csr.diag).map(|(m, d)| m / d).collect();
        md.sort_by(f64::total_cmp);
        let n = md.len();
        println!(
            "m/d quantiles: min {:.4} 1% {:.4} 10% {:.4} 50% {:.4} 90% {:.4}",
            md[0],
            md[n / 100],
            md[n / 10],
            md[n / 2],
            md[9 * n / 10]
        );
        let mut strong: Vec<f64> = (0..n)
            .map(|v| {
                let (s, e) = (csr.row[v] as usize, csr.row[v + 1] as usize);
                (s..e)
                    .map(|k| csr.coef[k] / csr.diag[v])
                    .fold(0.0, f64::max)
            })
            .collect();
        strong.sort_by(f64::total_cmp);
        println!(
            "max coupling/d quantiles: 50% {:.4} 90% {:.4} 99% {:.4} max {:.4}",
            strong[n / 2],
            strong[9 * n / 10],
            strong[99 * n / 100],
            strong[n - 1]
        );
        return;
    }
    if args[1] == "eis" {
        let mesh = crestline::io::read_mesh(Path::new(&args[2]), None).unwrap();
        let tol: f64 = args[3].parse().unwrap();
        let c0 = curvature::estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(Estimator::ShapeOperator),
        )
        .unwrap();
        // exact reference by Cholesky
        let mut cx = c0.clone();
        let opts = ExtremalitySmoothing {
            solver: LinearSolver::Cholesky,
            ..Default::default()
        };
        let sm = ExtremalitySmoother::new(&mesh, &cx, &opts).unwrap();
        for _ in 0..3 {
            sm.step(&mut cx.e_max, &mut cx.e_min).unwrap();
        }
        drop(sm);
        let csr = build_csr(&mesh, &c0, 1.0);
        // Morton order
        let bb = mesh.bounding_box();
        let mut keys: Vec<(u64, u32)> = mesh
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mut code = 0u64;
                let q: Vec<u64> = (0..3)
                    .map(|k| {
                        (((p[k] - bb.min[k]) / (bb.max[k] - bb.min[k]).max(1e-300)) * 2097151.0)
                            as u64
                    })
                    .collect();
                for bit in 0..21 {
                    for k in 0..3 {
                        code |= ((q[k] >> bit) & 1) << (3 * bit + k);
                    }
                }
                (code, i as u32)
            })
            .collect();
        keys.sort_unstable();
        let morton: Vec<u32> = keys.iter().map(|k| k.1).collect();
        for (name, order, blocks) in [
            ("natural", None, 1usize),
            ("natural", None, 8),
            ("morton", Some(&morton[..]), 1),
            ("morton", Some(&morton[..]), 2),
            ("morton", Some(&morton[..]), 8),
            ("morton", Some(&morton[..]), 32),
        ] {
            let sys = eis::Sys::from_perm(&csr, order);
            let n = mesh.num_vertices();
            eis::BLOCK.store(n.div_ceil(blocks), std::sync::atomic::Ordering::Relaxed);
            let mode = true;
            let x0: Vec<[f64; 2]> = c0
                .e_max
                .iter()
                .zip(&c0.e_min)
                .map(|(a, b)| [*a, *b])
                .collect();
            let mut x: Vec<[f64; 2]> = match order {
                Some(o) => o.iter().map(|&i| x0[i as usize]).collect(),
                None => x0,
            };
            print!("{name} blocks {blocks}: ");
            let t = Instant::now();
            let cp = cpu_s();
            let mut its = vec![];
            for _ in 0..3 {
                its.push(sys.solve(&mut x, tol, mode));
            }
            let el = t.elapsed().as_secs_f64();
            if let Some(o) = order {
                let mut y = vec![[0.0; 2]; x.len()];
                for (new, &old) in o.iter().enumerate() {
                    y[old as usize] = x[new];
                }
                x = y;
            }
            let rms = (x
                .iter()
                .zip(&cx.e_max)
                .map(|(u, v)| (u[0] - v).powi(2))
                .sum::<f64>()
                / cx.e_max.iter().map(|v| v * v).sum::<f64>())
            .sqrt();
            println!(
                "eisenstat {mode}: its {its:?} {el:.3} s cpu {:.2} rel l2 err vs cholesky {rms:.2e}",
                cpu_s() - cp
            );
        }
        return;
    }
    if args[1] == "cgbench" {
        let mesh = crestline::io::read_mesh(Path::new(&args[2]), None).unwrap();
        let tol: f64 = args[3].parse().unwrap();
        let c0 = curvature::estimate(
            &mesh,
            &CurvatureOptions::default().with_estimator(Estimator::ShapeOperator),
        )
        .unwrap();
        for round in 0..1 {
            let which = args.get(4).map(String::as_str).unwrap_or("both");
            if which != "csr" {
                // library
                let mut c = c0.clone();
                let pre = if which == "jacobi" {
                    crestline::smoothing::Preconditioner::Jacobi
                } else {
                    crestline::smoothing::Preconditioner::SymmetricGaussSeidel
                };
                let opts = ExtremalitySmoothing {
                    solver: LinearSolver::ConjugateGradient(
                        ConjugateGradientOptions::DEFAULT
                            .with_tolerance(tol)
                            .with_preconditioner(pre),
                    ),
                    ..Default::default()
                };
                let t = Instant::now();
                let cp = cpu_s();
                let sm = ExtremalitySmoother::new(&mesh, &c, &opts).unwrap();
                let t_setup = t.elapsed().as_secs_f64();
                let mut its = 0;
                for _ in 0..3 {
                    its += sm.step(&mut c.e_max, &mut c.e_min).unwrap();
                }
                println!(
                    "round {round} lib: setup {t_setup:.3} total {:.3} s cpu {:.2} its {its}",
                    t.elapsed().as_secs_f64(),
                    cpu_s() - cp
                );
            }
            let lib_e = c0.e_max.clone();
            if which == "lib" || which == "jacobi" {
                continue;
            }
            // csr
            let c = c0.clone();
            let t = Instant::now();
            let cp = cpu_s();
            let csr = build_csr(&mesh, &c, 1.0);
            let t_setup = t.elapsed().as_secs_f64();
            let mut x: Vec<[f64; 2]> = c
                .e_max
                .iter()
                .zip(&c.e_min)
                .map(|(a, b)| [*a, *b])
                .collect();
            let mut its = 0;
            for _ in 0..3 {
                its += csr.solve(&mut x, tol);
            }
            let d = x
                .iter()
                .zip(&lib_e)
                .map(|(a, b)| (a[0] - b).abs())
                .fold(0.0, f64::max);
            println!(
                "round {round} csr: setup {t_setup:.3} total {:.3} s cpu {:.2} its {its} maxdiff {d:e}",
                t.elapsed().as_secs_f64(),
                cpu_s() - cp
            );
        }
        return;
    }
    let path = Path::new(&args[1]);
    let solver = match args.get(2).map(String::as_str) {
        Some("cholesky") => LinearSolver::Cholesky,
        Some(t) if t.starts_with("jacobi:") => LinearSolver::ConjugateGradient(
            ConjugateGradientOptions::DEFAULT
                .with_tolerance(t[7..].parse().unwrap())
                .with_preconditioner(crestline::smoothing::Preconditioner::Jacobi),
        ),
        Some(t) => LinearSolver::ConjugateGradient(
            ConjugateGradientOptions::DEFAULT.with_tolerance(t.parse().unwrap()),
        ),
        None => LinearSolver::DEFAULT,
    };
    reset();
    let t0 = Instant::now();
    let bytes = std::fs::read(path).unwrap();
    let data = crestline::io::parse_mesh_bytes(&bytes, Format::resolve(path, None).unwrap(), path)
        .unwrap();
    drop(bytes);
    let faces_in = data.faces.len() as f64;
    let mut r = Report {
        faces: faces_in,
        t0,
        c0: 0.0,
    };
    r.stage("read+parse");
    let mesh = data.into_mesh(path).unwrap();
    r.stage("mesh+topology");
    let mut c = curvature::estimate(
        &mesh,
        &CurvatureOptions::default().with_estimator(Estimator::ShapeOperator),
    )
    .unwrap();
    r.stage("curvature");
    let opts = ExtremalitySmoothing {
        solver,
        ..Default::default()
    };
    let sm = ExtremalitySmoother::new(&mesh, &c, &opts).unwrap();
    r.stage("smoothing setup");
    let mut its = vec![];
    for _ in 0..opts.steps {
        its.push(sm.step(&mut c.e_max, &mut c.e_min).unwrap());
    }
    drop(sm);
    r.stage(&format!("smoothing steps {its:?}"));
    let (traced, rep) = trace_lines(&mesh, &c);
    r.stage("tracing");
    let diag = mesh.bounding_box().diagonal();
    let lines = filter_lines(
        traced,
        &LineFilter {
            measure: StrengthMeasure::Cyclideness,
            threshold: 1.0,
            min_length: 0.01,
        },
        diag,
    );
    r.stage("filtering");
    crestline::io::lines::write_lines(
        Path::new("/tmp/stage_profile.obj"),
        &lines,
        None,
        PlyEncoding::BinaryLittleEndian,
    )
    .unwrap();
    r.stage("write");
    println!(
        "lines {} length {:.6} singular {}/{}",
        lines.lines.len(),
        lines.total_length(),
        rep.singular_max,
        rep.singular_min
    );
    let em: f64 = c.e_max.iter().map(|x| x.abs()).sum();
    println!("sum|e_max| {em:.12e}");
}

pub mod exp {
    use rayon::prelude::*;
    const CH: usize = 1024;
    impl Csr {
        // A p for field f (0 or 1)
        fn row1(&self, v: usize, p: &[f64], f: u8) -> f64 {
            let (s, e) = (self.row[v] as usize, self.row[v + 1] as usize);
            let mut acc = 0.0;
            for k in s..e {
                let w = self.coef[k];
                acc +=
                    (if self.flip[k] & (1 << f) != 0 { -w } else { w }) * p[self.col[k] as usize];
            }
            self.diag[v] * p[v] - acc
        }
        // symmetric Gauss-Seidel with relaxation omega: z = P^{-1} r
        fn sgs(&self, r: &[f64], z: &mut [f64], f: u8, omega: f64) {
            let n = r.len();
            // forward: (D/ω + L) y = r   (L strict lower part of A = -coef*sign for col<v)
            for v in 0..n {
                let (s, e) = (self.row[v] as usize, self.row[v + 1] as usize);
                let mut acc = r[v];
                for k in s..e {
                    let j = self.col[k] as usize;
                    if j < v {
                        let w = self.coef[k];
                        acc += (if self.flip[k] & (1 << f) != 0 { -w } else { w }) * z[j];
                    }
                }
                z[v] = acc * omega / self.diag[v];
            }
            // scale: y <- (2-ω)/ω D y
            for v in 0..n {
                z[v] *= (2.0 - omega) / omega * self.diag[v];
            }
            // backward: (D/ω + U) z = y
            for v in (0..n).rev() {
                let (s, e) = (self.row[v] as usize, self.row[v + 1] as usize);
                let mut acc = z[v];
                for k in s..e {
                    let j = self.col[k] as usize;
                    if j > v {
                        let w = self.coef[k];
                        acc += (if self.flip[k] & (1 << f) != 0 { -w } else { w }) * z[j];
                    }
                }
                z[v] = acc * omega / self.diag[v];
            }
        }
        pub fn solve_sgs(
            &self,
            x: &mut [f64],
            f: u8,
            tol: f64,
            omega: f64,
            exact: Option<&[f64]>,
        ) -> usize {
            let n = x.len();
            let mut r = vec![0.0; n];
            let mut z = vec![0.0; n];
            let mut p = vec![0.0; n];
            let mut q = vec![0.0; n];
            let mut bb = 0.0;
            for v in 0..n {
                let b = self.mass[v] * x[v];
                bb += b * b;
                r[v] = b - self.row1(v, x, f);
            }
            self.sgs(&r, &mut z, f, omega);
            p.copy_from_slice(&z);
            let mut rz: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
            let mut rr: f64 = r.iter().map(|a| a * a).sum();
            let mut it = 0;
            while rr > tol * tol * bb {
                if let Some(ex) = exact {
                    let rms = (x.iter().zip(ex).map(|(u, v)| (u - v).powi(2)).sum::<f64>()
                        / ex.iter().map(|v| v * v).sum::<f64>())
                    .sqrt();
                    println!(
                        "sgs it {it:3} relres {:.3e} rel l2 err {:.3e}",
                        (rr / bb).sqrt(),
                        rms
                    );
                }
                it += 1;
                for v in 0..n {
                    q[v] = self.row1(v, &p, f);
                }
                let pq: f64 = p.iter().zip(&q).map(|(a, b)| a * b).sum();
                let alpha = rz / pq;
                for v in 0..n {
                    x[v] += alpha * p[v];
                    r[v] -= alpha * q[v];
                }
                self.sgs(&r, &mut z, f, omega);
                let rz2: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
                rr = r.iter().map(|a| a * a).sum();
                let beta = rz2 / rz;
                rz = rz2;
                for v in 0..n {
                    p[v] = z[v] + beta * p[v];
                }
            }
            it
        }
    }
    pub struct Csr {
        pub row: Vec<u32>,
        pub col: Vec<u32>,
        pub coef: Vec<f64>,
        pub flip: Vec<u8>,
        pub diag: Vec<f64>,
        pub mass: Vec<f64>,
    }
    impl Csr {
        #[inline]
        fn row_product(&self, v: usize, p: &[[f64; 2]]) -> [f64; 2] {
            let (s, e) = (self.row[v] as usize, self.row[v + 1] as usize);
            let mut acc = [0.0; 2];
            for k in s..e {
                let j = self.col[k] as usize;
                let w = self.coef[k];
                let fl = self.flip[k];
                let pj = p[j];
                acc[0] += (if fl & 1 != 0 { -w } else { w }) * pj[0];
                acc[1] += (if fl & 2 != 0 { -w } else { w }) * pj[1];
            }
            let d = self.diag[v];
            [d * p[v][0] - acc[0], d * p[v][1] - acc[1]]
        }
        pub fn solve(&self, x: &mut [[f64; 2]], tol: f64) -> usize {
            self.solve_traced(x, tol, None)
        }
        pub fn solve_traced(&self, x: &mut [[f64; 2]], tol: f64, exact: Option<&[f64]>) -> usize {
            let n = x.len();
            let mut r = vec![[0.0; 2]; n];
            let mut p = vec![[0.0; 2]; n];
            let mut q = vec![[0.0; 2]; n];
            let mut bb = [0.0; 2];
            let mut rr = [0.0; 2];
            let mut rz = [0.0; 2];
            for v in 0..n {
                let ax = self.row_product(v, x);
                for f in 0..2 {
                    let b = self.mass[v] * x[v][f];
                    r[v][f] = b - ax[f];
                    p[v][f] = r[v][f] / self.diag[v];
                    bb[f] += b * b;
                    rr[f] += r[v][f] * r[v][f];
                    rz[f] += r[v][f] * p[v][f];
                }
            }
            let mut it = 0;
            loop {
                if let Some(ex) = exact {
                    let sc = ex.iter().fold(0.0f64, |a, b| a.max(b.abs()));
                    let err = x
                        .iter()
                        .zip(ex)
                        .fold(0.0f64, |a, (u, v)| a.max((u[0] - v).abs()));
                    let rms = (x
                        .iter()
                        .zip(ex)
                        .map(|(u, v)| (u[0] - v).powi(2))
                        .sum::<f64>()
                        / ex.iter().map(|v| v * v).sum::<f64>())
                    .sqrt();
                    println!(
                        "it {it:3} relres {:.3e} maxerr/max {:.3e} rel l2 err {:.3e}",
                        (rr[0] / bb[0]).sqrt(),
                        err / sc,
                        rms
                    );
                }
                if (0..2).all(|f| rr[f] <= tol * tol * bb[f]) {
                    return it;
                }
                it += 1;
                let parts: Vec<[f64; 2]> = q
                    .par_chunks_mut(CH)
                    .enumerate()
                    .map(|(c, qs)| {
                        let mut pq = [0.0; 2];
                        for (i, qv) in qs.iter_mut().enumerate() {
                            let v = c * CH + i;
                            *qv = self.row_product(v, &p);
                            pq[0] += p[v][0] * qv[0];
                            pq[1] += p[v][1] * qv[1];
                        }
                        pq
                    })
                    .collect();
                let pq = parts
                    .iter()
                    .fold([0.0; 2], |a, b| [a[0] + b[0], a[1] + b[1]]);
                let alpha = [rz[0] / pq[0], rz[1] / pq[1]];
                let parts: Vec<[f64; 4]> = x
                    .par_chunks_mut(CH)
                    .zip(r.par_chunks_mut(CH))
                    .enumerate()
                    .map(|(c, (xs, rs))| {
                        let mut s = [0.0; 4];
                        for (i, (xv, rv)) in xs.iter_mut().zip(rs.iter_mut()).enumerate() {
                            let v = c * CH + i;
                            let inv = 1.0 / self.diag[v];
                            for f in 0..2 {
                                xv[f] += alpha[f] * p[v][f];
                                rv[f] -= alpha[f] * q[v][f];
                                s[f] += rv[f] * rv[f];
                                s[2 + f] += rv[f] * rv[f] * inv;
                            }
                        }
                        s
                    })
                    .collect();
                let s = parts.iter().fold([0.0; 4], |a, b| {
                    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
                });
                rr = [s[0], s[1]];
                let beta = [s[2] / rz[0], s[3] / rz[1]];
                rz = [s[2], s[3]];
                p.par_chunks_mut(CH)
                    .zip(r.par_chunks(CH))
                    .enumerate()
                    .for_each(|(c, (ps, rs))| {
                        for (i, (pv, rv)) in ps.iter_mut().zip(rs).enumerate() {
                            let inv = 1.0 / self.diag[c * CH + i];
                            for f in 0..2 {
                                pv[f] = rv[f] * inv + beta[f] * pv[f];
                            }
                        }
                    });
            }
        }
    }
}

pub fn build_csr(mesh: &TriMesh, c: &crestline::curvature::Curvature, time_step: f64) -> exp::Csr {
    let topo = mesh.topology();
    let w = crestline::smoothing::cotan_weights(mesh, mesh.positions());
    let mass = crestline::smoothing::lumped_mass(mesh, mesh.positions());
    let h = crestline::mesh::mean_edge_length(mesh);
    let t = time_step * h * h;
    let n = mesh.num_vertices();
    let mut row = vec![0u32; n + 1];
    for v in 0..n {
        row[v + 1] = row[v] + topo.vertex_edges(v as u32).len() as u32;
    }
    let nnz = row[n] as usize;
    let mut col = vec![0u32; nnz];
    let mut coef = vec![0.0; nnz];
    let mut flip = vec![0u8; nnz];
    let mut diag = mass.clone();
    for v in 0..n {
        let mut k = row[v] as usize;
        for &e in topo.vertex_edges(v as u32) {
            let [a, b] = topo.edge(e);
            let j = (a ^ b ^ v as u32) as usize;
            col[k] = j as u32;
            coef[k] = t * w[e as usize];
            let fm = c.dir_max[v].dot(&c.dir_max[j]) < 0.0;
            let fn_ = c.dir_min[v].dot(&c.dir_min[j]) < 0.0;
            flip[k] = fm as u8 | ((fn_ as u8) << 1);
            diag[v] += coef[k];
            k += 1;
        }
    }
    exp::Csr {
        row,
        col,
        coef,
        flip,
        diag,
        mass,
    }
}

pub mod eis {
    //! Prototype: Jacobi-scaled system Â = I − W, CG with Eisenstat block-SGS.
    use rayon::prelude::*;
    pub static BLOCK: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(1 << 30);
    #[inline]
    fn bsz() -> usize {
        BLOCK.load(std::sync::atomic::Ordering::Relaxed)
    }
    pub struct Sys {
        pub row: Vec<u32>,
        pub split: Vec<u32>,
        pub col: Vec<u32>,
        pub w: Vec<f64>,
        pub flip: Vec<u8>,
        pub sqd: Vec<f64>,
        pub mass: Vec<f64>,
    }
    #[inline]
    fn sg(w: f64, fl: u8, f: usize) -> f64 {
        f64::from_bits(w.to_bits() ^ ((((fl >> f) & 1) as u64) << 63))
    }
    impl Sys {
        pub fn from(csr: &super::exp::Csr) -> Sys {
            Self::from_perm(csr, None)
        }
        /// order[new] = old
        pub fn from_perm(csr: &super::exp::Csr, order: Option<&[u32]>) -> Sys {
            let n = csr.diag.len();
            let ident: Vec<u32> = (0..n as u32).collect();
            let order = order.unwrap_or(&ident);
            let mut inv = vec![0u32; n];
            for (new, &old) in order.iter().enumerate() {
                inv[old as usize] = new as u32;
            }
            let sqd0: Vec<f64> = csr.diag.iter().map(|d| d.sqrt()).collect();
            let sqd: Vec<f64> = order.iter().map(|&o| sqd0[o as usize]).collect();
            let mut col = vec![];
            let mut w = vec![];
            let mut flip = vec![];
            let mut row = vec![0u32];
            let mut split = vec![];
            for v in 0..n {
                let o = order[v] as usize;
                let (s, e) = (csr.row[o] as usize, csr.row[o + 1] as usize);
                let mut ent: Vec<(u32, f64, u8)> = (s..e)
                    .map(|k| {
                        (
                            inv[csr.col[k] as usize],
                            csr.coef[k] / (sqd0[o] * sqd0[csr.col[k] as usize]),
                            csr.flip[k],
                        )
                    })
                    .collect();
                ent.sort_by_key(|x| x.0);
                let sp = ent.iter().filter(|x| (x.0 as usize) < v).count();
                split.push((col.len() + sp) as u32);
                for (c, ww, fl) in ent {
                    col.push(c);
                    w.push(ww);
                    flip.push(fl);
                }
                row.push(col.len() as u32);
            }
            let mass = order.iter().map(|&o| csr.mass[o as usize]).collect();
            Sys {
                row,
                split,
                col,
                w,
                flip,
                sqd,
                mass,
            }
        }
        /// y = Â x (full)
        fn apply(&self, v: usize, x: &[[f64; 2]]) -> [f64; 2] {
            let (s, e) = (self.row[v] as usize, self.row[v + 1] as usize);
            let mut a = x[v];
            for k in s..e {
                let j = self.col[k] as usize;
                let (w, fl) = (self.w[k], self.flip[k]);
                a[0] -= sg(w, fl, 0) * x[j][0];
                a[1] -= sg(w, fl, 1) * x[j][1];
            }
            a
        }
        pub fn solve(&self, xs: &mut [[f64; 2]], tol: f64, eisenstat: bool) -> usize {
            let n = xs.len();
            // to scaled: ŷ = √d x ; b̂ = m x / √d
            let mut r = vec![[0.0; 2]; n];
            let yhat: Vec<[f64; 2]> = xs
                .iter()
                .zip(&self.sqd)
                .map(|(x, s)| [x[0] * s, x[1] * s])
                .collect();
            let mut bb = [0.0; 2];
            for v in 0..n {
                for f in 0..2 {
                    let b = self.mass[v] * xs[v][f] / self.sqd[v];
                    r[v][f] = b;
                    bb[f] += b * b;
                }
            }
            // r̂ = b̂ − Â ŷ
            let ay: Vec<[f64; 2]> = (0..n)
                .into_par_iter()
                .map(|v| self.apply(v, &yhat))
                .collect();
            let mut rr0 = [0.0; 2];
            for v in 0..n {
                for f in 0..2 {
                    r[v][f] -= ay[v][f];
                    rr0[f] += r[v][f] * r[v][f];
                }
            }
            drop(ay);
            let mut x = yhat;
            // warm or cold start
            for f in 0..2 {
                if rr0[f] > bb[f] {
                    for v in 0..n {
                        r[v][f] = self.mass[v] * xs[v][f] / self.sqd[v];
                        x[v][f] = 0.0;
                    }
                }
            }
            if eisenstat {
                // r̃ = (I−L)^{-1} r̂ ; x̃ = (I−Lᵀ) ŷ  (within blocks)
                self.forward(&mut r);
                let xt: Vec<[f64; 2]> = (0..n)
                    .map(|v| {
                        let mut a = x[v];
                        for k in self.split[v] as usize..self.row[v + 1] as usize {
                            let j = self.col[k] as usize;
                            if j / bsz() == v / bsz() {
                                let (w, fl) = (self.w[k], self.flip[k]);
                                a[0] -= sg(w, fl, 0) * x[j][0];
                                a[1] -= sg(w, fl, 1) * x[j][1];
                            }
                        }
                        a
                    })
                    .collect();
                x = xt;
                bb = [0.0; 2];
                let mut bt = vec![[0.0; 2]; n];
                for v in 0..n {
                    for f in 0..2 {
                        bt[v][f] = self.mass[v] * xs[v][f] / self.sqd[v];
                    }
                }
                self.forward(&mut bt);
                for v in 0..n {
                    for f in 0..2 {
                        bb[f] += bt[v][f] * bt[v][f];
                    }
                }
            }
            let mut p = r.clone();
            let mut q = vec![[0.0; 2]; n];
            let mut t = vec![[0.0; 2]; if eisenstat { n } else { 0 }];
            let mut rr = [0.0; 2];
            for v in 0..n {
                for f in 0..2 {
                    rr[f] += r[v][f] * r[v][f];
                }
            }
            let mut it = 0;
            while !(0..2).all(|f| rr[f] <= tol * tol * bb[f]) {
                it += 1;
                if eisenstat {
                    // t = (I−Lᵀ)^{-1} p within blocks (backward)
                    t.par_chunks_mut(bsz()).enumerate().for_each(|(c, ts)| {
                        for i in (0..ts.len()).rev() {
                            let v = c * bsz() + i;
                            let mut a = p[v];
                            for k in self.split[v] as usize..self.row[v + 1] as usize {
                                let j = self.col[k] as usize;
                                if j / bsz() == c {
                                    let (w, fl) = (self.w[k], self.flip[k]);
                                    a[0] += sg(w, fl, 0) * ts[j - c * bsz()][0];
                                    a[1] += sg(w, fl, 1) * ts[j - c * bsz()][1];
                                }
                            }
                            ts[i] = a;
                        }
                    });
                    // q = t + (I−L)^{-1}[p − t − E t]
                    let t = &t;
                    let parts: Vec<[f64; 2]> = q
                        .par_chunks_mut(bsz())
                        .enumerate()
                        .map(|(c, qs)| {
                            let mut pq = [0.0; 2];
                            for i in 0..qs.len() {
                                let v = c * bsz() + i;
                                let mut a = [p[v][0] - t[v][0], p[v][1] - t[v][1]];
                                for k in self.row[v] as usize..self.row[v + 1] as usize {
                                    let j = self.col[k] as usize;
                                    let (w, fl) = (self.w[k], self.flip[k]);
                                    if j / bsz() != c {
                                        a[0] -= sg(w, fl, 0) * t[j][0];
                                        a[1] -= sg(w, fl, 1) * t[j][1];
                                    } else if j < v {
                                        a[0] += sg(w, fl, 0) * qs[j - c * bsz()][0];
                                        a[1] += sg(w, fl, 1) * qs[j - c * bsz()][1];
                                    }
                                }
                                qs[i] = a; // s
                            }
                            for i in 0..qs.len() {
                                let v = c * bsz() + i;
                                for f in 0..2 {
                                    qs[i][f] += t[v][f];
                                    pq[f] += p[v][f] * qs[i][f];
                                }
                            }
                            pq
                        })
                        .collect();
                    let pq = parts
                        .iter()
                        .fold([0.0; 2], |a, b| [a[0] + b[0], a[1] + b[1]]);
                    let rz = rr;
                    let alpha = [rz[0] / pq[0], rz[1] / pq[1]];
                    let mut rn = [0.0; 2];
                    for v in 0..n {
                        for f in 0..2 {
                            x[v][f] += alpha[f] * p[v][f];
                            r[v][f] -= alpha[f] * q[v][f];
                            rn[f] += r[v][f] * r[v][f];
                        }
                    }
                    let beta = [rn[0] / rz[0], rn[1] / rz[1]];
                    rr = rn;
                    for v in 0..n {
                        for f in 0..2 {
                            p[v][f] = r[v][f] + beta[f] * p[v][f];
                        }
                    }
                } else {
                    let parts: Vec<[f64; 2]> = q
                        .par_chunks_mut(bsz())
                        .enumerate()
                        .map(|(c, qs)| {
                            let mut pq = [0.0; 2];
                            for (i, qv) in qs.iter_mut().enumerate() {
                                let v = c * bsz() + i;
                                *qv = self.apply(v, &p);
                                pq[0] += p[v][0] * qv[0];
                                pq[1] += p[v][1] * qv[1];
                            }
                            pq
                        })
                        .collect();
                    let pq = parts
                        .iter()
                        .fold([0.0; 2], |a, b| [a[0] + b[0], a[1] + b[1]]);
                    let alpha = [rr[0] / pq[0], rr[1] / pq[1]];
                    let mut rn = [0.0; 2];
                    for v in 0..n {
                        for f in 0..2 {
                            x[v][f] += alpha[f] * p[v][f];
                            r[v][f] -= alpha[f] * q[v][f];
                            rn[f] += r[v][f] * r[v][f];
                        }
                    }
                    let beta = [rn[0] / rr[0], rn[1] / rr[1]];
                    rr = rn;
                    for v in 0..n {
                        for f in 0..2 {
                            p[v][f] = r[v][f] + beta[f] * p[v][f];
                        }
                    }
                }
            }
            if eisenstat {
                // ŷ = (I−Lᵀ)^{-1} x̃ within blocks
                for c in 0..n.div_ceil(bsz()) {
                    for v in (c * bsz()..((c + 1) * bsz()).min(n)).rev() {
                        let mut a = x[v];
                        for k in self.split[v] as usize..self.row[v + 1] as usize {
                            let j = self.col[k] as usize;
                            if j / bsz() == c {
                                let (w, fl) = (self.w[k], self.flip[k]);
                                a[0] += sg(w, fl, 0) * x[j][0];
                                a[1] += sg(w, fl, 1) * x[j][1];
                            }
                        }
                        x[v] = a;
                    }
                }
            }
            for v in 0..n {
                for f in 0..2 {
                    xs[v][f] = x[v][f] / self.sqd[v];
                }
            }
            it
        }
        fn forward(&self, r: &mut [[f64; 2]]) {
            let n = r.len();
            for v in 0..n {
                let c = v / bsz();
                let mut a = r[v];
                for k in self.row[v] as usize..self.split[v] as usize {
                    let j = self.col[k] as usize;
                    if j / bsz() == c {
                        let (w, fl) = (self.w[k], self.flip[k]);
                        a[0] += sg(w, fl, 0) * r[j][0];
                        a[1] += sg(w, fl, 1) * r[j][1];
                    }
                }
                r[v] = a;
            }
        }
    }
}
