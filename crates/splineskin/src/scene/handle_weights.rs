//! A scene's weight functions from its handles ([`WeightInputs`] → [`handle_weights`]): the
//! closed-form families directly; the mesh families ([`mesh_weights`]) on the drawing's
//! triangulated domain with the handles' Dirichlet data, bounded biharmonic columns solved here
//! or given ([`SolvedColumns`], solved apart by [`super::bbw_columns`]).

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::domain::{Domain, DomainError, DomainOptions, MeshWeights};
use crate::drawing::Drawing;
use crate::stop::StopSignal;
use crate::weights::bbw::BbwOptions;
use crate::weights::coarse_to_fine::bbw_coarse_to_fine;
use crate::weights::harmonic::harmonic;
use crate::weights::{
    cage_boundary_data, DirichletData, MeanValue, SegmentShepard, Shepard, ShepardOptions,
    VertexWeights, WeightField, WeightsError,
};

use super::compat::AUTHORS_SHEPARD_SNAP;
use super::{
    handle_element, Compat, HandleKind, HandleSet, MeshFamily, Scene, SceneError, SceneFormat,
    WeightSpec,
};

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
    /// Stops the bounded biharmonic solve when raised ([`super::SetupControl::stop`]).
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
pub(super) fn domain_element(e: &DomainError, format: SceneFormat) -> Option<String> {
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

/// Raw (not normalised) bounded biharmonic columns of a rig, solved on the domain its scene
/// builds: `values[k * n_vertices + v]` is column `columns[k]` (a handle in rig order) at
/// domain vertex `v`.
///
/// ```
/// use splineskin::scene::{Compat, Scene};
/// let json = r#"{"splineskin_scene": 1,
///   "svg_text": "<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 C1 1 2 1 3 0' stroke='black'/></svg>",
///   "handles": [{"position": [0, 0]}, {"position": [1.5, 0.7]}, {"position": [3, 0]}],
///   "weights": {"family": "bbw"}}"#;
/// let scene = Scene::from_json(json, "example", None)?;
/// let first = scene.bbw_columns(Compat::None, &[0, 2], None)?;
/// let second = scene.bbw_columns(Compat::None, &[1], None)?;
/// assert_eq!(first.columns, [0, 2]);
/// assert_eq!(first.values.len(), 2 * first.n_vertices);
/// // Handle 0's column is 1 at its own vertex and 0 at the others'.
/// assert!(first.values[..first.n_vertices].iter().all(|w| (0.0..=1.0).contains(w)));
/// # let _ = second;
/// # Ok::<(), splineskin::scene::SceneError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolvedColumns {
    /// Vertices of the domain they were solved on.
    pub n_vertices: usize,
    /// The handles (rig order) of the columns, in the order of `values`.
    pub columns: Vec<usize>,
    /// The columns, one after the other, `n_vertices` each.
    pub values: Vec<f64>,
}

impl SolvedColumns {
    /// Checks them against a domain of `n_vertices` vertices and a rig of `n_handles` handles:
    /// the shape, columns that exist and do not repeat, values in `[0, 1]`. Errors name
    /// `weights.solved` of `origin`.
    fn check(&self, n_vertices: usize, n_handles: usize, origin: &str) -> Result<(), SceneError> {
        let invalid = |message: String| SceneError::invalid(origin, "weights.solved", message);
        if self.n_vertices != n_vertices {
            return Err(invalid(format!(
                "solved on a domain of {} vertices; this scene's has {n_vertices} (expected the \
                 same scene and domain options)",
                self.n_vertices
            )));
        }
        if self.values.len() != self.columns.len() * n_vertices {
            return Err(invalid(format!(
                "{} values for {} columns of {n_vertices} vertices",
                self.values.len(),
                self.columns.len()
            )));
        }
        let mut seen = vec![false; n_handles];
        for &c in &self.columns {
            match seen.get_mut(c) {
                None => {
                    return Err(invalid(format!(
                        "column {c} does not exist (the rig has {n_handles} handles)"
                    )))
                }
                Some(true) => return Err(invalid(format!("column {c} is given twice"))),
                Some(s) => *s = true,
            }
        }
        if let Some(k) = self.values.iter().position(|w| !(0.0..=1.0).contains(w)) {
            return Err(invalid(format!(
                "column {} at vertex {}: {} is not a bounded weight (expected 0 to 1)",
                self.columns[k / n_vertices],
                k % n_vertices,
                self.values[k]
            )));
        }
        Ok(())
    }
}

/// Every raw bounded biharmonic column of `inputs`' handles on `domain`: those given in
/// `inputs.solved` (checked against the domain), the others solved here. `n_vertices × h`.
pub(super) fn all_columns(
    drawing: &Drawing,
    inputs: &WeightInputs<'_>,
    options: &DomainOptions,
    domain: &Domain,
    data: &DirichletData,
) -> Result<VertexWeights, SceneError> {
    let h = data.n_columns();
    let Some(solved) = inputs.solved else {
        let all: Vec<usize> = (0..h).collect();
        return solve_columns(drawing, inputs, options, domain, data, &all);
    };
    let n = domain.mesh.n_vertices();
    solved.check(n, h, inputs.origin)?;
    // Row-major, as VertexWeights holds them: vertex v's weights at v * h ..
    let mut values = vec![0.0; n * h];
    let mut given = vec![false; h];
    for (k, &c) in solved.columns.iter().enumerate() {
        for (v, &w) in solved.values[k * n..(k + 1) * n].iter().enumerate() {
            values[v * h + c] = w;
        }
        given[c] = true;
    }
    let missing: Vec<usize> = (0..h).filter(|&c| !given[c]).collect();
    if !missing.is_empty() {
        let raw = solve_columns(drawing, inputs, options, domain, data, &missing)?;
        for (v, row) in values.chunks_mut(h).enumerate() {
            for (&c, &w) in missing.iter().zip(raw.row(v)) {
                row[c] = w;
            }
        }
    }
    VertexWeights::from_row_major(n, h, values).map_err(|e| weights_error(inputs, e))
}

/// The raw columns `columns` of `data` on `domain` (`n_vertices × columns.len()`), solved
/// coarse to fine (same minimiser, a fraction of the active-set re-solves), columns in
/// parallel. Errors name a column that does not exist.
pub(super) fn solve_columns(
    drawing: &Drawing,
    inputs: &WeightInputs<'_>,
    options: &DomainOptions,
    domain: &Domain,
    data: &DirichletData,
    columns: &[usize],
) -> Result<VertexWeights, SceneError> {
    let name = MeshFamily::Bbw.name();
    let selected = data
        .select_columns(columns)
        .map_err(|e| weights_error(inputs, e))?;
    let coarse_data = |d: &Domain| {
        handle_dirichlet_data(d, inputs, name)
            .ok()?
            .select_columns(columns)
            .ok()
    };
    let handles = &inputs.handles;
    bbw_coarse_to_fine(
        drawing,
        handles.points,
        &handles.bone_segments(),
        options,
        domain,
        &selected,
        coarse_data,
        &BbwOptions::default()
            .with_parallel(true)
            .with_stop(inputs.stop.cloned()),
    )
    .map_err(|e| weights_error(inputs, e))
}

/// A weights error of the `bbw` family of `inputs`' scene.
fn weights_error(inputs: &WeightInputs<'_>, e: WeightsError) -> SceneError {
    SceneError::Weights {
        origin: inputs.origin.to_string(),
        family: MeshFamily::Bbw.name(),
        source: Box::new(e),
    }
}
