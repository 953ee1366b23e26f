//! The blocks-world vocabulary: the predicates of kbc's standard library (std/blocks.pl) that
//! the simulated arms read from a program's initial state and write when the world is read
//! back. Defined once, here, for the simulator and for the compiler (which re-exports it as
//! `kbc::stdlib::blocks`): the VM never depends on the compiler.

/// A predicate: its name and arity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pred {
    /// The name.
    pub name: &'static str,
    /// The number of arguments.
    pub arity: usize,
}

/// `ontable(Block, X, Y)`: the block rests on the table, on cell (X, Y).
pub const ONTABLE: Pred = Pred { name: "ontable", arity: 3 };
/// `on(Block, Below, X, Y)`: the block rests on `Below`, whose stack stands on cell (X, Y).
pub const ON: Pred = Pred { name: "on", arity: 4 };
/// `clear(Block)`: nothing rests on the block.
pub const CLEAR: Pred = Pred { name: "clear", arity: 1 };
/// `available(Arm)`: the arm works and holds nothing.
pub const AVAILABLE: Pred = Pred { name: "available", arity: 1 };
/// `gripped(Arm, Block)`: the arm holds the block.
pub const GRIPPED: Pred = Pred { name: "gripped", arity: 2 };

/// Every predicate the world read back is made of.
pub const OBSERVED: [Pred; 5] = [ONTABLE, ON, CLEAR, AVAILABLE, GRIPPED];
