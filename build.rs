//! Generates the LR(1) parser from `grammar/kb.lalrpop` into `OUT_DIR`, and records the git
//! commit the binary is built from (`kbc --version`).
//!
//! The grammar lives outside `src/` so that the language definition is visible at the top of
//! the tree; `set_in_dir` tells lalrpop where to look, and `set_out_dir` keeps generated code
//! out of the source tree.

fn main() {
    println!("cargo:rerun-if-changed=grammar/kb.lalrpop");
    commit();
    let out_dir = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR for build scripts");
    lalrpop::Configuration::new()
        .set_in_dir("grammar")
        .set_out_dir(out_dir)
        .emit_rerun_directives(true)
        .process()
        .expect("grammar/kb.lalrpop failed to generate a parser");
}

/// Sets `KBC_COMMIT` to the short hash of the commit being built, or `unknown` outside a git
/// checkout (a crate from a registry, say). Changes not yet committed are not marked: the
/// build script does not rerun on every edit.
fn commit() {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let commit =
        git(&["rev-parse", "--short=12", "HEAD"]).filter(|h| !h.is_empty()).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=KBC_COMMIT={commit}");
    // A new commit, or a checkout of another one, changes HEAD or the ref it names.
    if let Some(git_dir) = git(&["rev-parse", "--git-dir"]) {
        println!("cargo:rerun-if-changed={git_dir}/HEAD");
        if let Some(reference) = git(&["symbolic-ref", "-q", "HEAD"]) {
            println!("cargo:rerun-if-changed={git_dir}/{reference}");
        }
    }
}
