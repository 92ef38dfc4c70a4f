//! Pattern language: text to a validated [`Pattern`].

pub mod model;

pub use model::*;
