//! When the kernels may use a second thread.
//!
//! The solves ([`crate::SolveThreads::Automatic`]) and `qeig`'s Gram–Schmidt passes split
//! long sweeps between the calling thread and one helper. That pays only on a machine with a
//! second core, and not inside a parallel region that already keeps the cores busy (a rayon
//! worker, for example one problem of a parallel batch). [`set_second_thread_allowed`] turns
//! it off for the whole process (for one-thread benchmarks, or when the caller runs its own
//! threads), like faer's `set_global_parallelism`; [`on_one_thread`] turns it off for one
//! computation on the calling thread (a Python call asked to use one thread, say).
//!
//! The helper is one thread that lives as long as the process ([`join`]): starting a thread
//! for every split sweep cost 50–90 µs here, as much as a whole triangular solve of a
//! 3,000-vertex Laplacian, while handing work to a waiting helper costs a few microseconds.
//! Between two pieces of work it waits by spinning for a few microseconds, then sleeps (`park`).

use std::cell::{Cell, UnsafeCell};
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicPtr, Ordering};
use std::thread::Thread;
use std::time::{Duration, Instant};

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

/// Stored reals of a sparse operand (a factor to solve with, a matrix to multiply by) from
/// which its sweeps are split between two threads, with the waiting helper ([`join`]).
/// Handing half a sweep to the helper costs a few microseconds, where starting a thread cost
/// 50–90 µs (and the threshold was 2¹⁹). Chosen on whole spectra, where solves and products
/// follow each other closely: Laplace spectra of 3k–11k-vertex meshes (factors of 90k–400k
/// reals) ran 1–18 % faster with it on a quiet machine (docs/PERFORMANCE.md, "A helper thread
/// that stays"); an isolated solve of a 23k-real factor does not gain. Solves and products
/// share it so that one Lanczos step's kernels split alike.
pub const SPLIT_REALS: usize = 1 << 16;

/// How long a waiting thread spins before it sleeps: long enough to span the gap between two
/// split kernels that follow each other (the two triangular solves of an operator application),
/// short enough that a helper spinning in vain costs little on a machine whose other core is
/// busy. Measured on an AMD EPYC host (docs/PERFORMANCE.md, "A helper thread that stays"): 50 µs
/// made small Laplace spectra 8–20 % faster on a quiet machine and 5–15 % slower with another
/// process busy; 10 µs gives 1–18 % and 0–6 %.
const SPIN: Duration = Duration::from_micros(10);

/// The use of the helper thread, held by one caller at a time ([`Lease::take`]).
struct Lease {
    helper: &'static Helper,
}

/// The process's helper thread.
struct Helper {
    /// The process that started the helper: a child made by `fork` (Python's
    /// `multiprocessing`, say) has a copy of this record but not the thread.
    process: u32,
    thread: Thread,
    /// Whether a [`Lease`] is out.
    leased: AtomicBool,
}

static HELPER: OnceLock<Option<Helper>> = OnceLock::new();

/// The job handed to the helper and not yet taken, or null.
static MAILBOX: AtomicPtr<Job> = AtomicPtr::new(std::ptr::null_mut());

/// `(first(), second())` for two independent pieces of work: `second` on the helper thread
/// while `first` runs on the calling thread, if the helper is free and takes `second` up
/// before `first` is done; otherwise the calling thread runs `second` after `first`. So a
/// helper that is asleep, descheduled on a busy machine, or used by another computation
/// costs a few microseconds, never a wait. Both have finished when this returns; a panic in
/// either is raised again here, once the other has ended (or, if `first` panicked before
/// `second` started, without running `second`).
///
/// Which thread runs `second` does not change what it computes. Callers decide whether two
/// threads pay ([`second_thread_allowed`] and the size of the work).
pub fn join<RA, RB: Send>(
    first: impl FnOnce() -> RA,
    second: impl FnOnce() -> RB + Send,
) -> (RA, RB) {
    Halves::Independent.run(first, second)
}

/// [`join`] for two halves that wait for each other (the split Gram–Schmidt sweep exchanges
/// coefficients after every pair of columns), so they must run at the same time: on the
/// helper thread if it is free, else on a thread started for the purpose.
pub fn join_concurrently<RA, RB: Send>(
    first: impl FnOnce() -> RA,
    second: impl FnOnce() -> RB + Send,
) -> (RA, RB) {
    Halves::Concurrent.run(first, second)
}

/// Whether the calling thread may run the second half itself ([`join`]) or the two must
/// run at the same time ([`join_concurrently`]).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Halves {
    Independent,
    Concurrent,
}

impl Halves {
    /// `(first(), second())` on the helper if it is free; otherwise independent halves one
    /// after the other on the calling thread, concurrent ones on a thread started for them.
    fn run<RA, RB: Send>(
        self,
        first: impl FnOnce() -> RA,
        second: impl FnOnce() -> RB + Send,
    ) -> (RA, RB) {
        match (Lease::take(), self) {
            (Some(lease), _) => lease.join(first, second, self),
            (None, Halves::Independent) => (first(), second()),
            (None, Halves::Concurrent) => std::thread::scope(|scope| {
                let helper = scope.spawn(second);
                let first = catch_unwind(AssertUnwindSafe(first));
                both(first, helper.join())
            }),
        }
    }
}

/// Both results, or the first panic raised again.
fn both<RA, RB>(first: std::thread::Result<RA>, second: std::thread::Result<RB>) -> (RA, RB) {
    match (first, second) {
        (Ok(a), Ok(b)) => (a, b),
        (Err(panic), _) | (_, Err(panic)) => resume_unwind(panic),
    }
}

impl Lease {
    /// The helper thread, if it could be started, belongs to this process and is free.
    fn take() -> Option<Lease> {
        let helper = HELPER.get_or_init(start_helper).as_ref()?;
        let free = helper.process == std::process::id()
            && helper
                .leased
                .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
                .is_ok();
        // Not `then_some`: a `Lease` made and dropped when it is not free would free it.
        free.then(|| Lease { helper })
    }

    /// Hands `second` to the helper through the mailbox and runs `first`. Then independent
    /// halves take `second` back if the helper has not taken it yet; otherwise this waits for
    /// the helper to report `second` done (the task lives on this stack until then).
    fn join<RA, RB: Send, B: FnOnce() -> RB + Send>(
        self,
        first: impl FnOnce() -> RA,
        second: B,
        halves: Halves,
    ) -> (RA, RB) {
        let mut task = Task {
            job: Job {
                run: run_task::<B, RB>,
                done: AtomicBool::new(false),
                caller: std::thread::current(),
            },
            work: UnsafeCell::new(Some(second)),
            result: UnsafeCell::new(None),
        };
        // From the whole task, not its `job` field: the helper reaches `work` and `result`.
        let job = std::ptr::from_ref(&task).cast::<Job>().cast_mut();
        MAILBOX.store(job, Ordering::Release);
        self.helper.thread.unpark();
        let first = catch_unwind(AssertUnwindSafe(first));
        let taken_back = halves == Halves::Independent
            && MAILBOX
                .compare_exchange(
                    job,
                    std::ptr::null_mut(),
                    Ordering::Acquire,
                    Ordering::Relaxed,
                )
                .is_ok();
        if taken_back {
            // The helper never saw the task: it is this thread's alone again.
            let second = task.work.get_mut().take().expect("the work is here");
            let first = first.unwrap_or_else(|panic| resume_unwind(panic));
            return (first, second());
        }
        wait_until(|| task.job.done.load(Ordering::Acquire).then_some(()));
        both(
            first,
            task.result.into_inner().expect("the helper ran the job"),
        )
    }
}

impl Drop for Lease {
    fn drop(&mut self) {
        self.helper.leased.store(false, Ordering::Release);
    }
}

/// What the helper is handed: the type-erased entry of a [`Task`].
struct Job {
    /// Runs the task whose `job` this is.
    run: unsafe fn(*const Job),
    /// Set by the helper when the task has run; the task may be gone right after.
    done: AtomicBool,
    caller: Thread,
}

/// A job with its work and result, on the caller's stack for the duration of [`Lease::join`].
#[repr(C)]
struct Task<F, R> {
    /// First, so that a pointer to it is a pointer to the task.
    job: Job,
    work: UnsafeCell<Option<F>>,
    result: UnsafeCell<Option<std::thread::Result<R>>>,
}

/// # Safety
/// `job` is the `job` of a live `Task<F, R>` that no other thread touches until `done` is set.
unsafe fn run_task<F: FnOnce() -> R, R>(job: *const Job) {
    // SAFETY: the caller's contract; `Task` is `repr(C)` with `job` first.
    let task = unsafe { &*job.cast::<Task<F, R>>() };
    // SAFETY: until `done`, only this thread uses `work` and `result`.
    let work = unsafe { (*task.work.get()).take() }.expect("a job runs once");
    let result = catch_unwind(AssertUnwindSafe(work));
    unsafe { *task.result.get() = Some(result) };
}

fn start_helper() -> Option<Helper> {
    let spawned = std::thread::Builder::new()
        .name("qsparse helper".into())
        .spawn(serve);
    spawned.ok().map(|handle| Helper {
        process: std::process::id(),
        thread: handle.thread().clone(),
        leased: AtomicBool::new(false),
    })
}

/// The helper's life: take a job, run it, report it done.
fn serve() {
    loop {
        let job = wait_until(|| {
            let job = MAILBOX.swap(std::ptr::null_mut(), Ordering::Acquire);
            (!job.is_null()).then_some(job)
        });
        // SAFETY: a published job belongs to a `Task` whose caller waits for `done`.
        unsafe {
            ((*job).run)(job);
            let caller = (*job).caller.clone();
            (*job).done.store(true, Ordering::Release);
            caller.unpark();
        }
    }
}

/// The first `Some` of `ready()`: asked in a loop for [`SPIN`], then after each wake-up.
/// Whoever makes `ready` true unparks the waiting thread afterwards.
fn wait_until<T>(mut ready: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(value) = ready() {
            return value;
        }
        if start.elapsed() < SPIN {
            std::hint::spin_loop();
        } else {
            std::thread::park();
        }
    }
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
    let (mut results, rest) = join(
        || on_one_thread(|| items.into_iter().map(f).collect::<Vec<R>>()),
        || on_one_thread(|| second.into_iter().map(f).collect::<Vec<R>>()),
    );
    results.extend(rest);
    results
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

    /// Halves that wait for each other run at the same time, on the helper or, while
    /// another caller holds it, on a thread of their own; a nested call works.
    #[test]
    fn concurrent_halves_run_at_the_same_time() {
        let meet = |barrier: &std::sync::Barrier, value: usize| {
            barrier.wait();
            value
        };
        std::thread::scope(|scope| {
            for caller in 0..4 {
                scope.spawn(move || {
                    for round in 0..50 {
                        let barrier = std::sync::Barrier::new(2);
                        let (a, (b, c)) = join_concurrently(
                            || meet(&barrier, caller),
                            || join_concurrently(|| meet(&barrier, round), || round + 1),
                        );
                        assert_eq!((a, b, c), (caller, round, round + 1));
                    }
                });
            }
        });
    }

    /// Independent halves give both results whether the helper runs the second, the caller
    /// takes it back, or the helper is held by another computation (here one that cannot
    /// finish before this `join` does).
    #[test]
    fn independent_halves_finish_whoever_runs_them() {
        use std::sync::atomic::AtomicUsize;
        let released = AtomicBool::new(false);
        let calls = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            scope.spawn(|| {
                join_concurrently(
                    || {},
                    || {
                        while !released.load(Ordering::Acquire) {
                            std::thread::yield_now();
                        }
                    },
                )
            });
            for round in 0..200 {
                let (a, b) = join(
                    || round * 2,
                    || {
                        calls.fetch_add(1, Ordering::Relaxed);
                        round * 3
                    },
                );
                assert_eq!((a, b), (round * 2, round * 3));
            }
            released.store(true, Ordering::Release);
        });
        assert_eq!(calls.load(Ordering::Relaxed), 200);
        assert_eq!(join(|| 1, || 2), (1, 2));
    }

    /// A panic on either side reaches the caller, after the other side has finished when
    /// the two run at the same time, and the helper serves the next caller.
    #[test]
    fn a_panic_of_either_half_is_raised_again() {
        use std::sync::atomic::AtomicUsize;
        let finished = AtomicUsize::new(0);
        let slow = || {
            std::thread::sleep(Duration::from_millis(20));
            finished.fetch_add(1, Ordering::SeqCst);
        };
        let first = catch_unwind(AssertUnwindSafe(|| {
            join_concurrently(|| panic!("first"), slow)
        }));
        assert!(first.is_err());
        assert_eq!(finished.load(Ordering::SeqCst), 1);
        let second = catch_unwind(AssertUnwindSafe(|| {
            join_concurrently(slow, || panic!("second"))
        }));
        assert!(second.is_err());
        assert_eq!(finished.load(Ordering::SeqCst), 2);
        assert!(catch_unwind(AssertUnwindSafe(|| join(|| panic!("first"), slow))).is_err());
        assert!(catch_unwind(AssertUnwindSafe(|| join(slow, || panic!("second")))).is_err());
        assert_eq!(join(|| 1, || 2), (1, 2));
        assert_eq!(join_concurrently(|| 1, || 2), (1, 2));
    }
}
