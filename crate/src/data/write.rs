//! Writing a dataset: kept meshes into `{split}-{k:05}.safetensors` shards, `manifest.jsonl`
//! and the attribution. The build and `subset` both write through `write_dataset`, so a
//! dataset written twice from the same entries and meshes is byte-identical.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use crate::Mesh;
use crate::data::dataset::{ManifestEntry, ShardWriter, Split};

use super::attribution::{LicenseTexts, write_attribution};
use super::error::DataError;
use super::files::{create_dir_all, file_name, list_dir, remove_file, write_atomic};

/// Shard size limits.
const SHARD_MAX_MESHES: usize = 4000;
const SHARD_MAX_BYTES: u64 = 256 << 20;

/// One shard written, as listed in `build.json` and `subset.json`.
#[derive(Debug, Serialize)]
pub struct ShardSummary {
    pub file: String,
    pub meshes: usize,
    pub bytes: u64,
}

/// Writes kept meshes as a dataset in `out`: `{split}-{k:05}.safetensors` shards (meshes
/// sorted by split and id, a new shard when one reaches [`SHARD_MAX_MESHES`] or
/// [`SHARD_MAX_BYTES`]; stale shards of an earlier run removed), `manifest.jsonl` (sorted by
/// id, `shard` and `index` filled in here) and the attribution ([`write_attribution`], with
/// `license_texts` giving a package's license files). Returns the shards and the mesh count
/// of each split.
pub(crate) fn write_dataset(
    out: &Path,
    kept: &mut [(ManifestEntry, Mesh)],
    license_texts: &LicenseTexts,
) -> Result<(Vec<ShardSummary>, BTreeMap<String, u64>), DataError> {
    create_dir_all(out)?;
    kept.sort_by(|a, b| (a.0.split, &a.0.id).cmp(&(b.0.split, &b.0.id)));
    // Stale shards of an earlier build would be mistaken for this one's.
    for p in list_dir(out)? {
        let n = file_name(&p);
        if n.ends_with(".safetensors") && Split::ALL.iter().any(|s| n.starts_with(s.name())) {
            remove_file(&p)?;
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
         -> Result<(), DataError> {
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
            // The bytes the mesh adds to the shard's tensors (positions, faces, two offsets).
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
        serde_json::to_writer(&mut manifest, e).map_err(|error| DataError::Json {
            what: "a manifest entry",
            error,
        })?;
        manifest.push(b'\n');
    }
    write_atomic(&out.join("manifest.jsonl"), &manifest)?;
    write_attribution(out, entries.into_iter(), license_texts)?;
    Ok((shards, splits))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    use crate::data::attribution::dataset_license_texts;
    use crate::data::dataset::Shard;
    use crate::data::shards::read_manifest;
    use crate::data::test_support::{fixture_dataset, temp_dir};

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
}
