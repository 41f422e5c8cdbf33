//! Write -> read round trips for the three writers (GLB, OBJ, PLY).

mod common;

use common::temp_dir;
use glam::Vec3;
use meshflow::Mesh;
use meshflow::geometry::primitives::{cube, grid, icosphere};
use meshflow::io::{
    Format, Limits, read_bytes, read_path, write_glb, write_obj, write_path, write_ply,
};
use proptest::prelude::*;

/// Deterministic unit normals for any mesh.
fn with_normals(mut m: Mesh) -> Mesh {
    m.normals = m
        .positions
        .iter()
        .map(|p| (*p + Vec3::new(0.1, 0.2, 0.3)).normalize())
        .collect();
    m
}

fn point_cloud() -> Mesh {
    Mesh::from_points(
        (0..50)
            .map(|i| {
                let t = i as f32 * 0.37;
                Vec3::new(t.sin(), t.cos() * 1e-3, -t * 123.456)
            })
            .collect(),
    )
}

fn meshes() -> Vec<(&'static str, Mesh)> {
    let mut v = vec![
        ("icosphere", icosphere(2)),
        ("grid", grid(4, 4)),
        ("cube", cube()),
        ("points", point_cloud()),
    ];
    let with: Vec<_> = v
        .iter()
        .map(|(n, m)| (*n, with_normals(m.clone())))
        .collect();
    v.extend(with);
    v
}

fn write(format: Format, m: &Mesh) -> Vec<u8> {
    match format {
        Format::Glb => write_glb(m),
        Format::Obj => write_obj(m).into_bytes(),
        Format::Ply => write_ply(m),
        _ => unreachable!(),
    }
}

fn assert_round_trip(format: Format, m: &Mesh) {
    let bytes = write(format, m);
    let back =
        read_bytes(&bytes, format, &Limits::default()).unwrap_or_else(|e| panic!("{format}: {e}"));
    back.validate().unwrap();
    let bits = |v: &[Vec3]| {
        v.iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        bits(&back.positions),
        bits(&m.positions),
        "{format} positions"
    );
    assert_eq!(back.faces, m.faces, "{format} faces");
    assert_eq!(bits(&back.normals), bits(&m.normals), "{format} normals");
}

#[test]
fn every_writer_round_trips_the_primitives() {
    for (name, m) in meshes() {
        for format in [Format::Glb, Format::Obj, Format::Ply] {
            eprintln!("{format} {name} normals={}", !m.normals.is_empty());
            assert_round_trip(format, &m);
        }
    }
}

#[test]
fn negative_zero_and_extreme_values_survive() {
    let m = Mesh::new(
        vec![
            Vec3::new(-0.0, f32::MAX, f32::MIN_POSITIVE),
            Vec3::new(1e-45, -f32::MAX, 0.1),
            Vec3::new(16777217.0, -3.4028235e38, 1.0 / 3.0),
        ],
        vec![[0, 1, 2], [2, 2, 2]],
    );
    for format in [Format::Glb, Format::Obj, Format::Ply] {
        assert_round_trip(format, &m);
    }
}

#[test]
fn write_glb_renormalises_and_drops_bad_normals() {
    let mut m = icosphere(1);
    m.normals = m.positions.iter().map(|p| *p * 3.0).collect();
    let back = read_bytes(&write_glb(&m), Format::Glb, &Limits::default()).unwrap();
    assert!(back.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
    m.normals[0] = Vec3::ZERO;
    let back = read_bytes(&write_glb(&m), Format::Glb, &Limits::default()).unwrap();
    assert!(back.normals.is_empty());
}

#[test]
fn write_path_and_read_path() {
    let dir = temp_dir("io-rt");
    let dir = dir.path();
    let m = with_normals(icosphere(1));
    for ext in ["glb", "obj", "ply", "GLB"] {
        let p = dir.join(format!("m.{ext}"));
        write_path(&m, &p).unwrap();
        let back = read_path(&p, &Limits::default()).unwrap();
        assert_eq!(back.positions, m.positions);
        assert_eq!(back.faces, m.faces);
    }
    // Unknown extension is a typed error; sniffing works without an extension.
    assert!(matches!(
        write_path(&m, &dir.join("m.stl")),
        Err(meshflow::io::WriteError::UnsupportedFormat { .. })
    ));
    let p = dir.join("noext");
    std::fs::write(&p, write_ply(&m)).unwrap();
    assert_eq!(read_path(&p, &Limits::default()).unwrap().faces, m.faces);
    std::fs::write(&p, write_glb(&m)).unwrap();
    assert_eq!(read_path(&p, &Limits::default()).unwrap().faces, m.faces);
    std::fs::write(&p, write_obj(&m)).unwrap();
    assert_eq!(read_path(&p, &Limits::default()).unwrap().faces, m.faces);
    // Writes replace the file whole and leave no temporary file beside it; a write that
    // cannot happen leaves nothing.
    let out = dir.join("again.glb");
    write_path(&m, &out).unwrap();
    write_path(&icosphere(0), &out).unwrap();
    assert_eq!(
        read_path(&out, &Limits::default()).unwrap().faces,
        icosphere(0).faces
    );
    let missing = dir.join("no-such-folder/m.glb");
    assert!(write_path(&m, &missing).is_err());
    let mut left: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        ["again.glb", "m.GLB", "m.glb", "m.obj", "m.ply", "noext"]
    );
}

#[test]
fn sniff_recognises_what_the_writers_produce() {
    let m = icosphere(1);
    assert_eq!(Format::sniff(&write_glb(&m)), Some(Format::Glb));
    assert_eq!(Format::sniff(&write_ply(&m)), Some(Format::Ply));
    assert_eq!(Format::sniff(write_obj(&m).as_bytes()), Some(Format::Obj));
    assert_eq!(Format::sniff(b"1 2 3\n4 5 6\n"), Some(Format::Points));
    assert_eq!(Format::sniff(b"{\"asset\":{}}"), Some(Format::Gltf));
    assert_eq!(Format::sniff(b"solid x\n"), Some(Format::Stl));
    assert_eq!(Format::sniff(&[0xff, 0xfe, 0x00, 0x01]), None);
    assert_eq!(Format::from_path("a/b.PtS".as_ref()), Some(Format::Points));
    assert_eq!(Format::from_path("a/b.gltf".as_ref()), Some(Format::Gltf));
    assert_eq!(Format::from_path("a/b".as_ref()), None);
}

fn finite() -> impl Strategy<Value = f32> {
    prop_oneof![
        -1e3f32..1e3,
        proptest::num::f32::NORMAL | proptest::num::f32::ZERO | proptest::num::f32::SUBNORMAL,
    ]
}

fn arb_mesh() -> impl Strategy<Value = Mesh> {
    (1usize..40, any::<bool>(), any::<bool>())
        .prop_flat_map(|(n, faces, normals)| {
            let pos = proptest::collection::vec((finite(), finite(), finite()), n);
            let nf = if faces { 0usize..60 } else { 0usize..1 };
            let fcs = proptest::collection::vec((0..n as u32, 0..n as u32, 0..n as u32), nf);
            let nn = if normals { n } else { 0 };
            let nrm = proptest::collection::vec((-1f32..1.0, -1f32..1.0, -1f32..1.0), nn);
            (pos, fcs, nrm)
        })
        .prop_map(|(pos, fcs, nrm)| {
            let mut m = Mesh::new(
                pos.into_iter()
                    .map(|(x, y, z)| Vec3::new(x, y, z))
                    .collect(),
                fcs.into_iter().map(|(a, b, c)| [a, b, c]).collect(),
            );
            m.normals = nrm
                .into_iter()
                .map(|(x, y, z)| Vec3::new(x, y, z).try_normalize().unwrap_or(Vec3::Z))
                .collect();
            m
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn random_meshes_round_trip(m in arb_mesh()) {
        for format in [Format::Glb, Format::Obj, Format::Ply] {
            assert_round_trip(format, &m);
        }
    }
}
