//! Allocator tuning for the command-line process: the one place in the workspace with
//! `unsafe` code, a single call into glibc.
//!
//! glibc maps allocations of 128 KiB or more with their own `mmap`, so that freeing them
//! returns the memory at once, but it raises that threshold to the size of the largest such
//! block freed so far (up to 32 MiB). After `extract` frees the file's bytes, the later stages'
//! arrays come from the heap, where freed blocks stay resident until the top of the heap is
//! free again. Pinned, the peak is lower and every large array is faulted in afresh (igea: 215
//! → 193 bytes per face, about 10% more wall time; `docs/benchmarks-history.md`, session 6).
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
