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

/// `f` of every item, in order; the items are split in two halves between the calling thread
/// and one helper when [`second_thread_allowed`] and there are at least two of them.
///
/// For independent work of similar size per item, such as the products and residuals of many
/// eigenpairs after a solve (each a sparse product or two). Items may be references, mutable
/// ones included. While the two halves run, the kernels inside `f` are kept on one thread
/// each ([`on_one_thread`]): both cores are busy already.
pub fn map_on_two_threads<T: Send, R: Send>(
    mut items: Vec<T>,
    f: impl Fn(T) -> R + Sync,
) -> Vec<R> {
    if items.len() < 2 || !second_thread_allowed() {
        return items.into_iter().map(f).collect();
    }
    let second = items.split_off(items.len() / 2);
    let f = &f;
    std::thread::scope(|scope| {
        let helper =
            scope.spawn(move || on_one_thread(|| second.into_iter().map(f).collect::<Vec<R>>()));
        let mut results: Vec<R> = on_one_thread(|| items.into_iter().map(f).collect());
        // A panic in `f` on the helper is raised again here, as on the calling thread.
        results.extend(
            helper
                .join()
                .unwrap_or_else(|p| std::panic::resume_unwind(p)),
        );
        results
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every item is mapped once, in order, on two threads and on one; mutable references
    /// are written through.
    #[test]
    fn split_work_is_the_sequential_work() {
        for count in [0usize, 1, 2, 3, 10, 101] {
            let items: Vec<usize> = (0..count).collect();
            let squares: Vec<usize> = items.iter().map(|i| i * i).collect();
            assert_eq!(map_on_two_threads(items.clone(), |i| i * i), squares);
            let one = on_one_thread(|| map_on_two_threads(items.clone(), |i| i * i));
            assert_eq!(one, squares);
            let mut doubled = items.clone();
            map_on_two_threads(doubled.iter_mut().collect(), |i| *i *= 2);
            assert_eq!(doubled, items.iter().map(|i| 2 * i).collect::<Vec<_>>());
        }
    }
}
