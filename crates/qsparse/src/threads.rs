//! When the kernels may use a second thread.
//!
//! The solves ([`crate::SolveThreads::Automatic`]) and `qeig`'s Gram–Schmidt passes split
//! long sweeps between the calling thread and one helper. That pays only on a machine with a
//! second core, and not inside a parallel region that already keeps the cores busy (a rayon
//! worker, for example one problem of a parallel batch). [`set_second_thread_allowed`] turns
//! it off for the whole process (for one-thread benchmarks, or when the caller runs its own
//! threads), like faer's `set_global_parallelism`; [`on_one_thread`] turns it off for one
//! computation on the calling thread (a Python call asked to use one thread, say).

use std::cell::Cell;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

static ALLOWED: AtomicBool = AtomicBool::new(true);

thread_local! {
    /// Set while [`on_one_thread`] runs on this thread.
    static ONE_THREAD: Cell<bool> = const { Cell::new(false) };
}

/// Runs `work` on the calling thread with the second thread forbidden for it (other threads
/// are unaffected); the previous setting is restored afterwards, also on a panic.
pub fn on_one_thread<T>(work: impl FnOnce() -> T) -> T {
    struct Restore(bool);
    impl Drop for Restore {
        fn drop(&mut self) {
            ONE_THREAD.set(self.0);
        }
    }
    let _restore = Restore(ONE_THREAD.replace(true));
    work()
}

/// Allows (the default) or forbids the second thread, process-wide.
pub fn set_second_thread_allowed(allowed: bool) {
    ALLOWED.store(allowed, Ordering::Relaxed);
}

/// Whether a second thread may help: allowed ([`set_second_thread_allowed`]), not inside
/// [`on_one_thread`], at least two cores, and the caller is not a rayon worker thread.
pub fn second_thread_allowed() -> bool {
    static CORES: OnceLock<usize> = OnceLock::new();
    let cores = *CORES
        .get_or_init(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get));
    ALLOWED.load(Ordering::Relaxed)
        && !ONE_THREAD.get()
        && cores >= 2
        && rayon::current_thread_index().is_none()
}
