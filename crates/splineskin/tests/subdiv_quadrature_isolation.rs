//! [`LimitQuadrature::for_cage`] refines only as deep as the Gauss nodes need: on every
//! OpenSubdiv regression shape the reader accepts, every node's stencil is exact, the node
//! positions equal those of the quadrature on the default-isolation surface, and so does `Â`;
//! the isolation chosen is printed (`--nocapture`).

mod common;

use splineskin::subdiv::{
    read_obj, LimitOptions, LimitQuadrature, LimitSurface, DEFAULT_GAUSS_POINTS,
    DEFAULT_ISOLATION_LEVEL,
};

/// Both sides are exact limit evaluations, summed in a different order: rounding, relative to
/// the bounding-box diagonal (positions) or to the largest entry (`Â`).
const TOLERANCE: f64 = 1e-12;

#[test]
fn subdiv_quadrature_isolation_matches_the_default() {
    let Some(shapes) = common::subdiv_shapes() else {
        return;
    };
    let mut checked = 0;
    let mut shallower = 0;
    for path in &shapes {
        // The reader refuses faces with a repeated vertex (subdiv_reference.rs lists them).
        let Ok(cage) = read_obj(path) else { continue };
        let name = path.file_stem().unwrap().to_string_lossy();
        let (surface, q) = LimitQuadrature::for_cage(&cage, DEFAULT_GAUSS_POINTS).unwrap();
        assert!(
            (0..q.n_nodes()).all(|k| q.stencil(k).exact),
            "{name}: a node is not exact"
        );
        let full = LimitSurface::new(&cage, &LimitOptions::default()).unwrap();
        let reference = LimitQuadrature::new(&full, DEFAULT_GAUSS_POINTS).unwrap();
        assert_eq!(q.n_nodes(), reference.n_nodes());
        let diag = cage.bounding_box_diagonal();
        let (mut a, mut b) = (vec![[0.0; 3]; q.n_nodes()], vec![[0.0; 3]; q.n_nodes()]);
        q.positions(cage.positions(), &mut a);
        reference.positions(cage.positions(), &mut b);
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            let d = (0..3).map(|c| (x[c] - y[c]).powi(2)).sum::<f64>().sqrt();
            assert!(d <= TOLERANCE * diag, "{name}: node {k} differs by {d:.2e}");
        }
        let (ga, gb) = (q.gram().to_dense(), reference.gram().to_dense());
        let scale = gb.norm_max();
        let mut worst = 0.0f64;
        for j in 0..ga.ncols() {
            for i in 0..ga.nrows() {
                worst = worst.max((ga[(i, j)] - gb[(i, j)]).abs());
            }
        }
        assert!(
            worst <= TOLERANCE * scale,
            "{name}: Â differs by {worst:.2e}"
        );
        if surface.isolation_level() < DEFAULT_ISOLATION_LEVEL {
            shallower += 1;
        }
        println!("{name:<32} isolation {}", surface.isolation_level());
        checked += 1;
    }
    assert!(checked >= 80, "only {checked} shapes read");
    println!("{shallower} of {checked} shapes need less than the default isolation");
}
