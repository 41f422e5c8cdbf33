//! Fitting a generated mesh to the points it was generated from.
//!
//! The DiT sees the input points only through its latent tokens' voxel positions, so a decoded
//! vertex can sit a fraction of a voxel off the surface the user gave. The input points are the
//! best evidence of that surface; [`fit_to_points`] moves the vertices onto it while keeping the
//! connectivity and the faces' orientation:
//!
//! 1. **Target.** For each vertex, its `neighbours` nearest input points give a
//!    local plane (their centroid and the direction of least spread, the smallest eigenvector of
//!    their covariance); the target is the vertex projected onto that plane. Only the offset
//!    across the surface is corrected, so vertices do not bunch up on the nearest samples.
//!    With `smoothing` above 0 the vertex is first moved that fraction of the way to the
//!    centroid of its neighbours along edges, and that point is projected: crowded vertices
//!    spread out along the surface.
//! 2. **Move, unless it folds.** Every vertex moves to its target; then any face whose normal
//!    turned by 90 degrees or more, or that lost its area, and any pair of faces on an edge that
//!    now close onto each other ([`crate::extract::manifold::FOLD_COS`]) when they did not before,
//!    shortens the moves of its vertices: half way, a quarter, then not at all, until no face
//!    is flipped or folded. Each pass shortens at least one move, so it ends, at worst where
//!    the iteration began.
//! 3. Repeat `iterations` times (the planes are re-estimated around the moved vertices).
//!
//! Faces, winding and vertex normals are untouched; the mesh stays as manifold as it was. The
//! cost is a k-nearest search per vertex and iteration among the points: about a
//! millisecond for 500 vertices against 4,096 points.

use rustc_hash::FxHashMap;

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use crate::extract::manifold::unit_normal;
use crate::geometry::nearest::PointIndex;
use crate::geometry::plane_fit::least_spread_direction;
use crate::geometry::topology::{Edge, folds};
use crate::surface::input::InputPoints;

/// Options of [`fit_to_points`] (missing JSON fields take the defaults).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FitOptions {
    /// Projection rounds; 0 turns fitting off.
    pub iterations: usize,
    /// Input points that define each vertex's local plane (at least 3 are used).
    pub neighbours: usize,
    /// Each round first moves a vertex this fraction of the way to the centroid of its
    /// neighbours along edges (0: none), evening out crumpled, crowded vertices before they
    /// are projected.
    pub smoothing: f32,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            iterations: 3,
            neighbours: 8,
            smoothing: 0.0,
        }
    }
}

impl FitOptions {
    /// No fitting.
    pub const OFF: Self = Self {
        iterations: 0,
        neighbours: 8,
        smoothing: 0.0,
    };
}

/// What [`fit_to_points`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    pub iterations: usize,
    pub vertices: usize,
    /// Vertex moves refused outright in the last round (even a quarter of the move flipped or
    /// folded a face).
    pub held_back: usize,
    /// Mean distance from a vertex to its nearest input point, before and after.
    pub mean_distance_before: f32,
    pub mean_distance_after: f32,
}

/// Moves the vertices of `positions` (faces or not) onto the surface sampled by the input
/// `points` (see the module documentation). With no finite point, no face or no iteration
/// nothing moves.
pub fn fit_to_points(
    positions: &mut [Vec3],
    faces: &[[u32; 3]],
    points: &InputPoints,
    opts: &FitOptions,
) -> FitReport {
    let vertices = positions.len();
    if opts.iterations == 0 {
        return FitReport {
            vertices,
            ..FitReport::default()
        };
    }
    let index = points.index();
    let mut report = FitReport {
        vertices,
        ..FitReport::default()
    };
    if index.is_empty() || vertices == 0 {
        return report;
    }
    let nearest = |p: Vec3| index.nearest(p).map_or(0.0, |(_, q, _)| p.distance(q));
    let mean_distance = |positions: &[Vec3]| {
        let sum: f64 = positions.iter().map(|&p| f64::from(nearest(p))).sum();
        (sum / vertices as f64) as f32
    };
    report.mean_distance_before = mean_distance(positions);
    let pairs = face_pairs(faces);
    let k = opts.neighbours.max(3);
    let ring = if opts.smoothing > 0.0 {
        crate::geometry::topology::adjacency(vertices, &crate::geometry::topology::edges(faces))
    } else {
        vec![Vec::new(); vertices]
    };
    for _ in 0..opts.iterations {
        let before = positions.to_vec();
        for (i, p) in positions.iter_mut().enumerate() {
            let around = &ring[i];
            let start = if around.is_empty() {
                *p
            } else {
                let centroid =
                    around.iter().map(|&j| before[j as usize]).sum::<Vec3>() / around.len() as f32;
                *p + (centroid - *p) * opts.smoothing
            };
            *p = project(start, index, k);
        }
        report.held_back = hold_back_folds(positions, &before, faces, &pairs);
        report.iterations += 1;
    }
    report.mean_distance_after = mean_distance(positions);
    report
}

/// `p` projected onto the plane of its `k` nearest `points` (their centroid, the direction of
/// least spread); `p` itself where they do not define a plane.
pub(crate) fn project(p: Vec3, points: &PointIndex, k: usize) -> Vec3 {
    let near: Vec<DVec3> = points.k_nearest(p, k).map(|(_, q)| q.as_dvec3()).collect();
    let Some(normal) = least_spread_direction(&near) else {
        return p;
    };
    let centroid = near.iter().copied().sum::<DVec3>() / near.len() as f64;
    let v = p.as_dvec3();
    (v - normal * (v - centroid).dot(normal)).as_vec3()
}

/// The two faces of each edge that has exactly two.
pub(crate) fn face_pairs(faces: &[[u32; 3]]) -> Vec<[usize; 2]> {
    let mut by_edge: FxHashMap<Edge, Vec<usize>> = FxHashMap::default();
    for (f, &[a, b, c]) in faces.iter().enumerate() {
        for (x, y) in [(a, b), (b, c), (c, a)] {
            by_edge.entry([x.min(y), x.max(y)]).or_default().push(f);
        }
    }
    let mut pairs: Vec<[usize; 2]> = by_edge
        .into_values()
        .filter_map(|f| <[usize; 2]>::try_from(f).ok())
        .collect();
    pairs.sort_unstable();
    pairs
}

/// Shortens the moves from `before` of the vertices of any face that flipped (normal turned by
/// 90 degrees or more, or area lost) or newly folds onto its neighbour across an edge: each
/// such vertex goes half as far, then a quarter, then stays where it was, until no face is
/// flipped or folded. Returns how many vertices were put all the way back.
pub(crate) fn hold_back_folds(
    positions: &mut [Vec3],
    before: &[Vec3],
    faces: &[[u32; 3]],
    pairs: &[[usize; 2]],
) -> usize {
    let old: Vec<Vec3> = faces.iter().map(|&f| unit_normal(before, f)).collect();
    let target = positions.to_vec();
    // How far along its move each vertex is: 1, 1/2, 1/4, then 0.
    let mut fraction = vec![1.0f32; positions.len()];
    loop {
        let new: Vec<Vec3> = faces.iter().map(|&f| unit_normal(positions, f)).collect();
        let mut bad: Vec<usize> = (0..faces.len())
            .filter(|&f| new[f] == Vec3::ZERO || new[f].dot(old[f]) <= 0.0)
            .collect();
        bad.extend(pairs.iter().flat_map(|&[f, g]| {
            let fold = |n: &[Vec3]| folds(n[f].as_dvec3(), n[g].as_dvec3());
            if fold(&new) && !fold(&old) {
                vec![f, g]
            } else {
                Vec::new()
            }
        }));
        let mut shortened = false;
        for f in bad {
            for i in faces[f] {
                let i = i as usize;
                if positions[i] != before[i] {
                    fraction[i] = if fraction[i] > 0.3 {
                        fraction[i] * 0.5
                    } else {
                        0.0
                    };
                    positions[i] = before[i] + (target[i] - before[i]) * fraction[i];
                    if fraction[i] == 0.0 {
                        // Exactly where it was, whatever the rounding of the line above.
                        positions[i] = before[i];
                    }
                    shortened = true;
                }
            }
        }
        if !shortened {
            return fraction.iter().filter(|&&t| t == 0.0).count();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_points(z: impl Fn(f32, f32) -> f32) -> Vec<Vec3> {
        let mut points = Vec::new();
        for i in 0..=40 {
            for j in 0..=40 {
                let (x, y) = (i as f32 / 20.0 - 1.0, j as f32 / 20.0 - 1.0);
                points.push(Vec3::new(x, y, z(x, y)));
            }
        }
        points
    }

    /// A 3x3 grid of vertices (8 faces, wound +z) lifted by `dz`.
    fn square(dz: impl Fn(usize) -> f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let positions = (0..9)
            .map(|k| {
                let (i, j) = (k % 3, k / 3);
                Vec3::new(i as f32 * 0.5 - 0.5, j as f32 * 0.5 - 0.5, dz(k))
            })
            .collect();
        let mut faces = Vec::new();
        for j in 0..2u32 {
            for i in 0..2u32 {
                let a = j * 3 + i;
                faces.push([a, a + 1, a + 4]);
                faces.push([a, a + 4, a + 3]);
            }
        }
        (positions, faces)
    }

    #[test]
    fn vertices_off_a_plane_land_on_it_without_sliding_along_it() {
        let points = grid_points(|_, _| 0.0);
        let (mut positions, faces) = square(|k| 0.05 * (k % 3) as f32 - 0.03);
        let xy: Vec<_> = positions.iter().map(|p| (p.x, p.y)).collect();
        let report = fit_to_points(
            &mut positions,
            &faces,
            &InputPoints::new(&points),
            &FitOptions::default(),
        );
        assert_eq!(report.vertices, 9);
        assert_eq!(report.held_back, 0);
        assert!(report.mean_distance_before > 0.02);
        for (p, (x, y)) in positions.iter().zip(xy) {
            assert!(p.z.abs() < 1e-5, "{p}");
            assert!((p.x - x).abs() < 1e-5 && (p.y - y).abs() < 1e-5, "{p}");
        }
        assert!(report.mean_distance_after < 1e-5);
    }

    #[test]
    fn smoothing_evens_out_a_crowded_vertex_and_keeps_it_on_the_surface() {
        // The centre vertex of the grid pushed next to a corner and lifted off the plane:
        // smoothing draws it back towards its neighbours' centroid, the projection onto the
        // plane; without smoothing it only lands on the plane where it is.
        let points = grid_points(|_, _| 0.0);
        let (mut crowded, faces) = square(|k| if k == 4 { 0.04 } else { 0.0 });
        crowded[4] = Vec3::new(-0.35, -0.35, 0.04);
        let mut plain = crowded.clone();
        fit_to_points(
            &mut plain,
            &faces,
            &InputPoints::new(&points),
            &FitOptions::default(),
        );
        let smooth = FitOptions {
            smoothing: 0.5,
            ..FitOptions::default()
        };
        let report = fit_to_points(&mut crowded, &faces, &InputPoints::new(&points), &smooth);
        assert_eq!(report.held_back, 0);
        assert!(crowded[4].z.abs() < 1e-5 && plain[4].z.abs() < 1e-5);
        assert!((plain[4].x + 0.35).abs() < 1e-5, "{}", plain[4]);
        assert!(
            crowded[4].truncate().length() < 0.5 * plain[4].truncate().length(),
            "{} vs {}",
            crowded[4],
            plain[4]
        );
    }

    #[test]
    fn a_move_that_would_collapse_faces_is_shortened() {
        // Points on the plane x = 0.6, across the square: projecting every vertex onto it
        // would collapse every face to a line, so the moves are shortened until none does.
        let (mut positions, faces) = square(|_| 0.0);
        let original = positions.clone();
        let normals_before: Vec<Vec3> = faces.iter().map(|&f| unit_normal(&positions, f)).collect();
        let points: Vec<Vec3> = (0..=40)
            .flat_map(|i| {
                (0..=40).map(move |j| Vec3::new(0.6, i as f32 / 20.0 - 1.0, j as f32 / 20.0 - 1.0))
            })
            .collect();
        fit_to_points(
            &mut positions,
            &faces,
            &InputPoints::new(&points),
            &FitOptions::default(),
        );
        for (f, &face) in faces.iter().enumerate() {
            let n = unit_normal(&positions, face);
            assert!(
                n != Vec3::ZERO && n.dot(normals_before[f]) > 0.0,
                "face {f} flipped"
            );
        }
        assert_ne!(positions, original, "shortened moves still move");
        let xs: Vec<f32> = positions.iter().map(|p| p.x).collect();
        assert!(xs.iter().any(|&x| (x - 0.6).abs() > 0.05), "{xs:?}");
    }

    #[test]
    fn no_points_or_no_iterations_leave_the_mesh_alone() {
        let (mut positions, faces) = square(|k| k as f32 * 0.01);
        let original = positions.clone();
        fit_to_points(
            &mut positions,
            &faces,
            &InputPoints::new(&[]),
            &FitOptions::default(),
        );
        assert_eq!(positions, original);
        let points = grid_points(|_, _| 0.0);
        fit_to_points(
            &mut positions,
            &faces,
            &InputPoints::new(&points),
            &FitOptions::OFF,
        );
        assert_eq!(positions, original);
        let nan = vec![Vec3::NAN; 10];
        fit_to_points(
            &mut positions,
            &faces,
            &InputPoints::new(&nan),
            &FitOptions::default(),
        );
        assert_eq!(positions, original);
    }
}
