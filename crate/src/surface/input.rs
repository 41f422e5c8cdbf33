//! The input points as the stages after extraction ask about them: an R-tree over the finite
//! ones and their spacing, built once per input and shared by every candidate's fitting,
//! completion and hole closing (built per call, they were most of those stages' time).

use glam::Vec3;
use rstar::RTree;
use rstar::primitives::GeomWithData;

/// A point of an R-tree with its index in the list it came from.
pub(crate) type Indexed = GeomWithData<[f32; 3], u32>;

/// The input points of [`crate::surface::fit::fit_to_points`],
/// [`crate::surface::complete::complete_surface`] and [`crate::surface::close::close_holes`]:
/// the finite ones in an R-tree, with their median spacing.
#[derive(Clone, Debug)]
pub struct InputPoints {
    tree: RTree<Indexed>,
    spacing: f32,
}

impl InputPoints {
    /// The finite ones of `points` (others are ignored), each keeping its index.
    pub fn new(points: &[Vec3]) -> Self {
        let tree = finite_point_tree(points);
        InputPoints {
            spacing: point_spacing(&tree),
            tree,
        }
    }

    /// The finite points' count.
    pub fn len(&self) -> usize {
        self.tree.size()
    }

    pub fn is_empty(&self) -> bool {
        self.tree.size() == 0
    }

    /// Median distance from a point to its nearest other point ([`point_spacing`]); 0 with
    /// fewer than two points.
    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    pub(crate) fn tree(&self) -> &RTree<Indexed> {
        &self.tree
    }
}

/// An R-tree over the finite ones of `points`, each carrying its index.
pub(crate) fn finite_point_tree(points: &[Vec3]) -> RTree<Indexed> {
    RTree::bulk_load(
        points
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_finite())
            .map(|(i, p)| GeomWithData::new(p.to_array(), i as u32))
            .collect(),
    )
}

/// Median distance from an input point to its nearest other point (over at most 1,024 of
/// them, evenly spread in index order).
pub(crate) fn point_spacing(tree: &RTree<Indexed>) -> f32 {
    let all: Vec<&Indexed> = tree.iter().collect();
    let stride = all.len().div_ceil(1024).max(1);
    let mut d: Vec<f32> = all
        .iter()
        .step_by(stride)
        .filter_map(|p| {
            tree.nearest_neighbor_iter(*p.geom())
                .find(|q| q.data != p.data)
                .map(|q| Vec3::from_array(*q.geom()).distance(Vec3::from_array(*p.geom())))
        })
        .collect();
    d.sort_by(f32::total_cmp);
    d.get(d.len() / 2).copied().unwrap_or(0.0)
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
