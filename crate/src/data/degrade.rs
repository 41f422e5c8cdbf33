//! Point clouds made to look like real scans: noisy and with part of the surface missing.
//! Used to measure how generation holds up on such input (`meshflow eval generate --noise
//! --missing`); the same functions can serve as conditioning augmentation.

use glam::Vec3;

use crate::Aabb;
use crate::rng::Rng;

/// What [`degrade`] does to a point cloud.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Degradation {
    /// Standard deviation of isotropic Gaussian noise added to every point, as a fraction of
    /// the bounding box's longest side (0.01: "1% noise").
    pub noise: f32,
    /// Fraction of the points removed as one contiguous region: the ones nearest a random
    /// input point (a patch the scanner never saw), in `[0, 1)`.
    pub missing: f32,
}

/// `points` with [`Degradation`] applied, seeded: first the region removed, then the noise.
/// An empty input stays empty; at least one point is always kept.
pub fn degrade(points: &[Vec3], how: &Degradation, seed: u64) -> Vec<Vec3> {
    let Some(aabb) = Aabb::of(points) else {
        return Vec::new();
    };
    let mut rng = Rng::new(seed);
    let mut kept = points.to_vec();
    let missing = how.missing.clamp(0.0, 1.0);
    if missing > 0.0 {
        let centre = points[rng.below(points.len())];
        let remove = ((points.len() as f32 * missing) as usize).min(points.len() - 1);
        kept.sort_by(|a, b| {
            a.distance_squared(centre)
                .total_cmp(&b.distance_squared(centre))
        });
        kept.drain(..remove);
    }
    if how.noise > 0.0 {
        let sigma = how.noise * aabb.max_extent();
        for p in &mut kept {
            *p += Vec3::new(
                rng.normal() as f32,
                rng.normal() as f32,
                rng.normal() as f32,
            ) * sigma;
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line() -> Vec<Vec3> {
        (0..100).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect()
    }

    #[test]
    fn a_missing_region_is_contiguous_and_the_right_size() {
        let how = Degradation {
            noise: 0.0,
            missing: 0.3,
        };
        let out = degrade(&line(), &how, 5);
        assert_eq!(out.len(), 70);
        // On a line, the removed 30 points are one run: the kept x values have one gap.
        let mut xs: Vec<i32> = out.iter().map(|p| p.x as i32).collect();
        xs.sort_unstable();
        let gaps = xs.windows(2).filter(|w| w[1] - w[0] > 1).count();
        assert!(gaps <= 1, "{xs:?}");
        assert_eq!(degrade(&line(), &how, 5), out, "seeded");
    }

    #[test]
    fn noise_has_the_asked_spread() {
        let how = Degradation {
            noise: 0.01,
            missing: 0.0,
        };
        let points = line();
        let out = degrade(&points, &how, 1);
        let sd = (out
            .iter()
            .zip(&points)
            .map(|(a, b)| a.distance_squared(*b))
            .sum::<f32>()
            / (3.0 * points.len() as f32))
            .sqrt();
        // Extent 99: sigma 0.99 per axis.
        assert!((sd - 0.99).abs() < 0.2, "{sd}");
        assert!(degrade(&[], &how, 1).is_empty());
    }
}
