//! Bundled example data and synthetic test drawings.
//!
//! * [`DEMO_SVG`] and [`DEMO_SCENE`]: a fish drawn for this project (`assets/demo.svg`) and a
//!   scene of ours rigging it with five point handles (head, body, tail, dorsal and anal fin)
//!   and three poses (`assets/demo-scene.json`, format in [`crate::scene::ours`]). The drawing
//!   has smooth junctions with unequal handles (G¹), exact C¹ ones, corners, a right-angle
//!   corner, gradients, a transformed group, circles, an ellipse, a rounded rectangle and a
//!   text label.
//! * [`tile`]: copies of a drawing on a grid, to make drawings of any size for benchmarks and
//!   scaling tests.
//! * [`octopus_outline`], [`octopus_handles`], [`octopus_domain`]: an octopus-like shape of
//!   ours (a round body and eight tapering arms) with nine point handles, the size of the
//!   deformation-operator paper's octopus (Poranne & Lipman 2016, Fig. 1), for the
//!   deformation-operator tests, benchmarks and study.
//! * [`OCTOPUS_SVG`] and [`OCTOPUS_SCENE`]: an octopus drawn for this project
//!   (`assets/octopus.svg`: one closed outline of 112 smooth cubics around a mantle and eight
//!   wavy arms, 32 suckers, eyes and a smile; 335 curves in 39 paths) rigged with nine point
//!   handles — the mantle's centre and the eight arm tips — and three poses
//!   (`assets/octopus-scene.json`). The drawing of the deformation-operator study and the
//!   spline join.
//! * [`SCRIPT_SVG`] and [`SCRIPT_SCENE`]: a line of calligraphic script drawn for this project
//!   as hand-digitised art comes out of an editor (`tools/make_script.py`): four closed
//!   strokes of 92 short cubics each, whose 352 side junctions the scene saves as G¹ although
//!   64 of them are 1–13.4° off and some have a handle on the anchor; four Shepard handles
//!   stand outside the drawing. The drawing of the rest-preserving junction kinds
//!   ([`crate::drawing::junction`]).

use kurbo::{Point, Vec2};

use crate::drawing::Drawing;

/// The demo drawing, an SVG document of about 600 × 400 user units.
pub const DEMO_SVG: &str = include_str!("../assets/demo.svg");

/// The demo scene (our format), naming `demo.svg` as its drawing: load it with
/// [`crate::scene::Scene::from_json`] and the `assets` folder as base folder, or replace the
/// file name by [`DEMO_SVG`].
pub const DEMO_SCENE: &str = include_str!("../assets/demo-scene.json");

/// Gap between neighbouring tiles of [`tile`], as a fraction of the larger side of the
/// drawing's control-point bounding box: 0.1. Enough that the tiles' control polygons do not
/// overlap, small enough that the tiling stays compact.
pub const TILE_MARGIN: f64 = 0.1;

/// Tiles copies of `drawing` on a grid until the result has at least `min_curves` curves.
///
/// The grid has `cols = ⌈√n_tiles⌉` columns and `rows = ⌈n_tiles / cols⌉` rows, with
/// `n_tiles = ⌈min_curves / n_curves⌉` (at least 1), and every cell is filled, so there may be
/// up to `cols − 1` more tiles than needed. Tile `(row, col)` is the drawing translated by
/// `(col · (w + m), row · (h + m))`, where `w × h` is the size of [`Drawing::control_bounds`]
/// and `m` = [`TILE_MARGIN`] `· max(w, h)`; tiles are stored row by row, each with all of the
/// drawing's paths in order and their joint kinds copied (not reclassified). The result has no
/// SVG source (`source: None`): it cannot be written back into a document.
///
/// The returned handles are one per distinct tile among the four corner tiles and the centre
/// tile `(rows / 2, cols / 2)` (so 5 for grids of at least 3 × 3, fewer for smaller ones): the
/// centroid of `handles` translated into that tile, or the centre of the bounding box when
/// `handles` is empty.
///
/// A drawing without curves is returned as a single tile: the copy of its (empty) paths, and
/// `handles` unchanged.
///
/// Memory grows with `min_curves` and is not bounded here: a `min_curves` beyond what memory
/// can hold panics (capacity overflow) or aborts (allocation failure). Callers taking it from
/// users bound it (the CLI's `bench --synthetic` does).
///
/// ```
/// use kurbo::Point;
/// use splineskin::drawing::{Drawing, JunctionOptions, Path};
/// use splineskin::examples::tile;
///
/// let pts = [(0.0, 0.0), (1.0, 1.0), (2.0, 1.0), (3.0, 0.0)].map(Point::from).to_vec();
/// let drawing = Drawing {
///     paths: vec![Path::new(pts, false, &JunctionOptions::default()).unwrap()],
///     ..Default::default()
/// };
/// let (big, handles) = tile(&drawing, &[Point::new(1.5, 0.5)], 10);
/// assert_eq!(big.n_curves(), 12); // a full 4 × 3 grid
/// assert_eq!(handles.len(), 5);
/// assert_eq!(handles[0], Point::new(1.5, 0.5)); // top-left tile: the handle itself
/// ```
pub fn tile(drawing: &Drawing, handles: &[Point], min_curves: usize) -> (Drawing, Vec<Point>) {
    let n_curves = drawing.n_curves();
    let Some(bounds) = drawing.control_bounds().filter(|_| n_curves > 0) else {
        let copy = Drawing {
            paths: drawing.paths.clone(),
            source: None,
        };
        return (copy, handles.to_vec());
    };
    let n_tiles = min_curves.div_ceil(n_curves).max(1);
    let cols = n_tiles.isqrt() + usize::from(n_tiles.isqrt().pow(2) < n_tiles);
    let rows = n_tiles.div_ceil(cols);
    let margin = TILE_MARGIN * bounds.width().max(bounds.height());
    let step = Vec2::new(bounds.width() + margin, bounds.height() + margin);
    let offset = |row: usize, col: usize| Vec2::new(col as f64 * step.x, row as f64 * step.y);

    let mut paths = Vec::with_capacity(rows * cols * drawing.paths.len());
    for row in 0..rows {
        for col in 0..cols {
            let d = offset(row, col);
            paths.extend(drawing.paths.iter().map(|path| {
                let mut copy = path.clone();
                for p in &mut copy.points {
                    *p += d;
                }
                copy
            }));
        }
    }

    let anchor = if handles.is_empty() {
        bounds.center()
    } else {
        let sum = handles.iter().fold(Vec2::ZERO, |s, p| s + p.to_vec2());
        (sum / handles.len() as f64).to_point()
    };
    let mut cells = vec![
        (0, 0),
        (0, cols - 1),
        (rows - 1, 0),
        (rows - 1, cols - 1),
        (rows / 2, cols / 2),
    ];
    let mut seen = Vec::with_capacity(cells.len());
    cells.retain(|c| {
        let new = !seen.contains(c);
        seen.push(*c);
        new
    });
    let tiled_handles = cells
        .into_iter()
        .map(|(row, col)| anchor + offset(row, col))
        .collect();

    (
        Drawing {
            paths,
            source: None,
        },
        tiled_handles,
    )
}

/// The octopus drawing, an SVG document of 640 × 600 user units whose outline (the path
/// `outline`) contains everything else, so that it is the boundary of the drawing's domain
/// ([`crate::domain`]).
pub const OCTOPUS_SVG: &str = include_str!("../assets/octopus.svg");

/// The octopus scene (our format), naming `octopus.svg`: nine point handles (the mantle's
/// centre, then the arm tips clockwise on screen from the top right), bounded biharmonic
/// weights, a deformation-operator section (symmetric ARAP, thin-plate splines, 1 000 samples in
/// discs of 0.1 of the diagonal: the poses move tips up to about that far), poses `wave`,
/// `reach` and `curl`, and an animation through them.
pub const OCTOPUS_SCENE: &str = include_str!("../assets/octopus-scene.json");

/// The octopus scene ([`OCTOPUS_SCENE`]) with its drawing ([`OCTOPUS_SVG`]) inline.
///
/// ```
/// let scene = splineskin::examples::octopus_scene();
/// assert_eq!(scene.handles.len(), 9);
/// ```
pub fn octopus_scene() -> crate::scene::Scene {
    let svg = serde_json::to_string(OCTOPUS_SVG).expect("a string always serialises");
    let json = OCTOPUS_SCENE.replacen(
        "\"svg\": \"octopus.svg\"",
        &format!("\"svg_text\": {svg}"),
        1,
    );
    crate::scene::Scene::from_json(&json, "octopus-scene.json (bundled)", None)
        .expect("the bundled octopus scene is valid (tested)")
}

/// A line of calligraphic script drawn for this project (`assets/script.svg`, module doc).
pub const SCRIPT_SVG: &str = include_str!("../assets/script.svg");

/// The script's scene (our format), naming `script.svg`: four point handles outside the
/// drawing, Shepard weights, every side junction saved as G¹ (`junctions`), poses `lean` and
/// `squeeze`.
pub const SCRIPT_SCENE: &str = include_str!("../assets/script-scene.json");

/// The script scene ([`SCRIPT_SCENE`]) with its drawing ([`SCRIPT_SVG`]) inline.
///
/// ```
/// let scene = splineskin::examples::script_scene();
/// assert_eq!(scene.handles.len(), 4);
/// assert_eq!(scene.junctions.len(), 352);
/// ```
pub fn script_scene() -> crate::scene::Scene {
    let svg = serde_json::to_string(SCRIPT_SVG).expect("a string always serialises");
    let json = SCRIPT_SCENE.replacen(
        "\"svg\": \"script.svg\"",
        &format!("\"svg_text\": {svg}"),
        1,
    );
    crate::scene::Scene::from_json(&json, "script-scene.json (bundled)", None)
        .expect("the bundled script scene is valid (tested)")
}

/// The bundled scene ([`DEMO_SCENE`]) with its drawing ([`DEMO_SVG`]) inline, ready to use
/// without files.
///
/// ```
/// let scene = splineskin::examples::demo_scene();
/// assert_eq!(scene.handles.len(), 5);
/// assert!(scene.svg_text.contains("<svg"));
/// ```
pub fn demo_scene() -> crate::scene::Scene {
    let svg = serde_json::to_string(DEMO_SVG).expect("a string always serialises");
    let json = DEMO_SCENE.replacen("\"svg\": \"demo.svg\"", &format!("\"svg_text\": {svg}"), 1);
    crate::scene::Scene::from_json(&json, "demo-scene.json (bundled)", None)
        .expect("the bundled scene is valid (tested)")
}

/// Arms of [`octopus_outline`].
pub const OCTOPUS_ARMS: usize = 8;
/// Body radius of [`octopus_outline`] (drawing units).
pub const OCTOPUS_BODY: f64 = 1.0;
/// Arm length of [`octopus_outline`], from the body's rim to the tip (drawing units).
pub const OCTOPUS_ARM: f64 = 2.2;

/// The outline of an octopus-like shape, counter-clockwise: eight arms of length
/// [`OCTOPUS_ARM`] around a body of radius [`OCTOPUS_BODY`] centred at the origin, each arm
/// tapering from 0.5 rad wide at the body to 0.06 rad at its tip (48 points).
pub fn octopus_outline() -> Vec<Point> {
    let mut points = Vec::with_capacity(6 * OCTOPUS_ARMS);
    for k in 0..OCTOPUS_ARMS {
        let theta = std::f64::consts::TAU * k as f64 / OCTOPUS_ARMS as f64;
        let at = |radius: f64, angle: f64| Point::new(radius * angle.cos(), radius * angle.sin());
        points.push(at(OCTOPUS_BODY, theta - 0.25));
        points.push(at(OCTOPUS_BODY + 0.5 * OCTOPUS_ARM, theta - 0.1));
        points.push(at(OCTOPUS_BODY + OCTOPUS_ARM, theta - 0.03));
        points.push(at(OCTOPUS_BODY + OCTOPUS_ARM, theta + 0.03));
        points.push(at(OCTOPUS_BODY + 0.5 * OCTOPUS_ARM, theta + 0.1));
        points.push(at(OCTOPUS_BODY, theta + 0.25));
    }
    points
}

/// The nine point handles of the octopus: the body's centre, then the eight arm tips (0.1
/// inside the tip), in the arms' order.
pub fn octopus_handles() -> Vec<Point> {
    let mut points = vec![Point::ZERO];
    for k in 0..OCTOPUS_ARMS {
        let theta = std::f64::consts::TAU * k as f64 / OCTOPUS_ARMS as f64;
        let r = OCTOPUS_BODY + OCTOPUS_ARM - 0.1;
        points.push(Point::new(r * theta.cos(), r * theta.sin()));
    }
    points
}

/// The octopus triangulated with its handles as vertices ([`crate::domain::Domain::build`]
/// on the outline as one closed SVG polygon path): triangles of at most `max_area_fraction` of the
/// bounding box's area, boundary samples `1/120` of its diagonal apart. `1.0 / 1800.0` gives
/// 1 991 vertices and 3 377 triangles (the deformation-operator benchmark's mesh), `1.0 / 300.0`
/// about 600 triangles (tests).
///
/// ```
/// use splineskin::examples::octopus_domain;
/// let domain = octopus_domain(1.0 / 300.0)?;
/// assert_eq!(domain.handle_vertices.len(), 9);
/// # Ok::<(), splineskin::domain::DomainError>(())
/// ```
pub fn octopus_domain(
    max_area_fraction: f64,
) -> Result<crate::domain::Domain, crate::domain::DomainError> {
    use crate::domain::{Domain, DomainOptions};
    use crate::drawing::{read_svg, ImportOptions};
    use std::fmt::Write;
    let outline = octopus_outline();
    let mut d = format!("M{} {}", outline[0].x, outline[0].y);
    for p in &outline[1..] {
        let _ = write!(d, " L{} {}", p.x, p.y);
    }
    let svg = format!(r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="{d} Z"/></svg>"#);
    let drawing = read_svg(&svg, &ImportOptions::default()).map_err(|_| {
        crate::domain::DomainError::EmptyDomain {
            reason: "the octopus outline did not parse (a bug)",
        }
    })?;
    let options = DomainOptions::default()
        .with_samples_per_diagonal(120.0)
        .with_max_area_fraction(max_area_fraction);
    Domain::build(&drawing, &octopus_handles(), &[], &options)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{JointKind, JunctionOptions, Path};

    /// A closed drop shape (a C⁰ tip and G¹ junctions) and an open wave with a C¹ junction.
    fn small_drawing() -> Drawing {
        let drop = [
            (0.0, 0.0),
            (2.0, 1.0),
            (3.0, 3.0),
            (2.0, 4.0),
            (1.5, 4.5),
            (-1.5, 4.5),
            (-2.0, 4.0),
            (-3.0, 3.0),
            (-2.0, 1.0),
            (0.0, 0.0),
        ]
        .map(Point::from)
        .to_vec();
        let wave = [
            (5.0, 0.0),
            (6.0, 2.0),
            (7.0, 2.0),
            (8.0, 0.0),
            (9.0, -2.0),
            (10.0, -2.0),
            (11.0, 0.0),
        ]
        .map(Point::from)
        .to_vec();
        let options = JunctionOptions::default();
        Drawing {
            paths: vec![
                Path::new(drop, true, &options).unwrap(),
                Path::new(wave, false, &options).unwrap(),
            ],
            source: None,
        }
    }

    /// The octopus's outline is its domain's boundary (it contains every other curve and the
    /// handles), its drawing has the documented size, and its poses move handles.
    #[test]
    fn octopus_scene_outline_bounds_its_domain() {
        use crate::domain::{Boundary, Domain, DomainOptions};
        let scene = octopus_scene();
        let drawing = scene.drawing(crate::scene::Compat::None).unwrap();
        assert_eq!((drawing.n_curves(), drawing.paths.len()), (335, 39));
        assert_eq!(drawing.paths[0].n_curves(), 112);
        let options = DomainOptions::default()
            .with_samples_per_diagonal(120.0)
            .with_max_area_fraction(1.0 / 1500.0);
        let domain = Domain::build(&drawing, &scene.handles, &[], &options).unwrap();
        assert_eq!(domain.boundary, Boundary::ClosedCurve { path: 0 });
        assert_eq!(domain.handle_vertices.len(), 9);
        assert_eq!(scene.poses.len(), 3);
    }

    #[test]
    fn tile_reaches_min_curves_on_a_full_grid() {
        let drawing = small_drawing();
        assert_eq!(drawing.n_curves(), 5);
        assert_eq!(drawing.paths[0].joints[0], JointKind::C0);
        assert_eq!(drawing.paths[1].joints[1], JointKind::C1);
        for min_curves in [0, 1, 5, 6, 24, 26, 1000] {
            let (tiled, handles) = tile(&drawing, &[Point::new(1.0, 2.0)], min_curves);
            let n_tiles = tiled.paths.len() / drawing.paths.len();
            assert_eq!(tiled.paths.len() % drawing.paths.len(), 0);
            assert!(tiled.n_curves() >= min_curves.max(1), "{min_curves}");
            assert_eq!(tiled.n_curves(), n_tiles * drawing.n_curves());
            // The grid is full: at most one row more than needed.
            let needed = min_curves.div_ceil(5).max(1);
            let cols = (needed as f64).sqrt().ceil() as usize;
            assert_eq!(n_tiles, cols * needed.div_ceil(cols), "{min_curves}");
            let expected_handles = match (needed.div_ceil(cols), cols) {
                (1, 1) => 1,
                (1, _) => 2,
                (r, c) if r <= 2 && c <= 2 => 4,
                _ => 5,
            };
            assert_eq!(handles.len(), expected_handles, "{min_curves}");
            assert!(tiled.source.is_none());
        }
    }

    #[test]
    fn tile_translates_exactly_and_copies_joints() {
        let drawing = small_drawing();
        let bounds = drawing.control_bounds().unwrap();
        let (tiled, handles) = tile(&drawing, &[Point::new(0.0, 1.0), Point::new(2.0, 3.0)], 40);
        // 8 tiles → a 3 × 3 grid.
        let cols = 3;
        assert_eq!(tiled.paths.len(), 9 * drawing.paths.len());
        let margin = TILE_MARGIN * bounds.width().max(bounds.height());
        let step = Vec2::new(bounds.width() + margin, bounds.height() + margin);
        for (t, copy) in tiled.paths.chunks(drawing.paths.len()).enumerate() {
            let d = Vec2::new((t % cols) as f64 * step.x, (t / cols) as f64 * step.y);
            for (original, path) in drawing.paths.iter().zip(copy) {
                assert_eq!(path.closed, original.closed);
                assert_eq!(path.joints, original.joints);
                for (p, q) in original.points.iter().zip(&path.points) {
                    assert_eq!(*q, *p + d);
                }
            }
        }
        // Handles: the centroid (1, 2) in the corner tiles and the centre tile.
        let at = |row: f64, col: f64| Point::new(1.0 + col * step.x, 2.0 + row * step.y);
        assert_eq!(
            handles,
            vec![at(0., 0.), at(0., 2.), at(2., 0.), at(2., 2.), at(1., 1.)]
        );
        // Neighbouring tiles' control boxes are separated by the margin.
        let first = tiled.paths[..2].iter().flat_map(|p| &p.points);
        let second = tiled.paths[2..4].iter().flat_map(|p| &p.points);
        let right_of_first = first.map(|p| p.x).fold(f64::MIN, f64::max);
        let left_of_second = second.map(|p| p.x).fold(f64::MAX, f64::min);
        assert!((left_of_second - right_of_first - margin).abs() < 1e-12);
    }

    #[test]
    fn tile_of_an_empty_drawing_is_itself() {
        let (tiled, handles) = tile(&Drawing::default(), &[Point::new(1.0, 1.0)], 100);
        assert!(tiled.paths.is_empty());
        assert_eq!(handles, vec![Point::new(1.0, 1.0)]);
    }

    #[test]
    fn demo_assets_are_embedded() {
        assert!(DEMO_SVG.starts_with("<svg"));
        assert!(DEMO_SCENE.contains("\"splineskin_scene\": 1"));
    }
}
