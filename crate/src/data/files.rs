//! File-system helpers of the data build: each I/O error comes back as a [`DataError::Io`]
//! naming its path, and names inside packages are read the same way everywhere.

use std::fs;
use std::path::{Path, PathBuf};

use super::error::DataError;

/// `error` of `action` ("open", "read", ...) on `path`, as a [`DataError`].
pub(crate) fn io_error(action: &'static str, path: &Path, error: std::io::Error) -> DataError {
    DataError::Io {
        action,
        path: path.to_path_buf(),
        error,
    }
}

/// The entries of `dir`, sorted; none when `dir` does not exist.
pub(crate) fn list_dir(dir: &Path) -> Result<Vec<PathBuf>, DataError> {
    if !dir.exists() {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for e in fs::read_dir(dir).map_err(|e| io_error("list", dir, e))? {
        out.push(e.map_err(|e| io_error("list", dir, e))?.path());
    }
    out.sort();
    Ok(out)
}

/// The last component of `p`, lossily as UTF-8 (empty when there is none).
pub(crate) fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Creates `dir` and its parents.
pub(crate) fn create_dir_all(dir: &Path) -> Result<(), DataError> {
    fs::create_dir_all(dir).map_err(|e| io_error("create", dir, e))
}

/// The bytes of `path`.
pub(crate) fn read(path: &Path) -> Result<Vec<u8>, DataError> {
    fs::read(path).map_err(|e| io_error("read", path, e))
}

/// Removes the file `path`.
pub(crate) fn remove_file(path: &Path) -> Result<(), DataError> {
    fs::remove_file(path).map_err(|e| io_error("remove", path, e))
}

/// Removes the folder `path` and everything in it.
pub(crate) fn remove_dir_all(path: &Path) -> Result<(), DataError> {
    fs::remove_dir_all(path).map_err(|e| io_error("remove", path, e))
}

/// Writes `bytes` to `path` through a temporary file ([`crate::io::write_atomic`]), so an
/// interrupted build never leaves a half-written shard or manifest.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), DataError> {
    crate::io::write_atomic(path, bytes).map_err(|e| io_error("write", path, e))
}

/// `value` as pretty JSON (`what` names it in the error, which only a bug can cause).
pub(crate) fn to_json_pretty<T: serde::Serialize>(
    value: &T,
    what: &'static str,
) -> Result<String, DataError> {
    serde_json::to_string_pretty(value).map_err(|error| DataError::Json { what, error })
}

/// `path` with `suffix` appended to its last component (`with_extension` would replace
/// whatever follows the last dot, e.g. of a version number).
pub(crate) fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let mut s = path.as_os_str().to_os_string();
    s.push(suffix);
    PathBuf::from(s)
}

/// The lowercase extension of the last component of a name inside a package, archive members
/// (`a.zip!b/c.OBJ`) included; empty when there is none.
pub(crate) fn extension(name: &str) -> String {
    let file = name.rsplit(['/', '!']).next().unwrap_or(name);
    match file.rfind('.') {
        Some(i) => file[i + 1..].to_ascii_lowercase(),
        None => String::new(),
    }
}
