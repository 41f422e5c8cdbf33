//! Faces lying on top of each other without sharing an edge: the test that keeps a surface
//! one layer thick.
//!
//! The manifold extraction's edge tests (at most two faces an edge, no fold across an edge)
//! see only faces that share an edge. Two faces that share one vertex or none can still cover
//! the same patch of surface, one a little above the other: a second layer, the "shards" a
//! viewer sees, and the reason such a mesh has far more faces than its vertices allow
//! (a single-layer surface has at most about two faces per vertex). [`FaceLayers`] holds the
//! accepted faces in an R-tree of their bounding boxes and refuses a new face that, seen
//! along its own normal, overlaps an accepted one lying within `tolerance` of its plane.
//!
//! The overlap test, for a new face `f` and an accepted face `g` sharing at most one vertex:
//! `g` is near-parallel to `f` (normals within 60 degrees, either orientation: windings are
//! not final while faces are being chosen) and each of `g`'s vertices is within `tolerance`
//! times `f`'s longest edge of `f`'s plane; then both are projected onto that plane and
//! tested by separating axes (the six edge normals), where intervals that overlap by less than
//! a millionth of the face's size count as separate, so faces that only touch at a vertex or
//! along a line do not overlap.
//!
//! The accepted faces' bounding boxes sit in a uniform grid of cubes about one face across
//! ([`cell_size`]): faces come and go one at a time while they are chosen, which a hash grid
//! takes in a few lookups where an R-tree rebalances. A box over more than 64 cells (a face
//! far larger than the rest) is kept in a list every query reads instead.

use std::cell::{Cell, RefCell};

use glam::{IVec3, Vec2, Vec3};
use rustc_hash::FxHashMap;

use crate::extract::manifold::unit_normal;

/// Smallest |cosine| between two faces' normals for them to count as lying on each other.
const PARALLEL_COS: f32 = 0.5;

/// Most grid cells one face's box is entered in, or one query reads; beyond, the face goes to
/// the list every query reads, and the query reads every face.
const MAX_CELLS: i64 = 64;

/// A grid cell's side for the faces `faces` of `positions`: twice the median of their longest
/// edges (at most 257 of them, evenly spread), so a typical face's box, and a query's box
/// around it, covers a few cells. 0 when no face has a positive finite size.
pub fn cell_size(positions: &[Vec3], faces: &[[u32; 3]]) -> f32 {
    let step = faces.len().div_ceil(257).max(1);
    let mut sizes: Vec<f32> = faces
        .iter()
        .step_by(step)
        .map(|&f| {
            let [a, b, c] = f.map(|v| positions[v as usize]);
            a.distance(b).max(b.distance(c)).max(c.distance(a))
        })
        .filter(|s| s.is_finite() && *s > 0.0)
        .collect();
    if sizes.is_empty() {
        return 0.0;
    }
    let mid = sizes.len() / 2;
    2.0 * *sizes.select_nth_unstable_by(mid, f32::total_cmp).1
}

/// An accepted face, its bounding box and its unit normal.
struct Entry {
    face: [u32; 3],
    lo: Vec3,
    hi: Vec3,
    normal: Vec3,
}

/// The accepted faces, for [`FaceLayers::overlaps`].
pub struct FaceLayers {
    tolerance: f32,
    /// Count only faces wound the same way (normals within 60 degrees, not either
    /// orientation): for faces whose windings are final, where the far side of a thin part
    /// faces away and is no second layer.
    oriented: bool,
    /// The grid's cell side; 0 or less keeps every face in `oversize`.
    cell: f32,
    /// Every face ever inserted, by id; a removed one stays, out of `live` and the grid.
    entries: Vec<Entry>,
    /// The ids of each face inserted and not removed (vertices in insertion order): one per
    /// insertion, so a face inserted twice stays until removed twice.
    live: FxHashMap<[u32; 3], Vec<u32>>,
    grid: FxHashMap<IVec3, Vec<u32>>,
    oversize: Vec<u32>,
    /// `stamps[id]` is the last query that read face `id` (`query` counts them from 1; 0 is
    /// never a query, and a u64 does not wrap), so a face in several cells is tested once per
    /// query without sorting the ids.
    stamps: RefCell<Vec<u64>>,
    query: Cell<u64>,
}

impl FaceLayers {
    /// No faces yet; `tolerance` is the largest distance from a face's plane, in its longest
    /// edges, at which another face counts as lying on it (0 or less: nothing ever overlaps).
    /// `cell` is the grid's cell side, about a typical face's size ([`cell_size`]); any value
    /// gives the same answers (0 or less, NaN or infinite: no grid), only slower when far off.
    pub fn new(tolerance: f32, cell: f32) -> Self {
        Self {
            tolerance,
            oriented: false,
            cell: if cell.is_finite() { cell } else { 0.0 },
            entries: Vec::new(),
            live: FxHashMap::default(),
            grid: FxHashMap::default(),
            oversize: Vec::new(),
            stamps: RefCell::new(Vec::new()),
            query: Cell::new(0),
        }
    }

    /// [`FaceLayers::new`] for wound faces: a face facing the other way is not on the same
    /// layer (the far side of a thin part).
    pub fn oriented(tolerance: f32, cell: f32) -> Self {
        Self {
            oriented: true,
            ..Self::new(tolerance, cell)
        }
    }

    /// The grid cells a box covers, or `None` when they are more than [`MAX_CELLS`].
    fn cells(&self, lo: Vec3, hi: Vec3) -> Option<(IVec3, IVec3)> {
        if self.cell <= 0.0 {
            return None;
        }
        // Float-to-int casts saturate, and each axis's span is bounded before the product is
        // taken, so no coordinate, however far off, can overflow the count.
        let (a, b) = (
            (lo / self.cell).floor().as_ivec3(),
            (hi / self.cell).floor().as_ivec3(),
        );
        let span = (b.as_i64vec3() - a.as_i64vec3() + 1).max(glam::I64Vec3::ONE);
        if span.max_element() > MAX_CELLS {
            return None;
        }
        (span.x * span.y * span.z <= MAX_CELLS).then_some((a, b))
    }

    fn for_cells(a: IVec3, b: IVec3, mut visit: impl FnMut(IVec3)) {
        for x in a.x..=b.x {
            for y in a.y..=b.y {
                for z in a.z..=b.z {
                    visit(IVec3::new(x, y, z));
                }
            }
        }
    }

    /// Records `face` as accepted.
    pub fn insert(&mut self, positions: &[Vec3], face: [u32; 3]) {
        if self.tolerance <= 0.0 {
            return;
        }
        let [a, b, c] = face.map(|v| positions[v as usize]);
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        let id = self.entries.len() as u32;
        let normal = unit_normal(positions, face);
        self.entries.push(Entry {
            face,
            lo,
            hi,
            normal,
        });
        self.live.entry(face).or_default().push(id);
        match self.cells(lo, hi) {
            Some((a, b)) => {
                Self::for_cells(a, b, |k| self.grid.entry(k).or_default().push(id));
            }
            None => self.oversize.push(id),
        }
    }

    /// Forgets an accepted `face` (its vertices in the order it was inserted with), once.
    pub fn remove(&mut self, face: [u32; 3]) {
        let Some(ids) = self.live.get_mut(&face) else {
            return;
        };
        let id = ids.pop().expect("a live face has an id");
        if ids.is_empty() {
            self.live.remove(&face);
        }
        let Entry { lo, hi, .. } = self.entries[id as usize];
        match self.cells(lo, hi) {
            Some((a, b)) => Self::for_cells(a, b, |k| {
                if let Some(ids) = self.grid.get_mut(&k) {
                    ids.retain(|&i| i != id);
                }
            }),
            None => self.oversize.retain(|&i| i != id),
        }
    }

    /// Whether `test` holds for a live face whose box meets the box `lo..hi`, each face
    /// tested at most once.
    fn any_near(&self, lo: Vec3, hi: Vec3, test: impl Fn(&Entry) -> bool) -> bool {
        let query = self.query.get() + 1;
        self.query.set(query);
        let mut stamps = self.stamps.borrow_mut();
        stamps.resize(self.entries.len(), 0);
        let mut read = |id: u32| {
            let stamp = &mut stamps[id as usize];
            if *stamp == query {
                return false;
            }
            *stamp = query;
            let e = &self.entries[id as usize];
            !(e.hi.cmplt(lo).any() || e.lo.cmpgt(hi).any()) && test(e)
        };
        if self.oversize.iter().any(|&id| read(id)) {
            return true;
        }
        match self.cells(lo, hi) {
            Some((a, b)) => {
                for x in a.x..=b.x {
                    for y in a.y..=b.y {
                        for z in a.z..=b.z {
                            let Some(ids) = self.grid.get(&IVec3::new(x, y, z)) else {
                                continue;
                            };
                            if ids.iter().any(|&id| read(id)) {
                                return true;
                            }
                        }
                    }
                }
                false
            }
            None => self.live.values().flatten().any(|&id| read(id)),
        }
    }

    /// Whether `face` overlaps an accepted face that shares at most one vertex with it (see
    /// the module documentation).
    pub fn overlaps(&self, positions: &[Vec3], face: [u32; 3]) -> bool {
        if self.tolerance <= 0.0 || self.live.is_empty() {
            return false;
        }
        let [a, b, c] = face.map(|v| positions[v as usize]);
        let normal = unit_normal(positions, face);
        if normal == Vec3::ZERO {
            return false;
        }
        let size = a.distance(b).max(b.distance(c)).max(c.distance(a));
        let reach = self.tolerance * size;
        let lo = a.min(b).min(c) - Vec3::splat(reach);
        let hi = a.max(b).max(c) + Vec3::splat(reach);
        let (u, v) = normal.any_orthonormal_pair();
        let flat = |p: Vec3| Vec2::new((p - a).dot(u), (p - a).dot(v));
        let mine = [a, b, c].map(flat);
        self.any_near(lo, hi, |other| {
            let g = other.face;
            if g.iter().filter(|v| face.contains(v)).count() >= 2 {
                return false;
            }
            let cos = other.normal.dot(normal);
            if (if self.oriented { cos } else { cos.abs() }) < PARALLEL_COS {
                return false;
            }
            let corners = g.map(|v| positions[v as usize]);
            if corners.iter().any(|&x| (x - a).dot(normal).abs() > reach) {
                return false;
            }
            triangles_overlap(mine, corners.map(flat), size * 1e-6)
        })
    }
}

/// Whether two 2-D triangles' interiors overlap by more than `eps` along every separating
/// axis candidate (their six edge normals).
fn triangles_overlap(s: [Vec2; 3], t: [Vec2; 3], eps: f32) -> bool {
    let axes = [s, t].into_iter().flat_map(|tri| {
        (0..3).map(move |k| {
            let e = tri[(k + 1) % 3] - tri[k];
            Vec2::new(-e.y, e.x)
        })
    });
    for axis in axes {
        let len = axis.length();
        if len <= 0.0 {
            continue;
        }
        let axis = axis / len;
        let span = |tri: [Vec2; 3]| {
            let d = tri.map(|p| p.dot(axis));
            (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]))
        };
        let (s0, s1) = span(s);
        let (t0, t1) = span(t);
        if s1.min(t1) - s0.max(t0) <= eps {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn positions() -> Vec<Vec3> {
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            // A copy of the first triangle shifted a little up and sideways.
            Vec3::new(0.2, 0.2, 0.05),
            Vec3::new(1.2, 0.2, 0.05),
            Vec3::new(0.2, 1.2, 0.05),
            // The neighbour across the edge 1-2, and one that touches at vertex 1 only.
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, -1.0, 0.0),
            // The first triangle far above: a real second surface (a thick part's far side).
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ]
    }

    #[test]
    fn a_second_layer_overlaps_but_neighbours_and_far_sides_do_not() {
        let p = positions();
        let mut layers = FaceLayers::new(0.2, 1.0);
        layers.insert(&p, [0, 1, 2]);
        assert!(layers.overlaps(&p, [3, 4, 5]));
        assert!(layers.overlaps(&p, [3, 5, 4]), "either winding");
        assert!(!layers.overlaps(&p, [1, 6, 2]), "shares an edge");
        assert!(!layers.overlaps(&p, [1, 7, 8]), "touches at a vertex");
        assert!(
            !layers.overlaps(&p, [9, 10, 11]),
            "a surface a whole edge away"
        );
        layers.remove([0, 1, 2]);
        assert!(!layers.overlaps(&p, [3, 4, 5]));
        assert!(!FaceLayers::new(0.0, 1.0).overlaps(&p, [3, 4, 5]));
    }

    /// The grid only decides which faces are compared: any cell size, from one that puts
    /// every face in the list every query reads to one that puts each in a single cell, gives
    /// the same answers, before and after removals.
    #[test]
    fn the_cell_size_never_changes_an_answer() {
        let mut rng = crate::rng::Rng::new(7);
        // Small random triangles in a unit box: many near-parallel neighbours at all scales.
        let p: Vec<Vec3> = (0..300)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), 0.1 * rng.next_f32()))
            .collect();
        let faces: Vec<[u32; 3]> = (0..100).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
        let typical = cell_size(&p, &faces);
        assert!(typical > 0.0);
        let answers = |cell: f32| {
            let mut layers = FaceLayers::new(0.3, cell);
            let mut out = Vec::new();
            for (k, &f) in faces.iter().enumerate() {
                out.push(layers.overlaps(&p, f));
                if k % 2 == 0 {
                    layers.insert(&p, f);
                }
            }
            for &f in faces.iter().step_by(4) {
                layers.remove(f);
            }
            // A face inserted twice stays until it is removed twice.
            let twice = faces[1];
            layers.insert(&p, twice);
            layers.insert(&p, twice);
            layers.remove(twice);
            out.extend(faces.iter().map(|&f| layers.overlaps(&p, f)));
            layers.remove(twice);
            out.extend(faces.iter().map(|&f| layers.overlaps(&p, f)));
            out
        };
        let linear = answers(0.0);
        assert!(linear.iter().any(|&o| o) && linear.iter().any(|&o| !o));
        for cell in [
            typical * 0.01,
            typical * 0.5,
            typical,
            typical * 4.0,
            100.0,
            f32::NAN,
        ] {
            assert_eq!(answers(cell), linear, "cell {cell}");
        }
    }

    /// A face millions of cells across in every axis goes to the list every query reads:
    /// counting its cells cannot overflow, and nothing walks them.
    #[test]
    fn a_huge_face_neither_overflows_nor_walks_its_cells() {
        let p = vec![
            Vec3::ZERO,
            Vec3::new(4_194_303.0, 2_097_151.0, 0.0),
            Vec3::new(0.0, 2_097_151.0, 2_097_151.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
        ];
        let mut layers = FaceLayers::new(0.2, 1.0);
        layers.insert(&p, [0, 1, 2]);
        layers.insert(&p, [3, 4, 5]);
        assert!(!layers.overlaps(&p, [0, 1, 2]));
        layers.remove([0, 1, 2]);
        assert!(!layers.overlaps(&p, [0, 1, 2]));
    }

    #[test]
    fn separating_axes() {
        let tri = [Vec2::ZERO, Vec2::X, Vec2::Y];
        let inside = [Vec2::splat(0.1), Vec2::new(0.3, 0.1), Vec2::new(0.1, 0.3)];
        let beside = [Vec2::X, Vec2::new(2.0, 0.0), Vec2::new(1.0, 1.0)];
        assert!(triangles_overlap(tri, inside, 1e-6));
        assert!(!triangles_overlap(tri, beside, 1e-6));
    }
}
