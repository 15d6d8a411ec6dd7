//! Where the process's long vectors live: the C library's allocator is told to map every
//! allocation of at least [`MAPPED_BYTES`] on its own and to unmap it when freed, so a fine
//! patch's vectors (8 MB each at 1024 x 1024) go back to the system when a Newton step frees
//! them instead of staying in the allocator's heap.
//!
//! The GNU C library starts with such a threshold (128 KiB) but raises it to the size of each
//! mapped block freed, up to 32 MiB: after a solve's first step every vector of a fine patch
//! is then carved from the heap, whose freed space is kept (and counted in the process's
//! resident memory) rather than returned. Measured on the frictionless Hertz patch of
//! 1024 x 1024 elements (2 cores): the whole `grasp solve` process peaked at 538 MB with the
//! moving threshold and at 428 MB with this fixed one, for 0.4 s more of the kernel's time
//! (513,000 page faults against 321,000: a freed long vector's pages are faulted in again
//! when the next one is made). The vectors a solve reuses from one Newton step to the next
//! are kept by the solver itself (its work vectors), which this does not touch.

/// Allocations of at least this many bytes are mapped on their own (4 MiB: a 512 x 512
/// patch's vectors, 2 MiB, stay in the heap).
const MAPPED_BYTES: i32 = 4 << 20;

/// Fixes the allocator's mapping threshold at [`MAPPED_BYTES`] (GNU C library only; elsewhere
/// nothing is done).
pub fn return_long_vectors_to_the_system() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `mallopt` only sets an allocator parameter; it is called before any thread
    // starts (the first thing `main` does).
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MAPPED_BYTES);
    }
}
