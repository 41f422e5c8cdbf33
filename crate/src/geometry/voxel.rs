//! Voxel indices of model-frame points at resolution 32: the positions the DiT's 3-D RoPE uses.
//!
//! Rule (docs/design.md section 2): per axis, `clamp(floor((p + 1) / 2 * 32), 0, 31)` for `p` in the
//! model frame [-1, 1]. The arithmetic is done in `f32` in exactly that order (add 1, halve,
//! multiply by 32, floor), as the reference does on float32 tensors, so points on a cell boundary
//! land in the same cell. So `-1 -> 0`, `1 -> 31` (the closed upper end is clamped into the last
//! cell), `-1 + k/16 -> k` exactly, and anything outside [-1, 1] clamps to the nearest end cell.
//! A NaN coordinate maps to cell 0 (documented choice; clean meshes have none).

use glam::Vec3;

/// Cells per axis.
pub const VOXEL_RESOLUTION: u32 = 32;

fn axis(c: f32) -> u32 {
    let r = VOXEL_RESOLUTION as f32;
    let cell = ((c + 1.0) / 2.0 * r).floor();
    if cell.is_nan() || cell <= 0.0 {
        0
    } else if cell >= r - 1.0 {
        VOXEL_RESOLUTION - 1
    } else {
        cell as u32
    }
}

/// The voxel cell `[ix, iy, iz]`, each in `0..32`, of a model-frame point (see module doc).
pub fn voxel_index(p: Vec3) -> [u32; 3] {
    [axis(p.x), axis(p.y), axis(p.z)]
}

/// [`voxel_index`] of every point, in order.
pub fn voxelize(points: &[Vec3]) -> Vec<[u32; 3]> {
    points.iter().map(|&p| voxel_index(p)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_boundaries() {
        assert_eq!(voxel_index(Vec3::splat(-1.0)), [0, 0, 0]);
        assert_eq!(voxel_index(Vec3::splat(1.0)), [31, 31, 31]);
        assert_eq!(voxel_index(Vec3::ZERO), [16, 16, 16]);
        for k in 0..32u32 {
            let lo = -1.0 + k as f32 / 16.0;
            assert_eq!(axis(lo), k, "cell start {lo}");
            if k > 0 {
                // Just below a boundary belongs to the previous cell. (One ulp below can round
                // back onto the boundary when 1 is added, so step a few ulps of 2.)
                assert_eq!(axis(lo - 1e-6), k - 1, "below {lo}");
            }
        }
        assert_eq!(axis(1.0f32.next_down()), 31);
        assert_eq!(axis(0.9375 - 1e-6), 30);
    }

    #[test]
    fn outside_and_nan_clamp() {
        assert_eq!(voxel_index(Vec3::new(-5.0, 7.0, -1.0001)), [0, 31, 0]);
        assert_eq!(
            voxel_index(Vec3::new(1.0001, f32::INFINITY, f32::NEG_INFINITY)),
            [31, 31, 0]
        );
        assert_eq!(voxel_index(Vec3::new(f32::NAN, 0.5, -0.5)), [0, 24, 8]);
        assert_eq!(
            voxelize(&[Vec3::ZERO, Vec3::splat(-1.0)]),
            vec![[16, 16, 16], [0, 0, 0]]
        );
    }
}
