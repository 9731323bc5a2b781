//! The per-frame product of a rig, `x = O · vec(T)` ([`super::SplineRig::update`]), on one
//! thread or split between the calling thread and helper threads.
//!
//! The product reads every entry of `O` once per frame (`2 · n_points × 6h` values), so on a
//! large drawing it is bound by memory bandwidth, which one core does not exhaust. Helper
//! threads started with the rig each compute a contiguous range of the points while the caller
//! computes the first range; each helper meets the caller on its own mutex and condition
//! variables. Nothing is allocated per frame: a helper keeps its own copy of the pose and its
//! own output buffer (both sized once), and the caller copies the helpers' points into place
//! (16 bytes per point against the `96 h` bytes of operator each point reads). Every point is
//! computed by the same function in the same order on any thread, so the result does not
//! depend on the split.
//!
//! **How many threads.** One per [`BYTES_PER_THREAD`] of operator, at most one per core
//! ([`update_threads`]): a thread pays for its wake-up (microseconds) only when its share of
//! the stream takes far longer, and the stream stops speeding up once the cores together read
//! as fast as memory delivers. Small operators (below [`PARALLEL_MIN_BYTES`]) stay on the
//! calling thread.

use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;

use kurbo::{Affine, Point};

/// Smallest operator split between two threads: 8 MiB of `f64` (about 17 000 chain points
/// with five handles). Below it the product takes well under a millisecond and fits in the
/// caches of this machine's class.
pub const PARALLEL_MIN_BYTES: usize = 2 * BYTES_PER_THREAD;

/// Operator bytes each thread of a split product streams at least: 4 MiB, about 0.3 ms at the
/// 10–15 GB/s one core reads, against the few microseconds a wake-up costs.
pub const BYTES_PER_THREAD: usize = 4 << 20;

/// Threads a product reading `bytes` per frame runs on, given `cores`: one per
/// [`BYTES_PER_THREAD`], at most `cores`, at least 1.
///
/// ```
/// # use splineskin_core::spline_fit::update_threads;
/// assert_eq!(update_threads(1 << 20, 16), 1);
/// assert_eq!(update_threads(8 << 20, 16), 2);
/// assert_eq!(update_threads(200 << 20, 16), 16);
/// assert_eq!(update_threads(200 << 20, 2), 2);
/// ```
pub fn update_threads(bytes: usize, cores: usize) -> usize {
    (bytes / BYTES_PER_THREAD).clamp(1, cores.max(1))
}

/// `O`, row-major `(2 · n_points) × (6 · n_handles)`, and how its product is computed.
pub(crate) struct FrameProduct {
    n_points: usize,
    n_handles: usize,
    operator: Arc<Vec<f64>>,
    /// What the product reads: `operator` itself, or its entries rounded to `f32`.
    entries: Entries,
    /// Whether helper threads may take part of the product.
    parallel: bool,
    helpers: Option<Box<Helpers>>,
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
    /// the helper threads ([`update_threads`] in all, the caller included).
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
        let helpers = if parallel {
            Helpers::start(&entries, n_points, n_handles)
        } else {
            None
        };
        FrameProduct {
            n_points,
            n_handles,
            operator,
            entries,
            parallel,
            helpers,
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

    /// Threads each product runs on: 1, or the caller and its helpers.
    pub fn threads(&self) -> usize {
        self.helpers.as_ref().map_or(1, |h| 1 + h.helpers.len())
    }

    /// Writes `O · vec(pose)` into `out`: points, or their coordinates `x0, y0, x1, …`
    /// ([`PointSink`]). `pose.len() == n_handles` and `out` holds `n_points` points (checked
    /// by the caller). Allocates nothing.
    pub fn apply<S: PointSink + ?Sized>(&self, pose: &[Affine], out: &mut S) {
        let n_cols = 6 * self.n_handles;
        match &self.helpers {
            None => self.entries.points(n_cols, pose, 0, out),
            Some(helpers) => {
                // One product at a time per rig: each helper has one slot.
                let _turn = lock(&helpers.turn);
                for helper in &helpers.helpers {
                    helper.post(pose);
                }
                let (mine, mut rest) = out.split_at_points(helpers.helpers[0].first);
                self.entries.points(n_cols, pose, 0, mine);
                for helper in &helpers.helpers {
                    let (theirs, next) = rest.split_at_points(helper.count);
                    helper.collect(theirs);
                    rest = next;
                }
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
            helpers: self
                .helpers
                .as_ref()
                .and_then(|_| Helpers::start(&self.entries, self.n_points, self.n_handles)),
        }
    }
}

impl std::fmt::Debug for FrameProduct {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FrameProduct")
            .field("n_points", &self.n_points)
            .field("n_handles", &self.n_handles)
            .field("operator_len", &self.operator.len())
            .field("threads", &self.threads())
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

/// The helper threads of a split product and the lock that gives one caller at a time the
/// whole set.
struct Helpers {
    helpers: Vec<Helper>,
    /// Held by a caller for a whole product.
    turn: Mutex<()>,
}

impl Helpers {
    /// Starts [`update_threads`]` − 1` helpers, each for a contiguous range of points after the
    /// caller's; `None` when the product stays on one thread (small operator, one core, or
    /// the system refuses a thread).
    fn start(entries: &Entries, n_points: usize, n_handles: usize) -> Option<Box<Helpers>> {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        if entries.bytes() < PARALLEL_MIN_BYTES {
            return None;
        }
        Helpers::start_with(
            entries,
            n_points,
            n_handles,
            update_threads(entries.bytes(), cores),
        )
    }

    /// [`Helpers::start`] with `threads` in all (caller included), whatever the operator's size.
    fn start_with(
        entries: &Entries,
        n_points: usize,
        n_handles: usize,
        threads: usize,
    ) -> Option<Box<Helpers>> {
        let threads = threads.min(n_points);
        if threads < 2 {
            return None;
        }
        // Thread t computes points [t·n/threads, (t+1)·n/threads).
        let start = |t: usize| t * n_points / threads;
        let helpers = (1..threads)
            .map(|t| {
                Helper::start(
                    entries.clone(),
                    start(t),
                    start(t + 1) - start(t),
                    n_handles,
                )
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Box::new(Helpers {
            helpers,
            turn: Mutex::new(()),
        }))
    }
}

/// A helper thread, computing points `first..first + count` of each product.
struct Helper {
    first: usize,
    count: usize,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl Helper {
    /// Starts the thread; `None` if the system refuses one.
    fn start(entries: Entries, first: usize, count: usize, n_handles: usize) -> Option<Helper> {
        let shared = Arc::new(Shared {
            slot: Mutex::new(Slot {
                state: State::Idle,
                pose: Vec::with_capacity(n_handles),
                points: vec![Point::ZERO; count],
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
        Some(Helper {
            first,
            count,
            shared,
            thread: Some(thread),
        })
    }

    /// Hands the helper `pose` and wakes it.
    fn post(&self, pose: &[Affine]) {
        {
            let mut slot = lock(&self.shared.slot);
            slot.pose.clear();
            slot.pose.extend_from_slice(pose);
            slot.state = State::Work;
        }
        self.shared.wake.notify_one();
    }

    /// Waits for the helper's points and copies them into `out` (`count` points).
    fn collect<S: PointSink + ?Sized>(&self, out: &mut S) {
        let mut slot = lock(&self.shared.slot);
        while slot.state != State::Done {
            slot = self
                .shared
                .done
                .wait(slot)
                .unwrap_or_else(|e| e.into_inner());
        }
        out.copy_points(&slot.points);
        slot.state = State::Idle;
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
        let op_bytes = op.len() * 8;
        assert!(op_bytes >= PARALLEL_MIN_BYTES);
        let serial = FrameProduct::new(op.clone(), n, h, false);
        let split = FrameProduct::new(op, n, h, true);
        assert_eq!(serial.threads(), 1);
        let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
        assert_eq!(split.threads(), update_threads(op_bytes, cores));
        assert_eq!(split.threads() >= 2, cores >= 2);
        let copy = split.clone();
        assert_eq!(copy.threads(), split.threads());
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
    fn a_product_split_in_five_equals_the_serial_one_bit_for_bit() {
        let (n, h) = (1003, 3);
        let op = operator(n, h);
        let serial = FrameProduct::new(op.clone(), n, h, false);
        let mut split = FrameProduct::new(op, n, h, false);
        split.helpers = Helpers::start_with(&split.entries, n, h, 5);
        assert_eq!(split.threads(), 5);
        let ranges: Vec<(usize, usize)> = split
            .helpers
            .as_ref()
            .unwrap()
            .helpers
            .iter()
            .map(|x| (x.first, x.count))
            .collect();
        assert_eq!(ranges, [(200, 201), (401, 200), (601, 201), (802, 201)]);
        for k in 0..3 {
            let t = pose(h, k);
            let (mut a, mut b) = (
                vec![Point::ZERO; n],
                vec![Point::new(f64::NAN, f64::NAN); n],
            );
            serial.apply(&t, a.as_mut_slice());
            split.apply(&t, b.as_mut_slice());
            assert_eq!(a, b, "frame {k}");
        }
    }

    #[test]
    fn small_operators_stay_on_the_calling_thread() {
        let product = FrameProduct::new(operator(10, 3), 10, 3, true);
        assert_eq!(product.threads(), 1);
        let mut out = vec![Point::ZERO; 10];
        product.apply(&pose(3, 0), out.as_mut_slice());
        assert!(out.iter().all(|p| p.x.is_finite() && p.y.is_finite()));
    }
}
