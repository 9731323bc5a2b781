//! Which discretisation a scene is read and solved with: ours, or the paper authors' code
//! exactly ([`Compat`]).

use crate::spline_fit::FlexibleOptions;

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
