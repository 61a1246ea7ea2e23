//! Feature lines: ridges and valleys traced on a mesh, as plain polylines.
//!
//! The stages of HPW 2005 (Table 1, steps 4–7), one file each:
//! [`trace`] (regular triangles, sec. 4.1), [`singular`] (sec. 4.2), [`assemble`] (maximal
//! polylines and their strengths), [`filter`] (thresholds), [`fair`] (spatial fairing,
//! sec. 5.2). [`trace_lines`] runs steps 4–6 for both families.
//!
//! YBS 2005 trace edge by edge instead ([`trace_edges`], after Ohtake et al. 2004) and join
//! broken pieces by gap jumping ([`gap`]); [`trace_crest_lines`] runs that for both families.
//!
//! Sharp creases are not crest lines: [`crease`] finds them as chains of mesh edges with a
//! large dihedral angle, and [`merge`] puts them and the crest lines into one set
//! ([`FeatureLine::crease`] tells them apart).
//!
//! On noisy surfaces [`debias`] moves the traced crest lines by the known displacement of the
//! jet fit's wide disc; on surfaces with white noise [`located`] drops the lines the noise
//! moves about.

pub mod assemble;
pub mod crease;
pub mod debias;
pub mod fair;
pub mod filter;
pub mod gap;
pub mod link;
pub mod located;
pub mod merge;
pub mod singular;
pub mod trace;
pub mod trace_edges;

use crate::curvature::Curvature;
use crate::mesh::{TriMesh, Vec3};

pub use singular::SingularCases;

/// Ridge (convex crest) or valley (concave crest).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LineKind {
    /// `e_max = 0`, `de_max/dt_max < 0`, `k_max > |k_min|`.
    Ridge,
    /// `e_min = 0`, `de_min/dt_min > 0`, `k_min < -|k_max|`.
    Valley,
}

impl LineKind {
    /// The lowercase name files and bindings use for the kind (`"ridge"`, `"valley"`).
    pub fn name(self) -> &'static str {
        match self {
            LineKind::Ridge => "ridge",
            LineKind::Valley => "valley",
        }
    }

    /// The curvature condition of the kind: its own principal curvature `k` (`k_max` for
    /// ridges, `k_min` for valleys) dominates the other's, `k > |k_other|` for ridges and
    /// `k < −|k_other|` for valleys.
    pub fn dominates(self, k: f64, k_other: f64) -> bool {
        match self {
            LineKind::Ridge => k > k_other.abs(),
            LineKind::Valley => k < -k_other.abs(),
        }
    }
}

/// Where a line point sits on the mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SurfacePoint {
    /// On edge `edge` (an index into [`crate::mesh::Topology::edges`]) at parameter `t`
    /// from its first (smaller) endpoint to its second.
    Edge {
        /// Edge index.
        edge: u32,
        /// Parameter in [0, 1].
        t: f64,
    },
    /// Inside face `face` (for example the barycentre of a trisector triangle).
    Face {
        /// Face index.
        face: u32,
    },
    /// At a vertex.
    Vertex(u32),
}

/// One polyline.
#[derive(Debug, Clone, PartialEq)]
pub struct FeatureLine {
    /// Ridge or valley.
    pub kind: LineKind,
    /// Points in order. A closed line does not repeat its first point at the end.
    pub points: Vec<Vec3>,
    /// Mesh location of each point; empty when unknown (lines read from a file).
    pub locations: Vec<SurfacePoint>,
    /// True when the last point joins the first.
    pub closed: bool,
    /// Length in model units.
    pub length: f64,
    /// Integral of |k| (the dominant principal curvature) along the line (Ohtake et al. 2004).
    pub curvature_integral: f64,
    /// YBS strength T = ∫ds · ∫C ds with C the cyclideness (YBS eqs. 5, 6), both integrals
    /// over the part of the line that is a crest ([`assemble::measure_line`]); scale
    /// independent.
    /// For a crease curve: see [`crease::CreaseCurve::strength`].
    pub strength: f64,
    /// True for a sharp crease of the mesh ([`crease`]): a chain of mesh edges whose dihedral
    /// angle is above the crease threshold, `kind` saying whether it is convex (ridge
    /// family) or concave (valley family). False for a crest line.
    pub crease: bool,
}

impl FeatureLine {
    /// A line through `points` known by its points alone (a line read from a file, or drawn
    /// by hand): its length from the points (with the closing segment when `closed`), no
    /// mesh locations, zero curvature integral and strength, not a crease. Other values go
    /// in with struct update syntax: `FeatureLine { strength, ..FeatureLine::new(..) }`.
    pub fn new(kind: LineKind, points: Vec<Vec3>, closed: bool) -> Self {
        FeatureLine {
            kind,
            length: polyline_length(&points, closed),
            points,
            locations: Vec::new(),
            closed,
            curvature_integral: 0.0,
            strength: 0.0,
            crease: false,
        }
    }

    /// The name files and bindings use for the line's class: `"ridge"`, `"valley"`,
    /// `"crease-ridge"` or `"crease-valley"`.
    pub fn kind_name(&self) -> &'static str {
        match (self.kind, self.crease) {
            (LineKind::Ridge, false) => "ridge",
            (LineKind::Valley, false) => "valley",
            (LineKind::Ridge, true) => "crease-ridge",
            (LineKind::Valley, true) => "crease-valley",
        }
    }
}

/// Length of a polyline, with the closing segment when `closed`.
pub(crate) fn polyline_length(points: &[Vec3], closed: bool) -> f64 {
    let open: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    match (closed, points.first(), points.last()) {
        (true, Some(first), Some(last)) => open + (*first - *last).norm(),
        _ => open,
    }
}

/// All feature lines found on a mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FeatureLines {
    /// The polylines, ridges and valleys mixed.
    pub lines: Vec<FeatureLine>,
}

impl FeatureLines {
    /// Lines of one kind.
    pub fn of_kind(&self, kind: LineKind) -> impl Iterator<Item = &FeatureLine> {
        self.lines.iter().filter(move |l| l.kind == kind)
    }

    /// Crease curves (`crease` true), or crest lines (false).
    pub fn creases(&self, crease: bool) -> impl Iterator<Item = &FeatureLine> {
        self.lines.iter().filter(move |l| l.crease == crease)
    }

    /// Total length of all lines.
    pub fn total_length(&self) -> f64 {
        // A fold from +0: `sum` of no lines would be -0.
        self.lines.iter().fold(0.0, |total, l| total + l.length)
    }
}

/// What tracing found, per family.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraceReport {
    /// Singular triangles of the max family (ridges).
    pub singular_max: usize,
    /// Singular triangles of the min family (valleys).
    pub singular_min: usize,
    /// Segments traced in regular triangles (both families).
    pub regular_segments: usize,
    /// Singular-triangle cases of the max family.
    pub cases_max: SingularCases,
    /// Singular-triangle cases of the min family.
    pub cases_min: SingularCases,
}

/// Steps 4–6 of HPW without filtering: traces both families in regular triangles, continues
/// the lines through singular triangles and joins the segments into polylines. The two
/// families are traced side by side (each family's joining of segments is partly sequential);
/// the ridges come first in the result.
pub fn trace_lines(mesh: &TriMesh, curvature: &Curvature) -> (FeatureLines, TraceReport) {
    let trace_family = |kind| {
        let family = trace::Family::of(curvature, kind);
        let mut segments = trace::trace_regular_triangles(mesh, &family);
        let regular = segments.segments.len();
        let singular = segments.singular_count();
        let cases = singular::process_singular_triangles(mesh, &mut segments);
        let lines = assemble::assemble_lines(mesh, &family, &segments);
        (lines, regular, singular, cases)
    };
    let (
        (mut lines, regular_max, singular_max, cases_max),
        (valleys, regular_min, singular_min, cases_min),
    ) = rayon::join(
        || trace_family(LineKind::Ridge),
        || trace_family(LineKind::Valley),
    );
    lines.extend(valleys);
    let report = TraceReport {
        singular_max,
        singular_min,
        regular_segments: regular_max + regular_min,
        cases_max,
        cases_min,
    };
    (FeatureLines { lines }, report)
}

/// YBS tracing for both families: crest points edge by edge, joined inside triangles (three
/// at the centroid of the three points), then gap jumping ([`jump_crest_gaps`]) unless `gaps`
/// is `None`. Returns the lines and the number of gaps jumped (joins of two lines and
/// closings of one).
pub fn trace_crest_lines(
    mesh: &TriMesh,
    curvature: &Curvature,
    gaps: Option<&gap::GapJumping>,
) -> (FeatureLines, usize) {
    // The two families side by side, ridges first in the result.
    let trace_family = |kind| {
        let family = trace::Family::of(curvature, kind);
        let segments = trace_edges::trace_crest_edges(mesh, &family);
        let mut family_lines = assemble::assemble_lines(mesh, &family, &segments);
        trace_edges::place_junctions(mesh, &family, &mut family_lines);
        family_lines
    };
    let (mut ridges, valleys) = rayon::join(
        || trace_family(LineKind::Ridge),
        || trace_family(LineKind::Valley),
    );
    ridges.extend(valleys);
    let mut lines = FeatureLines { lines: ridges };
    let joins = gaps.map_or(0, |options| {
        jump_crest_gaps(mesh, curvature, &mut lines, options)
    });
    (lines, joins)
}

/// YBS's gap jumping ([`gap::jump_gaps`]) on ridges and valleys separately; lines keep their
/// order by kind (ridges first). Returns the number of gaps jumped.
pub fn jump_crest_gaps(
    mesh: &TriMesh,
    curvature: &Curvature,
    lines: &mut FeatureLines,
    options: &gap::GapJumping,
) -> usize {
    let mut joins = 0;
    let mut out = Vec::with_capacity(lines.lines.len());
    for kind in [LineKind::Ridge, LineKind::Valley] {
        let family = trace::Family::of(curvature, kind);
        let mut family_lines: Vec<FeatureLine> = lines
            .lines
            .iter()
            .filter(|l| l.kind == kind)
            .cloned()
            .collect();
        joins += gap::jump_gaps(mesh, &family, &mut family_lines, options);
        out.extend(family_lines);
    }
    lines.lines = out;
    joins
}

/// Arc length at each point, and the total (with the closing segment when `closed`) last.
pub(crate) fn arc_lengths(points: &[Vec3], closed: bool) -> Vec<f64> {
    let mut arc = Vec::with_capacity(points.len() + 1);
    arc.push(0.0);
    for w in points.windows(2) {
        arc.push(arc[arc.len() - 1] + (w[1] - w[0]).norm());
    }
    let closing = if closed {
        (points[0] - points[points.len() - 1]).norm()
    } else {
        0.0
    };
    arc.push(arc[arc.len() - 1] + closing);
    arc
}
