//! The bytecode format: its identity now, its sections and instruction table later.
//!
//! docs/bytecode.md is the normative description; this module is its only implementation.

/// The four bytes every kbc bytecode file starts with.
pub const MAGIC: [u8; 4] = *b"KBBC";

/// The exact format version a loader accepts. A loader refuses every other version rather
/// than guessing at compatibility.
pub const FORMAT_VERSION: u16 = 0;
