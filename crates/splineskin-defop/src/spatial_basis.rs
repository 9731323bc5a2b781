//! [`SpatialBasis`]: the spatial basis `Φ = (φ_1, …, φ_|Φ|)` of a deformation operator
//! (Poranne & Lipman 2016, §3.1 and Appendix A; DESIGN.md §4), each function given by its
//! values at the mesh vertices and linear on each triangle, so `φ_i = Σ_v D_iv φ̃_v` over the
//! hat functions `φ̃_v` (the paper's `Φ = D Φ̃`).
//!
//! | basis | `|Φ|` | `D` | contains `1, x, y` | interpolates at the handles |
//! |---|---|---|---|---|
//! | [`SpatialBasis::hats`] | `n_vertices` | identity | yes | yes |
//! | [`SpatialBasis::laplacian_eigenfunctions`] | chosen | `1, x, y` then the smoothest eigenfunctions of [`EigenOperator`], M-orthonormal | yes, exactly | when `Φ(P)` has rank `n_handles` (checked by the fit) |
//! | [`SpatialBasis::biharmonic_coordinates`] | number of control vertices | linearly precise biharmonic coordinates (Wang et al. 2015) of the control vertices | yes (linear precision) | yes, when the handles are control vertices |
//!
//! The fit needs the linear functions in `Φ` (the rest pose is `D(x, P) = x`) and `Φ(P)` of
//! full rank (handles interpolated: the paper's Proposition 2).

use kurbo::Point;

use super::error::DefOpError;
use super::laplacian_eigen::{smallest_eigenpairs, EigenOperator};
use splineskin_core::mesh::operators::{lumped_mass, MassKind};
use splineskin_core::mesh::TriMesh;
use splineskin_core::weights::biharmonic_coordinates;

/// A function whose M-norm drops below this fraction of its own when the previous basis
/// functions are projected out is taken as dependent on them and skipped (dimensionless; the
/// eigensolver's null-space vectors are dependent on `1, x, y` to about 1e-12).
const DEPENDENT: f64 = 1e-6;

/// Which spatial basis a [`SpatialBasis`] is.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SpatialBasisKind {
    /// The piecewise linear hat functions, one per vertex (`D` = identity).
    Hats,
    /// The linear functions `1, x, y` and the smoothest eigenfunctions of an operator.
    LaplacianEigenfunctions {
        /// The operator whose eigenfunctions complete the basis.
        operator: EigenOperator,
    },
    /// Linearly precise biharmonic coordinates of control vertices.
    BiharmonicCoordinates {
        /// The control vertices, one per function.
        control_vertices: Vec<usize>,
    },
}

/// A spatial basis over a triangle mesh: `n_functions` functions, each linear on every
/// triangle, given by its values at the `n_vertices` vertices.
///
/// ```
/// use kurbo::Rect;
/// use splineskin_defop::{EigenOperator, SpatialBasis};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 16, 4)?;
/// let hats = SpatialBasis::hats(&mesh)?;
/// assert_eq!((hats.n_functions(), hats.value(3, 3), hats.value(3, 4)), (85, 1.0, 0.0));
/// let eigen = SpatialBasis::laplacian_eigenfunctions(&mesh, 12, EigenOperator::LinearlyPrecise)?;
/// assert_eq!(eigen.n_functions(), 12);
/// let coordinates = SpatialBasis::biharmonic_coordinates_sampled(&mesh, &[34, 50], 10)?;
/// assert_eq!(coordinates.n_functions(), 10);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SpatialBasis {
    kind: SpatialBasisKind,
    n_vertices: usize,
    n_functions: usize,
    /// `None` for the hats; otherwise function `i`'s vertex values at
    /// `values[i · n_vertices ..][..n_vertices]` (the rows of `D`).
    values: Option<Vec<f64>>,
}

impl SpatialBasis {
    /// The hat functions of `mesh`, one per vertex: the full finite-element space, in which the
    /// ground truth lives. Errors on an invalid mesh or a vertex in no triangle.
    pub fn hats(mesh: &TriMesh) -> Result<SpatialBasis, DefOpError> {
        check_mesh(mesh)?;
        Ok(SpatialBasis {
            kind: SpatialBasisKind::Hats,
            n_vertices: mesh.n_vertices(),
            n_functions: mesh.n_vertices(),
            values: None,
        })
    }

    /// `n_functions` functions: `1, x, y` and then the eigenfunctions of `operator` with the
    /// smallest eigenvalues (`K φ = λ M φ`, Voronoi lumped `M`; see [`EigenOperator`]), with
    /// any function dependent on the previous ones skipped (the constant for
    /// [`EigenOperator::Cotangent`], the three zero modes for
    /// [`EigenOperator::LinearlyPrecise`]), M-orthonormalised in that order. The linear
    /// functions are in the basis exactly, not to the eigensolver's accuracy.
    ///
    /// Errors on an invalid mesh, a vertex in no triangle, `n_functions` outside
    /// `3 ..= n_vertices`, or an eigensolver failure.
    pub fn laplacian_eigenfunctions(
        mesh: &TriMesh,
        n_functions: usize,
        operator: EigenOperator,
    ) -> Result<SpatialBasis, DefOpError> {
        check_mesh(mesh)?;
        let n = mesh.n_vertices();
        if !(3..=n).contains(&n_functions) {
            return Err(DefOpError::InvalidOption {
                name: "n_functions",
                value: n_functions.to_string(),
                expected: "between 3 (the linear functions) and the number of vertices",
            });
        }
        let mass = lumped_mass(mesh, MassKind::Voronoi);
        // Up to three eigenfunctions (the null space) are dependent on 1, x, y.
        let n_pairs = (n_functions + 3).min(n);
        let pairs = smallest_eigenpairs(mesh, operator, n_pairs)?;
        tracing::debug!(
            ?operator,
            n_pairs,
            lowest = pairs.values.first(),
            highest = pairs.values.last(),
            "Laplacian eigenvalues"
        );
        let linear = [
            vec![1.0; n],
            mesh.vertices.iter().map(|p| p.x).collect(),
            mesh.vertices.iter().map(|p| p.y).collect(),
        ];
        let candidates = linear
            .iter()
            .map(|v| v.as_slice())
            .chain(pairs.vectors.chunks(n));
        let mut values: Vec<f64> = Vec::with_capacity(n * n_functions);
        let mut count = 0;
        for candidate in candidates {
            if count == n_functions {
                break;
            }
            let mut f = candidate.to_vec();
            let before = m_norm(&f, &mass);
            // Modified Gram–Schmidt against the accepted functions, twice (Kahan's "twice is
            // enough" for orthogonality to rounding).
            for _ in 0..2 {
                for accepted in values.chunks(n) {
                    let dot: f64 = f
                        .iter()
                        .zip(accepted)
                        .zip(&mass)
                        .map(|((a, b), m)| a * b * m)
                        .sum();
                    f.iter_mut().zip(accepted).for_each(|(a, b)| *a -= dot * b);
                }
            }
            let after = m_norm(&f, &mass);
            if after <= DEPENDENT * before {
                continue;
            }
            values.extend(f.iter().map(|a| a / after));
            count += 1;
        }
        if count < n_functions {
            return Err(DefOpError::Eigensolver {
                detail: format!(
                    "only {count} independent functions among 1, x, y and {n_pairs} eigenfunctions (asked {n_functions})"
                ),
            });
        }
        Ok(SpatialBasis {
            kind: SpatialBasisKind::LaplacianEigenfunctions { operator },
            n_vertices: n,
            n_functions,
            values: Some(values),
        })
    }

    /// The linearly precise biharmonic coordinates of the vertices `control_vertices`
    /// ([`splineskin_core::weights::biharmonic_coordinates()`]), one function per control vertex: they
    /// hold the linear functions (linear precision) and interpolate any values at the control
    /// vertices. Errors as that function (at least three control vertices not on a line in
    /// every part of the mesh).
    pub fn biharmonic_coordinates(
        mesh: &TriMesh,
        control_vertices: &[usize],
    ) -> Result<SpatialBasis, DefOpError> {
        check_mesh(mesh)?;
        let weights = biharmonic_coordinates(mesh, control_vertices)?;
        let n = mesh.n_vertices();
        let k = control_vertices.len();
        let mut values = vec![0.0; n * k];
        for v in 0..n {
            for (i, &w) in weights.row(v).iter().enumerate() {
                values[i * n + v] = w;
            }
        }
        Ok(SpatialBasis {
            kind: SpatialBasisKind::BiharmonicCoordinates {
                control_vertices: control_vertices.to_vec(),
            },
            n_vertices: n,
            n_functions: k,
            values: Some(values),
        })
    }

    /// [`SpatialBasis::biharmonic_coordinates`] of `n_functions` control vertices: the
    /// `handles` first, then vertices chosen by farthest-point sampling (each the vertex
    /// farthest, in straight-line distance, from those already chosen; ties to the smaller
    /// index), which spreads them evenly over the shape. Errors as
    /// [`SpatialBasis::biharmonic_coordinates`], or if `n_functions` is below the number of
    /// handles or above the number of vertices.
    pub fn biharmonic_coordinates_sampled(
        mesh: &TriMesh,
        handles: &[usize],
        n_functions: usize,
    ) -> Result<SpatialBasis, DefOpError> {
        check_mesh(mesh)?;
        let n = mesh.n_vertices();
        if !(handles.len()..=n).contains(&n_functions) {
            return Err(DefOpError::InvalidOption {
                name: "n_functions",
                value: n_functions.to_string(),
                expected: "between the number of handles and the number of vertices",
            });
        }
        if let Some(handle) = handles.iter().position(|&v| v >= n) {
            return Err(DefOpError::HandleOutOfRange {
                handle,
                vertex: handles[handle],
                n_vertices: n,
            });
        }
        Self::biharmonic_coordinates(
            mesh,
            &farthest_point_sampling(&mesh.vertices, handles, n_functions),
        )
    }

    /// A basis from stored parts (the operator file): `values` as the field documents, `None`
    /// for the hats. The caller has checked the sizes.
    pub(crate) fn from_parts(
        kind: SpatialBasisKind,
        n_vertices: usize,
        n_functions: usize,
        values: Option<Vec<f64>>,
    ) -> SpatialBasis {
        SpatialBasis {
            kind,
            n_vertices,
            n_functions,
            values,
        }
    }

    /// Which basis this is.
    pub fn kind(&self) -> &SpatialBasisKind {
        &self.kind
    }

    /// Number of functions `|Φ|`.
    pub fn n_functions(&self) -> usize {
        self.n_functions
    }

    /// Number of mesh vertices the functions are given at.
    pub fn n_vertices(&self) -> usize {
        self.n_vertices
    }

    /// Whether this is the hat basis (`D` = identity).
    pub fn is_hats(&self) -> bool {
        self.values.is_none()
    }

    /// `φ_i` at vertex `v` (panics if out of range, like slice indexing).
    pub fn value(&self, i: usize, v: usize) -> f64 {
        assert!(
            i < self.n_functions && v < self.n_vertices,
            "φ_{i} at vertex {v}: out of range"
        );
        match &self.values {
            None => f64::from(u8::from(i == v)),
            Some(values) => values[i * self.n_vertices + v],
        }
    }

    /// Function `i`'s values at every vertex (`None` for the hats, whose values are `δ_iv`;
    /// panics if `i` is out of range).
    pub fn function(&self, i: usize) -> Option<&[f64]> {
        self.values
            .as_ref()
            .map(|values| &values[i * self.n_vertices..(i + 1) * self.n_vertices])
    }
}

/// `sqrt(fᵀ M f)` for a diagonal `M`.
fn m_norm(f: &[f64], mass: &[f64]) -> f64 {
    f.iter()
        .zip(mass)
        .map(|(a, m)| a * a * m)
        .sum::<f64>()
        .sqrt()
}

/// A valid mesh with every vertex in a triangle.
fn check_mesh(mesh: &TriMesh) -> Result<(), DefOpError> {
    mesh.check()?;
    if let Some(vertex) = mesh.referenced_vertices().iter().position(|&r| !r) {
        return Err(DefOpError::UnreferencedVertex { vertex });
    }
    Ok(())
}

/// `seeds` (distinct, in range) and then vertices each farthest from all chosen so far, until
/// `count` are chosen.
fn farthest_point_sampling(vertices: &[Point], seeds: &[usize], count: usize) -> Vec<usize> {
    let mut chosen: Vec<usize> = seeds.to_vec();
    let mut distance: Vec<f64> = vertices
        .iter()
        .map(|&p| {
            seeds
                .iter()
                .map(|&s| (p - vertices[s]).hypot2())
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    if seeds.is_empty() {
        chosen.push(0);
        distance
            .iter_mut()
            .zip(vertices)
            .for_each(|(d, &p)| *d = (p - vertices[0]).hypot2());
    }
    while chosen.len() < count {
        let mut best = 0;
        for (v, &d) in distance.iter().enumerate() {
            if d > distance[best] {
                best = v;
            }
        }
        chosen.push(best);
        let q = vertices[best];
        distance
            .iter_mut()
            .zip(vertices)
            .for_each(|(d, &p)| *d = d.min((p - q).hypot2()));
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Rect;

    #[test]
    fn eigenfunction_basis_is_m_orthonormal_and_holds_linear_functions() {
        let mesh = TriMesh::grid(Rect::new(0., 0., 3., 1.), 18, 6).unwrap();
        let n = mesh.n_vertices();
        let mass = lumped_mass(&mesh, MassKind::Voronoi);
        for operator in [EigenOperator::Cotangent, EigenOperator::LinearlyPrecise] {
            let basis = SpatialBasis::laplacian_eigenfunctions(&mesh, 15, operator).unwrap();
            let f = |i: usize| basis.function(i).unwrap();
            for i in 0..15 {
                for j in 0..15 {
                    let dot: f64 = (0..n).map(|v| f(i)[v] * f(j)[v] * mass[v]).sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!(
                        (dot - want).abs() < 1e-12,
                        "{operator:?}: ⟨φ_{i}, φ_{j}⟩ = {dot}"
                    );
                }
            }
            // x is in the span of the first three functions.
            let x: Vec<f64> = mesh.vertices.iter().map(|p| p.x).collect();
            let mut r = x.clone();
            for i in 0..3 {
                let dot: f64 = (0..n).map(|v| x[v] * f(i)[v] * mass[v]).sum();
                (0..n).for_each(|v| r[v] -= dot * f(i)[v]);
            }
            assert!(r.iter().all(|e| e.abs() < 1e-12), "{operator:?}");
        }
        assert!(matches!(
            SpatialBasis::laplacian_eigenfunctions(&mesh, 2, EigenOperator::Cotangent),
            Err(DefOpError::InvalidOption {
                name: "n_functions",
                ..
            })
        ));
    }

    #[test]
    fn farthest_point_sampling_spreads_from_the_seeds() {
        let v: Vec<Point> = (0..11).map(|i| Point::new(i as f64, 0.0)).collect();
        assert_eq!(farthest_point_sampling(&v, &[0], 3), vec![0, 10, 5]);
        assert_eq!(farthest_point_sampling(&v, &[3, 4], 3), vec![3, 4, 10]);
    }

    #[test]
    fn biharmonic_coordinate_basis_interpolates_at_control_vertices() {
        let mesh = TriMesh::grid(Rect::new(0., 0., 3., 1.), 12, 4).unwrap();
        let basis = SpatialBasis::biharmonic_coordinates_sampled(&mesh, &[27, 35], 8).unwrap();
        let SpatialBasisKind::BiharmonicCoordinates { control_vertices } = basis.kind() else {
            panic!("kind");
        };
        assert_eq!(&control_vertices[..2], &[27, 35]);
        for (i, &c) in control_vertices.iter().enumerate() {
            for j in 0..8 {
                assert_eq!(basis.value(j, c), if i == j { 1.0 } else { 0.0 });
            }
        }
    }
}
