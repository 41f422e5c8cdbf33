//! Completing a generated surface between its own vertices, where the input points say there
//! is surface.
//!
//! A small model's edge scores miss many true edges, so the manifold extraction leaves a lace:
//! fans and strips that touch at vertices, with a hole between almost every pair (27 holes a
//! mesh on the test split), and some faces spanning air. The vertices themselves are mostly
//! right, and after [`crate::surface::fit`] they lie on the input's surface; what is missing is faces
//! between them. [`complete_surface`] offers the triangles a surface through those vertices
//! would have, and lets the manifold extraction choose among them after the model's own faces:
//!
//! 1. **Weld** vertices closer than `weld_ratio` median edges of the model's faces: a decoder's
//!    near-duplicates make slivers that fold.
//! 2. **On the surface.** A triangle lies on the input surface when every probe of it (the
//!    centroid, the edge midpoints, then a barycentric grid about `max_gap` apart) is within
//!    `max_gap` point spacings of an input point (the spacing: the median distance from an
//!    input point to its nearest neighbour). With `drop_off_surface`, the model's faces that
//!    fail it (shards across a concavity, a thin part or a hole) are removed.
//! 3. **Candidates.** Every triangle `(i, j, l)` with `j` and `l` among the `neighbours`
//!    nearest vertices of `i` and one of them among the other's, none of whose edges is
//!    longer than `max_edge_ratio` median edges of the model's faces, with no angle under
//!    `min_angle_degrees`, that lies on the surface; with `require_vote` (the default), only
//!    those with at least one vote of step 4, which leaves a fifth of the surface tests.
//! 4. **Rank.** Each candidate gets a vote from each of its vertices whose local Delaunay
//!    triangulation has it: the vertex and its neighbours projected onto the input surface's
//!    tangent plane there (of its 16 nearest input points), where a triangle is Delaunay when
//!    its circumcircle holds no other neighbour. Neighbours steeper out of that plane than
//!    `max_slope` (a sine) are left out: they lie across a thin part, and projected onto this
//!    side they would break its triangles. Most votes first, then shortest perimeter.
//! 5. **Choose.** The model's faces ranked `model_priority` votes ahead of the candidates
//!    (infinite: all first; the default 0 ranks each by its own votes, so a model face the
//!    surface disagrees with gives way to a better candidate), then the candidates, through
//!    [`crate::extract::manifold::manifold_faces`] (holes up to `max_hole_edges` edges filled, the
//!    overlap test at `overlap_tolerance`, small pieces dropped as the extraction does): a
//!    candidate is accepted only if every edge keeps at most two faces, it does not fold onto
//!    a neighbour or lie on another face, and it can be wound consistently with its
//!    neighbours. So the result keeps every guarantee of the manifold extraction, and the
//!    model's connectivity wherever it had any. Winding preference: Algorithm 1's rule from
//!    the vertex normals.
//! 6. **Keep the model's surface if this loses it.** When the result has fewer than half the
//!    model's faces (input points far from the vertices, say), the model's mesh comes back
//!    unchanged.
//!
//! Generation ([`crate::pipeline::generate`]) then refines `refine_passes` times: fit again
//! ([`crate::surface::fit`], with a little `refine_smoothing` towards each vertex's neighbours) now that
//! the completed faces, not the model's sparse ones, decide which moves fold, and complete
//! again with those faces as the "model's". Each pass moves the vertices that the first fit
//! held back onto the surface and closes holes their old positions kept open (validation
//! split, two passes and voted candidates against one completion: CD x100 5.59 -> 5.31,
//! holes 10.7 -> 6.8; docs/experiments/2026-11-25-refined-completion.md).
//!
//! 7. **Seed what the model left out** (off by default: `seed_gap`). Completion only joins
//!    vertices the model made: where it made none (a table leg, a pole, the far side of a
//!    slab it drew as one sheet), the input has points and the mesh has nothing.
//!    [`seed_uncovered`] puts a vertex at input points the refined surface misses, in
//!    clusters of at least [`MIN_UNCOVERED_CLUSTER`] of the input, no two closer than
//!    `seed_gap` median edges, and generation completes and refines once more, so those
//!    vertices join the surface like the model's own (first 80 validation meshes, 0.7 against
//!    none: CD x100 -0.41, NC +0.017, EF1 +0.041, at 7% more faces and 0.35 more holes a
//!    mesh, the rims of the parts it brings back; docs/experiments/2026-12-07-seed-uncovered.md
//!    and 2026-12-07-seed-clusters.md).
//!
//! Cost: a k-nearest search and a local Delaunay test (k^3) per vertex, and per candidate a
//! few nearest-point queries; tens of milliseconds at 512 vertices. Seeding measures each
//! input point's distance to the surface once, and adds a completion and its refinement.

// Fx hashing: the keys are small vertex ids, and SipHash was 12% of this stage's profile.
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

use glam::{DVec3, Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::extract::manifold::{ManifoldOptions, ManifoldReport, manifold_faces};
use crate::extract::orient_face;
use crate::geometry::clean::{weld, weld_map};
use crate::geometry::nearest::PointIndex;
use crate::geometry::normals::vertex_normals;
use crate::geometry::plane_fit::least_spread_direction;
use crate::geometry::topology::sorted_face;
use crate::geometry::triangle::distances_to_faces;
use crate::surface::input::InputPoints;

/// Options of [`complete_surface`] (missing JSON fields take the defaults).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CompleteOptions {
    /// Offer candidate triangles at all.
    pub enabled: bool,
    /// Nearest vertices each vertex may form a triangle with.
    pub neighbours: usize,
    /// Longest candidate edge, in median edges of the model's faces.
    pub max_edge_ratio: f32,
    /// Smallest candidate angle, in degrees.
    pub min_angle_degrees: f32,
    /// Farthest any point of a candidate may be from an input point, in input point
    /// spacings.
    pub max_gap: f32,
    /// Also remove the model's faces that fail the same surface test (shards spanning air).
    pub drop_off_surface: bool,
    /// Weld vertices closer than this many median edges first (a decoder's near-duplicates
    /// make slivers that fold; 0: none).
    pub weld_ratio: f32,
    /// The overlap test of the final choice ([`crate::extract::overlap`]), in longest edges: with the
    /// vertices on the surface, a face lying on another one not next to it is a second layer.
    pub overlap_tolerance: f32,
    /// Close hole loops of at most this many edges afterwards (the extraction's own limit
    /// when smaller): with the vertices on the surface, longer loops close cleanly.
    pub max_hole_edges: usize,
    /// How far ahead of the candidates the model's faces are ranked, in local Delaunay votes:
    /// +infinity puts every model face first; any other value ranks each model face like a
    /// candidate (by its votes and perimeter) with this many votes added.
    pub model_priority: f32,
    /// The local Delaunay test at a vertex leaves out neighbours farther out of its tangent
    /// plane than this sine of the angle (1 or more: none left out).
    pub max_slope: f32,
    /// Rounds of fitting and completing again after the first completion (in
    /// [`crate::pipeline::generate`]); 0: one completion.
    pub refine_passes: usize,
    /// The [`crate::surface::fit::FitOptions::smoothing`] of those rounds' fits.
    pub refine_smoothing: f32,
    /// Offer only triangles that some vertex's local Delaunay triangulation has (step 4):
    /// fewer holes, a fifth of the surface tests.
    pub require_vote: bool,
    /// After the refinement, new vertices at the input points the surface misses
    /// ([`seed_uncovered`]), no two closer than this many median edges, then completion and
    /// its refinement once more (0, the default: none; 0.7 measured, module documentation
    /// step 7).
    #[serde(default)]
    pub seed_gap: f32,
}

impl Default for CompleteOptions {
    fn default() -> Self {
        Self {
            enabled: true,
            neighbours: 24,
            max_edge_ratio: 8.0,
            min_angle_degrees: 15.0,
            max_gap: 6.0,
            drop_off_surface: true,
            weld_ratio: 0.25,
            overlap_tolerance: 0.5,
            max_hole_edges: 8,
            model_priority: 0.0,
            max_slope: 0.7,
            refine_passes: 2,
            refine_smoothing: 0.05,
            require_vote: true,
            seed_gap: 0.0,
        }
    }
}

/// What [`complete_surface`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CompleteReport {
    /// Candidate triangles that passed the tests of step 1.
    pub candidates: usize,
    /// Faces of the result that the model had not made.
    pub added: usize,
    /// Vertices welded into a neighbour closer than [`CompleteOptions::weld_ratio`].
    pub welded_vertices: usize,
    /// Faces of the model removed because they leave the input surface.
    pub off_surface: usize,
    /// True when the completed surface had fewer than half the model's faces, so the model's
    /// mesh was returned unchanged.
    pub kept_model_surface: bool,
    /// Other faces of the model that the choice did not keep (they fold onto a neighbour now
    /// that the vertices have moved).
    pub model_faces_dropped: usize,
    /// Vertices added at input points the surface missed ([`seed_uncovered`]; absent from
    /// reports written before it, and read there as 0).
    #[serde(default)]
    pub seeded: usize,
}

/// The faces of a surface through `positions` (see the module documentation): `faces` (the
/// model's, manifold and consistently wound) completed by triangles that lie on the surface
/// sampled by `points`. `normals` are per vertex (winding preference), `manifold` the options
/// of the final choice (hole filling, small pieces). With no finite point, no vertex or
/// `enabled` off, `faces` comes back unchanged.
pub fn complete_surface(
    mesh: &Mesh,
    points: &InputPoints,
    opts: &CompleteOptions,
    manifold: &ManifoldOptions,
) -> (Mesh, CompleteReport) {
    let mut report = CompleteReport::default();
    if !opts.enabled || mesh.positions.len() < 3 {
        return (mesh.clone(), report);
    }
    let point_index = points.index();
    if point_index.len() < 2 {
        return (mesh.clone(), report);
    }
    let spacing = points.spacing();
    let edge_scale = median_edge(&mesh.positions, &mesh.faces).unwrap_or(spacing * 4.0);
    let (mut welded, merged) = weld(mesh, opts.weld_ratio * edge_scale);
    report.welded_vertices = merged;
    welded.faces.retain(|&[a, b, c]| a != b && b != c && c != a);
    let (positions, normals, faces) = (&welded.positions, &welded.normals, &welded.faces);
    let vertex_index = PointIndex::new(positions);
    let k = opts.neighbours.max(2);
    let near: Vec<HashSet<u32>> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // The k nearest others: the vertex itself is among the first k + 1.
            vertex_index
                .k_nearest(*p, k + 1)
                .map(|(j, _)| j)
                .filter(|&j| j != i as u32)
                .take(k)
                .collect()
        })
        .collect();
    let max_edge = opts.max_edge_ratio * edge_scale;
    let max_gap = opts.max_gap * spacing;
    let min_sin = opts.min_angle_degrees.to_radians().sin();
    let existing: HashSet<[u32; 3]> = faces.iter().map(|&f| sorted_face(f)).collect();
    let normals: Vec<Vec3> = if normals.len() == positions.len() {
        normals.clone()
    } else {
        vertex_normals(positions, faces)
    };
    let model_faces: Vec<[u32; 3]> = faces
        .iter()
        .copied()
        .filter(|f| {
            !opts.drop_off_surface
                || on_surface(f.map(|v| positions[v as usize]), point_index, max_gap)
        })
        .collect();
    report.off_surface = faces.len() - model_faces.len();
    let votes = local_delaunay_votes(positions, &near, point_index, opts.max_slope);

    // Rank, lower first: ten perimeters (in median edges) a vote, plus `bonus` votes.
    let rank = |tri: [u32; 3], perimeter: f32, bonus: f32| {
        let v = f32::from(votes.get(&sorted_face(tri)).copied().unwrap_or(0));
        perimeter / edge_scale - 10.0 * (v + bonus)
    };
    let mut candidates: Vec<([u32; 3], f32)> = Vec::new();
    let mut seen: HashSet<[u32; 3]> = HashSet::default();
    for (i, ni) in near.iter().enumerate() {
        let i = i as u32;
        let mut around: Vec<u32> = ni.iter().copied().collect();
        around.sort_unstable();
        for (x, &j) in around.iter().enumerate() {
            for &l in &around[x + 1..] {
                if !(near[j as usize].contains(&l) || near[l as usize].contains(&j)) {
                    continue;
                }
                let tri = sorted_face([i, j, l]);
                if existing.contains(&tri)
                    || (opts.require_vote && !votes.contains_key(&tri))
                    || !seen.insert(tri)
                {
                    continue;
                }
                let corners = tri.map(|v| positions[v as usize]);
                if let Some(perimeter) = usable(corners, max_edge, min_sin)
                    && on_surface(corners, point_index, max_gap)
                {
                    candidates.push((tri, rank(tri, perimeter, 0.0)));
                }
            }
        }
    }
    report.candidates = candidates.len();
    // The model's faces first (above any candidate), then the candidates by rank: most
    // votes, then shortest.
    candidates.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    let mut preferred: Vec<[u32; 3]> = model_faces.clone();
    let mut scores: Vec<f32> = model_faces
        .iter()
        .map(|&f| {
            if opts.model_priority == f32::INFINITY {
                return f32::MAX;
            }
            let corners = f.map(|v| positions[v as usize]);
            let perimeter = (0..3)
                .map(|k| corners[k].distance(corners[(k + 1) % 3]))
                .sum::<f32>();
            -rank(f, perimeter, opts.model_priority)
        })
        .collect();
    for (tri, rank) in &candidates {
        preferred.push(orient_face(*tri, positions, &normals));
        scores.push(-rank);
    }
    let manifold = ManifoldOptions {
        max_hole_edges: manifold.max_hole_edges.max(opts.max_hole_edges),
        overlap_tolerance: opts.overlap_tolerance,
        ..*manifold
    };
    let (chosen, _): (Vec<[u32; 3]>, ManifoldReport) =
        manifold_faces(positions, &preferred, &scores, &manifold);
    let kept: HashSet<[u32; 3]> = chosen.iter().map(|&f| sorted_face(f)).collect();
    report.model_faces_dropped = model_faces
        .iter()
        .filter(|f| !kept.contains(&sorted_face(**f)))
        .count();
    report.added = kept.iter().filter(|f| !existing.contains(*f)).count();
    if chosen.len() * 2 < mesh.faces.len() {
        // The points disagree with most of the model's surface (far denser or sparser than
        // the vertices, or elsewhere): keep what the model made rather than lose it.
        report.kept_model_surface = true;
        return (mesh.clone(), report);
    }
    welded.faces = chosen;
    (welded, report)
}

/// Input points farther than this many point spacings from the surface, and than
/// [`UNCOVERED_EDGES`] median edges, are missed by it ([`seed_uncovered`]): beyond the fit's
/// reach (a vertex on the surface is within about one spacing).
pub const UNCOVERED_SPACINGS: f32 = 2.0;

/// The same in median edges of the mesh: a face a few spacings long cuts across a curved or
/// noisy surface by more than two spacings without leaving anything out (at 2 spacings
/// alone, the noisy 12-sided cylinder took 72 seeds and ended with 488 faces for 44).
pub const UNCOVERED_EDGES: f32 = 0.5;

/// Fewest uncovered input points, as a share of the input, that [`seed_uncovered`] seeds
/// among: a cluster of missed points linked within the seed gap must hold this many. A
/// handful of stray points, or a sliver of a thin wall's far side, becomes a small open
/// patch, a hole for little distance gained (first 80 validation meshes at a seed gap of 0.7,
/// against no seeding: every cluster seeded, CD x100 -0.49 for +1.21 holes a mesh; 1/32,
/// -0.41 for +0.35; 1/16, -0.34 for +0.16; 8 seeds a cluster at the fewest, -0.38 for +0.48;
/// docs/experiments/2026-12-07-seed-clusters.md).
pub const MIN_UNCOVERED_CLUSTER: f32 = 1.0 / 32.0;

/// Adds a vertex at input points that `mesh`'s surface does not come within
/// [`UNCOVERED_SPACINGS`] point spacings (or [`UNCOVERED_EDGES`] median edges, whichever is
/// larger) of, no two closer than `gap_ratio` median edges of its faces, for completion to
/// connect to the surface around them (module documentation, step 7). Only clusters of such
/// points (linked within that gap) holding at least [`MIN_UNCOVERED_CLUSTER`] of the input
/// are seeded. The points are taken in the index's order, each where no point taken so far is
/// that near. A new vertex's normal, where the mesh has normals, is the plane normal of its
/// 16 nearest input points, turned to agree with the nearest vertex's. Returns how many were
/// added; none with fewer than 16 finite points, no face or no positive gap.
pub fn seed_uncovered(mesh: &mut Mesh, points: &InputPoints, gap_ratio: f32) -> usize {
    let index = points.index();
    if index.len() < 16 || gap_ratio.is_nan() || gap_ratio <= 0.0 {
        return 0;
    }
    let Some(edge) = median_edge(&mesh.positions, &mesh.faces) else {
        return 0;
    };
    let gap = gap_ratio * edge;
    let far = f64::from((UNCOVERED_SPACINGS * points.spacing()).max(UNCOVERED_EDGES * edge));
    let uncovered = uncovered_points(mesh, points, far);
    // Clusters of missed points: single linkage within the gap, what welding computes.
    let (cluster, clusters) = weld_map(&uncovered, gap);
    let mut size = vec![0usize; clusters];
    for &c in &cluster {
        size[c as usize] += 1;
    }
    let fewest = (MIN_UNCOVERED_CLUSTER * index.len() as f32).ceil() as usize;
    let mut taken: Vec<Vec3> = Vec::new();
    // A grid of cells `gap` wide: a point taken within `gap` of another lies in a
    // neighbouring cell.
    let mut cells: HashMap<[i32; 3], Vec<u32>> = HashMap::default();
    let cell = |p: Vec3| (p / gap).floor().as_ivec3().to_array();
    for (&p, &c) in uncovered.iter().zip(&cluster) {
        if size[c as usize] < fewest {
            continue;
        }
        let [x, y, z] = cell(p);
        let crowded = (-1..=1).any(|dx| {
            (-1..=1).any(|dy| {
                (-1..=1).any(|dz| {
                    (cells.get(&[x + dx, y + dy, z + dz]))
                        .is_some_and(|ids| ids.iter().any(|&i| taken[i as usize].distance(p) < gap))
                })
            })
        });
        if !crowded {
            cells.entry([x, y, z]).or_default().push(taken.len() as u32);
            taken.push(p);
        }
    }
    if !mesh.normals.is_empty() {
        let vertices = PointIndex::new(&mesh.positions);
        for &p in &taken {
            let around: Vec<DVec3> = index.k_nearest(p, 16).map(|(_, q)| q.as_dvec3()).collect();
            let n = least_spread_direction(&around).map_or(Vec3::ZERO, |n| n.as_vec3());
            let beside = vertices
                .nearest(p)
                .map_or(Vec3::ZERO, |(v, _, _)| mesh.normals[v as usize]);
            mesh.normals.push(if n.dot(beside) < 0.0 { -n } else { n });
        }
    }
    mesh.positions.extend_from_slice(&taken);
    taken.len()
}

/// The input points farther than `far` from `mesh`'s faces.
fn uncovered_points(mesh: &Mesh, points: &InputPoints, far: f64) -> Vec<Vec3> {
    let index = points.index();
    let distances = distances_to_faces(mesh, index.iter().map(|(_, p)| p));
    (index.iter().zip(distances))
        .filter(|&(_, d)| d > far)
        .map(|((_, p), _)| p)
        .collect()
}

/// For each triangle, how many of its vertices have it in their local Delaunay triangulation:
/// the vertex and its nearest vertices projected onto the input surface's tangent plane there
/// (the plane of its 16 nearest input points), where a triangle at the vertex is Delaunay when
/// its circumcircle holds none of the other projected neighbours. Three votes: all three
/// vertices agree the triangle belongs to the surface.
fn local_delaunay_votes(
    positions: &[Vec3],
    near: &[HashSet<u32>],
    points: &PointIndex,
    max_slope: f32,
) -> HashMap<[u32; 3], u8> {
    let mut votes: HashMap<[u32; 3], u8> = HashMap::default();
    for (i, ni) in near.iter().enumerate() {
        let p = positions[i];
        let around: Vec<DVec3> = points.k_nearest(p, 16).map(|(_, q)| q.as_dvec3()).collect();
        let Some(normal) = least_spread_direction(&around) else {
            continue;
        };
        let (u, v) = normal.as_vec3().any_orthonormal_pair();
        let mut ids: Vec<u32> = ni.iter().copied().collect();
        ids.sort_unstable();
        // A neighbour steeply out of the plane is across a thin part (the far side of a
        // slab), not on this sheet: projected, it would break this sheet's triangles.
        ids.retain(|&j| {
            let d = positions[j as usize] - p;
            d.dot(normal.as_vec3()).abs() <= max_slope * d.length()
        });
        let flat: Vec<Vec2> = ids
            .iter()
            .map(|&j| {
                let d = positions[j as usize] - p;
                Vec2::new(d.dot(u), d.dot(v))
            })
            .collect();
        for x in 0..ids.len() {
            for y in x + 1..ids.len() {
                let Some((centre, r2)) = circumcircle(Vec2::ZERO, flat[x], flat[y]) else {
                    continue;
                };
                let empty = (0..ids.len())
                    .filter(|&z| z != x && z != y)
                    .all(|z| flat[z].distance_squared(centre) >= r2 * (1.0 - 1e-5));
                if empty {
                    *votes
                        .entry(sorted_face([i as u32, ids[x], ids[y]]))
                        .or_default() += 1;
                }
            }
        }
    }
    votes
}

/// Centre and squared radius of the circle through three points, `None` when they are
/// (nearly) collinear.
fn circumcircle(a: Vec2, b: Vec2, c: Vec2) -> Option<(Vec2, f32)> {
    let (b, c) = (b - a, c - a);
    let d = 2.0 * (b.x * c.y - b.y * c.x);
    let scale = b.length_squared().max(c.length_squared());
    if d.abs() <= 1e-6 * scale {
        return None;
    }
    let (bb, cc) = (b.length_squared(), c.length_squared());
    let centre = Vec2::new(c.y * bb - b.y * cc, b.x * cc - c.x * bb) / d;
    Some((a + centre, centre.length_squared()))
}

/// Median edge length over `faces`, `None` without faces.
fn median_edge(positions: &[Vec3], faces: &[[u32; 3]]) -> Option<f32> {
    let mut lengths: Vec<f32> = faces
        .iter()
        .flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)])
        .map(|(a, b)| positions[a as usize].distance(positions[b as usize]))
        .collect();
    lengths.sort_by(f32::total_cmp);
    lengths.get(lengths.len() / 2).copied()
}

/// The triangle's perimeter if no edge is longer than `max_edge` and no angle's sine is below
/// `min_sin` (nor its angle obtuse past `180 - asin(min_sin)`).
fn usable(corners: [Vec3; 3], max_edge: f32, min_sin: f32) -> Option<f32> {
    let [a, b, c] = corners;
    let edges = [b - a, c - b, a - c];
    let lengths = edges.map(Vec3::length);
    if lengths.iter().any(|&l| !(l > 0.0 && l <= max_edge)) {
        return None;
    }
    // sin of each angle = |cross| / (product of its two sides); twice the area is |cross|.
    let twice_area = edges[0].cross(edges[1]).length();
    let sines = [
        twice_area / (lengths[2] * lengths[0]),
        twice_area / (lengths[0] * lengths[1]),
        twice_area / (lengths[1] * lengths[2]),
    ];
    (sines.iter().all(|&s| s >= min_sin)).then(|| lengths.iter().sum())
}

/// Whether every probe of the triangle is within `max_gap` of a point: the centroid, the
/// edge midpoints, then a barycentric grid fine enough that no part of the triangle is more
/// than about `max_gap` from a probe (at most 16 steps an edge).
pub(crate) fn on_surface(corners: [Vec3; 3], points: &PointIndex, max_gap: f32) -> bool {
    let [a, b, c] = corners;
    let near = |p: Vec3| points.any_within(p, max_gap);
    let coarse = [
        (a + b + c) / 3.0,
        (a + b) / 2.0,
        (b + c) / 2.0,
        (c + a) / 2.0,
    ];
    if !coarse.into_iter().all(near) {
        return false;
    }
    let longest = a.distance(b).max(b.distance(c)).max(c.distance(a));
    let steps = ((longest / max_gap.max(f32::MIN_POSITIVE)).ceil() as usize).clamp(2, 16);
    (0..=steps).all(|i| {
        (0..=steps - i).all(|j| {
            let k = steps - i - j;
            // The corners are vertices, already fitted to the surface.
            if i == steps || j == steps || k == steps {
                return true;
            }
            let (u, v, w) = (i as f32, j as f32, k as f32);
            near((a * u + b * v + c * w) / steps as f32)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::topology::TopologyReport;

    const MANIFOLD: ManifoldOptions = ManifoldOptions {
        max_hole_edges: 4,
        min_component_faces: 0,
        overlap_tolerance: 0.2,
    };

    /// Points every 0.02 on the square [-1, 1]^2 at z = 0.
    fn plane_points() -> Vec<Vec3> {
        (0..=100)
            .flat_map(|i| {
                (0..=100).map(move |j| Vec3::new(i as f32 * 0.02 - 1.0, j as f32 * 0.02 - 1.0, 0.0))
            })
            .collect()
    }

    /// A 5x5 grid of vertices spaced 0.4 on z = 0, normals +z, with the given faces.
    fn grid(faces: Vec<[u32; 3]>) -> Mesh {
        let positions: Vec<Vec3> = (0..25)
            .map(|k| Vec3::new((k % 5) as f32 * 0.4 - 0.8, (k / 5) as f32 * 0.4 - 0.8, 0.0))
            .collect();
        Mesh {
            normals: vec![Vec3::Z; positions.len()],
            positions,
            faces,
        }
    }

    #[test]
    fn a_lace_of_faces_becomes_one_sheet() {
        // Two faces of the model, far apart: the rest is for completion to find.
        let model = grid(vec![[0, 1, 6], [18, 19, 24]]);
        let (mesh, r) = complete_surface(
            &model,
            &InputPoints::new(&plane_points()),
            &CompleteOptions::default(),
            &MANIFOLD,
        );
        let topo = TopologyReport::of(&mesh);
        // The 4x4 cells of the grid, two triangles each, one piece with one border loop.
        assert_eq!(mesh.faces.len(), 32, "{r:?}");
        assert_eq!(
            (topo.non_manifold_edges, topo.inconsistent_winding_edges),
            (0, 0)
        );
        assert_eq!((topo.components, topo.holes), (1, 1));
        assert_eq!((r.model_faces_dropped, r.off_surface, r.added), (0, 0, 30));
        assert!(mesh.faces.contains(&[0, 1, 6]) && mesh.faces.contains(&[18, 19, 24]));
        // Wound like the model's faces and the normals: +z.
        for f in &mesh.faces {
            let [a, b, c] = f.map(|v| mesh.positions[v as usize]);
            assert!((b - a).cross(c - a).z > 0.0);
        }
    }

    /// The plane's points without those with |x| < 0.35: the grid's vertex column x = 0
    /// stands in a gap 0.7 wide, and every triangle reaching it has an edge midpoint 0.15 or
    /// more from the surface (a gap of 3 spacings is 0.06). Also the options that say so.
    fn gapped_points() -> (Vec<Vec3>, CompleteOptions) {
        let points = plane_points()
            .into_iter()
            .filter(|p| !(p.x > -0.35 && p.x < 0.35))
            .collect();
        let opts = CompleteOptions {
            max_gap: 3.0,
            ..Default::default()
        };
        (points, opts)
    }

    #[test]
    fn no_face_spans_where_the_input_has_no_points() {
        let (points, opts) = gapped_points();
        let (mesh, _) =
            complete_surface(&grid(vec![]), &InputPoints::new(&points), &opts, &MANIFOLD);
        assert!(mesh.faces.len() >= 16);
        for f in &mesh.faces {
            let xs = f.map(|v| mesh.positions[v as usize].x);
            let left = xs.iter().all(|&x| x <= -0.39);
            let right = xs.iter().all(|&x| x >= 0.39);
            assert!(left || right, "a face crosses the gap: {xs:?}");
        }
    }

    /// The grid's cells with x <= 0 (the left half), two triangles each, wound to +z.
    fn left_half() -> Mesh {
        let mut faces = Vec::new();
        for row in 0..4u32 {
            for col in 0..2u32 {
                let k = row * 5 + col;
                faces.extend([[k, k + 1, k + 6], [k, k + 6, k + 5]]);
            }
        }
        grid(faces)
    }

    #[test]
    fn seeds_go_where_the_input_goes_on_and_completion_covers_it() {
        let points = plane_points();
        let input = InputPoints::new(&points);
        let mut mesh = left_half();
        let before = mesh.positions.len();
        let seeded = seed_uncovered(&mut mesh, &input, 0.7);
        assert!(seeded > 10, "{seeded}");
        assert_eq!(mesh.positions.len(), before + seeded);
        assert_eq!(mesh.normals.len(), mesh.positions.len());
        let new = &mesh.positions[before..];
        // Each new vertex is an input point farther from the half [-0.8, 0] x [-0.8, 0.8]
        // than half a median edge (0.2; two spacings are 0.04), and no two are closer than
        // 0.7 median edges (0.28).
        for (i, p) in new.iter().enumerate() {
            assert!(points.contains(p));
            let dx = p.x.max(-0.8 - p.x).max(0.0);
            let dy = (p.y.abs() - 0.8).max(0.0);
            assert!(dx.hypot(dy) > 0.2 - 1e-6, "{p}");
            assert!(new[i + 1..].iter().all(|q| q.distance(*p) >= 0.28), "{p}");
        }
        // Their normals agree with the mesh's (+z).
        assert!(mesh.normals[before..].iter().all(|n| n.z > 0.99));
        // Completion covers the right half, manifold and consistently wound.
        let (done, _) = complete_surface(&mesh, &input, &CompleteOptions::default(), &MANIFOLD);
        let area = |m: &Mesh| -> f32 {
            (m.faces.iter())
                .map(|f| {
                    let [a, b, c] = f.map(|v| m.positions[v as usize]);
                    (b - a).cross(c - a).length() / 2.0
                })
                .sum()
        };
        assert!(area(&done) > 2.0 * area(&left_half()), "{}", area(&done));
        let topo = TopologyReport::of(&done);
        assert_eq!(
            (topo.non_manifold_edges, topo.inconsistent_winding_edges),
            (0, 0)
        );
    }

    #[test]
    fn a_surface_that_covers_its_input_gets_no_seeds() {
        // Points only where the half lies: nothing is missed.
        let points: Vec<Vec3> = (plane_points().into_iter())
            .filter(|p| p.x <= 0.0 && p.x >= -0.8 && p.y.abs() <= 0.8)
            .collect();
        let mut mesh = left_half();
        assert_eq!(
            seed_uncovered(&mut mesh, &InputPoints::new(&points), 0.7),
            0
        );
        assert_eq!(mesh.positions.len(), 25);
        // Nor with no gap, no faces or too few points.
        let mut mesh = left_half();
        let all = InputPoints::new(&plane_points());
        assert_eq!(seed_uncovered(&mut mesh, &all, 0.0), 0);
        assert_eq!(seed_uncovered(&mut grid(vec![]), &all, 0.7), 0);
        assert_eq!(
            seed_uncovered(&mut mesh, &InputPoints::new(&points[..8]), 0.7),
            0
        );
    }

    #[test]
    fn a_handful_of_stray_points_gets_no_seeds_and_a_part_does() {
        // The half's own points, and beside them, 0.6 above the plane, a stray patch of 4 x 4
        // points: under 1/32 of the input, so no seeds.
        let half: Vec<Vec3> = (plane_points().into_iter())
            .filter(|p| p.x <= 0.0 && p.x >= -0.8 && p.y.abs() <= 0.8)
            .collect();
        let patch = |side: usize| -> Vec<Vec3> {
            (0..side * side)
                .map(|k| Vec3::new((k % side) as f32 * 0.05, (k / side) as f32 * 0.05, 0.6))
                .collect()
        };
        let mut points = half.clone();
        points.extend(patch(4));
        let mut mesh = left_half();
        assert_eq!(
            seed_uncovered(&mut mesh, &InputPoints::new(&points), 0.7),
            0
        );
        // A patch of 20 x 20 (a ninth of the input) is a part: it gets seeds, all on it.
        let mut points = half;
        points.extend(patch(20));
        let seeded = seed_uncovered(&mut mesh, &InputPoints::new(&points), 0.7);
        assert!(seeded > 4, "{seeded}");
        assert!(mesh.positions[25..].iter().all(|p| p.z == 0.6));
    }

    #[test]
    fn a_model_face_across_the_gap_is_dropped() {
        let (points, opts) = gapped_points();
        // Vertices 1, 3 (x = -0.4, 0.4) and 8 (x = 0.4): a shard spanning the gap.
        let (mesh, r) = complete_surface(
            &grid(vec![[1, 3, 8]]),
            &InputPoints::new(&points),
            &opts,
            &MANIFOLD,
        );
        assert_eq!(r.off_surface, 1);
        assert!(!mesh.faces.iter().any(|f| sorted_face(*f) == [1, 3, 8]));
    }

    #[test]
    fn off_or_without_points_nothing_changes() {
        let model = grid(vec![[0, 1, 6]]);
        let off = CompleteOptions {
            enabled: false,
            ..Default::default()
        };
        let (a, _) = complete_surface(&model, &InputPoints::new(&plane_points()), &off, &MANIFOLD);
        let (b, _) = complete_surface(
            &model,
            &InputPoints::new(&[]),
            &CompleteOptions::default(),
            &MANIFOLD,
        );
        assert_eq!((a, b), (model.clone(), model));
    }

    #[test]
    fn slivers_and_long_edges_are_not_candidates() {
        let max = 1.0;
        let min_sin = 15f32.to_radians().sin();
        let good = [Vec3::ZERO, Vec3::X * 0.5, Vec3::Y * 0.5];
        assert!(usable(good, max, min_sin).is_some());
        let sliver = [Vec3::ZERO, Vec3::X * 0.5, Vec3::new(0.25, 0.01, 0.0)];
        assert!(usable(sliver, max, min_sin).is_none());
        let long = [Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0];
        assert!(usable(long, max, min_sin).is_none());
    }

    #[test]
    fn a_regular_fan_is_locally_delaunay_at_its_centre() {
        let c = circumcircle(Vec2::ZERO, Vec2::X, Vec2::Y).unwrap();
        assert!((c.0 - Vec2::splat(0.5)).length() < 1e-6 && (c.1 - 0.5).abs() < 1e-6);
        assert!(circumcircle(Vec2::ZERO, Vec2::X, Vec2::X * 2.0).is_none());
    }
}
