//! Rendering only: tables, Markdown, CSV, SVG/PNG plots. Functions return values; files
//! are written by [`crate::files`].

pub mod campbell;
pub mod chart;
pub(crate) mod clip;
pub mod design;
pub(crate) mod glossary;
pub mod html;
pub mod plot;
pub mod study;
pub mod style;
pub mod summary;
pub mod unbalance;
