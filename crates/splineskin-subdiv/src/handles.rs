//! The handles of a subdivision rig: points and bones (segments) in 3D.
//!
//! Handle `i` numbers points first (in their order), then bones: the order of the rig's
//! transforms, of weight columns and of every pose.

use super::affine3::{distance2, dot, sub};
use super::cage::Point3;
use super::error::SurfaceWeightsError;

/// Point handles and bones, in that order (module documentation).
///
/// ```
/// use splineskin_subdiv::Handles3;
/// let h = Handles3::new(vec![[0.0, 0.0, 0.0]], vec![[[1.0, 0.0, 0.0], [1.0, 2.0, 0.0]]])?;
/// assert_eq!(h.n_handles(), 2);
/// let mut d2 = [0.0; 2];
/// h.squared_distances([1.0, 1.0, 1.0], &mut d2);
/// assert_eq!(d2, [3.0, 1.0]); // to the point, to the bone's middle
/// # Ok::<(), splineskin_subdiv::SurfaceWeightsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Handles3 {
    points: Vec<Point3>,
    bones: Vec<[Point3; 2]>,
}

impl Handles3 {
    /// Checks that there is at least one handle, every coordinate is finite and every bone
    /// has two distinct ends.
    pub fn new(points: Vec<Point3>, bones: Vec<[Point3; 2]>) -> Result<Self, SurfaceWeightsError> {
        if points.is_empty() && bones.is_empty() {
            return Err(SurfaceWeightsError::NoHandles);
        }
        let n_points = points.len();
        for (i, p) in points.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(SurfaceWeightsError::BadHandle {
                    handle: i,
                    what: format!("point {p:?} is not finite"),
                });
            }
        }
        for (b, ends) in bones.iter().enumerate() {
            let handle = n_points + b;
            if !ends.iter().flatten().all(|c| c.is_finite()) {
                return Err(SurfaceWeightsError::BadHandle {
                    handle,
                    what: format!("bone ends {ends:?} are not finite"),
                });
            }
            if distance2(ends[0], ends[1]) == 0.0 {
                return Err(SurfaceWeightsError::BadHandle {
                    handle,
                    what: format!("bone ends {ends:?} coincide; expected two distinct points"),
                });
            }
        }
        Ok(Handles3 { points, bones })
    }

    /// Number of handles: points and bones.
    pub fn n_handles(&self) -> usize {
        self.points.len() + self.bones.len()
    }

    /// The point handles.
    pub fn points(&self) -> &[Point3] {
        &self.points
    }

    /// The bones, as their two ends.
    pub fn bones(&self) -> &[[Point3; 2]] {
        &self.bones
    }

    /// The pivot of handle `i`: a point handle's position, a bone's first end. Poses rotate
    /// and scale about it.
    ///
    /// # Panics
    /// If `i >= n_handles()`.
    pub fn pivot(&self, i: usize) -> Point3 {
        match self.points.get(i) {
            Some(&p) => p,
            None => self.bones[i - self.points.len()][0],
        }
    }

    /// The closest point of handle `i` to `x`.
    ///
    /// # Panics
    /// If `i >= n_handles()`.
    pub fn closest_point(&self, i: usize, x: Point3) -> Point3 {
        match self.points.get(i) {
            Some(&p) => p,
            None => closest_on_segment(self.bones[i - self.points.len()], x),
        }
    }

    /// `‖x − c_i(x)‖²` for every handle `i` (`c_i` the closest point), into `out`
    /// (`n_handles` long).
    pub fn squared_distances(&self, x: Point3, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate().take(self.n_handles()) {
            *o = distance2(x, self.closest_point(i, x));
        }
    }
}

/// The point of segment `[a, b]` closest to `x`.
fn closest_on_segment([a, b]: [Point3; 2], x: Point3) -> Point3 {
    let ab = sub(b, a);
    let t = (dot(sub(x, a), ab) / dot(ab, ab)).clamp(0.0, 1.0);
    std::array::from_fn(|k| a[k] + t * ab[k])
}

/// `n` indices into `points` spread by farthest-point sampling: first the point farthest from
/// the points' centroid, then each time the point farthest from those chosen (ties to the
/// lowest index). Fewer than `n` if there are fewer distinct points.
///
/// ```
/// use splineskin_subdiv::farthest_point_sample;
/// let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [10.0, 0.0, 0.0], [4.0, 0.0, 0.0]];
/// assert_eq!(farthest_point_sample(&points, 3), vec![2, 0, 3]);
/// ```
pub fn farthest_point_sample(points: &[Point3], n: usize) -> Vec<usize> {
    if points.is_empty() || n == 0 {
        return Vec::new();
    }
    let m = points.len() as f64;
    let centroid: Point3 = std::array::from_fn(|k| points.iter().map(|p| p[k]).sum::<f64>() / m);
    let farthest = |d: &[f64]| {
        let mut best = 0;
        for (i, &x) in d.iter().enumerate() {
            if x > d[best] {
                best = i;
            }
        }
        best
    };
    let mut d: Vec<f64> = points.iter().map(|p| distance2(*p, centroid)).collect();
    let mut chosen = vec![farthest(&d)];
    d.iter_mut()
        .zip(points)
        .for_each(|(x, p)| *x = distance2(*p, points[chosen[0]]));
    while chosen.len() < n {
        let next = farthest(&d);
        if d[next] == 0.0 {
            break;
        }
        chosen.push(next);
        for (x, p) in d.iter_mut().zip(points) {
            *x = x.min(distance2(*p, points[next]));
        }
    }
    chosen
}
