//! Quadrature along one curve: the nodes and node weights that integrate both the Gram matrix
//! `Â_j = ∫ b bᵀ dμ` and the weighted matrices `M_ij = ∫ w_i(B(t)) b bᵀ dμ` of curve `j` (the
//! weighted integrals `Ŵ_ij = C̄_j M_ij` are in [`super::weighted_integrals`]).
//!
//! Using one rule for both is what makes the fit exact on the invariants: when `Σ_i w_i ≡ 1`,
//! `Σ_i M_ij = Â_j` to rounding, so identity transforms reproduce the curve and one affine map
//! on every handle gives exactly that map of it (DESIGN.md §1, "Consistency").
//!
//! The measure `dμ` is `ℓ_j dt` (the paper's length weighting: `ℓ_j` the curve's undeformed
//! arc length) or `ℓ_j ‖B'(t)‖ dt` (the arc-length option of the authors' code: arc length
//! along the curve, the curve still weighted by its length, DESIGN.md §1 "Many curves").
//!
//! Two rules:
//! * [`Quadrature::Gauss`] (default): the curve is cut at the weight field's kinks
//!   ([`WeightField::kinks`]) and into `pieces` equal parameter intervals; each piece gets an
//!   `nodes`-point Gauss–Legendre rule (exact for `b bᵀ`, degree 6, from 4 nodes; for smooth
//!   weights the error decays like the `2·nodes`-th derivative).
//! * [`Quadrature::AuthorsMidpoint`]: the paper authors' rule (compatibility mode): `S`
//!   samples at `t_k = k/(S−1)`; interval `k` contributes `mean(w(t_k), w(t_k+1)) · dμ_k ·
//!   b(t_mid) b(t_mid)ᵀ`, with `dμ_k = L·Δt` (or `L·‖B(t_k+1) − B(t_k)‖` with arc length), `L` the
//!   polyline length over the samples.

use kurbo::{ParamCurveArclen, Point};

use crate::bezier::{self, gauss_legendre};
use crate::drawing::{Drawing, Path};
use crate::weights::WeightField;

use super::{ConstraintForm, FitOptions};

/// Default number of equal parameter pieces per curve for [`Quadrature::Gauss`]: 4.
pub const DEFAULT_PIECES: usize = 4;
/// Default Gauss–Legendre nodes per piece: 8 (exact to degree 15 per piece). With 4 pieces the
/// Shepard-weighted integrals of the bundled and the authors' drawings agree with a 256-node rule
/// to about 1e-7 relative.
pub const DEFAULT_NODES: usize = 8;
/// Samples per curve of the authors' midpoint rule: 100.
pub const AUTHORS_SAMPLES: usize = 100;

/// Smallest total measure of a curve, relative to the largest its path can have: 1e-6.
/// A curve of zero length has no energy of its own and would make the system singular; with this
/// floor its control points go to the (constant) skinned position of its point.
pub const MIN_RELATIVE_MEASURE: f64 = 1e-6;

/// Accuracy of arc lengths used as curve weights `ℓ_j`, relative to the chord: 1e-9.
const ARCLEN_RELATIVE_ACCURACY: f64 = 1e-9;

/// The integration rule of the fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Quadrature {
    /// Composite Gauss–Legendre: `pieces` equal pieces (further cut at weight kinks), `nodes`
    /// nodes each.
    Gauss {
        /// Equal parameter pieces per curve.
        pieces: usize,
        /// Gauss–Legendre nodes per piece (≥ 4 to integrate `b bᵀ` exactly).
        nodes: usize,
    },
    /// The paper authors' midpoint sum over `samples` uniform samples (compatibility mode).
    AuthorsMidpoint {
        /// Samples per curve (the authors use 100).
        samples: usize,
    },
}

impl Default for Quadrature {
    fn default() -> Self {
        Quadrature::Gauss {
            pieces: DEFAULT_PIECES,
            nodes: DEFAULT_NODES,
        }
    }
}

/// The measure of the energy along a curve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Measure {
    /// `ℓ_j dt`: each curve's energy weighted by its undeformed length (the paper).
    #[default]
    LengthWeighted,
    /// `ℓ_j ‖B'(t)‖ dt`: integrate with respect to arc length, each curve's energy still
    /// weighted by its undeformed length `ℓ_j`, as in the authors' code.
    ArcLength,
}

impl Measure {
    /// [`Measure::ArcLength`] if `arc_length`, else [`Measure::LengthWeighted`] (the scenes'
    /// `arc_length` / `usingArcLengthParameterization` flag).
    pub fn from_arc_length(arc_length: bool) -> Measure {
        if arc_length {
            Measure::ArcLength
        } else {
            Measure::LengthWeighted
        }
    }
}

/// The quadrature nodes of every curve of a drawing with the handle weights at them: the part
/// of the precomputation that depends on the weight functions.
///
/// Computed once by [`SampledCurves::sample`]; [`super::SplineRig::from_samples`] builds the rig
/// from it, so that changing only the fit (constraints, junction kinds) does not re-evaluate
/// the weights, and so that benchmarks can time the two phases separately.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin_core::spline_fit::{quadrature::SampledCurves, FitOptions};
/// use splineskin_core::weights::{Shepard, ShepardOptions};
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts, false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let w = Shepard::new(&[Point::ZERO], ShepardOptions::default());
/// let s = SampledCurves::sample(&drawing, &w, &FitOptions::default());
/// assert_eq!(s.n_curves(), 1);
/// // Four pieces of eight Gauss nodes.
/// assert_eq!(s.curve(0).t.len(), 32);
/// ```
#[derive(Clone, Debug)]
pub struct SampledCurves {
    n_handles: usize,
    node_offsets: Vec<usize>,
    t: Vec<f64>,
    omega: Vec<f64>,
    weights: Vec<f64>,
}

impl SampledCurves {
    /// Samples every curve of `drawing` with the rule and measure of `options`, evaluating
    /// `field` at the nodes.
    pub fn sample(drawing: &Drawing, field: &dyn WeightField, options: &FitOptions) -> Self {
        let h = field.n_handles();
        let mut out = SampledCurves {
            n_handles: h,
            node_offsets: vec![0],
            t: Vec::new(),
            omega: Vec::new(),
            weights: Vec::new(),
        };
        let sample_path = |path: &Path| {
            let mut builder = CurveSamples::new(options.quadrature);
            let mut part = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            let min_measure = min_measure(path, options.constraint_form, options.measure);
            for j in 0..path.n_curves() {
                let c = path.curve_points(j);
                builder.build(&c, field, options.quadrature, options.measure, min_measure);
                part.0.extend_from_slice(&builder.t);
                part.1.extend_from_slice(&builder.omega);
                part.2.extend_from_slice(&builder.weights);
                part.3.push(builder.t.len());
            }
            part
        };
        let parts: Vec<_> = if options.parallel {
            use rayon::prelude::*;
            drawing.paths.par_iter().map(sample_path).collect()
        } else {
            drawing.paths.iter().map(sample_path).collect()
        };
        for (t, omega, weights, counts) in parts {
            out.t.extend_from_slice(&t);
            out.omega.extend_from_slice(&omega);
            out.weights.extend_from_slice(&weights);
            for n in counts {
                let last = *out.node_offsets.last().unwrap_or(&0);
                out.node_offsets.push(last + n);
            }
        }
        out
    }

    /// Number of curves sampled (all paths, in order).
    pub fn n_curves(&self) -> usize {
        self.node_offsets.len() - 1
    }

    /// Number of handles whose weights were sampled.
    pub fn n_handles(&self) -> usize {
        self.n_handles
    }

    /// The nodes of curve `j` (counted over all paths of the drawing, in order).
    pub fn curve(&self, j: usize) -> CurveNodes<'_> {
        let r = self.node_offsets[j]..self.node_offsets[j + 1];
        CurveNodes {
            t: &self.t[r.clone()],
            omega: &self.omega[r.clone()],
            weights: &self.weights[r.start * self.n_handles..r.end * self.n_handles],
            n_handles: self.n_handles,
        }
    }
}

/// The floor of a curve's total measure in `path`: [`MIN_RELATIVE_MEASURE`] times the largest
/// total measure a curve of the path can have, bounded with its control-polygon length `L`
/// (`L` length-weighted, `L²` with arc length). None in the authors' form: they have no floor.
fn min_measure(path: &Path, form: ConstraintForm, measure: Measure) -> f64 {
    if form == ConstraintForm::Authors {
        return 0.0;
    }
    let max_len = (0..path.n_curves())
        .map(|j| {
            let c = path.curve_points(j);
            (c[1] - c[0]).hypot() + (c[2] - c[1]).hypot() + (c[3] - c[2]).hypot()
        })
        .fold(0.0, f64::max);
    let largest = match measure {
        Measure::LengthWeighted => max_len,
        Measure::ArcLength => max_len * max_len,
    };
    (MIN_RELATIVE_MEASURE * largest).max(f64::MIN_POSITIVE)
}

/// The quadrature of one curve: nodes `t`, node weights `omega` (measure included) and the
/// handle weights at the nodes (`t.len() × n_handles`, row-major).
#[derive(Clone, Copy, Debug)]
pub struct CurveNodes<'a> {
    /// Parameters `t_q` of the nodes.
    pub t: &'a [f64],
    /// Node weights `ω_q`.
    pub omega: &'a [f64],
    /// `w_i` at node `q`: entry `q · n_handles + i`.
    pub weights: &'a [f64],
    pub(super) n_handles: usize,
}

/// Builder of one curve's nodes, reused across curves to avoid reallocating.
#[derive(Clone, Debug, Default)]
struct CurveSamples {
    /// Parameters `t_q` of the nodes.
    t: Vec<f64>,
    omega: Vec<f64>,
    weights: Vec<f64>,
    scratch_kinks: Vec<f64>,
    scratch_w: Vec<f64>,
    /// Nodes and weights of the per-piece Gauss–Legendre rule (empty for other rules).
    gauss_t: Vec<f64>,
    gauss_w: Vec<f64>,
}

impl CurveSamples {
    /// A builder for `quadrature`: computes its Gauss–Legendre rule once.
    fn new(quadrature: Quadrature) -> Self {
        let (gauss_t, gauss_w) = match quadrature {
            Quadrature::Gauss { nodes, .. } => gauss_legendre(nodes.max(4)),
            Quadrature::AuthorsMidpoint { .. } => (Vec::new(), Vec::new()),
        };
        CurveSamples {
            gauss_t,
            gauss_w,
            ..Default::default()
        }
    }

    /// Fills `self` for the curve `c` with the rule `quadrature`, measure `measure`, handle
    /// weights from `field`, and `min_measure` as the floor of the curve's total measure (see
    /// [`MIN_RELATIVE_MEASURE`]).
    fn build(
        &mut self,
        c: &[Point; 4],
        field: &dyn WeightField,
        quadrature: Quadrature,
        measure: Measure,
        min_measure: f64,
    ) {
        let h = field.n_handles();
        self.t.clear();
        self.omega.clear();
        self.weights.clear();
        match quadrature {
            Quadrature::Gauss { pieces, .. } => {
                self.scratch_kinks.clear();
                field.kinks(c, &mut self.scratch_kinks);
                let pieces = pieces.max(1);
                self.scratch_kinks
                    .extend((1..pieces).map(|k| k as f64 / pieces as f64));
                self.scratch_kinks.retain(|t| *t > 0.0 && *t < 1.0);
                self.scratch_kinks.push(0.0);
                self.scratch_kinks.push(1.0);
                self.scratch_kinks.sort_by(f64::total_cmp);
                self.scratch_kinks.dedup();
                for piece in self.scratch_kinks.windows(2) {
                    let (a, b) = (piece[0], piece[1]);
                    for (&s, &w) in self.gauss_t.iter().zip(&self.gauss_w) {
                        self.t.push(a + (b - a) * s);
                        self.omega.push((b - a) * w);
                    }
                }
                let scale = match measure {
                    Measure::LengthWeighted => {
                        let cubic = kurbo::CubicBez::new(c[0], c[1], c[2], c[3]);
                        let chord = (c[3] - c[0]).hypot().max(f64::MIN_POSITIVE);
                        let len = cubic.arclen(ARCLEN_RELATIVE_ACCURACY * chord);
                        len.max(min_measure)
                    }
                    Measure::ArcLength => {
                        // ℓ_j ‖B'‖ dt per node, ℓ_j = ∫ ‖B'‖ dt by the same rule, so the total
                        // is ℓ_j². The floor adds a uniform parameter measure so that a
                        // degenerate (point) curve keeps a positive definite Gram matrix (the
                        // parameter weights sum to 1, so it adds exactly `floor`).
                        self.scratch_w.clear();
                        self.scratch_w
                            .extend(self.t.iter().map(|&t| bezier::derivative(c, t).hypot()));
                        let total: f64 = self
                            .omega
                            .iter()
                            .zip(&self.scratch_w)
                            .map(|(w, v)| w * v)
                            .sum();
                        let floor = (min_measure - total * total).max(0.0);
                        for (w, speed) in self.omega.iter_mut().zip(&self.scratch_w) {
                            *w *= speed * total + floor;
                        }
                        1.0
                    }
                };
                for w in &mut self.omega {
                    *w *= scale;
                }
                self.weights.resize(self.t.len() * h, 0.0);
                for (q, &t) in self.t.iter().enumerate() {
                    field.eval(bezier::eval(c, t), &mut self.weights[q * h..(q + 1) * h]);
                }
            }
            Quadrature::AuthorsMidpoint { samples } => {
                let s = samples.max(2);
                let dt = 1.0 / (s - 1) as f64;
                self.scratch_w.resize(s * h, 0.0);
                let mut prev = c[0];
                let mut polyline = 0.0;
                for k in 0..s {
                    let t = k as f64 * dt;
                    let p = bezier::eval(c, t);
                    field.eval(p, &mut self.scratch_w[k * h..(k + 1) * h]);
                    if k > 0 {
                        let chord = (p - prev).hypot();
                        polyline += chord;
                        let tm = t - 0.5 * dt;
                        self.t.push(tm);
                        self.omega.push(match measure {
                            Measure::LengthWeighted => dt,
                            Measure::ArcLength => chord,
                        });
                    }
                    prev = p;
                }
                for w in &mut self.omega {
                    *w *= polyline;
                }
                self.weights.resize((s - 1) * h, 0.0);
                for k in 0..s - 1 {
                    for i in 0..h {
                        self.weights[k * h + i] =
                            0.5 * (self.scratch_w[k * h + i] + self.scratch_w[(k + 1) * h + i]);
                    }
                }
            }
        }
    }

    #[cfg(test)]
    fn nodes(&self, n_handles: usize) -> CurveNodes<'_> {
        CurveNodes {
            t: &self.t,
            omega: &self.omega,
            weights: &self.weights,
            n_handles,
        }
    }
}

impl CurveNodes<'_> {
    /// `Σ_q ω_q b(t_q) b(t_q)ᵀ`: the curve's Gram matrix under this rule.
    pub fn gram(&self) -> [[f64; 4]; 4] {
        let mut a = [[0.0; 4]; 4];
        for (&t, &w) in self.t.iter().zip(self.omega) {
            let b = bezier::bernstein(t);
            for k in 0..4 {
                for l in 0..4 {
                    a[k][l] += w * b[k] * b[l];
                }
            }
        }
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::bernstein_gram;
    use crate::weights::{Shepard, ShepardOptions};

    fn curve() -> [Point; 4] {
        [(0.0, 0.0), (1.0, 2.0), (3.0, 2.0), (4.0, 0.0)].map(Point::from)
    }

    #[test]
    fn quadrature_gauss_gram_is_exact_times_length() {
        let field = Shepard::new(&[Point::new(0.0, 0.0)], ShepardOptions::default());
        let mut s = CurveSamples::new(Quadrature::default());
        s.build(
            &curve(),
            &field,
            Quadrature::default(),
            Measure::LengthWeighted,
            0.0,
        );
        let c = curve();
        let len = kurbo::CubicBez::new(c[0], c[1], c[2], c[3]).arclen(1e-12);
        let a = s.nodes(field.n_handles()).gram();
        let exact = bernstein_gram();
        for k in 0..4 {
            for l in 0..4 {
                assert!((a[k][l] - len * exact[k][l]).abs() < 1e-12 * len);
            }
        }
    }

    #[test]
    fn quadrature_weighted_grams_sum_to_gram() {
        let hs = [
            Point::new(0.0, 0.0),
            Point::new(4.0, 1.0),
            Point::new(2.0, 3.0),
        ];
        let field = Shepard::new(&hs, ShepardOptions::default());
        for q in [
            Quadrature::default(),
            Quadrature::AuthorsMidpoint { samples: 100 },
        ] {
            for m in [Measure::LengthWeighted, Measure::ArcLength] {
                let mut s = CurveSamples::new(q);
                s.build(&curve(), &field, q, m, 0.0);
                let a = s.nodes(field.n_handles()).gram();
                let mut ms = Vec::new();
                s.nodes(3).weighted_grams(&mut ms);
                for k in 0..4 {
                    for l in 0..4 {
                        let sum: f64 = ms.iter().map(|m| m[k][l]).sum();
                        assert!((sum - a[k][l]).abs() < 1e-13 * a[0][0].abs());
                    }
                }
            }
        }
    }

    #[test]
    fn quadrature_arc_length_total_is_curve_length() {
        let field = Shepard::new(&[Point::new(0.0, 0.0)], ShepardOptions::default());
        let q = Quadrature::Gauss {
            pieces: 8,
            nodes: 8,
        };
        let mut s = CurveSamples::new(q);
        s.build(&curve(), &field, q, Measure::ArcLength, 0.0);
        let c = curve();
        let len = kurbo::CubicBez::new(c[0], c[1], c[2], c[3]).arclen(1e-12);
        // ℓ ∫ ‖B'‖ dt = ℓ².
        let total: f64 = s.omega.iter().sum();
        assert!(
            (total - len * len).abs() < 1e-9 * len * len,
            "{total} vs {len}²"
        );
    }

    #[test]
    fn quadrature_degenerate_curve_gets_floor_measure() {
        let field = Shepard::new(&[Point::new(0.0, 0.0)], ShepardOptions::default());
        let p = [Point::new(1.0, 1.0); 4];
        let mut s = CurveSamples::new(Quadrature::default());
        for m in [Measure::LengthWeighted, Measure::ArcLength] {
            s.build(&p, &field, Quadrature::default(), m, 1e-3);
            let total: f64 = s.omega.iter().sum();
            assert!((total - 1e-3).abs() < 1e-15, "{m:?}: {total}");
        }
    }
}
