//! The committed fixture dataset (`tests/fixtures/dataset`, written by `meshflow data subset`
//! from a full build): real training meshes in the shard format, for tests that must run where
//! the source packages are not (CI). Checks that it loads, that the manifest describes the
//! shards exactly, that it may be redistributed (permissive licenses, license texts present),
//! that writing it again gives the same bytes, and that augmentation runs on every mesh read
//! through the shard reader.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use meshflow::data::augment::{AugmentOptions, augment};
use meshflow::data::dataset::{
    FilterOptions, ManifestEntry, Shard, ShardWriter, Split, filter, geometry_hash, is_permissive,
    split_key, split_of,
};
use meshflow::data::shards::{load_meshes, read_manifest};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/dataset")
}

fn manifest() -> Vec<ManifestEntry> {
    read_manifest(&dir()).unwrap()
}

fn shards() -> BTreeMap<String, Vec<u8>> {
    fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "safetensors"))
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                fs::read(&p).unwrap(),
            )
        })
        .collect()
}

#[test]
fn manifest_matches_the_shards() {
    let entries = manifest();
    let shards = shards();
    assert!(
        (30..=60).contains(&entries.len()),
        "{} meshes",
        entries.len()
    );
    assert!(
        entries.windows(2).all(|w| w[0].id < w[1].id),
        "sorted by id"
    );
    for split in Split::ALL {
        assert!(
            entries.iter().any(|e| e.split == split),
            "no {split} meshes"
        );
    }
    let parsed: BTreeMap<&String, Shard> = shards
        .iter()
        .map(|(n, b)| (n, Shard::from_bytes(b).unwrap()))
        .collect();
    let mut used = 0;
    for e in &entries {
        let shard = &parsed[&e.shard];
        assert!(
            e.shard.starts_with(e.split.name()),
            "{} in {}",
            e.id,
            e.shard
        );
        let m = shard.mesh(e.index);
        assert_eq!((m.positions.len(), m.faces.len()), (e.vertices, e.faces));
        assert_eq!(
            format!("{:016x}", geometry_hash(&m, 1e-4)),
            e.content_hash,
            "{}",
            e.id
        );
        // The model frame: longest side spans [-1, 1], centred.
        let b = m.aabb().unwrap();
        assert!((b.max_extent() - 2.0).abs() < 1e-4 && b.center().abs().max_element() < 1e-4);
        // Each mesh passes today's filter and sits in the split its source object hashes to.
        assert!(filter(&m, &FilterOptions::default()).is_ok(), "{}", e.path);
        assert_eq!(e.split, split_of(&split_key(&e.package, &e.path)));
        used += 1;
    }
    let total: usize = parsed.values().map(Shard::len).sum();
    assert_eq!(used, total, "every mesh in the shards has a manifest entry");
}

#[test]
fn licenses_are_permissive_and_their_texts_are_present() {
    let entries = manifest();
    let attribution = fs::read_to_string(dir().join("ATTRIBUTION.md")).unwrap();
    let index: Vec<serde_json::Value> =
        serde_json::from_slice(&fs::read(dir().join("licenses/index.json")).unwrap()).unwrap();
    for e in &entries {
        assert!(is_permissive(&e.license), "{}: {}", e.path, e.license);
        assert!(
            attribution.contains(&format!("| {} | {} |", e.package, e.package_version)),
            "{} is not in ATTRIBUTION.md",
            e.package
        );
        let files: Vec<&str> = index
            .iter()
            .filter(|f| f["package"] == e.package.as_str())
            .map(|f| f["file"].as_str().unwrap())
            .collect();
        assert!(!files.is_empty(), "no license text for {}", e.package);
        for f in files {
            let text = fs::read_to_string(dir().join("licenses").join(f)).unwrap();
            assert!(text.len() > 100, "{f} is too short to be a license");
        }
    }
}

#[test]
fn writing_the_meshes_again_gives_the_same_bytes() {
    for (name, bytes) in shards() {
        let shard = Shard::from_bytes(&bytes).unwrap();
        let mut w = ShardWriter::new();
        for i in 0..shard.len() {
            w.push(&shard.mesh(i));
        }
        assert!(w.finish() == bytes, "{name} is not what the writer writes");
    }
}

#[test]
fn augmentation_runs_on_every_mesh_of_the_fixture() {
    let opts = AugmentOptions {
        points: 512,
        ..AugmentOptions::default()
    };
    let entries = manifest();
    let meshes = load_meshes(&dir(), &entries).unwrap();
    assert_eq!(meshes.len(), entries.len());
    for (seed, (_, mesh)) in meshes.iter().enumerate() {
        let s = augment(mesh, &opts, seed as u64).unwrap();
        let b = s.mesh.aabb().unwrap();
        assert!(b.min.min_element() >= -1.0 - 1e-5 && b.max.max_element() <= 1.0 + 1e-5);
        assert_eq!(s.mesh.normals.len(), s.mesh.positions.len());
        assert_eq!(s.points.len(), 512);
    }
}
