//! The machine's memory read bandwidth, measured the way STREAM measures it: a plain sum over
//! a buffer far larger than the caches, split over every core, so that `bench` can say how far
//! the per-frame update (one pass over the rig's operator) is from what memory can deliver.

use std::time::Instant;

/// Bytes summed per measurement: 256 MiB of `f64`, well beyond any last-level cache here.
pub const BUFFER_BYTES: usize = 256 << 20;

/// Timed passes; the median is reported.
pub const PASSES: usize = 7;

/// Median bytes per second of summing [`BUFFER_BYTES`] with `threads` threads (one contiguous
/// part each), and the sum itself (kept so the passes are not optimised away).
///
/// ```text
/// bandwidth = BUFFER_BYTES / median over passes of (time of Σ_i x_i)
/// ```
pub fn read_bandwidth(threads: usize) -> f64 {
    let n = BUFFER_BYTES / std::mem::size_of::<f64>();
    // Distinct values (not all zero pages) so that every page is really read.
    let buffer: Vec<f64> = (0..n).map(|i| (i % 1024) as f64).collect();
    let threads = threads.max(1);
    let part = n.div_ceil(threads);
    let mut times = Vec::with_capacity(PASSES);
    for _ in 0..PASSES {
        let start = Instant::now();
        let total: f64 = std::thread::scope(|s| {
            let handles: Vec<_> = buffer
                .chunks(part)
                .map(|chunk| s.spawn(move || sum(chunk)))
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("a summing thread"))
                .sum()
        });
        times.push(start.elapsed().as_secs_f64());
        std::hint::black_box(total);
    }
    times.sort_by(f64::total_cmp);
    BUFFER_BYTES as f64 / times[PASSES / 2]
}

/// `Σ x_i` with eight independent accumulators, so that the loop is bound by loads, not by
/// the latency of one chain of additions.
fn sum(x: &[f64]) -> f64 {
    let mut acc = [0.0; 8];
    let chunks = x.chunks_exact(8);
    let tail: f64 = chunks.remainder().iter().sum();
    for c in chunks {
        for (a, v) in acc.iter_mut().zip(c) {
            *a += v;
        }
    }
    acc.iter().sum::<f64>() + tail
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sum_adds_every_element_whatever_the_remainder() {
        for n in [0usize, 1, 7, 8, 9, 63, 100] {
            let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let expected = (n * n.saturating_sub(1) / 2) as f64;
            assert_eq!(sum(&x), expected, "n = {n}");
        }
    }
}
