//! Files written whole or not at all: a temporary file beside the destination, renamed over it at the
//! end, created with the permissions any new file gets (tempfile's own are owner-only). Every staging
//! file alive is known, so that an interrupted run (Ctrl-C, SIGTERM) removes them ([`remove_all`]).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The staging files (and working folders) alive now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

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
                g.persist(&self.target).map_err(|e| e.error)
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

/// Whether two paths name the same regular file (by identity: links, other spellings and hard links
/// alike), or the same place where neither exists yet. Devices and pipes (`/dev/stdout`) are never
/// the same file as anything: they are written into, not replaced.
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    let (ra, rb) = (resolve(a), resolve(b));
    match (std::fs::metadata(&ra), std::fs::metadata(&rb)) {
        (Ok(ma), Ok(mb)) => {
            ma.is_file() && mb.is_file() && {
                #[cfg(unix)]
                {
                    use std::os::unix::fs::MetadataExt;
                    ma.dev() == mb.dev() && ma.ino() == mb.ino()
                }
                #[cfg(not(unix))]
                {
                    ra == rb
                }
            }
        }
        (Err(_), Err(_)) => ra == rb,
        _ => false,
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
