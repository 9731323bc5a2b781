//! Bounded biharmonic weights on a domain, solved coarse to fine.
//!
//! The active-set solve of [`crate::weights::bbw`] needs about one re-factorisation per ring
//! its active set's edge travels: 75–115 on a 20 000-vertex domain started from the unbounded
//! solution. Started instead from the same program solved on a coarser triangulation of the
//! same domain (interpolated onto the fine vertices), the edge only has to move by the coarse
//! level's error: 11–24 re-solves per handle on the turtles domain. The coarse level is solved
//! the same way from a coarser one still, until a level has at most [`DIRECT_VERTICES`]
//! vertices.
//!
//! Each level is [`Domain::build`] with the fine options coarsened by [`LEVEL_FACTOR`]: curve
//! samples `LEVEL_FACTOR` times sparser and triangles up to `LEVEL_FACTOR²` times larger, so
//! about `LEVEL_FACTOR²` times fewer vertices, with the same boundary, cage, holes, handles and
//! bones. The answer does not depend on the levels: the program is strictly convex, and the
//! fine solve stops at the same KKT tolerances whatever it starts from (only its iteration
//! count changes). A coarse level that cannot be built or solved (say a feature too thin for
//! its sampling) is not an error: the fine level then starts cold.

use kurbo::Point;

use super::bbw::{bounded_biharmonic, bounded_biharmonic_from, BbwOptions};
use super::{DirichletData, VertexWeights, WeightField, WeightsError};
use crate::domain::{Boundary, Domain, DomainOptions, MeshWeights};
use crate::drawing::Drawing;

/// Coarsening factor between levels, in sample spacing: 4 (so about 16 times fewer vertices
/// per level). Measured on the turtles domain (20 437 vertices, 5 handles): starting the fine
/// solve from 3 746 vertices takes 85 fine re-solves in all, from 8 745 takes 116.
pub const LEVEL_FACTOR: f64 = 4.0;

/// A level with at most this many vertices is solved from the unbounded solution: 2 000.
pub const DIRECT_VERTICES: usize = 2000;

/// Bounded biharmonic weights (raw, not normalised: [`bounded_biharmonic`]) on `fine`, the
/// domain [`Domain::build`] made of `drawing`, `points`, `bones` and `options`, with Dirichlet
/// data `fine_data`, solved coarse to fine (module documentation). `data` builds the same
/// Dirichlet data on a coarser level from its domain (for example, one column per point handle
/// with 1 at its vertex); when it returns `None` that level is skipped.
///
/// ```
/// use kurbo::Point;
/// use splineskin_core::domain::{Domain, DomainOptions};
/// use splineskin_core::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin_core::weights::{bbw::{bounded_biharmonic, BbwOptions}, DirichletData};
/// use splineskin_core::weights::coarse_to_fine::bbw_coarse_to_fine;
///
/// let arch = [(0.0, 0.0), (30.0, 40.0), (70.0, 40.0), (100.0, 0.0)].map(Point::from);
/// let path = Path::new(arch.to_vec(), false, &JunctionOptions::default()).unwrap();
/// let drawing = Drawing { paths: vec![path], source: None };
/// let handles = [Point::new(0.0, 0.0), Point::new(50.0, 30.0), Point::new(100.0, 0.0)];
/// let options = DomainOptions::default().with_max_area_fraction(1.0 / 2000.0);
/// let fine = Domain::build(&drawing, &handles, &[], &options)?;
/// let fine_data = DirichletData::handles(&fine.handle_vertices)?;
/// let data = |d: &Domain| DirichletData::handles(&d.handle_vertices).ok();
/// let bbw = BbwOptions::default();
/// let warm = bbw_coarse_to_fine(&drawing, &handles, &[], &options, &fine, &fine_data, data, &bbw)?;
/// let cold = bounded_biharmonic(&fine.mesh, &fine_data, &bbw)?;
/// let gap = warm.as_slice().iter().zip(cold.as_slice()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
/// assert!(gap < 1e-9, "{gap}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn bbw_coarse_to_fine<F>(
    drawing: &Drawing,
    points: &[Point],
    bones: &[[Point; 2]],
    options: &DomainOptions,
    fine: &Domain,
    fine_data: &DirichletData,
    data: F,
    bbw: &BbwOptions,
) -> Result<VertexWeights, WeightsError>
where
    F: Fn(&Domain) -> Option<DirichletData>,
{
    let levels = Levels {
        drawing,
        points,
        bones,
        data: &data,
        bbw,
    };
    levels.solve(options, fine, fine_data)
}

/// What every level shares: the drawing, points and bones each level's domain is built from,
/// the builder of a level's Dirichlet data, and the BBW options.
struct Levels<'a> {
    drawing: &'a Drawing,
    points: &'a [Point],
    bones: &'a [[Point; 2]],
    data: &'a dyn Fn(&Domain) -> Option<DirichletData>,
    bbw: &'a BbwOptions,
}

impl Levels<'_> {
    /// The weights on `fine` (built with `options`) for `fine_data`, started from the next
    /// coarser level when there is one.
    fn solve(
        &self,
        options: &DomainOptions,
        fine: &Domain,
        fine_data: &DirichletData,
    ) -> Result<VertexWeights, WeightsError> {
        match self.coarse_guess(options, fine) {
            Some(guess) => bounded_biharmonic_from(&fine.mesh, fine_data, self.bbw, &guess),
            None => bounded_biharmonic(&fine.mesh, fine_data, self.bbw),
        }
    }

    /// The weights of the next coarser level interpolated at `fine`'s vertices, or `None`
    /// when `fine` is small enough to solve directly or a coarser level fails.
    fn coarse_guess(&self, options: &DomainOptions, fine: &Domain) -> Option<VertexWeights> {
        if fine.mesh.n_vertices() <= DIRECT_VERTICES {
            return None;
        }
        let coarse_options = coarser(options);
        let coarse = match fine.boundary {
            // The art's outline is traced on a grid of the sample spacing; a coarse level
            // traces its own (rounder, larger) one, a poor start for the fine solve (about 4×
            // the re-solves on the bundled octopus). It keeps the fine outline instead,
            // simplified to a quarter of its own spacing.
            Boundary::Art { .. } => {
                let tolerance = 0.25 * LEVEL_FACTOR * fine.sample_spacing;
                let outline = fine.simplified_outline(tolerance);
                let build = Domain::build_within;
                build(
                    self.drawing,
                    self.points,
                    self.bones,
                    &coarse_options,
                    &outline,
                    fine.boundary,
                )
            }
            _ => Domain::build(self.drawing, self.points, self.bones, &coarse_options),
        }
        .ok()?;
        // A coarser level that is not smaller (everything pinned by handles or the vertex
        // cap) would not pay for itself.
        if coarse.mesh.n_vertices() * 2 > fine.mesh.n_vertices() {
            return None;
        }
        let coarse_data = (self.data)(&coarse)?;
        let weights = self.solve(&coarse_options, &coarse, &coarse_data).ok()?;
        let h = weights.n_handles();
        let field = MeshWeights::new(&coarse.mesh, weights.into_values(), h).ok()?;
        let n = fine.mesh.n_vertices();
        let mut values = vec![0.0; n * h];
        for (v, row) in values.chunks_mut(h).enumerate() {
            field.eval(fine.mesh.vertices[v], row);
        }
        VertexWeights::from_row_major(n, h, values).ok()
    }
}

/// The domain options of a quick preview of `options`' weights: two levels coarser (samples
/// `LEVEL_FACTOR²` = 16 times sparser, triangles up to 256 times larger; a few hundred
/// vertices on the bundled drawings), the same boundary rule. Solved there, a mesh family is
/// shape-aware like the exact weights and near them, in a few milliseconds (the editor shows it
/// while the exact weights compute).
///
/// ```
/// use splineskin_core::domain::DomainOptions;
/// use splineskin_core::weights::coarse_to_fine::preview_options;
/// let fine = DomainOptions::default();
/// let quick = preview_options(&fine);
/// assert_eq!(quick.samples_per_diagonal, fine.samples_per_diagonal / 16.0);
/// assert_eq!(quick.shape, fine.shape);
/// ```
pub fn preview_options(options: &DomainOptions) -> DomainOptions {
    coarser(&coarser(options))
}

/// `options` one level coarser: samples [`LEVEL_FACTOR`] times sparser, triangles up to
/// `LEVEL_FACTOR²` times larger (the area fraction capped at 1).
fn coarser(options: &DomainOptions) -> DomainOptions {
    let mut coarse = options.clone();
    coarse.samples_per_diagonal = options.samples_per_diagonal / LEVEL_FACTOR;
    coarse.max_area_fraction = (options.max_area_fraction * LEVEL_FACTOR * LEVEL_FACTOR).min(1.0);
    coarse
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{JunctionOptions, Path};

    /// A wavy open curve and three handles along it (no bones), meshed with `options` to
    /// about 5 000 vertices (`fine`): one coarse level (about 350 vertices) below the fine one.
    struct Fixture {
        drawing: Drawing,
        handles: Vec<Point>,
        options: DomainOptions,
        fine: Domain,
    }

    fn setup() -> Fixture {
        // M0 0 C30 60 70 -60 100 0 S170 60 200 0
        let wave = [
            (0., 0.),
            (30., 60.),
            (70., -60.),
            (100., 0.),
            (130., 60.),
            (170., 60.),
            (200., 0.),
        ];
        let path = Path::new(
            wave.map(Point::from).to_vec(),
            false,
            &JunctionOptions::default(),
        );
        let drawing = Drawing {
            paths: vec![path.unwrap()],
            source: None,
        };
        let handles = vec![
            Point::new(0.0, 0.0),
            Point::new(100.0, 0.0),
            Point::new(200.0, 0.0),
        ];
        let options = DomainOptions::default().with_max_area_fraction(1.0 / 4000.0);
        let fine = Domain::build(&drawing, &handles, &[], &options).unwrap();
        Fixture {
            drawing,
            handles,
            options,
            fine,
        }
    }

    impl Fixture {
        /// The levels of the fixture's drawing and handles.
        fn levels<'a>(
            &'a self,
            data: &'a dyn Fn(&Domain) -> Option<DirichletData>,
            bbw: &'a BbwOptions,
        ) -> Levels<'a> {
            Levels {
                drawing: &self.drawing,
                points: &self.handles,
                bones: &[],
                data,
                bbw,
            }
        }

        /// [`bbw_coarse_to_fine`] on the fine domain.
        fn coarse_to_fine(
            &self,
            fine_data: &DirichletData,
            data: impl Fn(&Domain) -> Option<DirichletData>,
            bbw: &BbwOptions,
        ) -> Result<VertexWeights, WeightsError> {
            bbw_coarse_to_fine(
                &self.drawing,
                &self.handles,
                &[],
                &self.options,
                &self.fine,
                fine_data,
                data,
                bbw,
            )
        }
    }

    #[test]
    fn coarse_to_fine_equals_a_cold_solve() {
        let f = setup();
        assert!(f.fine.mesh.n_vertices() > DIRECT_VERTICES);
        let data = |d: &Domain| DirichletData::handles(&d.handle_vertices).ok();
        let fine_data = data(&f.fine).unwrap();
        let bbw = BbwOptions::default();
        // The coarse level exists and is a real guess: bounded, but not the answer.
        let guess = f
            .levels(&data, &bbw)
            .coarse_guess(&f.options, &f.fine)
            .expect("a coarse level");
        let cold = bounded_biharmonic(&f.fine.mesh, &fine_data, &bbw).unwrap();
        let gap = |a: &VertexWeights| {
            a.as_slice()
                .iter()
                .zip(cold.as_slice())
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max)
        };
        assert!(gap(&guess) > 1e-4, "guess already exact: {:e}", gap(&guess));
        let warm = f.coarse_to_fine(&fine_data, data, &bbw).unwrap();
        // Same KKT tolerances, strictly convex program: the same minimiser up to the solve's
        // rounding (measured 1.5e-11 on the 20 437-vertex turtles domain).
        assert!(gap(&warm) < 1e-9, "{:e}", gap(&warm));
    }

    #[test]
    fn small_domains_and_failed_levels_start_cold() {
        let f = setup();
        let small_options = f.options.clone().with_max_area_fraction(1.0 / 200.0);
        let small = Domain::build(&f.drawing, &f.handles, &[], &small_options).unwrap();
        assert!(small.mesh.n_vertices() <= DIRECT_VERTICES);
        let data = |d: &Domain| DirichletData::handles(&d.handle_vertices).ok();
        let bbw = BbwOptions::default();
        assert!(f
            .levels(&data, &bbw)
            .coarse_guess(&small_options, &small)
            .is_none());
        // Coarse levels without data fall back to a cold start.
        let none = |_: &Domain| None;
        assert!(f
            .levels(&none, &bbw)
            .coarse_guess(&f.options, &f.fine)
            .is_none());
        let fine_data = DirichletData::handles(&f.fine.handle_vertices).unwrap();
        let cold = bounded_biharmonic(&f.fine.mesh, &fine_data, &bbw).unwrap();
        let fallback = f.coarse_to_fine(&fine_data, none, &bbw).unwrap();
        assert_eq!(fallback, cold);
        // Errors of the fine level are errors.
        let bad = DirichletData::new(vec![0], vec![2.0], 1).unwrap();
        assert!(matches!(
            f.coarse_to_fine(&bad, data, &bbw),
            Err(WeightsError::ValueOutOfBounds { .. })
        ));
    }
}
