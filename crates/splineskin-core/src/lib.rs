//! # splineskin-core
//!
//! The mathematics of splineskin, with no file format in it: cubic Bézier drawings
//! ([`drawing`], [`bezier`]), triangle meshes and their operators ([`mesh`]), the triangulated
//! domain of a drawing ([`domain`]), skinning weights ([`weights`]: Shepard, harmonic, bounded
//! biharmonic, mean-value coordinates, coarse-to-fine), the sparse factorisations they share
//! ([`linalg`]), and the closed-form spline fit with its per-frame rig
//! ([`spline_fit`]; Liu, Jacobson & Gingold 2014), and keyframed poses of plane and space
//! ([`animation`]).
//!
//! ```text
//! once:        drawing + handles + weights ──► SplineRig::precompute ──► dense operator O
//! each frame:  transforms T_i ──► rig.update(&T, &mut points)   (points = O · vec(T))
//! ```
//!
//! Arrows: nothing here imports another splineskin crate; `splineskin-svg`,
//! `splineskin-subdiv`, `splineskin-defop` and the `splineskin` facade build on it.
#![warn(clippy::print_stdout, clippy::print_stderr)]

pub mod animation;
pub mod atomic_write;
pub mod bezier;
pub mod domain;
pub mod drawing;
pub mod folds;
pub mod linalg;
pub mod mesh;
pub mod parallel;
pub mod spline_fit;
pub mod stop;
#[cfg(test)]
mod test_support;
mod union_find;
pub mod weights;
