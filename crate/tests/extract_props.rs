//! Property tests of Algorithm 1 on meshes it must reproduce exactly.

use glam::Vec3;
use meshflow::Mesh;
use meshflow::extract::{ExtractOptions, FaceSupport, extract_mesh, triangles_of_edges};
use meshflow::normals::vertex_normals;
use meshflow::primitives::{grid, icosphere};
use meshflow::rng::Rng;
use meshflow::topology::{TopologyReport, edges, rotate_min_first, sorted_face};
use proptest::prelude::*;

/// A perturbed icosphere or grid with some faces deleted and its vertices renumbered at random.
fn random_mesh(kind: u8, size: u32, jitter: f32, delete_percent: u64, seed: u64) -> Mesh {
    let mut m = match kind {
        0 => icosphere(size.min(3)),
        _ => grid(size + 1, size + 2),
    };
    let mut rng = Rng::new(seed);
    for p in &mut m.positions {
        *p += Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * jitter;
    }
    m.faces.retain(|_| rng.below(100) as u64 >= delete_percent);
    let mut perm: Vec<u32> = (0..m.positions.len() as u32).collect();
    rng.shuffle(&mut perm);
    let mut positions = vec![Vec3::ZERO; m.positions.len()];
    for (old, &new) in perm.iter().enumerate() {
        positions[new as usize] = m.positions[old];
    }
    let faces = m
        .faces
        .iter()
        .map(|f| f.map(|v| perm[v as usize]))
        .collect();
    Mesh::new(positions, faces)
}

fn sorted_set(faces: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut v: Vec<[u32; 3]> = faces.iter().map(|&f| sorted_face(f)).collect();
    v.sort_unstable();
    v
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn ground_truth_edges_give_exactly_the_faces(
        kind in 0u8..2, size in 1u32..4, jitter in 0.0f32..0.05, delete in 0u64..30, seed in any::<u64>()
    ) {
        let m = random_mesh(kind, size, jitter, delete, seed);
        let e = edges(&m.faces);
        // The property holds for meshes whose every 3-clique is a face.
        prop_assume!(sorted_set(&triangles_of_edges(m.positions.len(), &e)) == sorted_set(&m.faces));
        let normals = vertex_normals(&m.positions, &m.faces);
        let opts = ExtractOptions { fill_holes: false, compact: false, ..Default::default() };
        let (out, report) = extract_mesh(&m.positions, &normals, &e, FaceSupport::Geometric, &opts).unwrap();
        prop_assert_eq!(sorted_set(&out.faces), sorted_set(&m.faces));
        prop_assert_eq!(report.clique_faces, m.faces.len());
        // Winding follows the vertex normals; on these gently perturbed, consistently wound
        // meshes that is the original winding wherever the normals agree clearly with the face.
        let original: Vec<[u32; 3]> = m.faces.iter().map(|&f| rotate_min_first(f)).collect();
        for f in &out.faces {
            let [a, b, c] = f.map(|i| m.positions[i as usize]);
            let mean = (normals[f[0] as usize] + normals[f[1] as usize] + normals[f[2] as usize]).normalize();
            if (b - a).cross(c - a).normalize().dot(mean).abs() > 0.2 {
                prop_assert!(original.contains(&rotate_min_first(*f)), "face {:?} flipped", f);
            }
        }
        // With compaction the mesh keeps every face and loses only isolated vertices.
        let (compact, r) = extract_mesh(&m.positions, &normals, &e, FaceSupport::Geometric,
            &ExtractOptions { fill_holes: false, ..Default::default() }).unwrap();
        prop_assert_eq!(compact.faces.len(), m.faces.len());
        prop_assert_eq!(r.unreferenced_vertices_removed, TopologyReport::of(&m).isolated_vertices);
        prop_assert!(compact.validate().is_ok());
    }

    #[test]
    fn hole_repair_only_adds_faces(
        kind in 0u8..2, size in 1u32..4, delete in 0u64..30, max_hole in 3usize..12, seed in any::<u64>()
    ) {
        let m = random_mesh(kind, size, 0.0, delete, seed);
        let normals = vertex_normals(&m.positions, &m.faces);
        let e = edges(&m.faces);
        let base = ExtractOptions { fill_holes: false, compact: false, ..Default::default() };
        let (open, _) = extract_mesh(&m.positions, &normals, &e, FaceSupport::Geometric, &base).unwrap();
        let filled_opts = ExtractOptions { fill_holes: true, max_hole_edges: max_hole, ..base };
        let (filled, r) = extract_mesh(&m.positions, &normals, &e, FaceSupport::Geometric, &filled_opts).unwrap();
        let open_set = sorted_set(&open.faces);
        let filled_set = sorted_set(&filled.faces);
        prop_assert!(open_set.iter().all(|f| filled_set.binary_search(f).is_ok()));
        prop_assert_eq!(filled.faces.len(), open.faces.len() + r.hole_faces);
        // No face is ever added twice.
        let mut dedup = filled_set.clone();
        dedup.dedup();
        prop_assert_eq!(dedup.len(), filled_set.len());
        // Filling never leaves more holes than there were.
        prop_assert!(TopologyReport::of(&filled).holes <= TopologyReport::of(&open).holes);
    }

    #[test]
    fn non_manifold_filter_leaves_no_non_manifold_edge(
        n in 4usize..40, extra in 0usize..80, max_hole in 0usize..12, seed in any::<u64>()
    ) {
        // A random point set with random edges: plenty of non-manifold cliques.
        let mut rng = Rng::new(seed);
        let positions: Vec<Vec3> = (0..n).map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())).collect();
        let normals: Vec<Vec3> = (0..n).map(|_| Vec3::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5, 1.0).normalize()).collect();
        let e: Vec<[u32; 2]> = (0..extra + n).map(|_| [rng.below(n) as u32, rng.below(n) as u32]).collect();
        // Hole repair runs after the filter and must not give an edge a third face either.
        let opts = ExtractOptions {
            drop_non_manifold: true,
            fill_holes: max_hole >= 3,
            max_hole_edges: max_hole,
            ..Default::default()
        };
        let (out, _) = extract_mesh(&positions, &normals, &e, FaceSupport::Geometric, &opts).unwrap();
        prop_assert_eq!(TopologyReport::of(&out).non_manifold_edges, 0);
    }
}
