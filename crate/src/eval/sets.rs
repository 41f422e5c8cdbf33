//! The meshes an evaluation runs on: a split of a shard build, or every mesh file of a folder
//! prepared like the data build. Meshes the model cannot take (more vertices than its N) are
//! left out and said so, so a reader sees what the figures leave out.

use std::path::{Path, PathBuf};

use crate::Mesh;
use crate::data::dataset::Split;
use crate::data::shards::{ShardsError, load_split};
use crate::pipeline::reconstruct::prepare;

/// Named meshes to evaluate, in the model frame.
pub type NamedMeshes = Vec<(String, Mesh)>;

/// What an evaluation runs on.
pub struct EvalSet {
    pub meshes: NamedMeshes,
    /// Meshes left out, and why (one line each, or one line for a whole group).
    pub skipped: Vec<String>,
    /// Where the meshes came from, for the report.
    pub source: String,
}

/// Why there is nothing to evaluate.
#[derive(Debug, thiserror::Error)]
pub enum EvalSetError {
    #[error("--split {0}: expected train, val or test")]
    UnknownSplit(String),
    #[error("cannot list {path}: {source}")]
    List {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Shards(#[from] ShardsError),
    #[error("no mesh to evaluate")]
    Empty,
}

impl EvalSetError {
    /// Whether the caller asked for something that cannot be (a bad split name, an empty
    /// selection), rather than something failing to read.
    pub fn is_bad_input(&self) -> bool {
        matches!(self, Self::UnknownSplit(_) | Self::Empty)
    }
}

/// The split named `name` (`train`, `val` or `test`).
pub fn parse_split(name: &str) -> Result<Split, EvalSetError> {
    Split::ALL
        .into_iter()
        .find(|s| s.name() == name)
        .ok_or_else(|| EvalSetError::UnknownSplit(name.into()))
}

/// Every file of `dir` (sorted by name) read and prepared like the data build; files that fail
/// or have more than `max_vertices` vertices are listed as skipped.
pub fn folder_meshes(
    dir: &Path,
    max_vertices: usize,
) -> Result<(NamedMeshes, Vec<String>), EvalSetError> {
    let list = |source| EvalSetError::List {
        path: dir.to_path_buf(),
        source,
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(list)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    let (mut meshes, mut skipped) = (Vec::new(), Vec::new());
    for f in files {
        let name = f.display().to_string();
        let read = crate::io::read_path(&f, &crate::io::Limits::default());
        match read
            .map_err(|e| e.to_string())
            .and_then(|m| prepare(&m).map_err(|e| e.to_string()))
        {
            Ok((m, _)) if m.positions.len() <= max_vertices => meshes.push((name, m)),
            Ok((m, _)) => skipped.push(format!(
                "{name}: {} vertices > {max_vertices}",
                m.positions.len()
            )),
            Err(e) => skipped.push(format!("{name}: {e}")),
        }
    }
    Ok((meshes, skipped))
}

/// The meshes of `split` in the shard build `shards` with at most `max_vertices` vertices,
/// named `split#index` by their position in the split (so names stay stable when the limit
/// changes).
pub fn split_meshes(
    shards: &Path,
    split: Split,
    max_vertices: usize,
) -> Result<EvalSet, EvalSetError> {
    let all = load_split(shards, split)?;
    let total = all.len();
    let meshes: NamedMeshes = all
        .into_iter()
        .enumerate()
        .filter(|(_, m)| m.positions.len() <= max_vertices)
        .map(|(i, m)| (format!("{}#{i}", split.name()), m))
        .collect();
    let skipped = vec![format!(
        "{} of {total} meshes have more than {max_vertices} vertices",
        total - meshes.len(),
    )];
    let source = format!("{} split of {}", split.name(), shards.display());
    Ok(EvalSet {
        meshes,
        skipped,
        source,
    })
}

/// The meshes an evaluation runs on: every mesh file of `input` when given, else the split
/// named `split` of the shard build `shards`; at most `max_vertices` vertices each and at most
/// `limit` meshes (0 = all). No mesh at all is an error.
pub fn eval_set(
    input: Option<&Path>,
    split: &str,
    shards: &Path,
    max_vertices: usize,
    limit: usize,
) -> Result<EvalSet, EvalSetError> {
    let mut set = match input {
        Some(dir) => {
            let (meshes, skipped) = folder_meshes(dir, max_vertices)?;
            EvalSet {
                meshes,
                skipped,
                source: dir.display().to_string(),
            }
        }
        None => split_meshes(shards, parse_split(split)?, max_vertices)?,
    };
    if limit > 0 {
        set.meshes.truncate(limit);
    }
    if set.meshes.is_empty() {
        return Err(EvalSetError::Empty);
    }
    Ok(set)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixtures() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures")
    }

    #[test]
    fn a_split_keeps_the_meshes_that_fit_and_counts_the_rest() {
        let shards = fixtures().join("dataset");
        let all = eval_set(None, "train", &shards, usize::MAX, 0).unwrap();
        let small = eval_set(None, "train", &shards, 100, 0).unwrap();
        assert!(small.meshes.len() < all.meshes.len());
        assert!(small.meshes.iter().all(|(_, m)| m.positions.len() <= 100));
        let left_out = all.meshes.len() - small.meshes.len();
        assert_eq!(
            small.skipped,
            vec![format!(
                "{left_out} of {} meshes have more than 100 vertices",
                all.meshes.len()
            )]
        );
        // Names are positions in the split, whatever was left out before them.
        let names: Vec<&str> = all.meshes.iter().map(|(n, _)| n.as_str()).collect();
        assert!(
            small
                .meshes
                .iter()
                .all(|(n, _)| names.contains(&n.as_str()))
        );
        assert_eq!(
            eval_set(None, "train", &shards, usize::MAX, 2)
                .unwrap()
                .meshes
                .len(),
            2
        );
    }

    #[test]
    fn bad_selections_are_typed_errors() {
        let shards = fixtures().join("dataset");
        let e = eval_set(None, "training", &shards, 512, 0).err().unwrap();
        assert!(matches!(e, EvalSetError::UnknownSplit(_)) && e.is_bad_input());
        let e = eval_set(None, "train", &shards, 2, 0).err().unwrap();
        assert!(matches!(e, EvalSetError::Empty) && e.is_bad_input());
        let e = eval_set(None, "train", &fixtures().join("no such build"), 512, 0)
            .err()
            .unwrap();
        assert!(matches!(e, EvalSetError::Shards(_)) && !e.is_bad_input());
    }

    #[test]
    fn a_folder_lists_what_it_cannot_use() {
        let dir = std::env::temp_dir().join(format!("meshflow-eval-set-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::copy(
            fixtures().join("meshes/stone_lantern.obj"),
            dir.join("lantern.obj"),
        )
        .unwrap();
        std::fs::write(dir.join("broken.obj"), b"v 0 0\nf 1 2 3\n").unwrap();
        let set = eval_set(Some(&dir), "ignored", Path::new("unused"), 4096, 0).unwrap();
        assert_eq!(set.meshes.len(), 1);
        assert_eq!(set.skipped.len(), 1);
        assert!(set.skipped[0].contains("broken.obj"), "{:?}", set.skipped);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
