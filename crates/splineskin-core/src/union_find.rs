//! Union–find over `0..n` (a forest `parent`, with path halving), as used for mesh components
//! and for the unknowns that shared curves merge.
//!
//! Every union makes the smaller root the parent, so a root is the smallest member of its
//! set, and [`labels`] numbers the sets in the order of their smallest member.

/// A forest of `n` single-member sets.
pub(crate) fn singletons(n: usize) -> Vec<usize> {
    (0..n).collect()
}

/// The representative (smallest member) of `i`'s set, halving the path on the way.
pub(crate) fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Merges the sets of `i` and `j`.
pub(crate) fn union(parent: &mut [usize], i: usize, j: usize) {
    let (a, b) = (root(parent, i), root(parent, j));
    if a != b {
        parent[a.max(b)] = a.min(b);
    }
}

/// The set of each member, numbered from 0 in the order of the sets' smallest members, and
/// the number of sets.
pub(crate) fn labels(parent: &mut [usize]) -> (Vec<usize>, usize) {
    let mut label = vec![usize::MAX; parent.len()];
    let mut n_sets = 0;
    for i in 0..parent.len() {
        // The root is at most `i`, so it is labelled by the time `i` is reached.
        let r = root(parent, i);
        if label[r] == usize::MAX {
            label[r] = n_sets;
            n_sets += 1;
        }
        label[i] = label[r];
    }
    (label, n_sets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_number_sets_by_smallest_member() {
        let mut parent = singletons(6);
        union(&mut parent, 4, 1);
        union(&mut parent, 5, 3);
        union(&mut parent, 1, 5);
        assert_eq!(labels(&mut parent), (vec![0, 1, 2, 1, 1, 1], 3));
        assert_eq!(root(&mut parent, 5), 1);
    }
}
