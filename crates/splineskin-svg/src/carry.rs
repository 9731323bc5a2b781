//! The best-fit maps of the carried `<text>` and `<image>` elements ([`crate::follow`]) as
//! affine functions of a deformation's inputs, so that a live view updates them per frame with
//! one small product instead of sampling the deformation again.
//!
//! # Formula
//!
//! An element's best-fit map `A(q)` ([`crate::follow::best_fit_affine`]) is an affine function
//! of the images `q_k = f(p_k)` of its samples: the means, the cross term `X` and so the linear
//! part `M = X C⁻¹` are linear in `q`, and the translation `q̄ − M p̄` too (`C` and `p̄` depend
//! on the rest samples alone; so do the one-line case's direction and the one-point case's
//! `M = I`). When the deformation is itself affine in its inputs `x` (a skinning map
//! `f(p) = Σ_i w_i(p) T_i p̄` in the pose's coefficients, DESIGN.md §1),
//!
//! ```text
//! f(p) = f₀(p) + Σ_j x_j ∂_j f(p)      ⇒      A(x) = A(f₀) + Σ_j x_j (A(∂_j f) − A(0))
//! ```
//!
//! where `A(g)` is the best fit of the images `g(p_k)`. Each element's map is then six rows of
//! `n + 1` coefficients (the inputs and a constant), equal to the map
//! [`crate::follow::ElementMaps::from_map`] computes at any `x`, to rounding.

use kurbo::{Affine, Point, Vec2};

use crate::document::SvgError;
use crate::follow::{best_fit_affine, carried_regions, element_label, element_region};
use splineskin_core::drawing::Drawing;

/// The carried elements' best-fit maps as affine functions of `n_inputs` inputs (module doc).
///
/// ```
/// use kurbo::{Affine, Point, Vec2};
/// use splineskin_svg::carry::CarryOperator;
/// use splineskin_svg::{read_svg, ImportOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <rect width="4" height="2"/><text x="1" y="8">hi</text></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// // One input: the map p ↦ (1 + x) p, a uniform scale about the origin.
/// let carry = CarryOperator::new(&drawing, 1, &mut |p, d| {
///     d[0] = p.to_vec2(); // ∂f/∂x
///     d[1] = p.to_vec2(); // f at x = 0
/// })
/// .unwrap();
/// let mut maps = [Affine::IDENTITY];
/// carry.apply(&[2.0], &mut maps);
/// let expected = Affine::scale(3.0).as_coeffs();
/// assert!(maps[0].as_coeffs().iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-9));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct CarryOperator {
    n_inputs: usize,
    /// Per carried element, then per element asked for ([`CarryOperator::with_elements`]), its
    /// map's six coefficients (`Affine` order) as rows of `n_inputs + 1` numbers: the inputs',
    /// then the constant.
    coefficients: Vec<f64>,
    /// Elements asked for.
    n_elements: usize,
    /// Per carried element, its parent's user space → root user space.
    parents: Vec<Affine>,
}

impl CarryOperator {
    /// The operator of the carried elements of `drawing`'s document for a deformation affine
    /// in `n_inputs` inputs, given by `derivatives(p, d)`: `d[j] = ∂f(p)/∂x_j` for
    /// `j < n_inputs`, and `d[n_inputs] = f(p)` at `x = 0` (`d` has `n_inputs + 1` entries).
    /// A drawing without a source document carries nothing.
    ///
    /// Errors: [`SvgError::Xml`] if the source no longer parses; [`SvgError::NonFinitePoint`]
    /// when `derivatives` gives a non-finite value (naming the element).
    pub fn new(
        drawing: &Drawing,
        n_inputs: usize,
        derivatives: &mut dyn FnMut(Point, &mut [Vec2]),
    ) -> Result<CarryOperator, SvgError> {
        CarryOperator::with_elements(drawing, &[], n_inputs, derivatives)
    }

    /// [`CarryOperator::new`], with the maps of the imported elements `elements` (indices into
    /// the source's elements; paths for a drawing without a source) after the carried ones:
    /// their best-fit maps ([`crate::follow::ElementMaps::element_map`]), which a live view
    /// sets on their copies of user-space paint servers.
    pub fn with_elements(
        drawing: &Drawing,
        elements: &[usize],
        n_inputs: usize,
        derivatives: &mut dyn FnMut(Point, &mut [Vec2]),
    ) -> Result<CarryOperator, SvgError> {
        let carried = match &drawing.source {
            Some(source) => carried_regions(source)?,
            None => Vec::new(),
        };
        let parents: Vec<Affine> = carried.iter().map(|r| r.parent_to_root).collect();
        let mut regions: Vec<(String, Vec<Point>, Vec<f64>)> = carried
            .into_iter()
            .map(|r| {
                let w = vec![1.0; r.samples.len()];
                (r.label, r.samples, w)
            })
            .collect();
        regions.extend(elements.iter().map(|&k| {
            let (samples, weights) = element_region(drawing, k);
            (element_label(drawing, k), samples, weights)
        }));
        let file = drawing.source.as_ref().map_or("<drawing>", |s| &s.origin);
        let mut coefficients = Vec::with_capacity(regions.len() * 6 * (n_inputs + 1));
        for (label, samples, weights) in &regions {
            let non_finite = || SvgError::NonFinitePoint {
                file: file.to_string(),
                element: label.clone(),
                index: 0,
            };
            let rows =
                region_rows(samples, weights, n_inputs, derivatives).ok_or_else(non_finite)?;
            coefficients.extend(rows);
        }
        Ok(CarryOperator {
            n_inputs,
            coefficients,
            n_elements: elements.len(),
            parents,
        })
    }

    /// Number of carried elements.
    pub fn n_carried(&self) -> usize {
        self.parents.len()
    }

    /// Number of imported elements whose maps follow the carried ones'.
    pub fn n_elements(&self) -> usize {
        self.n_elements
    }

    /// Number of inputs.
    pub fn n_inputs(&self) -> usize {
        self.n_inputs
    }

    /// Per carried element, then per element asked for, six rows (`Affine`'s coefficient
    /// order) of `n_inputs + 1` coefficients: `A_r = Σ_j c_rj x_j + c_rn`.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// Per carried element, in document order, its parent's user space → root user space
    /// (`P`: the element's new `transform` is `P⁻¹ A P` before its own).
    pub fn parents(&self) -> &[Affine] {
        &self.parents
    }

    /// Writes each carried element's best-fit map at inputs `x`, then each element's asked
    /// for, into `out` (both checked against the operator's sizes; a mismatch writes nothing).
    /// Allocates nothing.
    pub fn apply(&self, x: &[f64], out: &mut [Affine]) {
        if x.len() != self.n_inputs || out.len() != self.n_carried() + self.n_elements {
            return;
        }
        let width = self.n_inputs + 1;
        for (e, map) in out.iter_mut().enumerate() {
            let mut c = [0.0; 6];
            for (r, value) in c.iter_mut().enumerate() {
                let row = &self.coefficients[(6 * e + r) * width..(6 * e + r + 1) * width];
                *value = row[self.n_inputs] + row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
            }
            *map = Affine::new(c);
        }
    }
}

/// Per carried `<text>` and `<image>` of `drawing`'s document, in document order (that of
/// [`CarryOperator`] and of [`crate::svg_out::SvgOptions::carried_marker`]), its parent's user
/// space → root user space. A drawing without a source document carries nothing.
///
/// Errors: [`SvgError::Xml`] if the source no longer parses.
pub fn carried_parents(drawing: &Drawing) -> Result<Vec<Affine>, SvgError> {
    Ok(match &drawing.source {
        Some(source) => carried_regions(source)?
            .iter()
            .map(|r| r.parent_to_root)
            .collect(),
        None => Vec::new(),
    })
}

/// One region's six rows of `n_inputs + 1` coefficients (module doc), `None` when a fit is not
/// finite.
fn region_rows(
    samples: &[Point],
    weights: &[f64],
    n_inputs: usize,
    derivatives: &mut dyn FnMut(Point, &mut [Vec2]),
) -> Option<Vec<f64>> {
    let (width, k) = (n_inputs + 1, samples.len());
    let mut d = vec![Vec2::ZERO; width];
    // Column j of the samples' images: `images[j * k + s]`.
    let mut images = vec![Point::ORIGIN; width * k];
    for (s, &p) in samples.iter().enumerate() {
        derivatives(p, &mut d);
        for (j, v) in d.iter().enumerate() {
            images[j * k + s] = v.to_point();
        }
    }
    let fit = |q: &[Point]| best_fit_affine(samples, q, weights);
    let zero = fit(&vec![Point::ORIGIN; k])?;
    let mut columns = Vec::with_capacity(width);
    for j in 0..width {
        let a = fit(&images[j * k..(j + 1) * k])?;
        columns.push(if j < n_inputs { difference(a, zero) } else { a });
    }
    Some(
        (0..6)
            .flat_map(|row| columns.iter().map(move |a| a.as_coeffs()[row]))
            .collect(),
    )
}

/// `a − b`, coefficient by coefficient.
fn difference(a: Affine, b: Affine) -> Affine {
    let (a, b) = (a.as_coeffs(), b.as_coeffs());
    Affine::new(std::array::from_fn(|i| a[i] - b[i]))
}
