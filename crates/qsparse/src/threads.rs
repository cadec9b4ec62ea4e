//! When the kernels may use a second thread.
//!
//! The solves ([`crate::SolveThreads::Automatic`]) and `qeig`'s Gram–Schmidt passes split
//! long sweeps between the calling thread and one helper. That pays only on a machine with a
//! second core, and not inside a parallel region that already keeps the cores busy (a rayon
//! worker, for example one problem of a parallel batch). [`set_second_thread_allowed`] turns
//! it off for the whole process (for one-thread benchmarks, or when the caller runs its own
//! threads), like faer's `set_global_parallelism`.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

static ALLOWED: AtomicBool = AtomicBool::new(true);

/// Allows (the default) or forbids the second thread, process-wide.
pub fn set_second_thread_allowed(allowed: bool) {
    ALLOWED.store(allowed, Ordering::Relaxed);
}

/// Whether a second thread may help: allowed ([`set_second_thread_allowed`]), at least two
/// cores, and the caller is not a rayon worker thread.
pub fn second_thread_allowed() -> bool {
    static CORES: OnceLock<usize> = OnceLock::new();
    let cores = *CORES
        .get_or_init(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get));
    ALLOWED.load(Ordering::Relaxed) && cores >= 2 && rayon::current_thread_index().is_none()
}
