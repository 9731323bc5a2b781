//! Where each precomputation is, for the page's progress display. The page names its request
//! (header [`JOB_HEADER`]) and asks `GET /api/progress/{job}` while it waits; the answer is the
//! stage the job is in (`queued`, `weights`, `rig`; operators: `domain`, `training`, `join`)
//! and for how long, with a count of the work done in that stage when the job reports one
//! ([`Count`]), or none once it is over. `POST /api/progress/{job}/stop` asks the job to stop
//! ([`ProgressBoard::stop`]): a training ends at its next ground-truth solve; other stages do
//! not look and run to their end.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use splineskin::defop::StopSignal;

/// A monotonic clock: seconds from a fixed origin.
pub type Clock = fn() -> f64;

/// Seconds since the first call, by the system's monotonic clock (`std::time::Instant`, which
/// WebAssembly in a page lacks: it passes the page's clock to
/// [`Editor::with_clock`](crate::Editor::with_clock)).
pub fn system_clock() -> f64 {
    static ORIGIN: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    ORIGIN
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_secs_f64()
}

/// What a job reports: its stage, the seconds spent in it and its count, if it reports one
/// (the answer of `GET /api/progress/{job}`).
pub type Stage = (&'static str, f64, Option<Count>);

/// Called with a job's name and stage whenever the stage or count changes.
pub type Listener = Box<dyn Fn(&str, Stage) + Send + Sync>;

/// The header naming a precomputation for [`ProgressBoard`].
pub const JOB_HEADER: &str = "x-splineskin-job";

/// Jobs followed at once: 64 (a page follows one; more are not followed, and still run).
pub const MAX_FOLLOWED: usize = 64;

/// Longest job name: 64 characters of `A–Z a–z 0–9 -`.
pub const MAX_JOB_NAME: usize = 64;

/// Work done in a stage that counts it: `done` of `total` units (ground-truth solves of a
/// training), in step `step` (from 1) of `steps` (its bootstrapping stages).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Count {
    /// Units finished.
    pub done: usize,
    /// Units in all.
    pub total: usize,
    /// Current step, from 1.
    pub step: usize,
    /// Number of steps.
    pub steps: usize,
}

/// A followed job: its stage, when the stage began (seconds of the board's clock), and its
/// count if it reports one.
type Entry = (&'static str, f64, Option<Count>);

/// What the board keeps of a followed job: its [`Entry`] and the signal that stops it.
type Job = (Entry, StopSignal);

/// The stage of every followed job and when it started.
pub struct ProgressBoard {
    jobs: Mutex<HashMap<String, Job>>,
    clock: Clock,
    listener: Mutex<Option<Listener>>,
    /// The one signal every followed job gets, if set ([`ProgressBoard::share_stop`]).
    shared_stop: Mutex<Option<StopSignal>>,
}

impl ProgressBoard {
    /// A board timing stages by `clock`.
    pub fn new(clock: Clock) -> ProgressBoard {
        ProgressBoard {
            jobs: Mutex::default(),
            clock,
            listener: Mutex::new(None),
            shared_stop: Mutex::new(None),
        }
    }

    /// Gives every job followed from now on `signal` as its stop signal, so that raising it
    /// stops whichever runs. For an editor that answers one request at a time and cannot hear
    /// `POST /api/progress/{job}/stop` while it computes (WebAssembly in a Web Worker): its host
    /// raises the flag itself, in memory it shares ([`StopSignal::address`]).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use splineskin::defop::StopSignal;
    /// use splineskin_editor::progress::{system_clock, ProgressBoard};
    /// let board = Arc::new(ProgressBoard::new(system_clock));
    /// let shared = StopSignal::new();
    /// board.share_stop(shared.clone());
    /// let job = board.follow("rig-1").unwrap();
    /// assert_eq!(job.stop_signal(), shared);
    /// shared.raise();
    /// assert!(job.stop_signal().is_raised());
    /// ```
    pub fn share_stop(&self, signal: StopSignal) {
        *self.shared_stop.lock().unwrap_or_else(|e| e.into_inner()) = Some(signal);
    }

    /// The board's clock.
    pub fn clock(&self) -> Clock {
        self.clock
    }

    /// Calls `listener` with every change of a followed job's stage or count, from the job's
    /// thread: a page whose editor runs in WebAssembly cannot ask while a job runs, so it is
    /// told.
    pub fn set_listener(&self, listener: Listener) {
        *self.listener.lock().unwrap_or_else(|e| e.into_inner()) = Some(listener);
    }

    /// Sets job `name`'s entry if it is followed, and tells the listener.
    fn update(&self, name: &str, change: impl FnOnce(&mut Entry, f64)) {
        let now = (self.clock)();
        let entry = {
            let mut jobs = self.jobs();
            let Some((entry, _)) = jobs.get_mut(name) else {
                return;
            };
            change(entry, now);
            *entry
        };
        if let Some(listener) = &*self.listener.lock().unwrap_or_else(|e| e.into_inner()) {
            listener(name, (entry.0, now - entry.1, entry.2));
        }
    }

    fn jobs(&self) -> std::sync::MutexGuard<'_, HashMap<String, Job>> {
        // Inserts and removals do not panic midway: a poisoned map is consistent.
        self.jobs.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Follows job `name` from now on (stage `queued`) until the returned guard is dropped —
    /// when the request ends, however it ends. `None` for a name that is not valid or when
    /// [`MAX_FOLLOWED`] jobs are followed already.
    pub fn follow(self: &Arc<Self>, name: &str) -> Option<Followed> {
        let valid = !name.is_empty()
            && name.len() <= MAX_JOB_NAME
            && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-');
        let mut jobs = self.jobs();
        if !valid || jobs.len() >= MAX_FOLLOWED || jobs.contains_key(name) {
            return None;
        }
        let shared = self.shared_stop.lock().unwrap_or_else(|e| e.into_inner());
        let stop = shared.clone().unwrap_or_default();
        jobs.insert(
            name.to_string(),
            (("queued", (self.clock)(), None), stop.clone()),
        );
        Some(Followed {
            board: self.clone(),
            name: name.to_string(),
            stop,
        })
    }

    /// The stage of job `name`, the seconds spent in it and its count, if it is followed.
    pub fn stage(&self, name: &str) -> Option<Stage> {
        let now = (self.clock)();
        self.jobs()
            .get(name)
            .map(|&((stage, since, count), _)| (stage, now - since, count))
    }

    /// Asks job `name` to stop ([`Followed::stop_signal`]); `false` when no such job is
    /// followed (it ended, or never began).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use splineskin_editor::progress::{system_clock, ProgressBoard};
    /// let board = Arc::new(ProgressBoard::new(system_clock));
    /// let job = board.follow("train-1").unwrap();
    /// let signal = job.stop_signal();
    /// assert!(!signal.is_raised());
    /// assert!(board.stop("train-1"));
    /// assert!(signal.is_raised());
    /// drop(job);
    /// assert!(!board.stop("train-1"));
    /// ```
    pub fn stop(&self, name: &str) -> bool {
        match self.jobs().get(name) {
            Some((_, signal)) => {
                signal.raise();
                true
            }
            None => false,
        }
    }
}

/// A followed job; dropping it ends the following.
pub struct Followed {
    board: Arc<ProgressBoard>,
    name: String,
    /// The signal the board raises for this job (a clone of its entry's).
    stop: StopSignal,
}

impl Followed {
    /// The signal [`ProgressBoard::stop`] raises for this job, for its training to hold
    /// ([`splineskin::defop::TrainOptions::stop`]).
    pub fn stop_signal(&self) -> StopSignal {
        self.stop.clone()
    }

    /// A reporter of the job's stages, for the job's thread: it changes the stage while the
    /// job is still followed and does nothing after.
    pub fn reporter(&self) -> impl Fn(&'static str) + Send + 'static {
        let board = self.board.clone();
        let name = self.name.clone();
        move |stage| board.update(&name, |entry, now| *entry = (stage, now, None))
    }

    /// A reporter of the count within the current stage (`stage` names it: entering a new
    /// stage restarts its clock), callable from several threads at once.
    pub fn counter(&self) -> impl Fn(&'static str, Count) + Send + Sync + 'static {
        let board = self.board.clone();
        let name = self.name.clone();
        move |stage, count| {
            board.update(&name, |entry, now| {
                let since = if entry.0 == stage { entry.1 } else { now };
                *entry = (stage, since, Some(count));
            })
        }
    }
}

impl Drop for Followed {
    fn drop(&mut self) {
        self.board.jobs().remove(&self.name);
    }
}
