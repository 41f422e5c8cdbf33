//! Manifold extraction, the default way decoded edges become faces (the paper's Algorithm 1
//! stays in [`crate::extract`] as `ExtractMethod::Paper`).
//!
//! Algorithm 1 keeps every 3-clique of the thresholded edge graph. Where a small model's edge
//! scores are uncertain, extra edges close extra cliques that overlap the true faces and put
//! three or more faces on an edge: the "shards". Here the cliques are only candidates, and the
//! decoder's edge scores decide between them:
//!
//! 1. **Rank.** Each candidate comes with a score, higher is better: its weakest edge's
//!    margin `d - tau` (how sure the model is of all three edges), or, from plain edges, how
//!    well its geometric normal agrees with its vertex normals ([`crate::extract::FaceSupport`]).
//!    Candidates with (numerically) no area are never accepted.
//! 2. **Accept best-first** (ties in the candidates' order). A candidate is accepted when
//!    - none of its three edges already has two faces (every edge stays manifold);
//!    - it does not fold back onto a face it shares an edge with: the two close onto each other
//!      at less than the angle [`FOLD_COS`] allows. (A quad with both diagonals has four
//!      3-cliques; the third one accepted would lie folded over the first two, which is what
//!      the overlapping sheets of Algorithm 1 are made of.)
//!    - with `overlap_tolerance` above 0, it does not lie on an accepted face that it shares
//!      at most one vertex with ([`crate::extract::overlap`]: a second layer);
//!    - and it can be wound consistently with its edge-neighbours. Accepted faces form pieces,
//!      each consistently wound up to one flip of the whole piece; a candidate joining pieces
//!      whose windings disagree flips one of them, and is refused only when two neighbours in
//!      one piece ask for opposite windings (a twist like a Moebius strip's).
//!
//!    Each piece is finally wound the way most of its faces point by Algorithm 1's rule
//!    ([`crate::extract::orient_face`], the vertex normals).
//! 3. **Fill small holes.** The edges with one face, each walked against that face, chain into
//!    hole loops (cut into simple loops where holes meet at a vertex). A loop of at most
//!    `max_hole_edges` edges is closed by ear clipping: of the ears `(h[i-1], h[i], h[i+1])`
//!    that pass the tests of step 2 and repeat no existing face (the border of a lone triangle
//!    is a 3-loop), the one whose normal best agrees with its neighbours' is added and `h[i]`
//!    leaves the loop, until it is closed; when the rest cannot be closed, the last ear is
//!    taken back and the next best tried (a bounded depth-first search). Faces are wound by now, so an ear's overlap test
//!    counts only faces facing its way (the far side of a thin part faces away and is no
//!    second layer). When no ear passes, the usual cause is a face next to the hole folded
//!    over it: for each hole edge in turn, the face on it is taken off (when its other two
//!    edges have two faces each, so the hole grows by one vertex, not into another hole) and
//!    the grown loop is clipped the same way; if that fails too the face goes back, and the
//!    loop stays open with nothing added.
//! 4. **Drop small pieces.** Pieces of faces joined through shared edges with fewer than
//!    `min_component_faces` faces are removed (with 2, the triangles that touch the rest at
//!    a vertex at most: each would be a hole of its own).
//!
//! Invariant, for any positions, normals, candidates and scores (`crate/tests/extract_props.rs`):
//! no edge has more than two faces, and the two faces on an edge walk it in opposite
//! directions. Steps 3 and 4 keep it: every ear passes the same tests, and removing faces cannot
//! break either property. The work is O(F log F) for F candidates (the sort), hash lookups
//! otherwise: well under a millisecond at the model's 512 vertices.

use glam::Vec3;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

use crate::extract::overlap::{FaceLayers, cell_size};
use crate::geometry::topology::{self, Edge, rotate_min_first, sorted_face};

/// Smallest cosine allowed between the normals of two faces that share an edge (consistently
/// wound). -0.8 rejects faces that close onto a neighbour at less than about 37 degrees
/// (normals more than 143 degrees apart): overlapping sheets, not the thin wedges and spikes of
/// real meshes, which stay above it (the extraction of the test split's ground-truth edges
/// loses no face to it; `meshflow extract`).
pub const FOLD_COS: f32 = -0.8;

/// Ears a hole's search may try before the hole is left open ([`Surface::fill`]): enough
/// for every clipping order of the small loops, a bound on the long ones.
const FILL_ATTEMPTS: usize = 256;

/// Options of [`manifold_faces`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ManifoldOptions {
    /// Close hole loops of at most this many edges (below 3: no hole filling).
    pub max_hole_edges: usize,
    /// Remove connected pieces with fewer faces than this (0 or 1: keep every piece).
    pub min_component_faces: usize,
    /// Refuse a face lying on an accepted one that shares at most one vertex with it, within
    /// this many of its longest edges of its plane ([`crate::extract::overlap`]; 0: no such test).
    pub overlap_tolerance: f32,
}

/// What [`manifold_faces`] did with its candidates.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ManifoldReport {
    /// Candidates accepted in step 2.
    pub accepted: usize,
    /// Candidates rejected because an edge already had two faces.
    pub rejected_non_manifold: usize,
    /// Candidates rejected because no winding agreed with their neighbours.
    pub rejected_winding: usize,
    /// Candidates rejected because they folded back onto a neighbour.
    pub rejected_fold: usize,
    /// Candidates rejected because they lay on an accepted face not next to them.
    pub rejected_overlap: usize,
    /// Candidates rejected for having no area.
    pub rejected_degenerate: usize,
    /// Boundary loops filled, the faces that added, and the loops left open.
    pub holes_filled: usize,
    pub hole_faces: usize,
    pub holes_left: usize,
    /// Pieces removed in step 4, and their faces.
    pub pieces_dropped: usize,
    pub piece_faces_dropped: usize,
}

/// The unit normal of a face, zero when it has (numerically) no area.
pub(crate) fn unit_normal(positions: &[Vec3], [a, b, c]: [u32; 3]) -> Vec3 {
    let [p, q, r] = [a, b, c].map(|i| positions[i as usize]);
    (q - p).cross(r - p).normalize_or_zero()
}

/// Whether triangles `(a, b, c)` and `(a, b, d)` on the edge `(a, b)` close onto each other
/// at less than the angle [`FOLD_COS`] allows, whatever their windings: the cosine between
/// the directions from the edge to `c` and to `d`, across the edge, is above `-FOLD_COS`.
fn folds(positions: &[Vec3], [a, b]: Edge, c: u32, d: u32) -> bool {
    let [pa, pb, pc, pd] = [a, b, c, d].map(|i| positions[i as usize]);
    let along = (pb - pa).normalize_or_zero();
    let across = |p: Vec3| {
        let v = p - pa;
        (v - along * v.dot(along)).normalize_or_zero()
    };
    across(pc).dot(across(pd)) > -FOLD_COS
}

/// Whether `face` walks its edge `{a, b}` from the smaller vertex to the larger.
fn walks_up(face: [u32; 3], a: u32, b: u32) -> bool {
    let (lo, hi) = (a.min(b), a.max(b));
    (0..3).any(|k| face[k] == lo && face[(k + 1) % 3] == hi)
}

/// Step 2's state: the accepted faces as first wound, the (at most two) faces on each edge,
/// and a union-find over faces whose pieces are consistently wound up to one flip each:
/// `flip[f]` says whether `f` must be flipped relative to `parent[f]`. Joining two pieces
/// whose windings disagree flips one of them as a whole instead of refusing the face.
struct Selection {
    faces: Vec<[u32; 3]>,
    parent: Vec<u32>,
    flip: Vec<bool>,
    on_edge: HashMap<Edge, [Option<u32>; 2]>,
    layers: FaceLayers,
}

impl Selection {
    /// `cell`: the overlap grid's cell side ([`cell_size`]).
    fn new(overlap_tolerance: f32, cell: f32) -> Self {
        Self {
            faces: Vec::new(),
            parent: Vec::new(),
            flip: Vec::new(),
            on_edge: HashMap::default(),
            layers: FaceLayers::new(overlap_tolerance, cell),
        }
    }

    /// The root of `f`'s piece and whether `f` is flipped relative to it (path-compressing).
    fn find(&mut self, f: u32) -> (u32, bool) {
        let mut path = Vec::new();
        let mut root = f;
        while self.parent[root as usize] != root {
            path.push(root);
            root = self.parent[root as usize];
        }
        let mut flipped = false;
        for &x in path.iter().rev() {
            flipped ^= self.flip[x as usize];
            self.flip[x as usize] = flipped;
            self.parent[x as usize] = root;
        }
        (root, f != root && self.flip[f as usize])
    }

    fn try_add(&mut self, positions: &[Vec3], face: [u32; 3]) -> Result<(), Refusal> {
        let edges = topology::face_edges(face);
        let mut neighbours = Vec::new();
        for (k, e) in edges.iter().enumerate() {
            match self.on_edge.get(e) {
                Some([Some(_), Some(_)]) => return Err(Refusal::NonManifold),
                Some([Some(g), None]) => neighbours.push((k, *g)),
                _ => {}
            }
        }
        // The vertex of `face` opposite its edge k is the one not on it.
        let opposite =
            |f: [u32; 3], e: Edge| *f.iter().find(|v| !e.contains(v)).expect("3 vertices");
        for &(k, g) in &neighbours {
            let e = edges[k];
            if folds(
                positions,
                e,
                opposite(face, e),
                opposite(self.faces[g as usize], e),
            ) {
                return Err(Refusal::Fold);
            }
        }
        if self.layers.overlaps(positions, face) {
            return Err(Refusal::Overlap);
        }
        // For each neighbour's piece: must `face` be flipped relative to that piece's root?
        let mut needs: Vec<(u32, bool)> = Vec::new();
        for &(k, g) in &neighbours {
            let [a, b] = edges[k];
            let (root, g_flipped) = self.find(g);
            let g_up = walks_up(self.faces[g as usize], a, b) ^ g_flipped;
            // Opposite directions on the shared edge.
            let flip = walks_up(face, a, b) == g_up;
            match needs.iter().find(|(r, _)| *r == root) {
                Some(&(_, f)) if f != flip => return Err(Refusal::Winding),
                Some(_) => {}
                None => needs.push((root, flip)),
            }
        }
        let id = self.faces.len() as u32;
        self.layers.insert(positions, face);
        self.faces.push(face);
        self.parent.push(id);
        self.flip.push(false);
        if let Some(&(first, flip_first)) = needs.first() {
            self.parent[id as usize] = first;
            self.flip[id as usize] = flip_first;
            for &(root, flip_root) in &needs[1..] {
                self.parent[root as usize] = first;
                self.flip[root as usize] = flip_first ^ flip_root;
            }
        }
        for e in edges {
            let slots = self.on_edge.entry(e).or_default();
            *slots.iter_mut().find(|s| s.is_none()).expect("checked") = Some(id);
        }
        Ok(())
    }

    /// Every accepted face wound consistently with its piece; each piece as a whole is wound
    /// the way most of its faces were first wound (Algorithm 1's rule, from the normals).
    fn oriented_faces(mut self) -> Vec<[u32; 3]> {
        let n = self.faces.len() as u32;
        let found: Vec<(u32, bool)> = (0..n).map(|f| self.find(f)).collect();
        let mut votes: HashMap<u32, i64> = HashMap::default();
        for &(root, flipped) in &found {
            *votes.entry(root).or_default() += if flipped { -1 } else { 1 };
        }
        (self.faces.iter().zip(&found))
            .map(|(&f, &(root, flipped))| {
                if flipped ^ (votes[&root] < 0) {
                    [f[0], f[2], f[1]]
                } else {
                    f
                }
            })
            .collect()
    }
}

/// Why a face cannot join the mesh.
enum Refusal {
    NonManifold,
    Winding,
    Fold,
    Overlap,
}

/// The accepted faces, and for every edge the (at most two) faces on it with the direction
/// each walks it (`true`: from the smaller vertex to the larger).
struct Surface<'a> {
    positions: &'a [Vec3],
    /// Every face ever added, by id; `alive[id]` is false once removed.
    faces: Vec<[u32; 3]>,
    alive: Vec<bool>,
    face_normals: Vec<Vec3>,
    on_edge: HashMap<Edge, [Option<(u32, bool)>; 2]>,
    vertex_sets: HashSet<[u32; 3]>,
    layers: FaceLayers,
}

impl<'a> Surface<'a> {
    /// `cell`: the overlap grid's cell side ([`cell_size`]).
    fn new(positions: &'a [Vec3], overlap_tolerance: f32, cell: f32) -> Self {
        Self {
            positions,
            faces: Vec::new(),
            alive: Vec::new(),
            face_normals: Vec::new(),
            on_edge: HashMap::default(),
            vertex_sets: HashSet::default(),
            layers: FaceLayers::oriented(overlap_tolerance, cell),
        }
    }

    fn unit_normal(&self, face: [u32; 3]) -> Vec3 {
        unit_normal(self.positions, face)
    }

    /// Checks `face`, wound as given, against the faces already on its edges.
    fn check(&self, face: [u32; 3]) -> Result<(), Refusal> {
        let normal = self.unit_normal(face);
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            let Some(slots) = self.on_edge.get(&[a.min(b), a.max(b)]) else {
                continue;
            };
            match slots {
                [Some(_), Some(_)] => return Err(Refusal::NonManifold),
                [Some((other, forward)), None] => {
                    if *forward == (a < b) {
                        return Err(Refusal::Winding);
                    }
                    if normal.dot(self.face_normals[*other as usize]) < FOLD_COS {
                        return Err(Refusal::Fold);
                    }
                }
                _ => {}
            }
        }
        if self.layers.overlaps(self.positions, face) {
            return Err(Refusal::Overlap);
        }
        Ok(())
    }

    fn add(&mut self, face: [u32; 3]) {
        let id = self.faces.len() as u32;
        for k in 0..3 {
            let (a, b) = (face[k], face[(k + 1) % 3]);
            let slots = self.on_edge.entry([a.min(b), a.max(b)]).or_default();
            let free = slots.iter_mut().find(|s| s.is_none()).expect("checked");
            *free = Some((id, a < b));
        }
        self.face_normals.push(self.unit_normal(face));
        self.vertex_sets.insert(sorted_face(face));
        self.layers.insert(self.positions, face);
        self.faces.push(face);
        self.alive.push(true);
    }

    /// Removes the most recently added face (to undo a partly filled hole).
    fn pop(&mut self) {
        let id = self.faces.len() as u32 - 1;
        self.remove(id);
        self.faces.pop();
        self.alive.pop();
        self.face_normals.pop();
    }

    /// Takes face `id` off the surface (its slot stays, marked dead).
    fn remove(&mut self, id: u32) {
        let face = self.faces[id as usize];
        self.alive[id as usize] = false;
        self.vertex_sets.remove(&sorted_face(face));
        self.layers.remove(face);
        for e in topology::face_edges(face) {
            let slots = self.on_edge.get_mut(&e).expect("edge of a face");
            for s in slots.iter_mut() {
                if matches!(s, Some((f, _)) if *f == id) {
                    *s = None;
                }
            }
            if slots.iter().all(Option::is_none) {
                self.on_edge.remove(&e);
            } else if slots[0].is_none() {
                slots.swap(0, 1);
            }
        }
    }

    /// The faces on the surface.
    fn alive_faces(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.faces
            .iter()
            .zip(&self.alive)
            .filter(|(_, alive)| **alive)
            .map(|(f, _)| *f)
    }

    /// The holes: every edge with one face, walked against that face, chained into loops. At a
    /// vertex where several holes meet, the walk is cut wherever it comes back to a vertex it
    /// has passed, so each loop is simple. (Around every vertex the one-face edges come in and
    /// go out equally often, so the walk always closes.)
    fn hole_loops(&self) -> Vec<Vec<u32>> {
        // Hole edges a -> b: the face on the edge walks b -> a.
        let hole_edges = self
            .on_edge
            .iter()
            .filter_map(|(&[lo, hi], slots)| match slots {
                [Some((_, forward)), None] => Some(if *forward { (hi, lo) } else { (lo, hi) }),
                _ => None,
            });
        topology::directed_loops(hole_edges)
    }

    /// How well `face` continues the faces already on its edges: the smallest cosine between
    /// its normal and theirs (1 when it has no neighbour).
    fn smoothness(&self, face: [u32; 3]) -> f32 {
        let normal = self.unit_normal(face);
        topology::face_edges(face)
            .iter()
            .filter_map(|e| self.on_edge.get(e).and_then(|s| s[0]))
            .map(|(f, _)| normal.dot(self.face_normals[f as usize]))
            .fold(1.0, f32::min)
    }

    /// Step 3: fills every hole loop of at most `max_hole_edges` edges that can be filled.
    fn fill_holes(&mut self, max_hole_edges: usize) -> HoleFilling {
        let mut done = HoleFilling::default();
        for hole in self.hole_loops() {
            let filled = if max_hole_edges >= 3 && hole.len() <= max_hole_edges {
                self.fill(&hole)
                    .or_else(|| self.fill_without_a_neighbour(&hole))
            } else {
                None
            };
            match filled {
                Some(faces) => {
                    done.filled += 1;
                    done.faces += faces;
                }
                None => done.left += 1,
            }
        }
        done
    }

    /// Step 3 for one hole (its vertices in hole order): ears `(h[i-1], h[i], h[i+1])` that
    /// pass the tests of step 2 are added smoothest first, and `h[i]` leaves the loop, until
    /// it is closed. When no ear passes partway, the last ear is taken back and the next best
    /// tried instead (a depth-first search over the clipping orders, at most
    /// [`FILL_ATTEMPTS`] ears a hole), since a greedy first ear often leaves a remainder that
    /// only folds; if none closes it, nothing is added.
    fn fill(&mut self, hole: &[u32]) -> Option<usize> {
        let mut poly = hole.to_vec();
        let mut attempts = FILL_ATTEMPTS;
        self.clip(&mut poly, &mut attempts).then(|| hole.len() - 2)
    }

    /// The search of [`Surface::fill`]: closes `poly` with ears, or leaves the surface as it
    /// found it and returns false.
    fn clip(&mut self, poly: &mut Vec<u32>, attempts: &mut usize) -> bool {
        let len = poly.len();
        if len < 3 {
            return true;
        }
        let ear_at =
            |poly: &[u32], i: usize| [poly[(i + len - 1) % len], poly[i], poly[(i + 1) % len]];
        let mut ears: Vec<(f32, usize)> = (0..len)
            .filter_map(|i| {
                let ear = ear_at(poly, i);
                let usable = ear[0] != ear[2]
                    && self.unit_normal(ear) != Vec3::ZERO
                    && !self.vertex_sets.contains(&sorted_face(ear))
                    && self.check(ear).is_ok();
                usable.then(|| (self.smoothness(ear), i))
            })
            .collect();
        // Smoothest first; among equals the first in hole order.
        ears.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        for (_, i) in ears {
            if *attempts == 0 {
                return false;
            }
            *attempts -= 1;
            self.add(ear_at(poly, i));
            let v = poly.remove(i);
            if poly.len() == 2 || self.clip(poly, attempts) {
                return true;
            }
            poly.insert(i, v);
            self.pop();
        }
        false
    }
}

impl Surface<'_> {
    /// Step 3 when no ear closes `hole`: usually a face next to it folds over it (fitting
    /// moved the vertices under it). For each hole edge `(a, b)` in turn, the face on it,
    /// `(b, a, x)`, is taken off when its two other edges have two faces each, so the hole grows
    /// to `a, x, b` and loses that face; if the grown hole closes, the face is replaced,
    /// otherwise it goes back. Returns the faces added (net of the one removed).
    fn fill_without_a_neighbour(&mut self, hole: &[u32]) -> Option<usize> {
        let n = hole.len();
        for i in 0..n {
            let (a, b) = (hole[i], hole[(i + 1) % n]);
            let Some(&[Some((g, _)), None]) = self.on_edge.get(&[a.min(b), a.max(b)]) else {
                continue;
            };
            let face = self.faces[g as usize];
            let Some(&x) = face.iter().find(|&&v| v != a && v != b) else {
                continue;
            };
            let two_faces = |u: u32, v: u32| {
                matches!(
                    self.on_edge.get(&[u.min(v), u.max(v)]),
                    Some([Some(_), Some(_)])
                )
            };
            if hole.contains(&x) || !two_faces(a, x) || !two_faces(x, b) {
                continue;
            }
            self.remove(g);
            // The removed face is an ear of the grown loop; re-adding it would only rebuild
            // the hole that just failed, so it stays barred while the loop is clipped.
            let barred = sorted_face(face);
            self.vertex_sets.insert(barred);
            let mut grown = hole.to_vec();
            grown.insert(i + 1, x);
            let filled = self.fill(&grown);
            self.vertex_sets.remove(&barred);
            if let Some(added) = filled {
                return Some(added - 1);
            }
            self.add(face);
        }
        None
    }
}

/// What hole filling did: loops filled, the faces that took, and loops left open.
#[derive(Clone, Copy, Debug, Default)]
struct HoleFilling {
    filled: usize,
    faces: usize,
    left: usize,
}

/// Steps 1-4 of the module doc: a manifold, consistently wound subset of `candidates` (plus
/// the faces that close holes), best-scored first. `candidates` are distinct vertex triples; `preferred[k]` is
/// candidate k wound by Algorithm 1's rule, used when nothing else decides its winding;
/// `scores[k]` ranks it (higher first; NaN ranks last). Returns the faces rotated to start at
/// their smallest vertex (winding kept) and sorted, so the output depends on which faces were
/// chosen, not on the order in which near-equal scores put them.
pub fn manifold_faces(
    positions: &[Vec3],
    preferred: &[[u32; 3]],
    scores: &[f32],
    opts: &ManifoldOptions,
) -> (Vec<[u32; 3]>, ManifoldReport) {
    assert_eq!(preferred.len(), scores.len(), "one score per candidate");
    let mut report = ManifoldReport::default();
    let mut order: Vec<usize> = (0..preferred.len()).collect();
    let key = |k: usize| {
        if scores[k].is_nan() {
            f32::NEG_INFINITY
        } else {
            scores[k]
        }
    };
    order.sort_by(|&x, &y| key(y).total_cmp(&key(x)).then(x.cmp(&y)));

    let cell = cell_size(positions, preferred);
    let mut selection = Selection::new(opts.overlap_tolerance, cell);
    for k in order {
        let face = preferred[k];
        if unit_normal(positions, face) == Vec3::ZERO {
            report.rejected_degenerate += 1;
            continue;
        }
        match selection.try_add(positions, face) {
            Ok(()) => report.accepted += 1,
            Err(Refusal::NonManifold) => report.rejected_non_manifold += 1,
            Err(Refusal::Winding) => report.rejected_winding += 1,
            Err(Refusal::Fold) => report.rejected_fold += 1,
            Err(Refusal::Overlap) => report.rejected_overlap += 1,
        }
    }
    // The accepted faces were checked already; the surface checks only the ears.
    let mut surface = Surface::new(positions, opts.overlap_tolerance, cell);
    for face in selection.oriented_faces() {
        surface.add(face);
    }

    let holes = surface.fill_holes(opts.max_hole_edges);
    (report.holes_filled, report.hole_faces, report.holes_left) =
        (holes.filled, holes.faces, holes.left);

    let mut faces: Vec<[u32; 3]> = surface.alive_faces().map(rotate_min_first).collect();
    faces.sort_unstable();
    if opts.min_component_faces > 1 {
        let (labels, count) = topology::edge_pieces(&faces);
        let mut size = vec![0usize; count];
        for &l in &labels {
            size[l as usize] += 1;
        }
        report.pieces_dropped = size
            .iter()
            .filter(|&&s| s < opts.min_component_faces)
            .count();
        let before = faces.len();
        let mut label = labels.into_iter();
        faces.retain(|_| {
            size[label.next().expect("a label per face") as usize] >= opts.min_component_faces
        });
        report.piece_faces_dropped = before - faces.len();
    }
    (faces, report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::topology::TopologyReport;

    fn square() -> Vec<Vec3> {
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ]
    }

    const OPTS: ManifoldOptions = ManifoldOptions {
        max_hole_edges: 4,
        min_component_faces: 0,
        overlap_tolerance: 0.2,
    };

    #[test]
    fn a_quad_with_both_diagonals_gives_two_faces_not_four() {
        // All four 3-cliques of the complete graph on a square, wound up (+z).
        let cands = [[0, 1, 2], [0, 2, 3], [0, 1, 3], [1, 2, 3]];
        let (faces, r) = manifold_faces(&square(), &cands, &[1.0, 0.9, 0.5, 0.4], &OPTS);
        assert_eq!(faces, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!((r.accepted, r.rejected_fold + r.rejected_winding), (2, 2));
    }

    #[test]
    fn winding_follows_the_best_face_not_the_normals() {
        // The second face's preferred winding disagrees with the first's: it is flipped.
        let (faces, r) = manifold_faces(&square(), &[[0, 1, 2], [0, 3, 2]], &[1.0, 0.5], &OPTS);
        assert_eq!(faces, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(r.accepted, 2);
        let mesh = crate::Mesh::new(square(), faces);
        assert_eq!(TopologyReport::of(&mesh).inconsistent_winding_edges, 0);
    }

    #[test]
    fn a_third_face_on_an_edge_is_refused() {
        let mut p = square();
        p.push(Vec3::new(0.5, 0.5, 1.0));
        let cands = [[0, 1, 2], [0, 2, 3], [0, 2, 4]];
        let (faces, r) = manifold_faces(&p, &cands, &[3.0, 2.0, 1.0], &OPTS);
        assert_eq!(faces.len(), 2);
        assert_eq!(r.rejected_non_manifold, 1);
    }

    #[test]
    fn holes_are_filled_against_their_border_and_lone_triangles_are_not_doubled() {
        // An octahedron without one face: the 3-loop is filled, wound like its neighbours.
        let o = crate::geometry::primitives::octahedron();
        let open: Vec<[u32; 3]> = o.faces[1..].to_vec();
        let scores = vec![1.0; open.len()];
        let (faces, r) = manifold_faces(&o.positions, &open, &scores, &OPTS);
        assert_eq!((r.holes_filled, r.hole_faces, faces.len()), (1, 1, 8));
        let closed = crate::Mesh::new(o.positions.clone(), faces);
        assert!(TopologyReport::of(&closed).is_clean_closed());
        // A lone triangle's border is a 3-loop; filling it would make a back-to-back copy.
        let (faces, r) = manifold_faces(&square(), &[[0, 1, 2]], &[1.0], &OPTS);
        assert_eq!((faces.len(), r.holes_left), (1, 1));
    }

    #[test]
    fn small_pieces_are_dropped() {
        let mut p = square();
        p.extend([
            Vec3::new(5.0, 0.0, 0.0),
            Vec3::new(6.0, 0.0, 0.0),
            Vec3::new(5.0, 1.0, 0.0),
        ]);
        let cands = [[0, 1, 2], [0, 2, 3], [4, 5, 6]];
        let opts = ManifoldOptions {
            min_component_faces: 2,
            ..OPTS
        };
        let (faces, r) = manifold_faces(&p, &cands, &[1.0; 3], &opts);
        assert_eq!(faces.len(), 2);
        assert_eq!((r.pieces_dropped, r.piece_faces_dropped), (1, 1));
    }

    #[test]
    fn degenerate_candidates_are_never_accepted() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let (faces, r) = manifold_faces(&p, &[[0, 1, 2]], &[1.0], &OPTS);
        assert!(faces.is_empty());
        assert_eq!(r.rejected_degenerate, 1);
    }

    #[test]
    fn a_hole_whose_smoothest_first_ear_leads_nowhere_is_closed_in_another_order() {
        // A ring of five faces around a bent pentagonal hole (a case found by random search):
        // clipping the smoothest ear first leaves a remainder whose every ear folds.
        let p: Vec<Vec3> = [
            [1.04, -0.28, 0.51],
            [0.07, 1.02, 0.43],
            [-0.77, 0.32, -0.28],
            [-0.68, -0.55, 0.25],
            [0.38, -1.02, -0.39],
            [1.9, 0.69, 0.46],
            [-0.82, 1.92, 0.18],
            [-2.14, 0.1, 0.36],
            [-0.44, -1.6, -0.1],
            [1.54, -1.02, 0.44],
        ]
        .map(Vec3::from_array)
        .to_vec();
        let ring: Vec<[u32; 3]> = (0..5).map(|k| [(k + 1) % 5, k, 5 + k]).collect();
        let surface_with_ring = || {
            let mut s = Surface::new(&p, 0.5, 1.0);
            for &f in &ring {
                assert!(s.check(f).is_ok(), "the ring is a clean surface");
                s.add(f);
            }
            s
        };
        // Greedy clipping (no ear taken back) gets stuck and leaves the ring as it was.
        let mut greedy = surface_with_ring();
        assert!(!greedy.clip(&mut vec![0, 1, 2, 3, 4], &mut 3));
        assert_eq!(greedy.alive_faces().count(), 5);
        // The search closes it with three faces that keep every guarantee.
        let opts = ManifoldOptions {
            max_hole_edges: 5,
            min_component_faces: 0,
            overlap_tolerance: 0.5,
        };
        let (faces, r) = manifold_faces(&p, &ring, &[1.0; 5], &opts);
        assert_eq!((r.holes_filled, r.hole_faces, faces.len()), (1, 3, 8));
        let topo = TopologyReport::of(&crate::Mesh::new(p.clone(), faces));
        assert_eq!(
            (topo.non_manifold_edges, topo.inconsistent_winding_edges),
            (0, 0)
        );
        assert_eq!(topo.holes, 1, "only the ring's outer border is left");
    }
}
