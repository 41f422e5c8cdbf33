//! The data build: source packages in, a dataset out.
//! [`build`](crate::data::build::build) takes a list of
//! [`PackageInput`](crate::data::packages::PackageInput)s (name, version, license, the files
//! of the unpacked package) so tests can run it on a small folder;
//! [`build_from_cache`](crate::data::build::build_from_cache) finds the allowed packages in
//! the cache (`meshflow data fetch` put them there), unpacks them once and calls it.
//!
//! Every mesh is read, cleaned, filtered and normalised to the model frame (per package, in
//! parallel, cached), then deduplicated and split here (the rules are in
//! [`crate::data::dataset`]); kept meshes go to `{split}-{k:05}.safetensors` shards, one
//! `manifest.jsonl` line each, with the attribution, and the counts to `build.json`. Shards
//! and manifest are byte-identical across runs for the same inputs.

use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use crate::Mesh;
use crate::data::dataset::{FilterOptions, ManifestEntry, mesh_id, split_key, split_of};

use super::attribution::license_texts;
use super::error::DataError;
use super::files::{create_dir_all, to_json_pretty, write_atomic};
use super::packages::{PackageInput, discover};
use super::process::{PIPELINE_VERSION, Record, bump, process_package};
use super::progress::DataEvent;
use super::sources::license_of;
use super::write::{ShardSummary, write_dataset};

/// How [`build`] filters and how much it reads.
#[derive(Clone, Debug, Default, Serialize)]
pub struct BuildOptions {
    pub filter: FilterOptions,
    /// Process at most this many mesh files per source (in path order); 0 = all.
    pub limit_per_source: usize,
    /// Threads reading meshes; 0 = rayon's global pool (one per core).
    pub jobs: usize,
}

/// What one source gave, in `build.json`.
#[derive(Debug, Default, Serialize)]
pub struct SourceSummary {
    pub version: String,
    pub license: String,
    pub from_cache: bool,
    /// Files seen, archive members included.
    pub files: u64,
    /// Files with a mesh extension (readable or not).
    pub mesh_files: u64,
    /// Meshes that passed the filter, before duplicates were removed.
    pub passed_filter: u64,
    pub kept: u64,
    pub splits: BTreeMap<String, u64>,
    pub skipped: BTreeMap<String, u64>,
    pub unsupported_extensions: BTreeMap<String, u64>,
}

/// `build.json`: what a build holds, per source and in total, and how it was made.
#[derive(Debug, Serialize)]
pub struct BuildSummary {
    pub tool: String,
    pub pipeline_version: u32,
    pub wall_time_s: f64,
    pub options: BuildOptions,
    pub kept: u64,
    pub splits: BTreeMap<String, u64>,
    pub skipped: BTreeMap<String, u64>,
    pub sources: BTreeMap<String, SourceSummary>,
    pub shards: Vec<ShardSummary>,
}

impl BuildSummary {
    /// The table `meshflow data build` prints: per source and in total, the skip reasons, and
    /// the shards written to `out` in `seconds`.
    pub fn report<'a>(&'a self, out: &'a Path, seconds: f64) -> impl fmt::Display + 'a {
        fmt::from_fn(move |f| {
            let row = |f: &mut fmt::Formatter<'_>,
                       name: &str,
                       passed: &str,
                       kept: u64,
                       splits: &BTreeMap<String, u64>| {
                let g = |k: &str| splits.get(k).copied().unwrap_or(0);
                let (train, val, test) = (g("train"), g("val"), g("test"));
                writeln!(
                    f,
                    "{name:<24} {passed:>7} {kept:>7} {train:>6} {val:>6} {test:>6}"
                )
            };
            let (s, p, k, tr, v, te) = ("source", "passed", "kept", "train", "val", "test");
            writeln!(f, "{s:<24} {p:>7} {k:>7} {tr:>6} {v:>6} {te:>6}")?;
            for (name, src) in &self.sources {
                row(
                    f,
                    name,
                    &src.passed_filter.to_string(),
                    src.kept,
                    &src.splits,
                )?;
            }
            row(f, "total", "", self.kept, &self.splits)?;
            writeln!(f, "skipped:")?;
            for (reason, n) in &self.skipped {
                writeln!(f, "  {reason:<40}{n:>8}")?;
            }
            let bytes: u64 = self.shards.iter().map(|x| x.bytes).sum();
            let mib = bytes as f64 / (1 << 20) as f64;
            let (n, out) = (self.shards.len(), out.display());
            write!(f, "{n} shards, {mib:.1} MiB, in {out}; {seconds:.1} s")
        })
    }
}

/// Builds shards, `manifest.jsonl`, `build.json` and the attribution in `out` from `packages`.
/// With `cache`, each package's result is reused while its inputs are unchanged. Progress
/// (each package's reading and counts) goes to `observer`.
pub fn build(
    packages: &[PackageInput],
    out: &Path,
    cache: Option<&Path>,
    opts: &BuildOptions,
    observer: &mut dyn FnMut(DataEvent<'_>),
) -> Result<BuildSummary, DataError> {
    let start = Instant::now();
    create_dir_all(out)?;
    // A pool of our own rather than rayon's global one, which a library must not configure;
    // one that cannot be made (no threads to spawn) leaves the global pool.
    let pool = (opts.jobs > 0)
        .then(|| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(opts.jobs)
                .build()
                .ok()
        })
        .flatten();
    let mut sources: BTreeMap<String, SourceSummary> = BTreeMap::new();
    // (package index, record, mesh) of every mesh that passed the filter.
    let mut all: Vec<(usize, Record, Mesh)> = Vec::new();
    let mut order: Vec<usize> = (0..packages.len()).collect();
    order.sort_by(|&a, &b| packages[a].name.cmp(&packages[b].name));
    for &k in &order {
        let pkg = &packages[k];
        if sources.contains_key(&pkg.name) {
            return Err(DataError::DuplicatePackage(pkg.name.clone()));
        }
        let t = Instant::now();
        let (result, from_cache) = process_package(pkg, opts, cache, pool.as_ref(), observer)?;
        observer(DataEvent::PackageDone {
            package: &pkg.name,
            files: result.files,
            mesh_files: result.mesh_files,
            passed_filter: result.records.len() as u64,
            from_cache,
            seconds: t.elapsed().as_secs_f64(),
        });
        sources.insert(
            pkg.name.clone(),
            SourceSummary {
                version: pkg.version.clone(),
                license: pkg.license.clone(),
                from_cache,
                files: result.files,
                mesh_files: result.mesh_files,
                passed_filter: result.records.len() as u64,
                skipped: result.skipped,
                unsupported_extensions: result.unsupported_extensions,
                ..Default::default()
            },
        );
        for (r, m) in result.records.into_iter().zip(result.meshes) {
            all.push((k, r, m));
        }
    }
    // Duplicates: first by (package, path) wins.
    all.sort_by(|a, b| (&packages[a.0].name, &a.1.path).cmp(&(&packages[b.0].name, &b.1.path)));
    let mut seen_hash: HashMap<String, ()> = HashMap::new();
    let mut seen_shape: HashMap<(usize, usize, usize, usize, usize), ()> = HashMap::new();
    let mut kept: Vec<(ManifestEntry, Mesh)> = Vec::new();
    for (k, r, m) in all {
        let pkg = &packages[k];
        let src = sources.get_mut(&pkg.name).expect("inserted above");
        if seen_hash.insert(r.content_hash.clone(), ()).is_some() {
            bump(&mut src.skipped, "duplicate");
            continue;
        }
        // The same object in another pose or level of detail has the same counts.
        let shape = (
            k,
            r.vertices,
            r.faces,
            r.max_degree,
            r.topology.boundary_edges,
        );
        if seen_shape.insert(shape, ()).is_some() {
            bump(&mut src.skipped, "duplicate_pose_or_lod");
            continue;
        }
        let split = split_of(&split_key(&pkg.name, &r.path));
        let license = license_of(pkg, &r.path);
        src.kept += 1;
        *src.splits.entry(split.name().into()).or_default() += 1;
        kept.push((
            ManifestEntry {
                id: format!("{:016x}", mesh_id(&pkg.name, &r.path, "")),
                split,
                shard: String::new(),
                index: 0,
                package: pkg.name.clone(),
                package_version: pkg.version.clone(),
                path: r.path,
                submesh: String::new(),
                license,
                vertices: r.vertices,
                faces: r.faces,
                max_degree: r.max_degree,
                topology: r.topology,
                clean: r.clean,
                up_axis: r.up_axis,
                center: r.center,
                scale: r.scale,
                content_hash: r.content_hash,
            },
            m,
        ));
    }
    let texts = |name: &str| match packages.iter().find(|p| p.name == name) {
        Some(pkg) => license_texts(pkg),
        None => Ok(Vec::new()),
    };
    let (shards, splits) = write_dataset(out, &mut kept, &texts)?;
    let mut skipped = BTreeMap::new();
    for s in sources.values() {
        for (k, v) in &s.skipped {
            *skipped.entry(k.clone()).or_default() += v;
        }
    }
    let summary = BuildSummary {
        tool: format!("meshflow {}", env!("CARGO_PKG_VERSION")),
        pipeline_version: PIPELINE_VERSION,
        wall_time_s: (start.elapsed().as_secs_f64() * 1000.0).round() / 1000.0,
        options: opts.clone(),
        kept: kept.len() as u64,
        splits,
        skipped,
        sources,
        shards,
    };
    write_atomic(
        &out.join("build.json"),
        to_json_pretty(&summary, "build.json")?.as_bytes(),
    )?;
    Ok(summary)
}

/// Builds `out` from the allowed packages in `cache` ([`discover`]), keeping per-package
/// results in `cache/cache`. Packages absent from the cache are reported to `observer`
/// ([`DataEvent::NotInCache`]) and left out; none at all is [`DataError::NoPackages`].
pub fn build_from_cache(
    cache: &Path,
    out: &Path,
    opts: &BuildOptions,
    observer: &mut dyn FnMut(DataEvent<'_>),
) -> Result<BuildSummary, DataError> {
    let (packages, missing) = discover(cache, observer)?;
    if packages.is_empty() {
        return Err(DataError::NoPackages {
            cache: cache.to_path_buf(),
        });
    }
    if !missing.is_empty() {
        observer(DataEvent::NotInCache { packages: &missing });
    }
    build(&packages, out, Some(&cache.join("cache")), opts, observer)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    use glam::Vec3;

    use crate::data::dataset::{Shard, geometry_hash};
    use crate::data::export::export_mesh;
    use crate::data::process::HASH_QUANTUM;
    use crate::data::shards::read_manifest;
    use crate::data::test_support::{fake_package, fixture, read_out, temp_dir};
    use crate::geometry::normalize::UpAxis;
    use crate::io::Limits;

    /// Progress is not under test here.
    fn quiet(_: DataEvent<'_>) {}

    #[test]
    fn building_twice_gives_identical_bytes_and_uses_the_cache() {
        let root = temp_dir("twice");
        let pkg = fake_package(&root);
        let opts = BuildOptions::default();
        let a = build(
            std::slice::from_ref(&pkg),
            &root.join("out-a"),
            None,
            &opts,
            &mut quiet,
        )
        .unwrap();
        let cache = root.join("cache");
        let b = build(
            std::slice::from_ref(&pkg),
            &root.join("out-b"),
            Some(&cache),
            &opts,
            &mut quiet,
        )
        .unwrap();
        let c = build(
            std::slice::from_ref(&pkg),
            &root.join("out-c"),
            Some(&cache),
            &opts,
            &mut quiet,
        )
        .unwrap();
        assert!(!b.sources["fake-data"].from_cache);
        assert!(c.sources["fake-data"].from_cache);
        let files_a = read_out(&root.join("out-a"));
        assert_eq!(files_a, read_out(&root.join("out-b")));
        assert_eq!(files_a, read_out(&root.join("out-c")));
        assert!(files_a.contains_key("manifest.jsonl"));
        let attribution = String::from_utf8(files_a["ATTRIBUTION.md"].clone()).unwrap();
        assert!(attribution.contains("| fake-data |"), "{attribution}");
        assert!(
            attribution.contains("`licenses/fake-data-0.txt`"),
            "{attribution}"
        );
        let copied = fs::read_to_string(root.join("out-a/licenses/fake-data-0.txt")).unwrap();
        assert_eq!(copied, "Fake copyright text\n");

        let src = &a.sources["fake-data"];
        assert_eq!(src.skipped.get("unsupported_format"), Some(&1));
        let text = a.report(Path::new("out-a"), 1.0).to_string();
        let lines: Vec<&str> = text.lines().collect();
        let header = "source                    passed    kept  train    val   test";
        assert_eq!(lines[0], header);
        assert!(lines[1].starts_with("fake-data                "), "{text}");
        assert!(
            text.contains("\n  unsupported_format                             1\n"),
            "{text}"
        );
        assert!(text.ends_with(" MiB, in out-a; 1.0 s"), "{text}");
        assert_eq!(src.unsupported_extensions.get("iqe"), Some(&1));
        assert_eq!(src.skipped.get("collision"), Some(&1));
        assert_eq!(src.skipped.get("duplicate"), Some(&1), "{:?}", src.skipped);
        assert_eq!(
            src.skipped.get("unreadable:malformed"),
            Some(&1),
            "{:?}",
            src.skipped
        );
        assert!(a.kept >= 3, "{a:?}");

        // The manifest points at every kept mesh, which round-trips through its shard.
        let manifest = String::from_utf8(files_a["manifest.jsonl"].clone()).unwrap();
        let entries: Vec<ManifestEntry> = manifest
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(entries.len() as u64, a.kept);
        assert!(entries.windows(2).all(|w| w[0].id < w[1].id));
        let paths: Vec<&str> = entries.iter().map(|e| e.path.as_str()).collect();
        assert!(
            paths.contains(&"usr/share/game/data.zip!more.pk3!models/stone_lantern.obj"),
            "{paths:?}"
        );
        for e in &entries {
            let shard = Shard::from_bytes(&files_a[&e.shard]).unwrap();
            let m = shard.mesh(e.index);
            assert_eq!((m.positions.len(), m.faces.len()), (e.vertices, e.faces));
            let aabb = m.aabb().unwrap();
            assert!((aabb.max_extent() - 2.0).abs() < 1e-4);
            assert!(aabb.min.min_element() >= -1.0001 && aabb.max.max_element() <= 1.0001);
            assert_eq!(
                e.content_hash,
                format!("{:016x}", geometry_hash(&m, HASH_QUANTUM))
            );
        }
        let _ = fs::remove_dir_all(&root);
    }

    #[test]
    fn a_changed_input_invalidates_the_cache() {
        let root = temp_dir("invalidate");
        let mut pkg = fake_package(&root);
        let cache = root.join("cache");
        let opts = BuildOptions::default();
        build(
            std::slice::from_ref(&pkg),
            &root.join("out"),
            Some(&cache),
            &opts,
            &mut quiet,
        )
        .unwrap();
        fs::write(
            pkg.files[0].abs.with_file_name("extra.obj"),
            fixture("deck_chair.obj"),
        )
        .unwrap();
        pkg = PackageInput::from_dir("fake-data", "1.0-1", "CC0-1.0", &root.join("pkg")).unwrap();
        let s = build(&[pkg], &root.join("out"), Some(&cache), &opts, &mut quiet).unwrap();
        assert!(!s.sources["fake-data"].from_cache);
        let _ = fs::remove_dir_all(&root);
    }

    #[test]
    fn a_z_up_source_is_rotated_to_y_up_and_back() {
        let root = temp_dir("zup");
        let mut pkg = fake_package(&root);
        let opts = BuildOptions::default();
        build(
            std::slice::from_ref(&pkg),
            &root.join("y"),
            None,
            &opts,
            &mut quiet,
        )
        .unwrap();
        pkg.name = "robosuite".into();
        build(
            std::slice::from_ref(&pkg),
            &root.join("z"),
            None,
            &opts,
            &mut quiet,
        )
        .unwrap();
        let load = |dir: &str| -> BTreeMap<String, (ManifestEntry, Mesh)> {
            let dir = root.join(dir);
            read_manifest(&dir)
                .unwrap()
                .into_iter()
                .map(|e| {
                    let shard = Shard::from_bytes(&fs::read(dir.join(&e.shard)).unwrap()).unwrap();
                    (e.path.clone(), (e.clone(), shard.mesh(e.index)))
                })
                .collect()
        };
        let (y, z) = (load("y"), load("z"));
        assert_eq!(y.keys().collect::<Vec<_>>(), z.keys().collect::<Vec<_>>());
        for (path, (ey, my)) in &y {
            let (ez, mz) = &z[path];
            assert_eq!((ey.up_axis, ez.up_axis), (UpAxis::Y, UpAxis::Z));
            // The rotation only permutes and negates coordinates, so it is exact.
            let rotated: Vec<Vec3> = my.positions.iter().map(|&p| UpAxis::Z.to_y_up(p)).collect();
            assert_eq!(mz.positions, rotated, "{path}");
            assert_eq!(mz.faces, my.faces, "{path}: same winding");
        }
        // `show --source-frame` undoes the rotation: the source file's box comes back.
        let (e, _) = &z["usr/share/game/bread.obj"];
        let out = root.join("bread.ply");
        export_mesh(&root.join("z"), &e.id, &out, true).unwrap();
        let shown = crate::io::read_path(&out, &Limits::default()).unwrap();
        let original = crate::io::read_path(
            &pkg.files
                .iter()
                .find(|f| f.rel.ends_with("bread.obj"))
                .unwrap()
                .abs,
            &Limits::default(),
        )
        .unwrap();
        let (a, b) = (shown.aabb().unwrap(), original.aabb().unwrap());
        let tol = 1e-4 * b.max_extent();
        assert!((a.min - b.min).abs().max_element() < tol, "{a:?} vs {b:?}");
        assert!((a.max - b.max).abs().max_element() < tol, "{a:?} vs {b:?}");
        let _ = fs::remove_dir_all(&root);
    }
}
