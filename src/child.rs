//! Programs tetwalk runs (TetGen, a user's answerer): each in a process group of its own, held to a
//! time limit, and ended with tetwalk — its whole group is killed when it runs past the limit, when it
//! is done (nothing it started is left running), and when tetwalk is interrupted ([`kill_all`]).

use std::process::{Child, Command, ExitStatus};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The process groups alive now.
static LIVE: Mutex<Vec<u32>> = Mutex::new(Vec::new());

/// Why a program did not run to its end.
#[derive(Debug, thiserror::Error)]
pub(crate) enum ChildError {
    /// It could not be started (not installed, not executable).
    #[error("cannot start it: {0}")]
    Spawn(std::io::Error),
    /// It ran past its time limit and was killed, with everything it started.
    #[error("it ran past its time limit of {0:?} and was stopped, with everything it started")]
    TimedOut(Duration),
    /// Talking to it failed.
    #[error("{0}")]
    Io(std::io::Error),
}

/// Start `cmd` in a process group of its own, known to [`kill_all`].
pub(crate) fn spawn(cmd: &mut Command) -> Result<Child, ChildError> {
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(cmd, 0);
    let child = cmd.spawn().map_err(ChildError::Spawn)?;
    if let Ok(mut live) = LIVE.lock() {
        live.push(child.id());
    }
    Ok(child)
}

/// Kill the process group `group` (the child and everything it started).
fn kill_group(group: u32) {
    #[cfg(unix)]
    // SAFETY: killpg only sends a signal; a group that is gone gives ESRCH, which is ignored.
    unsafe {
        libc::killpg(group as libc::pid_t, libc::SIGKILL);
    }
}

/// Wait for `child` at most `limit`; its group is killed then, or once it has ended (what it left
/// running goes with it).
pub(crate) fn wait(child: &mut Child, limit: Duration) -> Result<ExitStatus, ChildError> {
    let start = Instant::now();
    let mut pause = Duration::from_micros(200);
    let outcome = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Ok(status),
            Ok(None) if start.elapsed() > limit => {
                kill_group(child.id());
                let _ = child.wait();
                break Err(ChildError::TimedOut(limit));
            }
            Ok(None) => {
                std::thread::sleep(pause);
                pause = (pause * 2).min(Duration::from_millis(20));
            }
            Err(e) => break Err(ChildError::Io(e)),
        }
    };
    kill_group(child.id());
    if let Ok(mut live) = LIVE.lock() {
        live.retain(|&g| g != child.id());
    }
    outcome
}

/// Kill `child` and everything it started now, and reap it.
pub(crate) fn kill(child: &mut Child) {
    kill_group(child.id());
    let _ = child.wait();
    if let Ok(mut live) = LIVE.lock() {
        live.retain(|&g| g != child.id());
    }
}

/// Kill every program still running (an interrupted run's), with everything it started.
pub(crate) fn kill_all() {
    if let Ok(mut live) = LIVE.lock() {
        for g in live.drain(..) {
            kill_group(g);
        }
    }
}

/// A signal's name (`SIGSEGV`), for the signals a crashing or stopped program gets.
fn signal_name(signal: i32) -> Option<&'static str> {
    Some(match signal {
        1 => "SIGHUP",
        2 => "SIGINT",
        3 => "SIGQUIT",
        4 => "SIGILL",
        5 => "SIGTRAP",
        6 => "SIGABRT",
        7 => "SIGBUS",
        8 => "SIGFPE",
        9 => "SIGKILL",
        11 => "SIGSEGV",
        13 => "SIGPIPE",
        14 => "SIGALRM",
        15 => "SIGTERM",
        24 => "SIGXCPU",
        25 => "SIGXFSZ",
        31 => "SIGSYS",
        _ => return None,
    })
}

/// How a program ended, in words: its exit status, or the signal that killed it, named — also where
/// a shell (`sh -c`) reported its command's signal as status 128 + n.
pub(crate) fn said(status: ExitStatus) -> String {
    let named =
        |s: i32| signal_name(s).map_or(format!("signal {s}"), |n| format!("signal {s} ({n})"));
    #[cfg(unix)]
    if let Some(s) = std::os::unix::process::ExitStatusExt::signal(&status) {
        return format!("it was killed by {}", named(s));
    }
    match status.code() {
        Some(c @ 129..=159) if signal_name(c - 128).is_some() => format!(
            "it exited with status {c}: a shell's way of saying its command was killed by {}",
            named(c - 128)
        ),
        Some(c) => format!("it exited with status {c}"),
        None => format!("it ended ({status})"),
    }
}

#[cfg(test)]
mod tests {
    use std::process::Command;

    /// A crash is named whether the program or the shell around it reports it.
    #[test]
    fn an_ending_is_said_with_its_signals_name() {
        let run =
            |script: &str| super::said(Command::new("sh").args(["-c", script]).status().unwrap());
        assert_eq!(run("exit 3"), "it exited with status 3");
        assert_eq!(run("kill -SEGV $$"), "it was killed by signal 11 (SIGSEGV)");
        assert_eq!(
            run("sh -c 'kill -SEGV $$'; exit $?"),
            "it exited with status 139: a shell's way of saying its command was killed by signal 11 (SIGSEGV)"
        );
    }
}
