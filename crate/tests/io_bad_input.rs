//! Table-driven malformed inputs: every reader must answer each with the specific typed
//! error (never a panic, never an `Ok`), with a non-empty message.

mod common;

use std::path::Path;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::temp_dir;
use meshflow::io::{
    Format, Limits, Location, MAX_NODE_VISITS, MAX_PRIMITIVE_INSTANCES, ReadError, encode_base64,
    read_bytes, read_path, write_glb,
};

/// Reads `bytes` as `format` and checks the error with `ok`.
fn check(format: Format, bytes: &[u8], limits: &Limits, what: &str, ok: fn(&ReadError) -> bool) {
    match read_bytes(bytes, format, limits) {
        Ok(m) => panic!(
            "{format} case `{what}` was accepted: {} vertices",
            m.positions.len()
        ),
        Err(e) => {
            assert!(ok(&e), "{format} case `{what}`: unexpected error {e:?}");
            let msg = e.to_string();
            assert!(
                !msg.trim().is_empty(),
                "{format} case `{what}`: empty message"
            );
            eprintln!("{format} {what}: {msg}");
        }
    }
}

macro_rules! table {
    ($format:expr, $( $what:literal, $bytes:expr => $pat:pat ),+ $(,)?) => {{
        $( check($format, &Vec::<u8>::from($bytes), &Limits::default(), $what, |e| matches!(e, $pat)); )+
    }};
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn obj_bad_inputs() {
    table!(Format::Obj,
        "bad utf-8", b"v 0 0 0\n\xff\xfe\n".to_vec() => ReadError::InvalidUtf8 { offset: 8, .. },
        "nan", "v nan 0 0\n" => ReadError::NonFinite { location: Location::Line(1), .. },
        "inf", "v 0 0 0\nv 0 -inf 0\n" => ReadError::NonFinite { location: Location::Line(2), .. },
        "overflowing literal", "v 1e39 0 0\n" => ReadError::NonFinite { .. },
        "two coordinates", "v 1 2\n" => ReadError::Malformed { location: Location::Line(1), .. },
        "not a number", "v a b c\n" => ReadError::Malformed { .. },
        "index past the end", format!("{TRI}f 1 2 4\n") => ReadError::IndexOutOfRange { index: 4, count: 3, location: Location::Line(4), .. },
        "negative past the start", format!("{TRI}f -1 -2 -4\n") => ReadError::IndexOutOfRange { index: -4, .. },
        "zero index", format!("{TRI}f 0 1 2\n") => ReadError::IndexOutOfRange { index: 0, .. },
        "forward reference", format!("f 1 2 3\n{TRI}") => ReadError::IndexOutOfRange { count: 0, .. },
        "normal index out of range", format!("{TRI}vn 0 0 1\nf 1//1 2//2 3//1\n") => ReadError::IndexOutOfRange { what: "normals", index: 2, count: 1, .. },
        "texcoord index out of range", format!("{TRI}f 1/1 2/1 3/1\n") => ReadError::IndexOutOfRange { what: "texture coordinates", .. },
        "face without corners", format!("{TRI}f\n") => ReadError::Malformed { .. },
        "two corners, one out of range", format!("{TRI}f 1 9\n") => ReadError::IndexOutOfRange { index: 9, .. },
        "too many slashes", format!("{TRI}f 1/1/1/1 2 3\n") => ReadError::Malformed { .. },
        "huge index", format!("{TRI}f 1 2 99999999999999999999999\n") => ReadError::Malformed { .. },
        "normal not a number", format!("{TRI}vn 0 x 1\n") => ReadError::Malformed { location: Location::Line(4), .. },
        "normal with two numbers", format!("{TRI}vn 0 1\n") => ReadError::Malformed { location: Location::Line(4), .. },
        "no vertices", "# nothing\no x\n" => ReadError::Empty { .. },
        "empty file", "" => ReadError::Empty { .. },
    );
}

fn ply_header(format: &str, rest: &str) -> String {
    format!("ply\nformat {format} 1.0\n{rest}end_header\n")
}
const XYZ: &str = "property float x\nproperty float y\nproperty float z\n";

fn ply_tri_bin(index: i32) -> Vec<u8> {
    let mut b = ply_header(
        "binary_little_endian",
        &format!("element vertex 3\n{XYZ}element face 1\nproperty list uchar int vertex_indices\n"),
    )
    .into_bytes();
    for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        b.extend_from_slice(&c.to_le_bytes());
    }
    b.push(3);
    for i in [0, 1, index] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b
}

#[test]
fn ply_bad_inputs() {
    let vtx = |n: &str| format!("element vertex {n}\n{XYZ}");
    let mut nan = ply_tri_bin(2);
    let at = nan.len() - 13 - 4; // z of the last vertex
    nan[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    table!(Format::Ply,
        "wrong magic", "plx\nformat ascii 1.0\nend_header\n" => ReadError::Malformed { location: Location::Byte(0), .. },
        "garbage", b"\x00\x01\x02garbage".to_vec() => ReadError::Malformed { .. },
        "no end_header", "ply\nformat ascii 1.0\nelement vertex 1\n" => ReadError::Malformed { .. },
        "header too long", format!("ply\nformat ascii 1.0\ncomment {}\nend_header\n", "x".repeat(70_000)) => ReadError::Malformed { .. },
        "unknown encoding", "ply\nformat binary_middle_endian 1.0\nend_header\n" => ReadError::Malformed { location: Location::Line(2), .. },
        "version 2", "ply\nformat ascii 2.0\nend_header\n" => ReadError::Unsupported { .. },
        "property before element", ply_header("ascii", "property float x\n") => ReadError::Malformed { .. },
        "unknown type", ply_header("ascii", "element vertex 1\nproperty float128 x\n") => ReadError::Malformed { .. },
        "unknown keyword", ply_header("ascii", "elephant vertex 1\n") => ReadError::Malformed { .. },
        "absurd vertex count", ply_header("binary_little_endian", &vtx("4000000000")) => ReadError::TooLarge { value: 4_000_000_000, .. },
        "count beyond u64", ply_header("ascii", &vtx("99999999999999999999999")) => ReadError::Malformed { .. },
        "count larger than the file", ply_header("binary_little_endian", &vtx("1000")) => ReadError::Truncated { .. },
        "ascii count larger than the file", ply_header("ascii", &vtx("1000")) + "0 0 0\n" => ReadError::Truncated { .. },
        "binary truncated mid-face", { let mut b = ply_tri_bin(2); b.truncate(b.len() - 3); b } => ReadError::Truncated { .. },
        "list longer than the file", [ply_header("binary_little_endian", &format!("{}element junk 1\nproperty list uint float junk\n", vtx("1"))).as_bytes(), &[0u8; 12], &[0xff, 0xff, 0xff, 0x7f]].concat() => ReadError::Truncated { .. },
        "nan coordinate", nan => ReadError::NonFinite { location: Location::Byte(_), .. },
        "inf ascii", ply_header("ascii", &vtx("2")) + "0 0 0\n0 inf 0\n" => ReadError::NonFinite { location: Location::Line(9), .. },
        "index out of range", ply_tri_bin(3) => ReadError::IndexOutOfRange { index: 3, count: 3, .. },
        "negative index", ply_tri_bin(-1) => ReadError::IndexOutOfRange { index: -1, .. },
        "face with 2 vertices", ply_header("ascii", &format!("{}element face 1\nproperty list uchar int vertex_indices\n", vtx("3"))) + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n" => ReadError::Malformed { .. },
        "no vertex_indices", ply_header("ascii", &format!("{}element face 1\nproperty int a\n", vtx("1"))) + "0 0 0\n5\n" => ReadError::Malformed { .. },
        "missing z", ply_header("ascii", "element vertex 1\nproperty float x\nproperty float y\n") + "0 0\n" => ReadError::Malformed { .. },
        "bad utf-8 body", (ply_header("ascii", &vtx("1")) + "0 0 0 ").into_bytes().into_iter().chain([0xff]).collect::<Vec<u8>>() => ReadError::InvalidUtf8 { .. },
        "no vertices", ply_header("ascii", &vtx("0")) => ReadError::Empty { .. },
        "float list count", ply_header("ascii", "element face 1\nproperty list float int vertex_indices\n") => ReadError::Malformed { .. },
    );
}

fn stl_bin(count: u32, records: usize) -> Vec<u8> {
    let mut b = vec![b' '; 80];
    b.extend_from_slice(&count.to_le_bytes());
    b.resize(84 + 50 * records, 0);
    b
}

#[test]
fn stl_bad_inputs() {
    let mut nan = stl_bin(1, 1);
    nan[84 + 12 + 4..84 + 12 + 8].copy_from_slice(&f32::INFINITY.to_le_bytes());
    let facet = |v: &str| {
        format!("solid s\nfacet normal 0 0 1\nouter loop\n{v}endloop\nendfacet\nendsolid s\n")
    };
    table!(Format::Stl,
        "too short", b"not an stl".to_vec() => ReadError::Truncated { .. },
        "empty file", b"".to_vec() => ReadError::Truncated { .. },
        "count larger than file", stl_bin(10, 2) => ReadError::Truncated { .. },
        "absurd count", stl_bin(u32::MAX, 1) => ReadError::Truncated { .. },
        "zero triangles", stl_bin(0, 0) => ReadError::Empty { .. },
        "inf in binary", nan => ReadError::NonFinite { location: Location::Byte(96), .. },
        "nan in ascii", facet("vertex 0 0 0\nvertex NaN 0 0\nvertex 0 1 0\n") => ReadError::NonFinite { location: Location::Line(5), .. },
        "two vertices", facet("vertex 0 0 0\nvertex 1 0 0\n") => ReadError::Malformed { location: Location::Line(3), .. },
        "bad number", facet("vertex 0 0 0\nvertex 1 x 0\nvertex 0 1 0\n") => ReadError::Malformed { .. },
        "missing coordinate", facet("vertex 0 0 0\nvertex 1 0\nvertex 0 1 0\n") => ReadError::Malformed { .. },
        "vertex outside loop", "solid s\nvertex 0 0 0\nendsolid\n" => ReadError::Malformed { .. },
        "unclosed loop", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n" => ReadError::Malformed { .. },
        "garbage keyword", "solid s\nbanana\n" => ReadError::Malformed { .. },
        "bad utf-8", b"solid s\n\xc3\x28\n".to_vec() => ReadError::InvalidUtf8 { offset: 8, .. },
        "ascii without facets", "solid s\nendsolid s\n" => ReadError::Empty { .. },
    );
}

/// A valid one-triangle glTF with `patch` applied to the JSON text as (from, to) pairs.
fn gltf(patches: &[(&str, &str)]) -> Vec<u8> {
    let mut buf: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    buf.extend_from_slice(&[0, 0, 1, 0, 2, 0]);
    let mut doc = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}},{{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}}],"bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":6}}],"buffers":[{{"byteLength":42,"uri":"data:application/octet-stream;base64,{}"}}]}}"#,
        encode_base64(&buf)
    );
    for (from, to) in patches {
        assert!(doc.contains(from), "patch `{from}` does not apply");
        doc = doc.replacen(from, to, 1);
    }
    doc.into_bytes()
}

#[test]
fn gltf_bad_inputs() {
    assert!(read_bytes(&gltf(&[]), Format::Gltf, &Limits::default()).is_ok());
    let chain: String = (0..100)
        .map(|i| format!("{{\"children\":[{}]}},", i + 1))
        .collect::<String>()
        + "{\"mesh\":0}";
    let dag: String = (0..40)
        .map(|i| format!("{{\"children\":[{0},{0}]}},", i + 1))
        .collect::<String>()
        + "{\"mesh\":0}";
    table!(Format::Gltf,
        "bad json", "{\"asset\": " => ReadError::Malformed { .. },
        "not json", "hello" => ReadError::Malformed { location: Location::Line(1), .. },
        "deep nesting", format!("{{\"asset\":{{\"version\":\"2.0\"}},\"x\":{}", "[".repeat(100_000)) => ReadError::Malformed { .. },
        "bad utf-8", b"{\"asset\":\xff}".to_vec() => ReadError::InvalidUtf8 { offset: 9, .. },
        "no asset", gltf(&[("\"asset\":{\"version\":\"2.0\"},", "")]) => ReadError::Malformed { .. },
        "glTF 1.0", gltf(&[("\"2.0\"", "\"1.0\"")]) => ReadError::Unsupported { .. },
        "accessor out of bounds", gltf(&[("\"count\":3,\"type\":\"VEC3\"", "\"count\":100,\"type\":\"VEC3\"")]) => ReadError::Malformed { .. },
        "accessor offset out of bounds", gltf(&[("\"bufferView\":0,", "\"bufferView\":0,\"byteOffset\":30,")]) => ReadError::Malformed { .. },
        "bufferView past buffer", gltf(&[("\"byteOffset\":36,\"byteLength\":6", "\"byteOffset\":40,\"byteLength\":6")]) => ReadError::Malformed { .. },
        "view offset overflow", gltf(&[("\"byteOffset\":36,", "\"byteOffset\":18446744073709551615,")]) => ReadError::Malformed { .. },
        "stride too small", gltf(&[("{\"buffer\":0,\"byteLength\":36}", "{\"buffer\":0,\"byteLength\":36,\"byteStride\":4}")]) => ReadError::Malformed { .. },
        "negative count", gltf(&[("\"count\":3,\"type\":\"VEC3\"", "\"count\":-3,\"type\":\"VEC3\"")]) => ReadError::Malformed { .. },
        "absurd count", gltf(&[("\"count\":3,\"type\":\"VEC3\"", "\"count\":1000000000000,\"type\":\"VEC3\"")]) => ReadError::TooLarge { .. },
        "node cycle", gltf(&[("\"nodes\":[{\"mesh\":0}]", "\"nodes\":[{\"mesh\":0,\"children\":[1]},{\"children\":[0]}]")]) => ReadError::Malformed { .. },
        "self child", gltf(&[("{\"mesh\":0}", "{\"mesh\":0,\"children\":[0]}")]) => ReadError::Malformed { .. },
        "too deep", gltf(&[("{\"mesh\":0}", &chain)]) => ReadError::Malformed { .. },
        "exponential sharing", gltf(&[("{\"mesh\":0}", &dag)]) => ReadError::TooLarge { .. },
        "missing node", gltf(&[("\"nodes\":[0]", "\"nodes\":[7]")]) => ReadError::Malformed { .. },
        "missing scene", gltf(&[("\"scene\":0", "\"scene\":3")]) => ReadError::Malformed { .. },
        "missing mesh", gltf(&[("{\"mesh\":0}", "{\"mesh\":9}")]) => ReadError::Malformed { .. },
        "missing accessor", gltf(&[("\"POSITION\":0", "\"POSITION\":5")]) => ReadError::Malformed { .. },
        "no POSITION", gltf(&[("\"POSITION\":0", "\"TEXCOORD_0\":0")]) => ReadError::Malformed { .. },
        "index out of range", gltf(&[("\"count\":3,\"type\":\"VEC3\"", "\"count\":2,\"type\":\"VEC3\"")]) => ReadError::IndexOutOfRange { .. },
        "float indices", gltf(&[("\"componentType\":5123", "\"componentType\":5126"), ("\"byteLength\":6", "\"byteLength\":4")]) => ReadError::Malformed { .. },
        "unknown mode", gltf(&[("\"indices\":1", "\"indices\":1,\"mode\":9")]) => ReadError::Malformed { .. },
        "draco required", gltf(&[("\"scene\":0", "\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],\"scene\":0")]) => ReadError::Unsupported { .. },
        "meshopt primitive", gltf(&[("\"indices\":1", "\"indices\":1,\"extensions\":{\"KHR_draco_mesh_compression\":{}}")]) => ReadError::Unsupported { .. },
        "sparse", gltf(&[("\"type\":\"VEC3\"", "\"type\":\"VEC3\",\"sparse\":{}")]) => ReadError::Unsupported { .. },
        "bad base64", gltf(&[("base64,", "base64,*")]) => ReadError::Malformed { .. },
        "not base64", gltf(&[(";base64,", ",")]) => ReadError::Unsupported { .. },
        "external buffer from memory", gltf(&[("data:application/octet-stream;base64,", "b.bin?")]) => ReadError::Unsupported { .. },
        "byteLength larger than data", gltf(&[("\"byteLength\":42", "\"byteLength\":4200")]) => ReadError::Malformed { .. },
        "no meshes", gltf(&[("{\"mesh\":0}", "{}")]) => ReadError::Empty { .. },
        "bad rotation", gltf(&[("{\"mesh\":0}", "{\"mesh\":0,\"rotation\":[0,0,0,0]}")]) => ReadError::Malformed { .. },
    );
}

#[test]
fn gltf_nan_position_is_non_finite() {
    let mut buf: Vec<u8> = [f32::NAN, 0., 0.]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    buf.extend_from_slice(&[0; 4]);
    let doc = format!(
        r#"{{"asset":{{"version":"2.0"}},"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":0}}]}}],"accessors":[{{"bufferView":0,"componentType":5126,"count":1,"type":"VEC3"}}],"bufferViews":[{{"buffer":0,"byteLength":12}}],"buffers":[{{"byteLength":16,"uri":"data:,;base64,{}"}}]}}"#,
        encode_base64(&buf)
    );
    let e = read_bytes(doc.as_bytes(), Format::Gltf, &Limits::default()).unwrap_err();
    assert!(matches!(e, ReadError::NonFinite { .. }), "{e:?}");
}

fn glb_chunks(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let mut j = json.to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut out = b"glTF".to_vec();
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    if let Some(b) = bin {
        out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(b);
    }
    let len = out.len() as u32;
    out[8..12].copy_from_slice(&len.to_le_bytes());
    out
}

#[test]
fn glb_bad_inputs() {
    let good = write_glb(&meshflow::geometry::primitives::cube());
    assert!(read_bytes(&good, Format::Glb, &Limits::default()).is_ok());
    let patch = |f: fn(&mut Vec<u8>)| {
        let mut g = good.clone();
        f(&mut g);
        g
    };
    let doc = br#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":0}]}],"accessors":[{"bufferView":0,"componentType":5126,"count":1,"type":"VEC3"}],"bufferViews":[{"buffer":0,"byteLength":12}],"buffers":[{"byteLength":12}]}"#;
    table!(Format::Glb,
        "wrong magic", patch(|g| g[0] = b'x') => ReadError::Malformed { location: Location::Byte(0), .. },
        "header cut", good[..8].to_vec() => ReadError::Truncated { .. },
        "empty", b"".to_vec() => ReadError::Truncated { .. },
        "version 1", patch(|g| g[4] = 1) => ReadError::Unsupported { .. },
        "length past the end", patch(|g| g[9] = 0xff) => ReadError::Truncated { .. },
        "file cut short", good[..good.len() - 4].to_vec() => ReadError::Truncated { .. },
        "chunk length past the end", patch(|g| { let l = g.len() as u32; g[8..12].copy_from_slice(&l.to_le_bytes()); g[12..16].copy_from_slice(&u32::MAX.to_le_bytes()); }) => ReadError::Truncated { .. },
        "BIN before JSON", patch(|g| g[16..20].copy_from_slice(b"BIN\0")) => ReadError::Malformed { .. },
        "no chunks", [&b"glTF"[..], &2u32.to_le_bytes(), &12u32.to_le_bytes()].concat() => ReadError::Malformed { .. },
        "bad utf-8 json", glb_chunks(b"{\"a\":\"\xff\"}", None) => ReadError::InvalidUtf8 { offset: 26, .. },
        "bad json", glb_chunks(b"{\"asset\":", None) => ReadError::Malformed { .. },
        "no BIN chunk", glb_chunks(doc, None) => ReadError::Malformed { .. },
        "BIN chunk too small", glb_chunks(doc, Some(&[0; 8])) => ReadError::Malformed { .. },
        "nan in BIN", glb_chunks(doc, Some(&[0, 0, 0xc0, 0x7f, 0, 0, 0, 0, 0, 0, 0, 0])) => ReadError::NonFinite { .. },
    );
    assert!(
        read_bytes(
            &glb_chunks(doc, Some(&[0; 12])),
            Format::Glb,
            &Limits::default()
        )
        .is_ok()
    );
}

#[test]
fn points_bad_inputs() {
    table!(Format::Points,
        "bad utf-8", b"1 2 3\n\xff".to_vec() => ReadError::InvalidUtf8 { offset: 6, .. },
        "nan", "1 2 3\nnan 0 0\n" => ReadError::NonFinite { location: Location::Line(2), .. },
        "inf", "inf 0 0\n" => ReadError::NonFinite { .. },
        "overflow to inf", "1e39,0,0\n" => ReadError::NonFinite { .. },
        "two columns", "1 2 3\n1 2\n" => ReadError::Malformed { location: Location::Line(2), .. },
        "word after the first line", "1 2 3\n4 five 6\n" => ReadError::Malformed { .. },
        "second header", "x,y,z\nx,y,z\n" => ReadError::Malformed { .. },
        "empty", "" => ReadError::Empty { .. },
        "only comments", "# a\n// b\n\n" => ReadError::Empty { .. },
        "only a header", "x y z\n" => ReadError::Empty { .. },
        "only a count", "5\n" => ReadError::Empty { .. },
        "binary garbage", vec![0u8, 1, 2, 3, 0xff] => ReadError::InvalidUtf8 { .. },
    );
}

#[test]
fn limits_reject_with_too_large() {
    let tiny = Limits {
        max_bytes: 1 << 20,
        max_vertices: 2,
        max_faces: 1,
    };
    let obj = format!("{TRI}f 1 2 3\n");
    let ply = ply_tri_bin(2);
    let stl = stl_bin(3, 3);
    let cases: Vec<(Format, Vec<u8>, &str)> = vec![
        (Format::Obj, obj.clone().into_bytes(), "vertex count"),
        (Format::Ply, ply, "vertex count"),
        (Format::Stl, stl, "triangle count"),
        (
            Format::Points,
            b"1 2 3\n4 5 6\n7 8 9\n".to_vec(),
            "point count",
        ),
        (
            Format::Glb,
            write_glb(&meshflow::geometry::primitives::cube()),
            "accessor count",
        ),
        (Format::Gltf, gltf(&[]), "accessor count"),
    ];
    for (f, bytes, what) in cases {
        let e = read_bytes(&bytes, f, &tiny).unwrap_err();
        assert!(
            matches!(&e, ReadError::TooLarge { what: w, .. } if *w == what),
            "{f}: {e:?}"
        );
        assert!(!e.to_string().is_empty());
    }
    let few_faces = Limits {
        max_faces: 1,
        ..Limits::default()
    };
    let quad = format!("{TRI}v 1 1 0\nf 1 2 3 4\n");
    assert!(matches!(
        read_bytes(quad.as_bytes(), Format::Obj, &few_faces),
        Err(ReadError::TooLarge {
            what: "triangle count",
            value: 2,
            limit: 1,
            ..
        })
    ));
    let small = Limits {
        max_bytes: 10,
        ..Limits::default()
    };
    assert!(matches!(
        read_bytes(obj.as_bytes(), Format::Obj, &small),
        Err(ReadError::TooLarge {
            what: "file size in bytes",
            ..
        })
    ));
    let d = Limits::default();
    assert_eq!(
        (d.max_bytes, d.max_vertices, d.max_faces),
        (512 << 20, 1 << 24, 1 << 25)
    );
}

#[test]
fn unknown_format_has_a_message() {
    assert!(!ReadError::UnknownFormat.to_string().is_empty());
}

/// Runs `f` on another thread and fails the test if it has not answered within 20 s (so a
/// read that blocks or never ends is a failure, not a hung test run).
fn promptly<T: Send + 'static>(what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(20))
        .unwrap_or_else(|_| panic!("{what}: no answer within 20 s"))
}

/// Makes a FIFO at `p` with `mkfifo`; false where that tool is not available.
#[cfg(unix)]
fn mkfifo(p: &Path) -> bool {
    std::process::Command::new("mkfifo")
        .arg(p)
        .status()
        .is_ok_and(|s| s.success())
}

/// The `gltf` test document with its buffer at `uri` instead of in a `data:` URI.
fn gltf_external(uri: &str) -> String {
    let doc = String::from_utf8(gltf(&[])).unwrap();
    let start = doc.find("\"uri\":\"").unwrap() + 7;
    let end = start + doc[start..].find('"').unwrap();
    format!("{}{uri}{}", &doc[..start], &doc[end..])
}

/// The buffer of the `gltf` test document.
fn gltf_buffer() -> Vec<u8> {
    let mut b: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    b.extend_from_slice(&[0, 0, 1, 0, 2, 0]);
    b
}

#[test]
fn gltf_external_buffer_uris_stay_in_the_folder() {
    let dir = temp_dir("gltf-uris");
    let dir = dir.path();
    let inner = dir.join("in");
    std::fs::create_dir_all(inner.join("sub")).unwrap();
    // Valid buffers both inside and outside the folder: only the URI rule can refuse.
    std::fs::write(inner.join("ok.bin"), gltf_buffer()).unwrap();
    std::fs::write(dir.join("outside.bin"), gltf_buffer()).unwrap();
    let read = |uri: &str| {
        let p = inner.join("m.gltf");
        std::fs::write(&p, gltf_external(uri)).unwrap();
        read_path(&p, &Limits::default())
    };
    assert_eq!(read("ok.bin").unwrap().faces.len(), 1);
    assert_eq!(read("./ok.bin").unwrap().faces.len(), 1);
    assert_eq!(read("%6Fk.bin").unwrap().faces.len(), 1);
    let refused = [
        ("../outside.bin", "leaves the glTF file's folder"),
        ("%2E%2E/outside.bin", "leaves the glTF file's folder"),
        ("%2e%2e%2foutside.bin", "leaves the glTF file's folder"),
        ("sub/../../outside.bin", "leaves the glTF file's folder"),
        ("/etc/hostname", "absolute path"),
        ("%2Fetc%2Fhostname", "absolute path"),
        ("%2Fdev%2Fzero", "absolute path"),
        ("file:///etc/hostname", "not a relative file path"),
        ("file:%2F%2F%2Fetc%2Fhostname", "not a relative file path"),
        ("C:%5Cwindows%5Cwin.ini", "not a relative file path"),
        ("..%5Coutside.bin", "not a relative file path"),
        ("ok.bin%00", "not a relative file path"),
        ("", "names no file"),
        ("%2E", "names no file"),
    ];
    for (uri, why) in refused {
        match read(uri) {
            Err(e @ ReadError::Unsupported { .. }) => {
                let msg = e.to_string();
                assert!(msg.contains(why), "`{uri}`: {msg}");
                assert!(msg.contains("buffers[0]"), "`{uri}`: {msg}");
            }
            other => panic!("`{uri}`: {other:?}"),
        }
    }
    // A folder inside is not a file.
    for uri in ["sub", "sub/", "%73ub"] {
        match read(uri) {
            Err(ReadError::Io(e)) => {
                assert_eq!(e.kind(), std::io::ErrorKind::IsADirectory, "`{uri}`");
                assert!(e.to_string().contains("is a directory"), "`{uri}`: {e}");
            }
            other => panic!("`{uri}`: {other:?}"),
        }
    }
}

#[cfg(unix)]
#[test]
fn gltf_external_buffer_must_be_a_regular_file() {
    let dir = temp_dir("gltf-special");
    let dir = dir.path();
    let gltf_at = |uri: &str| {
        let p = dir.join(format!("{uri}.gltf"));
        std::fs::write(&p, gltf_external(uri)).unwrap();
        p
    };
    // A link inside the folder to a device: the link itself is allowed, the device is not.
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.bin")).unwrap();
    let p = gltf_at("zero.bin");
    match promptly("/dev/zero buffer", move || {
        read_path(&p, &Limits::default())
    }) {
        Err(ReadError::Io(e)) => {
            assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
            assert!(e.to_string().contains("character device"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    if mkfifo(&dir.join("fifo.bin")) {
        let p = gltf_at("fifo.bin");
        let r = promptly("FIFO buffer", move || read_path(&p, &Limits::default()));
        assert!(
            matches!(&r, Err(ReadError::Io(e)) if e.to_string().contains("FIFO")),
            "{r:?}"
        );
    }
}

/// `/proc` files report a size of 0 whatever they hold: the limit must hold on the bytes
/// that arrive, not on the size the metadata gives.
#[cfg(target_os = "linux")]
#[test]
fn reads_stop_at_the_limit_whatever_the_metadata_says() {
    let status = Path::new("/proc/self/status");
    let Ok(held) = std::fs::read(status) else {
        return; // no procfs here
    };
    assert_eq!(std::fs::metadata(status).unwrap().len(), 0);
    let dir = temp_dir("gltf-proc");
    let dir = dir.path();
    std::os::unix::fs::symlink(status, dir.join("status.bin")).unwrap();
    let doc = gltf_external("status.bin");
    std::fs::write(dir.join("m.gltf"), &doc).unwrap();
    let limit = doc.len() as u64 + 10;
    assert!((held.len() as u64) > limit + 1);
    let limits = Limits {
        max_bytes: limit,
        ..Limits::default()
    };
    let e = read_path(&dir.join("m.gltf"), &limits).unwrap_err();
    assert!(
        matches!(e, ReadError::TooLarge { what: "external buffer size", value, limit: l, .. } if value == limit + 1 && l == limit),
        "{e:?}"
    );
    // The same for the file read_path is given.
    let e = read_path(status, &limits).unwrap_err();
    assert!(
        matches!(e, ReadError::TooLarge { what: "file size in bytes", value, .. } if value == limit + 1),
        "{e:?}"
    );
}

#[test]
fn gltf_external_buffers_share_one_size_limit() {
    let dir = temp_dir("gltf-total");
    let dir = dir.path();
    let mut b = gltf_buffer();
    b.resize(4096, 0);
    std::fs::write(dir.join("b.bin"), b).unwrap();
    // Two buffers naming the same 4096-byte file, the second holding the indices.
    let doc = gltf_external("b.bin")
        .replace(
            "{\"buffer\":0,\"byteOffset\":36",
            "{\"buffer\":1,\"byteOffset\":36",
        )
        .replace(
            "\"buffers\":[{\"byteLength\":42,\"uri\":\"b.bin\"}]",
            "\"buffers\":[{\"byteLength\":42,\"uri\":\"b.bin\"},{\"byteLength\":42,\"uri\":\"b.bin\"}]",
        );
    std::fs::write(dir.join("m.gltf"), &doc).unwrap();
    let p = dir.join("m.gltf");
    assert_eq!(read_path(&p, &Limits::default()).unwrap().faces.len(), 1);
    // Each file, and the document, is under the limit; the two buffers together are not.
    assert!(doc.len() < 6000);
    let limits = Limits {
        max_bytes: 6000,
        ..Limits::default()
    };
    let e = read_path(&p, &limits).unwrap_err();
    assert!(
        matches!(
            e,
            ReadError::TooLarge {
                what: "total size of the external buffers",
                value: 8192,
                limit: 6000,
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn read_path_refuses_what_is_not_a_regular_file() {
    let dir = temp_dir("read-path-kinds");
    let dir = dir.path();
    // Named like a mesh, so neither the extension nor sniffing is what refuses it.
    let folder = dir.join("folder.obj");
    std::fs::create_dir_all(&folder).unwrap();
    match read_path(&folder, &Limits::default()) {
        Err(ReadError::Io(e)) => {
            assert_eq!(e.kind(), std::io::ErrorKind::IsADirectory);
            assert!(e.to_string().contains("is a directory"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    #[cfg(unix)]
    {
        for (dev, kind) in [
            ("/dev/zero", "character device"),
            ("/dev/null", "character device"),
        ] {
            if !Path::new(dev).exists() {
                continue;
            }
            match promptly(dev, move || read_path(Path::new(dev), &Limits::default())) {
                Err(ReadError::Io(e)) => {
                    assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput, "{dev}");
                    assert!(e.to_string().contains(kind), "{dev}: {e}");
                    assert!(e.to_string().contains(dev), "{dev}: {e}");
                }
                other => panic!("{dev}: {other:?}"),
            }
        }
        let fifo = dir.join("fifo.ply");
        if mkfifo(&fifo) {
            let r = promptly("FIFO", move || read_path(&fifo, &Limits::default()));
            assert!(
                matches!(&r, Err(ReadError::Io(e)) if e.to_string().contains("FIFO")),
                "{r:?}"
            );
        }
    }
}

#[test]
fn gltf_primitive_instances_are_bounded() {
    // 2^13 - 1 node instances (well under MAX_NODE_VISITS), the 2^12 leaves sharing one
    // mesh of 4096 line primitives: 2^24 primitive instances, past MAX_PRIMITIVE_INSTANCES.
    let levels = 12;
    let mut nodes: Vec<String> = (0..levels)
        .map(|i| format!("{{\"children\":[{0},{0}]}}", i + 1))
        .collect();
    nodes.push("{\"mesh\":0}".into());
    let prims = vec!["{\"mode\":1}"; 4096].join(",");
    let doc = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{}],"meshes":[{{"primitives":[{prims}]}}]}}"#,
        nodes.join(",")
    );
    assert!((1u64 << (levels + 1)) < MAX_NODE_VISITS);
    assert!((1u64 << levels) * 4096 > MAX_PRIMITIVE_INSTANCES);
    let start = Instant::now();
    let e = promptly("shared mesh of many primitives", move || {
        read_bytes(doc.as_bytes(), Format::Gltf, &Limits::default())
    })
    .unwrap_err();
    assert!(
        matches!(
            e,
            ReadError::TooLarge {
                what: "primitive instance count",
                limit: MAX_PRIMITIVE_INSTANCES,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "{:?}",
        start.elapsed()
    );
    // Without the sharing the same mesh is read once, and is merely empty (lines only).
    let once = format!(r#"{{"asset":{{"version":"2.0"}},"meshes":[{{"primitives":[{prims}]}}]}}"#);
    assert!(matches!(
        read_bytes(once.as_bytes(), Format::Gltf, &Limits::default()),
        Err(ReadError::Empty { .. })
    ));
}
