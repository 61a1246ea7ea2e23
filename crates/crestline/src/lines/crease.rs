//! Sharp creases: chains of mesh edges whose dihedral angle is above a threshold that is found
//! from the mesh itself, joined into curves from corner to corner.
//!
//! Crest lines are the extrema of a curvature that a smooth surface has; the sharp edges of a
//! CAD part have none (the curvature is a Dirac there), and a tessellation with long thin fans
//! has no vertex inside a planar face from which a curvature could be estimated. The edges of
//! the tessellation that lie on a sharp edge are found directly instead (as the "sharp edge"
//! filters of MeshLab and of CGAL's `detect_sharp_edges` do), and [`crate::lines::merge`] puts
//! them into one line set with the crest lines of the smooth parts.
//!
//! **Steps** ([`find_creases`] runs them in order):
//! 1. *Dihedral angles* ([`dihedral_angles`]): the signed angle between the normals of the two
//!    faces of every manifold edge, positive where the surface is convex. Boundary and
//!    non-manifold edges get NaN and are never creases.
//! 2. *Threshold* ([`gap_threshold`], unless an angle is given): a tessellation of a CAD part
//!    has two populations of edges, those inside faces (zero on planes, a few degrees on
//!    curved faces, bounded by the tessellator's chordal and angular tolerances) and those on
//!    sharp edges (the angles of the design, tens of degrees); between them the histogram of
//!    the angles is empty. The search looks for that gap on a logarithmic scale (so that it
//!    means the same at 2° and at 40°), with each edge counted by its length (so that it does
//!    not depend on how finely the faces are cut). A scanned or smooth mesh has a continuous
//!    spread of angles, no gap, and then no creases.
//! 3. *Tessellation edges* ([`is_facet_edge`]): a coarse tessellation of a cylinder or a fillet
//!    turns by the same few degrees at every edge across the surface, and can stand above the
//!    gap on its own (a cylinder exported as 54 facets has only flat edges and 6.7° edges). Such
//!    an edge has, at the far corner of one of its triangles, a nearly parallel edge turning the
//!    same way by a comparable angle; a crease is flanked by faces that turn much less. Edges
//!    turning by less than [`MAX_FACET_TURN`] with such a neighbour are not creases.
//! 4. *Curves* ([`chain_crease_edges`]): the crease edges are chained into polylines that end
//!    at corners (a vertex with one or three or more crease edges, a turn sharper than
//!    [`CreaseOptions::corner_angle`], a change from convex to concave) or close into loops.
//! 5. *Stray edges* ([`drop_stray_curves`]): connected sets of crease curves shorter than
//!    [`CreaseOptions::min_length`] times the bounding-box diagonal are dropped; the rule is
//!    in model units, so it does not depend on the triangulation.
//!
//! Each curve is convex (the ridge family) or concave (the valley family) by the sign of its
//! dihedral angles, weighted by length.
//!
//! **Limits.** A crease shallower than the steepest tessellation angle of the curved faces of
//! the same mesh cannot be told from them by angle; creases that cut across triangles (a
//! remeshed or scanned part whose triangulation ignores its sharp edges, like the shared
//! rocker arm) leave no gap and are left to the crest lines; two parallel creases one triangle
//! apart turning by the same angle below [`MAX_FACET_TURN`] look like the facets of a fillet.

use rayon::prelude::*;

use super::assemble::chain_links;
use super::{FeatureLine, FeatureLines, LineKind, SurfacePoint};
use crate::error::{Error, Result};
use crate::mesh::{TriMesh, Vec3, face_normals};

/// How the crease threshold is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum CreaseAngle {
    /// From the gap in the histogram of dihedral angles ([`gap_threshold`]); no creases when
    /// there is no gap.
    #[default]
    Auto,
    /// Edges whose dihedral angle exceeds this many degrees (in (0, 180)).
    Degrees(f64),
    /// No creases.
    Off,
}

/// Options of [`find_creases`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreaseOptions {
    /// The threshold on the dihedral angle.
    ///
    /// Default: [`CreaseAngle::Auto`].
    pub angle: CreaseAngle,
    /// Connected sets of crease curves shorter than this fraction of the bounding-box
    /// diagonal are dropped (stray edges of a tessellation).
    ///
    /// Default: 0.01 (as the minimum length of crest lines).
    pub min_length: f64,
    /// A curve ends where it turns by more than this many degrees from one edge to the next
    /// (a corner where only two crease edges meet). A tessellator cuts a curved sharp edge
    /// into at least 8 pieces per turn (45° each).
    ///
    /// Default: 50.
    pub corner_angle: f64,
}

impl CreaseOptions {
    /// The default options (see each field).
    pub const DEFAULT: Self = CreaseOptions {
        angle: CreaseAngle::Auto,
        min_length: 0.01,
        corner_angle: 50.0,
    };

    /// Sets [`CreaseOptions::angle`].
    pub fn with_angle(mut self, angle: CreaseAngle) -> Self {
        self.angle = angle;
        self
    }

    fn validate(&self) -> Result<()> {
        if let CreaseAngle::Degrees(d) = self.angle
            && !(d.is_finite() && d > 0.0 && d < 180.0)
        {
            return Err(Error::InvalidInput(format!(
                "crease angle must be between 0 and 180 degrees, got {d}"
            )));
        }
        if !(self.min_length.is_finite() && self.min_length >= 0.0) {
            return Err(Error::InvalidInput(format!(
                "crease minimum length must be a non-negative number, got {}",
                self.min_length
            )));
        }
        if !(self.corner_angle.is_finite() && (0.0..=180.0).contains(&self.corner_angle)) {
            return Err(Error::InvalidInput(format!(
                "crease corner angle must be between 0 and 180 degrees, got {}",
                self.corner_angle
            )));
        }
        Ok(())
    }
}

impl Default for CreaseOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A crease curve: a chain of crease edges.
#[derive(Debug, Clone, PartialEq)]
pub struct CreaseCurve {
    /// Mesh vertices in order; a closed curve does not repeat its first vertex.
    pub vertices: Vec<u32>,
    /// True when the last vertex joins the first.
    pub closed: bool,
    /// Convex (ridge family) or concave (valley family), by the length-weighted sign of the
    /// dihedral angles.
    pub convex: bool,
    /// Length in model units.
    pub length: f64,
    /// `∫ |θ| ds` along the curve (θ the dihedral angle in radians), model units.
    pub turning: f64,
}

impl CreaseCurve {
    /// A strength on the scale of the crest lines' `T = ∫ds · ∫C ds`, dimensionless:
    /// `(length / diagonal) · (turning / diagonal)`.
    pub fn strength(&self, diagonal: f64) -> f64 {
        if diagonal > 0.0 {
            self.length * self.turning / (diagonal * diagonal)
        } else {
            0.0
        }
    }
}

/// The creases of a mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Creases {
    /// The dihedral angle threshold used (degrees); `None` when creases are off or the
    /// automatic search found no gap.
    pub threshold: Option<f64>,
    /// Per edge of [`crate::mesh::Topology::edges`]: true for an edge of a kept crease curve.
    pub edges: Vec<bool>,
    /// The curves kept.
    pub curves: Vec<CreaseCurve>,
    /// Curves dropped as stray edges.
    pub dropped: usize,
    /// Cone points ([`cone_points`]): vertices where the surface comes to a point (the tip
    /// of a cone) without a crease.
    pub cones: Vec<u32>,
}

impl Creases {
    /// No creases on a mesh with `num_edges` edges.
    pub fn none(num_edges: usize) -> Self {
        Creases {
            threshold: None,
            edges: vec![false; num_edges],
            curves: Vec::new(),
            dropped: 0,
            cones: Vec::new(),
        }
    }

    /// True when no crease was kept (cone points do not count).
    pub fn is_empty(&self) -> bool {
        self.curves.is_empty()
    }

    /// Per vertex: true for a vertex on a kept crease edge or a cone point.
    pub fn vertices(&self, mesh: &TriMesh) -> Vec<bool> {
        let mut on = vec![false; mesh.num_vertices()];
        for &v in &self.cones {
            if let Some(x) = on.get_mut(v as usize) {
                *x = true;
            }
        }
        for c in &self.curves {
            for &v in &c.vertices {
                on[v as usize] = true;
            }
        }
        on
    }

    /// The curves as feature lines (`crease` set, points at the mesh vertices).
    pub fn lines(&self, mesh: &TriMesh) -> FeatureLines {
        let diagonal = mesh.bounding_box().diagonal();
        let lines = self
            .curves
            .iter()
            .map(|c| FeatureLine {
                kind: if c.convex {
                    LineKind::Ridge
                } else {
                    LineKind::Valley
                },
                points: c.vertices.iter().map(|&v| mesh.position(v)).collect(),
                locations: c
                    .vertices
                    .iter()
                    .map(|&v| SurfacePoint::Vertex(v))
                    .collect(),
                closed: c.closed,
                length: c.length,
                curvature_integral: if diagonal > 0.0 {
                    c.turning / diagonal
                } else {
                    0.0
                },
                strength: c.strength(diagonal),
                crease: true,
            })
            .collect();
        FeatureLines { lines }
    }
}

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
    let normals = face_normals(mesh);
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
fn runs_from(t: [u32; 3], a: u32, b: u32) -> bool {
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
/// widest one wins.
pub fn gap_threshold(angles: &[f64], lengths: &[f64]) -> Option<f64> {
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
    let widest = gaps.iter().map(|(i, j)| j - i).max()?;
    gaps.iter()
        .find(|(i, j)| 2 * (j - i) >= widest)
        .map(|(i, j)| (floor + step * (i + j) as f64 / 2.0).exp())
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

/// Relative difference below which two sides' angles (or areas) at a crease vertex count as
/// equal in [`widest_side`]: far above rounding (1e-16 of a sum of a few angles; a translation
/// by 1e4 of a unit model shifts positions by 1e-12 of their size) and far below any real
/// difference of a mesh.
pub const SIDE_TIE: f64 = 1e-9;

/// The faces at vertex `v` on its widest side: the faces around v joined across edges at v
/// that are not flagged in `crease_edges` (per edge), grouped into sides, and of those the one
/// with the largest total angle at v (ties up to [`SIDE_TIE`]: the larger area, then the side
/// whose centroid comes first in (x, y, z) order). All faces of v when no crease
/// edge meets it. A vertex on a crease is a sample of every side; its own fit and fields
/// describe this one (see [`crate::curvature::jet_fit`]).
pub fn widest_side(mesh: &TriMesh, v: u32, crease_edges: &[bool]) -> Vec<u32> {
    let topo = mesh.topology();
    let faces = topo.vertex_faces(v);
    // Union-find over the (few) faces at v.
    let mut side: Vec<usize> = (0..faces.len()).collect();
    fn root(side: &mut [usize], mut i: usize) -> usize {
        while side[i] != i {
            side[i] = side[side[i]];
            i = side[i];
        }
        i
    }
    for (i, &f) in faces.iter().enumerate() {
        for e in topo.face_edges(f) {
            let Some(&flag) = crease_edges.get(e as usize) else {
                continue;
            };
            let [a, b] = topo.edge(e);
            if flag || (a != v && b != v) {
                continue;
            }
            for &g in topo.edge_faces(e) {
                if let Some(j) = faces.iter().position(|&h| h == g) {
                    let (ri, rj) = (root(&mut side, i), root(&mut side, j));
                    side[ri] = rj;
                }
            }
        }
    }
    // Per side: total angle at v, area, and the sum of its face centroids taken from v.
    let p = mesh.position(v);
    let mut total = vec![0.0; faces.len()];
    let mut area = vec![0.0; faces.len()];
    let mut centroid = vec![Vec3::zeros(); faces.len()];
    for (i, &f) in faces.iter().enumerate() {
        let r = root(&mut side, i);
        let [a, b, c] = mesh.triangle(f as usize);
        total[r] += corner_angle(mesh, f, v);
        area[r] += 0.5 * (b - a).cross(&(c - a)).norm();
        centroid[r] += ((a - p) + (b - p) + (c - p)) / 3.0;
    }
    let roots: Vec<usize> = (0..faces.len())
        .filter(|&i| root(&mut side, i) == i)
        .collect();
    let widest = roots.iter().map(|&r| total[r]).fold(0.0, f64::max);
    // Angles equal up to rounding (a vertex on a straight crease between two flat sides has π
    // on each) are a tie: rounding changes with a translation and with the order of the faces,
    // and the choice must not. Ties go to the larger area (again up to rounding), then to the
    // side whose centroid comes first in (x, y, z) order.
    let tied = |x: f64, y: f64| (x - y).abs() <= SIDE_TIE * x.abs().max(y.abs());
    let Some(best) = roots
        .iter()
        .copied()
        .filter(|&r| tied(total[r], widest))
        .max_by(|&a, &b| {
            let by_area = if tied(area[a], area[b]) {
                std::cmp::Ordering::Equal
            } else {
                area[a].total_cmp(&area[b])
            };
            by_area.then_with(|| {
                let (ca, cb) = (centroid[a], centroid[b]);
                (cb.x.total_cmp(&ca.x))
                    .then(cb.y.total_cmp(&ca.y))
                    .then(cb.z.total_cmp(&ca.z))
            })
        })
    else {
        return Vec::new();
    };
    (0..faces.len())
        .filter(|&i| root(&mut side, i) == best)
        .map(|i| faces[i])
        .collect()
}

/// The angle of triangle `f` at its corner `v` (0 for a triangle that repeats `v`).
fn corner_angle(mesh: &TriMesh, f: u32, v: u32) -> f64 {
    let [a, b, c] = mesh.faces()[f as usize];
    let (q, r) = match v {
        _ if v == a => (b, c),
        _ if v == b => (c, a),
        _ if v == c => (a, b),
        _ => return 0.0,
    };
    if q == v || r == v {
        return 0.0;
    }
    let p = mesh.position(v);
    (mesh.position(q) - p).angle(&(mesh.position(r) - p))
}

/// Cone points: interior vertices whose angle deficit `2π − Σ angles` exceeds
/// [`MAX_FACET_TURN`] in magnitude and that no crease edge meets. A tessellation of a smooth
/// surface spreads its Gaussian curvature over many vertices; a cone's tip holds it all in one
/// (2.8 rad on a cone of half-angle 34°). Crest lines near one come from fits that straddle
/// the tip ([`crate::lines::merge`] cuts them).
pub fn cone_points(mesh: &TriMesh, crease_edges: &[bool]) -> Vec<u32> {
    let topo = mesh.topology();
    (0..mesh.num_vertices() as u32)
        .into_par_iter()
        .filter(|&v| {
            let edges = topo.vertex_edges(v);
            if edges.is_empty()
                || topo.vertex_kind(v) != crate::mesh::VertexKind::Interior
                || edges
                    .iter()
                    .any(|&e| crease_edges.get(e as usize).copied().unwrap_or(false))
            {
                return false;
            }
            let total: f64 = topo
                .vertex_faces(v)
                .iter()
                .map(|&f| corner_angle(mesh, f, v))
                .sum();
            (std::f64::consts::TAU - total).abs() > MAX_FACET_TURN.to_radians()
        })
        .collect()
}

/// Chains the edges flagged in `is_crease` into curves (see the module docs, step 4).
/// `angles` are those of [`dihedral_angles`]; `corner_angle` in degrees.
pub fn chain_crease_edges(
    mesh: &TriMesh,
    is_crease: &[bool],
    angles: &[f64],
    corner_angle: f64,
) -> Vec<CreaseCurve> {
    let topo = mesh.topology();
    let links: Vec<(usize, usize)> = topo
        .edges()
        .iter()
        .zip(is_crease)
        .filter(|(_, c)| **c)
        .map(|(&[a, b], _)| (a as usize, b as usize))
        .collect();
    let convex_of = |a: u32, b: u32| {
        topo.edge_between(a, b)
            .is_some_and(|e| angles[e as usize] > 0.0)
    };
    let cos_corner = corner_angle.to_radians().cos();
    // A corner at `v` between the edges u–v and v–w.
    let is_corner = |u: u32, v: u32, w: u32| {
        let (p, q, r) = (mesh.position(u), mesh.position(v), mesh.position(w));
        let turn = match ((q - p).try_normalize(0.0), (r - q).try_normalize(0.0)) {
            (Some(d0), Some(d1)) => d0.dot(&d1) < cos_corner,
            _ => false,
        };
        turn || convex_of(u, v) != convex_of(v, w)
    };
    let mut curves = Vec::new();
    for (path, closed) in chain_links(mesh.num_vertices(), &links) {
        let path: Vec<u32> = path.into_iter().map(|v| v as u32).collect();
        let n = path.len();
        if closed {
            let corners: Vec<usize> = (0..n)
                .filter(|&k| is_corner(path[(k + n - 1) % n], path[k], path[(k + 1) % n]))
                .collect();
            if corners.is_empty() {
                curves.push(build_curve(mesh, angles, path, true));
                continue;
            }
            // Rotate to start at a corner and cut there and at every other corner.
            let mut rotated: Vec<u32> = path[corners[0]..].to_vec();
            rotated.extend_from_slice(&path[..=corners[0]]);
            let cuts: Vec<usize> = corners
                .iter()
                .map(|&k| (k + n - corners[0]) % n)
                .chain([n])
                .collect();
            for pair in cuts.windows(2) {
                let piece = rotated[pair[0]..=pair[1]].to_vec();
                curves.push(build_curve(mesh, angles, piece, false));
            }
        } else {
            let mut start = 0;
            for k in 1..n.saturating_sub(1) {
                if is_corner(path[k - 1], path[k], path[k + 1]) {
                    curves.push(build_curve(mesh, angles, path[start..=k].to_vec(), false));
                    start = k;
                }
            }
            if n >= 2 {
                curves.push(build_curve(mesh, angles, path[start..].to_vec(), false));
            }
        }
    }
    curves
}

fn build_curve(mesh: &TriMesh, angles: &[f64], vertices: Vec<u32>, closed: bool) -> CreaseCurve {
    let topo = mesh.topology();
    let (mut length, mut turning, mut signed) = (0.0, 0.0, 0.0);
    let n = vertices.len();
    let segments = if closed { n } else { n.saturating_sub(1) };
    for k in 0..segments {
        let (a, b) = (vertices[k], vertices[(k + 1) % n]);
        let l = (mesh.position(b) - mesh.position(a)).norm();
        let theta = topo.edge_between(a, b).map_or(0.0, |e| angles[e as usize]);
        if theta.is_finite() {
            length += l;
            turning += theta.abs() * l;
            signed += theta * l;
        }
    }
    CreaseCurve {
        vertices,
        closed,
        convex: signed >= 0.0,
        length,
        turning,
    }
}

/// Drops the curves whose connected set of curves (curves sharing a vertex) is shorter than
/// `min_length` (model units). Returns the number of curves dropped.
pub fn drop_stray_curves(curves: &mut Vec<CreaseCurve>, min_length: f64) -> usize {
    // Union-find over the curves, joined through shared vertices.
    let mut parent: Vec<usize> = (0..curves.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut owner = std::collections::HashMap::new();
    for (i, c) in curves.iter().enumerate() {
        for &v in &c.vertices {
            if let Some(&j) = owner.get(&v) {
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri] = rj;
            } else {
                owner.insert(v, i);
            }
        }
    }
    let mut total = vec![0.0; curves.len()];
    for (i, c) in curves.iter().enumerate() {
        total[root(&mut parent, i)] += c.length;
    }
    let keep: Vec<bool> = (0..curves.len())
        .map(|i| total[root(&mut parent, i)] >= min_length)
        .collect();
    let before = curves.len();
    let mut k = 0;
    curves.retain(|_| {
        k += 1;
        keep[k - 1]
    });
    before - curves.len()
}

/// Finds the crease curves of `mesh` (all steps of the module docs).
///
/// # Errors
/// [`Error::InvalidInput`] for options out of range. A mesh never causes an error: a mesh
/// without manifold edges has no creases.
pub fn find_creases(mesh: &TriMesh, options: &CreaseOptions) -> Result<Creases> {
    options.validate()?;
    let topo = mesh.topology();
    let threshold = match options.angle {
        CreaseAngle::Off => None,
        CreaseAngle::Degrees(d) => Some(d.to_radians()),
        CreaseAngle::Auto => {
            let angles = dihedral_angles(mesh);
            let lengths = edge_lengths(mesh);
            let t = gap_threshold(&angles, &lengths);
            return Ok(creases_above(mesh, &angles, t, options));
        }
    };
    if threshold.is_none() {
        return Ok(Creases::none(topo.num_edges()));
    }
    let angles = dihedral_angles(mesh);
    Ok(creases_above(mesh, &angles, threshold, options))
}

fn edge_lengths(mesh: &TriMesh) -> Vec<f64> {
    mesh.topology()
        .edges()
        .par_iter()
        .map(|&[a, b]| (mesh.position(b) - mesh.position(a)).norm())
        .collect()
}

/// Steps 3 to 5 for a threshold in radians.
fn creases_above(
    mesh: &TriMesh,
    angles: &[f64],
    threshold: Option<f64>,
    options: &CreaseOptions,
) -> Creases {
    let Some(t) = threshold else {
        return Creases::none(mesh.topology().num_edges());
    };
    let diagonal = mesh.bounding_box().diagonal();
    let is_crease: Vec<bool> = (0..angles.len() as u32)
        .into_par_iter()
        .map(|e| {
            let a = angles[e as usize];
            a.is_finite() && a.abs() > t && !is_facet_edge(mesh, angles, e, diagonal)
        })
        .collect();
    let mut curves = chain_crease_edges(mesh, &is_crease, angles, options.corner_angle);
    let dropped = drop_stray_curves(&mut curves, options.min_length * diagonal);
    let topo = mesh.topology();
    let mut edges = vec![false; topo.num_edges()];
    for c in &curves {
        let n = c.vertices.len();
        let segments = if c.closed { n } else { n.saturating_sub(1) };
        for k in 0..segments {
            if let Some(e) = topo.edge_between(c.vertices[k], c.vertices[(k + 1) % n]) {
                edges[e as usize] = true;
            }
        }
    }
    let cones = if curves.is_empty() {
        Vec::new()
    } else {
        cone_points(mesh, &edges)
    };
    Creases {
        threshold: Some(t.to_degrees()),
        edges,
        curves,
        dropped,
        cones,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    /// A unit cube, each face two triangles, wound outward.
    fn cube() -> TriMesh {
        let p: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let faces = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        TriMesh::from_arrays(p, faces).unwrap()
    }

    #[test]
    fn cube_edges_are_twelve_convex_creases_between_corners() {
        let mesh = cube();
        let angles = dihedral_angles(&mesh);
        let right = angles
            .iter()
            .filter(|a| (**a - std::f64::consts::FRAC_PI_2).abs() < 1e-12)
            .count();
        assert_eq!(right, 12);
        assert_eq!(angles.iter().filter(|a| a.abs() < 1e-12).count(), 6);
        let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
        assert_eq!(creases.curves.len(), 12);
        assert!(creases.curves.iter().all(|c| c.convex && !c.closed));
        assert!(creases.curves.iter().all(|c| c.vertices.len() == 2));
        let t = creases.threshold.unwrap();
        assert!(t > FLAT_ANGLE && t < 90.0, "threshold {t}");
    }

    #[test]
    fn inward_cube_has_concave_creases() {
        let mesh = cube();
        let flipped: Vec<[u32; 3]> = mesh.faces().iter().map(|t| [t[0], t[2], t[1]]).collect();
        let mesh = TriMesh::new(mesh.positions().to_vec(), flipped).unwrap();
        let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
        assert_eq!(creases.curves.len(), 12);
        assert!(creases.curves.iter().all(|c| !c.convex));
    }

    #[test]
    fn smooth_meshes_have_no_gap() {
        for mesh in [shapes::icosphere(1.0, 3), shapes::torus(3.0, 1.0, 60, 20)] {
            let creases = find_creases(&mesh, &CreaseOptions::DEFAULT).unwrap();
            assert!(creases.is_empty(), "{:?}", creases.threshold);
        }
    }

    #[test]
    fn off_and_fixed_angles() {
        let mesh = cube();
        let off = CreaseOptions::DEFAULT.with_angle(CreaseAngle::Off);
        assert!(find_creases(&mesh, &off).unwrap().is_empty());
        let steep = CreaseOptions::DEFAULT.with_angle(CreaseAngle::Degrees(95.0));
        assert!(find_creases(&mesh, &steep).unwrap().is_empty());
        let right = CreaseOptions::DEFAULT.with_angle(CreaseAngle::Degrees(80.0));
        assert_eq!(find_creases(&mesh, &right).unwrap().curves.len(), 12);
        for bad in [0.0, 180.0, f64::NAN, -3.0] {
            let o = CreaseOptions::DEFAULT.with_angle(CreaseAngle::Degrees(bad));
            assert!(find_creases(&mesh, &o).is_err());
        }
    }

    #[test]
    fn boundary_edges_are_not_creases() {
        // Two triangles folded at 90 degrees: the fold is the only manifold edge.
        let mesh = TriMesh::from_arrays(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            vec![[0, 1, 2], [0, 3, 1]],
        )
        .unwrap();
        let angles = dihedral_angles(&mesh);
        assert_eq!(angles.iter().filter(|a| a.is_finite()).count(), 1);
        let fixed = CreaseOptions {
            min_length: 0.0,
            ..CreaseOptions::DEFAULT.with_angle(CreaseAngle::Degrees(45.0))
        };
        let creases = find_creases(&mesh, &fixed).unwrap();
        assert_eq!(creases.curves.len(), 1);
        assert_eq!(creases.edges.iter().filter(|e| **e).count(), 1);
    }

    #[test]
    fn gap_needs_populations_on_both_sides() {
        let flat = vec![0.0; 100];
        let ones = vec![1.0; 100];
        assert_eq!(gap_threshold(&flat, &ones), None);
        let mut angles = flat.clone();
        angles.extend([1.5; 12]);
        let lengths = vec![1.0; angles.len()];
        let t = gap_threshold(&angles, &lengths).unwrap().to_degrees();
        assert!(t > FLAT_ANGLE && t < 85.9, "{t}");
        // A continuous spread has no gap.
        let spread: Vec<f64> = (0..2000).map(|i| (i as f64 * 0.05).to_radians()).collect();
        assert_eq!(gap_threshold(&spread, &vec![1.0; 2000]), None);
    }

    #[test]
    fn stray_curves_are_dropped_by_length() {
        let mut curves = vec![
            CreaseCurve {
                vertices: vec![0, 1],
                closed: false,
                convex: true,
                length: 0.5,
                turning: 0.0,
            },
            CreaseCurve {
                vertices: vec![1, 2],
                closed: false,
                convex: true,
                length: 0.6,
                turning: 0.0,
            },
            CreaseCurve {
                vertices: vec![5, 6],
                closed: false,
                convex: true,
                length: 0.9,
                turning: 0.0,
            },
        ];
        assert_eq!(drop_stray_curves(&mut curves, 1.0), 1);
        assert_eq!(curves.len(), 2);
    }
}
