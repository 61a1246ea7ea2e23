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
//!    spread of angles, no gap, and then no creases. When none of the edges below the gap
//!    is a tessellation edge (step 3), the mesh has no curved faces: all its faces are
//!    planes and every edge above [`FLAT_ANGLE`] is a crease of the design (a roof ridge of
//!    5° on a block whose other edges turn by 90° is one edge, no population of its own).
//!    *Noise* (step 2b, [`filtered_normals`]): a scan of a machined part has noise on its
//!    faces that spreads their angles over the gap (at noise of 0.1 of the mean edge, 50° to
//!    68° inside planar faces, 38° to 50° on sharp edges). When there is no gap and the faces
//!    turn from their neighbours by at least [`NOISE_ROUGHNESS`] ([`roughness`]), the face
//!    normals are smoothed within the faces and not across the creases (a guided bilateral
//!    filter, see [`filtered_normals`]), and the gap is looked for again in the angles between
//!    them; the polyhedral rule above does not apply (noisy faces are no exact planes). The
//!    gaps considered end above the roughness: a crease the noise hid turns more than the
//!    noise turns the faces, and a gap below that is the filter's own (it evens the normals
//!    of a coarse smooth mesh into facets: a torus of 60 × 20 quads, roughness 6.2°, got one
//!    from 1° to 1.5°). Scans of smooth shapes and noisy smooth surfaces have no gap in these
//!    either (all the shared meshes; the public analytic cases, the 46 noisy ones made alike
//!    for issue 19 and 38 more with noise of 0.15 and 0.3 of the mean edge; coarse tori and
//!    capsules).
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
//!    [`CreaseOptions::min_length`] times the model size ([`TriMesh::model_size`]: the
//!    bounding-box diagonal of the largest part) are dropped; the rule is
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

use super::{FeatureLine, FeatureLines, LineKind, SurfacePoint};
use crate::error::{Error, Result};
use crate::mesh::TriMesh;

mod chain;
mod detect;
mod normals;
#[cfg(test)]
mod tests;

pub use chain::{chain_crease_edges, cone_points, drop_stray_curves};
pub use detect::{
    FLAT_ANGLE, Gap, MAX_CHORD_DEVIATION, MAX_FACET_TURN, dihedral_angles, dihedral_angles_between,
    gap_threshold, gap_thresholds, is_facet_edge,
};
pub use normals::{CONSISTENT, ITERATIONS, NOISE_ROUGHNESS, RANGE, filtered_normals, roughness};

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
    /// diagonal ([`TriMesh::model_size`]) are dropped (stray edges of a tessellation).
    ///
    /// Default: 0.01 (as the minimum length of crest lines).
    pub min_length: f64,
    /// A curve ends where it turns by more than this many degrees from one edge to the next
    /// (a corner where only two crease edges meet). A tessellator cuts a curved sharp edge
    /// into at least 8 pieces per turn (45° each).
    ///
    /// Default: 50.
    pub corner_angle: f64,
    /// With [`CreaseAngle::Auto`]: when the dihedral angles have no gap, look for one again in
    /// the angles between filtered face normals ([`filtered_normals`]; module docs, step 2b),
    /// so that a noisy scan of a machined part has its creases.
    ///
    /// Default: true.
    pub filter_noise: bool,
}

impl CreaseOptions {
    /// The default options (see each field).
    pub const DEFAULT: Self = CreaseOptions {
        angle: CreaseAngle::Auto,
        min_length: 0.01,
        corner_angle: 50.0,
        filter_noise: true,
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
    /// True when the threshold and the curves come from the angles between filtered normals
    /// (module docs, step 2b: the mesh's own angles had no gap).
    pub filtered: bool,
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
            filtered: false,
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

    /// The edges the curvature fits and the extremality smoothing do not reach across (per
    /// edge of [`crate::mesh::Topology::edges`]), or `None` when there are none: the kept
    /// crease edges, and the non-manifold edges of `mesh` (three or more faces: a wall
    /// meeting a face, two parts glued along an edge), crease or not. Across a non-manifold
    /// edge the surface goes on in several sheets; a disc that read them all would fit one
    /// surface through a T (on a cube with an inner wall, the faces beside the wall came out
    /// with 11 ridges and 4 valleys). Each sheet is then fitted on its own, as each side of a
    /// crease is ([`crate::curvature::estimate_split`]).
    pub fn barriers(&self, mesh: &TriMesh) -> Option<Vec<bool>> {
        let topo = mesh.topology();
        let mut barriers = if self.is_empty() {
            vec![false; topo.num_edges()]
        } else {
            self.edges.clone()
        };
        let mut any = !self.is_empty();
        for (e, barrier) in barriers.iter_mut().enumerate() {
            if topo.edge_faces(e as u32).len() > 2 {
                *barrier = true;
                any = true;
            }
        }
        any.then_some(barriers)
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
        let diagonal = mesh.model_size();
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
            let size = mesh.model_size();
            if let Some(gap) = crease_gap(mesh, &angles, &lengths, size, 0.0) {
                let t = polyhedral_threshold(mesh, &angles, gap.threshold, size);
                return Ok(creases_above(mesh, &angles, Some(t), options, size));
            }
            return Ok(if options.filter_noise {
                creases_between_filtered_normals(mesh, &lengths, options, size)
            } else {
                Creases::none(topo.num_edges())
            });
        }
    };
    if threshold.is_none() {
        return Ok(Creases::none(topo.num_edges()));
    }
    let angles = dihedral_angles(mesh);
    Ok(creases_above(
        mesh,
        &angles,
        threshold,
        options,
        mesh.model_size(),
    ))
}

/// Step 2b (module docs): the creases of a mesh whose dihedral angles have no gap, from the
/// angles between filtered normals, when it is rough enough for noise to have hidden one.
/// The filtered faces are no exact planes: no polyhedral rule.
fn creases_between_filtered_normals(
    mesh: &TriMesh,
    lengths: &[f64],
    options: &CreaseOptions,
    diagonal: f64,
) -> Creases {
    let rough = roughness(mesh);
    if rough < NOISE_ROUGHNESS.to_radians() {
        return Creases::none(mesh.topology().num_edges());
    }
    let angles = dihedral_angles_between(mesh, &filtered_normals(mesh));
    let t = crease_gap(mesh, &angles, lengths, diagonal, rough).map(|gap| gap.threshold);
    let mut creases = creases_above(mesh, &angles, t, options, diagonal);
    creases.filtered = t.is_some();
    creases
}

/// The gap of the automatic threshold: the lowest of the [`gap_thresholds`] ending above
/// `floor` (radians; the widest gap, which the others are measured against, may lie below it)
/// above which the edges up to the next gap are not mostly (by length) tessellation edges
/// ([`is_facet_edge`]):
/// a gap inside the spread of a tessellation's angles is not the one below the creases (the
/// facets of a chamfer's cone and a hole's fillet, 1° to 15°, left a thin stretch about 2°
/// on a bracket, above which every facet of the cone was taken for a crease). `None` when
/// there is no gap or only tessellation edges above every gap. `diagonal`: the model size.
fn crease_gap(
    mesh: &TriMesh,
    angles: &[f64],
    lengths: &[f64],
    diagonal: f64,
    floor: f64,
) -> Option<Gap> {
    let gaps = gap_thresholds(angles, lengths);
    (0..gaps.len())
        .filter(|&k| gaps[k].to > floor)
        .find(|&k| {
            let (low, high) = (gaps[k].to, gaps.get(k + 1).map(|g| g.from));
            let (mut facets, mut all) = (0.0, 0.0);
            for (e, (&a, &l)) in angles.iter().zip(lengths).enumerate() {
                let a = a.abs();
                if a > low && high.is_none_or(|h| a <= h) {
                    all += l;
                    if is_facet_edge(mesh, angles, e as u32, diagonal) {
                        facets += l;
                    }
                }
            }
            facets < 0.5 * all
        })
        .map(|k| gaps[k])
}

/// The automatic threshold `t` (radians), or [`FLAT_ANGLE`] when none of the edges between
/// the two (the low side of the gap) is a tessellation edge ([`is_facet_edge`]): the mesh
/// has no curved face then, only planes, and every edge that turns is a crease of the
/// design (module docs, step 2). `diagonal`: the model size.
fn polyhedral_threshold(mesh: &TriMesh, angles: &[f64], t: f64, diagonal: f64) -> f64 {
    let flat = FLAT_ANGLE.to_radians();
    let mut below = (0..angles.len() as u32).filter(|&e| {
        let a = angles[e as usize].abs();
        a > flat && a <= t
    });
    let tessellated = below
        .clone()
        .any(|e| is_facet_edge(mesh, angles, e, diagonal));
    if below.next().is_some() && !tessellated {
        flat
    } else {
        t
    }
}

fn edge_lengths(mesh: &TriMesh) -> Vec<f64> {
    mesh.topology()
        .edges()
        .par_iter()
        .map(|&[a, b]| (mesh.position(b) - mesh.position(a)).norm())
        .collect()
}

/// Steps 3 to 5 for a threshold in radians; `diagonal`: the model size.
fn creases_above(
    mesh: &TriMesh,
    angles: &[f64],
    threshold: Option<f64>,
    options: &CreaseOptions,
    diagonal: f64,
) -> Creases {
    let Some(t) = threshold else {
        return Creases::none(mesh.topology().num_edges());
    };
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
        filtered: false,
        edges,
        curves,
        dropped,
        cones,
    }
}
