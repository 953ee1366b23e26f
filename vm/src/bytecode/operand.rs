//! Operand types of the instruction table, each with its encoding, decoding, check against
//! the program's tables, and text for the disassembler.

use super::reader::Reader;
#[cfg(feature = "encode")]
use super::reader::{put_i64, put_u32};
use super::{Context, LoadError, LoadErrorKind};

/// What the disassembler needs to print operands by name.
#[cfg(feature = "disasm")]
pub(crate) trait Names {
    fn symbol(&self, index: u32) -> String;
    fn fluent(&self, index: u32) -> String;
    fn import(&self, index: u32) -> String;
}

/// One operand type.
pub(crate) trait Operand: Sized {
    /// The fewest bytes an encoded value takes (bounds list counts before allocating).
    const MIN_SIZE: usize;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, offsets: &[u32]);
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError>;
    /// Checks the value against the tables; a node reference is turned from a code offset
    /// into a node index.
    fn check(&mut self, cx: &Context, at: usize) -> Result<(), LoadError>;
    #[cfg(feature = "disasm")]
    fn show(&self, names: &dyn Names) -> String;
}

fn out_of_range(at: usize, what: &'static str, index: u64, len: usize) -> LoadError {
    LoadError::new(at, LoadErrorKind::IndexOutOfRange { what, index, len })
}

/// `index` must be below `len`, the length of the `what` table (a table read outside the
/// operands: imports, fluents, debug info, refinements).
pub(crate) fn check_index(at: usize, what: &'static str, index: u32, len: usize) -> Result<(), LoadError> {
    if (index as usize) < len { Ok(()) } else { Err(out_of_range(at, what, index as u64, len)) }
}

/// A child node: its index in the program's node list (a code offset in the file).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeRef(pub u32);

impl Operand for NodeRef {
    const MIN_SIZE: usize = 4;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, offsets: &[u32]) {
        put_u32(out, offsets[self.0 as usize]);
    }
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
        Ok(NodeRef(reader.u32()?))
    }
    fn check(&mut self, cx: &Context, at: usize) -> Result<(), LoadError> {
        match cx.node_at(self.0) {
            Some(index) => {
                self.0 = index;
                Ok(())
            }
            None => Err(LoadError::new(at, LoadErrorKind::NotANode { offset: self.0 })),
        }
    }
    #[cfg(feature = "disasm")]
    fn show(&self, _: &dyn Names) -> String {
        format!("@{}", self.0)
    }
}

/// An index into one of the program's tables, checked against that table's length.
macro_rules! index_operand {
    ($(#[$doc:meta])* $name:ident, $what:literal, |$cx:ident| $len:expr, |$self_:ident, $names:ident| $show:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub u32);

        impl Operand for $name {
            const MIN_SIZE: usize = 4;
            #[cfg(feature = "encode")]
            fn encode(&self, out: &mut Vec<u8>, _: &[u32]) {
                put_u32(out, self.0);
            }
            fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
                Ok($name(reader.u32()?))
            }
            fn check(&mut self, $cx: &Context, at: usize) -> Result<(), LoadError> {
                let len: usize = $len;
                if self.0 as usize >= len {
                    return Err(out_of_range(at, $what, self.0 as u64, len));
                }
                Ok(())
            }
            #[cfg(feature = "disasm")]
            fn show(&$self_, $names: &dyn Names) -> String {
                $show
            }
        }
    };
}

index_operand!(
    /// A time point of the plan: the moment a snap action happened.
    EventId, "event", |cx| cx.events, |self, _names| format!("e{}", self.0)
);
index_operand!(
    /// An entry of the import table: an action the host must provide.
    ImportId, "import", |cx| cx.imports.len(), |self, names| names.import(self.0)
);
index_operand!(
    /// An entry of the fluent table: a ground fact the blackboard tracks.
    FluentId, "fluent", |cx| cx.fluents, |self, names| names.fluent(self.0)
);

/// A time in program units (see `Module::time_scale`), not negative.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Time(pub i64);

impl Operand for Time {
    const MIN_SIZE: usize = 8;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, _: &[u32]) {
        put_i64(out, self.0);
    }
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
        Ok(Time(reader.i64()?))
    }
    fn check(&mut self, _: &Context, at: usize) -> Result<(), LoadError> {
        if self.0 < 0 {
            return Err(LoadError::new(at, LoadErrorKind::BadTime(self.0)));
        }
        Ok(())
    }
    #[cfg(feature = "disasm")]
    fn show(&self, _: &dyn Names) -> String {
        self.0.to_string()
    }
}

/// A greatest duration, or none (`inf`); encoded as -1 for none.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MaxTime(pub Option<i64>);

impl Operand for MaxTime {
    const MIN_SIZE: usize = 8;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, _: &[u32]) {
        put_i64(out, self.0.unwrap_or(-1));
    }
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
        let at = reader.position();
        match reader.i64()? {
            -1 => Ok(MaxTime(None)),
            t if t >= 0 => Ok(MaxTime(Some(t))),
            t => Err(LoadError::new(at, LoadErrorKind::BadTime(t))),
        }
    }
    fn check(&mut self, _: &Context, _: usize) -> Result<(), LoadError> {
        Ok(())
    }
    #[cfg(feature = "disasm")]
    fn show(&self, _: &dyn Names) -> String {
        self.0.map_or("inf".to_string(), |t| t.to_string())
    }
}

/// A ground argument of a host action or a fluent: an atom (a symbol) or an integer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Value {
    /// A symbol of the symbol table.
    Atom(u32),
    /// An integer.
    Int(i64),
}

impl Operand for Value {
    const MIN_SIZE: usize = 5;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, _: &[u32]) {
        match *self {
            Value::Atom(s) => {
                out.push(0);
                put_u32(out, s);
            }
            Value::Int(i) => {
                out.push(1);
                put_i64(out, i);
            }
        }
    }
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
        let at = reader.position();
        match reader.u8()? {
            0 => Ok(Value::Atom(reader.u32()?)),
            1 => Ok(Value::Int(reader.i64()?)),
            tag => Err(LoadError::new(at, LoadErrorKind::UnknownValueTag(tag))),
        }
    }
    fn check(&mut self, cx: &Context, at: usize) -> Result<(), LoadError> {
        match *self {
            Value::Atom(s) if s as usize >= cx.symbols => Err(out_of_range(at, "symbol", s as u64, cx.symbols)),
            _ => Ok(()),
        }
    }
    #[cfg(feature = "disasm")]
    fn show(&self, names: &dyn Names) -> String {
        match *self {
            Value::Atom(s) => names.symbol(s),
            Value::Int(i) => i.to_string(),
        }
    }
}

/// Wait until `after` program units have passed since `event`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Delay {
    /// The event waited for.
    pub event: EventId,
    /// The least time after it.
    pub after: Time,
}

impl Operand for Delay {
    const MIN_SIZE: usize = 12;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, offsets: &[u32]) {
        self.event.encode(out, offsets);
        self.after.encode(out, offsets);
    }
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
        Ok(Delay { event: EventId::decode(reader)?, after: Time::decode(reader)? })
    }
    fn check(&mut self, cx: &Context, at: usize) -> Result<(), LoadError> {
        self.event.check(cx, at)?;
        self.after.check(cx, at)
    }
    #[cfg(feature = "disasm")]
    fn show(&self, names: &dyn Names) -> String {
        format!("{}+{}", self.event.show(names), self.after.0)
    }
}

/// `add(F)` or `del(F)` on the blackboard.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Effect {
    /// True for add, false for delete.
    pub add: bool,
    /// The fluent.
    pub fluent: FluentId,
}

impl Operand for Effect {
    const MIN_SIZE: usize = 5;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, offsets: &[u32]) {
        out.push(self.add as u8);
        self.fluent.encode(out, offsets);
    }
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
        let at = reader.position();
        let add = match reader.u8()? {
            0 => false,
            1 => true,
            tag => return Err(LoadError::new(at, LoadErrorKind::UnknownValueTag(tag))),
        };
        Ok(Effect { add, fluent: FluentId::decode(reader)? })
    }
    fn check(&mut self, cx: &Context, at: usize) -> Result<(), LoadError> {
        self.fluent.check(cx, at)
    }
    #[cfg(feature = "disasm")]
    fn show(&self, names: &dyn Names) -> String {
        format!("{}({})", if self.add { "add" } else { "del" }, self.fluent.show(names))
    }
}

/// Conditions on the blackboard: every `require` fluent holds, no `forbid` fluent holds, and
/// in each `any` group at least one fluent holds (a Valid literal with free variables).
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Check {
    /// Fluents that must hold.
    pub require: Vec<FluentId>,
    /// Fluents that must not hold.
    pub forbid: Vec<FluentId>,
    /// Groups of which at least one fluent must hold.
    pub any: Vec<Vec<FluentId>>,
}

impl Operand for Check {
    const MIN_SIZE: usize = 12;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, offsets: &[u32]) {
        self.require.encode(out, offsets);
        self.forbid.encode(out, offsets);
        self.any.encode(out, offsets);
    }
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
        Ok(Check { require: Vec::decode(reader)?, forbid: Vec::decode(reader)?, any: Vec::decode(reader)? })
    }
    fn check(&mut self, cx: &Context, at: usize) -> Result<(), LoadError> {
        self.require.check(cx, at)?;
        self.forbid.check(cx, at)?;
        self.any.check(cx, at)
    }
    #[cfg(feature = "disasm")]
    fn show(&self, names: &dyn Names) -> String {
        let mut parts = Vec::new();
        parts.extend(self.require.iter().map(|f| f.show(names)));
        parts.extend(self.forbid.iter().map(|f| format!("not {}", f.show(names))));
        parts.extend(self.any.iter().map(|g| format!("any{}", g.show(names))));
        format!("[{}]", parts.join(", "))
    }
}

impl<T: Operand> Operand for Vec<T> {
    const MIN_SIZE: usize = 4;
    #[cfg(feature = "encode")]
    fn encode(&self, out: &mut Vec<u8>, offsets: &[u32]) {
        put_u32(out, self.len() as u32);
        for item in self {
            item.encode(out, offsets);
        }
    }
    fn decode(reader: &mut Reader<'_>) -> Result<Self, LoadError> {
        let n = reader.count(T::MIN_SIZE)?;
        let mut items = Vec::with_capacity(n);
        for _ in 0..n {
            items.push(T::decode(reader)?);
        }
        Ok(items)
    }
    fn check(&mut self, cx: &Context, at: usize) -> Result<(), LoadError> {
        self.iter_mut().try_for_each(|item| item.check(cx, at))
    }
    #[cfg(feature = "disasm")]
    fn show(&self, names: &dyn Names) -> String {
        format!("[{}]", self.iter().map(|item| item.show(names)).collect::<Vec<_>>().join(", "))
    }
}
