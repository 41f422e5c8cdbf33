//! Seeded area-uniform surface sampling (docs/design.md section 3: "sample 5,000 points uniformly by
//! area on each surface (seeded)").
//!
//! Reproducibility: for a given mesh, count and seed the samples are the same on every platform.
//! All arithmetic that decides a sample is done in `f64` with plain IEEE operations (no SIMD
//! reductions whose order could differ between targets), and randomness comes from the crate's
//! own [`Rng`]. Each sample draws exactly three `f64`s in this order: the face (inverse CDF of
//! the cumulative face areas), then `u` and `v` for the barycentric coordinates
//! `r1 = sqrt(u)`, `(1 - r1, r1 (1 - v), r1 v)`, which are uniform over the triangle.

use glam::{DVec3, Vec3};

use crate::Mesh;
use crate::rng::Rng;

/// Points sampled on a mesh's surface.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceSamples {
    pub points: Vec<Vec3>,
    /// The unit (geometric) normal of the face each point lies on, oriented by its winding.
    pub normals: Vec<Vec3>,
    /// The index of the face each point lies on.
    pub faces: Vec<u32>,
}

impl SurfaceSamples {
    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

/// The most samples one call may ask for (the readers' vertex limit, 16 Mi): a larger request
/// is an error rather than an allocation that cannot succeed.
pub const MAX_SAMPLES: usize = 1 << 24;

/// Why a surface cannot be sampled.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SampleError {
    #[error(
        "cannot sample a surface: the mesh has no faces ({vertices} vertices; a point cloud has no surface, use its points instead)"
    )]
    NoFaces { vertices: usize },
    #[error(
        "cannot sample a surface: the total area of the {faces} faces is zero (every face is degenerate; treat it as a point cloud)"
    )]
    ZeroArea { faces: usize },
    #[error("cannot sample a surface: face {face} uses vertex {index} but there are {vertices}")]
    IndexOutOfRange {
        face: usize,
        index: u32,
        vertices: usize,
    },
    #[error("cannot sample a surface: the total area is not finite (non-finite coordinates)")]
    NonFiniteArea,
    #[error("{count} samples asked for; at most {MAX_SAMPLES} are allowed")]
    TooMany { count: usize },
}

fn dvec(p: Vec3) -> DVec3 {
    DVec3::new(p.x as f64, p.y as f64, p.z as f64)
}

/// Cross product written out, so every platform rounds it identically.
fn cross(a: DVec3, b: DVec3) -> DVec3 {
    DVec3::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

fn norm(a: DVec3) -> f64 {
    (a.x * a.x + a.y * a.y + a.z * a.z).sqrt()
}

/// Samples `count` points uniformly by area on `mesh`'s surface, reproducibly for `seed`.
///
/// Faces of zero area are never chosen. Errors when the mesh has no faces (a point cloud: use
/// [`subsample_points`]), when the total area is zero or not finite, or when a face index is out
/// of range. `count == 0` gives empty samples (after the same checks).
pub fn sample_surface(mesh: &Mesh, count: usize, seed: u64) -> Result<SurfaceSamples, SampleError> {
    if count > MAX_SAMPLES {
        return Err(SampleError::TooMany { count });
    }
    if mesh.faces.is_empty() {
        return Err(SampleError::NoFaces {
            vertices: mesh.positions.len(),
        });
    }
    let vertices = mesh.positions.len();
    let mut corners = Vec::with_capacity(mesh.faces.len());
    let mut cumulative = Vec::with_capacity(mesh.faces.len());
    let mut total = 0.0f64;
    for (face, f) in mesh.faces.iter().enumerate() {
        if let Some(&index) = f.iter().find(|&&i| i as usize >= vertices) {
            return Err(SampleError::IndexOutOfRange {
                face,
                index,
                vertices,
            });
        }
        let [a, b, c] = f.map(|i| dvec(mesh.positions[i as usize]));
        let twice_area = norm(cross(b - a, c - a));
        total += 0.5 * twice_area;
        cumulative.push(total);
        corners.push([a, b, c]);
    }
    if !total.is_finite() {
        return Err(SampleError::NonFiniteArea);
    }
    if total <= 0.0 {
        return Err(SampleError::ZeroArea {
            faces: mesh.faces.len(),
        });
    }

    let mut rng = Rng::new(seed);
    let mut out = SurfaceSamples {
        points: Vec::with_capacity(count),
        normals: Vec::with_capacity(count),
        faces: Vec::with_capacity(count),
    };
    for _ in 0..count {
        let target = rng.next_f64() * total;
        // First face whose cumulative area exceeds the target: zero-area faces (equal
        // cumulative values) are skipped, and target < total keeps the index in range.
        let face = cumulative
            .partition_point(|&c| c <= target)
            .min(cumulative.len() - 1);
        let u = rng.next_f64();
        let v = rng.next_f64();
        let r1 = u.sqrt();
        let (w0, w1, w2) = (1.0 - r1, r1 * (1.0 - v), r1 * v);
        let [a, b, c] = corners[face];
        let p = DVec3::new(
            w0 * a.x + w1 * b.x + w2 * c.x,
            w0 * a.y + w1 * b.y + w2 * c.y,
            w0 * a.z + w1 * b.z + w2 * c.z,
        );
        let n = cross(b - a, c - a);
        let n = n / norm(n);
        out.points.push(p.as_vec3());
        out.normals.push(n.as_vec3());
        out.faces.push(face as u32);
    }
    Ok(out)
}

/// Samples `count` points uniformly by length on the segments `edges` of `positions`,
/// reproducibly for `seed` (the edge analogue of [`sample_surface`]: per sample, the segment
/// by the inverse CDF of the cumulative lengths, then the parameter along it). No segment, or
/// none of positive length, gives no points.
pub fn sample_segments(
    positions: &[Vec3],
    edges: &[[u32; 2]],
    count: usize,
    seed: u64,
) -> Vec<Vec3> {
    let mut cumulative = Vec::with_capacity(edges.len());
    let mut total = 0.0f64;
    for &[a, b] in edges {
        total += dvec(positions[a as usize]).distance(dvec(positions[b as usize]));
        cumulative.push(total);
    }
    if !(total > 0.0 && total.is_finite()) {
        return Vec::new();
    }
    let mut rng = Rng::new(seed);
    (0..count.min(MAX_SAMPLES))
        .map(|_| {
            let target = rng.next_f64() * total;
            let e = cumulative
                .partition_point(|&c| c <= target)
                .min(cumulative.len() - 1);
            let t = rng.next_f64();
            let [a, b] = edges[e].map(|i| dvec(positions[i as usize]));
            (a + (b - a) * t).as_vec3()
        })
        .collect()
}

/// Draws `count` of `points`, reproducibly for `seed`, for point clouds that stand in for a
/// surface: `subsample_indices(points.len(), count, seed)` mapped to the points.
pub fn subsample_points(points: &[Vec3], count: usize, seed: u64) -> Vec<Vec3> {
    subsample_indices(points.len(), count, seed)
        .into_iter()
        .map(|i| points[i])
        .collect()
}

/// `count` indices into `0..len`, reproducibly for `seed`.
///
/// When `count <= len` they are drawn without replacement (a partial Fisher-Yates shuffle, in
/// the drawn order; `count == len` gives `0..len` in order). When `count > len` every index is
/// used `count / len` times and the remaining `count % len` are drawn without replacement, so
/// the repetition is as even as it can be (a plain with-replacement draw would weight points
/// unevenly at random). `len == 0` gives no indices.
pub fn subsample_indices(len: usize, count: usize, seed: u64) -> Vec<usize> {
    if len == 0 {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(count);
    for _ in 0..count / len {
        out.extend(0..len);
    }
    let take = count % len;
    if take == 0 {
        return out;
    }
    let mut rng = Rng::new(seed);
    let mut order: Vec<usize> = (0..len).collect();
    for i in 0..take {
        let j = i + rng.below(len - i);
        order.swap(i, j);
        out.push(order[i]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{grid, icosphere};

    #[test]
    fn segment_samples_lie_on_the_segments_by_length() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 3.0, 0.0)];
        let s = sample_segments(&positions, &[[0, 1], [1, 2]], 4000, 7);
        assert_eq!(s, sample_segments(&positions, &[[0, 1], [1, 2]], 4000, 7));
        assert!(
            s.iter()
                .all(|p| (p.y.abs() < 1e-6 && (0.0..=1.0).contains(&p.x))
                    || ((p.x - 1.0).abs() < 1e-6 && (0.0..=3.0).contains(&p.y)))
        );
        // A quarter of the length is on the first segment.
        let first = s
            .iter()
            .filter(|p| p.y.abs() < 1e-6 && p.x < 1.0 - 1e-6)
            .count();
        assert!((first as f64 / 4000.0 - 0.25).abs() < 0.03, "{first}");
        assert!(sample_segments(&positions, &[], 10, 0).is_empty());
        assert!(sample_segments(&positions, &[[1, 1]], 10, 0).is_empty());
    }

    /// Barycentric coordinates of `p` in triangle `t` plus its distance to the triangle's plane.
    fn barycentric(p: Vec3, [a, b, c]: [Vec3; 3]) -> ([f64; 3], f64) {
        let (p, a, b, c) = (dvec(p), dvec(a), dvec(b), dvec(c));
        let n = cross(b - a, c - a);
        let area2 = n.dot(n);
        let w0 = cross(c - b, p - b).dot(n) / area2;
        let w1 = cross(a - c, p - c).dot(n) / area2;
        let w2 = cross(b - a, p - a).dot(n) / area2;
        let off_plane = (p - a).dot(n) / area2.sqrt();
        ([w0, w1, w2], off_plane.abs())
    }

    /// Two triangles in the plane z = 0 with areas 1 and 3.
    fn two_triangles() -> Mesh {
        Mesh::new(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(8.0, 0.0, 0.0),
                Vec3::new(5.0, 2.0, 0.0),
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        )
    }

    #[test]
    fn points_lie_on_their_faces_with_unit_normals() {
        let m = icosphere(2);
        let s = sample_surface(&m, 3000, 11).unwrap();
        assert_eq!(
            (s.points.len(), s.normals.len(), s.faces.len()),
            (3000, 3000, 3000)
        );
        for i in 0..s.len() {
            let t = m.triangle(s.faces[i] as usize);
            let (w, off) = barycentric(s.points[i], t);
            assert!(off < 1e-6, "sample {i} is {off} off its face's plane");
            for wk in w {
                assert!((-1e-5..=1.0 + 1e-5).contains(&wk), "sample {i}: {w:?}");
            }
            assert!((s.normals[i].length() - 1.0).abs() < 1e-6);
            // Outward-facing sphere: the face normal points away from the centre.
            assert!(s.normals[i].dot(s.points[i]) > 0.9);
        }
    }

    #[test]
    fn reproducible_per_seed() {
        let m = icosphere(1);
        let a = sample_surface(&m, 500, 3).unwrap();
        let b = sample_surface(&m, 500, 3).unwrap();
        let c = sample_surface(&m, 500, 4).unwrap();
        assert_eq!(a, b);
        assert_ne!(a.points, c.points);
        // A prefix of a longer run is the shorter run.
        let long = sample_surface(&m, 800, 3).unwrap();
        assert_eq!(&long.points[..500], &a.points[..]);
    }

    #[test]
    fn fixed_stream_on_every_platform() {
        // Pinned bit patterns: if these change, every seeded metric the project published changes.
        let s = sample_surface(&two_triangles(), 3, 0).unwrap();
        let bits: Vec<[u32; 3]> = s
            .points
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect();
        let expected = vec![
            [1088251243, 1024344092, 0],
            [1085607707, 1046125679, 0],
            [1068080682, 1046281385, 0],
        ];
        assert_eq!((s.faces.clone(), bits), (vec![1, 1, 0], expected));
    }

    #[test]
    fn uniform_by_area_two_triangles() {
        let n = 20_000;
        let s = sample_surface(&two_triangles(), n, 99).unwrap();
        let big = s.faces.iter().filter(|&&f| f == 1).count() as f64;
        let p = 0.75;
        let sigma = (p * (1.0 - p) / n as f64).sqrt();
        let frac = big / n as f64;
        assert!((frac - p).abs() < 4.0 * sigma, "fraction {frac}");
    }

    #[test]
    fn uniform_by_area_grid_chi_square() {
        let m = grid(4, 4);
        let n = 32_000;
        let s = sample_surface(&m, n, 5).unwrap();
        let mut counts = [0usize; 32];
        for &f in &s.faces {
            counts[f as usize] += 1;
        }
        let expected = n as f64 / 32.0;
        let chi2: f64 = counts
            .iter()
            .map(|&c| (c as f64 - expected).powi(2) / expected)
            .sum();
        // 31 degrees of freedom: mean 31, p = 0.001 at about 61.1; generous threshold.
        assert!(chi2 < 70.0, "chi-square {chi2}");
        // Within each face the point is uniform too: the mean barycentric coordinate is 1/3.
        let mut mean = [0.0f64; 3];
        for i in 0..s.len() {
            let (w, _) = barycentric(s.points[i], m.triangle(s.faces[i] as usize));
            for k in 0..3 {
                mean[k] += w[k] / n as f64;
            }
        }
        for mk in mean {
            assert!((mk - 1.0 / 3.0).abs() < 0.01, "{mean:?}");
        }
    }

    #[test]
    fn zero_area_faces_never_chosen() {
        let mut m = two_triangles();
        m.positions.push(Vec3::new(9.0, 9.0, 9.0));
        m.faces.insert(0, [6, 6, 6]);
        m.faces.insert(2, [0, 1, 1]);
        let s = sample_surface(&m, 5000, 1).unwrap();
        assert!(s.faces.iter().all(|&f| f == 1 || f == 3));
        assert!(s.normals.iter().all(|n| n.is_finite()));
    }

    #[test]
    fn errors() {
        let cloud = Mesh::from_points(vec![Vec3::ZERO, Vec3::X]);
        let e = sample_surface(&cloud, 10, 0).unwrap_err();
        assert_eq!(e, SampleError::NoFaces { vertices: 2 });
        assert!(e.to_string().contains("point cloud"));
        let flat = Mesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], vec![[0, 1, 2]]);
        assert_eq!(
            sample_surface(&flat, 10, 0).unwrap_err(),
            SampleError::ZeroArea { faces: 1 }
        );
        let broken = Mesh::new(vec![Vec3::ZERO], vec![[0, 1, 2]]);
        assert!(matches!(
            sample_surface(&broken, 10, 0),
            Err(SampleError::IndexOutOfRange { index: 1, .. })
        ));
        let mut inf = two_triangles();
        inf.positions[1].x = f32::INFINITY;
        assert!(sample_surface(&inf, 1, 0).is_err());
        assert!(sample_surface(&two_triangles(), 0, 0).unwrap().is_empty());
    }

    #[test]
    fn subsample_without_and_with_replacement() {
        let pts: Vec<Vec3> = (0..100).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
        let s = subsample_points(&pts, 40, 8);
        assert_eq!(s.len(), 40);
        let mut xs: Vec<i32> = s.iter().map(|p| p.x as i32).collect();
        xs.sort();
        xs.dedup();
        assert_eq!(xs.len(), 40, "drawn without replacement");
        assert_eq!(s, subsample_points(&pts, 40, 8));
        assert_ne!(s, subsample_points(&pts, 40, 9));

        let all = subsample_points(&pts, 100, 8);
        assert_eq!(all, pts, "count == len keeps every point once, in order");

        let more = subsample_points(&pts, 250, 8);
        assert_eq!(more.len(), 250);
        let mut uses = [0usize; 100];
        for p in &more {
            uses[p.x as usize] += 1;
        }
        assert!(uses.iter().all(|&u| u == 2 || u == 3));
        assert_eq!(uses.iter().filter(|&&u| u == 3).count(), 50);

        assert!(subsample_points(&[], 10, 0).is_empty());
        assert!(subsample_points(&pts, 0, 0).is_empty());
    }
}
