//! Sharpening: the model's mesh made exact where the input points say it is wrong: flat
//! where they are flat, creased where they crease, and with few faces where a region is flat.
//!
//! One objective: the squared distance from the mesh to the planes of the input points
//! (each point's plane fitted to its `plane_neighbours` nearest points, weighted by how
//! planar that neighbourhood is, or where the point lies in a planar region of the input the
//! region's one plane, [`PointPlanes`]; on a noisy input a point left out of every region
//! whose neighbours lie on their regions' planes joins the nearest of those), with as few
//! faces as that distance allows.
//! Five steps pursue it:
//!
//! 1. **Room.** Each face is split into four until the median edge is at most about three
//!    point spacings (at most `max_refine` times in the first round, `later_refine` in each
//!    later one), so that vertices can sit on a crease that the model's coarse edges cross.
//!    A later round starts from the last one's few large faces, already on the creases: one
//!    split gives it room to move them and leaves a quarter of the faces to collapse back
//!    (docs/experiments/2026-12-05-later-refine.md).
//! 2. **Placement.** Each vertex goes to the minimiser of the quadric of the planes of its
//!    `neighbours` nearest points, with eigenvalues below `rank_cutoff` of the largest
//!    truncated ([`Quadric::minimiser_near`], as dual contouring does): on a flat region the
//!    vertex moves across the plane only; next to a crease it snaps onto the crease line,
//!    next to a corner onto the corner. Where the input's planar regions meet within a
//!    spacing of the vertex, their own planes place it instead, on their crease line or
//!    corner (`PointPlanes::region_meet`): a vertex most of whose nearest points lie on
//!    one face would stay on that face. A move that would flip or fold a face is shortened.
//!    Then **reach**: the input points more than two spacings from the mesh pull the faces
//!    nearest them, along the surface only (`reach_steps` steps), so that an edge of the
//!    model's mesh that stops short of the input (a wedge's thin end) slides out to it.
//! 3. **Quadric decimation.** Garland and Heckbert's edge collapses, each vertex's quadric
//!    the planes of the input points nearest it, cheapest first, guarded by the link
//!    condition and a turn limit ([`EditMesh::plan_collapse`]), down to the face count the
//!    mesh came in with, and on below it while a collapse costs less than the flatness
//!    tolerance (RMS distance `flat_tolerance` of the mesh's size, or `noise_tolerance` times
//!    the points' own RMS off-plane spread, whichever is larger) and leaves no face farther
//!    from the input than twice that, or than the faces there were (`strays`): a flat region
//!    ends as a few large faces, a crease as one row of edges. No collapse takes the surface
//!    away from the input points it covered (`Coverage`), so a thin part (a leg, a fin)
//!    survives; where it refuses the collapses that would reach the incoming face count, more
//!    faces stay (14 of the 244 test-split meshes end with more faces than they came with).
//!    Delaunay flips between coplanar faces undo the slivers that greedy collapses leave, and
//!    the collapses go on.
//! 4. **Snap.** Each vertex goes to the truncated minimiser of all the planes it gathered, so
//!    that one whose region straddles a crease lands on it (or, as in placement, to where the
//!    planar regions near it meet).
//! 5. **Crease-aligned flips.** An edge whose two faces' probes (the edge's midpoint and the
//!    face centroids) lie clearly farther from the input planes than the other diagonal's
//!    would is flipped: an edge across a crease becomes one along it.
//!
//! The five steps run `passes` times (16 by default); each round starts nearer the input than
//! the last, so placement and collapses correct what the previous round left. The round kept
//! then loses the vertices it does not need (one inside a flat side, on a straight crease or
//! on a straight rim: [`remove_redundant_vertices`], within a quarter of a point spacing),
//! which the greedy collapses' order and guards can leave.
//!
//! The mesh stays manifold with consistent winding; its holes and pieces are kept (no edit
//! joins two boundaries), and no collapse or flip leaves more folded edges around it than
//! there were. A round is kept only with no more holes, folded edges or faces without area
//! than the mesh came with. The model's mesh decides the pieces, the holes and the rough shape;
//! its edges are mostly rebuilt ([`SharpenReport::model_edges_kept`] says how many survive:
//! 2-9% on the hard-surface set).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::geometry::edit::EditMesh;
use crate::geometry::nearest::PointIndex;
use crate::geometry::normals::vertex_normals;
use crate::geometry::plane_fit::{covariance, least_spread_direction};
use crate::geometry::plane_regions::{PlaneRegion, join_fringe, plane_regions, regions_noise};
use crate::geometry::quadric::Quadric;
use crate::geometry::quadric::symmetric_eigenvalues;
use crate::geometry::redundant_vertices::remove_redundant_vertices;
use crate::geometry::topology::{TopologyReport, edges};
use crate::geometry::triangle::{
    Bound, closest_point_weights, nearest_triangle, point_triangle_distance,
};
use crate::parallel::map_in_parallel;
use crate::surface::fit::{face_pairs, hold_back_folds};

/// Options of [`sharpen`] (missing JSON fields take the defaults).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SharpenOptions {
    /// Off: the mesh is left as it is.
    pub enabled: bool,
    /// Input points whose planes place each vertex.
    pub neighbours: usize,
    /// Points that define each input point's plane.
    pub plane_neighbours: usize,
    /// Eigenvalues of a vertex's quadric below this share of the largest are truncated.
    pub rank_cutoff: f64,
    /// Most 1-to-4 splits before placement, in the first round.
    pub max_refine: usize,
    /// The same in every later round, which starts from the last round's few large faces.
    pub later_refine: usize,
    /// Flatness tolerance: RMS distance, as a share of the input's longest side, that a
    /// collapse below the incoming face count may cost.
    pub flat_tolerance: f64,
    /// The same, in multiples of the input points' own RMS distance from their planes
    /// (noise); the larger of the two holds.
    pub noise_tolerance: f64,
    /// A collapse may turn a surviving face by at most this many degrees.
    pub max_turn_deg: f64,
    /// Rounds of the whole (split, place, flip, collapse, snap).
    pub passes: usize,
    /// Generation keeps the sharpened mesh when its distance to the input points is at most
    /// this many times the fitted mesh's (`pipeline::generate::sharpen_kept`; 1: never
    /// farther).
    pub accept_ratio: f64,
    /// Steps of reach in each round: the input points that the mesh does not come within two
    /// point spacings of draw the faces nearest them out along the surface (0: none).
    pub reach_steps: usize,
    /// Generation sharpens this many of its candidates, the nearest the input points first,
    /// and keeps the sharpened one nearest them (`pipeline::generate::keep_sharpened`; 1: only
    /// the candidate kept before sharpening).
    pub candidates: usize,
}

impl Default for SharpenOptions {
    fn default() -> Self {
        Self {
            enabled: true,
            neighbours: 10,
            plane_neighbours: 12,
            rank_cutoff: 0.08,
            max_refine: 2,
            later_refine: 1,
            flat_tolerance: 0.003,
            noise_tolerance: 3.0,
            max_turn_deg: 60.0,
            passes: 16,
            accept_ratio: 1.0,
            candidates: 1,
            reach_steps: 1,
        }
    }
}

/// What [`sharpen`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SharpenReport {
    pub faces_in: usize,
    /// Faces after the 1-to-4 splits, and how many splits.
    pub refined_faces: usize,
    pub refinements: usize,
    /// Vertices of the last round snapped onto a crease line (quadric rank 2, or two planar
    /// regions meeting) or a corner (rank 3, or three).
    pub crease_vertices: usize,
    pub corner_vertices: usize,
    /// Edges flipped to follow a crease, and edge collapses, over all rounds.
    pub flips: usize,
    pub collapses: usize,
    pub faces_out: usize,
    /// Share of the model's edges that are edges of the output (between the same two
    /// vertices, wherever they moved).
    pub model_edges_kept: f32,
    /// The collapse tolerance used (RMS distance, the input's frame).
    pub tolerance: f32,
    /// Whether a round's mesh was kept: [`sharpen`] always keeps the last; [`sharpen_judged`]
    /// none when its judge accepts none (generation's judge: no farther from the input points
    /// than the fitted mesh, `pipeline::generate::sharpen_kept`).
    pub accepted: bool,
    /// The distances to the input points that decided it (Chamfer to the points, holes
    /// counting against it, as candidates are ranked): the fitted mesh's and the sharpened
    /// one's. Zero when generation did not judge.
    pub input_distance_before: f64,
    pub input_distance_after: f64,
    /// The round whose mesh was kept (the last that the judge of [`sharpen_judged`]
    /// accepted; 0 when none was, or sharpening did not run).
    pub rounds_kept: usize,
    /// Holes that generation closed in the kept round's mesh (hole closing again, now that
    /// sharpening has flattened their rims: `pipeline::generate::sharpen_kept`); absent from
    /// reports written before, and read as 0.
    #[serde(default)]
    pub holes_closed: usize,
    /// Vertices of the kept round that the surface did not need, removed
    /// ([`remove_redundant_vertices`]); absent from reports written before, and read as 0.
    #[serde(default)]
    pub redundant_removed: usize,
}

impl SharpenReport {
    /// Whether sharpening ran at all (it leaves a mesh alone without faces, with too few
    /// planar input points, or when turned off).
    pub fn ran(&self) -> bool {
        self.faces_in > 0 && self.refined_faces > 0
    }
}

/// One line for a person: what sharpening did, or why the fitted mesh stayed.
impl std::fmt::Display for SharpenReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if !self.ran() {
            return f.write_str("not sharpened (no faces, or too few planar input points)");
        }
        if !self.accepted {
            return f.write_str(
                "every round of sharpening was farther from the input points than the fitted \
                 mesh; kept the fitted one",
            );
        }
        write!(
            f,
            "sharpened: {} -> {} faces (round {}; {} split, {} crease and {} corner vertices, {} \
             flips, {} collapses; {:.0}% of the model's edges kept; --no-sharpen turns it off)",
            self.faces_in,
            self.faces_out,
            self.rounds_kept,
            self.refined_faces,
            self.crease_vertices,
            self.corner_vertices,
            self.flips,
            self.collapses,
            100.0 * self.model_edges_kept
        )?;
        if self.redundant_removed > 0 {
            write!(
                f,
                "; {} vertices a flat face did not need removed",
                self.redundant_removed
            )?;
        }
        if self.holes_closed > 0 {
            write!(f, "; {} holes closed after it", self.holes_closed)?;
        }
        Ok(())
    }
}

/// Planar regions of the input ([`plane_regions`]): a point joins within this many times the
/// input's RMS distance from its neighbourhoods' planes (its noise) of the region's plane,
/// with its own plane at most [`REGION_ANGLE_DEG`] from the region's; a region is kept with
/// at least [`REGION_MIN_POINTS`] points whose RMS distance from its plane is at most
/// [`REGION_RMS`] times the noise.
const REGION_DISTANCE: f64 = 2.5;
const REGION_ANGLE_DEG: f64 = 25.0;
const REGION_RMS: f64 = 1.2;
const REGION_MIN_POINTS: usize = 36;
/// An input is noisy, and the points left out of its regions join them ([`join_fringe`]),
/// where its regions' noise ([`regions_noise`]) is over this many point spacings.
const NOISY_REGIONS: f64 = 0.35;

/// Where planar regions meet ([`PointPlanes::region_meet`]): the regions of this many points
/// nearest a vertex (twice a point's plane neighbours, as a region stops a spacing or two
/// short of a crease; 24 against 10 to 48 in docs/experiments/2026-12-06-region-meet.md)...
const MEET_NEIGHBOURS: usize = 24;
/// ...whose planes pass within this many point spacings of it.
const MEET_SPACINGS: f64 = 1.0;

/// The input points' planes, computed once per input and shared by its candidates.
///
/// A point within a spacing or two of a crease has neighbours on both sides, and the plane
/// fitted to them is tilted halfway between the two faces: a plane no face has. So each
/// point's plane carries a confidence, 1 where its neighbourhood is as planar as the input's
/// median one and falling with the square of its surface variation beyond twice that, and
/// the quadrics weigh the planes by it: near a crease, the planes of the faces on either
/// side decide, as they meet exactly on the crease line.
///
/// With noise, a plane fitted to a dozen neighbours tilts by a few degrees, and a large flat
/// face, measured against hundreds of such planes, costs more than the collapse tolerance
/// allows: a noisy box kept 88 faces. So the points of a planar region (grown over the
/// points' neighbourhoods, [`plane_regions`]) take the region's one plane instead, through
/// their projection onto it; a region is kept only where its points lie as near its plane as
/// the noise says they can, so a curved surface keeps its points' own planes.
#[derive(Clone, Debug, Default)]
pub struct PointPlanes {
    index: PointIndex,
    /// Unit normal of each input point's plane (by the point's index), zero where its
    /// neighbours span no plane: the plane of its planar region where it is in one
    /// ([`plane_regions`]), else the plane of its neighbours.
    normals: Vec<DVec3>,
    /// A point on each plane: the input point projected onto its region's plane, else the
    /// point itself.
    origins: Vec<DVec3>,
    /// Each plane's confidence in [0, 1] (see above).
    confidence: Vec<f64>,
    /// Median distance between neighbouring points.
    spacing: f64,
    /// Points with a plane (their neighbours span one).
    with_plane: usize,
    /// Median RMS distance of a neighbourhood from its plane (the input's noise, and
    /// curvature).
    rms_off_plane: f64,
    /// The input's planar regions, and the region of each point (by index) that is in one.
    regions: Vec<PlaneRegion>,
    region_of: Vec<Option<u32>>,
}

impl PointPlanes {
    /// The planes of `points` (non-finite ones ignored) from their `k` nearest points each.
    pub fn new(points: &[Vec3], k: usize) -> Self {
        let index = PointIndex::new(points);
        let mut normals = vec![DVec3::ZERO; points.len()];
        let mut variation = vec![f64::INFINITY; points.len()];
        let mut residuals = Vec::with_capacity(points.len());
        // Each point's plane on its own (in parallel where there are threads).
        let fitted = map_in_parallel(index.iter().collect(), |_, (i, p)| {
            let near: Vec<DVec3> = index
                .k_nearest(p, k.max(3))
                .map(|(_, q)| q.as_dvec3())
                .collect();
            least_spread_direction(&near)
                .map(|n| (i as usize, n, symmetric_eigenvalues(covariance(&near))))
        });
        for (i, n, values) in fitted.into_iter().flatten() {
            let total: f64 = values.iter().sum();
            normals[i] = n;
            variation[i] = values[0].max(0.0) / total.max(1e-300);
            residuals.push(values[0].max(0.0));
        }
        residuals.sort_by(f64::total_cmp);
        let rms_off_plane = residuals.get(residuals.len() / 2).map_or(0.0, |v| v.sqrt());
        let mut sorted: Vec<f64> = variation
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .collect();
        sorted.sort_by(f64::total_cmp);
        // A floor, so that an exactly flat input does not make every rounding a crease.
        let typical = sorted
            .get(sorted.len() / 2)
            .copied()
            .unwrap_or(0.0)
            .max(1e-4);
        let confidence = variation
            .iter()
            .map(|&v| {
                if v.is_finite() {
                    (2.0 * typical / v).powi(2).min(1.0)
                } else {
                    0.0
                }
            })
            .collect();
        let mut origins: Vec<DVec3> = points.iter().map(|p| p.as_dvec3()).collect();
        // Planar regions: a flat part's points take its one plane, which noise does not tilt.
        let spacing = index.spacing() as f64;
        let noise = rms_off_plane.max(0.01 * spacing);
        let (regions, mut of_point) = plane_regions(
            &index,
            &normals,
            &variation,
            k.max(3),
            REGION_DISTANCE * noise,
            REGION_ANGLE_DEG,
            REGION_RMS * noise,
            REGION_MIN_POINTS,
        );
        // A noisy input's regions stop short of its creases: the points there join the face
        // they lie on. A clean one's reach them, and joining there only costs the artist
        // meshes' fillets (docs/experiments/2026-12-06-crease-points.md).
        if regions_noise(&regions) > NOISY_REGIONS * spacing {
            join_fringe(
                &index,
                k.max(3),
                REGION_DISTANCE * noise,
                &regions,
                &mut of_point,
            );
        }
        for (i, region) in of_point.iter().enumerate() {
            if let Some(r) = region.map(|r| regions[r as usize]) {
                normals[i] = r.normal;
                let off = r.normal.dot(origins[i] - r.origin);
                origins[i] -= r.normal * off;
            }
        }
        PointPlanes {
            regions,
            region_of: of_point,
            origins,
            spacing,
            index,
            normals,
            confidence,
            with_plane: residuals.len(),
            rms_off_plane,
        }
    }

    /// The points' count (finite ones).
    pub fn len(&self) -> usize {
        self.index.len()
    }

    pub fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    /// The (finite) input points.
    fn points(&self) -> Vec<DVec3> {
        self.index.iter().map(|(_, p)| p.as_dvec3()).collect()
    }

    /// How well surface `normals` at `samples` agree with the input's planes: the mean
    /// absolute cosine between each sample's normal and the plane normal that stands for the
    /// input nearest it (the plane `nearest_plane` picks), over samples with one; `None`
    /// where none has. Normal consistency against the input, with no ground truth.
    pub fn normal_agreement(&self, samples: &[Vec3], normals: &[Vec3]) -> Option<f64> {
        let (mut sum, mut count) = (0.0f64, 0usize);
        for (x, n) in samples.iter().zip(normals) {
            if let Some((_, plane)) = self.nearest_plane(x.as_dvec3())
                && plane != DVec3::ZERO
            {
                sum += n.as_dvec3().dot(plane).abs();
                count += 1;
            }
        }
        (count > 0).then(|| sum / count as f64)
    }

    /// The point and plane normal that stand for the surface near `x`: the most confident of
    /// its 4 nearest points, the nearest among equals.
    fn nearest_plane(&self, x: DVec3) -> Option<(DVec3, DVec3)> {
        let mut best: Option<(f64, DVec3, DVec3)> = None;
        for (i, _) in self.index.k_nearest(x.as_vec3(), 4) {
            let c = self.confidence[i as usize];
            if best.is_none_or(|(b, _, _)| c > b + 1e-9) {
                best = Some((c, self.origins[i as usize], self.normals[i as usize]));
            }
        }
        best.map(|(_, p, n)| (p, n))
    }

    /// The quadric of the confidence-weighted planes of the `k` points nearest `x`, and the
    /// distance to the farthest of them.
    fn quadric_near(&self, x: DVec3, k: usize) -> (Quadric, f64) {
        let mut q = Quadric::default();
        let mut reach = 0.0f64;
        for (i, p) in self.index.k_nearest(x.as_vec3(), k) {
            let (i, p) = (i as usize, p.as_dvec3());
            reach = reach.max(p.distance(x));
            if self.normals[i] != DVec3::ZERO && self.confidence[i] > 0.0 {
                q += Quadric::plane(self.normals[i], self.origins[i], self.confidence[i]);
            }
        }
        (q, reach)
    }

    /// Where the input's planar regions meet near `x`: the point nearest `x` on the crease
    /// line of two regions, or the corner of three, with its rank (2 or 3). The regions are
    /// those of the [`MEET_NEIGHBOURS`] points nearest `x` whose planes pass within
    /// [`MEET_SPACINGS`] point spacings of it; planes whose quadric has a rank below 2 at
    /// `rank_cutoff` (under about 30 degrees apart at 0.08) do not meet. `None` where fewer
    /// than two regions meet there, or where their meeting is farther than two of those
    /// distances.
    ///
    /// Why the regions' planes and not the points': the quadric of a vertex's nearest points
    /// weighs each face by how many of its points are near, so a vertex within a spacing of a
    /// crease, most of whose points lie on one face, stays on that face; the clean box kept a
    /// crumpled seam of sliver faces along one edge that way (30 faces for its 12).
    fn region_meet(&self, x: DVec3, rank_cutoff: f64) -> Option<(DVec3, usize)> {
        let within = MEET_SPACINGS * self.spacing;
        let mut near: Vec<u32> = Vec::new();
        for (i, _) in self.index.k_nearest(x.as_vec3(), MEET_NEIGHBOURS) {
            if let Some(r) = self.region_of[i as usize]
                && !near.contains(&r)
            {
                near.push(r);
            }
        }
        let mut q = Quadric::default();
        for r in near.iter().map(|&r| self.regions[r as usize]) {
            if r.normal.dot(x - r.origin).abs() <= within {
                q += Quadric::plane(r.normal, r.origin, 1.0);
            }
        }
        let rank = q.rank(rank_cutoff);
        if rank < 2 {
            return None;
        }
        let y = q.minimiser_near(x, rank_cutoff);
        (y.distance(x) <= 2.0 * within).then_some((y, rank))
    }

    /// `x` projected onto the plane of [`Self::nearest_plane`] (`x` where there is none).
    fn project(&self, x: DVec3) -> DVec3 {
        self.nearest_plane(x)
            .map_or(x, |(p, normal)| x - normal * normal.dot(x - p))
    }

    /// Distance from `x` to the input surface: the least distance to the planes of its 6
    /// nearest points that are confident (at least one half; all of them where none is), so
    /// that a point on one face near a crease is not measured against the other face's plane.
    fn distance(&self, x: DVec3) -> f64 {
        let (mut confident, mut any) = (f64::INFINITY, f64::INFINITY);
        for (i, p) in self.index.k_nearest(x.as_vec3(), 6) {
            let (i, p) = (i as usize, p.as_dvec3());
            let d = if self.normals[i] == DVec3::ZERO {
                p.distance(x)
            } else {
                self.normals[i].dot(x - self.origins[i]).abs()
            };
            any = any.min(d);
            if self.confidence[i] >= 0.5 {
                confident = confident.min(d);
            }
        }
        if confident.is_finite() {
            confident
        } else if any.is_finite() {
            any
        } else {
            0.0
        }
    }

    /// Each point's plane, weighted by its confidence, for the points that have one.
    fn weighted_planes(&self) -> impl Iterator<Item = (DVec3, DVec3, f64)> + '_ {
        self.index.iter().filter_map(|(i, _)| {
            let i = i as usize;
            (self.normals[i] != DVec3::ZERO)
                .then(|| (self.origins[i], self.normals[i], self.confidence[i]))
        })
    }
}

/// Sharpens `mesh` (manifold, consistently wound) against the input `planes` (see the module
/// documentation). Without faces, with `enabled` off, or when fewer than 16 input points or
/// fewer than half of them have a plane (points on a line, all in one place), the mesh is
/// left alone.
pub fn sharpen(mesh: &mut Mesh, planes: &PointPlanes, opts: &SharpenOptions) -> SharpenReport {
    sharpen_judged(mesh, planes, opts, |_| true)
}

/// [`sharpen`], keeping the mesh of the last round that `acceptable` accepts: asked of the
/// last round first, then of each earlier one until it says yes (so a mesh whose last round
/// passes costs one question). When no round passes, `mesh` is left as it came and the
/// report says `accepted: false`. A later round is flatter and has fewer faces, so the last
/// acceptable one is the most sharpened mesh the judge allows.
pub fn sharpen_judged(
    mesh: &mut Mesh,
    planes: &PointPlanes,
    opts: &SharpenOptions,
    mut acceptable: impl FnMut(&Mesh) -> bool,
) -> SharpenReport {
    let mut report = SharpenReport {
        faces_in: mesh.faces.len(),
        faces_out: mesh.faces.len(),
        model_edges_kept: 1.0,
        accepted: true,
        ..SharpenReport::default()
    };
    let planar = planes.len() >= 16 && 2 * planes.with_plane >= planes.len();
    if !opts.enabled || mesh.faces.is_empty() || !planar || planes.spacing <= 0.0 {
        return report;
    }
    // The mesh's own size, which a few far outliers among the points do not inflate.
    let extent = mesh.aabb().map_or(0.0, |b| f64::from(b.max_extent()));
    let model_edges = edges(&mesh.faces);
    let mut m = EditMesh::from_mesh(mesh);
    let target_faces = m.face_count();

    let tolerance = (opts.flat_tolerance * extent).max(opts.noise_tolerance * planes.rms_off_plane);
    report.tolerance = tolerance as f32;
    let points = planes.points();
    // Each round's mesh, compacted: (positions, faces, the edit mesh's vertex of each).
    let mut rounds = Vec::with_capacity(opts.passes);
    for round in 0..opts.passes {
        let (mut crease, mut corner) = (0, 0);
        // 1. Room for the creases.
        let max_refine = if round == 0 {
            opts.max_refine
        } else {
            opts.later_refine
        };
        let mut splits = 0;
        while splits < max_refine && median_edge(&m).is_some_and(|l| l > 3.0 * planes.spacing) {
            m.subdivide();
            splits += 1;
        }
        report.refinements += splits;
        report.refined_faces = report.refined_faces.max(m.face_count());

        // 2. Placement: each vertex to the truncated minimiser of its nearby points' planes
        // (onto a crease or corner when it is next to one), or onto the nearest plane where
        // that minimiser is farther than those points.
        let before = m.positions.clone();
        let live: Vec<bool> = (0..before.len())
            .map(|v| !m.faces_of(v as u32).is_empty())
            .collect();
        m.positions = map_in_parallel(before.iter().zip(&live).collect(), |_, (&from, &live)| {
            if !live {
                return from;
            }
            if let Some((x, _)) = planes.region_meet(from, opts.rank_cutoff) {
                return x;
            }
            let (q, reach) = planes.quadric_near(from, opts.neighbours);
            let x = q.minimiser_near(from, opts.rank_cutoff);
            if x.distance(from) <= reach {
                x
            } else {
                planes.project(from)
            }
        });
        hold_back(&mut m, &before);
        // 2b. Reach: out to the input the model's mesh stops short of.
        let far = (REACH_SPACINGS * planes.spacing).max(3.0 * planes.rms_off_plane);
        for _ in 0..opts.reach_steps {
            reach(&mut m, &points, far, REACH_SPACINGS * planes.spacing);
        }

        // 3. Decimation on the input's planes: each vertex's quadric holds the planes of the
        // points nearest it.
        let mut quadrics = vertex_quadrics(&m, planes);
        report.collapses += decimate(
            &mut m,
            planes,
            &points,
            &mut quadrics,
            target_faces,
            tolerance,
            opts.max_turn_deg,
        );

        // 4. Snap: each vertex to the truncated minimiser of the planes it gathered, so vertices
        // whose region straddles a crease land on it, and on a corner where three planes meet.
        let before = m.positions.clone();
        for v in 0..m.positions.len() {
            if m.faces_of(v as u32).is_empty() {
                continue;
            }
            let q = quadrics[v];
            let (x, meet) = planes
                .region_meet(before[v], opts.rank_cutoff)
                .unwrap_or_else(|| {
                    let x = q.minimiser_near(before[v], opts.rank_cutoff);
                    // A far jump means an ill-conditioned system: keep the plane part only.
                    let far = x.distance(before[v]) > 4.0 * planes.spacing;
                    (
                        if far {
                            q.minimiser_near(before[v], 0.5)
                        } else {
                            x
                        },
                        0,
                    )
                });
            match q.rank(opts.rank_cutoff).max(meet) {
                2 => crease += 1,
                3 => corner += 1,
                _ => {}
            }
            m.positions[v] = x;
        }
        hold_back(&mut m, &before);

        // 5. Flips along the creases the snap made.
        report.flips += align_flips(&mut m, planes);
        report.crease_vertices = crease;
        report.corner_vertices = corner;
        rounds.push(m.compacted());
    }

    let had_normals = !mesh.normals.is_empty();
    let as_mesh = |positions: &[DVec3], faces: &[[u32; 3]]| {
        let mut out = Mesh::new(
            positions.iter().map(|p| p.as_vec3()).collect(),
            faces.to_vec(),
        );
        if had_normals {
            out.normals = vertex_normals(&out.positions, &out.faces);
        }
        out
    };
    // A round with more faces without area (several vertices can snap onto one corner), more
    // folded edges (a placement that the hold-back let through) or more holes than the mesh
    // came with is never kept: the mesh must stay as clean as it came.
    let clean_as = |t: &TopologyReport, t_in: &TopologyReport| {
        t.degenerate_faces <= t_in.degenerate_faces
            && t.folded_edges <= t_in.folded_edges
            && t.holes <= t_in.holes
    };
    let topology_in = TopologyReport::of(mesh);
    let Some((round, judged)) = rounds.iter().enumerate().rev().find_map(|(r, (p, f, _))| {
        let candidate = as_mesh(p, f);
        (clean_as(&TopologyReport::of(&candidate), &topology_in) && acceptable(&candidate))
            .then_some((r + 1, candidate))
    }) else {
        report.accepted = false;
        report.faces_out = mesh.faces.len();
        report.model_edges_kept = 1.0;
        return report;
    };
    report.rounds_kept = round;
    // The kept round's flat regions, straight creases and straight rims without the vertices
    // they do not need (greedy collapses leave some, by cost order and their guards).
    let mut edit = EditMesh::from_mesh(&judged);
    report.redundant_removed =
        remove_redundant_vertices(&mut edit, REDUNDANT_SPACINGS * planes.spacing);
    let (positions, faces, survivors) = edit.compacted();
    let judged = as_mesh(&positions, &faces);
    let kept: Vec<u32> = (survivors.iter())
        .map(|&v| rounds[round - 1].2[v as usize])
        .collect();
    let faces = &judged.faces;
    let out_edges: std::collections::HashSet<[u32; 2]> = faces
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .map(|[a, b]| {
            let (a, b) = (kept[a as usize], kept[b as usize]);
            [a.min(b), a.max(b)]
        })
        .collect();
    report.model_edges_kept = if model_edges.is_empty() {
        1.0
    } else {
        model_edges
            .iter()
            .filter(|e| out_edges.contains(*e))
            .count() as f32
            / model_edges.len() as f32
    };
    *mesh = judged;
    report.faces_out = mesh.faces.len();
    report
}

/// How far, in input point spacings, the removal of the vertices a flat region does not need
/// may move the surface: a quarter of a spacing, below what the input can tell.
const REDUNDANT_SPACINGS: f64 = 0.25;

/// Median edge length of the live faces.
fn median_edge(m: &EditMesh) -> Option<f64> {
    let mut lengths: Vec<f64> = m
        .edges()
        .iter()
        .map(|&[a, b]| m.positions[a as usize].distance(m.positions[b as usize]))
        .collect();
    lengths.sort_by(f64::total_cmp);
    lengths.get(lengths.len() / 2).copied()
}

fn face_normal(m: &EditMesh, f: [u32; 3]) -> DVec3 {
    let [a, b, c] = m.corners(f);
    (b - a).cross(c - a)
}

/// Shortens the placement's moves from `before` where a face would flip or fold onto its
/// neighbour ([`crate::surface::fit`]'s guard, on the live faces).
fn hold_back(m: &mut EditMesh, before: &[DVec3]) {
    let faces: Vec<[u32; 3]> = m.faces.iter().flatten().copied().collect();
    let pairs = face_pairs(&faces);
    let mut positions: Vec<Vec3> = m.positions.iter().map(|p| p.as_vec3()).collect();
    let from: Vec<Vec3> = before.iter().map(|p| p.as_vec3()).collect();
    hold_back_folds(&mut positions, &from, &faces, &pairs);
    for (v, p) in positions.iter().enumerate() {
        // Unmoved vertices keep their exact f64 position.
        m.positions[v] = if *p == from[v] {
            before[v]
        } else {
            p.as_dvec3()
        };
    }
}

/// How far, in point spacings, an input point must be from the mesh to draw it out
/// ([`reach`]), and how far a vertex moves at most in one step of it.
const REACH_SPACINGS: f64 = 2.0;

/// One step of reach: each input point farther than `far` from its nearest face (the
/// distance of Hoppe et al.'s mesh optimisation) pulls that face's vertices towards it by its
/// barycentric weights; each vertex moves by the weighted mean pull, its component along the
/// vertex's normal removed, at most `step`, and a move that would flip or fold a face is
/// shortened ([`hold_back`]). Along the surface only: an edge of the mesh that stops short of
/// the input (a wedge's thin end, the end of an arm) slides out to it over the rounds, while
/// where the surface lies stays placement's business, so a point off the surface (noise, a
/// part the model left out) cannot raise a spike. Points the mesh is near pull nothing.
fn reach(m: &mut EditMesh, points: &[DVec3], far: f64, step: f64) {
    let coverage = Coverage::new(m, points);
    let mut pull = vec![(DVec3::ZERO, 0.0); m.positions.len()];
    for (f, near) in coverage.of_face.iter().enumerate() {
        let Some(face) = m.faces[f] else { continue };
        let t = m.corners(face);
        for &p in near.iter().filter(|&&p| coverage.now[p as usize] > far) {
            let y = points[p as usize];
            let w = closest_point_weights(y, t);
            let off = y - (t[0] * w[0] + t[1] * w[1] + t[2] * w[2]);
            for (&v, w) in face.iter().zip(w) {
                pull[v as usize].0 += off * w;
                pull[v as usize].1 += w;
            }
        }
    }
    let before = m.positions.clone();
    for (v, &(sum, weight)) in pull.iter().enumerate() {
        if weight <= 0.0 {
            continue;
        }
        let normal = (m.faces_of(v as u32).iter())
            .map(|&f| face_normal(m, m.faces[f as usize].expect("live")))
            .sum::<DVec3>()
            .normalize_or_zero();
        let mean = sum / weight;
        let along = mean - normal * normal.dot(mean);
        m.positions[v] += along * (step / along.length().max(step));
    }
    hold_back(m, &before);
}

/// The squared probe distances of the two faces `(a, b, c)` and `(b, a, d)` on the edge
/// `(a, b)`: its midpoint and the two centroids.
fn pair_cost(m: &EditMesh, planes: &PointPlanes, [a, b, c, d]: [u32; 4]) -> f64 {
    let p = |v: u32| m.positions[v as usize];
    [
        (p(a) + p(b)) * 0.5,
        (p(a) + p(b) + p(c)) / 3.0,
        (p(a) + p(b) + p(d)) / 3.0,
    ]
    .iter()
    .map(|&x| planes.distance(x).powi(2))
    .sum()
}

/// Flips every edge whose faces lie clearly farther from the input planes than the other
/// diagonal's would (at most four passes); returns the flips made.
fn align_flips(m: &mut EditMesh, planes: &PointPlanes) -> usize {
    let floor = (0.1 * planes.spacing).powi(2);
    flip_passes(m, |m, [a, b, c, d]| {
        // Two faces in one plane are the same surface either way.
        let p = |v: u32| m.positions[v as usize];
        let n1 = (p(b) - p(a)).cross(p(c) - p(a)).normalize_or_zero();
        let n2 = (p(a) - p(b)).cross(p(d) - p(b)).normalize_or_zero();
        if n1.dot(n2) > COPLANAR_COS {
            return false;
        }
        let now = pair_cost(m, planes, [a, b, c, d]);
        now > floor && pair_cost(m, planes, [c, d, b, a]) < 0.5 * now
    })
}

/// Up to four passes over the edges, flipping each flippable edge `(a, b)` (faces `(a, b, c)`
/// and `(b, a, d)`) for which `wants([a, b, c, d])` holds, until a pass flips none; returns
/// the flips made.
fn flip_passes(m: &mut EditMesh, wants: impl Fn(&EditMesh, [u32; 4]) -> bool + Sync) -> usize {
    // `flip_apexes` wants the face that walks a -> b first; try the other way. Its guard
    // (`flip_keeps_shape`) gives the same answer either way round.
    let quad = |m: &EditMesh, [a, b]: [u32; 2]| match (m.flip_apexes(a, b), m.flip_apexes(b, a)) {
        (Some((c, d)), _) => Some([a, b, c, d]),
        (None, Some((c, d))) => Some([b, a, c, d]),
        _ => None,
    };
    let mut flips = 0;
    for _ in 0..4 {
        let edges = m.edges();
        // Flips move no vertex, so whether a flip is wanted depends only on its four
        // vertices: asked for every edge up front (in parallel where there are threads), and
        // again only for an edge whose faces an earlier flip of this pass changed. The guard
        // looks at the faces around too, which earlier flips change: asked when the flip is
        // due, and only of the few edges that want one.
        let asked: Vec<Option<([u32; 4], bool)>> = {
            let m = &*m;
            map_in_parallel(edges.clone(), |_, e| quad(m, e).map(|q| (q, wants(m, q))))
        };
        let mut changed = 0;
        for (e, asked) in edges.into_iter().zip(asked) {
            let Some(q) = quad(m, e) else { continue };
            let wanted = match asked {
                Some((was, answer)) if was == q => answer,
                _ => wants(m, q),
            };
            let [a, b, c, d] = q;
            if wanted && m.flip_keeps_shape(a, b, c, d) {
                m.flip(a, b, c, d);
                changed += 1;
            }
        }
        flips += changed;
        if changed == 0 {
            break;
        }
    }
    flips
}

/// The weight of a face's own plane in its vertices' quadrics, per unit area (the input's
/// planes weigh 1 per unit area). Small: a model face that bevels a crease must not hold its
/// vertices off the crease (at 0.05 the collapses that recover a crease cost more than the
/// tolerance and the bevels stayed).
const FACE_PLANE_WEIGHT: f64 = 0.002;

/// Each vertex's quadric: the planes of the input points nearest it (each weighted by its
/// share of the surface, the mean area per point, times its confidence), plus its faces'
/// own planes at [`FACE_PLANE_WEIGHT`] of their area, so that a vertex no point is near (a
/// surface the input does not see) keeps its faces' shape; and, for a boundary edge, a plane
/// through it across its face, which holds the outline.
fn vertex_quadrics(m: &EditMesh, planes: &PointPlanes) -> Vec<Quadric> {
    let n = m.positions.len();
    let mut quadrics = vec![Quadric::default(); n];
    let mut area = 0.0;
    for f in m.faces.iter().flatten() {
        let normal = face_normal(m, *f);
        let twice_area = normal.length();
        if twice_area <= 0.0 {
            continue;
        }
        area += 0.5 * twice_area;
        let [a, b, c] = m.corners(*f);
        let q = Quadric::plane(
            normal / twice_area,
            a,
            FACE_PLANE_WEIGHT * 0.5 * twice_area / 3.0,
        );
        for v in f {
            quadrics[*v as usize] += q;
        }
        for (i, j, p) in [(f[0], f[1], a), (f[1], f[2], b), (f[2], f[0], c)] {
            if m.faces_on_edge(i, j) == 1 {
                let along = m.positions[j as usize] - p;
                let across = along.cross(normal).normalize_or_zero();
                if across != DVec3::ZERO {
                    let q = Quadric::plane(across, p, along.length_squared());
                    quadrics[i as usize] += q;
                    quadrics[j as usize] += q;
                }
            }
        }
    }
    let live = m.vertex_index();
    if live.is_empty() {
        return quadrics;
    }
    let share = area / planes.with_plane.max(1) as f64;
    // The nearest vertex of each plane in parallel, the sums in order (the same floats either
    // way).
    let planes: Vec<(DVec3, DVec3, f64)> = planes.weighted_planes().collect();
    let nearest = map_in_parallel(planes.iter().collect(), |_, (x, _, _)| {
        live.nearest(x.as_vec3()).map(|(v, _, _)| v as usize)
    });
    for ((x, normal, confidence), v) in planes.into_iter().zip(nearest) {
        if let Some(v) = v {
            quadrics[v] += Quadric::plane(normal, x, share * confidence);
        }
    }
    quadrics
}

/// Quadric edge collapses, cheapest first, to `target` faces and on below while a collapse's
/// RMS cost is under `tolerance`; `quadrics` are summed as vertices merge. No collapse takes
/// the surface away from the input `points` it covers (`Coverage`). Returns the collapses
/// made.
#[allow(clippy::too_many_arguments)]
fn decimate(
    m: &mut EditMesh,
    planes: &PointPlanes,
    points: &[DVec3],
    quadrics: &mut [Quadric],
    target: usize,
    tolerance: f64,
    max_turn_deg: f64,
) -> usize {
    let n = m.positions.len();
    let min_cos = max_turn_deg.to_radians().cos();
    let mut version = vec![0u32; n];
    let mut heap = BinaryHeap::new();
    let candidate = |m: &EditMesh, q: &[Quadric], a: u32, b: u32| {
        let sum = q[a as usize] + q[b as usize];
        let (pa, pb) = (m.positions[a as usize], m.positions[b as usize]);
        let mid = (pa + pb) * 0.5;
        let mut x = sum.damped_minimiser(mid, 1e-3);
        if x.distance(mid) > pa.distance(pb) {
            x = [pa, pb, mid]
                .into_iter()
                .min_by(|u, v| sum.error(*u).total_cmp(&sum.error(*v)))
                .expect("three");
        }
        let cost = sum.error(x) / sum.weight.max(1e-300);
        (cost, x)
    };
    let push =
        |heap: &mut BinaryHeap<_>, m: &EditMesh, q: &[Quadric], v: &[u32], a: u32, b: u32| {
            // The survivor is the lower index, so the model's own vertices (numbered first) stay.
            let (a, b) = (a.min(b), a.max(b));
            let (cost, _) = candidate(m, q, a, b);
            heap.push((Reverse(OrdF64(cost)), a, b, v[a as usize], v[b as usize]));
        };
    let tolerance2 = tolerance * tolerance;
    let reach = (COVER_TOLERANCES * tolerance).max(planes.spacing);
    let mut coverage = Coverage::new(m, points);
    let mut collapses = 0;
    // Rounds: collapse until the cheapest allowed collapse is over the tolerance (or none is
    // allowed), then even out the flat fans that greedy collapses leave (Delaunay flips
    // between coplanar faces) so that refused collapses may pass, and go again.
    for round in 0..6 {
        if round > 0 {
            coverage.reassign(m);
        }
        heap.clear();
        for [a, b] in m.edges() {
            push(&mut heap, m, quadrics, &version, a, b);
        }
        let mut faces = m.face_count();
        let before_round = collapses;
        while let Some((Reverse(OrdF64(cost)), a, b, va, vb)) = heap.pop() {
            if version[a as usize] != va || version[b as usize] != vb {
                continue;
            }
            if faces <= target && cost > tolerance2 {
                break;
            }
            // The optimal point, else either end (a half-edge collapse), whichever passes the
            // guards first: in a flat region the ends cost as little and fold less often.
            let (_, best) = candidate(m, quadrics, a, b);
            let sum = quadrics[a as usize] + quadrics[b as usize];
            let ends = [m.positions[a as usize], m.positions[b as usize]];
            let limit = if faces <= target {
                tolerance2
            } else {
                f64::INFINITY
            };
            let Some(plan) = m.plan_collapse(a, b) else {
                continue;
            };
            let Some(x) = [best, ends[0], ends[1]].into_iter().find(|&x| {
                sum.error(x) / sum.weight.max(1e-300) <= limit.max(cost)
                    && m.collapse_keeps_shape(&plan, x, min_cos)
                    && (faces > target || !strays(m, planes, a, b, x, 2.0 * tolerance))
                    && !coverage.uncovers(m, a, b, x, reach)
            }) else {
                continue;
            };
            let moved = coverage.take(m, a, b);
            m.collapse(a, b, x);
            coverage.give(m, a, moved);
            faces = m.face_count();
            collapses += 1;
            let merged = quadrics[b as usize];
            quadrics[a as usize] += merged;
            version[a as usize] += 1;
            version[b as usize] += 1;
            for w in m.neighbours(a) {
                push(&mut heap, m, quadrics, &version, a, w);
            }
        }
        if delaunay_flips(m) == 0 || collapses == before_round {
            break;
        }
    }
    collapses
}

/// How far, in multiples of the collapse tolerance (and at least a point spacing), a collapse
/// may take the surface away from an input point it covered ([`Coverage`]).
const COVER_TOLERANCES: f64 = 4.0;

/// The input points each face stands for (each point's nearest face among those of its three
/// nearest vertices) and how far each point was from the surface when decimation began: a
/// collapse that would leave one of its faces' points more than a reach farther from the new
/// faces around it than that is refused. The quadrics and [`strays`] ask whether the mesh
/// stays near the input; this asks whether the input stays near the mesh (the distance from
/// the points to the mesh of Hoppe et al.'s mesh optimisation, as a guard), so that a thin
/// part (a table's leg, a fin) is not collapsed into the surface beside it.
struct Coverage<'p> {
    points: &'p [DVec3],
    of_face: Vec<Vec<u32>>,
    /// Each point's distance from its face at the start, and now.
    start: Vec<f64>,
    now: Vec<f64>,
}

impl<'p> Coverage<'p> {
    fn new(m: &EditMesh, points: &'p [DVec3]) -> Self {
        let mut c = Coverage {
            points,
            of_face: Vec::new(),
            start: Vec::new(),
            now: Vec::new(),
        };
        c.reassign(m);
        c.start = c.now.clone();
        c
    }

    /// Each point to its nearest face again (after flips).
    fn reassign(&mut self, m: &EditMesh) {
        self.of_face = vec![Vec::new(); m.faces.len()];
        let live = m.vertex_index();
        self.now = vec![f64::INFINITY; self.points.len()];
        if live.is_empty() {
            return;
        }
        let bounded: Vec<Option<([DVec3; 3], Bound)>> = m
            .faces
            .iter()
            .map(|f| {
                f.map(|f| {
                    let t = m.corners(f);
                    (t, Bound::around(t))
                })
            })
            .collect();
        let nearest = map_in_parallel(self.points.iter().collect(), |_, &x| {
            // The faces of the 3 nearest vertices, each once (a repeat never wins: the
            // first of equals does), borrowed from `bounded`.
            let mut faces: Vec<(u32, &([DVec3; 3], Bound))> = Vec::with_capacity(24);
            for (v, _) in live.k_nearest(x.as_vec3(), 3) {
                for &f in m.faces_of(v) {
                    if !faces.iter().any(|&(g, _)| g == f) {
                        faces.push((f, bounded[f as usize].as_ref().expect("live")));
                    }
                }
            }
            nearest_triangle(x, &faces, None)
        });
        for (i, n) in nearest.into_iter().enumerate() {
            if let Some((d, f)) = n {
                self.of_face[f as usize].push(i as u32);
                self.now[i] = d;
            }
        }
    }

    /// Whether collapsing `(a, b)` to `x` leaves a point of their faces more than `reach`
    /// farther from the faces around `x` than it was at the start.
    fn uncovers(&self, m: &EditMesh, a: u32, b: u32, x: DVec3, reach: f64) -> bool {
        let around = || m.faces_of(a).iter().chain(m.faces_of(b));
        let at = |v: u32| {
            if v == a || v == b {
                x
            } else {
                m.positions[v as usize]
            }
        };
        let removed = |f: &[u32; 3]| f.contains(&a) && f.contains(&b);
        let fan: Vec<([DVec3; 3], Bound)> = around()
            .map(|&f| m.faces[f as usize].expect("live"))
            .filter(|f| !removed(f))
            .map(|f| {
                let t = f.map(at);
                (t, Bound::around(t))
            })
            .collect();
        // A face's point moves with it, to the same weights on the moved face, by at most the
        // farther end's move: a point that cannot pass its limit that way needs no measuring.
        // The moved face is one of the new faces, or for a removed face the segment from `x`
        // to its third vertex, an edge of the new faces when a surviving face has that vertex
        // (else its points are always measured).
        let moves = x
            .distance(m.positions[a as usize])
            .max(x.distance(m.positions[b as usize]));
        let in_fan = |c: u32| {
            around()
                .map(|&f| m.faces[f as usize].expect("live"))
                .any(|f| !removed(&f) && f.contains(&c))
        };
        around().any(|&f| {
            let face = m.faces[f as usize].expect("live");
            let bounded = !removed(&face)
                || face
                    .iter()
                    .find(|&&v| v != a && v != b)
                    .is_some_and(|&c| in_fan(c));
            let (old, new) = (m.corners(face), face.map(at));
            self.of_face[f as usize].iter().any(|&p| {
                let limit = reach + self.start[p as usize];
                if bounded && self.now[p as usize] + moves <= limit {
                    return false;
                }
                let y = self.points[p as usize];
                if bounded {
                    let [u, v, w] = closest_point_weights(y, old);
                    if y.distance(new[0] * u + new[1] * v + new[2] * w) <= limit {
                        return false;
                    }
                }
                // No face of the fan within the limit (a face whose bound is beyond it is not).
                !fan.iter().any(|&(t, bound)| {
                    bound.distance_at_least(y) <= limit && point_triangle_distance(y, t) <= limit
                })
            })
        })
    }

    /// The points of the faces around `(a, b)`, before they collapse, each with its face.
    fn take(&mut self, m: &EditMesh, a: u32, b: u32) -> Vec<(u32, u32)> {
        let mut moved = Vec::new();
        for &f in m.faces_of(a).iter().chain(m.faces_of(b)) {
            moved.extend(self.of_face[f as usize].drain(..).map(|p| (p, f)));
        }
        moved
    }

    /// `moved` points, each to its nearest face around the surviving vertex `a` (its own face,
    /// where it survived, measured first: most points stay on it).
    fn give(&mut self, m: &EditMesh, a: u32, moved: Vec<(u32, u32)>) {
        let fan: Vec<(u32, ([DVec3; 3], Bound))> = m
            .faces_of(a)
            .iter()
            .map(|&f| {
                let t = m.corners(m.faces[f as usize].expect("live"));
                (f, (t, Bound::around(t)))
            })
            .collect();
        for (p, was) in moved {
            let y = self.points[p as usize];
            let guess = fan.iter().position(|&(f, _)| f == was);
            if let Some((d, f)) = nearest_triangle(y, &fan, guess) {
                self.of_face[f as usize].push(p);
                self.now[p as usize] = d;
            }
        }
    }
}

/// Whether collapsing `(a, b)` to `x` would leave a face around them whose centroid or edge
/// midpoints are farther than `limit` from the input planes, and farther than the faces there
/// now: the vertex quadrics measure where the vertices go, this where the faces between them
/// go (a collapse may not cut a corner off, but may straighten a bevel).
fn strays(m: &EditMesh, planes: &PointPlanes, a: u32, b: u32, x: DVec3, limit: f64) -> bool {
    let worst = |at: &dyn Fn(u32) -> DVec3, skip_edge: bool| {
        m.faces_of(a)
            .iter()
            .chain(m.faces_of(b))
            .filter_map(|&id| {
                let f = m.faces[id as usize].expect("live");
                if skip_edge && f.contains(&a) && f.contains(&b) {
                    return None;
                }
                let [p, q, r] = f.map(at);
                Some(
                    [
                        (p + q + r) / 3.0,
                        (p + q) * 0.5,
                        (q + r) * 0.5,
                        (r + p) * 0.5,
                    ]
                    .iter()
                    .map(|&probe| planes.distance(probe))
                    .fold(0.0, f64::max),
                )
            })
            .fold(0.0, f64::max)
    };
    let after = worst(
        &|v| {
            if v == a || v == b {
                x
            } else {
                m.positions[v as usize]
            }
        },
        true,
    );
    after > limit && after > worst(&|v| m.positions[v as usize], false)
}

/// Two faces with normals within 5 degrees count as one plane (cos 5 degrees, written out:
/// no trigonometry, so the browser's build decides as the native one does).
const COPLANAR_COS: f64 = 0.996_194_698_091_745_5;

/// Flips each edge between two nearly coplanar faces (normals within 5 degrees) whose
/// opposite angles sum to more than 180 degrees (the Delaunay test within their plane): the
/// slivers of a flat region become well-shaped faces without moving the surface. Returns the
/// flips made (at most four passes).
fn delaunay_flips(m: &mut EditMesh) -> usize {
    flip_passes(m, |m, [a, b, c, d]| {
        let p = |v: u32| m.positions[v as usize];
        let n1 = (p(b) - p(a)).cross(p(c) - p(a)).normalize_or_zero();
        let n2 = (p(a) - p(b)).cross(p(d) - p(b)).normalize_or_zero();
        if n1.dot(n2) < COPLANAR_COS {
            return false;
        }
        // The opposite angles sum past 180 degrees exactly when their cotangents sum below
        // zero (no trigonometry, so the browser's build decides as the native one does).
        let cot = |at: DVec3, u: DVec3, w: DVec3| {
            let (x, y) = (u - at, w - at);
            x.dot(y) / x.cross(y).length().max(1e-300)
        };
        cot(p(c), p(a), p(b)) + cot(p(d), p(a), p(b)) < -1e-9
    })
}

/// An `f64` ordered by `total_cmp`, for the collapse queue.
#[derive(Clone, Copy, Debug, PartialEq)]
struct OrdF64(f64);

impl Eq for OrdF64 {}

impl PartialOrd for OrdF64 {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}

impl Ord for OrdF64 {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::features::{SHARP_ANGLE_DEG, sharp_edges};
    use crate::geometry::hard_surface::cuboid;
    use crate::geometry::primitives::{grid, icosphere};
    use crate::geometry::sample::sample_surface;
    use crate::rng::Rng;

    /// The tests' box (its half-extents and mesh), 4,096 points sampled on it and their planes.
    fn box_and_planes() -> (Vec3, Mesh, Vec<Vec3>, PointPlanes) {
        let half = Vec3::new(0.9, 0.45, 0.63);
        let truth = cuboid(-half, half);
        let points = sample_surface(&truth, 4096, 1).unwrap().points;
        let planes = PointPlanes::new(&points, SharpenOptions::default().plane_neighbours);
        (half, truth, points, planes)
    }

    /// A blob standing in for the model's mesh of a box: an icosphere drawn most of the way
    /// onto the box (rounded corners and creases), its vertices jittered.
    fn blob_of_box(half: Vec3, seed: u64) -> Mesh {
        let mut m = icosphere(2);
        let mut rng = Rng::new(seed);
        for p in &mut m.positions {
            let j = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
            let on_cube = *p / p.abs().max_element();
            *p = p.lerp(on_cube, 0.6) * half + j * 0.03;
        }
        m
    }

    #[test]
    fn a_box_agrees_with_its_own_planes_and_a_blob_of_it_less() {
        let (half, truth, points, planes) = box_and_planes();
        let agreement = |m: &Mesh| {
            let s = sample_surface(m, 2048, 0).unwrap();
            planes.normal_agreement(&s.points, &s.normals).unwrap()
        };
        let (box_, blob) = (agreement(&truth), agreement(&blob_of_box(half, 2)));
        // 0.97 as the box's normal consistency against itself: samples within a spacing of
        // a crease may take the other face's plane.
        assert!(box_ > 0.95, "{box_}");
        assert!(blob < box_ - 0.03, "box {box_}, blob {blob}");
        // Winding does not matter (absolute cosine); no planes, no answer.
        let s = sample_surface(&truth, 2048, 0).unwrap();
        let flipped: Vec<Vec3> = s.normals.iter().map(|n| -*n).collect();
        assert_eq!(planes.normal_agreement(&s.points, &flipped), Some(box_));
        let none = PointPlanes::new(&[], 12);
        assert_eq!(
            none.normal_agreement(&points, &vec![Vec3::Z; points.len()]),
            None
        );
    }

    #[test]
    fn a_blob_of_a_box_comes_back_flat_and_creased_with_few_faces() {
        let (half, truth, _, planes) = box_and_planes();
        let mut mesh = blob_of_box(half, 2);
        let before = mesh.faces.len();
        let report = sharpen(&mut mesh, &planes, &SharpenOptions::default());
        let t = TopologyReport::of(&mesh);
        assert_eq!(
            (
                t.non_manifold_edges,
                t.inconsistent_winding_edges,
                t.boundary_edges
            ),
            (0, 0, 0),
            "{t:?}"
        );
        assert_eq!(t.degenerate_faces, 0);
        assert!(report.faces_out < before / 4, "{report:?}");
        let cmp = crate::eval::metrics::compare_meshes(&mesh, &truth, &Default::default()).unwrap();
        // 0.97 is the box's own floor: samples within a spacing of a crease find their nearest
        // neighbour on the other face (the ground truth against itself scores about 0.97).
        assert!(cmp.normal_consistency.unwrap() > 0.96, "{cmp:?}");
        assert!(
            cmp.sharp.edge_f_score.f_score > 0.8,
            "{:?} {report:?}",
            cmp.sharp
        );
        assert!(!sharp_edges(&mesh.positions, &mesh.faces, SHARP_ANGLE_DEG).is_empty());
    }

    #[test]
    fn the_rounds_after_the_first_split_at_most_later_refine_times() {
        let (half, _, _, planes) = box_and_planes();
        let blob = blob_of_box(half, 2);
        // Each round ends with the box's few large faces, far longer than three spacings, so
        // every round splits as often as it may: twice in the first, `later_refine` after.
        for later_refine in [0, 1, 2] {
            let opts = SharpenOptions {
                passes: 4,
                later_refine,
                ..SharpenOptions::default()
            };
            let report = sharpen(&mut blob.clone(), &planes, &opts);
            assert_eq!(report.refinements, 2 + 3 * later_refine, "{report:?}");
        }
    }

    #[test]
    fn the_judge_picks_the_last_round_it_accepts_or_none() {
        let (half, _, _, planes) = box_and_planes();
        let blob = blob_of_box(half, 2);
        let opts = SharpenOptions::default();
        // Asked of the last round first: refusing three questions keeps round passes - 3.
        let (mut mesh, mut asked) = (blob.clone(), 0);
        let report = sharpen_judged(&mut mesh, &planes, &opts, |_| {
            asked += 1;
            asked > 3
        });
        assert_eq!(
            (report.accepted, report.rounds_kept, asked),
            (true, opts.passes - 3, 4)
        );
        assert_eq!(report.faces_out, mesh.faces.len());
        assert_ne!(mesh, blob);
        // Refusing every round leaves the mesh as it came.
        let mut mesh = blob.clone();
        let report = sharpen_judged(&mut mesh, &planes, &opts, |_| false);
        assert_eq!((report.accepted, report.rounds_kept), (false, 0));
        assert_eq!(mesh, blob);
        assert!(
            report.to_string().contains("kept the fitted one"),
            "{report}"
        );
        // Accepting all is `sharpen`.
        let (mut a, mut b) = (blob.clone(), blob.clone());
        let judged = sharpen_judged(&mut a, &planes, &opts, |_| true);
        assert_eq!(judged, sharpen(&mut b, &planes, &opts));
        assert_eq!(a, b);
    }

    #[test]
    fn a_collapse_that_would_flatten_a_spike_the_points_cover_is_refused() {
        // A 6 x 6 grid on z = 0 with the vertex (3, 3) raised to a spike, its own surface the
        // input: collapsing the spike's tip onto its base leaves the spike's points far from
        // the surface; collapsing two flat vertices leaves every point where it was.
        let mut flat = grid(6, 6);
        let tip = 3 * 7 + 3;
        flat.positions[tip].z = 0.8;
        let points: Vec<DVec3> = sample_surface(&flat, 4096, 1)
            .unwrap()
            .points
            .iter()
            .map(|p| p.as_dvec3())
            .collect();
        let m = EditMesh::from_mesh(&flat);
        let coverage = Coverage::new(&m, &points);
        let base = tip as u32 - 1;
        assert!(m.neighbours(tip as u32).contains(&base));
        let reach = 0.02;
        assert!(coverage.uncovers(&m, base, tip as u32, m.positions[base as usize], reach));
        // (0, 1) and (1, 1), far from the spike: the surface does not move.
        let (a, b) = (7, 8);
        assert!(m.neighbours(a).contains(&b));
        assert!(!coverage.uncovers(&m, a, b, m.positions[a as usize], reach));
        // Every point is on the surface it was assigned to.
        let worst = coverage.start.iter().copied().fold(0.0, f64::max);
        assert!(worst < 1e-5, "{worst}");
    }

    #[test]
    fn the_planar_regions_of_a_box_meet_on_its_edges_and_corners() {
        let (half, _, _, planes) = box_and_planes();
        let (h, s) = (half.as_dvec3(), planes.spacing);
        let cutoff = SharpenOptions::default().rank_cutoff;
        // Within a spacing of an edge: onto the edge line, the nearest point of it.
        let (x, rank) = planes
            .region_meet(DVec3::new(0.1, h.y - 0.6 * s, h.z - 0.3 * s), cutoff)
            .unwrap();
        assert_eq!(rank, 2);
        assert!(x.distance(DVec3::new(0.1, h.y, h.z)) < 1e-4, "{x}");
        // Within a spacing of a corner: onto the corner where the three faces' regions are
        // among the nearest points, else onto one of its edges (a region stops a spacing or
        // two short of a crease, where the points' own planes tilt across it).
        let mut corners = 0;
        for sign in (0..8).map(|c| {
            DVec3::new(
                if c & 1 == 0 { -1.0 } else { 1.0 },
                if c & 2 == 0 { -1.0 } else { 1.0 },
                if c & 4 == 0 { -1.0 } else { 1.0 },
            )
        }) {
            let corner = sign * h;
            let (x, rank) = planes.region_meet(corner - sign * 0.5 * s, cutoff).unwrap();
            if rank == 3 {
                assert!(x.distance(corner) < 1e-4, "{x} {corner}");
                corners += 1;
            } else {
                // On an edge through the corner: two of its coordinates are the corner's.
                let on = (x - corner)
                    .abs()
                    .to_array()
                    .iter()
                    .filter(|d| **d < 1e-4)
                    .count();
                assert!(rank == 2 && on >= 2, "{x} {corner} {rank}");
            }
        }
        assert!(corners >= 6, "{corners} of 8 corners");
        // On a face, or two spacings from its edge: no crease there.
        assert_eq!(planes.region_meet(DVec3::new(0.1, 0.0, h.z), cutoff), None);
        assert_eq!(
            planes.region_meet(DVec3::new(0.1, h.y - 2.0 * s, h.z), cutoff),
            None
        );
        // A sphere has no planar regions to meet.
        let sphere = sample_surface(&icosphere(4), 4096, 1).unwrap().points;
        let round = PointPlanes::new(&sphere, SharpenOptions::default().plane_neighbours);
        assert!(
            sphere
                .iter()
                .step_by(97)
                .all(|p| round.region_meet(p.as_dvec3(), cutoff).is_none())
        );
    }

    #[test]
    fn a_finely_split_box_decimates_back_to_a_box() {
        let (_, truth, _, planes) = box_and_planes();
        let mut e = EditMesh::from_mesh(&truth);
        e.subdivide();
        e.subdivide();
        e.subdivide();
        let mut mesh = e.to_mesh();
        let report = sharpen(&mut mesh, &planes, &SharpenOptions::default());
        let cmp = crate::eval::metrics::compare_meshes(&mesh, &truth, &Default::default()).unwrap();
        assert!(report.faces_out <= 24, "{report:?}");
        assert!(cmp.sharp.edge_f_score.f_score > 0.9, "{:?}", cmp.sharp);
    }

    #[test]
    fn a_flat_sheet_stays_flat_and_open_and_loses_its_needless_faces() {
        let mut g = grid(8, 8);
        let points: Vec<Vec3> = (0..4096)
            .map(|i| Vec3::new((i % 64) as f32 / 63.0, (i / 64) as f32 / 63.0, 0.0))
            .collect();
        let planes = PointPlanes::new(&points, 12);
        let mut rng = Rng::new(5);
        for p in &mut g.positions {
            p.z = (rng.next_f32() - 0.5) * 0.02;
        }
        let holes = TopologyReport::of(&g).holes;
        let report = sharpen(&mut g, &planes, &SharpenOptions::default());
        let t = TopologyReport::of(&g);
        assert_eq!(
            (t.holes, t.non_manifold_edges, t.inconsistent_winding_edges),
            (holes, 0, 0)
        );
        assert!(g.positions.iter().all(|p| p.z.abs() < 1e-4), "not flat");
        assert!(report.faces_out < 40, "{report:?}");
        // The square's outline is kept.
        let b = g.aabb().unwrap();
        assert!(
            (b.min.truncate() - glam::Vec2::ZERO).length() < 1e-3,
            "{b:?}"
        );
        assert!(
            (b.max.truncate() - glam::Vec2::ONE).length() < 1e-3,
            "{b:?}"
        );
    }

    #[test]
    fn off_and_degenerate_inputs_leave_the_mesh_alone() {
        let mesh = icosphere(1);
        for planes in [
            PointPlanes::new(&[], 12),
            PointPlanes::new(&[Vec3::ONE; 100], 12),
            PointPlanes::new(
                &(0..100).map(|i| Vec3::X * i as f32).collect::<Vec<_>>(),
                12,
            ),
            PointPlanes::new(&[Vec3::NAN; 50], 12),
        ] {
            let mut m = mesh.clone();
            sharpen(&mut m, &planes, &SharpenOptions::default());
            let t = TopologyReport::of(&m);
            assert_eq!((t.non_manifold_edges, t.boundary_edges), (0, 0));
        }
        let points = sample_surface(&mesh, 1000, 0).unwrap().points;
        let mut m = mesh.clone();
        let off = SharpenOptions {
            enabled: false,
            ..Default::default()
        };
        sharpen(&mut m, &PointPlanes::new(&points, 12), &off);
        assert_eq!(m, mesh);
    }
}
