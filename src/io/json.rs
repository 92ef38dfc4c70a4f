//! Save and resume a fabric state as pretty JSON.
//!
//! Loading checks the same index consistency as the writers, so a
//! hand-edited file fails at load time with a message rather than later
//! inside a solver or exporter. Saving rejects non-finite positions: JSON
//! has no NaN, and serde_json would write `null`, which cannot be read back.
//!
//! Exactness: serde_json writes the shortest decimal that round-trips, but
//! parses it back exactly only with its `float_roundtrip` feature; without
//! it about one double in ten comes back one ulp off (see the ignored test).

use super::validate::check_structure;
use super::{write_atomic, IoError};
use crate::topology::Fabric;
use std::io;
use std::path::Path;

/// Writes `fabric` to `path` as pretty JSON (atomically).
pub fn save_json(fabric: &Fabric, path: &Path) -> Result<(), IoError> {
    check_structure(fabric).map_err(|source| IoError::Export {
        path: path.to_path_buf(),
        source,
    })?;
    write_atomic(path, |w| {
        serde_json::to_writer_pretty(&mut *w, fabric).map_err(io::Error::other)?;
        writeln!(w)
    })
}

/// Reads a fabric written by [`save_json`] (or by hand).
pub fn load_json(path: &Path) -> Result<Fabric, IoError> {
    let text = std::fs::read_to_string(path).map_err(|source| IoError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let fabric: Fabric = serde_json::from_str(&text).map_err(|e| IoError::Json {
        path: path.to_path_buf(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    check_structure(&fabric).map_err(|source| IoError::Export {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(fabric)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::fixtures::crossing;
    use crate::topology::SimInfo;

    #[test]
    fn round_trip_is_equal() {
        let mut fabric = crossing();
        // Values without short decimal forms, and the optional parts set.
        fabric.nodes[0].x.x = 1.0 / 3.0 * 1e-3;
        fabric.nodes[1].x.z = -std::f64::consts::PI * 1e-4;
        fabric.nodes[2].pinned = true;
        fabric.contacts[0].partner = Some(3);
        fabric.sim = Some(SimInfo {
            time: 0.125,
            newton_iterations: 7,
            residual: 3.1e-9,
        });
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("state.json");
        save_json(&fabric, &path).unwrap();
        assert_eq!(load_json(&path).unwrap(), fabric);
    }

    /// serde_json's default float parser is only "best effort": about one in
    /// ten random doubles comes back one ulp off, so a saved state does not
    /// resume bit for bit. Needs the `float_roundtrip` feature of serde_json
    /// in Cargo.toml (lead-owned); un-ignore once it is on.
    #[test]
    fn round_trip_is_bit_exact_for_arbitrary_positions() {
        let mut fabric = crossing();
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        for node in &mut fabric.nodes {
            for c in node.x.iter_mut() {
                // xorshift64: deterministic, no dependency.
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                *c = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.2;
            }
        }
        let text = serde_json::to_string_pretty(&fabric).unwrap();
        let back: Fabric = serde_json::from_str(&text).unwrap();
        assert_eq!(back, fabric);
    }

    #[test]
    fn malformed_json_names_file_line_and_column() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("broken.json");
        // The value of "meta" is missing: a comma on line 3, column 3.
        std::fs::write(&path, "{\n  \"meta\":\n  ,\n}").unwrap();
        let err = load_json(&path).unwrap_err();
        match &err {
            IoError::Json { line, column, .. } => assert_eq!((*line, *column), (3, 3), "{err}"),
            other => panic!("expected a JSON error, got {other}"),
        }
        assert!(
            err.to_string().starts_with(&format!("{}:3:3:", path.display())),
            "{err}"
        );
    }

    #[test]
    fn dangling_index_is_rejected_on_load() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("dangling.json");
        let mut fabric = crossing();
        save_json(&fabric, &path).unwrap();
        fabric.yarns[0].points[0].node = 99;
        let text = serde_json::to_string(&fabric).unwrap();
        std::fs::write(&path, text).unwrap();
        let err = load_json(&path).unwrap_err();
        assert!(err.to_string().contains("node 99"), "{err}");
    }

    #[test]
    fn missing_file_is_a_read_error_naming_it() {
        let err = load_json(Path::new("/nonexistent/knitsim.json")).unwrap_err();
        assert!(matches!(err, IoError::Read { .. }));
        assert!(err.to_string().contains("/nonexistent/knitsim.json"));
    }

    #[test]
    fn nan_position_is_refused_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nan.json");
        let mut fabric = crossing();
        fabric.nodes[1].x.y = f64::NAN;
        assert!(save_json(&fabric, &path).is_err());
        assert!(!path.exists());
    }
}
