//! From a [`Scene`] to what a rig is built from: the drawing (with the scene's junction
//! kinds), the weight functions and the fit options, in our default mode or in the paper
//! authors' compatibility mode.

use std::sync::Arc;

use kurbo::{Affine, Point};

use crate::domain::polygon::{check_cage, signed_area};
use crate::domain::{Domain, DomainError};
use crate::drawing::authors_svg::read_authors_drawing_named;
use crate::drawing::follow::{ElementMaps, FollowOptions};
use crate::drawing::{read_svg_named, Drawing, ImportOptions, JointKind, SvgError};
use crate::spline_fit::{FitOptions, FlexibleOptions};
use crate::stop::StopSignal;
use crate::weights::WeightField;

use super::compat::Compat;
use super::handle_weights::{domain_element, handle_weights, SolvedColumns, WeightInputs};
use super::{HandleSet, Scene, SceneError, SceneFormat};

/// How a scene's weights are solved beyond the scene itself ([`Scene::setup_with`]): a
/// signal that stops them (an editor whose user asked for other weights meanwhile), and
/// bounded biharmonic columns solved elsewhere. The default stops nothing and solves
/// everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct SetupControl<'a> {
    /// Stops the bounded biharmonic solve when raised.
    pub stop: Option<&'a StopSignal>,
    /// Bounded biharmonic columns already solved ([`Scene::bbw_columns`]), taken as given.
    pub solved: Option<&'a SolvedColumns>,
}

/// Everything a rig is built from.
pub struct Setup {
    /// The drawing, with the scene's junction kinds applied.
    pub drawing: Drawing,
    /// One weight function per handle.
    pub weights: Arc<dyn WeightField>,
    /// The fit options.
    pub options: FitOptions,
    /// Things the user should know (e.g. saved junction kinds that did not fit the drawing).
    pub warnings: Vec<String>,
    /// The triangulated domain the weights were solved on (mesh weight families only), for
    /// showing the mesh and reporting its size.
    pub domain: Option<Domain>,
}

impl Setup {
    /// The maps that carry gradients, patterns, markers, text and images with the skinning map
    /// `x ↦ Σᵢ wᵢ(x) Tᵢ x` of the weights under `pose` (each element's best-fit affine map,
    /// [`crate::drawing::follow`]); `None` when the pose does not have one map per weight
    /// function, and those elements then stay at rest (the caller says so).
    ///
    /// ```
    /// use kurbo::Affine;
    /// use splineskin::drawing::follow::FollowOptions;
    /// use splineskin::scene::Compat;
    /// let setup = splineskin::examples::demo_scene().setup(Compat::None)?;
    /// // Every handle moved alike: the skinning map is that move, and so is each element's map.
    /// let pose = vec![Affine::translate((5.0, 0.0)); setup.weights.n_handles()];
    /// let maps = setup.element_maps(&pose, &FollowOptions::default())?.expect("one map per handle");
    /// let map = maps.element_map(0).expect("the first element's map").as_coeffs();
    /// assert!(map.iter().zip([1.0, 0.0, 0.0, 1.0, 5.0, 0.0]).all(|(a, b)| (a - b).abs() < 1e-9));
    /// assert!(setup.element_maps(&pose[1..], &FollowOptions::default())?.is_none());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn element_maps(
        &self,
        pose: &[Affine],
        options: &FollowOptions,
    ) -> Result<Option<ElementMaps>, SvgError> {
        let field = &*self.weights;
        if pose.len() != field.n_handles() {
            return Ok(None);
        }
        let mut w = vec![0.0; pose.len()];
        let mut map = |p: Point| crate::naive::skin_point(field, pose, p, &mut w);
        ElementMaps::from_map(&self.drawing, &mut map, options).map(Some)
    }
}

impl Scene {
    /// Reads the scene's drawing, applies its junction kinds, and builds its weights and fit
    /// options for `compat`. Errors if the scene needs something not implemented
    /// ([`Scene::check_supported`]) or its drawing cannot be read.
    pub fn setup(&self, compat: Compat) -> Result<Setup, SceneError> {
        self.setup_with(compat, SetupControl::default())
    }

    /// [`Scene::setup`] under `control`: bounded biharmonic weights that stop when
    /// `control.stop` is raised ([`crate::weights::bbw::BbwOptions::stop`]; then a
    /// [`SceneError::Weights`] whose source is [`crate::weights::WeightsError::Stopped`]), and
    /// that take the columns `control.solved` as given ([`Scene::bbw_columns`]).
    pub fn setup_with(
        &self,
        compat: Compat,
        control: SetupControl<'_>,
    ) -> Result<Setup, SceneError> {
        self.check_supported()?;
        let (drawing, warnings) = self.drawing_with_junctions(compat)?;
        let options = self.fit_options(compat);
        let inputs = WeightInputs {
            stop: control.stop,
            solved: control.solved,
            ..self.weight_inputs(compat)
        };
        let (weights, domain) = handle_weights(&drawing, &inputs)?;
        Ok(Setup {
            drawing,
            weights,
            options,
            warnings,
            domain,
        })
    }

    /// The drawing [`Scene::setup`] rigs, without the weights: read with the importer of
    /// `compat`, the authors' saved junction kinds applied (if they fit the drawing) and then
    /// the scene's junction overrides ([`Scene::junctions`]). Returns it with what the user
    /// should know (saved kinds that did not fit; junctions saved C¹ or G¹ that the input does
    /// not have, [`Drawing::joint_mismatch_note`]). Errors name a junction override that does
    /// not exist or is an open end.
    pub fn drawing_with_junctions(
        &self,
        compat: Compat,
    ) -> Result<(Drawing, Vec<String>), SceneError> {
        let mut drawing = self.drawing(compat)?;
        // What the import drew other than written (path data up to its first error).
        let mut warnings = match (&drawing.source, compat) {
            (Some(source), Compat::None) => source.warnings.clone(),
            _ => Vec::new(),
        };
        if let Some(kinds) = &self.authors_joints {
            if let Some(w) = apply_authors_joints(&mut drawing, kinds, &self.svg_text, compat) {
                warnings.push(format!("{}: {w}", self.origin));
            }
        }
        for (i, o) in self.junctions.iter().enumerate() {
            let invalid = |message: String| {
                SceneError::invalid(&self.origin, format!("junctions[{i}]"), message)
            };
            let n_paths = drawing.paths.len();
            let path = drawing.paths.get_mut(o.path).ok_or_else(|| {
                invalid(format!(
                    "path {} does not exist (the drawing has {n_paths})",
                    o.path
                ))
            })?;
            let n_joints = path.joints.len();
            let slot = path.joints.get_mut(o.joint).ok_or_else(|| {
                invalid(format!(
                    "joint {} does not exist (path {} has {n_joints})",
                    o.joint, o.path
                ))
            })?;
            if *slot == JointKind::End {
                return Err(invalid(format!(
                    "joint {} of path {} is an open end: it has no junction",
                    o.joint, o.path
                )));
            }
            *slot = o.kind;
        }
        // Saved kinds the input does not have: our form keeps what the input has there
        // (the authors' form imposes the saved kinds as they are).
        if compat == Compat::None {
            let options = self.fit_options(compat).junctions;
            if let Some(note) = drawing.joint_mismatch_note(&options) {
                warnings.push(format!("{}: {note}", self.origin));
            }
        }
        Ok((drawing, warnings))
    }

    /// The fit options of the scene's measure in `compat`.
    pub fn fit_options(&self, compat: Compat) -> FitOptions {
        match compat {
            Compat::None => FitOptions::default().with_measure(self.measure),
            Compat::VectorSkinning => {
                FitOptions::vectorskinning(self.measure == crate::spline_fit::Measure::ArcLength)
            }
        }
    }

    /// The options of the flexible solve if the scene asks for flexible junctions
    /// ([`Scene::flexible`]): ours, or the authors' rule in compatibility mode.
    pub fn flexible_options(&self, compat: Compat) -> Option<FlexibleOptions> {
        self.flexible.then(|| compat.flexible_options())
    }

    /// The options of the flexible solve when the scene asks for it or `flag` (a command
    /// line's `--flexible`) does: [`Scene::flexible_options`], else `compat`'s
    /// ([`Compat::flexible_options`]) when `flag`, else `None`. What `deform`, `animate`,
    /// `compare` and `bench` use.
    pub fn flexible_options_or(&self, flag: bool, compat: Compat) -> Option<FlexibleOptions> {
        self.flexible_options(compat)
            .or_else(|| flag.then(|| compat.flexible_options()))
    }

    /// What the scene's weights are built from, in `compat`.
    pub fn weight_inputs(&self, compat: Compat) -> WeightInputs<'_> {
        WeightInputs {
            handles: self.handle_set(),
            family: &self.weights,
            domain: &self.domain,
            compat,
            origin: &self.origin,
            format: self.format,
            stop: None,
            solved: None,
        }
    }

    /// Reads the scene's SVG with the importer of `compat`, joints classified by it. Errors
    /// name [`Scene::svg_origin`] (our importer's as [`SceneError::Svg`], the authors' reader's
    /// as [`SceneError::Drawing`]); in our mode the drawing's [`crate::drawing::SvgSource`]
    /// carries it too, so export errors name it as well. In our mode a drawing the scene's
    /// maker read already ([`Scene::from_pins`]) is taken as it is, not read again.
    pub fn drawing(&self, compat: Compat) -> Result<Drawing, SceneError> {
        match compat {
            Compat::None => match self.read.of(&self.svg_text, &self.svg_origin) {
                // Read by the scene's maker already (Scene::from_pins): not read again.
                Some(drawing) => Ok(drawing),
                None => Ok(read_svg_named(
                    &self.svg_text,
                    &ImportOptions::default(),
                    &self.svg_origin,
                )?),
            },
            Compat::VectorSkinning => read_authors_drawing_named(&self.svg_text, &self.svg_origin)
                .map_err(|e| SceneError::Drawing {
                    origin: self.svg_origin.clone(),
                    source: Box::new(e),
                }),
        }
    }
}

/// Checks the rest handles that need no drawing: a cage of at least 3 vertices, without
/// zero-length edges, simple and counter-clockwise; no two point handles at the same place; no
/// bone of zero length. Errors name the element ([`SceneError::Invalid`]). (What needs the
/// drawing's size — near-coincidence, handles outside the domain — is checked when the domain
/// is built.)
pub fn check_rest_handles(
    handles: &HandleSet<'_>,
    origin: &str,
    format: SceneFormat,
) -> Result<(), SceneError> {
    let inputs_error = |e: DomainError| {
        SceneError::invalid(
            origin,
            domain_element(&e, format).unwrap_or_else(|| "handles".into()),
            e.to_string(),
        )
    };
    if let Some(cage) = handles.cage {
        check_cage(cage, 0.0).map_err(inputs_error)?;
        let area = signed_area(cage);
        if area == 0.0 || area.is_nan() {
            return Err(inputs_error(DomainError::EmptyDomain {
                reason: "the cage has zero area",
            }));
        }
    }
    let mut order: Vec<usize> = (0..handles.points.len()).collect();
    let key = |i: &usize| (handles.points[*i].x, handles.points[*i].y);
    order.sort_by(|a, b| {
        key(a)
            .partial_cmp(&key(b))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    for pair in order.windows(2) {
        if handles.points[pair[0]] == handles.points[pair[1]] {
            return Err(inputs_error(DomainError::CoincidentHandles {
                first: pair[0].min(pair[1]),
                second: pair[0].max(pair[1]),
                distance: 0.0,
            }));
        }
    }
    if let Some(bone) = handles.bones.iter().position(|b| b.ends[0] == b.ends[1]) {
        return Err(inputs_error(DomainError::DegenerateBone { bone }));
    }
    Ok(())
}

/// Applies the authors' saved per-joint kinds; returns what did not fit, if anything.
///
/// Their list has one entry per chain of their reading: every subpath of every `<path>`
/// element in document order, hidden layers, `defs` and clip paths included, other shapes
/// left out ([`crate::drawing::authors_svg`]). When the drawing has exactly that structure
/// (compatibility mode, or a document of visible `<path>`s only) entry `k` goes to path `k`.
/// Otherwise each path is matched to its entry through its source element
/// ([`crate::drawing::SvgSource::path_tag_position`]: the `k`-th `<path>`, subpath `s`), so
/// that hidden paths and paths our import reads but theirs does not (`<polygon>`, `<rect>`,
/// `use` copies, which keep their classified kinds) do not shift the others. An entry is
/// applied only where its length fits the path (`n` curves or its joint count).
///
/// Their `C1` is not strict C¹: their solver writes it as a tangent of fixed direction and
/// fixed length *ratio* (the input's), which is our [`JointKind::G1`]. In default mode it is
/// read as such, so a junction whose tangents have different lengths keeps its shape (strict
/// C¹ would make the lengths equal). Compatibility mode keeps the label: its constraint form
/// writes their rows for both.
fn apply_authors_joints(
    drawing: &mut Drawing,
    kinds: &[Vec<JointKind>],
    svg_text: &str,
    compat: Compat,
) -> Option<String> {
    if kinds.is_empty() {
        return None;
    }
    let fits = |p: &crate::drawing::Path, k: &[JointKind]| {
        k.len() == p.n_curves() || k.len() == p.joints.len()
    };
    let same_structure = kinds.len() == drawing.paths.len()
        && drawing.paths.iter().zip(kinds).all(|(p, k)| fits(p, k));
    let entries: Vec<Option<usize>> = if same_structure {
        (0..kinds.len()).map(Some).collect()
    } else {
        match authors_entries(drawing, kinds.len(), svg_text) {
            Some(entries) => entries,
            None => {
                return Some(format!(
                    "the saved junction kinds ({} paths) do not match the drawing as read ({} \
                     paths); they are ignored and junctions are classified from the geometry",
                    kinds.len(),
                    drawing.paths.len()
                ))
            }
        }
    };
    let mut unfit = Vec::new();
    for (i, entry) in entries.iter().enumerate() {
        if let Some(k) = entry {
            if !fits(&drawing.paths[i], &kinds[*k]) {
                unfit.push(i);
            }
        }
    }
    let n_applied = entries.iter().flatten().count() - unfit.len();
    for (i, (path, entry)) in drawing.paths.iter_mut().zip(&entries).enumerate() {
        let Some(k) = entry.filter(|_| !unfit.contains(&i)).map(|k| &kinds[k]) else {
            continue;
        };
        let n = path.joints.len();
        for (j, slot) in path.joints.iter_mut().enumerate() {
            let open_end = !path.closed && (j == 0 || j + 1 == n);
            if open_end {
                *slot = JointKind::End;
            } else if let Some(&kind) = k.get(j) {
                *slot = match (kind, compat) {
                    (JointKind::End, _) => *slot,
                    // Matched by element (their structure differs from ours), in default mode
                    // a saved smooth kind is not imposed where the input is not smooth: that
                    // would move the drawing at rest (the turtles have such junctions).
                    (JointKind::C1 | JointKind::G1, Compat::None)
                        if !same_structure
                            && matches!(*slot, JointKind::C0 | JointKind::FixedAngle) =>
                    {
                        *slot
                    }
                    (JointKind::C1, Compat::None) => JointKind::G1,
                    _ => kind,
                };
            }
        }
    }
    if unfit.is_empty() && n_applied == kinds.len() {
        return None;
    }
    let shown: Vec<String> = unfit.iter().take(5).map(|i| format!("path {i}")).collect();
    Some(format!(
        "{n_applied} of the {} saved junction kinds were applied{}",
        kinds.len(),
        if unfit.is_empty() {
            String::new()
        } else {
            format!(
                "; {} ({}{}) did not fit the curves as read and are classified from the geometry",
                unfit.len(),
                shown.join(", "),
                if unfit.len() > shown.len() {
                    ", …"
                } else {
                    ""
                }
            )
        }
    ))
}

/// For each path of `drawing`, the index of its entry in the authors' per-chain list of
/// `n_entries` ([`apply_authors_joints`]), through its source element; `None` where it has
/// none. `None` overall when the authors' reading of `svg_text` does not produce `n_entries`
/// chains, or the drawing has no source.
fn authors_entries(
    drawing: &Drawing,
    n_entries: usize,
    svg_text: &str,
) -> Option<Vec<Option<usize>>> {
    let source = drawing.source.as_ref()?;
    let chains = crate::drawing::authors_svg::read_authors_paths(svg_text).ok()?;
    if chains.len() != n_entries {
        return None;
    }
    // First chain and number of chains of every `<path>` element.
    let mut first: std::collections::HashMap<usize, (usize, usize)> = Default::default();
    for (k, chain) in chains.iter().enumerate() {
        first.entry(chain.element).or_insert((k, 0)).1 += 1;
    }
    // Our subpath count per element, so that elements read differently get no entries.
    let mut ours: std::collections::HashMap<usize, usize> = Default::default();
    for i in 0..drawing.paths.len() {
        if let Some((k, _)) = source.path_tag_position(i) {
            *ours.entry(k).or_default() += 1;
        }
    }
    Some(
        (0..drawing.paths.len())
            .map(|i| {
                let (k, s) = source.path_tag_position(i)?;
                let &(start, count) = first.get(&k)?;
                (ours.get(&k) == Some(&count)).then_some(start + s)
            })
            .collect(),
    )
}
