//! The triangle mesh (or point cloud) every part of the crate passes around.

use glam::Vec3;

/// A triangle mesh; with no faces it is a point cloud.
///
/// Invariants the constructors in this crate keep (and [`Mesh::validate`] checks):
/// every face index is `< positions.len()`, `normals` is empty or one per position, and all
/// coordinates are finite.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex unit normals, or empty when the source had none.
    pub normals: Vec<Vec3>,
    /// Triangles as vertex indices. Counter-clockwise seen from outside is front-facing.
    pub faces: Vec<[u32; 3]>,
}

/// Why a [`Mesh`] breaks its invariants.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    #[error("face {face} uses vertex {index} but the mesh has {vertices} vertices")]
    IndexOutOfRange {
        face: usize,
        index: u32,
        vertices: usize,
    },
    #[error("{normals} normals for {vertices} vertices (expected none or one per vertex)")]
    NormalCount { normals: usize, vertices: usize },
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFinite { vertex: usize },
}

impl Mesh {
    /// A mesh from positions and faces, without normals.
    pub fn new(positions: Vec<Vec3>, faces: Vec<[u32; 3]>) -> Self {
        Self {
            positions,
            normals: Vec::new(),
            faces,
        }
    }

    /// A point cloud (no faces).
    pub fn from_points(positions: Vec<Vec3>) -> Self {
        Self {
            positions,
            normals: Vec::new(),
            faces: Vec::new(),
        }
    }

    /// True when the mesh has no faces.
    pub fn is_point_cloud(&self) -> bool {
        self.faces.is_empty()
    }

    /// Checks the invariants listed on [`Mesh`].
    pub fn validate(&self) -> Result<(), MeshError> {
        let n = self.positions.len();
        if !self.normals.is_empty() && self.normals.len() != n {
            return Err(MeshError::NormalCount {
                normals: self.normals.len(),
                vertices: n,
            });
        }
        if let Some(vertex) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinite { vertex });
        }
        for (face, f) in self.faces.iter().enumerate() {
            if let Some(&index) = f.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::IndexOutOfRange {
                    face,
                    index,
                    vertices: n,
                });
            }
        }
        Ok(())
    }

    /// The axis-aligned bounding box of the positions, or `None` for an empty mesh.
    pub fn aabb(&self) -> Option<Aabb> {
        Aabb::of(&self.positions)
    }

    /// The three corner positions of face `f`.
    pub fn triangle(&self, f: usize) -> [Vec3; 3] {
        self.faces[f].map(|i| self.positions[i as usize])
    }

    /// Removes the vertices no face uses, renumbering the rest in their original order
    /// (normals follow). Returns how many were removed.
    pub fn remove_unreferenced_vertices(&mut self) -> usize {
        let n = self.positions.len();
        let mut new_index = vec![u32::MAX; n];
        for f in &self.faces {
            for &v in f {
                new_index[v as usize] = 0;
            }
        }
        let mut next = 0u32;
        for slot in new_index.iter_mut().filter(|s| **s == 0) {
            *slot = next;
            next += 1;
        }
        let keep = |i: &usize| new_index[*i] != u32::MAX;
        self.positions = (0..n).filter(keep).map(|i| self.positions[i]).collect();
        if !self.normals.is_empty() {
            self.normals = (0..n).filter(keep).map(|i| self.normals[i]).collect();
        }
        for f in &mut self.faces {
            *f = f.map(|v| new_index[v as usize]);
        }
        n - next as usize
    }

    /// Signed volume enclosed by the faces (the divergence theorem over their triangles):
    /// positive for a closed mesh wound counter-clockwise seen from outside.
    pub fn signed_volume(&self) -> f32 {
        (0..self.faces.len())
            .map(|f| {
                let [a, b, c] = self.triangle(f);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        // Folded from +0.0: an empty f64 sum is -0.0, which prints as "-0".
        (0..self.faces.len())
            .map(|f| triangle_area(self.triangle(f)) as f64)
            .fold(0.0, |a, b| a + b)
    }
}

/// Area of a triangle.
pub fn triangle_area([a, b, c]: [Vec3; 3]) -> f32 {
    0.5 * (b - a).cross(c - a).length()
}

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    /// The bounding box of `points`, or `None` when there are none.
    pub fn of(points: &[Vec3]) -> Option<Aabb> {
        let first = *points.first()?;
        Some(points.iter().fold(
            Aabb {
                min: first,
                max: first,
            },
            |b, &p| Aabb {
                min: b.min.min(p),
                max: b.max.max(p),
            },
        ))
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// The longest side.
    pub fn max_extent(&self) -> f32 {
        self.extent().max_element()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validate_catches_each_broken_invariant() {
        let mut m = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
        assert_eq!(m.validate(), Ok(()));
        m.faces.push([0, 1, 3]);
        assert!(matches!(
            m.validate(),
            Err(MeshError::IndexOutOfRange { index: 3, .. })
        ));
        m.faces.pop();
        m.normals = vec![Vec3::Z];
        assert!(matches!(m.validate(), Err(MeshError::NormalCount { .. })));
        m.normals.clear();
        m.positions[1].x = f32::NAN;
        assert_eq!(m.validate(), Err(MeshError::NonFinite { vertex: 1 }));
    }

    #[test]
    fn unreferenced_vertices_are_removed_in_order() {
        let mut m = Mesh::new(
            vec![Vec3::ZERO, Vec3::ONE, Vec3::X, Vec3::Y, Vec3::Z],
            vec![[0, 2, 4]],
        );
        m.normals = vec![Vec3::Z; 5];
        assert_eq!(m.remove_unreferenced_vertices(), 2);
        assert_eq!(m.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Z]);
        assert_eq!((m.faces.clone(), m.normals.len()), (vec![[0, 1, 2]], 3));
        assert_eq!(m.validate(), Ok(()));
    }

    #[test]
    fn aabb_and_area() {
        let m = Mesh::new(vec![Vec3::ZERO, Vec3::X * 2.0, Vec3::Y], vec![[0, 1, 2]]);
        let b = m.aabb().unwrap();
        assert_eq!(b.min, Vec3::ZERO);
        assert_eq!(b.max, Vec3::new(2.0, 1.0, 0.0));
        assert_eq!(b.max_extent(), 2.0);
        assert!((m.area() - 1.0).abs() < 1e-6);
        assert_eq!(Aabb::of(&[]), None);
        assert!(Mesh::from_points(vec![Vec3::ONE]).area().is_sign_positive());
    }
}
