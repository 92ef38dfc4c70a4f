//! Scenes: what to simulate around a fabric, and with which parameters.
//!
//! A scene is data (JSON), so a run is reproducible from its files alone.
//! Obstacles are signed distance fields with a stiff penalty; a scene that
//! has none costs nothing for them (no stencils are built).

pub mod obstacle;

pub use obstacle::{ObstaclePenalty, Shape};
