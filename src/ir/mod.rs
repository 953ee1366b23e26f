//! The data of each compiler stage. Each IR has a text form and a verifier beside it.
//!
//! - [`hir`]: the resolved knowledge base (actions, problems, static program), whose
//!   compound terms hold their arguments as [`args::Args`];
//! - [`unify`]: unification of HIR terms across items, for checks on the HIR.

pub mod args;
pub mod bt;
pub mod hir;
pub mod plan;
pub mod pop;
pub mod schedule;
pub mod stn;
pub mod task;
pub mod unify;
