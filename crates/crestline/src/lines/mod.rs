//! Feature lines: ridges and valleys traced on a mesh, as plain polylines.

use crate::mesh::Vec3;

/// Ridge (convex crest) or valley (concave crest).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LineKind {
    /// `e_max = 0`, `de_max/dt_max < 0`, `k_max > |k_min|`.
    Ridge,
    /// `e_min = 0`, `de_min/dt_min > 0`, `k_min < -|k_max|`.
    Valley,
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
    /// YBS strength T = ∫ds · ∫C ds with C the cyclideness (YBS eqs. 5, 6); scale independent.
    pub strength: f64,
}

/// All feature lines found on a mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FeatureLines {
    /// The polylines, ridges and valleys mixed.
    pub lines: Vec<FeatureLine>,
}
