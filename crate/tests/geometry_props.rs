//! Property tests of the geometry core: normals, cleaning, voxels, vertex order, tokens and
//! the guarded edits.

use glam::{DVec3, Vec3};
use meshflow::Mesh;
use meshflow::geometry::clean::{CleanOptions, clean};
use meshflow::geometry::edit::EditMesh;
use meshflow::geometry::normals::{face_normal, vertex_normals};
use meshflow::geometry::primitives::{cube, grid, icosphere};
use meshflow::geometry::topology;
use meshflow::geometry::voxel::{VOXEL_RESOLUTION, voxel_index};
use meshflow::model::tokens::{TokenConfig, build_tokens, vertex_order};
use meshflow::rng::Rng;
use proptest::prelude::*;

fn point() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A random triangle soup over 3..40 random points (faces may repeat or be degenerate).
fn soup() -> impl Strategy<Value = Mesh> {
    prop::collection::vec(point(), 3..40).prop_flat_map(|positions| {
        let n = positions.len() as u32;
        prop::collection::vec((0..n, 0..n, 0..n), 0..60).prop_map(move |faces| {
            Mesh::new(
                positions.clone(),
                faces.into_iter().map(|(a, b, c)| [a, b, c]).collect(),
            )
        })
    })
}

/// A soup with repeated points (exact and within the weld tolerance), duplicate, flipped and
/// degenerate faces: everything cleaning is for.
fn messy() -> impl Strategy<Value = Mesh> {
    (soup(), any::<u64>()).prop_map(|(mut m, seed)| {
        let mut rng = Rng::new(seed);
        let n = m.positions.len();
        for _ in 0..n / 2 {
            let p = m.positions[rng.below(n)];
            let jitter = if rng.below(2) == 0 { 0.0 } else { 1e-7 };
            m.positions.push(p + Vec3::splat(jitter));
        }
        let total = m.positions.len() as u32;
        let copies: Vec<[u32; 3]> = m.faces.iter().take(10).copied().collect();
        for (i, f) in copies.into_iter().enumerate() {
            m.faces.push(match i % 3 {
                0 => f,
                1 => [f[0], f[2], f[1]],
                _ => [f[1], f[2], f[0]],
            });
        }
        for _ in 0..5 {
            let v = rng.below(total as usize) as u32;
            m.faces.push([v, v, rng.below(total as usize) as u32]);
        }
        if rng.below(2) == 0 {
            m.normals = (0..m.positions.len()).map(|i| Vec3::X * i as f32).collect();
        }
        m
    })
}

/// Every face gets its own corners (as STL stores them), in a shuffled face order with each
/// face's corners rotated.
fn explode(m: &Mesh, seed: u64) -> Mesh {
    let mut rng = Rng::new(seed);
    let mut faces = m.faces.clone();
    rng.shuffle(&mut faces);
    let mut out = Mesh::default();
    for f in faces {
        let mut f = f;
        f.rotate_left(rng.below(3));
        let base = out.positions.len() as u32;
        out.positions.extend(f.map(|i| m.positions[i as usize]));
        out.faces.push([base, base + 1, base + 2]);
    }
    out
}

/// The topology report of an edit mesh's live faces.
fn edited_report(e: &EditMesh) -> topology::TopologyReport {
    let (p, f, _) = e.compacted();
    topology::TopologyReport::of(&Mesh::new(p.iter().map(|p| p.as_vec3()).collect(), f))
}

proptest! {
    /// Flips and collapses on a crumpled sphere (each vertex pushed up to 0.6 of the radius),
    /// with no turn limit on the collapses so that only the fold guard stands between two
    /// faces and doubling over: no edit leaves more folded edges than the mesh had, and the
    /// mesh stays closed and manifold.
    #[test]
    fn guarded_edits_add_no_folded_edges(
        push in prop::collection::vec(point(), 42),
        edits in prop::collection::vec((0usize..1000, any::<bool>()), 1..80),
    ) {
        let sphere = icosphere(1);
        let positions: Vec<DVec3> = (sphere.positions.iter().zip(&push))
            .map(|(p, d)| (*p + *d * 0.6).as_dvec3())
            .collect();
        let mut e = EditMesh::new(positions, &sphere.faces);
        let mut folded = edited_report(&e).folded_edges;
        for (pick, flip) in edits {
            let edges = e.edges();
            let [a, b] = edges[pick % edges.len()];
            if flip {
                let Some((c, d)) = e.flippable(a, b) else { continue };
                e.flip(a, b, c, d);
            } else {
                let x = (e.positions[a as usize] + e.positions[b as usize]) * 0.5;
                if !e.can_collapse(a, b, x, -1.0) {
                    continue;
                }
                e.collapse(a, b, x);
            }
            let r = edited_report(&e);
            prop_assert!(r.folded_edges <= folded, "{folded} -> {r:?}");
            prop_assert_eq!((r.non_manifold_edges, r.boundary_edges), (0, 0));
            prop_assert_eq!(r.inconsistent_winding_edges, 0);
            folded = r.folded_edges;
        }
    }

    /// The collapse guard counts folded edges around the collapse only: on a crumpled sphere,
    /// with no turn limit, a collapse the mesh's topology allows passes exactly when doing it
    /// leaves the whole mesh with no more folded edges than before.
    #[test]
    fn the_collapse_guard_counts_the_whole_meshs_folds(
        push in prop::collection::vec(point(), 42),
        picks in prop::collection::vec((0usize..1000, 0.0f64..1.0), 1..40),
    ) {
        let sphere = icosphere(1);
        let positions: Vec<DVec3> = (sphere.positions.iter().zip(&push))
            .map(|(p, d)| (*p + *d * 0.6).as_dvec3())
            .collect();
        let mut e = EditMesh::new(positions, &sphere.faces);
        for (pick, t) in picks {
            let edges = e.edges();
            let [a, b] = edges[pick % edges.len()];
            let Some(plan) = e.plan_collapse(a, b) else { continue };
            let x = e.positions[a as usize].lerp(e.positions[b as usize], t);
            let mut done = e.clone();
            done.collapse(a, b, x);
            let more = edited_report(&done).folded_edges > edited_report(&e).folded_edges;
            prop_assert_eq!(e.collapse_keeps_shape(&plan, x, -1.0), !more, "edge {:?}", (a, b));
            if !more {
                e = done;
            }
        }
    }

    /// Sharpening's flip passes ask an edge's flip guard in one orientation only: on a
    /// crumpled sphere, every edge that has a flip's apexes both ways round gets the same
    /// answer from `flip_keeps_shape` both ways round, and `flippable` agrees with the two
    /// asked in turn.
    #[test]
    fn the_flip_guard_is_the_same_either_way_round(push in prop::collection::vec(point(), 42)) {
        let sphere = icosphere(1);
        let positions: Vec<DVec3> = (sphere.positions.iter().zip(&push))
            .map(|(p, d)| (*p + *d * 0.6).as_dvec3())
            .collect();
        let e = EditMesh::new(positions, &sphere.faces);
        let mut asked = 0;
        for [a, b] in e.edges() {
            let (Some((c, d)), Some((d2, c2))) = (e.flip_apexes(a, b), e.flip_apexes(b, a)) else {
                continue;
            };
            prop_assert_eq!((c, d), (c2, d2));
            let either = e.flip_keeps_shape(a, b, c, d);
            prop_assert_eq!(either, e.flip_keeps_shape(b, a, d, c), "edge {:?}", (a, b));
            prop_assert_eq!(e.flippable(a, b), either.then_some((c, d)));
            asked += 1;
        }
        prop_assert_eq!(asked, e.edges().len());
    }

    /// The hole count is the surface's: splitting every face in four or numbering the vertices
    /// backwards changes no hole, whatever pinches the faces make (a soup over few vertices
    /// pinches at most of them; walking the boundary's edges counted differently).
    #[test]
    fn holes_do_not_change_when_faces_are_split_or_renumbered(m in soup()) {
        let mut m = m;
        m.faces.retain(|&[a, b, c]| a != b && b != c && c != a);
        let holes = topology::TopologyReport::of(&m).holes;
        // Split as sharpening's first step splits.
        let mut split = EditMesh::from_mesh(&m);
        split.subdivide();
        prop_assert_eq!(edited_report(&split).holes, holes);
        let last = m.positions.len() as u32 - 1;
        let backwards = Mesh::new(
            m.positions.iter().rev().copied().collect(),
            m.faces.iter().map(|f| f.map(|v| last - v)).collect(),
        );
        prop_assert_eq!(topology::TopologyReport::of(&backwards).holes, holes);
    }

    #[test]
    fn normals_are_unit(m in soup()) {
        let scale = m.aabb().unwrap().max_extent();
        // Non-degenerate faces only (degenerate ones would be dropped by cleaning).
        let faces: Vec<[u32; 3]> = (0..m.faces.len())
            .filter(|&f| {
                !topology::is_degenerate(&m.positions, m.faces[f], scale, topology::DEGENERATE_TOLERANCE)
            })
            .map(|f| m.faces[f])
            .collect();
        for n in vertex_normals(&m.positions, &faces) {
            prop_assert!((n.length() - 1.0).abs() < 1e-5, "{n}");
        }
        for f in &faces {
            let n = face_normal(f.map(|i| m.positions[i as usize]));
            prop_assert!((n.length() - 1.0).abs() < 1e-5, "{n}");
        }
    }

    #[test]
    fn cleaning_is_idempotent(m in messy()) {
        let opts = CleanOptions::default();
        let (once, _) = clean(&m, &opts);
        let (twice, report) = clean(&once, &opts);
        prop_assert!(report.is_empty(), "{report:?}");
        prop_assert_eq!(twice, once.clone());
        prop_assert_eq!(topology::TopologyReport::of(&once).degenerate_faces, 0);
        prop_assert!(once.normals.is_empty() || once.normals.len() == once.positions.len());
    }

    #[test]
    fn exploded_primitives_weld_back(seed in any::<u64>(), nx in 1u32..6, ny in 1u32..6) {
        for m in [icosphere(2), cube(), grid(nx, ny)] {
            let (c, r) = clean(&explode(&m, seed), &CleanOptions::default());
            prop_assert_eq!(c.positions.len(), m.positions.len());
            prop_assert_eq!(c.faces.len(), m.faces.len());
            prop_assert_eq!(r.welded_vertices, 3 * m.faces.len() - m.positions.len());
            let (a, b) = (topology::TopologyReport::of(&c), topology::TopologyReport::of(&m));
            prop_assert_eq!(a, b);
        }
    }

    #[test]
    fn voxel_indices_in_range(x in any::<f32>(), y in any::<f32>(), z in -2.0f32..2.0) {
        for i in voxel_index(Vec3::new(x, y, z)) {
            prop_assert!(i < VOXEL_RESOLUTION);
        }
    }

    #[test]
    fn vertex_order_is_sorted_permutation(
        pts in prop::collection::vec(
            // A few distinct values so ties are common.
            (0u8..4, 0u8..4, 0u8..4).prop_map(|(x, y, z)| Vec3::new(x as f32, y as f32, z as f32)),
            0..60,
        )
    ) {
        let order = vertex_order(&pts);
        let mut seen = order.clone();
        seen.sort_unstable();
        prop_assert_eq!(seen, (0..pts.len() as u32).collect::<Vec<_>>());
        for w in order.windows(2) {
            let (p, q) = (pts[w[0] as usize], pts[w[1] as usize]);
            let key = |p: Vec3| (p.z, p.y, p.x);
            prop_assert!(key(p) < key(q) || (key(p) == key(q) && w[0] < w[1]));
        }
    }

    #[test]
    fn tokens_are_consistent(m in soup(), extra in 0usize..20, seed in any::<u64>()) {
        let cfg = TokenConfig { num_vertices: m.positions.len() + extra, max_degree: 6, num_freqs: 4 };
        let t = build_tokens(&m, &cfg, seed).unwrap();
        let c = t.in_channels;
        prop_assert_eq!(c, cfg.in_channels());
        prop_assert_eq!(t.features.len(), cfg.num_vertices * c);
        prop_assert_eq!(t.mask.iter().filter(|&&b| b).count(), t.num_real);
        prop_assert_eq!(t.num_real, m.positions.len());
        prop_assert!(t.mask[..t.num_real].iter().all(|&b| b));
        for i in t.num_real..cfg.num_vertices {
            let row = t.row(i);
            prop_assert!((0..t.num_real).any(|j| t.row(j) == row));
            prop_assert!(t.positions[..t.num_real].contains(&t.positions[i]));
        }
        for (tok, &v) in t.order.iter().enumerate() {
            prop_assert_eq!(t.positions[tok], m.positions[v as usize]);
        }
        let mut rank = vec![0u32; m.positions.len()];
        for (tok, &v) in t.order.iter().enumerate() {
            rank[v as usize] = tok as u32;
        }
        let mut want: Vec<[u32; 2]> = topology::edges(&m.faces)
            .into_iter()
            .map(|[a, b]| {
                let (a, b) = (rank[a as usize], rank[b as usize]);
                [a.min(b), a.max(b)]
            })
            .collect();
        want.sort_unstable();
        prop_assert_eq!(&t.edges, &want);
        prop_assert!(t.edges.windows(2).all(|w| w[0] < w[1]));
    }
}
