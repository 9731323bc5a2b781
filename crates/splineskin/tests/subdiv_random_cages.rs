//! Random small cages — arbitrary polygons over a few vertices, so non-manifold edges,
//! bow-tie vertices, inconsistent orientation, boundaries and holes all occur — with random
//! crease, corner and hole tags: refinement and limit evaluation never panic, every interior
//! location falls on a regular (exact) patch at the default isolation level, ptex corners are
//! answered too, and every stencil is a partition of unity with derivative weights summing to
//! zero.

mod common;

use common::Rng;
use splineskin::subdiv::{
    refine_uniform, Cage, CornerTag, CreaseTag, LimitOptions, LimitSurface, Point3, SubdivError,
    SubdivTags, SurfaceLocation,
};

/// Number of random cages.
const N_CASES: usize = 400;

/// Interior parameters (away from ptex corners, where extraordinary points are unresolved).
const INTERIOR: [(f64, f64); 3] = [(0.1, 0.3), (0.5, 0.5), (0.9, 0.95)];

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        ((self.next_f64() * n as f64) as usize).min(n - 1)
    }

    fn cage(&mut self) -> Cage {
        let n_vertices = 4 + self.below(8);
        let n_faces = 1 + self.below(8);
        let positions: Vec<Point3> = (0..n_vertices)
            .map(|_| [self.next_f64(), self.next_f64(), self.next_f64()])
            .collect();
        let faces: Vec<Vec<u32>> = (0..n_faces)
            .map(|_| {
                let n = (3 + self.below(3)).min(n_vertices);
                let mut f: Vec<u32> = Vec::new();
                while f.len() < n {
                    let v = self.below(n_vertices) as u32;
                    if !f.contains(&v) {
                        f.push(v);
                    }
                }
                f
            })
            .collect();
        let mut tags = SubdivTags::default();
        if self.next_f64() < 0.5 {
            let f = &faces[self.below(n_faces)];
            let j = self.below(f.len());
            tags.creases.push(CreaseTag {
                vertices: [f[j], f[(j + 1) % f.len()]],
                sharpness: self.range(0.0, 12.0),
            });
        }
        if self.next_f64() < 0.3 {
            tags.corners.push(CornerTag {
                vertex: self.below(n_vertices) as u32,
                sharpness: self.range(0.0, 12.0),
            });
        }
        if self.next_f64() < 0.2 {
            tags.holes.push(self.below(n_faces) as u32);
        }
        Cage::new(positions, faces, tags).expect("distinct vertices and valid tags")
    }
}

#[test]
fn subdiv_random_cages_evaluate_everywhere() {
    let mut rng = Rng(0x5eed_cafe);
    let mut n_stencils = 0;
    for case in 0..N_CASES {
        let cage = rng.cage();
        let context = format!(
            "case {case}: faces {:?}, tags {:?}",
            cage.faces().collect::<Vec<_>>(),
            cage.tags()
        );
        let refined = refine_uniform(&cage, 2).unwrap_or_else(|e| panic!("{context}: {e}"));
        assert_eq!(
            refined.levels()[1].faces().len(),
            4 * refined.levels()[0].faces().len()
        );
        let surface = LimitSurface::new(&cage, &LimitOptions::default())
            .unwrap_or_else(|e| panic!("{context}: {e}"));
        for face in 0..cage.n_faces() as u32 {
            for subface in 0..surface.n_subfaces(face) {
                for (u, v) in INTERIOR {
                    let at = SurfaceLocation {
                        face,
                        subface,
                        u,
                        v,
                    };
                    match surface.stencil(at) {
                        Ok(st) => {
                            n_stencils += 1;
                            assert!(st.exact, "{context}: {at:?} not on a regular patch");
                            let sum: f64 = st.weights.iter().sum();
                            assert!((sum - 1.0).abs() < 1e-12, "{context}: {at:?}: Σw = {sum}");
                            let du: f64 = st.du_weights.iter().sum();
                            let dv: f64 = st.dv_weights.iter().sum();
                            assert!(du.abs() < 1e-9 && dv.abs() < 1e-9, "{context}: {at:?}");
                        }
                        Err(SubdivError::InHole { .. }) => assert!(surface.is_hole(face)),
                        Err(e) => panic!("{context}: {at:?}: {e}"),
                    }
                }
                // At a ptex corner the corner approximation answers.
                let corner = SurfaceLocation {
                    face,
                    subface,
                    u: 0.0,
                    v: 1.0,
                };
                match surface.stencil(corner) {
                    Ok(st) => assert!((st.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12),
                    Err(SubdivError::InHole { .. }) => assert!(surface.is_hole(face)),
                    Err(e) => panic!("{context}: {corner:?}: {e}"),
                }
            }
        }
        for v in 0..cage.n_vertices() as u32 {
            if let Ok(limit) = surface.vertex_limit(v) {
                let sum: f64 = limit.weights.iter().sum();
                assert!((sum - 1.0).abs() < 1e-12, "{context}: vertex {v}");
            }
        }
    }
    assert!(n_stencils > 2000, "{n_stencils} stencils evaluated");
}
