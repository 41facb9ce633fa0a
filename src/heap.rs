//! How the C allocator (glibc's `malloc`, which Rust's default allocator
//! calls) treats the big blocks a million bodies need.
//!
//! By default glibc serves blocks of up to 32 MiB from its heap once a few
//! have been freed, and keeps what is freed there for reuse: a table column
//! that doubles as shattering spawns fragments then leaves its old copy
//! resident beside the new one, and the temporaries of loading a scene stay
//! resident for the whole run. [`hand_back_big_blocks`] makes every block
//! of [`BIG_BLOCK`] or more a mapping of its own: freed, it goes back to the
//! system at once, and grown, it is moved by the kernel without a copy.
//! Buffers the stages keep between updates are allocated once and are not
//! affected; docs/benchmarks.md ("The update near its limit") has the
//! measurements. Elsewhere than on Linux with glibc, both functions do
//! nothing.

/// The smallest block given a mapping of its own, in bytes.
pub const BIG_BLOCK: usize = 1 << 20;

/// Makes blocks of [`BIG_BLOCK`] bytes or more mappings of their own, for
/// the whole process. Called once, first thing, by the binary.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
pub fn hand_back_big_blocks() {
    // SAFETY: `mallopt` is glibc's (this function is built for glibc
    // targets only); it takes two plain integers and changes only the
    // allocator's own parameters, under its lock. A threshold below
    // `c_int::MAX` is valid; blocks already allocated are unaffected.
    #[expect(unsafe_code, reason = "glibc's mallopt, a foreign function")]
    let done = unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, BIG_BLOCK as libc::c_int) };
    // On failure (0) the allocator keeps its defaults: more memory, same
    // results.
    let _ = done;
}

/// Makes blocks of [`BIG_BLOCK`] bytes or more mappings of their own.
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

/// Hands freed heap memory back to the system.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
pub fn release_free_memory() {}
