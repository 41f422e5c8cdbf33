//! One package of the build: its mesh files found (`.zip`, `.pk3`, `.sh3f` and `.wz` archives,
//! and archives inside them, opened and their members named `archive!member`), read in
//! parallel, rotated to Y-up, cleaned, filtered and normalised to the model frame
//! (`process_package`); the result is cached per package until its inputs change.

use std::collections::BTreeMap;
use std::fs;
use std::io::{Cursor, Read, Seek};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::Mesh;
use crate::data::dataset::{Fnv64, Shard, ShardWriter, filter, geometry_hash};
use crate::geometry::clean::{CleanOptions, CleanReport, clean};
use crate::geometry::normalize::{Normalization, UpAxis};
use crate::geometry::topology::TopologyReport;
use crate::io::{Format, Limits, read_bytes};

use super::build::BuildOptions;
use super::error::DataError;
use super::files::{create_dir_all, extension, io_error, write_atomic};
use super::packages::PackageInput;
use super::progress::DataEvent;
use super::sources::up_axis_of;

/// Bumped whenever processing changes, so per-package caches are rebuilt.
/// 2: sources rotated to Y-up ([`crate::data::sources::UP_AXES`]); the billboard-card filter.
/// 3: COLLADA, ASE, IQM and MD5 readers.
pub const PIPELINE_VERSION: u32 = 3;
/// Rounding of model-frame coordinates for the duplicate hash.
pub const HASH_QUANTUM: f32 = 1e-4;
/// Archives are opened and their members read like files.
const ARCHIVE_EXTENSIONS: [&str; 4] = ["zip", "pk3", "sh3f", "wz"];
/// Nested archives deeper than this are not opened.
const MAX_ARCHIVE_DEPTH: usize = 4;
/// Mesh formats found in the sources; those `crate::io` cannot read yet are counted as
/// "unsupported format" (others, like textures and sounds, are not meshes and are ignored).
const MESH_EXTENSIONS: [&str; 22] = [
    "obj", "ply", "stl", "gltf", "glb", "pmd", "spm", "md2", "md3", "md5mesh", "pie", "ase", "ac",
    "dae", "iqm", "iqe", "3ds", "x", "b3d", "ms3d", "lwo", "fbx",
];

/// A mesh that passed the filter, before duplicates are removed.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct Record {
    pub path: String,
    pub vertices: usize,
    pub faces: usize,
    pub max_degree: usize,
    pub topology: TopologyReport,
    pub clean: CleanReport,
    pub up_axis: UpAxis,
    pub center: [f32; 3],
    pub scale: f32,
    pub content_hash: String,
}

/// What one package gave, as cached in `cache/<package>-<version>.json` (the meshes, in
/// record order, are in the `.safetensors` beside it).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct PackageResult {
    pub fingerprint: String,
    pub files: u64,
    pub mesh_files: u64,
    pub records: Vec<Record>,
    /// Reason -> count: `unsupported_format`, `unreadable:<kind>`, `filter:<reason>`,
    /// `collision`, `procedural`, `archive_error`.
    pub skipped: BTreeMap<String, u64>,
    /// Extension -> count of the mesh files skipped as unsupported format.
    pub unsupported_extensions: BTreeMap<String, u64>,
    #[serde(skip)]
    pub meshes: Vec<Mesh>,
}

/// Where a mesh file's bytes are.
#[derive(Clone)]
enum Container {
    Disk(PathBuf),
    Memory(Arc<Vec<u8>>),
}

/// A batch of mesh files to read from one place: plain files (`container` None) or members
/// of one archive (by index).
struct Batch {
    container: Option<Container>,
    items: Vec<(String, Option<usize>, PathBuf)>,
}

enum Kind {
    Archive,
    Mesh,
    Unsupported(String),
    Collision,
    Procedural,
    Other,
}

/// What a file of a package is, by its name: an archive to open, a mesh to read (or one no
/// reader handles yet), a collision or procedurally generated mesh (not artist-made, so
/// skipped), or something else.
fn classify(name: &str) -> Kind {
    let lower = name.to_ascii_lowercase();
    let ext = extension(name);
    if ARCHIVE_EXTENSIONS.contains(&ext.as_str()) {
        return Kind::Archive;
    }
    let is_mesh_ext = MESH_EXTENSIONS.contains(&ext.as_str());
    let format = Format::from_path(Path::new(&format!("x.{ext}")));
    let readable = matches!(format, Some(f) if f != Format::Points);
    if !is_mesh_ext && !readable {
        return Kind::Other;
    }
    if lower.split(['/', '!']).any(|c| c.contains("collision")) {
        return Kind::Collision;
    }
    if lower.split(['/', '!']).any(|c| c == "random_urdfs") {
        return Kind::Procedural;
    }
    if readable {
        Kind::Mesh
    } else {
        Kind::Unsupported(ext)
    }
}

/// Adds one to `map[key]`.
pub(crate) fn bump(map: &mut BTreeMap<String, u64>, key: &str) {
    *map.entry(key.to_string()).or_default() += 1;
}

fn open_container(
    c: &Container,
) -> Result<zip::ZipArchive<Box<dyn ReadSeek>>, zip::result::ZipError> {
    let reader: Box<dyn ReadSeek> = match c {
        Container::Disk(p) => Box::new(std::io::BufReader::new(fs::File::open(p)?)),
        Container::Memory(b) => Box::new(Cursor::new(ArcBytes(b.clone()))),
    };
    zip::ZipArchive::new(reader)
}

trait ReadSeek: Read + Seek + Send {}
impl<T: Read + Seek + Send> ReadSeek for T {}

/// A nested archive's bytes, shared by the batches that read its members.
struct ArcBytes(Arc<Vec<u8>>);
impl AsRef<[u8]> for ArcBytes {
    fn as_ref(&self) -> &[u8] {
        &self.0
    }
}

/// Lists the mesh files of a package as batches, counting what is skipped on the way.
fn enumerate(pkg: &PackageInput, result: &mut PackageResult, batches: &mut Vec<Batch>) {
    let mut plain = Vec::new();
    for f in &pkg.files {
        result.files += 1;
        if f.rel.is_empty() {
            enumerate_archive(Container::Disk(f.abs.clone()), "", 0, result, batches);
            continue;
        }
        match classify(&f.rel) {
            Kind::Archive => enumerate_archive(
                Container::Disk(f.abs.clone()),
                &format!("{}!", f.rel),
                0,
                result,
                batches,
            ),
            Kind::Mesh => plain.push((f.rel.clone(), None, f.abs.clone())),
            kind => count_kind(kind, result),
        }
    }
    if !plain.is_empty() {
        batches.push(Batch {
            container: None,
            items: plain,
        });
    }
}

fn count_kind(kind: Kind, result: &mut PackageResult) {
    match kind {
        Kind::Unsupported(ext) => {
            result.mesh_files += 1;
            bump(&mut result.skipped, "unsupported_format");
            bump(&mut result.unsupported_extensions, &ext);
        }
        Kind::Collision => bump(&mut result.skipped, "collision"),
        Kind::Procedural => bump(&mut result.skipped, "procedural"),
        Kind::Archive | Kind::Mesh | Kind::Other => {}
    }
}

/// Lists an archive's mesh members as batches, opening nested archives (held in memory) up to
/// [`MAX_ARCHIVE_DEPTH`]. An archive that cannot be read counts as `archive_error`: one bad
/// file must not stop a build of thousands.
fn enumerate_archive(
    container: Container,
    prefix: &str,
    depth: usize,
    result: &mut PackageResult,
    batches: &mut Vec<Batch>,
) {
    let mut archive = match open_container(&container) {
        Ok(a) => a,
        Err(_) => {
            bump(&mut result.skipped, "archive_error");
            return;
        }
    };
    let mut members = Vec::new();
    let mut nested = Vec::new();
    for i in 0..archive.len() {
        let Some(Ok(name)) = archive.name_for_index(i) else {
            bump(&mut result.skipped, "archive_error");
            continue;
        };
        if name.ends_with('/') {
            continue;
        }
        let name = name.into_owned();
        result.files += 1;
        match classify(&name) {
            Kind::Archive if depth < MAX_ARCHIVE_DEPTH => nested.push((i, name)),
            Kind::Archive => bump(&mut result.skipped, "archive_error"),
            Kind::Mesh => members.push((format!("{prefix}{name}"), Some(i), PathBuf::new())),
            kind => count_kind(kind, result),
        }
    }
    for (i, name) in nested {
        let mut bytes = Vec::new();
        let ok = archive
            .by_index(i)
            .and_then(|mut f| Ok(f.read_to_end(&mut bytes)?));
        if ok.is_err() {
            bump(&mut result.skipped, "archive_error");
            continue;
        }
        enumerate_archive(
            Container::Memory(Arc::new(bytes)),
            &format!("{prefix}{name}!"),
            depth + 1,
            result,
            batches,
        );
    }
    // Members are read in chunks, each opening the archive once.
    for chunk in members.chunks(64) {
        batches.push(Batch {
            container: Some(container.clone()),
            items: chunk.to_vec(),
        });
    }
}

enum Outcome {
    Kept(Box<(Record, Mesh)>),
    Skipped(String),
}

/// The name of a [`crate::io::ReadError`] variant, in snake case ("truncated", ...).
fn error_kind(e: &crate::io::ReadError) -> String {
    let debug = format!("{e:?}");
    let name: String = debug
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric())
        .collect();
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_ascii_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_lowercase());
    }
    out
}

/// Reads one mesh file of `package`, rotates it to Y-up ([`up_axis_of`]), cleans, filters and
/// normalises it.
fn process(package: &str, path: &str, bytes: &[u8], opts: &BuildOptions) -> Outcome {
    let ext = extension(path);
    let Some(format) = Format::from_path(Path::new(&format!("x.{ext}"))) else {
        return Outcome::Skipped("unsupported_format".into());
    };
    let limits = Limits {
        max_bytes: 256 << 20,
        ..Limits::default()
    };
    let mut mesh = match read_bytes(bytes, format, &limits) {
        Ok(m) => m,
        Err(crate::io::ReadError::UnknownFormat) => {
            return Outcome::Skipped("unsupported_format".into());
        }
        Err(e) => return Outcome::Skipped(format!("unreadable:{}", error_kind(&e))),
    };
    mesh.normals.clear();
    let up_axis = up_axis_of(package, path);
    let mesh = up_axis.mesh_to_y_up(&mesh);
    let (cleaned, report) = clean(&mesh, &CleanOptions::default());
    let max_degree = match filter(&cleaned, &opts.filter) {
        Ok(d) => d,
        Err(r) => return Outcome::Skipped(format!("filter:{}", r.name())),
    };
    let aabb = cleaned
        .aabb()
        .expect("a mesh that passed the filter has vertices");
    let norm = Normalization::to_model_frame(aabb);
    let normalised = norm.apply_mesh(&cleaned);
    let record = Record {
        path: path.to_string(),
        vertices: normalised.positions.len(),
        faces: normalised.faces.len(),
        max_degree,
        topology: TopologyReport::of(&normalised),
        clean: report,
        up_axis,
        center: norm.center.to_array(),
        scale: norm.scale,
        content_hash: format!("{:016x}", geometry_hash(&normalised, HASH_QUANTUM)),
    };
    Outcome::Kept(Box::new((record, normalised)))
}

/// Reads and processes the files of one batch; a file that cannot be read is skipped
/// (`unreadable:io`, or `archive_error` for all of an archive that cannot be opened).
fn run_batch(package: &str, batch: &Batch, opts: &BuildOptions) -> Vec<(String, Outcome)> {
    let mut archive = match &batch.container {
        Some(c) => match open_container(c) {
            Ok(a) => Some(a),
            Err(_) => {
                return batch
                    .items
                    .iter()
                    .map(|(p, _, _)| (p.clone(), Outcome::Skipped("archive_error".into())))
                    .collect();
            }
        },
        None => None,
    };
    let mut out = Vec::with_capacity(batch.items.len());
    for (path, index, abs) in &batch.items {
        let bytes = match (&mut archive, index) {
            (Some(a), Some(i)) => a.by_index(*i).and_then(|mut f| {
                let mut b = Vec::with_capacity(f.size().min(256 << 20) as usize);
                f.read_to_end(&mut b)?;
                Ok(b)
            }),
            _ => fs::read(abs).map_err(zip::result::ZipError::from),
        };
        let outcome = match bytes {
            Ok(b) => process(package, path, &b, opts),
            Err(_) => Outcome::Skipped("unreadable:io".into()),
        };
        out.push((path.clone(), outcome));
    }
    out
}

/// Hash of the running executable, so that any change to the code (a reader fix that the
/// version number does not show) invalidates cached package results. Computed once.
fn executable_hash() -> u64 {
    static HASH: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    *HASH.get_or_init(|| {
        let mut h = Fnv64::new();
        match std::env::current_exe().and_then(fs::read) {
            Ok(bytes) => h.write(&bytes),
            // Without it nothing can be cached safely: a fresh value each run never matches.
            Err(_) => h.write(&std::process::id().to_le_bytes()),
        }
        h.finish()
    })
}

/// Hash of everything a package's result depends on: pipeline and tool version, the
/// executable itself, the formats `crate::io` reads, options, package identity and each
/// file's path, size and modification time.
fn fingerprint(pkg: &PackageInput, opts: &BuildOptions) -> Result<String, DataError> {
    let mut h = Fnv64::new();
    h.write(&PIPELINE_VERSION.to_le_bytes());
    h.write_str(env!("CARGO_PKG_VERSION"));
    h.write(&executable_hash().to_le_bytes());
    // A new reader (a new `Format`) changes what a package gives.
    for f in Format::ALL {
        h.write_str(f.name());
    }
    let filter = serde_json::to_string(&opts.filter).map_err(|error| DataError::Json {
        what: "the filter options",
        error,
    })?;
    h.write_str(&filter);
    h.write(&(opts.limit_per_source as u64).to_le_bytes());
    h.write_str(&pkg.name);
    h.write_str(&pkg.version);
    h.write_str(&pkg.license);
    for f in &pkg.files {
        let md = fs::metadata(&f.abs).map_err(|e| io_error("read", &f.abs, e))?;
        let mtime = md
            .modified()
            .ok()
            .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
            .map_or(0, |d| d.as_nanos());
        h.write_str(&f.rel);
        h.write(&md.len().to_le_bytes());
        h.write(&mtime.to_le_bytes());
    }
    Ok(format!("{:016x}", h.finish()))
}

fn cache_paths(cache: &Path, pkg: &PackageInput) -> (PathBuf, PathBuf) {
    let stem = format!("{}-{}", pkg.name, pkg.version.replace([':', '/'], "_"));
    (
        cache.join(format!("{stem}.json")),
        cache.join(format!("{stem}.safetensors")),
    )
}

/// The cached result of `pkg`, when there is one with fingerprint `fp` whose shard is whole;
/// anything else (missing, stale, corrupt) means processing the package again.
fn load_cached(cache: &Path, pkg: &PackageInput, fp: &str) -> Option<PackageResult> {
    let (json, shard) = cache_paths(cache, pkg);
    let mut result: PackageResult = serde_json::from_slice(&fs::read(json).ok()?).ok()?;
    if result.fingerprint != fp {
        return None;
    }
    let shard = Shard::from_bytes(&fs::read(shard).ok()?).ok()?;
    if shard.len() != result.records.len() {
        return None;
    }
    result.meshes = (0..shard.len()).map(|i| shard.mesh(i)).collect();
    Some(result)
}

fn store_cached(cache: &Path, pkg: &PackageInput, result: &PackageResult) -> Result<(), DataError> {
    create_dir_all(cache)?;
    let (json, shard) = cache_paths(cache, pkg);
    let mut w = ShardWriter::new();
    for m in &result.meshes {
        w.push(m);
    }
    write_atomic(&shard, &w.finish())?;
    let bytes = serde_json::to_vec(result).map_err(|error| DataError::Json {
        what: "a package result",
        error,
    })?;
    write_atomic(&json, &bytes)
}

/// Processes one package: its cached result when `cache` holds one for the same inputs
/// ([`fingerprint`]), else every mesh file read on `pool` (rayon's global pool when None)
/// and the result stored in `cache`. Returns the result and whether it came from the cache.
/// Progress goes to `observer` on this thread.
pub(crate) fn process_package(
    pkg: &PackageInput,
    opts: &BuildOptions,
    cache: Option<&Path>,
    pool: Option<&rayon::ThreadPool>,
    observer: &mut dyn FnMut(DataEvent<'_>),
) -> Result<(PackageResult, bool), DataError> {
    let fp = fingerprint(pkg, opts)?;
    if let Some(cached) = cache.and_then(|c| load_cached(c, pkg, &fp)) {
        return Ok((cached, true));
    }
    let mut result = PackageResult {
        fingerprint: fp,
        ..Default::default()
    };
    let mut batches = Vec::new();
    enumerate(pkg, &mut result, &mut batches);
    if opts.limit_per_source > 0 {
        let mut left = opts.limit_per_source;
        for b in &mut batches {
            let take = b.items.len().min(left);
            b.items.truncate(take);
            left -= take;
        }
        batches.retain(|b| !b.items.is_empty());
    }
    let total: usize = batches.iter().map(|b| b.items.len()).sum();
    result.mesh_files += total as u64;
    observer(DataEvent::ReadingStarted {
        package: &pkg.name,
        mesh_files: total as u64,
    });
    // Batches are read on rayon's threads from a helper thread; their counts come back over a
    // channel, so the observer is only ever called here and need not be `Send`.
    let (sender, counts) = std::sync::mpsc::channel::<u64>();
    let mut outcomes = std::thread::scope(|scope| {
        let reader = scope.spawn(move || {
            let read = || {
                batches
                    .par_iter()
                    .flat_map_iter(|b| {
                        let out = run_batch(&pkg.name, b, opts);
                        // The receiver outlives the reader, so this only fails if it panicked.
                        let _ = sender.send(out.len() as u64);
                        out
                    })
                    .collect::<Vec<_>>()
            };
            match pool {
                Some(pool) => pool.install(read),
                None => read(),
            }
        });
        // Ends when the reader drops its sender: when it is done or has panicked.
        for count in counts {
            observer(DataEvent::MeshesRead { count });
        }
        reader
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    });
    observer(DataEvent::ReadingFinished { package: &pkg.name });
    outcomes.sort_by(|a, b| a.0.cmp(&b.0));
    for (_, outcome) in outcomes {
        match outcome {
            Outcome::Kept(kept) => {
                let (record, mesh) = *kept;
                result.records.push(record);
                result.meshes.push(mesh);
            }
            Outcome::Skipped(reason) => {
                if reason == "unsupported_format" {
                    bump(&mut result.unsupported_extensions, "(unknown)");
                }
                bump(&mut result.skipped, &reason);
            }
        }
    }
    if let Some(c) = cache {
        store_cached(c, pkg, &result)?;
    }
    Ok((result, false))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::fetch::wheel_stem;
    use crate::data::packages::parse_deb_name;
    use crate::data::sources::license_of;

    #[test]
    fn classification() {
        assert!(matches!(classify("a/b.OBJ"), Kind::Mesh));
        assert!(matches!(classify("a/b.pk3"), Kind::Archive));
        assert!(matches!(classify("a/b.md2"), Kind::Mesh));
        for new in ["a/b.md5mesh", "a/b.DAE", "a/b.ase", "a/b.iqm"] {
            assert!(matches!(classify(new), Kind::Mesh), "{new}");
        }
        assert!(matches!(classify("a/b.iqe"), Kind::Unsupported(e) if e == "iqe"));
        assert!(matches!(classify("a/b.txt"), Kind::Other));
        assert!(matches!(classify("a/b.png"), Kind::Other));
        assert!(matches!(classify("x/collision/b.stl"), Kind::Collision));
        assert!(matches!(classify("x/b_collision.stl"), Kind::Collision));
        assert!(matches!(
            classify("pybullet_data/random_urdfs/000/000.obj"),
            Kind::Procedural
        ));
        assert_eq!(
            parse_deb_name("flightgear-data-models_1%3a2020.3.16+dfsg-1_all.deb"),
            Some(("flightgear-data-models".into(), "1:2020.3.16+dfsg-1".into()))
        );
        assert_eq!(wheel_stem("example-robot-data"), "example_robot_data");
        let pkg = PackageInput {
            name: "sweethome3d-furniture".into(),
            version: "1".into(),
            license: "CC-BY-3.0".into(),
            files: Vec::new(),
        };
        assert_eq!(license_of(&pkg, "a/BlendSwap-CC-0.sh3f!x.obj"), "CC0-1.0");
        assert_eq!(
            license_of(&pkg, "a/BlendSwap-CC-BY.sh3f!x.obj"),
            "CC-BY-3.0"
        );
    }
}
