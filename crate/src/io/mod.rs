//! Mesh and point-cloud readers and writers.
//!
//! Readers: OBJ, PLY (ascii and binary), STL (ascii and binary), glTF 2.0 (`.gltf` JSON with
//! `data:` or external buffers) and GLB, and plain point lists (XYZ/PTS/CSV/TXT); and the
//! game-asset formats PMD (0 A.D.), SPM (SuperTuxKart), MD2 (Quake II), MD3 (Quake III), PIE
//! (Warzone 2100), AC3D (FlightGear), ASE (3ds Max ASCII export), IQM (Inter-Quake Model) and
//! MD5 (`.md5mesh`, Doom 3); and COLLADA (`.dae`), as used by the robot descriptions.
//! Writers: GLB, OBJ and binary little-endian PLY.
//!
//! Every reader takes untrusted bytes: it never panics, checks every declared count against
//! the bytes actually present and against [`Limits`] before allocating, and reports problems
//! as a typed [`ReadError`] that names the format and, where it can, the line (text formats),
//! byte offset (binary formats) or JSON item (glTF) at fault.
//!
//! Rules shared by all readers:
//! - Positions must be finite ([`ReadError::NonFinite`]); a file without any vertex is
//!   [`ReadError::Empty`]; a face index outside the vertex list is
//!   [`ReadError::IndexOutOfRange`].
//! - Polygons are fan-triangulated; degenerate triangles (a repeated index) are kept as they
//!   are (cleaning is [`crate::geometry::clean`]'s job).
//! - Normals: a normal whose length is already within 1e-5 of one is kept bit-for-bit, others
//!   are renormalised; if any normal is zero-length or not finite, *all* normals are dropped
//!   (the mesh then has none, and [`crate::geometry::normals`] can recompute them). A non-finite normal
//!   is never an error, in any format (an OBJ `vn nan 0 0` included).

mod ac3d;
mod ase;
mod base64;
mod dae;
mod gltf;
mod iqm;
mod md2;
mod md3;
mod md5;
mod obj;
mod pie;
mod ply;
mod pmd;
mod points;
mod spm;
mod stl;
mod tokens;

use std::fmt;
use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::geometry::mesh::{Mesh, MeshError};

pub use ac3d::MAX_DEPTH as AC3D_MAX_DEPTH;
pub use ase::MAX_DEPTH as ASE_MAX_DEPTH;
pub use base64::encode as encode_base64;
pub use dae::{
    DaeInfo, MAX_NODE_DEPTH as DAE_MAX_NODE_DEPTH, MAX_NODE_VISITS as DAE_MAX_NODE_VISITS,
    MAX_XML_ATTRIBUTES as DAE_MAX_XML_ATTRIBUTES, MAX_XML_NODES as DAE_MAX_XML_NODES, UpAxis,
    read_dae,
};
pub use gltf::{MAX_NODE_DEPTH, MAX_NODE_VISITS, MAX_PRIMITIVE_INSTANCES, write_glb};
pub use md5::MAX_WEIGHTS_PER_VERTEX as MD5_MAX_WEIGHTS_PER_VERTEX;
pub use obj::write_obj;
pub use ply::{MAX_HEADER_BYTES as PLY_MAX_HEADER_BYTES, write_ply};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    Obj,
    Ply,
    Stl,
    /// glTF 2.0 JSON (`.gltf`).
    Gltf,
    /// Binary glTF 2.0 (`.glb`).
    Glb,
    /// A plain list of points, one per line (`.xyz`, `.pts`, `.csv`, `.txt`).
    Points,
    /// 0 A.D. model (`.pmd`).
    Pmd,
    /// SuperTuxKart mesh (`.spm`).
    Spm,
    /// Quake II model (`.md2`), first frame.
    Md2,
    /// Quake III model (`.md3`), first frame.
    Md3,
    /// Warzone 2100 model (`.pie`, text).
    Pie,
    /// AC3D model (`.ac`, text), as used by FlightGear.
    Ac3d,
    /// COLLADA document (`.dae`, XML), converted to metres and +Y up.
    Dae,
    /// 3ds Max ASCII export (`.ase`, text).
    Ase,
    /// Inter-Quake Model (`.iqm`, binary, version 2), bind pose.
    Iqm,
    /// Doom 3 mesh (`.md5mesh`, text), bind pose.
    Md5,
}

impl Format {
    /// Every format, in a stable order.
    pub const ALL: [Format; 16] = [
        Format::Obj,
        Format::Ply,
        Format::Stl,
        Format::Gltf,
        Format::Glb,
        Format::Points,
        Format::Pmd,
        Format::Spm,
        Format::Md2,
        Format::Md3,
        Format::Pie,
        Format::Ac3d,
        Format::Dae,
        Format::Ase,
        Format::Iqm,
        Format::Md5,
    ];

    /// The format implied by a file extension (case-insensitive), if any.
    pub fn from_path(p: &Path) -> Option<Format> {
        let ext = p.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "obj" => Format::Obj,
            "ply" => Format::Ply,
            "stl" => Format::Stl,
            "gltf" => Format::Gltf,
            "glb" => Format::Glb,
            "xyz" | "pts" | "csv" | "txt" => Format::Points,
            "pmd" => Format::Pmd,
            "spm" => Format::Spm,
            "md2" => Format::Md2,
            "md3" => Format::Md3,
            "pie" => Format::Pie,
            "ac" => Format::Ac3d,
            "dae" => Format::Dae,
            "ase" => Format::Ase,
            "iqm" => Format::Iqm,
            "md5mesh" => Format::Md5,
            _ => return None,
        })
    }

    /// Guesses the format from the first bytes of a file.
    ///
    /// Magic numbers first (`glTF`, `ply`, `PSMD`, `IDP2`, `IDP3`, `INTERQUAKEMODEL`, `SP` with a
    /// known version byte), then a JSON object (glTF), a `PIE ` header, an `AC3D` header, an
    /// `*3DSMAX_ASCIIEXPORT` header (ASE), an `MD5Version` header, an XML document whose start
    /// holds a `<COLLADA` element, an STL (`solid` or a binary whose triangle count matches the
    /// size exactly), an OBJ (lines starting with OBJ keywords, at least one `v`), and finally a
    /// list of numbers (points).
    pub fn sniff(bytes: &[u8]) -> Option<Format> {
        if bytes.starts_with(b"glTF") {
            return Some(Format::Glb);
        }
        if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r") {
            return Some(Format::Ply);
        }
        if bytes.starts_with(b"PSMD") {
            return Some(Format::Pmd);
        }
        if bytes.starts_with(b"IDP2") {
            return Some(Format::Md2);
        }
        if bytes.starts_with(b"IDP3") {
            return Some(Format::Md3);
        }
        if bytes.starts_with(b"INTERQUAKEMODEL\0") {
            return Some(Format::Iqm);
        }
        if spm::magic_matches(bytes) {
            return Some(Format::Spm);
        }
        if stl::binary_size_matches(bytes) {
            return Some(Format::Stl);
        }
        let head = &bytes[..bytes.len().min(4096)];
        // A text prefix: cut at the last complete UTF-8 character.
        let text = match std::str::from_utf8(head) {
            Ok(t) => t,
            Err(e) if e.error_len().is_none() => {
                std::str::from_utf8(&head[..e.valid_up_to()]).unwrap_or("")
            }
            Err(_) => return None,
        };
        let text = text.trim_start_matches('\u{feff}').trim_start();
        if text.starts_with('{') {
            return Some(Format::Gltf);
        }
        if text.starts_with("PIE ") {
            return Some(Format::Pie);
        }
        if text.starts_with("AC3Db") {
            return Some(Format::Ac3d);
        }
        if text.starts_with("*3DSMAX_ASCIIEXPORT") {
            return Some(Format::Ase);
        }
        if text.starts_with("MD5Version") {
            return Some(Format::Md5);
        }
        if text.starts_with('<') && text.contains("<COLLADA") {
            return Some(Format::Dae);
        }
        if text.starts_with("solid") {
            return Some(Format::Stl);
        }
        if obj::looks_like_obj(text) {
            return Some(Format::Obj);
        }
        if points::looks_like_points(text) {
            return Some(Format::Points);
        }
        None
    }

    /// A short human-readable name ("OBJ", "glTF", ...).
    pub fn name(&self) -> &'static str {
        match self {
            Format::Obj => "OBJ",
            Format::Ply => "PLY",
            Format::Stl => "STL",
            Format::Gltf => "glTF",
            Format::Glb => "GLB",
            Format::Points => "point list",
            Format::Pmd => "PMD",
            Format::Spm => "SPM",
            Format::Md2 => "MD2",
            Format::Md3 => "MD3",
            Format::Pie => "PIE",
            Format::Ac3d => "AC3D",
            Format::Dae => "COLLADA",
            Format::Ase => "ASE",
            Format::Iqm => "IQM",
            Format::Md5 => "MD5",
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Size limits a reader enforces before allocating.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Largest input accepted, in bytes. It also bounds each `data:` glTF buffer, and the
    /// external buffer files of a `.gltf` document, each and all together.
    pub max_bytes: u64,
    /// Most vertices (points) in the result.
    pub max_vertices: usize,
    /// Most triangles in the result (after fan triangulation).
    pub max_faces: usize,
}

impl Limits {
    /// Default [`Limits::max_bytes`]: 512 MiB.
    pub const DEFAULT_MAX_BYTES: u64 = 512 * 1024 * 1024;
    /// Default [`Limits::max_vertices`]: 16 Mi (16 777 216).
    pub const DEFAULT_MAX_VERTICES: usize = 1 << 24;
    /// Default [`Limits::max_faces`]: 32 Mi (33 554 432).
    pub const DEFAULT_MAX_FACES: usize = 1 << 25;
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_bytes: Self::DEFAULT_MAX_BYTES,
            max_vertices: Self::DEFAULT_MAX_VERTICES,
            max_faces: Self::DEFAULT_MAX_FACES,
        }
    }
}

/// Where in the input a problem is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// 1-based line of a text format.
    Line(usize),
    /// Byte offset from the start of the input.
    Byte(u64),
    /// An item of a glTF document, e.g. `accessors[3]`.
    Item(String),
    /// Nowhere in particular.
    Unknown,
}

impl fmt::Display for Location {
    /// Written with a leading space so messages read "OBJ line 3: ..." or "STL: ...".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(l) => write!(f, " line {l}"),
            Location::Byte(b) => write!(f, " at byte {b}"),
            Location::Item(s) => write!(f, " {s}"),
            Location::Unknown => Ok(()),
        }
    }
}

/// Why a file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("{format} data ends early at byte {offset} (at least {expected} more bytes expected)")]
    Truncated {
        format: Format,
        offset: u64,
        expected: u64,
    },
    #[error("{format}{location}: {message}")]
    Malformed {
        format: Format,
        location: Location,
        message: String,
    },
    #[error("{format}{location}: index {index} is out of range (there are {count} {what})")]
    IndexOutOfRange {
        format: Format,
        location: Location,
        /// What the index refers to, plural: "vertices", "normals", "texture coordinates".
        what: &'static str,
        /// The index as written in the file (1-based or negative for OBJ).
        index: i64,
        count: usize,
    },
    #[error("{format}{location}: a coordinate is not a finite number (NaN or infinity)")]
    NonFinite { format: Format, location: Location },
    #[error("{format}: {what} is {value}, more than the limit of {limit}")]
    TooLarge {
        format: Format,
        what: &'static str,
        value: u64,
        limit: u64,
    },
    #[error("{format} file contains no vertices")]
    Empty { format: Format },
    #[error("{format}: not supported: {what}")]
    Unsupported { format: Format, what: String },
    #[error(
        "unrecognised file format (expected OBJ, PLY, STL, glTF, GLB, PMD, SPM, MD2, MD3, PIE, AC3D, COLLADA, ASE, IQM, MD5 or a point list)"
    )]
    UnknownFormat,
    #[error("{format} file is not valid UTF-8 text (byte {offset})")]
    InvalidUtf8 { format: Format, offset: u64 },
    // The cause is part of the message rather than a `source`, so error chains that print
    // sources (anyhow's `{:#}`) do not repeat it.
    #[error("could not read the file: {0}")]
    Io(std::io::Error),
}

impl From<std::io::Error> for ReadError {
    fn from(e: std::io::Error) -> Self {
        ReadError::Io(e)
    }
}

/// Why a mesh could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("cannot write `{extension}` files (use .glb, .obj or .ply)")]
    UnsupportedFormat { extension: String },
    // As in ReadError: causes are in the message, not `source`, so chains print them once.
    #[error("the mesh is invalid: {0}")]
    InvalidMesh(MeshError),
    #[error("could not write the file: {0}")]
    Io(std::io::Error),
}

impl From<MeshError> for WriteError {
    fn from(e: MeshError) -> Self {
        WriteError::InvalidMesh(e)
    }
}

impl From<std::io::Error> for WriteError {
    fn from(e: std::io::Error) -> Self {
        WriteError::Io(e)
    }
}

/// Reads a mesh of a known format from memory.
///
/// A `.gltf` document read this way can only use `data:` URIs for its buffers; use
/// [`read_path`] for external buffer files.
pub fn read_bytes(bytes: &[u8], format: Format, limits: &Limits) -> Result<Mesh, ReadError> {
    check_limit(
        format,
        "file size in bytes",
        bytes.len() as u64,
        limits.max_bytes,
    )?;
    match format {
        Format::Obj => obj::read(bytes, limits),
        Format::Ply => ply::read(bytes, limits),
        Format::Stl => stl::read(bytes, limits),
        Format::Gltf => gltf::read_gltf(bytes, limits, None),
        Format::Glb => gltf::read_glb(bytes, limits),
        Format::Points => points::read(bytes, limits),
        Format::Pmd => pmd::read(bytes, limits),
        Format::Spm => spm::read(bytes, limits),
        Format::Md2 => md2::read(bytes, limits),
        Format::Md3 => md3::read(bytes, limits),
        Format::Pie => pie::read(bytes, limits),
        Format::Ac3d => ac3d::read(bytes, limits),
        Format::Dae => dae::read(bytes, limits),
        Format::Ase => ase::read(bytes, limits),
        Format::Iqm => iqm::read(bytes, limits),
        Format::Md5 => md5::read(bytes, limits),
    }
}

/// Reads a mesh file; the format comes from the extension, else from the content.
///
/// External buffers of a `.gltf` file are resolved relative to the file's folder. `path`
/// must name a regular file: a directory, device, FIFO or socket is refused, before it is
/// opened, with a [`ReadError::Io`] that says which it is.
pub fn read_path(path: &Path, limits: &Limits) -> Result<Mesh, ReadError> {
    let by_ext = Format::from_path(path);
    // When the format is not known yet a size problem is reported as a point list (the
    // catch-all), the limit being the same for every format.
    let bytes = read_file(
        path,
        by_ext.unwrap_or(Format::Points),
        "file size in bytes",
        limits.max_bytes,
    )?;
    let format = by_ext
        .or_else(|| Format::sniff(&bytes))
        .ok_or(ReadError::UnknownFormat)?;
    match format {
        Format::Gltf => {
            let base = path.parent().unwrap_or(Path::new("."));
            gltf::read_gltf(&bytes, limits, Some(base))
        }
        _ => read_bytes(&bytes, format, limits),
    }
}

/// The files of the folder `dir` that [`read_path`] reads by their extension
/// ([`Format::from_path`]), sorted by name: the inputs of a command run on a folder. Folders
/// and files of other types are left out, and so are entries that cannot be read.
pub fn mesh_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && Format::from_path(p).is_some())
        .collect();
    files.sort();
    Ok(files)
}

/// The file in the folder `dir` that holds the result for `input`: `input`'s name with its
/// last extension replaced by `extension` (`in/chair.v2.ply` -> `dir/chair.v2.glb`).
pub fn output_in(dir: &Path, input: &Path, extension: &str) -> PathBuf {
    let mut name = input.file_stem().unwrap_or_default().to_os_string();
    name.push(".");
    name.push(extension);
    dir.join(name)
}

/// Writes `mesh` in the format named by the extension of `path` (`.glb`, `.obj`, `.ply`).
///
/// The mesh must pass [`Mesh::validate`].
pub fn write_path(mesh: &Mesh, path: &Path) -> Result<(), WriteError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    if !matches!(ext.as_str(), "glb" | "obj" | "ply") {
        return Err(WriteError::UnsupportedFormat { extension: ext });
    }
    mesh.validate()?;
    let bytes = match ext.as_str() {
        "glb" => write_glb(mesh),
        "obj" => write_obj(mesh).into_bytes(),
        _ => write_ply(mesh),
    };
    write_atomic(path, &bytes)?;
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file in the same folder, renamed over `path`
/// once complete: a reader (or a crash) never sees a partial file, and an existing file is
/// replaced whole or not at all.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::other(format!("{} names no file", path.display())))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let written = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

// ---------------------------------------------------------------------------------------------
// Helpers shared by the readers.

/// Reads the regular file at `path`, refusing more than `limit` bytes ([`ReadError::TooLarge`]
/// naming `what`).
///
/// Anything else (a directory, a device such as `/dev/zero`, a FIFO, a socket) is refused
/// before it is opened, with an [`ReadError::Io`] error that says what the path is. The
/// size in the metadata is only a first check: at most `limit + 1` bytes are read, so a file
/// that grows, or whose reported size is wrong (as in `/proc`), cannot exceed the limit.
pub(crate) fn read_file(
    path: &Path,
    format: Format,
    what: &'static str,
    limit: u64,
) -> Result<Vec<u8>, ReadError> {
    use std::io::Read;
    let meta = std::fs::metadata(path)?;
    not_regular(path, &meta)?;
    check_limit(format, what, meta.len(), limit)?;
    let file = std::fs::File::open(path)?;
    // The path may have been replaced between the two looks; check what was opened.
    not_regular(path, &file.metadata()?)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    check_limit(format, what, bytes.len() as u64, limit)?;
    Ok(bytes)
}

/// An error naming what `path` is, unless it is a regular file.
fn not_regular(path: &Path, meta: &std::fs::Metadata) -> Result<(), ReadError> {
    let t = meta.file_type();
    if t.is_file() {
        return Ok(());
    }
    let (kind, what) = if t.is_dir() {
        (std::io::ErrorKind::IsADirectory, "a directory")
    } else {
        (std::io::ErrorKind::InvalidInput, special_kind(&t))
    };
    Err(ReadError::Io(std::io::Error::new(
        kind,
        format!("`{}` is {what}, not a regular file", path.display()),
    )))
}

#[cfg(unix)]
fn special_kind(t: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::FileType) -> &'static str {
    "a special file"
}

pub(crate) fn check_limit(
    format: Format,
    what: &'static str,
    value: u64,
    limit: u64,
) -> Result<(), ReadError> {
    if value > limit {
        Err(ReadError::TooLarge {
            format,
            what,
            value,
            limit,
        })
    } else {
        Ok(())
    }
}

pub(crate) fn malformed(
    format: Format,
    location: Location,
    message: impl Into<String>,
) -> ReadError {
    ReadError::Malformed {
        format,
        location,
        message: message.into(),
    }
}

/// The byte offset where `bytes` stop being UTF-8, as an error.
pub(crate) fn utf8(format: Format, bytes: &[u8]) -> Result<&str, ReadError> {
    std::str::from_utf8(bytes).map_err(|e| ReadError::InvalidUtf8 {
        format,
        offset: e.valid_up_to() as u64,
    })
}

/// Normalises normals as documented at the top of this module: keeps near-unit ones as they
/// are, renormalises others, and returns none at all if one is zero-length, not finite, or
/// if the count differs from `vertices`.
pub(crate) fn fix_normals(mut normals: Vec<Vec3>, vertices: usize) -> Vec<Vec3> {
    if normals.len() != vertices {
        return Vec::new();
    }
    for n in &mut normals {
        let len2 = n.length_squared();
        if !len2.is_finite() || len2 < 1e-30 {
            return Vec::new();
        }
        if (len2 - 1.0).abs() > 1e-5 {
            let v = n.as_dvec3().normalize();
            *n = v.as_vec3();
            if !n.is_finite() {
                return Vec::new();
            }
        }
    }
    normals
}

/// The final checks every reader ends with.
pub(crate) fn finish(
    format: Format,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
) -> Result<Mesh, ReadError> {
    if positions.is_empty() {
        return Err(ReadError::Empty { format });
    }
    let normals = fix_normals(normals, positions.len());
    Ok(Mesh {
        positions,
        normals,
        faces,
    })
}

/// Fan-triangulates a polygon given by its corner indices, pushing onto `faces`.
pub(crate) fn push_fan(
    format: Format,
    corners: &[u32],
    faces: &mut Vec<[u32; 3]>,
    limits: &Limits,
) -> Result<(), ReadError> {
    if corners.len() < 3 {
        return Ok(());
    }
    let added = corners.len() - 2;
    let total = faces.len().saturating_add(added);
    check_limit(
        format,
        "triangle count",
        total as u64,
        limits.max_faces as u64,
    )?;
    for i in 1..corners.len() - 1 {
        faces.push([corners[0], corners[i], corners[i + 1]]);
    }
    Ok(())
}

/// The vertex limit as a `u64`, capped so that indices fit in `u32`.
pub(crate) fn vertex_limit(limits: &Limits) -> u64 {
    (limits.max_vertices as u64).min(u32::MAX as u64)
}

/// A bounds-checked little-endian reader over untrusted bytes, for the binary game formats.
///
/// Running past the end is [`ReadError::Truncated`], with `offset` the input's length (where
/// the data ends) and `expected` how many more bytes were needed.
pub(crate) struct Cursor<'a> {
    format: Format,
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Cursor<'a> {
    pub(crate) fn new(format: Format, bytes: &'a [u8]) -> Self {
        Cursor {
            format,
            bytes,
            pos: 0,
        }
    }

    /// The offset of the next byte to read.
    pub(crate) fn pos(&self) -> u64 {
        self.pos as u64
    }

    pub(crate) fn remaining(&self) -> u64 {
        (self.bytes.len() - self.pos) as u64
    }

    /// Fails with `Truncated` unless `n` more bytes are present (`n` may be any size).
    pub(crate) fn need(&self, n: u64) -> Result<(), ReadError> {
        if n > self.remaining() {
            Err(ReadError::Truncated {
                format: self.format,
                offset: self.bytes.len() as u64,
                expected: n - self.remaining(),
            })
        } else {
            Ok(())
        }
    }

    pub(crate) fn take(&mut self, n: u64) -> Result<&'a [u8], ReadError> {
        self.need(n)?;
        let s = &self.bytes[self.pos..self.pos + n as usize];
        self.pos += n as usize;
        Ok(s)
    }

    pub(crate) fn skip(&mut self, n: u64) -> Result<(), ReadError> {
        self.take(n).map(|_| ())
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], ReadError> {
        let s = self.take(N as u64)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }

    pub(crate) fn u8(&mut self) -> Result<u8, ReadError> {
        Ok(self.array::<1>()?[0])
    }

    pub(crate) fn u16(&mut self) -> Result<u16, ReadError> {
        self.array().map(u16::from_le_bytes)
    }

    pub(crate) fn u32(&mut self) -> Result<u32, ReadError> {
        self.array().map(u32::from_le_bytes)
    }

    pub(crate) fn i32(&mut self) -> Result<i32, ReadError> {
        self.array().map(i32::from_le_bytes)
    }

    pub(crate) fn f32(&mut self) -> Result<f32, ReadError> {
        self.array().map(f32::from_le_bytes)
    }

    /// Three `f32`s; any of them NaN or infinite is [`ReadError::NonFinite`] at their offset.
    pub(crate) fn finite_vec3(&mut self) -> Result<Vec3, ReadError> {
        let at = self.pos();
        let v = self.vec3()?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(ReadError::NonFinite {
                format: self.format,
                location: Location::Byte(at),
            })
        }
    }

    /// Three `f32`s, finite or not.
    pub(crate) fn vec3(&mut self) -> Result<Vec3, ReadError> {
        Ok(Vec3::new(self.f32()?, self.f32()?, self.f32()?))
    }
}

/// `IndexOutOfRange` for a vertex index read at byte `at` of a binary format.
pub(crate) fn bad_vertex_index(format: Format, at: u64, index: u32, count: usize) -> ReadError {
    ReadError::IndexOutOfRange {
        format,
        location: Location::Byte(at),
        what: "vertices",
        index: index as i64,
        count,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folders_mesh_files_are_listed_sorted_without_other_entries() {
        let dir = std::env::temp_dir().join(format!("meshflow-io-list-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub.obj")).unwrap();
        for name in ["b.ply", "a.OBJ", "notes.md", "c.xyz"] {
            std::fs::write(dir.join(name), "").unwrap();
        }
        let names: Vec<String> = mesh_files(&dir)
            .unwrap()
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["a.OBJ", "b.ply", "c.xyz"]);
        assert!(mesh_files(&dir.join("missing")).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_output_keeps_the_inputs_name_up_to_its_last_extension() {
        let out = Path::new("out");
        let of = |input: &str| output_in(out, Path::new(input), "glb");
        assert_eq!(of("in/chair.v2.ply"), out.join("chair.v2.glb"));
        assert_eq!(of("lantern"), out.join("lantern.glb"));
        assert_eq!(of("in/.hidden.obj"), out.join(".hidden.glb"));
    }
}
