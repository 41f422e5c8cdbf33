//! Bounding-box normalisation: a uniform scale and a translation, and its inverse.
//!
//! The model works in [-1, 1] (the box's longest side spans [-1, 1], centred); the metrics of
//! DESIGN.md section 3 work in [-0.5, 0.5] computed from the ground truth's box and applied to
//! the prediction too. Scaling is uniform, so normals are unchanged.

use glam::Vec3;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::grid;

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
