//! [`SplineRig`]: the precomputed linear operator from handle transforms to control points.

use kurbo::{Affine, Point};

use super::frame_product::FrameProduct;
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
    /// `O`, row-major `(2 · n_points) × (6 · n_handles)`, and its per-frame product.
    product: FrameProduct,
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
    /// The output buffer of coordinates has the wrong length.
    #[error("output buffer holds {got} coordinates, the drawing's {points} points need {}", 2 * points)]
    Coordinates {
        /// Buffer length.
        got: usize,
        /// Chain points of the drawing.
        points: usize,
    },
}

/// The paths one system is solved for ([`SplineRig::precompute`]): a lone path, or the
/// members of a group sharing curves, with each member's rows of the operator.
struct Task<'a> {
    /// Path indices: one lone path, or a shared-curve group's members in the group's order.
    members: Vec<usize>,
    /// `rows[k]`: the operator rows of `members[k]` (two per point, `6h` entries each).
    rows: Vec<&'a mut [f64]>,
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
        // Each path's rows of the operator (its points are consecutive), handed to the task
        // that solves it: the tasks write their own rows, in parallel if asked, and the
        // operator is never copied.
        let mut rows_of: Vec<Option<&mut [f64]>> = Vec::with_capacity(drawing.paths.len());
        let mut rest = operator.as_mut_slice();
        for path in &drawing.paths {
            let (mine, others) = rest.split_at_mut(2 * path.points.len() * n_cols);
            rows_of.push(Some(mine));
            rest = others;
        }
        let mut tasks: Vec<Task<'_>> = Vec::new();
        for pi in 0..drawing.paths.len() {
            let members = match group_of[pi] {
                None => vec![pi],
                Some(g) if shared.groups[g][0] == pi => shared.groups[g].clone(),
                Some(_) => continue,
            };
            let rows = members
                .iter()
                .map(|&p| rows_of[p].take().expect("a path is in one task"))
                .collect();
            tasks.push(Task { members, rows });
        }
        let solve = |task: &Task<'_>| -> Result<Vec<PathOperator>, FitError> {
            let pi = task.members[0];
            match group_of[pi] {
                None => solve_path(
                    pi,
                    &drawing.paths[pi],
                    samples,
                    first_curves[pi],
                    options,
                    HandleMaps::Affine,
                )
                .map(|op| vec![op]),
                Some(_) => {
                    let members = &task.members;
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
                    solve_group(&members, n, samples, options, HandleMaps::Affine, &[])
                }
            }
        };
        // An error names the first failing path whatever the threads' timing.
        let solved: Vec<Vec<(usize, usize, bool)>> =
            crate::parallel::try_map_mut(&mut tasks, options.parallel, |_, task| {
                let ops = solve(task)?;
                let mut counts = Vec::with_capacity(ops.len());
                for ((&pi, rows), op) in task.members.iter().zip(&mut task.rows).zip(ops) {
                    for (row, src) in drawing.paths[pi].coordinate_rows(0) {
                        let row = &mut rows[row * n_cols..][..n_cols];
                        for (c, v) in row.iter_mut().enumerate() {
                            *v = op.operator[(src, c)];
                        }
                    }
                    counts.push((pi, op.n_constraints, op.rank_deficient));
                }
                Ok(counts)
            })?;
        drop(tasks);
        let mut n_constraints = 0;
        let mut rank_deficient_paths = Vec::new();
        for (pi, constraints, rank_deficient) in solved.into_iter().flatten() {
            n_constraints += constraints;
            if rank_deficient {
                rank_deficient_paths.push(pi);
            }
        }
        rank_deficient_paths.sort_unstable();
        let shared_groups = shared.groups.len();
        Ok(SplineRig {
            product: FrameProduct::new(operator, n_points, h, options.parallel),
            n_constraints,
            rank_deficient_paths,
            shared_groups,
        })
    }

    /// Deforms: writes the control points for the handle maps `pose` (one per handle) into
    /// `out` (length [`SplineRig::n_points`], layout of [`Drawing::flat_points`]). A dense
    /// matrix–vector product; allocates nothing. Built with [`FitOptions::parallel`] and an
    /// operator of 8 MiB or more, half of the points are computed by a helper thread started
    /// with the rig (the result is the same to the bit).
    pub fn update(&self, pose: &[Affine], out: &mut [Point]) -> Result<(), PoseError> {
        if pose.len() != self.product.n_handles() {
            return Err(PoseError::Transforms {
                got: pose.len(),
                expected: self.product.n_handles(),
            });
        }
        if out.len() != self.product.n_points() {
            return Err(PoseError::Output {
                got: out.len(),
                expected: self.product.n_points(),
            });
        }
        self.product.apply(pose, out);
        Ok(())
    }

    /// [`SplineRig::update`] writing coordinates: `out` holds `x0, y0, x1, y1, …`
    /// (`2 · n_points` values, the layout of an `n × 2` array in C order, of WebAssembly
    /// memory, of a numpy array), the same numbers to the bit. Allocates nothing.
    ///
    /// ```
    /// use kurbo::{Affine, Point};
    /// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
    /// use splineskin_core::spline_fit::{FitOptions, SplineRig};
    /// use splineskin_core::weights::{Shepard, ShepardOptions};
    /// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
    /// let drawing = Drawing {
    ///     paths: vec![Path::new(pts, false, &JunctionOptions::default()).unwrap()],
    ///     ..Default::default()
    /// };
    /// let weights = Shepard::new(&[Point::ZERO, Point::new(3.0, 0.0)], ShepardOptions::default());
    /// let rig = SplineRig::precompute(&drawing, &weights, &FitOptions::default()).unwrap();
    /// let pose = [Affine::rotate(0.3), Affine::translate((1.0, 2.0))];
    /// let mut points = vec![Point::ZERO; rig.n_points()];
    /// let mut coords = vec![0.0; 2 * rig.n_points()];
    /// rig.update(&pose, &mut points).unwrap();
    /// rig.update_coords(&pose, &mut coords).unwrap();
    /// assert!(points.iter().zip(coords.chunks(2)).all(|(p, xy)| p.x == xy[0] && p.y == xy[1]));
    /// assert!(rig.update_coords(&pose, &mut coords[1..]).is_err());
    /// ```
    pub fn update_coords(&self, pose: &[Affine], out: &mut [f64]) -> Result<(), PoseError> {
        if pose.len() != self.product.n_handles() {
            return Err(PoseError::Transforms {
                got: pose.len(),
                expected: self.product.n_handles(),
            });
        }
        if out.len() != 2 * self.product.n_points() {
            return Err(PoseError::Coordinates {
                got: out.len(),
                points: self.product.n_points(),
            });
        }
        self.product.apply(pose, out);
        Ok(())
    }

    /// The same rig with [`SplineRig::update`] reading the operator's entries rounded to `f32`
    /// (`single`), or in full `f64` (`!single`, how every rig is built). Rounded entries halve
    /// the bytes each update streams from memory (what bounds the update of a large drawing)
    /// at the price of a relative error of about `6e-8` per entry: the points move by up to
    /// about `6e-8 · Σ |O_rc T_c|`, which grows with the drawing's distance from the origin,
    /// not with its size. The products are summed in `f64`; [`SplineRig::operator`] stays the
    /// `f64` one.
    ///
    /// ```
    /// use kurbo::{Affine, Point};
    /// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
    /// use splineskin_core::spline_fit::{FitOptions, SplineRig};
    /// use splineskin_core::weights::{Shepard, ShepardOptions};
    ///
    /// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
    /// let drawing = Drawing {
    ///     paths: vec![Path::new(pts, false, &JunctionOptions::default()).unwrap()],
    ///     ..Default::default()
    /// };
    /// let weights = Shepard::new(&[Point::ZERO, Point::new(3.0, 0.0)], ShepardOptions::default());
    /// let rig = SplineRig::precompute(&drawing, &weights, &FitOptions::default()).unwrap();
    /// let single = rig.with_single_precision(true);
    /// assert_eq!(single.update_bytes(), rig.update_bytes() / 2);
    /// let pose = [Affine::rotate(0.3), Affine::translate((1.0, 2.0))];
    /// let (mut a, mut b) = (vec![Point::ZERO; rig.n_points()], vec![Point::ZERO; rig.n_points()]);
    /// rig.update(&pose, &mut a).unwrap();
    /// single.update(&pose, &mut b).unwrap();
    /// for (p, q) in a.iter().zip(&b) {
    ///     assert!((*p - *q).hypot() < 1e-6);
    /// }
    /// ```
    pub fn with_single_precision(&self, single: bool) -> SplineRig {
        SplineRig {
            product: self.product.with_single_precision(single),
            n_constraints: self.n_constraints,
            rank_deficient_paths: self.rank_deficient_paths.clone(),
            shared_groups: self.shared_groups,
        }
    }

    /// Threads [`SplineRig::update`] runs on: with [`FitOptions::parallel`] and an operator
    /// of at least [`super::PARALLEL_MIN_BYTES`], one per [`super::BYTES_PER_THREAD`] of
    /// operator up to the machine's cores ([`super::update_threads`]); else 1.
    pub fn update_threads(&self) -> usize {
        self.product.threads()
    }

    /// Whether [`SplineRig::update`] reads `f32` entries ([`SplineRig::with_single_precision`]).
    pub fn is_single_precision(&self) -> bool {
        self.product.is_single_precision()
    }

    /// Bytes of operator each [`SplineRig::update`] reads: `2 · n_points × 6h` entries of 8
    /// bytes, or 4 with [`SplineRig::with_single_precision`].
    pub fn update_bytes(&self) -> usize {
        self.product.bytes_per_frame()
    }

    /// Number of handles `h`.
    pub fn n_handles(&self) -> usize {
        self.product.n_handles()
    }

    /// Number of chain points written by [`SplineRig::update`].
    pub fn n_points(&self) -> usize {
        self.product.n_points()
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
        self.product.operator()
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
