//! A mesh round-tripped through its own adjacency (`meshflow extract`): cleaned, put in the
//! model frame, its vertices ordered as the MeshVAE's tokens, its ground-truth edges renumbered
//! into that order and turned back into faces by [`extract_mesh`]. What comes back shows what
//! extraction loses, adds or flips on a perfect decoder's edges.

use std::fmt;

use serde::Serialize;

use crate::Mesh;
use crate::extract::{ExtractError, ExtractOptions, ExtractReport, FaceSupport, extract_mesh};
use crate::geometry::clean::{CleanOptions, CleanReport, clean};
use crate::geometry::normalize::Normalization;
use crate::geometry::normals::vertex_normals;
use crate::geometry::topology::{TopologyReport, rotate_min_first, sorted_face};
use crate::model::tokens::{token_edges, vertex_order};

/// What a round trip did to a mesh (serialised as `meshflow extract --json` prints it).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RoundTrip {
    /// What cleaning changed before the round trip.
    pub clean: CleanReport,
    /// Faces of the cleaned mesh, the reference for the counts below.
    pub faces: usize,
    /// Faces extraction produced.
    pub extracted_faces: usize,
    /// Faces of the cleaned mesh that extraction did not produce.
    pub lost_faces: usize,
    /// Extracted faces that the cleaned mesh does not have (non-face 3-cliques, filled holes).
    pub extra_faces: usize,
    /// Faces produced with the opposite winding (the normal rule disagrees with the source).
    pub flipped_faces: usize,
    /// Extraction's own report.
    pub extract: ExtractReport,
    /// Topology of the cleaned mesh.
    pub topology_before: TopologyReport,
    /// Topology of the extracted mesh.
    pub topology_after: TopologyReport,
}

/// The report as `meshflow extract` prints it under the file name.
impl fmt::Display for RoundTrip {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use crate::geometry::topology::json;
        writeln!(f, "  cleaned: {}", json(&self.clean))?;
        writeln!(
            f,
            "  faces: {} -> {} extracted ({} lost, {} extra, {} flipped)",
            self.faces, self.extracted_faces, self.lost_faces, self.extra_faces, self.flipped_faces
        )?;
        writeln!(f, "  extraction: {}", json(&self.extract))?;
        writeln!(f, "{}", self.topology_before.titled("topology before"))?;
        write!(f, "{}", self.topology_after.titled("topology after"))
    }
}

/// Why a mesh cannot be round-tripped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RoundTripError {
    /// The input has no faces, so no edges to extract from.
    #[error("a point cloud: extract needs a mesh with faces")]
    PointCloud,
    /// Nothing is left after cleaning.
    #[error("empty after cleaning")]
    Empty,
    /// Extraction refused the edges.
    #[error(transparent)]
    Extract(#[from] ExtractError),
}

/// Round-trips `mesh` with `options` (compaction is turned off so every vertex keeps its
/// number). Returns the extracted mesh, on the cleaned mesh's vertices and coordinates, and
/// the report.
pub fn round_trip(
    mesh: &Mesh,
    options: &ExtractOptions,
) -> Result<(Mesh, RoundTrip), RoundTripError> {
    if mesh.is_point_cloud() {
        return Err(RoundTripError::PointCloud);
    }
    let (cleaned, clean_report) = clean(mesh, &CleanOptions::default());
    let aabb = cleaned.aabb().ok_or(RoundTripError::Empty)?;
    let model_frame = Normalization::to_model_frame(aabb).apply_mesh(&cleaned);
    // The token layer without its features (which would cost ~1.4 KB per vertex): every vertex
    // is a token in the VAE's order, and the ground-truth adjacency is renumbered into it.
    let order = vertex_order(&model_frame.positions);
    let normals = vertex_normals(&model_frame.positions, &model_frame.faces);
    let token_positions: Vec<_> = order
        .iter()
        .map(|&v| model_frame.positions[v as usize])
        .collect();
    let token_normals: Vec<_> = order.iter().map(|&v| normals[v as usize]).collect();
    let edges = token_edges(&model_frame.faces, &order);
    // Keep every token (no compaction) so the report can compare with the source's faces.
    let opts = ExtractOptions {
        compact: false,
        ..options.clone()
    };
    let (out, extract_report) = extract_mesh(
        &token_positions,
        &token_normals,
        &edges,
        FaceSupport::Geometric,
        &opts,
    )?;
    // Back to the cleaned mesh's numbering and coordinates.
    let original = |t: u32| order[t as usize];
    let faces: Vec<[u32; 3]> = out.faces.iter().map(|f| f.map(original)).collect();
    let result = Mesh {
        positions: cleaned.positions.clone(),
        normals: Vec::new(),
        faces,
    };
    let diff = FaceDiff::of(&cleaned.faces, &result.faces);
    let report = RoundTrip {
        clean: clean_report,
        faces: cleaned.faces.len(),
        extracted_faces: result.faces.len(),
        lost_faces: diff.lost,
        extra_faces: diff.extra,
        flipped_faces: diff.flipped,
        extract: extract_report,
        topology_before: TopologyReport::of(&cleaned),
        topology_after: TopologyReport::of(&result),
    };
    Ok((result, report))
}

/// How two face lists on the same vertices differ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct FaceDiff {
    /// Faces of the reference missing from the other list (as vertex sets).
    lost: usize,
    /// Faces of the other list missing from the reference (as vertex sets).
    extra: usize,
    /// Faces of the other list that the reference has only with the opposite winding.
    flipped: usize,
}

impl FaceDiff {
    fn of(reference: &[[u32; 3]], got: &[[u32; 3]]) -> Self {
        let as_set = |faces: &[[u32; 3]]| {
            let mut v: Vec<[u32; 3]> = faces.iter().map(|&f| sorted_face(f)).collect();
            v.sort_unstable();
            v
        };
        let (before, after) = (as_set(reference), as_set(got));
        let lost = before
            .iter()
            .filter(|f| after.binary_search(f).is_err())
            .count();
        let extra = after
            .iter()
            .filter(|f| before.binary_search(f).is_err())
            .count();
        // Rotating the smallest index first keeps the winding, so (a, c, b) is the flip of (a, b, c).
        let mut oriented: Vec<[u32; 3]> = reference.iter().map(|&f| rotate_min_first(f)).collect();
        oriented.sort_unstable();
        let flipped = got
            .iter()
            .map(|&f| rotate_min_first(f))
            .filter(|f| {
                oriented.binary_search(f).is_err()
                    && oriented.binary_search(&[f[0], f[2], f[1]]).is_ok()
            })
            .count();
        Self {
            lost,
            extra,
            flipped,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::icosphere;

    #[test]
    fn face_diff_counts_lost_extra_and_flipped_faces() {
        let reference = [[0, 1, 2], [0, 2, 3], [1, 3, 2]];
        // Same first face rotated, the second flipped, the third lost, one new face.
        let got = [[1, 2, 0], [0, 3, 2], [0, 1, 3]];
        assert_eq!(
            FaceDiff::of(&reference, &got),
            FaceDiff {
                lost: 1,
                extra: 1,
                flipped: 1
            }
        );
        assert_eq!(FaceDiff::of(&reference, &reference), FaceDiff::default());
    }

    #[test]
    fn an_icosphere_comes_back_whole() {
        let sphere = icosphere(2);
        let (out, report) = round_trip(&sphere, &ExtractOptions::default()).unwrap();
        assert_eq!(out.positions.len(), sphere.positions.len());
        assert_eq!(report.faces, sphere.faces.len());
        assert_eq!(report.extracted_faces, sphere.faces.len());
        assert_eq!(
            (report.lost_faces, report.extra_faces, report.flipped_faces),
            (0, 0, 0)
        );
        assert!(report.topology_after.is_clean_closed());
        let text = report.to_string();
        assert!(text.contains("\n  faces: 320 -> 320 extracted (0 lost, 0 extra, 0 flipped)\n"));
        assert!(text.contains("\ntopology after\n  vertices                    162\n"));
    }

    #[test]
    fn a_point_cloud_is_refused() {
        let cloud = Mesh::from_points(vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y]);
        assert_eq!(
            round_trip(&cloud, &ExtractOptions::default()).unwrap_err(),
            RoundTripError::PointCloud
        );
    }
}
