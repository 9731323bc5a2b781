//! Animation hand-off: a scene's frames written where 3D tools read them.
//!
//! | format | what it holds | written by |
//! |---|---|---|
//! | USD (`.usda`, text) | the fitted cage as a Catmull–Clark `Mesh` (faces, creases, corners, holes) with time-sampled `points`: tools that subdivide (Blender, Houdini, Maya, usdview) rebuild our limit surface | [`write_usda`] |
//! | glTF 2.0 (`.glb`) | the tessellated limit surface ([`LimitMesh`], triangles), one morph target per frame and an animation that steps through them: glTF has no subdivision, so the surface itself travels | [`write_glb`] |
//! | OBJ per frame | the fitted cage ([`to_obj_string`](super::to_obj_string)) | the CLI (`subdiv animate -o DIR`) |
//!
//! The fitted cage is not linear blend skinning of the rest cage (every vertex depends on
//! every handle's map through the fit), so no skeleton schema carries it: the frames are
//! baked. Both formats store coordinates as 32-bit floats (USD's `point3f`, glTF's `FLOAT`
//! accessors), so a written point is the `f64` one rounded to `f32`: within `2⁻²⁴` of its
//! largest coordinate.

use super::affine3::Affine3;
use super::cage::Point3;
use super::error::SubdivError;
use super::limit_mesh::LimitMesh;
use super::scene::{SubdivScene, SubdivSceneError, SubdivSetup};

mod gltf;
mod usd;

pub use gltf::{write_glb, SurfaceFrames, MAX_GLTF_FRAMES};
pub use usd::{write_usda, CageFrames};

/// Which axis of the model points up. USD's `upAxis` is Y or Z; glTF is always Y-up, so a
/// Z-up model is turned by a quarter turn about X on its node.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UpAxis {
    /// +Y up (OBJ's and glTF's habit).
    #[default]
    Y,
    /// +Z up (CAD's and Blender's world).
    Z,
}

/// Why frames could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum HandoffError {
    /// No frames, or times and frames of different lengths, or times not increasing.
    #[error("{what}")]
    Frames {
        /// What is wrong.
        what: String,
    },
    /// A frame holds a number of points other than the mesh's vertex count.
    #[error("frame {frame}: {got} points for a mesh of {expected} vertices")]
    PointCount {
        /// The frame.
        frame: usize,
        /// Points it has.
        got: usize,
        /// Vertices of the mesh.
        expected: usize,
    },
    /// A coordinate that is NaN or infinite, or beyond what a 32-bit float holds.
    #[error("frame {frame}: vertex {vertex}: coordinate {value} is not a finite 32-bit number")]
    NonFinite {
        /// The frame.
        frame: usize,
        /// The vertex.
        vertex: usize,
        /// The coordinate.
        value: f64,
    },
    /// Sampling the limit surface failed.
    #[error(transparent)]
    Subdiv(#[from] SubdivError),
    /// More frames than the format's writer takes.
    #[error("{n_frames} frames is more than the {max} a glTF morph animation holds here; lower the frame rate or write USD or OBJ frames")]
    TooManyFrames {
        /// Frames given.
        n_frames: usize,
        /// The limit.
        max: usize,
    },
}

/// A scene's animation fitted frame by frame: what the writers take.
#[derive(Clone, Debug)]
pub struct FittedAnimation {
    /// Frames per second.
    pub fps: f64,
    /// Every frame's time, seconds ([`SubdivScene::animation_frames`]).
    pub times: Vec<f64>,
    /// Every frame's fitted cage (the rig's update of that frame's pose).
    pub cages: Vec<Vec<Point3>>,
}

impl FittedAnimation {
    /// Samples `scene`'s animation and fits every frame with `setup`'s rig.
    ///
    /// ```no_run
    /// use splineskin_subdiv::handoff::{FittedAnimation, UpAxis};
    /// use splineskin_subdiv::SubdivScene;
    ///
    /// let scene = SubdivScene::load("tube-scene.json".as_ref())?;
    /// let setup = scene.setup()?;
    /// let frames = FittedAnimation::new(&scene, &setup)?;
    /// std::fs::write("tube.usda", frames.usda(&setup, "tube", UpAxis::Y)?)?;
    /// std::fs::write("tube.glb", frames.glb(&setup, 3, "tube", UpAxis::Y)?)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(scene: &SubdivScene, setup: &SubdivSetup) -> Result<Self, SubdivSceneError> {
        Self::of_frames(scene, scene.animation_frames()?, setup)
    }

    /// [`FittedAnimation::new`] of the frames `scene.animation_frames()` gave (for a caller that
    /// sampled them before the precompute, to fail early).
    pub fn of_frames(
        scene: &SubdivScene,
        frames: Vec<(f64, Vec<Affine3>)>,
        setup: &SubdivSetup,
    ) -> Result<Self, SubdivSceneError> {
        let mut cages = Vec::with_capacity(frames.len());
        for (f, (t, pose)) in frames.iter().enumerate() {
            let mut out = vec![[0.0; 3]; setup.cage.n_vertices()];
            setup
                .rig
                .update(pose, &mut out)
                .map_err(|source| SubdivSceneError::Invalid {
                    file: scene.file.clone(),
                    element: "animation".into(),
                    message: format!("frame {f} (t = {t} s): {source}"),
                })?;
            cages.push(out);
        }
        Ok(FittedAnimation {
            fps: scene.animation.as_ref().map_or(0.0, |a| a.fps()),
            times: frames.into_iter().map(|f| f.0).collect(),
            cages,
        })
    }

    /// The frames as USD text ([`write_usda`]): the cage of `setup`, prim `name`.
    pub fn usda(
        &self,
        setup: &SubdivSetup,
        name: &str,
        up: UpAxis,
    ) -> Result<String, HandoffError> {
        write_usda(&CageFrames {
            cage: &setup.cage,
            times: &self.times,
            positions: &self.cages,
            fps: self.fps,
            name,
            up,
        })
    }

    /// The frames as binary glTF ([`write_glb`]): the limit surface tessellated at `level`
    /// (the grid of [`LimitMesh`]), triangulated once at rest.
    pub fn glb(
        &self,
        setup: &SubdivSetup,
        level: usize,
        name: &str,
        up: UpAxis,
    ) -> Result<Vec<u8>, HandoffError> {
        let surface = setup.full_surface()?;
        let mesh = LimitMesh::new(&setup.cage, &surface, level)?;
        let positions: Vec<Vec<Point3>> = self
            .cages
            .iter()
            .map(|cage| {
                let mut out = vec![[0.0; 3]; mesh.n_vertices()];
                mesh.positions(cage, &mut out);
                out
            })
            .collect();
        let mut rest = vec![[0.0; 3]; mesh.n_vertices()];
        mesh.positions(setup.cage.positions(), &mut rest);
        write_glb(&SurfaceFrames {
            triangles: &mesh.triangles(&rest),
            times: &self.times,
            positions: &positions,
            name,
            up,
        })
    }
}

/// Checks frame times (finite, increasing, one per frame) and that every frame has `n`
/// points with coordinates that round to finite `f32`.
fn check_frames(times: &[f64], frames: &[Vec<Point3>], n: usize) -> Result<(), HandoffError> {
    if frames.is_empty() || times.len() != frames.len() {
        return Err(HandoffError::Frames {
            what: format!(
                "{} frame times for {} frames; expected one time per frame, at least one frame",
                times.len(),
                frames.len()
            ),
        });
    }
    if let Some(k) = (0..times.len())
        .find(|&k| !times[k].is_finite() || times[k] < 0.0 || (k > 0 && times[k] <= times[k - 1]))
    {
        return Err(HandoffError::Frames {
            what: format!(
                "frame {k}: time {} is not a finite time ≥ 0 after the frame before",
                times[k]
            ),
        });
    }
    for (f, frame) in frames.iter().enumerate() {
        if frame.len() != n {
            return Err(HandoffError::PointCount {
                frame: f,
                got: frame.len(),
                expected: n,
            });
        }
        for (v, p) in frame.iter().enumerate() {
            if let Some(&value) = p.iter().find(|c| !(**c as f32).is_finite()) {
                return Err(HandoffError::NonFinite {
                    frame: f,
                    vertex: v,
                    value,
                });
            }
        }
    }
    Ok(())
}

/// The smallest box holding `points` (as written, in `f32`): `(min, max)` per axis.
fn extent_f32(points: impl IntoIterator<Item = [f32; 3]>) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}
