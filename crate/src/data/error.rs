//! Why a step of the data build (fetch, unpack, build, subset, stats, show) failed.

use std::path::PathBuf;
use std::process::ExitStatus;

use crate::data::shards::ShardsError;
use crate::io::WriteError;

/// The data build's error. Each variant names the file, package or tool involved. As in
/// [`crate::io::ReadError`], causes are part of the message rather than `source`, so an error
/// chain prints them once; the exception is [`DataError::Write`], whose [`WriteError`] stays
/// reachable as the source (callers tell a wrong output extension from a failed write by it).
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// A file-system operation failed; `action` is the verb ("open", "read", "list",
    /// "create", "remove", "write").
    #[error("cannot {action} {}: {error}", path.display())]
    Io {
        action: &'static str,
        path: PathBuf,
        error: std::io::Error,
    },
    #[error(
        "`{program}` is not installed; `meshflow data` needs it to {what} \
         (on Debian or Ubuntu: apt-get install {install})"
    )]
    ToolMissing {
        program: String,
        /// What it was run for ("download 0ad-data (network?)").
        what: String,
        /// The Debian packages that provide it.
        install: &'static str,
    },
    #[error("cannot run `{program}`: {error}")]
    ToolSpawn {
        program: String,
        error: std::io::Error,
    },
    /// The tool ran and failed; `stderr_tail` is the last non-empty lines of its stderr,
    /// joined with ` | `.
    #[error("`{program}` failed to {what} ({status}): {stderr_tail}")]
    ToolFailed {
        program: String,
        what: String,
        status: ExitStatus,
        stderr_tail: String,
    },
    #[error("apt-cache knows no downloadable {package} (run `apt-get update`?)")]
    NotInApt { package: String },
    #[error("apt-get download did not leave {}: {error}", file.display())]
    DownloadMissing {
        file: PathBuf,
        error: Box<DataError>,
    },
    #[error("{} has SHA256 {got}, apt-cache says {expected}", file.display())]
    Checksum {
        file: PathBuf,
        got: String,
        expected: String,
    },
    #[error("pip download {project} left no wheel in {}", dir.display())]
    NoWheel { project: String, dir: PathBuf },
    /// A wheel whose license files could not be read (archives of the meshes themselves that
    /// cannot be read are counted as skipped, not errors).
    #[error("cannot read {} as a zip archive: {error}", path.display())]
    Zip {
        path: PathBuf,
        error: zip::result::ZipError,
    },
    #[error(
        "cannot read {} (built before license indexes; rebuild): {error}",
        path.display()
    )]
    NoLicenseIndex {
        path: PathBuf,
        error: std::io::Error,
    },
    #[error("{} is not a license index: {error}", path.display())]
    BadLicenseIndex {
        path: PathBuf,
        error: serde_json::Error,
    },
    /// The same package name appears twice among a build's inputs.
    #[error("package {0} is listed twice")]
    DuplicatePackage(String),
    /// The cache holds none of the allowed packages.
    #[error("no source packages in {} (run `meshflow data fetch` first)", cache.display())]
    NoPackages { cache: PathBuf },
    /// `show` was given an id the manifest does not have.
    #[error("no mesh with id {id} in {}", dir.display())]
    NoSuchMesh { id: String, dir: PathBuf },
    /// Reading the shard build (manifest or shards) failed.
    #[error(transparent)]
    Shards(#[from] ShardsError),
    #[error("cannot write {}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: WriteError,
    },
    #[error("cannot encode {} as PNG: {error}", path.display())]
    Png {
        path: PathBuf,
        error: png::EncodingError,
    },
    #[error("cannot serialise {what}: {error}")]
    Json {
        what: &'static str,
        error: serde_json::Error,
    },
}
