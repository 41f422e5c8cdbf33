//! Inputs for the extraction benchmarks, shared by the criterion benches and `meshflow bench`
//! so both time exactly the same work.

use glam::Vec3;

use crate::Mesh;
use crate::extract::{ExtractMethod, ExtractOptions, ExtractReport, FaceSupport, extract_mesh};
use crate::geometry::normals::vertex_normals;
use crate::geometry::primitives::icosphere;
use crate::geometry::topology::{Edge, edges};
use crate::rng::Rng;

/// Vertices with normals and an edge list: the input of [`extract_mesh`].
pub struct EdgeWorkload {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub edges: Vec<Edge>,
    /// The faces extraction must give back (ground-truth edges), or `None`.
    pub faces: Option<usize>,
}

impl EdgeWorkload {
    /// Extraction by `method` with default options on these edges (the timed work).
    pub fn extract(&self, method: ExtractMethod) -> (Mesh, ExtractReport) {
        let opts = ExtractOptions {
            method,
            ..Default::default()
        };
        extract_mesh(
            &self.positions,
            &self.normals,
            &self.edges,
            FaceSupport::Geometric,
            &opts,
        )
        .expect("a valid workload")
    }
}

/// The icosphere with `subdivisions` (162, 642, 2562, 10242 vertices for 2..=5) and its
/// ground-truth edges: extraction must give back its faces.
pub fn icosphere_edges(subdivisions: u32) -> EdgeWorkload {
    let m = icosphere(subdivisions);
    EdgeWorkload {
        normals: vertex_normals(&m.positions, &m.faces),
        edges: edges(&m.faces),
        faces: Some(m.faces.len()),
        positions: m.positions,
    }
}

/// `n` points spread evenly over the unit sphere (a Fibonacci lattice), each joined to its `k`
/// nearest neighbours: an over-connected graph whose 3-cliques overlap everywhere, like the
/// edges of an uncertain decoder (k = 8 gives about three times the faces of a triangulation).
pub fn over_connected_sphere(n: usize, k: usize) -> EdgeWorkload {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let positions: Vec<Vec3> = (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let a = golden * i as f32;
            Vec3::new(r * a.cos(), y, r * a.sin())
        })
        .collect();
    let mut edges = Vec::new();
    for (i, p) in positions.iter().enumerate() {
        let mut near: Vec<(f32, u32)> = (positions.iter().enumerate())
            .filter(|&(j, _)| j != i)
            .map(|(j, q)| (p.distance_squared(*q), j as u32))
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        edges.extend(
            near.iter()
                .take(k)
                .map(|&(_, j)| [j.min(i as u32), j.max(i as u32)]),
        );
    }
    edges.sort_unstable();
    edges.dedup();
    EdgeWorkload {
        normals: positions.clone(),
        positions,
        edges,
        faces: None,
    }
}

/// `n` x `dim` edge embeddings drawn from N(0, 0.12^2). With tau = 0.6 and dim 32 the edge
/// count grows with n (about 1 per vertex at n = 512, 24 at 4,096): denser than a decoded mesh,
/// so timings on it are on the safe side.
pub fn random_embeddings(n: usize, dim: usize, seed: u64) -> Vec<f32> {
    let mut rng = Rng::new(seed);
    (0..n * dim).map(|_| (rng.normal() * 0.12) as f32).collect()
}
