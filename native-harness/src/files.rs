//! Files as the commands read and write them: every error names the path.

use std::path::Path;

use anyhow::{Context, Result};
use meshflow::Mesh;
use meshflow::io::{Limits, read_path, write_atomic, write_path};
use serde::Serialize;

use crate::progress::step;

/// Reads a mesh or point cloud, under a spinner (a large file can take seconds).
pub fn read_mesh(path: &Path) -> Result<Mesh> {
    step(&format!("reading {}", path.display()), || {
        read_path(path, &Limits::default())
    })
    .with_context(|| format!("cannot read {}", path.display()))
}

/// Writes a mesh in the format named by the extension of `path`.
pub fn write_mesh(mesh: &Mesh, path: &Path) -> Result<()> {
    write_path(mesh, path).with_context(|| format!("cannot write {}", path.display()))
}

/// Creates the folder `dir` and its parents.
pub fn create_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))
}

/// Prints `value` as pretty JSON.
pub fn print_json(value: &impl Serialize) -> Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}

/// Writes `value` to `path` as pretty JSON, whole or not at all (a script reads it later),
/// creating the folder it goes in.
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        create_dir(dir)?;
    }
    let json = serde_json::to_string_pretty(value)? + "\n";
    write_atomic(path, json.as_bytes()).with_context(|| format!("cannot write {}", path.display()))
}
