//! A cage and its first uniform refinement taken as a cage of its own
//! ([`UniformLevel::to_cage`], decayed crease and corner sharpness carried as tags) have the
//! same limit surface: on every OpenSubdiv regression shape the reader accepts, the limit
//! position and derivatives at points of every ptex face equal those at the corresponding
//! points of the refined cage. This checks, independently of the reference files, that tags
//! are carried correctly and that limit evaluation agrees with itself across levels.

mod common;

use std::collections::HashMap;

use splineskin::subdiv::{
    read_obj, refine_uniform, Cage, LimitOptions, LimitSurface, SurfaceLocation,
};

/// Parameters sampled on every ptex face (away from 0.5, where a point lies on the border
/// between two children).
const PARAMS: [f64; 2] = [0.2, 0.7];

/// Shapes skipped for test time (3-4 s each in the dev profile: a valence-360 pole, and deep
/// isolation of 280 semi-sharp creases on four times the faces); `subdiv_reference.rs` checks
/// them against OpenSubdiv.
const SLOW: [&str; 2] = ["catmark_pole360", "catmark_rook"];

/// Largest accepted difference, as a fraction of the bounding-box diagonal: both sides are
/// exact limit evaluations in f64, through different refinement paths.
const TOLERANCE: f64 = 1e-11;

/// The location in the level-1 cage of ptex location `(face, subface, u, v)` of `cage`, and
/// the Jacobian of the map: `∂(u', v')/∂u = scale·a`, `∂(u', v')/∂v = scale·b`.
fn refined_location(
    cage: &Cage,
    level1: &splineskin::subdiv::UniformLevel,
    edge_point: &HashMap<[u32; 2], u32>,
    at: SurfaceLocation,
) -> (SurfaceLocation, f64, [f64; 2], [f64; 2]) {
    let fv = cage.face(at.face as usize);
    let n = fv.len();
    let nv = cage.n_vertices() as u32;
    let e = |a: u32, b: u32| edge_point[&[a.min(b), a.max(b)]];
    let centre = nv + at.face;
    // The child quad in ptex orientation, and the point's coordinates in it.
    let (frame, s, t, scale) = if n == 4 {
        let (right, top) = (at.u >= 0.5, at.v >= 0.5);
        let k = match (right, top) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        };
        let p = |i: usize| fv[(k + i) % 4];
        // Corner k's child quad, listed from the corner in the parent's orientation and then
        // rotated into quadrant order.
        let around = [p(0), e(p(0), p(1)), centre, e(p(3), p(0))];
        let frame: [u32; 4] = std::array::from_fn(|i| around[(i + 4 - k) % 4]);
        let s = if right { 2.0 * at.u - 1.0 } else { 2.0 * at.u };
        let t = if top { 2.0 * at.v - 1.0 } else { 2.0 * at.v };
        (frame, s, t, 2.0)
    } else {
        let j = at.subface as usize;
        let (vj, next, prev) = (fv[j], fv[(j + 1) % n], fv[(j + n - 1) % n]);
        ([vj, e(vj, next), centre, e(prev, vj)], at.u, at.v, 1.0)
    };
    let child = (0..level1.faces().len())
        .find(|&c| {
            level1.parent_faces()[c] == at.face
                && frame.iter().all(|v| level1.faces()[c].contains(v))
        })
        .expect("the child quad exists");
    let cv = level1.faces()[child];
    // Child ptex corners (0,0), (1,0), (1,1), (0,1) at its vertices 0..3; the map is affine.
    const C: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let corner = |v: u32| C[cv.iter().position(|&x| x == v).unwrap()];
    let (c0, c1, c3) = (corner(frame[0]), corner(frame[1]), corner(frame[3]));
    let a = [0, 1].map(|d| c1[d] - c0[d]);
    let b = [0, 1].map(|d| c3[d] - c0[d]);
    let uv = [0, 1].map(|d| c0[d] + s * a[d] + t * b[d]);
    (
        SurfaceLocation {
            face: child as u32,
            subface: 0,
            u: uv[0],
            v: uv[1],
        },
        scale,
        a,
        b,
    )
}

#[test]
fn subdiv_refined_cage_has_the_same_limit_surface() {
    let Some(paths) = common::subdiv_shapes() else {
        return;
    };
    let mut worst = (0.0f64, String::new());
    let mut n_shapes = 0;
    for path in &paths {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if SLOW.contains(&name.as_str()) {
            continue;
        }
        let Ok(cage) = read_obj(path) else {
            continue; // the degenerate-face shapes, see subdiv_reference.rs
        };
        let refined = refine_uniform(&cage, 1).unwrap();
        let level1 = &refined.levels()[0];
        let cage1 = level1.to_cage().unwrap();
        let first_edge_point = (level1.n_vertices() - level1.parent_edges().len()) as u32;
        let edge_point: HashMap<[u32; 2], u32> = level1
            .parent_edges()
            .iter()
            .enumerate()
            .map(|(e, &[a, b])| ([a.min(b), a.max(b)], first_edge_point + e as u32))
            .collect();
        let options = LimitOptions::default();
        let surface = LimitSurface::new(&cage, &options).unwrap();
        let surface1 = LimitSurface::new(&cage1, &options).unwrap();
        let diag = cage.bounding_box_diagonal();
        for face in 0..cage.n_faces() as u32 {
            if surface.is_hole(face) {
                continue;
            }
            for subface in 0..surface.n_subfaces(face) {
                for v in PARAMS {
                    for u in PARAMS {
                        let at = SurfaceLocation {
                            face,
                            subface,
                            u,
                            v,
                        };
                        let (at1, scale, a, b) = refined_location(&cage, level1, &edge_point, at);
                        assert!(!surface1.is_hole(at1.face), "{name}: {at:?}");
                        let (p, du, dv) = surface.evaluate(cage.positions(), at).unwrap();
                        let (q, du1, dv1) = surface1.evaluate(cage1.positions(), at1).unwrap();
                        // Chain rule through the affine map (u, v) -> (u', v').
                        let chain = |j: [f64; 2]| -> [f64; 3] {
                            std::array::from_fn(|k| scale * (j[0] * du1[k] + j[1] * dv1[k]))
                        };
                        let dist = |x: [f64; 3], y: [f64; 3]| {
                            (0..3).map(|k| (x[k] - y[k]).powi(2)).sum::<f64>().sqrt() / diag
                        };
                        let d = dist(p, q);
                        let dd = dist(du, chain(a)).max(dist(dv, chain(b)));
                        let e = d.max(dd);
                        assert!(
                            e <= TOLERANCE,
                            "{name}: {at:?} -> {at1:?}: {d:.2e}, {dd:.2e}"
                        );
                        if e >= worst.0 {
                            worst = (e, name.clone());
                        }
                    }
                }
            }
        }
        n_shapes += 1;
    }
    println!(
        "{n_shapes} shapes; worst difference {:.2e} of the diagonal ({})",
        worst.0, worst.1
    );
    assert_eq!(n_shapes, 83 - SLOW.len());
}
