//! glTF 2.0: `.gltf` JSON and binary `.glb`, reader and GLB writer.
//!
//! Read: every primitive of every mesh instance reachable from the default scene (or, with
//! no default, from the roots of every scene; with no scenes at all, every mesh once, untransformed).
//! Node transforms (matrix or TRS, composed down the hierarchy) are applied to positions;
//! normals use the inverse-transpose and are renormalised; triangle winding is flipped where
//! the transform's determinant is negative. Modes: TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN,
//! POINTS (as unconnected vertices); line modes are skipped. Indices u8/u16/u32; attributes
//! float or (normalized) integer components. The mesh has normals only when every primitive
//! read has a NORMAL attribute.
//!
//! Not supported (-> [`ReadError::Unsupported`]): sparse accessors, Draco / meshopt
//! compression and any other required extension that changes geometry, external buffers
//! when reading from memory, and external buffer URIs that are not plain relative paths
//! inside the `.gltf` file's folder (after percent-decoding: no absolute path, no `..`, no
//! scheme, drive letter or backslash).
//!
//! Every offset, length and stride is checked; the node graph must be acyclic and at most
//! [`MAX_NODE_DEPTH`] deep, at most [`MAX_NODE_VISITS`] node instances are expanded and at
//! most [`MAX_PRIMITIVE_INSTANCES`] primitive instances are read. External buffers must be
//! regular files and together hold at most [`Limits::max_bytes`].

use std::collections::BTreeMap;
use std::path::{Component, Path, PathBuf};

use glam::{Mat3, Mat4, Quat, Vec3};
use serde::Deserialize;

use super::{Format, Limits, Location, ReadError, check_limit, finish, malformed, vertex_limit};
use crate::geometry::mesh::Mesh;

/// Deepest node hierarchy accepted.
pub const MAX_NODE_DEPTH: usize = 64;
/// Most node instances expanded while walking the scene (guards against shared subtrees
/// that multiply exponentially).
pub const MAX_NODE_VISITS: u64 = 1 << 20;
/// Most primitive instances read while walking the scene: every instance of a mesh counts
/// all its primitives, even those skipped (lines), so that a few node instances of a mesh
/// with many primitives cannot multiply into unbounded work.
pub const MAX_PRIMITIVE_INSTANCES: u64 = 1 << 22;

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

// ---------------------------------------------------------------------------------------------
// The JSON subset we read.

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase")]
struct Root {
    asset: Option<Asset>,
    scene: Option<usize>,
    #[serde(default)]
    scenes: Vec<Scene>,
    #[serde(default)]
    nodes: Vec<Node>,
    #[serde(default)]
    meshes: Vec<GMesh>,
    #[serde(default)]
    accessors: Vec<Accessor>,
    #[serde(default)]
    buffer_views: Vec<BufferView>,
    #[serde(default)]
    buffers: Vec<Buffer>,
    #[serde(default)]
    extensions_required: Vec<String>,
}

#[derive(Deserialize)]
struct Asset {
    version: String,
}

#[derive(Deserialize, Default)]
struct Scene {
    #[serde(default)]
    nodes: Vec<usize>,
}

#[derive(Deserialize, Default)]
struct Node {
    #[serde(default)]
    children: Vec<usize>,
    mesh: Option<usize>,
    matrix: Option<[f32; 16]>,
    translation: Option<[f32; 3]>,
    rotation: Option<[f32; 4]>,
    scale: Option<[f32; 3]>,
}

#[derive(Deserialize)]
struct GMesh {
    #[serde(default)]
    primitives: Vec<Primitive>,
}

#[derive(Deserialize)]
struct Primitive {
    #[serde(default)]
    attributes: BTreeMap<String, usize>,
    indices: Option<usize>,
    #[serde(default = "default_mode")]
    mode: u32,
    #[serde(default)]
    extensions: BTreeMap<String, serde_json::Value>,
}

fn default_mode() -> u32 {
    4
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Accessor {
    buffer_view: Option<usize>,
    #[serde(default)]
    byte_offset: u64,
    component_type: u32,
    #[serde(default)]
    normalized: bool,
    count: u64,
    #[serde(rename = "type")]
    kind: String,
    sparse: Option<serde_json::Value>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct BufferView {
    buffer: usize,
    #[serde(default)]
    byte_offset: u64,
    byte_length: u64,
    byte_stride: Option<u64>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Buffer {
    uri: Option<String>,
    byte_length: u64,
}

/// Required extensions that do not change how geometry is read (or that we handle).
const HARMLESS_EXTENSIONS: &[&str] = &[
    "KHR_mesh_quantization",
    "KHR_texture_transform",
    "KHR_texture_basisu",
    "KHR_materials_unlit",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_lights_punctual",
    "EXT_texture_webp",
];

// ---------------------------------------------------------------------------------------------
// Entry points.

/// Reads a `.gltf` JSON document; `base` is the folder external buffer URIs are relative
/// to (`None`: only `data:` URIs are allowed).
pub(super) fn read_gltf(
    bytes: &[u8],
    limits: &Limits,
    base: Option<&Path>,
) -> Result<Mesh, ReadError> {
    let f = Format::Gltf;
    let text = super::utf8(f, bytes)?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let root = parse_json(f, text.as_bytes())?;
    Reader {
        f,
        root: &root,
        limits,
        base,
        bin: None,
        data: Vec::new(),
        external_bytes: 0,
    }
    .read()
}

/// Reads a binary glTF (GLB) container.
pub(super) fn read_glb(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let f = Format::Glb;
    let u32_at = |o: usize| -> Result<u32, ReadError> {
        bytes
            .get(o..o + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .ok_or(ReadError::Truncated {
                format: f,
                offset: bytes.len() as u64,
                expected: (o + 4 - bytes.len().min(o + 4)) as u64,
            })
    };
    if bytes.len() >= 4 && &bytes[..4] != GLB_MAGIC {
        return Err(malformed(
            f,
            Location::Byte(0),
            "missing `glTF` magic: not a GLB file",
        ));
    }
    let version = u32_at(4)?;
    if version != 2 {
        return Err(ReadError::Unsupported {
            format: f,
            what: format!("GLB container version {version} (only 2 is supported)"),
        });
    }
    let total = u32_at(8)? as u64;
    if total > bytes.len() as u64 {
        return Err(ReadError::Truncated {
            format: f,
            offset: bytes.len() as u64,
            expected: total - bytes.len() as u64,
        });
    }
    let bytes = &bytes[..total as usize];
    let mut pos = 12usize;
    let mut json: Option<&[u8]> = None;
    let mut bin: Option<&[u8]> = None;
    let mut json_offset = 0;
    while pos < bytes.len() {
        let len = u32_at(pos)? as usize;
        let kind = u32_at(pos + 4)?;
        let start = pos + 8;
        let end =
            start
                .checked_add(len)
                .filter(|&e| e <= bytes.len())
                .ok_or(ReadError::Truncated {
                    format: f,
                    offset: start as u64,
                    expected: (start as u64 + len as u64).saturating_sub(bytes.len() as u64),
                })?;
        let data = &bytes[start..end];
        match kind {
            CHUNK_JSON if json.is_none() && pos == 12 => {
                json = Some(data);
                json_offset = start;
            }
            CHUNK_BIN if json.is_some() && bin.is_none() => bin = Some(data),
            CHUNK_JSON | CHUNK_BIN => {
                return Err(malformed(
                    f,
                    Location::Byte(pos as u64),
                    "unexpected chunk order",
                ));
            }
            _ => {} // unknown chunks are ignored
        }
        pos = end;
    }
    let json = json.ok_or_else(|| malformed(f, Location::Byte(12), "no JSON chunk"))?;
    let text = std::str::from_utf8(json).map_err(|e| ReadError::InvalidUtf8 {
        format: f,
        offset: (json_offset + e.valid_up_to()) as u64,
    })?;
    let text = text.trim_end_matches(['\0', ' ']);
    let root = parse_json(f, text.as_bytes())?;
    Reader {
        f,
        root: &root,
        limits,
        base: None,
        bin,
        data: Vec::new(),
        external_bytes: 0,
    }
    .read()
}

fn parse_json(f: Format, bytes: &[u8]) -> Result<Root, ReadError> {
    serde_json::from_slice(bytes).map_err(|e| {
        malformed(
            f,
            Location::Line(e.line()),
            format!("invalid glTF JSON: {e}"),
        )
    })
}

// ---------------------------------------------------------------------------------------------

struct Reader<'a> {
    f: Format,
    root: &'a Root,
    limits: &'a Limits,
    base: Option<&'a Path>,
    bin: Option<&'a [u8]>,
    /// Loaded buffers, by index.
    data: Vec<Option<std::borrow::Cow<'a, [u8]>>>,
    /// Bytes read from external buffer files so far.
    external_bytes: u64,
}

/// What one accessor holds.
struct View<'b> {
    bytes: &'b [u8],
    count: usize,
    stride: usize,
    ctype: u32,
    normalized: bool,
}

impl View<'_> {
    fn component(&self, i: usize, c: usize) -> f32 {
        let size = component_size(self.ctype).unwrap_or(4);
        let o = i * self.stride + c * size;
        let b = &self.bytes[o..o + size];
        let n = self.normalized;
        match self.ctype {
            5120 => {
                let v = b[0] as i8 as f32;
                if n { (v / 127.0).max(-1.0) } else { v }
            }
            5121 => {
                let v = b[0] as f32;
                if n { v / 255.0 } else { v }
            }
            5122 => {
                let v = i16::from_le_bytes([b[0], b[1]]) as f32;
                if n { (v / 32767.0).max(-1.0) } else { v }
            }
            5123 => {
                let v = u16::from_le_bytes([b[0], b[1]]) as f32;
                if n { v / 65535.0 } else { v }
            }
            5125 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
            _ => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        }
    }

    fn index(&self, i: usize) -> u32 {
        let o = i * self.stride;
        let b = &self.bytes[o..];
        match self.ctype {
            5121 => b[0] as u32,
            5123 => u16::from_le_bytes([b[0], b[1]]) as u32,
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        }
    }
}

fn component_size(ctype: u32) -> Option<usize> {
    Some(match ctype {
        5120 | 5121 => 1,
        5122 | 5123 => 2,
        5125 | 5126 => 4,
        _ => return None,
    })
}

fn component_count(kind: &str) -> Option<usize> {
    Some(match kind {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT2" => 4,
        "MAT3" => 9,
        "MAT4" => 16,
        _ => return None,
    })
}

struct Out {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    all_have_normals: bool,
    /// Node instances expanded (see [`MAX_NODE_VISITS`]).
    visits: u64,
    /// Primitive instances read (see [`MAX_PRIMITIVE_INSTANCES`]).
    primitive_instances: u64,
}

impl<'a> Reader<'a> {
    fn err(&self, item: String, msg: impl Into<String>) -> ReadError {
        malformed(self.f, Location::Item(item), msg)
    }

    fn read(mut self) -> Result<Mesh, ReadError> {
        let f = self.f;
        let root = self.root;
        match &root.asset {
            Some(a) if a.version.starts_with("2.") => {}
            Some(a) => {
                return Err(ReadError::Unsupported {
                    format: f,
                    what: format!("glTF version {} (only 2.x is supported)", a.version),
                });
            }
            None => return Err(self.err("asset".into(), "missing `asset`")),
        }
        if let Some(e) = root
            .extensions_required
            .iter()
            .find(|e| !HARMLESS_EXTENSIONS.contains(&e.as_str()))
        {
            return Err(ReadError::Unsupported {
                format: f,
                what: format!("required extension {e}"),
            });
        }
        self.data = (0..root.buffers.len()).map(|_| None).collect();
        let mut out = Out {
            positions: Vec::new(),
            normals: Vec::new(),
            faces: Vec::new(),
            all_have_normals: true,
            visits: 0,
            primitive_instances: 0,
        };
        let roots: Vec<usize> = if root.scenes.is_empty() {
            for m in 0..root.meshes.len() {
                self.mesh(m, Mat4::IDENTITY, &mut out)?;
            }
            Vec::new()
        } else if let Some(s) = root.scene {
            let scene = root
                .scenes
                .get(s)
                .ok_or_else(|| self.err("scene".into(), format!("scene {s} does not exist")))?;
            scene.nodes.clone()
        } else {
            root.scenes
                .iter()
                .flat_map(|s| s.nodes.iter().copied())
                .collect()
        };
        let mut on_path = vec![false; root.nodes.len()];
        for r in roots {
            self.node(r, Mat4::IDENTITY, 0, &mut on_path, &mut out)?;
        }
        let normals = if out.all_have_normals {
            out.normals
        } else {
            Vec::new()
        };
        finish(f, out.positions, normals, out.faces)
    }

    fn node(
        &mut self,
        n: usize,
        parent: Mat4,
        depth: usize,
        on_path: &mut [bool],
        out: &mut Out,
    ) -> Result<(), ReadError> {
        let root = self.root;
        let node = root
            .nodes
            .get(n)
            .ok_or_else(|| self.err(format!("nodes[{n}]"), "node does not exist"))?;
        if on_path[n] {
            return Err(self.err(format!("nodes[{n}]"), "the node hierarchy has a cycle"));
        }
        if depth >= MAX_NODE_DEPTH {
            return Err(self.err(
                format!("nodes[{n}]"),
                format!("node hierarchy deeper than {MAX_NODE_DEPTH}"),
            ));
        }
        out.visits += 1;
        check_limit(self.f, "node instance count", out.visits, MAX_NODE_VISITS)?;
        let local = if let Some(m) = node.matrix {
            Mat4::from_cols_array(&m)
        } else {
            let t = Vec3::from_array(node.translation.unwrap_or([0.0; 3]));
            let s = Vec3::from_array(node.scale.unwrap_or([1.0; 3]));
            let r = node.rotation.unwrap_or([0.0, 0.0, 0.0, 1.0]);
            let q = Quat::from_array(r);
            let len = q.length();
            if !(len.is_finite() && len > 1e-6) {
                return Err(self.err(
                    format!("nodes[{n}].rotation"),
                    "rotation is not a valid quaternion",
                ));
            }
            Mat4::from_scale_rotation_translation(s, q / len, t)
        };
        let world = parent * local;
        if let Some(m) = node.mesh {
            self.mesh(m, world, out)?;
        }
        on_path[n] = true;
        for &c in &node.children {
            self.node(c, world, depth + 1, on_path, out)?;
        }
        on_path[n] = false;
        Ok(())
    }

    fn mesh(&mut self, m: usize, world: Mat4, out: &mut Out) -> Result<(), ReadError> {
        let root = self.root;
        let f = self.f;
        let limits = self.limits;
        let err = |item: String, msg: String| malformed(f, Location::Item(item), msg);
        let mesh = root
            .meshes
            .get(m)
            .ok_or_else(|| err(format!("meshes[{m}]"), "mesh does not exist".into()))?;
        out.primitive_instances = out
            .primitive_instances
            .saturating_add(mesh.primitives.len() as u64);
        check_limit(
            f,
            "primitive instance count",
            out.primitive_instances,
            MAX_PRIMITIVE_INSTANCES,
        )?;
        let normal_m = Mat3::from_mat4(world).inverse().transpose();
        let flip = world.determinant() < 0.0;
        // Identity: keep the stored bits exactly (no -0.0 + 0.0, no renormalising).
        let identity = world == Mat4::IDENTITY;
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let item = || format!("meshes[{m}].primitives[{p}]");
            if let Some(e) = prim
                .extensions
                .keys()
                .find(|e| e.contains("draco") || e.contains("meshopt") || e.contains("compression"))
            {
                return Err(ReadError::Unsupported {
                    format: f,
                    what: format!("compressed primitive ({e}) in {}", item()),
                });
            }
            let mode = prim.mode;
            if matches!(mode, 1..=3) {
                continue; // lines carry no surface
            }
            if mode > 6 {
                return Err(err(item(), format!("unknown primitive mode {mode}")));
            }
            let &pos_acc = prim
                .attributes
                .get("POSITION")
                .ok_or_else(|| err(item(), "primitive has no POSITION attribute".into()))?;
            let base = out.positions.len();
            {
                let v = self.accessor(pos_acc, &["VEC3"], vertex_limit(limits))?;
                let total = base as u64 + v.count as u64;
                check_limit(f, "vertex count", total, vertex_limit(limits))?;
                out.positions.reserve(v.count);
                for i in 0..v.count {
                    let local = Vec3::new(v.component(i, 0), v.component(i, 1), v.component(i, 2));
                    let w = if identity {
                        local
                    } else {
                        world.transform_point3(local)
                    };
                    if !w.is_finite() {
                        return Err(ReadError::NonFinite {
                            format: f,
                            location: Location::Item(format!("accessors[{pos_acc}] element {i}")),
                        });
                    }
                    out.positions.push(w);
                }
            }
            let count = out.positions.len() - base;
            match prim.attributes.get("NORMAL") {
                Some(&na) if out.all_have_normals => {
                    let v = self.accessor(na, &["VEC3"], vertex_limit(limits))?;
                    if v.count != count {
                        return Err(err(
                            format!("accessors[{na}]"),
                            format!("{} normals for {count} positions", v.count),
                        ));
                    }
                    out.normals.reserve(count);
                    for i in 0..count {
                        let local =
                            Vec3::new(v.component(i, 0), v.component(i, 1), v.component(i, 2));
                        out.normals.push(if identity {
                            local
                        } else {
                            (normal_m * local).normalize_or_zero()
                        });
                    }
                }
                Some(_) => {}
                None => {
                    out.all_have_normals = false;
                    out.normals = Vec::new();
                }
            }
            if mode == 0 {
                continue;
            }
            // Vertex ids of the primitive, in order.
            let ids: Vec<u32> = match prim.indices {
                Some(ia) => {
                    let max_idx = (limits.max_faces as u64).saturating_mul(3);
                    let v = self.accessor(ia, &["SCALAR"], max_idx)?;
                    if !matches!(v.ctype, 5121 | 5123 | 5125) {
                        return Err(err(
                            format!("accessors[{ia}]"),
                            format!("component type {} is not valid for indices", v.ctype),
                        ));
                    }
                    let mut ids = Vec::with_capacity(v.count);
                    for i in 0..v.count {
                        let x = v.index(i);
                        if x as usize >= count {
                            return Err(ReadError::IndexOutOfRange {
                                what: "vertices",
                                format: f,
                                location: Location::Item(format!("accessors[{ia}] element {i}")),
                                index: x as i64,
                                count,
                            });
                        }
                        ids.push(x);
                    }
                    ids
                }
                None => (0..count as u32).collect(),
            };
            let tris = match mode {
                4 => ids.len() / 3,
                _ => ids.len().saturating_sub(2),
            };
            check_limit(
                f,
                "triangle count",
                (out.faces.len() + tris) as u64,
                limits.max_faces as u64,
            )?;
            out.faces.reserve(tris);
            let b = base as u32;
            for t in 0..tris {
                let mut tri = match mode {
                    4 => [ids[3 * t], ids[3 * t + 1], ids[3 * t + 2]],
                    5 if t % 2 == 0 => [ids[t], ids[t + 1], ids[t + 2]],
                    5 => [ids[t + 1], ids[t], ids[t + 2]],
                    _ => [ids[0], ids[t + 1], ids[t + 2]],
                };
                if flip {
                    tri.swap(1, 2);
                }
                out.faces.push(tri.map(|i| i + b));
            }
        }
        Ok(())
    }

    /// Loads buffer `b`.
    fn buffer(&mut self, b: usize) -> Result<&[u8], ReadError> {
        let f = self.f;
        let item = format!("buffers[{b}]");
        let root = self.root;
        let buf = root
            .buffers
            .get(b)
            .ok_or_else(|| self.err(item.clone(), "buffer does not exist"))?;
        if self.data[b].is_none() {
            check_limit(
                f,
                "buffer byteLength",
                buf.byte_length,
                self.limits.max_bytes,
            )?;
            let data: std::borrow::Cow<'a, [u8]> = match &buf.uri {
                None => match (f, b, self.bin) {
                    (Format::Glb, 0, Some(bin)) => bin.into(),
                    _ => return Err(self.err(item, "buffer has no `uri` and no GLB BIN chunk")),
                },
                Some(uri) if uri.starts_with("data:") => {
                    let (_, payload) =
                        uri.split_once(";base64,")
                            .ok_or_else(|| ReadError::Unsupported {
                                format: f,
                                what: format!("{item}: data URI that is not base64"),
                            })?;
                    check_limit(
                        f,
                        "data URI size",
                        super::base64::decoded_len(payload) as u64,
                        self.limits.max_bytes,
                    )?;
                    super::base64::decode(payload)
                        .map_err(|i| {
                            malformed(
                                f,
                                Location::Item(item.clone()),
                                format!("invalid base64 at character {i} of the data URI"),
                            )
                        })?
                        .into()
                }
                Some(uri) => {
                    let bytes = self.external(&item, uri)?;
                    self.external_bytes += bytes.len() as u64;
                    check_limit(
                        f,
                        "total size of the external buffers",
                        self.external_bytes,
                        self.limits.max_bytes,
                    )?;
                    bytes.into()
                }
            };
            if (data.len() as u64) < buf.byte_length {
                return Err(self.err(
                    item,
                    format!(
                        "buffer holds {} bytes but declares byteLength {}",
                        data.len(),
                        buf.byte_length
                    ),
                ));
            }
            self.data[b] = Some(data);
        }
        Ok(self.data[b].as_deref().unwrap_or(&[]))
    }

    fn external(&self, item: &str, uri: &str) -> Result<Vec<u8>, ReadError> {
        let f = self.f;
        let Some(base) = self.base else {
            return Err(ReadError::Unsupported {
                format: f,
                what: format!("{item}: external buffer `{uri}` (read the file with read_path)"),
            });
        };
        let rel = relative_buffer_path(uri).map_err(|why| ReadError::Unsupported {
            format: f,
            what: format!("{item}: buffer URI `{uri}` {why}"),
        })?;
        super::read_file(
            &base.join(rel),
            f,
            "external buffer size",
            self.limits.max_bytes,
        )
    }

    /// Checks accessor `a` against its buffer view and buffer and returns its bytes.
    fn accessor(
        &mut self,
        a: usize,
        kinds: &[&str],
        max_count: u64,
    ) -> Result<View<'_>, ReadError> {
        let f = self.f;
        let root = self.root;
        let item = format!("accessors[{a}]");
        let acc = root
            .accessors
            .get(a)
            .ok_or_else(|| self.err(item.clone(), "accessor does not exist"))?;
        if acc.sparse.is_some() {
            return Err(ReadError::Unsupported {
                format: f,
                what: format!("{item}: sparse accessors"),
            });
        }
        if !kinds.contains(&acc.kind.as_str()) {
            return Err(self.err(
                item,
                format!("type {} where {} is expected", acc.kind, kinds.join("/")),
            ));
        }
        let comps = component_count(&acc.kind).unwrap_or(1);
        let csize = component_size(acc.component_type).ok_or_else(|| {
            self.err(
                item.clone(),
                format!("unknown componentType {}", acc.component_type),
            )
        })?;
        check_limit(f, "accessor count", acc.count, max_count)?;
        let elem = (comps * csize) as u64;
        let Some(bv) = acc.buffer_view else {
            return Err(ReadError::Unsupported {
                format: f,
                what: format!("{item}: accessor without bufferView"),
            });
        };
        let view = root
            .buffer_views
            .get(bv)
            .ok_or_else(|| self.err(item.clone(), format!("bufferView {bv} does not exist")))?;
        let vitem = format!("bufferViews[{bv}]");
        let stride = view.byte_stride.unwrap_or(elem);
        if stride < elem || stride > 252 {
            return Err(self.err(
                vitem,
                format!("byteStride {stride} is invalid for {elem}-byte elements"),
            ));
        }
        let view_end = view.byte_offset.checked_add(view.byte_length);
        let buffer = self.buffer(view.buffer)?;
        let buf_len = buffer.len() as u64;
        let Some(view_end) = view_end.filter(|&e| e <= buf_len) else {
            return Err(malformed(
                f,
                Location::Item(vitem),
                format!(
                    "byteOffset {} + byteLength {} is past the end of buffer {} ({buf_len} bytes)",
                    view.byte_offset, view.byte_length, view.buffer
                ),
            ));
        };
        // Bytes the accessor spans inside the view.
        let span = if acc.count == 0 {
            Some(0)
        } else {
            (acc.count - 1)
                .checked_mul(stride)
                .and_then(|s| s.checked_add(elem))
        };
        let end = span.and_then(|s| s.checked_add(acc.byte_offset));
        if end.is_none_or(|e| e > view.byte_length) {
            return Err(malformed(
                f,
                Location::Item(item),
                format!(
                    "{} elements from byteOffset {} do not fit in bufferView {bv} ({} bytes)",
                    acc.count, acc.byte_offset, view.byte_length
                ),
            ));
        }
        let start = (view.byte_offset + acc.byte_offset) as usize;
        let stop = start + span.unwrap_or(0) as usize;
        debug_assert!(stop as u64 <= view_end);
        Ok(View {
            bytes: &buffer[start..stop],
            count: acc.count as usize,
            stride: stride as usize,
            ctype: acc.component_type,
            normalized: acc.normalized,
        })
    }
}

/// The path a buffer URI names relative to the `.gltf` file's folder, or why it is refused.
///
/// The URI is percent-decoded first, so `%2E%2E/x` or `%2Fetc` are judged as the `../x` and
/// `/etc` they name. Only plain relative paths are accepted: no root or drive prefix, no `..`
/// (`.` is harmless), and no `:` (a scheme such as `file:` or a drive letter), `\` or NUL.
fn relative_buffer_path(uri: &str) -> Result<PathBuf, &'static str> {
    let decoded = percent_decode(uri);
    if decoded.contains([':', '\\', '\0']) {
        return Err("is not a relative file path");
    }
    let path = PathBuf::from(decoded);
    let mut names = 0;
    for c in path.components() {
        match c {
            Component::Normal(_) => names += 1,
            Component::CurDir => {}
            Component::ParentDir => return Err("leaves the glTF file's folder (`..`)"),
            Component::RootDir | Component::Prefix(_) => {
                return Err("is an absolute path, not relative to the glTF file's folder");
            }
        }
    }
    if names == 0 {
        return Err("names no file");
    }
    Ok(path)
}

fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && let Some(h) = s
                .get(i + 1..i + 3)
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        {
            out.push(h);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

// ---------------------------------------------------------------------------------------------
// Writer.

/// Writes a GLB (binary glTF 2.0) that the Khronos validator accepts without errors.
///
/// One node, one mesh, one primitive: `POSITION` (with min/max), `NORMAL` when the mesh has
/// normals (renormalised; if one cannot be, normals are left out) and `u32` indices in
/// TRIANGLES mode, or POINTS mode without indices for a point cloud. An empty mesh gives a
/// document with an empty scene. The mesh should pass [`Mesh::validate`]; GLB cannot hold
/// more than 4 GiB (about 150 M vertices with normals), which [`Limits`] keeps far away.
pub fn write_glb(mesh: &Mesh) -> Vec<u8> {
    use serde_json::json;
    let n = mesh.positions.len();
    let normals = super::fix_normals(mesh.normals.clone(), n);
    let mut bin: Vec<u8> = Vec::with_capacity(n * 24 + mesh.faces.len() * 12);
    for p in &mesh.positions {
        for c in p.to_array() {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    let pos_len = bin.len();
    for v in &normals {
        for c in v.to_array() {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    let nrm_len = bin.len() - pos_len;
    for f in &mesh.faces {
        for i in f {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    let idx_len = bin.len() - pos_len - nrm_len;

    let mut doc = json!({
        "asset": { "version": "2.0", "generator": "meshflow" },
        "scene": 0,
    });
    if n == 0 {
        doc["scenes"] = json!([{}]);
    } else {
        let aabb = mesh.aabb().unwrap_or(crate::geometry::mesh::Aabb {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        });
        let mut views =
            vec![json!({"buffer": 0, "byteOffset": 0, "byteLength": pos_len, "target": 34962})];
        let mut accessors = vec![json!({
            "bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
            "min": aabb.min.to_array(), "max": aabb.max.to_array(),
        })];
        let mut attributes = json!({ "POSITION": 0 });
        if nrm_len > 0 {
            attributes["NORMAL"] = json!(accessors.len());
            views.push(
                json!({"buffer": 0, "byteOffset": pos_len, "byteLength": nrm_len, "target": 34962}),
            );
            accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5126, "count": n, "type": "VEC3"}));
        }
        let mut primitive = json!({ "attributes": attributes, "mode": 0 });
        if idx_len > 0 {
            views.push(json!({"buffer": 0, "byteOffset": pos_len + nrm_len, "byteLength": idx_len, "target": 34963}));
            accessors.push(json!({
                "bufferView": views.len() - 1, "componentType": 5125,
                "count": mesh.faces.len() * 3, "type": "SCALAR",
            }));
            primitive["indices"] = json!(accessors.len() - 1);
            primitive["mode"] = json!(4);
        }
        doc["scenes"] = json!([{ "nodes": [0] }]);
        doc["nodes"] = json!([{ "mesh": 0 }]);
        doc["meshes"] = json!([{ "primitives": [primitive] }]);
        doc["accessors"] = json!(accessors);
        doc["bufferViews"] = json!(views);
        doc["buffers"] = json!([{ "byteLength": bin.len() }]);
    }
    let mut json_bytes = serde_json::to_vec(&doc).unwrap_or_default();
    while !json_bytes.len().is_multiple_of(4) {
        json_bytes.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let has_bin = !bin.is_empty();
    let total = 12 + 8 + json_bytes.len() + if has_bin { 8 + bin.len() } else { 0 };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(GLB_MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_bytes.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(&json_bytes);
    if has_bin {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::cube;

    /// Why the GLB container stays ours (docs/design.md section 7): `gltf`'s `Glb::from_slice`
    /// subtracts 12 from this length unchecked.
    #[test]
    fn glb_header_length_under_12_is_an_error() {
        let mut g = write_glb(&cube());
        g[8..12].copy_from_slice(&4u32.to_le_bytes());
        let e = read_glb(&g, &Limits::default()).unwrap_err();
        assert!(matches!(e, ReadError::Malformed { .. }), "{e:?}");
    }

    /// Chunks of an unknown type are skipped, as the GLB specification asks.
    #[test]
    fn glb_unknown_chunks_are_ignored() {
        let mut g = write_glb(&cube());
        g.extend_from_slice(&4u32.to_le_bytes());
        g.extend_from_slice(b"XTRA");
        g.extend_from_slice(&[0; 4]);
        let len = g.len() as u32;
        g[8..12].copy_from_slice(&len.to_le_bytes());
        let m = read_glb(&g, &Limits::default()).unwrap();
        assert_eq!(m.faces.len(), cube().faces.len());
    }

    /// A scene without `nodes` is valid glTF (our own empty GLB has one): it reads as empty,
    /// not as malformed.
    #[test]
    fn scene_without_nodes_is_empty_not_malformed() {
        let e = read_glb(&write_glb(&Mesh::default()), &Limits::default()).unwrap_err();
        assert!(matches!(e, ReadError::Empty { .. }), "{e:?}");
    }

    /// The fuzz seeds read without panicking, and what they give passes `Mesh::validate`.
    #[test]
    fn fuzz_seeds_read() {
        let seeds = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/seeds");
        for (dir, glb) in [("fuzz_gltf", false), ("fuzz_glb", true)] {
            for entry in std::fs::read_dir(seeds.join(dir)).unwrap() {
                let bytes = std::fs::read(entry.unwrap().path()).unwrap();
                let limits = Limits::default();
                let r = if glb {
                    read_glb(&bytes, &limits)
                } else {
                    read_gltf(&bytes, &limits, None)
                };
                if let Ok(m) = r {
                    assert!(m.validate().is_ok());
                }
            }
        }
    }
}
