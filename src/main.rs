fn main() -> std::process::ExitCode {
    kessler::cli::main()
}
