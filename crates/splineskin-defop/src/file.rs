//! The operator file: a trained [`DefOp`] with its mesh and how it was trained, in a versioned
//! binary format of our own, so that `splineskin defop eval`, `bench` and `deform` need
//! nothing else.
//!
//! ```text
//! offset  size  content
//! 0       8     magic bytes  b"SSKDEFOP"
//! 8       4     format version, u32 little-endian (OPERATOR_FORMAT_VERSION = 1)
//! 12      4     header length h in bytes, u32 little-endian
//! 16      h     header: UTF-8 JSON (sizes, handles, bases, training metadata)
//! 16 + h  …     arrays, back to back, little-endian, sizes given by the header:
//!               vertices       f64  2·n_vertices        (x0, y0, x1, y1, …)
//!               triangles      u32  3·n_triangles       (counter-clockwise corner indices)
//!               centres        f64  n_centres·2·n_handles (thin-plate centres, scaled z)
//!               coefficients   f64  2|Φ|·|Ψ|            (G, column-major; DefOp::coefficients)
//!               vertex_values  f64  n_vertices·|Φ|      (Dᵀ column-major; empty for the hats)
//! ```
//!
//! Reading checks the magic bytes, the version, the header, that the file holds exactly the
//! bytes the header announces (a truncated file or trailing bytes are refused), that every
//! value is finite and every index in range, and rebuilds the mesh ([`TriMesh::new`]) and the
//! bases; each error names the file and what was expected ([`OperatorFileError`]).
//! [`OperatorFile::save`] writes through a temporary file in the same folder and a rename,
//! so a failure never leaves a half-written operator.

use std::path::Path;

use kurbo::Point;
use serde::{Deserialize, Serialize};

use super::handle_basis::{HandleBasis, HandleBasisKind};
use super::laplacian_eigen::EigenOperator;
use super::operator::DefOp;
use super::spatial_basis::{SpatialBasis, SpatialBasisKind};
use splineskin_core::mesh::TriMesh;

/// The first eight bytes of every operator file.
pub const OPERATOR_MAGIC: [u8; 8] = *b"SSKDEFOP";

/// The format version this library writes and reads.
pub const OPERATOR_FORMAT_VERSION: u32 = 1;

/// Largest header accepted, in bytes (16 MiB: a header holds sizes, handle lists and the
/// control vertices of a reduced basis, kilobytes in practice).
const MAX_HEADER_BYTES: u32 = 1 << 24;

/// How an operator was trained: free-form metadata kept in the file for people and reports
/// (nothing in it is needed to evaluate the operator). Every field is optional.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
#[non_exhaustive]
pub struct TrainingMetadata {
    /// `"arap"` or `"symmetric-arap"`.
    pub energy: Option<String>,
    /// Training samples besides the rest configuration.
    pub n_samples: Option<usize>,
    /// The sampling region, as the CLI describes it (e.g. `"disc 0.05 of the diagonal"`).
    pub sample_region: Option<String>,
    /// The sampler's seed.
    pub seed: Option<u64>,
    /// Wall-clock seconds of the training (ground truths and fits).
    pub training_seconds: Option<f64>,
    /// The scene (or other source) the operator was trained from.
    pub source: Option<String>,
    /// The spatial basis as asked for (e.g. `"hats"`, `"eigen 100"`).
    pub spatial_basis: Option<String>,
}

/// A trained operator with the mesh it deforms and its training metadata: what an operator
/// file holds.
///
/// ```
/// use kurbo::{Point, Rect};
/// use splineskin_defop::{train, OperatorFile, SpatialBasis, TrainOptions, TrainingMetadata};
/// use splineskin_core::mesh::TriMesh;
/// let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2)?;
/// let handles = [9, 17];
/// let spatial = SpatialBasis::hats(&mesh)?;
/// let options = TrainOptions::default().with_n_samples(10);
/// let op = train(&mesh, &handles, &spatial, &options, &|_| {})?.op;
/// let file = OperatorFile::new(mesh, op, TrainingMetadata::default())?;
/// let bytes = file.to_bytes();
/// let read = OperatorFile::from_bytes(&bytes, "in memory")?;
/// let q = [Point::new(0.5, 0.6), Point::new(4.2, 0.4)];
/// assert_eq!(read.op.eval(&q)?, file.op.eval(&q)?); // bit-exact
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct OperatorFile {
    /// The mesh the operator deforms (its rest pose).
    pub mesh: TriMesh,
    /// The operator (its handles are vertices of `mesh`).
    pub op: DefOp,
    /// How it was trained.
    pub metadata: TrainingMetadata,
}

/// Why an operator file cannot be read or written. Every variant names the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OperatorFileError {
    /// The file cannot be read or written.
    #[error("{origin}: {action}: {source}")]
    Io {
        /// The file.
        origin: String,
        /// What was being done.
        action: &'static str,
        /// The system's error.
        source: std::io::Error,
    },
    /// The file does not start with [`OPERATOR_MAGIC`].
    #[error("{origin}: not a splineskin operator file (expected it to start with the bytes \"SSKDEFOP\"; write one with `splineskin defop train`)")]
    NotAnOperator {
        /// The file.
        origin: String,
    },
    /// The file's format version is not [`OPERATOR_FORMAT_VERSION`].
    #[error("{origin}: operator format version {found} (this splineskin reads version {expected}; retrain the operator)")]
    Version {
        /// The file.
        origin: String,
        /// The version found.
        found: u32,
        /// [`OPERATOR_FORMAT_VERSION`].
        expected: u32,
    },
    /// The file is shorter than its header announces.
    #[error("{origin}: truncated: {found} bytes, expected {expected} ({what})")]
    Truncated {
        /// The file.
        origin: String,
        /// Its length.
        found: usize,
        /// The length expected.
        expected: usize,
        /// What was being read.
        what: &'static str,
    },
    /// The file's content is inconsistent: bad header, a size mismatch, a non-finite value or
    /// an index out of range.
    #[error("{origin}: {detail}")]
    Invalid {
        /// The file.
        origin: String,
        /// What is wrong and what was expected.
        detail: String,
    },
}

/// The JSON header.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Header {
    n_vertices: usize,
    n_triangles: usize,
    /// Handle vertices, in configuration order.
    handles: Vec<usize>,
    spatial_basis: SpatialHeader,
    handle_basis: HandleHeader,
    /// `2|Φ|·|Ψ|`, for checking.
    n_coefficients: usize,
    training: TrainingMetadata,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SpatialHeader {
    /// `hats`, `laplacian-eigenfunctions` or `biharmonic-coordinates`.
    kind: String,
    n_functions: usize,
    /// Eigenfunctions: `cotangent` or `linearly-precise`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    operator: Option<String>,
    /// Biharmonic coordinates: the control vertices.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    control_vertices: Option<Vec<usize>>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct HandleHeader {
    /// `linear`, `quadratic`, `cubic` or `tps`.
    kind: String,
    scale: f64,
    /// Rest positions `P`, one per handle.
    rest: Vec<[f64; 2]>,
    n_centres: usize,
    n_functions: usize,
}

impl OperatorFile {
    /// Bundles an operator with its mesh. Errors (as [`OperatorFileError::Invalid`], origin
    /// `<new>`) if the operator is not one of this mesh: vertex counts differ, or a handle is
    /// not a vertex.
    pub fn new(
        mesh: TriMesh,
        op: DefOp,
        metadata: TrainingMetadata,
    ) -> Result<OperatorFile, OperatorFileError> {
        let invalid = |detail: String| OperatorFileError::Invalid {
            origin: "<new>".into(),
            detail,
        };
        if op.n_vertices() != mesh.n_vertices() {
            return Err(invalid(format!(
                "the operator deforms {} vertices, the mesh has {} (expected the operator of this mesh)",
                op.n_vertices(),
                mesh.n_vertices()
            )));
        }
        if let Some(&h) = op.handles().iter().find(|&&h| h >= mesh.n_vertices()) {
            return Err(invalid(format!(
                "handle vertex {h} is not a vertex of the {}-vertex mesh",
                mesh.n_vertices()
            )));
        }
        Ok(OperatorFile { mesh, op, metadata })
    }

    /// The rest positions of the handles (the mesh vertices at the handles).
    pub fn rest_handles(&self) -> Vec<Point> {
        self.op
            .handles()
            .iter()
            .map(|&h| self.mesh.vertices[h])
            .collect()
    }

    /// The file's bytes (layout in the module documentation).
    pub fn to_bytes(&self) -> Vec<u8> {
        let op = &self.op;
        let spatial = op.spatial_basis();
        let (kind, operator, control_vertices) = match spatial.kind() {
            SpatialBasisKind::Hats => ("hats", None, None),
            SpatialBasisKind::LaplacianEigenfunctions { operator } => (
                "laplacian-eigenfunctions",
                Some(
                    match operator {
                        EigenOperator::Cotangent => "cotangent",
                        EigenOperator::LinearlyPrecise => "linearly-precise",
                    }
                    .to_string(),
                ),
                None,
            ),
            SpatialBasisKind::BiharmonicCoordinates { control_vertices } => (
                "biharmonic-coordinates",
                None,
                Some(control_vertices.clone()),
            ),
        };
        let basis = op.handle_basis();
        let header = Header {
            n_vertices: self.mesh.n_vertices(),
            n_triangles: self.mesh.n_triangles(),
            handles: op.handles().to_vec(),
            spatial_basis: SpatialHeader {
                kind: kind.into(),
                n_functions: spatial.n_functions(),
                operator,
                control_vertices,
            },
            handle_basis: HandleHeader {
                kind: basis.kind().name().into(),
                scale: basis.scale(),
                rest: basis.rest().iter().map(|p| [p.x, p.y]).collect(),
                n_centres: basis.n_centres(),
                n_functions: basis.n_functions(),
            },
            n_coefficients: op.coefficients.len(),
            training: self.metadata.clone(),
        };
        // Serialising these plain structs cannot fail.
        let json = serde_json::to_vec(&header).unwrap_or_default();
        let mut bytes = Vec::with_capacity(
            16 + json.len()
                + 8 * (2 * self.mesh.n_vertices() + op.coefficients.len() + op.vertex_values.len())
                + 12 * self.mesh.n_triangles(),
        );
        bytes.extend_from_slice(&OPERATOR_MAGIC);
        bytes.extend_from_slice(&OPERATOR_FORMAT_VERSION.to_le_bytes());
        bytes.extend_from_slice(&(json.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&json);
        for p in &self.mesh.vertices {
            bytes.extend_from_slice(&p.x.to_le_bytes());
            bytes.extend_from_slice(&p.y.to_le_bytes());
        }
        for t in &self.mesh.triangles {
            for &v in t {
                bytes.extend_from_slice(&(v as u32).to_le_bytes());
            }
        }
        for k in 0..basis.n_centres() {
            for z in basis.centre(k) {
                bytes.extend_from_slice(&z.to_le_bytes());
            }
        }
        for value in op.coefficients.iter().chain(&op.vertex_values) {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
        bytes
    }

    /// Reads an operator from its bytes; `origin` names the file in errors.
    pub fn from_bytes(bytes: &[u8], origin: &str) -> Result<OperatorFile, OperatorFileError> {
        let file = FileBytes { bytes, origin };
        let (header, header_end) = file.header()?;
        let n = header.handles.len();
        let nv = header.n_vertices;
        let kind = file.handle_basis_kind(&header, n)?;
        let layout = file.layout(&header, header_end, kind, n)?;
        let xy = file.floats(header_end, layout.n_xy, "vertices")?;
        let tri_start = header_end + 8 * layout.n_xy;
        let centres_start = tri_start + 4 * layout.n_tri;
        let centres = file.floats(centres_start, layout.n_cen, "thin-plate centres")?;
        let coefficients_start = centres_start + 8 * layout.n_cen;
        let coefficients = file.floats(coefficients_start, layout.n_coef, "coefficients")?;
        let vertex_values = file.floats(
            coefficients_start + 8 * layout.n_coef,
            layout.n_vals,
            "spatial basis values",
        )?;
        let vertices: Vec<Point> = xy.chunks_exact(2).map(|c| Point::new(c[0], c[1])).collect();
        let triangles = file.triangles(tri_start, header.n_triangles, nv)?;
        let mesh = TriMesh::new(vertices, triangles)
            .map_err(|e| file.invalid(format!("invalid mesh: {e}")))?;
        let rest = file.rest_positions(&header, &mesh)?;
        let handle_basis = HandleBasis::from_parts(kind, rest, header.handle_basis.scale, centres)
            .map_err(|e| file.invalid(format!("handle basis: {e}")))?;
        let spatial_kind = file.spatial_basis_kind(&header)?;
        let hats = header.spatial_basis.kind == "hats";
        let nf = header.spatial_basis.n_functions;
        if hats && nf != nv {
            return Err(file.invalid(format!(
                "{nf} hat functions for {nv} vertices (expected one per vertex)"
            )));
        }
        let spatial =
            SpatialBasis::from_parts(spatial_kind, nv, nf, (!hats).then(|| vertex_values.clone()));
        let op = DefOp {
            spatial,
            handle_basis,
            handles: header.handles,
            coefficients,
            vertex_values,
        };
        Ok(OperatorFile {
            mesh,
            op,
            metadata: header.training,
        })
    }

    /// Reads the operator file at `path`.
    pub fn load(path: &Path) -> Result<OperatorFile, OperatorFileError> {
        let origin = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|source| OperatorFileError::Io {
            origin: origin.clone(),
            action: "cannot read the operator",
            source,
        })?;
        OperatorFile::from_bytes(&bytes, &origin)
    }

    /// Writes the operator to `path` atomically: a temporary file in the same folder, synced,
    /// then renamed over `path` (removed again on failure).
    pub fn save(&self, path: &Path) -> Result<(), OperatorFileError> {
        splineskin_core::atomic_write::write_atomically(path, &self.to_bytes()).map_err(|source| {
            OperatorFileError::Io {
                origin: path.display().to_string(),
                action: "cannot write the operator",
                source,
            }
        })
    }
}

/// The bytes of an operator file being read, and where they come from (for messages).
struct FileBytes<'b> {
    bytes: &'b [u8],
    origin: &'b str,
}

/// Where the arrays of an operator file lie: their lengths (in numbers) and the file's
/// length, from its header.
struct Layout {
    /// Vertex coordinates (`2 · n_vertices`).
    n_xy: usize,
    /// Triangle corners (`3 · n_triangles`).
    n_tri: usize,
    /// Thin-plate centres' coordinates.
    n_cen: usize,
    /// Coefficients (`2 · n_functions · |Ψ|`).
    n_coef: usize,
    /// The spatial basis's vertex values (none for hats).
    n_vals: usize,
}

impl FileBytes<'_> {
    fn invalid(&self, detail: String) -> OperatorFileError {
        OperatorFileError::Invalid {
            origin: self.origin.into(),
            detail,
        }
    }

    fn truncated(&self, expected: usize, what: &'static str) -> OperatorFileError {
        OperatorFileError::Truncated {
            origin: self.origin.into(),
            found: self.bytes.len(),
            expected,
            what,
        }
    }

    /// The little-endian `u32` at byte `at`.
    fn word(&self, at: usize) -> u32 {
        let b = self.bytes;
        u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
    }

    /// The header (after the magic, the version and its length) and the byte where it ends.
    fn header(&self) -> Result<(Header, usize), OperatorFileError> {
        let bytes = self.bytes;
        if bytes.len() < 8 || bytes[..8] != OPERATOR_MAGIC {
            return Err(OperatorFileError::NotAnOperator {
                origin: self.origin.into(),
            });
        }
        if bytes.len() < 16 {
            return Err(self.truncated(16, "the version and header length"));
        }
        let version = self.word(8);
        if version != OPERATOR_FORMAT_VERSION {
            return Err(OperatorFileError::Version {
                origin: self.origin.into(),
                found: version,
                expected: OPERATOR_FORMAT_VERSION,
            });
        }
        let header_len = self.word(12);
        if header_len > MAX_HEADER_BYTES {
            return Err(self.invalid(format!(
                "header of {header_len} bytes (expected at most {MAX_HEADER_BYTES})"
            )));
        }
        let header_end = 16 + header_len as usize;
        if bytes.len() < header_end {
            return Err(self.truncated(header_end, "the header"));
        }
        let header: Header = serde_json::from_slice(&bytes[16..header_end])
            .map_err(|e| self.invalid(format!("bad header JSON: {e}")))?;
        Ok((header, header_end))
    }

    /// The handle basis's kind, its centres and function count checked against it (`n`
    /// handles).
    fn handle_basis_kind(
        &self,
        header: &Header,
        n: usize,
    ) -> Result<HandleBasisKind, OperatorFileError> {
        let kind = match header.handle_basis.kind.as_str() {
            "linear" => HandleBasisKind::Linear,
            "quadratic" => HandleBasisKind::Quadratic,
            "cubic" => HandleBasisKind::Cubic,
            "tps" => HandleBasisKind::ThinPlateSpline,
            other => {
                return Err(self.invalid(format!(
                    "handle basis {other:?} (expected linear, quadratic, cubic or tps)"
                )))
            }
        };
        let n_centres = header.handle_basis.n_centres;
        if kind != HandleBasisKind::ThinPlateSpline && n_centres != 0 {
            return Err(self.invalid(format!(
                "{n_centres} thin-plate centres for a {} basis (expected none)",
                kind.name()
            )));
        }
        let n_psi = kind.n_functions(n, n_centres);
        if n_psi != header.handle_basis.n_functions {
            return Err(self.invalid(format!(
                "handle basis of {} functions (expected {n_psi} for a {} basis of {n} handles and {n_centres} centres)",
                header.handle_basis.n_functions,
                kind.name()
            )));
        }
        Ok(kind)
    }

    /// The arrays' [`Layout`], sizes computed with overflow checked (a hostile header must not
    /// make us allocate) and the file's length checked against them.
    fn layout(
        &self,
        header: &Header,
        header_end: usize,
        kind: HandleBasisKind,
        n: usize,
    ) -> Result<Layout, OperatorFileError> {
        let nv = header.n_vertices;
        let nf = header.spatial_basis.n_functions;
        let n_centres = header.handle_basis.n_centres;
        let n_psi = kind.n_functions(n, n_centres);
        let hats = header.spatial_basis.kind == "hats";
        let sizes = (|| {
            let vertices = nv.checked_mul(2)?;
            let triangles = header.n_triangles.checked_mul(3)?;
            let centres = n_centres.checked_mul(n.checked_mul(2)?)?;
            let coefficients = nf.checked_mul(2)?.checked_mul(n_psi)?;
            let vertex_values = if hats { 0 } else { nv.checked_mul(nf)? };
            let total = vertices
                .checked_add(centres)?
                .checked_add(coefficients)?
                .checked_add(vertex_values)?
                .checked_mul(8)?
                .checked_add(triangles.checked_mul(4)?)?
                .checked_add(header_end)?;
            Some((
                Layout {
                    n_xy: vertices,
                    n_tri: triangles,
                    n_cen: centres,
                    n_coef: coefficients,
                    n_vals: vertex_values,
                },
                total,
            ))
        })()
        .ok_or_else(|| self.invalid("array sizes overflow (a corrupt header)".into()))?;
        let (layout, total) = sizes;
        if header.n_coefficients != layout.n_coef {
            return Err(self.invalid(format!(
                "{} coefficients (expected 2·{nf}·{n_psi} = {})",
                header.n_coefficients, layout.n_coef
            )));
        }
        if self.bytes.len() < total {
            return Err(self.truncated(total, "the arrays the header announces"));
        }
        if self.bytes.len() > total {
            return Err(self.invalid(format!(
                "{} bytes after the arrays (expected the file to end at byte {total})",
                self.bytes.len() - total
            )));
        }
        Ok(layout)
    }

    /// `count` little-endian `f64` from byte `at`, all finite (else an error naming `what`).
    fn floats(&self, at: usize, count: usize, what: &str) -> Result<Vec<f64>, OperatorFileError> {
        let values: Vec<f64> = self.bytes[at..at + 8 * count]
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect();
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(self.invalid(format!(
                "{what}: value {k} is {} (expected finite values)",
                values[k]
            )));
        }
        Ok(values)
    }

    /// `n_triangles` triangles of `u32` corners from byte `at`, each below `nv`.
    fn triangles(
        &self,
        at: usize,
        n_triangles: usize,
        nv: usize,
    ) -> Result<Vec<[usize; 3]>, OperatorFileError> {
        let mut triangles = Vec::with_capacity(n_triangles);
        for (t, c) in self.bytes[at..at + 12 * n_triangles]
            .chunks_exact(12)
            .enumerate()
        {
            let corner = |k: usize| {
                u32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]]) as usize
            };
            let tri = [corner(0), corner(1), corner(2)];
            if let Some(&v) = tri.iter().find(|&&v| v >= nv) {
                return Err(self.invalid(format!(
                    "triangle {t}: corner {v} (expected a vertex index below {nv})"
                )));
            }
            triangles.push(tri);
        }
        Ok(triangles)
    }

    /// The handles' rest positions, one per handle, each its vertex of `mesh`.
    fn rest_positions(
        &self,
        header: &Header,
        mesh: &TriMesh,
    ) -> Result<Vec<Point>, OperatorFileError> {
        let nv = header.n_vertices;
        let n = header.handles.len();
        if let Some(&h) = header.handles.iter().find(|&&h| h >= nv) {
            return Err(self.invalid(format!(
                "handle vertex {h} (expected a vertex index below {nv})"
            )));
        }
        let rest: Vec<Point> = header
            .handle_basis
            .rest
            .iter()
            .map(|&[x, y]| Point::new(x, y))
            .collect();
        if rest.len() != n {
            return Err(self.invalid(format!(
                "{} rest positions for {n} handles (expected one per handle)",
                rest.len()
            )));
        }
        for (l, (&h, p)) in header.handles.iter().zip(&rest).enumerate() {
            if mesh.vertices[h] != *p {
                return Err(self.invalid(format!(
                    "handle {l}: rest position ({}, {}) is not its vertex {h} at ({}, {})",
                    p.x, p.y, mesh.vertices[h].x, mesh.vertices[h].y
                )));
            }
        }
        Ok(rest)
    }

    /// The spatial basis's kind, with its operator or control vertices.
    fn spatial_basis_kind(&self, header: &Header) -> Result<SpatialBasisKind, OperatorFileError> {
        Ok(match header.spatial_basis.kind.as_str() {
            "hats" => SpatialBasisKind::Hats,
            "laplacian-eigenfunctions" => SpatialBasisKind::LaplacianEigenfunctions {
                operator: match header.spatial_basis.operator.as_deref() {
                    Some("cotangent") => EigenOperator::Cotangent,
                    Some("linearly-precise") => EigenOperator::LinearlyPrecise,
                    other => {
                        return Err(self.invalid(format!(
                            "eigenfunction operator {other:?} (expected \"cotangent\" or \"linearly-precise\")"
                        )))
                    }
                },
            },
            "biharmonic-coordinates" => SpatialBasisKind::BiharmonicCoordinates {
                control_vertices: header.spatial_basis.control_vertices.clone().ok_or_else(
                    || self.invalid("biharmonic coordinates without control_vertices".into()),
                )?,
            },
            other => {
                return Err(self.invalid(format!(
                    "spatial basis {other:?} (expected hats, laplacian-eigenfunctions or biharmonic-coordinates)"
                )))
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{train, TrainOptions};
    use kurbo::Rect;

    fn trained(spatial: impl Fn(&TriMesh) -> SpatialBasis, kind: HandleBasisKind) -> OperatorFile {
        let mesh = TriMesh::grid(Rect::new(0., 0., 4., 1.), 8, 2).unwrap();
        let handles = [9, 17, 13];
        let basis = spatial(&mesh);
        let options = TrainOptions::default()
            .with_n_samples(12)
            .with_handle_basis(kind);
        let op = train(&mesh, &handles, &basis, &options, &|_| {})
            .unwrap()
            .op;
        let metadata = TrainingMetadata {
            energy: Some("symmetric-arap".into()),
            n_samples: Some(12),
            seed: Some(1),
            ..TrainingMetadata::default()
        };
        OperatorFile::new(mesh, op, metadata).unwrap()
    }

    #[test]
    fn operator_file_round_trip_is_bit_exact() {
        for file in [
            trained(
                |m| SpatialBasis::hats(m).unwrap(),
                HandleBasisKind::ThinPlateSpline,
            ),
            trained(
                |m| SpatialBasis::biharmonic_coordinates_sampled(m, &[9, 17, 13], 8).unwrap(),
                HandleBasisKind::Linear,
            ),
            trained(
                |m| {
                    SpatialBasis::laplacian_eigenfunctions(m, 10, EigenOperator::LinearlyPrecise)
                        .unwrap()
                },
                HandleBasisKind::Quadratic,
            ),
        ] {
            let read = OperatorFile::from_bytes(&file.to_bytes(), "test").unwrap();
            assert_eq!(read, file);
            let q = [
                Point::new(0.3, 0.7),
                Point::new(4.1, 0.2),
                Point::new(2.0, 0.9),
            ];
            assert_eq!(read.op.eval(&q).unwrap(), file.op.eval(&q).unwrap());
        }
    }

    #[test]
    fn operator_file_refuses_damage_naming_the_file() {
        let file = trained(|m| SpatialBasis::hats(m).unwrap(), HandleBasisKind::Linear);
        let bytes = file.to_bytes();
        let message = |b: &[u8]| {
            OperatorFile::from_bytes(b, "op.bin")
                .unwrap_err()
                .to_string()
        };
        assert!(message(b"hello world, not an operator").contains("not a splineskin operator"));
        assert!(message(&bytes[..bytes.len() - 3]).contains("truncated"));
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(message(&longer).contains("after the arrays"));
        let mut version = bytes.clone();
        version[8] = 7;
        assert!(message(&version).contains("version 7"));
        let mut nan = bytes.clone();
        let n = nan.len();
        nan[n - 8..].copy_from_slice(&f64::NAN.to_le_bytes());
        assert!(message(&nan).contains("expected finite"));
        for b in [&bytes[..3], &bytes[..20]] {
            assert!(message(b).starts_with("op.bin: "));
        }
    }

    #[test]
    fn operator_file_save_and_load() {
        let file = trained(
            |m| SpatialBasis::hats(m).unwrap(),
            HandleBasisKind::ThinPlateSpline,
        );
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("op.bin");
        file.save(&path).unwrap();
        assert_eq!(OperatorFile::load(&path).unwrap(), file);
        let missing = OperatorFile::load(&dir.path().join("missing.bin")).unwrap_err();
        assert!(missing.to_string().contains("missing.bin"));
        // Only the file itself in the folder: no temporary left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
