//! A scene made from a drawing already read and pins placed on it, with no scene file in
//! between: what a command line's `DRAWING.svg --pin X,Y --move I:DX,DY` describes. The scene
//! holds the same values a scene file of ours with those pins, that family and that pose would
//! give ([`ours`](super::ours)), checked the same way, and it keeps the drawing, so that
//! [`Scene::setup`] does not read the SVG a second time ([`ReadDrawing`]).

use std::sync::Arc;

use kurbo::{Affine, Point};

use super::ours::check_junction_overrides;
use super::{
    check_affine, check_point, setup::check_rest_handles, Engine, HandleSet, JunctionOverride,
    Pose, Scene, SceneError, SceneFormat, WeightSpec,
};
use crate::animation::Animation;
use crate::domain::DomainOptions;
use crate::drawing::{Drawing, SvgSource};
use crate::spline_fit::Measure;

/// A drawing, its pins and their pose: the parts of a scene that a drawing given without a
/// scene file has. See [`Scene::from_pins`].
#[derive(Clone, Debug)]
pub struct PinnedDrawing {
    /// The drawing, read from `svg_text` with the default import options (our importer).
    pub drawing: Drawing,
    /// The SVG document's text.
    pub svg_text: String,
    /// Where the drawing came from (its file name), for messages.
    pub origin: String,
    /// The point handles' rest positions.
    pub pins: Vec<Point>,
    /// The weight family.
    pub weights: WeightSpec,
    /// Options of the triangulated domain (mesh families).
    pub domain: DomainOptions,
    /// One map per pin.
    pub pose: Vec<Affine>,
}

impl Scene {
    /// The scene of `pinned`: its point handles, weights, domain and one pose, on its drawing.
    /// Checked as [`Scene::from_json`] checks a scene file of ours with the same content (the
    /// rest handles, the weights against them, every map finite and within
    /// [`MAX_COORDINATE`](super::MAX_COORDINATE)); errors name `pinned.origin` and the element
    /// as that file would have it (`handles[1]`, `poses[0].transforms[2]`). The drawing is kept:
    /// [`Scene::setup`] uses it instead of reading `svg_text` again.
    ///
    /// ```
    /// use kurbo::{Affine, Point};
    /// use splineskin::drawing::{read_svg, ImportOptions};
    /// use splineskin::scene::{pinned::PinnedDrawing, scene_domain_options, Compat, Scene, WeightSpec};
    /// let svg = "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>";
    /// let scene = Scene::from_pins(PinnedDrawing {
    ///     drawing: read_svg(svg, &ImportOptions::default())?,
    ///     svg_text: svg.into(),
    ///     origin: "curve.svg".into(),
    ///     pins: vec![Point::new(0.0, 0.0), Point::new(3.0, 0.0)],
    ///     weights: WeightSpec::parse("shepard", None, "curve.svg")?,
    ///     domain: scene_domain_options(),
    ///     pose: vec![Affine::IDENTITY, Affine::translate((0.0, 1.0))],
    /// })?;
    /// assert_eq!(scene.n_handles(), 2);
    /// assert_eq!(scene.setup(Compat::None)?.drawing.n_curves(), 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_pins(pinned: PinnedDrawing) -> Result<Scene, SceneError> {
        let PinnedDrawing {
            drawing,
            svg_text,
            origin,
            pins,
            weights,
            domain,
            pose,
        } = pinned;
        for (i, p) in pins.iter().enumerate() {
            check_point([p.x, p.y], &origin, format!("handles[{i}].position"))?;
        }
        let set = HandleSet {
            points: &pins,
            bones: &[],
            cage: None,
        };
        check_rest_handles(&set, &origin, SceneFormat::Ours)?;
        weights.check_handles(&set, &origin, "weights")?;
        let transforms = checked_maps(&pose, pins.len(), &origin, "poses[0]")?;
        Ok(Scene {
            svg_origin: origin.clone(),
            origin,
            read: ReadDrawing::new(drawing, &svg_text),
            svg_text,
            handles: pins,
            bones: Vec::new(),
            cage: None,
            weights,
            domain,
            engine: Engine::Ours,
            measure: Measure::from_arc_length(false),
            junctions: Vec::new(),
            authors_joints: None,
            poses: vec![Pose {
                name: None,
                transforms,
            }],
            flexible: false,
            animation: None,
            defop: None,
            format: SceneFormat::Ours,
        })
    }
}

impl Scene {
    /// The scene with the junction kinds `junctions` imposed (replacing any), checked as the
    /// `junctions` of a scene file: `end` cannot be imposed (error element
    /// `junctions[i].kind`).
    ///
    /// ```
    /// use splineskin::drawing::JointKind;
    /// use splineskin::scene::JunctionOverride;
    /// let scene = splineskin::examples::demo_scene();
    /// let c1 = JunctionOverride { path: 0, joint: 1, kind: JointKind::C1 };
    /// assert_eq!(scene.clone().with_junctions(vec![c1])?.junctions, vec![c1]);
    /// let end = JunctionOverride { kind: JointKind::End, ..c1 };
    /// assert!(scene.with_junctions(vec![end]).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_junctions(mut self, junctions: Vec<JunctionOverride>) -> Result<Scene, SceneError> {
        check_junction_overrides(&junctions, &self.origin)?;
        self.junctions = junctions;
        Ok(self)
    }

    /// The scene with `animation` as its keyframed poses, checked as a scene file's
    /// `animation`: each keyframe has one map per handle, finite and within
    /// [`MAX_COORDINATE`](super::MAX_COORDINATE) (error element
    /// `animation.keyframes[k].pose`).
    ///
    /// ```
    /// use kurbo::Affine;
    /// use splineskin::animation::{Animation, Keyframe};
    /// let scene = splineskin::examples::demo_scene();
    /// let n = scene.n_handles();
    /// let still = |time| Keyframe::new(time, vec![Affine::IDENTITY; n]);
    /// let animation = Animation::new(30.0, vec![still(0.0), still(1.0)])?;
    /// assert!(scene.clone().with_animation(animation)?.animation.is_some());
    /// let short = Animation::new(30.0, vec![Keyframe::new(0.0, vec![Affine::IDENTITY])])?;
    /// assert!(scene.with_animation(short).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_animation(mut self, animation: Animation) -> Result<Scene, SceneError> {
        for (k, key) in animation.keyframes().iter().enumerate() {
            let element = format!("animation.keyframes[{k}].pose");
            checked_maps(&key.transforms, self.n_handles(), &self.origin, &element)?;
        }
        self.animation = Some(animation);
        Ok(self)
    }

    /// The scene with `drawing` kept as its drawing as read, so that [`Scene::setup`] takes it
    /// instead of reading `svg_text` again: `drawing` must be what our importer reads of
    /// `svg_text` with the default options. It is taken only while its source is the scene's
    /// `svg_text` (otherwise the SVG is read as before), its source then named `svg_origin`. An editor that
    /// opened the drawing once gives it to every scene of it.
    ///
    /// ```
    /// use splineskin::scene::Compat;
    /// let scene = splineskin::examples::demo_scene();
    /// let drawing = scene.drawing(Compat::None)?;
    /// let scene = scene.with_drawing(drawing.clone());
    /// assert_eq!(scene.drawing(Compat::None)?.flat_points(), drawing.flat_points());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_drawing(mut self, drawing: Drawing) -> Scene {
        self.read = ReadDrawing::new(drawing, &self.svg_text);
        self
    }
}

/// `maps` checked as the pose `element` of `n` handles: one map per handle, each finite and
/// within [`MAX_COORDINATE`](super::MAX_COORDINATE) (elements `{element}.transforms[i]`).
fn checked_maps(
    maps: &[Affine],
    n: usize,
    origin: &str,
    element: &str,
) -> Result<Vec<Affine>, SceneError> {
    if maps.len() != n {
        return Err(SceneError::invalid(
            origin,
            element,
            format!(
                "{} transforms for {n} point handles (one per handle expected)",
                maps.len()
            ),
        ));
    }
    maps.iter()
        .enumerate()
        .map(|(i, &t)| check_affine(t, origin, format!("{element}.transforms[{i}]")))
        .collect()
}

/// The drawing of a scene as its maker already read it ([`Scene::from_pins`],
/// [`Scene::with_drawing`]), or nothing (a scene read from a file). [`Scene::drawing`] takes it
/// instead of reading the SVG again while it is still the drawing of the scene's `svg_text`
/// (named as the scene's `svg_origin` names it; a scene whose text was replaced, say by its
/// text-as-outlines version, is read anew). A drawing keeps as its source the text as browsers
/// read it ([`crate::drawing::svg_in::source_text`]), which differs from `svg_text` where that
/// reading rewrote it (entities expanded, CSS units): the text it was read from is then kept
/// too. It is a cache: two scenes compare equal whatever their caches hold.
#[derive(Clone, Default)]
pub struct ReadDrawing {
    drawing: Option<Arc<Drawing>>,
    /// The text `drawing` was read from, where its source holds another (the browsers'
    /// reading of it).
    read_from: Option<Arc<str>>,
}

impl ReadDrawing {
    /// `drawing` as read from `svg_text`, if it is: its source's text is `svg_text` or the
    /// browsers' reading of it; else nothing is held (the text is read anew when needed).
    pub(crate) fn new(drawing: Drawing, svg_text: &str) -> ReadDrawing {
        let Some(source) = drawing.source.as_ref() else {
            return ReadDrawing::default();
        };
        let read_from = match source.text == svg_text {
            true => None,
            false => match crate::drawing::svg_in::source_text(svg_text, &source.origin) {
                Ok(kept) if kept == source.text => Some(Arc::from(svg_text)),
                _ => return ReadDrawing::default(),
            },
        };
        ReadDrawing {
            drawing: Some(Arc::new(drawing)),
            read_from,
        }
    }

    /// The drawing held, if it was read from `svg_text`, its source named `svg_origin` (as
    /// reading the text under that name would name it).
    pub(crate) fn of(&self, svg_text: &str, svg_origin: &str) -> Option<Drawing> {
        let drawing = self.drawing.as_ref()?;
        let source = drawing.source.as_ref()?;
        let read_from = self.read_from.as_deref().unwrap_or(&source.text);
        if read_from != svg_text {
            return None;
        }
        let mut drawing = Drawing::clone(drawing);
        if source.origin != svg_origin {
            let renamed = SvgSource {
                origin: svg_origin.to_string(),
                ..SvgSource::clone(source)
            };
            drawing.source = Some(Arc::new(renamed));
        }
        Some(drawing)
    }
}

impl PartialEq for ReadDrawing {
    fn eq(&self, _: &ReadDrawing) -> bool {
        true
    }
}

impl std::fmt::Debug for ReadDrawing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let held = if self.drawing.is_some() {
            "held"
        } else {
            "none"
        };
        write!(f, "ReadDrawing({held})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{read_svg_named, ImportOptions};

    /// A drawing whose text the browsers' reading rewrites (an entity, a `rem` length) is still
    /// the drawing of that text: held, not read again; another text misses.
    #[test]
    fn a_drawing_read_through_the_lenient_reading_is_held_for_its_text() {
        let text = "<!DOCTYPE svg [<!ENTITY f \"fill:red\">]>\
            <svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 10\">\
            <rect style=\"&f;\" width=\"0.5rem\" height=\"4\"/></svg>";
        let drawing = read_svg_named(text, &ImportOptions::default(), "a.svg").unwrap();
        assert_ne!(
            drawing.source.as_ref().unwrap().text,
            text,
            "the reading rewrites it"
        );
        let read = ReadDrawing::new(drawing.clone(), text);
        let held = read.of(text, "a.svg").expect("held for its own text");
        assert_eq!(held.flat_points(), drawing.flat_points());
        assert!(read
            .of(&text.replace("height=\"4\"", "height=\"5\""), "a.svg")
            .is_none());
        // A drawing of another text is not held at all.
        let other = text.replace("0.5rem", "9");
        assert!(ReadDrawing::new(drawing, &other)
            .of(&other, "a.svg")
            .is_none());
    }
}
