//! Files written whole or not at all: a temporary file beside the destination, renamed over it at the
//! end, created with the permissions any new file gets (tempfile's own are owner-only).

use std::path::Path;

/// A temporary file in the folder of `dest` (the current folder for a bare name), for renaming onto
/// `dest` with `persist` once complete.
pub fn beside(dest: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let dir = match dest.parent() {
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
    builder.tempfile_in(dir)
}
