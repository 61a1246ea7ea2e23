//! The linear system of one implicit diffusion step, `(M + t L_σ) u' = M u`, as a faer sparse
//! matrix, and the plain Jacobi-preconditioned conjugate gradients that solve it.
//!
//! This is the system of HPW 2005 sec. 5.1 (the implicit smoothing of the extremalities,
//! after Desbrun, Meyer, Schröder and Barr 1999, eq. 9): `M` the lumped mass,
//! `(L_σ u)(p) = Σ_q w_pq (u(p) − σ_pq u(q))` the connection Laplacian with a sign
//! `σ_pq = ±1` per edge and field. `A = M + t L_σ` is symmetric positive definite for
//! non-negative weights, so conjugate gradients (Hestenes and Stiefel 1952; Saad, *Iterative
//! Methods for Sparse Linear Systems*, 2nd ed., Alg. 9.1) with the diagonal as
//! preconditioner converge. This is the reference solver
//! ([`super::LinearSolver::PlainConjugateGradient`]): short, in double precision, one field
//! at a time. The default ([`super::mixed_precision`]) solves the same system faster.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rayon::prelude::*;

use super::ConjugateGradientOptions;
use crate::error::{Error, Result};
use crate::mesh::Topology;

/// `A = M + t L_σ` for each field, and `M`, ready for [`DiffusionSystem::step`].
#[derive(Debug, Clone)]
pub struct DiffusionSystem {
    /// Per field: the full symmetric matrix (both triangles, rows sorted in every column).
    matrices: Vec<SparseColMat<u32, f64>>,
    /// Per field: the edges where `σ = −1` (`None`: none), kept for [`DiffusionSystem::update`].
    flips: Vec<Option<Vec<bool>>>,
    mass: Vec<f64>,
    options: ConjugateGradientOptions,
}

impl DiffusionSystem {
    /// Assembles `A` per field from per-edge weights `w_pq`, the lumped mass, the time step
    /// and, per field, the edges where `σ = −1` (`None`: `σ = +1` everywhere).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for invalid options or signs, or as [`check_system`].
    pub fn assemble(
        topology: &Topology,
        weights: &[f64],
        mass: Vec<f64>,
        time: f64,
        flips: &[Option<&[bool]>],
        options: ConjugateGradientOptions,
    ) -> Result<Self> {
        options.validate()?;
        let m = topology.num_edges();
        if flips.iter().flatten().any(|f| f.len() != m) {
            return Err(Error::InvalidInput(format!(
                "edge signs for other than {m} edges"
            )));
        }
        let mut system = DiffusionSystem {
            matrices: Vec::new(),
            flips: flips.iter().map(|f| f.map(<[bool]>::to_vec)).collect(),
            mass: Vec::new(),
            options,
        };
        system.update(topology, weights, mass, time)?;
        Ok(system)
    }

    /// Assembles the matrices again with new weights and mass (same mesh and signs).
    ///
    /// # Errors
    /// As [`check_system`].
    pub fn update(
        &mut self,
        topology: &Topology,
        weights: &[f64],
        mass: Vec<f64>,
        time: f64,
    ) -> Result<()> {
        check_system(topology, weights, &mass, time)?;
        self.matrices = self
            .flips
            .iter()
            .map(|f| assemble_matrix(topology, weights, &mass, time, f.as_deref()))
            .collect();
        self.mass = mass;
        Ok(())
    }

    /// Number of fields.
    pub fn fields(&self) -> usize {
        self.matrices.len()
    }

    /// `A` of field `f`.
    pub fn matrix(&self, f: usize) -> &SparseColMat<u32, f64> {
        &self.matrices[f]
    }

    /// One implicit step on every field, in place: solves `A x = M u` from `x = u`. Returns
    /// the iterations of the slowest field.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a wrong number or length of fields; [`Error::Solver`] when
    /// the tolerance is not reached within the iteration limit.
    pub fn step(&self, fields: &mut [&mut [f64]]) -> Result<usize> {
        self.step_within(fields, 0.0)
    }

    /// [`DiffusionSystem::step`] solved to the relative residual `tolerance` where that is
    /// looser than [`ConjugateGradientOptions::tolerance`].
    ///
    /// # Errors
    /// As [`DiffusionSystem::step`].
    pub fn step_within(&self, fields: &mut [&mut [f64]], tolerance: f64) -> Result<usize> {
        let options = ConjugateGradientOptions {
            tolerance: tolerance.max(self.options.tolerance),
            ..self.options
        };
        let n = self.mass.len();
        if fields.len() != self.fields() || fields.iter().any(|f| f.len() != n) {
            return Err(Error::InvalidInput(format!(
                "diffusion step: need {} fields of {n} values",
                self.fields()
            )));
        }
        let mut worst = 0;
        for (a, u) in self.matrices.iter().zip(fields.iter_mut()) {
            let b: Vec<f64> = self.mass.iter().zip(u.iter()).map(|(m, x)| m * x).collect();
            worst = worst.max(jacobi_cg(a, &b, u, &options)?);
        }
        Ok(worst)
    }
}

/// Checks that weights, masses and time make a system `M + t L_σ` every solver can solve:
/// one weight per edge, non-negative and finite in single precision, one positive mass per
/// vertex, and a non-negative time.
///
/// # Errors
/// [`Error::InvalidInput`] naming the first problem.
pub fn check_system(topology: &Topology, weights: &[f64], mass: &[f64], time: f64) -> Result<()> {
    let (n, m) = (topology.num_vertices(), topology.num_edges());
    if weights.len() != m || mass.len() != n {
        return Err(Error::InvalidInput(format!(
            "diffusion system: {} weights and {} masses for {m} edges and {n} vertices",
            weights.len(),
            mass.len()
        )));
    }
    if !(time.is_finite() && time >= 0.0) {
        return Err(Error::InvalidInput(format!(
            "diffusion time must be a non-negative number, got {time}"
        )));
    }
    if weights
        .par_iter()
        .any(|&w| !((w as f32).is_finite() && w >= 0.0))
    {
        return Err(Error::InvalidInput(
            "diffusion weights must be non-negative numbers (below 3.4e38)".into(),
        ));
    }
    if mass.par_iter().any(|m| !(m.is_finite() && *m > 0.0)) {
        return Err(Error::InvalidInput(
            "diffusion masses must be positive numbers".into(),
        ));
    }
    Ok(())
}

/// `A = M + t L_σ` with `σ = −1` on the edges `flips` marks, in compressed columns.
fn assemble_matrix(
    topology: &Topology,
    weights: &[f64],
    mass: &[f64],
    time: f64,
    flips: Option<&[bool]>,
) -> SparseColMat<u32, f64> {
    let n = mass.len();
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    col_ptr.push(0u32);
    for v in 0..n as u32 {
        let mut diagonal = mass[v as usize];
        let mut diagonal_at = None;
        // The edges of a vertex are ordered by neighbour, so the column's rows are sorted.
        for &e in topology.vertex_edges(v) {
            let [a, b] = topology.edge(e);
            let q = a ^ b ^ v;
            if q > v && diagonal_at.is_none() {
                diagonal_at = Some(values.len());
                row_idx.push(v);
                values.push(0.0);
            }
            let w = time * weights[e as usize];
            let sign = if flips.is_some_and(|f| f[e as usize]) {
                1.0
            } else {
                -1.0
            };
            row_idx.push(q);
            values.push(sign * w);
            diagonal += w;
        }
        let at = *diagonal_at.get_or_insert_with(|| {
            row_idx.push(v);
            values.push(0.0);
            values.len() - 1
        });
        values[at] = diagonal;
        col_ptr.push(row_idx.len() as u32);
    }
    let structure = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    SparseColMat::new(structure, values)
}

/// `y = A x` for a symmetric `A` (column `j` of `A` is its row `j`).
fn multiply(a: &SparseColMat<u32, f64>, x: &[f64], y: &mut [f64]) {
    let (col_ptr, row_idx, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    y.par_iter_mut().enumerate().for_each(|(j, y)| {
        let range = col_ptr[j] as usize..col_ptr[j + 1] as usize;
        *y = row_idx[range.clone()]
            .iter()
            .zip(&val[range])
            .map(|(&i, &v)| v * x[i as usize])
            .sum();
    });
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves `A x = b` by conjugate gradients preconditioned by the diagonal of `A`, from the
/// given `x`; stops when `‖b − A x‖₂ ≤ tolerance · ‖b‖₂`. Returns the iterations.
///
/// # Errors
/// [`Error::Solver`] when the tolerance is not reached within the iteration limit or the
/// iteration breaks down.
pub fn jacobi_cg(
    a: &SparseColMat<u32, f64>,
    b: &[f64],
    x: &mut [f64],
    options: &ConjugateGradientOptions,
) -> Result<usize> {
    let n = b.len();
    let (col_ptr, row_idx, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let inverse_diagonal: Vec<f64> = (0..n)
        .map(|j| {
            let range = col_ptr[j] as usize..col_ptr[j + 1] as usize;
            let k = range.start + row_idx[range].partition_point(|&i| (i as usize) < j);
            1.0 / val[k]
        })
        .collect();
    let goal = options.tolerance * dot(b, b).sqrt();
    let mut r = vec![0.0; n];
    multiply(a, x, &mut r);
    r.iter_mut().zip(b).for_each(|(r, b)| *r = b - *r);
    let mut z: Vec<f64> = r
        .iter()
        .zip(&inverse_diagonal)
        .map(|(r, d)| r * d)
        .collect();
    let mut p = z.clone();
    let mut ap = vec![0.0; n];
    let mut rz = dot(&r, &z);
    for iteration in 0..=options.max_iterations {
        if dot(&r, &r).sqrt() <= goal {
            return Ok(iteration);
        }
        multiply(a, &p, &mut ap);
        let alpha = rz / dot(&p, &ap);
        if !alpha.is_finite() {
            return Err(Error::Solver("conjugate gradients broke down".into()));
        }
        x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.iter_mut().zip(&ap).for_each(|(r, q)| *r -= alpha * q);
        z.iter_mut()
            .zip(r.iter().zip(&inverse_diagonal))
            .for_each(|(z, (r, d))| *z = r * d);
        let next = dot(&r, &z);
        let beta = next / rz;
        rz = next;
        p.iter_mut().zip(&z).for_each(|(p, z)| *p = z + beta * *p);
    }
    Err(Error::Solver(format!(
        "conjugate gradients did not reach the tolerance {} in {} iterations",
        options.tolerance, options.max_iterations
    )))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::smoothing::{
        ConjugateGradientOptions, DiffusionOperator, LinearSolver, cotan_weights_and_mass,
    };

    #[test]
    fn fast_solver_agrees_with_the_plain_one_on_a_real_mesh() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes/fandisk.obj");
        let mesh = crate::io::read_mesh(&path, None).expect("the shared meshes (fandisk.obj)");
        let h = crate::mesh::mean_edge_length(&mesh);
        // One plain field and one with signs, as HPW's smoothing of both families.
        let flips: Vec<bool> = mesh
            .topology()
            .edges()
            .iter()
            .map(|&[a, b]| (a + 3 * b) % 7 == 0)
            .collect();
        let start: Vec<f64> = mesh
            .positions()
            .iter()
            .map(|p| (p.x * 9.0).sin() * p.y + p.z * p.z)
            .collect();
        let run = |solver: LinearSolver| {
            let (w, mass) = cotan_weights_and_mass(&mesh, mesh.positions());
            let fields = [None, Some(flips.as_slice())];
            let op = DiffusionOperator::new(&mesh, w, mass, h * h, &fields, solver).unwrap();
            let (mut a, mut b) = (start.clone(), start.clone());
            op.steps(&mut [&mut a, &mut b], 3).unwrap();
            (a, b)
        };
        let fast = run(LinearSolver::DEFAULT);
        let tight = ConjugateGradientOptions::DEFAULT.with_tolerance(1e-12);
        let plain = run(LinearSolver::PlainConjugateGradient(tight));
        let scale = start.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        for (x, y) in [(&fast.0, &plain.0), (&fast.1, &plain.1)] {
            let worst = x
                .iter()
                .zip(y)
                .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
            // The default tolerance is 1e-5 of the right-hand side's norm.
            assert!(worst < 1e-4 * scale, "max difference {worst:e}");
        }
        assert!(
            fast.0
                .iter()
                .zip(&fast.1)
                .any(|(a, b)| (a - b).abs() > 1e-3)
        );
    }
}
