//! Outputs written in full under a temporary name and renamed into place, safely in folders that
//! other users can write to (cluster scratch, `/tmp`).
//!
//! A [`Temporary`] is a hidden file beside its target, `.NAME.PID-SEQ.tmp`, renamed onto the
//! target by [`Temporary::persist`] and removed when dropped before, so that a failed command never
//! leaves a half-written output.
//!
//! - **Created exclusively.** The temporary is created with `O_CREAT | O_EXCL` (Rust's
//!   `create_new`; HDF5 files with libhdf5's exclusive-create flag, which opens with `O_EXCL`),
//!   which never follows a symbolic link planted at its name, so another user cannot make us write
//!   into a file of their choosing. A name that is taken (by anything: a file, a link, a folder) is
//!   skipped for the next sequence number.
//! - **Stale temporaries.** The temporaries of this very output left by a process that no longer
//!   runs (a killed `convert`) are removed before a new one is created, but only regular files
//!   owned by the current user: never a link, a folder or another user's file.
//! - **Special files** (`/dev/null`, a named pipe) are refused as targets of a rename; callers write
//!   them in place ([`is_special_file`]).
//!
//! [`WriteLock`] guards files modified in place (`balance --store`); its lock file is opened without
//! following links. [`same_file`] tells whether two paths are one file (the same inode through a
//! link, a hard link or another spelling of the path), for commands that refuse an output that
//! is one of their inputs.

use std::fs::File;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Names tried before giving up on creating a temporary beside a target.
const MAX_ATTEMPTS: u32 = 1000;

/// Whether `path` exists and is not a regular file (a device such as `/dev/null`, a FIFO, a
/// socket; symbolic links are followed). Such outputs are written in place: renaming a file over
/// them would replace the device with a file.
pub fn is_special_file(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Whether `a` and `b` name the same existing file: one inode (Unix; symbolic and hard links and
/// other spellings of a path included), or, elsewhere, the same canonical path. `false` when
/// either does not exist.
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(first), Ok(second)) => same_inode(&first, &second, a, b),
        _ => false,
    }
}

#[cfg(unix)]
fn same_inode(a: &std::fs::Metadata, b: &std::fs::Metadata, _: &Path, _: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_inode(_: &std::fs::Metadata, _: &std::fs::Metadata, a: &Path, b: &Path) -> bool {
    matches!(
        (std::fs::canonicalize(a), std::fs::canonicalize(b)),
        (Ok(x), Ok(y)) if x == y
    )
}

/// A temporary file beside an output, created exclusively; renamed onto the output by
/// [`Temporary::persist`], removed when dropped before.
#[derive(Debug)]
pub struct Temporary {
    path: PathBuf,
    target: PathBuf,
    persisted: bool,
}

impl Temporary {
    /// Create a temporary for `target` and open it for writing.
    ///
    /// # Examples
    ///
    /// ```
    /// use std::io::Write;
    /// # let folder = tempfile::tempdir().unwrap();
    /// let target = folder.path().join("out.tsv");
    /// let (temporary, mut file) = contactmap::io::atomic::Temporary::create(&target).unwrap();
    /// file.write_all(b"chrom\tstart\tend\n").unwrap();
    /// drop(file);
    /// temporary.persist().unwrap();
    /// assert_eq!(std::fs::read(&target).unwrap(), b"chrom\tstart\tend\n");
    /// ```
    pub fn create(target: &Path) -> Result<(Temporary, File)> {
        Temporary::create_with(target, |candidate| {
            File::options()
                .write(true)
                .create_new(true)
                .open(candidate)
                .map_err(|e| Error::io(target, e))
        })
    }

    /// Create a temporary for `target` with `create`, which must create the file at the path it
    /// is given exclusively, failing when the name exists (`O_EXCL`; libhdf5's
    /// `H5F_ACC_EXCL`). A name found taken, before the call or after a failed one (another
    /// process got there first), is skipped for the next.
    pub fn create_with<T>(
        target: &Path,
        mut create: impl FnMut(&Path) -> Result<T>,
    ) -> Result<(Temporary, T)> {
        if is_special_file(target) {
            return Err(Error::Argument(format!(
                "'{}' is not a regular file: this output is written to a file",
                target.display()
            )));
        }
        let name = target
            .file_name()
            .ok_or_else(|| Error::Argument(format!("'{}' is not a file name", target.display())))?
            .to_string_lossy()
            .into_owned();
        check_output_folder(target)?;
        remove_stale_temporaries(target, &name);
        for _ in 0..MAX_ATTEMPTS {
            let candidate = target.with_file_name(next_name(&name));
            if candidate.symlink_metadata().is_ok() {
                continue;
            }
            match create(&candidate) {
                Ok(value) => {
                    return Ok((
                        Temporary {
                            path: candidate,
                            target: target.to_path_buf(),
                            persisted: false,
                        },
                        value,
                    ));
                }
                Err(error) => match candidate.symlink_metadata() {
                    // Another process took the name between our look and our create.
                    Ok(found) if !owned_regular_file(&found) => continue,
                    // Ours, and the create failed after making it: remove it.
                    Ok(_) => {
                        let _ = std::fs::remove_file(&candidate);
                        return Err(error);
                    }
                    Err(_) => return Err(error),
                },
            }
        }
        Err(Error::Invalid(format!(
            "{}: could not create a temporary file beside it ({MAX_ATTEMPTS} names taken)",
            target.display()
        )))
    }

    /// The temporary file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The output it becomes.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Rename the temporary onto its target (every handle on it should be closed first).
    pub fn persist(mut self) -> Result<()> {
        std::fs::rename(&self.path, &self.target).map_err(|e| Error::io(&self.target, e))?;
        self.persisted = true;
        Ok(())
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if !self.persisted {
            // Best effort: the temporary file is ours and incomplete.
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// The folder `target` is to be written in must exist: said in one line naming it, rather than
/// through libhdf5's error stack about a temporary's name.
///
/// ```
/// use contactmap::io::atomic::check_output_folder;
/// assert!(check_output_folder(std::path::Path::new("out.cool")).is_ok()); // the working folder
/// let error = check_output_folder(std::path::Path::new("no/such/folder/out.cool")).unwrap_err();
/// assert!(error.to_string().contains("the folder 'no/such/folder' does not exist"));
/// ```
pub fn check_output_folder(target: &Path) -> Result<()> {
    let folder = match target.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    };
    let (kind, problem) = match std::fs::metadata(folder) {
        Ok(found) if found.is_dir() => return Ok(()),
        Ok(_) => (
            std::io::ErrorKind::NotADirectory,
            "is not a folder".to_string(),
        ),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            (e.kind(), "does not exist (create it first)".to_string())
        }
        Err(e) => (e.kind(), format!("cannot be read ({e})")),
    };
    // an I/O error of the system's kind (Python: FileNotFoundError for a missing folder)
    Err(Error::io(
        target,
        std::io::Error::new(
            kind,
            format!(
                "cannot be written: the folder '{}' {problem}",
                folder.display()
            ),
        ),
    ))
}

/// The next temporary name of the output file `name`: `.NAME.PID-SEQ.tmp`.
fn next_name(name: &str) -> String {
    use std::sync::atomic::{AtomicU64, Ordering};
    static SEQUENCE: AtomicU64 = AtomicU64::new(0);
    format!(
        ".{name}.{}-{}.tmp",
        std::process::id(),
        SEQUENCE.fetch_add(1, Ordering::Relaxed)
    )
}

/// Run `write` on a temporary path beside `path` that `create` makes exclusively
/// ([`Temporary::create_with`]), then rename it to `path`; remove it on error.
pub fn with_temporary<T>(
    path: &Path,
    create: impl FnMut(&Path) -> Result<T>,
    write: impl FnOnce(&Path, T) -> Result<()>,
) -> Result<()> {
    let (temporary, value) = Temporary::create_with(path, create)?;
    write(temporary.path(), value)?;
    temporary.persist()
}

/// Whether `metadata` (not following links) is a regular file of the current user.
#[cfg(unix)]
fn owned_regular_file(metadata: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    metadata.file_type().is_file() && metadata.uid() == rustix::process::getuid().as_raw()
}

#[cfg(not(unix))]
fn owned_regular_file(metadata: &std::fs::Metadata) -> bool {
    metadata.file_type().is_file()
}

/// Remove the temporaries of the output `path` (`.NAME.PID-SEQ.tmp`) whose process no longer
/// runs, such as those of a killed `convert`, so that they cannot pile up.
///
/// A process is alive while `/proc/PID` exists (Linux). The temporaries of live processes, this
/// one's included, are never touched; without a readable `/proc` (other systems) nothing is
/// removed. Only regular files of the current user whose whole name has the temporary pattern of
/// this very output are candidates (never a link, a folder or another user's file). Failures are
/// ignored: this is housekeeping, and the write that follows reports any real problem with the
/// folder.
fn remove_stale_temporaries(path: &Path, name: &str) {
    let Some(alive) = process_liveness() else {
        return;
    };
    let folder = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    let prefix = format!(".{name}.");
    let own = std::process::id();
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(pid) = file_name
            .to_str()
            .and_then(|text| text.strip_prefix(prefix.as_str()))
            .and_then(|rest| rest.strip_suffix(".tmp"))
            .and_then(temporary_pid)
        else {
            continue;
        };
        // DirEntry::metadata does not follow links.
        if pid != own && !alive(pid) && entry.metadata().is_ok_and(|m| owned_regular_file(&m)) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// The PID in the `PID-SEQ` part of a temporary name (both decimal numbers), or `None`.
fn temporary_pid(text: &str) -> Option<u32> {
    let (pid, sequence) = text.split_once('-')?;
    let decimal = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if !decimal(pid) || !decimal(sequence) {
        return None;
    }
    pid.parse().ok()
}

/// A test of whether a process id belongs to a running process, where the system can tell
/// (`/proc/PID` on Linux, when `/proc` is mounted); `None` elsewhere.
fn process_liveness() -> Option<fn(u32) -> bool> {
    if cfg!(target_os = "linux") && Path::new("/proc/self").exists() {
        Some(|pid| Path::new("/proc").join(pid.to_string()).exists())
    } else {
        None
    }
}

/// An advisory lock on a file that is modified in place (`balance --store`), held until dropped.
///
/// The lock is an exclusive `flock` (Unix; elsewhere none is taken) on a hidden file beside the
/// target, `.NAME.lock`, so that two processes never write into the same file at once. It is
/// released, and the lock file removed, when the value is dropped; when the process ends
/// otherwise (killed), the kernel releases the lock and the next run reuses the left-over file.
/// The lock file is opened without following a link planted at its name, and only a regular file
/// is used as one.
#[derive(Debug)]
pub struct WriteLock {
    /// The locked lock file (closing it releases the lock).
    _file: File,
    /// Its path.
    path: PathBuf,
}

impl WriteLock {
    /// Take the lock for writing into `target`, or fail at once, naming `target`, when another
    /// process holds it.
    pub fn acquire(target: &Path) -> Result<WriteLock> {
        let name = target
            .file_name()
            .ok_or_else(|| Error::Argument(format!("'{}' is not a file name", target.display())))?;
        let path = target.with_file_name(format!(".{}.lock", name.to_string_lossy()));
        loop {
            let file = open_lock_file(&path)?;
            match try_lock_exclusive(&file) {
                Ok(true) => {}
                Ok(false) => {
                    return Err(Error::format(
                        target,
                        format!(
                            "another process is writing into this file (it holds the lock {}): \
                             nothing was changed; run again when it has finished",
                            path.display()
                        ),
                    ));
                }
                Err(e) => return Err(Error::io(&path, e)),
            }
            // A holder that finished between our open and our lock removed the file we locked:
            // lock the file now at `path` instead, so that two processes never both hold it.
            if same_open_file(&file, &path) {
                return Ok(WriteLock { _file: file, path });
            }
        }
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for WriteLock {
    fn drop(&mut self) {
        // Removed while still locked (a process waiting on the old file then sees that it is no
        // longer at `path` and retries); the lock goes with the descriptor.
        if cfg!(unix) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Open (or create) the lock file at `path` without following a link there; anything but a
/// regular file at that name is refused.
#[cfg(unix)]
fn open_lock_file(path: &Path) -> Result<File> {
    use std::os::unix::fs::OpenOptionsExt;
    let file = File::options()
        .create(true)
        .truncate(false)
        .write(true)
        .custom_flags(rustix::fs::OFlags::NOFOLLOW.bits() as i32)
        .open(path)
        .map_err(|e| {
            if path
                .symlink_metadata()
                .is_ok_and(|m| m.file_type().is_symlink())
            {
                Error::format(
                    path,
                    "this lock file is a symbolic link: remove it (someone may have planted it)",
                )
            } else {
                Error::io(path, e)
            }
        })?;
    if !file.metadata().is_ok_and(|m| m.is_file()) {
        return Err(Error::format(path, "this lock file is not a regular file"));
    }
    Ok(file)
}

#[cfg(not(unix))]
fn open_lock_file(path: &Path) -> Result<File> {
    File::options()
        .create(true)
        .truncate(false)
        .write(true)
        .open(path)
        .map_err(|e| Error::io(path, e))
}

/// Take an exclusive advisory lock (`flock`) on `file` without waiting: `Ok(false)` when another
/// open file description holds it. (rustix's `flock`, since `std::fs::File::try_lock` needs Rust
/// 1.89, above the crate's `rust-version`.)
#[cfg(unix)]
fn try_lock_exclusive(file: &File) -> std::io::Result<bool> {
    use rustix::fs::{FlockOperation, flock};
    match flock(file, FlockOperation::NonBlockingLockExclusive) {
        Ok(()) => Ok(true),
        Err(e) if e == rustix::io::Errno::WOULDBLOCK => Ok(false),
        Err(e) => Err(e.into()),
    }
}

/// Elsewhere no lock is taken: [`WriteLock`] only guards against other processes on Unix.
#[cfg(not(unix))]
fn try_lock_exclusive(_file: &File) -> std::io::Result<bool> {
    Ok(true)
}

/// True when the open `file` is the file now at `path`.
#[cfg(unix)]
fn same_open_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Without inode numbers the lock file is never removed ([`WriteLock`]'s drop), so the file
/// at `path` is always the one that was opened.
#[cfg(not(unix))]
fn same_open_file(_file: &File, _path: &Path) -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PID no process can have: above the kernel's `pid_max`.
    fn dead_pid() -> u32 {
        std::fs::read_to_string("/proc/sys/kernel/pid_max")
            .ok()
            .and_then(|text| text.trim().parse::<u32>().ok())
            .unwrap_or(1 << 22)
            + 1
    }

    /// An output in a missing folder, or under a file, is refused before anything is created,
    /// naming the output and the folder; `create` is never called.
    #[test]
    fn outputs_need_an_existing_folder() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("plain");
        std::fs::write(&file, b"x").unwrap();
        for (target, problem) in [
            (dir.path().join("nodir/out.cool"), "does not exist"),
            (file.join("out.cool"), "is not a folder"),
        ] {
            let error = Temporary::create_with(&target, |_| -> Result<()> {
                panic!("nothing is created for {}", target.display())
            })
            .unwrap_err()
            .to_string();
            let folder = target.parent().unwrap().display().to_string();
            assert!(error.contains(&target.display().to_string()), "{error}");
            assert!(error.contains(&format!("'{folder}' {problem}")), "{error}");
        }
        // a bare name is written in the working folder, which exists
        assert!(check_output_folder(Path::new("out.cool")).is_ok());
    }

    #[test]
    fn temporary_names_parse() {
        assert_eq!(temporary_pid("123-0"), Some(123));
        assert_eq!(temporary_pid("123-45"), Some(123));
        assert_eq!(temporary_pid("123"), None);
        assert_eq!(temporary_pid("x.123-0"), None);
        assert_eq!(temporary_pid("-0"), None);
        assert_eq!(temporary_pid("12-"), None);
        assert_eq!(temporary_pid("1+2-3"), None);
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out.cool");
        let dead = dir.path().join(format!(".out.cool.{}-0.tmp", dead_pid()));
        let own = dir
            .path()
            .join(format!(".out.cool.{}-7.tmp", std::process::id()));
        // Another output's temporary and a look-alike name are not this output's temporaries.
        let other = dir.path().join(format!(".out.cool.x.{}-0.tmp", dead_pid()));
        let unlike = dir
            .path()
            .join(format!(".out.cool.{}-0.tmp.keep", dead_pid()));
        for path in [&dead, &own, &other, &unlike] {
            std::fs::write(path, b"partial").unwrap();
        }
        // A dead process's name that is a link (to a file that must survive) or a folder.
        let victim = dir.path().join("victim.txt");
        std::fs::write(&victim, b"keep").unwrap();
        let link = dir.path().join(format!(".out.cool.{}-1.tmp", dead_pid()));
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        let folder = dir.path().join(format!(".out.cool.{}-2.tmp", dead_pid()));
        std::fs::create_dir(&folder).unwrap();

        let (temporary, _file) = Temporary::create(&out).unwrap();
        assert!(!dead.exists());
        assert!(own.exists() && other.exists() && unlike.exists());
        assert!(link.symlink_metadata().is_ok() && folder.is_dir());
        assert_eq!(std::fs::read(&victim).unwrap(), b"keep");
        assert_eq!(temporary.path().parent(), Some(dir.path()));
        assert!(temporary.path().is_file());
        drop(temporary);
    }

    /// Links planted at the next names are skipped, never written through.
    #[cfg(unix)]
    #[test]
    fn planted_links_are_never_followed() {
        let dir = tempfile::tempdir().unwrap();
        let victim = dir.path().join("victim.txt");
        std::fs::write(&victim, b"precious").unwrap();
        let out = dir.path().join("out.tsv");
        // The next names this process would try, each a link to the victim (or dangling).
        let probe = next_name("out.tsv");
        let (pid, sequence) = probe
            .strip_prefix(".out.tsv.")
            .and_then(|rest| rest.strip_suffix(".tmp"))
            .and_then(|rest| rest.split_once('-'))
            .unwrap();
        let first: u64 = sequence.parse().unwrap();
        for k in first + 1..first + 20 {
            let name = dir.path().join(format!(".out.tsv.{pid}-{k}.tmp"));
            if k % 2 == 0 {
                std::os::unix::fs::symlink(&victim, &name).unwrap();
            } else {
                std::os::unix::fs::symlink(dir.path().join("nowhere"), &name).unwrap();
            }
        }
        let (temporary, file) = Temporary::create(&out).unwrap();
        std::io::Write::write_all(&mut &file, b"result").unwrap();
        drop(file);
        temporary.persist().unwrap();
        assert_eq!(std::fs::read(&victim).unwrap(), b"precious");
        assert!(!dir.path().join("nowhere").exists());
        assert!(out.symlink_metadata().unwrap().file_type().is_file());
        assert_eq!(std::fs::read(&out).unwrap(), b"result");
    }

    #[test]
    fn a_failed_create_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out.cool");
        let error = Temporary::create_with(&out, |candidate| -> Result<()> {
            std::fs::write(candidate, b"half").unwrap();
            Err(Error::Data("no space".into()))
        })
        .unwrap_err();
        assert_eq!(error.to_string(), "no space");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn same_file_sees_links_and_other_spellings() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.cool");
        std::fs::write(&a, b"x").unwrap();
        let b = dir.path().join("b.cool");
        std::fs::write(&b, b"x").unwrap();
        assert!(same_file(&a, &a));
        assert!(same_file(&a, &dir.path().join(".").join("a.cool")));
        assert!(!same_file(&a, &b));
        assert!(!same_file(&a, &dir.path().join("missing")));
        #[cfg(unix)]
        {
            let soft = dir.path().join("soft.cool");
            std::os::unix::fs::symlink(&a, &soft).unwrap();
            let hard = dir.path().join("hard.cool");
            std::fs::hard_link(&a, &hard).unwrap();
            assert!(same_file(&a, &soft));
            assert!(same_file(&hard, &a));
        }
    }

    #[test]
    fn write_lock_is_exclusive_and_released_on_drop() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("m.cool");
        std::fs::write(&target, b"x").unwrap();
        let first = WriteLock::acquire(&target).unwrap();
        assert_eq!(first.path(), dir.path().join(".m.cool.lock"));
        let refused = WriteLock::acquire(&target).unwrap_err().to_string();
        assert!(refused.starts_with(&format!("{}: another process", target.display())));
        assert!(refused.contains(".m.cool.lock"), "{refused}");
        drop(first);
        assert!(!dir.path().join(".m.cool.lock").exists());
        let second = WriteLock::acquire(&target).unwrap();
        drop(second);
    }

    #[cfg(unix)]
    #[test]
    fn a_planted_lock_link_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("m.cool");
        std::fs::write(&target, b"x").unwrap();
        let victim = dir.path().join("victim");
        std::os::unix::fs::symlink(&victim, dir.path().join(".m.cool.lock")).unwrap();
        let refused = WriteLock::acquire(&target).unwrap_err().to_string();
        assert!(refused.contains("symbolic link"), "{refused}");
        assert!(!victim.exists());
    }
}
