//! The geometry core: the mesh type, normals, topology, surface sampling, normalisation to
//! the model frame, cleaning, and the small tools under them.

pub mod clean;
pub mod disjoint_sets;
/// Guarded local edits (collapse, flip, subdivision) on a manifold mesh.
pub mod edit;
/// Sharp edges (creases), for the surface metrics and the sharpening stage.
pub mod features;
/// The hard-surface set (box, bracket, wedge, stair, cylinder, table, house, hollow box).
pub mod hard_surface;
/// A mesh's summary figures (`meshflow inspect`).
pub mod inspect;
pub mod mesh;
/// Nearest points of a fixed set (a k-d tree): every stage after extraction asks it.
pub mod nearest;
pub mod normalize;
pub mod normals;
/// Faces turned outward: each piece wound so that it encloses a positive volume.
pub mod orient;
/// The best-fitting plane of a set of points (covariance, direction of least spread).
pub mod plane_fit;
/// Planar regions of a point cloud (region growing): the flat parts of a noisy scan.
pub mod plane_regions;
pub mod primitives;
/// Plane quadrics and their truncated minimiser (placement and decimation).
pub mod quadric;
/// Vertices a flat region, a straight crease or a straight boundary does not need, removed.
pub mod redundant_vertices;
pub mod sample;
/// Positions snapped to a grid on the input's box (the same start for sharpening everywhere).
pub mod snap;
pub mod topology;
/// Point-to-triangle distance (card detection, sharpening's coverage guard).
pub mod triangle;
pub mod voxel;
