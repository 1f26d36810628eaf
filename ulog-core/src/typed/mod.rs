//! Typed bindings (being written).
