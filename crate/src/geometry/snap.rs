//! Positions snapped to a grid laid on the input points' bounding box, so that two runs whose
//! positions differ by a few units in the last place (the CPU kernels natively and inside
//! WebAssembly round the model's outputs differently) hand the same positions to a greedy
//! stage after them, whose order of edits near-equal float costs would otherwise decide.
//!
//! The grid is the box's corner plus multiples of a step that is a fixed share of the box's
//! longest side: computed with IEEE arithmetic only, it is the same bits on every platform
//! for the same points, and it moves and scales with them, so a moved and scaled input snaps
//! to the moved and scaled grid (up to rounding).

use glam::Vec3;

use crate::Mesh;
use crate::geometry::mesh::Aabb;
use crate::geometry::topology::degenerate_faces;

/// A grid: the points `origin + k * step` on each axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub origin: Vec3,
    pub step: f32,
}

impl Grid {
    /// The grid over `points`: their bounding box's lower corner, and `2^-bits` of its longest
    /// side as the step. `None` without points or for a box without size or with infinite
    /// coordinates (NaN coordinates drop out of the box: `f32::min` and `max` skip them).
    pub fn over(points: &[Vec3], bits: i32) -> Option<Self> {
        let b = Aabb::of(points)?;
        Self {
            origin: b.min,
            step: b.max_extent(),
        }
        .finer(bits)
    }

    /// The grid on the same origin with `2^-bits` of this one's step (exact: a power of two),
    /// or `None` when that step is not a normal, finite number.
    pub fn finer(self, bits: i32) -> Option<Self> {
        let step = self.step * 2f32.powi(-bits);
        (self.origin.is_finite() && step.is_normal() && step.is_finite())
            .then_some(Self { step, ..self })
    }

    /// `p` moved to the nearest grid point (ties away from the origin).
    pub fn snap(&self, p: Vec3) -> Vec3 {
        self.origin + ((p - self.origin) / self.step).round() * self.step
    }
}

/// Snaps `mesh`'s positions to the coarsest grid over `points` ([`Grid::over`]) of
/// `coarsest_bits..=finest_bits` that leaves no more faces without area than it had, and
/// returns those bits; `None` (the mesh untouched) when every grid would take some face's
/// area or the points give no grid. Coarse first: two runs part only where a coordinate lies
/// within their difference of a cell's boundary, which is rarer the larger the cell.
pub fn snap_mesh(
    mesh: &mut Mesh,
    points: &[Vec3],
    coarsest_bits: i32,
    finest_bits: i32,
) -> Option<i32> {
    let coarsest = Grid::over(points, coarsest_bits)?;
    let before = degenerate_faces(mesh);
    for bits in coarsest_bits..=finest_bits {
        let grid = coarsest.finer(bits - coarsest_bits)?;
        let snapped = mesh.positions.iter().map(|&p| grid.snap(p)).collect();
        let original = std::mem::replace(&mut mesh.positions, snapped);
        if degenerate_faces(mesh) <= before {
            return Some(bits);
        }
        mesh.positions = original;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_lies_on_the_box_corner_with_a_share_of_its_longest_side() {
        let points = [Vec3::new(-1.0, 0.0, 0.0), Vec3::new(2.0, 0.5, 0.25)];
        let grid = Grid::over(&points, 4).unwrap();
        assert_eq!(grid.origin, Vec3::new(-1.0, 0.0, 0.0));
        assert_eq!(grid.step, 3.0 / 16.0);
        assert_eq!(Grid::over(&[], 12), None);
        assert_eq!(Grid::over(&[Vec3::ONE; 3], 12), None);
        let with_nan = Grid::over(&[Vec3::NAN, Vec3::ZERO, Vec3::X], 1).unwrap();
        assert_eq!((with_nan.origin, with_nan.step), (Vec3::ZERO, 0.5));
    }

    #[test]
    fn snapping_moves_by_at_most_half_a_step_and_lands_on_the_grid() {
        let grid = Grid::over(&[Vec3::splat(-0.7), Vec3::splat(1.3)], 12).unwrap();
        for i in 0..1000 {
            let p = Vec3::new(
                i as f32 * 0.001_37 - 0.6,
                (i as f32).sin(),
                -(i as f32) * 1e-4,
            );
            let s = grid.snap(p);
            assert!(
                (s - p).abs().max_element() <= grid.step * 0.500_1,
                "{s} from {p}"
            );
            let k = (s - grid.origin) / grid.step;
            assert!((k - k.round()).abs().max_element() < 1e-3, "{k}");
        }
    }

    #[test]
    fn positions_a_few_ulps_apart_snap_to_the_same_grid_point() {
        let grid = Grid::over(&[Vec3::ZERO, Vec3::ONE], 12).unwrap();
        let mut equal = 0;
        for i in 0..1000 {
            let x = 0.3 + i as f32 * 0.000_731;
            let a = grid.snap(Vec3::splat(x));
            let b = grid.snap(Vec3::splat(f32::from_bits(x.to_bits() + 3)));
            equal += usize::from(a == b);
        }
        // Only a coordinate within 3 ulps below a cell's boundary crosses it.
        assert!(equal >= 990, "{equal} of 1000");
    }

    #[test]
    fn a_moved_and_scaled_input_snaps_to_the_moved_and_scaled_grid() {
        let points = [Vec3::new(-0.4, 0.1, 0.2), Vec3::new(0.6, 0.3, 0.9)];
        let moved = points.map(|p| p * 3.0 + Vec3::new(10.0, -4.0, 2.5));
        let (a, b) = (
            Grid::over(&points, 8).unwrap(),
            Grid::over(&moved, 8).unwrap(),
        );
        for i in 0..200 {
            let p = Vec3::new(i as f32 * 0.0047 - 0.4, 0.2, 0.5);
            let q = p * 3.0 + Vec3::new(10.0, -4.0, 2.5);
            assert!((a.snap(p) * 3.0 + Vec3::new(10.0, -4.0, 2.5) - b.snap(q)).length() < 1e-4);
        }
    }

    #[test]
    fn a_face_smaller_than_the_coarse_cell_takes_a_finer_grid() {
        let points = [Vec3::ZERO, Vec3::ONE];
        // A unit triangle snaps on the coarsest grid (2^-2 of the side).
        let mut large = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
        assert_eq!(snap_mesh(&mut large, &points, 2, 12), Some(2));
        // One 0.01 across shrinks to a point on the grids up to 2^-5 (0.51 rounds to 0.5);
        // on 2^-6, 0.51 rounds to 0.515625 and the face keeps its area.
        let small = vec![
            Vec3::splat(0.5),
            Vec3::new(0.51, 0.5, 0.5),
            Vec3::new(0.5, 0.51, 0.5),
        ];
        let mut mesh = Mesh::new(small.clone(), vec![[0, 1, 2]]);
        assert_eq!(snap_mesh(&mut mesh, &points, 2, 12), Some(6));
        assert_ne!(mesh.positions, small);
        // Far smaller than the finest cell: left as it was.
        let tiny = vec![
            Vec3::splat(0.5),
            Vec3::new(0.500_01, 0.5, 0.5),
            Vec3::new(0.5, 0.500_01, 0.5),
        ];
        let mut mesh = Mesh::new(tiny.clone(), vec![[0, 1, 2]]);
        assert_eq!(snap_mesh(&mut mesh, &points, 2, 12), None);
        assert_eq!(mesh.positions, tiny);
    }
}
