//! Allocator tuning for the command-line process: the one place in the workspace with
//! `unsafe` code, a single call into glibc.
//!
//! glibc maps allocations of 128 KiB or more with their own `mmap`, so that freeing them
//! returns the memory at once, but it raises that threshold to the size of the largest such
//! block freed so far (up to 32 MiB). The first large block `extract` frees is the file's bytes
//! (14 MB for igea.off), then the pipeline's temporaries: from then on the arrays of the later
//! stages come from the heap, where freed blocks stay resident until the top of the heap is
//! free again. On igea this kept about 5.6 MiB that was no longer in use resident at the peak:
//! 215 bytes per face against 193 with the threshold pinned at 128 KiB (`BENCHMARKS.md`,
//! session 6). The price is that every large array is mapped afresh and its pages faulted in
//! again: about 10% of the wall time on igea.
//!
//! Pinning the threshold (any explicit setting turns glibc's adjustment off) keeps every large
//! array a mapping of its own, returned when it is freed. It is done by the binary only: the
//! library does not change the allocator of the program it runs in. Other platforms and C
//! libraries are left alone.

/// Pins glibc's mmap threshold at its default of 128 KiB (see the module docs). Does nothing
/// outside Linux with glibc, or when glibc refuses the setting.
pub fn return_large_blocks_when_freed() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        const THRESHOLD: libc::c_int = 128 * 1024;
        // SAFETY: `mallopt` only changes an allocator parameter; glibc allows it at any time
        // and from any thread, and the value is in its accepted range (0 to 32 MiB). A refusal
        // (return value 0) leaves the defaults, which are correct, only less frugal.
        #[allow(unsafe_code)]
        let _ = unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, THRESHOLD) };
    }
}
