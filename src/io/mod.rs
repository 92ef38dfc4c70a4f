//! Output: VTK, OBJ, PNG and JSON, each written to a temporary file and renamed.
