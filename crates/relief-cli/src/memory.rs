//! glibc's allocator told to keep freed memory for reuse, for the large grids every command
//! allocates and frees.
//!
//! By default glibc returns each block over its (adaptive) mmap threshold to the kernel when it
//! is freed, and trims the heap's free top beyond twice that threshold, so the next grid of that
//! size starts from fresh pages: one page fault per 4 KiB on first touch. A 2048² `relief diffuse`
//! frees and re-allocates hundreds of megabytes of grids (constraint maps, the solver's levels and
//! Krylov vectors, the noise parameters), and on a virtual machine those faults are slow. Blocks
//! below 32 MiB (the most glibc allows) now come from the heap, and the heap is trimmed beyond
//! 1 GiB of free top only. Measured on the 2-core VM with `relief -v diffuse
//! fixtures/scenes/mountain-ridges.json --resolution 2048`, six runs each, alternated: the
//! diffusion stage took 717–793 ms with glibc's defaults and 573–769 ms with these settings.
//! The price is memory: a process keeps its freed heap until it exits, and a block freed in one size
//! serves a later one only where it fits, so the peak can rise (`relief prominence` of the resampled
//! Jacksboro DEM, 6.85 M cells: 99 → 110 MiB resident at its peak, `docs/benchmarks.md`).
//!
//! This is the one `unsafe` call in the workspace: glibc's `mallopt` has no safe binding. Other
//! platforms and C libraries keep their allocator's defaults.

/// Sets the allocator up as the module docs say. Call it first thing in `main`.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
pub(crate) fn keep_freed_memory() {
    #[allow(unsafe_code, reason = "glibc's mallopt has no safe binding; see the SAFETY note")]
    // SAFETY: `mallopt` only sets allocator parameters (both values are in the ranges glibc
    // documents; it returns 0 and changes nothing otherwise). It is called before any other thread
    // exists, and glibc takes its arena lock for the change either way.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30);
    }
}

/// Elsewhere the allocator keeps its defaults.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
pub(crate) fn keep_freed_memory() {}
