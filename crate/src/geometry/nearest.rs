//! Nearest points of a fixed set: a k-d tree (`kiddo`'s immutable one) over the finite points,
//! each keeping its index in the list it came from. Every stage after extraction asks it
//! thousands of times per candidate (fitting's planes, completion's neighbourhoods, the
//! sharpening's planes and coverage, the distance to the input that ranks candidates); it
//! answers k-nearest queries about 3x faster than the R-tree the crate used before
//! (docs/experiments/2026-12-05-nearest-points.md).

use std::num::NonZero;
use std::sync::Arc;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};

/// The finite points of a list, searchable by distance.
#[derive(Clone, Debug)]
pub struct PointIndex {
    /// `None` with no finite point (kiddo builds no tree of nothing). Shared: kiddo's tree
    /// is not `Clone`, and a clone of an index asks the same tree.
    tree: Option<Arc<ImmutableKdTree<f32, 3>>>,
    /// The finite points, in their list's order, and the index each had there.
    points: Vec<Vec3>,
    ids: Vec<u32>,
}

impl Default for PointIndex {
    fn default() -> Self {
        PointIndex::new(&[])
    }
}

impl PointIndex {
    /// The finite ones of `points` (others are left out), each keeping its index.
    pub fn new(points: &[Vec3]) -> Self {
        PointIndex::with_ids((0u32..).zip(points.iter().copied()))
    }

    /// The finite ones of `points`, each with the index it is given.
    pub fn with_ids(points: impl IntoIterator<Item = (u32, Vec3)>) -> Self {
        let (ids, points): (Vec<u32>, Vec<Vec3>) =
            points.into_iter().filter(|(_, p)| p.is_finite()).unzip();
        let coords: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
        let tree = (!coords.is_empty())
            .then(|| ImmutableKdTree::new_from_slice(&coords).ok().map(Arc::new))
            .flatten();
        PointIndex { tree, points, ids }
    }

    /// How many finite points it holds.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The finite points with their indices, in their list's order.
    pub fn iter(&self) -> impl Iterator<Item = (u32, Vec3)> + '_ {
        self.ids.iter().copied().zip(self.points.iter().copied())
    }

    /// The point nearest `x`: its index, position and squared distance; `None` when empty.
    pub fn nearest(&self, x: Vec3) -> Option<(u32, Vec3, f32)> {
        let tree = self.tree.as_ref()?;
        let hit = tree
            .query(&x.to_array())
            .nearest_one::<SquaredEuclidean<f32>>()
            .execute();
        let slot = hit.item as usize;
        Some((self.ids[slot], self.points[slot], hit.distance))
    }

    /// The `k` points nearest `x` (fewer when there are fewer), nearest first: index and
    /// position.
    pub fn k_nearest(&self, x: Vec3, k: usize) -> impl Iterator<Item = (u32, Vec3)> + '_ {
        let found = match (&self.tree, NonZero::new(k)) {
            (Some(tree), Some(k)) => tree
                .query(&x.to_array())
                .nearest_n::<SquaredEuclidean<f32>>(k)
                .execute(),
            _ => Vec::new(),
        };
        found.into_iter().map(move |hit| {
            let slot = hit.item as usize;
            (self.ids[slot], self.points[slot])
        })
    }

    /// Whether some point lies within `radius` of `x`.
    pub fn any_within(&self, x: Vec3, radius: f32) -> bool {
        self.nearest(x)
            .is_some_and(|(_, _, d2)| d2 <= radius * radius)
    }

    /// Median distance from a point to its nearest other point (over at most 1,024 of them,
    /// evenly spread in index order); 0 with fewer than two points.
    pub fn spacing(&self) -> f32 {
        let stride = self.len().div_ceil(1024).max(1);
        let mut d: Vec<f32> = self
            .iter()
            .step_by(stride)
            .filter_map(|(i, p)| {
                // The nearest other point: itself (or a duplicate of it) comes first.
                self.k_nearest(p, 2)
                    .find(|&(j, _)| j != i)
                    .map(|(_, q)| q.distance(p))
            })
            .collect();
        d.sort_by(f32::total_cmp);
        d.get(d.len() / 2).copied().unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_k_nearest(points: &[Vec3], x: Vec3, k: usize) -> Vec<f32> {
        let mut d: Vec<f32> = points.iter().map(|p| p.distance_squared(x)).collect();
        d.sort_by(f32::total_cmp);
        d.truncate(k);
        d
    }

    #[test]
    fn k_nearest_agrees_with_brute_force_and_keeps_indices() {
        let mut rng = crate::rng::Rng::new(7);
        let points: Vec<Vec3> = (0..500)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32() * 0.1))
            .collect();
        let index = PointIndex::new(&points);
        for _ in 0..200 {
            let x = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 1.4 - 0.2;
            let got: Vec<(u32, Vec3)> = index.k_nearest(x, 6).collect();
            let want = brute_k_nearest(&points, x, 6);
            assert_eq!(got.len(), 6);
            for ((i, p), d) in got.iter().zip(&want) {
                assert_eq!(points[*i as usize], *p);
                assert_eq!(p.distance_squared(x), *d);
            }
            let (i, p, d2) = index.nearest(x).unwrap();
            assert_eq!(points[i as usize], p);
            assert_eq!(d2, want[0]);
            assert!(index.any_within(x, d2.sqrt() * 1.001));
            assert!(!index.any_within(x, d2.sqrt() * 0.999));
        }
    }

    #[test]
    fn non_finite_points_are_left_out_and_degenerate_sets_answer() {
        let nan = Vec3::new(f32::NAN, 0.0, 0.0);
        let index = PointIndex::new(&[nan, Vec3::ONE, Vec3::INFINITY, Vec3::ZERO]);
        assert_eq!(index.len(), 2);
        let ids: Vec<u32> = index
            .k_nearest(Vec3::splat(0.1), 5)
            .map(|(i, _)| i)
            .collect();
        assert_eq!(ids, vec![3, 1]);
        // Empty, one point, and thousands of copies of one point (a k-d tree's worst case).
        let empty = PointIndex::new(&[nan]);
        assert!(empty.is_empty() && empty.nearest(Vec3::ZERO).is_none());
        assert_eq!(empty.k_nearest(Vec3::ZERO, 3).count(), 0);
        assert_eq!(empty.spacing(), 0.0);
        assert_eq!(PointIndex::new(&[Vec3::ONE]).spacing(), 0.0);
        let same = PointIndex::new(&vec![Vec3::splat(0.5); 5000]);
        assert_eq!(same.k_nearest(Vec3::ZERO, 8).count(), 8);
        assert_eq!(same.spacing(), 0.0);
        // A grid on a plane: the spacing is the grid step.
        let grid: Vec<Vec3> = (0..900)
            .map(|i| Vec3::new((i % 30) as f32 * 0.1, (i / 30) as f32 * 0.1, 0.0))
            .collect();
        assert!((PointIndex::new(&grid).spacing() - 0.1).abs() < 1e-5);
    }
}
