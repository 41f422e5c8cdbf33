//! `meshflow data`: fetch the allowed sources (docs/data.md), build training shards from
//! them, and look at the result.
//!
//! The build core, [`build`], takes a list of [`PackageInput`]s (name, version, license, the
//! files of the unpacked package) so tests can run it on a small folder; [`build_command`]
//! finds the packages in the cache, unpacks them once and calls it.
//!
//! Per file: the format comes from the name ([`Format::from_path`]); `.zip`, `.pk3`, `.sh3f`
//! and `.wz` archives (and archives inside them) are opened and their members treated like
//! files, named `archive!member`. Every mesh is read, cleaned, filtered, normalised to the
//! model frame, deduplicated and split (the rules are in [`meshflow::data::dataset`]); kept meshes
//! go to `{split}-{k:05}.safetensors` shards, one `manifest.jsonl` line each, and the counts
//! to `build.json`. Shards and manifest are byte-identical across runs for the same inputs.

use std::collections::{BTreeMap, HashMap};
use std::fs;
use std::io::{Cursor, Read, Seek};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use meshflow::Mesh;
use meshflow::data::dataset::{
    FilterOptions, Fnv64, ManifestEntry, Shard, ShardWriter, Split, filter, geometry_hash, mesh_id,
    split_key, split_of,
};
use meshflow::geometry::clean::{CleanOptions, CleanReport, clean};
use meshflow::geometry::normalize::{Normalization, UpAxis};
use meshflow::geometry::topology::TopologyReport;
use meshflow::io::{Format, Limits, read_bytes};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::BadInput;
use crate::plot;
use meshflow::data::shards::{load_meshes, read_manifest};

/// Bumped whenever processing changes, so per-package caches are rebuilt.
/// 2: sources rotated to Y-up ([`UP_AXES`]); the billboard-card filter.
/// 3: COLLADA, ASE, IQM and MD5 readers.
const PIPELINE_VERSION: u32 = 3;
/// Rounding of model-frame coordinates for the duplicate hash.
const HASH_QUANTUM: f32 = 1e-4;
/// Shard size limits.
const SHARD_MAX_MESHES: usize = 4000;
const SHARD_MAX_BYTES: u64 = 256 << 20;
/// Archives are opened and their members read like files.
const ARCHIVE_EXTENSIONS: [&str; 4] = ["zip", "pk3", "sh3f", "wz"];
/// Nested archives deeper than this are not opened.
const MAX_ARCHIVE_DEPTH: usize = 4;
/// Mesh formats found in the sources; those `meshflow::io` cannot read yet are counted as
/// "unsupported format" (others, like textures and sounds, are not meshes and are ignored).
const MESH_EXTENSIONS: [&str; 22] = [
    "obj", "ply", "stl", "gltf", "glb", "pmd", "spm", "md2", "md3", "md5mesh", "pie", "ase", "ac",
    "dae", "iqm", "iqe", "3ds", "x", "b3d", "ms3d", "lwo", "fbx",
];

/// A Debian package of docs/data.md's table and its license.
pub const DEBIAN_SOURCES: [(&str, &str); 9] = [
    ("0ad-data", "CC-BY-SA-3.0"),
    ("supertuxkart-data", "CC-BY-SA-3.0/4.0 (some CC0, CC-BY)"),
    ("ufoai-data", "GPL-2+ / CC-BY(-SA)"),
    ("sweethome3d-furniture", "CC-BY-3.0"),
    ("warzone2100-data", "GPL-2+"),
    ("nexuiz-data", "GPL-2+"),
    ("openarena-data", "GPL-2+"),
    ("flightgear-data-models", "GPL-2+"),
    (
        "redeclipse-data",
        "CC (per asset, see the package's copyright file)",
    ),
];

/// Parts of a package licensed differently from the rest: (package, path fragment, license).
const LICENSE_OVERRIDES: [(&str, &str, &str); 1] =
    [("sweethome3d-furniture", "BlendSwap-CC-0.sh3f", "CC0-1.0")];

fn license_of(pkg: &PackageInput, path: &str) -> String {
    LICENSE_OVERRIDES
        .iter()
        .find(|(p, fragment, _)| *p == pkg.name && path.contains(fragment))
        .map_or_else(|| pkg.license.clone(), |(_, _, l)| l.to_string())
}

/// Which way is up in each source, by package and file extension (`*`: any); the first
/// matching row wins, and a package not listed is taken as Y-up. The build rotates every mesh
/// to the model frame's Y-up ([`UpAxis::to_y_up`]) before normalising it and records the
/// source's axis in the manifest (`up_axis`).
///
/// Evidence, from the 6,292-mesh build (docs/data.md sources): for each source and format,
/// the axis on which objects rest on the origin (their minimum is ~0 while the other two
/// axes are centred) and the longest axis of obviously upright objects (trees, towers, lamp
/// posts, flags, statues, characters):
/// - 0 A.D. PMD: rests on y in 24% of meshes (x, z: <1%); cypress, towers tall in y.
/// - SuperTuxKart SPM: fir and pine trees, lamp posts tall in y (Irrlicht is Y-up).
/// - Warzone 2100 PIE: rests on y in 60% (x, z: ~0).
/// - Sweet Home 3D OBJ: rests on y in 41%; chairs, lamps, doors tall in y.
/// - FlightGear AC3D: rests on y in 36%; towers tall in y (AC3D files are Y-up; FlightGear
///   rotates them when it loads them).
/// - Red Eclipse OBJ: rests on y in 60% (lamp post, pillar, safety post tall in y); its MD3
///   vegetation rests on z (Cube engines are Z-up).
/// - UFO:AI MD2 rests on z in 31% (x, y: ~0); its few OBJ (tanks, robots) rest on y.
/// - Nexuiz MD3 rests on z in 37%; OpenArena MD3 flags, palm tree and statue are tall in z
///   and teleporters rest on z (Quake III is Z-up); OpenArena's one OBJ rests on y.
/// - Robot wheels (STL, OBJ, DAE): URDF/MJCF link frames are Z-up (ROS REP 103); gripper,
///   leg and torso links are long in z. COLLADA files declare their `<up_axis>` and the DAE
///   reader already turns them to Y-up, hence the first row (any package).
/// - ASE, IQM and MD5 (Quake/Cube-family and 3ds Max exports) are Z-up like MD3.
pub const UP_AXES: [(&str, &str, UpAxis); 21] = [
    ("*", "dae", UpAxis::Y),
    ("0ad-data", "*", UpAxis::Y),
    ("supertuxkart-data", "*", UpAxis::Y),
    ("warzone2100-data", "*", UpAxis::Y),
    ("sweethome3d-furniture", "*", UpAxis::Y),
    ("flightgear-data-models", "*", UpAxis::Y),
    ("redeclipse-data", "obj", UpAxis::Y),
    ("redeclipse-data", "*", UpAxis::Z),
    ("ufoai-data", "obj", UpAxis::Y),
    ("ufoai-data", "*", UpAxis::Z),
    ("nexuiz-data", "obj", UpAxis::Y),
    ("nexuiz-data", "*", UpAxis::Z),
    ("openarena-data", "obj", UpAxis::Y),
    ("openarena-data", "*", UpAxis::Z),
    ("robosuite", "*", UpAxis::Z),
    ("example-robot-data", "*", UpAxis::Z),
    ("dm-control", "*", UpAxis::Z),
    ("rtb-data", "*", UpAxis::Z),
    ("metaworld", "*", UpAxis::Z),
    ("gymnasium-robotics", "*", UpAxis::Z),
    ("pybullet", "*", UpAxis::Z),
];

/// The up axis of a mesh file of `package` ([`UP_AXES`]).
pub fn up_axis_of(package: &str, path: &str) -> UpAxis {
    let ext = extension(path);
    UP_AXES
        .iter()
        .find(|(p, e, _)| (*p == "*" || *p == package) && (*e == "*" || *e == ext))
        .map_or(UpAxis::Y, |(_, _, axis)| *axis)
}

/// The PyPI projects of docs/data.md's table and their licenses.
pub const PYPI_SOURCES: [(&str, &str); 7] = [
    ("robosuite", "MIT"),
    ("example-robot-data", "BSD-3-Clause"),
    ("dm-control", "Apache-2.0"),
    ("rtb-data", "MIT"),
    ("metaworld", "MIT"),
    ("gymnasium-robotics", "MIT"),
    ("pybullet", "Zlib"),
];

pub fn default_cache() -> PathBuf {
    std::env::var_os("HOME")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("."))
        .join(".cache/meshflow/data")
}

/// The shard build a command reads: `dir`, or the default build's `CACHE/shards`.
pub fn shards_dir(dir: Option<PathBuf>) -> PathBuf {
    dir.unwrap_or_else(|| default_cache().join("shards"))
}

// ---------------------------------------------------------------------------------------
// fetch

fn run_tool(cmd: &mut Command, what: &str) -> Result<std::process::Output> {
    let program = cmd.get_program().to_string_lossy().into_owned();
    let out = cmd.output().map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            anyhow::anyhow!(
                "`{program}` is not installed; `meshflow data` needs it to {what} \
                 (on Debian or Ubuntu: apt-get install {})",
                if program == "pip" {
                    "python3-pip"
                } else {
                    "apt dpkg"
                }
            )
        } else {
            anyhow::anyhow!("cannot run `{program}`: {e}")
        }
    })?;
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let last: Vec<&str> = stderr.lines().rev().take(3).collect();
        let mut last: Vec<&str> = last.into_iter().rev().collect();
        last.retain(|l| !l.trim().is_empty());
        bail!(
            "`{program}` failed to {what} ({}): {}",
            out.status,
            last.join(" | ")
        );
    }
    Ok(out)
}

/// `apt-cache show`'s fields for the candidate version.
struct AptInfo {
    version: String,
    arch: String,
    sha256: String,
}

fn apt_info(package: &str) -> Result<AptInfo> {
    let out = run_tool(
        Command::new("apt-cache").args(["show", "--no-all-versions", package]),
        &format!("look up {package} (try `apt-get update`)"),
    )?;
    let text = String::from_utf8_lossy(&out.stdout);
    let field = |name: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(name).and_then(|r| r.strip_prefix(": ")))
            .map(|s| s.trim().to_string())
    };
    match (field("Version"), field("Architecture"), field("SHA256")) {
        (Some(version), Some(arch), Some(sha256)) => Ok(AptInfo {
            version,
            arch,
            sha256,
        }),
        _ => bail!("apt-cache knows no downloadable {package} (run `apt-get update`?)"),
    }
}

fn sha256_file(path: &Path) -> Result<String> {
    use sha2::{Digest, Sha256};
    let mut f = fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    loop {
        let n = f.read(&mut buf)?;
        if n == 0 {
            break;
        }
        h.update(&buf[..n]);
    }
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

/// The file name `apt-get download` gives a package (`:` of an epoch written `%3a`).
fn deb_file_name(package: &str, version: &str, arch: &str) -> String {
    format!("{package}_{}_{arch}.deb", version.replace(':', "%3a"))
}

/// Normalised PyPI project name (PEP 503, with `_` as wheels write it).
fn wheel_stem(project: &str) -> String {
    project.to_ascii_lowercase().replace(['-', '.'], "_")
}

pub fn fetch(cache: &Path) -> Result<()> {
    let debs = cache.join("debs");
    let wheels = cache.join("wheels");
    fs::create_dir_all(&debs).with_context(|| format!("cannot create {}", debs.display()))?;
    fs::create_dir_all(&wheels).with_context(|| format!("cannot create {}", wheels.display()))?;
    for (package, _) in DEBIAN_SOURCES {
        let info = apt_info(package)?;
        let file = debs.join(deb_file_name(package, &info.version, &info.arch));
        if file.exists() && sha256_file(&file)? == info.sha256 {
            println!("{package} {}: present, SHA256 ok", info.version);
            continue;
        }
        let t = Instant::now();
        println!("{package} {}: downloading ...", info.version);
        run_tool(
            Command::new("apt-get")
                .args(["download", package])
                .current_dir(&debs),
            &format!("download {package} (network?)"),
        )?;
        let got = sha256_file(&file)
            .with_context(|| format!("apt-get download did not leave {}", file.display()))?;
        if got != info.sha256 {
            bail!(
                "{} has SHA256 {got}, apt-cache says {}",
                file.display(),
                info.sha256
            );
        }
        println!(
            "{package} {}: downloaded {} MB in {:.0} s",
            info.version,
            fs::metadata(&file)?.len() >> 20,
            t.elapsed().as_secs_f64()
        );
    }
    for (project, _) in PYPI_SOURCES {
        if let Some(w) = find_wheel(&wheels, project)? {
            println!("{project}: present ({})", w.display());
            continue;
        }
        println!("{project}: downloading ...");
        run_tool(
            Command::new("pip")
                .args(["download", "--no-deps", project, "-d"])
                .arg(&wheels),
            &format!("download {project} (network?)"),
        )?;
        match find_wheel(&wheels, project)? {
            Some(w) => println!("{project}: downloaded {}", w.display()),
            None => bail!(
                "pip download {project} left no wheel in {}",
                wheels.display()
            ),
        }
    }
    Ok(())
}

fn find_wheel(dir: &Path, project: &str) -> Result<Option<PathBuf>> {
    let prefix = format!("{}-", wheel_stem(project));
    let mut found: Vec<PathBuf> = list_dir(dir)?
        .into_iter()
        .filter(|p| {
            let n = file_name(p).to_ascii_lowercase();
            n.starts_with(&prefix) && n.ends_with(".whl")
        })
        .collect();
    found.sort();
    Ok(found.pop())
}

fn list_dir(dir: &Path) -> Result<Vec<PathBuf>> {
    if !dir.exists() {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for e in fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))? {
        out.push(e?.path());
    }
    out.sort();
    Ok(out)
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

// ---------------------------------------------------------------------------------------
// build: inputs

/// One file of a package: its path inside the package (`/`-separated) and on disk. An empty
/// `rel` means the file *is* the package (a wheel): its members are named without a prefix.
#[derive(Clone, Debug)]
pub struct InputFile {
    pub rel: String,
    pub abs: PathBuf,
}

/// A source package as [`build`] takes it.
#[derive(Clone, Debug)]
pub struct PackageInput {
    pub name: String,
    pub version: String,
    pub license: String,
    pub files: Vec<InputFile>,
}

impl PackageInput {
    /// All files under `root`, named relative to it, sorted.
    pub fn from_dir(name: &str, version: &str, license: &str, root: &Path) -> Result<Self> {
        let mut files = Vec::new();
        let mut stack = vec![root.to_path_buf()];
        while let Some(dir) = stack.pop() {
            for e in fs::read_dir(&dir).with_context(|| format!("cannot list {}", dir.display()))? {
                let e = e?;
                let ty = e.file_type()?;
                let path = e.path();
                if ty.is_dir() {
                    stack.push(path);
                } else if ty.is_file() {
                    let rel = path
                        .strip_prefix(root)
                        .expect("under root")
                        .to_string_lossy()
                        .replace('\\', "/");
                    files.push(InputFile { rel, abs: path });
                }
            }
        }
        files.sort_by(|a, b| a.rel.cmp(&b.rel));
        Ok(PackageInput {
            name: name.into(),
            version: version.into(),
            license: license.into(),
            files,
        })
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct BuildOptions {
    pub filter: FilterOptions,
    /// Process at most this many mesh files per source (in path order); 0 = all.
    pub limit_per_source: usize,
    pub jobs: usize,
    #[serde(skip)]
    pub quiet: bool,
}

impl Default for BuildOptions {
    fn default() -> Self {
        Self {
            filter: FilterOptions::default(),
            limit_per_source: 0,
            jobs: 0,
            quiet: true,
        }
    }
}

// ---------------------------------------------------------------------------------------
// build: per-package processing

/// A mesh that passed the filter, before duplicates are removed.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Record {
    path: String,
    vertices: usize,
    faces: usize,
    max_degree: usize,
    topology: TopologyReport,
    clean: CleanReport,
    up_axis: UpAxis,
    center: [f32; 3],
    scale: f32,
    content_hash: String,
}

/// What one package gave, as cached in `cache/<package>-<version>.json` (the meshes, in
/// record order, are in the `.safetensors` beside it).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct PackageResult {
    fingerprint: String,
    files: u64,
    mesh_files: u64,
    records: Vec<Record>,
    /// Reason -> count: `unsupported_format`, `unreadable:<kind>`, `filter:<reason>`,
    /// `collision`, `procedural`, `archive_error`.
    skipped: BTreeMap<String, u64>,
    /// Extension -> count of the mesh files skipped as unsupported format.
    unsupported_extensions: BTreeMap<String, u64>,
    #[serde(skip)]
    meshes: Vec<Mesh>,
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

fn extension(name: &str) -> String {
    let file = name.rsplit(['/', '!']).next().unwrap_or(name);
    match file.rfind('.') {
        Some(i) => file[i + 1..].to_ascii_lowercase(),
        None => String::new(),
    }
}

enum Kind {
    Archive,
    Mesh,
    Unsupported(String),
    Collision,
    Procedural,
    Other,
}

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

fn bump(map: &mut BTreeMap<String, u64>, key: &str) {
    *map.entry(key.to_string()).or_default() += 1;
}

fn open_container(c: &Container) -> Result<zip::ZipArchive<Box<dyn ReadSeek>>> {
    let reader: Box<dyn ReadSeek> = match c {
        Container::Disk(p) => Box::new(std::io::BufReader::new(fs::File::open(p)?)),
        Container::Memory(b) => Box::new(Cursor::new(ArcBytes(b.clone()))),
    };
    Ok(zip::ZipArchive::new(reader)?)
}

trait ReadSeek: Read + Seek + Send {}
impl<T: Read + Seek + Send> ReadSeek for T {}

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
            .map_err(anyhow::Error::from)
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

/// The name of a [`meshflow::io::ReadError`] variant, in snake case ("truncated", ...).
fn error_kind(e: &meshflow::io::ReadError) -> String {
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
        Err(meshflow::io::ReadError::UnknownFormat) => {
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
            (Some(a), Some(i)) => a
                .by_index(*i)
                .map_err(anyhow::Error::from)
                .and_then(|mut f| {
                    let mut b = Vec::with_capacity(f.size().min(256 << 20) as usize);
                    f.read_to_end(&mut b)?;
                    Ok(b)
                }),
            _ => fs::read(abs).map_err(anyhow::Error::from),
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
/// executable itself, the formats `meshflow::io` reads, options, package identity and each
/// file's path, size and modification time.
fn fingerprint(pkg: &PackageInput, opts: &BuildOptions) -> Result<String> {
    let mut h = Fnv64::new();
    h.write(&PIPELINE_VERSION.to_le_bytes());
    h.write_str(env!("CARGO_PKG_VERSION"));
    h.write(&executable_hash().to_le_bytes());
    // A new reader (a new `Format`) changes what a package gives.
    for f in Format::ALL {
        h.write_str(f.name());
    }
    h.write_str(&serde_json::to_string(&opts.filter)?);
    h.write(&(opts.limit_per_source as u64).to_le_bytes());
    h.write_str(&pkg.name);
    h.write_str(&pkg.version);
    h.write_str(&pkg.license);
    for f in &pkg.files {
        let md =
            fs::metadata(&f.abs).with_context(|| format!("cannot read {}", f.abs.display()))?;
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

fn store_cached(cache: &Path, pkg: &PackageInput, result: &PackageResult) -> Result<()> {
    fs::create_dir_all(cache).with_context(|| format!("cannot create {}", cache.display()))?;
    let (json, shard) = cache_paths(cache, pkg);
    let mut w = ShardWriter::new();
    for m in &result.meshes {
        w.push(m);
    }
    write_atomic(&shard, &w.finish())?;
    write_atomic(&json, &serde_json::to_vec(result)?)
}

/// `path` with `suffix` appended to its last component (`with_extension` would replace
/// whatever follows the last dot, e.g. of a version number).
fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let mut s = path.as_os_str().to_os_string();
    s.push(suffix);
    PathBuf::from(s)
}

fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    meshflow::io::write_atomic(path, bytes)
        .with_context(|| format!("cannot write {}", path.display()))
}

fn process_package(
    pkg: &PackageInput,
    opts: &BuildOptions,
    cache: Option<&Path>,
) -> Result<(PackageResult, bool)> {
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
    let bar = if opts.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(total as u64)
    };
    bar.set_style(
        ProgressStyle::with_template("{msg:24} {bar:40} {pos}/{len} {elapsed}").expect("template"),
    );
    bar.set_message(pkg.name.clone());
    let mut outcomes: Vec<(String, Outcome)> = batches
        .par_iter()
        .flat_map_iter(|b| {
            let out = run_batch(&pkg.name, b, opts);
            bar.inc(out.len() as u64);
            out
        })
        .collect();
    bar.finish_and_clear();
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

// ---------------------------------------------------------------------------------------
// build: global steps

#[derive(Debug, Default, Serialize)]
pub struct SourceSummary {
    pub version: String,
    pub license: String,
    pub from_cache: bool,
    /// Files seen, archive members included.
    pub files: u64,
    /// Files with a mesh extension (readable or not).
    pub mesh_files: u64,
    /// Meshes that passed the filter, before duplicates were removed.
    pub passed_filter: u64,
    pub kept: u64,
    pub splits: BTreeMap<String, u64>,
    pub skipped: BTreeMap<String, u64>,
    pub unsupported_extensions: BTreeMap<String, u64>,
}

#[derive(Debug, Serialize)]
pub struct ShardSummary {
    pub file: String,
    pub meshes: usize,
    pub bytes: u64,
}

#[derive(Debug, Serialize)]
pub struct BuildSummary {
    pub tool: String,
    pub pipeline_version: u32,
    pub wall_time_s: f64,
    pub options: BuildOptions,
    pub kept: u64,
    pub splits: BTreeMap<String, u64>,
    pub skipped: BTreeMap<String, u64>,
    pub sources: BTreeMap<String, SourceSummary>,
    pub shards: Vec<ShardSummary>,
}

/// Builds shards, `manifest.jsonl` and `build.json` in `out` from `packages`. With `cache`,
/// each package's result is reused while its inputs are unchanged.
pub fn build(
    packages: &[PackageInput],
    out: &Path,
    cache: Option<&Path>,
    opts: &BuildOptions,
) -> Result<BuildSummary> {
    let start = Instant::now();
    fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut sources: BTreeMap<String, SourceSummary> = BTreeMap::new();
    // (package index, record, mesh) of every mesh that passed the filter.
    let mut all: Vec<(usize, Record, Mesh)> = Vec::new();
    let mut order: Vec<usize> = (0..packages.len()).collect();
    order.sort_by(|&a, &b| packages[a].name.cmp(&packages[b].name));
    for &k in &order {
        let pkg = &packages[k];
        if sources.contains_key(&pkg.name) {
            bail!(BadInput(format!("package {} is listed twice", pkg.name)));
        }
        let t = Instant::now();
        let (result, from_cache) = process_package(pkg, opts, cache)?;
        if !opts.quiet {
            println!(
                "{:<24} {:>7} files, {:>6} mesh files, {:>6} passed the filter{} ({:.1} s)",
                pkg.name,
                result.files,
                result.mesh_files,
                result.records.len(),
                if from_cache { ", cached" } else { "" },
                t.elapsed().as_secs_f64()
            );
        }
        sources.insert(
            pkg.name.clone(),
            SourceSummary {
                version: pkg.version.clone(),
                license: pkg.license.clone(),
                from_cache,
                files: result.files,
                mesh_files: result.mesh_files,
                passed_filter: result.records.len() as u64,
                skipped: result.skipped,
                unsupported_extensions: result.unsupported_extensions,
                ..Default::default()
            },
        );
        for (r, m) in result.records.into_iter().zip(result.meshes) {
            all.push((k, r, m));
        }
    }
    // Duplicates: first by (package, path) wins.
    all.sort_by(|a, b| (&packages[a.0].name, &a.1.path).cmp(&(&packages[b.0].name, &b.1.path)));
    let mut seen_hash: HashMap<String, ()> = HashMap::new();
    let mut seen_shape: HashMap<(usize, usize, usize, usize, usize), ()> = HashMap::new();
    let mut kept: Vec<(ManifestEntry, Mesh)> = Vec::new();
    for (k, r, m) in all {
        let pkg = &packages[k];
        let src = sources.get_mut(&pkg.name).expect("inserted above");
        if seen_hash.insert(r.content_hash.clone(), ()).is_some() {
            bump(&mut src.skipped, "duplicate");
            continue;
        }
        let shape = (
            k,
            r.vertices,
            r.faces,
            r.max_degree,
            r.topology.boundary_edges,
        );
        if seen_shape.insert(shape, ()).is_some() {
            bump(&mut src.skipped, "duplicate_pose_or_lod");
            continue;
        }
        let split = split_of(&split_key(&pkg.name, &r.path));
        let license = license_of(pkg, &r.path);
        src.kept += 1;
        *src.splits.entry(split.name().into()).or_default() += 1;
        kept.push((
            ManifestEntry {
                id: format!("{:016x}", mesh_id(&pkg.name, &r.path, "")),
                split,
                shard: String::new(),
                index: 0,
                package: pkg.name.clone(),
                package_version: pkg.version.clone(),
                path: r.path,
                submesh: String::new(),
                license,
                vertices: r.vertices,
                faces: r.faces,
                max_degree: r.max_degree,
                topology: r.topology,
                clean: r.clean,
                up_axis: r.up_axis,
                center: r.center,
                scale: r.scale,
                content_hash: r.content_hash,
            },
            m,
        ));
    }
    let texts = |name: &str| match packages.iter().find(|p| p.name == name) {
        Some(pkg) => license_texts(pkg),
        None => Ok(Vec::new()),
    };
    let (shards, splits) = write_dataset(out, &mut kept, &texts)?;
    let mut skipped = BTreeMap::new();
    for s in sources.values() {
        for (k, v) in &s.skipped {
            *skipped.entry(k.clone()).or_default() += v;
        }
    }
    let summary = BuildSummary {
        tool: format!("meshflow {}", env!("CARGO_PKG_VERSION")),
        pipeline_version: PIPELINE_VERSION,
        wall_time_s: (start.elapsed().as_secs_f64() * 1000.0).round() / 1000.0,
        options: opts.clone(),
        kept: kept.len() as u64,
        splits,
        skipped,
        sources,
        shards,
    };
    write_atomic(
        &out.join("build.json"),
        serde_json::to_string_pretty(&summary)?.as_bytes(),
    )?;
    Ok(summary)
}

/// Writes kept meshes as a dataset in `out`: `{split}-{k:05}.safetensors` shards (meshes
/// sorted by split and id, a new shard when one reaches [`SHARD_MAX_MESHES`] or
/// [`SHARD_MAX_BYTES`]; stale shards of an earlier run removed), `manifest.jsonl` (sorted by
/// id, `shard` and `index` filled in here) and the attribution ([`write_attribution`], with
/// `license_texts` giving a package's license files). `build` and `subset` both write through
/// it, so a dataset written twice from the same entries and meshes is byte-identical. Returns
/// the shards and the mesh count of each split.
fn write_dataset(
    out: &Path,
    kept: &mut [(ManifestEntry, Mesh)],
    license_texts: &LicenseTexts,
) -> Result<(Vec<ShardSummary>, BTreeMap<String, u64>)> {
    fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    kept.sort_by(|a, b| (a.0.split, &a.0.id).cmp(&(b.0.split, &b.0.id)));
    // Stale shards of an earlier build would be mistaken for this one's.
    for p in list_dir(out)? {
        let n = file_name(&p);
        if n.ends_with(".safetensors") && Split::ALL.iter().any(|s| n.starts_with(s.name())) {
            fs::remove_file(&p).with_context(|| format!("cannot remove {}", p.display()))?;
        }
    }
    let mut shards = Vec::new();
    let mut splits = BTreeMap::new();
    for split in Split::ALL {
        let items: Vec<&mut (ManifestEntry, Mesh)> =
            kept.iter_mut().filter(|e| e.0.split == split).collect();
        splits.insert(split.name().to_string(), items.len() as u64);
        let mut writer = ShardWriter::new();
        let mut members: Vec<&mut ManifestEntry> = Vec::new();
        let mut k = 0;
        let flush = |writer: ShardWriter,
                     members: &mut Vec<&mut ManifestEntry>,
                     k: &mut usize,
                     shards: &mut Vec<ShardSummary>|
         -> Result<()> {
            let name = format!("{}-{:05}.safetensors", split.name(), *k);
            let bytes = writer.finish();
            write_atomic(&out.join(&name), &bytes)?;
            shards.push(ShardSummary {
                file: name.clone(),
                meshes: members.len(),
                bytes: bytes.len() as u64,
            });
            for m in members.drain(..) {
                m.shard = name.clone();
            }
            *k += 1;
            Ok(())
        };
        for (entry, mesh) in items {
            let size = 12 * mesh.positions.len() as u64 + 12 * mesh.faces.len() as u64 + 16;
            if !writer.is_empty()
                && (writer.len() >= SHARD_MAX_MESHES
                    || writer.data_bytes() + size > SHARD_MAX_BYTES)
            {
                flush(
                    std::mem::take(&mut writer),
                    &mut members,
                    &mut k,
                    &mut shards,
                )?;
            }
            entry.index = writer.push(mesh);
            members.push(entry);
        }
        if !writer.is_empty() {
            flush(writer, &mut members, &mut k, &mut shards)?;
        }
    }
    let mut entries: Vec<&ManifestEntry> = kept.iter().map(|e| &e.0).collect();
    entries.sort_by(|a, b| a.id.cmp(&b.id));
    let mut manifest = Vec::new();
    for e in &entries {
        serde_json::to_writer(&mut manifest, e)?;
        manifest.push(b'\n');
    }
    write_atomic(&out.join("manifest.jsonl"), &manifest)?;
    write_attribution(out, entries.into_iter(), license_texts)?;
    Ok((shards, splits))
}

/// True for the paths license texts have: Debian's `usr/share/doc/<name>/copyright`, a wheel's
/// `*.dist-info/LICENSE*` or `*.dist-info/licenses/*`.
fn is_license_path(package: &str, path: &str) -> bool {
    let leaf = path.rsplit('/').next().unwrap_or("");
    path == format!("usr/share/doc/{package}/copyright")
        || (path.contains(".dist-info/")
            && (leaf.starts_with("LICENSE") || path.contains(".dist-info/licenses/")))
}

/// The license texts a package ships, as (path inside the package, bytes), sorted by path.
/// A wheel (an input file with an empty `rel`) is searched inside its zip.
fn license_texts(pkg: &PackageInput) -> Result<Vec<(String, Vec<u8>)>> {
    let mut found = Vec::new();
    for f in &pkg.files {
        if f.rel.is_empty() {
            let file = fs::File::open(&f.abs)
                .with_context(|| format!("cannot read {}", f.abs.display()))?;
            let mut zip = zip::ZipArchive::new(file)?;
            for i in 0..zip.len() {
                let mut member = zip.by_index(i)?;
                let name = member.name()?.to_string();
                if member.is_file() && is_license_path(&pkg.name, &name) {
                    let mut bytes = Vec::new();
                    std::io::Read::read_to_end(&mut member, &mut bytes)?;
                    found.push((name, bytes));
                }
            }
        } else if is_license_path(&pkg.name, &f.rel) {
            let bytes =
                fs::read(&f.abs).with_context(|| format!("cannot read {}", f.abs.display()))?;
            found.push((f.rel.clone(), bytes));
        }
    }
    found.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(found)
}

/// Package name -> its license texts as (path in the package, bytes).
type LicenseTexts<'a> = dyn Fn(&str) -> Result<Vec<(String, Vec<u8>)>> + 'a;

/// One license file copied to `licenses/`, as listed in `licenses/index.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct LicenseFile {
    package: String,
    /// The copy's name in `licenses/`.
    file: String,
    /// Where the text is in the package.
    path: String,
}

/// Writes `ATTRIBUTION.md` (per package and license: version, how many meshes are used, where
/// its license text is) and copies each used package's license files (`license_texts`:
/// package name -> (path in the package, bytes)) to `licenses/`, listed in
/// `licenses/index.json`, so any artefact derived from the shards can carry them and a subset
/// can copy them on. Per-mesh source paths are in the manifest.
fn write_attribution<'a>(
    out: &Path,
    entries: impl Iterator<Item = &'a ManifestEntry>,
    license_texts: &LicenseTexts,
) -> Result<()> {
    let mut used: BTreeMap<(&str, &str, &str), usize> = BTreeMap::new();
    for e in entries {
        *used
            .entry((&e.package, &e.package_version, &e.license))
            .or_default() += 1;
    }
    let licenses_dir = out.join("licenses");
    fs::create_dir_all(&licenses_dir)
        .with_context(|| format!("cannot create {}", licenses_dir.display()))?;
    // Copies of an earlier run's packages would otherwise linger.
    for p in list_dir(&licenses_dir)? {
        let n = file_name(&p);
        if n.ends_with(".txt") || n == "index.json" {
            fs::remove_file(&p).with_context(|| format!("cannot remove {}", p.display()))?;
        }
    }
    let mut text = String::from(
        "# Attribution\n\nThe meshes in these shards come from the packages below, under the \
         licenses listed. Each mesh's package, version, path inside the package and license are \
         in `manifest.jsonl`. Anything derived from the shards (trained weights, rendered \
         images, converted meshes) must carry this file and the `licenses/` folder.\n\n\
         | package | version | license | meshes | license files |\n|---|---|---|---:|---|\n",
    );
    let mut index: Vec<LicenseFile> = Vec::new();
    for ((name, version, license), count) in &used {
        let texts = license_texts(name)?;
        let mut copied = Vec::new();
        for (k, (path, bytes)) in texts.iter().enumerate() {
            let dest = format!("{name}-{k}.txt");
            write_atomic(&licenses_dir.join(&dest), bytes)?;
            copied.push(format!("`licenses/{dest}` (`{path}`)"));
            let file = LicenseFile {
                package: name.to_string(),
                file: dest,
                path: path.clone(),
            };
            if !index.contains(&file) {
                index.push(file);
            }
        }
        let files = if copied.is_empty() {
            "none shipped in the package".to_string()
        } else {
            copied.join(", ")
        };
        text.push_str(&format!(
            "| {name} | {version} | {license} | {count} | {files} |\n"
        ));
    }
    write_atomic(
        &licenses_dir.join("index.json"),
        serde_json::to_string_pretty(&index)?.as_bytes(),
    )?;
    write_atomic(&out.join("ATTRIBUTION.md"), text.as_bytes())
}

/// The license files a dataset in `dir` lists for `package` (`licenses/index.json`), as
/// [`write_attribution`] takes them.
fn dataset_license_texts(dir: &Path, package: &str) -> Result<Vec<(String, Vec<u8>)>> {
    let index_path = dir.join("licenses/index.json");
    let index: Vec<LicenseFile> =
        serde_json::from_slice(&fs::read(&index_path).with_context(|| {
            format!(
                "cannot read {} (built before license indexes; rebuild)",
                index_path.display()
            )
        })?)
        .with_context(|| format!("{} is not a license index", index_path.display()))?;
    index
        .into_iter()
        .filter(|f| f.package == package)
        .map(|f| {
            let p = dir.join("licenses").join(&f.file);
            let bytes = fs::read(&p).with_context(|| format!("cannot read {}", p.display()))?;
            Ok((f.path, bytes))
        })
        .collect()
}

// ---------------------------------------------------------------------------------------
// build: the real packages

/// `name_version_arch.deb` -> (name, version), `%3a` read back as `:`.
fn parse_deb_name(file: &str) -> Option<(String, String)> {
    let stem = file.strip_suffix(".deb")?;
    let mut parts = stem.split('_');
    let name = parts.next()?;
    let version = parts.next()?.replace("%3a", ":");
    Some((name.to_string(), version))
}

/// Unpacks a .deb once into `unpacked/<name>_<version>` (a marker file says it finished).
fn unpack_deb(deb: &Path, dir: &Path) -> Result<()> {
    let marker = dir.join(".meshflow-unpacked");
    if marker.exists() {
        return Ok(());
    }
    let tmp = with_suffix(dir, ".partial");
    if tmp.exists() {
        fs::remove_dir_all(&tmp).with_context(|| format!("cannot remove {}", tmp.display()))?;
    }
    fs::create_dir_all(&tmp).with_context(|| format!("cannot create {}", tmp.display()))?;
    run_tool(
        Command::new("dpkg-deb").arg("-x").arg(deb).arg(&tmp),
        &format!("unpack {}", deb.display()),
    )?;
    fs::write(tmp.join(".meshflow-unpacked"), file_name(deb))?;
    if dir.exists() {
        fs::remove_dir_all(dir).with_context(|| format!("cannot remove {}", dir.display()))?;
    }
    fs::rename(&tmp, dir).with_context(|| format!("cannot create {}", dir.display()))
}

/// The allowed packages present in `cache` (`debs/*.deb`, `wheels/*.whl`), unpacked.
pub fn discover(cache: &Path, quiet: bool) -> Result<(Vec<PackageInput>, Vec<String>)> {
    let mut packages = Vec::new();
    let mut missing = Vec::new();
    let debs = list_dir(&cache.join("debs"))?;
    for (name, license) in DEBIAN_SOURCES {
        let mut found: Vec<(String, PathBuf)> = debs
            .iter()
            .filter_map(|p| {
                let (n, v) = parse_deb_name(&file_name(p))?;
                (n == name).then(|| (v, p.clone()))
            })
            .collect();
        found.sort();
        let Some((version, deb)) = found.pop() else {
            missing.push(name.to_string());
            continue;
        };
        let dir = cache
            .join("unpacked")
            .join(format!("{name}_{}", version.replace(':', "%3a")));
        let t = Instant::now();
        if !dir.join(".meshflow-unpacked").exists() && !quiet {
            println!("unpacking {} ...", file_name(&deb));
        }
        unpack_deb(&deb, &dir)?;
        if !quiet && t.elapsed().as_secs_f64() > 1.0 {
            println!("  unpacked in {:.0} s", t.elapsed().as_secs_f64());
        }
        let mut pkg = PackageInput::from_dir(name, &version, license, &dir)?;
        pkg.files.retain(|f| f.rel != ".meshflow-unpacked");
        packages.push(pkg);
    }
    let wheels = cache.join("wheels");
    for (project, license) in PYPI_SOURCES {
        let Some(whl) = find_wheel(&wheels, project)? else {
            missing.push(project.to_string());
            continue;
        };
        let version = file_name(&whl)
            .split('-')
            .nth(1)
            .unwrap_or("unknown")
            .to_string();
        packages.push(PackageInput {
            name: project.to_string(),
            version,
            license: license.to_string(),
            files: vec![InputFile {
                rel: String::new(),
                abs: whl,
            }],
        });
    }
    Ok((packages, missing))
}

pub fn build_command(
    cache: &Path,
    out: Option<&Path>,
    jobs: usize,
    limit_per_source: usize,
) -> Result<()> {
    let start = Instant::now();
    let out = out.map_or_else(|| cache.join("shards"), Path::to_path_buf);
    if jobs > 0 {
        // Only the first call configures the global pool; later ones change nothing.
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(jobs)
            .build_global();
    }
    let (packages, missing) = discover(cache, false)?;
    if packages.is_empty() {
        bail!(BadInput(format!(
            "no source packages in {} (run `meshflow data fetch` first)",
            cache.display()
        )));
    }
    if !missing.is_empty() {
        println!("not in the cache (skipped): {}", missing.join(", "));
    }
    let opts = BuildOptions {
        limit_per_source,
        jobs,
        quiet: false,
        ..Default::default()
    };
    let s = build(&packages, &out, Some(&cache.join("cache")), &opts)?;
    println!();
    println!(
        "{:<24} {:>7} {:>7} {:>6} {:>6} {:>6}",
        "source", "passed", "kept", "train", "val", "test"
    );
    for (name, src) in &s.sources {
        let g = |k: &str| src.splits.get(k).copied().unwrap_or(0);
        println!(
            "{:<24} {:>7} {:>7} {:>6} {:>6} {:>6}",
            name,
            src.passed_filter,
            src.kept,
            g("train"),
            g("val"),
            g("test")
        );
    }
    let g = |k: &str| s.splits.get(k).copied().unwrap_or(0);
    println!(
        "{:<24} {:>7} {:>7} {:>6} {:>6} {:>6}",
        "total",
        "",
        s.kept,
        g("train"),
        g("val"),
        g("test")
    );
    println!("skipped:");
    for (reason, n) in &s.skipped {
        println!("  {reason:<40}{n:>8}");
    }
    let bytes: u64 = s.shards.iter().map(|x| x.bytes).sum();
    println!(
        "{} shards, {:.1} MiB, in {}; {:.1} s",
        s.shards.len(),
        bytes as f64 / (1 << 20) as f64,
        out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

// ---------------------------------------------------------------------------------------
// subset

/// What `meshflow data subset` selects (see [`subset`]).
#[derive(Clone, Debug, Serialize)]
pub struct SubsetOptions {
    pub train: usize,
    pub val: usize,
    pub test: usize,
    /// Only meshes with at most this many vertices.
    pub max_vertices: usize,
}

impl Default for SubsetOptions {
    fn default() -> Self {
        Self {
            train: 32,
            val: 4,
            test: 4,
            max_vertices: 512,
        }
    }
}

/// `subset.json`: what a subset holds and where it came from.
#[derive(Debug, Serialize)]
pub struct SubsetSummary {
    pub tool: String,
    pub options: SubsetOptions,
    /// The source build's pipeline version (from its `build.json`), when known.
    pub source_pipeline_version: Option<u32>,
    pub kept: usize,
    pub splits: BTreeMap<String, u64>,
    pub packages: BTreeMap<String, u64>,
    pub shards: Vec<ShardSummary>,
}

/// Picks the subset's entries: for each split, the permissively licensed
/// ([`meshflow::data::dataset::is_permissive`]) meshes of at most `max_vertices` vertices from the
/// packages in `with_license_text` (a mesh cannot be redistributed without its license text),
/// taken round-robin over packages so the sources vary (in name order, starting a third of
/// the way further for each split so validation and test do not always start at the same
/// package), and inside a package in id order (ids are hashes, so effectively a fixed random
/// order), objects not yet taken ([`split_key`]) first. Deterministic: the same manifest gives
/// the same subset.
fn select_subset(
    entries: &[ManifestEntry],
    with_license_text: &std::collections::BTreeSet<String>,
    opts: &SubsetOptions,
) -> Vec<ManifestEntry> {
    let packages: Vec<&String> = with_license_text.iter().collect();
    let mut picked = Vec::new();
    for (k, (split, quota)) in [
        (Split::Train, opts.train),
        (Split::Val, opts.val),
        (Split::Test, opts.test),
    ]
    .into_iter()
    .enumerate()
    {
        let mut queues: Vec<std::collections::VecDeque<&ManifestEntry>> = packages
            .iter()
            .map(|package| {
                let mut q: Vec<&ManifestEntry> = entries
                    .iter()
                    .filter(|e| {
                        e.split == split
                            && &&e.package == package
                            && meshflow::data::dataset::is_permissive(&e.license)
                            && e.vertices <= opts.max_vertices
                    })
                    .collect();
                q.sort_by(|a, b| a.id.cmp(&b.id));
                // One entry of each object first, then the rest.
                let mut seen = std::collections::HashSet::new();
                let (first, rest): (Vec<_>, Vec<_>) = q
                    .into_iter()
                    .partition(|e| seen.insert(split_key(&e.package, &e.path)));
                first.into_iter().chain(rest).collect()
            })
            .collect();
        let start = k * queues.len() / 3;
        queues.rotate_left(start);
        let mut taken = 0;
        while taken < quota && queues.iter().any(|q| !q.is_empty()) {
            for q in &mut queues {
                if taken == quota {
                    break;
                }
                if let Some(e) = q.pop_front() {
                    picked.push(e.clone());
                    taken += 1;
                }
            }
        }
    }
    picked
}

/// Writes a small dataset to `out` from the built one in `dir` (see [`select_subset`]): its
/// shards, manifest (entries unchanged except `shard` and `index`), attribution and the used
/// packages' license files, all through [`write_dataset`] like the build, plus `subset.json`.
pub fn subset(dir: &Path, out: &Path, opts: &SubsetOptions) -> Result<SubsetSummary> {
    let entries = read_manifest(dir)?;
    let packages: std::collections::BTreeSet<&String> =
        entries.iter().map(|e| &e.package).collect();
    let mut with_license_text = std::collections::BTreeSet::new();
    for package in packages {
        if !dataset_license_texts(dir, package)?.is_empty() {
            with_license_text.insert(package.clone());
        }
    }
    let picked = select_subset(&entries, &with_license_text, opts);
    let mut kept = load_meshes(dir, picked)?;
    let texts = |package: &str| dataset_license_texts(dir, package);
    let (shard_summaries, splits) = write_dataset(out, &mut kept, &texts)?;
    let mut packages = BTreeMap::new();
    for (e, _) in &kept {
        *packages.entry(e.package.clone()).or_default() += 1;
    }
    let source_pipeline_version = fs::read(dir.join("build.json"))
        .ok()
        .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
        .and_then(|v| v["pipeline_version"].as_u64())
        .map(|v| v as u32);
    let summary = SubsetSummary {
        tool: format!("meshflow {}", env!("CARGO_PKG_VERSION")),
        options: opts.clone(),
        source_pipeline_version,
        kept: kept.len(),
        splits,
        packages,
        shards: shard_summaries,
    };
    write_atomic(
        &out.join("subset.json"),
        serde_json::to_string_pretty(&summary)?.as_bytes(),
    )?;
    Ok(summary)
}

pub fn subset_command(dir: &Path, out: &Path, opts: &SubsetOptions) -> Result<()> {
    let s = subset(dir, out, opts)?;
    let g = |k: &str| s.splits.get(k).copied().unwrap_or(0);
    println!(
        "{} meshes ({} train, {} val, {} test) from {} packages -> {}",
        s.kept,
        g("train"),
        g("val"),
        g("test"),
        s.packages.len(),
        out.display()
    );
    for (p, n) in &s.packages {
        println!("  {p:<24}{n:>4}");
    }
    let bytes: u64 = s.shards.iter().map(|x| x.bytes).sum();
    println!("{} shards, {} bytes", s.shards.len(), bytes);
    Ok(())
}

// ---------------------------------------------------------------------------------------
// stats and show

/// One histogram panel: `values` binned over `0..=max`.
struct HistPanel {
    title: String,
    values: Vec<usize>,
    max: usize,
    color: [u8; 3],
}

/// Histogram panels stacked vertically, each with a title, labelled axes and
/// light grid lines, as PNG bytes. Deterministic: same panels, same bytes.
fn histogram_png(panels: &[HistPanel]) -> Result<Vec<u8>> {
    // 76 px of count labels, 700 px of bars, room for the last value label.
    const W: usize = 820;
    const PANEL_H: usize = 320;
    const BINS: usize = 50;
    const BAR_W: usize = 14;
    const SCALE: usize = 2;
    let mut img = plot::Canvas::new(W, PANEL_H * panels.len(), [255, 255, 255]);
    for (p, panel) in panels.iter().enumerate() {
        let top_y = p * PANEL_H;
        let mut bins = [0usize; BINS];
        for &v in &panel.values {
            bins[(v * BINS / (panel.max + 1)).min(BINS - 1)] += 1;
        }
        let tallest = bins.iter().copied().max().unwrap_or(0).max(1);
        // Left margin for the count labels, room above for the title and
        // below for the value labels.
        let frame = plot::Frame {
            x0: 76,
            y_base: top_y + PANEL_H - 44,
            w: BINS * BAR_W,
            h: PANEL_H - 44 - 64,
        };
        img.text(frame.x0, top_y + 14, &panel.title, SCALE, plot::BLACK);
        img.text(
            frame.x0 + 6,
            frame.y_base - frame.h - 22,
            "meshes",
            SCALE,
            [90, 90, 90],
        );
        for (b, &count) in bins.iter().enumerate() {
            let bar_h = count * frame.h / tallest;
            img.fill_rect(
                frame.x0 + b * BAR_W,
                frame.y_base - bar_h,
                BAR_W - 1,
                bar_h,
                panel.color,
            );
        }
        img.axes(
            frame,
            panel.max + 1,
            plot::nice_step(panel.max, 4),
            tallest,
            plot::nice_step(tallest, 4),
            SCALE,
        );
    }
    img.to_png()
}

pub fn stats(dir: &Path, out: Option<&Path>) -> Result<()> {
    let entries = read_manifest(dir)?;
    let out = out.map_or_else(|| dir.to_path_buf(), Path::to_path_buf);
    fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut csv =
        String::from("id,split,package,path,vertices,faces,max_degree,boundary_edges,components\n");
    for e in &entries {
        csv.push_str(&format!(
            "{},{},{},\"{}\",{},{},{},{},{}\n",
            e.id,
            e.split,
            e.package,
            e.path.replace('"', "\"\""),
            e.vertices,
            e.faces,
            e.max_degree,
            e.topology.boundary_edges,
            e.topology.components
        ));
    }
    let csv_path = out.join("stats.csv");
    write_atomic(&csv_path, csv.as_bytes())?;
    let f = FilterOptions::default();
    let png_path = out.join("stats.png");
    let median = |mut v: Vec<usize>| {
        v.sort_unstable();
        v.get(v.len() / 2).copied().unwrap_or(0)
    };
    let vertices: Vec<usize> = entries.iter().map(|e| e.vertices).collect();
    let faces: Vec<usize> = entries.iter().map(|e| e.faces).collect();
    let (median_v, median_f) = (median(vertices.clone()), median(faces.clone()));
    let png = histogram_png(&[
        HistPanel {
            title: format!(
                "Vertices per mesh ({} meshes, median {})",
                plot::thousands(entries.len()),
                plot::thousands(median_v)
            ),
            values: vertices,
            max: f.max_vertices,
            color: [40, 90, 200],
        },
        HistPanel {
            title: format!("Faces per mesh (median {})", plot::thousands(median_f)),
            values: faces,
            max: f.max_faces,
            color: [200, 90, 40],
        },
    ])?;
    write_atomic(&png_path, &png)?;
    println!(
        "{} meshes; median {} vertices, {} faces",
        entries.len(),
        median_v,
        median_f
    );
    println!(
        "wrote {} and {} (top: vertices 0..{}, bottom: faces 0..{}, {} bins each)",
        csv_path.display(),
        png_path.display(),
        f.max_vertices,
        f.max_faces,
        50
    );
    Ok(())
}

pub fn show(dir: &Path, id: &str, output: &Path, source_frame: bool) -> Result<()> {
    let entries = read_manifest(dir)?;
    let Some(e) = entries.iter().find(|e| e.id == id) else {
        bail!(BadInput(format!(
            "no mesh with id {id} in {}",
            dir.display()
        )));
    };
    let shard_path = dir.join(&e.shard);
    let bytes =
        fs::read(&shard_path).with_context(|| format!("cannot read {}", shard_path.display()))?;
    let shard = Shard::from_bytes(&bytes)
        .with_context(|| format!("{} is corrupt", shard_path.display()))?;
    let Some(mut mesh) = shard.get(e.index) else {
        bail!(
            "{} has no mesh {} (manifest and shards disagree)",
            e.shard,
            e.index
        );
    };
    if source_frame {
        let norm = Normalization {
            center: e.center.into(),
            scale: e.scale,
        };
        mesh = e.up_axis.mesh_from_y_up(&norm.inverse().apply_mesh(&mesh));
    }
    meshflow::io::write_path(&mesh, output)
        .with_context(|| format!("cannot write {}", output.display()))?;
    println!(
        "{} ({} {}, {}): {} vertices, {} faces -> {}",
        e.id,
        e.package,
        e.package_version,
        e.path,
        e.vertices,
        e.faces,
        output.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use std::io::Write;

    fn fixture(name: &str) -> Vec<u8> {
        let p = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/fixtures/meshes")
            .join(name);
        fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    }

    fn zip_of(members: &[(&str, Vec<u8>)]) -> Vec<u8> {
        let mut w = zip::ZipWriter::new(Cursor::new(Vec::new()));
        for (name, bytes) in members {
            w.start_file(*name, zip::write::SimpleFileOptions::default())
                .unwrap();
            w.write_all(bytes).unwrap();
        }
        w.finish().unwrap().into_inner()
    }

    fn temp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("meshflow-data-{}-{tag}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    /// A fake package: a loose OBJ, a zip of fixtures (with a nested .pk3, a copy of a mesh
    /// under another name, a collision mesh, an unsupported .iqe and a texture).
    fn fake_package(root: &Path) -> PackageInput {
        let pkg = root.join("pkg");
        fs::create_dir_all(pkg.join("usr/share/game")).unwrap();
        fs::write(pkg.join("usr/share/game/bread.obj"), fixture("bread.obj")).unwrap();
        fs::write(pkg.join("usr/share/game/readme.txt"), b"1 2 3\n").unwrap();
        let nested = zip_of(&[
            ("models/stone_lantern.obj", fixture("stone_lantern.obj")),
            ("models/copy_of_bread.obj", fixture("bread.obj")),
        ]);
        let data = zip_of(&[
            ("meshes/deck_chair.obj", fixture("deck_chair.obj")),
            ("meshes/garden_lantern.obj", fixture("garden_lantern.obj")),
            (
                "meshes/finger_lower_link.stl",
                fixture("finger_lower_link.stl"),
            ),
            ("meshes/solo_lower_leg.obj", fixture("solo_lower_leg.obj")),
            (
                "meshes/humanoid_box_ascii.stl",
                fixture("humanoid_box_ascii.stl"),
            ),
            (
                "meshes/collision/solo_lower_leg.obj",
                fixture("solo_lower_leg.obj"),
            ),
            ("meshes/broken.obj", b"v 1 2\nf 1 2 3\n".to_vec()),
            ("meshes/horse.iqe", b"# Inter-Quake Export".to_vec()),
            ("textures/horse.png", b"\x89PNG".to_vec()),
            ("more.pk3", nested),
        ]);
        fs::write(pkg.join("usr/share/game/data.zip"), data).unwrap();
        fs::create_dir_all(pkg.join("usr/share/doc/fake-data")).unwrap();
        fs::write(
            pkg.join("usr/share/doc/fake-data/copyright"),
            "Fake copyright text\n",
        )
        .unwrap();
        PackageInput::from_dir("fake-data", "1.0-1", "CC0-1.0", &pkg).unwrap()
    }

    fn read_out(out: &Path) -> BTreeMap<String, Vec<u8>> {
        list_dir(out)
            .unwrap()
            .into_iter()
            .filter(|p| p.is_file() && file_name(p) != "build.json")
            .map(|p| (file_name(&p), fs::read(&p).unwrap()))
            .collect()
    }

    #[test]
    fn building_twice_gives_identical_bytes_and_uses_the_cache() {
        let root = temp_dir("twice");
        let pkg = fake_package(&root);
        let opts = BuildOptions::default();
        let a = build(std::slice::from_ref(&pkg), &root.join("out-a"), None, &opts).unwrap();
        let cache = root.join("cache");
        let b = build(
            std::slice::from_ref(&pkg),
            &root.join("out-b"),
            Some(&cache),
            &opts,
        )
        .unwrap();
        let c = build(
            std::slice::from_ref(&pkg),
            &root.join("out-c"),
            Some(&cache),
            &opts,
        )
        .unwrap();
        assert!(!b.sources["fake-data"].from_cache);
        assert!(c.sources["fake-data"].from_cache);
        let files_a = read_out(&root.join("out-a"));
        assert_eq!(files_a, read_out(&root.join("out-b")));
        assert_eq!(files_a, read_out(&root.join("out-c")));
        assert!(files_a.contains_key("manifest.jsonl"));
        let attribution = String::from_utf8(files_a["ATTRIBUTION.md"].clone()).unwrap();
        assert!(attribution.contains("| fake-data |"), "{attribution}");
        assert!(
            attribution.contains("`licenses/fake-data-0.txt`"),
            "{attribution}"
        );
        let copied = fs::read_to_string(root.join("out-a/licenses/fake-data-0.txt")).unwrap();
        assert_eq!(copied, "Fake copyright text\n");

        let src = &a.sources["fake-data"];
        assert_eq!(src.skipped.get("unsupported_format"), Some(&1));
        assert_eq!(src.unsupported_extensions.get("iqe"), Some(&1));
        assert_eq!(src.skipped.get("collision"), Some(&1));
        assert_eq!(src.skipped.get("duplicate"), Some(&1), "{:?}", src.skipped);
        assert_eq!(
            src.skipped.get("unreadable:malformed"),
            Some(&1),
            "{:?}",
            src.skipped
        );
        assert!(a.kept >= 3, "{a:?}");

        // The manifest points at every kept mesh, which round-trips through its shard.
        let manifest = String::from_utf8(files_a["manifest.jsonl"].clone()).unwrap();
        let entries: Vec<ManifestEntry> = manifest
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(entries.len() as u64, a.kept);
        assert!(entries.windows(2).all(|w| w[0].id < w[1].id));
        let paths: Vec<&str> = entries.iter().map(|e| e.path.as_str()).collect();
        assert!(
            paths.contains(&"usr/share/game/data.zip!more.pk3!models/stone_lantern.obj"),
            "{paths:?}"
        );
        for e in &entries {
            let shard = Shard::from_bytes(&files_a[&e.shard]).unwrap();
            let m = shard.mesh(e.index);
            assert_eq!((m.positions.len(), m.faces.len()), (e.vertices, e.faces));
            let aabb = m.aabb().unwrap();
            assert!((aabb.max_extent() - 2.0).abs() < 1e-4);
            assert!(aabb.min.min_element() >= -1.0001 && aabb.max.max_element() <= 1.0001);
            assert_eq!(
                e.content_hash,
                format!("{:016x}", geometry_hash(&m, HASH_QUANTUM))
            );
        }
        let _ = fs::remove_dir_all(&root);
    }

    #[test]
    fn a_changed_input_invalidates_the_cache() {
        let root = temp_dir("invalidate");
        let mut pkg = fake_package(&root);
        let cache = root.join("cache");
        let opts = BuildOptions::default();
        build(
            std::slice::from_ref(&pkg),
            &root.join("out"),
            Some(&cache),
            &opts,
        )
        .unwrap();
        fs::write(
            pkg.files[0].abs.with_file_name("extra.obj"),
            fixture("deck_chair.obj"),
        )
        .unwrap();
        pkg = PackageInput::from_dir("fake-data", "1.0-1", "CC0-1.0", &root.join("pkg")).unwrap();
        let s = build(&[pkg], &root.join("out"), Some(&cache), &opts).unwrap();
        assert!(!s.sources["fake-data"].from_cache);
        let _ = fs::remove_dir_all(&root);
    }

    #[test]
    fn up_axes_by_source_and_format() {
        assert_eq!(
            up_axis_of("ufoai-data", "base/0models.pk3!a/b.md2"),
            UpAxis::Z
        );
        assert_eq!(
            up_axis_of("ufoai-data", "base/0models.pk3!a/b.OBJ"),
            UpAxis::Y
        );
        assert_eq!(
            up_axis_of("openarena-data", "x.pk3!models/m.md3"),
            UpAxis::Z
        );
        assert_eq!(up_axis_of("redeclipse-data", "data/a/tris.iqm"), UpAxis::Z);
        assert_eq!(up_axis_of("0ad-data", "public.zip!art/m.pmd"), UpAxis::Y);
        assert_eq!(
            up_axis_of("flightgear-data-models", "Models/a.ac"),
            UpAxis::Y
        );
        assert_eq!(up_axis_of("pybullet", "pybullet_data/a.obj"), UpAxis::Z);
        assert_eq!(up_axis_of("robosuite", "r/meshes/a.stl"), UpAxis::Z);
        assert_eq!(up_axis_of("fake-data", "a.obj"), UpAxis::Y);
        // COLLADA files come out of the reader Y-up, whatever the package.
        assert_eq!(up_axis_of("robosuite", "r/meshes/a.dae"), UpAxis::Y);
        // Every source of docs/data.md has a row.
        for (name, _) in DEBIAN_SOURCES.iter().chain(PYPI_SOURCES.iter()) {
            assert!(UP_AXES.iter().any(|(p, _, _)| p == name), "{name}");
        }
    }

    #[test]
    fn a_z_up_source_is_rotated_to_y_up_and_back() {
        let root = temp_dir("zup");
        let mut pkg = fake_package(&root);
        let opts = BuildOptions::default();
        build(std::slice::from_ref(&pkg), &root.join("y"), None, &opts).unwrap();
        pkg.name = "robosuite".into();
        build(std::slice::from_ref(&pkg), &root.join("z"), None, &opts).unwrap();
        let load = |dir: &str| -> BTreeMap<String, (ManifestEntry, Mesh)> {
            let dir = root.join(dir);
            read_manifest(&dir)
                .unwrap()
                .into_iter()
                .map(|e| {
                    let shard = Shard::from_bytes(&fs::read(dir.join(&e.shard)).unwrap()).unwrap();
                    (e.path.clone(), (e.clone(), shard.mesh(e.index)))
                })
                .collect()
        };
        let (y, z) = (load("y"), load("z"));
        assert_eq!(y.keys().collect::<Vec<_>>(), z.keys().collect::<Vec<_>>());
        for (path, (ey, my)) in &y {
            let (ez, mz) = &z[path];
            assert_eq!((ey.up_axis, ez.up_axis), (UpAxis::Y, UpAxis::Z));
            // The rotation only permutes and negates coordinates, so it is exact.
            let rotated: Vec<Vec3> = my.positions.iter().map(|&p| UpAxis::Z.to_y_up(p)).collect();
            assert_eq!(mz.positions, rotated, "{path}");
            assert_eq!(mz.faces, my.faces, "{path}: same winding");
        }
        // `show --source-frame` undoes the rotation: the source file's box comes back.
        let (e, _) = &z["usr/share/game/bread.obj"];
        let out = root.join("bread.ply");
        show(&root.join("z"), &e.id, &out, true).unwrap();
        let shown = meshflow::io::read_path(&out, &Limits::default()).unwrap();
        let original = meshflow::io::read_path(
            &pkg.files
                .iter()
                .find(|f| f.rel.ends_with("bread.obj"))
                .unwrap()
                .abs,
            &Limits::default(),
        )
        .unwrap();
        let (a, b) = (shown.aabb().unwrap(), original.aabb().unwrap());
        let tol = 1e-4 * b.max_extent();
        assert!((a.min - b.min).abs().max_element() < tol, "{a:?} vs {b:?}");
        assert!((a.max - b.max).abs().max_element() < tol, "{a:?} vs {b:?}");
        let _ = fs::remove_dir_all(&root);
    }

    /// The committed fixture dataset (tests/fixtures/dataset, written by `meshflow data
    /// subset` from a full build).
    fn fixture_dataset() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/dataset")
    }

    #[test]
    fn the_fixture_dataset_rewrites_byte_identically() {
        let dir = fixture_dataset();
        let entries = read_manifest(&dir).unwrap();
        let mut kept: Vec<(ManifestEntry, Mesh)> = entries
            .iter()
            .map(|e| {
                let shard = Shard::from_bytes(&fs::read(dir.join(&e.shard)).unwrap()).unwrap();
                (e.clone(), shard.mesh(e.index))
            })
            .collect();
        let root = temp_dir("fixture-rewrite");
        let texts = |package: &str| dataset_license_texts(&dir, package);
        let (shards, _) = write_dataset(&root, &mut kept, &texts).unwrap();
        let mut names: Vec<String> = shards.iter().map(|s| s.file.clone()).collect();
        names.extend(["manifest.jsonl", "ATTRIBUTION.md", "licenses/index.json"].map(String::from));
        for name in &names {
            assert_eq!(
                fs::read(root.join(name)).unwrap(),
                fs::read(dir.join(name)).unwrap(),
                "{name} differs when the fixture is written again"
            );
        }
        let _ = fs::remove_dir_all(&root);
    }

    #[test]
    fn subset_picks_permissive_small_meshes_across_sources_and_keeps_splits() {
        // The fixture is a dataset too: a subset of it is a smaller, valid one.
        let dir = fixture_dataset();
        let root = temp_dir("subset");
        let opts = SubsetOptions {
            train: 6,
            val: 1,
            test: 1,
            max_vertices: 300,
        };
        let s = subset(&dir, &root, &opts).unwrap();
        let entries = read_manifest(&root).unwrap();
        assert_eq!(entries.len(), s.kept);
        let all = read_manifest(&dir).unwrap();
        for e in &entries {
            let source = all.iter().find(|a| a.id == e.id).unwrap();
            assert_eq!(
                (e.split, &e.path, e.content_hash.as_str()),
                (source.split, &source.path, source.content_hash.as_str())
            );
            assert!(meshflow::data::dataset::is_permissive(&e.license) && e.vertices <= 300);
            let shard = Shard::from_bytes(&fs::read(root.join(&e.shard)).unwrap()).unwrap();
            assert_eq!(
                format!("{:016x}", geometry_hash(&shard.mesh(e.index), HASH_QUANTUM)),
                e.content_hash
            );
        }
        assert!(s.splits["train"] <= 6 && s.splits["val"] <= 1 && s.splits["test"] <= 1);
        assert!(
            s.packages.len() > 1,
            "round-robin over sources: {:?}",
            s.packages
        );
        // Deterministic, and the same again through the subset of the subset's own picks.
        let again = temp_dir("subset-again");
        subset(&dir, &again, &opts).unwrap();
        assert_eq!(read_out(&root), read_out(&again));
        let _ = fs::remove_dir_all(&root);
        let _ = fs::remove_dir_all(&again);
    }

    #[test]
    fn histogram_png_has_fixed_size_and_is_deterministic() {
        let panels = || {
            vec![
                HistPanel {
                    title: "Vertices per mesh (7 meshes, median 40)".into(),
                    values: vec![3, 40, 40, 41, 900, 4096, 5000],
                    max: 4096,
                    color: [40, 90, 200],
                },
                HistPanel {
                    title: "Faces per mesh (median 60)".into(),
                    values: vec![1, 60, 60, 61, 7999, 8000, 0],
                    max: 8000,
                    color: [200, 90, 40],
                },
            ]
        };
        let a = histogram_png(&panels()).unwrap();
        let b = histogram_png(&panels()).unwrap();
        assert_eq!(a, b, "two renders of the same data differ");
        let info = png::Decoder::new(Cursor::new(&a))
            .read_info()
            .unwrap()
            .info()
            .clone();
        assert_eq!((info.width, info.height), (820, 640));
        assert_eq!(info.color_type, png::ColorType::Rgb);
    }

    #[test]
    fn stats_and_show_read_the_build() {
        let root = temp_dir("stats");
        let pkg = fake_package(&root);
        let out = root.join("out");
        build(&[pkg], &out, None, &BuildOptions::default()).unwrap();
        stats(&out, None).unwrap();
        let csv = fs::read_to_string(out.join("stats.csv")).unwrap();
        let entries = read_manifest(&out).unwrap();
        assert_eq!(csv.lines().count(), entries.len() + 1);
        assert!(
            fs::read(out.join("stats.png"))
                .unwrap()
                .starts_with(b"\x89PNG")
        );
        let e = &entries[0];
        let glb = root.join("one.obj");
        show(&out, &e.id, &glb, true).unwrap();
        let m = meshflow::io::read_path(&glb, &Limits::default()).unwrap();
        assert_eq!(m.faces.len(), e.faces);
        assert!(show(&out, "nope", &glb, false).is_err());
        let _ = fs::remove_dir_all(&root);
    }

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
