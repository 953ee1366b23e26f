//! Compiler passes, one file each: a pass takes the previous stage's data and a diagnostics
//! sink and returns the next stage's data. The order they run in is written once, in
//! `crate::driver`.
//!
//! - [`load`]: files and their includes to parsed clauses in program order;
//! - [`lower`]: clauses to the resolved KB (HIR);
//! - [`library`]: the clauses of std/library.pl the KB calls;
//! - [`prelude`]: the states of tests whose `go` call follows other goals, from running them;
//! - [`check`]: whole-KB checks on the HIR;
//! - [`open_init`]: the values tried for the variables of a problem's initial facts.
//!
//! No pass does IO: included files arrive through a [`load::SourceLoader`].

pub mod bt;
pub mod check;
pub mod library;
pub mod load;
pub mod lower;
pub mod open_init;
pub mod pop;
pub mod prelude;
pub mod reassign;
pub mod refine;
pub mod schedule;
pub mod stn;
pub mod task;
