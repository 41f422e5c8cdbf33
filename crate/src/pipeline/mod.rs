//! The whole path from input to mesh: the vertex budget, generation (point cloud -> DiT ->
//! VAE decode -> extraction -> fitting and completion), reconstruction through the VAE, and
//! the shipped weights with their checks.

pub mod budget;
pub mod generate;
pub mod reconstruct;
pub mod shipped;
