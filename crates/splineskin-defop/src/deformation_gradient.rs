//! The deformation gradient `J_t` of a piecewise linear map on each triangle, and its split
//! into a similarity and an anti-similarity, which gives its singular values and closest
//! rotation in closed form.
//!
//! On triangle `t` with rest corners `p_0, p_1, p_2` and barycentric (hat) functions `φ_k`,
//! the map sending `p_k` to `u_k` is `f(x) = Σ_k u_k φ_k(x)`, with constant Jacobian
//!
//! ```text
//! J_t = Σ_k u_k ∇φ_kᵀ = [[a, b], [c, d]],   ∇φ_k = (p_{k+2} − p_{k+1})^⊥ / (2 A_t)
//! ```
//!
//! (`v^⊥ = (−v_y, v_x)`, indices mod 3, `A_t > 0` the rest area of the counter-clockwise
//! triangle). Any 2×2 matrix is uniquely a similarity plus an anti-similarity:
//!
//! ```text
//! J = [[E, −H], [H, E]] + [[F, G], [G, −F]],   E = (a+d)/2, H = (c−b)/2, F = (a−d)/2, G = (c+b)/2
//! Q = ‖(E, H)‖,  R = ‖(F, G)‖,   singular values  Σ = Q + R,  σ = Q − R   (σ < 0 ⇔ det J < 0)
//! ```
//!
//! and `det J = Q² − R²`. The closest rotation to `J` (maximising `tr(RᵀJ)` over SO(2)) is the
//! similarity part normalised, the rotation by `atan2(H, E)`; then `‖J − R‖²_F = 2(Q − 1)² +
//! 2R²`. This is the signed SVD that libigl computes numerically (`fit_rotations`, with the
//! sign of the smaller singular vector flipped when `det < 0`); the closed form is exact and
//! needs no iteration. (The split is classical: e.g. Smith & Schaefer 2015, *Bijective
//! parameterization with free boundaries*, §4, and Poranne & Lipman 2014.)

use kurbo::{Point, Vec2};

use splineskin_core::mesh::TriMesh;

/// A 2×2 matrix `[[a, b], [c, d]]` acting on column vectors: `(x, y) ↦ (a x + b y, c x + d y)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Jacobian {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
}

/// A [`Jacobian`]'s similarity `(E, H)` and anti-similarity `(F, G)` parts and their norms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ConformalSplit {
    pub e: f64,
    pub h: f64,
    pub f: f64,
    pub g: f64,
    /// `‖(E, H)‖`.
    pub q: f64,
    /// `‖(F, G)‖`.
    pub r: f64,
}

impl Jacobian {
    /// The split described in the module documentation.
    pub fn split(self) -> ConformalSplit {
        let e = 0.5 * (self.a + self.d);
        let h = 0.5 * (self.c - self.b);
        let f = 0.5 * (self.a - self.d);
        let g = 0.5 * (self.c + self.b);
        // Jacobian entries are ratios of lengths (order 1 whatever the drawing's scale), so the
        // plain square root cannot overflow; `hypot`'s care costs a tenth of a training.
        ConformalSplit {
            e,
            h,
            f,
            g,
            q: (e * e + h * h).sqrt(),
            r: (f * f + g * g).sqrt(),
        }
    }
}

impl ConformalSplit {
    /// `(cos θ, sin θ)` of the rotation closest to the matrix in the Frobenius norm. When the
    /// similarity part vanishes (`Q = 0`) every rotation is equally close; the identity is
    /// returned.
    pub fn closest_rotation(&self) -> (f64, f64) {
        if self.q > 0.0 {
            (self.e / self.q, self.h / self.q)
        } else {
            (1.0, 0.0)
        }
    }

    /// `‖J − R‖²_F` with `R` the closest rotation: `2(Q − 1)² + 2R²`.
    pub fn arap_density(&self) -> f64 {
        2.0 * ((self.q - 1.0).powi(2) + self.r * self.r)
    }
}

/// Per-triangle rest data of a mesh: areas `A_t` and hat-function gradients `∇φ_k`.
#[derive(Clone, Debug)]
pub(crate) struct TriangleGradients {
    /// The triangles' corner vertices (the mesh's).
    pub triangles: Vec<[usize; 3]>,
    /// `A_t`, positive.
    pub area: Vec<f64>,
    /// `∇φ_k` of corner `k` of triangle `t`.
    pub gradient: Vec<[Vec2; 3]>,
}

impl TriangleGradients {
    /// Rest data of a checked mesh (every triangle counter-clockwise, positive area).
    pub fn new(mesh: &TriMesh) -> TriangleGradients {
        let mut area = Vec::with_capacity(mesh.n_triangles());
        let mut gradient = Vec::with_capacity(mesh.n_triangles());
        for tri in &mesh.triangles {
            let p = tri.map(|i| mesh.vertices[i]);
            let double_area = (p[1] - p[0]).cross(p[2] - p[0]);
            area.push(0.5 * double_area);
            gradient.push(std::array::from_fn(|k| {
                let e = p[(k + 2) % 3] - p[(k + 1) % 3];
                Vec2::new(-e.y, e.x) / double_area
            }));
        }
        TriangleGradients {
            triangles: mesh.triangles.clone(),
            area,
            gradient,
        }
    }

    /// Number of triangles.
    pub fn n_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// `J_t` for the vertex positions `u`.
    pub fn jacobian(&self, t: usize, u: &[Point]) -> Jacobian {
        let tri = self.triangles[t];
        let g = &self.gradient[t];
        let mut j = Jacobian {
            a: 0.0,
            b: 0.0,
            c: 0.0,
            d: 0.0,
        };
        for k in 0..3 {
            let p = u[tri[k]];
            j.a += p.x * g[k].x;
            j.b += p.x * g[k].y;
            j.c += p.y * g[k].x;
            j.d += p.y * g[k].y;
        }
        j
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rounding allowance for a few products of O(1) numbers.
    const ROUNDING: f64 = 1e-14;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= ROUNDING * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn jacobian_of_an_affine_map_is_its_linear_part() {
        let v = vec![
            Point::new(0.3, 0.1),
            Point::new(2.0, 0.4),
            Point::new(0.7, 1.9),
        ];
        let mesh = TriMesh::new(v.clone(), vec![[0, 1, 2]]).unwrap();
        let rest = TriangleGradients::new(&mesh);
        assert!(close(rest.area[0], mesh.signed_area(0)));
        let (a, b, c, d) = (1.3, -0.4, 0.25, 0.8);
        let u: Vec<Point> = v
            .iter()
            .map(|p| Point::new(a * p.x + b * p.y + 5.0, c * p.x + d * p.y - 2.0))
            .collect();
        let j = rest.jacobian(0, &u);
        assert!(
            close(j.a, a) && close(j.b, b) && close(j.c, c) && close(j.d, d),
            "{j:?}"
        );
    }

    #[test]
    fn split_gives_singular_values_and_closest_rotation() {
        // J = Rot(0.7) · diag(2, −0.5) · Rot(−0.2): singular values 2 and 0.5, det < 0.
        let rot = |t: f64| [[t.cos(), -t.sin()], [t.sin(), t.cos()]];
        let mul = |x: [[f64; 2]; 2], y: [[f64; 2]; 2]| {
            let mut z = [[0.0; 2]; 2];
            for i in 0..2 {
                for j in 0..2 {
                    z[i][j] = x[i][0] * y[0][j] + x[i][1] * y[1][j];
                }
            }
            z
        };
        let m = mul(mul(rot(0.7), [[2.0, 0.0], [0.0, -0.5]]), rot(-0.2));
        let s = Jacobian {
            a: m[0][0],
            b: m[0][1],
            c: m[1][0],
            d: m[1][1],
        }
        .split();
        assert!(close(s.q + s.r, 2.0) && close(s.q - s.r, -0.5), "{s:?}");
        // Brute force: the best rotation angle maximises tr(Rᵀ J) = cos θ (a + d) + sin θ (c − b).
        let (cos, sin) = s.closest_rotation();
        let best = (0..100_000)
            .map(|k| k as f64 * std::f64::consts::TAU / 100_000.0)
            .max_by(|x, y| {
                let score = |t: f64| t.cos() * (m[0][0] + m[1][1]) + t.sin() * (m[1][0] - m[0][1]);
                score(*x).total_cmp(&score(*y))
            })
            .unwrap();
        assert!((cos - best.cos()).abs() < 1e-4 && (sin - best.sin()).abs() < 1e-4);
        // ‖J − R‖² from its entries.
        let direct = (m[0][0] - cos).powi(2)
            + (m[0][1] + sin).powi(2)
            + (m[1][0] - sin).powi(2)
            + (m[1][1] - cos).powi(2);
        assert!(close(s.arap_density(), direct));
    }
}
