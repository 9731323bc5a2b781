//! Stencils: values of refined or limit points as sparse `f64` weights over the cage vertices
//! (OpenSubdiv's `Far::StencilTable` / `LimitStencilTable`, in double precision).

use super::cage::Point3;

/// A table of stencils in CSR form: stencil `k` is `Σⱼ weights[j] · P[indices[j]]` for `j` in
/// `offsets[k]..offsets[k + 1]`, `P` the `n_control` cage positions. Immutable once built.
///
/// ```
/// use splineskin_subdiv::{parse_obj, refine_uniform};
///
/// let cage = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "quad.obj")?;
/// let refined = refine_uniform(&cage, 1)?;
/// let table = refined.levels()[0].stencils();
/// assert_eq!(table.n_stencils(), 9);
/// let mut out = vec![[0.0; 3]; table.n_stencils()];
/// table.apply(cage.positions(), &mut out);
/// // Vertex 4 is the face point: the centre of the quad.
/// assert_eq!(out[4], [0.5, 0.5, 0.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct StencilTable {
    n_control: usize,
    offsets: Vec<usize>,
    indices: Vec<u32>,
    weights: Vec<f64>,
}

impl StencilTable {
    pub(crate) fn new(n_control: usize) -> Self {
        StencilTable {
            n_control,
            offsets: vec![0],
            indices: Vec::new(),
            weights: Vec::new(),
        }
    }

    /// Appends a stencil.
    pub(crate) fn push(&mut self, weights: &[(u32, f64)]) {
        for &(i, w) in weights {
            self.indices.push(i);
            self.weights.push(w);
        }
        self.offsets.push(self.indices.len());
    }

    /// Number of stencils.
    pub fn n_stencils(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of control vertices the stencils refer to (the cage's vertex count).
    pub fn n_control(&self) -> usize {
        self.n_control
    }

    /// Stencil `k`: control vertex indices and their weights (same length, indices
    /// increasing).
    pub fn stencil(&self, k: usize) -> (&[u32], &[f64]) {
        let r = self.offsets[k]..self.offsets[k + 1];
        (&self.indices[r.clone()], &self.weights[r])
    }

    /// Writes every stencil applied to `control` into `out`.
    ///
    /// # Panics
    /// If `control.len() != n_control()` or `out.len() != n_stencils()`.
    pub fn apply(&self, control: &[Point3], out: &mut [Point3]) {
        assert_eq!(
            control.len(),
            self.n_control,
            "control: expected n_control() points"
        );
        assert_eq!(
            out.len(),
            self.n_stencils(),
            "out: expected n_stencils() points"
        );
        for (k, o) in out.iter_mut().enumerate() {
            let (idx, w) = self.stencil(k);
            *o = combine(idx, w, control);
        }
    }
}

/// `Σⱼ wⱼ · P[iⱼ]`.
pub(crate) fn combine(indices: &[u32], weights: &[f64], points: &[Point3]) -> Point3 {
    let mut acc = [0.0; 3];
    for (&i, &w) in indices.iter().zip(weights) {
        let p = points[i as usize];
        for k in 0..3 {
            acc[k] += w * p[k];
        }
    }
    acc
}

/// The limit surface at one location as weights over the cage vertices: the paper's `m_p`
/// (DESIGN.md §3) and its derivatives, `G(p) = Σ weights[j]·P[indices[j]]`,
/// `∂G/∂u = Σ du_weights[j]·P[indices[j]]`, likewise `∂G/∂v`. Indices are increasing; the
/// weights sum to 1 and the derivative weights to 0.
#[derive(Clone, Debug, PartialEq)]
pub struct LimitStencil {
    /// Control vertex indices.
    pub indices: Vec<u32>,
    /// Position weights.
    pub weights: Vec<f64>,
    /// Weights of the derivative along the location's `u`.
    pub du_weights: Vec<f64>,
    /// Weights of the derivative along the location's `v`.
    pub dv_weights: Vec<f64>,
    /// `true` when this is the exact limit surface (a regular patch); `false` for the
    /// approximation within `2^-isolation` of an extraordinary point (see
    /// [`LimitSurface`](crate::LimitSurface)).
    pub exact: bool,
}

impl LimitStencil {
    /// The limit position for the cage positions `control`.
    pub fn position(&self, control: &[Point3]) -> Point3 {
        combine(&self.indices, &self.weights, control)
    }

    /// The derivatives `(∂G/∂u, ∂G/∂v)` for the cage positions `control`.
    pub fn derivatives(&self, control: &[Point3]) -> (Point3, Point3) {
        (
            combine(&self.indices, &self.du_weights, control),
            combine(&self.indices, &self.dv_weights, control),
        )
    }
}
