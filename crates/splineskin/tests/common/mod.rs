//! Shared helpers of the integration tests: where the external data lives, and readers of it.
#![allow(dead_code)]

use std::path::PathBuf;

/// `../shared/data` relative to the repository root, if present. When it is missing the calling
/// test skips with a message that `.ci/run` counts, or fails when `CI` is set
/// ([`external_data::shared_data`]).
pub fn data_root() -> Option<PathBuf> {
    external_data::shared_data()
}

/// The OpenSubdiv shapes, `subdiv/shapes/*.obj` of the shared data, sorted by name; `None`,
/// and the calling test skips, when the data is missing (see [`data_root`]).
pub fn subdiv_shapes() -> Option<Vec<PathBuf>> {
    let root = data_root()?;
    let mut shapes: Vec<_> = std::fs::read_dir(root.join("subdiv/shapes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    shapes.sort();
    Some(shapes)
}

/// A small deterministic generator (SplitMix64), so that random test inputs are reproducible.
/// Test files add their own samplers (`impl Rng { fn pose(..) }`).
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

pub mod authors_outputs;
pub mod external_data;
pub mod measure;
pub mod reference_igl;
pub mod scene_compare;
pub mod test_dir;
