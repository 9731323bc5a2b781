//! What is not a curve follows the deformation too: user-space gradients and patterns,
//! fixed-orientation markers, `<text>` and `<image>` are carried by the **best-fit affine map**
//! of the deformation over each element, and strokes optionally scale with it.
//!
//! # The map of an element
//!
//! The deformation is a point map `f` (for skinning, `f(p) = Σ_i w_i(p) T_i p̄`, DESIGN.md §1).
//! Over an element's region `Ω` it is replaced by the affine map `A` minimising
//!
//! ```text
//! E(A) = Σ_k ω_k ‖A p_k − f(p_k)‖²      (p_k samples of Ω, ω_k their weights)
//! ```
//!
//! whose closed form is, with weighted means `p̄ = Σ ω_k p_k / Σ ω_k`, `q̄` likewise of the
//! images `q_k = f(p_k)`, the scatter `C = Σ ω_k (p_k − p̄)(p_k − p̄)ᵀ` and the cross term
//! `X = Σ ω_k (q_k − q̄)(p_k − p̄)ᵀ`:
//!
//! ```text
//! linear part  M = X C⁻¹,      translation  q̄ − M p̄            (normal equations of E)
//! ```
//!
//! ([`best_fit_affine`]). **Affine rather than similarity**, because (1) when every handle
//! carries the same affine map `T` (a rigid pose, but also a uniform or non-uniform scale or a
//! shear) the spline fit reproduces `T` exactly (DESIGN.md §1, consistency), and only the
//! affine fit gives back exactly `T` for the carried elements too, so that a document under any
//! common affine map stays one picture; (2) a shape stretched along one axis stretches its
//! gradient, pattern, label or photo the same way, which is what the outline shows; a
//! similarity would leave the fill's stripes at their old spacing inside a stretched shape.
//! The price is that a strongly sheared bend also shears text; a user who wants rigid labels
//! can keep them outside the deformed region.
//!
//! When the samples lie on one line, or nearly (`det C ≤` [`FLAT_REGION`] `· (tr C)²`: a straight
//! stroke), `C` cannot be inverted: the fit along the line is kept (`M u = X u / λ`, `u` the
//! line's direction, `λ` its variance) and completed conformally across it
//! (`M n = R₉₀ M u`, `n = R₉₀ u`). A region of a single point keeps only the translation.
//!
//! # The region of each element
//!
//! - a filled geometry element: the centres of a [`REGION_GRID`]² grid over its rest bounding
//!   box that lie inside its fill (nonzero winding of its subpaths, each closed as a fill is),
//!   equal weights; if fewer than three fall inside (a thin shape), or it is not filled, or its
//!   fill has no area: its rest curves, [`CURVE_SAMPLES`] points per curve at
//!   `t = (k + ½)/n`, each weighted by its curve's chord-polygon length `/ n`;
//! - an `<image>`: its `x y width height` rectangle, a [`REGION_GRID`]² grid;
//! - a `<text>`: an estimate of its box from its `x`, `y`, `font-size` (default 16), the
//!   number of characters (advance [`TEXT_ADVANCE`] em each), and `text-anchor`, from
//!   `0.8 em` above the baseline to `0.2 em` below, a [`REGION_GRID`]² grid. Glyph outlines are
//!   not known here (no fonts are loaded); the estimate only chooses where the map is sampled.
//!
//! # How each kind is carried
//!
//! With `L` an element's local → root map and `A` its best-fit affine (root user space), its
//! local map is `M = L⁻¹ A L`:
//!
//! - a `gradientUnits="userSpaceOnUse"` gradient, or a pattern with `patternUnits` and
//!   `patternContentUnits` `userSpaceOnUse`, used by the element's fill or stroke: the element
//!   gets its own copy of the paint server (written right after the original, id
//!   `<prefix><id>-<k>`), `gradientTransform`/`patternTransform` `= M · G` (`G` the original's,
//!   through `href` templates), and an inline `fill`/`stroke` naming the copy. Elements whose
//!   maps agree (within [`SAME_MAP`] of their size) share a copy; the original is left as it
//!   is for anything else that uses it. `objectBoundingBox` paint follows the deformed bounding
//!   box already (not exactly: a rotated shape's box does not rotate) and is left as it is.
//! - a marker with a fixed `orient` (an angle, default 0) on the element: SVG gives one
//!   orientation per marker reference, and `marker-mid` applies to every vertex of the path,
//!   so the marker is turned by the rotation of the **element's** best-fit map (not the local
//!   rotation at each vertex, which would need the path split): `orient + θ`, `θ` the angle of
//!   the rotation closest to `M`'s linear part (`θ = atan2(m₂₁ − m₁₂, m₁₁ + m₂₂)`), in a copy of
//!   the marker named by an inline `marker-start`/`-mid`/`-end`. `orient="auto"` markers turn
//!   with the deformed path's tangents already. Marker references are read from the element's
//!   and its ancestors' `marker*` attributes and `style` declarations (not from style sheets).
//! - `<text>` and `<image>` (outside `use` copies, `defs`, clip paths, masks, patterns,
//!   markers and nested `svg` elements; text on a `textPath` follows its path already): a
//!   `transform` attribute `matrix(P⁻¹ A P)` written before their own transform, `P` the map of
//!   their parent's user space to root user space, so their new local → root map is `A L`.
//! - stroke widths, with [`FollowOptions::scale_strokes`]: multiplied by the local scale
//!   `√|det M|` of the element's map (one width per element: SVG strokes have no varying
//!   width). **Off by default**, as in Adobe Illustrator, whose Puppet Warp moves anchor
//!   points and leaves stroke weights as they are (Illustrator scales strokes only in its
//!   transform tools, with the "Scale Strokes & Effects" preference). Carried text scales its
//!   stroke with its transform in either case.
//! - a stroked element whose local → root map `L` is not a similarity (a non-uniform scale or
//!   a shear, e.g. `scale(128 160)` around a `stroke-width=".6"` saltire): its stroke is drawn
//!   in that stretched frame, so turning only its path data inside `L` would draw the stroke in
//!   another frame (a quarter turn swaps the stroke's horizontal and vertical widths). Such an
//!   element is given a **stroke frame** `F` (root user space) and drawn as `F L`: its new
//!   `transform` is `T L⁻¹ F L` (`T` its own) and its path data are the deformed points mapped
//!   by `(F L)⁻¹`. `F = A` with [`FollowOptions::scale_strokes`] (the stroke follows `A`
//!   exactly; its width is not scaled again), else the best-fit rotation of the element's
//!   region (Procrustes: the orthogonal factor of the cross-covariance
//!   `X = Σ ω (q − q̄)(p − p̄)ᵀ = A C`, `C` the region's covariance — not of `A` itself, whose
//!   part across a thin region, a stroke along a line, is ill-conditioned: pinned along such a
//!   line and pulled at one end, `A` can shear and even mirror while the line only turns):
//!   `Q = [[cos θ, −sin θ], [sin θ, cos θ]]` with `θ = atan2(x₂₁ − x₁₂, x₁₁ + x₂₂)`, or the
//!   reflection `[[cos θ, sin θ], [sin θ, −cos θ]]` with `θ = atan2(x₂₁ + x₁₂, x₁₁ − x₂₂)`
//!   when it fits the samples better than any rotation by [`REFLECTION_MARGIN`] (a thin
//!   region cannot tell a mirror from a turn and keeps the rotation); placed so that
//!   `F p̄ = A p̄` at the mean `p̄` of the
//!   element's region. A rigid map on every pin thus draws the element exactly as the input
//!   under that map; under a bend its stroke keeps its rest shape, turned with the element. Its
//!   paint servers and markers are then carried by `(F L)⁻¹ A L` instead of `L⁻¹ A L`. Still
//!   documents only: an animated document keeps `L` (a SMIL `transform` animation interpolates
//!   separately from the path's).

use std::str::FromStr;

use kurbo::{Affine, BezPath, Point, Rect, Shape, Vec2};

use crate::document::SvgError;
use splineskin_core::drawing::source::ImportedElement;
use splineskin_core::drawing::{Drawing, PathRole, SvgSource};

/// Cells per side of the grid sampling an element's region: 16 (256 samples; the best-fit map
/// of a smooth deformation changes by well under 1 % of its size from 8 to 32).
pub const REGION_GRID: usize = 16;

/// Samples per curve when an element's region is its curves: 8.
pub const CURVE_SAMPLES: usize = 8;

/// Average advance of a character, in em, for the estimated box of a `<text>`: 0.55 (that of
/// common sans-serif faces on Latin text).
pub const TEXT_ADVANCE: f64 = 0.55;

/// Default `font-size` of a `<text>` in user units: 16 (CSS `medium`).
const DEFAULT_FONT_SIZE: f64 = 16.0;

/// Samples on one line, or nearly: `det C ≤ FLAT_REGION · (tr C)²`, i.e. the smaller principal
/// variance below about 1e-4 of the larger (a region thinner than about 1 : 100, relative, so
/// scale-free). Across so thin a region the least-squares fit is ill-conditioned: a stroke
/// that is almost straight (a gentle curve 64 units long bowing 0.6 units) got a map that
/// mirrors it under a mild bend; it is completed conformally instead, as a straight one.
pub const FLAT_REGION: f64 = 1e-4;

/// Two maps of one element agree (share a copy of its paint server or marker) when they differ
/// by at most 1e-9 of the element's size (relative, so scale-free; far above rounding, far
/// below anything visible).
pub const SAME_MAP: f64 = 1e-9;

/// Options of [`ElementMaps`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct FollowOptions {
    /// Multiply stroke widths by the local scale of each element's map (module doc).
    /// Default: `false`, as Illustrator's Puppet Warp.
    pub scale_strokes: bool,
}

impl FollowOptions {
    /// Sets [`FollowOptions::scale_strokes`].
    pub fn with_scale_strokes(mut self, on: bool) -> Self {
        self.scale_strokes = on;
        self
    }
}

/// The least-squares affine map taking `rest[k]` to `image[k]` with weights `weights[k]`
/// (module doc: formula, one-line and one-point regions). `None` when the slices differ in
/// length, are empty, or have no positive total weight or a non-finite value.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_svg::follow::best_fit_affine;
/// let t = Affine::new([2.0, 0.5, -0.3, 1.5, 4.0, -1.0]);
/// let rest = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 2.0)].map(Point::from);
/// let image: Vec<Point> = rest.iter().map(|&p| t * p).collect();
/// let a = best_fit_affine(&rest, &image, &[1.0; 4]).unwrap();
/// for (x, y) in a.as_coeffs().iter().zip(t.as_coeffs()) {
///     assert!((x - y).abs() < 1e-12);
/// }
/// ```
pub fn best_fit_affine(rest: &[Point], image: &[Point], weights: &[f64]) -> Option<Affine> {
    if rest.is_empty() || rest.len() != image.len() || rest.len() != weights.len() {
        return None;
    }
    let total: f64 = weights.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    let mean = |pts: &[Point]| {
        let mut m = Vec2::ZERO;
        for (p, &w) in pts.iter().zip(weights) {
            m += w * p.to_vec2();
        }
        (m / total).to_point()
    };
    let (p_mean, q_mean) = (mean(rest), mean(image));
    let (mut cxx, mut cxy, mut cyy) = (0.0, 0.0, 0.0);
    let mut x = [0.0; 4]; // [[x0, x1], [x2, x3]] = Σ ω (q − q̄)(p − p̄)ᵀ
    for ((p, q), &w) in rest.iter().zip(image).zip(weights) {
        let (dp, dq) = (*p - p_mean, *q - q_mean);
        cxx += w * dp.x * dp.x;
        cxy += w * dp.x * dp.y;
        cyy += w * dp.y * dp.y;
        x[0] += w * dq.x * dp.x;
        x[1] += w * dq.x * dp.y;
        x[2] += w * dq.y * dp.x;
        x[3] += w * dq.y * dp.y;
    }
    let trace = cxx + cyy;
    let det = cxx * cyy - cxy * cxy;
    // m = [[m0, m1], [m2, m3]] acting on column vectors.
    let m = if trace == 0.0 {
        [1.0, 0.0, 0.0, 1.0]
    } else if det <= FLAT_REGION * trace * trace {
        let angle = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
        let u = Vec2::new(angle.cos(), angle.sin());
        let lambda = u.x * (cxx * u.x + cxy * u.y) + u.y * (cxy * u.x + cyy * u.y);
        let mu = Vec2::new(x[0] * u.x + x[1] * u.y, x[2] * u.x + x[3] * u.y) / lambda;
        let n = Vec2::new(-u.y, u.x);
        let mn = Vec2::new(-mu.y, mu.x);
        // M = (M u) uᵀ + (M n) nᵀ
        [
            mu.x * u.x + mn.x * n.x,
            mu.x * u.y + mn.x * n.y,
            mu.y * u.x + mn.y * n.x,
            mu.y * u.y + mn.y * n.y,
        ]
    } else {
        // X C⁻¹, C⁻¹ = [[cyy, −cxy], [−cxy, cxx]] / det
        [
            (x[0] * cyy - x[1] * cxy) / det,
            (x[1] * cxx - x[0] * cxy) / det,
            (x[2] * cyy - x[3] * cxy) / det,
            (x[3] * cxx - x[2] * cxy) / det,
        ]
    };
    let t = q_mean.to_vec2()
        - Vec2::new(
            m[0] * p_mean.x + m[1] * p_mean.y,
            m[2] * p_mean.x + m[3] * p_mean.y,
        );
    let a = Affine::new([m[0], m[2], m[1], m[3], t.x, t.y]);
    a.is_finite().then_some(a)
}

/// The angle (radians) of the rotation closest to the linear part of `m` (its polar factor,
/// for a map that keeps orientation): `atan2(b − c, a + d)` in `Affine`'s `(a, b, c, d)`.
///
/// ```
/// use kurbo::Affine;
/// use splineskin_svg::follow::rotation_angle;
/// let m = Affine::rotate(0.3) * Affine::scale_non_uniform(2.0, 0.5);
/// assert!((rotation_angle(m) - 0.3).abs() < 1e-12);
/// ```
pub fn rotation_angle(m: Affine) -> f64 {
    let [a, b, c, d, _, _] = m.as_coeffs();
    (b - c).atan2(a + d)
}

/// The local scale `√|det|` of the linear part of `m` (its area scale, as a length).
pub fn local_scale(m: Affine) -> f64 {
    m.determinant().abs().sqrt()
}

/// A `<text>` or `<image>` carried by its best-fit map ([`ElementMaps`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Carried {
    /// Byte offset of the element in the source text.
    pub(crate) offset: usize,
    /// Its parent's user space → root user space (`P` in the module doc).
    pub(crate) parent_to_root: Affine,
    /// Its best-fit map, root user space (`A`).
    pub(crate) map: Affine,
}

/// The best-fit affine map of a deformation over every element of a drawing's document that
/// is not carried by its curves alone (module doc), computed once per pose and given to
/// [`crate::svg_out::write_svg_following`].
///
/// Once per pose: [`ElementMaps::from_map`] with the deformation's point map (for skinning,
/// `|p| splineskin::naive::skin_point(&weights, &pose, p, &mut scratch)`); then write with the
/// deformed points. This module knows no weights: any point map will do (a deformation
/// operator's, a test's closed form).
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin_svg::follow::{ElementMaps, FollowOptions};
/// use splineskin_svg::{read_svg, ImportOptions};
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
///   <rect width="4" height="2"/><text x="1" y="8">hi</text></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let t = Affine::rotate(0.5);
/// let maps = ElementMaps::from_map(&drawing, &mut |p| t * p, &FollowOptions::default()).unwrap();
/// let a = maps.element_map(0).unwrap();
/// assert!(a.as_coeffs().iter().zip(t.as_coeffs()).all(|(x, y)| (x - y).abs() < 1e-12));
/// assert_eq!(maps.n_carried(), 1); // the text
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ElementMaps {
    /// One per element of the source ([`splineskin_core::drawing::SvgSource::n_elements`]), root user space.
    pub(crate) elements: Vec<Affine>,
    /// Texts and images.
    pub(crate) carried: Vec<Carried>,
    /// One per element: its stroke frame `F` (module doc), `None` when it is drawn in its own
    /// frame `L` (not stroked, or `L` a similarity).
    pub(crate) stroke_frames: Vec<Option<Affine>>,
    /// The options they were computed with.
    pub(crate) options: FollowOptions,
    /// The number of paths of the drawing they were computed for (a consistency check).
    pub(crate) n_paths: usize,
}

impl ElementMaps {
    /// The best-fit affine maps of the point map `map` (root user space) over the elements of
    /// `drawing`'s document. A drawing without a source document has only its paths: their
    /// maps are computed, nothing else is carried.
    ///
    /// Errors: [`SvgError::Xml`] if the source no longer parses; [`SvgError::NonFinitePoint`]
    /// when `map` gives a non-finite point on an element's region (naming the element).
    pub fn from_map(
        drawing: &Drawing,
        map: &mut dyn FnMut(Point) -> Point,
        options: &FollowOptions,
    ) -> Result<ElementMaps, SvgError> {
        let mut fit = |label: &dyn Fn() -> String,
                       samples: &[Point],
                       weights: &[f64]|
         -> Result<Affine, SvgError> {
            let image: Vec<Point> = samples.iter().map(|&p| map(p)).collect();
            best_fit_affine(samples, &image, weights).ok_or_else(|| SvgError::NonFinitePoint {
                file: origin(drawing).to_string(),
                element: label(),
                index: 0,
            })
        };
        let mut elements = Vec::new();
        let mut stroke_frames = Vec::new();
        let mut carried = Vec::new();
        let n_elements = drawing
            .source
            .as_ref()
            .map_or(drawing.paths.len(), |s| s.elements.len());
        for k in 0..n_elements {
            let (s, w) = element_region(drawing, k);
            let a = fit(&|| element_label(drawing, k), &s, &w)?;
            elements.push(a);
            let element = drawing.source.as_ref().map(|source| &source.elements[k]);
            stroke_frames.push(element.and_then(|e| stroke_frame(e, a, &s, &w, options)));
        }
        if let Some(source) = &drawing.source {
            for region in carried_regions(source)? {
                let w = vec![1.0; region.samples.len()];
                let map = fit(&|| region.label.clone(), &region.samples, &w)?;
                carried.push(Carried {
                    offset: region.offset,
                    parent_to_root: region.parent_to_root,
                    map,
                });
            }
        }
        Ok(ElementMaps {
            elements,
            stroke_frames,
            carried,
            options: *options,
            n_paths: drawing.paths.len(),
        })
    }

    /// The best-fit map (root user space) of element `element` of the source
    /// ([`splineskin_core::drawing::SvgSource::n_elements`] order; path `element` for a drawing without a source).
    pub fn element_map(&self, element: usize) -> Option<Affine> {
        self.elements.get(element).copied()
    }

    /// The stroke frame `F` (root user space) of element `element` (module doc): `Some` when
    /// it is stroked inside a non-similar local map and is drawn as `F L` on export.
    pub fn stroke_frame(&self, element: usize) -> Option<Affine> {
        self.stroke_frames.get(element).copied().flatten()
    }

    /// Number of `<text>` and `<image>` elements carried.
    pub fn n_carried(&self) -> usize {
        self.carried.len()
    }

    /// The best-fit map (root user space) of the carried `<text>` or `<image>` starting at byte
    /// `offset` of the source text, if it is carried.
    pub fn carried_map(&self, offset: usize) -> Option<Affine> {
        self.carried
            .iter()
            .find(|c| c.offset == offset)
            .map(|c| c.map)
    }

    /// The best-fit maps (root user space) of the carried `<text>` and `<image>` elements, in
    /// document order (that of [`crate::carry::CarryOperator`]).
    pub fn carried_maps(&self) -> impl Iterator<Item = Affine> + '_ {
        self.carried.iter().map(|c| c.map)
    }

    /// The options they were computed with.
    pub fn options(&self) -> FollowOptions {
        self.options
    }
}

/// Two linear parts agree when they differ by at most 1e-9 of their size (relative).
pub const SIMILAR: f64 = 1e-9;

/// Whether the linear part of `l` is a similarity (rotation or reflection times a uniform
/// scale): `a = d, b = −c` or `a = −d, b = c` in `Affine`'s `(a, b, c, d)`, within [`SIMILAR`].
pub fn is_similarity(l: Affine) -> bool {
    let [a, b, c, d, _, _] = l.as_coeffs();
    let size = a.abs() + b.abs() + c.abs() + d.abs();
    let tolerance = SIMILAR * size;
    ((a - d).abs() + (b + c).abs() <= tolerance) || ((a + d).abs() + (b - c).abs() <= tolerance)
}

/// A stroke frame is a reflection only when the best-fit reflection of its region fits the
/// samples better than the best-fit rotation by this factor (the correlations
/// `|(x₁₁ − x₂₂, x₂₁ + x₁₂)| > 1.25 |(x₁₁ + x₂₂, x₂₁ − x₁₂)|` of the module doc): a mirror of
/// a region whose width is at least a ninth of its length.
pub const REFLECTION_MARGIN: f64 = 1.25;

/// Where an element's stroke frame is fitted (module doc, stroke frames): the weighted mean
/// `p̄` of its region's samples and their weighted covariance `C = Σ ω (p − p̄)(p − p̄)ᵀ / Σ ω`,
/// root user space. With the element's best-fit map `A`, [`StrokeFrameRegion::frame`] gives
/// its stroke frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrokeFrameRegion {
    /// `p̄`.
    pub centre: Point,
    /// `C` as `[c_xx, c_xy, c_yy]`.
    pub covariance: [f64; 3],
}

impl StrokeFrameRegion {
    /// The mean and covariance of `samples` weighted by `weights`; `None` without a positive
    /// total weight or for a non-finite value.
    pub fn of_samples(samples: &[Point], weights: &[f64]) -> Option<StrokeFrameRegion> {
        let total: f64 = weights.iter().sum();
        if total.is_nan() || total <= 0.0 || samples.len() != weights.len() {
            return None;
        }
        let sum = samples
            .iter()
            .zip(weights)
            .fold(Vec2::ZERO, |m, (p, &w)| m + w * p.to_vec2());
        let centre = (sum / total).to_point();
        let mut covariance = [0.0; 3];
        for (p, &w) in samples.iter().zip(weights) {
            let d = *p - centre;
            covariance[0] += w * d.x * d.x / total;
            covariance[1] += w * d.x * d.y / total;
            covariance[2] += w * d.y * d.y / total;
        }
        let region = StrokeFrameRegion { centre, covariance };
        (centre.is_finite() && covariance.iter().all(|c| c.is_finite())).then_some(region)
    }

    /// The stroke frame `F` of an element of this region whose best-fit map is `a` (without
    /// [`FollowOptions::scale_strokes`]): the best-fit rotation (or reflection, past
    /// [`REFLECTION_MARGIN`]) of the cross-covariance `X = A C`, moved so that `F p̄ = A p̄`.
    ///
    /// ```
    /// use kurbo::{Affine, Point};
    /// use splineskin_svg::follow::StrokeFrameRegion;
    /// let samples = [(0.0, 0.0), (4.0, 0.0), (0.0, 2.0), (4.0, 2.0)].map(Point::from);
    /// let region = StrokeFrameRegion::of_samples(&samples, &[1.0; 4]).unwrap();
    /// // A rigid map is its own frame; a scale about the centre leaves the frame the identity.
    /// let rigid = Affine::translate((3.0, -1.0)) * Affine::rotate(0.7);
    /// let f = region.frame(rigid);
    /// assert!(f.as_coeffs().iter().zip(rigid.as_coeffs()).all(|(x, y)| (x - y).abs() < 1e-12));
    /// let scale = Affine::scale_about(3.0, region.centre);
    /// assert!(region.frame(scale).as_coeffs().iter().zip(Affine::IDENTITY.as_coeffs()).all(|(x, y)| (x - y).abs() < 1e-12));
    /// ```
    pub fn frame(&self, a: Affine) -> Affine {
        let [cxx, cxy, cyy] = self.covariance;
        let [a0, a1, a2, a3, _, _] = a.as_coeffs();
        // X = A C (both as Affine's column-major (a, b, c, d)).
        let x = Affine::new([
            a0 * cxx + a2 * cxy,
            a1 * cxx + a3 * cxy,
            a0 * cxy + a2 * cyy,
            a1 * cxy + a3 * cyy,
            0.0,
            0.0,
        ]);
        let q = best_fit_orthogonal(x);
        let c = self.centre;
        Affine::translate(a * c - q * c) * q
    }
}

/// The orthogonal map `Q` (rotation, or reflection past [`REFLECTION_MARGIN`]) maximising
/// `tr(Qᵀ X)` for the cross-covariance `X` (module doc, stroke frames).
fn best_fit_orthogonal(x: Affine) -> Affine {
    let [a, b, c, d, _, _] = x.as_coeffs();
    let turn = (a + d).hypot(b - c);
    let mirror = (a - d).hypot(b + c);
    if mirror > REFLECTION_MARGIN * turn {
        let (sin, cos) = (b + c).atan2(a - d).sin_cos();
        Affine::new([cos, sin, sin, -cos, 0.0, 0.0])
    } else {
        Affine::rotate((b - c).atan2(a + d))
    }
}

/// The stroke frame of element `e` whose best-fit map is `a` over `samples` (weights
/// `weights`) (module doc): `None` unless it is stroked (and not clip geometry) inside a local
/// map that is not a similarity.
fn stroke_frame(
    e: &ImportedElement,
    a: Affine,
    samples: &[Point],
    weights: &[f64],
    options: &FollowOptions,
) -> Option<Affine> {
    if !has_stroke_frame(e) {
        return None;
    }
    if options.scale_strokes {
        return Some(a);
    }
    let frame = StrokeFrameRegion::of_samples(samples, weights)?.frame(a);
    frame.is_finite().then_some(frame)
}

/// Whether element `e` is drawn in a stroke frame (module doc): stroked, not clip geometry,
/// inside a local → root map that is not a similarity.
fn has_stroke_frame(e: &ImportedElement) -> bool {
    e.paint.stroke_width.is_some()
        && e.role != PathRole::ClipPath
        && !is_similarity(e.local_to_root)
}

/// Where the stroke frame of element `element` of `drawing`'s document is fitted (module doc):
/// `None` when the element has no stroke frame (or there is no such element). A live view that
/// computes the element's best-fit map `A` itself (a [`crate::carry::CarryOperator`]) draws it
/// as export does with [`StrokeFrameRegion::frame`]`(A)` (without
/// [`FollowOptions::scale_strokes`]).
///
/// ```
/// use splineskin_svg::{read_svg, ImportOptions};
/// use splineskin_svg::follow::stroke_frame_region;
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
///   <g transform="scale(4 1)"><path d="M5 20 L20 80" stroke="black" fill="none"/></g>
///   <path d="M5 20 L20 80" stroke="black" fill="none"/></svg>"#;
/// let drawing = read_svg(svg, &ImportOptions::default()).unwrap();
/// let c = stroke_frame_region(&drawing, 0).unwrap().centre;
/// assert!((c.x - 50.0).abs() < 1e-9 && (c.y - 50.0).abs() < 1e-9);
/// assert!(stroke_frame_region(&drawing, 1).is_none());
/// ```
pub fn stroke_frame_region(drawing: &Drawing, element: usize) -> Option<StrokeFrameRegion> {
    let e = drawing.source.as_ref()?.elements.get(element)?;
    if !has_stroke_frame(e) {
        return None;
    }
    let (samples, weights) = element_region(drawing, element);
    StrokeFrameRegion::of_samples(&samples, &weights)
}

/// Where the best-fit map of element `k` of `drawing`'s document is sampled (module doc; path
/// `k` for a drawing without a source): its samples and their weights.
pub(crate) fn element_region(drawing: &Drawing, k: usize) -> (Vec<Point>, Vec<f64>) {
    match &drawing.source {
        None => curve_samples(std::slice::from_ref(&drawing.paths[k])),
        Some(source) => {
            let e = &source.elements[k];
            let paths = &drawing.paths[e.paths.clone()];
            match e.paint.filled && !e.zero_area_fill {
                true => area_samples(paths).unwrap_or_else(|| curve_samples(paths)),
                false => curve_samples(paths),
            }
        }
    }
}

/// Element `k` of `drawing`'s document as messages name it (`path k` without a source).
pub(crate) fn element_label(drawing: &Drawing, k: usize) -> String {
    match &drawing.source {
        None => format!("path {k}"),
        Some(source) => source.elements[k].label.clone(),
    }
}

/// Where the best-fit map of a carried `<text>` or `<image>` is sampled (module doc).
pub(crate) struct CarriedRegion {
    /// Byte offset of the element in the source text.
    pub(crate) offset: usize,
    /// Its parent's user space → root user space (`P`).
    pub(crate) parent_to_root: Affine,
    /// The element as messages name it.
    pub(crate) label: String,
    /// A [`REGION_GRID`]² grid over its region, root user space (equal weights).
    pub(crate) samples: Vec<Point>,
}

/// The regions of the `<text>` and `<image>` elements of `source` that are carried, in
/// document order.
pub(crate) fn carried_regions(source: &SvgSource) -> Result<Vec<CarriedRegion>, SvgError> {
    let doc = crate::document::parse_xml(&source.text, &source.origin)?;
    Ok(carried_elements(&doc, source)
        .into_iter()
        .map(|(node, parent_to_root, local)| {
            let local_to_root = parent_to_root * own_transform(node);
            CarriedRegion {
                offset: node.range().start,
                parent_to_root,
                label: crate::document::node_label(&doc, node),
                samples: grid(local).into_iter().map(|p| local_to_root * p).collect(),
            }
        })
        .collect())
}

fn origin(drawing: &Drawing) -> &str {
    drawing
        .source
        .as_ref()
        .map_or("<drawing>", |s| s.origin.as_str())
}

/// [`CURVE_SAMPLES`] points per curve, weighted by the curve's chord-polygon length over the
/// number of samples (module doc).
fn curve_samples(paths: &[splineskin_core::drawing::Path]) -> (Vec<Point>, Vec<f64>) {
    let (mut s, mut w) = (Vec::new(), Vec::new());
    for path in paths {
        for j in 0..path.n_curves() {
            let [p0, p1, p2, p3] = path.curve_points(j);
            let length = (p1 - p0).hypot() + (p2 - p1).hypot() + (p3 - p2).hypot();
            let c = path.curve(j);
            for k in 0..CURVE_SAMPLES {
                let t = (k as f64 + 0.5) / CURVE_SAMPLES as f64;
                s.push(kurbo::ParamCurve::eval(&c, t));
                w.push(length / CURVE_SAMPLES as f64);
            }
        }
    }
    if w.iter().all(|&x| x == 0.0) {
        // All curves of zero length: their points, equally weighted.
        w.iter_mut().for_each(|x| *x = 1.0);
    }
    (s, w)
}

/// Centres of a [`REGION_GRID`]² grid over the paths' control box inside their fill (nonzero
/// rule, each subpath closed); `None` when fewer than three are inside.
fn area_samples(paths: &[splineskin_core::drawing::Path]) -> Option<(Vec<Point>, Vec<f64>)> {
    let mut bez = BezPath::new();
    let mut bounds: Option<Rect> = None;
    for path in paths {
        bez.move_to(path.points[0]);
        for j in 0..path.n_curves() {
            let [_, p1, p2, p3] = path.curve_points(j);
            bez.curve_to(p1, p2, p3);
        }
        bez.close_path();
        for &p in &path.points {
            bounds = Some(bounds.map_or(Rect::from_points(p, p), |r| r.union_pt(p)));
        }
    }
    let inside: Vec<Point> = grid(bounds?)
        .into_iter()
        .filter(|&p| bez.winding(p) != 0)
        .collect();
    (inside.len() >= 3).then(|| {
        let w = vec![1.0; inside.len()];
        (inside, w)
    })
}

/// Centres of a [`REGION_GRID`]² grid over `r`.
fn grid(r: Rect) -> Vec<Point> {
    let n = REGION_GRID;
    let mut out = Vec::with_capacity(n * n);
    for iy in 0..n {
        for ix in 0..n {
            let fx = (ix as f64 + 0.5) / n as f64;
            let fy = (iy as f64 + 0.5) / n as f64;
            out.push(Point::new(r.x0 + fx * r.width(), r.y0 + fy * r.height()));
        }
    }
    out
}

/// The `transform` attribute of `node` (identity when absent or unreadable: import has
/// checked every transform).
pub(crate) fn own_transform(node: roxmltree::Node) -> Affine {
    node.attribute("transform")
        .and_then(|v| svgtypes::Transform::from_str(v).ok())
        .map(|t| Affine::new([t.a, t.b, t.c, t.d, t.e, t.f]))
        .unwrap_or(Affine::IDENTITY)
}

/// Containers through which a `<text>` or `<image>` is drawn as it is in root user space.
const PLAIN_CONTAINERS: &[&str] = &["g", "a", "switch"];

/// The `<text>` and `<image>` elements that are carried (module doc), with their parent's
/// user space → root map and their region in their local coordinates.
pub(crate) fn carried_elements<'a, 'i>(
    doc: &'a roxmltree::Document<'i>,
    source: &splineskin_core::drawing::SvgSource,
) -> Vec<(roxmltree::Node<'a, 'i>, Affine, Rect)> {
    let root = doc.root_element();
    let mut out = Vec::new();
    for node in doc.descendants() {
        if !crate::document::is_svg_element(node) {
            continue;
        }
        let tag = node.tag_name().name();
        if tag != "text" && tag != "image" {
            continue;
        }
        let mut parent_to_root = Affine::IDENTITY;
        let mut plain = true;
        for a in node.ancestors().skip(1) {
            if a == root || !a.is_element() {
                break;
            }
            if !(crate::document::is_svg_element(a)
                && PLAIN_CONTAINERS.contains(&a.tag_name().name()))
            {
                plain = false;
                if a.tag_name().name() == "svg" {
                    tracing::warn!(
                        file = source.origin.as_str(),
                        element = %crate::document::node_label(doc, node),
                        "text or image inside a nested <svg> is not carried by the deformation"
                    );
                }
                break;
            }
            parent_to_root = own_transform(a) * parent_to_root;
        }
        if !plain {
            continue;
        }
        let region = match tag {
            "image" => image_region(node, source),
            _ if node
                .descendants()
                .any(|d| d.tag_name().name() == "textPath") =>
            {
                None
            }
            _ => Some(text_region(node)),
        };
        if let Some(region) = region {
            out.push((node, parent_to_root, region));
        }
    }
    out
}

/// An image's `x y width height` (percentages of the root viewport); `None` without a size.
fn image_region(
    node: roxmltree::Node,
    source: &splineskin_core::drawing::SvgSource,
) -> Option<Rect> {
    let vb = source.view_box;
    let length = |name: &str, base: f64| {
        node.attribute(name)
            .map(|v| crate::document::user_length(v, base).ok())
            .unwrap_or(Some(0.0))
    };
    let (x, y) = (length("x", vb.width())?, length("y", vb.height())?);
    let (w, h) = (length("width", vb.width())?, length("height", vb.height())?);
    if !(w > 0.0 && h > 0.0) {
        tracing::warn!(
            file = source.origin.as_str(),
            "an <image> without width and height is not carried by the deformation"
        );
        return None;
    }
    Some(Rect::new(x, y, x + w, y + h))
}

/// The estimated box of a `<text>` (module doc), in its local coordinates.
fn text_region(node: roxmltree::Node) -> Rect {
    let first = |name: &str| {
        node.attribute(name)
            .and_then(|v| v.split([' ', ',']).find(|s| !s.is_empty()))
            .and_then(|v| crate::document::user_length(v, 100.0).ok())
            .unwrap_or(0.0)
    };
    let (x, y) = (first("x"), first("y"));
    let em = inherited(node, "font-size")
        .and_then(|v| crate::document::user_length(&v, DEFAULT_FONT_SIZE).ok())
        .filter(|v| *v > 0.0)
        .unwrap_or(DEFAULT_FONT_SIZE);
    let n_chars = node
        .descendants()
        .filter(|d| d.is_text())
        .filter_map(|d| d.text())
        .map(|t| {
            t.split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
                .chars()
                .count()
        })
        .sum::<usize>()
        .max(1);
    let width = TEXT_ADVANCE * em * n_chars as f64;
    let x0 = match inherited(node, "text-anchor").as_deref() {
        Some("middle") => x - width / 2.0,
        Some("end") => x - width,
        _ => x,
    };
    Rect::new(x0, y - 0.8 * em, x0 + width, y + 0.2 * em)
}

/// The value of property `name` on `node` or its nearest ancestor that sets it, from `style`
/// declarations (first) or the presentation attribute (style sheets are not read).
pub(crate) fn inherited(node: roxmltree::Node, name: &str) -> Option<String> {
    for n in node.ancestors().filter(|n| n.is_element()) {
        if let Some(v) = declared(n, name) {
            return Some(v);
        }
    }
    None
}

/// The value of property `name` declared on `node` itself (`style`, then the attribute).
pub(crate) fn declared(node: roxmltree::Node, name: &str) -> Option<String> {
    if let Some(style) = node.attribute("style") {
        for decl in style.split(';') {
            if let Some((k, v)) = decl.split_once(':') {
                if k.trim() == name {
                    return Some(v.trim().trim_end_matches("!important").trim().to_string());
                }
            }
        }
    }
    node.attribute(name).map(|v| v.trim().to_string())
}

/// Whether two local maps agree within [`SAME_MAP`] over a region of size `size` (local
/// units): `‖ΔM‖·size + ‖Δt‖ ≤ SAME_MAP · (‖M‖·size + ‖t‖)`, coefficient-wise max norms.
pub(crate) fn same_map(a: Affine, b: Affine, size: f64) -> bool {
    let (ca, cb) = (a.as_coeffs(), b.as_coeffs());
    let lin = |c: &[f64; 6]| c[..4].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let tr = |c: &[f64; 6]| c[4].abs().max(c[5].abs());
    let d: [f64; 6] = std::array::from_fn(|k| ca[k] - cb[k]);
    lin(&d) * size + tr(&d) <= SAME_MAP * (lin(&ca) * size + tr(&ca))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn best_fit_affine_on_a_line_is_completed_conformally() {
        let t = Affine::translate((3.0, 1.0)) * Affine::rotate(0.4) * Affine::scale(2.0);
        let rest: Vec<Point> = (0..5)
            .map(|k| Point::new(k as f64, 2.0 * k as f64))
            .collect();
        let image: Vec<Point> = rest.iter().map(|&p| t * p).collect();
        let a = best_fit_affine(&rest, &image, &[1.0; 5]).unwrap();
        for (x, y) in a.as_coeffs().iter().zip(t.as_coeffs()) {
            assert!((x - y).abs() < 1e-12, "{a:?} vs {t:?}");
        }
        // One point: translation only.
        let p = [Point::new(5.0, 5.0)];
        let a = best_fit_affine(&p, &[Point::new(6.0, 4.0)], &[1.0]).unwrap();
        assert_eq!(a, Affine::translate((1.0, -1.0)));
    }

    #[test]
    fn best_fit_affine_is_scale_and_translation_invariant() {
        let rest: Vec<Point> = (0..30)
            .map(|k| Point::new((k as f64 * 2.1).sin(), (k as f64 * 1.3).cos()))
            .collect();
        let f = |p: Point| Point::new(p.x + 0.3 * p.y * p.y, p.y + 0.2 * p.x);
        let a = best_fit_affine(
            &rest,
            &rest.iter().map(|&p| f(p)).collect::<Vec<_>>(),
            &[1.0; 30],
        )
        .unwrap();
        // Scaled by 10^±6 and moved a thousand times its size away (f64 keeps the samples'
        // spread to ~1e-13 there).
        for (s, d) in [(1e-6, 1e-3), (1e6, -3e9)] {
            let to = Affine::translate((d, d)) * Affine::scale(s);
            let rest2: Vec<Point> = rest.iter().map(|&p| to * p).collect();
            let image2: Vec<Point> = rest.iter().map(|&p| to * f(p)).collect();
            let b = best_fit_affine(&rest2, &image2, &[1.0; 30]).unwrap();
            let expected = to * a * to.inverse();
            let probe = to * Point::new(0.5, 0.5);
            assert!((b * probe - expected * probe).hypot() < 1e-9 * s, "{s}");
        }
    }
}
