//! The mesh-based weight families' [`WeightField`]: [`MeshWeights`] (per-vertex weights on the
//! triangulated domain, [`crate::domain::locate`]) evaluated by barycentric interpolation, its
//! kinks the parameters where a curve crosses a mesh edge (the interpolant is only C⁰ there,
//! and the quadrature splits its pieces at them).

use kurbo::Point;

use super::WeightField;
use crate::domain::MeshWeights;

impl WeightField for MeshWeights {
    fn n_handles(&self) -> usize {
        MeshWeights::n_handles(self)
    }

    /// [`MeshWeights::weights_at`].
    fn eval(&self, p: Point, out: &mut [f64]) {
        self.weights_at(p, out)
    }

    /// [`MeshWeights::edge_crossings`].
    fn kinks(&self, curve: &[Point; 4], out: &mut Vec<f64>) {
        self.edge_crossings(curve, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::{bernstein, bernstein_gram, gauss_legendre};
    use crate::domain::locate::test_meshes::{grid_mesh, sampled, wavy};
    use crate::drawing::{Drawing, JunctionOptions, Path};
    use crate::spline_fit::quadrature::SampledCurves;
    use crate::spline_fit::FitOptions;

    /// The grid interpolant evaluated by its own formula (cell by `floor`, triangle by the
    /// fractional parts) — independent of the point location under test.
    fn grid_interpolant(n: usize, h: f64, f: impl Fn(Point) -> [f64; 2], p: Point) -> [f64; 2] {
        let (gx, gy) = (p.x / h, p.y / h);
        let i = (gx.floor() as usize).min(n - 1);
        let j = (gy.floor() as usize).min(n - 1);
        let (fx, fy) = (gx - i as f64, gy - j as f64);
        let at = |a: usize, b: usize| f(Point::new(a as f64 * h, b as f64 * h));
        let (w00, w10, w11, w01) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
        let mut out = [0.0; 2];
        for k in 0..2 {
            out[k] = if fx >= fy {
                (1.0 - fx) * w00[k] + (fx - fy) * w10[k] + fy * w11[k]
            } else {
                (1.0 - fy) * w00[k] + fx * w11[k] + (fy - fx) * w01[k]
            };
        }
        out
    }

    /// A field with the same values but no kinks: the quadrature then integrates across edges.
    struct NoKinks<'a>(&'a MeshWeights);
    impl WeightField for NoKinks<'_> {
        fn n_handles(&self) -> usize {
            self.0.n_handles()
        }
        fn eval(&self, p: Point, out: &mut [f64]) {
            self.0.weights_at(p, out)
        }
    }

    #[test]
    fn kinks_make_weighted_grams_exact() {
        let (n, h) = (12, 1.0);
        let mesh = grid_mesh(n, h);
        let w = sampled(&mesh, wavy);
        let curves: [[(f64, f64); 4]; 3] = [
            [(0.5, 0.7), (3.0, 11.0), (8.0, -2.0), (11.3, 9.1)],
            [(1.1, 10.9), (4.0, 4.0), (6.5, 6.5), (10.9, 1.2)],
            [(2.0, 2.0), (9.7, 2.5), (9.9, 9.6), (2.3, 9.8)],
        ];
        let paths = curves
            .iter()
            .map(|c| {
                Path::new(
                    c.map(Point::from).to_vec(),
                    false,
                    &JunctionOptions::default(),
                )
                .unwrap()
            })
            .collect();
        let drawing = Drawing {
            paths,
            ..Default::default()
        };
        let samples = SampledCurves::sample(&drawing, &w, &FitOptions::default());
        let plain = SampledCurves::sample(&drawing, &NoKinks(&w), &FitOptions::default());
        let (gt, gw) = gauss_legendre(16);
        let a_hat = bernstein_gram();
        let mut worst_with: f64 = 0.0;
        let mut worst_without: f64 = 0.0;
        for (j, c) in curves.iter().enumerate() {
            let c = c.map(Point::from);
            // Reference crossings: the curve's coordinates against each family of grid lines
            // (x = k, y = k, x − y = k), roots from kurbo's closed-form cubic solver on the
            // power-basis coefficients.
            let power = |f: &dyn Fn(Point) -> f64| {
                let q = c.map(f);
                [
                    q[0],
                    3.0 * (q[1] - q[0]),
                    3.0 * (q[2] - 2.0 * q[1] + q[0]),
                    q[3] - 3.0 * q[2] + 3.0 * q[1] - q[0],
                ]
            };
            let mut cuts = vec![0.0, 1.0];
            for f in [
                &(|p: Point| p.x) as &dyn Fn(Point) -> f64,
                &|p: Point| p.y,
                &|p: Point| p.x - p.y,
            ] {
                let pc = power(f);
                for k in -(n as i64)..=(n as i64) {
                    let roots =
                        kurbo::common::solve_cubic(pc[0] - k as f64 * h, pc[1], pc[2], pc[3]);
                    cuts.extend(roots.into_iter().filter(|t| *t > 0.0 && *t < 1.0));
                }
            }
            cuts.sort_by(f64::total_cmp);
            let mut reference = [[[0.0; 4]; 4]; 2];
            for piece in cuts.windows(2) {
                let (a, b) = (piece[0], piece[1]);
                for (&s, &gwk) in gt.iter().zip(&gw) {
                    let t = a + (b - a) * s;
                    let wv = grid_interpolant(n, h, wavy, crate::bezier::eval(&c, t));
                    let bt = bernstein(t);
                    for i in 0..2 {
                        for k in 0..4 {
                            for l in 0..4 {
                                reference[i][k][l] += (b - a) * gwk * wv[i] * bt[k] * bt[l];
                            }
                        }
                    }
                }
            }
            let nodes = samples.curve(j);
            // The rule's measure: ℓ_j dt, ℓ_j read back from its exact Gram matrix.
            let len = nodes.gram()[0][0] / a_hat[0][0];
            let mut m = Vec::new();
            nodes.weighted_grams(&mut m);
            let mut m_plain = Vec::new();
            plain.curve(j).weighted_grams(&mut m_plain);
            let scale = len * a_hat[0][0];
            for i in 0..2 {
                for k in 0..4 {
                    for l in 0..4 {
                        let r = len * reference[i][k][l];
                        worst_with = worst_with.max((m[i][k][l] - r).abs() / scale);
                        worst_without = worst_without.max((m_plain[i][k][l] - r).abs() / scale);
                    }
                }
            }
        }
        // Exact but for rounding and the crossing parameters' accuracy; without the kinks the
        // default rule (4 pieces × 8 nodes) misses the C⁰ corners by orders of magnitude more.
        assert!(worst_with < 1e-13, "with kinks: {worst_with:e}");
        assert!(worst_without > 1e-6, "without kinks: {worst_without:e}");
    }
}
