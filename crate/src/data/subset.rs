//! A small dataset (same format) picked from a build: permissively licensed, small meshes,
//! round-robin over sources, keeping their splits; for tests and CI fixtures
//! (`tests/fixtures/dataset` was written by it).

use std::collections::{BTreeMap, BTreeSet, HashSet, VecDeque};
use std::fmt;
use std::path::Path;

use serde::Serialize;

use crate::data::dataset::{ManifestEntry, Split, is_permissive, split_key};
use crate::data::shards::{load_meshes, read_manifest};

use super::attribution::dataset_license_texts;
use super::error::DataError;
use super::files::{to_json_pretty, write_atomic};
use super::write::{ShardSummary, write_dataset};

/// What [`subset`] selects.
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

impl SubsetSummary {
    /// What `meshflow data subset` prints: the counts, per package, and the shards in `out`.
    pub fn report<'a>(&'a self, out: &'a Path) -> impl fmt::Display + 'a {
        fmt::from_fn(move |f| {
            let g = |k: &str| self.splits.get(k).copied().unwrap_or(0);
            let (train, val, test) = (g("train"), g("val"), g("test"));
            let (kept, packages, out) = (self.kept, self.packages.len(), out.display());
            write!(f, "{kept} meshes ({train} train, {val} val, {test} test) ")?;
            writeln!(f, "from {packages} packages -> {out}")?;
            for (p, n) in &self.packages {
                writeln!(f, "  {p:<24}{n:>4}")?;
            }
            let bytes: u64 = self.shards.iter().map(|x| x.bytes).sum();
            write!(f, "{} shards, {bytes} bytes", self.shards.len())
        })
    }
}

/// Picks the subset's entries: for each split, the permissively licensed
/// ([`is_permissive`]) meshes of at most `max_vertices` vertices from the packages in
/// `with_license_text` (a mesh cannot be redistributed without its license text), taken
/// round-robin over packages so the sources vary (in name order, starting a third of the way
/// further for each split so validation and test do not always start at the same package),
/// and inside a package in id order (ids are hashes, so effectively a fixed random order),
/// objects not yet taken ([`split_key`]) first. Deterministic: the same manifest gives the
/// same subset.
fn select_subset(
    entries: &[ManifestEntry],
    with_license_text: &BTreeSet<String>,
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
        let mut queues: Vec<VecDeque<&ManifestEntry>> = packages
            .iter()
            .map(|package| {
                let mut q: Vec<&ManifestEntry> = entries
                    .iter()
                    .filter(|e| {
                        e.split == split
                            && &&e.package == package
                            && is_permissive(&e.license)
                            && e.vertices <= opts.max_vertices
                    })
                    .collect();
                q.sort_by(|a, b| a.id.cmp(&b.id));
                // One entry of each object first, then the rest.
                let mut seen = HashSet::new();
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

/// Writes a small dataset to `out` from the built one in `dir`: for each split, permissively
/// licensed meshes of at most `max_vertices` vertices from packages that ship a license text,
/// round-robin over packages, deterministically. Written: its shards, manifest (entries
/// unchanged except `shard` and `index`), attribution and the used packages' license files,
/// all as the build writes them, plus `subset.json`.
pub fn subset(dir: &Path, out: &Path, opts: &SubsetOptions) -> Result<SubsetSummary, DataError> {
    let entries = read_manifest(dir)?;
    let packages: BTreeSet<&String> = entries.iter().map(|e| &e.package).collect();
    let mut with_license_text = BTreeSet::new();
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
    // Provenance only: a build.json that is missing or unreadable leaves it unknown.
    let source_pipeline_version = std::fs::read(dir.join("build.json"))
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
        to_json_pretty(&summary, "subset.json")?.as_bytes(),
    )?;
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    use crate::data::dataset::{Shard, geometry_hash};
    use crate::data::process::HASH_QUANTUM;
    use crate::data::test_support::{fixture_dataset, read_out, temp_dir};

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
        let text = s.report(Path::new("sub")).to_string();
        let first = format!("{} meshes (6 train, 1 val, 1 test) from ", s.kept);
        assert!(
            text.starts_with(&first) && text.contains(" packages -> sub\n  "),
            "{text}"
        );
        let entries = read_manifest(&root).unwrap();
        assert_eq!(entries.len(), s.kept);
        let all = read_manifest(&dir).unwrap();
        for e in &entries {
            let source = all.iter().find(|a| a.id == e.id).unwrap();
            assert_eq!(
                (e.split, &e.path, e.content_hash.as_str()),
                (source.split, &source.path, source.content_hash.as_str())
            );
            assert!(is_permissive(&e.license) && e.vertices <= 300);
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
}
