//! Paint that follows the deformation: a gradient's end points keyframed through its element's
//! map at each frame ([`Writer::follow_gradient`]), or, where Lottie cannot draw the gradient in
//! root user space (a stretched radial, a sheared linear), a group drawn in the gradient's own
//! space whose transform is that map ([`Writer::gradient_space_group`], [`LottieParts`]).

use kurbo::{Point, Rect};
use serde_json::{json, Value};

use super::keyframes::{keyframes, keyframes_by};
use super::paint::Style;
use super::{bezier, group_transform, property, Kind, Writer};

impl Writer<'_> {
    /// The group of an element's fill drawn in its gradient's space (paint's [`Style::space`]):
    /// the element's paths mapped by `G_f⁻¹` at each frame `f`, the fill `value` (geometry in
    /// gradient units, `ends` its end points there), and a group transform `G_f = A_f · m`
    /// (`A_f` the element's map at frame `f`, `m` gradient units → root user space at rest),
    /// written as Lottie's position, rotation, skew and scale:
    ///
    /// ```text
    /// G(x) = p + R(r) · [[1, −tan sk], [0, 1]] · diag(s_x, s_y) · x
    /// A = [[a, c], [b, d]]:  r = atan2(b, a),  s_x = |(a, b)|,  s_y = det A / s_x,
    ///                        tan(−sk) = ((a, b) · (c, d)) / (s_x s_y),  p = (e, f)
    /// ```
    ///
    /// Frames are kept where the player's interpolation of the vertices and of those parts,
    /// composed, strays from the deformed paths or the gradient's mapped geometry by more than
    /// the tolerance ([`keyframes_by`]). `count`: its path keyframes count in the export's total
    /// (not when a stroke group writes the same paths). `None` when some `G_f` is singular.
    pub(super) fn gradient_space_group(
        &mut self,
        element: usize,
        m: kurbo::Affine,
        ends: [Point; 2],
        value: Value,
        count: bool,
    ) -> Option<Value> {
        let e = &self.source.elements[element];
        let paths: Vec<usize> = e.paths.clone().collect();
        let n = self.frames.len();
        let server = self.source.elements[element].paint.fill_server.clone();
        let carried = self.paint_maps(element, server.as_deref());
        let g: Vec<kurbo::Affine> = (0..n)
            .map(|f| carried.as_ref().map_or(kurbo::Affine::IDENTITY, |a| a[f]) * m)
            .collect();
        if g.iter()
            .any(|g| !(g.determinant().abs() > 0.0 && g.determinant().is_finite()))
        {
            return None;
        }
        let mut parts: Vec<LottieParts> = g.iter().map(|&g| LottieParts::of(g)).collect();
        // Turns continuous from frame to frame (the player interpolates the angle itself).
        for f in 1..n {
            let previous = parts[f - 1].rotation;
            let turns = ((previous - parts[f].rotation) / 360.0).round();
            parts[f].rotation += 360.0 * turns;
        }
        // Per frame: every path's points in gradient units, and in root space.
        let ranges: Vec<std::ops::Range<usize>> = paths
            .iter()
            .map(|&pi| self.offsets[pi]..self.offsets[pi] + self.drawing.paths[pi].points.len())
            .collect();
        let local: Vec<Vec<Point>> = (0..n)
            .map(|f| {
                let inverse = g[f].inverse();
                ranges
                    .iter()
                    .flat_map(|r| self.frames[f][r.clone()].iter().map(move |&p| inverse * p))
                    .collect()
            })
            .collect();
        let root: Vec<Vec<Point>> = (0..n)
            .map(|f| {
                ranges
                    .iter()
                    .flat_map(|r| self.frames[f][r.clone()].iter().copied())
                    .collect()
            })
            .collect();
        // The gradient's geometry: its end points and the point square to them.
        let axis = ends[1] - ends[0];
        let gradient_points = [
            ends[0],
            ends[1],
            ends[0] + kurbo::Vec2::new(-axis.y, axis.x),
        ];
        let tolerance2 = self.tolerance * self.tolerance;
        let numbers = &self.frame_numbers;
        let kept = keyframes_by(n, |a, b| {
            (a + 1..b).all(|k| {
                let u = (numbers[k] - numbers[a]) / (numbers[b] - numbers[a]);
                let shown = parts[a].lerp(&parts[b], u).affine();
                let paths_ok = local[k].iter().enumerate().all(|(i, _)| {
                    let v = local[a][i].lerp(local[b][i], u);
                    (shown * v - root[k][i]).hypot2() <= tolerance2
                });
                paths_ok
                    && gradient_points
                        .iter()
                        .all(|&q| (shown * q - g[k] * q).hypot2() <= tolerance2)
            })
        });
        if count {
            self.keyframes += kept.len() * paths.len();
        }
        let mut items: Vec<Value> = Vec::new();
        let mut start = 0;
        for (&pi, range) in paths.iter().zip(&ranges) {
            let path = &self.drawing.paths[pi];
            let closed = path.closed && !self.source.closed_without_z[pi];
            let len = range.len();
            let ks = property(&kept, numbers, Kind::Shape, |f| {
                bezier(path, &local[f][start..start + len], closed, None)
            });
            items.push(json!({"ty": "sh", "nm": format!("path {pi} in gradient space"), "ks": ks}));
            start += len;
        }
        items.push(value);
        let mut transform = group_transform(1.0);
        transform["p"] = property(&kept, numbers, Kind::Vector, |f| json!(parts[f].position));
        transform["s"] = property(&kept, numbers, Kind::Vector, |f| json!(parts[f].scale));
        transform["r"] = property(&kept, numbers, Kind::Scalar, |f| json!(parts[f].rotation));
        transform["sk"] = property(&kept, numbers, Kind::Scalar, |f| json!(parts[f].skew));
        if parts.iter().any(|p| p.skew.abs() > 1e-9) {
            let label = &self.source.elements[element].label;
            self.warnings.player(format!(
                "{label}: rlottie (1.3.8) ignores the skew (`sk`) of the group that draws its fill \
                 gradient in the gradient's own space: the shape and its gradient are drawn \
                 sheared otherwise"
            ));
        }
        items.push(transform);
        Some(json!({"ty": "gr", "nm": "fill in gradient space", "it": items}))
    }

    /// The map carrying element `element`'s paint server `server` (a gradient's id) from rest
    /// to each frame, root user space: for a gradient in `objectBoundingBox` units, from the
    /// element's bounding box at rest to its deformed one (in its local coordinates, as SVG
    /// measures it: `L · B_f · B₀⁻¹ · L⁻¹`, `B` the unit square → box map, `L` local → root);
    /// otherwise the element's maps, or `None` without them.
    pub(super) fn paint_maps(
        &self,
        element: usize,
        server: Option<&str>,
    ) -> Option<Vec<kurbo::Affine>> {
        if server.is_some_and(|id| self.bbox_servers.contains(id)) {
            let e = &self.source.elements[element];
            let to_local = e.local_to_root.inverse();
            let rest = local_bbox(
                to_local,
                e.paths
                    .clone()
                    .map(|pi| self.drawing.paths[pi].points.as_slice()),
            )?;
            let back = unit_to(rest).inverse();
            return Some(
                self.frames
                    .iter()
                    .map(|frame| {
                        let chains = e.paths.clone().map(|pi| {
                            &frame[self.offsets[pi]
                                ..self.offsets[pi] + self.drawing.paths[pi].points.len()]
                        });
                        match local_bbox(to_local, chains) {
                            Some(b) => e.local_to_root * unit_to(b) * back * to_local,
                            None => kurbo::Affine::IDENTITY,
                        }
                    })
                    .collect(),
            );
        }
        self.maps.map(|maps| {
            maps.iter()
                .map(|m| m.element_map(element).unwrap_or(kurbo::Affine::IDENTITY))
                .collect()
        })
    }

    /// Keyframes a gradient style's end points (`s`, `e`) through the element's map at each
    /// frame, where they move (a colour style is left alone). Without maps the gradient stays
    /// at rest, with a warning.
    pub(super) fn follow_gradient(
        &mut self,
        style: &mut Style,
        element: usize,
        server: Option<&str>,
    ) {
        let Some(ends) = style.ends else {
            return;
        };
        let Some(maps) = self.paint_maps(element, server) else {
            let label = &self.source.elements[element].label;
            self.warnings.add(format!(
                "{label}: its gradient is written at rest (no element maps were given)"
            ));
            return;
        };
        let per_frame: Vec<[Point; 2]> = maps.iter().map(|&a| ends.map(|p| a * p)).collect();
        let views: Vec<&[Point]> = per_frame.iter().map(|f| f.as_slice()).collect();
        let kept = keyframes(&views, &self.frame_numbers, self.tolerance);
        for (k, key) in ["s", "e"].into_iter().enumerate() {
            style.value[key] = property(&kept, &self.frame_numbers, Kind::Vector, |f| {
                let p = per_frame[f][k];
                json!([p.x, p.y])
            });
        }
    }
}

/// The tight bounding box of the cubic chains `chains` (root user space) mapped by `to_local`;
/// `None` when it has no area (SVG draws no `objectBoundingBox` paint then).
fn local_bbox<'a>(
    to_local: kurbo::Affine,
    chains: impl Iterator<Item = &'a [Point]>,
) -> Option<Rect> {
    let mut path = kurbo::BezPath::new();
    for chain in chains {
        let Some(&first) = chain.first() else {
            continue;
        };
        path.move_to(to_local * first);
        for c in chain[1..].chunks_exact(3) {
            path.curve_to(to_local * c[0], to_local * c[1], to_local * c[2]);
        }
    }
    let b = kurbo::Shape::bounding_box(&path);
    (b.width() > 0.0 && b.height() > 0.0).then_some(b)
}

/// `x ↦ (x0 + w x, y0 + h y)`: unit square → `rect`.
fn unit_to(rect: Rect) -> kurbo::Affine {
    kurbo::Affine::new([rect.width(), 0.0, 0.0, rect.height(), rect.x0, rect.y0])
}

/// An affine map as a Lottie group transform's parts (anchor at the origin):
/// `x ↦ p + R(r) · [[1, −tan sk], [0, 1]] · diag(s_x, s_y) · x`, angles in degrees, scales in
/// percent (lottie-web's transform order: scale, skew, rotation, position).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LottieParts {
    pub(super) position: [f64; 2],
    pub(super) scale: [f64; 2],
    pub(super) rotation: f64,
    pub(super) skew: f64,
}

impl LottieParts {
    /// The parts of `g` (invertible): a QR factorisation of its linear part.
    pub(super) fn of(g: kurbo::Affine) -> LottieParts {
        let [a, b, c, d, e, f] = g.as_coeffs();
        let sx = a.hypot(b);
        let (cos, sin) = (a / sx, b / sx);
        let along = cos * c + sin * d;
        let sy = -sin * c + cos * d;
        LottieParts {
            position: [e, f],
            scale: [100.0 * sx, 100.0 * sy],
            rotation: b.atan2(a).to_degrees(),
            skew: -(along / sy).atan().to_degrees(),
        }
    }

    /// The map these parts draw.
    pub(super) fn affine(&self) -> kurbo::Affine {
        let (sin, cos) = self.rotation.to_radians().sin_cos();
        let k = -self.skew.to_radians().tan();
        let (sx, sy) = (self.scale[0] / 100.0, self.scale[1] / 100.0);
        // R · [[sx, k sy], [0, sy]].
        let (a, b) = (cos * sx, sin * sx);
        let (c, d) = (cos * k * sy - sin * sy, sin * k * sy + cos * sy);
        kurbo::Affine::new([a, b, c, d, self.position[0], self.position[1]])
    }

    /// The parts a player shows at fraction `u` from `self` to `other`: each one linearly.
    fn lerp(&self, other: &LottieParts, u: f64) -> LottieParts {
        let l = |x: f64, y: f64| x + u * (y - x);
        LottieParts {
            position: [
                l(self.position[0], other.position[0]),
                l(self.position[1], other.position[1]),
            ],
            scale: [
                l(self.scale[0], other.scale[0]),
                l(self.scale[1], other.scale[1]),
            ],
            rotation: l(self.rotation, other.rotation),
            skew: l(self.skew, other.skew),
        }
    }
}
