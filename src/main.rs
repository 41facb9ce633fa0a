//! The `kessler` binary: everything is in the library; see `heap` and
//! `cli::main`.

fn main() -> std::process::ExitCode {
    kessler::memory::hand_back_big_blocks();
    kessler::cli::main()
}
