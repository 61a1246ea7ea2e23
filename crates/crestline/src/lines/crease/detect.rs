//! Steps 1 to 3 of [`find_creases`](super::find_creases): the dihedral angle of every edge, the
//! threshold at the gap of their histogram, and the tessellation edges that stand above it.

use rayon::prelude::*;

use crate::mesh::{TriMesh, Vec3, face_normals};

/// Dihedral angles below this are flat in the histogram of [`gap_threshold`] (degrees): float
/// noise of planar faces and the tessellation of gently curved ones. It is also the smallest
/// threshold the search can return.
pub const FLAT_ANGLE: f64 = 1.0;
/// A tessellation edge turns by less than this (degrees): tessellators keep the angle between
/// neighbouring facets of a smooth surface well below it (OpenCASCADE's default angular
/// deflection is 0.5 rad, 28.6°). Steeper edges are creases even between equal neighbours (a
/// hexagonal prism).
pub const MAX_FACET_TURN: f64 = 30.0;

/// The largest chordal deviation of a tessellation, as a fraction of the bounding-box
/// diagonal: CAD exporters use about 0.0005 (the shared parts) or less. Two parallel edges
/// turning by θ at a distance d stand for a smooth surface only if its chords deviate by
/// d·θ/8 at most this much; farther apart they are two creases (the 10° edges around the flat
/// top of a frustum).
pub const MAX_CHORD_DEVIATION: f64 = 0.002;

/// Bins of the histogram per doubling of the angle.
const BINS_PER_OCTAVE: f64 = 8.0;
/// A gap spans at least this ratio of angles.
const MIN_GAP_RATIO: f64 = 1.5;
/// A gap holds at most this share of the edge length of the equally wide stretches on either
/// side of it.
const MAX_GAP_SHARE: f64 = 0.1;
/// Each side of a gap holds at least this many edges (fewer are no evidence of a population).
const MIN_SIDE_EDGES: usize = 4;

/// The signed dihedral angle of every edge (radians, in [−π, π]): the angle between the
/// normals of its two faces, positive where the surface is convex (the far corner of one face
/// lies behind the plane of the other, normals outward). NaN for boundary and non-manifold
/// edges and where a face has no normal. Faces wound against each other are compared with
/// one normal flipped.
pub fn dihedral_angles(mesh: &TriMesh) -> Vec<f64> {
    dihedral_angles_between(mesh, &face_normals(mesh))
}

/// [`dihedral_angles`] between the given face normals (one per face, unit or zero), such as
/// the filtered ones of step 2b ([`super::filtered_normals`]).
pub fn dihedral_angles_between(mesh: &TriMesh, normals: &[Vec3]) -> Vec<f64> {
    let topo = mesh.topology();
    let faces = topo.faces();
    (0..topo.num_edges() as u32)
        .into_par_iter()
        .map(|e| {
            let [a, b] = topo.edge(e);
            let &[f, g] = topo.edge_faces(e) else {
                return f64::NAN;
            };
            let (tf, tg) = (faces[f as usize], faces[g as usize]);
            let nf = normals[f as usize];
            let mut ng = normals[g as usize];
            if nf == Vec3::zeros() || ng == Vec3::zeros() {
                return f64::NAN;
            }
            if runs_from(tf, a, b) == runs_from(tg, a, b) {
                ng = -ng;
            }
            let angle = nf.cross(&ng).norm().atan2(nf.dot(&ng));
            let Some(&c) = tg.iter().find(|&&v| v != a && v != b) else {
                return f64::NAN;
            };
            let behind = (mesh.position(c) - mesh.position(a)).dot(&nf) <= 0.0;
            if behind { angle } else { -angle }
        })
        .collect()
}

/// True when triangle `t` runs from `a` to `b` (rather than from `b` to `a`).
pub(super) fn runs_from(t: [u32; 3], a: u32, b: u32) -> bool {
    (0..3).any(|s| t[s] == a && t[(s + 1) % 3] == b)
}

/// The crease threshold of a mesh (radians) from its unsigned dihedral angles and edge
/// lengths, or `None` when the histogram has no gap (see the module docs).
///
/// The angles go into bins of an eighth of an octave from [`FLAT_ANGLE`] to 180°, each edge
/// weighing its length; smaller angles are flat. A gap is a run of bins spanning at least a
/// ratio of 1.5 whose weight is at most a tenth of that of the run of the same width on
/// either side (the flat edges belong to a run on the low side that reaches below
/// [`FLAT_ANGLE`]), with at least four edges on each side. The threshold is the geometric
/// middle of the chosen gap at its widest extent. NaN angles are ignored.
///
/// A CAD tessellation can show narrower gaps too, between its planar faces and the facets of
/// its curved ones (the hex nut of `../shared/quality`: nothing from 1° to 1.5°, cone facets
/// above) and between creases of different angles; the gap between the tessellation and the
/// creases is the wide one. So the lowest gap at least half as wide (on the log scale) as the
/// widest one wins ([`gap_thresholds`] lists them all, lowest first).
pub fn gap_threshold(angles: &[f64], lengths: &[f64]) -> Option<f64> {
    gap_thresholds(angles, lengths).first().map(|g| g.threshold)
}

/// A stretch of the histogram of dihedral angles without edges ([`gap_thresholds`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// The threshold it gives (radians): the geometric middle of its first extent at least
    /// half as wide as the widest gap of the mesh.
    pub threshold: f64,
    /// Where it starts (radians): the union of its overlapping extents runs from here …
    pub from: f64,
    /// … to here.
    pub to: f64,
}

/// The gaps of [`gap_threshold`]'s histogram that are at least half as wide as the widest
/// one, lowest first (overlapping extents are one gap); empty when there is no gap.
pub fn gap_thresholds(angles: &[f64], lengths: &[f64]) -> Vec<Gap> {
    let floor = FLAT_ANGLE.to_radians().ln();
    let step = std::f64::consts::LN_2 / BINS_PER_OCTAVE;
    let bins = ((std::f64::consts::PI.ln() - floor) / step).ceil() as usize;
    let mut mass = vec![0.0; bins + 1];
    let mut count = vec![0usize; bins + 1];
    let (mut flat_mass, mut flat_count) = (0.0, 0usize);
    for (&a, &l) in angles.iter().zip(lengths) {
        let a = a.abs();
        if !(a.is_finite() && l.is_finite() && l >= 0.0) {
            continue;
        }
        if a < FLAT_ANGLE.to_radians() {
            flat_mass += l;
            flat_count += 1;
        } else {
            let b = (((a.ln() - floor) / step) as usize).min(bins - 1);
            mass[b + 1] += l;
            count[b + 1] += 1;
        }
    }
    // Prefix sums: bins i..j hold mass[j] - mass[i].
    for i in 0..bins {
        mass[i + 1] += mass[i];
        count[i + 1] += count[i];
    }
    let run = |i: usize, j: usize| (mass[j] - mass[i], count[j] - count[i]);
    let min_width = (MIN_GAP_RATIO.ln() / step).ceil() as usize;
    let is_gap = |i: usize, j: usize| -> bool {
        let width = j - i;
        let (gap, _) = run(i, j);
        let (left, left_count) = if i >= width {
            run(i - width, i)
        } else {
            let (m, c) = run(0, i);
            (m + flat_mass, c + flat_count)
        };
        let (right, right_count) = run(j, (j + width).min(bins));
        left_count >= MIN_SIDE_EDGES
            && right_count >= MIN_SIDE_EDGES
            && gap <= MAX_GAP_SHARE * left.min(right)
    };
    // Each start's widest extent: for every start bin, the first valid end and those after
    // it while they stay valid.
    let gaps: Vec<(usize, usize)> = (0..bins)
        .filter_map(|i| {
            let mut end = None;
            for j in i + min_width..=bins {
                if is_gap(i, j) {
                    end = Some(j);
                } else if end.is_some() {
                    break;
                }
            }
            end.map(|j| (i, j))
        })
        .collect();
    let Some(widest) = gaps.iter().map(|(i, j)| j - i).max() else {
        return Vec::new();
    };
    let angle = |bin: f64| (floor + step * bin).exp();
    // Overlapping extents (in order of their starts) joined into one gap each: its first and
    // last bin, and its first extent wide enough to choose.
    type Extent = (usize, usize);
    let mut joined: Vec<(usize, usize, Option<Extent>)> = Vec::new();
    for &(i, j) in &gaps {
        let wide = 2 * (j - i) >= widest;
        match joined.last_mut() {
            Some((_, end, chosen)) if i < *end => {
                *end = (*end).max(j);
                if chosen.is_none() && wide {
                    *chosen = Some((i, j));
                }
            }
            _ => joined.push((i, j, wide.then_some((i, j)))),
        }
    }
    joined
        .into_iter()
        .filter_map(|(start, end, chosen)| {
            let (i, j) = chosen?;
            Some(Gap {
                threshold: angle((i + j) as f64 / 2.0),
                from: angle(start as f64),
                to: angle(end as f64),
            })
        })
        .collect()
}

/// True when edge `e` looks like one edge of the tessellation of a smooth surface: it turns
/// by less than [`MAX_FACET_TURN`], and at the far corner of one of its two triangles an edge
/// within 30° of parallel to it turns the same way by between a third and three times its
/// angle, close enough for a chordal deviation below [`MAX_CHORD_DEVIATION`] times
/// `diagonal`. `angles` are those of [`dihedral_angles`].
pub fn is_facet_edge(mesh: &TriMesh, angles: &[f64], e: u32, diagonal: f64) -> bool {
    let theta = angles[e as usize];
    if !(theta.is_finite() && theta.abs() < MAX_FACET_TURN.to_radians()) {
        return false;
    }
    let topo = mesh.topology();
    let [a, b] = topo.edge(e);
    let Some(dir) = (mesh.position(b) - mesh.position(a)).try_normalize(0.0) else {
        return false;
    };
    let parallel = 30f64.to_radians().cos();
    topo.edge_faces(e).iter().any(|&f| {
        let Some(&c) = topo.faces()[f as usize].iter().find(|&&v| v != a && v != b) else {
            return false;
        };
        let to_c = mesh.position(c) - mesh.position(a);
        let distance = (to_c - dir * to_c.dot(&dir)).norm();
        if distance * theta.abs() / 8.0 > MAX_CHORD_DEVIATION * diagonal {
            return false;
        }
        topo.vertex_edges(c).iter().any(|&n| {
            let phi = angles[n as usize];
            if n == e || !phi.is_finite() || phi * theta <= 0.0 {
                return false;
            }
            let ratio = phi / theta;
            if !(1.0 / 3.0..=3.0).contains(&ratio) {
                return false;
            }
            let [p, q] = topo.edge(n);
            (mesh.position(q) - mesh.position(p))
                .try_normalize(0.0)
                .is_some_and(|d| d.dot(&dir).abs() >= parallel)
        })
    })
}
