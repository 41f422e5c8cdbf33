//! One mesh of a build, by manifest id, written as GLB, OBJ or PLY (`meshflow data show`):
//! as stored (model frame, Y-up) or back in its source file's position, size and orientation.

use std::path::Path;

use crate::data::dataset::ManifestEntry;
use crate::data::shards::{load_meshes, read_manifest};
use crate::geometry::normalize::Normalization;

use super::error::DataError;

/// Writes the mesh with manifest id `id` of the build in `dir` to `output` (format from its
/// extension); with `source_frame`, the model-frame normalisation and the rotation to Y-up
/// are undone first. Returns the mesh's manifest entry.
pub fn export_mesh(
    dir: &Path,
    id: &str,
    output: &Path,
    source_frame: bool,
) -> Result<ManifestEntry, DataError> {
    let entries = read_manifest(dir)?;
    let Some(entry) = entries.into_iter().find(|e| e.id == id) else {
        return Err(DataError::NoSuchMesh {
            id: id.to_string(),
            dir: dir.to_path_buf(),
        });
    };
    let (entry, mut mesh) = load_meshes(dir, [entry])?
        .pop()
        .expect("one mesh per entry");
    if source_frame {
        let norm = Normalization {
            center: entry.center.into(),
            scale: entry.scale,
        };
        mesh = entry
            .up_axis
            .mesh_from_y_up(&norm.inverse().apply_mesh(&mesh));
    }
    crate::io::write_path(&mesh, output).map_err(|source| DataError::Write {
        path: output.to_path_buf(),
        source,
    })?;
    Ok(entry)
}
