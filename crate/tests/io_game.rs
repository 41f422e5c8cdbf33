//! The game-asset readers (PMD, SPM, MD2, MD3, PIE, AC3D, ASE, IQM, MD5) and COLLADA: real
//! sample files, malformed inputs, and an ignored survey over the extracted packages.

use std::path::PathBuf;

use glam::Vec3;
use meshflow::geometry::mesh::Mesh;
use meshflow::io::{
    DAE_MAX_NODE_DEPTH, DAE_MAX_XML_ATTRIBUTES, DAE_MAX_XML_NODES, DaeInfo, Format, Limits,
    Location, ReadError, UpAxis, read_bytes, read_dae, read_path,
};

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/game")
}

/// Reads every file of a game format (`.pmd`, `.spm`, `.md2`, `.md3`, `.pie`, `.ac`, `.ase`,
/// `.iqm`, `.md5mesh`) or COLLADA (`.dae`) under `$MESHFLOW_GAME_DATA` (the packages
/// unpacked, with the members of their archives extracted) and prints, per format, how many
/// were read, how many of those enclose a positive / negative signed volume, the mean
/// agreement of stored normals with the faces, the failures counted by error kind, and the
/// first errors. `scripts/extract_meshes.py DIR` makes such a folder from the data cache:
/// `MESHFLOW_GAME_DATA=DIR cargo test -p meshflow --test io_game -- --ignored --nocapture`
#[test]
#[ignore]
fn survey_real_packages() {
    let root = std::env::var_os("MESHFLOW_GAME_DATA").expect("set MESHFLOW_GAME_DATA");
    let mut files = Vec::new();
    let mut stack = vec![PathBuf::from(root)];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if matches!(
                Format::from_path(&p),
                Some(
                    Format::Pmd
                        | Format::Spm
                        | Format::Md2
                        | Format::Md3
                        | Format::Pie
                        | Format::Ac3d
                        | Format::Dae
                        | Format::Ase
                        | Format::Iqm
                        | Format::Md5
                )
            ) {
                files.push(p);
            }
        }
    }
    files.sort();
    #[derive(Default)]
    struct Stats {
        ok: usize,
        bad: usize,
        positive: usize,
        negative: usize,
        agreement: Vec<f32>,
        kinds: std::collections::BTreeMap<String, usize>,
        errors: Vec<String>,
        inverted: Vec<String>,
        diagonals: Vec<f32>,
    }
    let mut stats: std::collections::BTreeMap<String, Stats> = Default::default();
    for p in &files {
        let f = Format::from_path(p).unwrap();
        let s = stats.entry(f.name().to_string()).or_default();
        match read_path(p, &Limits::default()) {
            Ok(m) => {
                m.validate()
                    .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
                s.ok += 1;
                let (lo, hi) = bbox(&m);
                s.diagonals.push((hi - lo).length());
                let v = signed_volume(&m);
                if v > 0.0 {
                    s.positive += 1;
                } else if v < 0.0 {
                    s.negative += 1;
                    s.inverted.push(p.display().to_string());
                }
                if !m.normals.is_empty() && !m.faces.is_empty() {
                    s.agreement.push(normal_agreement(&m));
                }
            }
            Err(e) => {
                s.bad += 1;
                let kind = format!("{e:?}");
                let kind = kind.split([' ', '{', '(']).next().unwrap_or("").to_string();
                *s.kinds.entry(kind).or_default() += 1;
                s.errors.push(format!("{}: {e}", p.display()));
            }
        }
    }
    for (f, s) in &stats {
        let mean = s.agreement.iter().sum::<f32>() / s.agreement.len().max(1) as f32;
        println!(
            "{f}: {} read, {} failed; volume > 0: {}, < 0: {}; normals agree {mean:.3} (mean of {})",
            s.ok,
            s.bad,
            s.positive,
            s.negative,
            s.agreement.len()
        );
        let mut d = s.diagonals.clone();
        d.sort_by(f32::total_cmp);
        if !d.is_empty() {
            let q = |f: f32| d[((d.len() - 1) as f32 * f) as usize];
            println!(
                "    bounding-box diagonal: min {:.3}, median {:.3}, max {:.3}",
                q(0.0),
                q(0.5),
                q(1.0)
            );
        }
        for (kind, n) in &s.kinds {
            println!("    {n} x {kind}");
        }
        for e in s.errors.iter().take(20) {
            println!("    {e}");
        }
        for p in s.inverted.iter().take(10) {
            println!("    volume < 0: {p}");
        }
    }
}

fn read_fixture(rel: &str) -> (Vec<u8>, Mesh) {
    let path = fixtures().join(rel);
    let bytes = std::fs::read(&path).unwrap();
    let format = Format::from_path(&path).unwrap();
    assert_eq!(
        Format::sniff(&bytes),
        Some(format),
        "{rel} is not sniffed as {format}"
    );
    let m = read_path(&path, &Limits::default()).unwrap_or_else(|e| panic!("{rel}: {e}"));
    m.validate().unwrap_or_else(|e| panic!("{rel}: {e}"));
    (bytes, m)
}

fn bbox(m: &Mesh) -> (Vec3, Vec3) {
    let lo = m
        .positions
        .iter()
        .fold(Vec3::splat(f32::INFINITY), |a, &p| a.min(p));
    let hi = m
        .positions
        .iter()
        .fold(Vec3::splat(f32::NEG_INFINITY), |a, &p| a.max(p));
    (lo, hi)
}

fn assert_near(a: Vec3, b: [f32; 3], what: &str) {
    assert!(
        (a - Vec3::from_array(b)).abs().max_element() < 1e-3,
        "{what}: {a} != {b:?}"
    );
}

/// The signed volume the faces enclose: positive when they wind counter-clockwise seen from
/// outside.
fn signed_volume(m: &Mesh) -> f32 {
    m.faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| m.positions[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// How many vertices no face uses.
fn unused(m: &Mesh) -> usize {
    let mut used = vec![false; m.positions.len()];
    for f in &m.faces {
        for &i in f {
            used[i as usize] = true;
        }
    }
    used.iter().filter(|u| !**u).count()
}

/// The mean cosine between the stored normals of each face's corners and the face's
/// geometric normal: near 1 when the normals are decoded right (and point outwards).
fn normal_agreement(m: &Mesh) -> f32 {
    let mut sum = 0.0;
    let mut n = 0;
    for f in &m.faces {
        let [a, b, c] = f.map(|i| m.positions[i as usize]);
        let g = (b - a).cross(c - a);
        if g.length() < 1e-9 {
            continue;
        }
        let g = g.normalize();
        for &i in f {
            sum += m.normals[i as usize].dot(g);
            n += 1;
        }
    }
    sum / n as f32
}

// Expected counts and bounding boxes come from a separate Python reading of the same layouts
// (header counts, and for PIE the POINTS/POLYGONS blocks), not from these readers.

#[test]
fn pmd_fixtures() {
    // (file, vertices, triangles, bbox min, bbox max); one UV set, then two.
    for (rel, nv, nf, lo, hi) in [
        (
            "pmd/pine15.pmd",
            71,
            44,
            [-5.4916, -0.1202, -5.4297],
            [5.348, 14.2432, 5.4857],
        ),
        (
            "pmd/spart_barracks_nature.pmd",
            94,
            56,
            [-10.4007, -5.9673, -8.3814],
            [10.5757, 10.554, 11.5559],
        ),
    ] {
        let (_, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert_eq!(m.normals.len(), nv, "{rel}: PMD normals are kept");
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
        assert_eq!(unused(&m), 0, "{rel}: every vertex is used");
        assert!(
            normal_agreement(&m) > 0.5,
            "{rel}: normals disagree with faces"
        );
    }
}

#[test]
fn spm_fixtures() {
    // (file, vertices, triangles, has normals); static with colours and 3 meshes (one with
    // u16 indices), static with 6 meshes, skinned with tangents.
    for (rel, nv, nf) in [
        ("spm/stklib_redFlowerBush_a_main.spm", 290, 220),
        ("spm/lamp_2.spm", 133, 104),
        ("spm/emule_HeadLight_1.spm", 82, 114),
    ] {
        let (bytes, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert_eq!(m.normals.len(), nv, "{rel}: the normals flag is set");
        // The header's bounding box (bytes 4..28) encloses the mesh.
        let f = |k: usize| f32::from_le_bytes(bytes[4 + 4 * k..8 + 4 * k].try_into().unwrap());
        let (lo, hi) = bbox(&m);
        let eps = Vec3::splat(1e-3);
        assert!(
            lo.cmpge(Vec3::new(f(0), f(1), f(2)) - eps).all(),
            "{rel}: {lo}"
        );
        assert!(
            hi.cmple(Vec3::new(f(3), f(4), f(5)) + eps).all(),
            "{rel}: {hi}"
        );
        assert!(
            normal_agreement(&m) > 0.5,
            "{rel}: normals disagree with faces"
        );
    }
}

#[test]
fn md2_fixtures() {
    // Frame 0 only: fireext3 has 30 frames.
    for (rel, nv, nf, lo, hi) in [
        (
            "md2/box1.md2",
            8,
            12,
            [-12.864, -12.864, -2.9852],
            [12.7631, 12.7631, 22.6419],
        ),
        (
            "md2/fireext3.md2",
            70,
            132,
            [-5.7325, -4.4408, 0.1058],
            [5.673, 7.5421, 36.7766],
        ),
    ] {
        let (_, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert!(m.normals.is_empty(), "{rel}: MD2 normals are not read");
        assert!(signed_volume(&m) > 0.0, "{rel}: faces wind clockwise");
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
        assert_eq!(unused(&m), 0, "{rel}: every vertex is used");
    }
}

#[test]
fn md3_fixtures() {
    // Frame 0 only, two surfaces each: eye has 9 frames.
    for (rel, nv, nf, lo, hi) in [
        (
            "md3/eye.md3",
            35,
            54,
            [-2.609375, -1.859375, 0.0],
            [5.21875, 2.125, 3.828125],
        ),
        (
            "md3/nailgunam.md3",
            84,
            62,
            [-15.40625, -16.09375, -10.03125],
            [15.40625, 11.5, 15.15625],
        ),
    ] {
        let (_, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert_eq!(m.normals.len(), nv, "{rel}: MD3 normals are decoded");
        assert!(signed_volume(&m) > 0.0, "{rel}: faces wind clockwise");
        assert!(
            normal_agreement(&m) > 0.5,
            "{rel}: normals disagree with faces"
        );
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
    }
}

#[test]
fn ac3d_fixtures() {
    for (rel, nv, nf, lo, hi) in [
        // two line surfaces (skipped), nested objects
        (
            "ac/factory.ac",
            41,
            52,
            [-40.0, 0.0, -19.5],
            [40.0, 26.0, 17.5],
        ),
        // three levels of objects placed by `loc`, `data` blocks
        (
            "ac/tuxcopter.ac",
            107,
            98,
            [-9.6764, -3.7003, -11.2167],
            [9.6775, 3.69, 13.0662],
        ),
        // CRLF line ends, flat
        (
            "ac/Ensign.ac",
            49,
            72,
            [-0.3073, -1.8823, 0.0],
            [2.3432, 0.9683, 0.0],
        ),
    ] {
        let (_, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert!(m.normals.is_empty(), "{rel}: AC3D has no normals");
        assert!(signed_volume(&m) >= 0.0, "{rel}: faces wind clockwise");
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
    }
}

#[test]
fn pie_fixtures() {
    for (rel, nv, nf, lo, hi) in [
        // PIE 2, animated-texture polygons (flags 4200)
        ("pie/fxgrdexp.pie", 4, 4, [-23., 1., 0.], [22., 87., 0.]),
        // PIE 2, two levels, CONNECTORS
        (
            "pie/fxtracer_twin.pie",
            8,
            4,
            [-11., 0., -7.],
            [11., 0., 7.],
        ),
        // PIE 3, two levels
        (
            "pie/factory_module2.pie",
            29,
            40,
            [62.5112, 0.0, -170.369],
            [173.334, 150.0, 164.942],
        ),
        // PIE 3, CRLF line ends, CONNECTORS
        (
            "pie/gnhair.pie",
            32,
            40,
            [-11.0, 0.0, -49.8236],
            [11.0, 17.0, -9.8236],
        ),
    ] {
        let (_, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
        assert_eq!(unused(&m), 0, "{rel}: every vertex is used");
        // The two effects are flat; the models enclose a positive volume.
        assert!(signed_volume(&m) >= 0.0, "{rel}: faces wind clockwise");
    }
}

#[test]
fn dae_fixtures() {
    // Blender exports, Z up, in metres; the battery's node moves it by -0.0333 along z, which
    // becomes y once Z up is converted to Y up: (x, y, z) -> (x, z, -y).
    for (rel, nv, nf, lo, hi) in [
        (
            "dae/anymal_c_battery.dae",
            8,
            12,
            [-0.2259, -0.0701, -0.0625],
            [0.2322, 0.004, 0.0625],
        ),
        // polylist of triangles
        (
            "dae/hyq_lowerleg.dae",
            207,
            414,
            [-0.0219, -0.0355, -0.023],
            [0.362, 0.0355, 0.023],
        ),
    ] {
        let (bytes, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert!(m.normals.is_empty(), "{rel}: COLLADA normals are not read");
        assert!(signed_volume(&m) > 0.0, "{rel}: faces wind clockwise");
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
        let (_, info) = read_dae(&bytes, &Limits::default()).unwrap();
        assert_eq!(
            info,
            DaeInfo {
                up_axis: UpAxis::Z,
                meter: 1.0
            },
            "{rel}"
        );
    }
}

#[test]
fn ase_fixtures() {
    for (rel, nv, nf, lo, hi) in [
        // 3ds Max export (`*MESH_FACE 0:`), one object, CRLF line ends
        (
            "ase/teledevice.ase",
            44,
            84,
            [-98.1005, 1.2927, 0.0],
            [-10.419, 88.4809, 125.6791],
        ),
        // Q3Map2 conversion (`*MESH_FACE 0` without a colon), six objects, CRLF
        (
            "ase/glvsh_woodbrdg.ase",
            24,
            12,
            [-264.0, -16.0, 0.0],
            [264.0, 16.0, 4.0],
        ),
    ] {
        let (_, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert!(m.normals.is_empty(), "{rel}: ASE normals are not read");
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
        assert_eq!(unused(&m), 0, "{rel}: every vertex is used");
    }
    // The vertices are in world space already: the cone's apex-to-base axis starts at the
    // node's `*TM_POS`, which is not applied a second time.
    let (_, m) = read_fixture("ase/teledevice.ase");
    assert_near(
        m.positions[0],
        [-68.5099, 58.8903, 0.0],
        "teledevice vertex 0",
    );
    assert!(signed_volume(&m) > 0.0, "teledevice: faces wind clockwise");
}

#[test]
fn iqm_fixtures() {
    for (rel, nv, nf, lo, hi, first) in [
        // two meshes
        (
            "iqm/door01.iqm",
            38,
            28,
            [-6.0, -0.7, -8.0],
            [6.0, 0.7, 8.0],
            [6.0, 0.7, 0.0],
        ),
        (
            "iqm/cap.iqm",
            74,
            80,
            [-0.76, -1.7367, 0.3621],
            [0.7677, -0.1888, 0.9434],
            [-0.598_243, -1.301_226, 0.362_087],
        ),
    ] {
        let (_, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert_eq!(m.normals.len(), nv, "{rel}: IQM normals are kept");
        assert!(
            normal_agreement(&m) > 0.5,
            "{rel}: normals disagree with faces"
        );
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
        assert_near(m.positions[0], first, rel);
    }
    let (_, m) = read_fixture("iqm/cap.iqm");
    assert!(signed_volume(&m) > 0.0, "cap: faces wind clockwise");
    // An animation file: frames, no meshes.
    assert!(matches!(
        read_path(&fixtures().join("iqm/door01_idle.iqm"), &Limits::default()),
        Err(ReadError::Empty {
            format: Format::Iqm
        })
    ));
}

#[test]
fn md5_fixtures() {
    // Expected positions come from a separate Python skinning of the same files (w = -sqrt).
    for (rel, nv, nf, lo, hi, first) in [
        // 4 joints, 2 meshes, 16 vertices with two weights
        (
            "md5/flag.md5mesh",
            198,
            264,
            [-0.221, -0.2326, -0.112],
            [8.262, 0.2328, 14.7365],
            [0.11193, 0.11192, 0.60636],
        ),
        // 1 rotated joint: the barrel stands on z = 0.0228
        (
            "md5/barrel01.md5mesh",
            36,
            32,
            [-1.0716, -1.0716, 0.0228],
            [1.0716, 1.0716, 3.0421],
            [0.0, 0.0, 0.02285],
        ),
    ] {
        let (_, m) = read_fixture(rel);
        assert_eq!((m.positions.len(), m.faces.len()), (nv, nf), "{rel}");
        assert!(m.normals.is_empty(), "{rel}: MD5 has no normals");
        let (a, b) = bbox(&m);
        assert_near(a, lo, rel);
        assert_near(b, hi, rel);
        assert_near(m.positions[0], first, rel);
    }
    let (_, m) = read_fixture("md5/barrel01.md5mesh");
    assert!(signed_volume(&m) > 0.0, "barrel: faces wind clockwise");
}

// ---------------------------------------------------------------------------------------------
// Malformed inputs.

fn check(format: Format, bytes: &[u8], what: &str, ok: fn(&ReadError) -> bool) -> usize {
    match read_bytes(bytes, format, &Limits::default()) {
        Ok(m) => panic!(
            "{format} case `{what}` was accepted: {} vertices",
            m.positions.len()
        ),
        Err(e) => {
            assert!(ok(&e), "{format} case `{what}`: unexpected error {e:?}");
            assert!(!e.to_string().trim().is_empty());
            eprintln!("{format} {what}: {e}");
        }
    }
    1
}

macro_rules! table {
    ($format:expr, $( $what:literal, $bytes:expr => $pat:pat ),+ $(,)?) => {{
        let mut n = 0;
        $( n += check($format, &Vec::<u8>::from($bytes), $what, |e| matches!(e, $pat)); )+
        n
    }};
}

fn put_u32(b: &mut [u8], at: usize, v: u32) -> Vec<u8> {
    b[at..at + 4].copy_from_slice(&v.to_le_bytes());
    b.to_vec()
}

fn put_f32(b: &mut [u8], at: usize, v: f32) -> Vec<u8> {
    put_u32(b, at, v.to_bits())
}

fn fixture(rel: &str) -> Vec<u8> {
    std::fs::read(fixtures().join(rel)).unwrap()
}

#[test]
fn pmd_bad_inputs() {
    // pine15: 71 vertices of 52 bytes from byte 20; faces (u32 count) at 20 + 71 * 52 = 3712.
    let good = fixture("pmd/pine15.pmd");
    let g = || good.clone();
    let faces_at = 20 + 71 * 52;
    let n = table!(Format::Pmd,
        "empty", Vec::new() => ReadError::Truncated { offset: 0, .. },
        "magic only", b"PSMD".to_vec() => ReadError::Truncated { .. },
        "wrong magic", { let mut b = g(); b[0] = b'X'; b } => ReadError::Malformed { location: Location::Byte(0), .. },
        "version 5", put_u32(&mut g(), 4, 5) => ReadError::Unsupported { .. },
        "data size past the end", put_u32(&mut g(), 8, 1 << 20) => ReadError::Truncated { .. },
        "cut in the vertices", { let mut b = g(); b.truncate(1000); put_u32(&mut b, 8, 988) } => ReadError::Truncated { .. },
        "cut in the faces", { let mut b = g(); b.truncate(faces_at + 10); let s = b.len() as u32 - 12; put_u32(&mut b, 8, s) } => ReadError::Truncated { .. },
        "cut before the face count", { let mut b = g(); b.truncate(faces_at); let s = b.len() as u32 - 12; put_u32(&mut b, 8, s) } => ReadError::Truncated { .. },
        "vertex count 0xFFFFFFFF", put_u32(&mut g(), 12, u32::MAX) => ReadError::TooLarge { .. },
        "vertex count past the data", put_u32(&mut g(), 12, 1_000_000) => ReadError::Truncated { .. },
        "UV-set count 0xFFFFFFFF", put_u32(&mut g(), 16, u32::MAX) => ReadError::Truncated { .. },
        "face count 0xFFFFFFFF", put_u32(&mut g(), faces_at, u32::MAX) => ReadError::TooLarge { .. },
        "face count past the data", put_u32(&mut g(), faces_at, 100_000) => ReadError::Truncated { .. },
        "index out of range", { let mut b = g(); b[faces_at + 4..faces_at + 6].copy_from_slice(&71u16.to_le_bytes()); b } => ReadError::IndexOutOfRange { index: 71, count: 71, location: Location::Byte(3716), .. },
        "NaN coordinate", put_f32(&mut g(), 20 + 52 * 3 + 4, f32::NAN) => ReadError::NonFinite { location: Location::Byte(176), .. },
        "infinite coordinate", put_f32(&mut g(), 20, f32::INFINITY) => ReadError::NonFinite { .. },
        "no vertices", { let mut b = b"PSMD".to_vec(); for v in [4u32, 12, 0, 1, 0] { b.extend(v.to_le_bytes()); } b } => ReadError::Empty { .. },
    );
    assert!(n >= 10);
    // A NaN normal is not an error: all normals are dropped.
    let m = read_bytes(
        &put_f32(&mut g(), 32, f32::NAN),
        Format::Pmd,
        &Limits::default(),
    )
    .unwrap();
    assert!(m.normals.is_empty());
}

#[test]
fn spm_bad_inputs() {
    // box of the layout: header 28, u16 textures, names, u16 objects, u16 meshes, then meshes.
    let good = fixture("spm/lamp_2.spm");
    let g = || good.clone();
    let tiny = |kind: u8, flags: u8, body: &[u8]| {
        let mut b = vec![b'S', b'P', kind, flags];
        b.extend([0u8; 24]);
        b.extend(1u16.to_le_bytes()); // one material, no textures
        b.extend([0u8, 0u8]);
        b.extend(1u16.to_le_bytes()); // one object
        b.extend(1u16.to_le_bytes()); // one mesh
        b.extend(body);
        b
    };
    // one static mesh, positions only: 3 vertices, 3 u8 indices.
    let mesh = |nv: u32, ni: u32, material: u16, verts: &[[f32; 3]], idx: &[u8]| {
        let mut b = Vec::new();
        b.extend(nv.to_le_bytes());
        b.extend(ni.to_le_bytes());
        b.extend(material.to_le_bytes());
        for v in verts {
            for c in v {
                b.extend(c.to_le_bytes());
            }
        }
        b.extend(idx);
        b
    };
    let tri = [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]];
    assert_eq!(
        read_bytes(
            &tiny(0x0a, 0, &mesh(3, 3, 0, &tri, &[0, 1, 2])),
            Format::Spm,
            &Limits::default()
        )
        .unwrap()
        .faces,
        vec![[0, 1, 2]]
    );
    // The first mesh header of tiny(): 28 + 2 + 2 + 2 + 2 = 36.
    let n = table!(Format::Spm,
        "empty", Vec::new() => ReadError::Truncated { offset: 0, .. },
        "wrong magic", { let mut b = g(); b[1] = b'Q'; b } => ReadError::Malformed { location: Location::Byte(0), .. },
        "version 2", { let mut b = g(); b[2] = 0x12; b } => ReadError::Unsupported { .. },
        "type 5", { let mut b = g(); b[2] = 0x0d; b } => ReadError::Unsupported { .. },
        "cut in the header", g()[..20].to_vec() => ReadError::Truncated { .. },
        "cut in the texture names", g()[..40].to_vec() => ReadError::Truncated { .. },
        "cut in the vertices", g()[..1500].to_vec() => ReadError::Truncated { .. },
        "cut in the indices", g()[..g().len() - 5].to_vec() => ReadError::Truncated { .. },
        "vertex count 0xFFFFFFFF", tiny(0x0a, 0, &mesh(u32::MAX, 3, 0, &tri, &[0, 1, 2])) => ReadError::TooLarge { .. },
        "vertex count past the end", tiny(0x0a, 0, &mesh(1000, 3, 0, &tri, &[0, 1, 2])) => ReadError::Truncated { .. },
        "index count 0xFFFFFFFF", tiny(0x0a, 0, &mesh(3, 0xFFFF_FFFF, 0, &tri, &[0, 1, 2])) => ReadError::TooLarge { .. },
        "index count not a multiple of 3", tiny(0x0a, 0, &mesh(3, 4, 0, &tri, &[0, 1, 2, 0])) => ReadError::Malformed { location: Location::Byte(40), .. },
        "material out of range", tiny(0x0a, 0, &mesh(3, 3, 1, &tri, &[0, 1, 2])) => ReadError::IndexOutOfRange { what: "materials", index: 1, count: 1, .. },
        "index out of range", tiny(0x0a, 0, &mesh(3, 3, 0, &tri, &[0, 1, 3])) => ReadError::IndexOutOfRange { what: "vertices", index: 3, count: 3, location: Location::Byte(84), .. },
        "NaN coordinate", tiny(0x0a, 0, &mesh(3, 3, 0, &[[0., 0., 0.], [f32::NAN, 0., 0.], [0., 1., 0.]], &[0, 1, 2])) => ReadError::NonFinite { location: Location::Byte(58), .. },
        "no vertices", tiny(0x0a, 0, &mesh(0, 0, 0, &[], &[])) => ReadError::Empty { .. },
        "skinned but no joints", tiny(0x09, 0, &mesh(3, 3, 0, &tri, &[0, 1, 2])) => ReadError::Truncated { .. },
    );
    assert!(n >= 10);
}

#[test]
fn md2_bad_inputs() {
    // box1: 8 vertices, 12 triangles; header fields at 4 + 4k.
    let good = fixture("md2/box1.md2");
    let g = || good.clone();
    let field =
        |k: usize| i32::from_le_bytes(good[4 + 4 * k..8 + 4 * k].try_into().unwrap()) as usize;
    let (tris_at, frames_at) = (field(12), field(13));
    let n = table!(Format::Md2,
        "empty", Vec::new() => ReadError::Truncated { offset: 0, .. },
        "wrong magic", { let mut b = g(); b[3] = b'3'; b } => ReadError::Malformed { location: Location::Byte(0), .. },
        "version 7", put_u32(&mut g(), 4, 7) => ReadError::Unsupported { .. },
        "cut in the header", g()[..40].to_vec() => ReadError::Truncated { .. },
        "cut after the header", g()[..100].to_vec() => ReadError::Truncated { .. },
        "cut one byte short", g()[..g().len() - 1].to_vec() => ReadError::Truncated { expected: 1, .. },
        "negative vertex count", put_u32(&mut g(), 24, -1i32 as u32) => ReadError::Malformed { location: Location::Byte(24), .. },
        "vertex count 0x7FFFFFFF", put_u32(&mut g(), 24, i32::MAX as u32) => ReadError::TooLarge { .. },
        "triangle count 0x7FFFFFFF", put_u32(&mut g(), 32, i32::MAX as u32) => ReadError::TooLarge { .. },
        "triangles past the end", put_u32(&mut g(), 32, 100_000) => ReadError::Truncated { .. },
        "frame offset past the end", put_u32(&mut g(), 56, 1 << 20) => ReadError::Truncated { .. },
        "frame offset in the header", put_u32(&mut g(), 56, 8) => ReadError::Malformed { location: Location::Byte(56), .. },
        "frame size too small", put_u32(&mut g(), 16, 40) => ReadError::Malformed { location: Location::Byte(16), .. },
        "no frames", put_u32(&mut g(), 40, 0) => ReadError::Malformed { .. },
        "index out of range", { let mut b = g(); b[tris_at + 2..tris_at + 4].copy_from_slice(&8u16.to_le_bytes()); b } => ReadError::IndexOutOfRange { index: 8, count: 8, .. },
        "NaN scale", put_f32(&mut g(), frames_at + 4, f32::NAN) => ReadError::NonFinite { .. },
        "infinite translation", put_f32(&mut g(), frames_at + 12, f32::NEG_INFINITY) => ReadError::NonFinite { .. },
        "no vertices", put_u32(&mut g(), 24, 0) => ReadError::Empty { .. },
    );
    assert!(n >= 10);
}

#[test]
fn pie_bad_inputs() {
    let head = "PIE 3\nTYPE 10200\nTEXTURE 0 page.png 0 0\nLEVELS 1\nLEVEL 1\n";
    let pts = "POINTS 3\n 0 0 0\n 1 0 0\n 0 1 0\n";
    let good = format!("{head}{pts}POLYGONS 1\n 200 3 0 1 2 0 0 1 0 0 1\n");
    assert_eq!(
        read_bytes(good.as_bytes(), Format::Pie, &Limits::default())
            .unwrap()
            .faces,
        vec![[0, 1, 2]]
    );
    let n = table!(Format::Pie,
        "empty", "" => ReadError::Empty { .. },
        "bad utf-8", b"PIE 3\nTYPE \xff\n".to_vec() => ReadError::InvalidUtf8 { offset: 11, .. },
        "no header", format!("{pts}") => ReadError::Malformed { location: Location::Line(1), .. },
        "version 9", "PIE 9\n" => ReadError::Unsupported { .. },
        "bad version", "PIE x\n" => ReadError::Malformed { .. },
        "cut in the points", format!("{head}POINTS 3\n 0 0 0\n 1 0") => ReadError::Truncated { .. },
        "cut in the polygons", format!("{head}{pts}POLYGONS 2\n 200 3 0 1 2 0 0 1 0 0 1\n 200 3 0") => ReadError::Truncated { .. },
        "cut in the texture coordinates", format!("{head}{pts}POLYGONS 1\n 200 3 0 1 2 0 0 1") => ReadError::Truncated { .. },
        "cut before POLYGONS", format!("{head}{pts}") => ReadError::Malformed { location: Location::Line(4), .. },
        "point count 0xFFFFFFFF", format!("{head}POINTS 4294967295\n") => ReadError::TooLarge { .. },
        "point count u64::MAX", format!("{head}POINTS 18446744073709551615\n") => ReadError::TooLarge { .. },
        "polygon count 0xFFFFFFFF", format!("{head}{pts}POLYGONS 4294967295\n") => ReadError::TooLarge { .. },
        "negative point count", format!("{head}POINTS -3\n") => ReadError::Malformed { location: Location::Line(6), .. },
        "bad coordinate", format!("{head}POINTS 3\n 0 0 0\n 1 x 0\n 0 1 0\n") => ReadError::Malformed { location: Location::Line(8), .. },
        "NaN coordinate", format!("{head}POINTS 3\n 0 0 0\n 1 NaN 0\n 0 1 0\n") => ReadError::NonFinite { location: Location::Line(8), .. },
        "overflowing coordinate", format!("{head}POINTS 3\n 0 0 0\n 1 1e40 0\n 0 1 0\n") => ReadError::NonFinite { .. },
        "bad flags", format!("{head}{pts}POLYGONS 1\n 2g0 3 0 1 2 0 0 1 0 0 1\n") => ReadError::Malformed { location: Location::Line(11), .. },
        "bad texture coordinate", format!("{head}{pts}POLYGONS 1\n 200 3 0 1 2 0 0 1 z 0 1\n") => ReadError::Malformed { location: Location::Line(11), .. },
        "too many texture coordinates", format!("{head}{pts}POLYGONS 1\n 200 3 0 1 2 0 0 1 0 0 1 7\n") => ReadError::Malformed { location: Location::Line(11), .. },
        "index out of range", format!("{head}{pts}POLYGONS 1\n 200 3 0 1 3 0 0 1 0 0 1\n") => ReadError::IndexOutOfRange { index: 3, count: 3, location: Location::Line(11), .. },
        "negative index", format!("{head}{pts}POLYGONS 1\n 200 3 0 -1 2 0 0 1 0 0 1\n") => ReadError::Malformed { .. },
        "two corners", format!("{head}{pts}POLYGONS 1\n 200 2 0 1 0 0 1 0\n") => ReadError::Malformed { .. },
        "level out of order", format!("PIE 3\nLEVELS 2\nLEVEL 2\n{pts}") => ReadError::Malformed { location: Location::Line(3), .. },
        "missing level", format!("PIE 3\nLEVELS 2\nLEVEL 1\n{pts}POLYGONS 0\n") => ReadError::Malformed { location: Location::Line(2), .. },
        "POINTS outside a level", format!("PIE 3\n{pts}") => ReadError::Malformed { .. },
        "no points", format!("{head}POINTS 0\nPOLYGONS 0\n") => ReadError::Empty { .. },
    );
    assert!(n >= 10);
}

#[test]
fn md3_bad_inputs() {
    // eye: header fields at 72 + 4k; surface 1 at 612 (fields at 680 + 4k, 20 vertices,
    // triangles at 788), surface 2 at 2772; the file ends at 4412.
    let good = fixture("md3/eye.md3");
    let g = || good.clone();
    let n = table!(Format::Md3,
        "empty", Vec::new() => ReadError::Truncated { offset: 0, .. },
        "wrong magic", { let mut b = g(); b[3] = b'2'; b } => ReadError::Malformed { location: Location::Byte(0), .. },
        "version 16", put_u32(&mut g(), 4, 16) => ReadError::Unsupported { .. },
        "cut in the header", g()[..50].to_vec() => ReadError::Truncated { .. },
        "cut one byte short", g()[..g().len() - 1].to_vec() => ReadError::Truncated { expected: 1, .. },
        "negative surface count", put_u32(&mut g(), 84, -1i32 as u32) => ReadError::Malformed { location: Location::Byte(84), .. },
        "surface count past the end", put_u32(&mut g(), 84, 1000) => ReadError::Truncated { .. },
        "surface offset in the header", put_u32(&mut g(), 100, 8) => ReadError::Malformed { location: Location::Byte(100), .. },
        "surface offset past the end", put_u32(&mut g(), 100, 1 << 20) => ReadError::Truncated { .. },
        "surface without magic", { let mut b = g(); b[612] = b'X'; b } => ReadError::Malformed { location: Location::Byte(612), .. },
        "negative vertex count", put_u32(&mut g(), 692, -5i32 as u32) => ReadError::Malformed { location: Location::Byte(692), .. },
        "vertex count 0x7FFFFFFF", put_u32(&mut g(), 692, i32::MAX as u32) => ReadError::TooLarge { .. },
        "triangle count 0x7FFFFFFF", put_u32(&mut g(), 696, i32::MAX as u32) => ReadError::TooLarge { .. },
        "triangles past the end", put_u32(&mut g(), 696, 100_000) => ReadError::Truncated { .. },
        "vertex offset past the end", put_u32(&mut g(), 712, 1 << 20) => ReadError::Truncated { .. },
        "triangle offset in the surface header", put_u32(&mut g(), 700, 4) => ReadError::Malformed { location: Location::Byte(700), .. },
        "surface end offset 0", put_u32(&mut g(), 716, 0) => ReadError::Malformed { location: Location::Byte(716), .. },
        "surface without frames", put_u32(&mut g(), 684, 0) => ReadError::Malformed { location: Location::Byte(684), .. },
        "index out of range", put_u32(&mut g(), 792, 20) => ReadError::IndexOutOfRange { index: 20, count: 20, location: Location::Byte(792), .. },
        "negative index", put_u32(&mut g(), 788, -1i32 as u32) => ReadError::IndexOutOfRange { index: -1, .. },
        "no surfaces", put_u32(&mut g(), 84, 0) => ReadError::Empty { .. },
    );
    assert!(n >= 10);
    let small = Limits {
        max_vertices: 30,
        ..Limits::default()
    };
    assert!(matches!(
        read_bytes(&good, Format::Md3, &small),
        Err(ReadError::TooLarge { value: 35, .. })
    ));
}

#[test]
fn ac3d_bad_inputs() {
    let head = "AC3Db\nMATERIAL \"m\" rgb 1 1 1  amb 0 0 0  emis 0 0 0  spec 0 0 0  shi 0  trans 0\nOBJECT world\nkids 1\nOBJECT poly\n";
    let verts = "numvert 3\n0 0 0\n1 0 0\n0 1 0\n";
    let surf = "numsurf 1\nSURF 0x10\nmat 0\nrefs 3\n0 0 0\n1 1 0\n2 0 1\n";
    let good = format!("{head}{verts}{surf}kids 0\n");
    assert_eq!(
        read_bytes(good.as_bytes(), Format::Ac3d, &Limits::default())
            .unwrap()
            .faces,
        vec![[0, 1, 2]]
    );
    // Objects nested one deeper than allowed.
    let deep = {
        let mut s = String::from("AC3Db\n");
        for _ in 0..=meshflow::io::AC3D_MAX_DEPTH {
            s.push_str("OBJECT group\nkids 1\n");
        }
        s
    };
    let n = table!(Format::Ac3d,
        "empty", "" => ReadError::Empty { .. },
        "no header", format!("OBJECT world\nkids 0\n") => ReadError::Malformed { location: Location::Line(1), .. },
        "version c", "AC3Dc\nOBJECT world\nkids 0\n" => ReadError::Unsupported { .. },
        "junk outside an object", "AC3Db\nhello\n" => ReadError::Malformed { location: Location::Line(2), .. },
        "cut in the vertices", format!("{head}numvert 3\n0 0 0\n1 0") => ReadError::Malformed { location: Location::Line(8), .. },
        "cut before kids", format!("{head}{verts}") => ReadError::Truncated { .. },
        "fewer kids than declared", format!("AC3Db\nOBJECT world\nkids 2\nOBJECT poly\n{verts}{surf}kids 0\n") => ReadError::Truncated { .. },
        "cut in the refs", format!("{head}{verts}numsurf 1\nSURF 0x10\nrefs 3\n0 0 0\n") => ReadError::Truncated { .. },
        "data longer than the file", format!("{head}data 1000\nabc\n") => ReadError::Truncated { .. },
        "vertex count u64::MAX", format!("{head}numvert 18446744073709551615\n") => ReadError::TooLarge { .. },
        "negative vertex count", format!("{head}numvert -3\n") => ReadError::Malformed { location: Location::Line(6), .. },
        "bad coordinate", format!("{head}numvert 3\n0 0 0\n1 x 0\n0 1 0\n") => ReadError::Malformed { location: Location::Line(8), .. },
        "NaN coordinate", format!("{head}numvert 3\n0 0 0\n1 NaN 0\n0 1 0\n") => ReadError::NonFinite { location: Location::Line(8), .. },
        "overflowing coordinate", format!("{head}numvert 3\n0 0 0\n1 1e39 0\n0 1 0\n") => ReadError::NonFinite { .. },
        "infinite loc", format!("{head}loc inf 0 0\n{verts}kids 0\n") => ReadError::NonFinite { location: Location::Line(6), .. },
        "bad rot", format!("{head}rot 1 0 0 0 1 0 0 0\n") => ReadError::Malformed { .. },
        "bad flags", format!("{head}{verts}numsurf 1\nSURF 0xZZ\nrefs 0\nkids 0\n") => ReadError::Malformed { location: Location::Line(11), .. },
        "unknown surface type", format!("{head}{verts}numsurf 1\nSURF 0x13\nrefs 0\nkids 0\n") => ReadError::Malformed { location: Location::Line(11), .. },
        "SURF missing", format!("{head}{verts}numsurf 1\nrefs 0\nkids 0\n") => ReadError::Malformed { location: Location::Line(11), .. },
        "index out of range", format!("{head}{verts}numsurf 1\nSURF 0x10\nrefs 3\n0 0 0\n1 0 0\n3 0 0\nkids 0\n") => ReadError::IndexOutOfRange { index: 3, count: 3, location: Location::Line(15), .. },
        "refs before numvert", format!("{head}{surf}{verts}kids 0\n") => ReadError::IndexOutOfRange { count: 0, .. },
        "negative index", format!("{head}{verts}numsurf 1\nSURF 0x10\nrefs 3\n0 0 0\n-1 0 0\n2 0 0\nkids 0\n") => ReadError::Malformed { location: Location::Line(14), .. },
        "missing texture coordinate", format!("{head}{verts}numsurf 1\nSURF 0x10\nrefs 3\n0 0 0\n1 0\n2 0 0\nkids 0\n") => ReadError::Malformed { location: Location::Line(14), .. },
        "second numvert", format!("{head}{verts}{verts}kids 0\n") => ReadError::Malformed { location: Location::Line(10), .. },
        "child is not an OBJECT", format!("AC3Db\nOBJECT world\nkids 1\nnumvert 0\n") => ReadError::Malformed { location: Location::Line(4), .. },
        "nested too deep", deep => ReadError::TooLarge { what: "object nesting depth", .. },
        "no vertices", "AC3Db\nOBJECT world\nkids 0\n" => ReadError::Empty { .. },
    );
    assert!(n >= 10);
}

#[test]
fn sniffing_and_extensions() {
    for (name, f) in [
        ("a.PMD", Format::Pmd),
        ("a.spm", Format::Spm),
        ("a.md2", Format::Md2),
        ("a.MD3", Format::Md3),
        ("a.pie", Format::Pie),
        ("a.ac", Format::Ac3d),
        ("a.DAE", Format::Dae),
        ("a.ase", Format::Ase),
        ("a.iqm", Format::Iqm),
        ("a.md5mesh", Format::Md5),
    ] {
        assert_eq!(Format::from_path(std::path::Path::new(name)), Some(f));
        assert!(Format::ALL.contains(&f));
    }
    assert_eq!(Format::sniff(b"PIE 2\nTYPE 200\n"), Some(Format::Pie));
    assert_eq!(Format::sniff(b"IDP3\x0f\0\0\0"), Some(Format::Md3));
    assert_eq!(
        Format::sniff(b"AC3Db\r\nOBJECT world\r\n"),
        Some(Format::Ac3d)
    );
    assert_eq!(Format::sniff(b"SP\x0a\x01"), Some(Format::Spm));
    assert_eq!(
        Format::sniff(b"INTERQUAKEMODEL\0\x02\0\0\0"),
        Some(Format::Iqm)
    );
    assert_eq!(Format::sniff(b"MD5Version 10\n"), Some(Format::Md5));
    assert_eq!(
        Format::sniff(b"*3DSMAX_ASCIIEXPORT\t200\r\n"),
        Some(Format::Ase)
    );
    assert_eq!(
        Format::sniff(b"\xef\xbb\xbf<?xml version=\"1.0\"?>\n<COLLADA version=\"1.4.1\">"),
        Some(Format::Dae)
    );
    assert_eq!(Format::sniff(b"<?xml version=\"1.0\"?>\n<svg/>"), None);
    assert_eq!(Format::sniff(b"SP\x42\x01"), None);
}

/// A small COLLADA document: one quad (a polylist) and one triangle (a triangles element)
/// over four positions, placed by one node; `patches` are (from, to) text replacements.
fn dae_doc(patches: &[(&str, &str)]) -> String {
    let mut doc = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="g"><mesh>
      <source id="pos">
        <float_array id="arr" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
        <technique_common><accessor source="#arr" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
      <polylist count="1">
        <input semantic="VERTEX" source="#v" offset="0"/><input semantic="NORMAL" source="#v" offset="1"/>
        <vcount>4</vcount>
        <p>0 0 1 0 2 0 3 0</p>
      </polylist>
      <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 2 1</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_nodes><node id="lib"><instance_geometry url="#g"/></node></library_nodes>
  <library_visual_scenes><visual_scene id="s">
    <node id="n"><matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url="#g"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"##
    .to_string();
    for (from, to) in patches {
        assert!(doc.contains(from), "patch `{from}` does not apply");
        doc = doc.replacen(from, to, 1);
    }
    doc
}

#[test]
fn dae_bad_inputs() {
    let good = dae_doc(&[]);
    let m = read_bytes(good.as_bytes(), Format::Dae, &Limits::default()).unwrap();
    assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3], [0, 2, 1]]);
    let node = "<node id=\"n\"><matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url=\"#g\"/></node>";
    // Nodes nested one deeper than allowed, and a chain of shared library nodes that doubles
    // at every level (2^30 instances from 31 nodes).
    let deep = format!(
        "{}<instance_geometry url=\"#g\"/>{}",
        "<node>".repeat(DAE_MAX_NODE_DEPTH + 1),
        "</node>".repeat(DAE_MAX_NODE_DEPTH + 1)
    );
    let sharing: String = (0..30)
        .map(|i| format!("<node id=\"d{i}\"><instance_node url=\"#d{0}\"/><instance_node url=\"#d{0}\"/></node>", i + 1))
        .collect::<String>()
        + "<node id=\"d30\"/>";
    let n = table!(Format::Dae,
        "empty", "" => ReadError::Empty { .. },
        "bad utf-8", b"<COLLADA>\xff</COLLADA>".to_vec() => ReadError::InvalidUtf8 { offset: 9, .. },
        "not XML", "hello" => ReadError::Malformed { location: Location::Line(1), .. },
        "cut short", good[..good.len() / 2].to_string() => ReadError::Malformed { .. },
        "another root", "<?xml version=\"1.0\"?>\n<scene/>\n" => ReadError::Malformed { location: Location::Line(2), .. },
        "version 2", dae_doc(&[("version=\"1.4.1\"", "version=\"2.0\"")]) => ReadError::Unsupported { .. },
        "DTD", format!("<!DOCTYPE COLLADA [<!ENTITY a \"b\">]>{good}") => ReadError::Malformed { .. },
        "unknown up axis", dae_doc(&[("Y_UP", "W_UP")]) => ReadError::Malformed { location: Location::Line(3), .. },
        "zero unit", dae_doc(&[("meter=\"1\"", "meter=\"0\"")]) => ReadError::Malformed { location: Location::Line(3), .. },
        "missing geometry", dae_doc(&[("<instance_geometry url=\"#g\"/></node>\n", "<instance_geometry url=\"#nope\"/></node>\n")]) => ReadError::Malformed { location: Location::Line(23), .. },
        "URL to another file", dae_doc(&[("<instance_geometry url=\"#g\"/></node>\n", "<instance_geometry url=\"parts.dae#g\"/></node>\n")]) => ReadError::Unsupported { .. },
        "geometry URL naming a node", dae_doc(&[("<instance_geometry url=\"#g\"/></node>\n", "<instance_geometry url=\"#lib\"/></node>\n")]) => ReadError::Malformed { .. },
        "float_array count too large", dae_doc(&[("count=\"12\"", "count=\"13\"")]) => ReadError::Malformed { location: Location::Line(7), .. },
        "not a number", dae_doc(&[("1 1 0 0 1 0<", "1 1 0 0 x 0<")]) => ReadError::Malformed { location: Location::Line(7), .. },
        "accessor past its array", dae_doc(&[("count=\"4\" stride", "count=\"5\" stride")]) => ReadError::Malformed { location: Location::Line(8), .. },
        "accessor count 2^42", dae_doc(&[("count=\"4\" stride", "count=\"4398046511104\" stride")]) => ReadError::TooLarge { what: "vertex count", .. },
        "stride smaller than 3", dae_doc(&[("stride=\"3\"", "stride=\"2\"")]) => ReadError::Malformed { .. },
        "NaN coordinate", dae_doc(&[("1 1 0 0 1 0<", "1 NaN 0 0 1 0<")]) => ReadError::NonFinite { location: Location::Line(7), .. },
        "infinite matrix entry", dae_doc(&[("0 0 0 1</matrix>", "0 0 inf 1</matrix>")]) => ReadError::NonFinite { location: Location::Line(23), .. },
        "matrix of 15 numbers", dae_doc(&[("0 0 0 1</matrix>", "0 0 1</matrix>")]) => ReadError::Malformed { location: Location::Line(23), .. },
        "overflowing coordinate", dae_doc(&[("1 1 0 0 1 0<", "1 1e39 0 0 1 0<")]) => ReadError::NonFinite { location: Location::Line(23), .. },
        "index out of range", dae_doc(&[("<p>0 2 1</p>", "<p>0 4 1</p>")]) => ReadError::IndexOutOfRange { index: 4, count: 4, location: Location::Line(18), .. },
        "negative index", dae_doc(&[("<p>0 2 1</p>", "<p>0 -2 1</p>")]) => ReadError::Malformed { location: Location::Line(18), .. },
        "index 2^64", dae_doc(&[("<p>0 2 1</p>", "<p>0 18446744073709551616 1</p>")]) => ReadError::Malformed { .. },
        "corners not whole", dae_doc(&[("<p>0 0 1 0 2 0 3 0</p>", "<p>0 0 1 0 2 0 3</p>")]) => ReadError::Malformed { location: Location::Line(16), .. },
        "triangle count mismatch", dae_doc(&[("<triangles count=\"1\">", "<triangles count=\"2\">")]) => ReadError::Malformed { location: Location::Line(18), .. },
        "vcount past p", dae_doc(&[("<vcount>4</vcount>", "<vcount>5</vcount>")]) => ReadError::Malformed { location: Location::Line(15), .. },
        "no VERTEX input", dae_doc(&[("<triangles count=\"1\"><input semantic=\"VERTEX\"", "<triangles count=\"1\"><input semantic=\"NORMAL\"")]) => ReadError::Malformed { location: Location::Line(18), .. },
        "input offset 2^20", dae_doc(&[("source=\"#v\" offset=\"1\"", "source=\"#v\" offset=\"1048576\"")]) => ReadError::Malformed { .. },
        "no POSITION", dae_doc(&[("semantic=\"POSITION\"", "semantic=\"NORMAL\"")]) => ReadError::Malformed { location: Location::Line(12), .. },
        "instance_node cycle", dae_doc(&[("<node id=\"lib\">", "<node id=\"lib\"><instance_node url=\"#lib\"/>"), (node, "<node><instance_node url=\"#lib\"/></node>")]) => ReadError::Malformed { .. },
        "nested too deep", dae_doc(&[(node, deep.as_str())]) => ReadError::TooLarge { what: "node nesting depth", .. },
        "shared nodes multiplying", dae_doc(&[(node, "<node><instance_node url=\"#d0\"/></node>"), ("<node id=\"lib\">", &format!("{sharing}<node id=\"lib\">"))]) => ReadError::TooLarge { what: "node instance count", .. },
        "skew", dae_doc(&[("<matrix>", "<skew>45 0 1 0 1 0 0</skew><matrix>")]) => ReadError::Unsupported { .. },
        "no instances", dae_doc(&[(node, "<node/>")]) => ReadError::Empty { .. },
        "many attributes on one element", dae_doc(&[("<node id=\"n\">", &format!("<node {}>", (0..=DAE_MAX_XML_ATTRIBUTES).map(|i| format!("a{i}=\"\"")).collect::<Vec<_>>().join(" ")))]) => ReadError::TooLarge { what: "attributes of one XML element", .. },
        "many namespace declarations", dae_doc(&[("<node id=\"n\">", &format!("{}<node id=\"n\">", (0..65).map(|i| format!("<extra xmlns:p{i}=\"u\"/>")).collect::<String>()))]) => ReadError::TooLarge { what: "XML namespace declarations", .. },
        "too many XML nodes", dae_doc(&[("<node id=\"n\">", &format!("{}<node id=\"n\">", "<a/>".repeat(DAE_MAX_XML_NODES as usize)))]) => ReadError::TooLarge { what: "XML node count", .. },
    );
    assert!(n >= 12);
    let few = Limits {
        max_faces: 2,
        ..Limits::default()
    };
    assert!(matches!(
        read_bytes(good.as_bytes(), Format::Dae, &few),
        Err(ReadError::TooLarge {
            what: "triangle count",
            ..
        })
    ));
    // Bytes after `</COLLADA>` (a real robot file has them) are ignored.
    let junk = format!("{good}   </polylist>\n</mesh>\n");
    assert_eq!(
        read_bytes(junk.as_bytes(), Format::Dae, &Limits::default())
            .unwrap()
            .faces
            .len(),
        3
    );
}

#[test]
fn ase_bad_inputs() {
    let head = "*3DSMAX_ASCIIEXPORT\t200\n*GEOMOBJECT {\n\t*MESH {\n";
    let counts = "\t\t*MESH_NUMVERTEX 3\n\t\t*MESH_NUMFACES 1\n";
    let verts = "\t\t*MESH_VERTEX_LIST {\n\t\t\t*MESH_VERTEX 0 0 0 0\n\t\t\t*MESH_VERTEX 1 1 0 0\n\t\t\t*MESH_VERTEX 2 0 1 0\n\t\t}\n";
    let face = |f: &str| {
        format!("\t\t*MESH_FACE_LIST {{\n\t\t\t*MESH_FACE 0: {f} AB: 1 BC: 1 CA: 1\n\t\t}}\n")
    };
    let tail = "\t}\n}\n";
    let good = format!("{head}{counts}{verts}{}{tail}", face("A: 0 B: 1 C: 2"));
    assert_eq!(
        read_bytes(good.as_bytes(), Format::Ase, &Limits::default())
            .unwrap()
            .faces,
        vec![[0, 1, 2]]
    );
    let with_verts = |v: &str| {
        format!(
            "{head}{counts}\t\t*MESH_VERTEX_LIST {{\n{v}\t\t}}\n{}{tail}",
            face("A: 0 B: 1 C: 2")
        )
    };
    let deep = format!(
        "*3DSMAX_ASCIIEXPORT 200\n{}",
        "*GROUP \"g\" {\n".repeat(meshflow::io::ASE_MAX_DEPTH + 1)
    );
    let n = table!(Format::Ase,
        "empty", "" => ReadError::Empty { .. },
        "no header", format!("*GEOMOBJECT {{\n}}\n") => ReadError::Malformed { location: Location::Line(1), .. },
        "cut in the vertices", good[..good.find("*MESH_VERTEX 2").unwrap()].to_string() => ReadError::Truncated { .. },
        "cut in the faces", good[..good.find("AB:").unwrap()].to_string() => ReadError::Truncated { .. },
        "cut before the object ends", good[..good.len() - 2].to_string() => ReadError::Truncated { .. },
        "unmatched brace", format!("{good}}}\n") => ReadError::Malformed { location: Location::Line(16), .. },
        "vertex count u64::MAX", format!("{head}\t\t*MESH_NUMVERTEX 18446744073709551615\n") => ReadError::TooLarge { what: "vertex count", .. },
        "face count 2^40", format!("{head}\t\t*MESH_NUMVERTEX 3\n\t\t*MESH_NUMFACES 1099511627776\n") => ReadError::TooLarge { what: "triangle count", .. },
        "negative vertex count", format!("{head}\t\t*MESH_NUMVERTEX -3\n") => ReadError::Malformed { location: Location::Line(4), .. },
        "bad coordinate", with_verts("*MESH_VERTEX 0 0 0 0\n*MESH_VERTEX 1 x 0 0\n*MESH_VERTEX 2 0 1 0\n") => ReadError::Malformed { location: Location::Line(8), .. },
        "NaN coordinate", with_verts("*MESH_VERTEX 0 0 0 0\n*MESH_VERTEX 1 NaN 0 0\n*MESH_VERTEX 2 0 1 0\n") => ReadError::NonFinite { location: Location::Line(8), .. },
        "overflowing coordinate", with_verts("*MESH_VERTEX 0 0 0 0\n*MESH_VERTEX 1 1e39 0 0\n*MESH_VERTEX 2 0 1 0\n") => ReadError::NonFinite { location: Location::Line(8), .. },
        "vertex numbered out of order", with_verts("*MESH_VERTEX 0 0 0 0\n*MESH_VERTEX 2 0 0 0\n*MESH_VERTEX 1 0 1 0\n") => ReadError::Malformed { location: Location::Line(8), .. },
        "more vertices than declared", with_verts("*MESH_VERTEX 0 0 0 0\n*MESH_VERTEX 1 1 0 0\n*MESH_VERTEX 2 0 1 0\n*MESH_VERTEX 3 0 1 0\n") => ReadError::Malformed { location: Location::Line(10), .. },
        "fewer vertices than declared", with_verts("*MESH_VERTEX 0 0 0 0\n*MESH_VERTEX 1 1 0 0\n") => ReadError::Malformed { .. },
        "junk in the vertex list", with_verts("*MESH_VERTEX 0 0 0 0\n*MESH_TVERT 1 1 0 0\n") => ReadError::Malformed { location: Location::Line(8), .. },
        "index out of range", format!("{head}{counts}{verts}{}{tail}", face("A: 0 B: 3 C: 2")) => ReadError::IndexOutOfRange { index: 3, count: 3, location: Location::Line(12), .. },
        "negative index", format!("{head}{counts}{verts}{}{tail}", face("A: 0 B: -1 C: 2")) => ReadError::Malformed { location: Location::Line(12), .. },
        "missing B", format!("{head}{counts}{verts}{}{tail}", face("A: 0 C: 2")) => ReadError::Malformed { location: Location::Line(12), .. },
        "fewer faces than declared", format!("{head}\t\t*MESH_NUMVERTEX 3\n\t\t*MESH_NUMFACES 2\n{verts}{}{tail}", face("A: 0 B: 1 C: 2")) => ReadError::Malformed { .. },
        "faces before the counts", format!("{head}{}{tail}", face("A: 0 B: 1 C: 2")) => ReadError::Malformed { location: Location::Line(4), .. },
        "groups nested too deep", deep => ReadError::TooLarge { what: "group nesting depth", .. },
        "no objects", "*3DSMAX_ASCIIEXPORT 200\n*SCENE {\n}\n" => ReadError::Empty { .. },
    );
    assert!(n >= 12);
}

fn put_i32(b: &mut [u8], at: usize, v: i32) -> Vec<u8> {
    put_u32(b, at, v as u32)
}

#[test]
fn iqm_bad_inputs() {
    // door01: header fields at 16 + 4k; 6 vertex arrays at 204 (20 bytes each; positions
    // first, f32 x 3 at 324), 2 meshes at 156 (24 bytes each), 28 triangles at 2452; 38
    // vertices; the file ends at 3220.
    let good = fixture("iqm/door01.iqm");
    let g = || good.clone();
    let n = table!(Format::Iqm,
        "empty", Vec::new() => ReadError::Truncated { offset: 0, .. },
        "wrong magic", { let mut b = g(); b[0] = b'X'; b } => ReadError::Malformed { location: Location::Byte(0), .. },
        "version 1", put_u32(&mut g(), 16, 1) => ReadError::Unsupported { .. },
        "cut in the header", g()[..60].to_vec() => ReadError::Truncated { .. },
        "cut one byte short", g()[..g().len() - 1].to_vec() => ReadError::Truncated { expected: 1, .. },
        "file size past the end", put_u32(&mut g(), 20, 4000) => ReadError::Truncated { .. },
        "cut in the triangles", { let mut b = g(); b.truncate(2500); put_u32(&mut b, 20, 2500) } => ReadError::Truncated { .. },
        "vertex count 0xFFFFFFFF", put_u32(&mut g(), 48, u32::MAX) => ReadError::TooLarge { what: "vertex count", .. },
        "vertex count past the end", put_u32(&mut g(), 48, 1_000_000) => ReadError::Truncated { .. },
        "array count 0xFFFFFFFF", put_u32(&mut g(), 44, u32::MAX) => ReadError::Truncated { .. },
        "array offset in the header", put_u32(&mut g(), 52, 8) => ReadError::Malformed { location: Location::Byte(52), .. },
        "position offset in the header", put_u32(&mut g(), 204 + 16, 100) => ReadError::Malformed { location: Location::Byte(220), .. },
        "unknown array format", put_u32(&mut g(), 204 + 8, 9) => ReadError::Malformed { location: Location::Byte(212), .. },
        "positions of 2 components", put_u32(&mut g(), 204 + 12, 2) => ReadError::Malformed { location: Location::Byte(216), .. },
        "no position array", put_u32(&mut g(), 204, 9) => ReadError::Malformed { .. },
        "mesh triangles past the list", put_u32(&mut g(), 180 + 20, 15) => ReadError::Malformed { location: Location::Byte(196), .. },
        "mesh vertices past the list", put_u32(&mut g(), 180 + 12, 19) => ReadError::Malformed { location: Location::Byte(188), .. },
        "triangle count 0xFFFFFFFF", { let mut b = put_u32(&mut g(), 56, u32::MAX); put_u32(&mut b, 180 + 20, u32::MAX - 14) } => ReadError::TooLarge { what: "triangle count", .. },
        "mesh offset past the end", put_u32(&mut g(), 40, 1 << 20) => ReadError::Truncated { .. },
        "index out of range", put_u32(&mut g(), 2452 + 4, 38) => ReadError::IndexOutOfRange { index: 38, count: 38, location: Location::Byte(2456), .. },
        "negative index", put_i32(&mut g(), 2452, -1) => ReadError::IndexOutOfRange { .. },
        "NaN position", put_f32(&mut g(), 324 + 12 * 5 + 4, f32::NAN) => ReadError::NonFinite { location: Location::Byte(384), .. },
        "infinite position", put_f32(&mut g(), 324, f32::INFINITY) => ReadError::NonFinite { location: Location::Byte(324), .. },
        "no meshes", put_u32(&mut g(), 36, 0) => ReadError::Empty { .. },
    );
    assert!(n >= 12);
    // A NaN normal is not an error: the normals are dropped.
    let m = read_bytes(
        &put_f32(&mut g(), 1084, f32::NAN),
        Format::Iqm,
        &Limits::default(),
    )
    .unwrap();
    assert!(m.normals.is_empty());
}

#[test]
fn md5_bad_inputs() {
    let head = "MD5Version 10\ncommandline \"\"\nnumJoints 1\nnumMeshes 1\n";
    let joints = "joints {\n\t\"root\" -1 ( 0 0 0 ) ( 0 0 0 )\n}\n";
    let mesh = |body: &str| format!("{head}{joints}mesh {{\n\tshader \"s\"\n{body}}}\n");
    let verts = "\tnumverts 3\n\tvert 0 ( 0 0 ) 0 1\n\tvert 1 ( 0 0 ) 1 1\n\tvert 2 ( 0 0 ) 2 1\n";
    let tris = "\tnumtris 1\n\ttri 0 0 2 1\n";
    let weights = "\tnumweights 3\n\tweight 0 0 1 ( 0 0 0 )\n\tweight 1 0 1 ( 1 0 0 )\n\tweight 2 0 1 ( 0 1 0 )\n";
    let good = mesh(&format!("{verts}{tris}{weights}"));
    let m = read_bytes(good.as_bytes(), Format::Md5, &Limits::default()).unwrap();
    assert_eq!(m.faces, vec![[0, 1, 2]]);
    // Without the version line (as two Red Eclipse weapons) it is read all the same.
    let headless = good.replacen("MD5Version 10\n", "", 1);
    assert!(read_bytes(headless.as_bytes(), Format::Md5, &Limits::default()).is_ok());
    let n = table!(Format::Md5,
        "empty", "" => ReadError::Empty { .. },
        "version 11", good.replacen("10", "11", 1) => ReadError::Unsupported { .. },
        "bad version", "MD5Version ten\n" => ReadError::Malformed { location: Location::Line(1), .. },
        "unknown keyword", format!("{head}hello\n") => ReadError::Malformed { location: Location::Line(5), .. },
        "joints before numJoints", format!("MD5Version 10\n{joints}") => ReadError::Malformed { location: Location::Line(2), .. },
        "fewer joints than declared", good.replacen("numJoints 1", "numJoints 2", 1) => ReadError::Malformed { location: Location::Line(7), .. },
        "more joints than declared", good.replacen("numJoints 1", "numJoints 0", 1) => ReadError::Malformed { location: Location::Line(6), .. },
        "parent out of range", good.replacen("-1 (", "1 (", 1) => ReadError::IndexOutOfRange { what: "joints", index: 1, count: 1, location: Location::Line(6), .. },
        "NaN joint position", good.replacen("( 0 0 0 ) ( 0 0 0 )", "( 0 nan 0 ) ( 0 0 0 )", 1) => ReadError::NonFinite { location: Location::Line(6), .. },
        "missing parenthesis", good.replacen("( 0 0 0 ) ( 0 0 0 )", "( 0 0 0 ( 0 0 0 )", 1) => ReadError::Malformed { location: Location::Line(6), .. },
        "cut in the joints", format!("{head}joints {{\n\t\"root\" -1 ( 0 0") => ReadError::Truncated { .. },
        "cut in the mesh", good[..good.len() - 30].to_string() => ReadError::Truncated { .. },
        "vertex count 2^40", mesh("\tnumverts 1099511627776\n") => ReadError::TooLarge { what: "vertex count", .. },
        "triangle count 2^40", mesh("\tnumtris 1099511627776\n") => ReadError::TooLarge { what: "triangle count", .. },
        "negative vertex count", mesh("\tnumverts -1\n") => ReadError::Malformed { location: Location::Line(10), .. },
        "second numverts", mesh(&format!("{verts}\tnumverts 3\n")) => ReadError::Malformed { location: Location::Line(14), .. },
        "vertex numbered out of order", mesh("\tnumverts 3\n\tvert 1 ( 0 0 ) 0 1\n") => ReadError::Malformed { location: Location::Line(11), .. },
        "fewer vertices than declared", mesh(&format!("\tnumverts 4\n{}{tris}{weights}", &verts[12..])) => ReadError::Malformed { .. },
        "triangle index out of range", mesh(&format!("{verts}\tnumtris 1\n\ttri 0 0 3 1\n{weights}")) => ReadError::IndexOutOfRange { what: "vertices", index: 3, count: 3, location: Location::Line(15), .. },
        "weight joint out of range", mesh(&format!("{verts}{tris}\tnumweights 1\n\tweight 0 1 1 ( 0 0 0 )\n")) => ReadError::IndexOutOfRange { what: "joints", index: 1, count: 1, location: Location::Line(17), .. },
        "weights past the list", mesh(&format!("{verts}{tris}\tnumweights 2\n\tweight 0 0 1 ( 0 0 0 )\n\tweight 1 0 1 ( 1 0 0 )\n")) => ReadError::IndexOutOfRange { what: "weights", index: 2, count: 2, location: Location::Line(13), .. },
        "vertex without weights", mesh(&format!("{}{tris}{weights}", verts.replacen(") 0 1", ") 0 0", 1))) => ReadError::Malformed { location: Location::Line(11), .. },
        "infinite bias", mesh(&format!("{verts}{tris}{}", weights.replacen("0 0 1 (", "0 0 inf (", 1))) => ReadError::NonFinite { location: Location::Line(17), .. },
        "bad weight position", mesh(&format!("{verts}{tris}{}", weights.replacen("( 1 0 0 )", "( 1 x 0 )", 1))) => ReadError::Malformed { location: Location::Line(18), .. },
        "overflowing position", mesh(&format!("{verts}{tris}{}", weights.replacen("( 1 0 0 )", "( 1e39 0 0 )", 1))) => ReadError::NonFinite { location: Location::Line(18), .. },
        "no meshes", format!("{head}{joints}") => ReadError::Empty { .. },
        "too many weights on a vertex", mesh(&format!("\tnumverts 1\n\tvert 0 ( 0 0 ) 0 65\n\tnumweights 65\n{}", (0..65).map(|i| format!("\tweight {i} 0 0.01 ( 0 0 0 )\n")).collect::<String>())) => ReadError::TooLarge { what: "weights of one vertex", .. },
    );
    assert!(n >= 12);
}
