//! [`Puppet`]: a scene's drawing and handles with their weights and rig cached, for
//! interactive use (the editor): moving a handle's *transform* is one matrix–vector product;
//! moving its *rest position* recomputes the weights and the rig (DESIGN.md §2: "weights are a
//! precomputation; cache them with the rig").

use kurbo::{Affine, Point};

use super::handles::HandleSet;
use super::setup::{check_rest_handles, handle_weights, Compat, WeightInputs};
use super::{Bone, HandleKind, Scene, SceneError, SceneFormat, WeightSpec};
use crate::domain::{Domain, DomainOptions};
use crate::drawing::Drawing;
use crate::spline_fit::quadrature::SampledCurves;
use crate::spline_fit::{FitOptions, FlexibleOptions, FlexibleSolver, SplineRig};
use crate::weights::WeightField;

/// How often a [`Puppet`] has computed its weights and its rig, and run its update.
///
/// Tests use it to show that a pose change reuses both and a rest change recomputes both.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PuppetStats {
    /// Weight computations (for mesh families: triangulation and solve).
    pub weight_builds: u64,
    /// Rig precomputations ([`SplineRig::precompute`]).
    pub rig_builds: u64,
    /// Calls of [`Puppet::update`] that wrote a result.
    pub updates: u64,
}

/// The part of [`Puppet::from_scene_staged`]'s work that starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PuppetStage {
    /// Reading the drawing and computing the weights (mesh families: the domain and its solve).
    Weights,
    /// Precomputing the rig (with flexible junctions, the flexible solver too).
    Rig,
}

/// A rigged drawing whose handles can be edited: the weights and the rig are cached and only
/// recomputed when what they depend on changes.
///
/// | change | weights | rig |
/// |---|---|---|
/// | a pose ([`Puppet::set_pose`], [`Puppet::set_transform`]) | kept | kept |
/// | a rest position, adding or removing a handle, the cage, the family, the domain options | recomputed | recomputed |
/// | the fit options ([`Puppet::set_fit_options`]), flexible on or off ([`Puppet::set_flexible`]) | kept | recomputed |
///
/// **Flexible junctions.** When the scene asks for them (`"flexible": true`, the authors'
/// scenes) or [`Puppet::set_flexible`] turns them on, [`Puppet::update`] runs the flexible
/// solve ([`FlexibleSolver`]) instead of the mat-vec, warm-started from the previous update's
/// result (a drag moves the pose a little between frames); this allocates and costs a few
/// sparse refactorisations per frame.
///
/// Recomputation is **lazy**: an edit marks what it invalidates as stale (and is checked at
/// once: an edit that would make the handles invalid is refused and changes nothing); the
/// next [`Puppet::update`] or [`Puppet::rebuild`] recomputes it. An edit that sets what is
/// already there invalidates nothing. After any sequence of edits the result is exactly that
/// of a puppet built from scratch on the edited scene (same functions, same order).
///
/// ```text
/// once:         let mut puppet = Puppet::from_scene(&scene, Compat::None)?;
/// each frame:   puppet.set_transform(i, t)?;  puppet.update(&mut points)?;   // mat-vec only
/// on drop:      puppet.set_point_handle(i, p)?;  // next update recomputes weights and rig
/// ```
///
/// The pose has one map per handle in rig order (points, bones, cage vertices;
/// [`super::handles`]). Adding a handle gives it the identity; removing one drops its map.
///
/// ```
/// use kurbo::{Affine, Point};
/// use splineskin::scene::{Compat, Puppet, Scene};
/// let json = r#"{
///   "splineskin_scene": 1,
///   "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>",
///   "handles": [{"position": [0, 0]}, {"position": [3, 0]}]
/// }"#;
/// let scene = Scene::from_json(json, "example", None)?;
/// let mut puppet = Puppet::from_scene(&scene, Compat::None)?;
/// let mut points = vec![Point::ZERO; puppet.n_points()];
/// puppet.set_transform(1, Affine::translate((0.0, 2.0)))?;
/// puppet.update(&mut points)?;
/// assert_eq!(puppet.stats().weight_builds, 1); // the pose change reused the weights
/// puppet.set_point_handle(1, Point::new(2.5, 0.0))?;
/// puppet.update(&mut points)?;
/// assert_eq!(puppet.stats().weight_builds, 2); // the rest change recomputed them
/// # Ok::<(), splineskin::scene::SceneError>(())
/// ```
pub struct Puppet {
    origin: String,
    format: SceneFormat,
    compat: Compat,
    drawing: Drawing,
    points: Vec<Point>,
    bones: Vec<Bone>,
    cage: Option<Vec<Point>>,
    family: WeightSpec,
    domain_options: DomainOptions,
    fit_options: FitOptions,
    /// One map per handle, rig order.
    pose: Vec<Affine>,
    /// `None`: stale.
    weights: Option<(Box<dyn WeightField>, Option<Domain>)>,
    /// `None`: stale.
    rig: Option<SplineRig>,
    /// Flexible G¹ options, `None` for the fixed-ratio fit.
    flexible: Option<FlexibleOptions>,
    /// The flexible solver (flexible only; `None`: stale).
    solver: Option<FlexibleSolver>,
    /// The last flexible result, the next solve's warm start (empty: none).
    last: Vec<Point>,
    stats: PuppetStats,
}

impl Puppet {
    /// Sets up `scene` in `compat` ([`Scene::setup`]: drawing with its junction kinds, weights)
    /// and builds the rig at once. The pose is the scene's first (identity without poses).
    /// Errors if the scene's engine is a naive baseline (those are not rigs:
    /// [`super::Deformer`] applies them).
    pub fn from_scene(scene: &Scene, compat: Compat) -> Result<Puppet, SceneError> {
        Puppet::from_scene_staged(scene, compat, &mut |_| {})
    }

    /// [`Puppet::from_scene`], calling `stage` as each part of the work starts (for a progress
    /// display: the weights of mesh families and the rig of big drawings take seconds).
    ///
    /// ```
    /// use splineskin::scene::{Compat, Puppet, PuppetStage, Scene};
    /// let json = r#"{"splineskin_scene": 1,
    ///   "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0'/></svg>",
    ///   "handles": [{"position": [0, 0]}, {"position": [3, 0]}]}"#;
    /// let scene = Scene::from_json(json, "example", None)?;
    /// let mut stages = Vec::new();
    /// Puppet::from_scene_staged(&scene, Compat::None, &mut |s| stages.push(s))?;
    /// assert_eq!(stages, [PuppetStage::Weights, PuppetStage::Rig]);
    /// # Ok::<(), splineskin::scene::SceneError>(())
    /// ```
    pub fn from_scene_staged(
        scene: &Scene,
        compat: Compat,
        stage: &mut dyn FnMut(PuppetStage),
    ) -> Result<Puppet, SceneError> {
        if scene.engine != super::Engine::Ours {
            return Err(SceneError::Invalid {
                origin: scene.origin.clone(),
                element: "engine".into(),
                message: format!(
                    "a puppet deforms with engine 'ours'; this scene's engine is '{}' (a naive \
                     baseline: apply it with scene::Deformer)",
                    scene.engine.name()
                ),
            });
        }
        stage(PuppetStage::Weights);
        let setup = scene.setup(compat)?;
        let mut puppet = Puppet {
            origin: scene.origin.clone(),
            format: scene.format,
            compat,
            drawing: setup.drawing,
            points: scene.handles.clone(),
            bones: scene.bones.clone(),
            cage: scene.cage.clone(),
            family: scene.weights.clone(),
            domain_options: scene.domain.clone(),
            fit_options: setup.options,
            pose: scene
                .pose(0)
                .map(|p| p.transforms)
                .unwrap_or_else(|| vec![Affine::IDENTITY; scene.n_handles()]),
            weights: Some((setup.weights, setup.domain)),
            rig: None,
            flexible: scene.flexible_options(compat),
            solver: None,
            last: Vec::new(),
            stats: PuppetStats {
                weight_builds: 1,
                ..PuppetStats::default()
            },
        };
        stage(PuppetStage::Rig);
        puppet.rebuild()?;
        Ok(puppet)
    }

    /// Recomputes what is stale: the weights (if a rest position, the handle set, the family
    /// or the domain options changed), then the rig (if the weights or the fit options did).
    /// Does nothing when nothing is stale. On error the stale parts stay stale.
    pub fn rebuild(&mut self) -> Result<(), SceneError> {
        self.fresh_rig().map(|_| ())
    }

    /// The rig (and with flexible junctions the flexible solver), recomputing what is stale
    /// first.
    fn fresh_rig(&mut self) -> Result<&SplineRig, SceneError> {
        let weights = match self.weights.take() {
            Some(w) => w,
            None => {
                let built = handle_weights(&self.drawing, &self.inputs())?;
                self.stats.weight_builds += 1;
                built
            }
        };
        let weights = self.weights.insert(weights);
        let rig_error = |origin: &str, e: crate::spline_fit::FitError| SceneError::Rig {
            origin: origin.to_string(),
            source: Box::new(e),
        };
        if self.rig.is_none() {
            let (rig, solver) = match self.flexible {
                None => (
                    SplineRig::precompute(&self.drawing, weights.0.as_ref(), &self.fit_options)
                        .map_err(|e| rig_error(&self.origin, e))?,
                    None,
                ),
                Some(options) => {
                    let samples =
                        SampledCurves::sample(&self.drawing, weights.0.as_ref(), &self.fit_options);
                    let solver =
                        FlexibleSolver::new(&self.drawing, &samples, &self.fit_options, options)
                            .map_err(|e| rig_error(&self.origin, e))?;
                    (solver.rig().clone(), Some(solver))
                }
            };
            self.solver = solver;
            self.last.clear();
            self.stats.rig_builds += 1;
            self.rig = Some(rig);
        }
        Ok(self.rig.as_ref().expect("just built"))
    }

    /// Writes the drawing deformed by the current pose into `out` (length
    /// [`Puppet::n_points`], layout of [`Drawing::flat_points`]). Recomputes stale weights and
    /// rig first ([`Puppet::rebuild`]); otherwise one matrix–vector product, no allocation —
    /// or, with flexible junctions, the flexible solve warm-started from the previous result.
    pub fn update(&mut self, out: &mut [Point]) -> Result<(), SceneError> {
        self.fresh_rig()?;
        let fit_error =
            |origin: &str, e: Box<dyn std::error::Error + Send + Sync>| SceneError::Rig {
                origin: origin.to_string(),
                source: e,
            };
        match (&self.solver, &self.rig) {
            (Some(solver), _) => {
                let warm = (self.last.len() == out.len()).then_some(self.last.as_slice());
                solver
                    .solve(&self.pose, warm, out)
                    .map_err(|e| fit_error(&self.origin, Box::new(e)))?;
                self.last.clear();
                self.last.extend_from_slice(out);
            }
            (None, Some(rig)) => rig
                .update(&self.pose, out)
                .map_err(|e| fit_error(&self.origin, Box::new(e)))?,
            (None, None) => return Ok(()),
        }
        self.stats.updates += 1;
        Ok(())
    }

    /// Turns flexible G¹ and fixed-angle junctions on (`Some`) or off. Invalidates the rig
    /// (not the weights) when it changes something.
    pub fn set_flexible(&mut self, options: Option<FlexibleOptions>) {
        if options != self.flexible {
            self.flexible = options;
            self.invalidate_rig();
        }
    }

    /// The flexible options, `None` when junctions keep their ratio.
    pub fn flexible(&self) -> Option<&FlexibleOptions> {
        self.flexible.as_ref()
    }

    /// Sets every handle's map (one per handle, rig order). Invalidates nothing.
    pub fn set_pose(&mut self, transforms: &[Affine]) -> Result<(), SceneError> {
        if transforms.len() != self.pose.len() {
            return Err(self.invalid(
                "pose".into(),
                format!(
                    "{} transforms for {} handles (one per handle expected)",
                    transforms.len(),
                    self.pose.len()
                ),
            ));
        }
        self.pose.copy_from_slice(transforms);
        Ok(())
    }

    /// Sets handle `i`'s map (rig order). Invalidates nothing.
    pub fn set_transform(&mut self, i: usize, transform: Affine) -> Result<(), SceneError> {
        let n = self.pose.len();
        match self.pose.get_mut(i) {
            Some(t) => {
                *t = transform;
                Ok(())
            }
            None => Err(self.invalid(
                format!("pose[{i}]"),
                format!("no handle {i} (the puppet has {n})"),
            )),
        }
    }

    /// Moves point handle `i` to rest position `p`: weights and rig become stale (unless `p`
    /// is where it already is). Refused (nothing changed) if it would coincide with another
    /// point handle or is not finite.
    pub fn set_point_handle(&mut self, i: usize, p: Point) -> Result<(), SceneError> {
        let mut points = self.points.clone();
        let n = points.len();
        *points.get_mut(i).ok_or_else(|| {
            self.invalid(
                format!("handles[{i}]"),
                format!("no such point handle (there are {n})"),
            )
        })? = p;
        self.edit_rest(points, self.bones.clone(), self.cage.clone(), None)
    }

    /// Adds a point handle at rest position `p` with the identity map; returns its index among
    /// the point handles (= its rig index). Weights and rig become stale.
    pub fn add_point_handle(&mut self, p: Point) -> Result<usize, SceneError> {
        let mut points = self.points.clone();
        points.push(p);
        let i = points.len() - 1;
        let mut pose = self.pose.clone();
        pose.insert(i, Affine::IDENTITY);
        self.edit_rest(points, self.bones.clone(), self.cage.clone(), Some(pose))?;
        Ok(i)
    }

    /// Removes point handle `i` and its map. Weights and rig become stale.
    pub fn remove_point_handle(&mut self, i: usize) -> Result<(), SceneError> {
        if i >= self.points.len() {
            return Err(self.invalid(
                format!("handles[{i}]"),
                format!("no such point handle (there are {})", self.points.len()),
            ));
        }
        let mut points = self.points.clone();
        points.remove(i);
        let mut pose = self.pose.clone();
        pose.remove(i);
        self.edit_rest(points, self.bones.clone(), self.cage.clone(), Some(pose))
    }

    /// Replaces bone `b` (rest end points and kind). Weights and rig become stale unless it is
    /// unchanged.
    pub fn set_bone(&mut self, b: usize, bone: Bone) -> Result<(), SceneError> {
        let mut bones = self.bones.clone();
        let n = bones.len();
        *bones.get_mut(b).ok_or_else(|| {
            self.invalid(
                format!("bones[{b}]"),
                format!("no such bone (there are {n})"),
            )
        })? = bone;
        self.edit_rest(self.points.clone(), bones, self.cage.clone(), None)
    }

    /// Moves cage vertex `k` to rest position `p`. Weights and rig become stale unless it is
    /// unchanged. Refused if the cage would not stay a simple counter-clockwise polygon.
    pub fn set_cage_vertex(&mut self, k: usize, p: Point) -> Result<(), SceneError> {
        let mut cage = self.cage.clone().unwrap_or_default();
        let n = cage.len();
        *cage.get_mut(k).ok_or_else(|| {
            self.invalid(
                format!("cage[{k}]"),
                format!("no such cage vertex (the cage has {n})"),
            )
        })? = p;
        self.edit_rest(self.points.clone(), self.bones.clone(), Some(cage), None)
    }

    /// Replaces every rest handle at once. The pose is kept when the numbers of points, bones
    /// and cage vertices are unchanged, else reset to the identity.
    pub fn set_handles(
        &mut self,
        points: Vec<Point>,
        bones: Vec<Bone>,
        cage: Option<Vec<Point>>,
    ) -> Result<(), SceneError> {
        self.edit_rest(points, bones, cage, None)
    }

    /// Sets the weight family. Weights and rig become stale unless it is unchanged.
    pub fn set_weights(&mut self, family: WeightSpec) -> Result<(), SceneError> {
        family.check_handles(&self.handles(), &self.origin, "weights")?;
        if family != self.family {
            self.family = family;
            self.invalidate_weights();
        }
        Ok(())
    }

    /// Sets the domain options of the mesh families (their `cage` must be unset: the
    /// puppet's cage is used). Weights and rig become stale unless they are unchanged.
    pub fn set_domain_options(&mut self, options: DomainOptions) -> Result<(), SceneError> {
        if options.cage.is_some() {
            return Err(self.invalid(
                "domain.cage".into(),
                "set the cage with set_handles, not in the domain options".into(),
            ));
        }
        if options != self.domain_options {
            self.domain_options = options;
            self.invalidate_weights();
        }
        Ok(())
    }

    /// Sets the fit options. The rig becomes stale; the weights are kept.
    pub fn set_fit_options(&mut self, options: FitOptions) {
        if options != self.fit_options {
            self.fit_options = options;
            self.invalidate_rig();
        }
    }

    /// The drawing (with its junction kinds).
    pub fn drawing(&self) -> &Drawing {
        &self.drawing
    }

    /// The rest handles, rig order.
    pub fn handles(&self) -> HandleSet<'_> {
        HandleSet {
            points: &self.points,
            bones: &self.bones,
            cage: self.cage.as_deref(),
        }
    }

    /// Number of handles (points + bones + cage vertices).
    pub fn n_handles(&self) -> usize {
        self.pose.len()
    }

    /// Number of chain points [`Puppet::update`] writes.
    pub fn n_points(&self) -> usize {
        self.drawing.n_points()
    }

    /// The current pose, one map per handle.
    pub fn pose(&self) -> &[Affine] {
        &self.pose
    }

    /// The weight family.
    pub fn family(&self) -> &WeightSpec {
        &self.family
    }

    /// The domain options.
    pub fn domain_options(&self) -> &DomainOptions {
        &self.domain_options
    }

    /// The fit options.
    pub fn fit_options(&self) -> &FitOptions {
        &self.fit_options
    }

    /// The cached weights, or `None` while stale.
    pub fn weights(&self) -> Option<&dyn WeightField> {
        self.weights.as_ref().map(|w| w.0.as_ref())
    }

    /// The triangulated domain of the cached weights (mesh families), or `None` while stale
    /// or for closed-form families.
    pub fn domain(&self) -> Option<&Domain> {
        self.weights.as_ref().and_then(|w| w.1.as_ref())
    }

    /// The cached rig, or `None` while stale.
    pub fn rig(&self) -> Option<&SplineRig> {
        self.rig.as_ref()
    }

    /// Whether the next [`Puppet::update`] recomputes something.
    pub fn is_stale(&self) -> bool {
        self.weights.is_none() || self.rig.is_none()
    }

    /// Counts of weight and rig computations and updates so far.
    pub fn stats(&self) -> PuppetStats {
        self.stats
    }

    /// Validates new rest handles, then commits them with `pose` (or, if `None`, the current
    /// pose when the counts of each kind are unchanged, else the identity) and invalidates the
    /// weights if they differ. Nothing changes on error.
    fn edit_rest(
        &mut self,
        points: Vec<Point>,
        bones: Vec<Bone>,
        cage: Option<Vec<Point>>,
        pose: Option<Vec<Affine>>,
    ) -> Result<(), SceneError> {
        let set = HandleSet {
            points: &points,
            bones: &bones,
            cage: cage.as_deref(),
        };
        let finite = |kind: HandleKind, p: Point| {
            super::check_point([p.x, p.y], &self.origin, self.element(kind)).map(|_| ())
        };
        for (i, &p) in points.iter().enumerate() {
            finite(HandleKind::Point(i), p)?;
        }
        for (b, bone) in bones.iter().enumerate() {
            for p in bone.ends {
                finite(HandleKind::Bone(b), p)?;
            }
        }
        for (k, &p) in cage.iter().flatten().enumerate() {
            finite(HandleKind::CageVertex(k), p)?;
        }
        check_rest_handles(&set, &self.origin, self.format)?;
        self.family.check_handles(&set, &self.origin, "weights")?;
        if points == self.points && bones == self.bones && cage == self.cage {
            return Ok(());
        }
        let n_handles = set.n_handles();
        let old = self.handles();
        let same_counts = old.points.len() == points.len()
            && old.bones.len() == bones.len()
            && old.n_cage_vertices() == set.n_cage_vertices();
        match pose {
            Some(pose) => self.pose = pose,
            None if same_counts => {}
            None => self.pose = vec![Affine::IDENTITY; n_handles],
        }
        self.points = points;
        self.bones = bones;
        self.cage = cage;
        self.invalidate_weights();
        Ok(())
    }

    fn invalidate_weights(&mut self) {
        self.weights = None;
        self.invalidate_rig();
    }

    fn invalidate_rig(&mut self) {
        self.rig = None;
        self.solver = None;
        self.last.clear();
    }

    fn inputs(&self) -> WeightInputs<'_> {
        WeightInputs {
            handles: self.handles(),
            family: &self.family,
            domain: &self.domain_options,
            compat: self.compat,
            origin: &self.origin,
            format: self.format,
        }
    }

    fn element(&self, kind: HandleKind) -> String {
        super::handle_element(self.format, kind)
    }

    fn invalid(&self, element: String, message: String) -> SceneError {
        SceneError::Invalid {
            origin: self.origin.clone(),
            element,
            message,
        }
    }
}
