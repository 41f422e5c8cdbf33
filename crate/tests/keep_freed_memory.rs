//! `device::keep_freed_memory`, in a test binary of its own: the allocator's figures are the
//! whole process's, so no other test may allocate beside it.

/// With the policy, an 8 MiB buffer comes from the heap instead of a mapping of its own
/// (glibc's default maps it), and freeing it keeps the memory in the process.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[test]
fn a_freed_large_buffer_stays_in_the_process() {
    if !meshflow::device::keep_freed_memory() {
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
