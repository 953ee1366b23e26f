//! kbc compiles robot knowledge bases, written in a Prolog subset, into behaviour-tree
//! bytecode for the `kbvm` virtual machine.
//!
//! The pipeline is written once, in [`session::Session`] (see ARCHITECTURE.md for the codemap):
//!
//! ```text
//! text --syntax--> AST --load--> files in clause order --lower--> HIR (resolved KB) --check-->
//!      --task--> planning task --search--> plan --pop, stn, schedule, reassign--> schedule
//!      --bt, codegen--> bytecode
//! ```
//!
//! ```
//! use kbc::session::{PlanSettings, Session};
//! let mut session = Session::from_text("goal.pl", "t :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2)]).");
//! let planned = session.plan(0, &PlanSettings::default(), &mut kbc::planner::Silent).expect("a plan");
//! let built = session.build(&planned, None).expect("bytecode");
//! assert_eq!(&built.module.encode()[..4], b"KBBC");
//! ```
//!
//! Every stage reports problems as [`diag::Diagnostic`] values and keeps going. Features: the
//! library alone (`default-features = false`) compiles KBs with the core dependencies; `cli`
//! (the default, which the `kbc` binary needs) adds the command, `lsp` the language server,
//! `llm` the model client of `kbc draft`, `sim` the simulated arms and recovery.

pub mod builtins;
#[cfg(feature = "cli")]
pub mod cli;
pub mod codegen;
pub mod diag;
pub mod draft;
pub mod engine;
pub mod execute;
pub mod intern;
pub mod ir;
pub mod ladder;
#[cfg(feature = "lsp")]
pub mod lsp;
pub mod passes;
pub mod planner;
#[cfg(feature = "sim")]
pub mod recover;
pub mod render;
pub mod session;
pub mod source;
pub mod stdlib;
pub mod syntax;
pub mod validate;
