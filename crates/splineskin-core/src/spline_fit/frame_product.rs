//! The per-frame product of a rig, `x = O · vec(T)` ([`super::SplineRig::update`]), on one
//! thread or split between the calling thread and one helper thread.
//!
//! The product reads every entry of `O` once per frame (`2 · n_points × 6h` values), so on a
//! large drawing it is bound by memory bandwidth, which one core does not exhaust. A helper
//! thread started with the rig computes the second half of the points while the caller
//! computes the first; the two meet on a mutex and condition variable. Nothing is allocated
//! per frame: the helper keeps its own copy of the pose and its own output buffer (both sized
//! once), and the caller copies the helper's points into place (16 bytes per point against
//! the `96 h` bytes of operator each point reads). Every point is computed by the same
//! function in the same order on either thread, so the result does not depend on the split.
//!
//! Small operators (below [`PARALLEL_MIN_BYTES`]) stay on the calling thread: waking a
//! thread costs microseconds, more than such a product takes.

use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;

use kurbo::{Affine, Point};

/// Smallest operator split between two threads: 8 MiB of `f64` (about 17 000 chain points
/// with five handles). Below it the product takes well under a millisecond and fits in the
/// caches of this machine's class.
pub const PARALLEL_MIN_BYTES: usize = 8 << 20;

/// `O`, row-major `(2 · n_points) × (6 · n_handles)`, and how its product is computed.
pub(crate) struct FrameProduct {
    n_points: usize,
    n_handles: usize,
    operator: Arc<Vec<f64>>,
    /// What the product reads: `operator` itself, or its entries rounded to `f32`.
    entries: Entries,
    /// Whether a helper thread may take half of the product.
    parallel: bool,
    helper: Option<Box<Helper>>,
}

/// The entries the per-frame product reads. Kept in a `Vec` (behind the `Arc`) rather than an
/// `Arc<[T]>`: a large `Vec` starts on a page boundary, where the `Arc`'s header would shift
/// every row by 16 bytes; measured on the 10 000-curve tiling, the shifted rows streamed about
/// a third slower at best.
#[derive(Clone)]
enum Entries {
    F64(Arc<Vec<f64>>),
    /// Each entry rounded to the nearest `f32`: half the bytes to stream, products summed in
    /// `f64`.
    F32(Arc<Vec<f32>>),
}

impl Entries {
    fn bytes(&self) -> usize {
        match self {
            Entries::F64(e) => std::mem::size_of_val(e.as_slice()),
            Entries::F32(e) => std::mem::size_of_val(e.as_slice()),
        }
    }

    /// Points `first, first + 1, …` of the product into `out`.
    fn points<S: PointSink + ?Sized>(
        &self,
        n_cols: usize,
        pose: &[Affine],
        first: usize,
        out: &mut S,
    ) {
        match self {
            Entries::F64(e) => points_of(e, n_cols, pose, first, out),
            Entries::F32(e) => points_of(e, n_cols, pose, first, out),
        }
    }
}

impl FrameProduct {
    /// Wraps `operator` (row-major `(2 · n_points) × (6 · n_handles)`); with `parallel` and an
    /// operator of at least [`PARALLEL_MIN_BYTES`] on a machine with two or more cores, starts
    /// the helper thread.
    pub fn new(operator: Vec<f64>, n_points: usize, n_handles: usize, parallel: bool) -> Self {
        debug_assert_eq!(operator.len(), 2 * n_points * 6 * n_handles);
        let operator = Arc::new(operator);
        FrameProduct::with_entries(
            operator.clone(),
            Entries::F64(operator),
            n_points,
            n_handles,
            parallel,
        )
    }

    fn with_entries(
        operator: Arc<Vec<f64>>,
        entries: Entries,
        n_points: usize,
        n_handles: usize,
        parallel: bool,
    ) -> Self {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let large = entries.bytes() >= PARALLEL_MIN_BYTES;
        let helper = if parallel && large && cores >= 2 {
            Helper::start(entries.clone(), n_points, n_handles)
        } else {
            None
        };
        FrameProduct {
            n_points,
            n_handles,
            operator,
            entries,
            parallel,
            helper,
        }
    }

    /// The same operator with the product reading its entries rounded to `f32` (`single`) or
    /// in full (`!single`); split between two threads as [`FrameProduct::new`] decides.
    pub fn with_single_precision(&self, single: bool) -> Self {
        let entries = if single {
            Entries::F32(Arc::new(self.operator.iter().map(|&x| x as f32).collect()))
        } else {
            Entries::F64(self.operator.clone())
        };
        FrameProduct::with_entries(
            self.operator.clone(),
            entries,
            self.n_points,
            self.n_handles,
            self.parallel,
        )
    }

    /// Whether the product reads `f32` entries.
    pub fn is_single_precision(&self) -> bool {
        matches!(self.entries, Entries::F32(_))
    }

    /// Bytes the product reads per frame.
    pub fn bytes_per_frame(&self) -> usize {
        self.entries.bytes()
    }

    /// Number of chain points (rows / 2).
    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// Number of handles (columns / 6).
    pub fn n_handles(&self) -> usize {
        self.n_handles
    }

    /// The operator, row-major.
    pub fn operator(&self) -> &[f64] {
        &self.operator
    }

    /// Whether a helper thread computes half of each product.
    pub fn is_split(&self) -> bool {
        self.helper.is_some()
    }

    /// Writes `O · vec(pose)` into `out`: points, or their coordinates `x0, y0, x1, …`
    /// ([`PointSink`]). `pose.len() == n_handles` and `out` holds `n_points` points (checked
    /// by the caller). Allocates nothing.
    pub fn apply<S: PointSink + ?Sized>(&self, pose: &[Affine], out: &mut S) {
        let n_cols = 6 * self.n_handles;
        match &self.helper {
            None => self.entries.points(n_cols, pose, 0, out),
            Some(helper) => {
                // One product at a time per rig: the helper has one slot.
                let _turn = lock(&helper.turn);
                {
                    let mut slot = lock(&helper.shared.slot);
                    slot.pose.clear();
                    slot.pose.extend_from_slice(pose);
                    slot.state = State::Work;
                }
                helper.shared.wake.notify_one();
                let (mine, theirs) = out.split_at_points(helper.first);
                self.entries.points(n_cols, pose, 0, mine);
                let mut slot = lock(&helper.shared.slot);
                while slot.state != State::Done {
                    slot = helper
                        .shared
                        .done
                        .wait(slot)
                        .unwrap_or_else(|e| e.into_inner());
                }
                theirs.copy_points(&slot.points);
                slot.state = State::Idle;
            }
        }
    }
}

impl Clone for FrameProduct {
    /// The same operator (shared, not copied), with a helper thread of its own if this one has
    /// one.
    fn clone(&self) -> Self {
        FrameProduct {
            n_points: self.n_points,
            n_handles: self.n_handles,
            operator: self.operator.clone(),
            entries: self.entries.clone(),
            parallel: self.parallel,
            helper: self
                .helper
                .as_ref()
                .and_then(|_| Helper::start(self.entries.clone(), self.n_points, self.n_handles)),
        }
    }
}

impl std::fmt::Debug for FrameProduct {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FrameProduct")
            .field("n_points", &self.n_points)
            .field("n_handles", &self.n_handles)
            .field("operator_len", &self.operator.len())
            .field("split", &self.is_split())
            .field("single_precision", &self.is_single_precision())
            .finish()
    }
}

/// Where the product's points are written: a slice of [`Point`]s, or of their coordinates
/// `x0, y0, x1, y1, …` (two `f64` per point, the layout numpy arrays and WebAssembly memory
/// hold).
pub(crate) trait PointSink {
    /// Number of points held.
    fn n_points(&self) -> usize;
    /// Sets point `k` to `(x, y)`.
    fn put(&mut self, k: usize, x: f64, y: f64);
    /// The points before `k` and from `k` on.
    fn split_at_points(&mut self, k: usize) -> (&mut Self, &mut Self);
    /// Copies `points` (as many as held) in.
    fn copy_points(&mut self, points: &[Point]);
}

impl PointSink for [Point] {
    fn n_points(&self) -> usize {
        self.len()
    }
    #[inline]
    fn put(&mut self, k: usize, x: f64, y: f64) {
        self[k] = Point::new(x, y);
    }
    fn split_at_points(&mut self, k: usize) -> (&mut Self, &mut Self) {
        self.split_at_mut(k)
    }
    fn copy_points(&mut self, points: &[Point]) {
        self.copy_from_slice(points);
    }
}

impl PointSink for [f64] {
    fn n_points(&self) -> usize {
        self.len() / 2
    }
    #[inline]
    fn put(&mut self, k: usize, x: f64, y: f64) {
        self[2 * k] = x;
        self[2 * k + 1] = y;
    }
    fn split_at_points(&mut self, k: usize) -> (&mut Self, &mut Self) {
        self.split_at_mut(2 * k)
    }
    fn copy_points(&mut self, points: &[Point]) {
        for (xy, p) in self.chunks_exact_mut(2).zip(points) {
            xy[0] = p.x;
            xy[1] = p.y;
        }
    }
}

/// Points `first, first + 1, …` of `O · vec(pose)` into `out`: for point `k`, rows `2k` and
/// `2k + 1` of `O` against the six coefficients `(a, b, c, d, e, f)` of each handle's map.
fn points_of<T: Copy + Into<f64>, S: PointSink + ?Sized>(
    operator: &[T],
    n_cols: usize,
    pose: &[Affine],
    first: usize,
    out: &mut S,
) {
    let n = out.n_points();
    let rows = &operator[2 * first * n_cols..][..2 * n * n_cols];
    for (k, rows) in rows.chunks_exact(2 * n_cols).enumerate() {
        let (rx, ry) = rows.split_at(n_cols);
        let (mut x, mut y) = (0.0, 0.0);
        for ((t, ox), oy) in pose.iter().zip(rx.chunks_exact(6)).zip(ry.chunks_exact(6)) {
            let c = t.as_coeffs();
            x += dot6(ox, &c);
            y += dot6(oy, &c);
        }
        out.put(k, x, y);
    }
}

/// `Σ_k a_k c_k` over the six coefficients of a handle's affine map (`a`: six operator
/// entries), summed left to right.
#[inline]
fn dot6<T: Copy + Into<f64>>(a: &[T], c: &[f64; 6]) -> f64 {
    let a = &a[..6];
    a[0].into() * c[0]
        + a[1].into() * c[1]
        + a[2].into() * c[2]
        + a[3].into() * c[3]
        + a[4].into() * c[4]
        + a[5].into() * c[5]
}

/// Locks `m`, also after a panic elsewhere (the data are plain numbers, rewritten each frame).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Where the helper is in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    Idle,
    Work,
    Done,
    Exit,
}

/// What the caller and the helper share: the pose in, the helper's points out.
struct Slot {
    state: State,
    pose: Vec<Affine>,
    points: Vec<Point>,
}

struct Shared {
    slot: Mutex<Slot>,
    /// Signalled when there is work (or the rig is dropped).
    wake: Condvar,
    /// Signalled when the helper's points are ready.
    done: Condvar,
}

/// The helper thread, computing points `first..n_points` of each product.
struct Helper {
    first: usize,
    shared: Arc<Shared>,
    /// Held by a caller for a whole product.
    turn: Mutex<()>,
    thread: Option<JoinHandle<()>>,
}

impl Helper {
    /// Starts the thread; `None` if the system refuses one (the product then stays on the
    /// calling thread).
    fn start(entries: Entries, n_points: usize, n_handles: usize) -> Option<Box<Helper>> {
        let first = n_points / 2;
        let shared = Arc::new(Shared {
            slot: Mutex::new(Slot {
                state: State::Idle,
                pose: Vec::with_capacity(n_handles),
                points: vec![Point::ZERO; n_points - first],
            }),
            wake: Condvar::new(),
            done: Condvar::new(),
        });
        let theirs = shared.clone();
        let thread = std::thread::Builder::new()
            .name("splineskin-frame".into())
            .spawn(move || {
                let n_cols = 6 * n_handles;
                let mut slot = lock(&theirs.slot);
                loop {
                    match slot.state {
                        State::Exit => return,
                        State::Work => {
                            let Slot { pose, points, .. } = &mut *slot;
                            entries.points(n_cols, pose, first, points.as_mut_slice());
                            slot.state = State::Done;
                            theirs.done.notify_one();
                        }
                        State::Idle | State::Done => {}
                    }
                    slot = theirs.wake.wait(slot).unwrap_or_else(|e| e.into_inner());
                }
            })
            .ok()?;
        Some(Box::new(Helper {
            first,
            shared,
            turn: Mutex::new(()),
            thread: Some(thread),
        }))
    }
}

impl Drop for Helper {
    fn drop(&mut self) {
        lock(&self.shared.slot).state = State::Exit;
        self.shared.wake.notify_one();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An operator of `n_points` points and `h` handles with distinct, irregular entries.
    fn operator(n_points: usize, h: usize) -> Vec<f64> {
        (0..2 * n_points * 6 * h)
            .map(|i| ((i as f64) * 0.618_033_988_7).fract() - 0.5)
            .collect()
    }

    fn pose(h: usize, k: usize) -> Vec<Affine> {
        (0..h)
            .map(|i| {
                let a = 0.1 * (i + k) as f64;
                Affine::new([a.cos(), a.sin(), -a.sin(), a.cos(), i as f64, -(k as f64)])
            })
            .collect()
    }

    #[test]
    fn the_split_product_equals_the_serial_one_bit_for_bit() {
        // 9 MiB of operator: above the threshold.
        let (n, h) = (50_000, 2);
        let op = operator(n, h);
        assert!(op.len() * 8 >= PARALLEL_MIN_BYTES);
        let serial = FrameProduct::new(op.clone(), n, h, false);
        let split = FrameProduct::new(op, n, h, true);
        assert!(!serial.is_split());
        let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
        assert_eq!(split.is_split(), cores >= 2);
        let copy = split.clone();
        assert_eq!(copy.is_split(), split.is_split());
        let (mut a, mut b, mut c) = (
            vec![Point::ZERO; n],
            vec![Point::ZERO; n],
            vec![Point::ZERO; n],
        );
        for k in 0..5 {
            let t = pose(h, k);
            serial.apply(&t, a.as_mut_slice());
            split.apply(&t, b.as_mut_slice());
            copy.apply(&t, c.as_mut_slice());
            assert_eq!(a, b, "frame {k}");
            assert_eq!(a, c, "frame {k}");
            // Written as coordinates (the helper's half copied in as x, y): the same numbers.
            let mut xy = vec![f64::NAN; 2 * n];
            split.apply(&t, xy.as_mut_slice());
            assert!(a
                .iter()
                .zip(xy.chunks_exact(2))
                .all(|(p, q)| p.x == q[0] && p.y == q[1]));
        }
        // Point 0 restated: rows 0 and 1 against the coefficients.
        let t = pose(h, 4);
        let op = serial.operator();
        let expected: f64 = (0..6 * h)
            .map(|c| op[c] * t[c / 6].as_coeffs()[c % 6])
            .sum();
        assert!((a[0].x - expected).abs() <= 1e-12 * (1.0 + expected.abs()));
    }

    #[test]
    fn single_precision_rounds_each_entry_once() {
        let (n, h) = (50_000, 2);
        let op = operator(n, h);
        let full = FrameProduct::new(op.clone(), n, h, true);
        let single = full.with_single_precision(true);
        assert!(single.is_single_precision());
        assert_eq!(single.bytes_per_frame(), full.bytes_per_frame() / 2);
        // The f32 product equals the f64 product of the rounded entries, bit for bit.
        let rounded: Vec<f64> = op.iter().map(|&x| f64::from(x as f32)).collect();
        let reference = FrameProduct::new(rounded, n, h, false);
        let (mut a, mut b) = (vec![Point::ZERO; n], vec![Point::ZERO; n]);
        let t = pose(h, 2);
        single.apply(&t, a.as_mut_slice());
        reference.apply(&t, b.as_mut_slice());
        assert_eq!(a, b);
        let back = single.with_single_precision(false);
        assert!(!back.is_single_precision());
        assert_eq!(back.bytes_per_frame(), full.bytes_per_frame());
    }

    #[test]
    fn small_operators_stay_on_the_calling_thread() {
        let product = FrameProduct::new(operator(10, 3), 10, 3, true);
        assert!(!product.is_split());
        let mut out = vec![Point::ZERO; 10];
        product.apply(&pose(3, 0), out.as_mut_slice());
        assert!(out.iter().all(|p| p.x.is_finite() && p.y.is_finite()));
    }
}
