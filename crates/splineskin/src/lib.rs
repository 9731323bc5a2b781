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
//!
//! ## Crates
//!
//! This crate is the application layer and the facade of the workspace: it re-exports the
//! crates below at the paths they always had, so `splineskin::spline_fit::SplineRig` and
//! `splineskin::drawing::read_svg` work whichever crate holds them.
//!
//! | crate | what it computes | here as |
//! |---|---|---|
//! | `splineskin-core` | drawings, meshes, the domain, weights, the spline fit and its rig, keyframed poses | [`bezier`], [`drawing`], [`mesh`], [`domain`], [`weights`], [`spline_fit`], [`animation`] |
//! | `splineskin-svg` | SVG import, rewriting the same document, animated SVG, renders | [`drawing`] (`svg_in`, `svg_out`, …), [`render`], [`fonts`] |
//! | `splineskin-subdiv` | Catmull–Clark limit surfaces and their closed-form rig | [`subdiv`] |
//! | `splineskin-defop` | closed-form ARAP / symmetric-ARAP operators and their spline join | [`defop`] |
//! | `splineskin` (this one) | scenes, comparisons, metrics, baselines, adaptive control points, pictures, examples | [`scene`], [`compare`], [`metrics`], [`naive`], [`adaptive`], [`figure`], [`weight_map`], [`examples`] |

pub mod adaptive;
pub mod compare;
pub mod drawing;
pub mod errors;
pub mod examples;
pub mod figure;
pub mod metrics;
pub mod naive;
pub mod scene;
pub mod scene_animation;
pub mod subdiv;

pub use splineskin_core::{
    animation, atomic_write, bezier, domain, folds, mesh, spline_fit, stop, weights,
};
pub use splineskin_defop as defop;
pub use splineskin_svg::{fonts, render};

/// Pictures of handle weights, at the path they always had ([`figure::weight_map`]).
pub use figure::weight_map;

/// The README's code examples, compiled and run as doctests so they cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
