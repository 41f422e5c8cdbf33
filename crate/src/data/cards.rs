//! Billboard cards: meshes whose surface is mostly free-standing flat sheets of a few
//! triangles each (crossed tree and grass quads, crowd and cloud sprites, painted decals,
//! flag and shield planes, effect sprites), which stand in for geometry through a texture.
//! The bounding-box "flat" test misses them as soon as two cards cross.
//!
//! [`card_area_share`] measures how much of a mesh's area such cards hold:
//!
//! 1. **Flat regions.** Faces are grown into regions across shared edges, largest face first,
//!    while a neighbour's normal is within [`PLANE_ANGLE_DEG`] of the seed face's and its
//!    corners are within [`PLANE_DISTANCE`] of the seed's plane (measured against the seed,
//!    not the neighbour, so a finely tessellated curve does not chain into one "plane").
//! 2. **Open regions.** A region's perimeter is its edges not shared with another face of the
//!    same region. The part used by one face only is *boundary*; the rest is *crease* (the
//!    surface goes on at an angle). A card candidate has at most `max_faces` faces (a card is
//!    a quad or a small polygon) and at least [`MIN_FREE_FRACTION`] of its perimeter on the
//!    boundary.
//! 3. **Free regions.** A boundary edge can still be *attached*: the walls of a low-poly hut
//!    or a ruin modelled as separate single-sided quads meet at their edges without sharing
//!    vertices. Three points of each boundary edge (at 1/6, 1/2 and 5/6 of its length) are
//!    tested; one within [`ATTACH_DISTANCE`] of a face of another region that is *not
//!    parallel* to this one is attached. Parallel faces are skipped, so the back copy of a
//!    double-sided card (a second sheet with the other winding or diagonal that cleaning
//!    cannot merge) does not attach the front one. A candidate whose free boundary (the
//!    unattached sample points, by length) is at least [`MIN_FREE_FRACTION`] of its
//!    perimeter is a **card**.
//!
//! The share is the cards' area over the total area. Closed solids have no boundary, low-poly
//! buildings' wall sheets are attached to each other, and finely tessellated flat sheets
//! (cloth, tent flaps, subdivided flags) have more than `max_faces` faces, so all of these
//! score low; `dataset::filter` rejects a mesh whose share is at least
//! `FilterOptions::card_max_share`. Distances are relative to the bounding box's longest
//! side, so the result does not depend on the mesh's scale or position.

use glam::DVec3;
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{AABB, RTree};

use crate::Mesh;
use crate::geometry::topology::EdgeIncidence;
use crate::geometry::triangle::point_triangle_distance;

/// Largest angle between the normals of two faces of one flat region, in degrees.
pub const PLANE_ANGLE_DEG: f64 = 1.0;
/// Largest distance of a region's corners from its seed face's plane, relative to the bounding
/// box's longest side.
pub const PLANE_DISTANCE: f64 = 5e-4;
/// A boundary point closer than this to a non-parallel face of another region is attached;
/// relative to the bounding box's longest side (0.005 in the model frame's [-1, 1]).
pub const ATTACH_DISTANCE: f64 = 2.5e-3;
/// The fraction of a region's perimeter that must be boundary, and then free boundary, for the
/// region to be a card.
pub const MIN_FREE_FRACTION: f64 = 0.5;

/// Sample positions along a boundary edge for the attachment test.
const EDGE_SAMPLES: [f64; 3] = [1.0 / 6.0, 0.5, 5.0 / 6.0];

/// One flat region (step 1 of the module doc).
#[derive(Clone, Debug, Default)]
struct Region {
    normal: DVec3,
    faces: usize,
    area: f64,
    /// Length of the edges not shared with another face of the region.
    perimeter: f64,
    /// Length of the edges used by one face only.
    boundary: f64,
    /// Boundary length not attached to another region (step 3).
    free: f64,
}

/// The fraction (0..=1) of `mesh`'s area that lies in cards with at most `max_faces` faces
/// each (see the module doc). Degenerate faces count for nothing; a mesh without area gives 0.
pub fn card_area_share(mesh: &Mesh, max_faces: usize) -> f32 {
    let p: Vec<DVec3> = mesh.positions.iter().map(|v| v.as_dvec3()).collect();
    let Some(aabb) = mesh.aabb() else {
        return 0.0;
    };
    let longest = aabb.max_extent() as f64;
    if longest.is_nan() || longest <= 0.0 {
        return 0.0;
    }
    let corners = |f: usize| mesh.faces[f].map(|i| p[i as usize]);
    let (normals, areas): (Vec<DVec3>, Vec<f64>) = (0..mesh.faces.len())
        .map(|f| {
            let [a, b, c] = corners(f);
            let n = (b - a).cross(c - a);
            let len = n.length();
            if len > 0.0 && len.is_finite() {
                (n / len, 0.5 * len)
            } else {
                (DVec3::ZERO, 0.0)
            }
        })
        .unzip();
    let total: f64 = areas.iter().sum();
    if total.is_nan() || total <= 0.0 {
        return 0.0;
    }

    let inc = EdgeIncidence::new(&mesh.faces);
    let mut face_edges: Vec<Vec<u32>> = vec![Vec::new(); mesh.faces.len()];
    for e in 0..inc.edges.len() {
        for u in inc.uses_of(e) {
            face_edges[u.face as usize].push(e as u32);
        }
    }

    // 1. Flat regions, largest face first (ties by index, so the result is deterministic).
    const NONE: u32 = u32::MAX;
    let cos_tol = PLANE_ANGLE_DEG.to_radians().cos();
    let plane_tol = PLANE_DISTANCE * longest;
    let mut region_of = vec![NONE; mesh.faces.len()];
    let mut regions: Vec<Region> = Vec::new();
    let mut order: Vec<usize> = (0..mesh.faces.len()).filter(|&f| areas[f] > 0.0).collect();
    order.sort_by(|&a, &b| areas[b].total_cmp(&areas[a]).then(a.cmp(&b)));
    let mut stack = Vec::new();
    for seed in order {
        if region_of[seed] != NONE {
            continue;
        }
        let r = regions.len() as u32;
        let normal = normals[seed];
        let offset = normal.dot(corners(seed)[0]);
        let mut region = Region {
            normal,
            ..Default::default()
        };
        region_of[seed] = r;
        stack.push(seed);
        while let Some(f) = stack.pop() {
            region.faces += 1;
            region.area += areas[f];
            for &e in &face_edges[f] {
                for u in inc.uses_of(e as usize) {
                    let g = u.face as usize;
                    if region_of[g] != NONE
                        || areas[g] <= 0.0
                        || normals[g].dot(normal) < cos_tol
                        || corners(g)
                            .iter()
                            .any(|c| (normal.dot(*c) - offset).abs() > plane_tol)
                    {
                        continue;
                    }
                    region_of[g] = r;
                    stack.push(g);
                }
            }
        }
        regions.push(region);
    }

    // 2. Perimeter and boundary of each region; boundary edges of candidates kept for step 3.
    let mut boundary_edges: Vec<(u32, usize)> = Vec::new();
    for (e, &[a, b]) in inc.edges.iter().enumerate() {
        let uses = inc.uses_of(e);
        let length = (p[b as usize] - p[a as usize]).length();
        for (k, u) in uses.iter().enumerate() {
            let r = region_of[u.face as usize];
            if r == NONE {
                continue;
            }
            let shared = uses
                .iter()
                .enumerate()
                .any(|(j, v)| j != k && region_of[v.face as usize] == r);
            if shared {
                continue;
            }
            let region = &mut regions[r as usize];
            region.perimeter += length;
            if uses.len() == 1 {
                region.boundary += length;
                boundary_edges.push((r, e));
            }
        }
    }
    let candidate = |r: &Region| {
        r.faces <= max_faces && r.perimeter > 0.0 && r.boundary >= MIN_FREE_FRACTION * r.perimeter
    };
    if !regions.iter().any(candidate) {
        return 0.0;
    }

    // 3. Free boundary: sample points not near a non-parallel face of another region.
    let attach = ATTACH_DISTANCE * longest;
    let tree: RTree<GeomWithData<Rectangle<[f64; 3]>, u32>> = RTree::bulk_load(
        (0..mesh.faces.len())
            .filter(|&f| region_of[f] != NONE)
            .map(|f| {
                let [a, b, c] = corners(f);
                let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
                GeomWithData::new(
                    Rectangle::from_corners(lo.to_array(), hi.to_array()),
                    f as u32,
                )
            })
            .collect(),
    );
    for (r, e) in boundary_edges {
        let region = &regions[r as usize];
        if !candidate(region) {
            continue;
        }
        let [a, b] = inc.edges[e].map(|v| p[v as usize]);
        let length = (b - a).length();
        let mut free = 0.0;
        for t in EDGE_SAMPLES {
            let x = a + (b - a) * t;
            let query = AABB::from_corners((x - attach).to_array(), (x + attach).to_array());
            let attached = tree.locate_in_envelope_intersecting(query).any(|g| {
                let f = g.data as usize;
                region_of[f] != r
                    && normals[f].dot(region.normal).abs() < cos_tol
                    && point_triangle_distance(x, corners(f)) <= attach
            });
            if !attached {
                free += length / EDGE_SAMPLES.len() as f64;
            }
        }
        regions[r as usize].free += free;
    }
    let cards: f64 = regions
        .iter()
        .filter(|r| candidate(r) && r.free >= MIN_FREE_FRACTION * r.perimeter)
        .map(|r| r.area)
        .sum();
    (cards / total).min(1.0) as f32
}

/// A unit quad (two triangles) centred at `center`, spanned by `u` and `v` (half sizes
/// included), appended to `mesh`. Used by the tests here and in `dataset`.
#[cfg(test)]
pub(crate) fn push_quad(mesh: &mut Mesh, center: glam::Vec3, u: glam::Vec3, v: glam::Vec3) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend([
        center - u - v,
        center + u - v,
        center + u + v,
        center - u + v,
    ]);
    mesh.faces
        .extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{cube, grid, icosphere};
    use glam::Vec3;

    /// `n` vertical cards crossing at the vertical axis (a billboard tree), each a quad,
    /// optionally double-sided with the back copy triangulated along the other diagonal.
    fn crossed_cards(n: usize, double_sided: bool) -> Mesh {
        let mut m = Mesh::default();
        for k in 0..n {
            let angle = std::f32::consts::PI * k as f32 / n as f32;
            let u = Vec3::new(angle.cos(), 0.0, angle.sin());
            push_quad(&mut m, Vec3::new(0.0, 1.0, 0.0), u, Vec3::Y);
            if double_sided {
                let base = m.positions.len() as u32;
                let c = Vec3::new(0.0, 1.0, 0.0);
                m.positions.extend([
                    c - u - Vec3::Y,
                    c + u - Vec3::Y,
                    c + u + Vec3::Y,
                    c - u + Vec3::Y,
                ]);
                // Reversed winding, split along the other diagonal.
                m.faces
                    .extend([[base, base + 3, base + 1], [base + 1, base + 3, base + 2]]);
            }
        }
        m
    }

    /// A hut built from single-sided sheets that are not welded together, as low-poly game
    /// buildings often are: four walls meeting at the corners and a flat roof overhanging them.
    fn sheet_hut() -> Mesh {
        let mut m = Mesh::default();
        for z in [-1.0f32, 1.0] {
            push_quad(&mut m, Vec3::new(0.0, 1.0, z), Vec3::X, Vec3::Y);
        }
        for x in [-1.0f32, 1.0] {
            push_quad(&mut m, Vec3::new(x, 1.0, 0.0), Vec3::Z, Vec3::Y);
        }
        push_quad(
            &mut m,
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::X * 1.2,
            Vec3::Z * 1.2,
        );
        m
    }

    #[test]
    fn crossed_cards_are_cards() {
        for double in [false, true] {
            for n in [2, 3, 10] {
                let m = crossed_cards(n, double);
                let share = card_area_share(&m, 8);
                assert!(share > 0.99, "{n} cards (double-sided {double}): {share}");
            }
        }
    }

    #[test]
    fn solids_and_sheet_buildings_are_not_cards() {
        assert_eq!(card_area_share(&cube(), 8), 0.0);
        assert_eq!(card_area_share(&icosphere(2), 8), 0.0);
        // An open box (no lid): its walls are creased to each other, only the rim is free.
        let mut open = cube();
        let top: Vec<usize> = (0..open.faces.len())
            .filter(|&f| open.triangle(f).iter().all(|p| p.z > 0.0))
            .collect();
        assert_eq!(top.len(), 2);
        for f in top.into_iter().rev() {
            open.faces.remove(f);
        }
        assert_eq!(card_area_share(&open, 8), 0.0);
        // The walls are attached to each other at the corners and to the roof at the top; only
        // the overhanging roof is a free sheet.
        let hut = sheet_hut();
        let share = card_area_share(&hut, 8);
        let roof = 2.4 * 2.4 / (4.0 * 4.0 + 2.4 * 2.4);
        assert!(
            (share - roof).abs() < 1e-4,
            "hut: {share}, the roof is {roof}"
        );
    }

    #[test]
    fn finely_tessellated_sheets_are_not_cards() {
        // Two crossed 4x4 grids (32 faces each): flat sheets, but not cards of few faces.
        let mut m = grid(4, 4);
        m.positions
            .iter_mut()
            .for_each(|p| *p -= Vec3::new(0.5, 0.5, 0.0));
        let n = m.positions.len() as u32;
        let rotated: Vec<Vec3> = m
            .positions
            .iter()
            .map(|p| Vec3::new(p.z, p.y, p.x))
            .collect();
        m.positions.extend(rotated);
        let extra: Vec<[u32; 3]> = m.faces.iter().map(|f| f.map(|i| i + n)).collect();
        m.faces.extend(extra);
        assert_eq!(card_area_share(&m, 8), 0.0);
        assert!(card_area_share(&m, 64) > 0.99);
    }

    #[test]
    fn scale_and_position_do_not_matter() {
        let m = crossed_cards(3, true);
        let a = card_area_share(&m, 8);
        let moved = Mesh::new(
            m.positions
                .iter()
                .map(|p| *p * 250.0 + Vec3::new(1e3, -40.0, 7.0))
                .collect(),
            m.faces.clone(),
        );
        assert_eq!(a, card_area_share(&moved, 8));
        assert_eq!(card_area_share(&Mesh::default(), 8), 0.0);
    }
}
