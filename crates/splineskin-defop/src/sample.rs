//! [`Sampler`]: random handle configurations `Q_k` around the rest configuration `P`, where a
//! deformation operator is trained (Poranne & Lipman 2016, §3.3, "Defining the samples";
//! DESIGN.md §4).
//!
//! Each configuration moves every handle `ℓ` independently within a [`SampleRegion`] around
//! its rest position `p_ℓ`:
//!
//! | region | `q_ℓ` |
//! |---|---|
//! | [`SampleRegion::Disc`] | uniform in the disc of the radius around `p_ℓ` (`r = R √u`, angle uniform) |
//! | [`SampleRegion::Circle`] | uniform on the circle of the radius around `p_ℓ` |
//! | [`SampleRegion::Gaussian`] | `p_ℓ` plus an isotropic normal offset of the standard deviation (Box–Muller) |
//! | [`SampleRegion::VoronoiCell`] | uniform in `p_ℓ`'s Voronoi cell with respect to `P`, clipped to a rectangle (rejection sampling) |
//!
//! A sampler mixes regions with weights: each configuration draws its region first (the
//! paper's octopus: "with equal probability from discs around the samples, and the samples'
//! Voronoi cells"). The generator is SplitMix64 (Steele, Lea & Flood 2014), seeded, so a seed
//! gives the same configurations on every machine.

use kurbo::{Point, Rect, Vec2};

use super::error::DefOpError;
use super::handles::check_rest_handles;

/// Rejection-sampling draws allowed per handle in a Voronoi cell before giving up: a cell
/// covering 1e-4 of its rectangle would need 1e4 on average; this bounds a cell that is
/// (numerically) empty.
const MAX_REJECTIONS: usize = 1_000_000;

/// Where a handle's sampled position lies relative to its rest position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampleRegion {
    /// Uniform in the disc of this radius (drawing units).
    Disc {
        /// The radius.
        radius: f64,
    },
    /// Uniform on the circle of this radius (drawing units).
    Circle {
        /// The radius.
        radius: f64,
    },
    /// Normal with this standard deviation in each coordinate (drawing units).
    Gaussian {
        /// The standard deviation.
        sigma: f64,
    },
    /// Uniform in the handle's Voronoi cell with respect to the rest handles, within `bounds`
    /// (which must contain every rest handle).
    VoronoiCell {
        /// The rectangle the cells are clipped to.
        bounds: Rect,
    },
}

impl SampleRegion {
    fn check(&self, rest: &[Point]) -> Result<(), DefOpError> {
        let positive = |name: &'static str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(DefOpError::InvalidOption {
                    name,
                    value: value.to_string(),
                    expected: "a finite length > 0 (drawing units)",
                })
            }
        };
        match *self {
            SampleRegion::Disc { radius } | SampleRegion::Circle { radius } => {
                positive("radius", radius)
            }
            SampleRegion::Gaussian { sigma } => positive("sigma", sigma),
            SampleRegion::VoronoiCell { bounds } => {
                let finite = [bounds.x0, bounds.y0, bounds.x1, bounds.y1]
                    .iter()
                    .all(|v| v.is_finite());
                if !finite || bounds.width() <= 0.0 || bounds.height() <= 0.0 {
                    return Err(DefOpError::InvalidOption {
                        name: "bounds",
                        value: format!("{bounds:?}"),
                        expected: "a finite rectangle with positive width and height",
                    });
                }
                if let Some(handle) = rest.iter().position(|&p| !bounds.contains(p)) {
                    return Err(DefOpError::InvalidOption {
                        name: "bounds",
                        value: format!(
                            "{bounds:?} (handle {handle} at {:?} is outside)",
                            rest[handle]
                        ),
                        expected: "a rectangle containing every rest handle",
                    });
                }
                Ok(())
            }
        }
    }
}

/// Draws handle configurations from a weighted mix of [`SampleRegion`]s.
///
/// ```
/// use kurbo::Point;
/// use splineskin_defop::{SampleRegion, Sampler};
/// let rest = [Point::new(0., 0.), Point::new(3., 0.)];
/// let mut sampler = Sampler::new(&rest, &[(SampleRegion::Disc { radius: 0.5 }, 1.0)], 7)?;
/// for q in sampler.configurations(100) {
///     assert!(q.iter().zip(&rest).all(|(q, p)| (*q - *p).hypot() <= 0.5));
/// }
/// # Ok::<(), splineskin_defop::DefOpError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Sampler {
    rest: Vec<Point>,
    /// Regions with their cumulative weights, normalised to end at 1.
    regions: Vec<(SampleRegion, f64)>,
    /// Configurations to cover besides the rest ([`Sampler::with_cover`]), and the share of
    /// samples drawn around the way to them.
    cover: Vec<Vec<Point>>,
    cover_share: f64,
    state: u64,
}

impl Sampler {
    /// A sampler around the rest configuration `rest`, drawing each configuration's region
    /// with probability proportional to its weight, from the generator seeded with `seed`.
    /// Errors on no handle, a non-finite rest position, no region, a weight that is negative
    /// or not finite (or all zero), or a region with a bad size.
    pub fn new(
        rest: &[Point],
        regions: &[(SampleRegion, f64)],
        seed: u64,
    ) -> Result<Sampler, DefOpError> {
        check_rest_handles(rest)?;
        let total: f64 = regions.iter().map(|&(_, w)| w).sum();
        let bad_weight = regions.iter().any(|&(_, w)| !(w.is_finite() && w >= 0.0));
        if regions.is_empty() || bad_weight || !(total > 0.0 && total.is_finite()) {
            return Err(DefOpError::InvalidOption {
                name: "regions",
                value: format!("{regions:?}"),
                expected: "at least one region, weights finite, ≥ 0 and not all 0",
            });
        }
        let mut cumulative = 0.0;
        let mut normalised = Vec::with_capacity(regions.len());
        for &(region, weight) in regions {
            region.check(rest)?;
            cumulative += weight / total;
            normalised.push((region, cumulative));
        }
        Ok(Sampler {
            rest: rest.to_vec(),
            regions: normalised,
            cover: Vec::new(),
            cover_share: 0.0,
            state: seed,
        })
    }

    /// Also covers the configurations `targets` (one point per handle each, e.g. a scene's
    /// poses or its animation's frames): a `share` of the configurations (in `[0, 1]`) is
    /// drawn around a point of the straight way from the rest to a target, both uniform
    /// (target, then fraction `t` of the way), the region's offset added there instead of at
    /// the rest (a Voronoi cell stays the rest's). So an operator trained on them follows
    /// the handles as far as the poses take them, and everywhere on the way. Without targets
    /// or with a share of 0 the configurations are those of [`Sampler::new`].
    ///
    /// Errors on a target with another number of handles or a non-finite point, or a share
    /// outside `[0, 1]`.
    ///
    /// ```
    /// use kurbo::Point;
    /// use splineskin_defop::{SampleRegion, Sampler};
    /// let rest = [Point::new(0., 0.), Point::new(3., 0.)];
    /// let far = vec![Point::new(0., 0.), Point::new(3., 10.)];
    /// let mut sampler = Sampler::new(&rest, &[(SampleRegion::Disc { radius: 0.5 }, 1.0)], 7)?
    ///     .with_cover(vec![far], 0.5)?;
    /// let qs = sampler.configurations(400);
    /// // Some configurations reach the target's neighbourhood, none leaves the way's.
    /// assert!(qs.iter().any(|q| q[1].y > 9.0));
    /// assert!(qs.iter().all(|q| q[1].x >= 2.5 && q[1].x <= 3.5 && q[1].y <= 10.5));
    /// # Ok::<(), splineskin_defop::DefOpError>(())
    /// ```
    pub fn with_cover(
        mut self,
        targets: Vec<Vec<Point>>,
        share: f64,
    ) -> Result<Sampler, DefOpError> {
        let n = self.rest.len();
        if let Some(bad) = targets
            .iter()
            .position(|t| t.len() != n || !t.iter().all(|p| p.is_finite()))
        {
            return Err(DefOpError::InvalidOption {
                name: "cover",
                value: format!("configuration {bad}: {:?}", targets[bad]),
                expected: "one finite point per handle",
            });
        }
        if !(0.0..=1.0).contains(&share) {
            return Err(DefOpError::InvalidOption {
                name: "cover share",
                value: share.to_string(),
                expected: "a fraction in [0, 1]",
            });
        }
        self.cover = targets;
        self.cover_share = share;
        Ok(self)
    }

    /// The rest configuration.
    pub fn rest(&self) -> &[Point] {
        &self.rest
    }

    /// The next configuration (one point per handle).
    pub fn configuration(&mut self) -> Vec<Point> {
        let u = self.uniform();
        let region = self
            .regions
            .iter()
            .find(|&&(_, c)| u < c)
            .or(self.regions.last())
            .map(|&(r, _)| r)
            .unwrap_or(SampleRegion::Disc { radius: 0.0 });
        // Around a point of the way to a configuration to cover, or around the rest. (No draw
        // without targets: the configurations of a sampler without them are unchanged.)
        // `(target, t)`: the point at `t` of the way to cover target `target`.
        let way = (!self.cover.is_empty() && self.uniform() < self.cover_share).then(|| {
            let k = ((self.uniform() * self.cover.len() as f64) as usize).min(self.cover.len() - 1);
            (k, self.uniform())
        });
        (0..self.rest.len())
            .map(|l| {
                let q = self.handle_position(l, region);
                match (way, region) {
                    (
                        Some((k, t)),
                        SampleRegion::Disc { .. }
                        | SampleRegion::Circle { .. }
                        | SampleRegion::Gaussian { .. },
                    ) => q + (self.rest[l].lerp(self.cover[k][l], t) - self.rest[l]),
                    _ => q,
                }
            })
            .collect()
    }

    /// The next `count` configurations.
    pub fn configurations(&mut self, count: usize) -> Vec<Vec<Point>> {
        (0..count).map(|_| self.configuration()).collect()
    }

    fn handle_position(&mut self, l: usize, region: SampleRegion) -> Point {
        let p = self.rest[l];
        match region {
            SampleRegion::Disc { radius } => {
                let r = radius * self.uniform().sqrt();
                p + r * self.unit_vector()
            }
            SampleRegion::Circle { radius } => p + radius * self.unit_vector(),
            SampleRegion::Gaussian { sigma } => {
                // Box–Muller: two independent standard normals.
                let u = 1.0 - self.uniform(); // in (0, 1]
                let r = (-2.0 * u.ln()).sqrt();
                p + sigma * r * self.unit_vector()
            }
            SampleRegion::VoronoiCell { bounds } => {
                for _ in 0..MAX_REJECTIONS {
                    let q = Point::new(
                        bounds.x0 + bounds.width() * self.uniform(),
                        bounds.y0 + bounds.height() * self.uniform(),
                    );
                    let d = (q - p).hypot2();
                    // Ties go to the handle itself, so a cell is never empty.
                    if self.rest.iter().all(|&o| (q - o).hypot2() >= d) {
                        return q;
                    }
                }
                p
            }
        }
    }

    fn unit_vector(&mut self) -> Vec2 {
        let angle = std::f64::consts::TAU * self.uniform();
        Vec2::new(angle.cos(), angle.sin())
    }

    /// Uniform in `[0, 1)` (SplitMix64, 53 random bits).
    fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rest() -> Vec<Point> {
        vec![Point::new(0., 0.), Point::new(2., 0.), Point::new(1., 1.5)]
    }

    #[test]
    fn sampler_regions_hold_their_samples() {
        let p = rest();
        let bounds = Rect::new(-1., -1., 3., 3.);
        let cases = [
            SampleRegion::Disc { radius: 0.3 },
            SampleRegion::Circle { radius: 0.3 },
            SampleRegion::Gaussian { sigma: 0.3 },
            SampleRegion::VoronoiCell { bounds },
        ];
        for region in cases {
            let mut sampler = Sampler::new(&p, &[(region, 1.0)], 3).unwrap();
            let samples = sampler.configurations(2000);
            let mut mean_distance = 0.0;
            for q in &samples {
                for (l, (&q, &pl)) in q.iter().zip(&p).enumerate() {
                    let d = (q - pl).hypot();
                    mean_distance += d / (2000.0 * 3.0);
                    match region {
                        SampleRegion::Disc { radius } => assert!(d <= radius),
                        SampleRegion::Circle { radius } => assert!((d - radius).abs() < 1e-12),
                        SampleRegion::Gaussian { .. } => {}
                        SampleRegion::VoronoiCell { bounds } => {
                            assert!(bounds.contains(q));
                            assert!(p.iter().all(|&o| (q - o).hypot() >= d), "handle {l}");
                        }
                    }
                }
            }
            // Closed forms of the mean distance: 2R/3 in a disc, R on a circle, σ√(π/2)
            // (Rayleigh) for the Gaussian; 2 000 × 3 draws pin them to about 1 %.
            let expected = match region {
                SampleRegion::Disc { radius } => 2.0 * radius / 3.0,
                SampleRegion::Circle { radius } => radius,
                SampleRegion::Gaussian { sigma } => sigma * (std::f64::consts::PI / 2.0).sqrt(),
                SampleRegion::VoronoiCell { .. } => mean_distance,
            };
            assert!(
                (mean_distance - expected).abs() < 0.03 * expected,
                "{region:?}: mean distance {mean_distance} vs {expected}"
            );
        }
    }

    #[test]
    fn sampler_is_reproducible_and_mixes_regions() {
        let p = rest();
        let regions = [
            (SampleRegion::Disc { radius: 0.1 }, 1.0),
            (SampleRegion::Circle { radius: 1.0 }, 3.0),
        ];
        let a = Sampler::new(&p, &regions, 11).unwrap().configurations(400);
        let b = Sampler::new(&p, &regions, 11).unwrap().configurations(400);
        assert_eq!(a, b);
        let on_circle = a
            .iter()
            .filter(|q| ((q[0] - p[0]).hypot() - 1.0).abs() < 1e-12)
            .count();
        // Weight 3 of 4: about 300 of 400 (binomial standard deviation 8.7).
        assert!((260..340).contains(&on_circle), "{on_circle}");
    }

    #[test]
    fn sampler_refuses_bad_regions() {
        let p = rest();
        let disc = SampleRegion::Disc { radius: 1.0 };
        assert!(Sampler::new(&p, &[], 1).is_err());
        assert!(Sampler::new(&p, &[(disc, 0.0)], 1).is_err());
        assert!(Sampler::new(&p, &[(disc, f64::NAN)], 1).is_err());
        assert!(Sampler::new(&p, &[(SampleRegion::Disc { radius: -1.0 }, 1.0)], 1).is_err());
        let small = SampleRegion::VoronoiCell {
            bounds: Rect::new(0., 0., 1., 1.),
        };
        assert!(Sampler::new(&p, &[(small, 1.0)], 1).is_err()); // excludes handle 1
        assert!(Sampler::new(&[], &[(disc, 1.0)], 1).is_err());
    }

    #[test]
    fn sampler_cover_reaches_the_targets_and_changes_nothing_without_them() {
        let p = rest();
        let disc = SampleRegion::Disc { radius: 0.2 };
        let plain = Sampler::new(&p, &[(disc, 1.0)], 5)
            .unwrap()
            .configurations(50);
        // No targets, or a share of 0: the same configurations.
        let none = Sampler::new(&p, &[(disc, 1.0)], 5)
            .unwrap()
            .with_cover(Vec::new(), 0.5)
            .unwrap()
            .configurations(50);
        assert_eq!(plain, none);
        // One target far away: about half the samples lie on the way to it, within the disc
        // of the way, and some near the target itself.
        let target: Vec<Point> = p.iter().map(|q| *q + Vec2::new(10.0, 0.0)).collect();
        let qs = Sampler::new(&p, &[(disc, 1.0)], 5)
            .unwrap()
            .with_cover(vec![target], 0.5)
            .unwrap()
            .configurations(2000);
        let away = qs
            .iter()
            .filter(|q| (q[0] - p[0]).hypot() > 0.2 + 1e-12)
            .count();
        assert!((800..1200).contains(&away), "{away}");
        assert!(qs.iter().any(|q| q[0].x > 9.8));
        for q in &qs {
            // Every handle is offset by the same fraction of the way (within the disc).
            let t0 = q[0].x;
            for (l, (ql, pl)) in q.iter().zip(&p).enumerate() {
                assert!((ql.y - pl.y).abs() <= 0.2 + 1e-12, "handle {l}");
                assert!(((ql.x - pl.x) - t0).abs() <= 0.4 + 1e-12, "handle {l}");
            }
        }
        // Bad targets and shares are refused.
        let s = || Sampler::new(&p, &[(disc, 1.0)], 5).unwrap();
        assert!(s().with_cover(vec![vec![Point::ZERO]], 0.5).is_err());
        assert!(s()
            .with_cover(vec![vec![Point::new(f64::NAN, 0.0); 3]], 0.5)
            .is_err());
        assert!(s().with_cover(vec![p.clone()], 1.5).is_err());
    }
}
