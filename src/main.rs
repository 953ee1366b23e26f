//! The `kbc` command: a thin shell around the library, see `kbc::cli`.

/// mimalloc serves the compiler's many small allocations faster than the system allocator
/// (see Cargo.toml).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    kbc::cli::main()
}
