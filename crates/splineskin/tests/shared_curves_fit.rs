//! Shared curves and small pieces (issue 15): a 2 × 2 piece whose sides are shared with two
//! 48-unit bars, pulled by a handle on its corner. Paths that share curves are fitted as one
//! system; summed in absolute units, the bars' errors (a few percent of 48 units) would
//! outweigh the piece's whole size and the piece would be bent out of shape to spare them.
//! With each member weighed by its own size, the piece is fitted about as well as alone,
//! relative to its size, while every shared curve stays one curve.

use kurbo::{Affine, Point, Vec2};
use splineskin::bezier;
use splineskin::drawing::{read_svg, Drawing, ImportOptions};
use splineskin::metrics::target_samples;
use splineskin::spline_fit::{FitOptions, SplineRig};
use splineskin::weights::shepard::{Shepard, ShepardOptions};

/// The piece (path 0), a horizontal bar sharing the piece's left side (path 1) and a vertical
/// bar sharing its top side (path 2), both run the other way by the bars.
const SVG: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="-2 -2 56 56">
  <path d="M48 0 H50 V2 H48 Z"/>
  <path d="M0 0 H48 V2 H0 Z"/>
  <path d="M48 2 H50 V50 H48 Z"/>
</svg>"##;

/// Samples per curve at which fit and target are compared.
const SAMPLES: usize = 17;

/// Each path's largest distance from the skinned target over its own control-box diagonal,
/// with shared-curve fitting on or off.
fn relative_errors(drawing: &Drawing, share: bool) -> Vec<f64> {
    let handles = [(50.0, 0.0), (0.0, 1.0), (49.0, 50.0)].map(Point::from);
    let field = Shepard::new(&handles, ShepardOptions::default());
    let rig = SplineRig::precompute(
        drawing,
        &field,
        &FitOptions::default().with_share_curves(share),
    )
    .expect("precompute");
    let d = drawing.diagonal();
    let pose = [
        Affine::translate(Vec2::new(0.6, 0.8) * (0.15 * d)),
        Affine::rotate_about(30f64.to_radians(), handles[1]),
        Affine::IDENTITY,
    ];
    let mut out = vec![Point::ZERO; rig.n_points()];
    rig.update(&pose, &mut out).expect("update");
    let targets = target_samples(drawing, &field, &pose, SAMPLES);
    let mut targets = targets.iter();
    drawing
        .paths
        .iter()
        .zip(drawing.path_ranges())
        .map(|(path, range)| {
            let got = &out[range];
            let mut error = 0.0f64;
            for j in 0..path.n_curves() {
                let c = [got[3 * j], got[3 * j + 1], got[3 * j + 2], got[3 * j + 3]];
                for (k, target) in (0..SAMPLES).zip(&mut targets) {
                    let t = k as f64 / (SAMPLES - 1) as f64;
                    error = error.max((bezier::eval(&c, t) - *target).hypot());
                }
            }
            let r = kurbo::Rect::from_points(path.points[0], path.points[0]);
            let r = path.points.iter().fold(r, |r, &p| r.union_pt(p));
            error / (r.width().hypot(r.height()))
        })
        .collect()
}

/// Largest distance of the piece from its target, relative to its diagonal, fitted with the
/// bars: 5 %. Measured: 2.7 % (alone 0.08 %: its sides are the bars' sides, which follow the
/// bars); summed in absolute units, 37 %.
const PIECE_BOUND: f64 = 0.05;

/// How much larger a bar's relative error may be fitted with its neighbours than alone: 1.25.
/// Measured: 1.10 and 1.03.
const BAR_FACTOR: f64 = 1.25;

#[test]
fn a_small_piece_sharing_sides_with_long_bars_is_fitted_as_well_as_alone() {
    let drawing = read_svg(SVG, &ImportOptions::default()).expect("read");
    let alone = relative_errors(&drawing, false);
    let shared = relative_errors(&drawing, true);
    println!("relative errors, alone: {alone:.4?}; shared: {shared:.4?}");
    assert!(
        shared[0] <= PIECE_BOUND,
        "the piece: {:.4} of its diagonal from the target fitted with the bars ({:.4} alone)",
        shared[0],
        alone[0]
    );
    for p in 1..3 {
        assert!(
            shared[p] <= BAR_FACTOR * alone[p],
            "bar {p}: {:.4} of its diagonal fitted with its neighbours, {:.4} alone",
            shared[p],
            alone[p]
        );
    }
}
