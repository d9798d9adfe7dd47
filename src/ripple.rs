//! Placeholder: being written.

/// The figures of this model, made by `cellsurf figures`.
#[cfg(feature = "plot")]
pub const FIGURES: &[crate::figures::Figure] = &[];
