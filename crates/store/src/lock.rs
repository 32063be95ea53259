//! Output files owned by one run at a time, and output paths checked before
//! any work starts.
//!
//! A run that writes `FILE` (an atlas, a sweep, a merge) holds an exclusive
//! advisory lock on `.FILE.lock` beside it for its whole life, journal and
//! resume included; a second run on the same output is refused at once, naming
//! the holder's process id and host. The lock file is removed when the run
//! ends; a lock left by a killed run is not held by anyone (the kernel drops it
//! with the process) and is taken over.
//!
//! The lock follows the file, not its name: it is taken beside the canonical
//! path ([`canonical_output`]: folder resolved, a symbolic link followed to the
//! file it names), so `-o link.h5` and `-o target.h5` are the same output. A
//! symbolic link given as the output is kept: its target is written (replaced
//! by the new file), never the link.
//!
//! The lock, journal and temporary file of an output are the run's own
//! regular files: one that exists as anything else (a named pipe, a device, a
//! socket, a symbolic link) is refused with one line before it is opened
//! ([`check_own_file`]); opening a pipe for reading would block forever.

use crate::error::StoreError;
use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The journal path of an output file: `.<name>.journal` beside it.
pub fn journal_path(output: &Path) -> PathBuf {
    let name = output.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    hidden_beside(output, &name, ".journal")
}

/// The temporary path used while writing `path`: `.<stem>.partial.<ext>` beside
/// it (the extension is kept for writers that choose a format by it).
pub fn partial_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    match path.extension() {
        Some(ext) => hidden_beside(path, &stem, &format!(".partial.{}", ext.to_string_lossy())),
        None => hidden_beside(path, &stem, ".partial"),
    }
}

/// The longest file name (bytes) of the file systems an output goes to.
const MAX_NAME: usize = 255;

/// `.<name><suffix>` beside `path`; where that would be longer than a file
/// name may be (255 bytes), `name` is cut and its CRC-32 added, so that an
/// output whose own name is legal always has its temporary file and journal.
fn hidden_beside(path: &Path, name: &str, suffix: &str) -> PathBuf {
    let whole = format!(".{name}{suffix}");
    if whole.len() <= MAX_NAME {
        return path.with_file_name(whole);
    }
    let tag = format!("-{:08x}", crc32fast::hash(name.as_bytes()));
    let mut keep = MAX_NAME.saturating_sub(1 + tag.len() + suffix.len()).min(name.len());
    while !name.is_char_boundary(keep) {
        keep -= 1;
    }
    path.with_file_name(format!(".{}{tag}{suffix}", &name[..keep]))
}

/// The file that writing `output` writes: `output` in its folder's canonical
/// path (links and `..` resolved) or, when `output` is a symbolic link
/// (dangling or not), the file it names, followed through every link. The file
/// itself need not exist; its folder must.
pub fn canonical_output(output: &Path) -> Result<PathBuf, StoreError> {
    let mut path = output.to_path_buf();
    // As many links as the kernel follows (ELOOP beyond).
    for _ in 0..40 {
        let Some(name) = path.file_name() else {
            return Err(StoreError::format(output, "is not a file name"));
        };
        let parent = folder_of(&path);
        let folder = match parent.canonicalize() {
            Ok(f) if f.is_dir() => f,
            _ if path == output => return Err(StoreError::format(output, no_folder(parent))),
            _ => {
                return Err(StoreError::format(
                    output,
                    format!("is a symbolic link to {}, whose folder does not exist", path.display()),
                ))
            }
        };
        let full = folder.join(name);
        match std::fs::symlink_metadata(&full) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = std::fs::read_link(&full).map_err(|e| StoreError::io(&full, e))?;
                path = folder.join(target);
            }
            // A pipe or device is never replaced (a pipe would block the final
            // write); a folder is refused where the output is opened.
            Ok(m) if !m.file_type().is_file() && !m.file_type().is_dir() => {
                let what = kind_of(m.file_type());
                return Err(StoreError::format(output, format!("is {what}, not a regular file; refusing to write it")));
            }
            _ => return Ok(full),
        }
    }
    Err(StoreError::format(output, "too many levels of symbolic links"))
}

/// What a file type is, in words (for refusals).
fn kind_of(t: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a named pipe (FIFO)";
        }
        if t.is_socket() {
            return "a socket";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
    }
    if t.is_symlink() {
        "a symbolic link"
    } else if t.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// Checks that `path`, a file of the run's own (lock, journal, temporary
/// file; `what` names it), is absent or a regular file, without opening it
/// (a symbolic link is not followed: refused whatever it names). A folder
/// passes: opening it to write fails at once, as an output that cannot be
/// written (whose computed lines the journal keeps).
pub fn check_own_file(path: &Path, what: &str) -> Result<(), StoreError> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_file() || m.file_type().is_dir() => Ok(()),
        Ok(m) => Err(StoreError::format(
            path,
            format!(
                "the run's {what} is {}, not a regular file; refusing to open it (remove it and run again)",
                kind_of(m.file_type())
            ),
        )),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(StoreError::io(path, e)),
    }
}

/// Opens a file of the run's own (see [`check_own_file`]) with `options`,
/// never following a symbolic link and never blocking on a pipe that appeared
/// since the check; a handle that is not a regular file is refused.
pub(crate) fn open_own_file(path: &Path, what: &str, options: &mut OpenOptions) -> Result<File, StoreError> {
    check_own_file(path, what)?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(NOFOLLOW_NONBLOCK);
    }
    let file = options.open(path).map_err(|e| match e.raw_os_error() {
        // A link put there since the check, or a pipe without a reader.
        Some(n) if REFUSED_ERRNO.contains(&n) => StoreError::format(
            path,
            format!("the run's {what} is not a regular file; refusing to open it (remove it and run again)"),
        ),
        _ => StoreError::io(path, e),
    })?;
    match file.metadata() {
        Ok(m) if m.is_file() => Ok(file),
        Ok(m) => Err(StoreError::format(
            path,
            format!(
                "the run's {what} is {}, not a regular file; refusing to use it (remove it and run again)",
                kind_of(m.file_type())
            ),
        )),
        Err(e) => Err(StoreError::io(path, e)),
    }
}

/// O_NOFOLLOW | O_NONBLOCK for open(2), Linux's values (the `libc` crate is
/// not a dependency of the store); elsewhere no flags, and the check before
/// opening is the guard.
#[cfg(all(target_os = "linux", any(target_arch = "x86_64", target_arch = "x86", target_arch = "riscv64")))]
const NOFOLLOW_NONBLOCK: i32 = 0o400000 | 0o4000;
#[cfg(all(target_os = "linux", any(target_arch = "aarch64", target_arch = "arm")))]
const NOFOLLOW_NONBLOCK: i32 = 0o100000 | 0o4000;
#[cfg(not(all(
    target_os = "linux",
    any(
        target_arch = "x86_64",
        target_arch = "x86",
        target_arch = "riscv64",
        target_arch = "aarch64",
        target_arch = "arm"
    )
)))]
const NOFOLLOW_NONBLOCK: i32 = 0;

/// Linux's ELOOP (a link where none may be) and ENXIO (a pipe with no reader).
const REFUSED_ERRNO: [i32; 2] = [40, 6];

/// The lock path of an output file: `.<name>.lock` beside it.
pub fn lock_path(output: &Path) -> PathBuf {
    let name = output.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    hidden_beside(output, &name, ".lock")
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
    /// Takes the lock of `output` (beside its [`canonical_output`]), or fails
    /// at once when another run holds it; then checks that the output's
    /// journal and temporary file are absent or regular files
    /// ([`check_own_file`]), beside the canonical path and beside `output`.
    pub fn acquire(output: &Path) -> Result<OutputLock, StoreError> {
        let canonical = canonical_output(output)?;
        let path = lock_path(&canonical);
        let io = |e| StoreError::io(&path, e);
        loop {
            let mut options = OpenOptions::new();
            options.read(true).write(true).create(true).truncate(false);
            let mut file = open_own_file(&path, "lock file", &mut options)?;
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
            let lock = OutputLock { file, path };
            for out in [canonical.as_path(), output] {
                check_own_file(&journal_path(out), "journal")?;
                check_own_file(&partial_path(out), "temporary file")?;
            }
            return Ok(lock);
        }
    }
}

#[cfg(unix)]
pub(crate) fn same_file(a: &std::fs::Metadata, b: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
pub(crate) fn same_file(_: &std::fs::Metadata, _: &std::fs::Metadata) -> bool {
    true
}

/// Whether paths `a` and `b` name one existing file (the same path, a link
/// to it, or a hard link: the same device and inode).
pub(crate) fn same_path(a: &Path, b: &Path) -> bool {
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) if cfg!(unix) => same_file(&x, &y),
        _ => a.canonicalize().ok().is_some_and(|c| b.canonicalize().ok() == Some(c)),
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still held, so that no one can lock the old file.
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

/// Checks, before any work, that `output` can be written as a new or replaced
/// regular file: not a directory, not one of `inputs` (the scene, the parts
/// of a merge, or another output of the run, made or not), none of its
/// temporary, journal and lock files one of them, not a device or other
/// special file (an output is written beside its target and renamed over it,
/// which such a file cannot take), and in a folder that exists.
pub fn check_output(output: &Path, inputs: &[&Path]) -> Result<(), StoreError> {
    let bad = |m: &str| Err(StoreError::format(output, m.to_string()));
    if output.as_os_str().is_empty() {
        return Err(StoreError::format(Path::new("output"), "empty path"));
    }
    let Some(name) = output.file_name() else { return bad("is not a file name") };
    // Found only as the finished file is renamed into place, after the work.
    if name.len() > MAX_NAME {
        return bad(&format!("its name is {} bytes, more than a file name may have ({MAX_NAME})", name.len()));
    }
    check_folder(output)?;
    match std::fs::metadata(output) {
        Ok(m) if m.is_dir() => return bad("is a directory; give a file name"),
        Ok(m) if !m.is_file() => {
            return bad("exists and is not a regular file (a device, a pipe, …); refusing to replace it")
        }
        _ => {}
    }
    check_creatable(output)?;
    if let Some(out) = resolved(output) {
        for input in inputs {
            if resolved(input).is_some_and(|i| i == out) {
                let what = if input.exists() { "an input" } else { "another of the run's outputs" };
                return bad(&format!("is also {what} ({}); write the output elsewhere", input.display()));
            }
        }
    }
    // The files written beside it while it is made, which the run removes.
    for side in [partial_path(output), journal_path(output), lock_path(output)] {
        let Some(at) = resolved(&side) else { continue };
        if let Some(input) = inputs.iter().find(|i| resolved(i).is_some_and(|i| i == at)) {
            return bad(&format!(
                "its run writes and removes {}, which is an input ({}); name the output otherwise",
                side.display(),
                input.display()
            ));
        }
    }
    Ok(())
}

/// The file `path` names, links followed: its canonical path, or, where it
/// does not exist yet, the path its links lead to, in its folder's
/// canonical path (two outputs of one run that are to be the same new file,
/// one named through a link to the other, are the same path).
fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(c) = path.canonicalize() {
        return Some(c);
    }
    let mut p = path.to_path_buf();
    // A link to a file not made yet, followed (at most as deep as the system follows).
    for _ in 0..40 {
        let Ok(target) = std::fs::read_link(&p) else { break };
        p = match p.parent() {
            Some(folder) if target.is_relative() => folder.join(target),
            _ => target,
        };
    }
    let folder = match p.parent() {
        Some(f) if !f.as_os_str().is_empty() => f,
        _ => Path::new("."),
    };
    Some(folder.canonicalize().ok()?.join(p.file_name()?))
}

/// Checks, before any work, that the existing file `path` can be rewritten
/// in place (as `curves --into` does): it opens for writing, and its folder
/// takes the temporary file that replaces it.
pub fn check_writable(path: &Path) -> Result<(), StoreError> {
    let refused = |why: String| StoreError::format(path, why);
    std::fs::OpenOptions::new().write(true).open(path).map_err(|e| refused(format!("cannot be rewritten ({e})")))?;
    let probe = partial_path(path);
    let mut options = OpenOptions::new();
    options.write(true).create(true).truncate(true);
    open_own_file(&probe, "temporary file", &mut options).map_err(|e| match e {
        StoreError::Io { cause, .. } => refused(format!("its folder takes no new file ({cause})")),
        other => other,
    })?;
    std::fs::remove_file(&probe).map_err(|e| StoreError::io(&probe, e))
}

/// Moves a complete temporary file over `path` durably: the file's data is
/// synced before the rename, and the folder after it (a power loss leaves the
/// old file or the new one, never an empty one). A target that exists and is
/// not a regular file (a device such as /dev/null, a pipe) is never replaced:
/// the bytes are written into it instead; a folder is an error. A symbolic
/// link is kept: the file it names is replaced ([`canonical_output`]).
pub fn commit(tmp: &Path, path: &Path) -> Result<(), StoreError> {
    let resolved = match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => canonical_output(path)?,
        _ => path.to_path_buf(),
    };
    let path = resolved.as_path();
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
    let parent = folder_of(path);
    // Syncing a folder is not possible everywhere; the rename has happened.
    if let Ok(dir) = File::open(parent) {
        let _ = dir.sync_all();
    }
    Ok(())
}

/// Refuses an output `path` whose folder does not exist.
pub(crate) fn check_folder(path: &Path) -> Result<(), StoreError> {
    let parent = folder_of(path);
    if !parent.is_dir() {
        return Err(StoreError::format(path, no_folder(parent)));
    }
    Ok(())
}

/// Refuses an output whose folder takes no new file (`/proc`, a read-only
/// mount), before any work: a probe file of this process is created beside
/// it and removed at once (one left by another process means the folder
/// takes files).
fn check_creatable(path: &Path) -> Result<(), StoreError> {
    let folder = folder_of(path);
    let probe = folder.join(format!(".vibroatlas-probe-{}", std::process::id()));
    match OpenOptions::new().write(true).create_new(true).open(&probe) {
        Ok(_) => std::fs::remove_file(&probe).map_err(|e| StoreError::io(&probe, e)),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) => Err(StoreError::format(path, cannot_create(folder, &e))),
    }
}

/// The folder of an output `path` (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

/// Why no file can be made in `folder`, an output's folder.
fn cannot_create(folder: &Path, e: &std::io::Error) -> String {
    format!("cannot create a file in {}: {e}", folder.display())
}

/// Why `folder`, an output's folder, is none: the nearest part of its path
/// that exists is a file (`/tmp/notes is a file, not a folder`), or it does
/// not exist.
fn no_folder(folder: &Path) -> String {
    match folder.ancestors().find(|p| p.exists()) {
        Some(p) if !p.is_dir() => format!("{} is a file, not a folder", p.display()),
        _ => "its folder does not exist".to_string(),
    }
}

/// Writes `path` through `write`, which fills a temporary file beside it (see
/// [`crate::partial_path`]); the temporary replaces `path` only once complete
/// ([`commit`]), so a failure never leaves a half-written file under its name.
/// The writer's error becomes the source of a [`StoreError::Write`].
pub fn write_atomically<E: Into<Box<dyn std::error::Error + Send + Sync>>>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), StoreError> {
    check_folder(path)?;
    let tmp = partial_path(path);
    check_own_file(&tmp, "temporary file")?;
    // A folder no file can be made in (`/proc`, read-only) is named as the
    // user's, not through the temporary file's name.
    if let Err(e) = std::fs::File::create(&tmp) {
        let folder = folder_of(path);
        let cause = cannot_create(folder, &e);
        return Err(StoreError::Write { path: path.display().to_string(), cause: cause.into() });
    }
    if let Err(e) = write(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        return Err(StoreError::Write { path: path.display().to_string(), cause: e.into() });
    }
    commit(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

/// Creates the folder `dir` (and its missing parents); returns the outermost
/// folder it created, if any (for a caller to remove again when it writes
/// nothing there); the system's error when it cannot.
pub fn create_folder(dir: &Path) -> std::io::Result<Option<PathBuf>> {
    let missing: Option<PathBuf> = dir
        .ancestors()
        .filter(|p| !p.as_os_str().is_empty())
        .take_while(|p| std::fs::symlink_metadata(p).is_err())
        .last()
        .map(Path::to_path_buf);
    std::fs::create_dir_all(dir)?;
    Ok(missing)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::scratch;

    #[test]
    fn a_folder_is_created_and_its_outermost_new_parent_named() {
        let base = scratch("study-folder");
        let dir = base.join("a/b");
        assert_eq!(create_folder(&dir).unwrap(), Some(base.join("a")));
        assert!(dir.is_dir());
        assert_eq!(create_folder(&dir).unwrap(), None);
        std::fs::remove_dir_all(&base).unwrap();
    }

    /// An output whose name is as long as a file name may be is written: its
    /// temporary file and journal take a name cut to fit, one per output.
    #[test]
    fn the_longest_legal_name_is_written() {
        let dir = scratch("long-name");
        let out = dir.join(format!("{}.png", "b".repeat(251)));
        write_atomically(&out, |tmp| std::fs::write(tmp, b"figure")).unwrap();
        assert_eq!(std::fs::read(&out).unwrap(), b"figure");
        let other = dir.join(format!("{}c.png", "b".repeat(250)));
        for p in [partial_path(&out), journal_path(&out), lock_path(&out)] {
            assert!(p.file_name().unwrap().len() <= 255, "{}", p.display());
        }
        assert_ne!(partial_path(&out), partial_path(&other));
        assert_eq!(partial_path(&dir.join("a.png")), dir.join(".a.partial.png"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A folder where no file can be made is named, not the temporary
    /// file's name; the writer is not called.
    #[test]
    #[cfg(target_os = "linux")]
    fn a_folder_that_takes_no_file_is_named() {
        use std::error::Error;
        let out = Path::new("/proc/vibroatlas-figure.png");
        let mut called = false;
        let e = write_atomically(out, |_| -> Result<(), std::io::Error> {
            called = true;
            Ok(())
        })
        .unwrap_err();
        let said = format!("{e}: {}", e.source().unwrap());
        assert!(said.starts_with("/proc/vibroatlas-figure.png: cannot create a file in /proc: "), "{said}");
        assert!(!called);
        // The check before any work says the same, and leaves no probe behind.
        let said = check_output(out, &[]).unwrap_err().to_string();
        assert!(said.starts_with("/proc/vibroatlas-figure.png: cannot create a file in /proc: "), "{said}");
        let dir = scratch("probe");
        check_output(&dir.join("a.h5"), &[]).unwrap();
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A writer's error is the source of the store's (typed, whole), and
    /// nothing is put in place; an HDF5 error is a source on one line.
    #[test]
    fn a_failed_writer_is_the_source() {
        use std::error::Error;
        let dir = scratch("write-cause");
        let out = dir.join("a.csv");
        let e = write_atomically(&out, |_| Err(std::io::Error::other("disk full"))).unwrap_err();
        assert!(matches!(e, StoreError::Write { .. }), "{e:?}");
        let cause = e.source().expect("a source");
        assert_eq!(cause.downcast_ref::<std::io::Error>().map(|c| c.to_string()).as_deref(), Some("disk full"));
        assert_eq!(format!("{e}: {cause}"), format!("{}: disk full", out.display()));
        assert!(!out.exists() && !partial_path(&out).exists());
        let bad = dir.join("not-hdf5.h5");
        std::fs::write(&bad, "text").unwrap();
        let e = StoreError::hdf5(&bad, hdf5::File::open(&bad).unwrap_err());
        let cause = e.source().and_then(|c| c.downcast_ref::<crate::Hdf5Error>()).expect("the library's error");
        assert!(!cause.to_string().contains('\n') && cause.to_string().contains("file signature not found"), "{cause}");
        assert!(cause.library().contains_minor(hdf5::MinorErrorCode::NotHdf5));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_second_lock_is_refused_and_the_first_is_released_on_drop() {
        let dir = scratch("lock");
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
    fn the_lock_and_the_commit_follow_symbolic_links() {
        let dir = scratch("links");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let dir = dir.canonicalize().unwrap();
        std::os::unix::fs::symlink("sub/k.h5", dir.join("a.h5")).unwrap();
        std::os::unix::fs::symlink("a.h5", dir.join("b.h5")).unwrap();
        // A chain of links, dangling: the file it will be.
        assert_eq!(canonical_output(&dir.join("b.h5")).unwrap(), dir.join("sub/k.h5"));
        assert_eq!(canonical_output(&dir.join("sub/../c.h5")).unwrap(), dir.join("c.h5"));
        assert!(canonical_output(&dir.join("nope/c.h5")).is_err());
        std::os::unix::fs::symlink("loop.h5", dir.join("loop.h5")).unwrap();
        assert!(canonical_output(&dir.join("loop.h5")).unwrap_err().to_string().contains("too many levels"));
        // One lock for both names.
        let held = OutputLock::acquire(&dir.join("sub/k.h5")).unwrap();
        assert!(OutputLock::acquire(&dir.join("b.h5")).is_err());
        drop(held);
        // A commit through the link replaces its target and keeps the link.
        let tmp = dir.join("tmp");
        std::fs::write(&tmp, "new").unwrap();
        commit(&tmp, &dir.join("b.h5")).unwrap();
        assert!(std::fs::symlink_metadata(dir.join("b.h5")).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read_to_string(dir.join("sub/k.h5")).unwrap(), "new");
        // A pipe where the lock goes is refused, never opened. Made without a
        // child process: a fork would inherit the HDF5 files that other tests
        // of this process hold open, and their locks with them.
        let fifo = std::ffi::CString::new(dir.join(".p.h5.lock").into_os_string().into_encoded_bytes()).unwrap();
        // SAFETY: a valid NUL-terminated path; mkfifo only creates a file.
        assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
        let err = OutputLock::acquire(&dir.join("p.h5")).unwrap_err().to_string();
        assert!(err.contains("named pipe"), "{err}");
        assert!(check_own_file(&dir.join("a.h5"), "journal").unwrap_err().to_string().contains("symbolic link"));
        assert!(check_own_file(&dir.join("absent"), "journal").is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn outputs_that_are_folders_inputs_or_devices_are_refused() {
        let dir = scratch("out");
        let scene = dir.join("s.toml");
        std::fs::write(&scene, "x").unwrap();
        assert!(check_output(&dir, &[]).unwrap_err().to_string().contains("is a directory"));
        assert!(check_output(&scene, &[&scene]).unwrap_err().to_string().contains("is also an input"));
        assert!(check_output(Path::new("/dev/null"), &[]).is_err());
        // A device is written into, never replaced by a file.
        let tmp = dir.join("t");
        std::fs::write(&tmp, "bytes").unwrap();
        commit(&tmp, Path::new("/dev/null")).unwrap();
        assert!(!std::fs::metadata("/dev/null").unwrap().is_file() && !tmp.exists());
        assert!(check_output(&dir.join("nope/a.h5"), &[]).is_err());
        assert!(check_output(&dir.join("a.h5"), &[&scene]).is_ok());
        // A name longer than a file system takes, refused before the work
        // (the finished file's rename found it only after); 255 bytes taken.
        let long = dir.join(format!("{}.h5", "k".repeat(253)));
        assert!(check_output(&long, &[]).unwrap_err().to_string().contains("its name is 256 bytes"));
        assert!(check_output(&dir.join(format!("{}.h5", "k".repeat(252))), &[]).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
