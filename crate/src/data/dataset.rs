//! Training-data shards, the manifest that describes them, and the pure rules of the data
//! build (filter, duplicate keys, split).
//!
//! Nothing here touches the file system or spawns processes, so the same code reads shards
//! natively and in the browser; the data build (`build`, feature `data-build`) does the I/O.
//!
//! # Shard layout (`meshflow-shard`, version 1)
//!
//! A shard is one [safetensors](https://huggingface.co/docs/safetensors) file holding `M`
//! meshes, all already cleaned, rotated to Y-up and normalised to the model frame (longest
//! bounding-box side spanning [-1, 1], centred; see [`crate::geometry::normalize`]):
//!
//! | tensor           | dtype | shape            | content                                       |
//! |------------------|-------|------------------|-----------------------------------------------|
//! | `positions`      | F32   | `[V_total, 3]`   | vertex positions of all meshes, mesh by mesh  |
//! | `faces`          | U32   | `[F_total, 3]`   | triangles, indices *local* to their mesh      |
//! | `vertex_offsets` | U64   | `[M + 1]`        | mesh `i` owns vertices `vo[i]..vo[i+1]`       |
//! | `face_offsets`   | U64   | `[M + 1]`        | mesh `i` owns faces `fo[i]..fo[i+1]`          |
//!
//! The header's `__metadata__` is `{"format": "meshflow-shard", "version": "1"}`. Offsets
//! start at 0, never decrease and end at the tensor's row count; every face index of mesh `i`
//! is below its vertex count `vo[i+1] - vo[i]`. Normals are not stored: the loader recomputes
//! them (they change under augmentation anyway).
//!
//! [`ShardWriter::finish`] writes the bytes itself (header keys sorted, tensors in a fixed
//! order, header padded with spaces to a multiple of 8), so the same meshes give the same
//! bytes on every run and platform; [`Shard::from_bytes`] parses with the `safetensors` crate
//! and then checks every offset and index, returning a [`DatasetError`] on corrupt input.
//!
//! # Manifest
//!
//! `manifest.jsonl` holds one [`ManifestEntry`] per kept mesh, sorted by id. The id is
//! [`mesh_id`]: the hex of a 64-bit FNV-1a hash of the source package, the path inside it
//! (nested archive members joined with `!`) and the sub-mesh name, so it does not change
//! when other meshes are added or removed.

use std::collections::HashMap;
use std::fmt;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::data::cards::card_area_share;
use crate::geometry::clean::CleanReport;
use crate::geometry::normalize::UpAxis;
use crate::geometry::topology::{TopologyReport, adjacency, edges};

/// The `format` value in a shard's metadata.
pub const SHARD_FORMAT: &str = "meshflow-shard";
/// The `version` value in a shard's metadata.
pub const SHARD_VERSION: &str = "1";

/// Why a shard could not be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DatasetError {
    #[error("not a safetensors file: {0}")]
    Safetensors(String),
    #[error("the shard has no metadata `{key}` (is it a meshflow shard?)")]
    MissingMetadata { key: &'static str },
    #[error("the shard's metadata `{key}` is `{found}`, expected `{expected}`")]
    WrongMetadata {
        key: &'static str,
        found: String,
        expected: &'static str,
    },
    #[error("the shard has no tensor `{0}`")]
    MissingTensor(&'static str),
    #[error("tensor `{tensor}` has dtype {found}, expected {expected}")]
    WrongDtype {
        tensor: &'static str,
        found: String,
        expected: &'static str,
    },
    #[error("tensor `{tensor}` has shape {shape:?}, expected {expected}")]
    WrongShape {
        tensor: &'static str,
        shape: Vec<usize>,
        expected: &'static str,
    },
    #[error("`{tensor}`: {message}")]
    BadOffsets {
        tensor: &'static str,
        message: String,
    },
    #[error("mesh {mesh}, face {face}: vertex index {index} but the mesh has {vertices} vertices")]
    IndexOutOfRange {
        mesh: usize,
        face: usize,
        index: u32,
        vertices: u64,
    },
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFinite { vertex: usize },
}

/// Collects meshes and writes them as one shard (see the module doc).
#[derive(Clone, Debug)]
pub struct ShardWriter {
    positions: Vec<f32>,
    faces: Vec<u32>,
    vertex_offsets: Vec<u64>,
    face_offsets: Vec<u64>,
}

impl Default for ShardWriter {
    fn default() -> Self {
        Self::new()
    }
}

impl ShardWriter {
    pub fn new() -> Self {
        Self {
            positions: Vec::new(),
            faces: Vec::new(),
            vertex_offsets: vec![0],
            face_offsets: vec![0],
        }
    }

    /// Appends a mesh (positions and faces; normals are not stored) and returns its index in
    /// the shard. The mesh should satisfy [`Mesh::validate`]; the reader rejects shards whose
    /// meshes do not.
    pub fn push(&mut self, mesh: &Mesh) -> usize {
        self.positions
            .extend(mesh.positions.iter().flat_map(|p| p.to_array()));
        self.faces.extend(mesh.faces.iter().flatten());
        self.vertex_offsets
            .push(self.vertex_offsets[self.vertex_offsets.len() - 1] + mesh.positions.len() as u64);
        self.face_offsets
            .push(self.face_offsets[self.face_offsets.len() - 1] + mesh.faces.len() as u64);
        self.vertex_offsets.len() - 2
    }

    /// Number of meshes pushed so far.
    pub fn len(&self) -> usize {
        self.vertex_offsets.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Size in bytes of the tensor data so far (the header adds a few hundred bytes).
    pub fn data_bytes(&self) -> u64 {
        4 * (self.positions.len() + self.faces.len()) as u64
            + 8 * (self.vertex_offsets.len() + self.face_offsets.len()) as u64
    }

    /// The shard's bytes. Deterministic: the same meshes pushed in the same order give the
    /// same bytes.
    pub fn finish(self) -> Vec<u8> {
        let v_total = self.positions.len() / 3;
        let f_total = self.faces.len() / 3;
        let m1 = self.vertex_offsets.len();
        // Tensors in data order: the 8-byte types first so every tensor stays aligned.
        let tensors: [(&str, &str, Vec<usize>, Vec<u8>); 4] = [
            (
                "face_offsets",
                "U64",
                vec![m1],
                le_bytes(&self.face_offsets),
            ),
            (
                "vertex_offsets",
                "U64",
                vec![m1],
                le_bytes(&self.vertex_offsets),
            ),
            (
                "positions",
                "F32",
                vec![v_total, 3],
                le_bytes(&self.positions),
            ),
            ("faces", "U32", vec![f_total, 3], le_bytes(&self.faces)),
        ];
        // The header, keys in sorted order (`__metadata__` sorts first).
        let mut entries: Vec<(String, String)> = Vec::new();
        let mut offset = 0usize;
        for (name, dtype, shape, data) in &tensors {
            let shape: Vec<String> = shape.iter().map(usize::to_string).collect();
            entries.push((
                name.to_string(),
                format!(
                    "{{\"dtype\":\"{dtype}\",\"shape\":[{}],\"data_offsets\":[{offset},{}]}}",
                    shape.join(","),
                    offset + data.len()
                ),
            ));
            offset += data.len();
        }
        entries.push((
            "__metadata__".into(),
            format!("{{\"format\":\"{SHARD_FORMAT}\",\"version\":\"{SHARD_VERSION}\"}}"),
        ));
        entries.sort();
        let body: Vec<String> = entries
            .iter()
            .map(|(k, v)| format!("\"{k}\":{v}"))
            .collect();
        let mut header = format!("{{{}}}", body.join(",")).into_bytes();
        header.resize(header.len().next_multiple_of(8), b' ');
        let mut out = Vec::with_capacity(8 + header.len() + offset);
        out.extend_from_slice(&(header.len() as u64).to_le_bytes());
        out.extend_from_slice(&header);
        for (_, _, _, data) in &tensors {
            out.extend_from_slice(data);
        }
        out
    }
}

trait LeBytes: Copy {
    const SIZE: usize;
    fn put(self, out: &mut Vec<u8>);
    fn get(bytes: &[u8]) -> Self;
}

macro_rules! le_bytes {
    ($($t:ty),*) => {$(
        impl LeBytes for $t {
            const SIZE: usize = std::mem::size_of::<$t>();
            fn put(self, out: &mut Vec<u8>) {
                out.extend_from_slice(&self.to_le_bytes());
            }
            fn get(b: &[u8]) -> Self {
                <$t>::from_le_bytes(b[..Self::SIZE].try_into().expect("caller passes SIZE bytes"))
            }
        }
    )*};
}

le_bytes!(f32, u32, u64);

fn le_bytes<T: LeBytes>(values: &[T]) -> Vec<u8> {
    let mut out = Vec::with_capacity(values.len() * T::SIZE);
    for &v in values {
        v.put(&mut out);
    }
    out
}

fn from_le<T: LeBytes>(bytes: &[u8]) -> Vec<T> {
    bytes.chunks_exact(T::SIZE).map(T::get).collect()
}

/// A parsed, validated shard.
#[derive(Clone, Debug, PartialEq)]
pub struct Shard {
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    vertex_offsets: Vec<u64>,
    face_offsets: Vec<u64>,
}

fn tensor<'a>(
    st: &safetensors::SafeTensors<'a>,
    name: &'static str,
    dtype: safetensors::Dtype,
    expected_dtype: &'static str,
    columns: Option<usize>,
) -> Result<(&'a [u8], usize), DatasetError> {
    let view = st
        .tensor(name)
        .map_err(|_| DatasetError::MissingTensor(name))?;
    if view.dtype() != dtype {
        return Err(DatasetError::WrongDtype {
            tensor: name,
            found: format!("{:?}", view.dtype()),
            expected: expected_dtype,
        });
    }
    let shape = view.shape();
    let ok = match columns {
        Some(c) => shape.len() == 2 && shape[1] == c,
        None => shape.len() == 1,
    };
    if !ok {
        return Err(DatasetError::WrongShape {
            tensor: name,
            shape: shape.to_vec(),
            expected: if columns.is_some() { "[n, 3]" } else { "[n]" },
        });
    }
    Ok((view.data(), shape[0]))
}

fn check_offsets(tensor: &'static str, offsets: &[u64], total: usize) -> Result<(), DatasetError> {
    let bad = |message: String| Err(DatasetError::BadOffsets { tensor, message });
    if offsets.is_empty() {
        return bad("empty (needs at least the leading 0)".into());
    }
    if offsets[0] != 0 {
        return bad(format!("starts at {}, not 0", offsets[0]));
    }
    if let Some(i) = offsets.windows(2).position(|w| w[1] < w[0]) {
        return bad(format!("decreases at mesh {i}"));
    }
    let last = offsets[offsets.len() - 1];
    if last != total as u64 {
        return bad(format!("ends at {last} but there are {total} rows"));
    }
    Ok(())
}

impl Shard {
    /// Parses and validates a shard: metadata, tensor names, dtypes and shapes, offsets
    /// (start at 0, non-decreasing, end at the row count, one per mesh plus one), face
    /// indices and finite positions. Never panics on corrupt input.
    pub fn from_bytes(bytes: &[u8]) -> Result<Shard, DatasetError> {
        use safetensors::Dtype;
        let st = safetensors::SafeTensors::deserialize(bytes)
            .map_err(|e| DatasetError::Safetensors(e.to_string()))?;
        let (_, meta) = safetensors::SafeTensors::read_metadata(bytes)
            .map_err(|e| DatasetError::Safetensors(e.to_string()))?;
        let empty = HashMap::new();
        let md = meta.metadata().as_ref().unwrap_or(&empty);
        for (key, expected) in [("format", SHARD_FORMAT), ("version", SHARD_VERSION)] {
            match md.get(key) {
                None => return Err(DatasetError::MissingMetadata { key }),
                Some(v) if v != expected => {
                    return Err(DatasetError::WrongMetadata {
                        key,
                        found: v.clone(),
                        expected,
                    });
                }
                Some(_) => {}
            }
        }
        let (pos, v_total) = tensor(&st, "positions", Dtype::F32, "F32", Some(3))?;
        let (fac, f_total) = tensor(&st, "faces", Dtype::U32, "U32", Some(3))?;
        let (vo, m1) = tensor(&st, "vertex_offsets", Dtype::U64, "U64", None)?;
        let (fo, m1f) = tensor(&st, "face_offsets", Dtype::U64, "U64", None)?;
        if m1 != m1f {
            return Err(DatasetError::BadOffsets {
                tensor: "face_offsets",
                message: format!("{m1f} entries but vertex_offsets has {m1}"),
            });
        }
        let vertex_offsets: Vec<u64> = from_le(vo);
        let face_offsets: Vec<u64> = from_le(fo);
        check_offsets("vertex_offsets", &vertex_offsets, v_total)?;
        check_offsets("face_offsets", &face_offsets, f_total)?;
        let flat: Vec<f32> = from_le(pos);
        let positions: Vec<Vec3> = flat.chunks_exact(3).map(Vec3::from_slice).collect();
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(DatasetError::NonFinite { vertex });
        }
        let flat: Vec<u32> = from_le(fac);
        let faces: Vec<[u32; 3]> = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        for mesh in 0..m1 - 1 {
            let vertices = vertex_offsets[mesh + 1] - vertex_offsets[mesh];
            let (f0, f1) = (face_offsets[mesh] as usize, face_offsets[mesh + 1] as usize);
            for (k, f) in faces[f0..f1].iter().enumerate() {
                if let Some(&index) = f.iter().find(|&&i| u64::from(i) >= vertices) {
                    return Err(DatasetError::IndexOutOfRange {
                        mesh,
                        face: k,
                        index,
                        vertices,
                    });
                }
            }
        }
        Ok(Shard {
            positions,
            faces,
            vertex_offsets,
            face_offsets,
        })
    }

    /// Number of meshes.
    pub fn len(&self) -> usize {
        self.vertex_offsets.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Mesh `i` (without normals), or `None` past the end.
    pub fn get(&self, i: usize) -> Option<Mesh> {
        if i >= self.len() {
            return None;
        }
        let (v0, v1) = (
            self.vertex_offsets[i] as usize,
            self.vertex_offsets[i + 1] as usize,
        );
        let (f0, f1) = (
            self.face_offsets[i] as usize,
            self.face_offsets[i + 1] as usize,
        );
        Some(Mesh::new(
            self.positions[v0..v1].to_vec(),
            self.faces[f0..f1].to_vec(),
        ))
    }

    /// Mesh `i` (without normals).
    ///
    /// # Panics
    /// When `i >= self.len()`; use [`Shard::get`] for a checked look-up.
    pub fn mesh(&self, i: usize) -> Mesh {
        match self.get(i) {
            Some(m) => m,
            None => panic!("mesh {i} of a shard with {} meshes", self.len()),
        }
    }
}

/// The training split a mesh belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Split {
    Train,
    Val,
    Test,
}

impl Split {
    pub const ALL: [Split; 3] = [Split::Train, Split::Val, Split::Test];

    pub fn name(&self) -> &'static str {
        match self {
            Split::Train => "train",
            Split::Val => "val",
            Split::Test => "test",
        }
    }
}

impl fmt::Display for Split {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One kept mesh, as a line of `manifest.jsonl`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestEntry {
    /// [`mesh_id`] of (package, path, sub-mesh), 16 hex digits.
    pub id: String,
    pub split: Split,
    /// File name of the shard holding the mesh, e.g. `train-00000.safetensors`.
    pub shard: String,
    /// Index of the mesh in that shard.
    pub index: usize,
    /// Source package (Debian package or PyPI project name).
    pub package: String,
    pub package_version: String,
    /// Path inside the package; members of (nested) archives are joined with `!`.
    pub path: String,
    /// Sub-mesh name, empty when the file is one mesh (all readers merge sub-meshes today).
    pub submesh: String,
    /// License of the source (docs/data.md's per-source table).
    pub license: String,
    pub vertices: usize,
    pub faces: usize,
    pub max_degree: usize,
    pub topology: TopologyReport,
    pub clean: CleanReport,
    /// The source's up axis: the mesh was rotated from it to the model frame's Y-up first
    /// ([`UpAxis::to_y_up`]).
    pub up_axis: UpAxis,
    /// The model-frame normalisation applied after that rotation:
    /// `p_model = (up_axis.to_y_up(p_source) - center) * scale`.
    pub center: [f32; 3],
    pub scale: f32,
    /// [`geometry_hash`] of the stored mesh, 16 hex digits.
    pub content_hash: String,
}

/// The entry as `meshflow data show` names it: id, source, path and counts.
impl fmt::Display for ManifestEntry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (id, package, version, path) =
            (&self.id, &self.package, &self.package_version, &self.path);
        let (v, faces) = (self.vertices, self.faces);
        write!(
            f,
            "{id} ({package} {version}, {path}): {v} vertices, {faces} faces"
        )
    }
}

/// Licenses (SPDX ids, as the manifest writes them) that allow redistribution without
/// copyleft: meshes under them may go into fixtures and examples, with their license text.
pub const PERMISSIVE_LICENSES: [&str; 6] = [
    "CC0-1.0",
    "MIT",
    "BSD-2-Clause",
    "BSD-3-Clause",
    "Apache-2.0",
    "Zlib",
];

/// True when `license` is one of [`PERMISSIVE_LICENSES`] (exactly; a compound or per-asset
/// license string is not).
pub fn is_permissive(license: &str) -> bool {
    PERMISSIVE_LICENSES.contains(&license)
}

/// 64-bit FNV-1a, a small stable hash (the same on every platform and run).
#[derive(Clone, Copy, Debug)]
pub struct Fnv64(u64);

impl Default for Fnv64 {
    fn default() -> Self {
        Self::new()
    }
}

impl Fnv64 {
    pub fn new() -> Self {
        Fnv64(0xcbf2_9ce4_8422_2325)
    }

    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// Writes a length-prefixed string, so ("ab", "c") and ("a", "bc") hash apart.
    pub fn write_str(&mut self, s: &str) {
        self.write(&(s.len() as u64).to_le_bytes());
        self.write(s.as_bytes());
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// Stable id of a mesh: FNV-1a of package, path inside the package and sub-mesh name.
pub fn mesh_id(package: &str, path: &str, submesh: &str) -> u64 {
    let mut h = Fnv64::new();
    h.write_str(package);
    h.write_str(path);
    h.write_str(submesh);
    h.finish()
}

/// Hash of a mesh's shape for duplicate detection, independent of vertex and face order.
///
/// Meant for meshes already welded and in the model frame: coordinates are rounded to
/// `quantum` (1e-4 in the build) for the hash only, each face becomes its three rounded
/// corners rotated so the smallest comes first (winding kept), and the sorted face list is
/// hashed.
pub fn geometry_hash(mesh: &Mesh, quantum: f32) -> u64 {
    let q = |p: Vec3| -> [i32; 3] { (p / quantum).round().to_array().map(|c| c as i32) };
    let mut faces: Vec<[[i32; 3]; 3]> = mesh
        .faces
        .iter()
        .map(|f| {
            let c = f.map(|i| q(mesh.positions[i as usize]));
            let m = (0..3).min_by_key(|&k| c[k]).unwrap_or(0);
            [c[m], c[(m + 1) % 3], c[(m + 2) % 3]]
        })
        .collect();
    faces.sort_unstable();
    let mut h = Fnv64::new();
    h.write(&(faces.len() as u64).to_le_bytes());
    for f in &faces {
        for c in f.iter().flatten() {
            h.write(&c.to_le_bytes());
        }
    }
    h.finish()
}

/// Largest number of distinct neighbours of any vertex.
pub fn max_degree(mesh: &Mesh) -> usize {
    adjacency(mesh.positions.len(), &edges(&mesh.faces))
        .iter()
        .map(Vec::len)
        .max()
        .unwrap_or(0)
}

/// The mesh filter's limits (docs/data.md; the first three are the paper's).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FilterOptions {
    pub max_vertices: usize,
    pub max_faces: usize,
    pub max_degree: usize,
    pub min_faces: usize,
    /// Smallest bounding-box side relative to the largest (removes billboards and decals).
    pub min_aspect: f32,
    /// Largest share of the area that may lie in billboard cards
    /// ([`crate::data::cards::card_area_share`]); a mesh at or above it is rejected.
    pub card_max_share: f32,
    /// Most faces a flat free sheet may have to count as a card (a quad is 2).
    pub card_max_faces: usize,
}

impl Default for FilterOptions {
    fn default() -> Self {
        Self {
            max_vertices: 4096,
            max_faces: 8000,
            max_degree: 50,
            min_faces: 20,
            min_aspect: 0.02,
            card_max_share: 0.75,
            card_max_faces: 8,
        }
    }
}

/// Why [`filter`] rejected a mesh. Checked in the order listed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FilterReason {
    TooManyVertices,
    TooManyFaces,
    TooFewFaces,
    Flat,
    DegreeTooHigh,
    /// Mostly billboard cards: crossed or free-standing quads (see [`crate::data::cards`]).
    Card,
}

impl FilterReason {
    pub fn name(&self) -> &'static str {
        match self {
            FilterReason::TooManyVertices => "too_many_vertices",
            FilterReason::TooManyFaces => "too_many_faces",
            FilterReason::TooFewFaces => "too_few_faces",
            FilterReason::Flat => "flat",
            FilterReason::DegreeTooHigh => "degree_too_high",
            FilterReason::Card => "card",
        }
    }
}

/// Applies the filter to a *cleaned* mesh (welded, unreferenced vertices dropped); returns
/// its max vertex degree when it passes. The checks, in [`FilterReason`]'s order: vertex and
/// face counts, the bounding box's aspect ("flat": one side under `min_aspect` of the longest,
/// which catches single billboards and decals), vertex degree, then the per-face card test
/// ([`card_area_share`]: crossed billboards and other meshes made mostly of free-standing
/// quads, which a bounding box cannot see).
pub fn filter(mesh: &Mesh, opts: &FilterOptions) -> Result<usize, FilterReason> {
    if mesh.positions.len() > opts.max_vertices {
        return Err(FilterReason::TooManyVertices);
    }
    if mesh.faces.len() > opts.max_faces {
        return Err(FilterReason::TooManyFaces);
    }
    if mesh.faces.len() < opts.min_faces {
        return Err(FilterReason::TooFewFaces);
    }
    let extent = mesh.aabb().map_or(Vec3::ZERO, |b| b.extent());
    if extent.min_element() < opts.min_aspect * extent.max_element() || extent.max_element() <= 0.0
    {
        return Err(FilterReason::Flat);
    }
    let degree = max_degree(mesh);
    if degree > opts.max_degree {
        return Err(FilterReason::DegreeTooHigh);
    }
    if card_area_share(mesh, opts.card_max_faces) >= opts.card_max_share {
        return Err(FilterReason::Card);
    }
    Ok(degree)
}

/// The name of the source object a file holds, for the split: the file stem of the last
/// path component (after the last `!` or `/`), lower-cased, with LOD and pose/frame suffixes
/// removed (`_lod1`, `-lod2`, `lod0`, trailing digits and separators), repeatedly, so
/// `Tree_02_LOD1.pmd` and `tree_03.pmd` both give `tree`. A stem that would become empty is
/// kept whole.
pub fn object_name(path: &str) -> String {
    let file = path.rsplit(['!', '/', '\\']).next().unwrap_or(path);
    let stem = match file.rfind('.') {
        Some(i) if i > 0 => &file[..i],
        _ => file,
    };
    let lower = stem.to_ascii_lowercase();
    let mut s = lower.as_str();
    loop {
        let before = s.len();
        s = s.trim_end_matches(|c: char| c.is_ascii_digit() || "_-. ".contains(c));
        if let Some(rest) = s.strip_suffix("lod") {
            s = rest;
        }
        if s.len() == before {
            break;
        }
    }
    if s.is_empty() { lower } else { s.to_string() }
}

/// The key a mesh is split by: package, folder inside the package (after the last `!`) and
/// [`object_name`]. The folder keeps generic stems ("tris", "body", "link") of different
/// objects apart while LOD and pose copies, which sit beside each other, stay together.
pub fn split_key(package: &str, path: &str) -> String {
    let inner = path.rsplit('!').next().unwrap_or(path);
    let folder = inner.rsplit_once('/').map_or("", |(d, _)| d);
    format!("{package}/{folder}/{}", object_name(path))
}

/// The deterministic ~90/5/5 split of a [`split_key`].
pub fn split_of(key: &str) -> Split {
    let mut h = Fnv64::new();
    h.write_str(key);
    // A finaliser (splitmix64's) spreads FNV's low bits before taking the remainder.
    let mut z = h.finish();
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    match z % 100 {
        0..90 => Split::Train,
        90..95 => Split::Val,
        _ => Split::Test,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::{grid, icosphere, octahedron};
    use proptest::prelude::*;

    #[test]
    fn an_entry_reads_as_id_source_and_counts() {
        let dir =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/dataset");
        let e = &crate::data::shards::read_manifest(&dir).unwrap()[0];
        let text = format!(
            "{} ({} {}, {}): ",
            e.id, e.package, e.package_version, e.path
        );
        let counts = format!("{} vertices, {} faces", e.vertices, e.faces);
        assert_eq!(e.to_string(), text + &counts);
    }

    fn sample_meshes() -> Vec<Mesh> {
        vec![octahedron(), icosphere(1), Mesh::default(), grid(3, 2)]
    }

    fn shard_of(meshes: &[Mesh]) -> Vec<u8> {
        let mut w = ShardWriter::new();
        for (i, m) in meshes.iter().enumerate() {
            assert_eq!(w.push(m), i);
        }
        w.finish()
    }

    #[test]
    fn round_trip() {
        let meshes = sample_meshes();
        let bytes = shard_of(&meshes);
        assert_eq!(bytes, shard_of(&meshes), "deterministic");
        let shard = Shard::from_bytes(&bytes).unwrap();
        assert_eq!(shard.len(), meshes.len());
        for (i, m) in meshes.iter().enumerate() {
            assert_eq!(
                shard.mesh(i),
                Mesh::new(m.positions.clone(), m.faces.clone())
            );
        }
        assert!(shard.get(meshes.len()).is_none());
    }

    #[test]
    fn empty_shard_round_trips() {
        let shard = Shard::from_bytes(&ShardWriter::new().finish()).unwrap();
        assert!(shard.is_empty());
    }

    #[test]
    fn readable_by_safetensors_with_metadata() {
        let bytes = shard_of(&[octahedron()]);
        let (_, meta) = safetensors::SafeTensors::read_metadata(&bytes).unwrap();
        let md = meta.metadata().as_ref().unwrap();
        assert_eq!(md["format"], "meshflow-shard");
        assert_eq!(md["version"], "1");
        let st = safetensors::SafeTensors::deserialize(&bytes).unwrap();
        assert_eq!(st.tensor("positions").unwrap().shape(), &[6, 3]);
        assert_eq!(st.tensor("faces").unwrap().shape(), &[8, 3]);
        assert_eq!(st.tensor("vertex_offsets").unwrap().shape(), &[2]);
    }

    /// Writes a safetensors file with the given tensors and metadata via the crate itself.
    fn custom(
        tensors: Vec<(&str, safetensors::Dtype, Vec<usize>, Vec<u8>)>,
        meta: &[(&str, &str)],
    ) -> Vec<u8> {
        let views: Vec<(String, safetensors::tensor::TensorView)> = tensors
            .iter()
            .map(|(n, d, s, b)| {
                (
                    n.to_string(),
                    safetensors::tensor::TensorView::new(*d, s.clone(), b).unwrap(),
                )
            })
            .collect();
        let md: HashMap<String, String> = meta
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        safetensors::tensor::serialize(views, Some(md)).unwrap()
    }

    fn valid_parts() -> Vec<(&'static str, safetensors::Dtype, Vec<usize>, Vec<u8>)> {
        use safetensors::Dtype;
        let m = octahedron();
        let pos: Vec<f32> = m.positions.iter().flat_map(|p| p.to_array()).collect();
        let fac: Vec<u32> = m.faces.iter().flatten().copied().collect();
        vec![
            ("positions", Dtype::F32, vec![6, 3], le_bytes(&pos)),
            ("faces", Dtype::U32, vec![8, 3], le_bytes(&fac)),
            ("vertex_offsets", Dtype::U64, vec![2], le_bytes(&[0u64, 6])),
            ("face_offsets", Dtype::U64, vec![2], le_bytes(&[0u64, 8])),
        ]
    }

    const META: &[(&str, &str)] = &[("format", "meshflow-shard"), ("version", "1")];

    #[test]
    fn valid_custom_shard_parses() {
        Shard::from_bytes(&custom(valid_parts(), META)).unwrap();
    }

    #[test]
    fn corrupt_inputs_give_typed_errors() {
        use safetensors::Dtype;
        let err = |b: &[u8]| Shard::from_bytes(b).unwrap_err();
        assert!(matches!(err(b""), DatasetError::Safetensors(_)));
        let good = shard_of(&[octahedron()]);
        assert!(matches!(
            err(&good[..good.len() - 1]),
            DatasetError::Safetensors(_)
        ));
        assert!(matches!(
            err(&custom(valid_parts(), &[("version", "1")])),
            DatasetError::MissingMetadata { key: "format" }
        ));
        assert!(matches!(
            err(&custom(
                valid_parts(),
                &[("format", "meshflow-shard"), ("version", "2")]
            )),
            DatasetError::WrongMetadata { key: "version", .. }
        ));
        let mut p = valid_parts();
        p.remove(1);
        assert_eq!(err(&custom(p, META)), DatasetError::MissingTensor("faces"));
        let mut p = valid_parts();
        p[1].1 = Dtype::I32;
        assert!(matches!(
            err(&custom(p, META)),
            DatasetError::WrongDtype {
                tensor: "faces",
                ..
            }
        ));
        let mut p = valid_parts();
        p[0].2 = vec![9, 2];
        assert!(matches!(
            err(&custom(p, META)),
            DatasetError::WrongShape {
                tensor: "positions",
                ..
            }
        ));
        for offs in [[1u64, 6], [0, 5], [0, 7]] {
            let mut p = valid_parts();
            p[2].3 = le_bytes(&offs);
            assert!(matches!(
                err(&custom(p, META)),
                DatasetError::BadOffsets {
                    tensor: "vertex_offsets",
                    ..
                }
            ));
        }
        let mut p = valid_parts();
        p[2] = (
            "vertex_offsets",
            Dtype::U64,
            vec![3],
            le_bytes(&[0u64, 4, 6]),
        );
        assert!(matches!(
            err(&custom(p, META)),
            DatasetError::BadOffsets {
                tensor: "face_offsets",
                ..
            }
        ));
        // Two meshes, the second's faces use vertex 5 but it only has 2 vertices.
        let mut p = valid_parts();
        p[2] = (
            "vertex_offsets",
            Dtype::U64,
            vec![3],
            le_bytes(&[0u64, 4, 6]),
        );
        p[3] = ("face_offsets", Dtype::U64, vec![3], le_bytes(&[0u64, 0, 8]));
        assert!(matches!(
            err(&custom(p, META)),
            DatasetError::IndexOutOfRange { mesh: 1, .. }
        ));
        let mut p = valid_parts();
        p[0].3[4..8].copy_from_slice(&f32::NAN.to_le_bytes());
        assert_eq!(err(&custom(p, META)), DatasetError::NonFinite { vertex: 0 });
    }

    fn arb_mesh() -> impl Strategy<Value = Mesh> {
        (1usize..12).prop_flat_map(|n| {
            (
                prop::collection::vec(prop::array::uniform3(-1.0f32..1.0), n),
                prop::collection::vec(prop::array::uniform3(0..n as u32), 0..20),
            )
                .prop_map(|(p, f)| Mesh::new(p.into_iter().map(Vec3::from).collect(), f))
        })
    }

    proptest! {
        #[test]
        fn prop_round_trip(meshes in prop::collection::vec(arb_mesh(), 0..6)) {
            let shard = Shard::from_bytes(&shard_of(&meshes)).unwrap();
            prop_assert_eq!(shard.len(), meshes.len());
            for (i, m) in meshes.iter().enumerate() {
                prop_assert_eq!(&shard.mesh(i), m);
            }
        }

        #[test]
        fn prop_corruption_never_panics(
            meshes in prop::collection::vec(arb_mesh(), 0..4),
            flips in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
            cut in any::<prop::sample::Index>(),
        ) {
            let mut bytes = shard_of(&meshes);
            for (i, b) in flips {
                let k = i.index(bytes.len());
                bytes[k] ^= b;
            }
            let _ = Shard::from_bytes(&bytes);
            let k = cut.index(bytes.len());
            let _ = Shard::from_bytes(&bytes[..k]);
        }
    }

    #[test]
    fn filter_rules() {
        let f = FilterOptions::default();
        // icosphere(1): 42 vertices, 80 faces, degree 6.
        assert_eq!(filter(&icosphere(1), &f), Ok(6));
        assert_eq!(filter(&octahedron(), &f), Err(FilterReason::TooFewFaces));
        let flat = grid(8, 8);
        assert!(flat.faces.len() >= 20);
        assert_eq!(filter(&flat, &f), Err(FilterReason::Flat));
        let big = icosphere(5);
        assert_eq!(filter(&big, &f), Err(FilterReason::TooManyVertices));
        let tight = FilterOptions { max_faces: 50, ..f };
        assert_eq!(
            filter(&icosphere(1), &tight),
            Err(FilterReason::TooManyFaces)
        );
        let low_degree = FilterOptions { max_degree: 5, ..f };
        assert_eq!(
            filter(&icosphere(1), &low_degree),
            Err(FilterReason::DegreeTooHigh)
        );
        // Just under 2%: flat; at 2%: kept.
        let squash = |k: f32| Mesh {
            positions: icosphere(1)
                .positions
                .iter()
                .map(|p| *p * Vec3::new(1.0, 1.0, k))
                .collect(),
            ..icosphere(1)
        };
        assert_eq!(filter(&squash(0.019), &f), Err(FilterReason::Flat));
        assert!(filter(&squash(0.021), &f).is_ok());
    }

    #[test]
    fn crossed_billboards_are_cards_but_boxes_are_not() {
        use crate::data::cards::push_quad;
        let f = FilterOptions::default();
        // A billboard tree: ten vertical quads crossing at the trunk's axis (20 faces); its
        // bounding box is not flat.
        let mut tree = Mesh::default();
        for k in 0..10 {
            let a = std::f32::consts::PI * k as f32 / 10.0;
            push_quad(
                &mut tree,
                Vec3::Y,
                Vec3::new(a.cos(), 0.0, a.sin()),
                Vec3::Y,
            );
        }
        assert_eq!(filter(&tree, &f), Err(FilterReason::Card));
        // Ordinary low-poly solids of big flat faces pass: a subdivided box ...
        let (box_mesh, _) = crate::geometry::clean::clean(
            &subdivide(&subdivide(&crate::geometry::primitives::cube())),
            &crate::geometry::clean::CleanOptions::default(),
        );
        assert!(box_mesh.faces.len() >= 20);
        assert!(filter(&box_mesh, &f).is_ok());
        // ... and a house: the box with a gable roof on top (open underneath).
        let mut house = box_mesh.clone();
        house.faces.retain(|face| {
            !face
                .iter()
                .all(|&i| (house.positions[i as usize].y + 1.0).abs() < 1e-6)
        });
        let (r0, r1) = (
            house.positions.len() as u32,
            house.positions.len() as u32 + 1,
        );
        house
            .positions
            .extend([Vec3::new(-1.0, 2.0, 0.0), Vec3::new(1.0, 2.0, 0.0)]);
        let corner = |x: f32, z: f32| {
            house
                .positions
                .iter()
                .position(|p| *p == Vec3::new(x, 1.0, z))
                .unwrap() as u32
        };
        let (a, b, c, d) = (
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        );
        house.faces.extend([
            [a, r0, b],
            [b, r0, r1],
            [c, r1, d],
            [d, r1, r0],
            [a, d, r0],
            [b, r1, c],
        ]);
        assert!(filter(&house, &f).is_ok());
    }

    /// Splits every triangle into four at its edge midpoints.
    fn subdivide(m: &Mesh) -> Mesh {
        let mut out = Mesh::default();
        for f in 0..m.faces.len() {
            let [a, b, c] = m.triangle(f);
            let (ab, bc, ca) = ((a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5);
            for t in [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]] {
                let base = out.positions.len() as u32;
                out.positions.extend(t);
                out.faces.push([base, base + 1, base + 2]);
            }
        }
        out
    }

    #[test]
    fn object_names_drop_lod_and_pose_suffixes() {
        for (path, name) in [
            ("a/b/Tree_02_LOD1.pmd", "tree"),
            ("x.zip!art/meshes/tree_03.pmd", "tree"),
            ("horse-lod0.obj", "horse"),
            ("models/lod2/rock12.md2", "rock"),
            ("link7.stl", "link"),
            ("0123.obj", "0123"),
            ("chair", "chair"),
            ("foo.bar.obj", "foo.bar"),
        ] {
            assert_eq!(object_name(path), name, "{path}");
        }
        assert_eq!(split_key("p", "d.zip!m/e/tris.md2"), "p/m/e/tris");
    }

    #[test]
    fn split_is_deterministic_and_about_90_5_5() {
        let mut counts = [0usize; 3];
        for i in 0..20_000 {
            let key = format!("pkg/folder{}/object{i}x", i % 37);
            let s = split_of(&key);
            assert_eq!(s, split_of(&key));
            counts[s as usize] += 1;
        }
        assert!((17_600..18_400).contains(&counts[0]), "{counts:?}");
        assert!((800..1200).contains(&counts[1]), "{counts:?}");
        assert!((800..1200).contains(&counts[2]), "{counts:?}");
        // LOD and pose copies of one object share a split.
        assert_eq!(
            split_of(&split_key("p", "a/tree_lod1.obj")),
            split_of(&split_key("p", "a/tree2.obj"))
        );
    }

    #[test]
    fn geometry_hash_ignores_order_but_not_shape() {
        let m = icosphere(1);
        let h = geometry_hash(&m, 1e-4);
        // Reverse vertex order and rotate faces.
        let n = m.positions.len() as u32;
        let perm = Mesh::new(
            m.positions.iter().rev().copied().collect(),
            m.faces
                .iter()
                .rev()
                .map(|f| [n - 1 - f[1], n - 1 - f[2], n - 1 - f[0]])
                .collect(),
        );
        assert_eq!(geometry_hash(&perm, 1e-4), h);
        let mut moved = m.clone();
        moved.positions[0].x += 0.01;
        assert_ne!(geometry_hash(&moved, 1e-4), h);
        let mut flipped = m.clone();
        flipped.faces[0].swap(1, 2);
        assert_ne!(geometry_hash(&flipped, 1e-4), h);
    }

    #[test]
    fn ids_are_stable() {
        assert_eq!(mesh_id("a", "b", ""), mesh_id("a", "b", ""));
        assert_ne!(mesh_id("ab", "", ""), mesh_id("a", "b", ""));
        // FNV-1a of nothing is its offset basis.
        assert_eq!(Fnv64::new().finish(), 0xcbf2_9ce4_8422_2325);
    }
}
