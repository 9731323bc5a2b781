//! The editor's state ([`Editor`]): the documents and rigs kept between requests and the
//! stages of running precomputations. The routes read it; its requests are answered by
//! [`Editor::handle`] ([`crate::routes`], which dispatches to the routes).

use std::sync::{Arc, Mutex};

use splineskin::scene::Puppet;

use crate::document::Document;
use crate::progress::{Clock, Followed, ProgressBoard, JOB_HEADER};
use crate::request::{ApiError, Request};
use crate::store::{Rig, Store};

/// The editor: documents and rigs kept between requests, and the stages of running
/// precomputations.
pub struct Editor {
    /// Documents and rigs.
    pub store: Mutex<Store>,
    /// The stages of the precomputations pages follow.
    pub progress: Arc<ProgressBoard>,
}

impl Editor {
    /// An editor holding `initial` (if any) as the drawing shown first
    /// (`GET /api/initial`), timing stages by the system's monotonic clock.
    pub fn new(initial: Option<Document>) -> Editor {
        Editor::with_clock(initial, crate::progress::system_clock)
    }

    /// [`Editor::new`] with the clock `clock` (seconds from any fixed origin): WebAssembly in a
    /// page has no system clock of its own and passes the page's.
    pub fn with_clock(initial: Option<Document>, clock: Clock) -> Editor {
        let mut store = Store::default();
        if let Some(initial) = initial {
            store.set_initial(initial);
        }
        Editor {
            store: Mutex::new(store),
            progress: Arc::new(ProgressBoard::new(clock)),
        }
    }

    /// Follows the job `request` names in its [`JOB_HEADER`] (if any and valid) until the
    /// guard is dropped: a server calls it before the request waits for a free thread, so that
    /// the page sees it queued.
    pub fn follow(&self, request: &Request) -> Option<Followed> {
        self.progress.follow(request.header(JOB_HEADER)?)
    }

    pub(crate) fn store(&self) -> std::sync::MutexGuard<'_, Store> {
        // The store's methods do not panic midway; a poisoned lock holds consistent data.
        self.store.lock().unwrap_or_else(|e| e.into_inner())
    }

    pub(crate) fn document(&self, id: &str) -> Result<Arc<Document>, ApiError> {
        self.store().document(id).ok_or_else(|| {
            ApiError::new(
                404,
                format!("document {id} is no longer open (the editor keeps the latest few): open the drawing again"),
            )
        })
    }
}

/// Locks `rig`'s puppet; a lock poisoned by a failed solve is an internal error.
pub(crate) fn lock_puppet(rig: &Rig) -> Result<std::sync::MutexGuard<'_, Puppet>, ApiError> {
    rig.puppet
        .lock()
        .map_err(|_| ApiError::new(500, "the rig failed earlier (a bug): build it again"))
}
