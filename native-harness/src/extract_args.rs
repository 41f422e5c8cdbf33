//! Extraction options on the command line, shared by every command that extracts a mesh
//! (`extract`, `reconstruct`, `generate`, `eval vae`, `eval generate`).

use clap::Args;
use meshflow::extract::ExtractOptions;

#[derive(Args, Clone, Debug)]
pub struct ExtractArgs {
    /// Fill boundary loops of at most this many edges (0 = no hole repair).
    #[arg(long, default_value_t = 4)]
    pub max_hole_edges: usize,
    /// Drop faces that would make an edge non-manifold, keeping the best-supported ones (not
    /// in the paper's Algorithm 1; off by default).
    #[arg(long)]
    pub drop_non_manifold: bool,
}

impl ExtractArgs {
    /// The library's options for these flags; anything else stays at its default.
    pub fn options(&self) -> ExtractOptions {
        ExtractOptions {
            // A boundary loop has at least 3 edges, so 1 and 2 fill nothing either.
            fill_holes: self.max_hole_edges >= 3,
            max_hole_edges: self.max_hole_edges,
            drop_non_manifold: self.drop_non_manifold,
            ..Default::default()
        }
    }
}
