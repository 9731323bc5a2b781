//! Ours against the naive method, each against the skinned limit surface (Liu et al. 2014,
//! Fig. 8; DESIGN.md §3).
//!
//! ```text
//! target   s(p) = Σ_i w_i(p) T_i Ḡ(p)          every limit sample p of the rest surface, skinned
//! ours     G'(p) = C' m_p,   C' = rig.update(T)  the limit surface of the fitted cage
//! naive    G_n(p) = C_n m_p, C_n,v = Σ_i w_i(P_v) T_i P̄_v   the limit surface of the skinned cage
//! error    ‖G'(p) − s(p)‖ / D  and  ‖G_n(p) − s(p)‖ / D,   D the cage's bounding-box diagonal
//! ```
//!
//! The samples `p` are the vertices of a [`LimitMesh`] (by default at level
//! [`DEFAULT_COMPARE_LEVEL`]: `(2^L + 1)²` per quad face, shared along edges); `max` is the
//! largest error over them and `rms` the root mean square (each sample counted once, as the
//! paper's uniform samples are). The weights of the naive method are those the family gives a
//! cage vertex ([`SurfaceWeights::eval_cage_vertex`]).

use super::affine3::{affine3_apply, Affine3};
use super::cage::Point3;
use super::error::{SubdivError, SurfaceWeightsError};
use super::limit_mesh::LimitMesh;
use super::scene::SubdivSetup;
use super::surface_weights::{cage_weights, sample_weights};

/// Level of the sample mesh by default: 3, 81 samples per quad face (the paper: 100 per face).
pub const DEFAULT_COMPARE_LEVEL: usize = 3;

/// Why a comparison could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SubdivCompareError {
    /// Sampling the surface failed.
    #[error(transparent)]
    Subdiv(#[from] SubdivError),
    /// The weights could not be evaluated at the samples or cage vertices.
    #[error(transparent)]
    Weights(#[from] SurfaceWeightsError),
    /// The picture could not be made.
    #[error("comparison picture: {what}")]
    Picture {
        /// What failed.
        what: String,
    },
}

/// The samples of a comparison and everything about them that does not depend on the pose:
/// build once, compare many poses.
#[derive(Clone, Debug)]
pub struct ComparisonSamples {
    mesh: LimitMesh,
    rest: Vec<Point3>,
    /// Sample-major weights (`n_samples · h`).
    weights: Vec<f64>,
    /// Cage-vertex-major weights of the naive method (`n_vertices · h`).
    cage_weights: Vec<f64>,
    n_handles: usize,
    diagonal: f64,
}

impl ComparisonSamples {
    /// Samples `setup`'s limit surface at `level` and evaluates its weights there and at the
    /// cage vertices.
    pub fn new(setup: &SubdivSetup, level: usize) -> Result<Self, SubdivCompareError> {
        let surface = setup.full_surface()?;
        let mesh = LimitMesh::new(&setup.cage, &surface, level)?;
        let mut rest = vec![[0.0; 3]; mesh.n_vertices()];
        mesh.positions(setup.cage.positions(), &mut rest);
        let weights = sample_weights(setup.weights.as_ref(), &setup.cage, &mesh)?;
        let cage_weights = cage_weights(setup.weights.as_ref(), &setup.cage)?;
        Ok(ComparisonSamples {
            mesh,
            rest,
            weights,
            cage_weights,
            n_handles: setup.weights.n_handles(),
            diagonal: setup.cage.bounding_box_diagonal(),
        })
    }

    /// The sample mesh.
    pub fn mesh(&self) -> &LimitMesh {
        &self.mesh
    }

    /// The samples on the rest surface.
    pub fn rest(&self) -> &[Point3] {
        &self.rest
    }

    /// The length unit of the errors: the rest cage's bounding-box diagonal.
    pub fn diagonal(&self) -> f64 {
        self.diagonal
    }
}

/// Largest and root-mean-square error over the samples, fractions of the diagonal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSummary {
    /// Largest.
    pub max: f64,
    /// Root mean square.
    pub rms: f64,
}

impl ErrorSummary {
    fn of(errors: &[f64]) -> Self {
        let n = errors.len().max(1) as f64;
        ErrorSummary {
            max: errors.iter().copied().fold(0.0, f64::max),
            rms: (errors.iter().map(|e| e * e).sum::<f64>() / n).sqrt(),
        }
    }
}

/// One method's result: its cage, its limit samples, their errors.
#[derive(Clone, Debug)]
pub struct MethodResult {
    /// The deformed cage.
    pub cage: Vec<Point3>,
    /// Its limit surface at the samples.
    pub samples: Vec<Point3>,
    /// Distance of every sample to the target, as a fraction of the diagonal.
    pub errors: Vec<f64>,
    /// `max` and `rms` of `errors`.
    pub summary: ErrorSummary,
}

/// Ours and the naive method against the target, for one pose.
#[derive(Clone, Debug)]
pub struct SubdivComparison {
    /// The skinned rest samples `s(p)`.
    pub target: Vec<Point3>,
    /// The limit surface of the fitted cage.
    pub ours: MethodResult,
    /// The limit surface of the skinned cage.
    pub naive: MethodResult,
}

/// `out_k = Σ_i w_ki T_i p̄_k` for points `points`, weights `weights` (point-major, one row of
/// `transforms.len()` per point).
///
/// ```
/// use splineskin_subdiv::{skin_points, affine3_translation, AFFINE3_IDENTITY};
/// let mut out = [[0.0; 3]];
/// skin_points(&[[1.0, 0.0, 0.0]], &[0.25, 0.75], &[AFFINE3_IDENTITY, affine3_translation([0.0, 4.0, 0.0])], &mut out);
/// assert_eq!(out[0], [1.0, 3.0, 0.0]);
/// ```
pub fn skin_points(points: &[Point3], weights: &[f64], transforms: &[Affine3], out: &mut [Point3]) {
    let h = transforms.len();
    for ((o, p), w) in out.iter_mut().zip(points).zip(weights.chunks_exact(h)) {
        let mut s = [0.0; 3];
        for (wi, t) in w.iter().zip(transforms) {
            if *wi != 0.0 {
                let q = affine3_apply(t, *p);
                for k in 0..3 {
                    s[k] += wi * q[k];
                }
            }
        }
        *o = s;
    }
}

/// Compares ours and the naive method for the handle maps `transforms` (module
/// documentation).
pub fn compare_subdiv(
    setup: &SubdivSetup,
    samples: &ComparisonSamples,
    transforms: &[Affine3],
) -> Result<SubdivComparison, SubdivCompareError> {
    if transforms.len() != samples.n_handles {
        return Err(SubdivError::SizeMismatch {
            what: "transforms (one per handle)",
            expected: samples.n_handles,
            found: transforms.len(),
        }
        .into());
    }
    let n = samples.mesh.n_vertices();
    let mut target = vec![[0.0; 3]; n];
    skin_points(&samples.rest, &samples.weights, transforms, &mut target);
    let mut ours_cage = vec![[0.0; 3]; setup.cage.n_vertices()];
    setup.rig.update(transforms, &mut ours_cage)?;
    let mut naive_cage = vec![[0.0; 3]; setup.cage.n_vertices()];
    skin_points(
        setup.cage.positions(),
        &samples.cage_weights,
        transforms,
        &mut naive_cage,
    );
    let method = |cage: Vec<Point3>| {
        let mut at = vec![[0.0; 3]; n];
        samples.mesh.positions(&cage, &mut at);
        let errors: Vec<f64> = at
            .iter()
            .zip(&target)
            .map(|(a, b)| super::affine3::distance2(*a, *b).sqrt() / samples.diagonal)
            .collect();
        MethodResult {
            summary: ErrorSummary::of(&errors),
            cage,
            samples: at,
            errors,
        }
    };
    Ok(SubdivComparison {
        ours: method(ours_cage),
        naive: method(naive_cage),
        target,
    })
}
