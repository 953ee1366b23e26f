//! Interned names: atoms, functors, variable names and strings become 32-bit [`Symbol`]s.
//!
//! Every stage compares names constantly (unifying literals, looking up predicates), so names
//! are interned once by the lexer and compared as integers from then on. Symbol numbers depend
//! only on the order in which names are first seen, so they are deterministic for a given
//! input; nothing that reaches output iterates the interner's hash table.
//!
//! Names the compiler itself must recognise (`action`, `add`, `:-`, ...) are interned first, in
//! the fixed order of the [`sym`] module, so they can be matched as constants.

use std::hash::BuildHasher;

use hashbrown::HashTable;
use rustc_hash::FxBuildHasher;

/// An interned name. Compare with `==`; print with [`Interner::resolve`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Symbol(pub u32);

macro_rules! well_known_symbols {
    ($($name:ident = $text:literal,)*) => {
        /// Symbols the compiler recognises by name, interned first by [`Interner::new`].
        pub mod sym {
            use super::Symbol;
            well_known_symbols!(@consts 0u32, $($name,)*);
        }
        const WELL_KNOWN: &[&str] = &[$($text,)*];
    };
    (@consts $n:expr, $first:ident, $($rest:ident,)*) => {
        #[allow(missing_docs)]
        pub const $first: Symbol = Symbol($n);
        well_known_symbols!(@consts $n + 1u32, $($rest,)*);
    };
    (@consts $n:expr,) => {};
}

well_known_symbols! {
    // Punctuation and operators of the fixed operator table.
    NECK = ":-",
    COMMA = ",",
    SEMI = ";",
    ARROW = "->",
    NOT_PROVABLE = "\\+",
    DYNAMIC = "dynamic",
    DISCONTIGUOUS = "discontiguous",
    EQ = "=",
    NOT_UNIFY = "\\=",
    IDENTICAL = "==",
    NOT_IDENTICAL = "\\==",
    IS = "is",
    LT = "<",
    GT = ">",
    LE = "=<",
    GE = ">=",
    ARITH_EQ = "=:=",
    ARITH_NE = "=\\=",
    PLUS = "+",
    MINUS = "-",
    STAR = "*",
    SLASH = "/",
    INT_DIV = "//",
    MOD = "mod",
    NIL = "[]",
    CONS = "[|]",
    CUT = "!",
    // The KB vocabulary of the paper and of kbc.
    ACTION = "action",
    LL_ACTION = "ll_action",
    MAPPING = "mapping",
    RESOURCES = "resources",
    DURATION = "duration",
    INF = "inf",
    INIT_STATE = "init_state",
    GOAL_STATE = "goal_state",
    GO = "go",
    ADD = "add",
    DEL = "del",
    INCLUDE = "include",
    ENSURE_LOADED = "ensure_loaded",
    OP = "op",
    USE_MODULE = "use_module",
    MODULE = "module",
    LIBRARY = "library",
    LISTS = "lists",
    INITIALIZATION = "initialization",
    // Built-in predicates and functions of the resolution engine.
    TRUE = "true",
    FAIL = "fail",
    FALSE = "false",
    MEMBER = "member",
    NOT = "not",
    ABS = "abs",
    MIN = "min",
    MAX = "max",
    ANON = "_",
    // Spellings of problems in KBs written for the authors' two-level framework.
    HL_INIT = "hl_init",
    HL_GOAL = "hl_goal",
    LL_INIT = "ll_init",
    LL_GOAL = "ll_goal",
    // Operators of SWI-Prolog's table the grammar reads besides those above.
    AT_LT = "@<",
    AT_GT = "@>",
    AT_LE = "@=<",
    AT_GE = "@>=",
    UNIV = "=..",
    VARIANT = "=@=",
    NOT_VARIANT = "\\=@=",
    BIT_AND = "/\\",
    BIT_OR = "\\/",
    XOR = "xor",
    REM = "rem",
    DIV = "div",
    SHIFT_LEFT = "<<",
    SHIFT_RIGHT = ">>",
    POWER = "**",
    CARET = "^",
    BACKSLASH = "\\",
    CONSULT = "consult",
    LOAD_FILES = "load_files",
    COLON = ":",
}

/// The table of interned names.
///
/// The text of every name is appended to one arena string, and a symbol is an index into the
/// list of `(offset, length)` pairs that locate it there. The hash table holds only symbols and
/// compares a probed symbol's text with the name looked up, so interning a new name allocates
/// nothing beyond the occasional growth of the arena.
#[derive(Clone)]
pub struct Interner {
    table: HashTable<Symbol>,
    arena: String,
    spans: Vec<(u32, u32)>,
    hasher: FxBuildHasher,
}

impl std::fmt::Debug for Interner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Interner").field("len", &self.spans.len()).finish()
    }
}

impl Default for Interner {
    fn default() -> Self {
        Interner::new()
    }
}

fn text_of<'a>(arena: &'a str, spans: &[(u32, u32)], symbol: Symbol) -> &'a str {
    let (start, len) = spans[symbol.0 as usize];
    &arena[start as usize..(start + len) as usize]
}

impl Interner {
    /// A table holding the well-known symbols of [`sym`] and nothing else.
    pub fn new() -> Interner {
        let mut interner = Interner {
            table: HashTable::with_capacity(WELL_KNOWN.len()),
            arena: String::new(),
            spans: Vec::new(),
            hasher: FxBuildHasher,
        };
        for name in WELL_KNOWN {
            interner.intern(name);
        }
        interner
    }

    /// Makes room for `additional` more names of about `bytes` bytes in all.
    pub fn reserve(&mut self, additional: usize, bytes: usize) {
        let Interner { table, arena, spans, hasher } = self;
        table.reserve(additional, |&s| hasher.hash_one(text_of(arena, spans, s)));
        spans.reserve(additional);
        arena.reserve(bytes);
    }

    /// The symbol for `name`, adding it if it is new.
    pub fn intern(&mut self, name: &str) -> Symbol {
        let Interner { table, arena, spans, hasher } = self;
        let hash = hasher.hash_one(name);
        if let Some(&symbol) = table.find(hash, |&s| text_of(arena, spans, s) == name) {
            return symbol;
        }
        assert!(arena.len() + name.len() <= u32::MAX as usize, "more than 4 GiB of distinct names");
        let symbol = Symbol(spans.len() as u32);
        spans.push((arena.len() as u32, name.len() as u32));
        arena.push_str(name);
        table.insert_unique(hash, symbol, |&s| hasher.hash_one(text_of(arena, spans, s)));
        symbol
    }

    /// The symbol for `name` if it has been interned.
    pub fn get(&self, name: &str) -> Option<Symbol> {
        let hash = self.hasher.hash_one(name);
        self.table.find(hash, |&s| self.resolve(s) == name).copied()
    }

    /// The text of a symbol.
    pub fn resolve(&self, symbol: Symbol) -> &str {
        text_of(&self.arena, &self.spans, symbol)
    }

    /// True if `symbol` is one of the [`sym`] module's, interned by every [`Interner::new`]
    /// whether or not any text names it.
    pub fn is_well_known(symbol: Symbol) -> bool {
        (symbol.0 as usize) < WELL_KNOWN.len()
    }

    /// How many names are interned.
    pub fn len(&self) -> usize {
        self.spans.len()
    }

    /// True when nothing is interned (never, after [`Interner::new`]).
    pub fn is_empty(&self) -> bool {
        self.spans.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn well_known_symbols_resolve_to_their_text() {
        let interner = Interner::new();
        assert_eq!(interner.resolve(sym::NECK), ":-");
        assert_eq!(interner.resolve(sym::ACTION), "action");
        assert_eq!(interner.resolve(sym::ANON), "_");
        assert_eq!(interner.get("del"), Some(sym::DEL));
    }

    #[test]
    fn interning_is_idempotent_and_ordered() {
        let mut interner = Interner::new();
        let first = interner.intern("ontable");
        let second = interner.intern("clear");
        assert_eq!(interner.intern("ontable"), first);
        assert_eq!(second.0, first.0 + 1);
    }
}
