//! Closing the holes that extraction and completion leave open, where the input points say
//! there is surface.
//!
//! Completion fills the holes it can with triangles between existing vertices, and refuses
//! any that would fold, overlap or break the manifold. What it leaves is mostly small loops
//! pinched between pieces, and the open rim of a thin part, where the model put one sheet of
//! vertices inside the slab: no triangle between those vertices closes it without lying on
//! the sheet. [`close_holes`] closes each remaining boundary loop with a fan around one new
//! vertex, or between its own vertices:
//!
//! 1. **Loops.** The edges with one face, walked against that face and cut into simple loops
//!    where holes meet at a vertex ([`crate::geometry::topology::hole_loops`]).
//! 2. **Fan, or a triangulation.** A loop `v0 -> v1 -> ... -> v(k-1)` of four or more gets a vertex `c`
//!    and the faces `(v(i), v(i+1), c)`: `c` is the centroid of the loop's vertices projected
//!    onto the input surface there (the plane of its 8 nearest input points). When a fan face
//!    would face against the rest of the fan (a loop that is not star-shaped around `c`), the
//!    loop is triangulated between its own vertices instead: the least-area triangulation
//!    whose faces all face the way of the loop's Newell normal and add no diagonal that is an
//!    edge already (dynamic programming, loops of at most `MAX_TRIANGULATED`, 100, edges).
//!    A loop of three gets its one face, unless that face exists already (the
//!    border of a lone triangle). Every new face walks its loop edge opposite to the face
//!    already there, and each spoke or diagonal gets two new faces walking it both ways, so
//!    **every edge keeps at most two faces and the winding stays consistent**: the manifold
//!    extraction's edge guarantees hold (`crate/tests/extract_props.rs`). Its overlap test
//!    against the faces around the hole is not applied (a patch may lie over a face it does
//!    not touch); its fold test is, below. A new vertex's normal is the mean of its fan's.
//! 3. **Refusals.** A loop stays open when it is longer than `max_edges`, when it is the border
//!    of a lone triangle, or when neither a fan nor a triangulation closes it with faces that
//!    have area, face the patch's way, lie on the input surface (the completion's test:
//!    every probe of a face within `max_gap` point spacings of an input point) and fold
//!    neither onto each other nor onto the mesh's faces across the loop
//!    ([`crate::geometry::topology::folds`]): a hole the input has too, such as the open rim
//!    of a lampshade, is not capped across air, and no patch doubles back over its rim.
//! 4. **Cuts.** Where the model's surface is crumpled at a hole (a lace of small holes between
//!    faces turned over), the patch folds onto one or a few rim faces that are themselves
//!    turned the wrong way. When the only thing wrong with a loop's patch is folding onto at
//!    most `max_cut_faces` rim faces, those faces are cut once the other loops are closed, and
//!    the larger loop the cut opens is closed in their place (where its patch folds onto
//!    further faces, they are cut too, up to `max_cut_faces` in all). The cut is kept only if
//!    every loop it opens closes, and the mesh ends with fewer boundary loops and no more holes
//!    (the topology report's count) or pieces than before; otherwise the mesh stays as it was.
//!
//! On a thin part whose model put one sheet of vertices inside the slab, a cap over the sheet
//! would fold onto it along the rim, so the rim stays open: an open sheet, not a shell doubled
//! over onto itself. A curved open shell (a tube, a bowl) keeps its rim open too, as its cap
//! would span air. Generation closes again after sharpening (`pipeline::generate::sharpen_kept`),
//! without cuts: sharpening flattens some crumpled rims, and a patch that folded onto one
//! before lies flat on it after. Cost: a few nearest-point
//! queries per loop, and the O(k^3) triangulation for the loops a fan cannot close; a few
//! milliseconds at 512 vertices.

use std::collections::{HashMap, HashSet};

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::geometry::topology::{
    DEGENERATE_TOLERANCE, Edge, TopologyReport, face_edges, folds, hole_loops, sorted_edge,
    sorted_face,
};
use crate::surface::complete::on_surface;
use crate::surface::fit::project;
use crate::surface::input::InputPoints;

/// Longest loop closed between its own vertices when a fan cannot close it: the least-area
/// triangulation is O(k^3), about a million steps here.
const MAX_TRIANGULATED: usize = 100;

/// Options of [`close_holes`] (missing JSON fields take the defaults).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CloseOptions {
    /// Close holes at all.
    pub enabled: bool,
    /// Leave open the loops of more than this many edges (0: no limit).
    pub max_edges: usize,
    /// Leave open a loop whose fan would leave the input surface by more than this many input
    /// point spacings (0 or less: no surface test). 10, from the validation split: 6 leaves 2.6 holes
    /// a mesh, 10 leaves 1.3 at the same Chamfer distance, 16 leaves 0.9 at a higher one.
    pub max_gap: f32,
    /// Cut at most this many faces to close a loop whose patch would fold onto them (0: no
    /// cuts; module documentation, item 4).
    pub max_cut_faces: usize,
}

impl Default for CloseOptions {
    fn default() -> Self {
        Self {
            enabled: true,
            max_edges: 0,
            max_gap: 10.0,
            max_cut_faces: 6,
        }
    }
}

/// What [`close_holes`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CloseReport {
    /// Boundary loops closed, and the faces and vertices that added.
    pub holes_closed: usize,
    pub faces_added: usize,
    pub vertices_added: usize,
    /// Boundary loops open at the end (too long, collinear, off the input surface, folding, or
    /// the border of a lone triangle), as this walk cuts them: where holes meet at one vertex
    /// the directed walk may cut them into a different number of loops than the topology
    /// report's undirected one ([`crate::geometry::topology::TopologyReport::holes`], the figure to
    /// report).
    pub holes_left: usize,
    /// Faces cut to close loops whose patches would fold onto them (module documentation,
    /// item 4); absent from reports written before cuts, and read there as 0.
    #[serde(default)]
    pub faces_cut: usize,
}

/// Closes the boundary loops of `mesh` where the surface sampled by `points` goes on (see the
/// module documentation). `mesh` should be manifold and consistently wound (what the manifold
/// extraction gives); edges with more than two faces are left as they are. New vertices are
/// appended, with normals when the mesh has them; faces are appended too, except that a cut
/// (module documentation, item 4) removes up to `max_cut_faces` faces per loop. Non-finite
/// points are ignored; with fewer than two finite points there is no surface test, and with
/// fewer than three no projection.
pub fn close_holes(mesh: &mut Mesh, points: &InputPoints, opts: &CloseOptions) -> CloseReport {
    let mut report = CloseReport::default();
    if !opts.enabled {
        return report;
    }
    let closer = Closer {
        points,
        opts,
        max_gap: opts.max_gap * points.spacing(),
        // The topology report's own test for a face without area, so no new face counts as one.
        min_area2: DEGENERATE_TOLERANCE * mesh.aabb().map_or(1.0, |b| b.max_extent()).powi(2),
    };
    let existing: HashSet<[u32; 3]> = mesh.faces.iter().map(|&f| sorted_face(f)).collect();
    let mut edges: HashSet<Edge> = mesh.faces.iter().flat_map(|&f| face_edges(f)).collect();
    let rims = walked_edges(&mesh.faces);
    // Loops refused only because their patch folds onto a few rim faces: tried again with
    // those faces cut, once the others are closed.
    let mut folded = Vec::new();
    for hole in hole_loops(&mesh.faces) {
        let k = hole.len();
        let too_long = opts.max_edges > 0 && k > opts.max_edges;
        let lone_triangle = k == 3 && existing.contains(&sorted_face([hole[0], hole[1], hole[2]]));
        if too_long || lone_triangle {
            continue;
        }
        match closer.patch(mesh, &hole, &rims, &edges) {
            Ok(patch) => {
                edges.extend(patch.faces.iter().flat_map(|&f| face_edges(f)));
                patch.add_to(mesh, &mut report);
            }
            Err(onto) if !onto.is_empty() && onto.len() <= opts.max_cut_faces => folded.push(
                onto.iter()
                    .map(|&f| mesh.faces[f as usize])
                    .collect::<Vec<_>>(),
            ),
            Err(_) => {}
        }
    }
    for onto in folded {
        // An earlier cut may have taken these faces: cut only where all are still there.
        let at: Option<Vec<u32>> = (onto.iter())
            .map(|f| mesh.faces.iter().position(|g| g == f).map(|i| i as u32))
            .collect();
        if let Some(at) = at {
            closer.cut_and_close(mesh, &at, &mut report);
        }
    }
    report.holes_left = hole_loops(&mesh.faces).len();
    report
}

/// What [`close_holes`] tests each new face against.
struct Closer<'a> {
    points: &'a InputPoints,
    opts: &'a CloseOptions,
    /// `max_gap` in the input's units.
    max_gap: f32,
    /// Twice the least area of a new face (the topology report's test for a face without area).
    min_area2: f32,
}

/// The faces (and the new vertex of a fan) that close one loop.
struct Patch {
    faces: Vec<[u32; 3]>,
    /// A fan's new vertex and its normal (the fan's mean).
    hub: Option<(Vec3, Vec3)>,
}

impl Patch {
    fn add_to(self, mesh: &mut Mesh, report: &mut CloseReport) {
        if let Some((hub, normal)) = self.hub {
            mesh.positions.push(hub);
            if !mesh.normals.is_empty() {
                mesh.normals.push(normal);
            }
            report.vertices_added += 1;
        }
        report.holes_closed += 1;
        report.faces_added += self.faces.len();
        mesh.faces.extend(self.faces);
    }
}

impl Closer<'_> {
    /// Whether a new face with `corners` has area, faces along `along` and lies on the input.
    fn acceptable(&self, corners: [Vec3; 3], along: Vec3) -> bool {
        let points = self.points.index();
        let n = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        n.length() > self.min_area2
            && n.dot(along) > 0.0
            && (points.len() < 2
                || self.opts.max_gap <= 0.0
                || on_surface(corners, points, self.max_gap))
    }

    /// The patch that closes `hole` in `mesh` (a fan, else a triangulation; module
    /// documentation), or the faces of `mesh` that the first patch refused only for folding
    /// onto them would fold onto (empty where nothing that folds would close it).
    fn patch(
        &self,
        mesh: &Mesh,
        hole: &[u32],
        rims: &HashMap<Edge, u32>,
        edges: &HashSet<Edge>,
    ) -> Result<Patch, Vec<u32>> {
        let k = hole.len();
        let at = |v: u32| mesh.positions[v as usize];
        let mut onto = None;
        if k > 3 {
            let centre = hole.iter().map(|&v| at(v)).sum::<Vec3>() / k as f32;
            let hub = project(centre, self.points.index(), 8);
            let h = mesh.positions.len() as u32;
            let faces: Vec<[u32; 3]> = (0..k).map(|i| [hole[i], hole[(i + 1) % k], h]).collect();
            let at_hub = |v: u32| mesh.positions.get(v as usize).copied().unwrap_or(hub);
            let corners: Vec<[Vec3; 3]> = faces.iter().map(|f| f.map(at_hub)).collect();
            let mean: Vec3 = (corners.iter())
                .map(|c| (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero())
                .sum();
            if corners.iter().all(|&c| self.acceptable(c, mean)) {
                match patch_folds(&faces, &mesh.faces, rims, at_hub) {
                    Some(rim) => onto = Some(rim),
                    None => {
                        let normal = mean.try_normalize().unwrap_or(Vec3::Z);
                        let hub = Some((hub, normal));
                        return Ok(Patch { faces, hub });
                    }
                }
            }
        }
        let accept = |c: [Vec3; 3], along: Vec3| self.acceptable(c, along);
        let rim = |i: usize| {
            let g = rims.get(&[hole[(i + 1) % k], hole[i]])?;
            let [a, b, c] = mesh.faces[*g as usize].map(|v| at(v).as_dvec3());
            Some((b - a).cross(c - a))
        };
        let triangulated = triangulate(hole, &mesh.positions, edges, self.min_area2, &rim, &accept);
        if let Some(faces) = triangulated {
            match patch_folds(&faces, &mesh.faces, rims, at) {
                Some(rim) => {
                    onto.get_or_insert(rim);
                }
                None => return Ok(Patch { faces, hub: None }),
            }
        }
        Err(onto.unwrap_or_default())
    }

    /// Cuts the faces `onto` from `mesh` and closes the loops that the cut opens; where a
    /// patch of such a loop folds onto further faces, those are cut too, up to
    /// `max_cut_faces` in all. The result is kept only where every opened loop closes and the
    /// mesh ends with fewer boundary loops and no more holes or pieces than it had.
    fn cut_and_close(&self, mesh: &mut Mesh, onto: &[u32], report: &mut CloseReport) {
        let mut cut: Vec<[u32; 3]> = onto.iter().map(|&f| mesh.faces[f as usize]).collect();
        let (trial, closed) = 'grow: loop {
            let mut trial = mesh.clone();
            trial.faces.retain(|f| !cut.contains(f));
            // The loops the cut opens run along the cut faces' edges.
            let opened: HashSet<Edge> = cut.iter().flat_map(|&f| face_edges(f)).collect();
            let edges: HashSet<Edge> = trial.faces.iter().flat_map(|&f| face_edges(f)).collect();
            let rims = walked_edges(&trial.faces);
            let mut closed = CloseReport::default();
            for hole in hole_loops(&trial.faces) {
                let n = hole.len();
                if !(0..n).any(|i| opened.contains(&sorted_edge(hole[i], hole[(i + 1) % n]))) {
                    continue;
                }
                match self.patch(&trial, &hole, &rims, &edges) {
                    Ok(patch) => patch.add_to(&mut trial, &mut closed),
                    Err(more) => {
                        let more: Vec<[u32; 3]> = (more.iter())
                            .map(|&f| trial.faces[f as usize])
                            .filter(|f| mesh.faces.contains(f) && !cut.contains(f))
                            .collect();
                        if more.is_empty() || cut.len() + more.len() > self.opts.max_cut_faces {
                            return;
                        }
                        cut.extend(more);
                        continue 'grow;
                    }
                }
            }
            break (trial, closed);
        };
        let (before, after) = (TopologyReport::of(mesh), TopologyReport::of(&trial));
        let fewer_loops = hole_loops(&trial.faces).len() < hole_loops(&mesh.faces).len();
        if fewer_loops && after.holes <= before.holes && after.components <= before.components {
            *mesh = trial;
            report.holes_closed += 1;
            report.faces_added += closed.faces_added;
            report.vertices_added += closed.vertices_added;
            report.faces_cut += cut.len();
        }
    }
}

/// The face walking each directed edge of `faces` (the last one, where several do).
fn walked_edges(faces: &[[u32; 3]]) -> HashMap<Edge, u32> {
    (faces.iter().enumerate())
        .flat_map(|(i, &[a, b, c])| [([a, b], i as u32), ([b, c], i as u32), ([c, a], i as u32)])
        .collect()
}

/// The faces of `faces` (by index) that a face of `patch` folds onto ([`folds`]) across its
/// edge (`rims`: [`walked_edges`] of `faces`), with the vertices at `at`; an empty list when a
/// fold is within the patch, `None` when nothing folds.
fn patch_folds(
    patch: &[[u32; 3]],
    faces: &[[u32; 3]],
    rims: &HashMap<Edge, u32>,
    at: impl Fn(u32) -> Vec3,
) -> Option<Vec<u32>> {
    let normal = |f: [u32; 3]| {
        let [a, b, c] = f.map(|v| at(v).as_dvec3());
        (b - a).cross(c - a)
    };
    let own = walked_edges(patch);
    let mut onto = Vec::new();
    let mut within = false;
    for &f in patch {
        let [a, b, c] = f;
        for [u, v] in [[a, b], [b, c], [c, a]] {
            let across = match (own.get(&[v, u]), rims.get(&[v, u])) {
                (Some(&g), _) => Err(patch[g as usize]),
                (None, Some(&g)) => Ok(g),
                (None, None) => continue,
            };
            let other = across.map_or_else(|g| g, |g| faces[g as usize]);
            if folds(normal(f), normal(other)) {
                match across {
                    Ok(g) => onto.push(g),
                    Err(_) => within = true,
                }
            }
        }
    }
    onto.sort_unstable();
    onto.dedup();
    match (within, onto.is_empty()) {
        (false, true) => None,
        (true, _) => Some(Vec::new()),
        (false, false) => Some(onto),
    }
}

/// The loop `hole` triangulated between its own vertices: of the triangulations whose every
/// face has area, faces the way of the loop's Newell normal, adds no diagonal that is an
/// edge already and folds ([`folds`]) neither onto the face across a loop edge (`rim(i)`: the
/// normal of the face across the edge from `hole[i]` to the next) nor onto the face below it
/// in the triangulation, the one of least area (dynamic programming over the loop's
/// sub-chains, as in Barequet and Sharir's and Liepa's hole filling; the fold test between two
/// new faces keeps the best sub-triangulation only, so a fold-free one may be missed), if its
/// faces also pass `acceptable` (given the normal). The faces keep the loop's direction, as
/// the fan's do. `None` when there is no such triangulation, or the loop is longer than
/// [`MAX_TRIANGULATED`].
fn triangulate(
    hole: &[u32],
    positions: &[Vec3],
    edges: &HashSet<Edge>,
    min_area2: f32,
    rim: &impl Fn(usize) -> Option<DVec3>,
    acceptable: &impl Fn([Vec3; 3], Vec3) -> bool,
) -> Option<Vec<[u32; 3]>> {
    let k = hole.len();
    if k > MAX_TRIANGULATED {
        return None;
    }
    let at = |i: usize| positions[hole[i] as usize];
    let normal = (0..k)
        .map(|i| at(i).cross(at((i + 1) % k)))
        .sum::<Vec3>()
        .try_normalize()?;
    // A chord (i, j) of the loop may be a face's side unless it is a mesh edge already (the
    // loop's own edges, j = i + 1 and (0, k - 1), are the sides every face must reach).
    let free = |i: usize, j: usize| {
        j == i + 1 || (i == 0 && j == k - 1) || { !edges.contains(&sorted_edge(hole[i], hole[j])) }
    };
    // area[i][j]: the least area of a triangulation of the chain i..=j closed by the chord
    // (i, j), with the middle vertex chosen for it; infinite where there is none.
    let mut area = vec![vec![f32::INFINITY; k]; k];
    let mut middle = vec![vec![usize::MAX; k]; k];
    for i in 0..k - 1 {
        area[i][i + 1] = 0.0;
    }
    for span in 2..k {
        for i in 0..k - span {
            let j = i + span;
            if !free(i, j) {
                continue;
            }
            for m in i + 1..j {
                let n = (at(m) - at(i)).cross(at(j) - at(i));
                let (a, b) = (area[i][m], area[m][j]);
                if !(a.is_finite() && b.is_finite())
                    || n.length() <= min_area2
                    || n.dot(normal) <= 0.0
                {
                    continue;
                }
                // The faces next to this one: across a loop edge, the mesh's; across a
                // chord, the top face of the sub-triangulation below it.
                let below = |p: usize, q: usize| {
                    if q == p + 1 {
                        rim(p)
                    } else {
                        let r = middle[p][q];
                        Some((at(r) - at(p)).cross(at(q) - at(p)).as_dvec3())
                    }
                };
                let mut next = [below(i, m), below(m, j)]
                    .into_iter()
                    .flatten()
                    .chain((i == 0 && j == k - 1).then(|| rim(k - 1)).flatten());
                if next.any(|o| folds(n.as_dvec3(), o)) {
                    continue;
                }
                let total = a + b + n.length();
                if total < area[i][j] {
                    area[i][j] = total;
                    middle[i][j] = m;
                }
            }
        }
    }
    if !area[0][k - 1].is_finite() {
        return None;
    }
    let mut faces = Vec::with_capacity(k - 2);
    let mut chains = vec![(0, k - 1)];
    while let Some((i, j)) = chains.pop() {
        if j <= i + 1 {
            continue;
        }
        let m = middle[i][j];
        faces.push([hole[i], hole[m], hole[j]]);
        chains.extend([(i, m), (m, j)]);
    }
    faces
        .iter()
        .all(|f| acceptable(f.map(|v| positions[v as usize]), normal))
        .then_some(faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extract::manifold::unit_normal;
    use crate::geometry::primitives::{cube, icosphere};
    use crate::geometry::topology::TopologyReport;

    fn without_faces(mut mesh: Mesh, remove: &[usize]) -> Mesh {
        let mut k = 0;
        mesh.faces.retain(|_| {
            k += 1;
            !remove.contains(&(k - 1))
        });
        mesh
    }

    /// The cube [-1, 1]^3 without its two top triangles: one square hole.
    fn open_box() -> Mesh {
        let cube = cube();
        let top: Vec<usize> = (0..cube.faces.len())
            .filter(|&f| {
                cube.faces[f]
                    .iter()
                    .all(|&v| cube.positions[v as usize].y > 0.0)
            })
            .collect();
        assert_eq!(top.len(), 2);
        without_faces(cube, &top)
    }

    #[test]
    fn holes_in_a_closed_surface_close_cleanly() {
        // Two separate holes on opposite sides (a single missing face, and two adjacent ones
        // making a quad: faces 160 and 163 are a corner and the centre of one face split in four).
        let mut sphere = icosphere(2);
        sphere.normals = sphere.positions.iter().map(|p| p.normalize()).collect();
        let holed = without_faces(sphere.clone(), &[0, 160, 163]);
        let before = TopologyReport::of(&holed);
        assert_eq!(before.holes, 2, "{before:?}");
        let mut closed = holed.clone();
        let report = close_holes(
            &mut closed,
            &InputPoints::new(&[]),
            &CloseOptions::default(),
        );
        let after = TopologyReport::of(&closed);
        assert!(after.is_clean_closed(), "{after:?}");
        assert_eq!(report.holes_closed, before.holes);
        assert_eq!(report.holes_left, 0);
        assert_eq!(
            closed.positions.len(),
            holed.positions.len() + report.vertices_added
        );
        assert_eq!(closed.normals.len(), closed.positions.len());
        // New vertices lie inside the hole (near the sphere), not far off.
        for p in &closed.positions[holed.positions.len()..] {
            assert!((p.length() - 1.0).abs() < 0.1, "{p}");
        }
    }

    #[test]
    fn an_open_box_gets_a_lid_wound_like_its_walls() {
        // A cube without its two top triangles: one square hole, closed by a 4-face fan.
        let mut open = open_box();
        let report = close_holes(&mut open, &InputPoints::new(&[]), &CloseOptions::default());
        assert_eq!(
            (
                report.holes_closed,
                report.faces_added,
                report.vertices_added
            ),
            (1, 4, 1)
        );
        let after = TopologyReport::of(&open);
        assert!(after.is_clean_closed(), "{after:?}");
        assert_eq!(after.folded_edges, 0);
        // The lid faces up, as the removed top did.
        for &f in &open.faces[open.faces.len() - 4..] {
            assert!(unit_normal(&open.positions, f).y > 0.99);
        }
    }

    #[test]
    fn long_loops_lone_triangles_and_disabled_options_stay_open() {
        let cube = cube();
        let mut open = without_faces(cube.clone(), &[0, 1]);
        let long_only = CloseOptions {
            max_edges: 3,
            ..CloseOptions::default()
        };
        let report = close_holes(&mut open, &InputPoints::new(&[]), &long_only);
        assert_eq!((report.holes_closed, report.holes_left), (0, 1));
        let off = CloseOptions {
            enabled: false,
            ..CloseOptions::default()
        };
        assert_eq!(
            close_holes(&mut open, &InputPoints::new(&[]), &off),
            CloseReport::default()
        );
        // A lone triangle's border is a loop of three, and doubling it would close nothing.
        let mut lone = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![],
            faces: vec![[0, 1, 2]],
        };
        let report = close_holes(&mut lone, &InputPoints::new(&[]), &CloseOptions::default());
        assert_eq!((report.holes_closed, report.holes_left), (0, 1));
        assert_eq!(lone.faces.len(), 1);
    }

    /// Points on the faces of the cube [-1, 1]^3 whose outward axis passes `keep`.
    fn cube_points(keep: impl Fn(Vec3) -> bool) -> Vec<Vec3> {
        let mut points = Vec::new();
        for axis in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
            if !keep(axis) {
                continue;
            }
            let (u, v) = axis.any_orthonormal_pair();
            for i in 0..=40 {
                for j in 0..=40 {
                    let (a, b) = (i as f32 / 20.0 - 1.0, j as f32 / 20.0 - 1.0);
                    points.push(axis + u * a + v * b);
                }
            }
        }
        points
    }

    #[test]
    fn a_hole_is_capped_only_where_the_input_has_surface() {
        let open = open_box();
        // The input is an open box too: the lid would span air, so the hole stays.
        let mut kept = open.clone();
        let report = close_holes(
            &mut kept,
            &InputPoints::new(&cube_points(|a| a != Vec3::Y)),
            &CloseOptions::default(),
        );
        assert_eq!((report.holes_closed, report.holes_left), (0, 1));
        assert_eq!(kept, open);
        // The input is closed: the lid goes on, its new vertex on the top face's plane.
        let mut closed = open.clone();
        let report = close_holes(
            &mut closed,
            &InputPoints::new(&cube_points(|_| true)),
            &CloseOptions::default(),
        );
        assert_eq!((report.holes_closed, report.vertices_added), (1, 1));
        assert!((closed.positions.last().unwrap().y - 1.0).abs() < 1e-5);
        assert!(TopologyReport::of(&closed).is_clean_closed());
    }

    /// Points on a regular `n` by `n` grid of the unit square at z = 0 (the plane of
    /// `primitives::grid`), corners included.
    fn square_points(n: u32) -> Vec<Vec3> {
        (0..=n)
            .flat_map(|i| {
                (0..=n).map(move |j| Vec3::new(i as f32 / n as f32, j as f32 / n as f32, 0.0))
            })
            .collect()
    }

    #[test]
    fn a_hole_no_fan_can_close_is_triangulated_between_its_own_vertices() {
        // A U-shaped hole in a flat 7 x 6 grid: its centre lies on the faces between the U's
        // arms, so a fan from there would fold over them.
        let mut sheet = crate::geometry::primitives::grid(7, 6);
        let quad = |f: &[u32; 3], m: &Mesh| {
            let c = f.iter().map(|&v| m.positions[v as usize]).sum::<Vec3>() / 3.0;
            ((c.x * 7.0) as i32, (c.y * 6.0) as i32)
        };
        let before = sheet.clone();
        sheet.faces.retain(|f| {
            let (x, y) = quad(f, &before);
            !((y == 1 && (1..=5).contains(&x)) || ((x == 1 || x == 5) && (1..=4).contains(&y)))
        });
        // Input points over the U's box only: the grid's outer border (whose cap would lie on
        // the sheet's back) stays open, as its cap would span the unsampled margin.
        let points: Vec<Vec3> = square_points(60)
            .into_iter()
            .filter(|p| {
                (1.0 / 7.0..=6.0 / 7.0).contains(&p.x) && (1.0 / 6.0..=5.0 / 6.0).contains(&p.y)
            })
            .collect();
        let mut closed = sheet.clone();
        let report = close_holes(
            &mut closed,
            &InputPoints::new(&points),
            &CloseOptions::default(),
        );
        assert_eq!(
            (
                report.holes_closed,
                report.vertices_added,
                report.holes_left
            ),
            (1, 0, 1),
            "{report:?}"
        );
        assert_eq!(closed.faces.len(), before.faces.len());
        for &f in &closed.faces {
            assert!(unit_normal(&closed.positions, f).z > 0.99, "{f:?}");
        }
        let t = TopologyReport::of(&closed);
        assert_eq!(
            (t.holes, t.non_manifold_edges, t.inconsistent_winding_edges),
            (1, 0, 0)
        );
    }

    #[test]
    fn a_cap_that_would_fold_onto_its_rim_is_refused() {
        // A flat sheet sampled on its own plane: the cap over its border lies on the input, but
        // it is the sheet's back face, doubled over onto every rim face, so the border stays
        // open and the sheet is left as it was.
        let sheet = crate::geometry::primitives::grid(4, 4);
        let points = square_points(40);
        let mut out = sheet.clone();
        let report = close_holes(
            &mut out,
            &InputPoints::new(&points),
            &CloseOptions::default(),
        );
        assert_eq!(
            (report.holes_closed, report.holes_left),
            (0, 1),
            "{report:?}"
        );
        assert_eq!(out, sheet);
    }

    #[test]
    fn a_rim_face_turned_over_the_hole_is_cut_and_the_larger_hole_closed() {
        // A 3 x 3 sheet without its middle square, one rim face turned over the hole (its far
        // corner, vertex 1, pulled in over the hole): any patch of the hole folds onto that
        // face, so it is cut and the larger loop closed, and nothing is folded any more.
        let mut sheet = crate::geometry::primitives::grid(3, 3);
        let middle = |f: &[u32; 3], m: &Mesh| {
            let c = f.iter().map(|&v| m.positions[v as usize]).sum::<Vec3>() / 3.0;
            (1.0 / 3.0..2.0 / 3.0).contains(&c.x) && (1.0 / 3.0..2.0 / 3.0).contains(&c.y)
        };
        let whole = sheet.clone();
        sheet.faces.retain(|f| !middle(f, &whole));
        sheet.positions[1] = Vec3::new(0.55, 0.5, 0.01);
        let before = TopologyReport::of(&sheet);
        assert_eq!((before.holes, before.folded_edges), (2, 2), "{before:?}");
        for (max_cut_faces, closed) in [(0, 0), (1, 1)] {
            let opts = CloseOptions {
                max_cut_faces,
                ..CloseOptions::default()
            };
            let mut out = sheet.clone();
            let report = close_holes(&mut out, &InputPoints::new(&[]), &opts);
            let t = TopologyReport::of(&out);
            assert_eq!(
                (report.holes_closed, report.faces_cut, t.holes),
                (closed, closed, 2 - closed),
                "{report:?} {t:?}"
            );
            assert_eq!(t.folded_edges, if closed == 1 { 0 } else { 2 }, "{t:?}");
            assert_eq!((t.non_manifold_edges, t.inconsistent_winding_edges), (0, 0));
            assert_eq!(report.holes_left, 2 - closed);
        }
    }
}
