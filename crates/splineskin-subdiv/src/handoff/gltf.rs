//! The limit surface's frames as binary glTF 2.0 (`.glb`): one triangle mesh whose base is
//! frame 0, one morph target per later frame (position and normal differences from frame 0),
//! and one animation whose `weights` channel runs through them.
//!
//! ```text
//! weights(t_0) = 0,   weights(t_k) = e_k (target k alone at 1),   LINEAR in between
//! position(t)  = base + Σ_k w_k(t) · (frame_k − base)
//! ```
//!
//! so at every frame time a player shows that frame's surface, and between frames the linear
//! blend of the two around it. Normals are each frame's area-weighted vertex normals of the
//! triangles. Layout: one buffer (the GLB's binary chunk); indices, positions, normals, the
//! animation's times and weights each in their own view, 4-byte aligned. The model sits on
//! one node; for a Z-up model that node turns it a quarter turn about X (glTF is Y-up).

use std::collections::BTreeMap;

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};

use super::super::cage::Point3;
use super::{check_frames, extent_f32, HandoffError, UpAxis};

/// Most frames a glTF morph animation is written with: 1 000 (each frame is a morph target of
/// every vertex, and the weights channel holds frames² numbers).
pub const MAX_GLTF_FRAMES: usize = 1000;

/// The frames of an animated triangle mesh.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceFrames<'a> {
    /// Triangles (counter-clockwise seen from outside), indices into every frame's points.
    pub triangles: &'a [[u32; 3]],
    /// Every frame's time, seconds, increasing.
    pub times: &'a [f64],
    /// Every frame's vertex positions (the same count each).
    pub positions: &'a [Vec<Point3>],
    /// The mesh's and node's name.
    pub name: &'a str,
    /// Which axis of the model is up.
    pub up: UpAxis,
}

/// The binary glTF of `frames` (module documentation).
///
/// ```
/// use splineskin_subdiv::handoff::{write_glb, SurfaceFrames, UpAxis};
///
/// let rest = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let lifted: Vec<[f64; 3]> = rest.iter().map(|p| [p[0], p[1], p[2] + 1.0]).collect();
/// let glb = write_glb(&SurfaceFrames {
///     triangles: &[[0, 1, 2]], times: &[0.0, 1.0], positions: &[rest, lifted],
///     name: "tri", up: UpAxis::Y,
/// })?;
/// assert_eq!(&glb[..4], b"glTF");
/// assert_eq!(u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize, glb.len());
/// # Ok::<(), splineskin_subdiv::handoff::HandoffError>(())
/// ```
pub fn write_glb(frames: &SurfaceFrames) -> Result<Vec<u8>, HandoffError> {
    let n_vertices = frames.positions.first().map_or(0, |f| f.len());
    check_frames(frames.times, frames.positions, n_vertices)?;
    if frames.positions.len() > MAX_GLTF_FRAMES {
        return Err(HandoffError::TooManyFrames {
            n_frames: frames.positions.len(),
            max: MAX_GLTF_FRAMES,
        });
    }
    if let Some(t) = frames
        .triangles
        .iter()
        .find(|t| t.iter().any(|&v| v as usize >= n_vertices))
    {
        return Err(HandoffError::Frames {
            what: format!("triangle {t:?} refers past the {n_vertices} vertices"),
        });
    }
    let mut doc = Document::default();
    let mesh = doc.mesh(frames);
    let node = doc.root.push(json::Node {
        mesh: Some(mesh),
        name: Some(frames.name.to_owned()),
        rotation: match frames.up {
            UpAxis::Y => None,
            // −90° about X: (x, y, z) ↦ (x, z, −y), Z-up to Y-up.
            UpAxis::Z => Some(json::scene::UnitQuaternion([
                -std::f32::consts::FRAC_1_SQRT_2,
                0.0,
                0.0,
                std::f32::consts::FRAC_1_SQRT_2,
            ])),
        },
        ..Default::default()
    });
    if frames.positions.len() > 1 {
        doc.animation(frames.times, node);
    }
    let scene = doc.root.push(json::Scene {
        extensions: Default::default(),
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    doc.root.scene = Some(scene);
    Ok(doc.into_glb())
}

/// The glTF document being built and its binary chunk.
#[derive(Default)]
struct Document {
    root: json::Root,
    bin: Vec<u8>,
}

impl Document {
    /// Appends `bytes` as a buffer view (4-byte aligned) with `target`.
    fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: Default::default(),
            extras: Default::default(),
        })
    }

    /// An accessor of `count` elements of `type_` over a new view of `bytes`.
    fn accessor(
        &mut self,
        bytes: &[u8],
        (component, type_, count): (json::accessor::ComponentType, json::accessor::Type, usize),
        target: Option<json::buffer::Target>,
        bounds: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(bytes, target);
        let (min, max) = match bounds {
            Some((lo, hi)) => (Some(lo.into()), Some(hi.into())),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: Default::default(),
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// A VEC3 float accessor of `values` (with min and max, as positions need).
    fn vec3(&mut self, values: &[[f32; 3]]) -> json::Index<json::Accessor> {
        let (lo, hi) = extent_f32(values.iter().copied());
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        self.accessor(
            &bytes,
            (
                json::accessor::ComponentType::F32,
                json::accessor::Type::Vec3,
                values.len(),
            ),
            Some(json::buffer::Target::ArrayBuffer),
            Some((lo.to_vec(), hi.to_vec())),
        )
    }

    /// The mesh: base frame 0, a morph target per later frame.
    fn mesh(&mut self, frames: &SurfaceFrames) -> json::Index<json::Mesh> {
        let indices: Vec<u8> = frames
            .triangles
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let indices = self.accessor(
            &indices,
            (
                json::accessor::ComponentType::U32,
                json::accessor::Type::Scalar,
                3 * frames.triangles.len(),
            ),
            Some(json::buffer::Target::ElementArrayBuffer),
            None,
        );
        let positions: Vec<Vec<[f32; 3]>> = frames
            .positions
            .iter()
            .map(|f| f.iter().map(|p| p.map(|c| c as f32)).collect())
            .collect();
        let normals: Vec<Vec<[f32; 3]>> = frames
            .positions
            .iter()
            .map(|f| vertex_normals(f, frames.triangles))
            .collect();
        let base_positions = self.vec3(&positions[0]);
        let base_normals = self.vec3(&normals[0]);
        let targets: Vec<json::mesh::MorphTarget> = (1..positions.len())
            .map(|k| json::mesh::MorphTarget {
                positions: Some(self.vec3(&difference(&positions[k], &positions[0]))),
                normals: Some(self.vec3(&difference(&normals[k], &normals[0]))),
                tangents: None,
            })
            .collect();
        let n_targets = targets.len();
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), base_positions);
        attributes.insert(Valid(json::mesh::Semantic::Normals), base_normals);
        self.root.push(json::Mesh {
            extensions: Default::default(),
            extras: Default::default(),
            name: Some(frames.name.to_owned()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: Default::default(),
                extras: Default::default(),
                indices: Some(indices),
                material: None,
                mode: Valid(json::mesh::Mode::Triangles),
                targets: (n_targets > 0).then_some(targets),
            }],
            weights: (n_targets > 0).then(|| vec![0.0; n_targets]),
        })
    }

    /// The animation: at frame `k`'s time, target `k` (frame `k`'s difference) at weight 1
    /// and every other at 0; frame 0 all 0.
    fn animation(&mut self, times: &[f64], node: json::Index<json::Node>) {
        let n_targets = times.len() - 1;
        let input: Vec<f32> = times.iter().map(|&t| t as f32).collect();
        let input_bytes: Vec<u8> = input.iter().flat_map(|v| v.to_le_bytes()).collect();
        let input = self.accessor(
            &input_bytes,
            (
                json::accessor::ComponentType::F32,
                json::accessor::Type::Scalar,
                input.len(),
            ),
            None,
            Some((vec![input[0]], vec![input[input.len() - 1]])),
        );
        let mut weights = vec![0f32; times.len() * n_targets];
        for k in 1..times.len() {
            weights[k * n_targets + (k - 1)] = 1.0;
        }
        let weight_bytes: Vec<u8> = weights.iter().flat_map(|v| v.to_le_bytes()).collect();
        let output = self.accessor(
            &weight_bytes,
            (
                json::accessor::ComponentType::F32,
                json::accessor::Type::Scalar,
                weights.len(),
            ),
            None,
            None,
        );
        self.root.push(json::Animation {
            extensions: Default::default(),
            extras: Default::default(),
            channels: vec![json::animation::Channel {
                sampler: json::Index::new(0),
                target: json::animation::Target {
                    extensions: Default::default(),
                    extras: Default::default(),
                    node,
                    path: Valid(json::animation::Property::MorphTargetWeights),
                },
                extensions: Default::default(),
                extras: Default::default(),
            }],
            name: Some("frames".into()),
            samplers: vec![json::animation::Sampler {
                extensions: Default::default(),
                extras: Default::default(),
                input,
                interpolation: Valid(json::animation::Interpolation::Linear),
                output,
            }],
        });
    }

    /// The GLB container: header, JSON chunk (padded with spaces), binary chunk (padded with
    /// zeros), each chunk 4-byte aligned (glTF 2.0 §4.4).
    fn into_glb(mut self) -> Vec<u8> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.root.buffers = vec![json::Buffer {
            byte_length: USize64::from(self.bin.len()),
            name: None,
            uri: None,
            extensions: Default::default(),
            extras: Default::default(),
        }];
        self.root.asset = json::Asset {
            generator: Some(format!("splineskin {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        };
        let mut text = self
            .root
            .to_vec()
            .expect("a glTF document of plain numbers and strings serialises");
        while text.len() % 4 != 0 {
            text.push(b' ');
        }
        let total = 12 + 8 + text.len() + 8 + self.bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&self.bin);
        out
    }
}

fn difference(a: &[[f32; 3]], b: &[[f32; 3]]) -> Vec<[f32; 3]> {
    a.iter()
        .zip(b)
        .map(|(p, q)| std::array::from_fn(|k| p[k] - q[k]))
        .collect()
}

/// Area-weighted vertex normals of `triangles` at `points`, unit length (`[0, 0, 1]` where
/// the triangles around a vertex have no area).
fn vertex_normals(points: &[Point3], triangles: &[[u32; 3]]) -> Vec<[f32; 3]> {
    use splineskin_core::mesh::vec3::{cross, norm, sub};
    let mut sum = vec![[0.0f64; 3]; points.len()];
    for t in triangles {
        let [a, b, c] = t.map(|v| points[v as usize]);
        // Twice the area times the unit normal.
        let n = cross(sub(b, a), sub(c, a));
        for &v in t {
            for k in 0..3 {
                sum[v as usize][k] += n[k];
            }
        }
    }
    sum.iter()
        .map(|n| {
            let length = norm(*n);
            if length > 0.0 && length.is_finite() {
                n.map(|c| (c / length) as f32)
            } else {
                [0.0, 0.0, 1.0]
            }
        })
        .collect()
}
