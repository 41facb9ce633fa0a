//! The `kessler` binary: everything is in the library; see `cli::main`.

fn main() -> std::process::ExitCode {
    kessler::cli::main()
}
