//! The `domain` section of a scene file, read by our format ([`super::ours`]) and by the
//! deformation-operator settings ([`super::defop`]).

use serde::Deserialize;

use crate::domain::DomainOptions;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
/// The `domain` section of a scene (and of its `defop` section): the options of the
/// triangulated domain, each optional ([`DomainOptions`] gives defaults and ranges).
pub(crate) struct DomainFile {
    #[serde(default)]
    min_angle: Option<f64>,
    #[serde(default)]
    max_area_fraction: Option<f64>,
    #[serde(default)]
    holes: Option<bool>,
    #[serde(default)]
    max_vertices: Option<usize>,
    #[serde(default)]
    samples_per_diagonal: Option<f64>,
    #[serde(default)]
    max_samples_per_curve: Option<usize>,
    #[serde(default)]
    max_curve_samples: Option<usize>,
    #[serde(default)]
    padding: Option<f64>,
}

impl DomainFile {
    pub(crate) fn options(&self) -> DomainOptions {
        self.options_over(DomainOptions::default())
    }

    /// `base` with the options this section sets.
    pub(crate) fn options_over(&self, base: DomainOptions) -> DomainOptions {
        let mut o = base;
        if let Some(v) = self.min_angle {
            o = o.with_min_angle(v);
        }
        if let Some(v) = self.max_area_fraction {
            o = o.with_max_area_fraction(v);
        }
        if let Some(v) = self.holes {
            o = o.with_holes(v);
        }
        if let Some(v) = self.max_vertices {
            o = o.with_max_vertices(v);
        }
        if let Some(v) = self.samples_per_diagonal {
            o = o.with_samples_per_diagonal(v);
        }
        if let Some(v) = self.max_samples_per_curve {
            o = o.with_max_samples_per_curve(v);
        }
        if let Some(v) = self.max_curve_samples {
            o = o.with_max_curve_samples(v);
        }
        if let Some(v) = self.padding {
            o = o.with_padding(v);
        }
        o
    }
}
