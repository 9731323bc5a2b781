//! The mesh operators against libigl 2.6.3 on the reference-igl meshes (bar, U shape):
//! `cotmatrix` and the Voronoi and barycentric `massmatrix` diagonals.

mod common;

use common::reference_igl::ReferenceIgl;
use splineskin::mesh::operators::{cotangent_laplacian, lumped_mass, MassKind};

/// `cotmatrix` tolerance, relative to the largest entry: our cotangents come from dot and
/// cross products, libigl's from squared edge lengths and Heron's area, so entries differ by
/// rounding only (measured: 3.8e-16 of the largest entry, same sparsity pattern).
const COTMATRIX_RELATIVE: f64 = 1e-12;

/// Mass tolerance, relative per entry: the same formula summed in a different order (measured:
/// 6.5e-16 at most, Voronoi and barycentric, both meshes).
const MASS_RELATIVE: f64 = 1e-15;

#[test]
fn cotangent_laplacian_matches_libigl_cotmatrix() {
    for (shape, reference) in ReferenceIgl::all() {
        let mesh = reference.tri_mesh();
        let l = cotangent_laplacian(&mesh);
        let coo = &reference.operators.cotmatrix;
        assert_eq!((coo.rows, coo.cols), (mesh.n_vertices(), mesh.n_vertices()));
        let scale = coo.v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        // Same pattern, entry by entry: faer stores the columns sorted like the reference.
        let mut k = 0;
        let mut worst: f64 = 0.0;
        let mut worst_entry_relative: f64 = 0.0;
        for j in 0..l.ncols() {
            for (i, &v) in l.row_idx_of_col(j).zip(l.val_of_col(j)) {
                // The reference lists (i, j) sorted by row then column; our column j is row j
                // of a symmetric matrix.
                assert!(k < coo.v.len(), "{shape}: extra entry ({j}, {i})");
                assert_eq!(
                    (coo.i[k], coo.j[k]),
                    (j, i),
                    "{shape}: pattern differs at {k}"
                );
                let d = (v - coo.v[k]).abs();
                worst = worst.max(d);
                worst_entry_relative = worst_entry_relative.max(d / coo.v[k].abs().max(1e-300));
                k += 1;
            }
        }
        assert_eq!(k, coo.v.len(), "{shape}: missing entries");
        eprintln!(
            "{shape}: cotmatrix max |Δ| = {worst:.2e} = {:.2e} of max|L| = {scale:.3}; worst per-entry relative {worst_entry_relative:.2e}",
            worst / scale
        );
        assert!(worst <= COTMATRIX_RELATIVE * scale, "{shape}: {worst:e}");
    }
}

#[test]
fn lumped_mass_matches_libigl_massmatrix() {
    for (shape, reference) in ReferenceIgl::all() {
        let mesh = reference.tri_mesh();
        for (kind, expected) in [
            (
                MassKind::Voronoi,
                &reference.operators.massmatrix_voronoi_diag,
            ),
            (
                MassKind::Barycentric,
                &reference.operators.massmatrix_barycentric_diag,
            ),
        ] {
            let m = lumped_mass(&mesh, kind);
            assert_eq!(m.len(), expected.len());
            let (mut worst_abs, mut worst_rel) = (0.0f64, 0.0f64);
            for (v, (&a, &b)) in m.iter().zip(expected).enumerate() {
                let d = (a - b).abs();
                worst_abs = worst_abs.max(d);
                worst_rel = worst_rel.max(d / b.abs());
                assert!(
                    d <= MASS_RELATIVE * b.abs(),
                    "{shape} {kind:?} vertex {v}: {a} vs {b}"
                );
            }
            eprintln!(
                "{shape} {kind:?}: mass max |Δ| = {worst_abs:.2e}, max relative {worst_rel:.2e}"
            );
            let total: f64 = m.iter().sum();
            assert!((total - reference.mesh.total_area).abs() <= 1e-13 * total);
        }
    }
}

#[test]
fn boundary_loop_matches_reference() {
    for (shape, reference) in ReferenceIgl::all() {
        let loops = reference.tri_mesh().boundary_loops().unwrap();
        assert_eq!(loops.len(), 1, "{shape}: one boundary loop");
        // Same cycle, up to the starting vertex.
        let expected = &reference.mesh.boundary_loop;
        let ours = &loops[0];
        assert_eq!(ours.len(), expected.len());
        let shift = expected
            .iter()
            .position(|&v| v == ours[0])
            .expect("shared vertex");
        for (k, &v) in ours.iter().enumerate() {
            assert_eq!(
                v,
                expected[(k + shift) % expected.len()],
                "{shape}: loop differs at {k}"
            );
        }
    }
}
