//! From a pattern to yarn-level topology: the [`Fabric`].

pub mod fabric;

pub use fabric::*;
