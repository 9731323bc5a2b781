//! The choice of rule ([`FlexibleRule`]) and its stopping parameters ([`FlexibleOptions`]),
//! with their defaults.

/// Default stopping tolerance: a step ([`FlexibleRule::Newton`]) or a round of a direction and
/// a ratio step ([`FlexibleRule::Alternating`]) lowering the path's energy by less than this
/// fraction ends the iteration: 1e-5. On the authors' scenes and the
/// bundled drawing, the points then move by less than 1e-4 of the bounding-box diagonal from
/// where a 1e-9 tolerance takes them (tests/flexible_g1.rs), far below what can be seen.
pub const DEFAULT_TOLERANCE: f64 = 1e-5;

/// Default cap on the linear solves (steps) per path: 40 (20 rounds).
pub const DEFAULT_MAX_STEPS: usize = 40;

/// How the iteration is run and stopped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum FlexibleRule {
    /// Ours, the default: Gauss–Newton steps on the junctions' directions and tangent
    /// lengths together, monotone, stopping on the relative energy decrease of a step (the
    /// [`flexible`](super) module doc).
    #[default]
    Newton,
    /// Ours by alternation: monotone direction and ratio steps, stopping on the relative energy
    /// decrease of a round (the [`flexible`](super) module doc). Converges to the same fits as [`FlexibleRule::Newton`],
    /// in more (and cheaper-to-set-up) linear solves.
    Alternating,
    /// The paper authors' schedule, resets and stopping test (the [`flexible`](super) module doc), for compatibility
    /// mode.
    Authors,
}

/// Options of the flexible solve.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FlexibleOptions {
    /// The schedule. Default: [`FlexibleRule::Newton`].
    pub rule: FlexibleRule,
    /// Relative energy decrease per step ([`FlexibleRule::Newton`]) or round
    /// ([`FlexibleRule::Alternating`]) under which the iteration stops (not used by the authors'
    /// rule). Default: [`DEFAULT_TOLERANCE`].
    pub tolerance: f64,
    /// Largest number of steps per path (not the authors' rule, which does at
    /// most `1 + 2 ·` [`AUTHORS_MAX_ROUNDS`](super::AUTHORS_MAX_ROUNDS)). Default: [`DEFAULT_MAX_STEPS`].
    pub max_steps: usize,
}

impl Default for FlexibleOptions {
    fn default() -> Self {
        FlexibleOptions {
            rule: FlexibleRule::Newton,
            tolerance: DEFAULT_TOLERANCE,
            max_steps: DEFAULT_MAX_STEPS,
        }
    }
}

impl FlexibleOptions {
    /// The authors' rule (compatibility mode `vectorskinning`).
    pub fn vectorskinning() -> Self {
        FlexibleOptions {
            rule: FlexibleRule::Authors,
            ..Default::default()
        }
    }
    /// Sets [`FlexibleOptions::rule`].
    pub fn with_rule(mut self, rule: FlexibleRule) -> Self {
        self.rule = rule;
        self
    }
    /// Sets [`FlexibleOptions::tolerance`].
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }
    /// Sets [`FlexibleOptions::max_steps`].
    pub fn with_max_steps(mut self, max_steps: usize) -> Self {
        self.max_steps = max_steps;
        self
    }
}
