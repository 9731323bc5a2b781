//! [`HandleBasis`]: the handle basis `Ψ = (ψ_1, …, ψ_|Ψ|)` of a deformation operator, functions
//! of the handle configuration `Q = (q_1, …, q_n) ∈ R^{2n}` (Poranne & Lipman 2016, §3.1;
//! DESIGN.md §4).
//!
//! The functions are written in the scaled displacement from the rest configuration `P`,
//!
//! ```text
//! z = (Q − P) / scale ∈ R^{2n},   z_{2ℓ} = (q_ℓ.x − p_ℓ.x) / scale,   z_{2ℓ+1} = (q_ℓ.y − p_ℓ.y) / scale
//! ```
//!
//! which spans the same functions as the raw coordinates (polynomials of a degree are closed
//! under affine changes of variable; for the thin-plate spline see below) and keeps the
//! monomials of order one near the rest pose. Every basis starts with the linear part, so
//! `ψ_0 = 1` and `ψ_{1+a} = z_a`; the handle positions are `q_ℓ = p_ℓ + scale · z`, a
//! combination of these (the paper's Proposition 2 needs them in `Ψ`).
//!
//! | kind | functions, in order | `|Ψ|` (n handles, m samples) | 9 handles |
//! |---|---|---|---|
//! | [`HandleBasisKind::Linear`] | `1, z_a` | `1 + 2n` | 19 |
//! | [`HandleBasisKind::Quadratic`] | linear, then `z_a z_b` for `a ≤ b` | `1 + 3n + 2n²` | 190 |
//! | [`HandleBasisKind::Cubic`] | quadratic, then `z_a z_b z_c` for `a ≤ b ≤ c` | `1 + 11n/3 + 4n² + 4n³/3` = `C(2n+3, 3)` | 1 330 |
//! | [`HandleBasisKind::ThinPlateSpline`] | linear, then `φ(‖z − z_k‖)`, `φ(r) = r² log r`, one per centre `z_k` | `1 + 2n + m` | 19 + m |
//!
//! The thin-plate spline's kernel is conditionally positive definite of order 2 in any
//! dimension, so with its coefficients `a` orthogonal to the linear polynomials at the centres
//! (`Σ_k a_k = 0`, `Σ_k a_k z_k = 0`: the fit imposes it) interpolation at distinct centres not
//! all on one hyperplane is unique (Wendland 2005, *Scattered Data Approximation*, ch. 8).
//! Under those conditions `Σ_k a_k ‖z − z_k‖² = Σ_k a_k ‖z_k‖²` is constant, so scaling `z`
//! (which adds a multiple of `r²` to `φ`) does not change the space.

use kurbo::Point;

use super::error::DefOpError;
use super::handles::{check_finite_targets, check_rest_handles};

/// Which family of handle functions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum HandleBasisKind {
    /// Polynomials of degree ≤ 1.
    Linear,
    /// Polynomials of degree ≤ 2.
    Quadratic,
    /// Polynomials of degree ≤ 3.
    Cubic,
    /// Linear polynomials and one thin-plate spline `r² log r` per centre (training sample).
    ThinPlateSpline,
}

impl HandleBasisKind {
    /// Every kind, from the smallest space to the largest.
    pub const ALL: [HandleBasisKind; 4] = [
        HandleBasisKind::Linear,
        HandleBasisKind::Quadratic,
        HandleBasisKind::Cubic,
        HandleBasisKind::ThinPlateSpline,
    ];

    /// The basis' name as the study and the CLI print it: `linear`, `quadratic`, `cubic`,
    /// `tps`.
    pub fn name(self) -> &'static str {
        match self {
            HandleBasisKind::Linear => "linear",
            HandleBasisKind::Quadratic => "quadratic",
            HandleBasisKind::Cubic => "cubic",
            HandleBasisKind::ThinPlateSpline => "tps",
        }
    }

    /// Number of functions for `n_handles` handles and, for the thin-plate spline,
    /// `n_centres` centres (ignored by the polynomials).
    ///
    /// ```
    /// use splineskin_defop::HandleBasisKind;
    /// assert_eq!(HandleBasisKind::Linear.n_functions(9, 0), 19);
    /// assert_eq!(HandleBasisKind::Quadratic.n_functions(9, 0), 1 + 27 + 162);
    /// assert_eq!(HandleBasisKind::Cubic.n_functions(9, 0), 1330);
    /// assert_eq!(HandleBasisKind::ThinPlateSpline.n_functions(9, 1000), 1019);
    /// ```
    pub fn n_functions(self, n_handles: usize, n_centres: usize) -> usize {
        let d = 2 * n_handles;
        match self {
            HandleBasisKind::Linear => 1 + d,
            HandleBasisKind::Quadratic => 1 + d + d * (d + 1) / 2,
            HandleBasisKind::Cubic => 1 + d + d * (d + 1) / 2 + d * (d + 1) * (d + 2) / 6,
            HandleBasisKind::ThinPlateSpline => 1 + d + n_centres,
        }
    }
}

/// A handle basis over the configurations of `n_handles` point handles with rest positions
/// `P`.
///
/// ```
/// use kurbo::Point;
/// use splineskin_defop::HandleBasis;
/// let rest = [Point::new(0., 0.), Point::new(2., 0.)];
/// let basis = HandleBasis::polynomial(2, &rest, 0.5)?;
/// assert_eq!(basis.n_functions(), 1 + 3 * 2 + 2 * 4);
/// let mut psi = vec![0.0; basis.n_functions()];
/// basis.eval(&[Point::new(0.5, 0.), Point::new(2., -1.)], &mut psi)?;
/// // 1, then z = (Q − P) / 0.5 = (1, 0, 0, −2), then the products z_a z_b, a ≤ b.
/// assert_eq!(&psi[..5], &[1.0, 1.0, 0.0, 0.0, -2.0]);
/// assert_eq!(psi[5], 1.0); // z_0²
/// assert_eq!(psi[14], 4.0); // z_3²
/// # Ok::<(), splineskin_defop::DefOpError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct HandleBasis {
    kind: HandleBasisKind,
    rest: Vec<Point>,
    scale: f64,
    /// Thin-plate spline centres `z_k`, `n_centres × 2n` row-major (empty for polynomials).
    centres: Vec<f64>,
}

impl HandleBasis {
    /// The polynomials of degree ≤ `degree` (1, 2 or 3) in `z = (Q − P) / scale`. Errors on
    /// another degree, no handles, a non-finite rest position, or a scale that is not finite
    /// and positive.
    pub fn polynomial(
        degree: usize,
        rest: &[Point],
        scale: f64,
    ) -> Result<HandleBasis, DefOpError> {
        let kind = match degree {
            1 => HandleBasisKind::Linear,
            2 => HandleBasisKind::Quadratic,
            3 => HandleBasisKind::Cubic,
            _ => {
                return Err(DefOpError::InvalidOption {
                    name: "degree",
                    value: degree.to_string(),
                    expected: "1 (linear), 2 (quadratic) or 3 (cubic)",
                })
            }
        };
        check_rest(rest, scale)?;
        Ok(HandleBasis {
            kind,
            rest: rest.to_vec(),
            scale,
            centres: Vec::new(),
        })
    }

    /// The linear polynomials and one thin-plate spline centred at each configuration of
    /// `centres` (each `n_handles` points). Errors as [`HandleBasis::polynomial`], or on a
    /// centre of the wrong size or not finite.
    pub fn thin_plate_spline(
        rest: &[Point],
        scale: f64,
        centres: &[Vec<Point>],
    ) -> Result<HandleBasis, DefOpError> {
        check_rest(rest, scale)?;
        let mut flat = Vec::with_capacity(centres.len() * 2 * rest.len());
        for centre in centres {
            if centre.len() != rest.len() {
                return Err(DefOpError::TargetCount {
                    given: centre.len(),
                    n_handles: rest.len(),
                });
            }
            check_finite_targets(centre)?;
            for (q, p) in centre.iter().zip(rest) {
                flat.push((q.x - p.x) / scale);
                flat.push((q.y - p.y) / scale);
            }
        }
        Ok(HandleBasis {
            kind: HandleBasisKind::ThinPlateSpline,
            rest: rest.to_vec(),
            scale,
            centres: flat,
        })
    }

    /// A basis from stored parts (the operator file): thin-plate centres already in the scaled
    /// displacement `z`, `n_centres × 2n` row-major (empty for polynomials). The caller has
    /// checked the sizes; the rest and scale are checked here.
    pub(crate) fn from_parts(
        kind: HandleBasisKind,
        rest: Vec<Point>,
        scale: f64,
        centres: Vec<f64>,
    ) -> Result<HandleBasis, DefOpError> {
        check_rest(&rest, scale)?;
        Ok(HandleBasis {
            kind,
            rest,
            scale,
            centres,
        })
    }

    /// The family.
    pub fn kind(&self) -> HandleBasisKind {
        self.kind
    }

    /// Number of handles `n`.
    pub fn n_handles(&self) -> usize {
        self.rest.len()
    }

    /// The rest configuration `P`.
    pub fn rest(&self) -> &[Point] {
        &self.rest
    }

    /// The length unit of `z` (drawing units).
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// Number of thin-plate spline centres (0 for polynomials).
    pub fn n_centres(&self) -> usize {
        self.centres.len() / (2 * self.rest.len()).max(1)
    }

    /// Number of functions `|Ψ|`.
    pub fn n_functions(&self) -> usize {
        self.kind.n_functions(self.n_handles(), self.n_centres())
    }

    /// Index of the function `z_{2ℓ+axis}` (axis 0: x, 1: y) of handle `ℓ`.
    pub fn linear_index(&self, handle: usize, axis: usize) -> usize {
        1 + 2 * handle + axis
    }

    /// Centre `k` of a thin-plate spline basis in the scaled displacement `z` (`2n` values;
    /// panics if `k` is out of range).
    pub fn centre(&self, k: usize) -> &[f64] {
        let d = 2 * self.n_handles();
        &self.centres[k * d..(k + 1) * d]
    }

    /// Writes `ψ_j(Q)` for every function into `out` (length [`HandleBasis::n_functions`]).
    /// Allocates nothing. Errors if `q` does not hold one point per handle or `out` has the
    /// wrong length; a non-finite `q` gives non-finite values (the caller checks inputs once).
    pub fn eval(&self, q: &[Point], out: &mut [f64]) -> Result<(), DefOpError> {
        if q.len() != self.n_handles() {
            return Err(DefOpError::TargetCount {
                given: q.len(),
                n_handles: self.n_handles(),
            });
        }
        if out.len() != self.n_functions() {
            return Err(DefOpError::BufferLength {
                given: out.len(),
                expected: self.n_functions(),
            });
        }
        let d = 2 * self.n_handles();
        out[0] = 1.0;
        for (l, (q, p)) in q.iter().zip(&self.rest).enumerate() {
            out[1 + 2 * l] = (q.x - p.x) / self.scale;
            out[2 + 2 * l] = (q.y - p.y) / self.scale;
        }
        let (z, rest) = out.split_at_mut(1 + d);
        let z = &z[1..];
        match self.kind {
            HandleBasisKind::Linear => {}
            HandleBasisKind::Quadratic | HandleBasisKind::Cubic => {
                let mut next = 0;
                for a in 0..d {
                    for b in a..d {
                        rest[next] = z[a] * z[b];
                        next += 1;
                    }
                }
                if self.kind == HandleBasisKind::Cubic {
                    for a in 0..d {
                        for b in a..d {
                            let zab = z[a] * z[b];
                            for c in b..d {
                                rest[next] = zab * z[c];
                                next += 1;
                            }
                        }
                    }
                }
            }
            HandleBasisKind::ThinPlateSpline => {
                for (value, centre) in rest.iter_mut().zip(self.centres.chunks_exact(d)) {
                    let r2: f64 = z.iter().zip(centre).map(|(a, b)| (a - b) * (a - b)).sum();
                    *value = thin_plate(r2);
                }
            }
        }
        Ok(())
    }
}

/// `φ(r) = r² log r = ½ r² log r²` from `r²`, with `φ(0) = 0` (its limit).
pub(crate) fn thin_plate(r2: f64) -> f64 {
    if r2 > 0.0 {
        0.5 * r2 * r2.ln()
    } else {
        0.0
    }
}

fn check_rest(rest: &[Point], scale: f64) -> Result<(), DefOpError> {
    check_rest_handles(rest)?;
    if !(scale.is_finite() && scale > 0.0) {
        return Err(DefOpError::InvalidOption {
            name: "scale",
            value: scale.to_string(),
            expected: "a finite length > 0 (drawing units)",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rest() -> Vec<Point> {
        vec![Point::new(0., 0.), Point::new(1., 2.), Point::new(-3., 0.5)]
    }

    #[test]
    fn handle_basis_counts_match_the_paper() {
        for n in 1..12 {
            let nf = n as f64;
            let quadratic = 1.0 + 3.0 * nf + 2.0 * nf * nf;
            let cubic = 1.0 + 11.0 * nf / 3.0 + 4.0 * nf * nf + 4.0 * nf.powi(3) / 3.0;
            assert_eq!(
                HandleBasisKind::Quadratic.n_functions(n, 0) as f64,
                quadratic
            );
            assert!((HandleBasisKind::Cubic.n_functions(n, 0) as f64 - cubic).abs() < 1e-9);
        }
    }

    #[test]
    fn handle_basis_cubic_monomials_are_distinct_and_complete() {
        let p = rest();
        let basis = HandleBasis::polynomial(3, &p, 2.0).unwrap();
        // With z = (2, 3, 5, 7, 11, 13), distinct primes, distinct monomials of degree ≤ 3
        // have distinct values (unique factorisation): all values distinct means no monomial
        // is repeated, and there are C(6 + 3, 3) = 84 of them.
        let primes = [2.0, 3.0, 5.0, 7.0, 11.0, 13.0];
        let q: Vec<Point> = p
            .iter()
            .enumerate()
            .map(|(l, p)| Point::new(p.x + 2.0 * primes[2 * l], p.y + 2.0 * primes[2 * l + 1]))
            .collect();
        let mut psi = vec![0.0; basis.n_functions()];
        basis.eval(&q, &mut psi).unwrap();
        let mut sorted = psi.clone();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup();
        assert_eq!(sorted.len(), psi.len(), "two monomials coincide");
        assert_eq!(psi.len(), 84); // C(9, 3)
    }

    #[test]
    fn handle_basis_thin_plate_vanishes_at_its_centre() {
        let p = rest();
        let centres = vec![
            vec![
                Point::new(0.1, 0.),
                Point::new(1., 2.),
                Point::new(-3., 0.5),
            ],
            p.clone(),
        ];
        let basis = HandleBasis::thin_plate_spline(&p, 0.5, &centres).unwrap();
        assert_eq!(basis.n_functions(), 1 + 6 + 2);
        let mut psi = vec![0.0; basis.n_functions()];
        basis.eval(&centres[0], &mut psi).unwrap();
        assert_eq!(psi[7], 0.0);
        // r = 0.1 / 0.5 = 0.2 from the second centre.
        assert!((psi[8] - 0.04 * 0.2f64.ln()).abs() < 1e-15);
        assert!(basis.eval(&p[1..], &mut psi).is_err());
        assert!(basis.eval(&p, &mut psi[1..]).is_err());
        assert!(HandleBasis::polynomial(4, &p, 1.0).is_err());
        assert!(HandleBasis::polynomial(1, &p, 0.0).is_err());
    }
}
