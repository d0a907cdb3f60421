//! Writes the generated WGSL module, `src/gpu/tetwalk.wgsl`, from the Rust definitions and templates
//! (`tetwalk::gpu::shader::generate`); with `--check` only says whether the committed file is stale,
//! and fails if it is (as `tests/gpu_shader.rs` does).

use std::process::ExitCode;

fn main() -> ExitCode {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/gpu/tetwalk.wgsl");
    let now = tetwalk::gpu::shader::generate();
    let check = match std::env::args().skip(1).collect::<Vec<_>>().as_slice() {
        [] => false,
        [flag] if flag == "--check" => true,
        _ => {
            eprintln!("usage: cargo run --example codegen [-- --check]");
            return ExitCode::from(2);
        }
    };
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    if committed == now {
        println!("{path} is up to date");
        return ExitCode::SUCCESS;
    }
    if check {
        eprintln!("{path} is stale: run `cargo run --example codegen`");
        return ExitCode::FAILURE;
    }
    // Written beside it and renamed over it, so that a failed write leaves the old file whole.
    let tmp = format!("{path}.tmp");
    match std::fs::write(&tmp, &now).and_then(|()| std::fs::rename(&tmp, path)) {
        Ok(()) => {
            println!("wrote {path}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            eprintln!("{path}: {e}");
            ExitCode::FAILURE
        }
    }
}
