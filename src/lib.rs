//! kbc compiles robot knowledge bases, written in a Prolog subset, into behaviour-tree
//! bytecode for the `kbvm` virtual machine.
//!
//! The pipeline, in the order the passes run (see ARCHITECTURE.md for the codemap):
//!
//! ```text
//! text --syntax--> AST --passes::load--> files in clause order --passes::lower--> HIR (resolved KB)
//!      --passes::check--> diagnostics on names, arities, variables
//! ```
//!
//! Every stage reports problems as [`diag::Diagnostic`] values and keeps going; the CLI
//! (`src/cli`) and the language server (`src/lsp`) are the only places that read files or
//! print.

pub mod builtins;
pub mod cli;
pub mod codegen;
pub mod diag;
pub mod draft;
pub mod engine;
pub mod execute;
pub mod intern;
pub mod ir;
pub mod ladder;
pub mod lsp;
pub mod passes;
pub mod planner;
pub mod recover;
pub mod render;
pub mod session;
pub mod source;
pub mod stdlib;
pub mod syntax;
pub mod validate;
