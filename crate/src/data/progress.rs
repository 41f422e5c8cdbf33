//! What the data build reports while it works. The library prints nothing: `fetch`,
//! `discover` and `build` call an observer (`&mut dyn FnMut(DataEvent)`) with these events,
//! always on the caller's thread, and the caller shows them (the CLI prints a line or draws a
//! progress bar).

use std::fmt;
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

/// The line the CLI prints for the event; empty for the events it shows as a progress bar
/// (`ReadingStarted`, `MeshesRead`, `ReadingFinished`) and for an unpacking of at most 1 s.
impl fmt::Display for DataEvent<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            DataEvent::DebPresent { package, version } => {
                write!(f, "{package} {version}: present, SHA256 ok")
            }
            DataEvent::DebDownloading { package, version } => {
                write!(f, "{package} {version}: downloading ...")
            }
            DataEvent::DebDownloaded {
                package,
                version,
                bytes,
                seconds,
            } => write!(
                f,
                "{package} {version}: downloaded {} MB in {seconds:.0} s",
                bytes >> 20
            ),
            DataEvent::WheelPresent { project, wheel } => {
                write!(f, "{project}: present ({})", wheel.display())
            }
            DataEvent::WheelDownloading { project } => write!(f, "{project}: downloading ..."),
            DataEvent::WheelDownloaded { project, wheel } => {
                write!(f, "{project}: downloaded {}", wheel.display())
            }
            DataEvent::Unpacking { deb } => {
                let name = deb.file_name().unwrap_or_default().to_string_lossy();
                write!(f, "unpacking {name} ...")
            }
            DataEvent::Unpacked { seconds, .. } if seconds > 1.0 => {
                write!(f, "  unpacked in {seconds:.0} s")
            }
            DataEvent::NotInCache { packages } => {
                write!(f, "not in the cache (skipped): {}", packages.join(", "))
            }
            DataEvent::PackageDone {
                package,
                files,
                mesh_files,
                passed_filter,
                from_cache,
                seconds,
            } => write!(
                f,
                "{package:<24} {files:>7} files, {mesh_files:>6} mesh files, \
                 {passed_filter:>6} passed the filter{} ({seconds:.1} s)",
                if from_cache { ", cached" } else { "" },
            ),
            DataEvent::Unpacked { .. }
            | DataEvent::ReadingStarted { .. }
            | DataEvent::MeshesRead { .. }
            | DataEvent::ReadingFinished { .. } => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_read_as_the_cli_prints_them() {
        let done = DataEvent::PackageDone {
            package: "blender-data",
            files: 1234,
            mesh_files: 56,
            passed_filter: 7,
            from_cache: true,
            seconds: 2.31,
        };
        assert_eq!(
            done.to_string(),
            "blender-data                1234 files,     56 mesh files,      7 passed the filter, \
             cached (2.3 s)"
        );
        let deb = DataEvent::Unpacking {
            deb: Path::new("/cache/x_1.0_all.deb"),
        };
        assert_eq!(deb.to_string(), "unpacking x_1.0_all.deb ...");
        assert_eq!(DataEvent::MeshesRead { count: 3 }.to_string(), "");
        let quick = DataEvent::Unpacked {
            deb: Path::new("x.deb"),
            seconds: 0.5,
        };
        assert_eq!(quick.to_string(), "");
    }
}
