//! Arguments several commands share: the extraction options (`extract`, `reconstruct`,
//! `generate`, `eval vae`, `eval generate`) and the backend a model runs on.

use anyhow::Result;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use meshflow::burn::tensor::Device;
use meshflow::device::{BackendKind, device};
use meshflow::extract::{ExtractMethod, ExtractOptions};

/// A flag that takes one of `names`, parsed by `T`'s `FromStr`; `--help` lists the names.
pub fn one_of<T>(names: impl IntoIterator<Item = &'static str>) -> impl TypedValueParser<Value = T>
where
    T: std::str::FromStr + Clone + Send + Sync + 'static,
    T::Err: Into<Box<dyn std::error::Error + Send + Sync>>,
{
    PossibleValuesParser::new(names).try_map(|name| name.parse::<T>())
}

/// `--backend`: the library's [`BackendKind`] (cpu = Burn's flex backend, wgpu = burn-wgpu
/// over Vulkan, ndarray = Burn's ndarray backend in a build with `--features ndarray`, for
/// comparison with flex).
#[derive(Args, Clone, Copy)]
pub struct BackendArg {
    #[arg(long = "backend", value_name = "BACKEND", default_value = "cpu", value_parser = one_of::<BackendKind>(BackendKind::ALL.map(BackendKind::name)))]
    pub kind: BackendKind,
}

impl BackendArg {
    /// The backend's device; an error when this build or machine has none.
    pub fn device(self) -> Result<Device> {
        device(self.kind).map_err(|e| anyhow::anyhow!(e))
    }
}

/// `--extraction`: how edges become faces.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extraction {
    /// Faces accepted best-first by the model's edge margins: 0 non-manifold edges, 0
    /// inconsistently wound edges, small holes filled, tiny pieces dropped.
    Manifold,
    /// The paper's Algorithm 1: every 3-clique of the edge graph is a face.
    Paper,
}

/// The extraction options, for every command that extracts a mesh.
#[derive(Args, Clone, Debug)]
pub struct ExtractionArgs {
    /// How edges become faces: `manifold` (default) or the paper's Algorithm 1 (`paper`).
    #[arg(long, value_enum, default_value = "manifold")]
    pub extraction: Extraction,
    /// Fill boundary loops of at most this many edges (0 = no hole repair).
    #[arg(long, default_value_t = 4)]
    pub max_hole_edges: usize,
    /// With `--extraction manifold`: drop connected pieces of fewer faces than this (default
    /// 2: lone triangles; 0 keeps every piece).
    #[arg(long, default_value_t = 2)]
    pub min_piece_faces: usize,
    /// With `--extraction manifold`: also offer faces whose edges' spacetime distance is above
    /// tau minus this (after every face above tau), to close gaps where the decoder missed an
    /// edge (>= 0).
    #[arg(long, default_value_t = 0.3)]
    pub candidate_slack: f32,
    /// With `--extraction manifold`: refuse a face lying on an accepted face that it shares
    /// at most one vertex with, within this many of its longest edges of its plane (a second
    /// layer of faces; 0 = no such test).
    #[arg(long, default_value_t = ExtractOptions::default().overlap_tolerance)]
    pub overlap_tolerance: f32,
    /// With `--extraction paper`: drop faces that would make an edge non-manifold, keeping the
    /// best-supported ones (not in the paper's Algorithm 1; off by default; an error with
    /// the manifold method).
    #[arg(long)]
    pub drop_non_manifold: bool,
}

impl ExtractionArgs {
    /// The library's options for these flags; anything else stays at its default.
    pub fn options(&self) -> ExtractOptions {
        ExtractOptions {
            method: match self.extraction {
                Extraction::Manifold => ExtractMethod::Manifold,
                Extraction::Paper => ExtractMethod::Paper,
            },
            // A boundary loop has at least 3 edges, so 1 and 2 fill nothing either.
            fill_holes: self.max_hole_edges >= 3,
            max_hole_edges: self.max_hole_edges,
            min_component_faces: self.min_piece_faces,
            candidate_slack: self.candidate_slack,
            overlap_tolerance: self.overlap_tolerance,
            drop_non_manifold: self.drop_non_manifold,
            ..Default::default()
        }
    }
}
