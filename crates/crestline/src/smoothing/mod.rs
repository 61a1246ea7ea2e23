//! Implicit diffusion on meshes: the machinery behind steps 1 and 3 of HPW 2005 (Table 1).
//!
//! - [`extremality`]: sign-aware smoothing of the extremality coefficients (HPW sec. 5.1),
//!   homogeneous or with per-vertex diffusion factors (inhomogeneous smoothing, HPW sec. 6).
//! - [`surface`]: optional pre-smoothing of the surface by implicit fairing (Desbrun, Meyer,
//!   Schröder, Barr 1999).
//!
//! Both solve `(M + t L) u_new = M u_old` per implicit time step, with `M` the lumped
//! (barycentric) mass matrix and `L` a positive semi-definite cotan Laplacian. The matrix is
//! the same in every step, so it is factorised once (faer's sparse Cholesky with a
//! fill-reducing ordering) and the factorisation is reused; [`DiffusionOperator`] is that
//! stateful object.
//!
//! Cotan weights "stay sane": the weight of an edge is `½ Σ cot(opposite angle)` over its faces,
//! each cotangent capped at ±[`MAX_COT`] (slivers), and a negative total (an edge opposite
//! two obtuse angles) is clamped to zero. With non-negative weights the operator stays
//! positive semi-definite, so every implicit step is unconditionally stable.

pub mod extremality;
pub mod surface;

use faer::Side;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::mesh::{TriMesh, Vec3};

/// Cap on the magnitude of one cotangent (an angle of about 0.06°).
pub const MAX_COT: f64 = 1e3;

/// Per-edge cotan weights `w_e = ½ Σ_faces cot(angle opposite e)`, clamped to `>= 0`,
/// indexed like [`crate::mesh::Topology::edges`].
pub fn cotan_weights(mesh: &TriMesh, positions: &[Vec3]) -> Vec<f64> {
    let topo = mesh.topology();
    let faces = mesh.faces();
    (0..topo.num_edges() as u32)
        .into_par_iter()
        .map(|e| {
            let [a, b] = topo.edge(e);
            let w: f64 = topo
                .edge_faces(e)
                .iter()
                .map(|&f| {
                    let t = faces[f as usize];
                    let c = t.iter().copied().find(|&x| x != a && x != b).unwrap_or(a);
                    let pc = positions[c as usize];
                    let (u, v) = (positions[a as usize] - pc, positions[b as usize] - pc);
                    let sin = u.cross(&v).norm();
                    let cos = u.dot(&v);
                    let cot = if sin > 0.0 {
                        cos / sin
                    } else {
                        MAX_COT.copysign(cos)
                    };
                    0.5 * cot.clamp(-MAX_COT, MAX_COT)
                })
                .sum();
            w.max(0.0)
        })
        .collect()
}

/// Lumped mass: a third of the area of each vertex's star. Vertices without faces get the
/// mean mass so that the system stays definite (their values are simply kept).
pub fn lumped_mass(mesh: &TriMesh, positions: &[Vec3]) -> Vec<f64> {
    let faces = mesh.faces();
    let topo = mesh.topology();
    let area = |f: u32| {
        let [a, b, c] = faces[f as usize].map(|i| positions[i as usize]);
        0.5 * (b - a).cross(&(c - a)).norm()
    };
    let mut mass: Vec<f64> = (0..mesh.num_vertices() as u32)
        .into_par_iter()
        .map(|v| topo.vertex_faces(v).iter().map(|&f| area(f)).sum::<f64>() / 3.0)
        .collect();
    let positive: Vec<f64> = mass.iter().copied().filter(|&m| m > 0.0).collect();
    let fill = if positive.is_empty() {
        1.0
    } else {
        positive.iter().sum::<f64>() / positive.len() as f64
    };
    for m in &mut mass {
        if *m <= 0.0 {
            *m = fill;
        }
    }
    mass
}

/// A factorised implicit diffusion step `(M + t L_σ) u' = M u`.
///
/// `L_σ` is the connection Laplacian `(L_σ u)(p) = Σ_q w_pq (u(p) − σ_pq u(q))` with
/// `σ_pq ∈ {−1, +1}` per edge (all `+1` gives the ordinary Laplacian). It is positive
/// semi-definite for non-negative weights, so `M + t L_σ` is positive definite.
#[derive(Debug)]
pub struct DiffusionOperator {
    llt: Llt<u32, f64>,
    mass: Vec<f64>,
}

/// The symbolic (pattern-only) part of a factorisation, shareable between operators on the
/// same mesh (for example the two extremality families).
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

impl DiffusionOperator {
    /// Factorises `M + t L_σ`.
    ///
    /// `weights` are per-edge non-negative diffusion weights (cotan weights, possibly scaled
    /// by local factors), `signs` per-edge `σ` (`None` means all `+1`), `mass` the lumped mass
    /// and `time` the step `t` (in units of area).
    ///
    /// # Errors
    /// [`Error::Solver`] when the matrix is not numerically positive definite.
    pub fn new(
        pattern: &DiffusionPattern,
        weights: &[f64],
        signs: Option<&[f64]>,
        mass: &[f64],
        time: f64,
    ) -> Result<Self> {
        let n = mass.len();
        let mut values = vec![0.0; pattern.row_idx.len()];
        let mut diagonal = mass.to_vec();
        for j in 0..n {
            let range = pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize;
            for k in range {
                if let Some(e) = pattern.entry_edge[k] {
                    let w = time * weights[e as usize];
                    values[k] = -w * signs.map_or(1.0, |s| s[e as usize]);
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
        Ok(DiffusionOperator {
            llt,
            mass: mass.to_vec(),
        })
    }

    /// One implicit step on `k` fields stored column after column in `values`
    /// (`values.len() == k · n`), in place.
    pub fn step(&self, values: &mut [f64]) {
        let n = self.mass.len();
        if n == 0 {
            return;
        }
        let k = values.len() / n;
        let mut rhs = faer::Mat::<f64>::from_fn(n, k, |i, j| self.mass[i] * values[j * n + i]);
        self.llt.solve_in_place(rhs.as_mut());
        for j in 0..k {
            for i in 0..n {
                values[j * n + i] = rhs[(i, j)];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    #[test]
    fn cotan_weights_of_a_right_isoceles_pair() {
        // Unit square split along the diagonal 0-2: both angles opposite the diagonal are 90°,
        // angles opposite the sides are 45° (cot = 1) → side weights ½, diagonal 0.
        let m = TriMesh::from_arrays(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let w = cotan_weights(&m, m.positions());
        for (e, &[a, b]) in m.topology().edges().iter().enumerate() {
            let expected = if (a, b) == (0, 2) { 0.0 } else { 0.5 };
            assert!((w[e] - expected).abs() < 1e-12, "edge {a}-{b}: {}", w[e]);
        }
    }

    #[test]
    fn laplacian_annihilates_constants_and_keeps_the_mean() {
        // (M + tL) u' = M u preserves Σ M u for σ = +1, and constants are fixed points.
        let m = shapes::torus(3.0, 1.0, 20, 10);
        let pattern = DiffusionPattern::new(&m).unwrap();
        let w = cotan_weights(&m, m.positions());
        let mass = lumped_mass(&m, m.positions());
        let op = DiffusionOperator::new(&pattern, &w, None, &mass, 0.5).unwrap();
        let mut c = vec![2.5; m.num_vertices()];
        op.step(&mut c);
        assert!(c.iter().all(|x| (x - 2.5).abs() < 1e-10));
        let mut u: Vec<f64> = m.positions().iter().map(|p| p.x * p.z + p.y).collect();
        let before: f64 = u.iter().zip(&mass).map(|(a, b)| a * b).sum();
        let spread_before = u.iter().cloned().fold(f64::MIN, f64::max);
        op.step(&mut u);
        let after: f64 = u.iter().zip(&mass).map(|(a, b)| a * b).sum();
        assert!((before - after).abs() < 1e-9 * before.abs().max(1.0));
        assert!(u.iter().cloned().fold(f64::MIN, f64::max) < spread_before);
    }
}
