//! [`SplineRig`]: the precomputed linear operator from handle transforms to control points.

use kurbo::{Affine, Point};

use super::quadrature::SampledCurves;
use super::shared_curves::{group_unknowns, SharedCurves};
use super::system::{solve_group, solve_path, GroupMember, HandleMaps, PathOperator};
use super::ConstraintForm;
use super::{FitError, FitOptions};
use crate::drawing::Drawing;
use crate::weights::WeightField;

/// A drawing rigged to a set of handles: all of the fit's precomputation, ready to deform.
///
/// The deformed control points are linear in the handles' affine maps:
/// `x = O · vec(T)`, with `x` all chain point coordinates of the drawing (`2 · n_points`
/// values, x then y per point, paths concatenated as in [`Drawing::flat_points`]) and `vec(T)`
/// the `6h` coefficients of the handles' maps in SVG order `(a, b, c, d, e, f)` (as
/// [`Affine::as_coeffs`]). `O` is dense: every handle can move every point.
///
/// ```text
/// once:        let rig = SplineRig::precompute(&drawing, &weights, &FitOptions::default())?;
/// each frame:  rig.update(&transforms, &mut points)?;     // one dense mat-vec, no allocation
/// ```
///
/// Paths are independent systems, except those that share curves, which are solved as one
/// ([`super::shared_curves`]): each system is factored once (sparse LU of its KKT matrix) and
/// solved for all `6h` right-hand sides.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin_core::spline_fit::{FitOptions, SplineRig};
/// use splineskin_core::weights::{Shepard, ShepardOptions};
///
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts.clone(), false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let handles = [Point::new(0.0, 0.0), Point::new(3.0, 0.0)];
/// let weights = Shepard::new(&handles, ShepardOptions::default());
/// let rig = SplineRig::precompute(&drawing, &weights, &FitOptions::default()).unwrap();
///
/// // The same translation on every handle translates the drawing exactly.
/// let t = Affine::translate((5.0, -2.0));
/// let mut out = vec![Point::ZERO; rig.n_points()];
/// rig.update(&[t, t], &mut out).unwrap();
/// for (p, q) in pts.iter().zip(&out) {
///     assert!((t * *p - *q).hypot() < 1e-12);
/// }
/// ```
#[derive(Clone, Debug)]
pub struct SplineRig {
    n_handles: usize,
    n_points: usize,
    /// Row-major `(2 · n_points) × (6 · n_handles)`.
    operator: Vec<f64>,
    n_constraints: usize,
    rank_deficient_paths: Vec<usize>,
    shared_groups: usize,
}

/// A pose or output buffer of the wrong size was given to [`SplineRig::update`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PoseError {
    /// The number of transforms differs from the number of handles.
    #[error("{got} transforms given for {expected} handles")]
    Transforms {
        /// Transforms given.
        got: usize,
        /// Handles of the rig.
        expected: usize,
    },
    /// The output buffer has the wrong length.
    #[error("output buffer holds {got} points, the drawing has {expected}")]
    Output {
        /// Buffer length.
        got: usize,
        /// Chain points of the drawing.
        expected: usize,
    },
}

impl SplineRig {
    /// Builds the rig: validates the drawing, samples the weights at the quadrature nodes
    /// ([`SampledCurves::sample`]) and calls [`SplineRig::from_samples`].
    pub fn precompute(
        drawing: &Drawing,
        weights: &dyn WeightField,
        options: &FitOptions,
    ) -> Result<SplineRig, FitError> {
        if weights.n_handles() == 0 {
            return Err(FitError::NoHandles);
        }
        validate(drawing)?;
        let samples = SampledCurves::sample(drawing, weights, options);
        SplineRig::from_validated(drawing, &samples, options)
    }

    /// Builds the rig from weights already sampled at the quadrature nodes of `drawing` (with
    /// the same `options`): integrates, assembles and factors each path's system once and
    /// solves it for the `6h` right-hand sides.
    pub fn from_samples(
        drawing: &Drawing,
        samples: &SampledCurves,
        options: &FitOptions,
    ) -> Result<SplineRig, FitError> {
        validate(drawing)?;
        SplineRig::from_validated(drawing, samples, options)
    }

    /// [`SplineRig::from_samples`] on a drawing already checked by `validate`.
    fn from_validated(
        drawing: &Drawing,
        samples: &SampledCurves,
        options: &FitOptions,
    ) -> Result<SplineRig, FitError> {
        let h = samples.n_handles();
        if h == 0 {
            return Err(FitError::NoHandles);
        }
        if samples.n_curves() != drawing.n_curves() {
            return Err(FitError::SamplesMismatch {
                sampled: samples.n_curves(),
                curves: drawing.n_curves(),
            });
        }
        let n_points = drawing.n_points();
        let n_cols = 6 * h;
        let mut operator = vec![0.0; 2 * n_points * n_cols];
        // Paths are independent systems: solve them (in parallel if asked), then copy each
        // path's operator rows into place.
        let mut first_curves = Vec::with_capacity(drawing.paths.len());
        let mut c = 0;
        for path in &drawing.paths {
            first_curves.push(c);
            c += path.n_curves();
        }
        // Paths that share curves are solved together, as one system per group
        // (super::shared_curves); the others alone.
        let shared = if options.share_curves && options.constraint_form == ConstraintForm::Ours {
            SharedCurves::find(drawing)
        } else {
            SharedCurves::default()
        };
        let mut group_of = vec![None; drawing.paths.len()];
        for (g, members) in shared.groups.iter().enumerate() {
            for &p in members {
                group_of[p] = Some(g);
            }
        }
        let tasks: Vec<(usize, Option<usize>)> = (0..drawing.paths.len())
            .filter_map(|pi| match group_of[pi] {
                None => Some((pi, None)),
                Some(g) if shared.groups[g][0] == pi => Some((pi, Some(g))),
                Some(_) => None,
            })
            .collect();
        let solve = |&(pi, group): &(usize, Option<usize>)| match group {
            None => solve_path(
                pi,
                &drawing.paths[pi],
                samples,
                first_curves[pi],
                options,
                HandleMaps::Affine,
            )
            .map(|op| vec![(pi, op)]),
            Some(g) => {
                let members = &shared.groups[g];
                let paths: Vec<_> = members.iter().map(|&p| &drawing.paths[p]).collect();
                let (unknowns, n) = group_unknowns(&paths, members, &shared.copies);
                let members: Vec<GroupMember<'_>> = members
                    .iter()
                    .zip(unknowns)
                    .map(|(&p, unknowns)| GroupMember {
                        index: p,
                        path: &drawing.paths[p],
                        first_curve: first_curves[p],
                        unknowns,
                        copies: shared
                            .copies
                            .iter()
                            .filter(|c| c.copy.path == p)
                            .map(|c| c.copy.curve)
                            .collect(),
                    })
                    .collect();
                let ops = solve_group(&members, n, samples, options, HandleMaps::Affine)?;
                Ok(members.iter().map(|m| m.index).zip(ops).collect())
            }
        };
        // An error names the first failing path whatever the threads' timing.
        let solved: Vec<Vec<(usize, PathOperator)>> =
            crate::parallel::try_map(&tasks, options.parallel, |_, task| solve(task))?;
        let mut by_path: Vec<Option<PathOperator>> =
            (0..drawing.paths.len()).map(|_| None).collect();
        for (pi, op) in solved.into_iter().flatten() {
            by_path[pi] = Some(op);
        }
        let mut n_constraints = 0;
        let mut rank_deficient_paths = Vec::new();
        let paths = drawing.paths.iter().zip(drawing.path_ranges());
        for (pi, ((path, range), solved)) in paths.zip(&by_path).enumerate() {
            let offset = range.start;
            let solved = solved.as_ref().expect("every path is solved");
            n_constraints += solved.n_constraints;
            if solved.rank_deficient {
                rank_deficient_paths.push(pi);
            }
            for (row, src) in path.coordinate_rows(offset) {
                let row = &mut operator[row * n_cols..][..n_cols];
                for (c, v) in row.iter_mut().enumerate() {
                    *v = solved.operator[(src, c)];
                }
            }
        }
        let shared_groups = shared.groups.len();
        Ok(SplineRig {
            n_handles: h,
            n_points,
            operator,
            n_constraints,
            rank_deficient_paths,
            shared_groups,
        })
    }

    /// Deforms: writes the control points for the handle maps `pose` (one per handle) into
    /// `out` (length [`SplineRig::n_points`], layout of [`Drawing::flat_points`]). A dense
    /// matrix–vector product; allocates nothing.
    pub fn update(&self, pose: &[Affine], out: &mut [Point]) -> Result<(), PoseError> {
        if pose.len() != self.n_handles {
            return Err(PoseError::Transforms {
                got: pose.len(),
                expected: self.n_handles,
            });
        }
        if out.len() != self.n_points {
            return Err(PoseError::Output {
                got: out.len(),
                expected: self.n_points,
            });
        }
        let n_cols = 6 * self.n_handles;
        for (p, rows) in out.iter_mut().zip(self.operator.chunks_exact(2 * n_cols)) {
            let (rx, ry) = rows.split_at(n_cols);
            let (mut x, mut y) = (0.0, 0.0);
            for ((t, ox), oy) in pose.iter().zip(rx.chunks_exact(6)).zip(ry.chunks_exact(6)) {
                let c = t.as_coeffs();
                x += dot6(ox, &c);
                y += dot6(oy, &c);
            }
            *p = Point::new(x, y);
        }
        Ok(())
    }

    /// Number of handles `h`.
    pub fn n_handles(&self) -> usize {
        self.n_handles
    }

    /// Number of chain points written by [`SplineRig::update`].
    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// Number of linear junction constraint rows over all paths.
    pub fn n_constraints(&self) -> usize {
        self.n_constraints
    }

    /// Number of groups of paths solved together because they share curves
    /// ([`super::shared_curves`]).
    pub fn n_shared_groups(&self) -> usize {
        self.shared_groups
    }

    /// Paths whose system was found rank deficient (only with [`FitOptions::check_rank`]);
    /// their points are whatever the LU factorisation produced.
    pub fn rank_deficient_paths(&self) -> &[usize] {
        &self.rank_deficient_paths
    }

    /// The operator `O`, row-major `(2 · n_points) × (6 · n_handles)`: row `2k + d` gives
    /// coordinate `d` of point `k`, column `6i + c` coefficient `c` of handle `i`'s map.
    pub fn operator(&self) -> &[f64] {
        &self.operator
    }
}

/// Checks the drawing's chains, joint lists and coordinates (what every fit needs).
pub fn validate(drawing: &Drawing) -> Result<(), FitError> {
    if drawing.paths.is_empty() {
        return Err(FitError::NoPaths);
    }
    for (pi, path) in drawing.paths.iter().enumerate() {
        if !crate::drawing::is_chain(&path.points, path.closed) {
            return Err(FitError::BadChain {
                path: pi,
                n_points: path.points.len(),
            });
        }
        let n = path.n_curves();
        let expected = if path.closed { n } else { n + 1 };
        if path.joints.len() != expected {
            return Err(FitError::JointCount {
                path: pi,
                got: path.joints.len(),
                expected,
                n_curves: n,
            });
        }
        if let Some((k, p)) = path
            .points
            .iter()
            .enumerate()
            .find(|(_, p)| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(FitError::NonFinite {
                path: pi,
                point: k,
                x: p.x,
                y: p.y,
            });
        }
    }
    Ok(())
}

/// `Σ_k a_k c_k` over the six coefficients of a handle's affine map (`a`: six operator
/// entries), summed left to right.
#[inline]
fn dot6(a: &[f64], c: &[f64; 6]) -> f64 {
    a[0] * c[0] + a[1] * c[1] + a[2] * c[2] + a[3] * c[3] + a[4] * c[4] + a[5] * c[5]
}
