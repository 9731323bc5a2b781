//! Real SVG art made by others (issue 15): every file of every npm package of `test-art/` (see
//! its `package.json`; `.ci/run` runs `npm ci` there, the files are never copied into this
//! repository), read and rigged as a user would, with invariants checked on every path:
//!
//! * **import**: a file usvg reads (and renders geometry from) is read by
//!   [`splineskin::drawing::read_svg_file`], and the rig builds: no refusal, no panic
//!   (`catch_unwind` around every stage). usvg itself is asked only about the files our import
//!   refuses (our import reads through usvg: what it reads, usvg reads);
//! * three point handles, placed by farthest-point sampling of the drawing's on-curve points,
//!   with Shepard weights ([`Shepard`], default options) and the default fit:
//!   * **identity**: the identity pose reproduces every path's points to
//!     [`EXACT_RELATIVE`] of that path's own bounding-box diagonal, plus [`EXACT_ULPS`] ulps of
//!     the largest coordinate of the path (input and expected output);
//!   * **rigid**: one rotation + translation on every handle gives exactly that map of every
//!     point, same tolerance;
//!   * **deformation**: one handle moved by [`DEFORM_MOVE`] of the drawing's diagonal, another
//!     turned by [`DEFORM_TURN_DEGREES`] about its position, the third fixed: every path's
//!     fitted curves stay within [`DEFORM_PATH_FRACTION`] of that path's diagonal plus
//!     [`DEFORM_DRAWING_FRACTION`] of the drawing's diagonal of the skinned target
//!     `s(t) = Σ w_i(B(t)) T_i B(t)` ([`target_samples`], compared at [`DEFORM_SAMPLES`]
//!     equal parameters per curve, as [`splineskin::metrics::chain_metrics`] does);
//! * the same three checks with **harmonic** weights (a mesh family, solved on the drawing's
//!   triangulated domain through a scene, as `splineskin deform` does) on a deterministic
//!   subset: every [`HARMONIC_EVERY`]-th file of each package (bbw would cost minutes).
//!
//! Per package it prints a table of counts per outcome and the worst cases by name (file, path
//! index, element, size of the path, error), and writes every failure to
//! `target/test-diffs/real-art-corpus.txt`. Timings are printed, never asserted.
//!
//! Without `test-art/node_modules` (or a package missing from it) the test prints that it
//! skipped and why and passes, except when `CI` is set: then it fails.

mod common;

use std::cell::{Cell, RefCell};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use kurbo::{Affine, Point, Rect, Vec2};
use rayon::prelude::*;
use splineskin::bezier;
use splineskin::drawing::{read_svg_file, Drawing, ImportOptions, SvgError};
use splineskin::metrics::target_samples;
use splineskin::scene::{Compat, Scene};
use splineskin::spline_fit::{FitOptions, SplineRig};
use splineskin::weights::{Shepard, ShepardOptions, WeightField};

use common::external_data;

/// An npm package of art: where npm puts its SVG files.
struct Package {
    /// The npm name, as in `test-art/package.json`.
    name: &'static str,
    /// The folder of its SVG files, relative to `node_modules`.
    folder: &'static str,
    /// What kind of art it is.
    about: &'static str,
}

/// The packages of `test-art/package.json`.
const PACKAGES: [Package; 5] = [
    Package {
        name: "openmoji",
        folder: "openmoji/color/svg",
        about: "colour emoji, 72-unit viewBox, strokes and fills",
    },
    Package {
        name: "@twemoji/svg",
        folder: "@twemoji/svg",
        about: "colour emoji, 36-unit viewBox, fills",
    },
    Package {
        name: "flag-icons",
        folder: "flag-icons/flags/4x3",
        about: "flags, clip paths, transforms, uses and markers",
    },
    Package {
        name: "bootstrap-icons",
        folder: "bootstrap-icons/icons",
        about: "icons, 16-unit viewBox, compound fills with holes",
    },
    Package {
        name: "@mdi/svg",
        folder: "@mdi/svg/svg",
        about: "Material Design icons, 24-unit viewBox, one compound path each",
    },
];

/// Tolerance of the exact invariants (identity, rigid), relative to the diagonal of the path's
/// own control-point bounding box: 1e-9 (issue 15). Measured errors are far below it (the
/// largest ratio to the tolerance is printed).
const EXACT_RELATIVE: f64 = 1e-9;

/// Files of the five packages that still break an invariant (issue 15 is not done): 507 before
/// the fit's dependent rows, point subpaths, centring and balance were fixed, 242 after (most
/// missed the identity tolerance by a factor of 2-5: the solve's defect in the translation
/// columns, times the path's distance from the origin), 2 once the similarity part of the
/// operator was made exact, 1 once fixed angles between straight sides without handles stopped
/// locking polygons, with shared curves fitted once (the default) as without. The one left is
/// Twemoji's 26d1 with harmonic weights: the moved handle sits on the edge of an 8 × 4 pill,
/// so the target pulls a spike out of its outline, 6.8 units high and narrow, with a corner at
/// the handle where the input is G¹; the fixed-ratio fit reaches 4.0 of the 6.8 and misses by
/// 2.79 against a tolerance of 2.69 (flexible G¹: 2.23, with the junction made C⁰: 1.31).
/// The spike is the harmonic weights' own: a point has no capacity for Laplace's equation, so
/// a point handle's harmonic weight narrows to a needle as the domain is refined. With the
/// domain's `samples_per_diagonal` at 125, 250, 500 (default), 1000, 2000 the same fit misses
/// by 1.56, 2.08, 2.79, 3.32, 3.56 (flexible 1.04, 1.53, 2.23, 2.77, 3.01). Control points
/// added where the fit falls short would follow it closer. The test fails when more files
/// break; lower this as fixes land, to 0.
const KNOWN_VIOLATING_FILES: usize = 1;

/// Rounding allowance of the exact invariants, in ulps of the path's largest absolute
/// coordinate (input and expected output): 64. A path far smaller than its distance to the
/// origin (a 0.01-unit dot at x = 600) cannot be reproduced closer than a few ulps of its
/// coordinates, whatever its own size; 64 ulps of 600 is 8.5e-12 units.
const EXACT_ULPS: f64 = 64.0;

/// The deformation's translation of handle 0, as a fraction of the drawing's diagonal: 15 %.
const DEFORM_MOVE: f64 = 0.15;

/// The deformation's turn of handle 1 about its position, degrees: 30.
const DEFORM_TURN_DEGREES: f64 = 30.0;

/// Largest distance of a deformed path from its skinned target, as a fraction of that path's
/// own diagonal: 25 % (plus [`DEFORM_DRAWING_FRACTION`]). Generous on purpose: it does not
/// grade the fit, it catches fits that collapse or blow up.
const DEFORM_PATH_FRACTION: f64 = 0.25;

/// Part of the deformation tolerance relative to the drawing's diagonal: 1 % (for paths so
/// small that a fraction of their own size is below what the weights' variation allows).
const DEFORM_DRAWING_FRACTION: f64 = 0.01;

/// Uniform parameters per curve at which the deformation is compared with its target: 17
/// (`t = 0, 1/16, …, 1`).
const DEFORM_SAMPLES: usize = 17;

/// The rigid map of the rigid check: a turn by this angle (degrees) about the drawing's
/// centre, then a translation by [`RIGID_SHIFT`] times its diagonal.
const RIGID_DEGREES: f64 = 40.0;

/// The rigid map's translation, as fractions of the drawing's diagonal.
const RIGID_SHIFT: (f64, f64) = (0.2, -0.1);

/// Point handles per drawing: 3.
const N_HANDLES: usize = 3;

/// The harmonic-weights checks run on every this-many-th file of each package (in file-name
/// order, starting with the first).
const HARMONIC_EVERY: usize = 200;

/// Worst cases listed per package and check.
const N_WORST: usize = 6;

/// Which check a failure is of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Check {
    Identity,
    Rigid,
    Deformation,
}

impl Check {
    fn name(self) -> &'static str {
        match self {
            Check::Identity => "identity",
            Check::Rigid => "rigid",
            Check::Deformation => "deformation",
        }
    }
}

/// The weights a check ran with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Family {
    Shepard,
    Harmonic,
}

impl Family {
    fn name(self) -> &'static str {
        match self {
            Family::Shepard => "shepard",
            Family::Harmonic => "harmonic",
        }
    }
}

/// The path of a drawing that failed a check worst (largest error / tolerance).
#[derive(Clone, Debug)]
struct PathFailure {
    /// Index of the path in the drawing.
    path: usize,
    /// Its element (`path#id (line n)`).
    element: String,
    /// Its number of curves.
    n_curves: usize,
    /// Whether it is closed.
    closed: bool,
    /// Its control-point bounding box.
    bounds: Rect,
    /// The error (drawing units; infinite for non-finite output).
    error: f64,
    /// The tolerance (drawing units).
    tolerance: f64,
    /// Paths of the drawing failing this check.
    n_failing: usize,
}

impl PathFailure {
    fn ratio(&self) -> f64 {
        if self.error.is_finite() {
            self.error / self.tolerance
        } else {
            f64::INFINITY
        }
    }
}

impl std::fmt::Display for PathFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "path {} ({}; {} curve{}, {}, {:.4} × {:.4} at ({:.4}, {:.4})): error {:.3e} > \
             tolerance {:.3e} ({} failing path{} in the file)",
            self.path,
            self.element,
            self.n_curves,
            if self.n_curves == 1 { "" } else { "s" },
            if self.closed { "closed" } else { "open" },
            self.bounds.width(),
            self.bounds.height(),
            self.bounds.x0,
            self.bounds.y0,
            self.error,
            self.tolerance,
            self.n_failing,
            if self.n_failing == 1 { "" } else { "s" },
        )
    }
}

/// What happened to one file.
#[derive(Debug)]
enum Outcome {
    /// usvg itself does not read the file (not held against us).
    UsvgRefuses(String),
    /// usvg reads it but renders no path from it: nothing to deform.
    NothingToDeform,
    /// usvg reads it, our import refuses it.
    Refused(String),
    /// The import read it, the Shepard rig does not build.
    RigRefused(String),
    /// The import read it and the rig built; the checks' results.
    Checked(Checks),
}

/// The results of the checks of one file.
#[derive(Debug, Default)]
struct Checks {
    /// Curves of the drawing.
    n_curves: usize,
    /// Per (family, check): `Ok(worst error / tolerance)` or the worst failing path.
    results: BTreeMap<(Family, Check), Result<f64, PathFailure>>,
    /// The harmonic rig's refusal (setup or fit), when the file is in the harmonic subset.
    harmonic_refused: Option<String>,
}

/// A panic caught during one stage of one file.
#[derive(Debug)]
struct Panicked {
    stage: &'static str,
    message: String,
}

/// One file's report.
#[derive(Debug)]
struct FileReport {
    /// The file name within its package's folder.
    name: String,
    outcome: Result<Outcome, Panicked>,
}

/// Wall time spent per stage over all files (nanoseconds, summed over threads).
#[derive(Default)]
struct StageTimes {
    usvg: AtomicU64,
    import: AtomicU64,
    shepard_rig: AtomicU64,
    checks: AtomicU64,
    harmonic: AtomicU64,
}

impl StageTimes {
    fn add(counter: &AtomicU64, since: Instant) {
        counter.fetch_add(since.elapsed().as_nanos() as u64, Ordering::Relaxed);
    }
}

thread_local! {
    /// Set while a corpus file is processed on this thread: its panics are caught and reported
    /// in the table, not printed by the panic hook.
    static IN_CORPUS: Cell<bool> = const { Cell::new(false) };
    /// Where the last caught panic of this thread happened.
    static PANIC_LOCATION: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Runs `f` as stage `stage` of a corpus file: a panic becomes [`Panicked`] with its message
/// and location.
fn stage<T>(name: &'static str, f: impl FnOnce() -> T) -> Result<T, Panicked> {
    IN_CORPUS.with(|c| c.set(true));
    let result = catch_unwind(AssertUnwindSafe(f));
    IN_CORPUS.with(|c| c.set(false));
    result.map_err(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "(non-string panic payload)".into());
        let at = PANIC_LOCATION.with(|l| l.borrow_mut().take());
        Panicked {
            stage: name,
            message: match at {
                Some(at) => format!("{message} (at {at})"),
                None => message,
            },
        }
    })
}

/// The control-point bounding box of a path's points.
fn bounds_of(points: &[Point]) -> Rect {
    let first = points[0];
    points
        .iter()
        .fold(Rect::from_points(first, first), |r, &p| r.union_pt(p))
}

fn diagonal(r: Rect) -> f64 {
    r.width().hypot(r.height())
}

/// `N_HANDLES` handle positions: farthest-point samples of the drawing's on-curve points,
/// starting from the one farthest from the centre of its bounding box (ties: the first in
/// document order). Deterministic; coincide only if the on-curve points do.
fn place_handles(drawing: &Drawing) -> Vec<Point> {
    let on_curve: Vec<Point> = drawing
        .paths
        .iter()
        .flat_map(|p| p.points.iter().step_by(3).copied())
        .collect();
    let centre = drawing.control_bounds().map_or(Point::ZERO, |r| r.center());
    let farthest = |dist: &dyn Fn(Point) -> f64| {
        let mut best = (on_curve[0], f64::NEG_INFINITY);
        for &p in &on_curve {
            let d = dist(p);
            if d > best.1 {
                best = (p, d);
            }
        }
        best.0
    };
    let mut handles = vec![farthest(&|p| (p - centre).hypot2())];
    while handles.len() < N_HANDLES {
        let chosen = handles.clone();
        handles.push(farthest(&|p| {
            chosen
                .iter()
                .map(|&h| (p - h).hypot2())
                .fold(f64::INFINITY, f64::min)
        }));
    }
    handles
}

/// The rigid map of the rigid check for `drawing`.
fn rigid_map(drawing: &Drawing) -> Affine {
    let r = drawing.control_bounds().unwrap_or(Rect::ZERO);
    let d = diagonal(r);
    Affine::translate(Vec2::new(RIGID_SHIFT.0 * d, RIGID_SHIFT.1 * d))
        * Affine::rotate_about(RIGID_DEGREES.to_radians(), r.center())
}

/// The deformation's pose: handle 0 moved by [`DEFORM_MOVE`] of the diagonal (direction
/// (0.6, 0.8)), handle 1 turned by [`DEFORM_TURN_DEGREES`] about its position, handle 2 fixed.
fn deformation_pose(drawing: &Drawing, handles: &[Point]) -> Vec<Affine> {
    let d = drawing.diagonal();
    vec![
        Affine::translate(Vec2::new(0.6, 0.8) * (DEFORM_MOVE * d)),
        Affine::rotate_about(DEFORM_TURN_DEGREES.to_radians(), handles[1]),
        Affine::IDENTITY,
    ]
}

/// The element label of path `pi` of `drawing`.
fn element_of(drawing: &Drawing, pi: usize) -> String {
    drawing
        .source
        .as_ref()
        .map_or_else(|| "no source".into(), |s| s.element_label(pi))
}

/// The path-by-path check of `got` (the rig's output, layout of [`Drawing::flat_points`]):
/// `measure` gives a path's error and tolerance from the path, its bounds and its points in
/// `got`, the paths visited in order. Returns the largest error / tolerance, or the worst
/// failing path (its ratio the largest) with the count of failing paths.
fn check_paths(
    drawing: &Drawing,
    got: &[Point],
    mut measure: impl FnMut(&splineskin::drawing::Path, Rect, &[Point]) -> (f64, f64),
) -> Result<f64, PathFailure> {
    let mut worst_ratio = 0.0f64;
    let mut failure: Option<PathFailure> = None;
    let mut n_failing = 0;
    for (pi, (path, range)) in drawing.paths.iter().zip(drawing.path_ranges()).enumerate() {
        let bounds = bounds_of(&path.points);
        let (error, tolerance) = measure(path, bounds, &got[range]);
        if error <= tolerance {
            worst_ratio = worst_ratio.max(error / tolerance);
        } else {
            n_failing += 1;
            let f = PathFailure {
                path: pi,
                element: element_of(drawing, pi),
                n_curves: path.n_curves(),
                closed: path.closed,
                bounds,
                error,
                tolerance,
                n_failing: 0,
            };
            if failure.as_ref().is_none_or(|w| f.ratio() > w.ratio()) {
                failure = Some(f);
            }
        }
    }
    match failure {
        Some(f) => Err(PathFailure { n_failing, ..f }),
        None => Ok(worst_ratio),
    }
}

/// The larger of `error` and `e`, a NaN `e` (which compares false) counting as infinite.
fn max_error(error: f64, e: f64) -> f64 {
    if e.is_finite() {
        error.max(e)
    } else {
        f64::INFINITY
    }
}

/// Checks that `got` (the rig's output, layout of [`Drawing::flat_points`]) is `map` of every
/// point of `drawing`, path by path, to the exact tolerance ([`EXACT_RELATIVE`] of the path's
/// diagonal plus [`EXACT_ULPS`] ulps of its largest coordinate). Returns the largest error /
/// tolerance, or the worst failing path.
fn check_exact(drawing: &Drawing, got: &[Point], map: Affine) -> Result<f64, PathFailure> {
    check_paths(drawing, got, |path, bounds, out| {
        let mut magnitude = 0.0f64;
        let mut error = 0.0f64;
        for (&p, &q) in path.points.iter().zip(out) {
            let want = map * p;
            magnitude = magnitude.max(p.x.abs().max(p.y.abs()));
            magnitude = magnitude.max(want.x.abs().max(want.y.abs()));
            error = max_error(error, (q - want).hypot());
        }
        let tolerance = EXACT_RELATIVE * diagonal(bounds) + EXACT_ULPS * f64::EPSILON * magnitude;
        (error, tolerance)
    })
}

/// Checks that every path of the deformed `got` stays within [`DEFORM_PATH_FRACTION`] of its
/// diagonal plus [`DEFORM_DRAWING_FRACTION`] of the drawing's of the skinned target under
/// `field` and `pose`, at [`DEFORM_SAMPLES`] parameters per curve. Returns the largest
/// distance / tolerance, or the worst failing path.
fn check_deformation(
    drawing: &Drawing,
    field: &dyn WeightField,
    pose: &[Affine],
    got: &[Point],
) -> Result<f64, PathFailure> {
    let targets = target_samples(drawing, field, pose, DEFORM_SAMPLES);
    let drawing_part = DEFORM_DRAWING_FRACTION * drawing.diagonal();
    let mut targets = targets.iter();
    check_paths(drawing, got, |path, bounds, out| {
        let mut error = 0.0f64;
        for j in 0..path.n_curves() {
            let c = [out[3 * j], out[3 * j + 1], out[3 * j + 2], out[3 * j + 3]];
            for (k, target) in (0..DEFORM_SAMPLES).zip(&mut targets) {
                let t = k as f64 / (DEFORM_SAMPLES - 1) as f64;
                error = max_error(error, (bezier::eval(&c, t) - *target).hypot());
            }
        }
        let tolerance = DEFORM_PATH_FRACTION * diagonal(bounds) + drawing_part;
        (error, tolerance)
    })
}

/// Runs the three checks of one rig, recording them under `family`.
fn run_checks(
    family: Family,
    drawing: &Drawing,
    field: &dyn WeightField,
    rig: &SplineRig,
    handles: &[Point],
    checks: &mut Checks,
) {
    let mut out = vec![Point::ZERO; rig.n_points()];
    let pose = |p: &[Affine], out: &mut Vec<Point>| {
        if let Err(e) = rig.update(p, out) {
            panic!("update refused a pose of the right size: {e}");
        }
    };
    pose(&[Affine::IDENTITY; N_HANDLES], &mut out);
    let identity = check_exact(drawing, &out, Affine::IDENTITY);
    checks.results.insert((family, Check::Identity), identity);
    let rigid = rigid_map(drawing);
    pose(&[rigid; N_HANDLES], &mut out);
    checks
        .results
        .insert((family, Check::Rigid), check_exact(drawing, &out, rigid));
    let deformation = deformation_pose(drawing, handles);
    pose(&deformation, &mut out);
    let deformed = check_deformation(drawing, field, &deformation, &out);
    checks
        .results
        .insert((family, Check::Deformation), deformed);
}

/// The harmonic rig of `file` with `handles`, through a scene as `splineskin deform` builds it:
/// its drawing, weights and rig, or the refusal.
fn harmonic_rig(
    file: &Path,
    handles: &[Point],
) -> Result<(Drawing, std::sync::Arc<dyn WeightField>, SplineRig), String> {
    let text = std::fs::read_to_string(file).map_err(|e| e.to_string())?;
    let handles: Vec<serde_json::Value> = handles
        .iter()
        .map(|h| serde_json::json!({ "position": [h.x, h.y] }))
        .collect();
    let scene = serde_json::json!({
        "splineskin_scene": 1,
        "svg_text": text,
        "handles": handles,
        "weights": { "family": "harmonic" },
    });
    let origin = file.display().to_string();
    let scene =
        Scene::from_json(&scene.to_string(), &origin, None).map_err(|e| format!("scene: {e}"))?;
    let setup = scene
        .setup(Compat::None)
        .map_err(|e| format!("setup: {e}"))?;
    let rig = SplineRig::precompute(&setup.drawing, &*setup.weights, &setup.options)
        .map_err(|e| format!("fit: {e}"))?;
    Ok((setup.drawing, setup.weights, rig))
}

/// Whether usvg renders at least one path from `group` (clip paths, masks and patterns are not
/// rendered content).
fn has_paths(group: &usvg::Group) -> bool {
    group.children().iter().any(|node| match node {
        usvg::Node::Path(_) => true,
        usvg::Node::Group(g) => has_paths(g),
        _ => false,
    })
}

/// What usvg makes of a file: `Ok(whether it renders a path)`, or its refusal.
fn usvg_reading(file: &Path) -> Result<bool, String> {
    let bytes = std::fs::read(file).map_err(|e| e.to_string())?;
    usvg::Tree::from_data(&bytes, &usvg::Options::default())
        .map(|tree| has_paths(tree.root()))
        .map_err(|e| e.to_string())
}

/// Reads, rigs and checks one file (the harmonic checks too when `harmonic`).
fn process_file(file: &Path, harmonic: bool, times: &StageTimes) -> Result<Outcome, Panicked> {
    let t = Instant::now();
    let drawing = stage("import", || read_svg_file(file, &ImportOptions::default()))?;
    StageTimes::add(&times.import, t);
    let drawing = match drawing {
        Ok(d) => d,
        Err(e) => {
            let t = Instant::now();
            let usvg = stage("usvg", || usvg_reading(file))?;
            StageTimes::add(&times.usvg, t);
            return Ok(match (usvg, e) {
                (Err(usvg), _) => Outcome::UsvgRefuses(usvg),
                (Ok(false), SvgError::NoPaths { .. }) => Outcome::NothingToDeform,
                (Ok(_), e) => Outcome::Refused(e.to_string()),
            });
        }
    };
    let t = Instant::now();
    let handles = stage("handles", || place_handles(&drawing))?;
    let field = Shepard::new(&handles, ShepardOptions::default());
    let rig = stage("shepard rig", || {
        SplineRig::precompute(&drawing, &field, &FitOptions::default())
    })?;
    StageTimes::add(&times.shepard_rig, t);
    let rig = match rig {
        Ok(r) => r,
        Err(e) => return Ok(Outcome::RigRefused(e.to_string())),
    };
    let mut checks = Checks {
        n_curves: drawing.n_curves(),
        ..Checks::default()
    };
    let t = Instant::now();
    stage("shepard checks", || {
        run_checks(
            Family::Shepard,
            &drawing,
            &field,
            &rig,
            &handles,
            &mut checks,
        )
    })?;
    StageTimes::add(&times.checks, t);
    if harmonic {
        let t = Instant::now();
        let built = stage("harmonic rig", || harmonic_rig(file, &handles))?;
        match built {
            Ok((drawing, field, rig)) => stage("harmonic checks", || {
                run_checks(
                    Family::Harmonic,
                    &drawing,
                    &*field,
                    &rig,
                    &handles,
                    &mut checks,
                )
            })?,
            Err(e) => checks.harmonic_refused = Some(e),
        }
        StageTimes::add(&times.harmonic, t);
    }
    Ok(Outcome::Checked(checks))
}

/// The SVG files of a package's folder, sorted by name.
fn package_files(folder: &Path) -> Vec<PathBuf> {
    let entries = match std::fs::read_dir(folder) {
        Ok(e) => e,
        Err(e) => panic!("cannot list {}: {e}", folder.display()),
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("svg")))
        .collect();
    files.sort();
    files
}

/// Counts of one package, per outcome.
#[derive(Default)]
struct Tally {
    files: usize,
    usvg_refuses: usize,
    nothing: usize,
    refused: usize,
    rig_refused: usize,
    panics: usize,
    checked: usize,
    curves: usize,
    /// Files checked and failed, per (family, check).
    checked_by: BTreeMap<(Family, Check), usize>,
    failed_by: BTreeMap<(Family, Check), usize>,
    /// Largest error / tolerance among passing files, per (family, check).
    passing_margin: BTreeMap<(Family, Check), f64>,
    harmonic_refused: usize,
    /// Files breaking at least one invariant.
    violating_files: usize,
}

impl Tally {
    fn of(reports: &[FileReport]) -> Tally {
        let mut t = Tally {
            files: reports.len(),
            ..Tally::default()
        };
        for r in reports {
            match &r.outcome {
                Err(_) => {
                    t.panics += 1;
                    t.violating_files += 1;
                }
                Ok(Outcome::UsvgRefuses(_)) => t.usvg_refuses += 1,
                Ok(Outcome::NothingToDeform) => t.nothing += 1,
                Ok(Outcome::Refused(_)) => {
                    t.refused += 1;
                    t.violating_files += 1;
                }
                Ok(Outcome::RigRefused(_)) => {
                    t.rig_refused += 1;
                    t.violating_files += 1;
                }
                Ok(Outcome::Checked(c)) => {
                    t.checked += 1;
                    t.curves += c.n_curves;
                    t.harmonic_refused += usize::from(c.harmonic_refused.is_some());
                    let failed = c.results.values().any(Result::is_err);
                    t.violating_files += usize::from(failed || c.harmonic_refused.is_some());
                    for (&key, result) in &c.results {
                        *t.checked_by.entry(key).or_default() += 1;
                        match result {
                            Ok(ratio) => {
                                let m = t.passing_margin.entry(key).or_default();
                                *m = m.max(*ratio);
                            }
                            Err(_) => *t.failed_by.entry(key).or_default() += 1,
                        }
                    }
                }
            }
        }
        t
    }

    fn failed(&self, key: (Family, Check)) -> usize {
        self.failed_by.get(&key).copied().unwrap_or(0)
    }
}

/// The table of one package, and its worst cases by name.
fn package_report(package: &Package, reports: &[FileReport], wall: f64) -> String {
    let t = Tally::of(reports);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n== {} ({}): {} files, {:.1} s wall",
        package.name, package.about, t.files, wall
    );
    let read = t.files - t.usvg_refuses;
    let mut row = |label: &str, n: usize| {
        let _ = writeln!(s, "  {label:<44} {n:>6}");
    };
    row("files", t.files);
    row("read by usvg", read);
    row("  nothing to deform (usvg renders no path)", t.nothing);
    row("  refused by our import", t.refused);
    row("  rig refused (Shepard)", t.rig_refused);
    row("  panics", t.panics);
    row("  rigged and checked (Shepard)", t.checked);
    row("    their curves", t.curves);
    row("files breaking at least one invariant", t.violating_files);
    for family in [Family::Shepard, Family::Harmonic] {
        for check in [Check::Identity, Check::Rigid, Check::Deformation] {
            let key = (family, check);
            let Some(&n) = t.checked_by.get(&key) else {
                continue;
            };
            let margin = t.passing_margin.get(&key).copied().unwrap_or(0.0);
            let _ = writeln!(
                s,
                "  {:<44} {:>6} of {:>5}   (passing files: error ≤ {:.2e} of the tolerance)",
                format!("    {} {} failures", family.name(), check.name()),
                t.failed(key),
                n,
                margin
            );
        }
    }
    if t.checked_by
        .contains_key(&(Family::Harmonic, Check::Identity))
        || t.harmonic_refused > 0
    {
        let _ = writeln!(
            s,
            "  {:<44} {:>6}",
            "    harmonic rig refused", t.harmonic_refused
        );
    }
    // Worst cases by name.
    let list = |s: &mut String, title: &str, items: Vec<(f64, String)>| {
        if items.is_empty() {
            return;
        }
        let mut items = items;
        items.sort_by(|a, b| b.0.total_cmp(&a.0).then_with(|| a.1.cmp(&b.1)));
        let _ = writeln!(s, "  {title} ({}; worst {}):", items.len(), N_WORST);
        for (_, line) in items.iter().take(N_WORST) {
            let _ = writeln!(s, "    {line}");
        }
    };
    let mut usvg_refusals = Vec::new();
    let mut refusals = Vec::new();
    let mut panics = Vec::new();
    let mut failures: BTreeMap<(Family, Check), Vec<(f64, String)>> = BTreeMap::new();
    for r in reports {
        match &r.outcome {
            Err(p) => panics.push((0.0, format!("{}: in {}: {}", r.name, p.stage, p.message))),
            Ok(Outcome::UsvgRefuses(e)) => usvg_refusals.push((0.0, format!("{}: {e}", r.name))),
            Ok(Outcome::Refused(e)) => refusals.push((0.0, format!("{}: import: {e}", r.name))),
            Ok(Outcome::RigRefused(e)) => refusals.push((0.0, format!("{}: rig: {e}", r.name))),
            Ok(Outcome::Checked(c)) => {
                if let Some(e) = &c.harmonic_refused {
                    refusals.push((0.0, format!("{}: harmonic {e}", r.name)));
                }
                for (&key, result) in &c.results {
                    if let Err(f) = result {
                        failures
                            .entry(key)
                            .or_default()
                            .push((f.ratio(), format!("{}: {f}", r.name)));
                    }
                }
            }
            _ => {}
        }
    }
    list(
        &mut s,
        "not read by usvg (not held against us)",
        usvg_refusals,
    );
    list(&mut s, "refusals", refusals);
    list(&mut s, "panics", panics);
    for ((family, check), items) in failures {
        let title = format!("{} {} failures", family.name(), check.name());
        list(&mut s, &title, items);
    }
    s
}

/// Every failure of every package, one per line (for `target/test-diffs/`).
fn failure_lines(package: &Package, reports: &[FileReport]) -> Vec<String> {
    let mut lines = Vec::new();
    for r in reports {
        let name = format!("{}/{}", package.folder, r.name);
        match &r.outcome {
            Err(p) => lines.push(format!("{name}\tpanic in {}\t{}", p.stage, p.message)),
            Ok(Outcome::Refused(e)) => lines.push(format!("{name}\trefused by import\t{e}")),
            Ok(Outcome::RigRefused(e)) => lines.push(format!("{name}\trig refused\t{e}")),
            Ok(Outcome::Checked(c)) => {
                if let Some(e) = &c.harmonic_refused {
                    lines.push(format!("{name}\tharmonic rig refused\t{e}"));
                }
                for ((family, check), result) in &c.results {
                    if let Err(f) = result {
                        lines.push(format!(
                            "{name}\t{} {} failure\t{f}",
                            family.name(),
                            check.name()
                        ));
                    }
                }
            }
            _ => {}
        }
    }
    lines
}

/// A panic hook that stays quiet on threads processing a corpus file (their panics are caught
/// and reported) and remembers where they panicked; other panics go to the hook that was
/// installed before. Dropping the guard puts the default hook back.
struct QuietPanics;

impl QuietPanics {
    fn install() -> QuietPanics {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if IN_CORPUS.with(Cell::get) {
                let at = info.location().map(|l| l.to_string());
                PANIC_LOCATION.with(|l| *l.borrow_mut() = at);
            } else {
                previous(info);
            }
        }));
        QuietPanics
    }
}

impl Drop for QuietPanics {
    fn drop(&mut self) {
        let _ = std::panic::take_hook();
    }
}

#[test]
fn real_art_corpus_invariants() {
    let Some(root) = external_data::test_art() else {
        return;
    };
    let started = Instant::now();
    let times = StageTimes::default();
    let mut report = String::new();
    let mut all_failures = Vec::new();
    let mut totals = Tally::default();
    let mut missing = Vec::new();
    {
        let _quiet = QuietPanics::install();
        for package in &PACKAGES {
            let folder = root.join(package.folder);
            if !folder.is_dir() {
                missing.push(package.name);
                continue;
            }
            let files = package_files(&folder);
            let t = Instant::now();
            let reports: Vec<FileReport> = files
                .par_iter()
                .enumerate()
                .map(|(k, file)| FileReport {
                    name: file
                        .file_name()
                        .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
                    outcome: process_file(file, k % HARMONIC_EVERY == 0, &times),
                })
                .collect();
            report += &package_report(package, &reports, t.elapsed().as_secs_f64());
            all_failures.extend(failure_lines(package, &reports));
            let tally = Tally::of(&reports);
            totals.files += tally.files;
            totals.checked += tally.checked;
            totals.curves += tally.curves;
            totals.violating_files += tally.violating_files;
        }
    }
    let secs = |c: &AtomicU64| c.load(Ordering::Relaxed) as f64 * 1e-9;
    let _ = writeln!(
        report,
        "\nall packages: {} files, {} rigged ({} curves), {} files break an invariant; {:.1} s \
         wall. Time per stage, summed over threads: usvg {:.1} s, import {:.1} s, Shepard rig \
         {:.1} s, Shepard checks {:.1} s, harmonic (every {}th file: domain, weights, rig, \
         checks) {:.1} s",
        totals.files,
        totals.checked,
        totals.curves,
        totals.violating_files,
        started.elapsed().as_secs_f64(),
        secs(&times.usvg),
        secs(&times.import),
        secs(&times.shepard_rig),
        secs(&times.checks),
        HARMONIC_EVERY,
        secs(&times.harmonic),
    );
    let diffs = external_data::repository_root().join("target/test-diffs");
    let list = diffs.join("real-art-corpus.txt");
    let written = std::fs::create_dir_all(&diffs)
        .and_then(|()| std::fs::write(&list, all_failures.join("\n") + "\n"));
    match written {
        Ok(()) => {
            let _ = writeln!(report, "every failure, one per line: {}", list.display());
        }
        Err(e) => {
            let _ = writeln!(report, "cannot write {}: {e}", list.display());
        }
    }
    eprintln!("{report}");
    if !missing.is_empty() {
        external_data::skip(&format!(
            "{} of {} art packages missing from test-art/node_modules ({}): run `npm ci` in \
             test-art/",
            missing.len(),
            PACKAGES.len(),
            missing.join(", ")
        ));
    }
    assert!(
        totals.violating_files <= KNOWN_VIOLATING_FILES,
        "{} of {} real-art files break an invariant, more than the {KNOWN_VIOLATING_FILES} known \
         (tables above; every failure in {})",
        totals.violating_files,
        totals.files,
        list.display()
    );
}

/// The checks fail on wrong results: a point moved by 1e-8 of its path's diagonal breaks the
/// exact check, a wrong map too, a non-finite point too; a deformed drawing far from its target
/// breaks the deformation check, and the right results pass.
#[test]
fn real_art_checks_detect_errors() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 72 72">
        <path d="M10 10 C20 0 40 0 50 10 S60 40 50 50 Z"/>
        <path d="M600 60 h0.01 v0.01 h-0.01 z"/></svg>"#;
    let drawing = splineskin::drawing::read_svg(svg, &ImportOptions::default()).expect("svg");
    let points = drawing.flat_points();
    assert_eq!(
        check_exact(&drawing, &points, Affine::IDENTITY).ok(),
        Some(0.0)
    );
    let map = rigid_map(&drawing);
    let mapped: Vec<Point> = points.iter().map(|&p| map * p).collect();
    assert!(check_exact(&drawing, &mapped, map).is_ok());
    assert!(check_exact(&drawing, &points, map).is_err());
    // Moving the small square's first point by 1e-8 of its diagonal is caught, and names it.
    let small = drawing.paths[0].points.len();
    let mut moved = points.clone();
    moved[small].x += 1e-8 * 0.01 * std::f64::consts::SQRT_2;
    let failure = check_exact(&drawing, &moved, Affine::IDENTITY).expect_err("moved point");
    assert_eq!((failure.path, failure.n_failing), (1, 1));
    assert!(failure.element.starts_with("path"), "{}", failure.element);
    let mut nan = points.clone();
    nan[1].y = f64::NAN;
    let failure = check_exact(&drawing, &nan, Affine::IDENTITY).expect_err("NaN");
    assert_eq!(failure.path, 0);
    assert!(failure.error.is_infinite());

    // The deformation check: the fit passes, the undeformed drawing does not (handle 0 moves by
    // 15 % of the diagonal, far more than 25 % of the path's plus 1 % of the drawing's).
    let leaf = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 72 72">
        <path d="M10 10 C20 0 40 0 50 10 S60 40 50 50 C40 60 20 60 10 50 Z"/>
        <path d="M30 30 C32 28 36 28 38 30"/></svg>"#;
    let leaf = splineskin::drawing::read_svg(leaf, &ImportOptions::default()).expect("svg");
    let handles = place_handles(&leaf);
    assert_eq!(handles.len(), N_HANDLES);
    assert!(handles[0] != handles[1] && handles[1] != handles[2] && handles[0] != handles[2]);
    let field = Shepard::new(&handles, ShepardOptions::default());
    let pose = deformation_pose(&leaf, &handles);
    let rig = SplineRig::precompute(&leaf, &field, &FitOptions::default()).expect("rig");
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&pose, &mut out).expect("update");
    let ratio = check_deformation(&leaf, &field, &pose, &out).expect("the fit follows");
    assert!(ratio < 1.0);
    let failure = check_deformation(&leaf, &field, &pose, &leaf.flat_points()).expect_err("rest");
    assert!(failure.error > failure.tolerance);
    out[1].x = f64::NAN;
    let failure = check_deformation(&leaf, &field, &pose, &out).expect_err("NaN");
    assert_eq!(failure.path, 0);
    assert!(failure.error.is_infinite());
}
