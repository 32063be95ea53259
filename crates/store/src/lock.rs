//! Output files owned by one run at a time, and output paths checked before
//! any work starts.
//!
//! A run that writes `FILE` (an atlas, a sweep, a merge) holds an exclusive
//! advisory lock on `.FILE.lock` beside it for its whole life, journal and
//! resume included; a second run on the same output is refused at once, naming
//! the holder's process id and host. The lock file is removed when the run
//! ends; a lock left by a killed run is not held by anyone (the kernel drops it
//! with the process) and is taken over.

use crate::error::StoreError;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The lock path of an output file: `.<name>.lock` beside it.
pub fn lock_path(output: &Path) -> PathBuf {
    let name = output.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    output.with_file_name(format!(".{name}.lock"))
}

/// An exclusive lock on an output file, released (and its lock file removed)
/// when dropped.
#[derive(Debug)]
pub struct OutputLock {
    file: File,
    path: PathBuf,
}

/// Who holds a lock: `pid N on HOST`, as written into the lock file.
fn holder() -> String {
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .unwrap_or_else(|_| "this host".into());
    format!("pid {} on {host}", std::process::id())
}

impl OutputLock {
    /// Takes the lock of `output`, or fails at once when another run holds it.
    pub fn acquire(output: &Path) -> Result<OutputLock, StoreError> {
        let path = lock_path(output);
        let io = |e| StoreError::io(&path, e);
        loop {
            let mut file =
                OpenOptions::new().read(true).write(true).create(true).truncate(false).open(&path).map_err(io)?;
            match file.try_lock() {
                Ok(()) => {}
                Err(std::fs::TryLockError::WouldBlock) => {
                    let mut who = String::new();
                    let _ = file.read_to_string(&mut who);
                    let who = if who.trim().is_empty() { "another run".to_string() } else { who.trim().to_string() };
                    return Err(StoreError::format(
                        output,
                        format!("is being written by another vibroatlas run ({who}); wait for it, or write elsewhere"),
                    ));
                }
                Err(std::fs::TryLockError::Error(e)) => return Err(io(e)),
            }
            // The holder before us may have removed the file after we opened
            // it: then our lock is on a file nobody else will open. Try again.
            let same = match (file.metadata(), std::fs::metadata(&path)) {
                (Ok(a), Ok(b)) => same_file(&a, &b),
                _ => false,
            };
            if !same {
                continue;
            }
            file.set_len(0).map_err(io)?;
            file.rewind().map_err(io)?;
            writeln!(file, "{}", holder()).map_err(io)?;
            return Ok(OutputLock { file, path });
        }
    }
}

#[cfg(unix)]
fn same_file(a: &std::fs::Metadata, b: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_file(_: &std::fs::Metadata, _: &std::fs::Metadata) -> bool {
    true
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still held, so that no one can lock the old file.
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

/// Checks, before any work, that `output` can be written as a new or replaced
/// regular file: not a directory, not one of `inputs` (the scene, the parts of
/// a merge), not a device or other special file unless `force`, and in a folder
/// that exists.
pub fn check_output(output: &Path, inputs: &[&Path], force: bool) -> Result<(), StoreError> {
    let bad = |m: &str| Err(StoreError::format(output, m.to_string()));
    if output.as_os_str().is_empty() {
        return Err(StoreError::format(Path::new("output"), "empty path"));
    }
    if output.file_name().is_none() {
        return bad("is not a file name");
    }
    let parent = output.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return bad("its folder does not exist");
    }
    match std::fs::metadata(output) {
        Ok(m) if m.is_dir() => return bad("is a directory; give a file name"),
        Ok(m) if !m.is_file() && !force => {
            return bad("exists and is not a regular file (a device, a pipe, …); refusing to replace it")
        }
        _ => {}
    }
    if let Ok(out) = output.canonicalize() {
        for input in inputs {
            if input.canonicalize().is_ok_and(|i| i == out) {
                return bad(&format!("is also an input ({}); write the output elsewhere", input.display()));
            }
        }
    }
    Ok(())
}

/// Checks, before any work, that the existing file `path` can be rewritten
/// in place (as `curves --into` does): it opens for writing, and its folder
/// takes the temporary file that replaces it.
pub fn check_writable(path: &Path) -> Result<(), StoreError> {
    let refused = |why: String| StoreError::format(path, why);
    std::fs::OpenOptions::new().write(true).open(path).map_err(|e| refused(format!("cannot be rewritten ({e})")))?;
    let probe = crate::partial_path(path);
    std::fs::File::create(&probe).map_err(|e| refused(format!("its folder takes no new file ({e})")))?;
    std::fs::remove_file(&probe).map_err(|e| StoreError::io(&probe, e))
}

/// Moves a complete temporary file over `path` durably: the file's data is
/// synced before the rename, and the folder after it (a power loss leaves the
/// old file or the new one, never an empty one). A target that exists and is
/// not a regular file (a device such as /dev/null, a pipe) is never replaced:
/// the bytes are written into it instead; a folder is an error.
pub fn commit(tmp: &Path, path: &Path) -> Result<(), StoreError> {
    let io = |e| StoreError::io(path, e);
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => return Err(StoreError::format(path, "is a directory; give a file name")),
        Ok(m) if !m.is_file() => {
            let mut from = File::open(tmp).map_err(io)?;
            let mut to = OpenOptions::new().write(true).open(path).map_err(io)?;
            std::io::copy(&mut from, &mut to).map_err(io)?;
            return std::fs::remove_file(tmp).map_err(io);
        }
        _ => {}
    }
    File::open(tmp).and_then(|f| f.sync_all()).map_err(io)?;
    std::fs::rename(tmp, path).map_err(io)?;
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    // Syncing a folder is not possible everywhere; the rename has happened.
    if let Ok(dir) = File::open(parent) {
        let _ = dir.sync_all();
    }
    Ok(())
}

/// Refuses an output `path` whose folder does not exist.
pub(crate) fn check_folder(path: &Path) -> Result<(), StoreError> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(StoreError::format(path, "its folder does not exist"));
    }
    Ok(())
}

/// Writes `path` through `write`, which fills a temporary file beside it (see
/// [`crate::partial_path`]); the temporary replaces `path` only once complete
/// ([`commit`]), so a failure never leaves a half-written file under its name.
pub fn write_atomically<E: std::fmt::Display>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), StoreError> {
    check_folder(path)?;
    let tmp = crate::partial_path(path);
    if let Err(e) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        // One line, whatever the writer's message spans (HDF5's span several).
        return Err(StoreError::format(path, e.to_string().split_whitespace().collect::<Vec<_>>().join(" ")));
    }
    commit(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_is_refused_and_the_first_is_released_on_drop() {
        let dir = std::env::temp_dir().join(format!("vibroatlas-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("a.h5");
        let first = OutputLock::acquire(&out).unwrap();
        let err = OutputLock::acquire(&out).unwrap_err().to_string();
        assert!(err.contains("another vibroatlas run (pid "), "{err}");
        drop(first);
        assert!(!lock_path(&out).exists());
        let again = OutputLock::acquire(&out).unwrap();
        drop(again);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn outputs_that_are_folders_inputs_or_devices_are_refused() {
        let dir = std::env::temp_dir().join(format!("vibroatlas-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("s.toml");
        std::fs::write(&scene, "x").unwrap();
        assert!(check_output(&dir, &[], false).unwrap_err().to_string().contains("is a directory"));
        assert!(check_output(&scene, &[&scene], false).unwrap_err().to_string().contains("is also an input"));
        assert!(check_output(Path::new("/dev/null"), &[], false).is_err());
        assert!(check_output(Path::new("/dev/null"), &[], true).is_ok());
        // A device is written into, never replaced by a file.
        let tmp = dir.join("t");
        std::fs::write(&tmp, "bytes").unwrap();
        commit(&tmp, Path::new("/dev/null")).unwrap();
        assert!(!std::fs::metadata("/dev/null").unwrap().is_file() && !tmp.exists());
        assert!(check_output(&dir.join("nope/a.h5"), &[], false).is_err());
        assert!(check_output(&dir.join("a.h5"), &[&scene], false).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
