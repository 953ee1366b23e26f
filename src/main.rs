//! The `kbc` command: a thin shell around the library, see `kbc::cli`.

fn main() -> std::process::ExitCode {
    kbc::cli::main()
}
