//! Where each precomputation is, for the page's progress display. The page names its request
//! (header [`JOB_HEADER`]) and asks `GET /api/progress/{job}` while it waits; the answer is the
//! stage the job is in (`queued`, `weights`, `rig`) and for how long, or none once it is over.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// The header naming a precomputation for [`ProgressBoard`].
pub const JOB_HEADER: &str = "x-splineskin-job";

/// Jobs followed at once: 64 (a page follows one; more are not followed, and still run).
pub const MAX_FOLLOWED: usize = 64;

/// Longest job name: 64 characters of `A–Z a–z 0–9 -`.
pub const MAX_JOB_NAME: usize = 64;

/// The stage of every followed job and when it started.
#[derive(Default)]
pub struct ProgressBoard {
    jobs: Mutex<HashMap<String, (&'static str, Instant)>>,
}

impl ProgressBoard {
    fn jobs(&self) -> std::sync::MutexGuard<'_, HashMap<String, (&'static str, Instant)>> {
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
        jobs.insert(name.to_string(), ("queued", Instant::now()));
        Some(Followed {
            board: self.clone(),
            name: name.to_string(),
        })
    }

    /// The stage of job `name` and the seconds spent in it, if it is followed.
    pub fn stage(&self, name: &str) -> Option<(&'static str, f64)> {
        self.jobs()
            .get(name)
            .map(|&(stage, since)| (stage, since.elapsed().as_secs_f64()))
    }
}

/// A followed job; dropping it ends the following.
pub struct Followed {
    board: Arc<ProgressBoard>,
    name: String,
}

impl Followed {
    /// A reporter of the job's stages, for the job's thread: it changes the stage while the
    /// job is still followed and does nothing after.
    pub fn reporter(&self) -> impl Fn(&'static str) + Send + 'static {
        let board = self.board.clone();
        let name = self.name.clone();
        move |stage| {
            if let Some(entry) = board.jobs().get_mut(&name) {
                *entry = (stage, Instant::now());
            }
        }
    }
}

impl Drop for Followed {
    fn drop(&mut self) {
        self.board.jobs().remove(&self.name);
    }
}
