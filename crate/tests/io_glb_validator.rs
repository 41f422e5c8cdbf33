//! Runs the Khronos glTF validator (through `tests/validate-gltf.mjs`) on GLBs from
//! `write_glb`. Needs Node.js and `npm ci` at the repository root.

mod common;

use std::path::PathBuf;
use std::process::Command;

use common::temp_dir;
use glam::Vec3;
use meshflow::Mesh;
use meshflow::geometry::primitives::{grid, icosphere};
use meshflow::io::write_glb;

#[test]
fn write_glb_output_passes_the_khronos_validator() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    assert!(
        root.join("node_modules/gltf-validator").is_dir(),
        "node_modules/gltf-validator is missing: run `npm ci` in {}",
        root.display()
    );
    let dir = temp_dir("glb-validate");
    let dir = dir.path();

    let mut sphere = icosphere(2);
    sphere.normals = sphere.positions.iter().map(|p| p.normalize()).collect();
    let points = Mesh::from_points(
        (0..100)
            .map(|i| Vec3::new(i as f32, (i * i) as f32 * 0.01, -1.0))
            .collect(),
    );
    let mut points_n = points.clone();
    points_n.normals = vec![Vec3::new(0.0, 3.0, 4.0); 100]; // not unit: write_glb renormalises
    let files = [
        ("icosphere_normals.glb", sphere),
        ("grid.glb", grid(4, 4)),
        ("points.glb", points),
        ("points_normals.glb", points_n),
    ];
    let mut paths = Vec::new();
    for (name, m) in &files {
        let p = dir.join(name);
        std::fs::write(&p, write_glb(m)).unwrap();
        paths.push(p);
    }
    let out = Command::new("node")
        .arg(root.join("tests/validate-gltf.mjs"))
        .args(&paths)
        .current_dir(&root)
        .output()
        .expect("could not run `node` (is Node.js installed?)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{stdout}{stderr}");
    assert!(
        out.status.success(),
        "glTF validator reported errors:\n{stdout}{stderr}"
    );
}
