//! Optional surface pre-smoothing (HPW 2005, Table 1, step 1) by implicit fairing after
//! Desbrun, Meyer, Schröder and Barr, "Implicit fairing of irregular meshes using diffusion
//! and curvature flow", SIGGRAPH 1999.
//!
//! Each step solves `(M + t L) X' = M X` for the three coordinates. Two flows:
//! - [`Flow::MeanCurvature`]: cotan weights recomputed from the current positions every step
//!   (curvature flow; little tangential drift on irregular meshes);
//! - [`Flow::Laplacian`]: cotan weights of the input, kept for every step (faster).
//!
//! The three coordinates are solved together by the solver of [`SurfaceSmoothing::solver`].
//!
//! Implicit smoothing shrinks a closed surface; with `preserve_volume` the result is scaled
//! about its centroid back to the enclosed volume of the input (Desbrun et al., sec. 5.3).
//! Vertices on boundaries move like the others (natural boundary condition).

use crate::error::{Error, Result};
use crate::mesh::{TriMesh, Vec3, mean_edge_length};

use super::{DiffusionOperator, LinearSolver, cotan_weights_and_mass};

/// Which flow [`smooth_surface`] integrates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Flow {
    /// Mean-curvature flow: weights from the current positions each step.
    #[default]
    MeanCurvature,
    /// Laplacian (heat) flow with the input's cotan weights.
    Laplacian,
}

/// Options of [`smooth_surface`].
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceSmoothing {
    /// Number of implicit steps. Default: 0 (pre-smoothing is off unless asked for).
    pub steps: usize,
    /// Step size relative to the squared mean edge length. Default: 0.5.
    pub time_step: f64,
    /// The flow. Default: [`Flow::MeanCurvature`].
    pub flow: Flow,
    /// Rescale to the input's volume after smoothing a closed mesh. Default: true.
    pub preserve_volume: bool,
    /// The linear solver of the implicit steps. Default: [`LinearSolver::DEFAULT`].
    pub solver: LinearSolver,
}

impl Default for SurfaceSmoothing {
    fn default() -> Self {
        SurfaceSmoothing {
            steps: 0,
            time_step: 0.5,
            flow: Flow::MeanCurvature,
            preserve_volume: true,
            solver: LinearSolver::DEFAULT,
        }
    }
}

/// Returns a smoothed copy of `mesh` (same connectivity).
///
/// # Errors
/// [`Error::InvalidInput`] for a non-finite or negative step; [`Error::Solver`] when a
/// factorisation fails or the iterative solver does not converge.
pub fn smooth_surface(mesh: &TriMesh, options: &SurfaceSmoothing) -> Result<TriMesh> {
    if !(options.time_step.is_finite() && options.time_step >= 0.0) {
        return Err(Error::InvalidInput(format!(
            "time step must be a non-negative number, got {}",
            options.time_step
        )));
    }
    if options.steps == 0 || mesh.num_faces() == 0 {
        return Ok(mesh.clone());
    }
    let n = mesh.num_vertices();
    let h = mean_edge_length(mesh);
    let time = options.time_step * h * h;
    let volume_before = enclosed_volume(mesh, mesh.positions());
    let mut xyz: [Vec<f64>; 3] =
        std::array::from_fn(|k| mesh.positions().iter().map(|p| p[k]).collect());
    let mut operator: Option<DiffusionOperator<'_>> = None;
    // After the first step a failure is the flow's doing: curvature flow shrinks a surface
    // and pinches its thin parts, and long enough it leaves triangles without area.
    let collapsed = |step: usize, e: Error| -> Error {
        if step == 0 {
            return e;
        }
        Error::Solver(format!(
            "surface pre-smoothing failed at step {} of {}: the flow has collapsed the surface \
             (triangles of no area) after {step} steps; use fewer steps or a smaller time step \
             ({e})",
            step + 1,
            options.steps
        ))
    };
    for step in 0..options.steps {
        let positions = || -> Vec<Vec3> {
            (0..n)
                .map(|i| Vec3::new(xyz[0][i], xyz[1][i], xyz[2][i]))
                .collect()
        };
        match &mut operator {
            None => {
                let (weights, mass) = cotan_weights_and_mass(mesh, &positions());
                operator = Some(DiffusionOperator::new(
                    mesh,
                    weights,
                    mass,
                    time,
                    &[None, None, None],
                    options.solver,
                )?);
            }
            // The mass changes with the positions in curvature flow; the operator holds the
            // mass of the step it was built for, as the implicit scheme requires.
            Some(op) if options.flow == Flow::MeanCurvature => {
                let (weights, mass) = cotan_weights_and_mass(mesh, &positions());
                op.update(weights, mass, time)
                    .map_err(|e| collapsed(step, e))?;
            }
            Some(_) => {}
        }
        if let Some(op) = &operator {
            let [x, y, z] = &mut xyz;
            op.step(&mut [x.as_mut_slice(), y, z])
                .map_err(|e| collapsed(step, e))?;
        }
    }
    let mut positions: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(xyz[0][i], xyz[1][i], xyz[2][i]))
        .collect();
    drop(xyz);
    let closed = mesh.info().closed;
    if options.preserve_volume && closed && volume_before.abs() > 0.0 {
        let volume_after = enclosed_volume(mesh, &positions);
        if volume_after.abs() > 0.0 && volume_after.signum() == volume_before.signum() {
            let scale = (volume_before / volume_after).cbrt();
            let center = positions.iter().sum::<Vec3>() / n as f64;
            for p in &mut positions {
                *p = center + (*p - center) * scale;
            }
        }
    }
    mesh.with_positions(positions)
}

/// Signed volume enclosed by the faces (meaningful for closed, consistently wound meshes).
fn enclosed_volume(mesh: &TriMesh, positions: &[Vec3]) -> f64 {
    mesh.faces()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            a.dot(&b.cross(&c)) / 6.0
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;
    use crate::smoothing::ConjugateGradientOptions;

    /// A sphere with deterministic radial noise.
    fn noisy_sphere() -> TriMesh {
        let m = shapes::icosphere(1.0, 4);
        let p = m
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| p * (1.0 + 0.02 * (((i * 2654435761) % 1000) as f64 / 500.0 - 1.0)))
            .collect();
        m.with_positions(p).unwrap()
    }

    fn radial_spread(m: &TriMesh) -> f64 {
        let r: Vec<f64> = m.positions().iter().map(|p| p.norm()).collect();
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        (r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / r.len() as f64).sqrt() / mean
    }

    #[test]
    fn fairing_removes_noise_and_keeps_volume() {
        let noisy = noisy_sphere();
        for flow in [Flow::MeanCurvature, Flow::Laplacian] {
            let opts = SurfaceSmoothing {
                steps: 3,
                flow,
                ..Default::default()
            };
            let smooth = smooth_surface(&noisy, &opts).unwrap();
            assert!(
                radial_spread(&smooth) < 0.3 * radial_spread(&noisy),
                "{flow:?}"
            );
            let v0 = enclosed_volume(&noisy, noisy.positions());
            let v1 = enclosed_volume(&smooth, smooth.positions());
            assert!((v0 - v1).abs() < 1e-9 * v0.abs());
        }
    }

    #[test]
    fn solvers_agree() {
        let noisy = noisy_sphere();
        for flow in [Flow::MeanCurvature, Flow::Laplacian] {
            let run = |solver| {
                let opts = SurfaceSmoothing {
                    steps: 3,
                    flow,
                    solver,
                    ..Default::default()
                };
                smooth_surface(&noisy, &opts).unwrap()
            };
            let tight = ConjugateGradientOptions::DEFAULT.with_tolerance(1e-12);
            let cg = run(LinearSolver::ConjugateGradient(tight));
            let exact = run(LinearSolver::Cholesky);
            for (a, b) in cg.positions().iter().zip(exact.positions()) {
                assert!((a - b).norm() < 1e-10, "{flow:?}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn a_collapsed_surface_is_named_in_the_error() {
        // A small bump on a square sheet under long curvature flow: its boundary stays, the
        // rest shrinks until triangles lose their area.
        let bump = |x: f64, y: f64| 0.3 * (-(x * x + y * y) / 0.05).exp();
        let mesh = crate::shapes::height_field(bump, [-1.0, 1.0], [-1.0, 1.0], 40, 40);
        let options = SurfaceSmoothing {
            steps: 60,
            ..SurfaceSmoothing::default()
        };
        let message = smooth_surface(&mesh, &options).unwrap_err().to_string();
        assert!(message.contains("collapsed the surface"), "{message}");
        assert!(message.contains("use fewer steps"), "{message}");
        // One sentence, without the source's indentation in it.
        assert!(!message.contains("  "), "{message}");
    }

    #[test]
    fn zero_steps_is_the_identity() {
        let m = noisy_sphere();
        let s = smooth_surface(&m, &SurfaceSmoothing::default()).unwrap();
        assert_eq!(s.positions(), m.positions());
    }
}
