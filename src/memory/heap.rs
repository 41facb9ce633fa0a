//! How the C allocator (glibc's `malloc`, which Rust's default allocator
//! calls) treats the big blocks a million bodies need.
//!
//! By default glibc serves blocks of up to 32 MiB from its heap once a few
//! have been freed, and keeps what is freed there for reuse: a table column
//! that doubles as shattering spawns fragments then leaves its old copy
//! resident beside the new one, and the temporaries of loading a scene stay
//! resident for the whole run. [`hand_back_big_blocks`] makes every block
//! of [`BIG_BLOCK`] (1 MiB) or more a mapping of its own: freed, it goes
//! back to the system at once, and grown, it is moved by the kernel without
//! a copy. Smaller blocks stay on the heap, and its free top is kept up to
//! [`KEPT_FREE`] (glibc's default, once told where big blocks start, would
//! hand back all but 128 KiB, so that the scratch an update allocates and
//! frees, a few MiB at a million bodies, would fault in fresh pages every
//! update). All threads share one heap ([`HEAPS`]), so that what a worker
//! frees serves the next block any thread asks for. Buffers the stages keep
//! between updates are allocated once and are not affected;
//! docs/benchmarks.md ("The update near its limit") has the measurements.
//! Elsewhere than on Linux with glibc, both functions do nothing.

/// The smallest block given a mapping of its own, in bytes. The scratch an
/// update allocates and frees stays below it (the filing's slots, 16 bytes
/// a cell for each chunk of boxes) up to the grid's most cells, 65 536 (a
/// few million bodies), where each chunk's reaches it.
pub const BIG_BLOCK: usize = 1 << 20;

/// Free memory kept at the top of the heap for the next blocks, in bytes.
pub const KEPT_FREE: usize = 64 << 20;

/// Heaps the allocator keeps, for all threads together. glibc's default
/// gives threads heaps of their own (up to eight a core), each keeping
/// what its thread freed: the scratch the workers of a parallel update
/// allocate and free was then resident once per worker (about 5 MB at a
/// million bodies on two threads). An update allocates a few blocks a
/// chunk, so the one heap's lock is not contended.
pub const HEAPS: usize = 1;

/// Makes blocks of [`BIG_BLOCK`] bytes or more mappings of their own, keeps
/// [`KEPT_FREE`] bytes free at the heap's top and has every thread share
/// [`HEAPS`] heap, for the whole process. Called once, first thing, by the
/// binary, before it starts any thread.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
pub fn hand_back_big_blocks() {
    for (parameter, bytes) in [
        (libc::M_MMAP_THRESHOLD, BIG_BLOCK),
        (libc::M_TRIM_THRESHOLD, KEPT_FREE),
        (libc::M_ARENA_MAX, HEAPS),
    ] {
        // SAFETY: `mallopt` is glibc's (this function is built for glibc
        // targets only); it takes two plain integers and changes only the
        // allocator's own parameters, under its lock. Thresholds below
        // `c_int::MAX` and a positive heap count are valid; blocks already
        // allocated are unaffected.
        #[expect(unsafe_code, reason = "glibc's mallopt, a foreign function")]
        let done = unsafe { libc::mallopt(parameter, bytes as libc::c_int) };
        // On failure (0) the allocator keeps that default: other memory
        // use, the same results.
        let _ = done;
    }
}

/// Does nothing: the settings are glibc's.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
pub fn hand_back_big_blocks() {}

/// Hands freed heap memory back to the system. glibc's allocator keeps
/// what was freed below [`BIG_BLOCK`]; without this, a benchmark's later
/// runs would count it in their peak.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
pub fn release_free_memory() {
    // SAFETY: `malloc_trim` is glibc's (this function is built for glibc
    // targets only), takes a plain integer, touches only the allocator's
    // own free lists under the allocator's lock, and may be called at any
    // time from any thread.
    #[expect(unsafe_code, reason = "glibc's malloc_trim, a foreign function")]
    unsafe {
        libc::malloc_trim(0);
    }
}

/// Does nothing: `malloc_trim` is glibc's.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
pub fn release_free_memory() {}
