//! The tool's process: how it ends when interrupted (Ctrl-C, SIGTERM, SIGHUP) or when its standard
//! output closes under it, and Mesa's runtime folder; set first thing by `cli::main`.

/// The exit status of a run whose standard output was closed under it: that of a program SIGPIPE
/// ends (128 + 13), as `tetwalk methods | head -1` expects.
pub(crate) const CLOSED_OUTPUT: u8 = 141;

/// Whether an error is a write to a closed pipe.
pub(crate) fn closed_output(e: &(dyn std::error::Error + 'static)) -> bool {
    let mut at = Some(e);
    while let Some(err) = at {
        if let Some(io) = err.downcast_ref::<std::io::Error>()
            && io.kind() == std::io::ErrorKind::BrokenPipe
        {
            return true;
        }
        at = err.source();
    }
    false
}

/// A closed or full standard output (`tetwalk methods | head -1`, `> /dev/full`) ends the command
/// quietly, with a non-zero status and its staging files removed: `print!` panics on such a write, and
/// this hook turns that panic into the exit (status [`CLOSED_OUTPUT`] for a closed pipe, else 2 with
/// one line saying why). Every other panic is reported as before.
pub(crate) fn quiet_on_closed_output() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let p = info.payload();
        let msg = p
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| p.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if let Some(why) = msg.strip_prefix("failed printing to stdout: ") {
            crate::staged::remove_all();
            if why.contains("Broken pipe") {
                std::process::exit(CLOSED_OUTPUT.into());
            }
            eprintln!("tetwalk: standard output: {why}");
            std::process::exit(2);
        }
        default(info);
    }));
}

/// Ctrl-C, SIGTERM or SIGHUP: stop the programs tetwalk runs (TetGen, an answerer) with everything
/// they started, remove the staging files of the outputs being written and the working folders
/// (nothing half-written is left behind), say so, and exit with status 130.
pub(crate) fn clean_on_interrupt() {
    let set = ctrlc::set_handler(|| {
        crate::child::kill_all();
        let n = crate::staged::remove_all();
        let kept = crate::staged::written();
        eprintln!(
            "tetwalk: interrupted; {} removed, {}",
            crate::report::counted(
                n as u64,
                "unfinished output file",
                "unfinished output files"
            ),
            match kept {
                0 => "nothing written".to_string(),
                k => format!(
                    "{} written whole before it kept (found cases filed as they were found)",
                    crate::report::counted(k as u64, "file", "files")
                ),
            }
        );
        std::process::exit(130);
    });
    if let Err(e) = set {
        eprintln!(
            "tetwalk: cannot watch for Ctrl-C ({e}): an interrupted run may leave .tetwalk-* files"
        );
    }
}

/// Mesa's drivers print "XDG_RUNTIME_DIR is invalid or not set" at every adapter query when the
/// variable is missing (as in CI and containers): give them a private directory of their own.
pub(crate) fn quiet_mesa() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return;
    }
    let dir = std::env::temp_dir().join("tetwalk-xdg-runtime");
    let made = std::fs::create_dir_all(&dir).and_then(|_| {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700))
    });
    if made.is_ok() {
        // SAFETY: called first thing in main, before any thread exists.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    }
}
