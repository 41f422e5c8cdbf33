//! What the data build reports while it works. The library prints nothing: `fetch`,
//! `discover` and `build` call an observer (`&mut dyn FnMut(DataEvent)`) with these events,
//! always on the caller's thread, and the caller shows them (the CLI prints a line or draws a
//! progress bar).

use std::path::Path;

/// One step of `fetch`, `discover` or `build`, in the order they happen.
#[derive(Clone, Copy, Debug)]
pub enum DataEvent<'a> {
    /// `fetch`: the package's `.deb` is in the cache with the SHA256 apt expects.
    DebPresent { package: &'a str, version: &'a str },
    /// `fetch`: `apt-get download` starts.
    DebDownloading { package: &'a str, version: &'a str },
    /// `fetch`: the download finished and its SHA256 matches.
    DebDownloaded {
        package: &'a str,
        version: &'a str,
        bytes: u64,
        seconds: f64,
    },
    /// `fetch`: a wheel of the project is in the cache.
    WheelPresent { project: &'a str, wheel: &'a Path },
    /// `fetch`: `pip download` starts.
    WheelDownloading { project: &'a str },
    /// `fetch`: `pip download` left this wheel.
    WheelDownloaded { project: &'a str, wheel: &'a Path },
    /// `discover`: a `.deb` not unpacked before is being unpacked.
    Unpacking { deb: &'a Path },
    /// `discover`: that unpacking finished.
    Unpacked { deb: &'a Path, seconds: f64 },
    /// `build_from_cache`: allowed packages absent from the cache (the build goes on without
    /// them).
    NotInCache { packages: &'a [String] },
    /// `build`: the package's mesh files start being read (not sent for a cached package).
    ReadingStarted { package: &'a str, mesh_files: u64 },
    /// `build`: `count` more mesh files of that package were read.
    MeshesRead { count: u64 },
    /// `build`: all of that package's mesh files were read.
    ReadingFinished { package: &'a str },
    /// `build`: one package is done (processed or taken from the cache).
    PackageDone {
        package: &'a str,
        /// Files seen, archive members included.
        files: u64,
        mesh_files: u64,
        passed_filter: u64,
        from_cache: bool,
        seconds: f64,
    },
}
