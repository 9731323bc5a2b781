//! The `domain` section of a scene file, read by our format ([`super::ours`]) and by the
//! deformation-operator settings ([`super::defop`]).

use serde::Deserialize;

use crate::domain::{DomainOptions, DomainShape};

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
    #[serde(default)]
    shape: Option<ShapeFile>,
    #[serde(default)]
    margin: Option<f64>,
}

/// `domain.shape`: the names of [`DomainShape`].
#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum ShapeFile {
    Enclosing,
    Art,
}

impl From<ShapeFile> for DomainShape {
    fn from(s: ShapeFile) -> DomainShape {
        match s {
            ShapeFile::Enclosing => DomainShape::Enclosing,
            ShapeFile::Art => DomainShape::Art,
        }
    }
}

/// The domain options of our scene format where the file says nothing: the defaults, with the
/// art-shaped domain ([`DomainShape::Art`]) so that a pin's influence stays in the part of the
/// art it is on. The paper authors' scenes keep [`DomainOptions::default`] (their enclosing
/// curve or the padded box).
///
/// ```
/// use splineskin::domain::DomainShape;
/// assert_eq!(splineskin::scene::scene_domain_options().shape, DomainShape::Art);
/// ```
pub fn scene_domain_options() -> DomainOptions {
    DomainOptions::default().with_shape(DomainShape::Art)
}

impl DomainFile {
    pub(crate) fn options(&self) -> DomainOptions {
        self.options_over(scene_domain_options())
    }

    /// `base` with the options this section sets.
    pub(crate) fn options_over(&self, base: DomainOptions) -> DomainOptions {
        /// `o`, or `o` with `with(o, v)` when the section sets `v`.
        fn set<T>(
            o: DomainOptions,
            v: Option<T>,
            with: fn(DomainOptions, T) -> DomainOptions,
        ) -> DomainOptions {
            match v {
                Some(v) => with(o, v),
                None => o,
            }
        }
        let o = set(base, self.min_angle, DomainOptions::with_min_angle);
        let o = set(
            o,
            self.max_area_fraction,
            DomainOptions::with_max_area_fraction,
        );
        let o = set(o, self.holes, DomainOptions::with_holes);
        let o = set(o, self.max_vertices, DomainOptions::with_max_vertices);
        let o = set(
            o,
            self.samples_per_diagonal,
            DomainOptions::with_samples_per_diagonal,
        );
        let o = set(
            o,
            self.max_samples_per_curve,
            DomainOptions::with_max_samples_per_curve,
        );
        let o = set(
            o,
            self.max_curve_samples,
            DomainOptions::with_max_curve_samples,
        );
        let o = set(o, self.padding, DomainOptions::with_padding);
        let o = set(
            o,
            self.shape.map(DomainShape::from),
            DomainOptions::with_shape,
        );
        set(o, self.margin, DomainOptions::with_margin)
    }
}
