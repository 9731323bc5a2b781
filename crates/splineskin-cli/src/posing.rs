//! How a command poses a scene: the discretisation (`--compat`) and flexible junctions
//! (`--flexible`), as the library's [`PoseOptions`].

use splineskin::scene::{Compat, PoseOptions};

/// How `deform` and `animate` pose a scene: `--compat` and `--flexible`.
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct PosingArgs {
    /// Reproduce another implementation's discretisation exactly.
    #[arg(long, value_enum, default_value_t = CompatArg::None)]
    pub compat: CompatArg,
    /// Flexible G¹ and fixed-angle junctions: parallel tangents (fixed angle: their angle) with
    /// the tangent-length ratio free, fitted by iteration. Scenes can ask for it themselves
    /// (`"flexible": true`; the authors' scenes always do).
    #[arg(long)]
    pub flexible: bool,
}

impl PosingArgs {
    /// The library's posing options; the per-frame product on a second thread when `parallel`
    /// (not where frames are deformed in parallel already).
    pub fn options(self, parallel: bool) -> PoseOptions {
        PoseOptions {
            compat: self.compat.into(),
            flexible: self.flexible,
            parallel,
        }
    }
}

/// The `--compat` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CompatArg {
    /// Our discretisation (default).
    None,
    /// The paper authors' code exactly (their SVG reading, quadrature and constraint rows).
    Vectorskinning,
}

impl From<CompatArg> for Compat {
    fn from(c: CompatArg) -> Self {
        match c {
            CompatArg::None => Compat::None,
            CompatArg::Vectorskinning => Compat::VectorSkinning,
        }
    }
}
