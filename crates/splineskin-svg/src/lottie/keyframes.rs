//! Which frames of a path to keep as Lottie keyframes ([`keyframes`]).

use kurbo::Point;

/// The frames of one path to keep as keyframes so that a player's linear interpolation
/// between consecutive kept frames passes every dropped frame within `tolerance` (drawing
/// units; every control point). `frames[k]` holds the path's control points at time
/// `times[k]` (increasing), all of the same length. The first and last frames are always kept, or only the first when nothing
/// moves.
///
/// Greedy: from the last kept frame `a`, the next kept frame is the farthest `b` such that
/// every frame strictly between `a` and `b` is within the tolerance of its interpolation at
/// `(t_k − t_a)/(t_b − t_a)`. With `tolerance = 0` every frame that differs from the
/// interpolation at all is kept.
///
/// ```
/// use kurbo::Point;
/// use splineskin_svg::lottie::keyframes;
/// // One point moving right at constant speed, then back.
/// let xs = [0.0, 1.0, 2.0, 3.0, 2.0, 1.0];
/// let frames: Vec<Vec<Point>> = xs.iter().map(|&x| vec![Point::new(x, 0.0)]).collect();
/// let views: Vec<&[Point]> = frames.iter().map(|f| f.as_slice()).collect();
/// let times = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5];
/// assert_eq!(keyframes(&views, &times, 1e-9), vec![0, 3, 5]);
/// ```
pub fn keyframes(frames: &[&[Point]], times: &[f64], tolerance: f64) -> Vec<usize> {
    debug_assert_eq!(frames.len(), times.len());
    if frames.iter().all(|f| *f == frames[0]) {
        return if frames.is_empty() {
            Vec::new()
        } else {
            vec![0]
        };
    }
    keyframes_by(frames.len(), |a, b| spans(frames, times, a, b, tolerance))
}

/// The greedy choice of [`keyframes`] over `n` frames with another test: `spans(a, b)` says
/// whether the player's interpolation from kept frame `a` to kept frame `b` passes every frame
/// strictly between them. The first and last frames are kept.
pub(super) fn keyframes_by(n: usize, spans: impl Fn(usize, usize) -> bool) -> Vec<usize> {
    if n == 0 {
        return Vec::new();
    }
    let mut kept = vec![0];
    let mut a = 0;
    while a + 1 < n {
        // The farthest b whose span a..b interpolates every frame in between.
        let mut b = a + 1;
        while b + 1 < n && spans(a, b + 1) {
            b += 1;
        }
        kept.push(b);
        a = b;
    }
    kept
}

/// Whether every frame strictly between `a` and `b` is within `tolerance` of the linear
/// interpolation of frames `a` and `b`.
fn spans(frames: &[&[Point]], times: &[f64], a: usize, b: usize, tolerance: f64) -> bool {
    let (pa, pb) = (frames[a], frames[b]);
    let tol2 = tolerance * tolerance;
    (a + 1..b).all(|k| {
        let t = (times[k] - times[a]) / (times[b] - times[a]);
        frames[k]
            .iter()
            .zip(pa.iter().zip(pb))
            .all(|(&p, (&x, &y))| (p - x.lerp(y, t)).hypot2() <= tol2)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn views(frames: &[Vec<Point>]) -> Vec<&[Point]> {
        frames.iter().map(|f| f.as_slice()).collect()
    }

    #[test]
    fn keyframes_bound_the_interpolation_error() {
        // A point on a circle, 61 frames over a half turn: the chord error of a span of
        // angle θ is r(1 − cos(θ/2)) at its middle.
        let frames: Vec<Vec<Point>> = (0..=60)
            .map(|k| {
                let a = std::f64::consts::PI * k as f64 / 60.0;
                vec![Point::new(a.cos(), a.sin()), Point::new(2.0, 0.0)]
            })
            .collect();
        let v = views(&frames);
        let times: Vec<f64> = (0..=60).map(|k| k as f64 / 30.0).collect();
        for tol in [1e-2, 1e-3, 1e-4] {
            let kept = keyframes(&v, &times, tol);
            assert_eq!((kept[0], *kept.last().unwrap()), (0, 60));
            // Every frame within the tolerance of the interpolation of its kept neighbours.
            for w in kept.windows(2) {
                assert!(spans(&v, &times, w[0], w[1], tol), "{tol}: {w:?}");
            }
            // No more than spans of the longest length the chord error allows at mid-span
            // (the greedy may do better: an odd span's frames miss its middle).
            let step = 2.0 * (1.0 - tol).acos() / (std::f64::consts::PI / 60.0);
            let at_most = (60.0 / step.floor().max(1.0)).ceil() as usize + 1;
            assert!(kept.len() <= at_most, "{tol}: {} > {at_most}", kept.len());
            if tol == 1e-2 {
                assert!(kept.len() < 61, "some frames dropped");
            }
        }
        assert_eq!(keyframes(&v, &times, 0.0).len(), 61);
        // Uneven times: a frame late in its span is interpolated at its own time.
        let xs = [0.0, 1.0, 3.0];
        let uneven: Vec<Vec<Point>> = xs.iter().map(|&x| vec![Point::new(x, 0.0)]).collect();
        assert_eq!(
            keyframes(&views(&uneven), &[0.0, 1.0, 3.0], 1e-12),
            vec![0, 2]
        );
        assert_eq!(
            keyframes(&views(&uneven), &[0.0, 1.0, 2.0], 1e-12),
            vec![0, 1, 2]
        );
    }

    #[test]
    fn keyframes_of_a_still_path_and_of_two_frames() {
        let still = vec![vec![Point::new(1.0, 2.0)]; 5];
        assert_eq!(
            keyframes(&views(&still), &[0.0, 1.0, 2.0, 3.0, 4.0], 0.0),
            vec![0]
        );
        let two = vec![vec![Point::ZERO], vec![Point::new(1.0, 0.0)]];
        assert_eq!(keyframes(&views(&two), &[0.0, 1.0], 1.0), vec![0, 1]);
        assert!(keyframes(&[], &[], 1.0).is_empty());
    }
}
