//! `kbvm` runs behaviour-tree bytecode produced by the `kbc` compiler.
//!
//! This crate is the single definition of the bytecode format: the compiler depends on it to
//! encode programs, and the VM never depends on the compiler. At this stage it holds only the
//! format's identity (magic bytes and version); the loader, verifier and tick engine follow.

#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod bytecode;
