//! The front end's first half: text to syntax tree.
//!
//! [`lexer`] turns text into cooked tokens, [`parser`] turns tokens into clauses (recovering
//! from errors), [`ast`] is the tree, [`printer`] writes terms back as Prolog, and [`ops`] is the
//! fixed operator table they share; `text` splits and compacts printed terms as plain text. Nothing here knows what an action or a problem is; that is
//! `passes::lower`'s job.

pub mod ast;
pub mod lexer;
pub mod ops;
pub mod parser;
pub mod printer;
pub(crate) mod text;

pub use parser::parse_source;
