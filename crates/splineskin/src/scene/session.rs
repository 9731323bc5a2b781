//! [`Puppet`]: the editable layer over a [`PosedDrawing`], for interactive use (the editor):
//! it keeps the rest handles, the weight family and the options, and the posed drawing built
//! from them (weights and rig) until an edit invalidates it. Moving a handle's *transform* is
//! one [`PosedDrawing::update`] (for the fixed-ratio rig one matrix–vector product); moving its
//! *rest position* recomputes the weights and the rig (DESIGN.md §2: "weights are a
//! precomputation; cache them with the rig").

use kurbo::{Affine, Point};

use super::compat::Compat;
use super::deformer::Deformer;
use super::handle_weights::{handle_weights, WeightInputs};
use super::handles::HandleSet;
use super::posed::PosedDrawing;
use super::setup::{check_rest_handles, Setup, SetupControl};
use super::{Bone, HandleKind, Scene, SceneError, SceneFormat, WeightSpec};
use crate::domain::{Domain, DomainOptions};
use crate::drawing::Drawing;
use crate::spline_fit::{FitOptions, FlexibleOptions, SplineRig};
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

/// A puppet with adaptive control points ([`Puppet::refined`]) and what the refinement did.
#[non_exhaustive]
pub struct RefinedPuppet {
    /// The puppet of the refined drawing.
    pub puppet: Puppet,
    /// Per path, per joint of the refined drawing: whether the anchor was inserted (as
    /// [`crate::adaptive::Refined::inserted`]).
    pub inserted: Vec<Vec<bool>>,
    /// The largest distance of the fit from the target over the poses, fraction of the
    /// drawing's diagonal.
    pub worst: f64,
    /// Rounds of splitting done.
    pub rounds: usize,
    /// Whether every curve is within the tolerance (else the curve budget ran out).
    pub met: bool,
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
/// solve ([`crate::spline_fit::FlexibleSolver`]) instead of the mat-vec, warm-started from the
/// previous update's result (a drag moves the pose a little between frames); this allocates
/// and costs a few sparse refactorisations per frame.
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
    points: Vec<Point>,
    bones: Vec<Bone>,
    cage: Option<Vec<Point>>,
    family: WeightSpec,
    domain_options: DomainOptions,
    fit_options: FitOptions,
    /// One map per handle, rig order.
    pose: Vec<Affine>,
    /// What is computed: the drawing only, its weights too, or the whole posed drawing.
    cache: Cache,
    /// Flexible G¹ options, `None` for the fixed-ratio fit.
    flexible: Option<FlexibleOptions>,
    /// The last flexible result, the next solve's warm start (empty: none).
    last: Vec<Point>,
    stats: PuppetStats,
}

/// What a [`Puppet`] has computed.
enum Cache {
    /// The drawing only: the weights (and so the rig) are stale.
    Drawing(Drawing),
    /// The drawing and its weights (the setup's fit options may be stale): the rig is stale.
    Weights(Setup),
    /// Everything.
    Posed(PosedDrawing),
}

impl Cache {
    fn drawing(&self) -> &Drawing {
        match self {
            Cache::Drawing(drawing) => drawing,
            Cache::Weights(setup) => &setup.drawing,
            Cache::Posed(posed) => posed.drawing(),
        }
    }

    fn setup(&self) -> Option<&Setup> {
        match self {
            Cache::Drawing(_) => None,
            Cache::Weights(setup) => Some(setup),
            Cache::Posed(posed) => Some(posed.setup()),
        }
    }
}

impl Puppet {
    /// Sets up `scene` in `compat` ([`Scene::setup`]: drawing with its junction kinds, weights)
    /// and builds the rig at once. The pose is the scene's first (identity without poses).
    /// Errors if the scene's engine is a naive baseline (those are not rigs:
    /// [`PosedDrawing`] applies them).
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
        Puppet::from_scene_with(scene, compat, stage, SetupControl::default())
    }

    /// [`Puppet::from_scene_staged`] under `control` ([`Scene::setup_with`]): bounded
    /// biharmonic weights that stop when asked (an editor's superseded request frees its
    /// cores) and columns solved elsewhere taken as given.
    ///
    /// ```
    /// use splineskin::scene::{Compat, Puppet, Scene, SceneError, SetupControl};
    /// use splineskin::stop::StopSignal;
    /// use splineskin::weights::WeightsError;
    /// let json = r#"{"splineskin_scene": 1,
    ///   "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0' stroke='black'/></svg>",
    ///   "handles": [{"position": [0, 0]}, {"position": [3, 0]}], "weights": {"family": "bbw"}}"#;
    /// let scene = Scene::from_json(json, "example", None)?;
    /// let stop = StopSignal::new();
    /// stop.raise();
    /// let control = SetupControl { stop: Some(&stop), ..Default::default() };
    /// let stopped = Puppet::from_scene_with(&scene, Compat::None, &mut |_| {}, control);
    /// let Err(SceneError::Weights { source, .. }) = stopped else { panic!("not stopped") };
    /// assert_eq!(source.downcast_ref::<WeightsError>(), Some(&WeightsError::Stopped));
    /// let control = SetupControl::default();
    /// assert!(Puppet::from_scene_with(&scene, Compat::None, &mut |_| {}, control).is_ok());
    /// # Ok::<(), splineskin::scene::SceneError>(())
    /// ```
    pub fn from_scene_with(
        scene: &Scene,
        compat: Compat,
        stage: &mut dyn FnMut(PuppetStage),
        control: SetupControl<'_>,
    ) -> Result<Puppet, SceneError> {
        if scene.engine != super::Engine::Ours {
            return Err(SceneError::Invalid {
                origin: scene.origin.clone(),
                element: "engine".into(),
                message: format!(
                    "a puppet deforms with engine 'ours'; this scene's engine is '{}' (a naive \
                     baseline: apply it with scene::PosedDrawing)",
                    scene.engine.name()
                ),
            });
        }
        stage(PuppetStage::Weights);
        let setup = scene.setup_with(compat, control)?;
        let mut puppet = Puppet {
            origin: scene.origin.clone(),
            format: scene.format,
            compat,
            points: scene.handles.clone(),
            bones: scene.bones.clone(),
            cage: scene.cage.clone(),
            family: scene.weights.clone(),
            domain_options: scene.domain.clone(),
            fit_options: setup.options,
            cache: Cache::Weights(setup),
            pose: scene
                .pose(0)
                .map(|p| p.transforms)
                .unwrap_or_else(|| vec![Affine::IDENTITY; scene.n_handles()]),
            flexible: scene.flexible_options(compat),
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
        let cache = self.take_cache();
        let (cache, result) = self.refreshed(cache);
        self.cache = cache;
        result
    }

    /// `cache` with what is stale recomputed: the weights, then the rig (and with flexible
    /// junctions the flexible solver). On error, what was computed before the failing step.
    fn refreshed(&mut self, cache: Cache) -> (Cache, Result<(), SceneError>) {
        let mut setup = match cache {
            Cache::Posed(posed) => return (Cache::Posed(posed), Ok(())),
            Cache::Weights(setup) => setup,
            Cache::Drawing(drawing) => match handle_weights(&drawing, &self.inputs()) {
                Ok((weights, domain)) => {
                    self.stats.weight_builds += 1;
                    Setup {
                        drawing,
                        weights,
                        options: self.fit_options,
                        warnings: Vec::new(),
                        domain,
                    }
                }
                Err(e) => return (Cache::Drawing(drawing), Err(e)),
            },
        };
        setup.options = self.fit_options;
        match Deformer::fit(
            &setup.drawing,
            setup.weights.as_ref(),
            &setup.options,
            self.flexible,
        ) {
            Ok(deformer) => {
                self.last.clear();
                self.stats.rig_builds += 1;
                let posed = PosedDrawing::from_parts(self.origin.clone(), setup, deformer);
                (Cache::Posed(posed), Ok(()))
            }
            Err(e) => {
                let error = SceneError::Rig {
                    origin: self.origin.clone(),
                    source: Box::new(e),
                };
                (Cache::Weights(setup), Err(error))
            }
        }
    }

    /// Writes the drawing deformed by the current pose into `out` (length
    /// [`Puppet::n_points`], layout of [`Drawing::flat_points`]). Recomputes stale weights and
    /// rig first ([`Puppet::rebuild`]); then [`PosedDrawing::update`]: one matrix–vector
    /// product, no allocation — or, with flexible junctions, the flexible solve warm-started
    /// from the previous result. A result that is not finite is an error
    /// ([`super::UpdateError::NotFinite`]).
    pub fn update(&mut self, out: &mut [Point]) -> Result<(), SceneError> {
        self.rebuild()?;
        let Cache::Posed(posed) = &self.cache else {
            return Ok(());
        };
        let warm = (self.last.len() == out.len()).then_some(self.last.as_slice());
        let report = posed
            .update_from(&self.pose, warm, out)
            .map_err(|e| SceneError::Rig {
                origin: self.origin.clone(),
                source: Box::new(e),
            })?;
        if report.flexible.is_some() {
            self.last.clear();
            self.last.extend_from_slice(out);
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
        let points = self.replaced(&self.points, i, p, "handles", |n| {
            format!("no such point handle (there are {n})")
        })?;
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
        let bones = self.replaced(&self.bones, b, bone, "bones", |n| {
            format!("no such bone (there are {n})")
        })?;
        self.edit_rest(self.points.clone(), bones, self.cage.clone(), None)
    }

    /// Moves cage vertex `k` to rest position `p`. Weights and rig become stale unless it is
    /// unchanged. Refused if the cage would not stay a simple counter-clockwise polygon.
    pub fn set_cage_vertex(&mut self, k: usize, p: Point) -> Result<(), SceneError> {
        let cage = self.cage.as_deref().unwrap_or_default();
        let cage = self.replaced(cage, k, p, "cage", |n| {
            format!("no such cage vertex (the cage has {n})")
        })?;
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
        self.cache.drawing()
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
        self.drawing().n_points()
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
        self.cache.setup().map(|s| s.weights.as_ref())
    }

    /// The triangulated domain of the cached weights (mesh families), or `None` while stale
    /// or for closed-form families.
    pub fn domain(&self) -> Option<&Domain> {
        self.cache.setup().and_then(|s| s.domain.as_ref())
    }

    /// The cached rig, or `None` while stale.
    pub fn rig(&self) -> Option<&SplineRig> {
        self.posed().and_then(|p| p.rig())
    }

    /// The cached posed drawing (weights, rig and, with flexible junctions, the flexible
    /// solver), or `None` while stale.
    pub fn posed(&self) -> Option<&PosedDrawing> {
        match &self.cache {
            Cache::Posed(posed) => Some(posed),
            _ => None,
        }
    }

    /// Whether the next [`Puppet::update`] recomputes something.
    pub fn is_stale(&self) -> bool {
        self.posed().is_none()
    }

    /// A puppet of this one's drawing with adaptive control points
    /// ([`crate::adaptive::refine`]): input curves split at rest where the fit falls further
    /// than `options.tolerance` from the skinned target under any of `poses`. The new puppet
    /// shares this one's weights (the drawing is the same shape, so they are not recomputed),
    /// handles, pose, family and flexible setting; its drawing has the split curves, the new
    /// anchors G¹. Computes what is stale first ([`Puppet::rebuild`]).
    ///
    /// Errors: those of [`Puppet::rebuild`], and the refinement's (a tolerance that is not
    /// positive, no poses, a pose of the wrong length) as [`SceneError::Rig`].
    ///
    /// ```
    /// use kurbo::{Affine, Point};
    /// use splineskin::adaptive::AdaptiveOptions;
    /// use splineskin::scene::{Compat, Puppet, Scene};
    /// // One long curve whose ends are lifted while its middle stays: one cubic cannot follow.
    /// let json = r#"{"splineskin_scene": 1,
    ///   "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C30 0 70 0 100 0'/></svg>",
    ///   "handles": [{"position": [0, 0]}, {"position": [50, 0]}, {"position": [100, 0]}]}"#;
    /// let mut puppet = Puppet::from_scene(&Scene::from_json(json, "example", None)?, Compat::None)?;
    /// let lift = Affine::translate((0.0, 20.0));
    /// let pose = vec![lift, Affine::IDENTITY, lift];
    /// let refined = puppet.refined(&[pose.clone()], &AdaptiveOptions::default())?;
    /// assert!(refined.met && refined.puppet.drawing().n_curves() > 1);
    /// assert_eq!(refined.puppet.stats().weight_builds, 0); // the weights were shared
    /// // The artist's anchors are kept; the new ones are marked.
    /// assert!(!refined.inserted[0][0] && refined.inserted[0].iter().any(|&b| b));
    /// # Ok::<(), splineskin::scene::SceneError>(())
    /// ```
    pub fn refined(
        &mut self,
        poses: &[Vec<Affine>],
        options: &crate::adaptive::AdaptiveOptions,
    ) -> Result<RefinedPuppet, SceneError> {
        self.rebuild()?;
        let Cache::Posed(posed) = &self.cache else {
            unreachable!("rebuild leaves the puppet posed or errs")
        };
        let setup = posed.setup();
        let rig_error = |e: Box<dyn std::error::Error + Send + Sync>| SceneError::Rig {
            origin: self.origin.clone(),
            source: e,
        };
        let refined = crate::adaptive::refine(
            &setup.drawing,
            setup.weights.as_ref(),
            &setup.options,
            poses,
            options,
        )
        .map_err(|e| rig_error(Box::new(e)))?;
        let deformer = match self.flexible {
            Some(flexible) => Deformer::Flexible(Box::new(
                refined
                    .flexible_solver(setup.weights.as_ref(), &setup.options, flexible)
                    .map_err(|e| rig_error(Box::new(e)))?,
            )),
            None => Deformer::Fixed(refined.rig),
        };
        let setup = Setup {
            drawing: refined.drawing,
            weights: setup.weights.clone(),
            options: setup.options,
            warnings: setup.warnings.clone(),
            domain: setup.domain.clone(),
        };
        let puppet = Puppet {
            origin: self.origin.clone(),
            format: self.format,
            compat: self.compat,
            points: self.points.clone(),
            bones: self.bones.clone(),
            cage: self.cage.clone(),
            family: self.family.clone(),
            domain_options: self.domain_options.clone(),
            fit_options: self.fit_options,
            pose: self.pose.clone(),
            cache: Cache::Posed(PosedDrawing::from_parts(
                self.origin.clone(),
                setup,
                deformer,
            )),
            flexible: self.flexible,
            last: Vec::new(),
            stats: PuppetStats {
                rig_builds: 1,
                ..PuppetStats::default()
            },
        };
        Ok(RefinedPuppet {
            puppet,
            inserted: refined.inserted,
            worst: refined.worst,
            rounds: refined.rounds,
            met: refined.met,
        })
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
        let drawing = match self.take_cache() {
            Cache::Drawing(drawing) => drawing,
            Cache::Weights(setup) => setup.drawing,
            Cache::Posed(posed) => posed.into_setup().drawing,
        };
        self.cache = Cache::Drawing(drawing);
        self.last.clear();
    }

    fn invalidate_rig(&mut self) {
        self.cache = match self.take_cache() {
            Cache::Posed(posed) => Cache::Weights(posed.into_setup()),
            stale => stale,
        };
        self.last.clear();
    }

    /// The cache, leaving an empty drawing in its place (to be replaced at once).
    fn take_cache(&mut self) -> Cache {
        std::mem::replace(&mut self.cache, Cache::Drawing(Drawing::default()))
    }

    fn inputs(&self) -> WeightInputs<'_> {
        WeightInputs {
            handles: self.handles(),
            family: &self.family,
            domain: &self.domain_options,
            compat: self.compat,
            origin: &self.origin,
            format: self.format,
            stop: None,
            solved: None,
        }
    }

    fn element(&self, kind: HandleKind) -> String {
        super::handle_element(self.format, kind)
    }

    /// A copy of `items` (elements `element[..]` of the scene) with entry `i` replaced by
    /// `value`, or the error naming `element[i]` with `missing(items.len())`.
    fn replaced<T: Clone>(
        &self,
        items: &[T],
        i: usize,
        value: T,
        element: &str,
        missing: impl FnOnce(usize) -> String,
    ) -> Result<Vec<T>, SceneError> {
        if i >= items.len() {
            return Err(self.invalid(format!("{element}[{i}]"), missing(items.len())));
        }
        let mut items = items.to_vec();
        items[i] = value;
        Ok(items)
    }

    fn invalid(&self, element: String, message: String) -> SceneError {
        SceneError::invalid(&self.origin, element, message)
    }
}
