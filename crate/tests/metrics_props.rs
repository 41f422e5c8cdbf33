//! Property tests of sampling and the evaluation metrics (docs/design.md section 3).

use glam::Vec3;
use meshflow::Mesh;
use meshflow::eval::metrics::{
    CompareOptions, Comparison, chamfer_hausdorff, compare_meshes, edge_scores,
};
use meshflow::geometry::primitives::{cube, icosphere, octahedron};
use meshflow::geometry::sample::sample_surface;
use proptest::prelude::*;

fn point() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn points(max: usize) -> impl Strategy<Value = Vec<Vec3>> {
    prop::collection::vec(point(), 1..max)
}

fn dist(p: Vec3, q: Vec3) -> f64 {
    let d = [p.x - q.x, p.y - q.y, p.z - q.z].map(|c| c as f64);
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// O(n m) reference: (mean, max) of nearest distances from `from` to `to`.
fn brute_one_sided(from: &[Vec3], to: &[Vec3]) -> (f64, f64) {
    let d: Vec<f64> = from
        .iter()
        .map(|&p| to.iter().map(|&q| dist(p, q)).fold(f64::INFINITY, f64::min))
        .collect();
    (
        d.iter().sum::<f64>() / d.len() as f64,
        d.iter().copied().fold(0.0, f64::max),
    )
}

fn transformed(m: &Mesh, scale: f32, shift: Vec3) -> Mesh {
    Mesh {
        positions: m.positions.iter().map(|&p| p * scale + shift).collect(),
        ..m.clone()
    }
}

fn rel_close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-12)
}

fn assert_same_numbers(a: &Comparison, b: &Comparison, tol: f64) {
    let pairs = [
        (a.chamfer_x100, b.chamfer_x100),
        (a.hausdorff_x100, b.hausdorff_x100),
        (a.distances.a_to_b_mean, b.distances.a_to_b_mean),
        (a.distances.b_to_a_mean, b.distances.b_to_a_mean),
        (a.normal_consistency.unwrap(), b.normal_consistency.unwrap()),
    ];
    for (x, y) in pairs {
        assert!(rel_close(x, y, tol), "{x} vs {y}\n{a:?}\n{b:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn nearest_matches_brute_force(a in points(40), b in points(40)) {
        let d = chamfer_hausdorff(&a, &b).unwrap();
        let (am, ax) = brute_one_sided(&a, &b);
        let (bm, bx) = brute_one_sided(&b, &a);
        prop_assert!((d.a_to_b_mean - am).abs() < 1e-6);
        prop_assert!((d.b_to_a_mean - bm).abs() < 1e-6);
        prop_assert!((d.a_to_b_max - ax).abs() < 1e-6);
        prop_assert!((d.b_to_a_max - bx).abs() < 1e-6);
        prop_assert!((d.chamfer - (am + bm)).abs() < 1e-6);
        prop_assert!((d.hausdorff - ax.max(bx)).abs() < 1e-6);
    }

    #[test]
    fn chamfer_and_hausdorff_are_symmetric_and_ordered(a in points(60), b in points(60)) {
        let ab = chamfer_hausdorff(&a, &b).unwrap();
        let ba = chamfer_hausdorff(&b, &a).unwrap();
        prop_assert!((ab.chamfer - ba.chamfer).abs() < 1e-12);
        prop_assert_eq!(ab.hausdorff, ba.hausdorff);
        prop_assert_eq!(ab.a_to_b_mean, ba.b_to_a_mean);
        prop_assert!(ab.hausdorff >= ab.a_to_b_mean && ab.hausdorff >= ab.b_to_a_mean);
        prop_assert!(ab.a_to_b_max >= ab.a_to_b_mean && ab.b_to_a_max >= ab.b_to_a_mean);
        prop_assert!(ab.chamfer >= 0.0 && ab.chamfer.is_finite());
        let aa = chamfer_hausdorff(&a, &a).unwrap();
        prop_assert_eq!((aa.chamfer, aa.hausdorff), (0.0, 0.0));
    }

    #[test]
    fn translation_bounds(a in points(80), d in point()) {
        let d = d * 0.05;
        let b: Vec<Vec3> = a.iter().map(|&p| p + d).collect();
        let len = d.length() as f64;
        let r = chamfer_hausdorff(&a, &b).unwrap();
        // Every point's partner is at most |d| away; f32 rounding of p + d adds a little.
        let eps = 1e-6;
        prop_assert!(r.a_to_b_max <= len + eps && r.b_to_a_max <= len + eps);
        prop_assert!(r.hausdorff <= len + eps);
        prop_assert!(r.chamfer <= 2.0 * len + 2.0 * eps);
    }

    #[test]
    fn samples_lie_on_their_faces(
        tris in prop::collection::vec((point(), point(), point()), 1..8),
        seed in any::<u64>(),
    ) {
        let mut m = Mesh::default();
        for (i, (a, b, c)) in tris.into_iter().enumerate() {
            m.positions.extend([a, b, c]);
            let k = 3 * i as u32;
            m.faces.push([k, k + 1, k + 2]);
        }
        prop_assume!(m.area() > 1e-3);
        let s = sample_surface(&m, 200, seed).unwrap();
        prop_assert_eq!(&s, &sample_surface(&m, 200, seed).unwrap());
        for i in 0..s.points.len() {
            let [a, b, c] = m.triangle(s.faces[i] as usize);
            let n = (b - a).cross(c - a);
            prop_assume!(n.length() > 1e-4);
            let p = s.points[i];
            let area = n.length();
            let w = [
                (c - b).cross(p - b).dot(n) / (area * area),
                (a - c).cross(p - c).dot(n) / (area * area),
                (b - a).cross(p - a).dot(n) / (area * area),
            ];
            let tol = 1e-3;
            prop_assert!(w.iter().all(|&x| x > -tol && x < 1.0 + tol), "{:?}", w);
            prop_assert!(((p - a).dot(n) / area).abs() < 1e-4);
            prop_assert!((s.normals[i].length() - 1.0).abs() < 1e-5);
            prop_assert!(s.normals[i].dot(n / area) > 0.999);
        }
    }

    #[test]
    fn edge_scores_ignore_order_and_bound(
        p in prop::collection::vec((0u32..8, 0u32..8), 0..20),
        a in prop::collection::vec((0u32..8, 0u32..8), 0..20),
    ) {
        let p: Vec<[u32; 2]> = p.into_iter().map(|(i, j)| [i, j]).collect();
        let a: Vec<[u32; 2]> = a.into_iter().map(|(i, j)| [i, j]).collect();
        let s = edge_scores(&p, &a);
        let flipped: Vec<[u32; 2]> = p.iter().rev().map(|&[i, j]| [j, i]).collect();
        let doubled: Vec<[u32; 2]> = p.iter().chain(&p).copied().collect();
        prop_assert_eq!(s, edge_scores(&flipped, &a));
        prop_assert_eq!(s, edge_scores(&doubled, &a));
        let swapped = edge_scores(&a, &p);
        prop_assert_eq!((s.precision, s.recall, s.f1), (swapped.recall, swapped.precision, swapped.f1));
        for x in [s.precision, s.recall, s.f1] {
            prop_assert!((0.0..=1.0).contains(&x));
        }
        prop_assert!(s.true_positives <= s.predicted.min(s.actual));
        let own = edge_scores(&a, &a);
        prop_assert_eq!(own.f1, 1.0);
    }
}

#[test]
fn scale_invariance_power_of_two_is_exact() {
    let opts = CompareOptions::default();
    let (pred, gt) = (cube(), icosphere(3));
    let base = compare_meshes(&pred, &gt, &opts).unwrap();
    // Scaling by a power of two is exact in floating point, so every number is bit-identical.
    let scaled = compare_meshes(
        &transformed(&pred, 8.0, Vec3::ZERO),
        &transformed(&gt, 8.0, Vec3::ZERO),
        &opts,
    )
    .unwrap();
    assert_eq!(base, scaled);
}

#[test]
fn scale_invariance_by_seven() {
    let opts = CompareOptions::default();
    for (pred, gt) in [(cube(), icosphere(3)), (octahedron(), icosphere(2))] {
        let base = compare_meshes(&pred, &gt, &opts).unwrap();
        let scaled = compare_meshes(
            &transformed(&pred, 7.0, Vec3::ZERO),
            &transformed(&gt, 7.0, Vec3::ZERO),
            &opts,
        )
        .unwrap();
        // f32 rounding of the scaled coordinates (about 1e-7 of the box) is all that differs.
        assert_same_numbers(&base, &scaled, 1e-6);
        assert_eq!(base.pred_topology, scaled.pred_topology);
    }
}

#[test]
fn same_transform_on_both_sides_gives_the_same_numbers() {
    let opts = CompareOptions::default();
    let pred = transformed(&icosphere(2), 0.9, Vec3::new(0.05, 0.0, 0.0));
    let gt = icosphere(3);
    let base = compare_meshes(&pred, &gt, &opts).unwrap();
    let (s, t) = (3.7, Vec3::new(-12.0, 5.5, 0.25));
    let both = compare_meshes(&transformed(&pred, s, t), &transformed(&gt, s, t), &opts).unwrap();
    assert_same_numbers(&base, &both, 1e-4);
    // Transforming only the prediction is not normalised away: the ground truth sets the frame.
    let only_pred = compare_meshes(&transformed(&pred, s, t), &gt, &opts).unwrap();
    assert!(only_pred.chamfer_x100 > 10.0 * base.chamfer_x100);
}

#[test]
fn identical_spheres_only_show_sampling_noise() {
    // Independent 5,000-point samples of the same sphere (diameter 1 in the metric frame, area
    // pi) are not at distance 0: the floor is CD = sqrt(pi / 5000) = 0.0251, i.e. 2.51 x100.
    let sphere = icosphere(3);
    for seed in [0, 1, 2] {
        let opts = CompareOptions {
            seed,
            ..Default::default()
        };
        let c = compare_meshes(&sphere, &sphere, &opts).unwrap();
        assert!(c.chamfer_x100 > 2.2 && c.chamfer_x100 < 2.8, "{c:?}");
        assert!(c.normal_consistency.unwrap() > 0.95);
        let far = compare_meshes(&cube(), &sphere, &opts).unwrap();
        assert!(far.chamfer_x100 > 2.0 + c.chamfer_x100, "{far:?}");
    }
}
