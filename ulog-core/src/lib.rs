//! ULog core (being written).
pub mod typed;
