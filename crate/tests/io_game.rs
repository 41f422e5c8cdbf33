//! The game-asset readers (PMD, SPM, MD2, MD3, PIE, AC3D): real sample files, malformed inputs, and an
//! ignored survey over the extracted Debian packages.

use std::path::PathBuf;

use glam::Vec3;
use meshflow::io::{Format, Limits, Location, ReadError, read_bytes, read_path};
use meshflow::mesh::Mesh;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/game")
}

/// Reads every `.pmd`, `.spm`, `.md2`, `.md3`, `.pie` and `.ac` file under `$MESHFLOW_GAME_DATA` and prints,
/// per format, how many were read, how many of those enclose a positive / negative signed
/// volume, the mean agreement of stored normals with the faces, and the first errors.
/// `MESHFLOW_GAME_DATA=/work/scratch-game cargo test -p meshflow --test io_game -- --ignored --nocapture`
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
        errors: Vec<String>,
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
                let v = signed_volume(&m);
                if v > 0.0 {
                    s.positive += 1;
                } else if v < 0.0 {
                    s.negative += 1;
                }
                if !m.normals.is_empty() && !m.faces.is_empty() {
                    s.agreement.push(normal_agreement(&m));
                }
            }
            Err(e) => {
                s.bad += 1;
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
        for e in s.errors.iter().take(20) {
            println!("    {e}");
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
    assert_eq!(Format::sniff(b"SP\x42\x01"), None);
}
