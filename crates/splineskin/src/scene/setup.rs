//! From a [`Scene`] to what a rig is built from: the drawing (with the scene's junction
//! kinds), the weight functions and the fit options, in our default mode or in the paper
//! authors' compatibility mode.

use std::sync::Arc;

use crate::domain::polygon::{check_cage, signed_area};
use crate::domain::{Domain, DomainError, DomainOptions, MeshWeights};
use crate::drawing::authors_svg::read_authors_drawing_named;
use crate::drawing::{read_svg_named, Drawing, ImportOptions, JointKind};
use crate::spline_fit::{FitOptions, FlexibleOptions};
use crate::stop::StopSignal;
use crate::weights::harmonic::harmonic;
use crate::weights::{
    cage_boundary_data, DirichletData, MeanValue, SegmentShepard, Shepard, ShepardOptions,
    WeightField, WeightsError,
};

use super::bbw_columns::{all_columns, SolvedColumns};
use super::{
    handle_element, HandleKind, HandleSet, MeshFamily, Scene, SceneError, SceneFormat, WeightSpec,
};

/// Squared distance under which a quadrature sample takes a handle's weight outright in the
/// authors' Shepard code: 1e-8 squared drawing units.
pub const AUTHORS_SHEPARD_SNAP: f64 = 1e-8;

/// Which discretisation to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum Compat {
    /// Ours: usvg import with exact degree elevation, Gauss quadrature consistent between both
    /// sides, strict C¹, constraints through the next distinct control point.
    #[default]
    None,
    /// The paper authors' code exactly (`--compat vectorskinning`): their SVG reading (only
    /// `<path>`, no transforms, lines as `start, start, end, end`), 100-sample midpoint
    /// integration, polyline-length weighting, their constraint rows, their Shepard snapping.
    VectorSkinning,
}

impl Compat {
    /// The flexible solve's options of this mode: ours, or the authors' rule in compatibility
    /// mode.
    pub fn flexible_options(self) -> FlexibleOptions {
        match self {
            Compat::None => FlexibleOptions::default(),
            Compat::VectorSkinning => FlexibleOptions::vectorskinning(),
        }
    }

    /// Parses the CLI's name (`vectorskinning`).
    pub fn from_name(name: &str) -> Option<Compat> {
        match name {
            "none" | "ours" => Some(Compat::None),
            "vectorskinning" => Some(Compat::VectorSkinning),
            _ => None,
        }
    }
}

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
        let mut warnings = Vec::new();
        let mut drawing = self.drawing(compat)?;
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
    /// carries it too, so export errors name it as well.
    pub fn drawing(&self, compat: Compat) -> Result<Drawing, SceneError> {
        match compat {
            Compat::None => Ok(read_svg_named(
                &self.svg_text,
                &ImportOptions::default(),
                &self.svg_origin,
            )?),
            Compat::VectorSkinning => read_authors_drawing_named(&self.svg_text, &self.svg_origin)
                .map_err(|e| SceneError::Drawing {
                    origin: self.svg_origin.clone(),
                    source: Box::new(e),
                }),
        }
    }
}

/// What a scene's weights are built from ([`handle_weights`]).
#[derive(Clone, Copy, Debug)]
pub struct WeightInputs<'a> {
    /// The rest handles (rig order: points, bones, cage vertices).
    pub handles: HandleSet<'a>,
    /// The family.
    pub family: &'a WeightSpec,
    /// Options of the triangulated domain (mesh families); the cage is taken from `handles`.
    pub domain: &'a DomainOptions,
    /// The discretisation (compatibility mode snaps Shepard weights as the authors do).
    pub compat: Compat,
    /// The scene, for messages.
    pub origin: &'a str,
    /// The scene's format, for naming handles in messages ([`Scene::element`]).
    pub format: SceneFormat,
    /// Stops the bounded biharmonic solve when raised ([`SetupControl::stop`]).
    pub stop: Option<&'a StopSignal>,
    /// Bounded biharmonic columns already solved elsewhere (another worker,
    /// [`Scene::bbw_columns`]): taken as they are instead of solved again (`bbw` only).
    pub solved: Option<&'a SolvedColumns>,
}

impl WeightInputs<'_> {
    /// The domain options with the handles' cage, if any.
    pub fn domain_options(&self) -> DomainOptions {
        match self.handles.cage {
            Some(cage) => self.domain.clone().with_cage(cage.to_vec()),
            None => self.domain.clone(),
        }
    }
}

/// The weights of `inputs.handles` on `drawing`, one column per handle in rig order, and the
/// triangulated domain they were solved on (mesh families only):
///
/// * `shepard`: [`Shepard`] for point handles alone (as before bones existed, bit for bit),
///   [`SegmentShepard`] (distance to the segment) when there are bones;
/// * `harmonic`, `biharmonic`, `bbw`: [`mesh_weights`];
/// * `mvc`: [`MeanValue`] of the cage (defined in the whole plane, inside and outside).
///
/// Errors: handle kinds the family cannot weigh ([`WeightSpec::check_handles`]), no handles, a
/// family not implemented, and those of [`mesh_weights`].
pub fn handle_weights(
    drawing: &Drawing,
    inputs: &WeightInputs<'_>,
) -> Result<(Arc<dyn WeightField>, Option<Domain>), SceneError> {
    let handles = &inputs.handles;
    inputs
        .family
        .check_handles(handles, inputs.origin, "weights")?;
    if handles.n_handles() == 0 {
        return Err(SceneError::invalid(
            inputs.origin,
            "handles",
            "no handles: place at least one (a point handle, a bone or a cage)",
        ));
    }
    if inputs.solved.is_some() {
        bbw_only(inputs.family, inputs.origin, "weights.solved")?;
    }
    match inputs.family {
        WeightSpec::Shepard { exponent } => {
            let options = shepard_options(*exponent, inputs.compat);
            let field: Arc<dyn WeightField> = if handles.bones.is_empty() {
                Arc::new(Shepard::new(handles.points, options))
            } else {
                Arc::new(SegmentShepard::new(
                    handles.points,
                    &handles.bone_segments(),
                    options,
                ))
            };
            Ok((field, None))
        }
        WeightSpec::Mesh(family) => {
            let (weights, domain) = mesh_weights(drawing, inputs, *family)?;
            Ok((Arc::new(weights), Some(domain)))
        }
        WeightSpec::MeanValue => {
            // `check_handles` made sure there is a cage and nothing else.
            let cage = handles.cage.unwrap_or(&[]);
            let weights = MeanValue::new(cage).map_err(|e| match e {
                WeightsError::Cage(e) => domain_error(e, inputs, "mvc"),
                e => SceneError::Weights {
                    origin: inputs.origin.to_string(),
                    family: "mvc",
                    source: Box::new(e),
                },
            })?;
            Ok((Arc::new(weights), None))
        }
        WeightSpec::NotImplemented(name) => Err(SceneError::NotImplemented {
            origin: inputs.origin.to_string(),
            what: format!("weight function '{name}'"),
        }),
    }
}

/// The Shepard options of a scene: its exponent, and in compatibility mode the authors' snap
/// ([`AUTHORS_SHEPARD_SNAP`]).
fn shepard_options(exponent: f64, compat: Compat) -> ShepardOptions {
    let snap = match compat {
        Compat::None => 0.0,
        Compat::VectorSkinning => AUTHORS_SHEPARD_SNAP,
    };
    ShepardOptions::default()
        .with_exponent(exponent)
        .with_snap_distance_squared(snap)
}

impl Scene {
    /// The Shepard weights [`Scene::setup`] builds for `compat`, as the concrete
    /// [`Shepard`] (whose analytic gradient the Jacobian baseline uses), when the scene's
    /// family is Shepard and its handles are points only; else `None`.
    ///
    /// ```
    /// use splineskin::scene::{Compat, Scene};
    /// let scene = Scene::from_json(r#"{"splineskin_scene": 1,
    ///     "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 L10 0'/></svg>",
    ///     "handles": [{"position": [0, 0]}, {"position": [10, 0]}]}"#, "inline", None)?;
    /// assert!(scene.point_shepard(Compat::None).is_some());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn point_shepard(&self, compat: Compat) -> Option<Shepard> {
        match self.weights {
            WeightSpec::Shepard { exponent } if self.bones.is_empty() && self.cage.is_none() => {
                Some(Shepard::new(
                    &self.handles,
                    shepard_options(exponent, compat),
                ))
            }
            _ => None,
        }
    }
}

/// Weights of a mesh `family` for the handles of `inputs`: the drawing's domain is triangulated
/// ([`Domain::build`] with the scene's domain options and cage) with the point handles, bone
/// chains and curve samples as vertices; the family is solved on that mesh with the Dirichlet
/// data of `handle_dirichlet_data`; [`MeshWeights`] interpolates the vertex weights (exact
/// piecewise-linear, with the mesh edges as quadrature kinks; outside the mesh a point takes
/// the weights of the nearest boundary point). Returns the weights and the domain.
///
/// * `harmonic`: `Δw = 0` (`k = 1`); on a cage alone these are harmonic coordinates;
/// * `biharmonic`: `Δ²w = 0` (`k = 2`), natural boundary conditions;
/// * `bbw`: bounded biharmonic weights, rows normalised to sum to 1.
///
/// The Dirichlet rows sum to 1, so the harmonic and biharmonic weights sum to 1 everywhere
/// (constants solve both equations); the solve meets that only to its rounding (about 200 ulps
/// on a 20 000-vertex domain), so their rows are divided by their sums too. A partition of unity
/// to the last few bits is what makes the identity and a common affine map on every handle
/// come back exactly, however far the drawing is from the origin.
///
/// Errors name the element concerned ([`SceneError::Invalid`], e.g. `handles[2]`, `bones[0]`,
/// `cage[3]`, `domain.min_angle`) when the domain refuses the handles or options, else
/// [`SceneError::Weights`].
pub fn mesh_weights(
    drawing: &Drawing,
    inputs: &WeightInputs<'_>,
    family: MeshFamily,
) -> Result<(MeshWeights, Domain), SceneError> {
    let wrap = |source: Box<dyn std::error::Error + Send + Sync>| SceneError::Weights {
        origin: inputs.origin.to_string(),
        family: family.name(),
        source,
    };
    let (options, domain, data) = mesh_domain(drawing, inputs, family.name())?;
    let mesh = &domain.mesh;
    let weights = match family {
        MeshFamily::Harmonic | MeshFamily::Biharmonic => {
            let k = if family == MeshFamily::Harmonic { 1 } else { 2 };
            harmonic(mesh, &data, k).and_then(|mut w| w.normalize_rows().map(|()| w))
        }
        MeshFamily::Bbw => {
            // Solved coarse to fine, handles in parallel (those not given), then normalised
            // like libigl's users do.
            let mut raw = all_columns(drawing, inputs, &options, &domain, &data)?;
            raw.normalize_rows().map(|()| raw)
        }
    }
    .map_err(|e| wrap(Box::new(e)))?;
    let weights = MeshWeights::new(mesh, weights.into_values(), inputs.handles.n_handles())
        .map_err(|e| wrap(Box::new(e)))?
        .with_attachments(&domain.attachments);
    Ok((weights, domain))
}

/// Refuses `family` unless it is `bbw`, naming `element` of `origin`: columns are solved apart
/// and given ([`Scene::bbw_columns`], [`WeightInputs::solved`]) for bounded biharmonic weights
/// only.
pub(super) fn bbw_only(family: &WeightSpec, origin: &str, element: &str) -> Result<(), SceneError> {
    if *family == WeightSpec::Mesh(MeshFamily::Bbw) {
        return Ok(());
    }
    Err(SceneError::invalid(
        origin,
        element,
        format!(
            "columns are solved apart for 'bbw' weights only; these are '{}'",
            family.name()
        ),
    ))
}

/// What a mesh family of `inputs`' handles is solved on: the domain options (with the cage),
/// the triangulated domain of `drawing` and the handles' Dirichlet data on it
/// ([`handle_dirichlet_data`]). Errors as [`mesh_weights`]'s, for `family`.
pub(super) fn mesh_domain(
    drawing: &Drawing,
    inputs: &WeightInputs<'_>,
    family: &'static str,
) -> Result<(DomainOptions, Domain, DirichletData), SceneError> {
    let handles = &inputs.handles;
    let options = inputs.domain_options();
    let domain = Domain::build(drawing, handles.points, &handles.bone_segments(), &options)
        .map_err(|e| domain_error(e, inputs, family))?;
    let data = handle_dirichlet_data(&domain, inputs, family)?;
    Ok((options, domain, data))
}

/// The Dirichlet data of the handles of `inputs` on `domain`, one column per handle in rig
/// order:
///
/// * point handle `i`: 1 at its vertex (`domain.handle_vertices[i]`), 0 at every other fixed
///   vertex;
/// * bone `b`: 1 at every vertex along it (`domain.bone_vertices[b]`), 0 elsewhere; at an end
///   shared by `m` bones each of them gets `1/m` (the data of every vertex sum to 1);
/// * cage vertex `k`: along the outer boundary, piecewise linear between the cage's corners
///   ([`cage_boundary_data`]: `1 − s` on the edge from corner `k` to corner `k + 1` and `s` on
///   the edge before it, `s ∈ [0, 1]` the position along the edge; Joshi et al. 2007, harmonic
///   coordinates). Point handles and bones have weight 0 on the cage; holes' boundaries are
///   free. On a cage alone the `harmonic` family is thus exactly
///   [`crate::weights::harmonic_coordinates`].
///
/// Errors: a point handle or bone end on the cage (its vertex would carry two kinds of data).
/// `family` names the weights in messages.
pub fn handle_dirichlet_data(
    domain: &Domain,
    inputs: &WeightInputs<'_>,
    family: &'static str,
) -> Result<DirichletData, SceneError> {
    let handles = &inputs.handles;
    let (n_p, n_b) = (handles.points.len(), handles.bones.len());
    let h = handles.n_handles();
    let n_vertices = domain.mesh.n_vertices();
    let invalid = |kind: HandleKind, message: String| {
        SceneError::invalid(inputs.origin, handle_element(inputs.format, kind), message)
    };
    let bug = |what: &'static str| SceneError::Weights {
        origin: inputs.origin.to_string(),
        family,
        source: Box::new(crate::domain::DomainError::Bug(what)),
    };
    let mut rows = DirichletRows {
        owner: vec![None; n_vertices],
        vertices: Vec::new(),
        values: Vec::new(),
        n_columns: h,
    };
    if domain.handle_vertices.len() != n_p || domain.bone_vertices.len() != n_b {
        return Err(bug("the domain does not have one vertex per handle"));
    }
    for (i, &v) in domain.handle_vertices.iter().enumerate() {
        if rows.owner[v].is_some() {
            return Err(bug("two point handles share a vertex"));
        }
        let row = rows.add(v, HandleKind::Point(i));
        rows.values[row * h + i] = 1.0;
    }
    // Bone rows: count how many bones meet at each vertex, then write 1/m.
    let mut bone_rows: Vec<usize> = Vec::new();
    for (b, chain) in domain.bone_vertices.iter().enumerate() {
        for &v in chain {
            let row = match rows.owner[v] {
                None => {
                    let row = rows.add(v, HandleKind::Bone(b));
                    bone_rows.push(row);
                    row
                }
                Some((HandleKind::Bone(_), row)) => row,
                Some(_) => return Err(bug("a bone passes through a point handle")),
            };
            rows.values[row * h + n_p + b] = 1.0;
        }
    }
    for row in bone_rows {
        let r = &mut rows.values[row * h..(row + 1) * h];
        let m: f64 = r.iter().sum();
        r.iter_mut().for_each(|w| *w /= m);
    }
    if handles.cage.is_some() {
        let cage = cage_boundary_data(domain).map_err(|e| SceneError::Weights {
            origin: inputs.origin.to_string(),
            family,
            source: Box::new(e),
        })?;
        let (first_column, n_c) = (n_p + n_b, cage.n_columns());
        for (r, &v) in cage.vertices().iter().enumerate() {
            let values = cage.values_at(r);
            // The corner with the largest weight here, and the edge the vertex lies on.
            let nonzero: Vec<usize> = (0..n_c).filter(|&k| values[k] != 0.0).collect();
            let corner = (0..n_c)
                .max_by(|&a, &b| values[a].total_cmp(&values[b]))
                .unwrap_or(0);
            if let Some((kind, _)) = rows.owner[v] {
                let place = match nonzero[..] {
                    [a, b] => {
                        let edge = if (a + 1) % n_c == b { a } else { b };
                        format!(
                            "on the cage's edge {edge} (from cage[{edge}] to cage[{}])",
                            (edge + 1) % n_c
                        )
                    }
                    _ => format!("at cage[{corner}]"),
                };
                return Err(invalid(
                    kind,
                    format!(
                        "lies {place}, where the cage's weights are prescribed: move it inside \
                         the cage"
                    ),
                ));
            }
            let row = rows.add(v, HandleKind::CageVertex(corner));
            rows.values[row * h + first_column..][..n_c].copy_from_slice(values);
        }
    }
    DirichletData::new(rows.vertices, rows.values, h).map_err(|e| SceneError::Weights {
        origin: inputs.origin.to_string(),
        family,
        source: Box::new(e),
    })
}

/// Dirichlet rows being gathered: which handle first fixed each vertex (and its row), the
/// fixed vertices and their values (`n_columns` per row).
struct DirichletRows {
    owner: Vec<Option<(HandleKind, usize)>>,
    vertices: Vec<usize>,
    values: Vec<f64>,
    n_columns: usize,
}

impl DirichletRows {
    /// A new row of zeros for vertex `v`, fixed by `kind`; returns its index.
    fn add(&mut self, v: usize, kind: HandleKind) -> usize {
        let row = self.vertices.len();
        self.owner[v] = Some((kind, row));
        self.vertices.push(v);
        self.values.extend(std::iter::repeat_n(0.0, self.n_columns));
        row
    }
}

/// A domain error as a scene error naming the element concerned, where there is one.
fn domain_error(e: DomainError, inputs: &WeightInputs<'_>, family: &'static str) -> SceneError {
    match domain_element(&e, inputs.format) {
        Some(element) => {
            SceneError::invalid(inputs.origin, element, format!("{family} weights: {e}"))
        }
        None => SceneError::Weights {
            origin: inputs.origin.to_string(),
            family,
            source: Box::new(e),
        },
    }
}

/// The scene element a domain error is about (`handles[2]`, `bones[0] and bones[1]`,
/// `cage[3]`, `domain.min_angle`, …), if any.
fn domain_element(e: &DomainError, format: SceneFormat) -> Option<String> {
    let name = |kind: HandleKind| handle_element(format, kind);
    let both = |a: HandleKind, b: HandleKind| format!("{} and {}", name(a), name(b));
    Some(match e {
        DomainError::NonFiniteHandle { handle }
        | DomainError::HandleOutsideDomain { handle, .. } => name(HandleKind::Point(*handle)),
        DomainError::CoincidentHandles { first, second, .. } => {
            both(HandleKind::Point(*first), HandleKind::Point(*second))
        }
        DomainError::NonFiniteBone { bone }
        | DomainError::DegenerateBone { bone }
        | DomainError::BoneOutsideDomain { bone } => name(HandleKind::Bone(*bone)),
        DomainError::BonesCross { first, second } => {
            both(HandleKind::Bone(*first), HandleKind::Bone(*second))
        }
        DomainError::HandleOnBone { handle, bone } => {
            both(HandleKind::Point(*handle), HandleKind::Bone(*bone))
        }
        DomainError::CageNonFinite { vertex } => format!("cage[{vertex}]"),
        DomainError::CageDegenerateEdge { edge } => format!("cage[{edge}]"),
        DomainError::CageSelfIntersecting { first, .. } => format!("cage[{first}]"),
        DomainError::CageTooFewVertices { .. } | DomainError::CageClockwise { .. } => {
            "cage".to_string()
        }
        DomainError::EmptyDomain { .. } => "domain".to_string(),
        DomainError::InvalidOption { name, .. } => format!("domain.{name}"),
        _ => return None,
    })
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
