//! Training-time augmentation.
//!
//! The shards hold each mesh once, in the Y-up model frame ([`crate::data::dataset`]); every pass
//! over them sees a different random variant, drawn here rather than stored:
//!
//! 1. a rotation about the up axis (+Y) by a uniform angle (the shards' up axis is already
//!    right, so only the heading is arbitrary);
//! 2. an anisotropic scale, each axis's factor uniform in `[1 - j, 1 + j]` (`j` =
//!    [`AugmentOptions::scale_jitter`], 0.1 by default), applied after the rotation;
//! 3. re-normalisation to the model frame (the bounding box's longest side spans [-1, 1],
//!    centred), like [`Normalization::to_model_frame`], which only translates and scales
//!    uniformly;
//! 4. vertex normals: the mesh's own, or [`vertex_normals`] when it has none (shards store
//!    none), mapped by the inverse transpose of the linear part, `S^-1 R` (the rotation is
//!    orthonormal), and renormalised. That is the exact map of a surface normal under the
//!    transform: a face normal mapped this way is the transformed face's normal;
//! 5. a point cloud for the DiT's condition: [`sample_surface`] (area-uniform) on the
//!    augmented mesh, with each point's face normal.
//!
//! Determinism: a sample depends only on the mesh, the options and its seed (the VAE's
//! training draws the seeds from its run's generator, in its shuffled batch order). The angle is drawn without trigonometry (a point
//! drawn uniformly in the unit disc, normalised), and every transform is computed in `f64`
//! with plain IEEE operations, so results are the same on every platform.

use glam::{DVec3, Vec3};

use crate::Mesh;
use crate::geometry::normalize::Normalization;
use crate::geometry::normals::vertex_normals;
use crate::geometry::sample::{SampleError, SurfaceSamples, sample_surface};
use crate::rng::Rng;

/// What [`augment`] draws and samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AugmentOptions {
    /// Rotate about the up axis (+Y) by a uniform random angle.
    pub rotate: bool,
    /// Each axis is scaled by a factor uniform in `[1 - scale_jitter, 1 + scale_jitter]`
    /// (0 = no scaling). At most 0.5.
    pub scale_jitter: f32,
    /// Surface points sampled for the condition.
    pub points: usize,
}

impl Default for AugmentOptions {
    fn default() -> Self {
        Self {
            rotate: true,
            scale_jitter: 0.1,
            points: 4096,
        }
    }
}

/// The random transform of one sample: `p -> normalization(S R p)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Augmentation {
    /// `[cos, sin]` of the rotation angle about +Y (`x' = cos x + sin z`, `z' = -sin x + cos z`).
    pub rotation: [f64; 2],
    /// Per-axis scale factors `S`, applied after the rotation.
    pub scale: [f64; 3],
    /// The re-normalisation to the model frame applied last.
    pub normalization: Normalization,
}

impl Augmentation {
    /// Draws the rotation and scale (the normalisation is filled in by [`augment`]).
    fn draw(opts: &AugmentOptions, rng: &mut Rng) -> Self {
        let rotation = if opts.rotate {
            // A uniform point of the unit disc has a uniform angle.
            loop {
                let x = 2.0 * rng.next_f64() - 1.0;
                let z = 2.0 * rng.next_f64() - 1.0;
                let r2 = x * x + z * z;
                if r2 <= 1.0 && r2 > 1e-12 {
                    let r = r2.sqrt();
                    break [x / r, z / r];
                }
            }
        } else {
            [1.0, 0.0]
        };
        let j = f64::from(opts.scale_jitter.clamp(0.0, 0.5));
        let scale = [0; 3].map(|_| 1.0 + j * (2.0 * rng.next_f64() - 1.0));
        Augmentation {
            rotation,
            scale,
            normalization: Normalization::IDENTITY,
        }
    }

    fn rotate(&self, p: DVec3) -> DVec3 {
        let [c, s] = self.rotation;
        DVec3::new(c * p.x + s * p.z, p.y, -s * p.x + c * p.z)
    }

    /// The linear part `S R` applied to a point (before the normalisation).
    pub fn linear(&self, p: Vec3) -> Vec3 {
        let r = self.rotate(p.as_dvec3());
        DVec3::new(
            r.x * self.scale[0],
            r.y * self.scale[1],
            r.z * self.scale[2],
        )
        .as_vec3()
    }

    /// A unit normal mapped by the inverse transpose of the linear part, `S^-1 R`, and
    /// renormalised (`+Z` if it degenerates, which an invertible map never does to a unit
    /// vector).
    pub fn normal(&self, n: Vec3) -> Vec3 {
        let r = self.rotate(n.as_dvec3());
        let m = DVec3::new(
            r.x / self.scale[0],
            r.y / self.scale[1],
            r.z / self.scale[2],
        );
        let len = (m.x * m.x + m.y * m.y + m.z * m.z).sqrt();
        if len > 0.0 && len.is_finite() {
            (m / len).as_vec3()
        } else {
            Vec3::Z
        }
    }

    /// The full transform of a point: the linear part, then the normalisation.
    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.normalization.apply(self.linear(p))
    }
}

/// One training example: an augmented mesh and the point cloud that conditions on it.
#[derive(Clone, Debug, PartialEq)]
pub struct TrainingSample {
    /// The augmented mesh in the model frame, with unit vertex normals.
    pub mesh: Mesh,
    /// Area-uniform surface points of `mesh`, with the unit normals of their faces.
    pub points: SurfaceSamples,
    pub augmentation: Augmentation,
}

/// Augments `mesh` (see the module doc), reproducibly for `seed`. Errors when the mesh has
/// no surface to sample (no faces, or zero or non-finite area).
pub fn augment(
    mesh: &Mesh,
    opts: &AugmentOptions,
    seed: u64,
) -> Result<TrainingSample, SampleError> {
    let mut rng = Rng::new(seed);
    let (out, aug) = transform(mesh, opts, &mut rng);
    let points = sample_surface(&out, opts.points, rng.next_u64())?;
    Ok(TrainingSample {
        mesh: out,
        points,
        augmentation: aug,
    })
}

/// Steps 1-4 of the module doc only (no point cloud): the augmented mesh and its transform,
/// drawn from `rng`. The VAE trains on these.
pub fn augment_mesh(mesh: &Mesh, opts: &AugmentOptions, rng: &mut Rng) -> (Mesh, Augmentation) {
    transform(mesh, opts, rng)
}

fn transform(mesh: &Mesh, opts: &AugmentOptions, rng: &mut Rng) -> (Mesh, Augmentation) {
    let mut aug = Augmentation::draw(opts, rng);
    let normals = if mesh.normals.len() == mesh.positions.len() {
        mesh.normals.clone()
    } else {
        vertex_normals(&mesh.positions, &mesh.faces)
    };
    let positions: Vec<Vec3> = mesh.positions.iter().map(|&p| aug.linear(p)).collect();
    if let Some(aabb) = crate::Aabb::of(&positions) {
        aug.normalization = Normalization::to_model_frame(aabb);
    }
    let out = Mesh {
        positions: positions
            .iter()
            .map(|&p| aug.normalization.apply(p))
            .collect(),
        normals: normals.iter().map(|&n| aug.normal(n)).collect(),
        faces: mesh.faces.clone(),
    };
    (out, aug)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::normals::face_normal;
    use crate::geometry::primitives::{cube, icosphere};
    use crate::rng::Rng;
    use proptest::prelude::*;

    /// An icosphere stretched, sheared and moved: convex, so every vertex normal agrees with
    /// the faces around it.
    fn blob(stretch: [f32; 3], shear: f32, offset: [f32; 3]) -> Mesh {
        let mut m = icosphere(1);
        for p in &mut m.positions {
            *p = Vec3::new(
                p.x * stretch[0] + shear * p.y,
                p.y * stretch[1],
                p.z * stretch[2],
            ) + Vec3::from(offset);
        }
        m
    }

    fn arb_blob() -> impl Strategy<Value = Mesh> {
        (
            prop::array::uniform3(0.2f32..3.0),
            -0.5f32..0.5,
            prop::array::uniform3(-5.0f32..5.0),
        )
            .prop_map(|(s, h, o)| blob(s, h, o))
    }

    fn edge_lengths(m: &Mesh) -> Vec<f64> {
        crate::geometry::topology::edges(&m.faces)
            .iter()
            .map(|&[a, b]| {
                (m.positions[a as usize].as_dvec3() - m.positions[b as usize].as_dvec3()).length()
            })
            .collect()
    }

    const POINTS: AugmentOptions = AugmentOptions {
        rotate: true,
        scale_jitter: 0.1,
        points: 256,
    };

    proptest! {
        #[test]
        fn rotation_keeps_edge_lengths_and_winding(m in arb_blob(), seed in any::<u64>()) {
            let opts = AugmentOptions { scale_jitter: 0.0, ..POINTS };
            let s = augment(&m, &opts, seed).unwrap();
            let [c, sn] = s.augmentation.rotation;
            prop_assert!((c * c + sn * sn - 1.0).abs() < 1e-12);
            // Only rotated and uniformly rescaled: every edge changes by the same factor.
            let k = f64::from(s.augmentation.normalization.scale);
            for (a, b) in edge_lengths(&m).iter().zip(edge_lengths(&s.mesh)) {
                prop_assert!((b - k * a).abs() <= 1e-5 * (1.0 + b), "{a} -> {b}, factor {k}");
            }
            // Winding: each face normal is the rotated original one (a proper rotation).
            for f in 0..m.faces.len() {
                let before = face_normal(m.triangle(f));
                let after = face_normal(s.mesh.triangle(f));
                prop_assert!(s.augmentation.normal(before).dot(after) > 0.9999);
            }
        }

        #[test]
        fn normals_are_unit_and_agree_with_the_faces(m in arb_blob(), seed in any::<u64>()) {
            let s = augment(&m, &POINTS, seed).unwrap();
            for k in s.augmentation.scale {
                prop_assert!((0.9..=1.1).contains(&k));
            }
            // The inverse transpose maps each face normal to the transformed face's normal.
            for f in 0..m.faces.len() {
                let mapped = s.augmentation.normal(face_normal(m.triangle(f)));
                let actual = face_normal(s.mesh.triangle(f));
                prop_assert!(mapped.dot(actual) > 0.9999, "face {f}: {mapped} vs {actual}");
            }
            // Vertex normals are unit and keep pointing out of the surface: where the original
            // vertex normal clearly agrees with a face around it, the mapped one still does.
            let original = vertex_normals(&m.positions, &m.faces);
            for (v, n) in s.mesh.normals.iter().enumerate() {
                prop_assert!((n.length() - 1.0).abs() < 1e-5);
                for (f, face) in s.mesh.faces.iter().enumerate() {
                    if face.contains(&(v as u32))
                        && original[v].dot(face_normal(m.triangle(f))) > 0.2
                    {
                        prop_assert!(n.dot(face_normal(s.mesh.triangle(f))) > 0.0);
                    }
                }
            }
            // Surface points lie in the model frame with their face's unit normal.
            prop_assert_eq!(s.points.len(), 256);
            for (i, n) in s.points.normals.iter().enumerate() {
                let face = face_normal(s.mesh.triangle(s.points.faces[i] as usize));
                prop_assert!((n.length() - 1.0).abs() < 1e-5);
                prop_assert!(n.dot(face) > 0.9999);
                prop_assert!(s.points.points[i].abs().max_element() <= 1.0 + 1e-5);
            }
        }

        #[test]
        fn stays_in_the_model_frame(m in arb_blob(), seed in any::<u64>()) {
            let s = augment(&m, &POINTS, seed).unwrap();
            let b = s.mesh.aabb().unwrap();
            prop_assert!(b.min.min_element() >= -1.0 - 1e-5 && b.max.max_element() <= 1.0 + 1e-5);
            prop_assert!((b.max_extent() - 2.0).abs() < 1e-5);
            prop_assert!(b.center().abs().max_element() < 1e-5);
        }

        #[test]
        fn same_seed_same_sample(m in arb_blob(), seed in any::<u64>()) {
            let a = augment(&m, &POINTS, seed).unwrap();
            prop_assert_eq!(&a, &augment(&m, &POINTS, seed).unwrap());
            let b = augment(&m, &POINTS, seed ^ 1).unwrap();
            prop_assert_ne!(a.augmentation, b.augmentation);
        }
    }

    #[test]
    fn rotation_angles_cover_the_circle() {
        let mut quadrants = [0usize; 4];
        for seed in 0..4000 {
            let [c, s] =
                Augmentation::draw(&AugmentOptions::default(), &mut Rng::new(seed)).rotation;
            quadrants[usize::from(c < 0.0) * 2 + usize::from(s < 0.0)] += 1;
        }
        assert!(
            quadrants.iter().all(|&q| (900..1100).contains(&q)),
            "{quadrants:?}"
        );
        let none = AugmentOptions {
            rotate: false,
            scale_jitter: 0.0,
            ..AugmentOptions::default()
        };
        let a = Augmentation::draw(&none, &mut Rng::new(3));
        assert_eq!((a.rotation, a.scale), ([1.0, 0.0], [1.0; 3]));
    }

    #[test]
    fn existing_normals_are_transformed_not_recomputed() {
        let mut m = cube();
        m.normals = vec![Vec3::Y; m.positions.len()];
        let s = augment(&m, &POINTS, 5).unwrap();
        let expected = s.augmentation.normal(Vec3::Y);
        assert!(s.mesh.normals.iter().all(|&n| n == expected));
        // Up stays up under a rotation about Y and a positive scale.
        assert!((expected - Vec3::Y).length() < 1e-6);
        assert!(augment(&Mesh::from_points(vec![Vec3::ONE]), &POINTS, 0).is_err());
    }
}
