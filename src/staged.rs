//! Files written whole or not at all: a temporary file beside the destination, renamed over it at the
//! end, created with the permissions any new file gets (tempfile's own are owner-only). Every staging
//! file alive is known, so that an interrupted run (Ctrl-C, SIGTERM) removes them ([`remove_all`]).

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The staging files (and working folders) alive now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Files written whole so far (renamed onto their targets): what an interrupted run keeps.
static WRITTEN: AtomicUsize = AtomicUsize::new(0);

/// How many files this run has written whole so far.
pub(crate) fn written() -> usize {
    WRITTEN.load(Ordering::Relaxed)
}

/// The open file descriptor a path names, where it names one rather than a file: `/dev/stdin`,
/// `/dev/stdout`, `/dev/stderr`, `/dev/fd/N`, `/proc/self/fd/N` or `/proc/PID/fd/N` of this
/// process, itself or through symbolic links to it. Such a target is written into (at the
/// descriptor's own offset, after what was printed there), never renamed over.
pub(crate) fn descriptor(p: &Path) -> Option<i32> {
    let mut p = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let me = std::process::id().to_string();
    for _ in 0..MAX_LINKS {
        let s = p.to_string_lossy();
        let n = match s.as_ref() {
            "/dev/stdin" => Some(0),
            "/dev/stdout" => Some(1),
            "/dev/stderr" => Some(2),
            _ => ["/dev/fd/", "/proc/self/fd/", &format!("/proc/{me}/fd/")]
                .iter()
                .find_map(|pre| s.strip_prefix(pre))
                .and_then(|n| n.parse::<i32>().ok()),
        };
        if n.is_some() {
            return n;
        }
        match std::fs::read_link(&p) {
            Ok(target) => {
                let dir = p.parent().map(Path::to_path_buf).unwrap_or_default();
                p = std::path::absolute(dir.join(target)).unwrap_or(p);
            }
            Err(_) => return None,
        }
    }
    None
}

/// Which file an open descriptor is (device and inode), where it is one.
#[cfg(unix)]
pub(crate) fn identity_of_fd(fd: i32) -> Option<(u64, u64, bool)> {
    // SAFETY: fstat only fills the struct it is given; a closed descriptor gives an error.
    let mut st: libc::stat = unsafe { std::mem::zeroed() };
    (unsafe { libc::fstat(fd, &mut st) } == 0).then_some((
        st.st_dev as u64,
        st.st_ino as u64,
        st.st_mode & libc::S_IFMT == libc::S_IFREG,
    ))
}

/// Which file a path leads to (device, inode, whether a regular file): a descriptor's open file
/// ([`descriptor`]), or the file its links lead to; `None` where nothing is there yet.
#[cfg(unix)]
pub(crate) fn identity(p: &Path) -> Option<(u64, u64, bool)> {
    use std::os::unix::fs::MetadataExt;
    if let Some(fd) = descriptor(p) {
        return identity_of_fd(fd);
    }
    std::fs::metadata(resolve(p))
        .ok()
        .map(|m| (m.dev(), m.ino(), m.is_file()))
}

/// A staging file: removed when dropped unpersisted, and by [`remove_all`]. Where the target is not a
/// regular file (a device such as `/dev/stdout`, a FIFO), there is nothing to rename onto: the output
/// is written straight into it.
pub(crate) struct Staging {
    file: std::fs::File,
    /// Where it is renamed to: the target, its symbolic links followed (a link stays a link).
    target: PathBuf,
    /// The staging file's path, which removes it when dropped, until persisted; `None` when writing
    /// straight into the target.
    guard: Option<tempfile::TempPath>,
}

impl Staging {
    /// Rename it onto its target (or, written straight into it, flush).
    pub(crate) fn persist(mut self) -> std::io::Result<()> {
        std::io::Write::flush(&mut self.file)?;
        match self.guard.take() {
            Some(g) => {
                forget(&g);
                g.persist(&self.target).map_err(|e| e.error)?;
                WRITTEN.fetch_add(1, Ordering::Relaxed);
                Ok(())
            }
            None => Ok(()),
        }
    }
}

impl std::io::Write for Staging {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if let Some(g) = &self.guard {
            forget(g);
        }
    }
}

fn forget(path: &Path) {
    if let Ok(mut live) = LIVE.lock() {
        live.retain(|p| p != path);
    }
}

/// A temporary file in the folder of `dest` (the current folder for a bare name; with symbolic links
/// followed, dangling ones too, the real target's folder: [`resolve`]), for renaming onto it with [`Staging::persist`] once complete;
/// an error when `dest` is a folder. A target that exists and is not a regular file (a device, a
/// FIFO) is opened and written straight into: renaming over it would replace it.
pub(crate) fn beside(dest: &Path) -> std::io::Result<Staging> {
    if dest.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "is a folder: give a file's path",
        ));
    }
    #[cfg(unix)]
    if let Some(fd) = descriptor(dest) {
        // What was printed there first, then this, at the descriptor's own offset.
        use std::io::Write;
        let _ = std::io::stdout().flush();
        let _ = std::io::stderr().flush();
        // SAFETY: dup only makes a new descriptor for the same open file; a closed one errs.
        let copy = unsafe { libc::dup(fd) };
        if copy < 0 {
            return Err(std::io::Error::last_os_error());
        }
        // SAFETY: `copy` is a descriptor just made, owned by nothing else.
        let file = unsafe { <std::fs::File as std::os::fd::FromRawFd>::from_raw_fd(copy) };
        return Ok(Staging {
            file,
            target: dest.to_path_buf(),
            guard: None,
        });
    }
    let real = resolve(dest);
    if std::fs::metadata(&real).is_ok_and(|m| !m.is_file()) {
        let file = std::fs::OpenOptions::new().write(true).open(&real)?;
        return Ok(Staging {
            file,
            target: real,
            guard: None,
        });
    }
    let dir = match real.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".tetwalk-");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // The umask applies, as for any file a program creates.
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let (file, guard) = builder.tempfile_in(dir)?.into_parts();
    if let Ok(mut live) = LIVE.lock() {
        live.push(guard.to_path_buf());
    }
    Ok(Staging {
        file,
        target: real,
        guard: Some(guard),
    })
}

/// Most symbolic links followed from one path (as Linux's own limit).
const MAX_LINKS: usize = 40;

/// Where a path leads: the real file, its symbolic links followed (a dangling one too, to the file it
/// names, which writing then makes), as an absolute path; for a path that does not exist, its real
/// folder joined with its name.
pub(crate) fn resolve(p: &Path) -> PathBuf {
    let mut p = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    for _ in 0..MAX_LINKS {
        match std::fs::read_link(&p) {
            Ok(target) => {
                let dir = p.parent().map(Path::to_path_buf).unwrap_or_default();
                p = std::path::absolute(dir.join(target)).unwrap_or(p);
            }
            Err(_) => break,
        }
    }
    if let Ok(real) = std::fs::canonicalize(&p) {
        return real;
    }
    match (p.parent(), p.file_name()) {
        (Some(dir), Some(name)) => std::fs::canonicalize(dir)
            .map(|d| d.join(name))
            .unwrap_or(p.clone()),
        _ => p,
    }
}

/// Whether two paths name the same regular file (by identity: links, other spellings, hard links and
/// descriptors such as `/dev/stdin` alike), or the same place where neither exists yet. Devices and
/// pipes are never the same file as anything: they are written into, not replaced.
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    match (identity(a), identity(b)) {
        (Some((da, ia, fa)), Some((db, ib, fb))) => fa && fb && da == db && ia == ib,
        (None, None) => resolve(a) == resolve(b),
        _ => false,
    }
    #[cfg(not(unix))]
    {
        resolve(a) == resolve(b)
    }
}

/// Write `bytes` to `dest` whole or not at all (staged beside it, then renamed).
pub(crate) fn write(dest: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut s = beside(dest)?;
    std::io::Write::write_all(&mut s, bytes)?;
    s.persist()
}

/// A working folder (TetGen's, while a scene is built) that an interrupted run removes too: made
/// when tracked, removed with everything in it when dropped, or by [`remove_all`].
pub(crate) struct WorkDir(PathBuf);

impl WorkDir {
    /// A fresh folder under the temporary directory, tracked.
    pub(crate) fn new() -> std::io::Result<WorkDir> {
        let path = tempfile::Builder::new()
            .prefix(".tetwalk-")
            .tempdir()?
            .keep();
        if let Ok(mut live) = LIVE.lock() {
            live.push(path.clone());
        }
        Ok(WorkDir(path))
    }

    /// The folder.
    pub(crate) fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for WorkDir {
    fn drop(&mut self) {
        forget(&self.0);
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Remove every staging file and working folder alive (an interrupted run's); returns how many were
/// removed.
pub(crate) fn remove_all() -> usize {
    let Ok(mut live) = LIVE.lock() else {
        return 0;
    };
    live.drain(..)
        .filter(|p| match p.is_dir() {
            true => std::fs::remove_dir_all(p).is_ok(),
            false => std::fs::remove_file(p).is_ok(),
        })
        .count()
}
