//! When the kernels may use a second thread.
//!
//! The solves ([`crate::SolveThreads::Automatic`]) and `qeig`'s Gram–Schmidt passes split
//! long sweeps between the calling thread and one helper. That pays only on a machine with a
//! second core, and not inside a parallel region that already keeps the cores busy (a rayon
//! worker, for example one problem of a parallel batch).

use std::sync::OnceLock;

/// Whether a second thread may help: at least two cores, and the caller is not a rayon
/// worker thread.
pub fn second_thread_allowed() -> bool {
    static CORES: OnceLock<usize> = OnceLock::new();
    let cores = *CORES
        .get_or_init(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get));
    cores >= 2 && rayon::current_thread_index().is_none()
}
