//! Step 2b of [`find_creases`](super::find_creases): the face normals of a noisy mesh,
//! smoothed within the faces of the surface and not across its creases, so that the dihedral
//! angles between them have the gap of step 2 again.
//!
//! **Why.** A scan of a machined part has its sharp edges and noise on every face. Measured on
//! the public uniform parts of `../shared/quality/cad` moved along their normals by noise of
//! 0.05 and 0.1 of the mean edge: the dihedral angles of the edges inside planar faces reach
//! 50–68° at 0.1, those of the sharp edges go down to 38–50°, and the histogram has no gap. The
//! crest lines of the jet fit, widened by the noise, then stand in for the edges: two edges
//! closer than the disc (a chamfer) come out as one line between them, and the fit's response
//! to a kink puts spurious lines on the faces beside it.
//!
//! **The filter** is a joint bilateral filter of the face normals (Zheng, Fu, Au and Tai,
//! *Bilateral Normal Filtering for Mesh Denoising*, IEEE TVCG 2011, eq. 6) whose range weight
//! compares guidance normals rather than the noisy normals themselves, as in *Guided Mesh
//! Normal Filtering* (Zhang, Deng, Zhang, Bouaziz and Liu, Pacific Graphics 2015). It works
//! on the normals of one consistent winding ([`crate::mesh::orientation`]; a triangle wound
//! against its neighbours would otherwise be averaged into theirs and its edges read as
//! folds). Once: the spacing s_f of face f is the mean distance from its centroid to those
//! of the faces across its edges, and the patch of f is f and the faces that share a vertex
//! with it and whose centroids lie within [`PATCH_REACH`] s_f (on a regular mesh all of them;
//! in an open fan of slivers the nearby ones). Then [`ITERATIONS`] rounds of:
//! 1. *Patch means.* The mean normal of a patch is the area-weighted mean of its faces',
//!    its spread the area-weighted mean of their squared distances from it.
//! 2. *Guidance.* The guidance normal g_f is the mean of f's own patch, or, when a face of it
//!    has a patch of less than half that spread ([`CONSISTENT`]), the mean of the least
//!    spread such patch. A face beside a crease has a patch across it; the patch of its
//!    neighbour on the same side is far more consistent, and guides it with that side's
//!    normal. (Zhang et al. always take the most consistent patch; on a coarse smooth mesh,
//!    whose patches all spread alike, that choice follows small differences and breaks the
//!    normals into facets: the public coarse torus got 25 diagonals of creases.)
//! 3. *Filter.* `n_f ← normalize(A_f n_f + Σ_g A_g W_s(|c_f − c_g|) W_r(|g_f − g_g|) n_g)` over
//!    the other faces g of the patch (A the areas, c the centroids), with Gaussians `W_s` of
//!    width (s_f + s_g) / 2 (local, so that parts meshed at different densities are filtered
//!    alike) and `W_r` of width [`RANGE`].
//!
//! The guidance is what makes the filter robust: the range weights of a sliver, whose own
//! normal is off by tens of degrees on a clean irregular mesh, are those of its patch's mean
//! (its area weighs little in it), so it takes its neighbours' normal. Plain bilateral
//! filtering (the noisy normal as its own guidance) keeps such outliers, whose edges then stand
//! above a gap: the public irregular torus got 0.5 diagonals of creases.
//!
//! **Measured** (`score_cad.py --cases`, default HPW): the eight public uniform parts with
//! noise of 0.05 and 0.1 of the mean edge, mean F1 0.798 → 0.980 (BENCHMARKS.md, "Noisy
//! machined parts"); none of the shared meshes (scans, the smooth and the subdivided models)
//! nor of the public analytic cases, the 46 noisy ones made alike for issue 19 and 38 more
//! with noise of 0.15 and 0.3 of the mean edge gains a crease, nor do coarse tori and
//! capsules.

use rayon::prelude::*;

use super::detect::runs_from;
use crate::mesh::{TriMesh, Vec3, face_normal_and_area, orientation};

/// Step 2b runs on meshes whose [`roughness`] is at least this (degrees). Noise that turns
/// faces less leaves the gap of step 2: the noisy parts of the module docs keep it up to noise
/// of 0.04 of the mean edge (roughness about 3°) and lose it at 0.05 (3.7°). Below it the
/// filter's cost, about 1 µs per face (0.26 s on the 268K faces of igea, roughness 1.6°; a
/// horse of 3M faces from Loop subdivision, 0.45°), is not spent.
pub const NOISE_ROUGHNESS: f64 = 2.0;

/// Rounds of the filter.
pub const ITERATIONS: usize = 5;

/// Width of the range weight, in distance between unit normals (0.3: an angle of 17°). Noise
/// of 0.1 of the mean edge turns the normals of neighbouring faces by about this much; a
/// chamfer of 30° (a distance of 0.52) is 1.7 widths away (weight 0.22). Measured on the noisy parts of the
/// module docs: 0.4 mixed the hex nut's chamfers with its faces (F1 1.000 → 0.803 at noise
/// 0.05 of the mean edge).
pub const RANGE: f64 = 0.3;

/// A face's guidance comes from another patch when that patch spreads less than this share of
/// its own (module docs, step 2). Measured on the noisy parts: 0.25 gives the same lines
/// (mean F1 within 0.003); 1 (any less spread patch) broke the coarse public torus and
/// superquadric into facets.
pub const CONSISTENT: f64 = 0.5;

/// The face normals of `mesh` after the filter of the module docs (zero for degenerate faces,
/// as [`crate::mesh::face_normals`] gives them). The filter averages the normals of one
/// consistent winding ([`crate::mesh::orientation`]); each keeps the side of its own
/// triangle's winding, as [`super::dihedral_angles_between`] expects.
pub fn filtered_normals(mesh: &TriMesh) -> Vec<Vec3> {
    let faces = mesh.topology().faces();
    let (_, reversed) = orientation(mesh);
    let side = |f: usize| if reversed[f] { -1.0 } else { 1.0 };
    let (mut normals, areas): (Vec<Vec3>, Vec<f64>) = (0..faces.len())
        .into_par_iter()
        .map(|f| {
            let (n, area) = face_normal_and_area(mesh, f);
            (n * side(f), area)
        })
        .unzip();
    let centroids = centroids(mesh);
    let spacing = local_spacings(mesh, &centroids);
    let patches = Patches::new(mesh, &centroids, &spacing);
    let range = 0.5 / (RANGE * RANGE);
    for _ in 0..ITERATIONS {
        let means: Vec<(Vec3, f64)> = (0..faces.len())
            .into_par_iter()
            .map(|f| patch_mean(f, patches.of(f), &normals, &areas))
            .collect();
        let guidance: Vec<Vec3> = (0..faces.len())
            .into_par_iter()
            .map(|f| {
                let own = means[f];
                let best = patches
                    .of(f)
                    .iter()
                    .map(|&g| means[g as usize])
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .filter(|b| b.1 < CONSISTENT * own.1);
                best.unwrap_or(own).0
            })
            .collect();
        normals = (0..faces.len())
            .into_par_iter()
            .map(|f| {
                let n = normals[f];
                if n == Vec3::zeros() {
                    return n;
                }
                let mut sum = n * areas[f];
                for &g in patches.of(f) {
                    let g = g as usize;
                    // Twin faces (a triangle stored twice) have no spacing: weight 1.
                    let sigma = 0.5 * (spacing[f] + spacing[g]);
                    let d_s = (centroids[f] - centroids[g]).norm_squared()
                        / (2.0 * sigma * sigma).max(f64::MIN_POSITIVE);
                    let d_r = range * (guidance[f] - guidance[g]).norm_squared();
                    sum += normals[g] * (areas[g] * (-d_s - d_r).exp());
                }
                sum.try_normalize(0.0).unwrap_or(n)
            })
            .collect();
    }
    for (f, n) in normals.iter_mut().enumerate() {
        *n *= side(f);
    }
    normals
}

/// How far faces turn from their neighbours (radians): the median, over every k-th face (at
/// most 20,000 of them) with a normal and a neighbour, of the angle between the face's
/// normal and the area-weighted mean normal of the faces across its edges (wound alike).
/// On a smooth surface it falls with the size of the triangles; noise keeps it up (noise
/// along the normals of 0.05 of the mean edge: 3.7°; 0.1: 7.4°). See [`NOISE_ROUGHNESS`].
pub fn roughness(mesh: &TriMesh) -> f64 {
    let topo = mesh.topology();
    let n = topo.faces().len();
    // A median needs no more than a sample: every k-th face, about ROUGHNESS_SAMPLES of them.
    let stride = n.div_ceil(ROUGHNESS_SAMPLES).max(1);
    let mut angles: Vec<f64> = (0..n.div_ceil(stride))
        .into_par_iter()
        .filter_map(|k| {
            let f = k * stride;
            let (nf, _) = face_normal_and_area(mesh, f);
            if nf == Vec3::zeros() {
                return None;
            }
            let t = topo.faces()[f];
            let mut sum = Vec3::zeros();
            for s in 0..3 {
                let Some(g) = topo.face_across(f as u32, s) else {
                    continue;
                };
                let (ng, area) = face_normal_and_area(mesh, g as usize);
                // A neighbour wound the same way along the edge is wound against f.
                let flip = runs_from(topo.faces()[g as usize], t[s], t[(s + 1) % 3]);
                sum += ng * if flip { -area } else { area };
            }
            let m = sum.try_normalize(0.0)?;
            Some(nf.cross(&m).norm().atan2(nf.dot(&m)))
        })
        .collect();
    if angles.is_empty() {
        return 0.0;
    }
    let mid = angles.len() / 2;
    *angles.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// Faces [`roughness`] looks at, at most.
const ROUGHNESS_SAMPLES: usize = 20_000;

/// The centroid of every face.
fn centroids(mesh: &TriMesh) -> Vec<Vec3> {
    (0..mesh.num_faces())
        .into_par_iter()
        .map(|f| {
            let [a, b, c] = mesh.triangle(f);
            (a + b + c) / 3.0
        })
        .collect()
}

/// Area-weighted mean normal of face `f`'s patch and its spread (module docs, step 1); the
/// spread is infinite for a patch without area.
fn patch_mean(f: usize, others: &[u32], normals: &[Vec3], areas: &[f64]) -> (Vec3, f64) {
    let members = || std::iter::once(f).chain(others.iter().map(|&g| g as usize));
    let (sum, weight) = members().fold((Vec3::zeros(), 0.0), |(s, w), g| {
        (s + normals[g] * areas[g], w + areas[g])
    });
    let Some(mean) = sum.try_normalize(0.0) else {
        return (normals[f], f64::INFINITY);
    };
    let spread = members()
        .map(|g| areas[g] * (normals[g] - mean).norm_squared())
        .sum::<f64>()
        / weight;
    (mean, spread)
}

/// Per face, the mean distance from its centroid to those of the faces across its edges (0
/// for a face without such neighbours): the width of the spatial weight and the reach of
/// the patch, local so that parts meshed at different densities are filtered alike. (The
/// median was tried, to keep the patches of a closed fan small, see [`PATCH_REACH`]: the
/// noisy irregular spheres of issue 19 then got creases.)
fn local_spacings(mesh: &TriMesh, centroids: &[Vec3]) -> Vec<f64> {
    let topo = mesh.topology();
    (0..centroids.len() as u32)
        .into_par_iter()
        .map(|f| {
            let (sum, count) =
                topo.face_neighbors(f)
                    .into_iter()
                    .flatten()
                    .fold((0.0, 0.0), |(s, c), g| {
                        let d = (centroids[f as usize] - centroids[g as usize]).norm();
                        (s + d, c + 1.0)
                    });
            if count > 0.0 { sum / count } else { 0.0 }
        })
        .collect()
}

/// The other faces of every face's patch, in one array: those that share a vertex with it
/// and whose centroids lie within [`PATCH_REACH`] of its spacing ([`local_spacings`]).
struct Patches {
    offsets: Vec<usize>,
    faces: Vec<u32>,
}

/// A patch reaches this many times its face's spacing: on a regular mesh the faces that
/// share a vertex lie at 1, √3 and 2 spacings, all inside; in a fan of slivers around a
/// vertex of high valence (the pole of a capsule, an exported disc) only the nearby ones
/// are, so the patch stays local (the whole fan made a guidance of its mean, which evened
/// the first ring of a capsule into a crease) and small (a fan of n faces gave n² entries).
/// Finding them still reads every face around each corner: a fan of n faces costs n² distance
/// checks (about 1.4 ns each: 4.6 s for a fan of 40,000, measured in a review), which step 2b
/// pays only on a mesh without a gap and rough enough (an exported CAD fan has its gap). In a
/// closed fan (a pole), each sliver's third neighbour lies across the ring and widens its
/// spacing: patches of about a third of the fan (620 faces in a cone of 2,000 slivers; a noisy
/// sphere of 20,000 segments and 12 rings took 11 s and 1.5 GB in step 2b, measured in a
/// review). Left as is: the median spacing keeps them small but gave noisy irregular
/// spheres creases.
const PATCH_REACH: f64 = 2.5;

impl Patches {
    fn new(mesh: &TriMesh, centroids: &[Vec3], spacing: &[f64]) -> Self {
        let topo = mesh.topology();
        let triangles = topo.faces();
        // The faces around each corner, without f, without those met at an earlier corner,
        // and within reach.
        let around = |f: usize| {
            let t = triangles[f];
            let reach = (PATCH_REACH * spacing[f]).powi(2);
            (0..3).flat_map(move |k| {
                topo.vertex_faces(t[k]).iter().copied().filter(move |&g| {
                    let g = g as usize;
                    g != f
                        && !t[..k].iter().any(|v| triangles[g].contains(v))
                        && (centroids[g] - centroids[f]).norm_squared() <= reach
                })
            })
        };
        let counts: Vec<usize> = (0..triangles.len())
            .into_par_iter()
            .map(|f| around(f).count())
            .collect();
        let mut offsets = Vec::with_capacity(counts.len() + 1);
        offsets.push(0);
        for c in counts {
            offsets.push(offsets.last().copied().unwrap_or(0) + c);
        }
        let faces = (0..triangles.len())
            .into_par_iter()
            .flat_map_iter(around)
            .collect();
        Patches { offsets, faces }
    }

    fn of(&self, f: usize) -> &[u32] {
        &self.faces[self.offsets[f]..self.offsets[f + 1]]
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A flat grid of `n × n` squares in z = 0, split into triangles.
    fn grid(n: u32) -> TriMesh {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.push(Vec3::new(i as f64, j as f64, 0.0));
            }
        }
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let a = j * (n + 1) + i;
                faces.push([a, a + 1, a + n + 2]);
                faces.push([a, a + n + 2, a + n + 1]);
            }
        }
        TriMesh::new(positions, faces).unwrap()
    }

    /// The grid folded into a roof along its middle column (x = n/2) turning by `fold`
    /// degrees, every vertex then moved along its normal by noise of `noise` mean edges
    /// ([`crate::shapes::with_normal_noise`] with `seed`).
    pub(in crate::lines::crease) fn noisy_roof(
        n: u32,
        fold: f64,
        noise: f64,
        seed: u64,
    ) -> TriMesh {
        let slope = (fold.to_radians() / 2.0).tan();
        let half = f64::from(n) / 2.0;
        let grid = grid(n);
        let positions = grid
            .positions()
            .iter()
            .map(|p| Vec3::new(p.x, p.y, slope * (half - (p.x - half).abs())))
            .collect();
        crate::shapes::with_normal_noise(&grid.with_positions(positions).unwrap(), noise, seed)
            .unwrap()
    }

    #[test]
    fn the_filter_flattens_the_noise_and_keeps_the_fold() {
        let mesh = noisy_roof(30, 40.0, 0.1, 1);
        let topo = mesh.topology();
        // The fold: the middle column (15) of the 31 × 31 vertices.
        let on_fold = |e: usize| topo.edge(e as u32).iter().all(|v| v % 31 == 15);
        let raw = super::super::dihedral_angles(&mesh);
        let filtered = super::super::dihedral_angles_between(&mesh, &filtered_normals(&mesh));
        let median = |angles: &[f64], fold: bool| {
            let mut v: Vec<f64> = (0..angles.len())
                .filter(|&e| angles[e].is_finite() && on_fold(e) == fold)
                .map(|e| angles[e].abs().to_degrees())
                .collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let (raw_flat, flat) = (median(&raw, false), median(&filtered, false));
        let (raw_fold, fold) = (median(&raw, true), median(&filtered, true));
        assert!(
            raw_flat > 3.0,
            "the noise turns the faces by {raw_flat:.2} degrees"
        );
        assert!(
            flat < raw_flat / 4.0,
            "flat edges {raw_flat:.2} -> {flat:.2} degrees"
        );
        // The faces beside the fold mix a little across it (the range weight of 40° is
        // 0.08): measured 38.5 -> 32.7 degrees (flat edges 9.65 -> 0.49); 29 to 37 over 60
        // seeds.
        assert!(
            (25.0..42.0).contains(&fold),
            "fold {raw_fold:.1} -> {fold:.1} degrees"
        );
        assert!(roughness(&mesh).to_degrees() >= NOISE_ROUGHNESS);
    }

    fn patches(mesh: &TriMesh) -> Patches {
        let centroids = centroids(mesh);
        Patches::new(mesh, &centroids, &local_spacings(mesh, &centroids))
    }

    #[test]
    fn patches_hold_each_face_sharing_a_vertex_once() {
        let mesh = grid(4);
        let patches = patches(&mesh);
        let faces = mesh.topology().faces();
        for f in 0..faces.len() {
            let mut expected: Vec<u32> = (0..faces.len() as u32)
                .filter(|&g| {
                    g as usize != f && faces[g as usize].iter().any(|v| faces[f].contains(v))
                })
                .collect();
            let mut got = patches.of(f).to_vec();
            expected.sort_unstable();
            got.sort_unstable();
            assert_eq!(got, expected, "face {f}");
        }
        // An inner face of a regular grid touches 12 others.
        assert!((0..faces.len()).any(|f| patches.of(f).len() == 12));
    }

    #[test]
    fn patches_in_a_fan_of_slivers_stay_near() {
        // A disc of 200 slivers around its centre: each shares the centre with all others.
        let n = 200u32;
        let mut positions = vec![Vec3::zeros()];
        positions.extend((0..n).map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / f64::from(n);
            Vec3::new(a.cos(), a.sin(), 0.0)
        }));
        let faces = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
        let mesh = TriMesh::new(positions, faces).unwrap();
        let patches = patches(&mesh);
        for f in 0..n as usize {
            assert!(
                patches.of(f).len() <= 6,
                "face {f}: {}",
                patches.of(f).len()
            );
        }
    }

    #[test]
    fn a_triangle_wound_against_its_neighbours_keeps_its_side() {
        let mesh = noisy_roof(30, 40.0, 0.1, 1);
        let mut faces = mesh.faces().to_vec();
        for t in faces.iter_mut().step_by(13) {
            t.swap(1, 2);
        }
        let rewound = TriMesh::new(mesh.positions().to_vec(), faces).unwrap();
        let (a, b) = (filtered_normals(&mesh), filtered_normals(&rewound));
        for (f, t) in rewound.faces().iter().enumerate() {
            let expected = if f % 13 == 0 { -a[f] } else { a[f] };
            assert!((b[f] - expected).norm() < 1e-9, "face {f} {t:?}");
        }
        assert!((roughness(&mesh) - roughness(&rewound)).abs() < 1e-12);
    }

    #[test]
    fn degenerate_faces_keep_a_zero_normal() {
        let mesh = grid(3);
        let mut positions = mesh.positions().to_vec();
        // Vertex 1 onto the diagonal from vertex 0 to vertex 5: face 0, [0, 1, 5], has no
        // area (`with_positions` keeps the faces; `new` would drop it).
        positions[1] = Vec3::new(0.5, 0.5, 0.0);
        let mesh = mesh.with_positions(positions).unwrap();
        assert_eq!(mesh.faces()[0], [0, 1, 5]);
        let normals = filtered_normals(&mesh);
        assert_eq!(normals[0], Vec3::zeros());
        assert!(normals[1..].iter().all(|n| (n.norm() - 1.0).abs() < 1e-12));
        let empty = TriMesh::new(vec![Vec3::zeros(); 3], Vec::new()).unwrap();
        assert!(filtered_normals(&empty).is_empty());
        assert_eq!(roughness(&empty), 0.0);
    }
}
