//! A triangle mesh open to local edits (edge collapse, edge flip, 1-to-4 subdivision) that
//! keep it manifold and its winding consistent.
//!
//! Each vertex keeps the list of its faces, so an edit touches only the faces around it.
//! The guards are the classical ones: a collapse must pass the link condition (the two
//! vertices share no neighbour but the apexes of the edge's faces; Dey et al., "Topology
//! Preserving Edge Contraction", 1999) and may not join two boundaries across an interior edge
//! or turn a face by more than a limit; a flip may not create an edge that exists or leave a
//! vertex of degree 2. Neither may leave more folded edges around it than there were (two
//! neighbouring faces doubled over, [`crate::geometry::topology::folds`]): a guard on each
//! face alone lets two faces close onto each other. Hand-written: the crates that simplify
//! meshes (meshopt) bind C++ that does not build for the browser module, and none exposes both guarded flips and collapses.

use glam::DVec3;

use crate::geometry::nearest::PointIndex;
use crate::geometry::topology::folds;

/// A manifold triangle mesh under local edits (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct EditMesh {
    pub positions: Vec<DVec3>,
    /// Faces by index; dead ones are `None` (indices stay stable during edits).
    pub faces: Vec<Option<[u32; 3]>>,
    /// The live faces of each vertex.
    vertex_faces: Vec<Vec<u32>>,
}

/// The faces on the edge `(a, b)`: `a` to `b` in the first, if any, then the others.
#[derive(Clone, Copy, Debug, Default)]
struct EdgeFaces {
    count: usize,
    faces: [u32; 2],
    /// The vertex of each face opposite the edge.
    apex: [u32; 2],
}

impl EditMesh {
    /// The mesh of `positions` and `faces` (indices in range, three distinct vertices each;
    /// faces that break that are left out).
    pub fn new(positions: Vec<DVec3>, faces: &[[u32; 3]]) -> Self {
        let mut m = EditMesh {
            vertex_faces: vec![Vec::new(); positions.len()],
            positions,
            faces: Vec::with_capacity(faces.len()),
        };
        for &f in faces {
            let n = m.positions.len() as u32;
            if f.iter().all(|&v| v < n) && f[0] != f[1] && f[1] != f[2] && f[0] != f[2] {
                m.push_face(f);
            }
        }
        m
    }

    fn push_face(&mut self, f: [u32; 3]) -> u32 {
        let id = self.faces.len() as u32;
        self.faces.push(Some(f));
        for v in f {
            self.vertex_faces[v as usize].push(id);
        }
        id
    }

    fn kill_face(&mut self, id: u32) {
        if let Some(f) = self.faces[id as usize].take() {
            for v in f {
                self.vertex_faces[v as usize].retain(|&g| g != id);
            }
        }
    }

    /// Live faces.
    pub fn face_count(&self) -> usize {
        self.faces.iter().flatten().count()
    }

    /// The live vertices (those with a face), indexed by position for nearest queries.
    pub fn vertex_index(&self) -> PointIndex {
        PointIndex::with_ids(
            (0..self.positions.len() as u32)
                .filter(|&v| !self.faces_of(v).is_empty())
                .map(|v| (v, self.positions[v as usize].as_vec3())),
        )
    }

    /// The live faces of vertex `v`.
    pub fn faces_of(&self, v: u32) -> &[u32] {
        &self.vertex_faces[v as usize]
    }

    /// The corners of a live face.
    pub fn corners(&self, f: [u32; 3]) -> [DVec3; 3] {
        f.map(|v| self.positions[v as usize])
    }

    fn edge_faces(&self, a: u32, b: u32) -> EdgeFaces {
        // Faces walking a -> b come first, the latest found first, then the others in the
        // order found; only the first two are kept. Counted in place: this runs for every
        // edge an edit guard looks at.
        let (mut forward, mut backward) = ([(0, 0); 2], [(0, 0); 2]);
        let (mut n_forward, mut n_backward) = (0, 0);
        for &id in &self.vertex_faces[a as usize] {
            let f = self.faces[id as usize].expect("vertex lists hold live faces");
            if let Some(k) = f.iter().position(|&v| v == a) {
                let (next, prev) = (f[(k + 1) % 3], f[(k + 2) % 3]);
                if next == b {
                    forward = [(id, prev), forward[0]];
                    n_forward += 1;
                } else if prev == b {
                    if n_backward < 2 {
                        backward[n_backward] = (id, next);
                    }
                    n_backward += 1;
                }
            }
        }
        let first_two = forward[..n_forward.min(2)]
            .iter()
            .chain(&backward[..n_backward.min(2)]);
        let mut e = EdgeFaces {
            count: n_forward + n_backward,
            ..EdgeFaces::default()
        };
        for (slot, &(id, apex)) in first_two.take(2).enumerate() {
            e.faces[slot] = id;
            e.apex[slot] = apex;
        }
        e
    }

    /// The vertices joined to `v` by an edge, sorted, without repeats.
    pub fn neighbours(&self, v: u32) -> Vec<u32> {
        let mut out: Vec<u32> = self.vertex_faces[v as usize]
            .iter()
            .flat_map(|&id| self.faces[id as usize].expect("live"))
            .filter(|&w| w != v)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// How many live faces the edge `(a, b)` has (1 on a boundary, 2 inside).
    pub fn faces_on_edge(&self, a: u32, b: u32) -> usize {
        self.edge_faces(a, b).count
    }

    /// Whether an edge of `v` has only one face (or more than two).
    pub fn is_boundary(&self, v: u32) -> bool {
        self.neighbours(v)
            .into_iter()
            .any(|w| self.faces_on_edge(v, w) != 2)
    }

    /// The live edges, each once as `[a, b]` with `a < b`.
    pub fn edges(&self) -> Vec<[u32; 2]> {
        let mut out: Vec<[u32; 2]> = self
            .faces
            .iter()
            .flatten()
            .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
            .map(|[a, b]| [a.min(b), a.max(b)])
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Whether collapsing the edge `(a, b)` into `a`, placed at `x`, keeps the mesh manifold,
    /// keeps every surviving face turned by less than `acos(min_cos)`, leaves none without
    /// area and leaves no more folded edges around it than there were (see the module
    /// documentation).
    pub fn can_collapse(&self, a: u32, b: u32, x: DVec3, min_cos: f64) -> bool {
        let e = self.edge_faces(a, b);
        if e.count == 0 || e.count > 2 {
            return false;
        }
        let apexes = &e.apex[..e.count];
        let (na, nb) = (self.neighbours(a), self.neighbours(b));
        let shared = na.iter().filter(|v| nb.binary_search(v).is_ok()).count();
        if shared != e.count || !apexes.iter().all(|v| na.binary_search(v).is_ok()) {
            return false;
        }
        if e.count == 2 && self.is_boundary(a) && self.is_boundary(b) {
            return false;
        }
        // A tetrahedron (or a lone triangle) would lose its last faces, or fold onto itself.
        let remaining =
            self.vertex_faces[a as usize].len() + self.vertex_faces[b as usize].len() - 2 * e.count;
        if remaining < 2 || na.len() + nb.len() <= 2 + 2 * e.count {
            return false;
        }
        let on_edge = |id: u32| e.faces[..e.count].contains(&id);
        // Two faces on the same three vertices afterwards (a pillow hanging off the mesh by its
        // corners): possible when the edge's apexes are joined around both ends, which the
        // neighbour count above does not see.
        let sorted = |f: [u32; 3]| {
            let mut f = f.map(|v| if v == b { a } else { v });
            f.sort_unstable();
            f
        };
        let around_a: Vec<[u32; 3]> = self.vertex_faces[a as usize]
            .iter()
            .filter(|&&id| !on_edge(id))
            .map(|&id| sorted(self.faces[id as usize].expect("live")))
            .collect();
        if self.vertex_faces[b as usize]
            .iter()
            .filter(|&&id| !on_edge(id))
            .any(|&id| around_a.contains(&sorted(self.faces[id as usize].expect("live"))))
        {
            return false;
        }
        for &id in self.vertex_faces[a as usize]
            .iter()
            .chain(&self.vertex_faces[b as usize])
        {
            if on_edge(id) {
                continue;
            }
            let f = self.faces[id as usize].expect("live");
            let before = self.corners(f);
            let after = f.map(|v| {
                if v == a || v == b {
                    x
                } else {
                    self.positions[v as usize]
                }
            });
            let n0 = (before[1] - before[0]).cross(before[2] - before[0]);
            let n1 = (after[1] - after[0]).cross(after[2] - after[0]);
            let (l0, l1) = (n0.length(), n1.length());
            let scale = (after[1] - after[0])
                .length_squared()
                .max((after[2] - after[0]).length_squared())
                .max((after[2] - after[1]).length_squared());
            // A face without area has no orientation to keep; it only has to gain some.
            if l1 <= 1e-9 * scale || (l0 > 1e-12 * scale && n0.dot(n1) < min_cos * l0 * l1) {
                return false;
            }
        }
        let near = self.faces_near(&[a, b]);
        let after: Vec<[u32; 3]> = (near.iter())
            .filter(|&&id| !on_edge(id))
            .map(|&id| self.face(id).map(|v| if v == b { a } else { v }))
            .collect();
        let moved = |v: u32| {
            if v == a {
                x
            } else {
                self.positions[v as usize]
            }
        };
        !self.folds_more(&near, &after, moved)
    }

    /// Whether the faces `after` (with the vertices at `at`) that an edit puts in place of the
    /// faces `near` ([`Self::faces_near`] of the edited vertices) have more folded edges.
    fn folds_more(&self, near: &[u32], after: &[[u32; 3]], at: impl Fn(u32) -> DVec3) -> bool {
        let before: Vec<[u32; 3]> = near.iter().map(|&id| self.face(id)).collect();
        self.folded_among(after, at) > self.folded_among(&before, |v| self.positions[v as usize])
    }

    fn face(&self, id: u32) -> [u32; 3] {
        self.faces[id as usize].expect("live")
    }

    /// The faces of `vertices` and the faces across their edges, once each: every face whose
    /// normal or neighbour an edit of those vertices can change.
    fn faces_near(&self, vertices: &[u32]) -> Vec<u32> {
        let mut near: Vec<u32> = (vertices.iter())
            .flat_map(|&v| self.vertex_faces[v as usize].iter().copied())
            .collect();
        near.sort_unstable();
        near.dedup();
        let across: Vec<u32> = (near.iter())
            .flat_map(|&id| {
                let [p, q, r] = self.face(id);
                [[p, q], [q, r], [r, p]]
            })
            .flat_map(|[u, v]| {
                let e = self.edge_faces(u, v);
                e.faces.into_iter().take(e.count)
            })
            .collect();
        near.extend(across);
        near.sort_unstable();
        near.dedup();
        near
    }

    /// The folded edges ([`folds`]) between the faces of `faces`, each walked both ways within
    /// the list, with the vertices at `at`.
    fn folded_among(&self, faces: &[[u32; 3]], at: impl Fn(u32) -> DVec3) -> usize {
        let normals: Vec<DVec3> = (faces.iter())
            .map(|f| {
                let [p, q, r] = f.map(&at);
                (q - p).cross(r - p)
            })
            .collect();
        let mut walked: Vec<(u32, u32, usize)> = (faces.iter().enumerate())
            .flat_map(|(i, &[p, q, r])| [(p, q, i), (q, r, i), (r, p, i)])
            .collect();
        walked.sort_unstable();
        (walked.iter())
            .filter(|&&(u, v, _)| u < v)
            .filter(|&&(u, v, f)| {
                let from = walked.partition_point(|&(p, q, _)| (p, q) < (v, u));
                (walked[from..].iter())
                    .take_while(|&&(p, q, _)| (p, q) == (v, u))
                    .any(|&(_, _, g)| folds(normals[f], normals[g]))
            })
            .count()
    }

    /// Collapses `(a, b)` into `a` at `x` (after [`Self::can_collapse`]): the edge's faces go,
    /// `b`'s other faces take `a` instead.
    pub fn collapse(&mut self, a: u32, b: u32, x: DVec3) {
        let e = self.edge_faces(a, b);
        for &id in &e.faces[..e.count] {
            self.kill_face(id);
        }
        for id in std::mem::take(&mut self.vertex_faces[b as usize]) {
            let f = self.faces[id as usize].as_mut().expect("live");
            for v in f.iter_mut() {
                if *v == b {
                    *v = a;
                }
            }
            self.vertex_faces[a as usize].push(id);
        }
        self.positions[a as usize] = x;
    }

    /// The two apexes `(c, d)` of the edge `(a, b)` if it can be flipped to `(c, d)`: the
    /// edge has two faces, `(a, b, c)` walking a -> b and `(b, a, d)` ([`Self::flip_apexes`]),
    /// and the flip passes [`Self::flip_keeps_shape`].
    pub fn flippable(&self, a: u32, b: u32) -> Option<(u32, u32)> {
        let (c, d) = self.flip_apexes(a, b)?;
        self.flip_keeps_shape(a, b, c, d).then_some((c, d))
    }

    /// The apexes `(c, d)` of the edge `(a, b)`'s two faces, `(a, b, c)` walking a -> b and
    /// `(b, a, d)` the other way, if it has exactly those (`c != d`): what a flip would join,
    /// before asking whether it may ([`Self::flip_keeps_shape`]).
    pub fn flip_apexes(&self, a: u32, b: u32) -> Option<(u32, u32)> {
        let e = self.edge_faces(a, b);
        if e.count != 2 {
            return None;
        }
        let (c, d) = (e.apex[0], e.apex[1]);
        // The first face walks a -> b; the second must walk b -> a (consistent winding).
        let second = self.faces[e.faces[1] as usize].expect("live");
        let k = second.iter().position(|&v| v == b)?;
        (second[(k + 1) % 3] == a && c != d).then_some((c, d))
    }

    /// Whether flipping the edge `(a, b)` of faces `(a, b, c)` and `(b, a, d)` (from
    /// [`Self::flip_apexes`]) to `(c, d)` keeps the mesh sound: no edge `(c, d)` yet, `a` and
    /// `b` each keep at least three neighbours, both new faces keep the orientation of the
    /// pair (their normals within 90 degrees of the old faces' summed normal) with some area,
    /// and no more edges around it fold than before.
    pub fn flip_keeps_shape(&self, a: u32, b: u32, c: u32, d: u32) -> bool {
        if self.neighbours(c).binary_search(&d).is_ok()
            || self.neighbours(a).len() <= 3
            || self.neighbours(b).len() <= 3
        {
            return false;
        }
        let p = |v: u32| self.positions[v as usize];
        let normal = |u: u32, v: u32, w: u32| (p(v) - p(u)).cross(p(w) - p(u));
        let old = normal(a, b, c).normalize_or_zero() + normal(b, a, d).normalize_or_zero();
        let new = [normal(a, d, c), normal(b, c, d)];
        let scale = p(c).distance_squared(p(d));
        if !new
            .iter()
            .all(|n| n.length() > 1e-9 * scale && n.dot(old) > 0.0)
        {
            return false;
        }
        let e = self.edge_faces(a, b);
        let near = self.faces_near(&[a, b]);
        let mut after: Vec<[u32; 3]> = (near.iter())
            .filter(|&&id| !e.faces.contains(&id))
            .map(|&id| self.face(id))
            .collect();
        after.extend([[a, d, c], [b, c, d]]);
        !self.folds_more(&near, &after, p)
    }

    /// Flips `(a, b)` to `(c, d)` (after [`Self::flippable`] gave `(c, d)`): faces
    /// `(a, b, c)` and `(b, a, d)` become `(a, d, c)` and `(b, c, d)`.
    pub fn flip(&mut self, a: u32, b: u32, c: u32, d: u32) {
        let e = self.edge_faces(a, b);
        for &id in &e.faces[..e.count] {
            self.kill_face(id);
        }
        self.push_face([a, d, c]);
        self.push_face([b, c, d]);
    }

    /// Splits every face into four at its edges' midpoints (one new vertex per edge, shared
    /// by the edge's faces), so boundaries and winding are kept. Old vertices keep their
    /// indices; the new ones follow.
    pub fn subdivide(&mut self) {
        let mut midpoint = std::collections::HashMap::new();
        let old: Vec<[u32; 3]> = self.faces.iter().flatten().copied().collect();
        let mut positions = self.positions.clone();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<DVec3>| {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push((positions[a as usize] + positions[b as usize]) * 0.5);
                (positions.len() - 1) as u32
            })
        };
        let mut faces = Vec::with_capacity(old.len() * 4);
        for [a, b, c] in old {
            let (ab, bc, ca) = (
                mid(a, b, &mut positions),
                mid(b, c, &mut positions),
                mid(c, a, &mut positions),
            );
            faces.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        *self = EditMesh::new(positions, &faces);
    }

    /// The live faces, with the vertices they use renumbered in order, and the old index of
    /// each kept vertex.
    pub fn compacted(&self) -> (Vec<DVec3>, Vec<[u32; 3]>, Vec<u32>) {
        let mut new_index = vec![u32::MAX; self.positions.len()];
        let mut kept = Vec::new();
        let mut faces = Vec::new();
        for f in self.faces.iter().flatten() {
            faces.push(f.map(|v| {
                if new_index[v as usize] == u32::MAX {
                    new_index[v as usize] = kept.len() as u32;
                    kept.push(v);
                }
                new_index[v as usize]
            }));
        }
        let positions = kept.iter().map(|&v| self.positions[v as usize]).collect();
        (positions, faces, kept)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mesh;
    use crate::geometry::primitives::{cube, grid, icosphere};
    use crate::geometry::topology::TopologyReport;

    fn edit(m: &Mesh) -> EditMesh {
        EditMesh::new(m.positions.iter().map(|p| p.as_dvec3()).collect(), &m.faces)
    }

    fn report(e: &EditMesh) -> TopologyReport {
        let (p, f, _) = e.compacted();
        TopologyReport::of(&Mesh::new(p.iter().map(|p| p.as_vec3()).collect(), f))
    }

    #[test]
    fn subdivision_keeps_topology_and_quadruples_faces() {
        for m in [cube(), grid(3, 2), icosphere(1)] {
            let before = TopologyReport::of(&m);
            let mut e = edit(&m);
            e.subdivide();
            let after = report(&e);
            assert_eq!(after.faces, 4 * before.faces);
            assert_eq!(after.holes, before.holes);
            assert_eq!(after.inconsistent_winding_edges, 0);
            assert_eq!(after.non_manifold_edges, 0);
        }
    }

    #[test]
    fn collapses_keep_a_sphere_a_sphere_down_to_what_the_guards_allow() {
        let mut e = edit(&icosphere(2));
        loop {
            let pick = e.edges().into_iter().find(|&[a, b]| {
                let x = (e.positions[a as usize] + e.positions[b as usize]) * 0.5;
                e.can_collapse(a, b, x, 0.0)
            });
            let Some([a, b]) = pick else { break };
            let x = (e.positions[a as usize] + e.positions[b as usize]) * 0.5;
            e.collapse(a, b, x);
            let r = report(&e);
            assert_eq!((r.non_manifold_edges, r.boundary_edges), (0, 0), "{r:?}");
            assert_eq!(r.inconsistent_winding_edges, 0);
            assert_eq!((r.components, r.folded_edges), (1, 0));
        }
        // Down to 20 faces (12 vertices): below that, every collapse here would fold two faces.
        assert!(e.face_count() <= 20, "{}", e.face_count());
    }

    #[test]
    fn the_link_condition_refuses_a_pinch() {
        // A strip of two triangles: collapsing the shared interior edge would join two
        // boundary vertices across it.
        let g = grid(1, 1);
        let e = edit(&g);
        let [a, b] = [0u32, 3];
        assert!(!e.can_collapse(a, b, DVec3::splat(0.5), 0.0));
    }

    #[test]
    fn a_flip_turns_a_quad_diagonal_and_keeps_the_winding() {
        let g = grid(2, 2);
        let mut e = edit(&g);
        // The corner vertex 0 has three neighbours: its diagonal may not flip.
        assert_eq!(e.flippable(0, 4), None);
        // (1, 4) joins faces (0, 1, 4) and (1, 5, 4): it flips to (0, 5).
        assert_eq!(e.flippable(1, 4), Some((0, 5)));
        e.flip(1, 4, 0, 5);
        let r = report(&e);
        assert_eq!(
            (r.faces, r.non_manifold_edges, r.inconsistent_winding_edges),
            (8, 0, 0)
        );
        assert!(e.neighbours(0).contains(&5));
        assert!(!e.neighbours(1).contains(&4));
        // Flipping back onto an existing edge is refused: (0, 5) flips only to (1, 4).
        assert_eq!(
            e.flippable(0, 5).map(|(c, d)| [c.min(d), c.max(d)]),
            Some([1, 4])
        );
    }
}
