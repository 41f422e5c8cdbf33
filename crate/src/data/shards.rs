//! Reading a shard build from disk: its `manifest.jsonl` and the meshes of the
//! `{split}-{k:05}.safetensors` shards it names ([`crate::data::dataset`] has the formats and parses
//! shard bytes; this is the one place that finds and reads the files). Training, evaluation
//! and `meshflow data` all read builds through it.

use std::borrow::Borrow;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::Mesh;
use crate::data::dataset::{DatasetError, ManifestEntry, Shard, Split};

/// Why a shard build could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ShardsError {
    #[error("cannot read {path} ({source}){hint}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
        /// What to do about it, where there is something (a build not made yet).
        hint: &'static str,
    },
    #[error("{path} line {line}: not a manifest entry ({message})")]
    Manifest {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{path} is corrupt: {source}")]
    Corrupt { path: PathBuf, source: DatasetError },
    #[error("{shard} has no mesh {index} (manifest and shards disagree)")]
    MissingMesh { shard: String, index: usize },
}

/// The entries of `dir/manifest.jsonl`, in file order.
pub fn read_manifest(dir: &Path) -> Result<Vec<ManifestEntry>, ShardsError> {
    let path = dir.join("manifest.jsonl");
    let text = std::fs::read_to_string(&path).map_err(|source| ShardsError::Read {
        path: path.clone(),
        source,
        hint: "; run `meshflow data build` first",
    })?;
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            serde_json::from_str(l).map_err(|e| ShardsError::Manifest {
                path: path.clone(),
                line: i + 1,
                message: e.to_string(),
            })
        })
        .collect()
}

/// The meshes of manifest `entries` of the build in `dir`, each with its entry, in the
/// entries' order; every shard is read and checked once.
pub fn load_meshes<E: Borrow<ManifestEntry>>(
    dir: &Path,
    entries: impl IntoIterator<Item = E>,
) -> Result<Vec<(E, Mesh)>, ShardsError> {
    let mut shards: HashMap<String, Shard> = HashMap::new();
    let mut out = Vec::new();
    for e in entries {
        let entry = e.borrow();
        if !shards.contains_key(&entry.shard) {
            let path = dir.join(&entry.shard);
            let bytes = std::fs::read(&path).map_err(|source| ShardsError::Read {
                path: path.clone(),
                source,
                hint: "",
            })?;
            let shard = Shard::from_bytes(&bytes)
                .map_err(|source| ShardsError::Corrupt { path, source })?;
            shards.insert(entry.shard.clone(), shard);
        }
        let Some(mesh) = shards[&entry.shard].get(entry.index) else {
            return Err(ShardsError::MissingMesh {
                shard: entry.shard.clone(),
                index: entry.index,
            });
        };
        out.push((e, mesh));
    }
    Ok(out)
}

/// The meshes of one split of the build in `dir`, in manifest order.
pub fn load_split(dir: &Path, split: Split) -> Result<Vec<Mesh>, ShardsError> {
    let entries = read_manifest(dir)?;
    let wanted = entries.iter().filter(|e| e.split == split);
    Ok(load_meshes(dir, wanted)?
        .into_iter()
        .map(|(_, m)| m)
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/dataset")
    }

    #[test]
    fn the_fixture_build_reads_split_by_split() {
        let entries = read_manifest(&fixture()).unwrap();
        let meshes = load_meshes(&fixture(), &entries).unwrap();
        assert_eq!(meshes.len(), entries.len());
        for (entry, mesh) in &meshes {
            assert_eq!(
                (mesh.positions.len(), mesh.faces.len()),
                (entry.vertices, entry.faces)
            );
        }
        let per_split: usize = Split::ALL
            .iter()
            .map(|&s| load_split(&fixture(), s).unwrap().len())
            .sum();
        assert_eq!(per_split, entries.len());
    }

    #[test]
    fn a_missing_build_or_a_wrong_index_is_an_error_that_says_so() {
        let missing = read_manifest(Path::new("/nonexistent/build")).unwrap_err();
        assert!(
            missing.to_string().contains("meshflow data build"),
            "{missing}"
        );
        let mut entry = read_manifest(&fixture()).unwrap().remove(0);
        entry.index = 1 << 20;
        let wrong = load_meshes(&fixture(), [entry]).unwrap_err();
        assert!(matches!(wrong, ShardsError::MissingMesh { .. }), "{wrong}");
    }
}
