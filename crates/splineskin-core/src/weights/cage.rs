//! Harmonic coordinates of a cage (DESIGN.md §2; Joshi, Meyer, DeRose, Green & Sanocki 2007,
//! "Harmonic coordinates for character articulation", SIGGRAPH).
//!
//! The weight `w_i` of cage corner `c_i` is the harmonic function inside the cage whose
//! boundary values are piecewise linear along the cage's edges: 1 at `c_i`, 0 at every other
//! corner, linear in between.
//!
//! ```text
//! Δ w_i = 0  inside the cage,    w_i(c_k + s (c_{k+1} − c_k)) = (1 − s) δ_ik + s δ_i(k+1)  on edge k
//! ```
//!
//! Discretised on a caged [`Domain`] (`DomainOptions::with_cage`) with P1 elements: the
//! boundary data fix every vertex of the outer boundary loop (the cage corners and the Steiner
//! points refinement put on the cage's edges, [`cage_boundary_data`]) and
//! [`mod@super::harmonic`] solves `L w = 0` (cotangent Laplacian, `k = 1`) at the other
//! vertices. The discrete coordinates inherit the continuous ones' properties:
//!
//! * partition of unity: the data sum to 1 at every boundary vertex and `L` kills constants;
//! * linear precision `Σ_i w_i c_i = x` at every vertex: the data reproduce the function `x`
//!   on the boundary (its vertices lie on the edges), and the cotangent Laplacian is exact on
//!   linear functions at interior vertices;
//! * `0 ≤ w_i ≤ 1` (discrete maximum principle): the refined Delaunay mesh has non-negative
//!   cotangent weights.
//!
//! Holes of the domain (`DomainOptions::with_holes`) are free boundaries (natural Neumann
//! conditions); linear precision then no longer holds near them. Point handles and bones of the
//! domain are ignored: the weights have one column per cage corner.

use kurbo::Point;

use super::harmonic::harmonic;
use super::mvc::bounding_diagonal;
use super::{DirichletData, VertexWeights, WeightsError};
use crate::domain::{Boundary, Domain, COINCIDENT_RELATIVE};

/// The Dirichlet data of the harmonic coordinates of `domain`'s cage: one row per vertex of the
/// outer boundary loop, one column per cage corner (`domain.cage_vertices.len()`). A boundary
/// vertex at `c_k + s (c_{k+1} − c_k)` gets `1 − s` in column `k`, `s` in column `k + 1 mod n`
/// and 0 elsewhere; the corners get the identity.
///
/// The loop is walked from corner 0; the vertices met before corner `k + 1` lie on edge `k`,
/// and `s` is their projection onto it. Errors: [`WeightsError::NoCage`] if the domain was
/// built without a cage; [`WeightsError::CageBoundary`] if the outer boundary does not follow
/// the cage (a corner not on it or out of order, or a vertex farther than
/// [`COINCIDENT_RELATIVE`] × the cage's bounding-box diagonal from its edge, or not strictly
/// after the previous vertex along it) — which a domain from [`Domain::build`] never does.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::{Domain, DomainOptions};
/// use splineskin_core::drawing::Drawing;
/// use splineskin_core::weights::cage_boundary_data;
/// let cage = [(0., 0.), (4., 0.), (4., 2.), (0., 2.)].map(Point::from).to_vec();
/// let options = DomainOptions::default().with_cage(cage).with_max_area_fraction(0.05);
/// let domain = Domain::build(&Drawing::default(), &[], &[], &options)?;
/// let data = cage_boundary_data(&domain)?;
/// assert_eq!(data.n_columns(), 4);
/// assert_eq!(data.vertices().len(), domain.boundary_loops[0].len());
/// for (row, &v) in data.vertices().iter().enumerate() {
///     let p = domain.mesh.vertices[v];
///     if p.y == 0.0 {
///         // On the bottom edge, from corner 0 at x = 0 to corner 1 at x = 4.
///         assert_eq!(data.values_at(row), &[1.0 - p.x / 4.0, p.x / 4.0, 0.0, 0.0]);
///     }
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn cage_boundary_data(domain: &Domain) -> Result<DirichletData, WeightsError> {
    let corners = &domain.cage_vertices;
    let n = corners.len();
    if n == 0 || domain.boundary != Boundary::Cage {
        return Err(WeightsError::NoCage);
    }
    let mesh = &domain.mesh;
    let n_vertices = mesh.n_vertices();
    if let Some(&vertex) = corners.iter().find(|&&v| v >= n_vertices) {
        return Err(WeightsError::CageBoundary {
            vertex,
            reason: "cage corner is not a vertex of the mesh",
        });
    }
    let outer = domain
        .boundary_loops
        .first()
        .ok_or(WeightsError::CageBoundary {
            vertex: corners[0],
            reason: "the domain has no boundary loop",
        })?;
    // corner_of[v]: which cage corner mesh vertex v is, if any.
    let mut corner_of: Vec<Option<usize>> = vec![None; n_vertices];
    for (k, &v) in corners.iter().enumerate() {
        corner_of[v] = Some(k);
    }
    let start = outer
        .iter()
        .position(|&v| v == corners[0])
        .ok_or(WeightsError::CageBoundary {
            vertex: corners[0],
            reason: "cage corner 0 is not on the outer boundary loop",
        })?;
    let corner_points: Vec<Point> = corners.iter().map(|&v| mesh.vertices[v]).collect();
    let tolerance = COINCIDENT_RELATIVE * bounding_diagonal(&corner_points);

    let len = outer.len();
    let mut vertices = Vec::with_capacity(len);
    let mut values = vec![0.0; len * n];
    let mut edge = 0; // the cage edge being walked: from corner `edge` to `edge + 1 mod n`
    let mut last_s = 0.0;
    for k in 0..len {
        let v = outer[(start + k) % len];
        if v >= n_vertices {
            return Err(WeightsError::CageBoundary {
                vertex: v,
                reason: "boundary vertex is not a vertex of the mesh",
            });
        }
        let row = &mut values[k * n..(k + 1) * n];
        vertices.push(v);
        match corner_of[v] {
            Some(0) if k == 0 => row[0] = 1.0,
            Some(c) if c == edge + 1 => {
                row[c] = 1.0;
                edge = c;
                last_s = 0.0;
            }
            Some(_) => {
                return Err(WeightsError::CageBoundary {
                    vertex: v,
                    reason: "cage corner met out of order along the outer boundary loop",
                })
            }
            None => {
                let (a, b) = (corner_points[edge], corner_points[(edge + 1) % n]);
                let (ab, ap) = (b - a, mesh.vertices[v] - a);
                let len2 = ab.hypot2();
                let s = ap.dot(ab) / len2;
                let off = ap.cross(ab).abs() / len2.sqrt();
                if off > tolerance {
                    return Err(WeightsError::CageBoundary {
                        vertex: v,
                        reason: "boundary vertex is off the cage edge between its corners",
                    });
                }
                if !(s > last_s && s < 1.0) {
                    return Err(WeightsError::CageBoundary {
                        vertex: v,
                        reason: "boundary vertex is not between the previous one and the next corner along its cage edge",
                    });
                }
                row[edge] = 1.0 - s;
                row[(edge + 1) % n] = s;
                last_s = s;
            }
        }
    }
    if edge != n - 1 {
        return Err(WeightsError::CageBoundary {
            vertex: corners[edge + 1],
            reason: "cage corner is not on the outer boundary loop",
        });
    }
    DirichletData::new(vertices, values, n)
}

/// Harmonic coordinates of `domain`'s cage: `n_vertices × n_corners` weights, column `i` the
/// harmonic function with the piecewise linear boundary data of corner `i`
/// ([`cage_boundary_data`]; module documentation). Wrap them in
/// [`crate::domain::MeshWeights`] to evaluate them anywhere. The boundary rows sum to 1, so
/// the coordinates do everywhere (constants are harmonic); each row is divided by its sum after
/// the solve, so that they do to the last bits rather than to the solve's rounding.
///
/// Errors: those of [`cage_boundary_data`] and of [`harmonic`] (an invalid mesh).
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::{Domain, DomainOptions, MeshWeights};
/// use splineskin_core::drawing::Drawing;
/// use splineskin_core::weights::{harmonic_coordinates, WeightField};
/// // An L-shaped cage, coarsely meshed.
/// let cage = [(0., 0.), (4., 0.), (4., 2.), (2., 2.), (2., 4.), (0., 4.)].map(Point::from);
/// let options = DomainOptions::default().with_cage(cage.to_vec()).with_max_area_fraction(0.02);
/// let domain = Domain::build(&Drawing::default(), &[], &[], &options)?;
/// let w = harmonic_coordinates(&domain)?;
/// assert_eq!(w.n_handles(), 6);
/// // Evaluated anywhere inside: the weights sum to 1, lie in [0, 1] and reproduce the point
/// // (linear precision; P1 interpolation of vertex values that reproduce it).
/// let field = MeshWeights::new(&domain.mesh, w.into_values(), 6)?;
/// let p = Point::new(0.7, 3.1);
/// let mut out = [0.0; 6];
/// field.eval(p, &mut out);
/// assert!((out.iter().sum::<f64>() - 1.0).abs() < 1e-12);
/// assert!(out.iter().all(|&wi| (-1e-12..=1.0 + 1e-12).contains(&wi)));
/// let q = cage.iter().zip(&out).fold(Point::ZERO, |acc, (c, wi)| acc + c.to_vec2() * *wi);
/// assert!((q - p).hypot() < 1e-10);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn harmonic_coordinates(domain: &Domain) -> Result<VertexWeights, WeightsError> {
    let mut w = harmonic(&domain.mesh, &cage_boundary_data(domain)?, 1)?;
    w.normalize_rows()?;
    Ok(w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domain::DomainOptions;
    use crate::drawing::Drawing;

    fn square_domain() -> Domain {
        let cage = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(Point::from);
        let options = DomainOptions::default()
            .with_cage(cage.to_vec())
            .with_max_area_fraction(0.02);
        Domain::build(&Drawing::default(), &[], &[], &options).unwrap()
    }

    #[test]
    fn cage_boundary_data_needs_a_cage() {
        let mut domain = square_domain();
        domain.cage_vertices.clear();
        assert_eq!(cage_boundary_data(&domain), Err(WeightsError::NoCage));
        let mut padded = square_domain();
        padded.boundary = Boundary::Padded;
        assert_eq!(harmonic_coordinates(&padded), Err(WeightsError::NoCage));
    }

    #[test]
    fn cage_boundary_data_rejects_a_boundary_off_the_cage() {
        // Corners swapped: met out of order.
        let mut swapped = square_domain();
        swapped.cage_vertices.swap(1, 2);
        assert!(matches!(
            cage_boundary_data(&swapped),
            Err(WeightsError::CageBoundary { .. })
        ));
        // A boundary vertex moved off its edge.
        let mut moved = square_domain();
        let corners = moved.cage_vertices.clone();
        let v = *moved.boundary_loops[0]
            .iter()
            .find(|v| !corners.contains(v))
            .unwrap();
        moved.mesh.vertices[v].x += 1e-3;
        moved.mesh.vertices[v].y += 1e-3;
        assert_eq!(
            cage_boundary_data(&moved),
            Err(WeightsError::CageBoundary {
                vertex: v,
                reason: "boundary vertex is off the cage edge between its corners"
            })
        );
        // A corner that is not on the boundary (an interior vertex).
        let mut inner = square_domain();
        let on_boundary = inner.boundary_loops[0].clone();
        let interior = (0..inner.mesh.n_vertices())
            .find(|v| !on_boundary.contains(v))
            .unwrap();
        inner.cage_vertices[2] = interior;
        assert!(matches!(
            cage_boundary_data(&inner),
            Err(WeightsError::CageBoundary { .. })
        ));
    }

    #[test]
    fn cage_boundary_data_is_the_identity_at_corners_and_sums_to_one() {
        let domain = square_domain();
        let data = cage_boundary_data(&domain).unwrap();
        assert_eq!(data.vertices().len(), domain.boundary_loops[0].len());
        for (row, &v) in data.vertices().iter().enumerate() {
            let values = data.values_at(row);
            if let Some(k) = domain.cage_vertices.iter().position(|&c| c == v) {
                for (i, &w) in values.iter().enumerate() {
                    assert_eq!(w, if i == k { 1.0 } else { 0.0 });
                }
            }
            let sum: f64 = values.iter().sum();
            // 1 − s + s: one rounding.
            assert!((sum - 1.0).abs() <= f64::EPSILON, "{sum}");
        }
    }
}
