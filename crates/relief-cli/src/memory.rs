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
//! Every thread also allocates from one arena. By default glibc gives each thread that allocates
//! while another holds the lock an arena of its own, and a block freed there serves only that
//! arena's later requests; rayon runs each job on whichever worker is free, so a grid freed by one
//! worker went unused while the next one faulted in fresh pages. A first 2048² `relief diffuse`
//! of `volcanic-island-48` took 105 k page faults with an arena per thread and 74 k with one
//! (`mountain` 125 k → 80–93 k); the diffusion stage's time changed within the VM's noise (2
//! cores: 484–549 against 471–507 ms), and so did `relief demo` and a small `relief vectorize`:
//! no contention on the one arena's lock showed in those runs.
//!
//! This is the one `unsafe` call in the workspace: glibc's `mallopt` has no safe binding. Other
//! platforms and C libraries keep their allocator's defaults.

/// Sets the allocator up as the module docs say. Call it first thing in `main`.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
pub(crate) fn keep_freed_memory() {
    #[allow(unsafe_code, reason = "glibc's mallopt has no safe binding; see the SAFETY note")]
    // SAFETY: `mallopt` only sets allocator parameters (every value is in the range glibc
    // documents; it returns 0 and changes nothing otherwise). It is called before any other thread
    // exists, and glibc takes its arena lock for the change either way.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 1 << 30);
        libc::mallopt(libc::M_ARENA_MAX, 1);
    }
}

/// Elsewhere the allocator keeps its defaults.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
pub(crate) fn keep_freed_memory() {}
