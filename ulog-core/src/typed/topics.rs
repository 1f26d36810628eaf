//! Several topics at once: an enum with one variant per binding
//! (`#[derive(ULogTopics)]`), planned per subscription like a single binding.

use ulog_format::Layout;

use super::error::{DecodeError, Mismatch};
use super::message::ULogMessage;
use super::plan::RawPlan;

/// An enum of bindings, one tuple variant per ULog message, derived with
/// `#[derive(ULogTopics)]`; read with [`scan_topics`](crate::scan_topics).
pub trait ULogTopics: Sized {
    /// The message names of the variants, in declaration order.
    const NAMES: &'static [&'static str];

    /// The other names of each variant's topic ([`ULogMessage::ALIASES`]), in the
    /// order of [`NAMES`](Self::NAMES) (empty: none).
    const ALIASES: &'static [&'static [&'static str]] = &[];

    /// Plans variant `variant` (an index into [`NAMES`](Self::NAMES)) for a
    /// subscription's layout; `None` if there is no such variant.
    fn plan(variant: usize, layout: &Layout) -> Option<Result<TopicPlan, Mismatch>>;

    /// Decodes a payload with a plan made by [`plan`](Self::plan).
    fn decode(plan: &TopicPlan, payload: &[u8]) -> Result<Self, DecodeError>;

    /// The variant bound to message `name`, by its name or else one of its aliases.
    fn variant_of(name: &str) -> Option<usize> {
        Self::NAMES.iter().position(|n| *n == name).or_else(|| {
            Self::ALIASES
                .iter()
                .position(|aliases| aliases.contains(&name))
        })
    }
}

/// The plan of one variant of a [`ULogTopics`] enum for one subscription.
#[derive(Debug, Clone)]
pub struct TopicPlan {
    variant: usize,
    raw: RawPlan,
}

impl TopicPlan {
    /// Plans binding `T` as variant `variant`.
    pub fn new<T: ULogMessage>(variant: usize, layout: &Layout) -> Result<TopicPlan, Mismatch> {
        RawPlan::new::<T>(layout).map(|raw| TopicPlan { variant, raw })
    }

    /// The variant this plan decodes.
    pub fn variant(&self) -> usize {
        self.variant
    }

    /// Decodes a payload as `T`: the binding of this plan's variant (generated code
    /// calls it with the right type; another type decodes other bytes, safely).
    #[inline]
    pub fn decode_as<T: ULogMessage>(&self, payload: &[u8]) -> Result<T, DecodeError> {
        self.raw.decode::<T>(payload)
    }
}
