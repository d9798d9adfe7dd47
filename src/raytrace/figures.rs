//! placeholder
use crate::figures::Figure;
/// The figures.
pub const FIGURES: &[Figure] = &[];
