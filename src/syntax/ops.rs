//! The fixed operator table, for printing terms back in the notation they are read in.
//!
//! The grammar (grammar/kb.lalrpop) encodes the same table as its precedence levels; this
//! module is what printers use to decide between infix notation and parentheses. A test in
//! `syntax::printer` checks the two agree by printing and re-parsing terms.

use crate::intern::{Interner, Symbol, sym};

/// Operator types, as in ISO Prolog.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpType {
    /// Infix, both arguments of lower priority.
    Xfx,
    /// Infix, right-associative.
    Xfy,
    /// Infix, left-associative.
    Yfx,
    /// Prefix, argument of lower priority.
    Fx,
    /// Prefix, argument of equal or lower priority.
    Fy,
}

/// An operator's priority and type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OpDef {
    /// 1 to 1200; lower binds tighter.
    pub priority: u16,
    /// The type.
    pub kind: OpType,
}

impl OpDef {
    /// The highest priority allowed for the left and right arguments.
    pub fn argument_limits(self) -> (u16, u16) {
        let p = self.priority;
        match self.kind {
            OpType::Xfx => (p - 1, p - 1),
            OpType::Xfy => (p - 1, p),
            OpType::Yfx => (p, p - 1),
            OpType::Fx => (0, p - 1),
            OpType::Fy => (0, p),
        }
    }
}

/// The infix definition of `name`, if it is an infix operator.
pub fn infix(name: Symbol) -> Option<OpDef> {
    let (priority, kind) = match name {
        sym::NECK => (1200, OpType::Xfx),
        sym::SEMI => (1100, OpType::Xfy),
        sym::ARROW => (1050, OpType::Xfy),
        sym::COMMA => (1000, OpType::Xfy),
        sym::EQ
        | sym::NOT_UNIFY
        | sym::IDENTICAL
        | sym::NOT_IDENTICAL
        | sym::IS
        | sym::LT
        | sym::GT
        | sym::LE
        | sym::GE
        | sym::ARITH_EQ
        | sym::ARITH_NE
        | sym::AT_LT
        | sym::AT_GT
        | sym::AT_LE
        | sym::AT_GE
        | sym::UNIV
        | sym::VARIANT
        | sym::NOT_VARIANT => (700, OpType::Xfx),
        sym::PLUS | sym::MINUS | sym::BIT_AND | sym::BIT_OR => (500, OpType::Yfx),
        sym::STAR
        | sym::SLASH
        | sym::INT_DIV
        | sym::MOD
        | sym::REM
        | sym::DIV
        | sym::XOR
        | sym::SHIFT_LEFT
        | sym::SHIFT_RIGHT => (400, OpType::Yfx),
        sym::POWER => (200, OpType::Xfx),
        sym::CARET | sym::COLON => (200, OpType::Xfy),
        _ => return None,
    };
    Some(OpDef { priority, kind })
}

/// The prefix definition of `name`, if it is a prefix operator.
pub fn prefix(name: Symbol) -> Option<OpDef> {
    let (priority, kind) = match name {
        sym::NECK => (1200, OpType::Fx),
        sym::DYNAMIC | sym::DISCONTIGUOUS => (1150, OpType::Fx),
        sym::NOT_PROVABLE => (900, OpType::Fy),
        sym::MINUS | sym::PLUS | sym::BACKSLASH => (200, OpType::Fy),
        _ => return None,
    };
    Some(OpDef { priority, kind })
}

/// True if `name` is any operator of the table.
pub fn is_operator(name: Symbol) -> bool {
    infix(name).is_some() || prefix(name).is_some()
}

/// Writes an atom, quoted when it would not read back as the same atom.
pub fn write_atom(out: &mut String, interner: &Interner, name: Symbol) {
    write_atom_text(out, interner.resolve(name));
}

/// Writes the atom named `text`, quoted when it would not read back as the same atom (`'_A'`,
/// `'a b'`).
pub fn write_atom_text(out: &mut String, text: &str) {
    if atom_needs_quotes(text) {
        out.push('\'');
        for c in text.chars() {
            match c {
                '\'' => out.push_str("\\'"),
                '\\' => out.push_str("\\\\"),
                '\n' => out.push_str("\\n"),
                '\t' => out.push_str("\\t"),
                c => out.push(c),
            }
        }
        out.push('\'');
    } else {
        out.push_str(text);
    }
}

/// True if `text` is an atom written without quotes: a lower-case letter, then letters,
/// digits and `_` (`b1`, `grip_start`).
pub fn quote_free_atom(text: &str) -> bool {
    text.as_bytes().first().is_some_and(u8::is_ascii_lowercase)
        && text.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

fn atom_needs_quotes(text: &str) -> bool {
    let bytes = text.as_bytes();
    let Some(&first) = bytes.first() else { return true };
    if first.is_ascii_lowercase() {
        return !bytes.iter().all(|b| b.is_ascii_alphanumeric() || *b == b'_');
    }
    if text == "[]" || text == "!" || text == ";" || text == "," || text == "|" {
        return text == "," || text == "|";
    }
    let symbolic = |b: &u8| b"+-*/\\^<>=~:.?@#&$".contains(b);
    // `/*` inside a symbol atom would start a comment.
    !(bytes.iter().all(symbolic) && text != "." && !text.contains("/*"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoting_follows_prolog_rules() {
        let mut interner = Interner::new();
        let mut check = |text: &str, expected: &str| {
            let symbol = interner.intern(text);
            let mut out = String::new();
            write_atom(&mut out, &interner, symbol);
            assert_eq!(out, expected);
        };
        check("foo_1", "foo_1");
        check("Foo", "'Foo'");
        check("a b", "'a b'");
        check("=..", "=..");
        check("it's", "'it\\'s'");
        check("[]", "[]");
        check(",", "','");
        check("", "''");
    }
}
