//! The hard-surface set (`tests/fixtures/hard_surface/`, made by
//! `meshflow::geometry::hard_surface`): the files are the primitives, and generation at the
//! defaults gives each shape back flat, creased and with few faces.
//!
//! `MESHFLOW_WRITE_FIXTURES=1 cargo test --release --test hard_surface` rewrites the files.

mod common;

use std::path::PathBuf;

use meshflow::Mesh;
use meshflow::data::degrade::{Degradation, degrade};
use meshflow::eval::metrics::{CompareOptions, compare_meshes};
use meshflow::geometry::hard_surface::hard_surface_set;
use meshflow::geometry::sample::sample_surface;
use meshflow::io::{Limits, read_path, write_path};
use meshflow::pipeline::generate::{GenerateOptions, input_points};

fn dir() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/fixtures/hard_surface"
    ))
}

/// The 4,096 surface points of shape `k` (seeded by `k`), clean or with 1% noise.
fn points(mesh: &Mesh, k: usize, noise: f32) -> Vec<glam::Vec3> {
    let clean = sample_surface(mesh, 4096, k as u64).unwrap().points;
    let how = Degradation {
        noise,
        missing: 0.0,
    };
    if noise > 0.0 {
        degrade(&clean, &how, 1000 + k as u64)
    } else {
        clean
    }
}

#[test]
fn the_fixture_files_are_the_primitives() {
    let write = std::env::var_os("MESHFLOW_WRITE_FIXTURES").is_some();
    for (k, (name, mesh)) in hard_surface_set().into_iter().enumerate() {
        let files = [
            (dir().join(format!("{name}.obj")), mesh.clone()),
            (
                dir().join(format!("points/{name}.ply")),
                Mesh::from_points(points(&mesh, k, 0.0)),
            ),
            (
                dir().join(format!("points/{name}_noise1.ply")),
                Mesh::from_points(points(&mesh, k, 0.01)),
            ),
        ];
        for (path, expected) in files {
            if write {
                write_path(&expected, &path).unwrap();
            }
            let read = read_path(&path, &Limits::default()).unwrap();
            assert_eq!(read.faces, expected.faces, "{}", path.display());
            assert_eq!(read.positions.len(), expected.positions.len());
            for (a, b) in read.positions.iter().zip(&expected.positions) {
                assert!(a.distance(*b) < 1e-5, "{}: {a} vs {b}", path.display());
            }
        }
    }
}

/// The input points of each of `shapes` (the fixture files `points/{name}{suffix}.ply`:
/// suffix "" for the clean ones, "_noise1" for those with 1% noise).
fn inputs(shapes: &[(&str, Mesh)], suffix: &str) -> Vec<Vec<glam::Vec3>> {
    (shapes.iter())
        .map(|(name, _)| {
            let path = dir().join(format!("points/{name}{suffix}.ply"));
            read_path(&path, &Limits::default()).unwrap().positions
        })
        .collect()
}

/// Mean normal consistency and edge F-score of generation at the defaults over the clean
/// hard-surface inputs, with and without sharpening.
#[test]
fn sharpening_makes_the_hard_surface_set_flatter_and_sharper() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let shapes = hard_surface_set();
    let inputs = inputs(&shapes, "");
    let score = |opts: &GenerateOptions| {
        let out = generator.generate(&inputs, opts, &mut |_, _| true).unwrap();
        let (mut nc, mut ef1) = (0.0, 0.0);
        for (g, (_, truth)) in out.iter().zip(&shapes) {
            let t = &g.topology;
            assert_eq!((t.non_manifold_edges, t.inconsistent_winding_edges), (0, 0));
            let c = compare_meshes(&g.mesh, truth, &CompareOptions::default()).unwrap();
            nc += c.normal_consistency.unwrap() / shapes.len() as f64;
            ef1 += c.sharp.edge_f_score.f_score / shapes.len() as f64;
        }
        (nc, ef1)
    };
    let sharp = score(&GenerateOptions::default());
    let mut plain = GenerateOptions::default();
    plain.sharpen.enabled = false;
    let plain = score(&plain);
    assert!(sharp.0 > plain.0 + 0.02, "NC {sharp:?} vs {plain:?}");
    assert!(sharp.1 > plain.1 + 0.05, "EF1 {sharp:?} vs {plain:?}");
}

/// The clean box's file as a user runs it (`meshflow generate
/// tests/fixtures/hard_surface/points/box.ply`, the defaults, seed 0) comes back as its ground
/// truth: 8 vertices and 12 faces.
#[test]
fn the_clean_box_file_comes_back_as_eight_corners_and_twelve_faces() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let read = read_path(&dir().join("points/box.ply"), &Limits::default()).unwrap();
    let points = input_points(&read, 0).unwrap();
    let out = generator
        .generate(&[points], &GenerateOptions::default(), &mut |_, _| true)
        .unwrap();
    let mesh = &out[0].mesh;
    // 17 vertices and 30 faces before a vertex near two planar regions went onto their crease
    // line (2026-12-06): a seam of sliver faces along one edge.
    assert_eq!((mesh.positions.len(), mesh.faces.len()), (8, 12));
    let truth = &hard_surface_set()[0].1;
    let c = compare_meshes(mesh, truth, &CompareOptions::default()).unwrap();
    assert!(c.sharp.edge_f_score.f_score > 0.95, "{:?}", c.sharp);
}

/// Each clean file as a user runs it (`meshflow generate tests/fixtures/hard_surface/points/
/// NAME.ply`, the defaults, seed 0) comes back facing out, as its shape does: the L-bracket
/// came back inside out (extraction winds each piece the way the decoder's normals vote)
/// before generation turned every piece outward.
#[test]
fn the_clean_files_come_back_facing_out() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    // The table and the hollow box still come back crumpled, as the model makes them
    // (docs/experiments/2026-12-08-thin-walls.md): a face between the two sides of a wall is
    // nearest either, and which says nothing about how it faces.
    let shapes: Vec<(&str, Mesh)> = (hard_surface_set().into_iter())
        .filter(|(name, _)| !["table", "hollow_box"].contains(name))
        .collect();
    let inputs: Vec<Vec<glam::Vec3>> = (shapes.iter())
        .map(|(name, _)| {
            let path = dir().join(format!("points/{name}.ply"));
            input_points(&read_path(&path, &Limits::default()).unwrap(), 0).unwrap()
        })
        .collect();
    // One at a time, as the CLI runs one file: an input's candidates are seeded by its place
    // in the batch too.
    for (points, (name, truth)) in inputs.into_iter().zip(&shapes) {
        let out = generator
            .generate(&[points], &GenerateOptions::default(), &mut |_, _| true)
            .unwrap();
        let facing = facing(&out[0].mesh, truth);
        assert!(facing > 0.5, "{name}: facing {facing}");
    }
}

/// Mean edge F-score and faces per ground-truth face of generation at the defaults over the
/// hard-surface inputs with 1% noise (the fixture files).
#[test]
fn noisy_flat_faces_come_back_as_few_flat_faces() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let shapes = hard_surface_set();
    let inputs = inputs(&shapes, "_noise1");
    let out = generator
        .generate(&inputs, &GenerateOptions::default(), &mut |_, _| true)
        .unwrap();
    let (mut ef1, mut faces) = (0.0, 0.0);
    for (g, (_, truth)) in out.iter().zip(&shapes) {
        let t = &g.topology;
        assert_eq!((t.non_manifold_edges, t.inconsistent_winding_edges), (0, 0));
        // The report is the shipped mesh's, after sharpening removed the vertices it did not
        // need (some of these shapes lose a few).
        assert_eq!(
            (t.vertices, t.faces),
            (g.mesh.positions.len(), g.mesh.faces.len())
        );
        let c = compare_meshes(&g.mesh, truth, &CompareOptions::default()).unwrap();
        ef1 += c.sharp.edge_f_score.f_score / shapes.len() as f64;
        faces += g.mesh.faces.len() as f64 / truth.faces.len() as f64 / shapes.len() as f64;
    }
    // Measured (2026-12-06): EF1 0.22 and 6.9x the faces with each point's own plane, which
    // the noise tilts (a flat side came back as a dozen faces, creased between them); 0.33
    // and 5.3x with the planes of the input's planar regions; 0.39 and 5.5x with a vertex near
    // two or three regions placed where they meet; 0.43 and 4.7x with the points next to a
    // crease joining the face they lie on.
    assert!(ef1 > 0.41 && faces < 5.2, "EF1 {ef1}, {faces}x the faces");
}

#[test]
fn reach_brings_the_hard_surface_set_nearer_its_ground_truth() {
    // Where the model's mesh stops short of the input (a wedge's thin end, the L-bracket's
    // far end, the table's legs), sharpening's reach slides it out along the surface.
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let shapes = hard_surface_set();
    let inputs = inputs(&shapes, "");
    let chamfer = |reach_steps: usize| {
        let mut opts = GenerateOptions::default();
        opts.sharpen.reach_steps = reach_steps;
        let out = generator
            .generate(&inputs, &opts, &mut |_, _| true)
            .unwrap();
        (out.iter().zip(&shapes))
            .map(|(g, (_, truth))| {
                assert_manifold_unfolded(g);
                compare_meshes(&g.mesh, truth, &CompareOptions::default())
                    .unwrap()
                    .chamfer_x100
            })
            .collect::<Vec<f64>>()
    };
    let (without, with) = (chamfer(0), chamfer(1));
    let mean = |cd: &[f64]| cd.iter().sum::<f64>() / cd.len() as f64;
    let worst = |cd: &[f64]| cd.iter().copied().fold(0.0, f64::max);
    // Measured: CD x100 3.92 without, 3.42 with (per shape both ways: the L-bracket 6.20 ->
    // 3.84, the wedge 2.45 -> 2.92); the worst shape 7.46 -> 6.79. Since the candidates'
    // seeds were derived apart (2026-12-07): 3.89 -> 3.53 (the table 5.81 -> 3.95, the wedge
    // 2.91 -> 2.31), the worst shape the same mesh both ways (the hollow box, 8.22).
    assert!(
        mean(&with) < 0.95 * mean(&without) && worst(&with) <= worst(&without),
        "with {with:?}, without {without:?}"
    );
}

/// With `seed_gap` (off by default), vertices at the input points the surface misses are
/// completed into it, and the mesh stays manifold, consistently wound and without folds. One
/// candidate, so that the same draw is compared (among several, seeding can change which one
/// is kept). On this set the model leaves little out that a cluster of 1/32 of the input
/// holds: seeds land on three of the eight noisy shapes and the share of the input left
/// uncovered does not fall (measured 2026-12-07: 5.6% without, 6.2% with; at twelve
/// candidates, seeding every cluster had taken 6.1% to 5.1%). The gain is on artists' meshes
/// (docs/experiments/2026-12-07-seed-clusters.md). Held here: seeds are placed, and the
/// surface completed through them covers the input about as well.
#[test]
fn seeding_keeps_the_surface_sound() {
    let (models, device) = common::shipped_on_cpu();
    let generator = models.generator(&device);
    let shapes = hard_surface_set();
    let inputs = inputs(&shapes, "_noise1");
    let run = |seed_gap: f32| {
        let mut opts = GenerateOptions {
            samples: 1,
            ..GenerateOptions::default()
        };
        opts.complete.seed_gap = seed_gap;
        let out = generator
            .generate(&inputs, &opts, &mut |_, _| true)
            .unwrap();
        let seeded = out.iter().filter(|g| g.complete.seeded > 0).count();
        let uncovered = (out.iter().zip(&inputs))
            .map(|(g, points)| {
                assert_manifold_unfolded(g);
                uncovered_share(&g.mesh, points)
            })
            .sum::<f64>()
            / shapes.len() as f64;
        (uncovered, seeded)
    };
    let ((without, none), (with, seeded)) = (run(0.0), run(0.7));
    assert_eq!(none, 0);
    assert!(seeded >= 2, "{seeded} shapes seeded");
    assert!(
        with < 1.2 * without,
        "uncovered {with} with, {without} without"
    );
}

/// No non-manifold, inconsistently wound or folded edge in a generated mesh.
fn assert_manifold_unfolded(g: &meshflow::pipeline::generate::Generated) {
    let t = &g.topology;
    assert_eq!(
        (
            t.non_manifold_edges,
            t.inconsistent_winding_edges,
            t.folded_edges
        ),
        (0, 0, 0)
    );
}

/// How `mesh` faces against `truth`: the area-weighted mean cosine between each face's
/// normal and that of the face of `truth` nearest its centroid (1: the same side out; -1:
/// inside out).
fn facing(mesh: &Mesh, truth: &Mesh) -> f64 {
    use meshflow::geometry::triangle::point_triangle_distance;
    let normal = |m: &Mesh, f: usize| {
        let [a, b, c] = m.triangle(f).map(|v| v.as_dvec3());
        (b - a).cross(c - a)
    };
    let (mut sum, mut area) = (0.0, 0.0);
    for f in 0..mesh.faces.len() {
        let n = normal(mesh, f);
        let centre = mesh
            .triangle(f)
            .iter()
            .map(|v| v.as_dvec3())
            .sum::<glam::DVec3>()
            / 3.0;
        let nearest = (0..truth.faces.len())
            .min_by(|&x, &y| {
                let d = |g: usize| {
                    point_triangle_distance(centre, truth.triangle(g).map(|v| v.as_dvec3()))
                };
                d(x).total_cmp(&d(y))
            })
            .expect("the truth has faces");
        sum += n
            .normalize_or_zero()
            .dot(normal(truth, nearest).normalize_or_zero())
            * n.length();
        area += n.length();
    }
    sum / area.max(1e-300)
}

/// The share of `points` farther than two of their spacings from `mesh`'s faces.
fn uncovered_share(mesh: &Mesh, points: &[glam::Vec3]) -> f64 {
    let far = 2.0 * f64::from(meshflow::geometry::nearest::PointIndex::new(points).spacing());
    let distances = meshflow::geometry::triangle::distances_to_faces(mesh, points.iter().copied());
    distances.iter().filter(|&&d| d > far).count() as f64 / points.len() as f64
}
