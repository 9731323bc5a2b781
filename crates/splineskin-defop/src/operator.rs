//! [`DefOp`]: a fitted `(Φ, Ψ)` deformation operator (Poranne & Lipman 2016, Eq. (3);
//! DESIGN.md §4) and its evaluation,
//!
//! ```text
//! D(x, Q) = Σ_i Σ_j C_ij φ_i(x) ψ_j(Q)         positions = Dᵀ · (G · ψ(Q))
//! ```
//!
//! with `G` (`|Φ| × |Ψ|` per coordinate, the paper's `Cᵀ`) fitted once by [`DefOp::fit`] and
//! `Dᵀ` (`n_vertices × |Φ|`) the spatial functions' vertex values (the identity for the hats).
//! An evaluation is the handle basis at `Q` (`|Ψ|` values), one matrix–vector product with `G`
//! (the coefficients `c_i(Q)` of the spatial functions: for a fixed `Q` the operator is linear
//! blend skinning with weights `φ_i` and translations `c_i`, DESIGN.md's join) and, for a
//! reduced basis, one with `Dᵀ`.
//!
//! ```text
//! once:            DefOp::fit(…)                      (or a DefOp from training)
//! once per thread: let mut ev = op.evaluator();       (owns the scratch)
//! each frame:      ev.eval(&q, &mut positions)        (allocates nothing)
//! ```

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
use kurbo::Point;

use super::error::DefOpError;
use super::handle_basis::HandleBasis;
use super::handles::check_finite_targets;
use super::spatial_basis::SpatialBasis;

/// A deformation operator: spatial basis, handle basis and the fitted coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct DefOp {
    pub(crate) spatial: SpatialBasis,
    pub(crate) handle_basis: HandleBasis,
    pub(crate) handles: Vec<usize>,
    /// `G`, column-major `2|Φ| × |Ψ|`: row `i` holds `φ_i`'s x coefficients over `Ψ`, row
    /// `|Φ| + i` its y coefficients.
    pub(crate) coefficients: Vec<f64>,
    /// `Dᵀ`, column-major `n_vertices × |Φ|` (empty for the hats).
    pub(crate) vertex_values: Vec<f64>,
}

impl DefOp {
    /// The spatial basis `Φ`.
    pub fn spatial_basis(&self) -> &SpatialBasis {
        &self.spatial
    }

    /// The handle basis `Ψ`.
    pub fn handle_basis(&self) -> &HandleBasis {
        &self.handle_basis
    }

    /// The handle vertices, in the order configurations list their points.
    pub fn handles(&self) -> &[usize] {
        &self.handles
    }

    /// Number of handles.
    pub fn n_handles(&self) -> usize {
        self.handles.len()
    }

    /// Number of mesh vertices an evaluation gives.
    pub fn n_vertices(&self) -> usize {
        self.spatial.n_vertices()
    }

    /// `G` as a column-major `2|Φ| × |Ψ|` matrix (rows `i` and `|Φ| + i`: `φ_i`'s x and y
    /// coefficients).
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// The vertex positions each handle function contributes: `u_v(Q) = Σ_j ψ_j(Q) U_vj` with
    /// `U = Dᵀ G` (module doc), returned row-major `n_vertices × 2|Ψ|`: entry `v · 2|Ψ| + 2j`
    /// is the x of `U_vj`, the next its y. An evaluation is this matrix times `ψ(Q)`, so
    /// anything linear in the deformed vertices is linear in `ψ` through it.
    ///
    /// ```
    /// use kurbo::{Point, Rect};
    /// use splineskin_defop::{DefOp, DefOpOptions, HandleBasisKind, SpatialBasis};
    /// use splineskin_core::mesh::TriMesh;
    /// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
    /// let handles = [9, 17];
    /// let shift = |k: usize| kurbo::Vec2::new(0.1 * k as f64, 0.);
    /// let configurations: Vec<Vec<Point>> =
    ///     (0..6).map(|k| vec![Point::new(0., 0.5) + shift(k), Point::new(4., 0.5) + shift(k)]).collect();
    /// let solutions: Vec<Vec<Point>> =
    ///     (0..6).map(|k| mesh.vertices.iter().map(|&p| p + shift(k)).collect()).collect();
    /// let spatial = SpatialBasis::hats(&mesh)?;
    /// let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Linear);
    /// let op = DefOp::fit(&mesh, &handles, &spatial, &configurations, &solutions, &options)?;
    /// let u = op.function_positions();
    /// let n_psi = op.handle_basis().n_functions();
    /// // ψ₀ = 1 is the constant function: at the rest configuration only it is on, and its
    /// // column holds the rest mesh.
    /// let v = 5;
    /// let rest = mesh.vertices[v];
    /// assert!((u[v * 2 * n_psi] - rest.x).abs() < 1e-9 && (u[v * 2 * n_psi + 1] - rest.y).abs() < 1e-9);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn function_positions(&self) -> Vec<f64> {
        let n_vertices = self.n_vertices();
        let n_phi = self.spatial.n_functions();
        let n_psi = self.handle_basis.n_functions();
        let mut out = vec![0.0; n_vertices * 2 * n_psi];
        for (j, column) in self.coefficients.chunks_exact(2 * n_phi).enumerate() {
            let (cx, cy) = column.split_at(n_phi);
            if self.spatial.is_hats() {
                for (v, (&x, &y)) in cx.iter().zip(cy).enumerate() {
                    out[v * 2 * n_psi + 2 * j] = x;
                    out[v * 2 * n_psi + 2 * j + 1] = y;
                }
                continue;
            }
            for (i, values) in self.vertex_values.chunks_exact(n_vertices).enumerate() {
                let (a, b) = (cx[i], cy[i]);
                for (v, &d) in values.iter().enumerate() {
                    out[v * 2 * n_psi + 2 * j] += a * d;
                    out[v * 2 * n_psi + 2 * j + 1] += b * d;
                }
            }
        }
        out
    }

    /// A worker for evaluations, owning its scratch (one per thread).
    pub fn evaluator(&self) -> DefOpEvaluator<'_> {
        DefOpEvaluator {
            op: self,
            psi: vec![0.0; self.handle_basis.n_functions()],
            c: vec![0.0; 2 * self.spatial.n_functions()],
            xy: vec![0.0; 2 * self.n_vertices()],
        }
    }

    /// The deformed vertices at the configuration `q` (allocating; see
    /// [`DefOpEvaluator::eval`] for the per-frame form).
    pub fn eval(&self, q: &[Point]) -> Result<Vec<Point>, DefOpError> {
        let mut positions = vec![Point::ZERO; self.n_vertices()];
        self.evaluator().eval(q, &mut positions)?;
        Ok(positions)
    }
}

/// Evaluates a [`DefOp`] without allocating: the handle basis values, the spatial
/// coefficients and (reduced bases) the vertex positions live in its buffers.
///
/// ```
/// use kurbo::{Point, Rect};
/// use splineskin_defop::{DefOp, DefOpOptions, HandleBasisKind, SpatialBasis};
/// use splineskin_core::mesh::TriMesh;
/// // A strip whose two handles' every configuration is "translate the strip" (a made-up
/// // ground truth): the linear operator reproduces it exactly.
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// let handles = [9, 17];
/// let configurations: Vec<Vec<Point>> = (0..6)
///     .map(|k| vec![Point::new(0.1 * k as f64, 0.5), Point::new(4.0 + 0.1 * k as f64, 0.5)])
///     .collect();
/// let solutions: Vec<Vec<Point>> = (0..6)
///     .map(|k| mesh.vertices.iter().map(|&p| p + kurbo::Vec2::new(0.1 * k as f64, 0.)).collect())
///     .collect();
/// let spatial = SpatialBasis::hats(&mesh)?;
/// let options = DefOpOptions::default().with_handle_basis(HandleBasisKind::Linear);
/// let op = DefOp::fit(&mesh, &handles, &spatial, &configurations, &solutions, &options)?;
/// let mut evaluator = op.evaluator();
/// let mut positions = vec![Point::ZERO; mesh.n_vertices()];
/// evaluator.eval(&[Point::new(0.25, 0.5), Point::new(4.25, 0.5)], &mut positions)?;
/// assert!((positions[0] - Point::new(0.25, 0.)).hypot() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct DefOpEvaluator<'a> {
    op: &'a DefOp,
    psi: Vec<f64>,
    /// `G ψ`: the x coefficients of every spatial function, then the y ones.
    c: Vec<f64>,
    /// Reduced bases: `Dᵀ c`, x column then y column.
    xy: Vec<f64>,
}

impl DefOpEvaluator<'_> {
    /// The operator evaluated.
    pub fn op(&self) -> &DefOp {
        self.op
    }

    /// Writes the deformed vertex positions at the configuration `q` (one point per handle)
    /// into `positions` (one per vertex). Allocates nothing. Errors (before any work) on a
    /// wrong count or a non-finite `q`.
    pub fn eval(&mut self, q: &[Point], positions: &mut [Point]) -> Result<(), DefOpError> {
        let n_vertices = self.op.n_vertices();
        if positions.len() != n_vertices {
            return Err(DefOpError::PositionCount {
                given: positions.len(),
                n_vertices,
            });
        }
        self.spatial_coefficients(q)?;
        if self.op.spatial.is_hats() {
            let (x, y) = self.c.split_at(n_vertices);
            for ((p, &x), &y) in positions.iter_mut().zip(x).zip(y) {
                *p = Point::new(x, y);
            }
            return Ok(());
        }
        // Dᵀ c, one column of Dᵀ (a function's vertex values, contiguous) at a time: two
        // fused multiply-adds per value, streamed once (faer's product with a two-column
        // right-hand side measured 5 times slower here).
        let n_functions = self.op.spatial.n_functions();
        let (cx, cy) = self.c.split_at(n_functions);
        let (x, y) = self.xy.split_at_mut(n_vertices);
        x.fill(0.0);
        y.fill(0.0);
        for (i, column) in self.op.vertex_values.chunks_exact(n_vertices).enumerate() {
            let (a, b) = (cx[i], cy[i]);
            for ((x, y), &d) in x.iter_mut().zip(y.iter_mut()).zip(column) {
                *x += a * d;
                *y += b * d;
            }
        }
        for ((p, &x), &y) in positions.iter_mut().zip(x.iter()).zip(y.iter()) {
            *p = Point::new(x, y);
        }
        Ok(())
    }

    /// The coefficients `c_i(Q) = G ψ(Q)` of the spatial functions at the configuration `q`:
    /// the x coefficient of every function, then the y ones (`2|Φ|` values). They are the
    /// translations of the linear blend skinning the operator is at `q`. Allocates nothing.
    pub fn spatial_coefficients(&mut self, q: &[Point]) -> Result<&[f64], DefOpError> {
        coefficients_at(
            &self.op.handle_basis,
            &self.op.coefficients,
            q,
            &mut self.psi,
            &mut self.c,
        )?;
        Ok(&self.c)
    }
}

/// `out = G ψ(q)`: the handle functions `ψ` at the configuration `q` (written to `psi`, one per
/// column of `G`), then `G` (`coefficients`, column-major, `out.len() × psi.len()`) times
/// them. Errors on a target that is not finite. Allocates nothing: what both the operator's
/// evaluator and the spline rig run each frame.
pub(crate) fn coefficients_at(
    handle_basis: &HandleBasis,
    coefficients: &[f64],
    q: &[Point],
    psi: &mut [f64],
    out: &mut [f64],
) -> Result<(), DefOpError> {
    check_finite_targets(q)?;
    handle_basis.eval(q, psi)?;
    let (rows, n_psi) = (out.len(), psi.len());
    let g = MatRef::from_column_major_slice(coefficients, rows, n_psi);
    let psi = MatRef::from_column_major_slice(&*psi, n_psi, 1);
    let out = MatMut::from_column_major_slice_mut(out, rows, 1);
    matmul(out, Accum::Replace, g, psi, 1.0, Par::Seq);
    Ok(())
}
