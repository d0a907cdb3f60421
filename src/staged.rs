//! Files written whole or not at all: a temporary file beside the destination, renamed over it at the
//! end, created with the permissions any new file gets (tempfile's own are owner-only). Every staging
//! file alive is known, so that an interrupted run (Ctrl-C, SIGTERM) removes them ([`remove_all`]).

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The staging files alive now.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// A staging file: removed when dropped unpersisted, and by [`remove_all`]. Where the target is not a
/// regular file (a device such as `/dev/stdout`, a FIFO), there is nothing to rename onto: the output
/// is written straight into it.
pub struct Staging {
    file: std::fs::File,
    /// Where it is renamed to: the target, its symbolic links followed (a link stays a link).
    target: PathBuf,
    /// The staging file's path, which removes it when dropped, until persisted; `None` when writing
    /// straight into the target.
    guard: Option<tempfile::TempPath>,
}

impl Staging {
    /// Rename it onto its target (or, written straight into it, flush).
    pub fn persist(mut self) -> std::io::Result<()> {
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
/// followed, the real target's folder), for renaming onto it with [`Staging::persist`] once complete;
/// an error when `dest` is a folder. A target that exists and is not a regular file (a device, a
/// FIFO) is opened and written straight into: renaming over it would replace it.
pub fn beside(dest: &Path) -> std::io::Result<Staging> {
    if dest.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "is a folder: give a file's path",
        ));
    }
    let real = std::fs::canonicalize(dest).unwrap_or_else(|_| dest.to_path_buf());
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

/// Write `bytes` to `dest` whole or not at all (staged beside it, then renamed).
pub fn write(dest: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut s = beside(dest)?;
    std::io::Write::write_all(&mut s, bytes)?;
    s.persist()
}

/// Remove every staging file alive (an interrupted run's); returns how many were removed.
pub fn remove_all() -> usize {
    let Ok(mut live) = LIVE.lock() else {
        return 0;
    };
    live.drain(..)
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count()
}
