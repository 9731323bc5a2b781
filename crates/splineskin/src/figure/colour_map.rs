//! Colour maps of the pictures.
//!
//! **Weights** ([`weight_colour`]): viridis on `[0, 1]`, and two ramps of hues viridis never uses
//! for values below 0 and above 1 (the negative lobes and overshoots of unbounded families such
//! as biharmonic weights), so that out-of-range values cannot be mistaken for in-range ones.
//!
//! ```text
//!   −0.5 ◄── crimson … coral │ viridis: purple → blue → teal → green → yellow │ pink … magenta ──► 1.5
//!   (below, saturated at −FULL)  0                                         1    (above, saturated at 1 + FULL)
//! ```
//!
//! **Viridis** (van der Walt & Smith, matplotlib's default colour map since 2.0) is a sequential
//! map designed to be perceptually uniform, legible in greyscale and to readers with the common
//! colour-vision deficiencies. Here it is its nine colours at `t = 0, 1/8, …, 1` (matplotlib's
//! published values, rounded to 8 bits), interpolated linearly in sRGB: lightness stays
//! monotone, which is what reading a weight off the picture needs.
//!
//! **Errors** ([`error_colour`], the comparison pictures of [`crate::compare`]): plasma (the
//! same authors' sibling map, dark blue → magenta → orange) on its range `[0, 7/8]`, so that the
//! largest error is a saturated orange that reads on a white background, where viridis's and
//! plasma's pale yellow ends would not. Its dark blue zero is far from the grey of the curves
//! drawn with it.

/// Viridis at `t = k/8`, `k = 0…8`, 8-bit sRGB.
pub const VIRIDIS_KNOTS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// Plasma at `t = k/8`, `k = 0…7`, 8-bit sRGB (matplotlib's published values, rounded); its
/// pale yellow end (`t = 1`) is left out: see the module doc.
pub const PLASMA_KNOTS: [[u8; 3]; 8] = [
    [13, 8, 135],
    [75, 3, 161],
    [125, 3, 168],
    [168, 34, 150],
    [203, 70, 121],
    [229, 107, 93],
    [248, 148, 65],
    [253, 195, 40],
];

/// How far out of `[0, 1]` a value must be to be drawn as out of range: 1e-6 weight units.
/// Bounded families (Shepard, harmonic, bounded biharmonic) leave `[0, 1]` only by rounding,
/// a few units of 1e-16; a lobe of an unbounded family that matters is orders of magnitude
/// larger.
pub const OUT_OF_RANGE_TOLERANCE: f64 = 1e-6;

/// Excess beyond `[0, 1]` at which the out-of-range ramps reach their deepest colour: 0.5
/// weight units (half the whole range; biharmonic lobes on drawings are typically a few
/// hundredths to a few tenths).
pub const OUT_OF_RANGE_FULL: f64 = 0.5;

/// Colour just below 0 (light coral) …
pub const BELOW_LIGHT: [u8; 3] = [255, 128, 96];
/// … to at or below `−OUT_OF_RANGE_FULL` (crimson).
pub const BELOW_DEEP: [u8; 3] = [160, 0, 24];
/// Colour just above 1 (light pink) …
pub const ABOVE_LIGHT: [u8; 3] = [255, 184, 232];
/// … to at or above `1 + OUT_OF_RANGE_FULL` (magenta).
pub const ABOVE_DEEP: [u8; 3] = [190, 0, 160];

/// Viridis at `t`, clamped to `[0, 1]` (NaN gives the colour of 0).
///
/// ```
/// use splineskin::figure::colour_map::{viridis, VIRIDIS_KNOTS};
/// assert_eq!(viridis(0.0), VIRIDIS_KNOTS[0]);
/// assert_eq!(viridis(1.0), [253, 231, 37]);
/// assert_eq!(viridis(0.5), VIRIDIS_KNOTS[4]);
/// assert_eq!(viridis(7.0), viridis(1.0));
/// ```
pub fn viridis(t: f64) -> [u8; 3] {
    piecewise_linear(&VIRIDIS_KNOTS, t)
}

/// The colour of a normalised error `e` (0 exact, 1 the largest error shown): plasma's knots
/// [`PLASMA_KNOTS`] spread evenly over `[0, 1]`, `e` clamped to `[0, 1]` (NaN gives the colour
/// of 0).
///
/// ```
/// use splineskin::figure::colour_map::{error_colour, PLASMA_KNOTS};
/// assert_eq!(error_colour(0.0), PLASMA_KNOTS[0]);
/// assert_eq!(error_colour(1.0), PLASMA_KNOTS[7]);
/// assert_eq!(error_colour(3.0 / 7.0), PLASMA_KNOTS[3]);
/// assert_eq!(error_colour(-1.0), error_colour(0.0));
/// ```
pub fn error_colour(e: f64) -> [u8; 3] {
    piecewise_linear(&PLASMA_KNOTS, e)
}

/// The colour at `t` (clamped to `[0, 1]`, NaN as 0) of the map through `knots` at even
/// spacing, interpolated linearly in sRGB.
fn piecewise_linear(knots: &[[u8; 3]], t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let last = knots.len() - 1;
    let x = t * last as f64;
    let k = (x.floor() as usize).min(last - 1);
    mix(knots[k], knots[k + 1], x - k as f64)
}

/// Where a weight value falls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Range {
    /// Below `−OUT_OF_RANGE_TOLERANCE`.
    Below,
    /// Within `[0, 1]` up to [`OUT_OF_RANGE_TOLERANCE`].
    Within,
    /// Above `1 + OUT_OF_RANGE_TOLERANCE`.
    Above,
}

/// Classifies `w` against `[0, 1]` with [`OUT_OF_RANGE_TOLERANCE`].
pub fn range_of(w: f64) -> Range {
    if w < -OUT_OF_RANGE_TOLERANCE {
        Range::Below
    } else if w > 1.0 + OUT_OF_RANGE_TOLERANCE {
        Range::Above
    } else {
        Range::Within
    }
}

/// The colour of weight `w`: [`viridis`] within `[0, 1]` (up to [`OUT_OF_RANGE_TOLERANCE`]),
/// otherwise the below or above ramp, from its light end just outside the range to its deep
/// end [`OUT_OF_RANGE_FULL`] beyond it.
///
/// ```
/// use splineskin::figure::colour_map::*;
/// assert_eq!(weight_colour(1.0), viridis(1.0));
/// assert_eq!(weight_colour(-1e-12), viridis(0.0)); // rounding is not a lobe
/// assert_eq!(weight_colour(-0.5), BELOW_DEEP);
/// assert_eq!(weight_colour(2.0), ABOVE_DEEP);
/// assert_ne!(weight_colour(-0.01), viridis(0.0));
/// ```
pub fn weight_colour(w: f64) -> [u8; 3] {
    match range_of(w) {
        Range::Within => viridis(w),
        Range::Below => ramp(BELOW_LIGHT, BELOW_DEEP, -w),
        Range::Above => ramp(ABOVE_LIGHT, ABOVE_DEEP, w - 1.0),
    }
}

/// The out-of-range ramp from `light` to `deep` at excess `e > 0`.
fn ramp(light: [u8; 3], deep: [u8; 3], e: f64) -> [u8; 3] {
    mix(light, deep, (e / OUT_OF_RANGE_FULL).min(1.0))
}

/// `a + s (b − a)` per channel, rounded; `s ∈ [0, 1]`.
pub(crate) fn mix(a: [u8; 3], b: [u8; 3], s: f64) -> [u8; 3] {
    let channel =
        |k: usize| (f64::from(a[k]) + s * (f64::from(b[k]) - f64::from(a[k]))).round() as u8;
    [channel(0), channel(1), channel(2)]
}

/// Relative luminance of an sRGB colour in `[0, 1]` (ITU-R BT.709 weights on the encoded
/// values: a cheap ordering of light and dark, enough to pick a contrasting line colour).
pub(crate) fn luma(c: [u8; 3]) -> f64 {
    (0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2])) / 255.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Asserts that the luma of `colour(t)` never falls by more than `slack` between
    /// neighbouring samples `t = k / 1000` of `[0, 1]`.
    fn assert_luma_rises(colour: impl Fn(f64) -> [u8; 3], slack: f64) {
        let mut previous = -1.0;
        for k in 0..=1000 {
            let l = luma(colour(f64::from(k) / 1000.0));
            assert!(l >= previous - slack, "t = {}: {l} < {previous}", k);
            previous = l;
        }
    }

    #[test]
    fn viridis_lightness_is_monotone() {
        assert_luma_rises(viridis, 1e-3);
        assert!(luma(viridis(1.0)) - luma(viridis(0.0)) > 0.7);
    }

    #[test]
    fn error_colour_lightness_is_monotone_and_reads_on_white() {
        // BT.709 luma on encoded values is a rough lightness: plasma's first knots trade
        // blue for red and dip by 2e-3 in it.
        assert_luma_rises(error_colour, 5e-3);
        // The largest error is no lighter than 0.8 (white is 1).
        assert!(luma(error_colour(1.0)) < 0.8);
    }

    #[test]
    fn viridis_passes_through_its_knots() {
        for (k, knot) in VIRIDIS_KNOTS.iter().enumerate() {
            assert_eq!(viridis(k as f64 / 8.0), *knot, "knot {k}");
        }
        // Halfway between two knots: their rounded mean.
        assert_eq!(viridis(1.0 / 16.0), [70, 23, 103]);
    }

    #[test]
    fn weight_colour_out_of_range_is_off_viridis() {
        // No out-of-range colour is within 40 levels (per channel, max norm) of any viridis
        // colour: they cannot be read as in-range values.
        let distance = |a: [u8; 3], b: [u8; 3]| {
            (0..3)
                .map(|k| (i32::from(a[k]) - i32::from(b[k])).abs())
                .max()
                .unwrap()
        };
        for e in [1e-5, 0.01, 0.1, 0.25, 0.5, 3.0] {
            for c in [weight_colour(-e), weight_colour(1.0 + e)] {
                let nearest = (0..=256)
                    .map(|k| distance(c, viridis(f64::from(k) / 256.0)))
                    .min()
                    .unwrap();
                assert!(nearest > 40, "excess {e}: {c:?} is {nearest} from viridis");
            }
        }
        assert_eq!(weight_colour(-OUT_OF_RANGE_TOLERANCE / 2.0), viridis(0.0));
        assert_eq!(
            weight_colour(1.0 + OUT_OF_RANGE_TOLERANCE / 2.0),
            viridis(1.0)
        );
        assert_eq!(weight_colour(-2e-6), BELOW_LIGHT);
        assert_eq!(range_of(f64::NAN), Range::Within);
    }
}
