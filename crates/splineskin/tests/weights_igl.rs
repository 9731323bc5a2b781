//! Mesh weight families against libigl 2.6.3 on the reference-igl meshes (bar, U shape):
//! `harmonic` with k = 1 and k = 2, `bbw` raw and row-normalised, `biharmonic_coordinates`
//! (Wang et al. 2015, the Crouzeix–Raviart variant); and the properties the
//! weights must have whatever the reference: interpolation at handles, partition of unity,
//! bounds, and the KKT conditions of the bounded program.

mod common;

use common::reference_igl::ReferenceIgl;
use splineskin::mesh::operators::polyharmonic_energy;
use splineskin::weights::{
    bbw_weights, biharmonic_coordinates, bounded_biharmonic, harmonic_weights, BbwOptions,
    DirichletData, VertexWeights,
};

/// Harmonic and biharmonic weights solve the same linear system as libigl's, factored
/// differently: they agree to rounding times the system's conditioning (measured: 4.9e-15 for
/// k = 1 and 1.8e-12 for k = 2 at most). The issue asks 1e-8; 1e-9 is the README's figure.
const HARMONIC_TOLERANCE: f64 = 1e-9;

/// BBW: the program is strictly convex, so any exact solver gives its unique minimiser; the
/// difference is the two active-set solvers' stopping tolerances. libigl's output has bound
/// vertices whose multipliers have the wrong sign by up to 6e-10 of max|Q| (its kkt_check),
/// which moves its weights by about 1e-8 from the exact minimiser (the README's independent
/// solver: 6e-8 on the bar; ours: 6.0e-8 on the bar, 2.2e-9 on the U). 1e-6 is the README's
/// suggestion; the issue allows 1e-4.
const BBW_TOLERANCE: f64 = 1e-6;

/// Linearly precise biharmonic coordinates: the same linear system as libigl's (its energy
/// scaled by the largest Crouzeix–Raviart mass, which changes no minimiser), factored
/// differently; the README's figure is 1e-9 for this (Crouzeix–Raviart) construction.
const BIHARMONIC_COORDINATES_TOLERANCE: f64 = 1e-9;

fn max_abs_difference(ours: &VertexWeights, reference: &[Vec<f64>]) -> f64 {
    assert_eq!(ours.n_vertices(), reference.len());
    let mut worst: f64 = 0.0;
    for (v, row) in reference.iter().enumerate() {
        assert_eq!(row.len(), ours.n_handles());
        for (i, &r) in row.iter().enumerate() {
            worst = worst.max((ours.get(v, i) - r).abs());
        }
    }
    worst
}

/// w_i = 1 at handle i's vertex and 0 at the other handles, exactly.
fn assert_interpolates(w: &VertexWeights, handles: &[usize], what: &str) {
    for (i, &v) in handles.iter().enumerate() {
        for j in 0..handles.len() {
            assert_eq!(
                w.get(v, j),
                if i == j { 1.0 } else { 0.0 },
                "{what}: handle {i}, weight {j}"
            );
        }
    }
}

fn max_row_sum_error(w: &VertexWeights) -> f64 {
    (0..w.n_vertices())
        .map(|v| (w.row(v).iter().sum::<f64>() - 1.0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn harmonic_weights_match_libigl() {
    for (shape, reference) in ReferenceIgl::all() {
        let mesh = reference.tri_mesh();
        let handles = &reference.handles.indices;
        for (k, expected) in [
            (1, &reference.weights.harmonic_k1.W),
            (2, &reference.weights.harmonic_k2.W),
        ] {
            let w = harmonic_weights(&mesh, handles, k).unwrap();
            let d = max_abs_difference(&w, expected);
            eprintln!("{shape}: harmonic k={k} max |Δ| = {d:.2e}");
            assert!(d <= HARMONIC_TOLERANCE, "{shape} k={k}: {d:e}");
            assert_interpolates(&w, handles, &format!("{shape} k={k}"));
            // The identity data sum to 1 and constants are in the energies' null space, so the
            // weights are a partition of unity without normalisation.
            let pu = max_row_sum_error(&w);
            assert!(pu < 1e-10, "{shape} k={k}: rows sum to 1 ± {pu:e}");
            if k == 1 {
                // Maximum principle (these meshes are Delaunay: non-negative cotangent weights).
                let (lo, hi) = min_max(&w);
                assert!(lo >= -1e-14 && hi <= 1.0 + 1e-14, "{shape}: [{lo}, {hi}]");
            }
        }
    }
}

fn min_max(w: &VertexWeights) -> (f64, f64) {
    w.as_slice()
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}

#[test]
fn bbw_matches_libigl_raw_and_normalised() {
    for (shape, reference) in ReferenceIgl::all() {
        let mesh = reference.tri_mesh();
        let handles = &reference.handles.indices;
        for parallel in [false, true] {
            let options = BbwOptions::default().with_parallel(parallel);
            let raw =
                bounded_biharmonic(&mesh, &DirichletData::handles(handles).unwrap(), &options)
                    .unwrap();
            let d_raw = max_abs_difference(&raw, &reference.weights.bbw_raw.W);
            let normalised = bbw_weights(&mesh, handles, &options).unwrap();
            let d_normalised = max_abs_difference(&normalised, &reference.weights.bbw_normalized.W);
            eprintln!(
                "{shape} (parallel: {parallel}): bbw raw max |Δ| = {d_raw:.2e}, normalised {d_normalised:.2e}"
            );
            assert!(d_raw <= BBW_TOLERANCE, "{shape}: raw {d_raw:e}");
            assert!(
                d_normalised <= BBW_TOLERANCE,
                "{shape}: normalised {d_normalised:e}"
            );

            // Bounds hold exactly, handles interpolate exactly, normalised rows sum to 1.
            for w in [&raw, &normalised] {
                let (lo, hi) = min_max(w);
                assert!(lo >= 0.0 && hi <= 1.0, "{shape}: [{lo}, {hi}]");
                assert_interpolates(w, handles, shape);
            }
            let pu = max_row_sum_error(&normalised);
            assert!(pu < 1e-14, "{shape}: normalised rows sum to 1 ± {pu:e}");
            // Raw rows: at least 1 (libigl's: 1 to 1.052 on the bar, 1 to 1.076 on the U).
            let max_raw_sum = (0..raw.n_vertices())
                .map(|v| raw.row(v).iter().sum::<f64>())
                .fold(0.0, f64::max);
            eprintln!("{shape}: raw rows sum up to {max_raw_sum:.4}");
        }
    }
}

/// The KKT conditions of min ½wᵀQw s.t. w[b] = bc, 0 ≤ w ≤ 1, checked with Q rebuilt from the
/// public operators: gradient g = Qw zero at free vertices, ≥ 0 at the lower bound, ≤ 0 at the
/// upper bound (relative to max|Q|, as libigl's kkt_check), and the bound counts compared with
/// libigl's.
#[test]
fn bbw_satisfies_kkt_conditions() {
    // Rounding of g = Qw for w ∈ [0, 1]: a few units of 1e-16 times the ~20 entries of a row.
    const KKT_TOLERANCE: f64 = 1e-12;
    for (shape, reference) in ReferenceIgl::all() {
        let mesh = reference.tri_mesh();
        let handles = &reference.handles.indices;
        let raw = bounded_biharmonic(
            &mesh,
            &DirichletData::handles(handles).unwrap(),
            &BbwOptions::default(),
        )
        .unwrap();
        let q = polyharmonic_energy(&mesh, 2);
        let q_max = q.val().iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (i, igl) in reference.weights.bbw_raw.kkt_check.iter().enumerate() {
            assert_eq!(igl.handle, i);
            let w = raw.column(i);
            let mut g = vec![0.0; w.len()];
            for j in 0..q.ncols() {
                for (r, &x) in q.row_idx_of_col(j).zip(q.val_of_col(j)) {
                    g[r] += x * w[j];
                }
            }
            let (mut free_residual, mut lower_min, mut upper_max) =
                (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
            let (mut n_lower, mut n_upper) = (0, 0);
            for v in 0..w.len() {
                if handles.contains(&v) {
                    continue;
                }
                let gv = g[v] / q_max;
                if w[v] == 0.0 {
                    n_lower += 1;
                    lower_min = lower_min.min(gv);
                } else if w[v] == 1.0 {
                    n_upper += 1;
                    upper_max = upper_max.max(gv);
                } else {
                    free_residual = free_residual.max(gv.abs());
                }
            }
            eprintln!(
                "{shape} handle {i}: free |g| ≤ {free_residual:.1e}, lower min g {lower_min:.1e}, upper max g {upper_max:.1e}, at bounds {n_lower}/{n_upper} (libigl {}/{}, free |g| ≤ {:.1e})",
                igl.n_at_lower, igl.n_at_upper, igl.max_abs_grad_inactive_rel
            );
            assert!(
                free_residual <= KKT_TOLERANCE,
                "{shape} handle {i}: free gradient {free_residual:e}"
            );
            assert!(
                lower_min >= -KKT_TOLERANCE,
                "{shape} handle {i}: lower multiplier {lower_min:e}"
            );
            assert!(
                upper_max <= KKT_TOLERANCE,
                "{shape} handle {i}: upper multiplier {upper_max:e}"
            );
        }
    }
}

#[test]
fn biharmonic_coordinates_match_libigl() {
    for (shape, reference) in ReferenceIgl::all() {
        let mesh = reference.tri_mesh();
        let handles = &reference.handles.indices;
        let w = biharmonic_coordinates(&mesh, handles).unwrap();
        let d = max_abs_difference(&w, &reference.weights.biharmonic_coordinates_wang2015.W);
        eprintln!("{shape}: biharmonic coordinates (Wang 2015) max |Δ| = {d:.2e}");
        assert!(d <= BIHARMONIC_COORDINATES_TOLERANCE, "{shape}: {d:e}");
        assert_interpolates(&w, handles, shape);
        let pu = max_row_sum_error(&w);
        assert!(pu < 1e-10, "{shape}: rows sum to 1 ± {pu:e}");
        // Linear precision: Σ_i w_i(v) p_i = v.
        let mut worst: f64 = 0.0;
        for (v, p) in mesh.vertices.iter().enumerate() {
            let (mut x, mut y) = (0.0, 0.0);
            for (i, &h) in handles.iter().enumerate() {
                x += w.get(v, i) * mesh.vertices[h].x;
                y += w.get(v, i) * mesh.vertices[h].y;
            }
            worst = worst.max((x - p.x).abs()).max((y - p.y).abs());
        }
        eprintln!("{shape}: linear precision to {worst:.1e}");
        assert!(worst < 1e-10, "{shape}: linear precision {worst:e}");
    }
}
