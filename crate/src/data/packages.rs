//! The build's inputs: source packages as lists of files
//! ([`PackageInput`](crate::data::packages::PackageInput)), and the allowed packages found in
//! the cache ([`discover`](crate::data::packages::discover)), each `.deb` unpacked once with
//! `dpkg-deb`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use super::error::DataError;
use super::fetch::{find_wheel, run_tool};
use super::files::{create_dir_all, file_name, io_error, list_dir, remove_dir_all, with_suffix};
use super::progress::DataEvent;
use super::sources::{DEBIAN_SOURCES, PYPI_SOURCES};

/// Marks an unpacked folder as complete (written last, so an interrupted unpack is redone).
const UNPACKED_MARKER: &str = ".meshflow-unpacked";

/// One file of a package: its path inside the package (`/`-separated) and on disk. An empty
/// `rel` means the file *is* the package (a wheel): its members are named without a prefix.
#[derive(Clone, Debug)]
pub struct InputFile {
    pub rel: String,
    pub abs: PathBuf,
}

/// A source package as [`crate::data::build::build`] takes it.
#[derive(Clone, Debug)]
pub struct PackageInput {
    pub name: String,
    pub version: String,
    pub license: String,
    pub files: Vec<InputFile>,
}

impl PackageInput {
    /// All files under `root`, named relative to it, sorted.
    pub fn from_dir(
        name: &str,
        version: &str,
        license: &str,
        root: &Path,
    ) -> Result<Self, DataError> {
        let mut files = Vec::new();
        let mut stack = vec![root.to_path_buf()];
        while let Some(dir) = stack.pop() {
            let list = |e| io_error("list", &dir, e);
            for e in fs::read_dir(&dir).map_err(list)? {
                let e = e.map_err(list)?;
                let ty = e.file_type().map_err(list)?;
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

/// `name_version_arch.deb` -> (name, version), `%3a` read back as `:`.
pub(crate) fn parse_deb_name(file: &str) -> Option<(String, String)> {
    let stem = file.strip_suffix(".deb")?;
    let mut parts = stem.split('_');
    let name = parts.next()?;
    let version = parts.next()?.replace("%3a", ":");
    Some((name.to_string(), version))
}

/// Unpacks a .deb into `dir`: into `dir.partial` first, renamed when complete, so a
/// half-unpacked package is never taken for a whole one.
fn unpack_deb(deb: &Path, dir: &Path) -> Result<(), DataError> {
    let tmp = with_suffix(dir, ".partial");
    if tmp.exists() {
        remove_dir_all(&tmp)?;
    }
    create_dir_all(&tmp)?;
    run_tool(
        Command::new("dpkg-deb").arg("-x").arg(deb).arg(&tmp),
        &format!("unpack {}", deb.display()),
    )?;
    let marker = tmp.join(UNPACKED_MARKER);
    fs::write(&marker, file_name(deb)).map_err(|e| io_error("write", &marker, e))?;
    if dir.exists() {
        remove_dir_all(dir)?;
    }
    fs::rename(&tmp, dir).map_err(|e| io_error("create", dir, e))
}

/// The allowed packages present in `cache` (`debs/*.deb`, newest version of each, unpacked
/// into `unpacked/<name>_<version>`; `wheels/*.whl`, read in place), and the names of those
/// absent. Unpacking is reported to `observer`.
pub fn discover(
    cache: &Path,
    observer: &mut dyn FnMut(DataEvent<'_>),
) -> Result<(Vec<PackageInput>, Vec<String>), DataError> {
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
        if !dir.join(UNPACKED_MARKER).exists() {
            let t = Instant::now();
            observer(DataEvent::Unpacking { deb: &deb });
            unpack_deb(&deb, &dir)?;
            observer(DataEvent::Unpacked {
                deb: &deb,
                seconds: t.elapsed().as_secs_f64(),
            });
        }
        let mut pkg = PackageInput::from_dir(name, &version, license, &dir)?;
        pkg.files.retain(|f| f.rel != UNPACKED_MARKER);
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
