fn main() -> std::process::ExitCode {
    tetwalk::cli::main()
}
