//! The 2D data model: a [`Drawing`] is a list of [`Path`]s, each a chain of cubic Bézier
//! curves, open or closed, with a [`JointKind`] at every on-curve point ([`junction`]), and
//! optionally the record of the SVG document it came from ([`SvgSource`]).
//!
//! The model knows no SVG syntax: the `splineskin-svg` crate reads documents into drawings and
//! writes deformed geometry back into the same text. All coordinates are `f64` in the root
//! element's user space (viewBox units).

pub mod junction;
pub mod source;

pub use junction::{
    classify_joints, coincidence_distance, JointKind, JointMismatch, JunctionOptions,
};
pub use source::{ElementKind, SvgSource};

/// What a path of a drawing is in its document, so that code which should only look at what
/// is drawn (the weights' domain, error figures, pictures) can leave the rest out, while every
/// path is still deformed and written back.
///
/// Rule: a path is [`PathRole::Hidden`] when it or an ancestor (or a `use` through which it is
/// instantiated) has `display: none` (attribute, `style` or CSS) — browsers and usvg do not draw
/// it, but unhiding its layer shows it, so it is deformed like everything else;
/// [`PathRole::Unpainted`] when it is laid out but paints nothing (`visibility: hidden` or
/// `collapse`, or neither fill nor stroke); [`PathRole::ClipPath`] and [`PathRole::Mask`] for
/// the geometry of a `<clipPath>` or the content of a `<mask>` (they shape what other elements
/// show, are never drawn themselves); [`PathRole::Visible`] otherwise. A drawing without a
/// source document has only visible paths.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum PathRole {
    /// Drawn.
    #[default]
    Visible,
    /// Not rendered because of `display: none` on it or an ancestor; deformed and written back.
    Hidden,
    /// Rendered but invisible: `visibility` hidden/collapse, or no fill and no stroke.
    Unpainted,
    /// Geometry of a `<clipPath>`.
    ClipPath,
    /// Content of a `<mask>`.
    Mask,
}

impl PathRole {
    /// Whether the path itself is drawn ([`PathRole::Visible`]).
    pub fn is_drawn(self) -> bool {
        self == PathRole::Visible
    }
}

use kurbo::{CubicBez, Point, Rect};

/// A drawing: subpaths in document order, and (when it came from SVG) what is needed to write
/// deformed geometry back into the same document.
#[derive(Clone, Debug, Default)]
pub struct Drawing {
    /// Every subpath of every imported element, in document order.
    pub paths: Vec<Path>,
    /// The SVG document the drawing came from, if any (needed to write deformed geometry back into it).
    pub source: Option<std::sync::Arc<SvgSource>>,
}

/// One subpath: a chain of `n ≥ 1` cubic Bézier curves.
///
/// `points` holds the `3n + 1` chain points `P_0 … P_3n`; curve `j` is
/// `P_3j, P_3j+1, P_3j+2, P_3j+3`. A closed path repeats its first point at the end
/// (`P_3n == P_0`). `joints[k]` is the kind of the on-curve point `P_3k` (the start of curve
/// `k`): `n + 1` entries for an open path (the two ends are [`JointKind::End`]), `n` for a closed
/// one (`joints[0]` is the junction between the last and the first curve).
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    /// The `3n + 1` chain points.
    pub points: Vec<Point>,
    /// Whether the last curve joins the first.
    pub closed: bool,
    /// The continuity kind at each on-curve point (see the type doc for its length).
    pub joints: Vec<JointKind>,
}

impl Path {
    /// Builds a path from its chain points, classifying its joints with `options`.
    ///
    /// Returns `None` if `points.len()` is not `3n + 1` with `n ≥ 1`, or if `closed` is asked
    /// but the last point differs from the first.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::drawing::{JointKind, JunctionOptions, Path};
    /// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from);
    /// let path = Path::new(pts.to_vec(), false, &JunctionOptions::default()).unwrap();
    /// assert_eq!(path.n_curves(), 1);
    /// assert_eq!(path.joints, vec![JointKind::End, JointKind::End]);
    /// ```
    pub fn new(points: Vec<Point>, closed: bool, options: &JunctionOptions) -> Option<Path> {
        if !is_chain(&points, closed) {
            return None;
        }
        let joints = classify_joints(&points, closed, options);
        Some(Path {
            points,
            closed,
            joints,
        })
    }

    /// Number of cubic curves `n`.
    #[inline]
    pub fn n_curves(&self) -> usize {
        (self.points.len() - 1) / 3
    }

    /// The control points of curve `j`.
    #[inline]
    pub fn curve_points(&self, j: usize) -> [Point; 4] {
        let p = &self.points[3 * j..3 * j + 4];
        [p[0], p[1], p[2], p[3]]
    }

    /// Curve `j` as a kurbo cubic.
    #[inline]
    pub fn curve(&self, j: usize) -> CubicBez {
        let [p0, p1, p2, p3] = self.curve_points(j);
        CubicBez::new(p0, p1, p2, p3)
    }

    /// Number of distinct unknown points of the fit: `3n + 1` open, `3n` closed (the repeated
    /// first point is not a separate unknown).
    #[inline]
    pub fn n_unknown_points(&self) -> usize {
        if self.closed {
            self.points.len() - 1
        } else {
            self.points.len()
        }
    }

    /// The unknown point (in `0..n_unknown_points()`) that chain point `k` is: `k` itself,
    /// except the repeated last point of a closed path, which is point 0.
    #[inline]
    pub fn unknown_index(&self, k: usize) -> usize {
        let m = self.n_unknown_points();
        if k >= m {
            k - m
        } else {
            k
        }
    }

    /// The coordinate rows of the path's points: for each chain point `k` in order and axis
    /// `d` (x = 0, y = 1), the row `2 (first + k) + d` of a drawing's flat coordinate list in
    /// which the path's first point is point `first` ([`Drawing::path_ranges`]), with the
    /// row `2 u + d` of its unknown `u` ([`Path::unknown_index`]): where a path's solved rows
    /// go in the drawing's.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::drawing::{JunctionOptions, Path};
    /// let p = [(0., 0.), (1., 1.), (2., 1.), (0., 0.)].map(Point::from);
    /// let closed = Path::new(p.to_vec(), true, &JunctionOptions::default()).unwrap();
    /// let rows: Vec<(usize, usize)> = closed.coordinate_rows(5).collect();
    /// assert_eq!(rows[..2], [(10, 0), (11, 1)]);
    /// // The closing point is point 0 again.
    /// assert_eq!(rows[6..], [(16, 0), (17, 1)]);
    /// ```
    pub fn coordinate_rows(&self, first: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.points.len()).flat_map(move |k| {
            let u = self.unknown_index(k);
            (0..2).map(move |d| (2 * (first + k) + d, 2 * u + d))
        })
    }
}

/// Whether `points` is a chain of cubics: `3n + 1` points with `n ≥ 1`, and, if `closed`, the
/// last point equal to the first.
///
/// ```
/// use kurbo::Point;
/// let p = [Point::ZERO, Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::ZERO];
/// assert!(splineskin_core::drawing::is_chain(&p, true));
/// assert!(!splineskin_core::drawing::is_chain(&p[..3], false));
/// ```
pub fn is_chain(points: &[Point], closed: bool) -> bool {
    points.len() >= 4
        && (points.len() - 1) % 3 == 0
        && (!closed || points[0] == points[points.len() - 1])
}

impl Drawing {
    /// Total number of cubic curves over all paths.
    pub fn n_curves(&self) -> usize {
        self.paths.iter().map(Path::n_curves).sum()
    }

    /// Total number of chain points over all paths (each path's `points.len()`): the length of
    /// the flat point buffers that rigs write ([`Drawing::with_points`] reads them back).
    pub fn n_points(&self) -> usize {
        self.paths.iter().map(|p| p.points.len()).sum()
    }

    /// Where each path's chain points stand in the flat point buffers (all paths' points
    /// concatenated in path order, [`Drawing::n_points`] long, as rigs write them): one range
    /// per path, in path order.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
    /// let o = JunctionOptions::default();
    /// let line = |x: f64| (0..4).map(|k| Point::new(x, k as f64)).collect::<Vec<_>>();
    /// let two = (0..7).map(|k| Point::new(k as f64, 0.0)).collect::<Vec<_>>();
    /// let drawing = Drawing {
    ///     paths: vec![Path::new(line(0.0), false, &o).unwrap(), Path::new(two, false, &o).unwrap()],
    ///     ..Default::default()
    /// };
    /// let ranges: Vec<_> = drawing.path_ranges().collect();
    /// assert_eq!(ranges, vec![0..4, 4..11]);
    /// ```
    pub fn path_ranges(&self) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
        self.paths.iter().scan(0, |offset, path| {
            let start = *offset;
            *offset += path.points.len();
            Some(start..*offset)
        })
    }

    /// All chain points of all paths, concatenated in path order.
    pub fn flat_points(&self) -> Vec<Point> {
        self.paths
            .iter()
            .flat_map(|p| p.points.iter().copied())
            .collect()
    }

    /// A copy of this drawing with its chain points replaced by `points` (concatenated in path
    /// order, `self.n_points()` of them). Joint kinds are kept. Returns `None` on a length
    /// mismatch.
    pub fn with_points(&self, points: &[Point]) -> Option<Drawing> {
        if points.len() != self.n_points() {
            return None;
        }
        let mut out = self.clone();
        for (path, range) in out.paths.iter_mut().zip(self.path_ranges()) {
            path.points.copy_from_slice(&points[range]);
        }
        Some(out)
    }

    /// The role of path `path_index` in its document ([`PathRole`]; `Visible` for a drawing
    /// without a source or an index out of range).
    /// (`splineskin_svg`'s crate documentation has an example.)
    pub fn path_role(&self, path_index: usize) -> PathRole {
        self.source
            .as_ref()
            .map_or(PathRole::Visible, |s| s.path_role(path_index))
    }

    /// Whether path `path_index` is drawn ([`PathRole::is_drawn`] of [`Drawing::path_role`]).
    pub fn is_drawn(&self, path_index: usize) -> bool {
        self.path_role(path_index).is_drawn()
    }

    /// Every junction whose kind its input does not have, as `(path index, mismatch)`
    /// ([`junction::joint_mismatches`]): where our fit keeps the input's own tangent relation
    /// rather than the kind's, so that the rest pose is reproduced.
    pub fn joint_mismatches(&self, options: &JunctionOptions) -> Vec<(usize, JointMismatch)> {
        self.paths
            .iter()
            .enumerate()
            .flat_map(|(i, path)| {
                junction::joint_mismatches(&path.points, path.closed, &path.joints, options)
                    .into_iter()
                    .map(move |m| (i, m))
            })
            .collect()
    }

    /// A sentence for the user about [`Drawing::joint_mismatches`], `None` when there are
    /// none: how many junctions saved as C¹ or G¹ the input does not satisfy, the largest
    /// angle between their tangents, how many have no tangent on a side, and what the fit
    /// does there ([`junction::rest_relation`]).
    ///
    /// ```
    /// use kurbo::{Point, Vec2};
    /// use splineskin_core::drawing::{Drawing, JointKind, JunctionOptions, Path};
    /// let d = Vec2::from_angle(3f64.to_radians());
    /// let q = Point::new(3.0, 0.0);
    /// let pts = vec![Point::ZERO, Point::new(1.0, 0.0), Point::new(2.0, 0.0), q, q + d, q + 2.0 * d, q + 3.0 * d];
    /// let o = JunctionOptions::default();
    /// let mut path = Path::new(pts, false, &o).unwrap();
    /// path.joints[1] = JointKind::G1; // as a scene would save it
    /// let drawing = Drawing { paths: vec![path], ..Default::default() };
    /// let note = drawing.joint_mismatch_note(&o).unwrap();
    /// assert!(note.starts_with("1 of 1 junctions saved as C1 or G1 are not so in the input (tangents up to 3.0° apart)"), "{note}");
    /// ```
    pub fn joint_mismatch_note(&self, options: &JunctionOptions) -> Option<String> {
        let mismatches = self.joint_mismatches(options);
        if mismatches.is_empty() {
            return None;
        }
        let smooth = self
            .paths
            .iter()
            .flat_map(|p| p.joints.iter())
            .filter(|k| matches!(k, JointKind::C1 | JointKind::G1))
            .count();
        let largest = mismatches
            .iter()
            .filter_map(|(_, m)| m.angle)
            .fold(0.0f64, f64::max);
        let without = mismatches.iter().filter(|(_, m)| m.angle.is_none()).count();
        let mut note = format!(
            "{} of {smooth} junctions saved as C1 or G1 are not so in the input (tangents up to {:.1}° apart",
            mismatches.len(),
            largest.to_degrees()
        );
        if without > 0 {
            note += &format!("; {without} without a tangent on a side, kept C0");
        }
        note += &format!(
            "): those within {:.1}° keep their input turn and length ratio, the others only their position (C0), so the rest pose is the drawing",
            options.smooth_angle.to_degrees()
        );
        Some(note)
    }

    /// The axis-aligned bounding box of all control points (`None` for an empty drawing).
    pub fn control_bounds(&self) -> Option<Rect> {
        let mut it = self.paths.iter().flat_map(|p| p.points.iter());
        let first = *it.next()?;
        Some(it.fold(Rect::from_points(first, first), |r, &p| r.union_pt(p)))
    }

    /// Length of the diagonal of [`Drawing::control_bounds`] (0 for an empty drawing): the
    /// scale that relative tolerances and error figures refer to.
    pub fn diagonal(&self) -> f64 {
        self.control_bounds()
            .map(|r| r.width().hypot(r.height()))
            .unwrap_or(0.0)
    }
}
