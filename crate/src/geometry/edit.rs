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

use crate::Mesh;
use crate::geometry::nearest::PointIndex;
use crate::geometry::topology::folds;

/// A manifold triangle mesh under local edits (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct EditMesh {
    pub positions: Vec<DVec3>,
    /// Faces by index; dead ones are `None` (indices stay stable during edits). Read only:
    /// the edits keep the vertex lists and the live count in step with it.
    pub faces: Vec<Option<[u32; 3]>>,
    /// The live faces of each vertex.
    vertex_faces: Vec<Vec<u32>>,
    /// How many faces are live, kept as edits go (decimation asks after every collapse).
    live_faces: usize,
}

/// An edge collapse that keeps the mesh manifold ([`EditMesh::plan_collapse`]), to be tried
/// at one position or more ([`EditMesh::collapse_keeps_shape`]).
#[derive(Debug)]
pub struct CollapsePlan {
    a: u32,
    b: u32,
    /// The faces of `a` and `b`, and the same with `b` renamed `a`, the edge's faces gone.
    before: Vec<[u32; 3]>,
    after: Vec<[u32; 3]>,
    /// The folded edges of `before`, counted when first asked.
    folded_before: std::cell::OnceCell<usize>,
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
            live_faces: 0,
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
        self.live_faces += 1;
        for v in f {
            self.vertex_faces[v as usize].push(id);
        }
        id
    }

    fn kill_face(&mut self, id: u32) {
        if let Some(f) = self.faces[id as usize].take() {
            self.live_faces -= 1;
            for v in f {
                self.vertex_faces[v as usize].retain(|&g| g != id);
            }
        }
    }

    /// Live faces.
    pub fn face_count(&self) -> usize {
        self.live_faces
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
        // The edge (v, w) has as many faces as v's faces that hold w: count each neighbour's
        // appearances in one sorted list rather than walking v's faces once per neighbour.
        let mut others: Vec<u32> = self.vertex_faces[v as usize]
            .iter()
            .flat_map(|&id| self.face(id))
            .filter(|&w| w != v)
            .collect();
        others.sort_unstable();
        others.chunk_by(|p, q| p == q).any(|run| run.len() != 2)
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
    /// documentation): [`Self::plan_collapse`] then [`Self::collapse_keeps_shape`].
    pub fn can_collapse(&self, a: u32, b: u32, x: DVec3, min_cos: f64) -> bool {
        self.plan_collapse(a, b)
            .is_some_and(|plan| self.collapse_keeps_shape(&plan, x, min_cos))
    }

    /// The collapse of the edge `(a, b)` into `a` if it keeps the mesh manifold, wherever `a`
    /// goes: the link condition, no two boundaries joined across an interior edge, no
    /// tetrahedron or pillow closed. Separate from [`Self::collapse_keeps_shape`] so that a
    /// caller trying several positions asks once.
    pub fn plan_collapse(&self, a: u32, b: u32) -> Option<CollapsePlan> {
        let e = self.edge_faces(a, b);
        if e.count == 0 || e.count > 2 {
            return None;
        }
        let apexes = &e.apex[..e.count];
        let (na, nb) = (self.neighbours(a), self.neighbours(b));
        let shared = na.iter().filter(|v| nb.binary_search(v).is_ok()).count();
        if shared != e.count || !apexes.iter().all(|v| na.binary_search(v).is_ok()) {
            return None;
        }
        if e.count == 2 && self.is_boundary(a) && self.is_boundary(b) {
            return None;
        }
        // A tetrahedron (or a lone triangle) would lose its last faces, or fold onto itself.
        let remaining =
            self.vertex_faces[a as usize].len() + self.vertex_faces[b as usize].len() - 2 * e.count;
        if remaining < 2 || na.len() + nb.len() <= 2 + 2 * e.count {
            return None;
        }
        // The faces of `a` and `b` before, and after with `b` renamed `a` (the edge's own
        // faces, the only ones holding both, go).
        let before = self.faces_of_both(a, b);
        let after: Vec<[u32; 3]> = (before.iter())
            .filter(|f| !(f.contains(&a) && f.contains(&b)))
            .map(|f| f.map(|v| if v == b { a } else { v }))
            .collect();
        // Two faces on the same three vertices afterwards (a pillow hanging off the mesh by its
        // corners): possible when the edge's apexes are joined around both ends, which the
        // neighbour count above does not see.
        let sorted = |f: &[u32; 3]| {
            let mut f = *f;
            f.sort_unstable();
            f
        };
        let of_a = self.vertex_faces[a as usize].len() - e.count;
        let (around_a, around_b) = after.split_at(of_a);
        let around_a: Vec<[u32; 3]> = around_a.iter().map(sorted).collect();
        if around_b.iter().any(|f| around_a.contains(&sorted(f))) {
            return None;
        }
        Some(CollapsePlan {
            a,
            b,
            before,
            after,
            folded_before: std::cell::OnceCell::new(),
        })
    }

    /// Whether the planned collapse with `a` at `x` turns no surviving face by more than
    /// `acos(min_cos)`, leaves none without area and leaves no more folded edges around it.
    pub fn collapse_keeps_shape(&self, plan: &CollapsePlan, x: DVec3, min_cos: f64) -> bool {
        let (a, b) = (plan.a, plan.b);
        let moved = |v: u32| {
            if v == a || v == b {
                x
            } else {
                self.positions[v as usize]
            }
        };
        for f in plan
            .before
            .iter()
            .filter(|f| !(f.contains(&a) && f.contains(&b)))
        {
            let before = self.corners(*f);
            let after = f.map(moved);
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
        // With no folded edge after, there cannot be more than before: most edits end here,
        // and the count before is taken only when needed (once per plan).
        let after = self.folded_around(&[a, b], &plan.after, moved);
        after == 0
            || after
                <= *plan.folded_before.get_or_init(|| {
                    self.folded_around(&[a, b], &plan.before, |v| self.positions[v as usize])
                })
    }

    /// The folded edges ([`folds`]) on the edges of `fan`, all the faces of the `edited`
    /// vertices as an edit leaves them, with the vertices at `at`: each edge counts once for
    /// each face walking it from its lower vertex that folds against a face walking it back.
    /// The faces across the fan's outer edges are the mesh's own. Edges away from the fan keep
    /// their faces and normals, so comparing this before and after an edit compares the whole
    /// mesh's count.
    fn folded_around(&self, edited: &[u32], fan: &[[u32; 3]], at: impl Fn(u32) -> DVec3) -> usize {
        let mut edges: Vec<[u32; 2]> = (fan.iter())
            .flat_map(|&[p, q, r]| [[p, q], [q, r], [r, p]])
            .map(|[u, v]| [u.min(v), u.max(v)])
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let normal = |f: [u32; 3]| {
            let [p, q, r] = f.map(&at);
            (q - p).cross(r - p)
        };
        let walks = |f: [u32; 3], u: u32, v: u32| (0..3).any(|k| f[k] == u && f[(k + 1) % 3] == v);
        let mut on_edge: Vec<[u32; 3]> = Vec::with_capacity(4);
        let mut folded = 0;
        for [u, v] in edges {
            on_edge.clear();
            on_edge.extend(fan.iter().filter(|f| f.contains(&u) && f.contains(&v)));
            // An edge of an edited vertex has only the fan's faces.
            if !edited.contains(&u) && !edited.contains(&v) {
                on_edge.extend(
                    (self.vertex_faces[u as usize].iter())
                        .map(|&id| self.face(id))
                        .filter(|f| f.contains(&v) && !edited.iter().any(|e| f.contains(e))),
                );
            }
            folded += (on_edge.iter())
                .filter(|&&f| walks(f, u, v))
                .filter(|&&f| {
                    (on_edge.iter())
                        .filter(|&&g| walks(g, v, u))
                        .any(|&g| folds(normal(f), normal(g)))
                })
                .count();
        }
        folded
    }

    /// The faces of `a` (in order), then those of `b` without `a`: each face of either once.
    fn faces_of_both(&self, a: u32, b: u32) -> Vec<[u32; 3]> {
        let of_a = self.vertex_faces[a as usize]
            .iter()
            .map(|&id| self.face(id));
        let of_b = self.vertex_faces[b as usize]
            .iter()
            .map(|&id| self.face(id));
        of_a.chain(of_b.filter(|f| !f.contains(&a))).collect()
    }

    fn face(&self, id: u32) -> [u32; 3] {
        self.faces[id as usize].expect("live")
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
        let fan = self.faces_of_both(a, b);
        let mut after: Vec<[u32; 3]> = (fan.iter())
            .filter(|f| !(f.contains(&a) && f.contains(&b)))
            .copied()
            .collect();
        after.extend([[a, d, c], [b, c, d]]);
        let folded = self.folded_around(&[a, b], &after, p);
        folded == 0 || folded <= self.folded_around(&[a, b], &fan, p)
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

    /// `mesh` open to edits (its positions in f64).
    pub fn from_mesh(mesh: &Mesh) -> Self {
        EditMesh::new(
            mesh.positions.iter().map(|p| p.as_dvec3()).collect(),
            &mesh.faces,
        )
    }

    /// The live faces as a mesh ([`Self::compacted`], positions back in f32, no normals).
    pub fn to_mesh(&self) -> Mesh {
        let (positions, faces, _) = self.compacted();
        Mesh::new(positions.iter().map(|p| p.as_vec3()).collect(), faces)
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
    use crate::geometry::primitives::{cube, grid, icosphere};
    use crate::geometry::topology::TopologyReport;

    fn edit(m: &Mesh) -> EditMesh {
        EditMesh::from_mesh(m)
    }

    fn report(e: &EditMesh) -> TopologyReport {
        TopologyReport::of(&e.to_mesh())
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
