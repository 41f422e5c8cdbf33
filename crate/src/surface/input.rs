//! The input points as the stages after extraction ask about them: a nearest-point index over
//! the finite ones and their spacing, built once per input and shared by every candidate's fitting,
//! completion and hole closing (built per call, they were most of those stages' time).

use glam::Vec3;

use crate::geometry::nearest::PointIndex;

/// The input points of [`crate::surface::fit::fit_to_points`],
/// [`crate::surface::complete::complete_surface`] and [`crate::surface::close::close_holes`]:
/// the finite ones, indexed for nearest-point queries, with their median spacing.
#[derive(Clone, Debug)]
pub struct InputPoints {
    index: PointIndex,
    spacing: f32,
}

impl InputPoints {
    /// The finite ones of `points` (others are ignored), each keeping its index.
    pub fn new(points: &[Vec3]) -> Self {
        let index = PointIndex::new(points);
        InputPoints {
            spacing: index.spacing(),
            index,
        }
    }

    /// The finite points' count.
    pub fn len(&self) -> usize {
        self.index.len()
    }

    pub fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    /// Median distance from a point to its nearest other point ([`PointIndex::spacing`]); 0
    /// with fewer than two points.
    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    pub(crate) fn index(&self) -> &PointIndex {
        &self.index
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_points_are_left_out_and_the_spacing_is_the_median_gap() {
        let mut points: Vec<Vec3> = (0..10)
            .map(|i| Vec3::new(i as f32 * 0.5, 0.0, 0.0))
            .collect();
        points.push(Vec3::new(f32::NAN, 0.0, 0.0));
        points.push(Vec3::splat(f32::INFINITY));
        let input = InputPoints::new(&points);
        assert_eq!(input.len(), 10);
        assert!((input.spacing() - 0.5).abs() < 1e-6, "{}", input.spacing());
        let one = InputPoints::new(&[Vec3::ONE]);
        assert_eq!((one.len(), one.spacing()), (1, 0.0));
        assert!(InputPoints::new(&[]).is_empty());
    }
}
