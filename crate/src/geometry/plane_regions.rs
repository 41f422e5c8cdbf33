//! Planar regions of a point cloud by region growing: the flat parts of a scan, each with one
//! plane fitted to all of its points.
//!
//! A plane fitted to a point's dozen nearest neighbours tilts with the noise (a few degrees at
//! 1% noise), and a flat face's quadric, summed from hundreds of such planes, then charges a
//! large face for the tilt and not for any real bend. One plane fitted to the whole region
//! does not tilt: its error falls with the square root of the region's points.
//!
//! Written here: point-cloud plane segmentation lives in C++ libraries (PCL, Open3D), and
//! growing over the crate's own k-d tree ([`PointIndex`](crate::geometry::nearest::PointIndex))
//! takes a hundred lines.

use glam::{DVec3, Vec3};

use crate::geometry::nearest::PointIndex;
use crate::geometry::plane_fit::least_spread_direction;

/// One planar region: a unit normal, a point on its plane, and its member points' count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneRegion {
    pub normal: DVec3,
    pub origin: DVec3,
    pub members: usize,
    /// The RMS distance of its members from its plane.
    pub rms: f64,
}

/// Planar regions of the points of `index`, grown over each point's `k` nearest neighbours,
/// most planar points (`variation`, by index, lowest first) seeding first. A neighbour joins
/// when it lies within `max_distance` of the region's plane and its own plane `normals` (by
/// index; zero for none) turns at most `max_angle_deg` from the region's; the region's
/// plane is fitted again to all its members each time they double. A region is kept when it
/// ends with at least `min_members` points and their RMS distance from its plane is at most
/// `max_rms` (a curved patch grows until its bend passes `max_distance`, and fails this).
/// Returns the kept regions and, by point index, the region each point belongs to.
#[allow(clippy::too_many_arguments)]
pub fn plane_regions(
    index: &PointIndex,
    normals: &[DVec3],
    variation: &[f64],
    k: usize,
    max_distance: f64,
    max_angle_deg: f64,
    max_rms: f64,
    min_members: usize,
) -> (Vec<PlaneRegion>, Vec<Option<u32>>) {
    let n = normals.len();
    let min_cos = max_angle_deg.to_radians().cos();
    let position: Vec<Option<DVec3>> = {
        let mut p = vec![None; n];
        for (i, x) in index.iter() {
            p[i as usize] = Some(x.as_dvec3());
        }
        p
    };
    let mut seeds: Vec<usize> = (0..n)
        .filter(|&i| position[i].is_some() && normals[i] != DVec3::ZERO)
        .collect();
    seeds.sort_by(|&a, &b| variation[a].total_cmp(&variation[b]).then(a.cmp(&b)));
    // Tried and not taken, or taken by a kept region.
    let mut visited = vec![false; n];
    let mut of_point = vec![None; n];
    let mut regions = Vec::new();
    for seed in seeds {
        if visited[seed] {
            continue;
        }
        let mut normal = normals[seed];
        let mut origin = position[seed].expect("seeds have positions");
        let mut members = vec![seed];
        visited[seed] = true;
        let mut next_fit = 8;
        let mut front = 0;
        while front < members.len() {
            let p = position[members[front]].expect("members have positions");
            front += 1;
            for (j, q) in index.k_nearest(p.as_vec3(), k) {
                let j = j as usize;
                if visited[j] || normals[j] == DVec3::ZERO {
                    continue;
                }
                let q = q.as_dvec3();
                if normal.dot(q - origin).abs() <= max_distance
                    && normal.dot(normals[j]).abs() >= min_cos
                {
                    visited[j] = true;
                    members.push(j);
                    if members.len() >= next_fit {
                        (normal, origin) = fit_plane(&members, &position, normal);
                        next_fit *= 2;
                    }
                }
            }
        }
        (normal, origin) = fit_plane(&members, &position, normal);
        let rms = (members
            .iter()
            .map(|&i| normal.dot(position[i].expect("member") - origin).powi(2))
            .sum::<f64>()
            / members.len() as f64)
            .sqrt();
        if members.len() >= min_members && rms <= max_rms {
            let id = regions.len() as u32;
            for &i in &members {
                of_point[i] = Some(id);
            }
            regions.push(PlaneRegion {
                normal,
                origin,
                members: members.len(),
                rms,
            });
        } else {
            // Not a region: its points may seed or join another (only the seed stays tried,
            // so that the loop ends).
            for &i in &members[1..] {
                visited[i] = false;
            }
        }
    }
    (regions, of_point)
}

/// The input's noise as its planar regions see it: the median, over the regions' points, of
/// their region's RMS distance from its plane (0 without regions). A region is kept only where
/// its points lie near one plane, so curvature, which the points' own neighbourhoods mix into
/// their spread, stays out of it: on 60 validation inputs 0.065 point spacings clean and 0.60
/// with 1% noise (docs/experiments/2026-12-06-crease-points.md).
pub fn regions_noise(regions: &[PlaneRegion]) -> f64 {
    let mut by_rms: Vec<(f64, usize)> = regions.iter().map(|r| (r.rms, r.members)).collect();
    by_rms.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: usize = by_rms.iter().map(|&(_, m)| m).sum();
    let mut seen = 0;
    for (rms, members) in by_rms {
        seen += members;
        if 2 * seen >= total {
            return rms;
        }
    }
    0.0
}

/// Each point of `index` in no region (`of_point`) whose `k` nearest points all lie within
/// `max_distance` of the planes of their regions joins the one of those regions whose plane it
/// lies nearest, within `max_distance`. Growth stops a spacing or two short of a crease in a
/// noisy input, where a point's own plane tilts halfway between the two faces; by its distance
/// such a point lies on one of them, and then its face's exact plane, not the tilted one, is
/// what the sharpening's quadrics read there (with 1% noise, a box's corners were cut off
/// without it). A neighbourhood that the planes do not explain is a curve running into a plane
/// (a fillet, a rounded rim), whose first ring joining the plane would flatten it: it stays
/// out. One pass from the grown regions, so a region reaches one neighbourhood further and no
/// more; its plane stays the grown one.
pub fn join_fringe(
    index: &PointIndex,
    k: usize,
    max_distance: f64,
    regions: &[PlaneRegion],
    of_point: &mut [Option<u32>],
) {
    let grown = of_point.to_vec();
    let off = |r: u32, q: Vec3| {
        let plane = regions[r as usize];
        plane.normal.dot(q.as_dvec3() - plane.origin).abs()
    };
    let (mut neighbours, mut near): (Vec<(u32, Vec3)>, Vec<u32>) = (Vec::new(), Vec::new());
    for (i, x) in index.iter() {
        if grown[i as usize].is_some() {
            continue;
        }
        neighbours.clear();
        neighbours.extend(index.k_nearest(x, k));
        near.clear();
        for &(j, _) in &neighbours {
            if let Some(r) = grown[j as usize]
                && !near.contains(&r)
            {
                near.push(r);
            }
        }
        let explained =
            (neighbours.iter()).all(|&(_, q)| near.iter().any(|&r| off(r, q) <= max_distance));
        if explained {
            // The nearest plane; the first region met among equals.
            of_point[i as usize] = (near.iter())
                .map(|&r| (off(r, x), r))
                .filter(|&(d, _)| d <= max_distance)
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, r)| r);
        }
    }
}

/// The least-squares plane of `members` (its normal turned to agree with `towards`), or the
/// old plane where they span none.
fn fit_plane(members: &[usize], position: &[Option<DVec3>], towards: DVec3) -> (DVec3, DVec3) {
    let points: Vec<DVec3> = members
        .iter()
        .map(|&i| position[i].expect("member"))
        .collect();
    let centre = points.iter().sum::<DVec3>() / points.len() as f64;
    match least_spread_direction(&points) {
        Some(n) => (if n.dot(towards) < 0.0 { -n } else { n }, centre),
        None => (towards, centre),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::degrade::{Degradation, degrade};
    use crate::geometry::plane_fit::covariance;
    use crate::geometry::quadric::symmetric_eigenvalues;
    use glam::Vec3;

    /// Points on two faces of a box's corner (x = 0 for y, z in [0, 1], and y = 0 for x, z
    /// in [0, 1]), with Gaussian noise of `noise` (the box is 1 across).
    fn crease(noise: f32, seed: u64) -> Vec<Vec3> {
        let mut points = Vec::new();
        for i in 0..30 {
            for j in 0..30 {
                let (u, v) = ((i as f32 + 0.5) / 30.0, (j as f32 + 0.5) / 30.0);
                points.push(Vec3::new(0.0, u, v));
                points.push(Vec3::new(u, 0.0, v));
            }
        }
        let how = Degradation {
            noise,
            missing: 0.0,
        };
        degrade(&points, &how, seed)
    }

    /// Each point's plane from its 12 nearest points, as the sharpening computes them: the
    /// normals, their variation, and the median RMS distance from the planes.
    fn local_planes(index: &PointIndex, n: usize) -> (Vec<DVec3>, Vec<f64>, f64) {
        let mut normals = vec![DVec3::ZERO; n];
        let mut variation = vec![f64::INFINITY; n];
        let mut residuals = Vec::new();
        for (i, p) in index.iter() {
            let near: Vec<DVec3> = index.k_nearest(p, 12).map(|(_, q)| q.as_dvec3()).collect();
            let values = symmetric_eigenvalues(covariance(&near));
            normals[i as usize] = least_spread_direction(&near).unwrap_or(DVec3::ZERO);
            variation[i as usize] = values[0] / values.iter().sum::<f64>();
            residuals.push(values[0].max(0.0).sqrt());
        }
        residuals.sort_by(f64::total_cmp);
        (normals, variation, residuals[residuals.len() / 2])
    }

    /// The regions of `points` with the limits sharpening uses (2.5 times the noise, 25
    /// degrees, RMS 1.2 times the noise, 36 points), the noise being the median RMS distance
    /// of a neighbourhood from its plane (at least 1e-4, so that clean points have limits);
    /// the local normals, and that noise.
    fn grow(index: &PointIndex, n: usize) -> (Vec<PlaneRegion>, Vec<Option<u32>>, Vec<DVec3>, f64) {
        let (normals, variation, noise) = local_planes(index, n);
        let noise = noise.max(1e-4);
        let (regions, of_point) = plane_regions(
            index,
            &normals,
            &variation,
            12,
            2.5 * noise,
            25.0,
            1.2 * noise,
            36,
        );
        (regions, of_point, normals, noise)
    }

    #[test]
    fn noisy_faces_of_a_crease_become_two_exact_planes() {
        let noise = 0.01;
        let points = crease(noise, 7);
        let index = PointIndex::new(&points);
        let (regions, of_point, normals, _) = grow(&index, points.len());
        // The local planes tilt with the noise.
        let tilt = points
            .iter()
            .zip(&normals)
            .filter(|(p, _)| p.x.abs() < 0.5 * noise && p.y > 0.2)
            .map(|(_, n)| n.x.abs().clamp(-1.0, 1.0).acos().to_degrees())
            .fold(0.0f64, f64::max);
        assert!(tilt > 3.0, "local planes tilt {tilt} degrees");
        assert_eq!(regions.len(), 2, "{regions:?}");
        for r in &regions {
            let axis = r.normal.abs().max_element();
            assert!(axis > 0.9995, "region plane tilts: {r:?}");
            assert!(r.members > 700, "{r:?}");
        }
        // Points of the x = 0 face away from the crease belong to its region, but for the
        // few that the noise takes past the distance limit; none to the other face's.
        let face: Vec<Option<u32>> = points
            .iter()
            .zip(&of_point)
            .filter(|(p, _)| p.y > 0.2 && p.x.abs() < 0.05)
            .map(|(_, r)| *r)
            .collect();
        let own = face
            .iter()
            .filter(|r| r.is_some_and(|r| regions[r as usize].normal.x.abs() > 0.999))
            .count();
        let other = face.iter().flatten().count() - own;
        assert!(
            own as f64 >= 0.9 * face.len() as f64,
            "{own} of {}",
            face.len()
        );
        assert_eq!(other, 0);
    }

    #[test]
    fn noisy_points_next_to_a_crease_join_the_face_they_lie_on() {
        let points = crease(0.01, 7);
        let index = PointIndex::new(&points);
        let (regions, mut of_point, _, noise) = grow(&index, points.len());
        assert_eq!(regions.len(), 2, "{regions:?}");
        // The regions see the noise, 0.01 here.
        let seen = regions_noise(&regions);
        assert!((0.007..0.013).contains(&seen), "{seen}");
        // Points within a spacing (1/30) of the crease line, away from its ends: few are in a
        // region as grown, their own planes turned between the faces...
        let band: Vec<usize> = (0..points.len())
            .filter(|&i| {
                let p = points[i];
                p.x.max(p.y) < 1.0 / 30.0 && p.z > 0.1 && p.z < 0.9
            })
            .collect();
        let in_region = |of: &[Option<u32>]| band.iter().filter(|&&i| of[i].is_some()).count();
        let grown = in_region(&of_point);
        // ...and most join one, a face whose plane they lie near (not those with a neighbour
        // that the noise takes farther than the limit from both planes).
        join_fringe(&index, 12, 2.5 * noise, &regions, &mut of_point);
        let joined = in_region(&of_point);
        assert!(
            4 * grown < band.len() && 2 * joined > band.len(),
            "{grown} grown, then {joined} of {} next to the crease in a region",
            band.len()
        );
        for &i in &band {
            if let Some(r) = of_point[i].map(|r| regions[r as usize]) {
                let d = r.normal.dot(points[i].as_dvec3() - r.origin).abs();
                assert!(d <= 2.5 * noise, "{d} from its region's plane");
            }
        }
    }

    #[test]
    fn clean_regions_see_no_noise() {
        let points = crease(0.0, 7);
        let index = PointIndex::new(&points);
        let (regions, ..) = grow(&index, points.len());
        assert!(regions_noise(&regions) < 1e-4, "{regions:?}");
    }

    #[test]
    fn a_sphere_has_no_large_planar_region() {
        let sphere = crate::geometry::primitives::icosphere(4);
        let points: Vec<Vec3> = sphere.positions.iter().map(|&p| p * 0.5).collect();
        let index = PointIndex::new(&points);
        let (regions, ..) = grow(&index, points.len());
        assert!(regions.is_empty(), "{regions:?}");
    }
}
