//! A global allocator that counts allocations, for tests that prove a function allocates
//! nothing (STYLE.md: "no allocation per frame").
//!
//! [`CountingAlloc`] forwards every request to [`System`] and, while the *calling thread* is
//! inside [`count`], also counts it. Install it in the test binary that uses it (a global
//! allocator applies to the whole binary, so keep such tests in their own file under
//! `tests/`):
//!
//! ```
//! use counting_alloc::{count, CountingAlloc};
//!
//! #[global_allocator]
//! static ALLOCATOR: CountingAlloc = CountingAlloc;
//!
//! fn main() {
//!     let (v, counts) = count(|| std::hint::black_box(vec![1.0; 8]));
//!     assert_eq!(counts.allocations, 1);
//!     let (sum, counts) = count(|| v.iter().sum::<f64>());
//!     assert_eq!((sum, counts.allocations), (8.0, 0));
//! }
//! ```
//!
//! Counting is per thread: test threads running in parallel do not disturb each other, and
//! work that the counted function hands to other threads is not counted. Without the
//! allocator installed nothing is ever counted, so a test should also check that its counter
//! sees an allocation it makes on purpose.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::thread::LocalKey;

/// The system allocator, counting the requests of a thread while it is inside [`count`].
#[derive(Clone, Copy, Debug, Default)]
pub struct CountingAlloc;

/// Requests counted by [`count`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// `alloc`, `alloc_zeroed` and `realloc` calls.
    pub allocations: u64,
    /// `dealloc` calls.
    pub deallocations: u64,
}

// Constant-initialised thread-locals without destructors: reading them never allocates, so
// the allocator can use them.
thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
    static DEALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

/// Adds one to `counter` if this thread is counting.
fn record(counter: &'static LocalKey<Cell<u64>>) {
    // `try_with`: during thread teardown the thread-locals may be gone; nothing is counted then.
    let counting = COUNTING.try_with(Cell::get).unwrap_or(false);
    if counting {
        let _ = counter.try_with(|c| c.set(c.get() + 1));
    }
}

// SAFETY: every method forwards its arguments unchanged to `System`, which upholds the
// `GlobalAlloc` contract; the counting touches only thread-local `Cell`s and never allocates.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        record(&ALLOCATIONS);
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        record(&ALLOCATIONS);
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        record(&ALLOCATIONS);
        // SAFETY: forwarded with the caller's guarantees (`ptr` came from `System` through us).
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        record(&DEALLOCATIONS);
        // SAFETY: forwarded with the caller's guarantees (`ptr` came from `System` through us).
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Restores the thread's counting state when dropped (also when `f` panics).
struct Window {
    was_counting: bool,
    allocations: u64,
    deallocations: u64,
}

impl Drop for Window {
    fn drop(&mut self) {
        COUNTING.with(|c| c.set(self.was_counting));
        ALLOCATIONS.with(|c| c.set(c.get() + self.allocations));
        DEALLOCATIONS.with(|c| c.set(c.get() + self.deallocations));
    }
}

/// Runs `f` and returns its result with the allocator requests it made on this thread. Counts
/// nothing unless [`CountingAlloc`] is the binary's global allocator. Windows may nest: an
/// inner window's requests count in the outer one too.
pub fn count<R>(f: impl FnOnce() -> R) -> (R, Counts) {
    let window = Window {
        was_counting: COUNTING.with(Cell::get),
        allocations: ALLOCATIONS.with(|c| c.replace(0)),
        deallocations: DEALLOCATIONS.with(|c| c.replace(0)),
    };
    COUNTING.with(|c| c.set(true));
    let result = f();
    COUNTING.with(|c| c.set(false));
    let counts = Counts {
        allocations: ALLOCATIONS.with(Cell::get),
        deallocations: DEALLOCATIONS.with(Cell::get),
    };
    drop(window);
    (result, counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::hint::black_box;

    #[global_allocator]
    static ALLOCATOR: CountingAlloc = CountingAlloc;

    #[test]
    fn count_sees_allocations_and_frees() {
        let (v, counts) = count(|| black_box(vec![1.0f64; 16]));
        assert_eq!(
            counts,
            Counts {
                allocations: 1,
                deallocations: 0
            }
        );
        let ((), counts) = count(|| drop(black_box(v)));
        assert_eq!(counts.deallocations, 1);
        // Growing a vector reallocates.
        let (_, counts) = count(|| {
            let mut v = black_box(Vec::<u64>::with_capacity(1));
            v.extend(0..1000);
            black_box(v)
        });
        assert!(counts.allocations >= 2, "{counts:?}");
    }

    #[test]
    fn count_of_arithmetic_is_zero() {
        let (sum, counts) = count(|| (0..1000u64).map(black_box).sum::<u64>());
        assert_eq!(sum, 499_500);
        assert_eq!(counts, Counts::default());
    }

    #[test]
    fn count_ignores_other_threads_and_outside_work() {
        // Spawning allocates on this thread (a handful of requests); the thousand boxes the
        // spawned thread makes are not ours.
        let (boxes, counts) = count(|| {
            std::thread::spawn(|| (0..1000u64).map(|i| *black_box(Box::new(i))).sum::<u64>())
                .join()
                .unwrap()
        });
        assert_eq!(boxes, 499_500);
        assert!(counts.allocations < 100, "{counts:?}");
        let _outside = black_box(vec![0u8; 64]);
        let (_, counts) = count(|| black_box(1 + 1));
        assert_eq!(counts, Counts::default());
    }

    #[test]
    fn count_nests_and_recovers_from_panics() {
        let (inner, outer) = count(|| {
            let (_, inner) = count(|| black_box(Box::new(1u64)));
            let _second = black_box(Box::new(2u64));
            inner
        });
        assert_eq!(inner.allocations, 1);
        assert_eq!(outer.allocations, 2);
        let panicked = std::panic::catch_unwind(|| count(|| panic!("inside")));
        assert!(panicked.is_err());
        // Not counting any more.
        assert!(!COUNTING.with(Cell::get));
    }
}
