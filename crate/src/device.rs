//! Where the networks run: Burn's CPU backend (flex; ndarray with the `ndarray` feature, for
//! comparison) or, with the `wgpu` feature, burn-wgpu
//! pinned to Vulkan (lavapipe without a GPU, NVIDIA's driver on a real one). Pinning matters:
//! wgpu would otherwise fall back to OpenGL silently (docs/design.md section 6). On glibc,
//! [`keep_freed_memory`] sets the allocator policy the CPU backend runs fastest with.

use burn::tensor::Device;

/// Which backend a command runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BackendKind {
    /// Burn's flex backend on the CPU.
    Cpu,
    /// burn-wgpu over Vulkan.
    Wgpu,
    /// Burn's ndarray backend on the CPU (feature `ndarray`; kept to measure flex against).
    Ndarray,
}

impl BackendKind {
    /// Every kind, in the order the command line lists them.
    pub const ALL: [BackendKind; 3] = [BackendKind::Cpu, BackendKind::Wgpu, BackendKind::Ndarray];

    /// The name used on the command line and in logs.
    pub fn name(self) -> &'static str {
        match self {
            BackendKind::Cpu => "cpu",
            BackendKind::Wgpu => "wgpu",
            BackendKind::Ndarray => "ndarray",
        }
    }
}

impl std::str::FromStr for BackendKind {
    type Err = String;

    /// The kind called `name` ([`BackendKind::name`]).
    fn from_str(name: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.map(Self::name).to_vec();
                format!(
                    "unknown backend {name:?}: expected one of {}",
                    names.join(", ")
                )
            })
    }
}

/// A device of the given kind. `Wgpu` fails with a message when the build lacks the `wgpu`
/// feature or no Vulkan device can be opened.
pub fn device(kind: BackendKind) -> Result<Device, String> {
    match kind {
        BackendKind::Cpu => cpu(),
        BackendKind::Wgpu => vulkan(),
        BackendKind::Ndarray => ndarray(),
    }
}

/// Burn's flex backend on the CPU.
#[cfg(feature = "cpu")]
pub fn cpu() -> Result<Device, String> {
    Ok(Device::flex())
}

/// Whether `device` is Burn's CPU backend (flex), where a batch is worth splitting over
/// threads; a GPU takes it whole.
#[cfg(feature = "cpu")]
pub fn is_cpu(device: &Device) -> bool {
    *device == Device::flex()
}

/// Without the `cpu` feature there is no CPU device.
#[cfg(not(feature = "cpu"))]
pub fn is_cpu(_device: &Device) -> bool {
    false
}

/// Without the `cpu` feature (the WebGPU browser module, whose CPU path is the separate
/// meshflow_cpu module) there is no CPU backend.
#[cfg(not(feature = "cpu"))]
pub fn cpu() -> Result<Device, String> {
    Err("this build has no CPU backend (build with the `cpu` feature; in the browser the CPU path is meshflow_cpu.js)".into())
}

/// Burn 0.22 deprecates ndarray in favour of flex; it stays reachable for the comparison.
#[cfg(feature = "ndarray")]
#[allow(deprecated)]
fn ndarray() -> Result<Device, String> {
    Ok(Device::ndarray())
}

#[cfg(not(feature = "ndarray"))]
fn ndarray() -> Result<Device, String> {
    Err("this build has no ndarray backend (build the CLI with `--features ndarray`)".into())
}

/// The burn-wgpu device on Vulkan. Burn's runtime can be initialised once per process, so the
/// device is created once and cloned afterwards. (The browser opens WebGPU asynchronously
/// instead, in `web/api.rs`.)
#[cfg(all(feature = "wgpu", not(target_family = "wasm")))]
pub fn vulkan() -> Result<Device, String> {
    use burn::tensor::wgpu::WgpuBackend;
    use std::sync::OnceLock;
    static VULKAN: OnceLock<Result<Device, String>> = OnceLock::new();
    VULKAN
        .get_or_init(|| {
            Device::wgpu_options()
                .graphics_api(WgpuBackend::Vulkan)
                .init()
                .map_err(|e| {
                    format!(
                        "no Vulkan device for burn-wgpu ({e}); install mesa-vulkan-drivers for \
                         lavapipe, or use the CPU backend"
                    )
                })
        })
        .clone()
}

/// Without the `wgpu` feature (or on wasm, where WebGPU opens asynchronously) there is no
/// Vulkan device.
#[cfg(any(not(feature = "wgpu"), target_family = "wasm"))]
pub fn vulkan() -> Result<Device, String> {
    Err("this build has no native wgpu backend (enable the `wgpu` feature)".into())
}

/// The CPU's model name (from `/proc/cpuinfo`; "unknown CPU" elsewhere), for benchmark and
/// training records.
#[cfg(not(target_arch = "wasm32"))]
pub fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

/// The threads the work runs on: the size of rayon's pool, which Burn's CPU backend and the
/// per-input stages share (`RAYON_NUM_THREADS` sets it), not the machine's core count.
#[cfg(not(target_arch = "wasm32"))]
pub fn threads() -> usize {
    rayon::current_num_threads()
}

/// The CPU and the threads the work runs on, as a training manifest or a benchmark records the
/// machine: "`cpu_name`, N threads". N is the thread pool's size (Burn's CPU backend and the
/// per-input stages share rayon's global pool), so a run limited by `RAYON_NUM_THREADS=1`
/// beside another says 1, not the machine's core count.
#[cfg(not(target_arch = "wasm32"))]
pub fn machine_description() -> String {
    let threads = threads();
    let plural = if threads == 1 { "" } else { "s" };
    format!("{}, {threads} thread{plural}", cpu_name())
}

/// Sets the C allocator of this process to keep freed memory for reuse: for a program that runs
/// one job and exits, as the `meshflow` command does (it calls this first).
///
/// Burn's CPU backend allocates a fresh buffer for most tensor operations and frees it soon
/// after, many of them megabytes large. With glibc's defaults such a buffer is mapped from the
/// kernel and unmapped on free (above a threshold that adapts only up to the largest block
/// freed so far), and freed memory at the top of the heap goes back to the kernel: each new
/// buffer then costs a page fault and a zeroed page per 4 KiB. Measuring 30 steps of the VAE's
/// first stage made 530,000 page faults by default and 151,000 with this policy, which also
/// stops one decode's freed buffers from changing the speed of the next stages
/// (docs/experiments/2026-11-29-pair-head-input-and-allocator.md). The process keeps its peak
/// memory until it exits.
///
/// Serves blocks up to 32 MiB (glibc's largest allowed threshold) from the heap and keeps up
/// to 1 GiB of freed heap. Left as it is when the user sets glibc's own variables
/// (`MALLOC_MMAP_THRESHOLD_`, `MALLOC_TRIM_THRESHOLD_`, `GLIBC_TUNABLES`). Only on
/// glibc targets; a no-op elsewhere. Returns whether glibc took the policy; without it only
/// the speed changes.
pub fn keep_freed_memory() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        const VARIABLES: [&str; 3] = [
            "MALLOC_MMAP_THRESHOLD_",
            "MALLOC_TRIM_THRESHOLD_",
            "GLIBC_TUNABLES",
        ];
        if VARIABLES.iter().any(|v| std::env::var_os(v).is_some()) {
            return false;
        }
        // SAFETY: mallopt only sets allocator parameters, under glibc's own lock. A refused
        // value (return 0) leaves glibc's default, which is correct, only slower.
        unsafe {
            libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20) == 1
                && libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30) == 1
        }
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    false
}

#[cfg(test)]
mod tests {
    use super::BackendKind;

    /// Each kind parses back from its command-line name; anything else is refused by name.
    #[test]
    fn backend_names_round_trip() {
        for kind in BackendKind::ALL {
            assert_eq!(kind.name().parse::<BackendKind>(), Ok(kind));
        }
        let err = "gpu".parse::<BackendKind>().unwrap_err();
        assert!(
            err.contains("\"gpu\"") && err.contains("cpu, wgpu, ndarray"),
            "{err}"
        );
    }

    /// The recorded thread count is the pool the work runs in, not the machine's cores.
    #[cfg(not(target_arch = "wasm32"))]
    #[test]
    fn machine_description_counts_the_pool_it_runs_in() {
        let in_pool = |n| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap();
            pool.install(super::machine_description)
        };
        assert!(in_pool(1).ends_with(", 1 thread"), "{}", in_pool(1));
        assert!(in_pool(3).ends_with(", 3 threads"), "{}", in_pool(3));
    }
}
