//! Output: VTK, OBJ, PNG and JSON, each written to a temporary file and renamed.
//!
//! Every writer takes a [`Fabric`](crate::topology::Fabric), because the same
//! type is both the compiled topology and the simulation state (see
//! `topology::fabric`). Whatever stage produced it, the exporters draw it the
//! same way: through [`Fabric::curves`](crate::topology::Fabric::curves).
//!
//! Why atomic: a relaxation can run for minutes and is interrupted with
//! Ctrl-C, and viewers such as ParaView reload files while they change. A
//! reader must see either the previous complete file or the new complete
//! file, never a truncated one. [`atomic::write_atomic`] provides that for all
//! formats: temporary file in the same directory (so `rename` stays on one
//! filesystem and is atomic on POSIX), `fsync`, `rename`, and removal of the
//! temporary file on any error.
//!
//! Formats and who reads them:
//! - [`vtk`]: legacy ASCII VTK for ParaView and meshio (centre lines plus
//!   per-point kind and `u`), for inspecting the simulation state.
//! - [`obj`]: smooth tube meshes with per-yarn materials, for renderers.
//! - [`png`]: a shaded orthographic preview of the RS face, for people.
//! - [`json`]: the full `Fabric`, to save and resume a state.
//! - [`vtu`]: VTK XML frames and `.pvd` collections of a dynamic run
//!   (ParaView's animation), and triangle meshes of obstacles.

pub mod atomic;
mod error;
#[cfg(test)]
pub(crate) mod fixtures;
pub mod json;
pub mod obj;
pub mod png;
mod raster;
pub mod smooth;
pub mod tube;
mod validate;
pub mod vtk;
pub mod vtu;

pub use atomic::write_atomic;
pub use error::{ExportError, IoError};
pub use json::{load_json, save_json};
pub use obj::{write_obj, ObjOptions};
pub use png::{fit_preview, render_preview, write_png, Background, PngOptions, PngScale};
pub use smooth::SmoothOptions;
pub use tube::{TubeMesh, TubeOptions};
pub use vtk::{write_vtk, VtkCells, VtkOptions};
pub use vtu::{write_pvd, write_triangles_vtu, write_vtu, PvdEntry};
