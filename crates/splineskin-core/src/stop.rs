//! Stopping long computations from elsewhere: a [`StopSignal`] shared by the computation and,
//! say, a user interface that no longer wants its result.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Asks a running computation to stop: clones share one flag, so the caller keeps a clone and
/// calls [`StopSignal::raise`]; the computation checks [`StopSignal::is_raised`] between steps
/// (the bounded biharmonic solve between active-set iterations,
/// [`crate::weights::bbw::BbwOptions::stop`]; a deformation operator's training between its
/// ground-truth solves) and returns its crate's `Stopped` error.
///
/// ```
/// use splineskin_core::stop::StopSignal;
/// let signal = StopSignal::new();
/// let held = signal.clone();
/// assert!(!held.is_raised());
/// signal.raise();
/// assert!(held.is_raised());
/// assert_eq!(signal, held);
/// assert_ne!(signal, StopSignal::new());
/// ```
#[derive(Clone, Debug, Default)]
pub struct StopSignal(Arc<AtomicBool>);

impl StopSignal {
    /// A signal not raised, held by nobody else yet.
    pub fn new() -> StopSignal {
        StopSignal::default()
    }

    /// Raises the signal: every holder's computation stops at its next check.
    pub fn raise(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether it was raised.
    pub fn is_raised(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// Where the flag lives in memory: one byte, 0 until raised, 1 after (an `AtomicBool`). A
    /// host sharing the memory raises it by an atomic store of 1 there: the WebAssembly
    /// editor's page does, for a worker it no longer wants, which cannot hear a request while
    /// it computes (`crates/splineskin-wasm`, docs/webassembly.md).
    ///
    /// ```
    /// use splineskin_core::stop::StopSignal;
    /// let signal = StopSignal::new();
    /// assert_eq!(signal.address(), signal.clone().address());
    /// assert_ne!(signal.address(), StopSignal::new().address());
    /// ```
    pub fn address(&self) -> usize {
        Arc::as_ptr(&self.0) as usize
    }
}

/// Two signals are equal when they are the same flag (not merely two unraised ones).
impl PartialEq for StopSignal {
    fn eq(&self, other: &StopSignal) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}
