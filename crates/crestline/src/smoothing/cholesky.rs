//! Sparse Cholesky factorisation of the implicit diffusion matrix `M + t L_σ` (faer, with a
//! fill-reducing ordering) — the exact alternative to the default conjugate gradients
//! ([`super::LinearSolver::Cholesky`]).
//!
//! The symbolic analysis of the pattern (the mesh's vertex graph) is done once; each distinct
//! sign pattern σ gets its own numeric factorisation, which every step then reuses. Exact to
//! rounding, but the fill-in of the factors costs time and several hundred bytes per face.

use faer::Side;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};

use crate::error::{Error, Result};
use crate::mesh::TriMesh;

/// The symbolic (pattern-only) part of a factorisation, shared by every factor on one mesh.
#[derive(Debug, Clone)]
pub struct DiffusionPattern {
    symbolic: SymbolicLlt<u32>,
    col_ptr: Vec<u32>,
    row_idx: Vec<u32>,
    /// For each stored entry: `None` for the diagonal, `Some(edge)` for an off-diagonal one.
    entry_edge: Vec<Option<u32>>,
}

impl DiffusionPattern {
    /// Analyses the sparsity pattern of the mesh's vertex graph (lower triangle).
    ///
    /// # Errors
    /// [`Error::Solver`] when the symbolic factorisation fails (out of memory).
    pub fn new(mesh: &TriMesh) -> Result<Self> {
        let topo = mesh.topology();
        let n = mesh.num_vertices();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(n + topo.num_edges());
        let mut entry_edge = Vec::with_capacity(n + topo.num_edges());
        let mut column: Vec<(u32, u32)> = Vec::new();
        col_ptr.push(0u32);
        for j in 0..n as u32 {
            column.clear();
            column.extend(topo.vertex_edges(j).iter().filter_map(|&e| {
                let [a, b] = topo.edge(e);
                let other = if a == j { b } else { a };
                (other > j).then_some((other, e))
            }));
            column.sort_unstable();
            row_idx.push(j);
            entry_edge.push(None);
            for &(i, e) in &column {
                row_idx.push(i);
                entry_edge.push(Some(e));
            }
            col_ptr.push(row_idx.len() as u32);
        }
        let structure =
            SymbolicSparseColMat::new_checked(n, n, col_ptr.clone(), None, row_idx.clone());
        let symbolic = SymbolicLlt::try_new(structure.as_ref(), Side::Lower)
            .map_err(|e| Error::Solver(format!("symbolic Cholesky failed: {e:?}")))?;
        Ok(DiffusionPattern {
            symbolic,
            col_ptr,
            row_idx,
            entry_edge,
        })
    }
}

/// Factorised `M + t L_σ` for one or more fields (one factor per distinct sign pattern).
#[derive(Debug)]
pub struct CholeskySystem {
    pattern: DiffusionPattern,
    /// Per field: the edges where σ = −1 (`None`: none).
    flips: Vec<Option<Vec<bool>>>,
    /// Per field: index into `factors`.
    field_factor: Vec<usize>,
    factors: Vec<Llt<u32, f64>>,
    mass: Vec<f64>,
}

impl CholeskySystem {
    /// Analyses the pattern and factorises one matrix per distinct sign pattern.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for mismatched lengths; [`Error::Solver`] when a matrix is not
    /// numerically positive definite.
    pub fn new(
        mesh: &TriMesh,
        weights: &[f64],
        mass: Vec<f64>,
        time: f64,
        flips: &[Option<&[bool]>],
    ) -> Result<Self> {
        let m = mesh.topology().num_edges();
        if weights.len() != m
            || mass.len() != mesh.num_vertices()
            || flips.iter().flatten().any(|f| f.len() != m)
        {
            return Err(Error::InvalidInput(
                "diffusion system: weights, masses or signs do not match the mesh".into(),
            ));
        }
        let mut distinct: Vec<Option<Vec<bool>>> = Vec::new();
        let mut field_factor = Vec::with_capacity(flips.len());
        for f in flips {
            let f = f.map(<[bool]>::to_vec);
            let k = match distinct.iter().position(|d| *d == f) {
                Some(k) => k,
                None => {
                    distinct.push(f);
                    distinct.len() - 1
                }
            };
            field_factor.push(k);
        }
        let mut system = CholeskySystem {
            pattern: DiffusionPattern::new(mesh)?,
            flips: distinct,
            field_factor,
            factors: Vec::new(),
            mass,
        };
        system.factorise(weights, time)?;
        Ok(system)
    }

    /// Refactorises with new weights and mass (same mesh and signs), reusing the symbolic
    /// analysis.
    ///
    /// # Errors
    /// As [`CholeskySystem::new`].
    pub fn update(&mut self, weights: &[f64], mass: Vec<f64>, time: f64) -> Result<()> {
        if mass.len() != self.mass.len() {
            return Err(Error::InvalidInput(
                "diffusion system: masses do not match the mesh".into(),
            ));
        }
        self.mass = mass;
        self.factorise(weights, time)
    }

    /// Number of fields.
    pub fn fields(&self) -> usize {
        self.field_factor.len()
    }

    fn factorise(&mut self, weights: &[f64], time: f64) -> Result<()> {
        let pattern = &self.pattern;
        if weights.len() != pattern.entry_edge.iter().flatten().count() {
            return Err(Error::InvalidInput(
                "diffusion system: weights do not match the mesh".into(),
            ));
        }
        let n = self.mass.len();
        let mut factors = Vec::with_capacity(self.flips.len());
        for flips in &self.flips {
            let mut values = vec![0.0; pattern.row_idx.len()];
            let mut diagonal = self.mass.clone();
            for j in 0..n {
                let range = pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize;
                for k in range {
                    if let Some(e) = pattern.entry_edge[k] {
                        let w = time * weights[e as usize];
                        let flipped = flips.as_ref().is_some_and(|f| f[e as usize]);
                        values[k] = if flipped { w } else { -w };
                        diagonal[j] += w;
                        diagonal[pattern.row_idx[k] as usize] += w;
                    }
                }
            }
            for j in 0..n {
                // The first entry of every column is its diagonal.
                values[pattern.col_ptr[j] as usize] = diagonal[j];
            }
            let structure = SymbolicSparseColMat::new_checked(
                n,
                n,
                pattern.col_ptr.clone(),
                None,
                pattern.row_idx.clone(),
            );
            let matrix = SparseColMat::new(structure, values);
            let llt =
                Llt::try_new_with_symbolic(pattern.symbolic.clone(), matrix.as_ref(), Side::Lower)
                    .map_err(|e| Error::Solver(format!("Cholesky factorisation failed: {e:?}")))?;
            factors.push(llt);
        }
        self.factors = factors;
        Ok(())
    }

    /// One implicit step on every field, in place.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a wrong number or length of fields.
    pub fn step(&self, fields: &mut [&mut [f64]]) -> Result<()> {
        let n = self.mass.len();
        if fields.len() != self.fields() || fields.iter().any(|f| f.len() != n) {
            return Err(Error::InvalidInput(format!(
                "diffusion step: need {} fields of {n} values",
                self.fields()
            )));
        }
        if n == 0 {
            return Ok(());
        }
        for (k, llt) in self.factors.iter().enumerate() {
            let members: Vec<usize> = (0..fields.len())
                .filter(|&f| self.field_factor[f] == k)
                .collect();
            let mut rhs = faer::Mat::<f64>::from_fn(n, members.len(), |i, j| {
                self.mass[i] * fields[members[j]][i]
            });
            llt.solve_in_place(rhs.as_mut());
            for (j, &f) in members.iter().enumerate() {
                for (i, x) in fields[f].iter_mut().enumerate() {
                    *x = rhs[(i, j)];
                }
            }
        }
        Ok(())
    }
}
