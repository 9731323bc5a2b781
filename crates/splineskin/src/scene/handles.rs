//! Handle kinds of a scene — point handles, bones and a cage — and how a posed bone or cage
//! vertex becomes the affine map the rig takes (DESIGN.md §2).
//!
//! The rig and the weights number the handles **points first, then bones, then cage
//! vertices**: with `n_p` points, `n_b` bones and `n_c` cage vertices, handle `i < n_p` is
//! point `i`, handle `n_p + b` is bone `b` and handle `n_p + n_b + k` is cage vertex `k`.
//! Every pose has one affine map per handle in that order.
//!
//! | kind | rest geometry | weight | posed as |
//! |---|---|---|---|
//! | point | a position `p` | `w = 1` at `p` | any affine map |
//! | bone | a segment `p₀ p₁` | `w = 1` along the segment (mesh families) | a rigid map or a similarity ([`BoneTransform`]) |
//! | cage vertex | vertex `v_k` of a counter-clockwise polygon | cage coordinates (mean value, harmonic) | a translation |

use kurbo::{Affine, Point, Vec2};

/// A handle as drawn on the panels: where its weight is 1 at rest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HandleMarker {
    /// A point handle (or a cage vertex): a ring.
    Point(Point),
    /// A bone: the segment between its end points.
    Segment([Point; 2]),
}

impl HandleMarker {
    /// The points that define it.
    pub fn points(&self) -> &[Point] {
        match self {
            HandleMarker::Point(p) => std::slice::from_ref(p),
            HandleMarker::Segment(ends) => ends,
        }
    }

    /// Whether all its coordinates are finite.
    pub fn is_finite(&self) -> bool {
        self.points()
            .iter()
            .all(|p| p.x.is_finite() && p.y.is_finite())
    }
}

/// How a posed bone is interpreted.
///
/// Given its posed end points `q₀, q₁` (rest `p₀, p₁`, directions `u = p₁ − p₀`,
/// `v = q₁ − q₀`), the bone's map is
///
/// ```text
/// rigid:   T(x) = q₀ + R (x − p₀),          R the rotation taking u/|u| to v/|v| (length ignored)
/// affine:  T(x) = q₀ + (|v|/|u|) R (x − p₀)   the similarity mapping p₀ ↦ q₀ and p₁ ↦ q₁
/// ```
///
/// In complex notation the affine map is `z ↦ q₀ + (v / u)(z − p₀)`; the rigid one divides
/// `v / u` by its modulus. A pose that gives a bone a matrix instead must, for a rigid bone,
/// give a rotation and translation (checked to [`RIGID_TOLERANCE`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BoneTransform {
    /// Rotation and translation only (the default).
    #[default]
    Rigid,
    /// Any affine map; posed by end points it is the similarity through both.
    Affine,
}

impl BoneTransform {
    /// The name used in scenes (`rigid`, `affine`).
    pub fn name(self) -> &'static str {
        match self {
            BoneTransform::Rigid => "rigid",
            BoneTransform::Affine => "affine",
        }
    }
}

/// Largest deviation of a rigid bone's linear part from a rotation: `1e-9` (dimensionless,
/// on the entries of `MᵀM − I` and on `a − d`, `b + c`). A rotation written with ten
/// significant digits passes; any visible scale or shear does not.
pub const RIGID_TOLERANCE: f64 = 1e-9;

/// A bone: a segment handle whose weight is 1 along its whole length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bone {
    /// Rest end points `p₀, p₁`.
    pub ends: [Point; 2],
    /// How its pose is interpreted.
    pub transform: BoneTransform,
}

/// Why a bone pose cannot be turned into a map.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum BonePoseError {
    /// The rest bone has zero length: its direction is undefined.
    #[error("the bone has zero length at rest")]
    ZeroRestLength,
    /// A rigid bone was posed with coincident end points: its direction is undefined.
    #[error("the posed end points coincide, so a rigid bone's direction is undefined")]
    ZeroPosedLength,
    /// A rigid bone was given a map that is not a rotation and translation.
    #[error("a rigid bone's map must be a rotation and translation; this one scales or shears ({deviation:e} from a rotation, tolerance {RIGID_TOLERANCE:e})")]
    NotRigid {
        /// Largest deviation found (see [`RIGID_TOLERANCE`]).
        deviation: f64,
    },
}

impl Bone {
    /// The map taking the rest bone to the posed end points `posed`, by [`BoneTransform`].
    ///
    /// ```
    /// use kurbo::{Affine, Point};
    /// use splineskin::scene::{Bone, BoneTransform};
    /// let bone = Bone { ends: [Point::new(0.0, 0.0), Point::new(2.0, 0.0)], transform: BoneTransform::Rigid };
    /// // Posed pointing up from (1, 1), twice as long.
    /// let posed = [Point::new(1.0, 1.0), Point::new(1.0, 5.0)];
    /// let rigid = bone.posed_by_ends(posed)?;
    /// assert!((rigid * Point::new(2.0, 0.0) - Point::new(1.0, 3.0)).hypot() < 1e-15); // length kept
    /// let affine = Bone { transform: BoneTransform::Affine, ..bone }.posed_by_ends(posed)?;
    /// assert!((affine * Point::new(2.0, 0.0) - Point::new(1.0, 5.0)).hypot() < 1e-15); // both ends hit
    /// # Ok::<(), splineskin::scene::BonePoseError>(())
    /// ```
    pub fn posed_by_ends(&self, posed: [Point; 2]) -> Result<Affine, BonePoseError> {
        let [p0, p1] = self.ends;
        let [q0, q1] = posed;
        let (u, v) = (p1 - p0, q1 - q0);
        let u2 = u.hypot2();
        if u2 <= 0.0 || !u2.is_finite() {
            return Err(BonePoseError::ZeroRestLength);
        }
        // v / u as a complex number: (v · ū) / |u|².
        let (mut re, mut im) = (u.dot(v) / u2, u.cross(v) / u2);
        if self.transform == BoneTransform::Rigid {
            let modulus = re.hypot(im);
            if modulus <= 0.0 || !modulus.is_finite() {
                return Err(BonePoseError::ZeroPosedLength);
            }
            re /= modulus;
            im /= modulus;
        }
        Ok(map_about(re, im, p0, q0))
    }

    /// Checks that `map` is allowed for this bone: any map for an affine bone, a rotation and
    /// translation (to [`RIGID_TOLERANCE`]) for a rigid one.
    pub fn check_map(&self, map: Affine) -> Result<Affine, BonePoseError> {
        if self.transform == BoneTransform::Affine {
            return Ok(map);
        }
        let [a, b, c, d, _, _] = map.as_coeffs();
        let deviation = [a - d, b + c, a * a + b * b - 1.0, c * c + d * d - 1.0]
            .into_iter()
            .map(f64::abs)
            .fold(0.0, f64::max);
        if deviation <= RIGID_TOLERANCE {
            Ok(map)
        } else {
            Err(BonePoseError::NotRigid { deviation })
        }
    }
}

/// `x ↦ q + (re + i·im)(x − p)`: SVG coefficients `(re, im, −im, re, e, f)`.
fn map_about(re: f64, im: f64, p: Point, q: Point) -> Affine {
    let linear = Affine::new([re, im, -im, re, 0.0, 0.0]);
    let moved = linear * p;
    Affine::new([re, im, -im, re, q.x - moved.x, q.y - moved.y])
}

/// A handle's map from parts, as scenes write them (`{"translate": t, "rotate": θ, "scale":
/// [sx, sy]}`, [`super::ours`]): scale by `(sx, sy)`, then rotate by `θ` degrees, both about
/// `pivot`, then translate by `t`:
///
/// ```text
/// x ↦ pivot + t + R(θ) S(sx, sy) (x − pivot)
/// ```
///
/// With SVG's y axis pointing down, a positive `θ` turns clockwise on screen.
///
/// ```
/// use kurbo::{Point, Vec2};
/// use splineskin::scene::handles::transform_about;
/// let pivot = Point::new(10.0, 20.0);
/// let t = transform_about(pivot, Vec2::new(1.0, 0.0), 90.0, (2.0, 2.0));
/// assert!((t * pivot - Point::new(11.0, 20.0)).hypot() < 1e-12);
/// // One unit right of the pivot: scaled to two, turned to below it, moved right by one.
/// assert!((t * Point::new(11.0, 20.0) - Point::new(11.0, 22.0)).hypot() < 1e-12);
/// ```
pub fn transform_about(
    pivot: Point,
    translate: Vec2,
    rotate_degrees: f64,
    scale: (f64, f64),
) -> Affine {
    let about = pivot.to_vec2();
    Affine::translate(about + translate)
        * Affine::rotate(rotate_degrees.to_radians())
        * Affine::scale_non_uniform(scale.0, scale.1)
        * Affine::translate(-about)
}

/// The translation moving a cage vertex (or point handle) at rest position `rest` to `posed`.
pub fn translation_to(rest: Point, posed: Point) -> Affine {
    Affine::translate(posed - rest)
}

/// The map of a cage vertex at `rest` whose pose is given as the affine map `map`: the vertex
/// moves to `map · rest`, and the handle's map is that translation (cage vertices only
/// translate). For every vertex of a linearly precise cage this makes one affine map `A` on
/// all vertices deform the drawing by exactly `A`.
pub fn cage_vertex_map(rest: Point, map: Affine) -> Affine {
    translation_to(rest, map * rest)
}

/// What a handle is, for reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HandleKind {
    /// Point handle `index`.
    Point(usize),
    /// Bone `index`.
    Bone(usize),
    /// Cage vertex `index`.
    CageVertex(usize),
}

/// The rest handles of a scene, borrowed, in rig order: points, then bones, then cage
/// vertices (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandleSet<'a> {
    /// Point handles.
    pub points: &'a [Point],
    /// Bones.
    pub bones: &'a [Bone],
    /// The cage polygon (counter-clockwise), if any.
    pub cage: Option<&'a [Point]>,
}

impl HandleSet<'_> {
    /// The markers pictures draw for these handles at rest, in rig order: point handles and
    /// cage vertices as rings, bones as segments.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin::scene::handles::HandleMarker;
    /// use splineskin::scene::HandleSet;
    /// let points = [Point::new(1.0, 2.0)];
    /// let set = HandleSet { points: &points, bones: &[], cage: None };
    /// assert_eq!(set.markers(), vec![HandleMarker::Point(Point::new(1.0, 2.0))]);
    /// ```
    pub fn markers(&self) -> Vec<HandleMarker> {
        let points = self.points.iter().map(|&p| HandleMarker::Point(p));
        let bones = self.bones.iter().map(|b| HandleMarker::Segment(b.ends));
        let cage = self
            .cage
            .unwrap_or(&[])
            .iter()
            .map(|&p| HandleMarker::Point(p));
        points.chain(bones).chain(cage).collect()
    }

    /// Number of cage vertices (0 without a cage).
    pub fn n_cage_vertices(&self) -> usize {
        self.cage.map_or(0, <[Point]>::len)
    }

    /// Number of handles: points + bones + cage vertices.
    pub fn n_handles(&self) -> usize {
        self.points.len() + self.bones.len() + self.n_cage_vertices()
    }

    /// What handle `i` (rig order) is, or `None` past the end.
    pub fn kind(&self, i: usize) -> Option<HandleKind> {
        let (n_p, n_b) = (self.points.len(), self.bones.len());
        if i < n_p {
            Some(HandleKind::Point(i))
        } else if i < n_p + n_b {
            Some(HandleKind::Bone(i - n_p))
        } else if i < self.n_handles() {
            Some(HandleKind::CageVertex(i - n_p - n_b))
        } else {
            None
        }
    }

    /// The rest point each handle turns about, in rig order: a point handle's position, a
    /// bone's first end, a cage vertex. Named transforms (`rotate`, `scale`) of a pose act
    /// about it.
    pub fn pivots(&self) -> Vec<Point> {
        let mut out: Vec<Point> = self.points.to_vec();
        out.extend(self.bones.iter().map(|b| b.ends[0]));
        out.extend(self.cage.unwrap_or(&[]).iter().copied());
        out
    }

    /// The bones as bare segments, for [`crate::domain::Domain::build`].
    pub fn bone_segments(&self) -> Vec<[Point; 2]> {
        self.bones.iter().map(|b| b.ends).collect()
    }

    /// The identity pose with a rotation about each handle's pivot by `angle(i)` radians
    /// turned into the map the handle's kind allows: used by benchmarks and tests to make
    /// varied valid poses. Cage vertices get the translation `angle(i) · (1, 1)` instead.
    pub fn wobble(&self, angle: impl Fn(usize) -> f64) -> Vec<Affine> {
        self.pivots()
            .iter()
            .enumerate()
            .map(|(i, &c)| match self.kind(i) {
                Some(HandleKind::CageVertex(_)) => Affine::translate(Vec2::new(angle(i), angle(i))),
                _ => {
                    let c = c.to_vec2();
                    Affine::translate(c) * Affine::rotate(angle(i)) * Affine::translate(-c)
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bone(kind: BoneTransform) -> Bone {
        Bone {
            ends: [Point::new(1.0, 2.0), Point::new(4.0, 6.0)],
            transform: kind,
        }
    }

    /// By hand: rest direction (3, 4) (length 5), posed (−8, 6) (length 10) from (0, 0): the
    /// rotation takes (3, 4)/5 to (−4, 3)/5, i.e. cos θ = (3·−4 + 4·3)/25 = 0, sin θ =
    /// (3·3 − 4·−4)/25 = 1: +90°, matrix [[0, −1], [1, 0]]; the similarity scales it by 2.
    #[test]
    fn bone_pose_from_ends_by_hand() {
        let posed = [Point::new(0.0, 0.0), Point::new(-8.0, 6.0)];
        let rigid = bone(BoneTransform::Rigid).posed_by_ends(posed).unwrap();
        // R (x − p₀) + q₀ with R = [[0, −1], [1, 0]]: e = −(0·1 − 1·2) = 2, f = −(1·1 + 0·2) = −1.
        let want = [0.0, 1.0, -1.0, 0.0, 2.0, -1.0];
        for (g, w) in rigid.as_coeffs().iter().zip(want) {
            assert!((g - w).abs() < 1e-15, "{:?}", rigid.as_coeffs());
        }
        let affine = bone(BoneTransform::Affine).posed_by_ends(posed).unwrap();
        let want = [0.0, 2.0, -2.0, 0.0, 4.0, -2.0];
        for (g, w) in affine.as_coeffs().iter().zip(want) {
            assert!((g - w).abs() < 1e-15, "{:?}", affine.as_coeffs());
        }
        // The rigid map keeps the length: p₁ goes to q₀ + 5 · (−4, 3)/5.
        assert!((rigid * Point::new(4.0, 6.0) - Point::new(-4.0, 3.0)).hypot() < 1e-14);
        assert!((affine * Point::new(4.0, 6.0) - Point::new(-8.0, 6.0)).hypot() < 1e-14);
    }

    #[test]
    fn bone_pose_errors() {
        let b = bone(BoneTransform::Rigid);
        let p = Point::new(3.0, 3.0);
        assert_eq!(b.posed_by_ends([p, p]), Err(BonePoseError::ZeroPosedLength));
        // An affine bone may collapse (the similarity of scale 0 is a map).
        let collapsed = bone(BoneTransform::Affine).posed_by_ends([p, p]).unwrap();
        assert_eq!(collapsed * Point::new(9.0, -1.0), p);
        let zero = Bone {
            ends: [p, p],
            transform: BoneTransform::Affine,
        };
        assert_eq!(
            zero.posed_by_ends([p, Point::ZERO]),
            Err(BonePoseError::ZeroRestLength)
        );
        assert!(b
            .check_map(Affine::rotate(0.3).then_translate((1.0, 2.0).into()))
            .is_ok());
        assert!(matches!(
            b.check_map(Affine::scale(1.01)),
            Err(BonePoseError::NotRigid { .. })
        ));
        assert!(matches!(
            b.check_map(Affine::skew(0.1, 0.0)),
            Err(BonePoseError::NotRigid { .. })
        ));
        // A reflection is not a rotation.
        assert!(b.check_map(Affine::FLIP_X).is_err());
        assert!(bone(BoneTransform::Affine)
            .check_map(Affine::scale(3.0))
            .is_ok());
    }

    #[test]
    fn handle_set_orders_points_bones_cage() {
        let points = [Point::new(0.0, 0.0)];
        let bones = [bone(BoneTransform::Rigid)];
        let cage = [
            Point::new(0.0, 0.0),
            Point::new(5.0, 0.0),
            Point::new(0.0, 5.0),
        ];
        let set = HandleSet {
            points: &points,
            bones: &bones,
            cage: Some(&cage),
        };
        assert_eq!(set.n_handles(), 5);
        assert_eq!(set.kind(0), Some(HandleKind::Point(0)));
        assert_eq!(set.kind(1), Some(HandleKind::Bone(0)));
        assert_eq!(set.kind(4), Some(HandleKind::CageVertex(2)));
        assert_eq!(set.kind(5), None);
        assert_eq!(set.pivots()[1], Point::new(1.0, 2.0));
        let m = Affine::rotate(0.5).then_translate((3.0, 1.0).into());
        let t = cage_vertex_map(cage[1], m);
        assert_eq!(t * cage[1], m * cage[1]);
        assert_eq!(t.as_coeffs()[..4], [1.0, 0.0, 0.0, 1.0]);
    }
}
