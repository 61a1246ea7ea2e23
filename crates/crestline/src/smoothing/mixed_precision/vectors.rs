//! The working vectors of the mixed-precision solver and the passes over them: all fields
//! of a vertex together, chunks of [`CHUNK`] rows summed in order.

use rayon::prelude::*;

use super::CHUNK;
use crate::error::Error;

/// The single-precision vectors of the Jacobi solver: the diagonal, the residual `r`, the
/// search direction `p`, `q = A p` and the correction `e`, all fields of a vertex together.
pub(super) struct Work<const K: usize> {
    pub(super) d: Vec<f32>,
    pub(super) r: Vec<[f32; K]>,
    pub(super) p: Vec<[f32; K]>,
    pub(super) q: Vec<[f32; K]>,
    pub(super) e: Vec<[f32; K]>,
    /// The step's right-hand side `b = M x₀`, stored once a second round needs it (empty
    /// before: `x` still holds `x₀`).
    pub(super) rhs: Vec<[f64; K]>,
}

impl<const K: usize> Work<K> {
    /// `p = D⁻¹ r`, `e = 0`; returns `r·D⁻¹r` per field.
    pub(super) fn start_correction(&mut self) -> [f64; K] {
        let Work { d, r, p, e, .. } = self;
        let sums = p
            .par_chunks_mut(CHUNK)
            .zip(e.par_chunks_mut(CHUNK))
            .zip(r.par_chunks(CHUNK))
            .zip(d.par_chunks(CHUNK))
            .map(|(((ps, es), rs), ds)| {
                let mut rz = [0.0; K];
                for (((p, e), r), &d) in ps.iter_mut().zip(es).zip(rs).zip(ds) {
                    for f in 0..K {
                        p[f] = r[f] / d;
                        e[f] = 0.0;
                        rz[f] += f64::from(r[f] * p[f]);
                    }
                }
                [rz]
            })
            .collect::<Vec<_>>();
        let [rz] = add_up(&sums);
        rz
    }

    /// `e += α p`, `r −= α q`; returns the new `r·D⁻¹r` per field.
    pub(super) fn advance(&mut self, alpha: &[f32; K]) -> [f64; K] {
        let Work { d, r, p, q, e, .. } = self;
        let sums = r
            .par_chunks_mut(CHUNK)
            .zip(e.par_chunks_mut(CHUNK))
            .zip(p.par_chunks(CHUNK))
            .zip(q.par_chunks(CHUNK))
            .zip(d.par_chunks(CHUNK))
            .map(|((((rs, es), ps), qs), ds)| {
                let mut rz = [0.0; K];
                for ((((r, e), p), q), &d) in rs.iter_mut().zip(es).zip(ps).zip(qs).zip(ds) {
                    for f in 0..K {
                        e[f] += alpha[f] * p[f];
                        r[f] -= alpha[f] * q[f];
                        rz[f] += f64::from(r[f] * r[f] / d);
                    }
                }
                [rz]
            })
            .collect::<Vec<_>>();
        let [rz] = add_up(&sums);
        rz
    }

    /// `p = D⁻¹ r + β p`.
    pub(super) fn next_direction(&mut self, beta: &[f32; K]) {
        let Work { d, r, p, .. } = self;
        p.par_chunks_mut(CHUNK)
            .zip(r.par_chunks(CHUNK))
            .zip(d.par_chunks(CHUNK))
            .for_each(|((ps, rs), ds)| {
                for ((p, r), &d) in ps.iter_mut().zip(rs).zip(ds) {
                    for f in 0..K {
                        p[f] = r[f] / d + beta[f] * p[f];
                    }
                }
            });
    }
}

/// The largest relative residual `√(r·D⁻¹r / b·D⁻¹b)` among the fields not yet done.
pub(super) fn worst_relative<const K: usize>(
    rz: &[f64; K],
    rhs_norm2: &[f64; K],
    done: &[bool; K],
) -> f64 {
    (0..K)
        .filter(|&f| !done[f])
        .map(|f| (rz[f] / rhs_norm2[f]).sqrt())
        .fold(0.0, f64::max)
}

pub(super) fn not_finite() -> Error {
    Error::Solver("conjugate gradients: the values to smooth are not finite".into())
}

/// Per-chunk partial sums added in chunk order (deterministic).
pub(super) fn add_up<const K: usize, const S: usize>(partials: &[[[f64; K]; S]]) -> [[f64; K]; S] {
    let mut total = [[0.0; K]; S];
    for part in partials {
        for (t, p) in total.iter_mut().zip(part) {
            for (a, b) in t.iter_mut().zip(p) {
                *a += b;
            }
        }
    }
    total
}

/// The fields cut into [`CHUNK`]-row pieces, regrouped chunk by chunk (piece `f` of a group
/// belongs to field `f`).
/// Sets the fields that start cold (at zero instead of their values) to zero.
pub(super) fn zero_cold_fields<const K: usize>(x: &mut [&mut [f64]], cold: &[bool; K]) {
    for (field, _) in x.iter_mut().zip(cold).filter(|(_, cold)| **cold) {
        field.fill(0.0);
    }
}

/// `x += e` for every field.
pub(super) fn add_correction<const K: usize>(x: &mut [&mut [f64]], e: &[[f32; K]]) {
    field_chunks(x)
        .into_par_iter()
        .zip(e.par_chunks(CHUNK))
        .for_each(|(mut xs, es)| {
            for (i, e) in es.iter().enumerate() {
                for f in 0..K {
                    xs[f][i] += f64::from(e[f]);
                }
            }
        });
}

pub(super) fn field_chunks<'a>(fields: &'a mut [&mut [f64]]) -> Vec<Vec<&'a mut [f64]>> {
    let mut groups: Vec<Vec<&'a mut [f64]>> = Vec::new();
    for field in fields.iter_mut() {
        for (c, piece) in field.chunks_mut(CHUNK).enumerate() {
            if c == groups.len() {
                groups.push(Vec::new());
            }
            groups[c].push(piece);
        }
    }
    groups
}
