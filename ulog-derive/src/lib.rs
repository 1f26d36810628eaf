//! Derive macros for ULog topic bindings (see the typed-bindings issue); empty until then.
