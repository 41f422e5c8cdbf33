//! The C allocator's policy for this process: keep freed memory for reuse.
//!
//! Burn's CPU backend allocates a fresh buffer for most tensor operations and frees it soon
//! after, many of them megabytes large. With glibc's defaults such a buffer is mapped from the
//! kernel and unmapped on free (above a threshold that adapts only up to the largest block
//! freed so far), and freed memory at the top of the heap goes back to the kernel: each new
//! buffer then costs a page fault and a zeroed page per 4 KiB. Measuring 30 steps of the VAE's
//! first stage made 530,000 page faults by default and 151,000 with the policy below, which
//! also stops one decode's freed buffers from changing the speed of the next stages
//! (BENCHMARKS.md, "The pair head without its input built; freed memory kept"). The process
//! keeps its peak memory until it exits, which a command that runs one job and ends can
//! afford.

/// Serves blocks up to 32 MiB (glibc's largest allowed threshold) from the heap and keeps up
/// to 1 GiB of freed heap. Left as it is when the user sets glibc's own variables
/// (`MALLOC_MMAP_THRESHOLD_`, `MALLOC_TRIM_THRESHOLD_`, `GLIBC_TUNABLES`). Only on
/// glibc targets; a no-op elsewhere. Returns whether glibc took the policy.
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

#[cfg(all(test, target_os = "linux", target_env = "gnu"))]
mod tests {
    /// With the policy, an 8 MiB buffer comes from the heap instead of a mapping of its own
    /// (glibc's default maps it), and freeing it keeps the memory in the process.
    #[test]
    fn a_freed_large_buffer_stays_in_the_process() {
        if !super::keep_freed_memory() {
            eprintln!("glibc's own variables are set: the policy is theirs, nothing to test");
            return;
        }
        let info = || unsafe { libc::mallinfo2() };
        const SIZE: usize = 8 << 20;
        let before = info();
        let buffer = std::hint::black_box(vec![1u8; SIZE]);
        let held = info();
        assert!(
            held.hblkhd < before.hblkhd + SIZE,
            "the buffer was mapped on its own ({} -> {} bytes mapped)",
            before.hblkhd,
            held.hblkhd
        );
        drop(buffer);
        let after = info();
        assert!(
            after.fordblks + SIZE / 2 >= held.fordblks + SIZE,
            "the freed buffer went back to the kernel ({} -> {} bytes free in the heap)",
            held.fordblks,
            after.fordblks
        );
    }
}
