//! Vertices the surface does not need: one inside a flat region, on a straight crease or on a
//! straight stretch of boundary goes, by a half-edge collapse into a neighbour that leaves the
//! surface where it was (within a tolerance), so a flat face ends as few triangles as its
//! outline allows. Hand-written on [`EditMesh`](crate::geometry::edit::EditMesh): a
//! simplifier driven by an error budget (quadric decimation) stops at its budget, not at the
//! last vertex that changes nothing.

use glam::DVec3;

use crate::geometry::edit::EditMesh;
use crate::geometry::triangle::point_triangle_distance;

/// No face around a removed vertex may turn by more than about 1 degree (cos 1 degree,
/// written out: no trigonometry, so the browser's build decides as the native one does).
const SAME_PLANE_COS: f64 = 0.999_847_695_156_391_2;

/// Removes, pass after pass until none is left, each vertex whose collapse into one of its
/// neighbours moves the surface by at most `tolerance`: the removed vertex stays within
/// `tolerance` of the faces that replace its own, the neighbour within `tolerance` of the
/// planes of the faces it joins, seven points of each new face within `tolerance` of the old
/// faces and of each old face within it of the new ones, no face turns by more than about a
/// degree, and the mesh stays manifold with no more folded edges ([`EditMesh::can_collapse`]).
/// Each collapse is judged against the mesh as it is then, so over several the surface can
/// drift by more; on a flat side or a straight crease it does not move at all. Of the
/// neighbours that qualify, the one whose new faces have the largest smallest angle takes it.
/// Returns the vertices removed.
pub fn remove_redundant_vertices(m: &mut EditMesh, tolerance: f64) -> usize {
    let mut removed = 0;
    loop {
        let before = removed;
        for v in 0..m.positions.len() as u32 {
            if m.faces_of(v).is_empty() {
                continue;
            }
            let best = (m.neighbours(v).into_iter())
                .filter_map(|u| keeps_surface(m, u, v, tolerance).map(|shape| (u, shape)))
                .max_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((u, _)) = best {
                m.collapse(u, v, m.positions[u as usize]);
                removed += 1;
            }
        }
        if removed == before {
            return removed;
        }
    }
}

/// If collapsing `v` into `u` (at `u`'s place) leaves the surface within `tolerance` of where
/// it was: the smallest sine of an angle of the faces it leaves `v`'s fan (larger is better
/// shaped).
fn keeps_surface(m: &EditMesh, u: u32, v: u32, tolerance: f64) -> Option<f64> {
    let (pu, pv) = (m.positions[u as usize], m.positions[v as usize]);
    let moved: Vec<([DVec3; 3], [DVec3; 3])> = (m.faces_of(v).iter())
        .filter_map(|&id| m.faces[id as usize])
        .filter(|f| !f.contains(&u))
        .map(|f| {
            let old = f.map(|w| m.positions[w as usize]);
            let new = f.map(|w| if w == v { pu } else { m.positions[w as usize] });
            (old, new)
        })
        .collect();
    for (old, _) in &moved {
        let normal = (old[1] - old[0]).cross(old[2] - old[0]).normalize_or_zero();
        if normal == DVec3::ZERO || normal.dot(pu - old[0]).abs() > tolerance {
            return None;
        }
    }
    // A vertex whose faces all hold `u` (a fan's last face) is covered by the edge's faces,
    // which go: only a vertex with faces left over can be judged.
    if moved.is_empty() || nearest(pv, moved.iter().map(|(_, new)| *new)) > tolerance {
        return None;
    }
    // And each new face lies on the old ones: a sliver's plane says little about where the
    // surface is, and a face swung in it from `v` to a far `u` would pass the tests above.
    let old: Vec<[DVec3; 3]> = (m.faces_of(v).iter())
        .filter_map(|&id| m.faces[id as usize])
        .map(|f| f.map(|w| m.positions[w as usize]))
        .collect();
    let new: Vec<[DVec3; 3]> = moved.iter().map(|(_, t)| *t).collect();
    let covered_by = |t: &[DVec3; 3], by: &[[DVec3; 3]]| {
        PROBES.iter().all(|[a, b, c]| {
            nearest(*a * t[0] + *b * t[1] + *c * t[2], by.iter().copied()) <= tolerance
        })
    };
    // Both ways: the old faces' probes on the new ones too (a rim cut short).
    let on_old = |t: &[DVec3; 3]| covered_by(t, &old);
    let on_new = |t: &[DVec3; 3]| covered_by(t, &new);
    if !new.iter().all(on_old)
        || !old.iter().all(on_new)
        || !m.can_collapse(u, v, pu, SAME_PLANE_COS)
    {
        return None;
    }
    Some(
        (moved.iter())
            .map(|(_, t)| smallest_angle_sine(*t))
            .fold(f64::INFINITY, f64::min),
    )
}

/// Where a face is checked against the faces on the other side of a collapse (barycentric
/// weights): its centroid, its edges' midpoints and the points halfway from the centroid to
/// its corners.
const PROBES: [[f64; 3]; 7] = [
    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.5],
    [0.5, 0.0, 0.5],
    [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
];

/// The distance from `x` to the nearest of `triangles`.
fn nearest(x: DVec3, triangles: impl Iterator<Item = [DVec3; 3]>) -> f64 {
    triangles
        .map(|t| point_triangle_distance(x, t))
        .fold(f64::INFINITY, f64::min)
}

/// The sine of the triangle's smallest angle (0 for one without area).
fn smallest_angle_sine([a, b, c]: [DVec3; 3]) -> f64 {
    let twice_area = (b - a).cross(c - a).length();
    // sin(angle at a) = 2 area / (|ab| |ac|); the smallest angle is opposite the shortest side,
    // so between the two longest.
    let mut sides = [a.distance(b), b.distance(c), c.distance(a)];
    sides.sort_by(f64::total_cmp);
    twice_area / (sides[1] * sides[2]).max(1e-300)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mesh;
    use crate::geometry::primitives::{cube, grid, icosphere};
    use crate::geometry::sample::sample_surface;
    use crate::geometry::topology::TopologyReport;
    use glam::Vec3;

    /// The farthest that samples of either mesh are from the other's surface (a Hausdorff
    /// distance up to the sampling).
    fn farthest_apart(a: &Mesh, b: &Mesh) -> f64 {
        let one_way = |from: &Mesh, to: &Mesh| {
            let samples = sample_surface(from, 2000, 7).unwrap();
            (samples.points.iter().chain(&from.positions))
                .map(|x| {
                    (0..to.faces.len())
                        .map(|f| {
                            point_triangle_distance(
                                x.as_dvec3(),
                                to.triangle(f).map(|c| c.as_dvec3()),
                            )
                        })
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max)
        };
        one_way(a, b).max(one_way(b, a))
    }

    fn removed(m: &Mesh, tolerance: f64) -> (Mesh, usize) {
        let mut e = EditMesh::from_mesh(m);
        let n = remove_redundant_vertices(&mut e, tolerance);
        (e.to_mesh(), n)
    }

    #[test]
    fn a_box_with_slivers_along_its_edges_stays_where_it_was() {
        // A finely split cube whose vertices near an edge are pushed onto it (with a jitter far
        // under the tolerance): flat sides to clear, and along its edges slivers whose planes,
        // tilted by the jitter, say nothing about the surface.
        let tolerance = 0.01;
        let mut rng = crate::rng::Rng::new(3);
        let mut e = EditMesh::from_mesh(&cube());
        for _ in 0..3 {
            e.subdivide();
        }
        for p in &mut e.positions {
            let near: Vec<usize> = (0..3).filter(|&k| p[k].abs() > 0.6).collect();
            if near.len() >= 2 {
                for k in near {
                    p[k] = p[k].signum();
                }
            }
            let j = DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) - 0.5;
            *p += j * 1e-4;
        }
        let m = e.to_mesh();
        let (out, n) = removed(&m, tolerance);
        let apart = farthest_apart(&m, &out);
        assert!(n > 100, "{n} removed");
        assert!(apart <= tolerance + 1e-6, "{n} removed, {apart} apart");
    }

    #[test]
    fn a_finely_split_square_becomes_two_triangles() {
        let (out, n) = removed(&grid(6, 5), 1e-6);
        assert_eq!((n, out.positions.len(), out.faces.len()), (38, 4, 2));
        let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
        for p in &out.positions {
            assert!(corners.contains(&(p.x, p.y)), "{p}");
        }
        assert!((out.area() - 1.0).abs() < 1e-6);
        let t = TopologyReport::of(&out);
        assert_eq!(
            (t.holes, t.non_manifold_edges, t.inconsistent_winding_edges),
            (1, 0, 0)
        );
    }

    #[test]
    fn a_split_cube_becomes_its_eight_corners_and_twelve_faces() {
        let mut e = EditMesh::from_mesh(&cube());
        e.subdivide();
        e.subdivide();
        assert_eq!(e.face_count(), 192);
        let n = remove_redundant_vertices(&mut e, 1e-6);
        let out = e.to_mesh();
        assert_eq!((n, out.positions.len(), out.faces.len()), (90, 8, 12));
        assert!(
            out.positions.iter().all(|p| p.abs() == Vec3::ONE),
            "{:?}",
            out.positions
        );
        assert!((out.signed_volume() - 8.0).abs() < 1e-5);
        let t = TopologyReport::of(&out);
        assert_eq!(
            (t.holes, t.non_manifold_edges, t.inconsistent_winding_edges),
            (0, 0, 0)
        );
    }

    #[test]
    fn bumps_creases_corners_and_curves_stay_where_they_were() {
        let tolerance = 0.01;
        // A bump higher than the tolerance, a crease across a sheet, a sphere, a sheet bent
        // by less than the tolerance (it may flatten, by at most that).
        let mut bump = grid(6, 6);
        bump.positions[24].z = 0.05;
        let mut bent = grid(6, 6);
        for p in &mut bent.positions {
            p.z = 0.4 * (p.x - 0.5).abs();
        }
        let mut shallow = grid(6, 6);
        for p in &mut shallow.positions {
            p.z = 0.004 * (p.x - 0.5).abs();
        }
        for (name, m) in [
            ("bump", bump),
            ("bent", bent),
            ("sphere", icosphere(2)),
            ("shallow", shallow),
        ] {
            let (out, n) = removed(&m, tolerance);
            let apart = farthest_apart(&m, &out);
            assert!(
                apart <= tolerance + 1e-6,
                "{name}: {n} removed, {apart} apart"
            );
            let t = TopologyReport::of(&out);
            assert_eq!(
                (
                    t.non_manifold_edges,
                    t.inconsistent_winding_edges,
                    t.folded_edges
                ),
                (0, 0, 0),
                "{name}"
            );
            assert_eq!(t.holes, TopologyReport::of(&m).holes, "{name}");
            match name {
                // The bump's tip and the crease's ends stay; the sphere has no flat vertex.
                "bump" => assert!(out.positions.iter().any(|p| p.z == 0.05), "{name}"),
                "bent" => assert_eq!((out.positions.len(), out.faces.len()), (6, 4), "{name}"),
                "sphere" => assert_eq!(n, 0),
                _ => {}
            }
        }
    }
}
