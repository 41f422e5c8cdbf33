//! Bounding-box normalisation: a uniform scale and a translation, and its inverse; and the
//! rotation that brings a source's up axis to the model frame's.
//!
//! The model works in [-1, 1] (the box's longest side spans [-1, 1], centred); the metrics of
//! docs/design.md section 3 work in [-0.5, 0.5] computed from the ground truth's box and applied to
//! the prediction too. Scaling is uniform, so normals are unchanged.
//!
//! The model frame is **Y-up** (as in glTF): +Y points up, and the training data is rotated
//! there from each source's own convention ([`UpAxis`]) before it is normalised.

use glam::{Mat3, Vec3};
use serde::{Deserialize, Serialize};

use crate::{Aabb, Mesh};

/// `p -> (p - center) * scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Normalization {
    pub center: Vec3,
    pub scale: f32,
}

impl Normalization {
    pub const IDENTITY: Normalization = Normalization {
        center: Vec3::ZERO,
        scale: 1.0,
    };

    /// Maps `aabb`'s centre to the origin and its longest side to length `2 * half_extent`.
    /// A box of zero size (a single point) only gets translated.
    pub fn fit(aabb: Aabb, half_extent: f32) -> Self {
        // In f64: for coordinates near f32::MAX the f32 sum and extent overflow.
        let (min, max) = (aabb.min.as_dvec3(), aabb.max.as_dvec3());
        let longest = (max - min).max_element();
        let scale = if longest > 0.0 {
            2.0 * half_extent as f64 / longest
        } else {
            1.0
        };
        Normalization {
            center: ((min + max) * 0.5).as_vec3(),
            scale: scale as f32,
        }
    }

    /// The model's frame: the longest side spans [-1, 1].
    pub fn to_model_frame(aabb: Aabb) -> Self {
        Self::fit(aabb, 1.0)
    }

    /// The metrics frame: the longest side spans [-0.5, 0.5].
    pub fn to_metric_frame(aabb: Aabb) -> Self {
        Self::fit(aabb, 0.5)
    }

    pub fn apply(&self, p: Vec3) -> Vec3 {
        // In f64 for the same reason: p - center can exceed f32::MAX before scaling.
        ((p.as_dvec3() - self.center.as_dvec3()) * self.scale as f64).as_vec3()
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Normalization {
        // (p / s + c) = (p - (-c s)) * (1 / s)
        Normalization {
            center: -self.center * self.scale,
            scale: 1.0 / self.scale,
        }
    }

    /// Applies the transform to a mesh's positions (normals are unchanged by a uniform scale).
    pub fn apply_mesh(&self, mesh: &Mesh) -> Mesh {
        Mesh {
            positions: mesh.positions.iter().map(|&p| self.apply(p)).collect(),
            ..mesh.clone()
        }
    }
}

/// Which axis points up in a source's coordinates. The model frame is Y-up (glTF's
/// convention); [`UpAxis::to_y_up`] is the proper rotation (determinant +1, so handedness and
/// face winding are kept) that takes a source's coordinates there.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// +Y up (glTF, PMD, SPM, PIE, AC3D, most OBJ exports): nothing to do.
    #[default]
    Y,
    /// +Z up (Quake-family MD2/MD3, Blender, ROS/URDF robot meshes): rotated by -90 degrees
    /// about X, `(x, y, z) -> (x, z, -y)`, the same map Blender's glTF exporter applies.
    Z,
}

impl UpAxis {
    pub fn name(&self) -> &'static str {
        match self {
            UpAxis::Y => "y",
            UpAxis::Z => "z",
        }
    }

    /// The rotation from the source's coordinates to the Y-up model frame.
    pub fn rotation(&self) -> Mat3 {
        match self {
            UpAxis::Y => Mat3::IDENTITY,
            // Columns are the images of the source's X, Y and Z axes.
            UpAxis::Z => Mat3::from_cols(Vec3::X, -Vec3::Z, Vec3::Y),
        }
    }

    /// A point or direction from the source's coordinates to Y-up. Exact: it only permutes
    /// and negates coordinates.
    pub fn to_y_up(&self, p: Vec3) -> Vec3 {
        match self {
            UpAxis::Y => p,
            UpAxis::Z => Vec3::new(p.x, p.z, -p.y),
        }
    }

    /// The inverse of [`UpAxis::to_y_up`].
    pub fn from_y_up(&self, p: Vec3) -> Vec3 {
        match self {
            UpAxis::Y => p,
            UpAxis::Z => Vec3::new(p.x, -p.z, p.y),
        }
    }

    /// Rotates a mesh's positions and normals to Y-up (faces are unchanged: a rotation keeps
    /// their winding).
    pub fn mesh_to_y_up(&self, mesh: &Mesh) -> Mesh {
        Mesh {
            positions: mesh.positions.iter().map(|&p| self.to_y_up(p)).collect(),
            normals: mesh.normals.iter().map(|&n| self.to_y_up(n)).collect(),
            faces: mesh.faces.clone(),
        }
    }

    /// The inverse of [`UpAxis::mesh_to_y_up`].
    pub fn mesh_from_y_up(&self, mesh: &Mesh) -> Mesh {
        Mesh {
            positions: mesh.positions.iter().map(|&p| self.from_y_up(p)).collect(),
            normals: mesh.normals.iter().map(|&n| self.from_y_up(n)).collect(),
            faces: mesh.faces.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::normals::face_normal;
    use crate::geometry::primitives::{grid, icosphere};

    #[test]
    fn up_axis_rotation_is_proper_and_keeps_winding() {
        for axis in [UpAxis::Y, UpAxis::Z] {
            let r = axis.rotation();
            assert_eq!(r.determinant(), 1.0, "{axis:?}: a proper rotation");
            assert!((r.transpose() * r).abs_diff_eq(Mat3::IDENTITY, 0.0));
            for p in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(1.5, -2.0, 0.25)] {
                assert_eq!(
                    axis.to_y_up(p),
                    r * p,
                    "{axis:?}: the matrix and the fast path agree"
                );
                assert_eq!(axis.from_y_up(axis.to_y_up(p)), p);
            }
            // A rotated outward-facing sphere is still outward-facing: the winding is kept.
            let mut m = icosphere(1);
            m.positions
                .iter_mut()
                .for_each(|p| *p += Vec3::new(3.0, -1.0, 2.0));
            let rotated = axis.mesh_to_y_up(&m);
            for f in 0..m.faces.len() {
                let before = face_normal(m.triangle(f));
                let after = face_normal(rotated.triangle(f));
                assert!((axis.to_y_up(before) - after).length() < 1e-5, "face {f}");
            }
            assert_eq!(axis.mesh_from_y_up(&rotated), m);
        }
        // Z-up's up becomes the model frame's up; its forward (+Y) goes to -Z.
        assert_eq!(UpAxis::Z.to_y_up(Vec3::Z), Vec3::Y);
        assert_eq!(UpAxis::Z.to_y_up(Vec3::Y), -Vec3::Z);
        assert_eq!(UpAxis::Z.to_y_up(Vec3::X), Vec3::X);
        assert_eq!(serde_json::to_string(&UpAxis::Z).unwrap(), "\"z\"");
    }

    #[test]
    fn frames_and_inverse() {
        let mut m = grid(2, 2);
        for p in &mut m.positions {
            *p = *p * Vec3::new(4.0, 2.0, 1.0) + Vec3::new(10.0, -3.0, 5.0);
        }
        let n = Normalization::to_model_frame(m.aabb().unwrap());
        let b = n.apply_mesh(&m).aabb().unwrap();
        assert!((b.min - Vec3::new(-1.0, -0.5, 0.0)).length() < 1e-6);
        assert!((b.max - Vec3::new(1.0, 0.5, 0.0)).length() < 1e-6);
        let half = Normalization::to_metric_frame(m.aabb().unwrap());
        assert!((half.apply_mesh(&m).aabb().unwrap().max_extent() - 1.0).abs() < 1e-6);
        for &p in &m.positions {
            assert!((n.inverse().apply(n.apply(p)) - p).length() < 1e-5);
        }
        let huge = Aabb {
            min: Vec3::splat(-3e38),
            max: Vec3::splat(3e38),
        };
        let n = Normalization::to_model_frame(huge);
        assert!((n.apply(huge.max) - Vec3::ONE).abs().max_element() < 1e-6);
        assert!((n.apply(huge.min) + Vec3::ONE).abs().max_element() < 1e-6);
        let single = Normalization::to_model_frame(Aabb {
            min: Vec3::ONE,
            max: Vec3::ONE,
        });
        assert_eq!(single.apply(Vec3::ONE), Vec3::ZERO);
    }
}
