//! Inputs the data build's tests share: fixture meshes, a fake package, the committed fixture
//! dataset, scratch folders.

use std::collections::BTreeMap;
use std::fs;
use std::io::{Cursor, Write};
use std::path::{Path, PathBuf};

use super::files::{file_name, list_dir};
use super::packages::PackageInput;

/// The bytes of `tests/fixtures/meshes/<name>`.
pub(crate) fn fixture(name: &str) -> Vec<u8> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/fixtures/meshes")
        .join(name);
    fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A zip archive of `members` (name, bytes).
fn zip_of(members: &[(&str, Vec<u8>)]) -> Vec<u8> {
    let mut w = zip::ZipWriter::new(Cursor::new(Vec::new()));
    for (name, bytes) in members {
        w.start_file(*name, zip::write::SimpleFileOptions::default())
            .unwrap();
        w.write_all(bytes).unwrap();
    }
    w.finish().unwrap().into_inner()
}

/// An empty scratch folder for the test `tag` (unique per process).
pub(crate) fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("meshflow-data-{}-{tag}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

/// A fake package: a loose OBJ, a zip of fixtures (with a nested .pk3, a copy of a mesh
/// under another name, a collision mesh, an unsupported .iqe and a texture).
pub(crate) fn fake_package(root: &Path) -> PackageInput {
    let pkg = root.join("pkg");
    fs::create_dir_all(pkg.join("usr/share/game")).unwrap();
    fs::write(pkg.join("usr/share/game/bread.obj"), fixture("bread.obj")).unwrap();
    fs::write(pkg.join("usr/share/game/readme.txt"), b"1 2 3\n").unwrap();
    let nested = zip_of(&[
        ("models/stone_lantern.obj", fixture("stone_lantern.obj")),
        ("models/copy_of_bread.obj", fixture("bread.obj")),
    ]);
    let data = zip_of(&[
        ("meshes/deck_chair.obj", fixture("deck_chair.obj")),
        ("meshes/garden_lantern.obj", fixture("garden_lantern.obj")),
        (
            "meshes/finger_lower_link.stl",
            fixture("finger_lower_link.stl"),
        ),
        ("meshes/solo_lower_leg.obj", fixture("solo_lower_leg.obj")),
        (
            "meshes/humanoid_box_ascii.stl",
            fixture("humanoid_box_ascii.stl"),
        ),
        (
            "meshes/collision/solo_lower_leg.obj",
            fixture("solo_lower_leg.obj"),
        ),
        ("meshes/broken.obj", b"v 1 2\nf 1 2 3\n".to_vec()),
        ("meshes/horse.iqe", b"# Inter-Quake Export".to_vec()),
        ("textures/horse.png", b"\x89PNG".to_vec()),
        ("more.pk3", nested),
    ]);
    fs::write(pkg.join("usr/share/game/data.zip"), data).unwrap();
    fs::create_dir_all(pkg.join("usr/share/doc/fake-data")).unwrap();
    fs::write(
        pkg.join("usr/share/doc/fake-data/copyright"),
        "Fake copyright text\n",
    )
    .unwrap();
    PackageInput::from_dir("fake-data", "1.0-1", "CC0-1.0", &pkg).unwrap()
}

/// The files directly in `out` (name -> bytes), `build.json` left out (it holds a wall time).
pub(crate) fn read_out(out: &Path) -> BTreeMap<String, Vec<u8>> {
    list_dir(out)
        .unwrap()
        .into_iter()
        .filter(|p| p.is_file() && file_name(p) != "build.json")
        .map(|p| (file_name(&p), fs::read(&p).unwrap()))
        .collect()
}

/// The committed fixture dataset (tests/fixtures/dataset, written by `meshflow data
/// subset` from a full build).
pub(crate) fn fixture_dataset() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/dataset")
}
