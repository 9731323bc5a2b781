//! Which curve points the pins of a drawing hold ([`crate::SplineJoin::new`]):
//! a pin placed on a stroke holds the curve point under it, constrained to the deformation there
//! in the join's fit; a pin inside a fill holds nothing.

use kurbo::{CubicBez, ParamCurve, ParamCurveNearest, Point};
use splineskin_core::drawing::Drawing;

/// Largest distance from a pin to the drawing's curves at which the nearest curve point is
/// held by it ([`SplineJoin::new`]), as a fraction of the mesh's bounding-box diagonal: 0.002
/// (a pin placed on a stroke holds the curve under it; a pin inside a fill holds nothing: held
/// there, the nearest curve, say a small decoration near an arm's tip, would be bent to the
/// deformation's sharpest point).
///
/// [`SplineJoin::new`]: crate::SplineJoin::new
pub const PIN_SNAP_FRACTION: f64 = 0.002;

/// A curve point a pin holds: curve `curve` of its path at `t`, rest point `point`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Held {
    pub(crate) curve: usize,
    pub(crate) t: f64,
    pub(crate) point: Point,
}

/// For each path, the curve points the pins hold: each pin's nearest curve point over the
/// drawing when within `snap`; per curve the nearest pin's; none equal to another's point
/// (an anchor shared by two curves is held once).
pub(crate) fn held_points(drawing: &Drawing, pins: &[Point], snap: f64) -> Vec<Vec<Held>> {
    let mut held: Vec<Vec<(Held, f64)>> = vec![Vec::new(); drawing.paths.len()];
    for &pin in pins {
        let mut best: Option<(usize, Held, f64)> = None;
        for (pi, path) in drawing.paths.iter().enumerate() {
            for j in 0..path.n_curves() {
                let [p0, p1, p2, p3] = path.curve_points(j);
                let nearest = CubicBez::new(p0, p1, p2, p3).nearest(pin, 1e-12 * snap.max(1e-300));
                let d = nearest.distance_sq.sqrt();
                if d <= snap && best.as_ref().is_none_or(|b| d < b.2) {
                    let point = CubicBez::new(p0, p1, p2, p3).eval(nearest.t);
                    best = Some((
                        pi,
                        Held {
                            curve: j,
                            t: nearest.t,
                            point,
                        },
                        d,
                    ));
                }
            }
        }
        let Some((pi, h, d)) = best else { continue };
        let same_point = |o: &Held| (o.point - h.point).hypot() <= 1e-9 * snap;
        match held[pi]
            .iter()
            .position(|(o, _)| o.curve == h.curve || same_point(o))
        {
            Some(k) if held[pi][k].1 > d => held[pi][k] = (h, d),
            Some(_) => {}
            None => held[pi].push((h, d)),
        }
    }
    held.into_iter()
        .map(|v| v.into_iter().map(|(h, _)| h).collect())
        .collect()
}
