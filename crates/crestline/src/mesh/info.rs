//! A mesh's health report: counts of everything that makes real meshes awkward.

use serde::Serialize;

use super::{EdgeKind, TriMesh, VertexKind, mean_edge_length};

/// Counts and bounds of a mesh, as `crestline info` prints them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshInfo {
    /// Vertices, including unreferenced ones.
    pub vertices: usize,
    /// Triangles kept (after fan triangulation and dropping degenerate ones).
    pub faces: usize,
    /// Undirected edges.
    pub edges: usize,
    /// Vertices no face uses.
    pub unreferenced_vertices: usize,
    /// Used vertices at bitwise the position of an earlier used vertex: pieces exported side
    /// by side (see [`super::weld_coincident`], which merges them).
    pub coincident_vertices: usize,
    /// Triangles dropped for a repeated index or zero area.
    pub degenerate_faces: usize,
    /// Edges with one face.
    pub boundary_edges: usize,
    /// Closed loops of boundary edges.
    pub boundary_loops: usize,
    /// Edges with three or more faces.
    pub non_manifold_edges: usize,
    /// Vertices whose faces form several fans or that touch a non-manifold edge.
    pub non_manifold_vertices: usize,
    /// Connected components (faces sharing a vertex are connected).
    pub components: usize,
    /// Closed components, and open ones with holes small enough to have an inside, whose
    /// triangles face inward (negative volume; once wound consistently, see
    /// [`super::orient_outward`]).
    pub inward_components: usize,
    /// Components in which some triangles are wound against their neighbours.
    pub inconsistent_components: usize,
    /// Triangles wound against the rest of their patch (those [`super::orient_outward`]
    /// reverses first).
    pub rewound_faces: usize,
    /// Patches that cannot be wound consistently (non-orientable: a Möbius strip).
    pub non_orientable_patches: usize,
    /// V - E + F over referenced vertices.
    pub euler_characteristic: i64,
    /// No boundary edges and no non-manifold edges.
    pub closed: bool,
    /// Smallest corner of the bounding box of referenced vertices.
    pub bbox_min: [f64; 3],
    /// Largest corner.
    pub bbox_max: [f64; 3],
    /// Length of the bounding-box diagonal.
    pub diagonal: f64,
    /// The size relative lengths of the feature-line pipeline are fractions of: the diagonal
    /// of the largest connected component ([`TriMesh::model_size`]); the diagonal when the
    /// mesh is one piece.
    pub model_size: f64,
    /// Mean length of the edges.
    pub mean_edge_length: f64,
    /// The spacing along x, y and z of the grid a marching-cubes mesh left as marching cubes
    /// made it lies on ([`super::find_lattice`]); `None` for any other mesh.
    pub marching_cubes_grid: Option<[f64; 3]>,
}

impl MeshInfo {
    /// Computes the report.
    pub fn of(mesh: &TriMesh) -> Self {
        let topo = mesh.topology();
        let unreferenced = topo.count_vertices(VertexKind::Unreferenced);
        let boundary_edges = topo.count_edges(EdgeKind::Boundary);
        let non_manifold_edges = topo.count_edges(EdgeKind::NonManifold);
        let (orientation, _) = super::orientation(mesh);
        let bbox = mesh.bounding_box();
        let euler = (mesh.num_vertices() - unreferenced) as i64 - topo.num_edges() as i64
            + mesh.num_faces() as i64;
        MeshInfo {
            vertices: mesh.num_vertices(),
            faces: mesh.num_faces(),
            edges: topo.num_edges(),
            unreferenced_vertices: unreferenced,
            coincident_vertices: super::coincident_vertices(mesh),
            degenerate_faces: mesh.degenerate_faces(),
            boundary_edges,
            boundary_loops: topo.boundary_loops(mesh.faces()),
            non_manifold_edges,
            non_manifold_vertices: topo.count_vertices(VertexKind::NonManifold),
            components: orientation.components,
            inward_components: orientation.inward,
            inconsistent_components: orientation.inconsistent,
            rewound_faces: orientation.rewound_faces,
            non_orientable_patches: orientation.non_orientable,
            euler_characteristic: euler,
            closed: boundary_edges == 0 && non_manifold_edges == 0 && mesh.num_faces() > 0,
            bbox_min: bbox.min,
            bbox_max: bbox.max,
            diagonal: bbox.diagonal(),
            model_size: mesh.model_size(),
            mean_edge_length: mean_edge_length(mesh),
            marching_cubes_grid: super::find_lattice(mesh).map(|lattice| lattice.spacing),
        }
    }
}

impl std::fmt::Display for MeshInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "vertices               {}", self.vertices)?;
        writeln!(f, "faces                  {}", self.faces)?;
        writeln!(f, "edges                  {}", self.edges)?;
        writeln!(f, "unreferenced vertices  {}", self.unreferenced_vertices)?;
        writeln!(f, "coincident vertices    {}", self.coincident_vertices)?;
        writeln!(
            f,
            "degenerate faces       {} (dropped)",
            self.degenerate_faces
        )?;
        writeln!(f, "boundary edges         {}", self.boundary_edges)?;
        writeln!(f, "boundary loops         {}", self.boundary_loops)?;
        writeln!(f, "non-manifold edges     {}", self.non_manifold_edges)?;
        writeln!(f, "non-manifold vertices  {}", self.non_manifold_vertices)?;
        writeln!(f, "components             {}", self.components)?;
        writeln!(
            f,
            "facing inward          {} components",
            self.inward_components
        )?;
        writeln!(
            f,
            "inconsistent winding   {} components ({} triangles against their neighbours)",
            self.inconsistent_components, self.rewound_faces
        )?;
        writeln!(
            f,
            "non-orientable         {} patches",
            self.non_orientable_patches
        )?;
        writeln!(f, "euler characteristic   {}", self.euler_characteristic)?;
        writeln!(
            f,
            "closed                 {}",
            if self.closed { "yes" } else { "no" }
        )?;
        let [a, b, c] = self.bbox_min;
        let [x, y, z] = self.bbox_max;
        writeln!(
            f,
            "bounding box           ({a:.6}, {b:.6}, {c:.6}) .. ({x:.6}, {y:.6}, {z:.6})"
        )?;
        writeln!(f, "diagonal               {:.6}", self.diagonal)?;
        writeln!(
            f,
            "model size             {:.6}{}",
            self.model_size,
            if self.components > 1 {
                " (diagonal of the largest part)"
            } else {
                ""
            }
        )?;
        writeln!(f, "mean edge length       {:.6}", self.mean_edge_length)?;
        match self.marching_cubes_grid {
            None => write!(f, "marching cubes grid    none"),
            Some([x, y, z]) => write!(
                f,
                "marching cubes grid    spacing {x:.6} x {y:.6} x {z:.6} (every vertex on an edge of \
                 it, as marching cubes leaves them: their terraces come out as crest lines)"
            ),
        }
    }
}
