//! The accuracy modes: what each costs is measured in docs/benchmarks.md and
//! docs/accuracy.md; why each keeps the digits it keeps is in docs/derivations/accuracy.md.

use std::fmt;
use std::str::FromStr;

/// How a narrow-phase kernel evaluates the quadratic. Every mode applies the same contact
/// policy (docs/derivations/policies.md); they differ only in rounding.
///
/// ```
/// use spheresweep::Accuracy;
/// assert_eq!(Accuracy::default(), Accuracy::Stable);
/// assert_eq!("double".parse::<Accuracy>(), Ok(Accuracy::Double));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Accuracy {
    /// The seed's formula literally in f32: `B² − 4AC`, `(−B ∓ √disc)/2A`.
    Textbook,
    /// f32, rearranged: half-`B`, the discriminant as `A·D² − ‖r0 × v‖²`, roots without
    /// cancellation, far anchors of planes and cylinders moved next to the origin.
    #[default]
    Stable,
    /// The `Stable` formulas in f64 lanes on the f32 inputs, rounded once to f32 at the end.
    Double,
}

impl Accuracy {
    /// Every mode, cheapest first.
    pub const ALL: [Accuracy; 3] = [Accuracy::Textbook, Accuracy::Stable, Accuracy::Double];

    /// The lower-case name used on the command line and in reports.
    ///
    /// ```
    /// use spheresweep::Accuracy;
    /// assert_eq!(Accuracy::Textbook.name(), "textbook");
    /// assert_eq!(Accuracy::Stable.to_string(), Accuracy::Stable.name());
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            Accuracy::Textbook => "textbook",
            Accuracy::Stable => "stable",
            Accuracy::Double => "double",
        }
    }
}

impl fmt::Display for Accuracy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An accuracy name that is not one of `textbook`, `stable`, `double`.
///
/// ```
/// use spheresweep::{Accuracy, accuracy::UnknownAccuracy};
/// let err = "fast".parse::<Accuracy>().unwrap_err();
/// assert_eq!(err, UnknownAccuracy("fast".to_owned()));
/// assert!(err.to_string().contains("\"fast\""));
/// ```
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown accuracy mode {0:?}: expected textbook, stable or double")]
pub struct UnknownAccuracy(pub String);

impl FromStr for Accuracy {
    type Err = UnknownAccuracy;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Accuracy::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| UnknownAccuracy(s.to_owned()))
    }
}
