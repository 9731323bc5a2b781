//! A small software rasteriser for pictures of surfaces: z-buffered triangles, flat Lambert
//! shading, a colour per vertex interpolated across each triangle, orthographic camera.
//!
//! ```text
//! view direction  d = cos el · (sin az · s + cos az · f) + sin el · u
//!                 (u the up axis; f, s the next axes cyclically: for y up, f = z and s = x,
//!                  so az = el = 0 looks down −z)
//! screen          x_s = s·(p − c)·right + W/2,   y_s = H/2 − s·(p − c)·up,   depth = (p − c)·d
//! shade           AMBIENT + (1 − AMBIENT)·|n̂·l̂|   (two-sided; l̂ the light, from over the viewer's left shoulder)
//! ```
//!
//! A [`Camera`] is fitted to a set of points so that their bounding box fills the image
//! with a margin. Pixels are sampled at their centres; [`Raster::to_rgba`] downsamples a
//! supersampled raster by box filtering.

use splineskin_core::mesh::vec3::{cross, dot, norm, sub};
use splineskin_subdiv::Point3;

/// Share of light every lit surface gets whatever its orientation: 0.35.
pub const AMBIENT: f64 = 0.35;

/// Fraction of the image the fitted bounding box's extent spans: 0.92.
pub const FILL: f64 = 0.92;

/// Direction towards the light in camera coordinates (right, up, towards the viewer), before
/// normalisation: from the upper left, in front (the usual key light of product shots).
pub const LIGHT: [f64; 3] = [-0.4, 0.6, 0.7];

/// An orthographic camera (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    centre: Point3,
    right: Point3,
    up: Point3,
    /// Towards the viewer.
    back: Point3,
    scale: f64,
    width: u32,
    height: u32,
}

impl Camera {
    /// A camera looking at `points` from azimuth `az` and elevation `el` (radians) about the
    /// up axis `up` (0, 1, 2 for x, y, z; module documentation), fitted to their bounding
    /// box: its centre in the middle of the image, the box's extent along the image axes
    /// filling `FILL` (0.92) of it.
    pub fn fit(points: &[Point3], up: usize, az: f64, el: f64, width: u32, height: u32) -> Camera {
        let axis = |k: usize| {
            let mut e = [0.0; 3];
            e[k % 3] = 1.0;
            e
        };
        let (u, f, s) = (axis(up), axis(up + 1), axis(up + 2));
        let (sa, ca) = az.sin_cos();
        let (se, ce) = el.sin_cos();
        let back: Point3 = std::array::from_fn(|k| ce * (sa * s[k] + ca * f[k]) + se * u[k]);
        let right = {
            let r = cross(u, back);
            let n = norm(r);
            r.map(|x| x / n)
        };
        let up = cross(back, right);
        let (lo, hi) = splineskin_subdiv::bounds3(points);
        let centre: Point3 = std::array::from_fn(|k| 0.5 * (lo[k] + hi[k]));
        let (mut ex, mut ey) = (0.0f64, 0.0f64);
        for p in points {
            let d = sub(*p, centre);
            ex = ex.max(dot(d, right).abs());
            ey = ey.max(dot(d, up).abs());
        }
        let sx = if ex > 0.0 {
            FILL * 0.5 * f64::from(width) / ex
        } else {
            1.0
        };
        let sy = if ey > 0.0 {
            FILL * 0.5 * f64::from(height) / ey
        } else {
            1.0
        };
        Camera {
            centre,
            right,
            up,
            back,
            scale: sx.min(sy).min(1e300),
            width,
            height,
        }
    }

    /// The aspect ratio (height over width) of `points` seen from `(up, az, el)`: for choosing an
    /// image size before fitting.
    pub fn aspect(points: &[Point3], up: usize, az: f64, el: f64) -> f64 {
        let c = Camera::fit(points, up, az, el, 1000, 1000);
        let (mut ex, mut ey) = (0.0f64, 0.0f64);
        for p in points {
            let d = sub(*p, c.centre);
            ex = ex.max(dot(d, c.right).abs());
            ey = ey.max(dot(d, c.up).abs());
        }
        if ex > 0.0 {
            ey / ex
        } else {
            1.0
        }
    }

    /// `(x, y, depth)` of `p` on the screen; larger depth is nearer the viewer.
    pub fn project(&self, p: Point3) -> [f64; 3] {
        let d = sub(p, self.centre);
        [
            0.5 * f64::from(self.width) + self.scale * dot(d, self.right),
            0.5 * f64::from(self.height) - self.scale * dot(d, self.up),
            dot(d, self.back),
        ]
    }

    /// The light direction: from the upper left, in front of the viewer.
    fn light(&self) -> Point3 {
        let l: Point3 = std::array::from_fn(|k| {
            LIGHT[0] * self.right[k] + LIGHT[1] * self.up[k] + LIGHT[2] * self.back[k]
        });
        let n = norm(l);
        l.map(|x| x / n)
    }
}

/// A colour and depth buffer.
#[derive(Clone, Debug)]
pub struct Raster {
    width: u32,
    height: u32,
    colour: Vec<[f64; 3]>,
    depth: Vec<f64>,
}

impl Raster {
    /// A `width × height` raster cleared to `background` (linear 0..1 RGB) at infinite depth.
    pub fn new(width: u32, height: u32, background: [f64; 3]) -> Raster {
        let n = width as usize * height as usize;
        Raster {
            width,
            height,
            colour: vec![background; n],
            depth: vec![f64::NEG_INFINITY; n],
        }
    }

    /// Draws the triangles `triangles` of the points `positions` seen by `camera`, vertex `v`
    /// coloured `colours[v]` (0..1 RGB), interpolated linearly, times the triangle's flat
    /// Lambert shade.
    pub fn draw(
        &mut self,
        camera: &Camera,
        positions: &[Point3],
        triangles: &[[u32; 3]],
        colours: &[[f64; 3]],
    ) {
        let light = camera.light();
        let screen: Vec<[f64; 3]> = positions.iter().map(|p| camera.project(*p)).collect();
        for t in triangles {
            let [a, b, c] = t.map(|v| v as usize);
            let n = cross(
                sub(positions[b], positions[a]),
                sub(positions[c], positions[a]),
            );
            let len = norm(n);
            if len.is_nan() || len <= 0.0 {
                continue;
            }
            let shade = AMBIENT + (1.0 - AMBIENT) * (dot(n, light) / len).abs();
            let (p0, p1, p2) = (screen[a], screen[b], screen[c]);
            let area = edge(p0, p1, p2);
            if area.abs() <= f64::MIN_POSITIVE {
                continue;
            }
            let x0 = p0[0].min(p1[0]).min(p2[0]).floor().max(0.0) as u32;
            let x1 = (p0[0].max(p1[0]).max(p2[0]).ceil() as i64).min(i64::from(self.width) - 1);
            let y0 = p0[1].min(p1[1]).min(p2[1]).floor().max(0.0) as u32;
            let y1 = (p0[1].max(p1[1]).max(p2[1]).ceil() as i64).min(i64::from(self.height) - 1);
            if x1 < 0 || y1 < 0 {
                continue;
            }
            for y in y0..=y1 as u32 {
                for x in x0..=x1 as u32 {
                    let q = [f64::from(x) + 0.5, f64::from(y) + 0.5, 0.0];
                    let w0 = edge(p1, p2, q) / area;
                    let w1 = edge(p2, p0, q) / area;
                    let w2 = edge(p0, p1, q) / area;
                    if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                        continue;
                    }
                    let z = w0 * p0[2] + w1 * p1[2] + w2 * p2[2];
                    let k = y as usize * self.width as usize + x as usize;
                    if z <= self.depth[k] {
                        continue;
                    }
                    self.depth[k] = z;
                    self.colour[k] = std::array::from_fn(|ch| {
                        shade * (w0 * colours[a][ch] + w1 * colours[b][ch] + w2 * colours[c][ch])
                    });
                }
            }
        }
    }

    /// The raster as 8-bit RGBA, downsampled by `factor` (each output pixel the mean of a
    /// `factor × factor` block; the raster's size must be a multiple of it).
    pub fn to_rgba(&self, factor: u32) -> (u32, u32, Vec<u8>) {
        let f = factor.max(1);
        let (w, h) = (self.width / f, self.height / f);
        let mut out = Vec::with_capacity(w as usize * h as usize * 4);
        let n = f64::from(f * f);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0.0; 3];
                for dy in 0..f {
                    for dx in 0..f {
                        let k = (y * f + dy) as usize * self.width as usize + (x * f + dx) as usize;
                        for ch in 0..3 {
                            sum[ch] += self.colour[k][ch];
                        }
                    }
                }
                for s in sum {
                    out.push((s / n * 255.0).round().clamp(0.0, 255.0) as u8);
                }
                out.push(255);
            }
        }
        (w, h, out)
    }
}

/// Twice the signed area of the screen triangle `(a, b, c)` (the edge function of `c`
/// against `a → b`).
fn edge(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raster_draws_the_nearer_triangle_and_shades() {
        // Two overlapping squares facing the viewer (y up, az = el = 0 looks down −z): the one at
        // z = 1 hides the one at z = 0.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.25, 0.25, 1.0],
            [0.75, 0.25, 1.0],
            [0.75, 0.75, 1.0],
            [0.25, 0.75, 1.0],
        ];
        let tris = [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
        let colours: Vec<[f64; 3]> = (0..8)
            .map(|v| {
                if v < 4 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 0.0, 1.0]
                }
            })
            .collect();
        let camera = Camera::fit(&p, 1, 0.0, 0.0, 100, 100);
        let mut r = Raster::new(100, 100, [1.0; 3]);
        // Far square drawn last: the depth test must keep the near one.
        r.draw(&camera, &p, &tris[2..], &colours);
        r.draw(&camera, &p, &tris[..2], &colours);
        let (w, h, rgba) = r.to_rgba(1);
        assert_eq!((w, h), (100, 100));
        let px = |x: usize, y: usize| &rgba[(y * 100 + x) * 4..][..3];
        // Centre: blue, facing the light at some angle: shaded between AMBIENT and 1.
        let c = px(50, 50);
        assert!(c[0] == 0 && c[1] == 0 && c[2] > 90 && c[2] < 255, "{c:?}");
        // Near a corner of the big square: red. Outside: white.
        let corner = px(8, 8);
        assert!(corner[0] > 90 && corner[2] == 0, "{corner:?}");
        assert_eq!(px(1, 1), &[255, 255, 255]);
    }
}
