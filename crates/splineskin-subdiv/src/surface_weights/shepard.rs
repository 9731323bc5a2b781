//! Shepard (inverse-distance) weights of 3D point handles and bones.
//!
//! ```text
//! w_i(x) = d_i(x)^(−a) / Σ_k d_k(x)^(−a),   d_i = ‖x − p_i‖ (point),  min_{s∈[0,1]} ‖x − (b₀ + s(b₁ − b₀))‖ (bone)
//! ```
//!
//! the 3D form of [`splineskin_core::weights::SegmentShepard`], evaluated by the same ratios
//! (`(d_min/d_i)^a`, no overflow near a handle) and with the same options
//! ([`ShepardOptions`]: the exponent `a`, 2 by default, and the snap distance). On a handle —
//! a point handle's position, anywhere on a bone's segment — the limit is used: weight 1
//! there, 0 for the others. Defined everywhere in space: a surface point is weighted at its
//! position, a cage vertex (for the naive method) at its own position.

use super::super::cage::Point3;
use super::super::error::SurfaceWeightsError;
use super::super::handles::Handles3;
use super::SpatialWeights;
use splineskin_core::weights::shepard::weights_from_squared_distances;
use splineskin_core::weights::ShepardOptions;

/// Shepard weights of [`Handles3`] (module documentation).
///
/// ```
/// use splineskin_subdiv::{Handles3, Shepard3};
/// use splineskin_core::weights::ShepardOptions;
///
/// let handles = Handles3::new(vec![[0.0, 0.0, 2.0]], vec![[[0.0, 0.0, 0.0], [4.0, 0.0, 0.0]]])?;
/// let w = Shepard3::new(handles, ShepardOptions::default())?;
/// let mut out = [0.0; 2];
/// w.at([3.0, 0.0, 0.0], &mut out); // on the bone
/// assert_eq!(out, [0.0, 1.0]);
/// w.at([0.0, 0.0, 1.0], &mut out); // 1 from both
/// assert_eq!(out, [0.5, 0.5]);
/// # Ok::<(), splineskin_subdiv::SurfaceWeightsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Shepard3 {
    handles: Handles3,
    options: ShepardOptions,
}

impl Shepard3 {
    /// Shepard weights of `handles`. Errors if the exponent is not positive and finite or the
    /// snap distance is negative or not finite.
    pub fn new(handles: Handles3, options: ShepardOptions) -> Result<Self, SurfaceWeightsError> {
        if !(options.exponent > 0.0 && options.exponent.is_finite()) {
            return Err(SurfaceWeightsError::BadOption {
                what: format!(
                    "Shepard exponent {}; expected a positive finite number",
                    options.exponent
                ),
            });
        }
        if !(options.snap_distance_squared >= 0.0 && options.snap_distance_squared.is_finite()) {
            return Err(SurfaceWeightsError::BadOption {
                what: format!(
                    "Shepard snap distance² {}; expected a finite number ≥ 0",
                    options.snap_distance_squared
                ),
            });
        }
        Ok(Shepard3 { handles, options })
    }

    /// The handles.
    pub fn handles(&self) -> &Handles3 {
        &self.handles
    }

    /// The weights at the point `x` of space, into `out` (`n_handles` long).
    pub fn at(&self, x: Point3, out: &mut [f64]) {
        self.handles.squared_distances(x, out);
        weights_from_squared_distances(out, &self.options);
    }
}

impl SpatialWeights for Shepard3 {
    fn n_spatial_handles(&self) -> usize {
        self.handles.n_handles()
    }

    fn weights_at(&self, x: Point3, out: &mut [f64]) {
        self.at(x, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shepard3_partition_of_unity_and_closed_form() {
        let handles = Handles3::new(
            vec![[0.0, 0.0, 0.0], [3.0, 1.0, -1.0]],
            vec![[[0.0, 2.0, 0.0], [0.0, 2.0, 4.0]]],
        )
        .unwrap();
        let w = Shepard3::new(handles, ShepardOptions::default()).unwrap();
        let x = [0.5, 0.5, 2.0];
        let mut out = [0.0; 3];
        w.at(x, &mut out);
        assert!((out.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        // 1/d² each: d² = 4.5, 15.5 and (to the bone's point (0, 2, 2)) 2.5.
        let u = [1.0 / 4.5, 1.0 / 15.5, 1.0 / 2.5];
        let s: f64 = u.iter().sum();
        for i in 0..3 {
            assert!((out[i] - u[i] / s).abs() < 1e-15, "{out:?}");
        }
        // On the bone, beyond its end: the end counts.
        w.at([0.0, 2.0, 1.0], &mut out);
        assert_eq!(out, [0.0, 0.0, 1.0]);
        w.at([3.0, 1.0, -1.0], &mut out);
        assert_eq!(out, [0.0, 1.0, 0.0]);
        let bad = Shepard3::new(
            Handles3::new(vec![[0.0; 3]], vec![]).unwrap(),
            ShepardOptions::default().with_exponent(f64::NAN),
        );
        assert!(matches!(bad, Err(SurfaceWeightsError::BadOption { .. })));
    }
}
