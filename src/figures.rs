//! The figure registry (feature `plot`): every model's published figures in one list.
//!
//! Each model lists its own figures ([`crate::growth::figures::FIGURES`],
//! [`crate::ripple::FIGURES`], ...); [`all`] gathers them for `cellsurf figures`. Nothing in
//! the library imports this module: it sits above every model.

use crate::plot::Figure;

/// Every figure of every model: the growth paper's, then the related models'.
pub fn all() -> impl Iterator<Item = &'static Figure> {
    crate::growth::figures::FIGURES
        .iter()
        .chain(crate::windripples::FIGURES)
        .chain(crate::dunes::FIGURES)
        .chain(crate::cursor::FIGURES)
        .chain(crate::ripple::FIGURES)
        .chain(crate::raytrace::FIGURES)
        .chain(crate::tile::FIGURES)
}

/// The figure called `name`.
pub fn find(name: &str) -> Option<&'static Figure> {
    all().find(|f| f.name == name)
}
