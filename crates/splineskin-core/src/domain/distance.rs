//! Exact Euclidean distance transform on a grid of cells: for every cell, the distance from its
//! centre to the nearest centre of a marked cell. Used to grow the art's painted region by the
//! domain's margin ([`super::DomainShape::Art`]) and, by the automatic pins, to measure how deep a
//! cell lies inside a shape.
//!
//! The squared distance `D(q) = min_p ‖q − p‖²` over marked cells `p` separates into rows and
//! columns: a 1-D pass along every row, then along every column of its result, each the lower
//! envelope of the parabolas `(q − p)² + f(p)` (Felzenszwalb & Huttenlocher, *Distance
//! Transforms of Sampled Functions*, Theory of Computing 8, 2012). Linear in the number of
//! cells.

/// Per cell of an `n_cols × n_rows` grid (row-major), the Euclidean distance, in cells, from
/// its centre to the nearest centre of a cell with `marked` set; `f64::INFINITY` everywhere
/// when nothing is marked.
///
/// ```
/// use splineskin_core::domain::distance::distance_to_marked;
/// // A 5 × 3 grid with its middle cell marked.
/// let mut marked = vec![false; 15];
/// marked[7] = true;
/// let d = distance_to_marked(&marked, 5, 3);
/// assert_eq!(d[7], 0.0);
/// assert_eq!(d[9], 2.0); // two cells to the right
/// assert_eq!(d[0], 5f64.sqrt()); // two left, one up
/// ```
pub fn distance_to_marked(marked: &[bool], n_cols: usize, n_rows: usize) -> Vec<f64> {
    assert_eq!(marked.len(), n_cols * n_rows, "mask size");
    if !marked.iter().any(|&m| m) {
        return vec![f64::INFINITY; marked.len()];
    }
    // Larger than any squared distance within the grid.
    let far = ((n_cols * n_cols + n_rows * n_rows) as f64 + 1.0) * 4.0;
    let mut f: Vec<f64> = marked.iter().map(|&m| if m { 0.0 } else { far }).collect();
    let mut scratch = Envelope::default();
    let mut line = Vec::with_capacity(n_cols.max(n_rows));
    for row in f.chunks_mut(n_cols) {
        line.clear();
        line.extend_from_slice(row);
        scratch.squared_1d(&line, row);
    }
    let mut column = vec![0.0; n_rows];
    for col in 0..n_cols {
        line.clear();
        line.extend((0..n_rows).map(|row| f[row * n_cols + col]));
        scratch.squared_1d(&line, &mut column);
        for (row, &d) in column.iter().enumerate() {
            f[row * n_cols + col] = d;
        }
    }
    f.iter_mut().for_each(|d| *d = d.sqrt());
    f
}

/// The lower envelope's breakpoints, kept between lines.
#[derive(Default)]
struct Envelope {
    v: Vec<usize>,
    z: Vec<f64>,
}

impl Envelope {
    /// `out[q] = min_p (q − p)² + f[p]`.
    fn squared_1d(&mut self, f: &[f64], out: &mut [f64]) {
        let n = f.len();
        self.v.clear();
        self.v.resize(n, 0);
        self.z.clear();
        self.z.resize(n + 1, 0.0);
        let (v, z) = (&mut self.v, &mut self.z);
        let sq = |q: usize| (q * q) as f64;
        let mut k = 0;
        z[0] = f64::NEG_INFINITY;
        z[1] = f64::INFINITY;
        for q in 1..n {
            loop {
                let p = v[k];
                let s = ((f[q] + sq(q)) - (f[p] + sq(p))) / (2.0 * (q as f64 - p as f64));
                if s <= z[k] && k > 0 {
                    k -= 1;
                } else {
                    k += 1;
                    v[k] = q;
                    z[k] = s;
                    z[k + 1] = f64::INFINITY;
                    break;
                }
            }
        }
        let mut k = 0;
        for (q, o) in out.iter_mut().enumerate() {
            while z[k + 1] < q as f64 {
                k += 1;
            }
            let p = v[k];
            *o = (q as f64 - p as f64).powi(2) + f[p];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_matches_brute_force() {
        let (w, h) = (23, 17);
        let marked: Vec<bool> = (0..w * h).map(|k| (k * 7919) % 61 == 3).collect();
        let d = distance_to_marked(&marked, w, h);
        for q in 0..w * h {
            let (qr, qc) = ((q / w) as f64, (q % w) as f64);
            let brute = (0..w * h)
                .filter(|&p| marked[p])
                .map(|p| ((p / w) as f64 - qr).hypot((p % w) as f64 - qc))
                .fold(f64::INFINITY, f64::min);
            assert!((d[q] - brute).abs() < 1e-12, "{q}: {} vs {brute}", d[q]);
        }
    }

    #[test]
    fn distance_of_nothing_marked_is_infinite() {
        assert!(distance_to_marked(&[false; 6], 3, 2)
            .iter()
            .all(|d| d.is_infinite()));
    }
}
