//! Implicit diffusion on meshes: the machinery behind steps 1 and 3 of HPW 2005 (Table 1).
//!
//! - [`extremality`]: sign-aware smoothing of the extremality coefficients (HPW sec. 5.1),
//!   homogeneous or with per-vertex diffusion factors (inhomogeneous smoothing, HPW sec. 6).
//! - [`surface`]: optional pre-smoothing of the surface by implicit fairing (Desbrun, Meyer,
//!   Schröder, Barr 1999).
//!
//! Both solve `(M + t L_σ) u_new = M u_old` per implicit time step ([`system`]), with `M` the
//! lumped (barycentric) mass matrix and `L_σ` a positive semi-definite cotan (connection)
//! Laplacian. [`DiffusionOperator`] is the stateful object that holds the matrix between
//! steps, with one of three solvers ([`LinearSolver`]):
//! - [`mixed_precision`] (default): Jacobi-preconditioned conjugate gradients in mixed
//!   precision, warm-started, all fields in one pass; fast and linear in memory;
//! - [`system`]: the same method written plainly on a faer sparse matrix, the reference;
//! - [`cholesky`]: faer's sparse Cholesky, factorised once per sign pattern; exact to rounding
//!   but its fill-in costs time and memory.
//!
//! Cotan weights "stay sane": the weight of an edge is `½ Σ cot(opposite angle)` over its faces,
//! each cotangent capped at ±[`MAX_COT`] (slivers), and a negative total (an edge opposite
//! two obtuse angles) is clamped to zero. With non-negative weights the operator stays
//! positive semi-definite, so every implicit step is unconditionally stable.
//! [`along_line_weights`] are the weights of an anisotropic diffusion (faster along a
//! direction field), capped and clamped alike.

pub mod cholesky;
pub mod extremality;
pub mod mixed_precision;
pub mod surface;
pub mod system;

use rayon::prelude::*;

use crate::error::Result;
use crate::mesh::{TriMesh, Vec3};
use crate::slices::split_at;

pub use cholesky::{CholeskySystem, DiffusionPattern};
pub use mixed_precision::{ConjugateGradientOptions, ConnectionSystem, round_weights};
pub use system::DiffusionSystem;

/// Cap on the magnitude of one cotangent (an angle of about 0.06°).
pub const MAX_COT: f64 = 1e3;

/// Per-edge cotan weights `w_e = ½ Σ_faces cot(angle opposite e)`, clamped to `>= 0`,
/// indexed like [`crate::mesh::Topology::edges`].
pub fn cotan_weights(mesh: &TriMesh, positions: &[Vec3]) -> Vec<f64> {
    (0..mesh.topology().num_edges() as u32)
        .into_par_iter()
        .map(|e| cotan_weight(mesh, positions, e))
        .collect()
}

/// The cotan weight of edge `e` (see [`cotan_weights`]).
#[inline]
fn cotan_weight(mesh: &TriMesh, positions: &[Vec3], e: u32) -> f64 {
    let topo = mesh.topology();
    let faces = mesh.faces();
    let [a, b] = topo.edge(e);
    let w: f64 = topo
        .edge_faces(e)
        .iter()
        .map(|&f| 0.5 * opposite_cot(faces[f as usize], positions, [a, b]))
        .sum();
    w.max(0.0)
}

/// The cotangent of the angle of triangle `t` opposite its edge `[a, b]`, capped at
/// ±[`MAX_COT`].
#[inline]
fn opposite_cot(t: [u32; 3], positions: &[Vec3], [a, b]: [u32; 2]) -> f64 {
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
    cot.clamp(-MAX_COT, MAX_COT)
}

/// Per-edge weights, indexed like [`crate::mesh::Topology::edges`], of a diffusion that is up
/// to `factor` times faster along the direction field `along` (per vertex, unit, sign
/// irrelevant) than across it, and across it as the cotan weights' (with `factor` 1 they are
/// the cotan weights).
///
/// Per face the linear finite-element stiffness `∫ ∇φ_p · D ∇φ_q` of the tensor
/// `D = P + θ (factor − 1) T`: `P` the projection onto the face's plane, `T` the mean of
/// `s sᵀ` over its three corners' directions `s`, and `θ ∈ [0, 1]` the largest share for which
/// the face's weight on none of its edges falls below the cotan weight's or zero, whichever is
/// lower. An anisotropic tensor gives negative weights on a face whose edges do not follow its
/// direction (a diagonal across the lines), and clamping them would diffuse across the lines
/// as fast as along: such a face diffuses as the cotan weights do (θ = 0), and one with an
/// edge along the lines up to `factor` times faster along them. The anisotropic part is
/// capped at `(factor − 1)` · [`MAX_COT`] / 2 per face and edge, as a cotangent is, and a
/// negative total is clamped to zero, as for [`cotan_weights`]: the operator stays positive
/// semi-definite. Faces without area, and corners without a finite direction, add nothing to
/// it.
pub fn along_line_weights(mesh: &TriMesh, along: &[Vec3], factor: f64) -> Vec<f64> {
    let topo = mesh.topology();
    let (faces, positions) = (mesh.faces(), mesh.positions());
    let cap = (factor - 1.0).abs() * 0.5 * MAX_COT;
    // The weights of face t on its edges [t0, t1], [t1, t2], [t2, t0]: the cotan part and the
    // anisotropic part.
    let parts = |t: [u32; 3]| -> [(f64, f64); 3] {
        let edge = |k: usize| [t[k], t[(k + 1) % 3]];
        let cotans = [0, 1, 2].map(|k| 0.5 * opposite_cot(t, positions, edge(k)));
        let p = t.map(|v| positions[v as usize]);
        let cross = (p[1] - p[0]).cross(&(p[2] - p[0]));
        let twice_area = cross.norm();
        if twice_area <= 0.0 || twice_area.is_nan() {
            return cotans.map(|cotan| (cotan, 0.0));
        }
        // The gradients of the corners' hat functions, in the face's plane.
        let n = cross / twice_area;
        let grads = [0, 1, 2].map(|i| n.cross(&(p[(i + 2) % 3] - p[(i + 1) % 3])) / twice_area);
        let directions = t.map(|v| along[v as usize]);
        std::array::from_fn(|k| {
            let (grad_a, grad_b) = (grads[k], grads[(k + 1) % 3]);
            let t_part = directions
                .iter()
                .map(|s| grad_a.dot(s) * grad_b.dot(s))
                .sum::<f64>()
                / 3.0;
            // The weight is minus the stiffness entry (max/min: no panic on a NaN factor).
            let anisotropic = -(factor - 1.0) * 0.5 * twice_area * t_part;
            if anisotropic.is_finite() {
                (cotans[k], anisotropic.max(-cap).min(cap))
            } else {
                (cotans[k], 0.0)
            }
        })
    };
    // Per face, its weights on its edges [t0, t1], [t1, t2], [t2, t0], with its share θ of
    // the anisotropic part.
    let face_weights: Vec<[f64; 3]> = faces
        .par_iter()
        .map(|&t| {
            let parts = parts(t);
            let share = parts.iter().fold(1.0_f64, |share, &(cotan, anisotropic)| {
                if anisotropic < 0.0 {
                    share.min(cotan.max(0.0) / -anisotropic)
                } else {
                    share
                }
            });
            parts.map(|(cotan, anisotropic)| cotan + share * anisotropic)
        })
        .collect();
    (0..topo.num_edges() as u32)
        .into_par_iter()
        .map(|e| {
            let [a, b] = topo.edge(e);
            let w: f64 = topo
                .edge_faces(e)
                .iter()
                .map(|&f| {
                    let t = faces[f as usize];
                    (0..3)
                        .find(|&k| {
                            let (p, q) = (t[k], t[(k + 1) % 3]);
                            (p, q) == (a, b) || (p, q) == (b, a)
                        })
                        .map_or(0.0, |k| face_weights[f as usize][k])
                })
                .sum();
            w.max(0.0)
        })
        .collect()
}

/// Lumped mass: a third of the area of each vertex's star. Vertices without faces get the
/// mean mass so that the system stays definite (their values are simply kept).
pub fn lumped_mass(mesh: &TriMesh, positions: &[Vec3]) -> Vec<f64> {
    let mut mass: Vec<f64> = (0..mesh.num_vertices() as u32)
        .into_par_iter()
        .map(|v| star_mass(mesh, positions, v))
        .collect();
    fill_empty_masses(&mut mass);
    mass
}

/// A third of the area of the star of `v` (0 without faces).
#[inline]
fn star_mass(mesh: &TriMesh, positions: &[Vec3], v: u32) -> f64 {
    let faces = mesh.faces();
    let area = |f: u32| {
        let [a, b, c] = faces[f as usize].map(|i| positions[i as usize]);
        0.5 * (b - a).cross(&(c - a)).norm()
    };
    mesh.topology()
        .vertex_faces(v)
        .iter()
        .map(|&f| area(f))
        .sum::<f64>()
        / 3.0
}

/// Gives vertices without mass the mean of the others (1 when none has any).
fn fill_empty_masses(mass: &mut [f64]) {
    let (sum, count) = mass
        .iter()
        .filter(|&&m| m > 0.0)
        .fold((0.0, 0usize), |(s, c), &m| (s + m, c + 1));
    let fill = if count == 0 { 1.0 } else { sum / count as f64 };
    for m in mass {
        if *m <= 0.0 {
            *m = fill;
        }
    }
}

/// [`cotan_weights`] and [`lumped_mass`] in one pass over the vertices, with bit for bit the
/// same values.
///
/// Each vertex computes its mass and the weights of the edges to its higher neighbours, whose
/// faces are its own: the star's faces and positions are read once, where the two separate
/// passes fetch them from scattered places twice. Edge ids run vertex by vertex (the edges
/// `(v, w)`, `w > v`, by increasing `w`), so a block of vertices writes one range of weights.
pub fn cotan_weights_and_mass(mesh: &TriMesh, positions: &[Vec3]) -> (Vec<f64>, Vec<f64>) {
    let topo = mesh.topology();
    let edges = topo.edges();
    let n = mesh.num_vertices();
    let mut weights = vec![0.0; edges.len()];
    let mut mass = vec![0.0; n];
    // Block b holds vertices from `b · VERTEX_BLOCK` and the edges from `edge_bounds[b]`.
    let edge_bounds: Vec<usize> = (0..n)
        .step_by(VERTEX_BLOCK)
        .chain([n])
        .map(|v| edges.partition_point(|e| (e[0] as usize) < v))
        .collect();
    split_at(&mut weights, &edge_bounds)
        .into_par_iter()
        .zip(mass.par_chunks_mut(VERTEX_BLOCK))
        .enumerate()
        .for_each(|(b, (weights, mass))| {
            let first_edge = edge_bounds[b];
            let mut e = first_edge;
            for (i, m) in mass.iter_mut().enumerate() {
                let v = b * VERTEX_BLOCK + i;
                *m = star_mass(mesh, positions, v as u32);
                while e < first_edge + weights.len() && edges[e][0] as usize == v {
                    weights[e - first_edge] = cotan_weight(mesh, positions, e as u32);
                    e += 1;
                }
            }
        });
    fill_empty_masses(&mut mass);
    (weights, mass)
}

/// The power of two nearest `x` (1 for zero, non-finite or extreme values): dividing by it
/// is exact.
fn power_of_two_near(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let exponent = x.log2().round().clamp(-1000.0, 1000.0) as i32;
    2f64.powi(exponent)
}

/// The mass and the time step divided by the power of two nearest the mean mass: the system
/// `(M + t L) u' = M u` is the same, but its entries are near 1 whatever the model's unit
/// (single precision holds 1e±38; the mass of a model in nanometres is 1e-18 m²).
fn unit_mass(mut mass: Vec<f64>, time: f64) -> (Vec<f64>, f64) {
    let mean = mass.iter().sum::<f64>() / mass.len().max(1) as f64;
    let scale = power_of_two_near(mean);
    if scale != 1.0 {
        mass.par_iter_mut().for_each(|m| *m /= scale);
    }
    (mass, time / scale)
}

/// Vertices per parallel work item of [`cotan_weights_and_mass`].
const VERTEX_BLOCK: usize = 2048;

/// How the implicit steps are solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LinearSolver {
    /// Jacobi-preconditioned conjugate gradients in mixed precision, warm-started from the
    /// previous step ([`mixed_precision`]).
    ConjugateGradient(ConjugateGradientOptions),
    /// The same method in double precision, one field at a time, on the assembled matrix
    /// ([`system`]): the reference, about twice as slow.
    PlainConjugateGradient(ConjugateGradientOptions),
    /// Sparse Cholesky factorisation, once per sign pattern ([`cholesky`]).
    Cholesky,
}

impl LinearSolver {
    /// The default: conjugate gradients with [`ConjugateGradientOptions::DEFAULT`].
    pub const DEFAULT: Self = LinearSolver::ConjugateGradient(ConjugateGradientOptions::DEFAULT);
}

impl Default for LinearSolver {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// An implicit diffusion step `(M + t L_σ) u' = M u` on one or more fields, ready to be
/// taken repeatedly.
///
/// `L_σ` is the connection Laplacian `(L_σ u)(p) = Σ_q w_pq (u(p) − σ_pq u(q))` with
/// `σ_pq ∈ {−1, +1}` per edge and field (all `+1` gives the ordinary Laplacian). It is
/// positive semi-definite for non-negative weights, so `M + t L_σ` is positive definite.
#[derive(Debug)]
pub struct DiffusionOperator<'m> {
    mesh: &'m TriMesh,
    solver: Solver<'m>,
}

#[derive(Debug)]
enum Solver<'m> {
    ConjugateGradient(ConnectionSystem<'m>),
    Plain(DiffusionSystem),
    Cholesky(CholeskySystem),
}

impl<'m> DiffusionOperator<'m> {
    /// Prepares `M + t L_σ`.
    ///
    /// The weights are rounded to single precision first (a relative change below 6e-8),
    /// the precision the conjugate-gradient rows store them in, so that every solver solves
    /// the same system.
    ///
    /// `weights` are per-edge non-negative diffusion weights (cotan weights or
    /// [`along_line_weights`], possibly scaled by local factors), `mass` the lumped mass, `time` the step `t` (in units of area) and
    /// `flips` one entry per field: the edges where `σ = −1` (`None`: `σ = +1` everywhere).
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] for mismatched lengths or invalid solver options;
    /// [`crate::Error::Solver`] when a Cholesky factorisation fails.
    pub fn new(
        mesh: &'m TriMesh,
        mut weights: Vec<f64>,
        mass: Vec<f64>,
        time: f64,
        flips: &[Option<&[bool]>],
        solver: LinearSolver,
    ) -> Result<Self> {
        round_weights(&mut weights);
        let (mass, time) = unit_mass(mass, time);
        let solver = match solver {
            LinearSolver::ConjugateGradient(options) => Solver::ConjugateGradient(
                ConnectionSystem::new(mesh.topology(), weights, mass, time, flips, options)?,
            ),
            LinearSolver::PlainConjugateGradient(options) => Solver::Plain(
                DiffusionSystem::assemble(mesh.topology(), &weights, mass, time, flips, options)?,
            ),
            LinearSolver::Cholesky => {
                Solver::Cholesky(CholeskySystem::new(mesh, &weights, mass, time, flips)?)
            }
        };
        Ok(DiffusionOperator { mesh, solver })
    }

    /// Replaces the weights and the mass (same mesh, signs and time step), for flows whose
    /// weights change every step.
    ///
    /// # Errors
    /// As [`DiffusionOperator::new`].
    pub fn update(&mut self, mut weights: Vec<f64>, mass: Vec<f64>, time: f64) -> Result<()> {
        round_weights(&mut weights);
        let (mass, time) = unit_mass(mass, time);
        match &mut self.solver {
            Solver::ConjugateGradient(s) => s.update(weights, mass, time),
            Solver::Plain(s) => s.update(self.mesh.topology(), &weights, mass, time),
            Solver::Cholesky(s) => s.update(&weights, mass, time),
        }
    }

    /// The mesh the operator lives on.
    pub fn mesh(&self) -> &'m TriMesh {
        self.mesh
    }

    /// Number of fields each step takes.
    pub fn fields(&self) -> usize {
        match &self.solver {
            Solver::ConjugateGradient(s) => s.fields(),
            Solver::Plain(s) => s.fields(),
            Solver::Cholesky(s) => s.fields(),
        }
    }

    /// One implicit step on every field, in place (`fields[f]` holds one value per vertex).
    /// Returns the conjugate-gradient iterations of the slowest field (0 for Cholesky).
    ///
    /// # Errors
    /// [`crate::Error::InvalidInput`] for a wrong number or length of fields;
    /// [`crate::Error::Solver`] when conjugate gradients do not converge.
    pub fn step(&self, fields: &mut [&mut [f64]]) -> Result<usize> {
        self.steps(fields, 1)
    }

    /// `count` steps, each from the result of the last (conjugate gradients keep their
    /// working vectors from step to step). Returns the conjugate-gradient iterations of all
    /// steps (0 for Cholesky).
    ///
    /// # Errors
    /// As [`DiffusionOperator::step`].
    pub fn steps(&self, fields: &mut [&mut [f64]], count: usize) -> Result<usize> {
        self.steps_within(fields, count, 0.0)
    }

    /// [`DiffusionOperator::steps`] solved only to the relative residual `tolerance`, where
    /// that is looser than the solver's own [`ConjugateGradientOptions::tolerance`] (fields
    /// of which only a statistic is read). Cholesky solves exactly either way.
    ///
    /// # Errors
    /// As [`DiffusionOperator::step`].
    pub fn steps_within(
        &self,
        fields: &mut [&mut [f64]],
        count: usize,
        tolerance: f64,
    ) -> Result<usize> {
        // Each field divided by the power of two nearest its largest magnitude, and
        // multiplied back after: exact, and single precision neither overflows nor
        // underflows on fields of a model in nanometres or in light years.
        let scales: Vec<f64> = fields
            .iter()
            .map(|f| {
                power_of_two_near(
                    f.par_iter()
                        .fold(|| 0.0, |m: f64, x| m.max(x.abs()))
                        .reduce(|| 0.0, f64::max),
                )
            })
            .collect();
        let rescale = |fields: &mut [&mut [f64]], by: &dyn Fn(f64) -> f64| {
            for (field, &scale) in fields.iter_mut().zip(&scales) {
                if scale != 1.0 {
                    let factor = by(scale);
                    field.par_iter_mut().for_each(|x| *x *= factor);
                }
            }
        };
        rescale(fields, &|scale| 1.0 / scale);
        let result = self.solve_steps(fields, count, tolerance);
        rescale(fields, &|scale| scale);
        result
    }

    fn solve_steps(
        &self,
        fields: &mut [&mut [f64]],
        count: usize,
        tolerance: f64,
    ) -> Result<usize> {
        match &self.solver {
            Solver::ConjugateGradient(s) => s.steps_within(fields, count, tolerance),
            Solver::Plain(s) => {
                let mut iterations = 0;
                for _ in 0..count {
                    iterations += s.step_within(fields, tolerance)?;
                }
                Ok(iterations)
            }
            Solver::Cholesky(s) => {
                for _ in 0..count {
                    s.step(fields)?;
                }
                Ok(0)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    /// On a square grid split along diagonals (right isosceles triangles), the diffusion
    /// `factor` times faster along x is the five-point stencil with weight `factor` on the
    /// x-edges, 1 on the y-edges and 0 on the diagonals (interior edges; boundary edges have
    /// one face and half of it). With factor 1 the weights are the cotan weights.
    #[test]
    fn along_line_weights_on_a_square_grid() {
        let n = 6;
        for pattern in [
            shapes::GridPattern::Uniform,
            shapes::GridPattern::Alternating,
        ] {
            let m = shapes::height_field_with(|_, _| 0.0, [0.0, 1.0], [0.0, 1.0], n, n, pattern);
            let along = vec![Vec3::x(); m.num_vertices()];
            assert_eq!(
                along_line_weights(&m, &along, 1.0),
                cotan_weights(&m, m.positions())
            );
            let weights = along_line_weights(&m, &along, 3.0);
            for (e, (&[a, b], &w)) in m.topology().edges().iter().zip(&weights).enumerate() {
                let d = m.position(b) - m.position(a);
                let share = m.topology().edge_faces(e as u32).len() as f64 / 2.0;
                let expected = if d.y.abs() < 1e-12 {
                    3.0 * share
                } else if d.x.abs() < 1e-12 {
                    share
                } else {
                    0.0
                };
                assert!(
                    (w - expected).abs() < 1e-9,
                    "{pattern:?} edge {d:?}: {w} against {expected}"
                );
            }
        }
    }

    /// Two implicit steps of a field of curvature units (1/length²) on `mesh` scaled by
    /// `scale`, with the time step of the extremality smoothing (the squared edge length),
    /// by `solver`; the result in the units of the unscaled mesh.
    fn steps_at_scale(mesh: &TriMesh, scale: f64, solver: LinearSolver) -> Vec<f64> {
        let positions: Vec<Vec3> = mesh.positions().iter().map(|p| p * scale).collect();
        let scaled = TriMesh::new(positions, mesh.faces().to_vec()).unwrap();
        let (weights, mass) = cotan_weights_and_mass(&scaled, scaled.positions());
        let time = crate::mesh::mean_edge_length(&scaled).powi(2);
        let operator =
            DiffusionOperator::new(&scaled, weights, mass, time, &[None], solver).unwrap();
        let mut field: Vec<f64> = mesh
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| (p.x.sin() + (i % 7) as f64) / (scale * scale))
            .collect();
        operator.steps(&mut [&mut field], 2).unwrap();
        field.iter().map(|x| x * scale * scale).collect()
    }

    #[test]
    fn steps_do_not_depend_on_the_models_unit() {
        // In nanometres or in light years, single precision would underflow or overflow in
        // the mass, the time step or the values (conjugate gradients broke down on both).
        let mesh = shapes::torus(3.0, 1.0, 30, 12);
        for solver in [
            LinearSolver::DEFAULT,
            LinearSolver::PlainConjugateGradient(ConjugateGradientOptions::DEFAULT),
            LinearSolver::Cholesky,
        ] {
            let unit = steps_at_scale(&mesh, 1.0, solver);
            for scale in [1e-21, 1e19, 0.25] {
                let scaled = steps_at_scale(&mesh, scale, solver);
                let worst = unit
                    .iter()
                    .zip(&scaled)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(worst < 1e-4, "{solver:?} at scale {scale}: off by {worst}");
                if scale == 0.25 {
                    // A power of two scales every operation exactly.
                    assert_eq!(unit, scaled, "{solver:?}");
                }
            }
        }
    }

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
    fn fused_weights_and_mass_are_the_separate_ones() {
        // Bit for bit, on a closed surface, an open one and a non-manifold soup.
        let mut fin = shapes::torus(3.0, 1.0, 12, 8);
        let mut soup = fin.faces().to_vec();
        soup.push([0, 1, 40]);
        soup.push([0, 1, 50]);
        fin = TriMesh::from_arrays(
            fin.positions().iter().map(|p| [p.x, p.y, p.z]).collect(),
            soup,
        )
        .unwrap();
        for m in [
            shapes::ellipsoid(1.0, 0.7, 0.4, 3),
            shapes::waving_disk(1.0, 6),
            fin,
        ] {
            let (w, mass) = cotan_weights_and_mass(&m, m.positions());
            let (w0, mass0) = (
                cotan_weights(&m, m.positions()),
                lumped_mass(&m, m.positions()),
            );
            assert!(w.iter().zip(&w0).all(|(a, b)| a.to_bits() == b.to_bits()));
            assert!(
                mass.iter()
                    .zip(&mass0)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
            );
            assert_eq!((w.len(), mass.len()), (w0.len(), mass0.len()));
        }
    }

    /// Every solver, the conjugate gradients run to a tight tolerance.
    fn solvers() -> [LinearSolver; 3] {
        let tight = ConjugateGradientOptions::DEFAULT.with_tolerance(1e-13);
        [
            LinearSolver::ConjugateGradient(tight),
            LinearSolver::PlainConjugateGradient(tight),
            LinearSolver::Cholesky,
        ]
    }

    #[test]
    fn laplacian_annihilates_constants_and_keeps_the_mean() {
        // (M + tL) u' = M u preserves Σ M u for σ = +1, and constants are fixed points.
        let m = shapes::torus(3.0, 1.0, 20, 10);
        for solver in solvers() {
            let w = cotan_weights(&m, m.positions());
            let mass = lumped_mass(&m, m.positions());
            let op = DiffusionOperator::new(&m, w, mass.clone(), 0.5, &[None], solver).unwrap();
            let mut c = vec![2.5; m.num_vertices()];
            op.step(&mut [&mut c]).unwrap();
            assert!(c.iter().all(|x| (x - 2.5).abs() < 1e-10), "{solver:?}");
            let mut u: Vec<f64> = m.positions().iter().map(|p| p.x * p.z + p.y).collect();
            let before: f64 = u.iter().zip(&mass).map(|(a, b)| a * b).sum();
            let spread_before = u.iter().cloned().fold(f64::MIN, f64::max);
            op.step(&mut [&mut u]).unwrap();
            let after: f64 = u.iter().zip(&mass).map(|(a, b)| a * b).sum();
            assert!(
                (before - after).abs() < 1e-9 * before.abs().max(1.0),
                "{solver:?}"
            );
            assert!(u.iter().cloned().fold(f64::MIN, f64::max) < spread_before);
        }
    }

    #[test]
    fn conjugate_gradients_agree_with_cholesky() {
        // Two fields with different signs and one without, on an ellipsoid (irregular
        // cotan weights), several steps: warm starts must not drift from the exact solves.
        let m = shapes::ellipsoid(1.0, 0.7, 0.4, 3);
        let topo = m.topology();
        let flips: Vec<bool> = topo
            .edges()
            .iter()
            .map(|&[a, b]| (a * 7 + b) % 5 == 0)
            .collect();
        let h = crate::mesh::mean_edge_length(&m);
        let start: Vec<f64> = m
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| p.x * p.y + (p.z * 9.0).sin() + if i % 2 == 0 { 0.1 } else { -0.1 })
            .collect();
        let run = |solver: LinearSolver| {
            let w = cotan_weights(&m, m.positions());
            let mass = lumped_mass(&m, m.positions());
            let fields = [None, Some(flips.as_slice())];
            let op = DiffusionOperator::new(&m, w, mass, 2.0 * h * h, &fields, solver).unwrap();
            let (mut a, mut b) = (start.clone(), start.clone());
            for _ in 0..4 {
                op.step(&mut [&mut a, &mut b]).unwrap();
            }
            (a, b)
        };
        let [fast, plain, exact] = solvers().map(run);
        let scale = start.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        for cg in [&fast, &plain] {
            for (x, y) in [(&cg.0, &exact.0), (&cg.1, &exact.1)] {
                let worst = x
                    .iter()
                    .zip(y)
                    .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
                assert!(worst < 1e-10 * scale, "max difference {worst:e}");
            }
            // The signs matter: the two fields differ.
            assert!(cg.0.iter().zip(&cg.1).any(|(a, b)| (a - b).abs() > 1e-3));
        }
    }
}
