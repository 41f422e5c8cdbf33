//! Downloading the allowed sources into the cache: the Debian packages with `apt-get
//! download` (checked against apt's SHA256) and the PyPI wheels with `pip download`. Files
//! already present and verified are kept, so a second fetch downloads nothing.

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Instant;

use super::error::DataError;
use super::files::{create_dir_all, file_name, io_error, list_dir};
use super::progress::DataEvent;
use super::sources::{DEBIAN_SOURCES, PYPI_SOURCES};

/// Runs an external tool (`apt-get`, `pip`, `dpkg-deb`) to `what`; a tool that is missing,
/// cannot start or fails is an error saying which and why (for a failure, the last lines of
/// its stderr, where the tools put the reason).
pub(crate) fn run_tool(cmd: &mut Command, what: &str) -> Result<Output, DataError> {
    let program = cmd.get_program().to_string_lossy().into_owned();
    let out = cmd.output().map_err(|error| {
        if error.kind() == std::io::ErrorKind::NotFound {
            DataError::ToolMissing {
                install: if program == "pip" {
                    "python3-pip"
                } else {
                    "apt dpkg"
                },
                program: program.clone(),
                what: what.to_string(),
            }
        } else {
            DataError::ToolSpawn {
                program: program.clone(),
                error,
            }
        }
    })?;
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let last: Vec<&str> = stderr.lines().rev().take(3).collect();
        let mut last: Vec<&str> = last.into_iter().rev().collect();
        last.retain(|l| !l.trim().is_empty());
        return Err(DataError::ToolFailed {
            program,
            what: what.to_string(),
            status: out.status,
            stderr_tail: last.join(" | "),
        });
    }
    Ok(out)
}

/// `apt-cache show`'s fields for the candidate version.
struct AptInfo {
    version: String,
    arch: String,
    sha256: String,
}

fn apt_info(package: &str) -> Result<AptInfo, DataError> {
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
        _ => Err(DataError::NotInApt {
            package: package.to_string(),
        }),
    }
}

/// The SHA256 of a file, in lowercase hex; read in 1 MiB pieces, since packages run to
/// gigabytes.
fn sha256_file(path: &Path) -> Result<String, DataError> {
    use sha2::{Digest, Sha256};
    let mut f = fs::File::open(path).map_err(|e| io_error("open", path, e))?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    loop {
        let n = f.read(&mut buf).map_err(|e| io_error("read", path, e))?;
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
pub(crate) fn wheel_stem(project: &str) -> String {
    project.to_ascii_lowercase().replace(['-', '.'], "_")
}

/// The newest wheel of `project` in `dir` (by file name), if any.
pub(crate) fn find_wheel(dir: &Path, project: &str) -> Result<Option<PathBuf>, DataError> {
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

/// Downloads the allowed Debian packages ([`DEBIAN_SOURCES`], into `cache/debs`) and PyPI
/// wheels ([`PYPI_SOURCES`], into `cache/wheels`); a package already there with apt's SHA256,
/// or a wheel already there, is kept. Stops at the first failure. Reports each step to
/// `observer`.
pub fn fetch(cache: &Path, observer: &mut dyn FnMut(DataEvent<'_>)) -> Result<(), DataError> {
    let debs = cache.join("debs");
    let wheels = cache.join("wheels");
    create_dir_all(&debs)?;
    create_dir_all(&wheels)?;
    for (package, _) in DEBIAN_SOURCES {
        let info = apt_info(package)?;
        let version = info.version.as_str();
        let file = debs.join(deb_file_name(package, version, &info.arch));
        if file.exists() && sha256_file(&file)? == info.sha256 {
            observer(DataEvent::DebPresent { package, version });
            continue;
        }
        let t = Instant::now();
        observer(DataEvent::DebDownloading { package, version });
        run_tool(
            Command::new("apt-get")
                .args(["download", package])
                .current_dir(&debs),
            &format!("download {package} (network?)"),
        )?;
        let got = sha256_file(&file).map_err(|error| DataError::DownloadMissing {
            file: file.clone(),
            error: Box::new(error),
        })?;
        if got != info.sha256 {
            return Err(DataError::Checksum {
                file,
                got,
                expected: info.sha256,
            });
        }
        let bytes = fs::metadata(&file)
            .map_err(|e| io_error("read", &file, e))?
            .len();
        observer(DataEvent::DebDownloaded {
            package,
            version,
            bytes,
            seconds: t.elapsed().as_secs_f64(),
        });
    }
    for (project, _) in PYPI_SOURCES {
        if let Some(wheel) = find_wheel(&wheels, project)? {
            observer(DataEvent::WheelPresent {
                project,
                wheel: &wheel,
            });
            continue;
        }
        observer(DataEvent::WheelDownloading { project });
        run_tool(
            Command::new("pip")
                .args(["download", "--no-deps", project, "-d"])
                .arg(&wheels),
            &format!("download {project} (network?)"),
        )?;
        match find_wheel(&wheels, project)? {
            Some(wheel) => observer(DataEvent::WheelDownloaded {
                project,
                wheel: &wheel,
            }),
            None => {
                return Err(DataError::NoWheel {
                    project: project.to_string(),
                    dir: wheels,
                });
            }
        }
    }
    Ok(())
}
