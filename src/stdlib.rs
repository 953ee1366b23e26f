//! The standard KB library, written in the DSL itself and embedded in the binary.

/// The standard library's multi-arm blocks world, used when the given files declare no actions.
pub const STD_BLOCKS: &str = include_str!("../std/blocks.pl");

/// The arm-level actions of the simulated arms, loaded with [`STD_BLOCKS`].
pub const STD_ARMS: &str = include_str!("../std/arms.pl");

/// The name diagnostics show for [`STD_ARMS`].
pub const STD_ARMS_NAME: &str = "<std>/arms.pl";

/// The library predicates kbc writes in Prolog (`passes::library` loads those a KB calls).
pub const STD_LIBRARY: &str = include_str!("../std/library.pl");

/// The name diagnostics show for [`STD_LIBRARY`].
pub const STD_LIBRARY_NAME: &str = "<std>/library.pl";

/// The name diagnostics show for [`STD_BLOCKS`].
pub const STD_BLOCKS_NAME: &str = "<std>/blocks.pl";

/// std/blocks.pl's vocabulary: the predicates the simulated arms read and write (defined in
/// `kbvm`, which never depends on the compiler).
pub use kbvm::blocks;
