//! All-or-nothing file output.
//!
//! The content goes to a fresh temporary file next to the target (same
//! directory, hence same filesystem, which makes `rename` atomic on POSIX),
//! is flushed and `fsync`ed, then renamed over the target. Any error on the
//! way removes the temporary file, so a failed export leaves the previous
//! file untouched and no debris. After the rename the directory is synced as
//! well (best effort), so the new name itself survives a crash.

use super::IoError;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporary files of concurrent writers in one process; the
/// process id distinguishes processes.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `path` atomically with the bytes `fill` produces.
///
/// `fill` receives a buffered writer; if it returns an error, nothing at
/// `path` changes and the temporary file is removed.
pub fn write_atomic<F>(path: &Path, fill: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let write_err = |source| IoError::Write {
        path: path.to_path_buf(),
        source,
    };
    let (temp_path, file) = create_temp(path).map_err(write_err)?;
    let result = fill_and_sync(file, fill).and_then(|()| fs::rename(&temp_path, path));
    if let Err(e) = result {
        // The original error matters more than a failed cleanup.
        let _ = fs::remove_file(&temp_path);
        return Err(write_err(e));
    }
    sync_parent_dir(path);
    Ok(())
}

fn fill_and_sync<F>(file: File, fill: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let mut writer = BufWriter::new(file);
    fill(&mut writer)?;
    let file = writer.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()
}

/// Creates `.<name>.<pid>.<n>.tmp` next to `path`; `create_new` guarantees
/// we never clobber someone else's file.
fn create_temp(path: &Path) -> io::Result<(PathBuf, File)> {
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "path has no file name"))?
        .to_string_lossy();
    let dir = parent_dir(path);
    loop {
        let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
        let temp = dir.join(format!(".{name}.{}.{n}.tmp", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => return Ok((temp, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Persists the directory entry after `rename`. Not all platforms can open a
/// directory for syncing, and the data itself is already safe, so failures
/// are ignored.
fn sync_parent_dir(path: &Path) {
    if let Ok(dir) = File::open(parent_dir(path)) {
        let _ = dir.sync_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir_entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_content_and_leaves_no_temp_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        write_atomic(&path, |w| w.write_all(b"hello")).unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"hello");
        assert_eq!(dir_entries(dir.path()), vec!["out.txt"]);
    }

    #[test]
    fn failure_half_way_leaves_no_file_and_no_temp() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        let err = write_atomic(&path, |w| {
            w.write_all(&[b'x'; 100_000])?;
            Err(io::Error::other("disk on fire"))
        })
        .unwrap_err();
        assert!(err.to_string().contains("out.txt"), "error names the path: {err}");
        assert!(err.to_string().contains("disk on fire"));
        assert!(dir_entries(dir.path()).is_empty(), "{:?}", dir_entries(dir.path()));
    }

    #[test]
    fn failure_keeps_existing_file_untouched() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        fs::write(&path, b"previous").unwrap();
        let result = write_atomic(&path, |w| {
            w.write_all(b"partial new content")?;
            Err(io::Error::other("interrupted"))
        });
        assert!(result.is_err());
        assert_eq!(fs::read(&path).unwrap(), b"previous");
        assert_eq!(dir_entries(dir.path()), vec!["out.txt"]);
    }

    #[test]
    fn replaces_existing_file_on_success() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.txt");
        fs::write(&path, b"previous, longer content").unwrap();
        write_atomic(&path, |w| w.write_all(b"new")).unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"new");
    }

    #[test]
    fn missing_directory_is_an_error_naming_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no/such/dir/out.txt");
        let err = write_atomic(&path, |w| w.write_all(b"x")).unwrap_err();
        assert!(matches!(err, IoError::Write { .. }));
        assert!(err.to_string().contains("no/such/dir/out.txt"), "{err}");
    }
}
