//! The join of a deformation operator with the spline fit (DESIGN.md, "The join"; issue 7,
//! item 6): point-handle, ARAP-quality deformation of a Bézier drawing in closed form, the
//! drawing staying a drawing of the same cubics under its junction constraints.
//!
//! [`DefOpRig`] has the formula, its sources, the recipe and an example; [`SplineJoin`] is its
//! part that depends on the drawing and the mesh only, reused for every operator on them, with
//! the curve points the pins hold ([`crate::PIN_SNAP_FRACTION`]); [`crate::DrawingDefOp`] builds
//! everything from a drawing and its handles.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};
use std::collections::HashMap;
use std::sync::Mutex;

use kurbo::Point;

use super::error::DefOpError;
use super::handle_basis::HandleBasis;
use super::operator::coefficients_at;
use super::operator::DefOp;
use super::pin_holding::{held_points, Held, PIN_SNAP_FRACTION};
use splineskin_core::domain::{Domain, MeshWeights};
use splineskin_core::drawing::Drawing;
use splineskin_core::mesh::TriMesh;
use splineskin_core::spline_fit::quadrature::SampledCurves;
use splineskin_core::spline_fit::system::{solve_path_with_points, HandleMaps, PointConstraint};
use splineskin_core::spline_fit::{validate, FitOptions};
use splineskin_core::weights::WeightField;

/// Largest distance of a drawing's point outside the operator's mesh, as a fraction of the
/// mesh's bounding-box diagonal: 0.05. Beyond it the nearest-boundary values are a guess too
/// far from anything the operator was trained on (and a drawing wholly outside, in other
/// units or coordinates, is caught).
pub const OUTSIDE_TOLERANCE_FRACTION: f64 = 0.05;

/// A drawing joined to a deformation operator: the drawing's control points as a closed-form
/// function of the handle configuration, `G_spline ψ(Q)`, junction constraints kept.
///
/// **Formula.** For a fixed handle configuration `Q` a [`DefOp`] (Poranne & Lipman 2016,
/// Eq. (3)) is a sum of spatial functions times vectors,
///
/// ```text
/// D(x, Q) = Σ_i φ_i(x) c_i(Q),      c(Q) = G ψ(Q)        (G: 2|Φ| × |Ψ|, DefOp::coefficients)
/// ```
///
/// which is linear blend skinning (Liu et al. 2014 §3) with weights `φ_i` and the pure
/// translations `T_i = [0 0 c_i]`. Between vertices a spatial function is the linear
/// interpolation of its vertex values (the hats' own definition; a reduced basis is given by
/// its vertex values `Dᵀ` only), so along a curve the target is the deformed mesh
/// `positions(Q) = Dᵀ G ψ(Q)` interpolated linearly in each triangle. Paper 1's
/// fit (Liu et al. 2014 §4; DESIGN.md §1: the junction-constrained least squares, solved per
/// path) is linear in its target, so with `F` the fit operator from mesh vertex positions to
/// the drawing's control points (junction constraints included),
///
/// ```text
/// control points(Q) = F · positions(Q) = F Dᵀ G · ψ(Q) = G_spline · ψ(Q)
/// G_spline = F Dᵀ G                                   (2 · n_points × |Ψ|, dense)
/// ```
///
/// `F` is the spline fit with the mesh's hat functions as weights and translations as maps:
/// column `(v, d)` of `F` is the fit of the target "hat of vertex `v`, times unit vector `d`".
/// Only the vertices of the triangles a path's curves cross have a non-zero column, so `F` is
/// assembled per path over those vertices (the quadrature cuts curves at mesh edges, where the
/// hats have kinks: [`MeshWeights`]' rule, exact for the piecewise-cubic weights) and never
/// over the whole mesh.
///
/// **Properties** (tested in `tests/defop_spline_join.rs`): at the rest configuration `Q = P`
/// the operator reproduces the rest mesh, its linear interpolation reproduces the identity
/// `x ↦ x` (every spatial basis here is linearly precise), and the fit reproduces a cubic
/// target, so the drawing comes back unchanged (to rounding); at any
/// `Q` the result satisfies every junction constraint of the drawing (C¹ equal tangents, G¹
/// parallel tangents with the input's length ratio, closed paths closed).
///
/// **Outside the mesh.** The drawing should lie in the operator's mesh (for a mesh from
/// [`Domain::build`] on the drawing, it does). Curve points outside it take the values of the
/// nearest boundary point, as [`MeshWeights`] does; [`DefOpRig::n_nodes_outside`] counts the
/// quadrature nodes where that happened, and a point farther out than
/// [`OUTSIDE_TOLERANCE_FRACTION`] of the mesh's diagonal is refused
/// ([`DefOpError::DrawingOutsideMesh`]).
///
/// ```text
/// once:            let rig = DefOpRig::precompute(&drawing, &mesh, &op, &FitOptions::default())?;
/// once per thread: let mut ev = rig.evaluator();          (owns ψ and the product's scratch)
/// each frame:      ev.update(&q, &mut points)?;           (ψ(Q), one dense mat-vec; allocates nothing)
/// ```
///
/// Without a mesh at hand, [`DrawingDefOp::train`] triangulates the drawing's domain
/// ([`training_domain_options`]), trains the operator ([`train`]) and builds the rig.
///
/// [`DrawingDefOp::train`]: crate::DrawingDefOp::train
/// [`training_domain_options`]: crate::training_domain_options
/// [`train`]: crate::train
///
/// ```
/// use kurbo::{Point, Rect, Vec2};
/// use splineskin_defop::{DefOp, DefOpOptions, DefOpRig, HandleBasisKind, SpatialBasis};
/// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin_core::mesh::TriMesh;
/// use splineskin_core::spline_fit::FitOptions;
///
/// // A strip with two handles and a made-up ground truth: every configuration translates the
/// // strip by the first handle's offset. A linear operator reproduces it exactly.
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// let handles = [9, 17]; // (0, 0.5) and (4, 0.5)
/// let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
/// let shifts = [(0.0, 0.0), (0.3, 0.1), (-0.2, 0.4), (0.1, -0.3), (0.5, 0.2)];
/// let configurations: Vec<Vec<Point>> =
///     shifts.iter().map(|&s| rest.iter().map(|&p| p + Vec2::from(s)).collect()).collect();
/// let solutions: Vec<Vec<Point>> =
///     shifts.iter().map(|&s| mesh.vertices.iter().map(|&p| p + Vec2::from(s)).collect()).collect();
/// let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Linear);
/// let op = DefOp::fit(&mesh, &handles, &SpatialBasis::hats(&mesh)?, &configurations, &solutions, &options)?;
///
/// // A wave drawn on the strip.
/// let wave = [(0.5, 0.5), (1.5, 0.9), (2.5, 0.1), (3.5, 0.5)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(wave.clone(), false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let rig = DefOpRig::precompute(&drawing, &mesh, &op, &FitOptions::default())?;
/// let mut evaluator = rig.evaluator();
/// let mut points = vec![Point::ZERO; rig.n_points()];
/// let q: Vec<Point> = rest.iter().map(|&p| p + Vec2::new(0.25, -0.5)).collect();
/// evaluator.update(&q, &mut points)?;
/// for (p, w) in points.iter().zip(&wave) {
///     assert!((*p - (*w + Vec2::new(0.25, -0.5))).hypot() < 1e-12);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// Output layout: the chain points of every path, concatenated as in
/// [`Drawing::flat_points`] (a closed path's last point repeats its first), as
/// [`splineskin_core::spline_fit::SplineRig::update`] writes them.
#[derive(Clone, Debug)]
pub struct DefOpRig {
    handle_basis: HandleBasis,
    n_points: usize,
    /// `G_spline`, column-major `2 n_points × |Ψ|`: row `2k + d` is coordinate `d` of point `k`.
    coefficients: Vec<f64>,
    n_nodes_outside: usize,
    max_outside_distance: f64,
    rank_deficient_paths: Vec<usize>,
}

/// The first pass over a path: a one-handle field that records every point it is evaluated at
/// (the quadrature's, whatever the rule) and reports the mesh's kinks.
struct Touched<'a> {
    locator: &'a MeshWeights,
    points: Mutex<Vec<Point>>,
}

impl WeightField for Touched<'_> {
    fn n_handles(&self) -> usize {
        1
    }

    fn eval(&self, p: Point, out: &mut [f64]) {
        out.fill(0.0);
        if let Ok(mut points) = self.points.lock() {
            points.push(p);
        }
    }

    fn kinks(&self, curve: &[Point; 4], out: &mut Vec<f64>) {
        self.locator.kinks(curve, out)
    }
}

/// A path's own vertices: the mesh vertices its quadrature nodes interpolate from, numbered
/// locally. A [`WeightField`] whose handle `a` is the hat function of local vertex `a`.
struct LocalHats<'a> {
    locator: &'a MeshWeights,
    /// Global vertex → local index, for the vertices the path touches.
    local: &'a HashMap<u32, u32>,
    n_local: usize,
}

impl WeightField for LocalHats<'_> {
    fn n_handles(&self) -> usize {
        self.n_local
    }

    fn eval(&self, p: Point, out: &mut [f64]) {
        out.fill(0.0);
        let Some(at) = self.locator.interpolation(p) else {
            out.fill(f64::NAN);
            return;
        };
        for (&v, &c) in at.vertices.iter().zip(&at.coefficients) {
            match self.local.get(&v) {
                Some(&a) => out[a as usize] += c,
                // The vertices were gathered at these very points: unreachable. NaN makes the
                // path's solve fail (FitError::Singular) rather than drop a weight.
                _ if c != 0.0 => out.fill(f64::NAN),
                _ => {}
            }
        }
    }

    fn kinks(&self, curve: &[Point; 4], out: &mut Vec<f64>) {
        self.locator.kinks(curve, out)
    }
}

impl DefOpRig {
    /// Precomputes the join of `drawing` with `op`, an operator on `mesh` (the mesh it was
    /// fitted or trained on), with the fit's quadrature, measure and junction constraints from
    /// `options`: per path, the fit `F` over the vertices its curves touch (one sparse LU, `2`
    /// right-hand sides per vertex), then `F Dᵀ G`. The operator's handles pin the art under them
    /// ([`SplineJoin::new`]). The same as [`SplineJoin::new`] then [`SplineJoin::rig`]; keep
    /// the [`SplineJoin`] to join other operators on the same mesh.
    ///
    /// Errors: an invalid mesh, an operator of another vertex count
    /// ([`DefOpError::BasisMismatch`]), a malformed drawing ([`DefOpError::Fit`]), a point of
    /// the drawing farther outside the mesh than [`OUTSIDE_TOLERANCE_FRACTION`] of its
    /// diagonal ([`DefOpError::DrawingOutsideMesh`]).
    pub fn precompute(
        drawing: &Drawing,
        mesh: &TriMesh,
        op: &DefOp,
        options: &FitOptions,
    ) -> Result<DefOpRig, DefOpError> {
        mesh.check()?;
        check_vertex_count(op, mesh.n_vertices())?;
        let pins: Vec<Point> = op.handles().iter().map(|&h| mesh.vertices[h]).collect();
        SplineJoin::new(drawing, mesh, &pins, options)?.rig(op)
    }

    /// [`DefOpRig::precompute`] on the domain the operator was trained on: checks that the
    /// domain's handle vertices are the operator's ([`DefOpError::HandleMismatch`]).
    pub fn from_domain(
        drawing: &Drawing,
        domain: &Domain,
        op: &DefOp,
        options: &FitOptions,
    ) -> Result<DefOpRig, DefOpError> {
        if domain.handle_vertices != op.handles {
            return Err(DefOpError::HandleMismatch {
                domain: domain.handle_vertices.clone(),
                op: op.handles.clone(),
            });
        }
        DefOpRig::precompute(drawing, &domain.mesh, op, options)
    }

    /// A worker for updates, owning its scratch (one per thread).
    pub fn evaluator(&self) -> DefOpRigEvaluator<'_> {
        DefOpRigEvaluator {
            rig: self,
            psi: vec![0.0; self.handle_basis.n_functions()],
            xy: vec![0.0; 2 * self.n_points],
        }
    }

    /// The deformed control points at the configuration `q` (allocating; see
    /// [`DefOpRigEvaluator::update`] for the per-frame form).
    pub fn deform(&self, q: &[Point]) -> Result<Vec<Point>, DefOpError> {
        let mut points = vec![Point::ZERO; self.n_points];
        self.evaluator().update(q, &mut points)?;
        Ok(points)
    }

    /// Writes the drawing's coordinates at the configuration `q` into `out` as
    /// `x0, y0, x1, y1, …` (`2 ·` [`DefOpRig::n_points`] values, [`Drawing::flat_points`]
    /// order): `out = G_spline ψ(q)`, with `ψ(q)` computed in `psi` (length
    /// `handle_basis().n_functions()`). For callers that own the output memory (numpy arrays,
    /// WebAssembly) and keep their own scratch; allocates nothing. Errors (before any work) on a
    /// wrong count, a non-finite `q` or a wrong buffer length.
    ///
    /// ```
    /// # use kurbo::{Point, Rect};
    /// # use splineskin_defop::{DefOp, DefOpOptions, DefOpRig, HandleBasisKind, SpatialBasis};
    /// # use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
    /// # use splineskin_core::mesh::TriMesh;
    /// # use splineskin_core::spline_fit::FitOptions;
    /// # let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
    /// # let handles = [9, 17];
    /// # let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
    /// # let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Linear);
    /// # let op = DefOp::fit(&mesh, &handles, &SpatialBasis::hats(&mesh)?, &[rest.clone()],
    /// #     &[mesh.vertices.clone()], &options)?;
    /// let line = [(0.5, 0.5), (1.5, 0.5), (2.5, 0.5), (3.5, 0.5)].map(Point::from).to_vec();
    /// let drawing = Drawing {
    ///     paths: vec![Path::new(line.clone(), false, &JunctionOptions::default()).unwrap()],
    ///     ..Default::default()
    /// };
    /// let rig = DefOpRig::precompute(&drawing, &mesh, &op, &FitOptions::default())?;
    /// let mut psi = vec![0.0; rig.handle_basis().n_functions()];
    /// let mut coords = vec![0.0; 2 * rig.n_points()];
    /// rig.write_coords(&rest, &mut psi, &mut coords)?;
    /// // The same numbers as the points `deform` gives.
    /// let points = rig.deform(&rest)?;
    /// assert!(points.iter().zip(coords.chunks_exact(2)).all(|(p, xy)| p.x == xy[0] && p.y == xy[1]));
    /// // The rest configuration gives the drawing back.
    /// assert!(points.iter().zip(&line).all(|(p, l)| (*p - *l).hypot() < 1e-12));
    /// // Buffers of the wrong length are refused.
    /// assert!(rig.write_coords(&rest, &mut psi, &mut coords[1..]).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn write_coords(
        &self,
        q: &[Point],
        psi: &mut [f64],
        out: &mut [f64],
    ) -> Result<(), DefOpError> {
        if out.len() != 2 * self.n_points {
            return Err(DefOpError::BufferLength {
                given: out.len(),
                expected: 2 * self.n_points,
            });
        }
        if psi.len() != self.handle_basis.n_functions() {
            return Err(DefOpError::BufferLength {
                given: psi.len(),
                expected: self.handle_basis.n_functions(),
            });
        }
        if q.len() != self.n_handles() {
            return Err(DefOpError::TargetCount {
                given: q.len(),
                n_handles: self.n_handles(),
            });
        }
        coefficients_at(&self.handle_basis, &self.coefficients, q, psi, out)
    }

    /// Number of handles a configuration has.
    pub fn n_handles(&self) -> usize {
        self.handle_basis.n_handles()
    }

    /// Number of chain points written (all paths, [`Drawing::flat_points`] layout).
    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// The handle basis `Ψ` (the operator's).
    pub fn handle_basis(&self) -> &HandleBasis {
        &self.handle_basis
    }

    /// `G_spline` as a column-major `2 n_points × |Ψ|` matrix: row `2k + d` gives coordinate
    /// `d` of chain point `k`.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// Quadrature points of the drawing (where the fit evaluates its weights) that lie outside
    /// the mesh: they took the values of the nearest boundary point (0 when the drawing is
    /// inside the mesh).
    pub fn n_nodes_outside(&self) -> usize {
        self.n_nodes_outside
    }

    /// The largest distance of those nodes to the mesh, drawing units (0 when none).
    pub fn max_outside_distance(&self) -> f64 {
        self.max_outside_distance
    }

    /// Paths whose fit system was found rank deficient (only with
    /// [`FitOptions::check_rank`], as [`splineskin_core::spline_fit::SplineRig::rank_deficient_paths`]);
    /// their points are whatever the LU factorisation produced.
    pub fn rank_deficient_paths(&self) -> &[usize] {
        &self.rank_deficient_paths
    }
}

/// The operator-independent half of the join: for every path of a drawing, the fit `F` over
/// the mesh vertices its curves touch ([`DefOpRig`]'s formula). `F` depends on the drawing,
/// the mesh and the fit options only, so an operator retrained on the same mesh (more samples,
/// e.g. around a configuration the user dragged to) is joined by products alone:
/// `G_spline = F · (Dᵀ G)` at the touched vertices, milliseconds where the fit took a good
/// part of a second on the octopus.
///
/// ```
/// # use kurbo::{Point, Rect, Vec2};
/// # use splineskin_defop::{DefOp, DefOpOptions, DefOpRig, HandleBasisKind, SpatialBasis, SplineJoin};
/// # use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// # use splineskin_core::mesh::TriMesh;
/// # use splineskin_core::spline_fit::FitOptions;
/// # let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// # let handles = [9, 17];
/// # let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
/// # let shifts = [(0.0, 0.0), (0.3, 0.1), (-0.2, 0.4), (0.1, -0.3), (0.5, 0.2)];
/// # let configurations: Vec<Vec<Point>> =
/// #     shifts.iter().map(|&s| rest.iter().map(|&p| p + Vec2::from(s)).collect()).collect();
/// # let solutions: Vec<Vec<Point>> =
/// #     shifts.iter().map(|&s| mesh.vertices.iter().map(|&p| p + Vec2::from(s)).collect()).collect();
/// # let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Linear);
/// # let op = DefOp::fit(&mesh, &handles, &SpatialBasis::hats(&mesh)?, &configurations, &solutions, &options)?;
/// let line = [(0.5, 0.5), (1.5, 0.5), (2.5, 0.5), (3.5, 0.5)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(line, false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let pins: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
/// let join = SplineJoin::new(&drawing, &mesh, &pins, &FitOptions::default())?;
/// let rig = join.rig(&op)?; // and again for every operator on this mesh
/// let direct = DefOpRig::precompute(&drawing, &mesh, &op, &FitOptions::default())?;
/// assert_eq!(rig.coefficients(), direct.coefficients());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct SplineJoin {
    n_vertices: usize,
    n_points: usize,
    paths: Vec<PathFit>,
    parallel: bool,
    n_nodes_outside: usize,
    max_outside_distance: f64,
    rank_deficient_paths: Vec<usize>,
    n_held: usize,
}

/// A path to fit, where it sits in the drawing, and the curve points pins hold on it.
struct FittedPath<'a> {
    index: usize,
    path: &'a splineskin_core::drawing::Path,
    /// Its first chain point in the drawing's layout.
    offset: usize,
    held: &'a [Held],
}

/// One path's fit over the mesh vertices it touches.
#[derive(Clone, Debug)]
struct PathFit {
    /// The touched vertices, in local order.
    vertices: Vec<u32>,
    /// `F`: `2m × 2 n_local` (`m` unknown points), column `2a + d` the translation coordinate
    /// `d` of local vertex `a`.
    f: Mat<f64>,
    /// `(row of G_spline, row of F)` for every coordinate the path writes.
    rows: Vec<(usize, usize)>,
    n_nodes_outside: usize,
    max_outside_distance: f64,
    rank_deficient: bool,
}

impl SplineJoin {
    /// Fits every path of `drawing` over the hats of `mesh` (module documentation; the work
    /// of [`DefOpRig::precompute`] that does not involve the operator), holding the art
    /// under each of `pins` (the operator's handles at rest).
    ///
    /// **Pins hold the art** (Puppet Warp's promise, and the join's side of the paper's
    /// Proposition 1: the operator interpolates its handles at every configuration). A
    /// least-squares fit alone lets the curve under a pin slide off it where the deformation
    /// is sharpest, which is at a dragged point handle (ARAP-type energies concentrate
    /// stretch in the handle's one-ring). So the curve point nearest each pin on the art
    /// (within [`PIN_SNAP_FRACTION`] of the mesh's diagonal) is constrained to the deformed
    /// mesh at that point ([`PointConstraint`]); for a pin exactly on a curve that is the pin
    /// itself, so the curve passes through it at every configuration. One pin per curve (the nearest), none
    /// on an anchor another pin holds. At the rest configuration the constraint holds for the
    /// input, so the drawing still comes back unchanged. Errors as [`DefOpRig::precompute`]'s,
    /// but for the operator's.
    pub fn new(
        drawing: &Drawing,
        mesh: &TriMesh,
        pins: &[Point],
        options: &FitOptions,
    ) -> Result<SplineJoin, DefOpError> {
        mesh.check()?;
        validate(drawing)?;
        let n_vertices = mesh.n_vertices();
        // One value per vertex (unused): the field only locates points and finds kinks.
        let locator = MeshWeights::new(mesh, vec![0.0; n_vertices], 1)?;
        let bounds = mesh.vertices.iter().fold(
            kurbo::Rect::from_points(mesh.vertices[0], mesh.vertices[0]),
            |r, &p| r.union_pt(p),
        );
        let tolerance = OUTSIDE_TOLERANCE_FRACTION * bounds.width().hypot(bounds.height());
        let ranges: Vec<_> = drawing.path_ranges().collect();
        let held = held_points(
            drawing,
            pins,
            PIN_SNAP_FRACTION * mesh.bounding_box_diagonal(),
        );
        // Paths are independent: fit them in parallel if asked.
        let paths: Vec<PathFit> =
            splineskin_core::parallel::try_map(&drawing.paths, options.parallel, |pi, path| {
                let fitted = FittedPath {
                    index: pi,
                    path,
                    offset: ranges[pi].start,
                    held: &held[pi],
                };
                fit_path(&locator, tolerance, options, fitted)
            })?;
        let n_held = held.iter().map(Vec::len).sum();
        let n_nodes_outside = paths.iter().map(|p| p.n_nodes_outside).sum();
        let max_outside_distance = paths
            .iter()
            .map(|p| p.max_outside_distance)
            .fold(0.0, f64::max);
        if n_nodes_outside > 0 {
            tracing::warn!(
                "{n_nodes_outside} quadrature nodes of the drawing lie outside the operator's mesh (at most {max_outside_distance:e} drawing units): they take the nearest boundary point's values"
            );
        }
        Ok(SplineJoin {
            n_vertices,
            n_points: drawing.n_points(),
            rank_deficient_paths: (0..paths.len())
                .filter(|&pi| paths[pi].rank_deficient)
                .collect(),
            paths,
            parallel: options.parallel,
            n_nodes_outside,
            max_outside_distance,
            n_held,
        })
    }

    /// Curve points held by pins ([`SplineJoin::new`]).
    pub fn n_held(&self) -> usize {
        self.n_held
    }

    /// The rig of `op` (an operator on this join's mesh): `G_spline = F Dᵀ G`, path by path.
    /// Errors on an operator of another vertex count ([`DefOpError::BasisMismatch`]).
    pub fn rig(&self, op: &DefOp) -> Result<DefOpRig, DefOpError> {
        check_vertex_count(op, self.n_vertices)?;
        let n_phi = op.spatial.n_functions();
        let n_psi = op.handle_basis.n_functions();
        let g = MatRef::from_column_major_slice(&op.coefficients, 2 * n_phi, n_psi);
        let blocks: Vec<Mat<f64>> =
            splineskin_core::parallel::try_map(&self.paths, self.parallel, |_, path| {
                // The local vertices' positions as rows over Ψ (row 2a + d: coordinate d of
                // local vertex a), i.e. the rows of Dᵀ G at those vertices.
                let positions = local_positions(op, g, &path.vertices);
                let mut block = Mat::<f64>::zeros(path.f.nrows(), n_psi);
                matmul(
                    block.as_mut(),
                    Accum::Replace,
                    path.f.as_ref(),
                    positions.as_ref(),
                    1.0,
                    Par::Seq,
                );
                Ok::<_, DefOpError>(block)
            })?;
        let rows = 2 * self.n_points;
        let mut coefficients = vec![0.0; rows * n_psi];
        for (path, block) in self.paths.iter().zip(&blocks) {
            for &(row, src) in &path.rows {
                for c in 0..n_psi {
                    coefficients[c * rows + row] = block[(src, c)];
                }
            }
        }
        Ok(DefOpRig {
            handle_basis: op.handle_basis.clone(),
            n_points: self.n_points,
            coefficients,
            n_nodes_outside: self.n_nodes_outside,
            max_outside_distance: self.max_outside_distance,
            rank_deficient_paths: self.rank_deficient_paths.clone(),
        })
    }

    /// Number of chain points a rig of this join writes.
    pub fn n_points(&self) -> usize {
        self.n_points
    }
}

/// Refuses an operator whose vertex count is not the mesh's.
fn check_vertex_count(op: &DefOp, n_vertices: usize) -> Result<(), DefOpError> {
    if op.n_vertices() != n_vertices {
        return Err(DefOpError::BasisMismatch {
            basis_vertices: op.n_vertices(),
            n_vertices,
        });
    }
    Ok(())
}

/// `F` for a path: its quadrature points and the vertices they touch, then its fit over
/// those vertices' hats, the held points constrained to the hats' interpolation there.
fn fit_path(
    locator: &MeshWeights,
    tolerance: f64,
    options: &FitOptions,
    fitted: FittedPath<'_>,
) -> Result<PathFit, DefOpError> {
    let FittedPath {
        index: pi,
        path,
        offset,
        held,
    } = fitted;
    let one = Drawing {
        paths: vec![path.clone()],
        ..Default::default()
    };
    // First pass: the points where the path's quadrature evaluates its weights (nodes cut at
    // mesh edges; the authors' rule's samples), and the vertices they touch.
    let touched = Touched {
        locator,
        points: Mutex::new(Vec::new()),
    };
    SampledCurves::sample(&one, &touched, options);
    let mut points = touched.points.into_inner().unwrap_or_default();
    // The held points' triangles count as touched (their hats enter the constraint rows).
    points.extend(held.iter().map(|h| h.point));
    let mut local: HashMap<u32, u32> = HashMap::new();
    let mut vertices: Vec<u32> = Vec::new();
    let mut n_nodes_outside = 0;
    let mut max_outside_distance: f64 = 0.0;
    for p in points {
        let at = locator.interpolation(p).ok_or(DefOpError::Domain(
            splineskin_core::domain::DomainError::EmptyDomain {
                reason: "the mesh has no boundary (a bug: valid meshes have one)",
            },
        ))?;
        if at.outside_distance > 0.0 {
            if at.outside_distance > tolerance {
                return Err(DefOpError::DrawingOutsideMesh {
                    path: pi,
                    x: p.x,
                    y: p.y,
                    distance: at.outside_distance,
                    tolerance,
                });
            }
            n_nodes_outside += 1;
            max_outside_distance = max_outside_distance.max(at.outside_distance);
        }
        for &v in &at.vertices {
            local.entry(v).or_insert_with(|| {
                vertices.push(v);
                (vertices.len() - 1) as u32
            });
        }
    }
    let field = LocalHats {
        locator,
        local: &local,
        n_local: vertices.len(),
    };
    let samples = SampledCurves::sample(&one, &field, options);
    let constraints: Vec<PointConstraint> = held
        .iter()
        .filter_map(|h| {
            let at = locator.interpolation(h.point)?;
            let weights = at
                .vertices
                .iter()
                .zip(&at.coefficients)
                .filter(|(_, &c)| c != 0.0)
                .filter_map(|(v, &c)| local.get(v).map(|&a| (a as usize, c)))
                .collect();
            Some(PointConstraint {
                curve: h.curve,
                t: h.t,
                point: h.point,
                weights,
            })
        })
        .collect();
    // F: 2m × 2 n_local, column 2a + d = translation coordinate d of local vertex a.
    let solved = solve_path_with_points(
        pi,
        path,
        &samples,
        0,
        options,
        HandleMaps::Translation,
        &constraints,
    )?;
    Ok(PathFit {
        vertices,
        f: solved.operator,
        rows: path.coordinate_rows(offset).collect(),
        n_nodes_outside,
        max_outside_distance,
        rank_deficient: solved.rank_deficient,
    })
}

/// Rows of `Dᵀ G` at `vertices`: `2 · vertices.len() × |Ψ|`, row `2a + d` coordinate `d` of
/// vertex `vertices[a]`'s position over `Ψ`.
fn local_positions(op: &DefOp, g: MatRef<'_, f64>, vertices: &[u32]) -> Mat<f64> {
    let n_phi = op.spatial.n_functions();
    let n_local = vertices.len();
    let mut out = Mat::<f64>::zeros(2 * n_local, g.ncols());
    if op.spatial.is_hats() {
        for (a, &v) in vertices.iter().enumerate() {
            for d in 0..2 {
                out.row_mut(2 * a + d)
                    .copy_from(g.row(d * n_phi + v as usize));
            }
        }
        return out;
    }
    // Dᵀ at the local vertices (n_local × |Φ|), times G's x rows and y rows.
    let n_vertices = op.n_vertices();
    let dt = Mat::<f64>::from_fn(n_local, n_phi, |a, i| {
        op.vertex_values[i * n_vertices + vertices[a] as usize]
    });
    for d in 0..2 {
        let mut part = Mat::<f64>::zeros(n_local, g.ncols());
        matmul(
            part.as_mut(),
            Accum::Replace,
            dt.as_ref(),
            g.subrows(d * n_phi, n_phi),
            1.0,
            Par::Seq,
        );
        for a in 0..n_local {
            out.row_mut(2 * a + d).copy_from(part.row(a));
        }
    }
    out
}

/// Updates a [`DefOpRig`] without allocating: `ψ(Q)` and the product live in its buffers.
///
/// ```
/// # use kurbo::{Point, Rect, Vec2};
/// # use splineskin_defop::{DefOp, DefOpOptions, DefOpRig, HandleBasisKind, SpatialBasis};
/// # use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// # use splineskin_core::mesh::TriMesh;
/// # use splineskin_core::spline_fit::FitOptions;
/// # let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// # let handles = [9, 17];
/// # let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
/// # let shifts = [(0.0, 0.0), (0.3, 0.1), (-0.2, 0.4), (0.1, -0.3), (0.5, 0.2)];
/// # let configurations: Vec<Vec<Point>> =
/// #     shifts.iter().map(|&s| rest.iter().map(|&p| p + Vec2::from(s)).collect()).collect();
/// # let solutions: Vec<Vec<Point>> =
/// #     shifts.iter().map(|&s| mesh.vertices.iter().map(|&p| p + Vec2::from(s)).collect()).collect();
/// # let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Linear);
/// # let op = DefOp::fit(&mesh, &handles, &SpatialBasis::hats(&mesh)?, &configurations, &solutions, &options)?;
/// let line = [(0.5, 0.5), (1.5, 0.5), (2.5, 0.5), (3.5, 0.5)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(line.clone(), false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let rig = DefOpRig::precompute(&drawing, &mesh, &op, &FitOptions::default())?;
/// let mut evaluator = rig.evaluator();
/// let mut points = vec![Point::ZERO; rig.n_points()];
/// // The rest configuration gives the drawing back.
/// evaluator.update(&rest, &mut points)?;
/// assert!(points.iter().zip(&line).all(|(p, l)| (*p - *l).hypot() < 1e-12));
/// // One point per handle, finite: anything else is refused.
/// assert!(evaluator.update(&rest[..1], &mut points).is_err());
/// assert!(evaluator.update(&[rest[0], Point::new(f64::NAN, 0.0)], &mut points).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct DefOpRigEvaluator<'a> {
    rig: &'a DefOpRig,
    psi: Vec<f64>,
    /// `G_spline ψ`: x, y of every point in turn.
    xy: Vec<f64>,
}

impl DefOpRigEvaluator<'_> {
    /// The rig evaluated.
    pub fn rig(&self) -> &DefOpRig {
        self.rig
    }

    /// Writes the drawing's control points at the configuration `q` (one point per handle)
    /// into `out` ([`DefOpRig::n_points`] points): `ψ(q)`, then `G_spline ψ(q)`. Allocates
    /// nothing. Errors (before any work) on a wrong count, a non-finite `q` or a wrong
    /// buffer length.
    pub fn update(&mut self, q: &[Point], out: &mut [Point]) -> Result<(), DefOpError> {
        if out.len() != self.rig.n_points {
            return Err(DefOpError::BufferLength {
                given: out.len(),
                expected: self.rig.n_points,
            });
        }
        // The handle count and finiteness are checked by `write_coords`.
        self.rig.write_coords(q, &mut self.psi, &mut self.xy)?;
        for (p, xy) in out.iter_mut().zip(self.xy.chunks_exact(2)) {
            *p = Point::new(xy[0], xy[1]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use kurbo::{Affine, Rect, Vec2};

    use super::*;
    use crate::{Arap, ArapOptions, DefOpOptions, HandleBasisKind, SpatialBasis};
    use splineskin_core::drawing::{JunctionOptions, Path};
    use splineskin_core::spline_fit::SplineRig;

    /// A strip `[0, 4] × [0, 1]` with two handles and a quadratic operator fitted to ARAP
    /// solutions.
    fn strip_operator() -> (TriMesh, DefOp, Vec<Point>) {
        let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 16, 4).unwrap();
        let handles = [34, 50]; // (0, 0.5) and (4, 0.5)
        let rest: Vec<Point> = handles.iter().map(|&h| mesh.vertices[h]).collect();
        let arap = Arap::new(&mesh, &handles, ArapOptions::default()).unwrap();
        let offsets = [
            (0.0, 0.0, 0.0, 0.0),
            (0.0, 0.0, -0.3, 0.8),
            (0.2, -0.1, 0.1, -0.6),
            (-0.2, 0.3, 0.4, 0.2),
            (0.1, 0.2, -0.5, -0.3),
            (0.3, -0.3, 0.2, 0.7),
            (-0.1, -0.2, -0.2, 0.4),
            (0.0, 0.4, 0.3, -0.1),
        ];
        let configurations: Vec<Vec<Point>> = offsets
            .iter()
            .map(|&(a, b, c, d)| vec![rest[0] + Vec2::new(a, b), rest[1] + Vec2::new(c, d)])
            .collect();
        let solutions: Vec<Vec<Point>> = configurations
            .iter()
            .map(|q| {
                let mut u = mesh.vertices.clone();
                arap.solve(q, &mut u).unwrap();
                u
            })
            .collect();
        let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Quadratic);
        let spatial = SpatialBasis::hats(&mesh).unwrap();
        let op = DefOp::fit(
            &mesh,
            &handles,
            &spatial,
            &configurations,
            &solutions,
            &options,
        )
        .unwrap();
        (mesh, op, rest)
    }

    #[test]
    fn join_outside_the_mesh_takes_the_nearest_boundary_values() {
        let (mesh, op, rest) = strip_operator();
        // A wave leaving the strip through its right side, 0.1 beyond it (tolerance: 5 % of
        // the diagonal, 0.21).
        let wave = [(2.5, 0.5), (3.2, 0.9), (3.8, 0.1), (4.1, 0.5)].map(Point::from);
        let drawing = Drawing {
            paths: vec![Path::new(wave.to_vec(), false, &JunctionOptions::default()).unwrap()],
            ..Default::default()
        };
        let options = FitOptions::default();
        let rig = DefOpRig::precompute(&drawing, &mesh, &op, &options).unwrap();
        assert!(rig.n_nodes_outside() > 0);
        // The last Gauss node is just before the end point.
        let d = rig.max_outside_distance();
        assert!(d > 0.09 && d < 0.1, "{d}");
        // The same as the spline fit with MeshWeights of the deformed strip (its outside
        // rule), whose x and y coordinates are the weights of two unit translations.
        let q = [
            rest[0] + Vec2::new(0.1, 0.3),
            rest[1] + Vec2::new(-0.4, 0.5),
        ];
        let positions = op.eval(&q).unwrap();
        let w: Vec<f64> = positions.iter().flat_map(|p| [p.x, p.y]).collect();
        let field = MeshWeights::new(&mesh, w, 2).unwrap();
        let spline = SplineRig::precompute(&drawing, &field, &options).unwrap();
        let mut want = vec![Point::ZERO; 4];
        let pose = [
            Affine::new([0.0, 0.0, 0.0, 0.0, 1.0, 0.0]),
            Affine::new([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]),
        ];
        spline.update(&pose, &mut want).unwrap();
        let got = rig.deform(&q).unwrap();
        for (g, w) in got.iter().zip(&want) {
            assert!((*g - *w).hypot() < 1e-12, "{got:?} vs {want:?}");
        }
        // At rest the target is the curve inside the mesh and its clamp to x ≤ 4 outside: not
        // a cubic, so the fit moves the curve, by less than the clamp.
        let rest_points = rig.deform(&rest).unwrap();
        let moved = rest_points
            .iter()
            .zip(&wave)
            .map(|(p, w)| (*p - *w).hypot())
            .fold(0.0, f64::max);
        assert!(moved > 1e-4 && moved < 0.1, "{moved}");
        // Twice as far out: refused.
        let far = [(2.5, 0.5), (3.2, 0.9), (3.8, 0.1), (4.3, 0.5)].map(Point::from);
        let drawing = Drawing {
            paths: vec![Path::new(far.to_vec(), false, &JunctionOptions::default()).unwrap()],
            ..Default::default()
        };
        assert!(matches!(
            DefOpRig::precompute(&drawing, &mesh, &op, &options),
            Err(DefOpError::DrawingOutsideMesh { path: 0, .. })
        ));
    }
}
