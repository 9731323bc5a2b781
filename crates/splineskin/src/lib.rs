//! # splineskin
//!
//! Deform cubic Bézier drawings with linear blend skinning **and keep them splines**: the
//! skinned curve `s(t) = Σ_i w_i(B(t)) T_i B(t)` is not a cubic, so each curve is replaced by the
//! cubic closest to it in the L² sense, subject to the continuity the drawing had at its
//! junctions (Liu, Jacobson & Gingold, *Skinning Cubic Bézier Splines and Catmull-Clark
//! Subdivision Surfaces*, SIGGRAPH Asia 2014). The fit is linear in the handle transforms, so it
//! is split into a one-off precomputation and a per-frame matrix–vector product.
//!
//! ```text
//! once:        drawing + handles + weights ──► SplineRig::precompute ──► dense operator O
//! each frame:  transforms T_i ──► rig.update(&T, &mut points)   (points = O · vec(T))
//! ```
#![warn(clippy::print_stdout, clippy::print_stderr)]

pub mod animation;
mod atomic_write;
pub mod bezier;
pub mod compare;
pub mod defop;
pub mod domain;
pub mod drawing;
pub mod examples;
pub mod figure;
pub mod fonts;
mod linalg;
pub mod mesh;
pub mod metrics;
pub mod naive;
pub mod render;
pub mod scene;
pub mod spline_fit;
pub mod subdiv;
pub mod weight_map;
pub mod weights;

/// The README's code examples, compiled and run as doctests so they cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
