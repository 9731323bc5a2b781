//! The editor's dispatch: [`Editor::handle`] answers a request by the route its method and
//! path name ([`crate::document_routes`], [`crate::rig_routes`], [`crate::defop_routes`]; the
//! crate's documentation has the table). The top of the crate: nothing in it imports this.

use crate::editor::Editor;
use crate::progress::Followed;
use crate::request::{ApiError, Request, Response};
use crate::{defop_routes, document_routes, rig_routes, subdiv_routes};

impl Editor {
    /// Answers `request`, following its job ([`JOB_HEADER`](crate::progress::JOB_HEADER)) while
    /// it runs.
    pub fn handle(&self, request: &Request) -> Response {
        let followed = self.follow(request);
        self.handle_followed(request, followed.as_ref())
    }

    /// Answers `request`, its job's stages reported to `followed`.
    pub fn handle_followed(&self, request: &Request, followed: Option<&Followed>) -> Response {
        match self.route(request, followed) {
            Ok(response) => response,
            Err(e) => e.into_response(),
        }
    }

    /// Whether `request` is heavy work (a precomputation, solve, grid or export), which a
    /// server runs off its event loop and a few at a time; the others answer at once.
    pub fn is_heavy(request: &Request) -> bool {
        !matches!(
            segments(&request.path).as_slice(),
            ["initial"] | ["progress", _] | ["progress", _, "stop"]
        )
    }

    fn route(&self, request: &Request, followed: Option<&Followed>) -> Result<Response, ApiError> {
        let method = request.method.as_str();
        let (get, post) = (method == "GET", method == "POST");
        match (segments(&request.path).as_slice(), get, post) {
            (["initial"], true, _) => document_routes::initial(self),
            (["open"], _, true) => document_routes::open(self, request),
            (["rig"], _, true) => rig_routes::rig(self, request, followed),
            (["weights", "columns"], _, true) => rig_routes::columns(self, request, followed),
            (["rigs", id, "solve"], _, true) => rig_routes::solve(self, id, request),
            (["rigs", id, "weights"], true, _) => rig_routes::weights(self, id, request),
            (["rigs", id, "mesh"], true, _) => rig_routes::mesh(self, id),
            (["rigs", id, "operator"], true, _) => rig_routes::operator(self, id),
            (["rigs", id, "carry"], true, _) => rig_routes::carry(self, id),
            (["rigs", id, "refine"], _, true) => rig_routes::refine(self, id, request),
            (["progress", job], true, _) => rig_routes::progress(self, job),
            (["progress", job, "stop"], _, true) => rig_routes::stop(self, job),
            (["defop"], _, true) => defop_routes::defop(self, request, followed),
            (["subdiv", "open"], _, true) => subdiv_routes::open(request),
            (["subdiv", "rig"], _, true) => subdiv_routes::rig(self, request),
            (["subdiv", "export"], _, true) => subdiv_routes::export(request),
            (["defops", id, "carry"], true, _) => defop_routes::carry(self, id),
            (["defops", id, "deform"], _, true) => defop_routes::deform(self, id, request),
            (["defops", id, "follow"], _, true) => defop_routes::follow(self, id, request),
            (["documents", id, "export"], _, true) => document_routes::export(self, id, request),
            (["documents", id, "outside"], _, true) => document_routes::outside(self, id, request),
            (["documents", id, "pins"], _, true) => document_routes::pins(self, id, request),
            (["documents", id, "scene"], _, true) => document_routes::save_scene(self, id, request),
            (["documents", id, "lottie"], _, true) => document_routes::lottie(self, id, request),
            (["documents", id, "animation"], _, true) => {
                document_routes::animation(self, id, request)
            }
            (_, false, false) => Err(ApiError::new(
                405,
                format!("{method}: the editor's routes take GET or POST"),
            )),
            _ => Err(ApiError::new(404, "no such API route")),
        }
    }
}

/// The segments of `path` after `/api/` (none when it is not under `/api/`).
fn segments(path: &str) -> Vec<&str> {
    match path.strip_prefix("/api/") {
        Some(rest) => rest.split('/').collect(),
        None => Vec::new(),
    }
}
