use super::*;
use crate::mesh::TriMesh;
use crate::shapes;
use crate::smoothing::{cotan_weights, lumped_mass};

fn system<'m>(
    mesh: &'m TriMesh,
    time: f64,
    flips: &[Option<&[bool]>],
    options: ConjugateGradientOptions,
) -> ConnectionSystem<'m> {
    let w = cotan_weights(mesh, mesh.positions());
    let m = lumped_mass(mesh, mesh.positions());
    ConnectionSystem::new(mesh.topology(), w, m, time, flips, options).unwrap()
}

/// `(M + t L_σ) u` at every vertex, written out from the definition, with the weights
/// in the single precision the system stores.
fn apply(mesh: &TriMesh, time: f64, flips: Option<&[bool]>, u: &[f64]) -> Vec<f64> {
    let mut w = cotan_weights(mesh, mesh.positions());
    round_weights(&mut w);
    let m = lumped_mass(mesh, mesh.positions());
    let topo = mesh.topology();
    (0..mesh.num_vertices())
        .map(|v| {
            let mut out = m[v] * u[v];
            for &e in topo.vertex_edges(v as u32) {
                let [a, b] = topo.edge(e);
                let q = if a as usize == v { b } else { a } as usize;
                let sigma = if flips.is_some_and(|f| f[e as usize]) {
                    -1.0
                } else {
                    1.0
                };
                out += time * w[e as usize] * (u[v] - sigma * u[q]);
            }
            out
        })
        .collect()
}

#[test]
fn solution_satisfies_the_system() {
    let mesh = shapes::torus(3.0, 1.0, 30, 12);
    let flips: Vec<bool> = (0..mesh.topology().num_edges())
        .map(|e| e % 3 == 0)
        .collect();
    let mass = lumped_mass(&mesh, mesh.positions());
    let u0: Vec<f64> = mesh.positions().iter().map(|p| p.x.sin() + p.z).collect();
    let rhs: Vec<f64> = u0.iter().zip(&mass).map(|(u, m)| u * m).collect();
    let scale = rhs.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    for time in [0.01, 0.3] {
        let options = ConjugateGradientOptions::DEFAULT.with_tolerance(1e-12);
        let sys = system(&mesh, time, &[None, Some(&flips)], options);
        let (mut a, mut b) = (u0.clone(), u0.clone());
        let iterations = sys.step(&mut [&mut a, &mut b]).unwrap();
        assert!(iterations > 0);
        for (u, f) in [(&a, None), (&b, Some(flips.as_slice()))] {
            let lhs = apply(&mesh, time, f, u);
            let worst = lhs
                .iter()
                .zip(&rhs)
                .fold(0.0f64, |s, (l, r)| s.max((l - r).abs()));
            assert!(worst < 1e-9 * scale, "t = {time}: residual {worst:e}");
        }
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let mesh = shapes::torus(3.0, 1.0, 60, 24);
    let flips: Vec<bool> = (0..mesh.topology().num_edges())
        .map(|e| e % 7 == 0)
        .collect();
    let u0: Vec<f64> = mesh
        .positions()
        .iter()
        .map(|p| (3.0 * p.x).sin() * p.z)
        .collect();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let options = ConjugateGradientOptions::DEFAULT;
            let sys = system(&mesh, 0.05, &[Some(&flips), None], options);
            let (mut a, mut b) = (u0.clone(), u0.clone());
            sys.step(&mut [&mut a, &mut b]).unwrap();
            (a, b)
        })
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn a_cold_field_starts_at_zero_even_when_no_round_runs() {
    // A rough field under a long step is further from the solution than zero, so it starts
    // at zero; with a tolerance that zero already meets, that is the result.
    let m = shapes::torus(3.0, 1.0, 24, 12);
    let rough: Vec<f64> = (0..m.num_vertices())
        .map(|v| if v % 2 == 0 { 1.0 } else { -1.0 })
        .collect();
    let h = crate::mesh::mean_edge_length(&m);
    for tolerance in [2.0, 1e-8] {
        let options = ConjugateGradientOptions::DEFAULT.with_tolerance(tolerance);
        let s = system(&m, 50.0 * h * h, &[None], options);
        let mut x = rough.clone();
        let iterations = s.step(&mut [&mut x]).unwrap();
        if tolerance > 1.0 {
            assert_eq!(iterations, 0);
            assert!(x.iter().all(|&v| v == 0.0));
        } else {
            assert!(iterations > 0);
            let exact = apply(&m, 50.0 * h * h, None, &x);
            let mass = lumped_mass(&m, m.positions());
            for v in 0..m.num_vertices() {
                let b = mass[v] * rough[v];
                assert!((exact[v] - b).abs() < 1e-6 * mass[v], "{v}");
            }
        }
    }
}

#[test]
fn iteration_limit_is_an_error() {
    let mesh = shapes::torus(3.0, 1.0, 30, 12);
    let options = ConjugateGradientOptions::DEFAULT
        .with_tolerance(1e-14)
        .with_max_iterations(2);
    let sys = system(&mesh, 0.3, &[None], options);
    let mut u: Vec<f64> = mesh.positions().iter().map(|p| p.x * p.y).collect();
    let err = sys.step(&mut [&mut u]).unwrap_err();
    assert!(matches!(err, Error::Solver(_)), "{err}");
    assert!(err.to_string().contains("did not converge"), "{err}");
}

#[test]
fn non_finite_values_are_an_error_not_a_panic() {
    let mesh = shapes::torus(3.0, 1.0, 10, 6);
    let options = ConjugateGradientOptions::DEFAULT;
    let sys = system(&mesh, 0.3, &[None], options);
    for bad in [f64::NAN, f64::INFINITY] {
        let mut u = vec![1.0; mesh.num_vertices()];
        u[3] = bad;
        let result = sys.step(&mut [&mut u]);
        assert!(matches!(result, Err(Error::Solver(_))), "{result:?}");
    }
}

#[test]
fn rejects_bad_input() {
    let mesh = shapes::torus(3.0, 1.0, 10, 6);
    let w = cotan_weights(&mesh, mesh.positions());
    let m = lumped_mass(&mesh, mesh.positions());
    let topo = mesh.topology();
    let ok = ConjugateGradientOptions::DEFAULT;
    let new = |w: &[f64], m: &[f64], fields: &[Option<&[bool]>], o| {
        ConnectionSystem::new(topo, w.to_vec(), m.to_vec(), 1.0, fields, o)
    };
    assert!(new(&w, &m, &[None], ok.with_tolerance(0.0)).is_err());
    assert!(new(&w, &m, &[None], ok.with_max_iterations(0)).is_err());
    assert!(new(&w, &m, &[], ok).is_err());
    assert!(new(&w, &m, &[None; MAX_FIELDS + 1], ok).is_err());
    assert!(new(&w[1..], &m, &[None], ok).is_err());
    assert!(new(&w, &m, &[Some(&[true; 3])], ok).is_err());
    let mut negative = w.clone();
    negative[0] = -1.0;
    assert!(new(&negative, &m, &[None], ok).is_err());
    let mut zero_mass = m.clone();
    zero_mass[0] = 0.0;
    assert!(new(&w, &zero_mass, &[None], ok).is_err());
    let sys = new(&w, &m, &[None, None], ok).unwrap();
    let mut u = vec![0.0; mesh.num_vertices()];
    assert!(sys.step(&mut [&mut u]).is_err());
    assert!(
        sys.step(&mut [&mut u[1..].to_vec(), &mut u.clone()])
            .is_err()
    );
}

/// The relative residual `‖b − A u‖ / ‖b‖` of one step from `u0` to `u` (σ = +1), in the
/// norm of the solver's stopping test (`D^{-½}`, D the diagonal of A).
fn scaled_residual(mesh: &TriMesh, time: f64, u0: &[f64], u: &[f64]) -> f64 {
    let mut w = cotan_weights(mesh, mesh.positions());
    round_weights(&mut w);
    let mass = lumped_mass(mesh, mesh.positions());
    let topo = mesh.topology();
    let lhs = apply(mesh, time, None, u);
    let (mut r2, mut b2) = (0.0, 0.0);
    for v in 0..mesh.num_vertices() {
        let row: f64 = topo
            .vertex_edges(v as u32)
            .iter()
            .map(|&e| w[e as usize])
            .sum();
        let diagonal = mass[v] + time * row;
        let b = mass[v] * u0[v];
        r2 += (b - lhs[v]).powi(2) / diagonal;
        b2 += b * b / diagonal;
    }
    (r2 / b2).sqrt()
}

#[test]
fn steps_within_a_looser_tolerance_stop_there_and_never_below_the_solvers() {
    let mesh = shapes::torus(3.0, 1.0, 40, 16);
    let u0: Vec<f64> = mesh
        .positions()
        .iter()
        .enumerate()
        .map(|(i, p)| p.x.sin() + ((i * 7919) % 13) as f64 / 13.0)
        .collect();
    let time = 0.5;
    let sys = system(&mesh, time, &[None], ConjugateGradientOptions::DEFAULT);
    let mut tight = u0.clone();
    let tight_iterations = sys.step(&mut [&mut tight]).unwrap();
    let mut loose = u0.clone();
    let loose_iterations = sys.steps_within(&mut [&mut loose], 1, 1e-2).unwrap();
    assert!(
        loose_iterations < tight_iterations,
        "{loose_iterations} against {tight_iterations}"
    );
    let (tight_residual, loose_residual) = (
        scaled_residual(&mesh, time, &u0, &tight),
        scaled_residual(&mesh, time, &u0, &loose),
    );
    assert!(tight_residual <= 1e-5, "{tight_residual}");
    assert!(
        loose_residual <= 1e-2 && loose_residual > 1e-5,
        "{loose_residual}"
    );
    // A tolerance tighter than the solver's is not taken: the solver's own holds.
    let mut same = u0.clone();
    let same_iterations = sys.steps_within(&mut [&mut same], 1, 1e-9).unwrap();
    assert_eq!(same_iterations, tight_iterations);
    assert_eq!(same, tight);
}

#[test]
fn the_double_precision_fallback_solves_the_same_system() {
    // The step that mixed precision cannot finish is taken again this way (module docs):
    // from the same start, with the same signs, it must meet the same stopping test.
    let mesh = shapes::torus(3.0, 1.0, 30, 12);
    let flips: Vec<bool> = (0..mesh.topology().num_edges())
        .map(|e| e % 5 == 0)
        .collect();
    let time = 0.7;
    let sys = system(
        &mesh,
        time,
        &[None, Some(&flips)],
        ConjugateGradientOptions::DEFAULT,
    );
    let u0: Vec<f64> = mesh.positions().iter().map(|p| p.x * p.y + p.z).collect();
    let (mut a, mut b) = (u0.clone(), u0.clone());
    let iterations = sys
        .double_precision_step(&mut [&mut a, &mut b], None, 1e-10)
        .unwrap();
    assert!(iterations > 0);
    let check = |u: &[f64], flips: Option<&[bool]>| {
        let lhs = apply(&mesh, time, flips, u);
        let m = lumped_mass(&mesh, mesh.positions());
        let (mut r2, mut b2) = (0.0f64, 0.0f64);
        for v in 0..u.len() {
            r2 += (m[v] * u0[v] - lhs[v]).powi(2);
            b2 += (m[v] * u0[v]).powi(2);
        }
        (r2 / b2).sqrt()
    };
    assert!(check(&a, None) < 1e-8, "{}", check(&a, None));
    assert!(
        check(&b, Some(&flips)) < 1e-8,
        "{}",
        check(&b, Some(&flips))
    );
    // And the mixed-precision step agrees with it to its tolerance.
    let (mut c, mut d) = (u0.clone(), u0.clone());
    sys.step(&mut [&mut c, &mut d]).unwrap();
    let worst = a
        .iter()
        .zip(&c)
        .chain(b.iter().zip(&d))
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let scale = u0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(worst < 1e-4 * scale, "{worst} against {scale}");
}
