//! Training data: the shard format and the build's pure rules ([`dataset`]), reading a build
//! from disk ([`shards`]), augmentation, and the degradations the robustness figures use.
//! With feature `data-build` (native only: it runs `apt-get`, `pip` and `dpkg-deb` and reads
//! archives on threads), the data build itself: fetching the allowed sources, reading them
//! into shards, subsets, statistics and single-mesh export (`meshflow data`). It prints
//! nothing; progress goes to the caller through `progress::DataEvent`.

pub mod augment;
pub mod cards;
pub mod dataset;
pub mod degrade;
#[cfg(not(target_arch = "wasm32"))]
pub mod shards;

/// ATTRIBUTION.md and the `licenses/` copies of a dataset.
#[cfg(feature = "data-build")]
mod attribution;
/// The build: packages in, shards, manifest and build.json out.
#[cfg(feature = "data-build")]
pub mod build;
/// The data build's error type.
#[cfg(feature = "data-build")]
pub mod error;
/// One mesh of a build written as GLB, OBJ or PLY (`meshflow data show`).
#[cfg(feature = "data-build")]
pub mod export;
/// Downloading the allowed packages and wheels into the cache.
#[cfg(feature = "data-build")]
pub mod fetch;
/// File-system helpers whose errors name their path.
#[cfg(feature = "data-build")]
mod files;
/// The build's inputs: packages as file lists, found and unpacked from the cache.
#[cfg(feature = "data-build")]
pub mod packages;
/// The raster canvas the statistics histogram is drawn on.
#[cfg(feature = "data-build")]
mod plot;
/// One package: mesh files found, read, cleaned, filtered, normalised; cached.
#[cfg(feature = "data-build")]
mod process;
/// The events the build reports instead of printing.
#[cfg(feature = "data-build")]
pub mod progress;
/// The allowed sources, their licenses and up axes, the cache folder.
#[cfg(feature = "data-build")]
pub mod sources;
/// stats.csv and the stats.png histograms of a build.
#[cfg(feature = "data-build")]
pub mod stats;
/// A small dataset picked from a build, for tests and fixtures.
#[cfg(feature = "data-build")]
pub mod subset;
/// Shared inputs of the data build's tests.
#[cfg(all(test, feature = "data-build"))]
mod test_support;
/// Writing shards and the manifest of a dataset.
#[cfg(feature = "data-build")]
mod write;

#[cfg(feature = "data-build")]
pub use error::DataError;
#[cfg(feature = "data-build")]
pub use progress::DataEvent;
