//! Attribution of a dataset: `ATTRIBUTION.md` (per package and license: version, how many
//! meshes are used, where its license text is) and a copy of each used package's license
//! files in `licenses/`, listed in `licenses/index.json`, so any artefact derived from the
//! shards can carry them and a subset can copy them on.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::data::dataset::ManifestEntry;

use super::error::DataError;
use super::files::{
    create_dir_all, file_name, io_error, list_dir, read, remove_file, to_json_pretty, write_atomic,
};
use super::packages::PackageInput;

/// Package name -> its license texts as (path in the package, bytes).
pub(crate) type LicenseTexts<'a> = dyn Fn(&str) -> Result<Vec<(String, Vec<u8>)>, DataError> + 'a;

/// True for the paths license texts have: Debian's `usr/share/doc/<name>/copyright`, a wheel's
/// `*.dist-info/LICENSE*` or `*.dist-info/licenses/*`.
fn is_license_path(package: &str, path: &str) -> bool {
    let leaf = path.rsplit('/').next().unwrap_or("");
    path == format!("usr/share/doc/{package}/copyright")
        || (path.contains(".dist-info/")
            && (leaf.starts_with("LICENSE") || path.contains(".dist-info/licenses/")))
}

/// The license texts a package ships, as (path inside the package, bytes), sorted by path.
/// A wheel (an input file with an empty `rel`) is searched inside its zip.
pub(crate) fn license_texts(pkg: &PackageInput) -> Result<Vec<(String, Vec<u8>)>, DataError> {
    let mut found = Vec::new();
    for f in &pkg.files {
        if f.rel.is_empty() {
            let zip_error = |error| DataError::Zip {
                path: f.abs.clone(),
                error,
            };
            let file = std::fs::File::open(&f.abs).map_err(|e| io_error("read", &f.abs, e))?;
            let mut zip = zip::ZipArchive::new(file).map_err(zip_error)?;
            for i in 0..zip.len() {
                let mut member = zip.by_index(i).map_err(zip_error)?;
                let name = member.name().map_err(zip_error)?.to_string();
                if member.is_file() && is_license_path(&pkg.name, &name) {
                    let mut bytes = Vec::new();
                    member
                        .read_to_end(&mut bytes)
                        .map_err(|e| zip_error(e.into()))?;
                    found.push((name, bytes));
                }
            }
        } else if is_license_path(&pkg.name, &f.rel) {
            found.push((f.rel.clone(), read(&f.abs)?));
        }
    }
    found.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(found)
}

/// One license file copied to `licenses/`, as listed in `licenses/index.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct LicenseFile {
    package: String,
    /// The copy's name in `licenses/`.
    file: String,
    /// Where the text is in the package.
    path: String,
}

/// Writes `ATTRIBUTION.md` for the manifest `entries` and copies each used package's license
/// files (`license_texts`: package name -> (path in the package, bytes)) to `licenses/`,
/// listed in `licenses/index.json`. Per-mesh source paths are in the manifest.
pub(crate) fn write_attribution<'a>(
    out: &Path,
    entries: impl Iterator<Item = &'a ManifestEntry>,
    license_texts: &LicenseTexts,
) -> Result<(), DataError> {
    let mut used: BTreeMap<(&str, &str, &str), usize> = BTreeMap::new();
    for e in entries {
        *used
            .entry((&e.package, &e.package_version, &e.license))
            .or_default() += 1;
    }
    let licenses_dir = out.join("licenses");
    create_dir_all(&licenses_dir)?;
    // Copies of an earlier run's packages would otherwise linger.
    for p in list_dir(&licenses_dir)? {
        let n = file_name(&p);
        if n.ends_with(".txt") || n == "index.json" {
            remove_file(&p)?;
        }
    }
    let mut text = String::from(
        "# Attribution\n\nThe meshes in these shards come from the packages below, under the \
         licenses listed. Each mesh's package, version, path inside the package and license are \
         in `manifest.jsonl`. Anything derived from the shards (trained weights, rendered \
         images, converted meshes) must carry this file and the `licenses/` folder.\n\n\
         | package | version | license | meshes | license files |\n|---|---|---|---:|---|\n",
    );
    let mut index: Vec<LicenseFile> = Vec::new();
    for ((name, version, license), count) in &used {
        let texts = license_texts(name)?;
        let mut copied = Vec::new();
        for (k, (path, bytes)) in texts.iter().enumerate() {
            let dest = format!("{name}-{k}.txt");
            write_atomic(&licenses_dir.join(&dest), bytes)?;
            copied.push(format!("`licenses/{dest}` (`{path}`)"));
            let file = LicenseFile {
                package: name.to_string(),
                file: dest,
                path: path.clone(),
            };
            // A package used under two licenses (an override) lists its files once.
            if !index.contains(&file) {
                index.push(file);
            }
        }
        let files = if copied.is_empty() {
            "none shipped in the package".to_string()
        } else {
            copied.join(", ")
        };
        text.push_str(&format!(
            "| {name} | {version} | {license} | {count} | {files} |\n"
        ));
    }
    write_atomic(
        &licenses_dir.join("index.json"),
        to_json_pretty(&index, "licenses/index.json")?.as_bytes(),
    )?;
    write_atomic(&out.join("ATTRIBUTION.md"), text.as_bytes())
}

/// The license files a dataset in `dir` lists for `package` (`licenses/index.json`), as
/// [`write_attribution`] takes them.
pub(crate) fn dataset_license_texts(
    dir: &Path,
    package: &str,
) -> Result<Vec<(String, Vec<u8>)>, DataError> {
    let index_path = dir.join("licenses/index.json");
    let bytes = std::fs::read(&index_path).map_err(|error| DataError::NoLicenseIndex {
        path: index_path.clone(),
        error,
    })?;
    let index: Vec<LicenseFile> =
        serde_json::from_slice(&bytes).map_err(|error| DataError::BadLicenseIndex {
            path: index_path.clone(),
            error,
        })?;
    index
        .into_iter()
        .filter(|f| f.package == package)
        .map(|f| Ok((f.path, read(&dir.join("licenses").join(&f.file))?)))
        .collect()
}
