//! Cleaning of imported meshes (docs/data.md, "Cleaning"): welding, then removal of degenerate,
//! duplicate and back-to-back faces and of unreferenced vertices.
//!
//! Rules, in the order [`clean`] applies them:
//! 1. **Weld** vertices whose Euclidean distance is `<= weld_tolerance * L`, `L` = the longest
//!    side of the input's bounding box. There is no quantisation or grid snapping: a spatial hash
//!    (cells of side `2 * tolerance`) only finds candidates, the test is the real distance
//!    (computed in `f64`). Welding is transitive (union-find), so a *chain* of points each within
//!    the tolerance of the next collapses to one vertex even when its ends are farther apart
//!    than the tolerance; the result does not depend on the order candidates are visited.
//!    Each welded class keeps the position (and normal) of its lowest-indexed vertex, and the
//!    classes keep the relative order of those vertices. With `L = 0` (all points equal) or a
//!    zero tolerance only exactly equal positions weld (`-0.0 == 0.0`).
//! 2. **Degenerate faces** are dropped: a face with a repeated vertex (after welding) or whose
//!    cross product `(b - a) x (c - a)` (in `f32`, on the welded positions) has length
//!    `<= degenerate_tolerance * L^2` (default `1e-10`, the threshold
//!    [`crate::geometry::topology::is_degenerate`] uses, so a cleaned mesh reports no degenerate faces).
//! 3. **Duplicate faces** (the same three vertices in the same cyclic orientation) are dropped,
//!    keeping the first.
//! 4. **Back-to-back faces** (the same three vertices in the opposite orientation, i.e. a
//!    double-sided copy) are dropped, keeping the first of the pair.
//! 5. **Unreferenced vertices** are dropped (the rest are compacted in their relative order and
//!    the faces remapped). Not for point clouds: an input without faces is only welded.
//!
//! Normals, when present, follow their vertices. Everything is deterministic and `O(n)`
//! expected time for well-spread points (hash maps; a 10k-vertex mesh takes milliseconds);
//! many distinct points crowded within one weld cell are compared pairwise. Positions must be finite
//! ([`Mesh::validate`]); face indices out of range panic.
//!
//! Cleaning is idempotent: the kept representatives of different classes are more than the
//! tolerance apart, and the second pass's tolerance (relative to a bounding box that can only
//! shrink) is no larger.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::geometry::disjoint_sets::DisjointSets;
use crate::geometry::topology::{DEGENERATE_TOLERANCE, is_degenerate};

/// Tunables of [`clean`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CleanOptions {
    /// Weld distance relative to the bounding box's longest side (default `1e-6`).
    pub weld_tolerance: f32,
    /// A face whose cross-product length is at most this times the longest side squared is
    /// degenerate (default `1e-10`).
    pub degenerate_tolerance: f32,
}

impl Default for CleanOptions {
    fn default() -> Self {
        Self {
            weld_tolerance: 1e-6,
            degenerate_tolerance: DEGENERATE_TOLERANCE,
        }
    }
}

/// What [`clean`] removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CleanReport {
    /// Vertices merged into another (input vertex count minus welded vertex count).
    pub welded_vertices: usize,
    /// Faces with a repeated vertex (after welding) or no area.
    pub degenerate_faces: usize,
    /// Repeated faces with the same orientation.
    pub duplicate_faces: usize,
    /// Repeated faces with the opposite orientation (double-sided copies).
    pub back_to_back_faces: usize,
    /// Vertices no remaining face uses (counted after welding).
    pub unreferenced_vertices: usize,
}

impl CleanReport {
    /// True when cleaning changed nothing.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

fn exact_key(p: Vec3) -> [u32; 3] {
    // `+ 0.0` turns -0.0 into +0.0 so both hash alike.
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// Welding classes of `positions` at absolute distance `distance` (see the module doc).
/// Returns, per input vertex, the index of its class, and the number of classes. Classes are
/// numbered in the order of their first (lowest-indexed) vertex.
pub fn weld_map(positions: &[Vec3], distance: f32) -> (Vec<u32>, usize) {
    let n = positions.len();
    let mut sets = DisjointSets::new(n);
    // Exact duplicates first (typical for STL-like per-face vertices): cheap, and it keeps the
    // spatial pass from seeing crowded cells.
    let mut first_at: HashMap<[u32; 3], u32> = HashMap::with_capacity(n);
    let mut unique: Vec<u32> = Vec::with_capacity(n);
    for (i, &p) in positions.iter().enumerate() {
        match first_at.entry(exact_key(p)) {
            Entry::Occupied(e) => sets.union(i as u32, *e.get()),
            Entry::Vacant(e) => {
                e.insert(i as u32);
                unique.push(i as u32);
            }
        }
    }
    drop(first_at);
    if distance > 0.0 && distance.is_finite() {
        let tol = distance as f64;
        let cell = 2.0 * tol;
        let tol2 = tol * tol;
        // Clamped so that neighbouring-cell arithmetic cannot overflow for a tiny tolerance;
        // far-apart points sharing a clamped cell are still compared by real distance.
        const KEY_LIMIT: f64 = (1u64 << 52) as f64;
        let key = |p: DVec3| -> [i64; 3] {
            (p / cell)
                .floor()
                .to_array()
                .map(|c| c.clamp(-KEY_LIMIT, KEY_LIMIT) as i64)
        };
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::with_capacity(unique.len());
        for &i in &unique {
            let p = positions[i as usize].as_dvec3();
            let [kx, ky, kz] = key(p);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let Some(list) = cells.get(&[kx + dx, ky + dy, kz + dz]) else {
                            continue;
                        };
                        for &j in list {
                            if (positions[j as usize].as_dvec3() - p).length_squared() <= tol2 {
                                sets.union(i, j);
                            }
                        }
                    }
                }
            }
            cells.entry([kx, ky, kz]).or_default().push(i);
        }
    }
    // Roots are the smallest index of their class, so classes are numbered by first vertex.
    sets.labels(|_| true)
}

/// Welds vertices within the absolute `distance` (see the module doc) and remaps the faces
/// (without removing any face). Returns the welded mesh and how many vertices were merged away.
pub fn weld(mesh: &Mesh, distance: f32) -> (Mesh, usize) {
    let (class, count) = weld_map(&mesh.positions, distance);
    let mut positions = Vec::with_capacity(count);
    let mut normals = Vec::with_capacity(if mesh.normals.is_empty() { 0 } else { count });
    for (i, &c) in class.iter().enumerate() {
        if c as usize == positions.len() {
            positions.push(mesh.positions[i]);
            if !mesh.normals.is_empty() {
                normals.push(mesh.normals[i]);
            }
        }
    }
    let faces = mesh
        .faces
        .iter()
        .map(|f| f.map(|v| class[v as usize]))
        .collect();
    let merged = mesh.positions.len() - count;
    (
        Mesh {
            positions,
            normals,
            faces,
        },
        merged,
    )
}

/// The sorted triple of a face and whether the face is an even permutation of it.
fn canonical(f: [u32; 3]) -> ([u32; 3], bool) {
    let mut s = f;
    s.sort_unstable();
    // Rotations of the sorted triple are the even permutations.
    let even = f == s || f == [s[1], s[2], s[0]] || f == [s[2], s[0], s[1]];
    (s, even)
}

/// Cleans `mesh` by the rules in the module doc. Returns the cleaned mesh and what was removed.
pub fn clean(mesh: &Mesh, opts: &CleanOptions) -> (Mesh, CleanReport) {
    let scale = mesh.aabb().map_or(0.0, |b| b.max_extent());
    let (welded, merged) = weld(mesh, opts.weld_tolerance * scale);
    let mut report = CleanReport {
        welded_vertices: merged,
        ..Default::default()
    };
    if mesh.faces.is_empty() {
        return (welded, report);
    }

    let mut seen: HashMap<[u32; 3], bool> = HashMap::with_capacity(welded.faces.len());
    let mut faces = Vec::with_capacity(welded.faces.len());
    for &f in &welded.faces {
        if is_degenerate(&welded.positions, f, scale, opts.degenerate_tolerance) {
            report.degenerate_faces += 1;
            continue;
        }
        let (key, even) = canonical(f);
        match seen.entry(key) {
            Entry::Vacant(e) => {
                e.insert(even);
                faces.push(f);
            }
            Entry::Occupied(e) if *e.get() == even => report.duplicate_faces += 1,
            Entry::Occupied(_) => report.back_to_back_faces += 1,
        }
    }
    let mut out = Mesh {
        positions: welded.positions,
        normals: welded.normals,
        faces,
    };
    report.unreferenced_vertices = out.remove_unreferenced_vertices();
    (out, report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{cube, grid, icosphere, octahedron};
    use crate::geometry::topology::TopologyReport;

    /// Every face gets its own three vertices, as STL stores them.
    fn explode(m: &Mesh) -> Mesh {
        let mut out = Mesh::default();
        for f in &m.faces {
            let base = out.positions.len() as u32;
            out.positions.extend(f.map(|i| m.positions[i as usize]));
            out.faces.push([base, base + 1, base + 2]);
        }
        out
    }

    #[test]
    fn tiny_tolerance_with_huge_coordinates_does_not_overflow() {
        let positions = [
            Vec3::splat(3e38),
            Vec3::splat(-3e38),
            Vec3::splat(3e38),
            Vec3::ZERO,
        ];
        let (class, count) = weld_map(&positions, f32::MIN_POSITIVE);
        assert_eq!(count, 3);
        assert_eq!(class[0], class[2]);
    }

    #[test]
    fn clean_primitives_are_untouched() {
        for m in [octahedron(), cube(), icosphere(2), grid(4, 3)] {
            let (c, r) = clean(&m, &CleanOptions::default());
            assert!(r.is_empty(), "{r:?}");
            assert_eq!(c, m);
        }
    }

    #[test]
    fn exploded_meshes_weld_back() {
        for m in [octahedron(), cube(), icosphere(2), grid(4, 3)] {
            let (c, r) = clean(&explode(&m), &CleanOptions::default());
            assert_eq!(c.positions.len(), m.positions.len());
            assert_eq!(c.faces.len(), m.faces.len());
            assert_eq!(r.welded_vertices, 3 * m.faces.len() - m.positions.len());
            assert_eq!(
                TopologyReport::of(&c).boundary_edges,
                TopologyReport::of(&m).boundary_edges
            );
        }
    }

    #[test]
    fn near_points_weld_far_points_do_not() {
        // Longest side 1, tolerance 1e-3 -> weld distance 1e-3.
        let opts = CleanOptions {
            weld_tolerance: 1e-3,
            ..Default::default()
        };
        let pts = vec![
            Vec3::ZERO,
            Vec3::new(0.0009, 0.0, 0.0),
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(0.5, 0.0011, 0.0),
            Vec3::ONE,
        ];
        let (c, r) = clean(&Mesh::from_points(pts.clone()), &opts);
        assert_eq!(r.welded_vertices, 1);
        assert_eq!(c.positions, vec![pts[0], pts[2], pts[3], pts[4]]);
        // A chain 0 - 0.0009 - 0.0018: ends are 1.8e-3 apart but weld through the middle.
        let chain = vec![
            Vec3::new(0.0018, 0.0, 0.0),
            Vec3::ZERO,
            Vec3::new(0.0009, 0.0, 0.0),
            Vec3::ONE,
        ];
        let (c, r) = clean(&Mesh::from_points(chain.clone()), &opts);
        assert_eq!(r.welded_vertices, 2);
        assert_eq!(c.positions, vec![chain[0], chain[3]]);
    }

    #[test]
    fn no_snapping_across_cell_boundaries() {
        // Two points straddling any grid line still weld; positions are not moved.
        let d = 1e-6f32;
        let a = Vec3::new(0.25 - 0.4 * d, 0.0, 0.0);
        let b = Vec3::new(0.25 + 0.4 * d, 0.0, 0.0);
        let (c, r) = clean(
            &Mesh::from_points(vec![a, b, Vec3::ONE]),
            &CleanOptions::default(),
        );
        assert_eq!(r.welded_vertices, 1);
        assert_eq!(c.positions[0], a);
    }

    #[test]
    fn face_rules_and_normals() {
        let mut m = octahedron();
        m.normals = m.positions.clone();
        m.positions.push(Vec3::new(0.0, 0.0, 1.0 + 1e-7)); // 6: welds to 4 (not bit-equal)
        m.normals.push(-Vec3::Z);
        m.positions.push(Vec3::splat(0.3)); // 7: unreferenced
        m.normals.push(Vec3::X);
        m.faces.push([4, 6, 0]); // welds into a degenerate face
        m.faces.push([2, 1, 4]); // duplicate of face 1
        m.faces.push([1, 4, 2]); // duplicate (rotation)
        m.faces.push([4, 1, 2]); // back-to-back of face 1
        m.faces.push([0, 0, 1]); // repeated vertex
        m.faces.push([0, 1, 1]);
        let (c, r) = clean(&m, &CleanOptions::default());
        assert_eq!(
            r,
            CleanReport {
                welded_vertices: 1,
                degenerate_faces: 3,
                duplicate_faces: 2,
                back_to_back_faces: 1,
                unreferenced_vertices: 1,
            }
        );
        let o = octahedron();
        assert_eq!(c.positions, o.positions);
        assert_eq!(c.faces, o.faces);
        assert_eq!(c.normals, o.positions);
    }

    #[test]
    fn zero_area_face_is_degenerate() {
        let m = Mesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::Y],
            vec![[0, 1, 2], [0, 1, 3]],
        );
        let (c, r) = clean(&m, &CleanOptions::default());
        assert_eq!(r.degenerate_faces, 1);
        assert_eq!(r.unreferenced_vertices, 1);
        assert_eq!(c.faces, vec![[0, 1, 2]]);
        assert_eq!(c.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    }

    #[test]
    fn point_clouds_and_empty() {
        let (c, r) = clean(&Mesh::default(), &CleanOptions::default());
        assert_eq!((c, r), (Mesh::default(), CleanReport::default()));
        // All points equal: longest side 0, exact welding only.
        let pts = vec![Vec3::ONE, Vec3::ONE, Vec3::ONE];
        let (c, r) = clean(&Mesh::from_points(pts), &CleanOptions::default());
        assert_eq!((c.positions.len(), r.welded_vertices), (1, 2));
        // -0.0 and 0.0 are the same position.
        let (c, _) = weld(
            &Mesh::from_points(vec![Vec3::ZERO, -Vec3::ZERO, Vec3::X]),
            0.0,
        );
        assert_eq!(c.positions.len(), 2);
    }

    #[test]
    fn large_mesh_is_fast_and_idempotent() {
        let m = explode(&icosphere(5)); // 20480 faces, 61440 corners
        let t = std::time::Instant::now();
        let (c, r) = clean(&m, &CleanOptions::default());
        let elapsed = t.elapsed();
        assert_eq!(c.positions.len(), 10242);
        assert_eq!(r.welded_vertices, 61440 - 10242);
        assert!(elapsed.as_secs_f64() < 2.0, "{elapsed:?}");
        let (c2, r2) = clean(&c, &CleanOptions::default());
        assert!(r2.is_empty());
        assert_eq!(c2, c);
    }
}
