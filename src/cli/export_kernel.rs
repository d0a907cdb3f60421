//! `tetwalk export-kernel`: `certified` written in a shader language (`crate::gpu::export`), for
//! a user's own GPU code; the host finishes what it leaves unsettled with `kernels/c/certified.h`.

use super::Status;
use super::args::choice;
use crate::backend::{ShaderLang as Lang, export_kernel as export};
use std::io::Write;
use std::process::ExitCode;

#[derive(clap::Args)]
pub(crate) struct Args {
    /// The method: `certified`, the one that is never wrong (its f32 stage; unsettled cases are
    /// answered -2, for the host to finish with kernels/c/certified.h).
    #[arg(value_parser = ["certified"])]
    method: String,
    /// The language: WGSL as tetwalk runs it, or GLSL (450, Vulkan), HLSL (shader model 5.1) or MSL
    /// (2.1), translated by naga.
    #[arg(long, value_parser = choice::<Lang>())]
    lang: Lang,
    /// Write it here (default: standard output).
    #[arg(long, short)]
    out: Option<std::path::PathBuf>,
}

impl super::Io for Args {
    fn io(&self) -> super::Files {
        super::Files::default().output("--out", self.out.as_deref())
    }
}

pub(crate) fn run(a: Args) -> Status {
    let text = export(a.lang).map_err(|e| e.to_string())?;
    match &a.out {
        Some(path) => crate::staged::write(path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))?,
        None => std::io::stdout()
            .lock()
            .write_all(text.as_bytes())
            .map_err(|e| format!("standard output: {e}"))?,
    }
    Ok(ExitCode::SUCCESS)
}
