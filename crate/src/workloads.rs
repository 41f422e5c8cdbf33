//! Inputs for the extraction benchmarks, shared by the criterion benches and `meshflow bench`
//! so both time exactly the same work.

use glam::Vec3;

use crate::Mesh;
use crate::extract::{ExtractOptions, ExtractReport, FaceSupport, extract_mesh};
use crate::normals::vertex_normals;
use crate::primitives::icosphere;
use crate::rng::Rng;
use crate::topology::{Edge, edges};

/// An icosphere with its ground-truth edges and area-weighted normals: extraction from these
/// edges must give back the icosphere's faces.
pub struct GroundTruthEdges {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub edges: Vec<Edge>,
    pub faces: usize,
}

impl GroundTruthEdges {
    /// Algorithm 1 with default options on these edges (the timed work).
    pub fn extract(&self) -> (Mesh, ExtractReport) {
        extract_mesh(
            &self.positions,
            &self.normals,
            &self.edges,
            FaceSupport::Geometric,
            &ExtractOptions::default(),
        )
        .expect("a valid icosphere")
    }
}

/// The icosphere with `subdivisions` (162, 642, 2562, 10242 vertices for 2..=5).
pub fn icosphere_edges(subdivisions: u32) -> GroundTruthEdges {
    let m = icosphere(subdivisions);
    GroundTruthEdges {
        normals: vertex_normals(&m.positions, &m.faces),
        edges: edges(&m.faces),
        faces: m.faces.len(),
        positions: m.positions,
    }
}

/// `n` x `dim` edge embeddings drawn from N(0, 0.12^2). With tau = 0.6 and dim 32 the edge
/// count grows with n (about 1 per vertex at n = 512, 24 at 4,096): denser than a decoded mesh,
/// so timings on it are on the safe side.
pub fn random_embeddings(n: usize, dim: usize, seed: u64) -> Vec<f32> {
    let mut rng = Rng::new(seed);
    (0..n * dim).map(|_| (rng.normal() * 0.12) as f32).collect()
}
