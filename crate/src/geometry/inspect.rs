//! The figures `meshflow inspect` reports for a mesh or point cloud: counts, bounding box,
//! surface area, the largest vertex degree and the topology report.

use std::fmt;

use glam::Vec3;
use serde::Serialize;

use crate::geometry::topology::{TopologyReport, adjacency, edges};
use crate::{Aabb, Mesh};

/// A mesh's summary (serialised as `meshflow inspect --json` prints it, after the file name).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Inspection {
    /// Vertex count.
    pub vertices: usize,
    /// Face count.
    pub faces: usize,
    /// True when there are no faces.
    pub point_cloud: bool,
    /// Whether per-vertex normals are present.
    pub has_normals: bool,
    /// Bounding box corners (zero for an empty mesh).
    pub bbox_min: [f32; 3],
    /// See `bbox_min`.
    pub bbox_max: [f32; 3],
    /// Total face area.
    pub surface_area: f64,
    /// Most edges at one vertex (0 without faces).
    pub max_vertex_degree: usize,
    /// The topology report.
    pub topology: TopologyReport,
}

impl Inspection {
    /// Measures `mesh` (which must satisfy [`Mesh::validate`]).
    pub fn of(mesh: &Mesh) -> Self {
        // An empty mesh has no box; report a point at the origin rather than fail.
        let aabb = mesh.aabb().unwrap_or(Aabb {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        });
        let degree = adjacency(mesh.positions.len(), &edges(&mesh.faces))
            .iter()
            .map(Vec::len)
            .max();
        Self {
            vertices: mesh.positions.len(),
            faces: mesh.faces.len(),
            point_cloud: mesh.is_point_cloud(),
            has_normals: !mesh.normals.is_empty(),
            bbox_min: aabb.min.to_array(),
            bbox_max: aabb.max.to_array(),
            surface_area: mesh.area(),
            max_vertex_degree: degree.unwrap_or(0),
            topology: TopologyReport::of(mesh),
        }
    }
}

/// The summary as `meshflow inspect` prints it under the file name.
impl fmt::Display for Inspection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = if self.point_cloud {
            "point cloud"
        } else {
            "triangle mesh"
        };
        let (v, faces, normals) = (self.vertices, self.faces, self.has_normals);
        writeln!(
            f,
            "  {kind}: {v} vertices, {faces} faces, normals: {normals}"
        )?;
        writeln!(
            f,
            "  bounding box: {:?} .. {:?}",
            self.bbox_min, self.bbox_max
        )?;
        let (area, degree) = (self.surface_area, self.max_vertex_degree);
        writeln!(f, "  surface area: {area:.6}   max vertex degree: {degree}")?;
        write!(f, "{}", self.topology.titled("topology"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::icosphere;

    #[test]
    fn the_text_of_a_cube_names_its_counts() {
        let text = Inspection::of(&crate::geometry::primitives::cube()).to_string();
        let first = text.lines().next().unwrap();
        assert_eq!(
            first,
            "  triangle mesh: 8 vertices, 12 faces, normals: false"
        );
        assert!(
            text.contains("\ntopology\n  vertices                    8\n"),
            "{text}"
        );
    }

    #[test]
    fn an_icosphere_is_summarised() {
        let m = icosphere(1);
        let i = Inspection::of(&m);
        assert_eq!((i.vertices, i.faces), (42, 80));
        assert!(!i.point_cloud);
        assert_eq!(i.max_vertex_degree, 6);
        assert!((i.surface_area - m.area()).abs() < 1e-12);
        assert!(i.topology.is_clean_closed());
        for k in 0..3 {
            assert!(i.bbox_min[k] < 0.0 && i.bbox_max[k] > 0.0);
        }
    }

    #[test]
    fn an_empty_mesh_has_a_zero_box_and_degree() {
        let i = Inspection::of(&Mesh::from_points(Vec::new()));
        assert_eq!((i.vertices, i.max_vertex_degree), (0, 0));
        assert!(i.point_cloud);
        assert_eq!((i.bbox_min, i.bbox_max), ([0.0; 3], [0.0; 3]));
    }
}
