//! Readers on small hand-written inputs, one or more per format variant.

mod common;

use common::temp_dir;
use glam::Vec3;
use meshflow::Mesh;
use meshflow::io::{Format, Limits, encode_base64, read_bytes, read_path};

fn read(bytes: &[u8], f: Format) -> Mesh {
    let m = read_bytes(bytes, f, &Limits::default()).unwrap_or_else(|e| panic!("{e}"));
    m.validate().unwrap();
    m
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

// ------------------------------------------------------------------------------------- PLY

const QUAD: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];

/// A binary PLY with a double x, an extra uchar and list on vertices, a quad and a triangle
/// with an extra face property, and an extra element.
fn binary_ply(big: bool) -> Vec<u8> {
    let enc = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut b = format!(
        "ply\nformat {enc} 1.0\ncomment c\nelement vertex 4\nproperty float64 x\nproperty uchar red\nproperty float32 y\nproperty list uint8 int16 stuff\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face 2\nproperty int8 flag\nproperty list uchar ushort vertex_index\nelement material 1\nproperty list int uchar name\nend_header\n"
    )
    .into_bytes();
    macro_rules! put {
        ($v:expr) => {
            if big {
                b.extend_from_slice(&$v.to_be_bytes())
            } else {
                b.extend_from_slice(&$v.to_le_bytes())
            }
        };
    }
    for (i, p) in QUAD.iter().enumerate() {
        put!(p[0] as f64);
        b.push(200);
        put!(p[1]);
        b.push(i as u8); // list of i shorts
        for k in 0..i {
            put!(k as i16);
        }
        put!(p[2]);
        put!(0f32);
        put!(0f32);
        put!(2f32); // not unit: renormalised
    }
    b.push(7);
    b.push(4);
    for i in [0u16, 1, 2, 3] {
        put!(i);
    }
    b.push(0xff);
    b.push(3);
    for i in [0u16, 2, 1] {
        put!(i);
    }
    put!(3i32);
    b.extend_from_slice(b"abc");
    b
}

#[test]
fn ply_binary_little_and_big_endian() {
    for big in [false, true] {
        let m = read(&binary_ply(big), Format::Ply);
        assert_eq!(m.positions, QUAD.map(Vec3::from_array).to_vec());
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3], [0, 2, 1]]);
        assert_eq!(m.normals, vec![Vec3::Z; 4]);
    }
}

#[test]
fn ply_ascii_crlf_point_cloud_and_types() {
    let s = "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty double x\r\nproperty double y\r\nproperty double z\r\nproperty int intensity\r\nend_header\r\n1.5 -2 3e2 7\r\n0 0 0 1\r\n-0 1 1 1\r\n";
    let m = read(s.as_bytes(), Format::Ply);
    assert!(m.is_point_cloud());
    assert_eq!(m.positions[0], Vec3::new(1.5, -2.0, 300.0));
    assert_eq!(m.positions.len(), 3);
}

#[test]
fn ply_faces_before_vertices_and_vertex_indices_uint() {
    let s = "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar uint vertex_indices\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n3 2 1 0\n0 0 0\n1 0 0\n0 1 0\n";
    let m = read(s.as_bytes(), Format::Ply);
    assert_eq!(m.faces, vec![[2, 1, 0]]);
}

// ------------------------------------------------------------------------------------- STL

fn binary_stl(header: &[u8], tris: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut b = header.to_vec();
    b.resize(80, b' ');
    b.extend_from_slice(&(tris.len() as u32).to_le_bytes());
    for t in tris {
        for c in [0f32, 0.0, 1.0] {
            b.extend_from_slice(&c.to_le_bytes());
        }
        for v in t {
            for c in v {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.extend_from_slice(&0u16.to_le_bytes());
    }
    b
}

const TWO_TRIS: [[[f32; 3]; 3]; 2] = [
    [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]],
    [[1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
];

#[test]
fn stl_binary_including_solid_header() {
    for header in [&b"binary stl"[..], b"solid but really binary"] {
        let bytes = binary_stl(header, &TWO_TRIS);
        assert_eq!(Format::sniff(&bytes), Some(Format::Stl));
        let m = read(&bytes, Format::Stl);
        assert_eq!(m.positions.len(), 4, "shared corners merged");
        assert_eq!(m.faces, vec![[0, 1, 2], [1, 3, 2]]);
    }
}

#[test]
fn stl_merges_only_bit_identical_corners() {
    let mut t = TWO_TRIS;
    t[1][0] = [1.0 + f32::EPSILON, 0.0, 0.0];
    t[1][2] = [-0.0, 1.0, 0.0]; // -0.0 differs from 0.0 bitwise: not merged
    let m = read(&binary_stl(b"x", &t), Format::Stl);
    assert_eq!(m.positions.len(), 6);
}

#[test]
fn stl_ascii() {
    let s = "  solid cube\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 0 1 0\n    endloop\n  endfacet\n  facet normal 0 0 1\n    outer loop\n      vertex 1 0 0\n      vertex 1 1 0\n      vertex 0 1 0\n    endloop\n  endfacet\nendsolid cube\nsolid second\nfacet normal 0 0 0\nouter loop\nvertex 0 0 5\nvertex 1e0 0 5\nvertex 0 1 5\nendloop\nendfacet\nendsolid\n";
    let m = read(s.as_bytes(), Format::Stl);
    assert_eq!(m.positions.len(), 7);
    assert_eq!(m.faces.len(), 3);
}

// ------------------------------------------------------------------------------------- OBJ

#[test]
fn obj_face_syntaxes_negative_indices_polygons() {
    let s = "# header\r\nmtllib x.mtl\r\no thing\r\nv 0 0 0\r\nv 1 0 0 1.0\r\nv 1 1 0 0.1 0.2 0.3\r\nv 0 1 0\r\nv 0.5 0.5 1\r\nvt 0 0\r\nvt 1 1\r\nvn 0 0 1\r\ng a b\r\nusemtl red\r\ns off\r\nf 1 2 3\r\nf 1/1 3/2 4/1\r\nf 1//1 2//1 5//1\r\nf 2/2/1 3/1/1 5/2/1\r\nf -5/-2/-1 -4/-1/-1 -3/-2/-1 -2/-1/-1 -1/-2/-1\r\nl 1 2\r\np 3\r\n";
    let m = read(s.as_bytes(), Format::Obj);
    assert_eq!(m.positions.len(), 5);
    assert_eq!(m.positions[1], Vec3::X);
    assert_eq!(&m.faces[..4], &[[0, 1, 2], [0, 2, 3], [0, 1, 4], [1, 2, 4]]);
    // The pentagon fan-triangulated from its first corner.
    assert_eq!(&m.faces[4..], &[[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    assert!(m.normals.is_empty(), "the first faces have no normals");
}

#[test]
fn obj_normals_when_every_corner_has_one() {
    let s = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 2\nvn 0 1 0\nf 1//1 2//1 3//1\nf 2//2 4//2 3//2\n";
    let m = read(s.as_bytes(), Format::Obj);
    // Vertex 2 (index 1) keeps the normal of its first reference; 2 is renormalised.
    assert_eq!(m.normals, vec![Vec3::Z, Vec3::Z, Vec3::Z, Vec3::Y]);
}

#[test]
fn obj_non_finite_normals_drop_all_normals() {
    // The module rule: a non-finite normal is not an error; the mesh just gets no normals.
    let faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn nan 0 0\nf 1//1 2//2 3//1\n";
    let m = read(faces.as_bytes(), Format::Obj);
    assert_eq!(m.faces, vec![[0, 1, 2]]);
    assert!(m.normals.is_empty());
    let cloud = "v 0 0 0\nv 1 0 0\nvn 0 0 1\nvn 0 -inf 0\n";
    let m = read(cloud.as_bytes(), Format::Obj);
    assert_eq!(m.positions.len(), 2);
    assert!(m.normals.is_empty());
    // An overflowing literal is an infinity too.
    let m = read(b"v 0 0 0\nvn 1e39 0 0\n", Format::Obj);
    assert!(m.normals.is_empty());
    // A `vn` no vertex takes is simply unused.
    let unused = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn nan nan nan\nf 1//1 2//1 3//1\n";
    assert_eq!(
        read(unused.as_bytes(), Format::Obj).normals,
        vec![Vec3::Z; 3]
    );
}

#[test]
fn obj_point_cloud() {
    let m = read(b"v 1 2 3\nv 4 5 6\nvn 1 0 0\nvn 0 1 0\n", Format::Obj);
    assert!(m.is_point_cloud());
    assert_eq!(m.normals, vec![Vec3::X, Vec3::Y]);
}

// ------------------------------------------------------------------------------------ glTF

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// One triangle (0,0,0) (1,0,0) (0,1,0) with u16 indices and normals +Z, under a parent
/// node translated by (1,2,3) whose child is scaled by 2 and rotated 90 degrees about Z.
fn gltf_doc(child_scale: [f32; 3], uri: &str) -> String {
    let h = std::f32::consts::FRAC_1_SQRT_2;
    format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0]}}, {{"nodes": [2]}}],
  "nodes": [
    {{"children": [1], "translation": [1, 2, 3]}},
    {{"mesh": 0, "scale": {child_scale:?}, "rotation": [0, 0, {h}, {h}]}},
    {{"mesh": 0}}
  ],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2}}]}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]}},
    {{"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"}},
    {{"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}}
  ],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 72}},
    {{"buffer": 0, "byteOffset": 72, "byteLength": 6}}
  ],
  "buffers": [{{"byteLength": 78, "uri": "{uri}"}}]
}}"#
    )
}

fn gltf_buffer() -> Vec<u8> {
    let mut b = f32s(&[
        0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 1., 0., 0., 1.,
    ]);
    for i in [0u16, 1, 2] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b
}

fn data_uri() -> String {
    format!(
        "data:application/octet-stream;base64,{}",
        encode_base64(&gltf_buffer())
    )
}

#[test]
fn gltf_data_uri_and_node_hierarchy_transforms() {
    let doc = gltf_doc([2.0, 2.0, 2.0], &data_uri());
    let m = read(doc.as_bytes(), Format::Gltf);
    // (1,0,0): scale 2 -> (2,0,0), rotate 90 about Z -> (0,2,0), translate -> (1,4,3).
    let want = [
        Vec3::new(1., 2., 3.),
        Vec3::new(1., 4., 3.),
        Vec3::new(-1., 2., 3.),
    ];
    for (p, w) in m.positions.iter().zip(want) {
        assert!(close(*p, w), "{p} vs {w}");
    }
    assert_eq!(m.faces, vec![[0, 1, 2]]);
    assert!(m.normals.iter().all(|n| close(*n, Vec3::Z)));
}

#[test]
fn gltf_mirroring_flips_winding_and_normals() {
    let doc = gltf_doc([1.0, 1.0, -1.0], &data_uri());
    let m = read(doc.as_bytes(), Format::Gltf);
    assert_eq!(m.faces, vec![[0, 2, 1]]);
    assert!(m.normals.iter().all(|n| close(*n, -Vec3::Z)));
}

#[test]
fn gltf_external_buffer_via_read_path() {
    let dir = temp_dir("gltf-ext");
    let dir = dir.path();
    std::fs::create_dir_all(dir.join("sub dir")).unwrap();
    std::fs::write(dir.join("sub dir/b.bin"), gltf_buffer()).unwrap();
    let doc = gltf_doc([1.0; 3], "sub%20dir/b.bin");
    std::fs::write(dir.join("m.gltf"), &doc).unwrap();
    let m = read_path(&dir.join("m.gltf"), &Limits::default()).unwrap();
    assert_eq!(m.faces.len(), 1);
    assert!(close(m.positions[1], Vec3::new(1.0, 3.0, 3.0)));
    // From memory the external file cannot be resolved.
    assert!(matches!(
        read_bytes(doc.as_bytes(), Format::Gltf, &Limits::default()),
        Err(meshflow::io::ReadError::Unsupported { .. })
    ));
}

#[test]
fn gltf_without_default_scene_and_without_scenes() {
    let doc = gltf_doc([1.0; 3], &data_uri()).replace("\"scene\": 0,", "");
    // Both scenes' roots: the transformed instance and the untransformed one.
    assert_eq!(read(doc.as_bytes(), Format::Gltf).faces.len(), 2);
    let doc = doc.replace("\"scenes\": [{\"nodes\": [0]}, {\"nodes\": [2]}],", "");
    let m = read(doc.as_bytes(), Format::Gltf);
    assert_eq!(m.positions[1], Vec3::X, "every mesh once, untransformed");
}

#[test]
fn gltf_strip_fan_and_points_modes() {
    let base = gltf_doc([1.0; 3], &data_uri()).replace("\"scene\": 0,", "\"scene\": 1,");
    for (mode, faces) in [(5, vec![[0u32, 1, 2]]), (6, vec![[0, 1, 2]]), (0, vec![])] {
        let doc = base.replace(
            "\"indices\": 2}",
            &format!("\"indices\": 2, \"mode\": {mode}}}"),
        );
        let m = read(doc.as_bytes(), Format::Gltf);
        assert_eq!(m.faces, faces, "mode {mode}");
        assert_eq!(m.positions.len(), 3);
    }
}

#[test]
fn glb_written_by_write_glb() {
    let m = meshflow::geometry::primitives::grid(3, 2);
    let back = read(&meshflow::io::write_glb(&m), Format::Glb);
    assert_eq!(back, m);
}

// ---------------------------------------------------------------------------------- Points

#[test]
fn points_variants() {
    let m = read(b"# comment\n1 2 3\n\n4\t5\t6\n", Format::Points);
    assert_eq!(
        m.positions,
        vec![Vec3::new(1., 2., 3.), Vec3::new(4., 5., 6.)]
    );
    assert!(m.normals.is_empty());
    // XYZ with normals (6 numbers per line, unit-ish).
    let m = read(b"1 2 3 0 0 1\n4 5 6 0 0.6 0.8\n", Format::Points);
    assert_eq!(m.normals, vec![Vec3::Z, Vec3::new(0., 0.6, 0.8)]);
    // Colours are not normals.
    assert!(
        read(b"1 2 3 255 128 0\n", Format::Points)
            .normals
            .is_empty()
    );
    // PTS: count line, x y z intensity r g b.
    let m = read(
        b"2\n1 2 3 -100 255 0 0\n4 5 6 -90 0 255 0\n",
        Format::Points,
    );
    assert_eq!(m.positions.len(), 2);
    assert!(m.normals.is_empty());
    // CSV with a header, commas, semicolons, CRLF, // comments.
    let m = read(
        b"x,y,z,intensity\r\n1,2,3,4\r\n// note\r\n4;5;6\r\n7, 8, 9\r\n",
        Format::Points,
    );
    assert_eq!(m.positions.len(), 3);
    assert_eq!(m.positions[2], Vec3::new(7., 8., 9.));
}

#[test]
fn gltf_interleaved_stride_u8_indices_matrix_and_quantized_normals() {
    // Interleaved: position (3 f32) + normal (3 f32) per vertex, stride 24.
    let mut buf = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
        buf.extend(f32s(&p));
        buf.extend(f32s(&[0., 0., 1.]));
    }
    let idx_at = buf.len();
    buf.extend_from_slice(&[0, 1, 2, 0]); // u8 indices + padding
    let q_at = buf.len();
    buf.extend_from_slice(&[0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0]); // i8 normalized normals, stride 4
    let doc = format!(
        r#"{{"asset":{{"version":"2.0"}},"extensionsRequired":["KHR_mesh_quantization"],
  "scenes":[{{"nodes":[0]}}],"scene":0,
  "nodes":[{{"mesh":0,"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 10,0,0,1]}}],
  "meshes":[{{"primitives":[
    {{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":2}},
    {{"attributes":{{"POSITION":0,"NORMAL":3}},"indices":2}}]}}],
  "accessors":[
    {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}},
    {{"bufferView":0,"byteOffset":12,"componentType":5126,"count":3,"type":"VEC3"}},
    {{"bufferView":1,"componentType":5121,"count":3,"type":"SCALAR"}},
    {{"bufferView":2,"componentType":5120,"normalized":true,"count":3,"type":"VEC3"}}],
  "bufferViews":[
    {{"buffer":0,"byteLength":72,"byteStride":24}},
    {{"buffer":0,"byteOffset":{idx_at},"byteLength":3}},
    {{"buffer":0,"byteOffset":{q_at},"byteLength":12,"byteStride":4}}],
  "buffers":[{{"byteLength":{},"uri":"data:application/gltf-buffer;base64,{}"}}]}}"#,
        buf.len(),
        encode_base64(&buf)
    );
    let m = read(doc.as_bytes(), Format::Gltf);
    assert_eq!(m.positions.len(), 6, "two primitives, vertices not shared");
    assert_eq!(m.positions[1], Vec3::new(11., 0., 0.));
    assert_eq!(m.faces, vec![[0, 1, 2], [3, 4, 5]]);
    assert!(
        m.normals.iter().all(|n| close(*n, Vec3::Z)),
        "{:?}",
        m.normals
    );
}

#[test]
fn gltf_missing_external_buffer_is_an_io_error() {
    let dir = temp_dir("gltf-missing");
    let dir = dir.path();
    std::fs::write(dir.join("m.gltf"), gltf_doc([1.0; 3], "nope.bin")).unwrap();
    let e = read_path(&dir.join("m.gltf"), &Limits::default()).unwrap_err();
    assert!(matches!(e, meshflow::io::ReadError::Io(_)), "{e:?}");
    assert!(!e.to_string().is_empty());
}

#[test]
fn obj_two_corner_faces_are_skipped() {
    let m = read_bytes(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\nf 3\n",
        Format::Obj,
        &Limits::default(),
    )
    .unwrap();
    assert_eq!(m.faces, vec![[0, 1, 2]]);
}

#[test]
fn format_names() {
    let names: Vec<_> = Format::ALL.iter().map(|f| f.to_string()).collect();
    assert_eq!(
        names,
        [
            "OBJ",
            "PLY",
            "STL",
            "glTF",
            "GLB",
            "point list",
            "PMD",
            "SPM",
            "MD2",
            "MD3",
            "PIE",
            "AC3D",
            "COLLADA",
            "ASE",
            "IQM",
            "MD5"
        ]
    );
}
