//! Generates the LR(1) parser from `grammar/kb.lalrpop` into `OUT_DIR`.
//!
//! The grammar lives outside `src/` so that the language definition is visible at the top of
//! the tree; `set_in_dir` tells lalrpop where to look, and `set_out_dir` keeps generated code
//! out of the source tree.

fn main() {
    println!("cargo:rerun-if-changed=grammar/kb.lalrpop");
    let out_dir = std::env::var("OUT_DIR").expect("cargo sets OUT_DIR for build scripts");
    lalrpop::Configuration::new()
        .set_in_dir("grammar")
        .set_out_dir(out_dir)
        .emit_rerun_directives(true)
        .process()
        .expect("grammar/kb.lalrpop failed to generate a parser");
}
