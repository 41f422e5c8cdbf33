//! The sources the data build may use (docs/data.md): the Debian packages and PyPI projects
//! with their licenses, the parts licensed differently, each source's up axis, and where the
//! cache of downloads and builds lives.

use std::path::PathBuf;

use crate::geometry::normalize::UpAxis;

use super::files::extension;
use super::packages::PackageInput;

/// A Debian package of docs/data.md's table and its license.
pub const DEBIAN_SOURCES: [(&str, &str); 9] = [
    ("0ad-data", "CC-BY-SA-3.0"),
    ("supertuxkart-data", "CC-BY-SA-3.0/4.0 (some CC0, CC-BY)"),
    ("ufoai-data", "GPL-2+ / CC-BY(-SA)"),
    ("sweethome3d-furniture", "CC-BY-3.0"),
    ("warzone2100-data", "GPL-2+"),
    ("nexuiz-data", "GPL-2+"),
    ("openarena-data", "GPL-2+"),
    ("flightgear-data-models", "GPL-2+"),
    (
        "redeclipse-data",
        "CC (per asset, see the package's copyright file)",
    ),
];

/// The PyPI projects of docs/data.md's table and their licenses.
pub const PYPI_SOURCES: [(&str, &str); 7] = [
    ("robosuite", "MIT"),
    ("example-robot-data", "BSD-3-Clause"),
    ("dm-control", "Apache-2.0"),
    ("rtb-data", "MIT"),
    ("metaworld", "MIT"),
    ("gymnasium-robotics", "MIT"),
    ("pybullet", "Zlib"),
];

/// Parts of a package licensed differently from the rest: (package, path fragment, license).
pub const LICENSE_OVERRIDES: [(&str, &str, &str); 1] =
    [("sweethome3d-furniture", "BlendSwap-CC-0.sh3f", "CC0-1.0")];

/// The license of the file at `path` in `pkg`: its [`LICENSE_OVERRIDES`] row, else the
/// package's.
pub(crate) fn license_of(pkg: &PackageInput, path: &str) -> String {
    LICENSE_OVERRIDES
        .iter()
        .find(|(p, fragment, _)| *p == pkg.name && path.contains(fragment))
        .map_or_else(|| pkg.license.clone(), |(_, _, l)| l.to_string())
}

/// Which way is up in each source, by package and file extension (`*`: any); the first
/// matching row wins, and a package not listed is taken as Y-up. The build rotates every mesh
/// to the model frame's Y-up ([`UpAxis::to_y_up`]) before normalising it and records the
/// source's axis in the manifest (`up_axis`).
///
/// Evidence, from the 6,292-mesh build (docs/data.md sources): for each source and format,
/// the axis on which objects rest on the origin (their minimum is ~0 while the other two
/// axes are centred) and the longest axis of obviously upright objects (trees, towers, lamp
/// posts, flags, statues, characters):
/// - 0 A.D. PMD: rests on y in 24% of meshes (x, z: <1%); cypress, towers tall in y.
/// - SuperTuxKart SPM: fir and pine trees, lamp posts tall in y (Irrlicht is Y-up).
/// - Warzone 2100 PIE: rests on y in 60% (x, z: ~0).
/// - Sweet Home 3D OBJ: rests on y in 41%; chairs, lamps, doors tall in y.
/// - FlightGear AC3D: rests on y in 36%; towers tall in y (AC3D files are Y-up; FlightGear
///   rotates them when it loads them).
/// - Red Eclipse OBJ: rests on y in 60% (lamp post, pillar, safety post tall in y); its MD3
///   vegetation rests on z (Cube engines are Z-up).
/// - UFO:AI MD2 rests on z in 31% (x, y: ~0); its few OBJ (tanks, robots) rest on y.
/// - Nexuiz MD3 rests on z in 37%; OpenArena MD3 flags, palm tree and statue are tall in z
///   and teleporters rest on z (Quake III is Z-up); OpenArena's one OBJ rests on y.
/// - Robot wheels (STL, OBJ, DAE): URDF/MJCF link frames are Z-up (ROS REP 103); gripper,
///   leg and torso links are long in z. COLLADA files declare their `<up_axis>` and the DAE
///   reader already turns them to Y-up, hence the first row (any package).
/// - ASE, IQM and MD5 (Quake/Cube-family and 3ds Max exports) are Z-up like MD3.
pub const UP_AXES: [(&str, &str, UpAxis); 21] = [
    ("*", "dae", UpAxis::Y),
    ("0ad-data", "*", UpAxis::Y),
    ("supertuxkart-data", "*", UpAxis::Y),
    ("warzone2100-data", "*", UpAxis::Y),
    ("sweethome3d-furniture", "*", UpAxis::Y),
    ("flightgear-data-models", "*", UpAxis::Y),
    ("redeclipse-data", "obj", UpAxis::Y),
    ("redeclipse-data", "*", UpAxis::Z),
    ("ufoai-data", "obj", UpAxis::Y),
    ("ufoai-data", "*", UpAxis::Z),
    ("nexuiz-data", "obj", UpAxis::Y),
    ("nexuiz-data", "*", UpAxis::Z),
    ("openarena-data", "obj", UpAxis::Y),
    ("openarena-data", "*", UpAxis::Z),
    ("robosuite", "*", UpAxis::Z),
    ("example-robot-data", "*", UpAxis::Z),
    ("dm-control", "*", UpAxis::Z),
    ("rtb-data", "*", UpAxis::Z),
    ("metaworld", "*", UpAxis::Z),
    ("gymnasium-robotics", "*", UpAxis::Z),
    ("pybullet", "*", UpAxis::Z),
];

/// The up axis of a mesh file of `package` ([`UP_AXES`]).
pub fn up_axis_of(package: &str, path: &str) -> UpAxis {
    let ext = extension(path);
    UP_AXES
        .iter()
        .find(|(p, e, _)| (*p == "*" || *p == package) && (*e == "*" || *e == ext))
        .map_or(UpAxis::Y, |(_, _, axis)| *axis)
}

/// The default cache folder, `~/.cache/meshflow/data` (`./.cache/...` without `HOME`): the
/// downloads (`debs/`, `wheels/`), unpacked packages, per-package results and the build.
pub fn default_cache() -> PathBuf {
    std::env::var_os("HOME")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("."))
        .join(".cache/meshflow/data")
}

/// The shard build a command reads: `dir`, or the default build's `CACHE/shards`.
pub fn shards_dir(dir: Option<PathBuf>) -> PathBuf {
    dir.unwrap_or_else(|| default_cache().join("shards"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn up_axes_by_source_and_format() {
        assert_eq!(
            up_axis_of("ufoai-data", "base/0models.pk3!a/b.md2"),
            UpAxis::Z
        );
        assert_eq!(
            up_axis_of("ufoai-data", "base/0models.pk3!a/b.OBJ"),
            UpAxis::Y
        );
        assert_eq!(
            up_axis_of("openarena-data", "x.pk3!models/m.md3"),
            UpAxis::Z
        );
        assert_eq!(up_axis_of("redeclipse-data", "data/a/tris.iqm"), UpAxis::Z);
        assert_eq!(up_axis_of("0ad-data", "public.zip!art/m.pmd"), UpAxis::Y);
        assert_eq!(
            up_axis_of("flightgear-data-models", "Models/a.ac"),
            UpAxis::Y
        );
        assert_eq!(up_axis_of("pybullet", "pybullet_data/a.obj"), UpAxis::Z);
        assert_eq!(up_axis_of("robosuite", "r/meshes/a.stl"), UpAxis::Z);
        assert_eq!(up_axis_of("fake-data", "a.obj"), UpAxis::Y);
        // COLLADA files come out of the reader Y-up, whatever the package.
        assert_eq!(up_axis_of("robosuite", "r/meshes/a.dae"), UpAxis::Y);
        // Every source of docs/data.md has a row.
        for (name, _) in DEBIAN_SOURCES.iter().chain(PYPI_SOURCES.iter()) {
            assert!(UP_AXES.iter().any(|(p, _, _)| p == name), "{name}");
        }
    }
}
