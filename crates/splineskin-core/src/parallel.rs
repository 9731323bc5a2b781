//! Independent jobs run on rayon's threads or one after the other, with the same result.
//!
//! The fit, the rig and the operator crates solve one job per path (or per group of paths);
//! the jobs share nothing, so they may run in parallel. Either way the results come back in
//! the jobs' order and a failure is reported for the first failing job in that order, so the
//! message never depends on the threads' timing.

use rayon::prelude::*;

/// `f(k, &items[k])` for every `k`, in parallel when `parallel` is set: the results in the
/// items' order, or the error of the first item (in the items' order) that failed.
///
/// Run in parallel, every job runs to the end before the first error is picked; run in order,
/// the jobs after the first failure are skipped. The value returned is the same.
///
/// ```
/// use splineskin_core::parallel::try_map;
/// let halves = |_: usize, &x: &i32| if x % 2 == 0 { Ok(x / 2) } else { Err(x) };
/// assert_eq!(try_map(&[2, 4, 6], true, halves), Ok(vec![1, 2, 3]));
/// assert_eq!(try_map(&[2, 3, 5], true, halves), Err(3));
/// assert_eq!(try_map(&[2, 3, 5], false, halves), Err(3));
/// ```
pub fn try_map<T, U, E, F>(items: &[T], parallel: bool, f: F) -> Result<Vec<U>, E>
where
    T: Sync,
    U: Send,
    E: Send,
    F: Fn(usize, &T) -> Result<U, E> + Sync,
{
    // The jobs take shared references: hand them out as the items of `try_map_mut`.
    let mut refs: Vec<&T> = items.iter().collect();
    try_map_mut(&mut refs, parallel, |k, item| f(k, item))
}

/// [`try_map`] over items the jobs may change: `f(k, &mut items[k])` for every `k`, in
/// parallel when `parallel` is set; the results in the items' order, or the error of the first
/// item (in the items' order) that failed. For jobs that each write into their own part of one
/// output (say the disjoint slices of one buffer).
///
/// ```
/// use splineskin_core::parallel::try_map_mut;
/// let mut out = vec![0; 6];
/// let mut parts: Vec<&mut [i32]> = out.chunks_mut(2).collect();
/// let sums = try_map_mut(&mut parts, true, |k, part| {
///     part.fill(k as i32 + 1);
///     Ok::<_, ()>(part.len())
/// });
/// assert_eq!(sums, Ok(vec![2, 2, 2]));
/// assert_eq!(out, [1, 1, 2, 2, 3, 3]);
/// ```
pub fn try_map_mut<T, U, E, F>(items: &mut [T], parallel: bool, f: F) -> Result<Vec<U>, E>
where
    T: Send,
    U: Send,
    E: Send,
    F: Fn(usize, &mut T) -> Result<U, E> + Sync,
{
    if parallel {
        let results: Vec<Result<U, E>> = items
            .par_iter_mut()
            .enumerate()
            .map(|(k, item)| f(k, item))
            .collect();
        results.into_iter().collect()
    } else {
        items
            .iter_mut()
            .enumerate()
            .map(|(k, item)| f(k, item))
            .collect()
    }
}
