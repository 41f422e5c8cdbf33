//! The geometry core: the mesh type, normals, topology, surface sampling, normalisation to
//! the model frame, cleaning, and the small tools under them.

pub mod clean;
pub mod disjoint_sets;
/// A mesh's summary figures (`meshflow inspect`).
pub mod inspect;
pub mod mesh;
pub mod normalize;
pub mod normals;
pub mod primitives;
pub mod sample;
pub mod topology;
pub mod voxel;
