//! The triangulated domain of a drawing, on which the mesh weight families (harmonic,
//! biharmonic, bounded biharmonic) are solved, and the evaluation of per-vertex weights inside
//! the fit ([`MeshWeights`]). DESIGN.md §2, Liu et al. 2014 §5.
//!
//! ```text
//! drawing + handles ──► Domain::build ──► TriMesh + handle vertex indices ──► weight solver
//!                                                                              │ #V × h weights
//! quadrature nodes ◄── MeshWeights (point location, barycentric, kinks) ◄──────┘
//! ```
//!
//! **The domain** is a conforming constrained Delaunay triangulation with quality refinement
//! (Ruppert/Chew refinement, by the `spade` crate) of, in order of preference:
//!
//! 1. the user's cage polygon ([`DomainOptions::cage`]), which must be simple and
//!    counter-clockwise (positive [`polygon::signed_area`]) — a clockwise cage is rejected
//!    ([`DomainError::CageClockwise`]) rather than silently reversed, because cage weights are
//!    indexed by cage vertex and their order is the user's;
//! 2. else the largest closed path of the drawing (by the area of its flattening), when it
//!    contains all other geometry (curve samples within one sample spacing of it, handles and
//!    bones strictly inside) — [`Boundary::ClosedCurve`]. Small loops where the path crosses
//!    itself (at most 16, holding under 1 % of its area together: a closing curve that
//!    overshoots its start, a twisted cusp) are cut off first
//!    ([`polygon::without_small_loops`]); the path's own samples in them lie outside the domain
//!    and take the weights of the nearest boundary point;
//! 3. else the bounding box of the curves and handles, padded on every side by
//!    [`DomainOptions::padding`] times the drawing's diagonal — [`Boundary::Padded`].
//!
//! The paper authors' code always gives Triangle one closed path's sampled outline (meant to be
//! the largest by bounding box) and does not check that the rest of the drawing is inside it:
//! samples outside belong to no triangle, their BBW solve then fails, and their code silently
//! uses Shepard weights instead (two of their saved BBW scenes; see
//! `tests/vectorskinning_mesh_weights.rs`). Rule 2 checks containment instead, counting curves
//! drawn along the outline (within one sample spacing) as on it.
//!
//! With [`DomainOptions::holes`], closed paths inside the boundary that enclose nothing else
//! (no curve sample, handle or bone) and are simple become holes.
//!
//! **Vertices.** Every point handle is a vertex ([`Domain::handle_vertices`]); every bone is a
//! chain of vertices joined by constraint edges ([`Domain::bone_vertices`]), so a weight set to
//! one at those vertices is one along the whole segment. Curves are sampled uniformly in
//! parameter, curve `j` into `n_j = clamp(⌈ℓ_j / s⌉, 1, max_samples_per_curve)` intervals
//! (`ℓ_j` its arc length), with spacing `s = D / samples_per_diagonal` (`D` the diagonal of the
//! curves' bounding box) — about one sample per pixel for a drawing shown 500 px across, and
//! at most 100 per curve, as in the paper (§5: "100 samples per curve or one per pixel,
//! whichever is sparser"). If the total exceeds `max_curve_samples`, `s` grows until it does
//! not. A sample closer than `s/2` to a vertex already placed or to a constraint edge is
//! skipped (near-duplicates only force needless refinement), as are samples outside the
//! domain. Refinement then adds Steiner points until every triangle has its smallest angle
//! above [`DomainOptions::min_angle`] (except where two constraint edges meet at a smaller
//! angle) and an area below `max_area_fraction · area(domain)`, within `max_vertices`
//! vertices in total.

mod art_region;
pub mod crossings;
pub mod distance;
mod grid;
pub mod locate;
pub mod polygon;
mod triangulate;

pub use locate::MeshWeights;

use kurbo::Point;

use crate::drawing::Drawing;
use crate::mesh::{MeshError, TriMesh};

/// Default smallest triangle angle of refinement: 25°. Ruppert's algorithm terminates for
/// limits up to about 20.7° in theory and works in practice to about 30–33°; 25° leaves room
/// while keeping cotangent weights well conditioned (cot 25° ≈ 2.1).
pub const DEFAULT_MIN_ANGLE: f64 = 25.0;
/// Default largest triangle area, as a fraction of the domain's area: 1/5000, so that even
/// regions far from any curve get triangles of about 1/70 of the domain's size.
pub const DEFAULT_MAX_AREA_FRACTION: f64 = 1.0 / 5000.0;
/// Default largest number of vertices of the domain: 250 000 (refinement stops there and
/// reports [`Domain::refinement_complete`] = false).
pub const DEFAULT_MAX_VERTICES: usize = 250_000;
/// Default curve sample spacing, as samples per diagonal of the drawing: 500 (see the module
/// documentation).
pub const DEFAULT_SAMPLES_PER_DIAGONAL: f64 = 500.0;
/// Default cap of samples per curve: 100 (the paper's figure).
pub const DEFAULT_MAX_SAMPLES_PER_CURVE: usize = 100;
/// Default cap of curve samples over the whole drawing: 100 000.
pub const DEFAULT_MAX_CURVE_SAMPLES: usize = 100_000;
/// Default padding of the bounding-box domain, as a fraction of the drawing's diagonal: 0.05.
pub const DEFAULT_PADDING: f64 = 0.05;
/// Default margin of the art-shaped domain ([`DomainShape::Art`]), as a fraction of the
/// drawing's diagonal: 0.01 (Puppet Warp's "expansion"). Parts of the art closer than about
/// twice the margin are joined.
pub const DEFAULT_MARGIN: f64 = 0.01;
/// Largest accepted margin of the art-shaped domain, as a fraction of the diagonal: 1.
pub const MAX_MARGIN: f64 = 1.0;
/// Largest accepted minimum angle: 34° (beyond it refinement does not terminate and only the
/// vertex cap stops it).
pub const MAX_MIN_ANGLE: f64 = 34.0;
/// Two handles (or a handle and a bone, or a cage vertex and its neighbour) closer than this
/// fraction of the drawing's diagonal are coincident: 1e-9.
pub const COINCIDENT_RELATIVE: f64 = 1e-9;

/// Options of [`Domain::build`].
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::{Boundary, Domain, DomainError, DomainOptions};
/// use splineskin_core::drawing::Drawing;
///
/// // A cage alone (no drawing) is a domain; coarser than the defaults.
/// let cage = [(0., 0.), (10., 0.), (10., 10.), (0., 10.)].map(Point::from).to_vec();
/// let options = DomainOptions::default()
///     .with_cage(cage.clone())
///     .with_min_angle(30.0)
///     .with_max_area_fraction(0.01);
/// let handles = [Point::new(2.0, 2.0), Point::new(8.0, 5.0)];
/// let domain = Domain::build(&Drawing::default(), &handles, &[], &options)?;
/// assert_eq!(domain.boundary, Boundary::Cage);
/// assert!((domain.area - 100.0).abs() < 1e-12);
/// assert!(Domain::min_angle_of(&domain.mesh) >= 30.0 - 1e-9);
/// // The same cage clockwise is refused.
/// let reversed: Vec<Point> = cage.iter().rev().copied().collect();
/// let err = Domain::build(&Drawing::default(), &handles, &[], &options.with_cage(reversed));
/// assert!(matches!(err, Err(DomainError::CageClockwise { .. })));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct DomainOptions {
    /// The user's cage: a simple counter-clockwise polygon (closed implicitly; a last vertex
    /// repeating the first is dropped). Default: none (the domain is chosen from the drawing).
    pub cage: Option<Vec<Point>>,
    /// Make holes where the drawing has them (closed paths enclosing nothing). Default: false.
    pub holes: bool,
    /// Smallest triangle angle refinement aims for, in degrees, in `[0, MAX_MIN_ANGLE]`.
    /// Default: [`DEFAULT_MIN_ANGLE`].
    pub min_angle: f64,
    /// Largest triangle area as a fraction of the domain's area, in `(0, 1]`.
    /// Default: [`DEFAULT_MAX_AREA_FRACTION`].
    pub max_area_fraction: f64,
    /// Largest number of vertices. Default: [`DEFAULT_MAX_VERTICES`].
    pub max_vertices: usize,
    /// Curve sample spacing as samples per drawing diagonal (positive).
    /// Default: [`DEFAULT_SAMPLES_PER_DIAGONAL`].
    pub samples_per_diagonal: f64,
    /// Cap of samples per curve (≥ 1). Default: [`DEFAULT_MAX_SAMPLES_PER_CURVE`].
    pub max_samples_per_curve: usize,
    /// Cap of curve samples in total. Default: [`DEFAULT_MAX_CURVE_SAMPLES`].
    pub max_curve_samples: usize,
    /// Padding of the bounding-box domain as a fraction of the diagonal (positive).
    /// Default: [`DEFAULT_PADDING`].
    pub padding: f64,
    /// Which region the domain covers when there is no cage. Default:
    /// [`DomainShape::Enclosing`] (the paper's rule, which the authors' scenes keep).
    pub shape: DomainShape,
    /// Margin of the art-shaped domain ([`DomainShape::Art`]) as a fraction of the drawing's
    /// diagonal, in `[0, MAX_MARGIN]`. Default: [`DEFAULT_MARGIN`].
    pub margin: f64,
}

/// Which region a domain without a cage covers ([`DomainOptions::shape`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum DomainShape {
    /// The largest closed path of the drawing when it contains everything, else the padded
    /// bounding box (rules 2 and 3 of the module documentation; the paper's domain).
    #[default]
    Enclosing,
    /// The art itself: the region the drawing paints (fills, strokes at their width), grown by
    /// [`DomainOptions::margin`], with its holes, one connected part per group of shapes that
    /// touch, overlap or lie within twice the margin of each other; parts without a handle are
    /// left out, and their curves take the weights of the nearest pinned art
    /// ([`Boundary::Art`]). A pin's influence thus never crosses background: a leg drawn apart
    /// from its neighbour is joined to it only through the body they share.
    Art,
}

impl DomainShape {
    /// The shape's name in scene files and on the command line: `enclosing` or `art`.
    pub fn name(self) -> &'static str {
        match self {
            DomainShape::Enclosing => "enclosing",
            DomainShape::Art => "art",
        }
    }

    /// The shape named `name` ([`DomainShape::name`]).
    ///
    /// ```
    /// use splineskin_core::domain::DomainShape;
    /// assert_eq!(DomainShape::from_name("art"), Some(DomainShape::Art));
    /// assert_eq!(DomainShape::from_name("box"), None);
    /// ```
    pub fn from_name(name: &str) -> Option<DomainShape> {
        [DomainShape::Enclosing, DomainShape::Art]
            .into_iter()
            .find(|s| s.name() == name)
    }
}

impl Default for DomainOptions {
    fn default() -> Self {
        DomainOptions {
            cage: None,
            holes: false,
            min_angle: DEFAULT_MIN_ANGLE,
            max_area_fraction: DEFAULT_MAX_AREA_FRACTION,
            max_vertices: DEFAULT_MAX_VERTICES,
            samples_per_diagonal: DEFAULT_SAMPLES_PER_DIAGONAL,
            max_samples_per_curve: DEFAULT_MAX_SAMPLES_PER_CURVE,
            max_curve_samples: DEFAULT_MAX_CURVE_SAMPLES,
            padding: DEFAULT_PADDING,
            shape: DomainShape::Enclosing,
            margin: DEFAULT_MARGIN,
        }
    }
}

impl DomainOptions {
    /// Sets [`DomainOptions::cage`].
    pub fn with_cage(mut self, cage: Vec<Point>) -> Self {
        self.cage = Some(cage);
        self
    }
    /// Sets [`DomainOptions::holes`].
    pub fn with_holes(mut self, holes: bool) -> Self {
        self.holes = holes;
        self
    }
    /// Sets [`DomainOptions::min_angle`] (degrees).
    pub fn with_min_angle(mut self, degrees: f64) -> Self {
        self.min_angle = degrees;
        self
    }
    /// Sets [`DomainOptions::max_area_fraction`].
    pub fn with_max_area_fraction(mut self, fraction: f64) -> Self {
        self.max_area_fraction = fraction;
        self
    }
    /// Sets [`DomainOptions::max_vertices`].
    pub fn with_max_vertices(mut self, n: usize) -> Self {
        self.max_vertices = n;
        self
    }
    /// Sets [`DomainOptions::samples_per_diagonal`].
    pub fn with_samples_per_diagonal(mut self, n: f64) -> Self {
        self.samples_per_diagonal = n;
        self
    }
    /// Sets [`DomainOptions::max_samples_per_curve`].
    pub fn with_max_samples_per_curve(mut self, n: usize) -> Self {
        self.max_samples_per_curve = n;
        self
    }
    /// Sets [`DomainOptions::max_curve_samples`].
    pub fn with_max_curve_samples(mut self, n: usize) -> Self {
        self.max_curve_samples = n;
        self
    }
    /// Sets [`DomainOptions::padding`].
    pub fn with_padding(mut self, fraction: f64) -> Self {
        self.padding = fraction;
        self
    }
    /// Sets [`DomainOptions::shape`].
    pub fn with_shape(mut self, shape: DomainShape) -> Self {
        self.shape = shape;
        self
    }
    /// Sets [`DomainOptions::margin`] (fraction of the diagonal).
    pub fn with_margin(mut self, fraction: f64) -> Self {
        self.margin = fraction;
        self
    }
}

/// What the domain's outer boundary is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// The user's cage.
    Cage,
    /// The closed path `path` of the drawing (index into `Drawing::paths`).
    ClosedCurve {
        /// The path.
        path: usize,
    },
    /// The padded bounding box.
    Padded,
    /// The art's own shape grown by the margin ([`DomainShape::Art`]): `parts` connected
    /// parts, each holding a handle; `unpinned` parts of the art without a handle were left
    /// out.
    Art {
        /// Connected parts of the domain.
        parts: usize,
        /// Parts of the art left out for holding no handle.
        unpinned: usize,
    },
}

impl std::fmt::Display for Boundary {
    /// What the boundary is, in words for summaries (`splineskin info`, the editor's mesh view).
    ///
    /// ```
    /// use splineskin_core::domain::Boundary;
    /// let art = Boundary::Art { parts: 3, unpinned: 1 };
    /// assert_eq!(art.to_string(), "the art (3 parts, 1 part without a pin left out)");
    /// assert_eq!(Boundary::ClosedCurve { path: 2 }.to_string(), "closed path 2");
    /// ```
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let plural = |n: usize, word: &str| format!("{n} {word}{}", if n == 1 { "" } else { "s" });
        match *self {
            Boundary::Cage => write!(f, "the cage"),
            Boundary::ClosedCurve { path } => write!(f, "closed path {path}"),
            Boundary::Padded => write!(f, "the padded bounding box"),
            Boundary::Art { parts, unpinned } => {
                write!(f, "the art ({}", plural(parts, "part"))?;
                if unpinned > 0 {
                    write!(f, ", {} without a pin left out", plural(unpinned, "part"))?;
                }
                write!(f, ")")
            }
        }
    }
}

/// A triangulated domain: the mesh and where the handles are in it.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::{Boundary, Domain, DomainOptions};
/// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
///
/// let arch = [(0.0, 0.0), (30.0, 40.0), (70.0, 40.0), (100.0, 0.0)].map(Point::from);
/// let path = Path::new(arch.to_vec(), false, &JunctionOptions::default()).unwrap();
/// let drawing = Drawing { paths: vec![path], source: None };
/// let handles = [Point::new(0.0, 0.0), Point::new(100.0, 0.0)];
/// let domain = Domain::build(&drawing, &handles, &[], &DomainOptions::default())?;
/// assert_eq!(domain.boundary, Boundary::Padded);
/// assert_eq!(domain.mesh.vertices[domain.handle_vertices[1]], handles[1]);
/// assert!(domain.mesh.n_triangles() > 1000);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Domain {
    /// The triangle mesh (counter-clockwise triangles).
    pub mesh: TriMesh,
    /// The vertex of each point handle, in the order given.
    pub handle_vertices: Vec<usize>,
    /// The vertices along each bone, from its first end point to its second, in order.
    pub bone_vertices: Vec<Vec<usize>>,
    /// The vertex of each cage corner, in the cage's order (empty without a cage).
    pub cage_vertices: Vec<usize>,
    /// The boundary of the mesh as closed vertex loops (the last vertex joins the first), by
    /// decreasing signed area: the outer ones first (one per part of an art-shaped domain,
    /// [`Boundary::Art`]) and counter-clockwise, then the holes, clockwise. Includes the Steiner
    /// points refinement placed on boundary edges.
    pub boundary_loops: Vec<Vec<usize>>,
    /// What the outer boundary is.
    pub boundary: Boundary,
    /// Area of the domain (outer polygon minus holes), drawing units squared; the triangles'
    /// areas sum to it.
    pub area: f64,
    /// Curve sample spacing `s` used (drawing units).
    pub sample_spacing: f64,
    /// Number of curve samples inserted as vertices (after skipping near-duplicates and
    /// samples outside the domain).
    pub n_curve_samples: usize,
    /// Whether refinement met the angle and area goals before the vertex cap.
    pub refinement_complete: bool,
    /// The parts of the art left out of an art-shaped domain for holding no handle, each
    /// attached to a vertex of the mesh whose weights it takes ([`Boundary::Art`]; empty for
    /// the other boundaries).
    pub attachments: Vec<Attachment>,
}

/// A part of the art outside the mesh that takes the weights of one mesh vertex everywhere
/// ([`Domain::attachments`], [`MeshWeights::with_attachments`]): it moves as one piece, by the
/// blend of the handles' maps at that vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct Attachment {
    /// The part's region: closed polygons (its outline counter-clockwise, holes clockwise).
    pub loops: Vec<Vec<Point>>,
    /// The mesh vertex nearest to the part (a boundary vertex).
    pub vertex: usize,
}

impl Domain {
    /// Triangulates the domain of `drawing` with point handles at `points` and bones (segments)
    /// `bones` — see the module documentation for what the domain is and which vertices it has.
    ///
    /// Errors (none panics): non-finite or coincident handles, a degenerate bone or two bones
    /// crossing (sharing an end point is fine), a handle on a bone, a handle or bone outside
    /// the domain, a bad cage (fewer than 3 vertices, non-finite, a zero-length edge,
    /// self-intersecting, clockwise), an empty domain (no curves and no cage, or zero area),
    /// options out of range.
    pub fn build(
        drawing: &Drawing,
        points: &[Point],
        bones: &[[Point; 2]],
        options: &DomainOptions,
    ) -> Result<Domain, DomainError> {
        triangulate::build(drawing, points, bones, options, None)
    }

    /// [`Domain::build`] within the closed polygons `loops` (outer ones counter-clockwise,
    /// holes clockwise) instead of the boundary the options choose, reported as `boundary`:
    /// the coarse levels of an art-shaped domain share its outline, simplified
    /// ([`Domain::simplified_outline`]), so that a coarse solve is a good start for the fine
    /// one. Errors as [`Domain::build`], and crossing polygons
    /// ([`DomainError::Bug`]).
    pub(crate) fn build_within(
        drawing: &Drawing,
        points: &[Point],
        bones: &[[Point; 2]],
        options: &DomainOptions,
        loops: &[Vec<Point>],
        boundary: Boundary,
    ) -> Result<Domain, DomainError> {
        let given = triangulate::Given { loops, boundary };
        triangulate::build(drawing, points, bones, options, Some(given))
    }

    /// The boundary loops as polygons, each simplified to within `tolerance`
    /// (Douglas–Peucker; a loop that would keep fewer than 3 vertices is kept whole).
    pub(crate) fn simplified_outline(&self, tolerance: f64) -> Vec<Vec<Point>> {
        self.boundary_loops
            .iter()
            .map(|l| {
                let poly: Vec<Point> = l.iter().map(|&v| self.mesh.vertices[v]).collect();
                polygon::simplify_closed(&poly, tolerance)
            })
            .collect()
    }

    /// Number of holes: boundary loops turning clockwise ([`Domain::boundary_loops`]).
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::domain::{Domain, DomainOptions};
    /// use splineskin_core::drawing::Drawing;
    /// let cage = [(0., 0.), (10., 0.), (10., 10.), (0., 10.)].map(Point::from).to_vec();
    /// let options = DomainOptions::default().with_cage(cage).with_max_area_fraction(0.05);
    /// let domain = Domain::build(&Drawing::default(), &[Point::new(5.0, 5.0)], &[], &options)?;
    /// assert_eq!(domain.n_holes(), 0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn n_holes(&self) -> usize {
        self.boundary_loops
            .iter()
            .filter(|l| {
                let p: Vec<Point> = l.iter().map(|&i| self.mesh.vertices[i]).collect();
                polygon::signed_area(&p) < 0.0
            })
            .count()
    }

    /// Smallest angle over all triangles, in degrees.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_core::domain::Domain;
    /// use splineskin_core::mesh::TriMesh;
    /// let v = [(0., 0.), (1., 0.), (0., 1.)].map(Point::from).to_vec();
    /// let mesh = TriMesh::new(v, vec![[0, 1, 2]])?;
    /// assert!((Domain::min_angle_of(&mesh) - 45.0).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn min_angle_of(mesh: &TriMesh) -> f64 {
        (0..mesh.n_triangles())
            .map(|t| triangle_min_angle(mesh, t))
            .fold(f64::INFINITY, f64::min)
    }
}

/// Smallest interior angle of triangle `t`, in degrees.
pub(crate) fn triangle_min_angle(mesh: &TriMesh, t: usize) -> f64 {
    let [a, b, c] = mesh.triangles[t].map(|i| mesh.vertices[i]);
    let angle = |p: Point, q: Point, r: Point| {
        let (u, v) = (q - p, r - p);
        u.cross(v).abs().atan2(u.dot(v)).to_degrees()
    };
    angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b))
}

/// Why a domain cannot be built or mesh weights cannot be evaluated.
#[derive(Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum DomainError {
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// No handles.
    #[error("no handles: weights need at least one")]
    NoHandles,
    /// More vertices or triangles than 32-bit indices hold.
    #[error("mesh too large: {n_vertices} vertices, {n_triangles} triangles (at most 2^32 - 1)")]
    TooLarge {
        /// Vertices.
        n_vertices: usize,
        /// Triangles.
        n_triangles: usize,
    },
    /// The weight matrix has the wrong length.
    #[error("weights: expected {n_vertices} vertices × {n_handles} handles, got {len} values")]
    WeightsLength {
        /// Vertices of the mesh.
        n_vertices: usize,
        /// Handles.
        n_handles: usize,
        /// Values given.
        len: usize,
    },
    /// A weight is NaN or infinite.
    #[error("weight of handle {handle} at vertex {vertex} is not finite")]
    NonFiniteWeight {
        /// The vertex.
        vertex: usize,
        /// The handle.
        handle: usize,
    },
    /// An edge belongs to more than two triangles.
    #[error("edge {a}–{b} belongs to {n_triangles} triangles (at most 2 in a planar mesh)")]
    NonManifoldEdge {
        /// One end.
        a: usize,
        /// The other end.
        b: usize,
        /// Triangles sharing it.
        n_triangles: usize,
    },
    /// A handle position is NaN or infinite.
    #[error("handle {handle}: position is not finite")]
    NonFiniteHandle {
        /// The point handle.
        handle: usize,
    },
    /// A bone end is NaN or infinite.
    #[error("bone {bone}: end point is not finite")]
    NonFiniteBone {
        /// The bone.
        bone: usize,
    },
    /// A control point of the drawing is NaN or infinite.
    #[error("path {path}: a control point is not finite")]
    NonFiniteDrawing {
        /// The path.
        path: usize,
    },
    /// Two point handles at the same place.
    #[error("handles {first} and {second} coincide (distance {distance:e}): their weights would be both 1 at one point")]
    CoincidentHandles {
        /// The first handle.
        first: usize,
        /// The second handle.
        second: usize,
        /// Their distance.
        distance: f64,
    },
    /// A bone of zero length.
    #[error("bone {bone} has zero length: use a point handle")]
    DegenerateBone {
        /// The bone.
        bone: usize,
    },
    /// Two bones cross or overlap (other than at a shared end point).
    #[error("bones {first} and {second} intersect other than at a shared end point")]
    BonesCross {
        /// The first bone.
        first: usize,
        /// The second bone.
        second: usize,
    },
    /// A point handle lies on a bone.
    #[error("handle {handle} lies on bone {bone}")]
    HandleOnBone {
        /// The point handle.
        handle: usize,
        /// The bone.
        bone: usize,
    },
    /// A point handle is outside the domain (the cage, or inside a hole).
    #[error("handle {handle} at ({x}, {y}) is outside the domain (the cage)")]
    HandleOutsideDomain {
        /// The point handle.
        handle: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// A bone leaves the domain.
    #[error("bone {bone} is not inside the domain (the cage)")]
    BoneOutsideDomain {
        /// The bone.
        bone: usize,
    },
    /// A cage with fewer than three vertices.
    #[error("cage has {n_vertices} distinct vertices; a polygon needs at least 3")]
    CageTooFewVertices {
        /// Vertices given (after dropping a repeated closing vertex).
        n_vertices: usize,
    },
    /// A cage vertex is NaN or infinite.
    #[error("cage vertex {vertex} is not finite")]
    CageNonFinite {
        /// The vertex.
        vertex: usize,
    },
    /// Two consecutive cage vertices coincide.
    #[error("cage edge {edge} (vertex {edge} to the next) has zero length")]
    CageDegenerateEdge {
        /// The edge (from vertex `edge` to `edge + 1`, cyclically).
        edge: usize,
    },
    /// The cage crosses or touches itself.
    #[error("cage is not simple: edges {first} and {second} intersect")]
    CageSelfIntersecting {
        /// One edge (from vertex `first` to the next).
        first: usize,
        /// The other.
        second: usize,
    },
    /// The cage is clockwise.
    #[error("cage is clockwise (signed area {signed_area:e}); give its vertices counter-clockwise (reverse the list)")]
    CageClockwise {
        /// Its signed area (negative).
        signed_area: f64,
    },
    /// Nothing to triangulate.
    #[error("empty domain: {reason}")]
    EmptyDomain {
        /// Why.
        reason: &'static str,
    },
    /// An option out of its range.
    #[error("option {name} = {value} is out of range ({expected})")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The accepted range.
        expected: &'static str,
    },
    /// The triangulator refused the input (coordinates too large or too small for its exact
    /// predicates).
    #[error("triangulation failed: {reason}")]
    Triangulation {
        /// The triangulator's message.
        reason: String,
    },
    /// An internal invariant failed.
    #[error("bug: {0}")]
    Bug(&'static str),
}
