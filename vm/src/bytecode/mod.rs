//! The bytecode format, defined once: the [`Module`] a compiler builds, its encoding, and its
//! decoding with full verification.
//!
//! docs/bytecode.md is the normative description; this module is its only implementation.
//! The instruction table lives in `instructions.rs`; everything that reads or writes nodes is
//! derived from it. Decoding never trusts the input: every read is bounds-checked, every count
//! is checked against the bytes left before anything is allocated, every index against its
//! table, every child reference against the node starts, and the nodes must form one tree.

#[cfg(feature = "disasm")]
mod disasm;
mod instructions;
mod operand;
mod reader;

use std::fmt;

pub use instructions::Instr;
use operand::Operand;
use operand::check_index;
pub use operand::{Check, Delay, Effect, EventId, FluentId, ImportId, MaxTime, NodeRef, Time, Value};
use reader::Reader;
#[cfg(feature = "encode")]
use reader::{put_u16, put_u32};

/// The four bytes every kbc bytecode file starts with.
pub const MAGIC: [u8; 4] = *b"KBBC";

/// The exact format version a loader accepts. A loader refuses every other version rather
/// than guessing at compatibility.
pub const FORMAT_VERSION: u16 = 2;

/// The deepest tree a loader accepts (the root at depth 1).
pub const MAX_DEPTH: usize = 4096;

const HEADER_SIZE: usize = 16;
const SECTION_ENTRY_SIZE: usize = 12;
const MAX_SECTIONS: usize = 8;
/// The code section starts with the root's offset, the event count and the time scale.
#[cfg(feature = "encode")]
const CODE_HEADER_SIZE: usize = 12;

/// Section kinds, in the order they appear in a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
#[repr(u32)]
pub enum SectionKind {
    /// The symbol table: atom names.
    Symbols = 1,
    /// The action import table: name and arity of every action the host must provide.
    Imports = 2,
    /// The fluent table: every ground fact the blackboard tracks, and which hold initially.
    Fluents = 3,
    /// The node code: the root, the event count, the time scale, then the nodes.
    Code = 4,
    /// Optional: each action node's KB source location and text.
    Debug = 5,
    /// Optional: the arm-level steps a start or act node's action is refined into.
    Refinements = 6,
}

impl SectionKind {
    fn from_u32(kind: u32) -> Option<SectionKind> {
        Some(match kind {
            1 => SectionKind::Symbols,
            2 => SectionKind::Imports,
            3 => SectionKind::Fluents,
            4 => SectionKind::Code,
            5 => SectionKind::Debug,
            6 => SectionKind::Refinements,
            _ => return None,
        })
    }
}

/// An action the host must provide.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Import {
    /// Its name, a symbol.
    pub name: u32,
    /// Its number of arguments.
    pub arity: u16,
}

/// A ground fact of the blackboard.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fluent {
    /// The predicate name, a symbol.
    pub functor: u32,
    /// The arguments.
    pub args: Vec<Value>,
    /// True if it holds in the initial state.
    pub initial: bool,
}

/// Where an action node comes from in the KB.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DebugEntry {
    /// The node.
    pub node: NodeRef,
    /// The file, an index in [`DebugInfo::files`].
    pub file: u32,
    /// The line, from 1.
    pub line: u32,
    /// The column, from 1.
    pub column: u32,
    /// What to call the node in messages (the snap action's text), a symbol.
    pub label: u32,
}

/// The optional debug-info section.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct DebugInfo {
    /// File names, as symbols.
    pub files: Vec<u32>,
    /// Entries, at most one per node.
    pub entries: Vec<DebugEntry>,
}

/// A host call with ground arguments: one arm-level step of a refinement.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Call {
    /// The host action.
    pub import: ImportId,
    /// Its arguments, as many as the import's arity.
    pub args: Vec<Value>,
}

/// The arm-level steps that carry out the action of a start, end or act node (from the KB's
/// `mapping/2`): a host that provides the steps but not the high-level action runs them in
/// order instead; an end node's steps once the tree allows the action to end.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Refinement {
    /// The start, end or act node.
    pub node: NodeRef,
    /// The steps, at least one.
    pub steps: Vec<Call>,
}

/// A whole program: what a compiler builds and [`Module::encode`] writes, and what
/// [`Module::decode`] gives back after verification (`decode(encode(m)) == m`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Module {
    /// Atom names.
    pub symbols: Vec<String>,
    /// Host actions.
    pub imports: Vec<Import>,
    /// Blackboard facts.
    pub fluents: Vec<Fluent>,
    /// How many events (snap-action time points) the nodes record.
    pub events: u32,
    /// Program time units per KB time unit (kbc writes 1000: times are thousandths).
    pub time_scale: u32,
    /// The root node.
    pub root: NodeRef,
    /// The nodes; child references are indices in this list.
    pub nodes: Vec<Instr>,
    /// Source locations, if kept.
    pub debug: Option<DebugInfo>,
    /// Refinements of action nodes into arm-level steps, by ascending node (empty: the
    /// section is left out).
    pub refinements: Vec<Refinement>,
}

/// Why a file was refused, and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoadError {
    /// The byte offset in the file where the problem is.
    pub offset: usize,
    /// What is wrong.
    pub kind: LoadErrorKind,
}

/// What is wrong with a file.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum LoadErrorKind {
    /// The file does not start with [`MAGIC`].
    BadMagic,
    /// The format version is not [`FORMAT_VERSION`].
    UnsupportedVersion(u16),
    /// The file ends (or a section ends) before a value that should be there.
    Truncated {
        /// Bytes needed.
        needed: usize,
        /// Bytes left.
        available: usize,
    },
    /// A count of items that cannot fit in the bytes left.
    CountTooLarge {
        /// The count read.
        count: usize,
        /// Bytes left.
        available: usize,
    },
    /// A reserved field is not zero, or a flag byte is not 0 or 1.
    Reserved,
    /// More sections than the format has.
    TooManySections(usize),
    /// A section kind the format does not define.
    UnknownSection(u32),
    /// A section kind given twice.
    DuplicateSection(SectionKind),
    /// A required section is absent.
    MissingSection(SectionKind),
    /// A section outside the file, overlapping another, out of order, or leaving a gap.
    BadSectionBounds,
    /// Bytes after the last section, or a section with bytes its contents do not use.
    TrailingBytes,
    /// A symbol that is not UTF-8.
    BadUtf8,
    /// An opcode the instruction table does not define.
    UnknownOpcode(u8),
    /// A value or effect tag the format does not define.
    UnknownValueTag(u8),
    /// An index past the end of its table.
    IndexOutOfRange {
        /// Which table.
        what: &'static str,
        /// The index read.
        index: u64,
        /// The table's length.
        len: usize,
    },
    /// A node reference that is not the start of a node.
    NotANode {
        /// The code offset referred to.
        offset: u32,
    },
    /// The nodes do not form one tree under the root.
    NotATree(&'static str),
    /// The tree is deeper than [`MAX_DEPTH`].
    TooDeep,
    /// A negative time, or a least duration above the greatest.
    BadTime(i64),
    /// A host action called with another number of arguments than its import declares.
    ArityMismatch {
        /// The import's arity.
        expected: u16,
        /// The arguments given.
        found: usize,
    },
    /// Events recorded by no node or by several, or an end whose start is not a start node.
    BadEvent(&'static str, u32),
    /// A time scale of zero.
    BadTimeScale,
    /// A refinement entry that breaks a rule of its section.
    BadRefinement(&'static str),
}

impl LoadError {
    pub(crate) fn new(offset: usize, kind: LoadErrorKind) -> LoadError {
        LoadError { offset, kind }
    }
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "at byte {}: ", self.offset)?;
        match &self.kind {
            LoadErrorKind::BadMagic => write!(f, "not a kbc bytecode file (expected the magic bytes `KBBC`)"),
            LoadErrorKind::UnsupportedVersion(v) => {
                write!(f, "format version {v}, but this loader reads version {FORMAT_VERSION} only")
            }
            LoadErrorKind::Truncated { needed, available } => {
                write!(f, "truncated: {needed} bytes needed, {available} left")
            }
            LoadErrorKind::CountTooLarge { count, available } => {
                write!(f, "a count of {count} items cannot fit in the {available} bytes left")
            }
            LoadErrorKind::Reserved => write!(f, "a reserved field or flag has a value the format does not define"),
            LoadErrorKind::TooManySections(n) => write!(f, "{n} sections, at most {MAX_SECTIONS} allowed"),
            LoadErrorKind::UnknownSection(k) => write!(f, "unknown section kind {k}"),
            LoadErrorKind::DuplicateSection(k) => write!(f, "section {k:?} given twice"),
            LoadErrorKind::MissingSection(k) => write!(f, "required section {k:?} is missing"),
            LoadErrorKind::BadSectionBounds => {
                write!(f, "a section lies outside the file, overlaps another, is out of order or leaves a gap")
            }
            LoadErrorKind::TrailingBytes => write!(f, "bytes that belong to nothing"),
            LoadErrorKind::BadUtf8 => write!(f, "a symbol is not valid UTF-8"),
            LoadErrorKind::UnknownOpcode(op) => write!(f, "unknown opcode 0x{op:02x}"),
            LoadErrorKind::UnknownValueTag(tag) => write!(f, "unknown tag {tag}"),
            LoadErrorKind::IndexOutOfRange { what, index, len } => {
                write!(f, "{what} index {index} out of range (the table has {len})")
            }
            LoadErrorKind::NotANode { offset } => write!(f, "code offset {offset} is not the start of a node"),
            LoadErrorKind::NotATree(why) => write!(f, "the nodes do not form a tree: {why}"),
            LoadErrorKind::TooDeep => write!(f, "the tree is deeper than {MAX_DEPTH} levels"),
            LoadErrorKind::BadTime(t) => write!(f, "bad time {t}"),
            LoadErrorKind::ArityMismatch { expected, found } => {
                write!(f, "{found} arguments for a host action of arity {expected}")
            }
            LoadErrorKind::BadEvent(why, e) => write!(f, "event e{e}: {why}"),
            LoadErrorKind::BadTimeScale => write!(f, "the time scale is zero"),
            LoadErrorKind::BadRefinement(why) => write!(f, "bad refinement: {why}"),
        }
    }
}

impl std::error::Error for LoadError {}

/// What operand checks need: the sizes of the tables and where nodes start.
pub(crate) struct Context {
    pub(crate) symbols: usize,
    pub(crate) fluents: usize,
    pub(crate) imports: Vec<Import>,
    pub(crate) events: usize,
    /// Code offsets of the nodes, ascending.
    pub(crate) node_starts: Vec<u32>,
}

impl Context {
    /// The index of the node that starts at code offset `offset`.
    pub(crate) fn node_at(&self, offset: u32) -> Option<u32> {
        self.node_starts.binary_search(&offset).ok().map(|i| i as u32)
    }
}

impl Module {
    /// The bytes of the module. The same module always gives the same bytes.
    #[cfg(feature = "encode")]
    pub fn encode(&self) -> Vec<u8> {
        // Node offsets: an operand's size does not depend on the offsets it refers to.
        let zeros = vec![0u32; self.nodes.len()];
        let mut offsets = Vec::with_capacity(self.nodes.len());
        let mut at = CODE_HEADER_SIZE as u32;
        let mut scratch = Vec::new();
        for node in &self.nodes {
            offsets.push(at);
            scratch.clear();
            node.encode(&mut scratch, &zeros);
            at += scratch.len() as u32;
        }
        let mut sections: Vec<(SectionKind, Vec<u8>)> = Vec::new();
        let mut symbols = Vec::new();
        put_u32(&mut symbols, self.symbols.len() as u32);
        for s in &self.symbols {
            put_u32(&mut symbols, s.len() as u32);
            symbols.extend_from_slice(s.as_bytes());
        }
        sections.push((SectionKind::Symbols, symbols));
        let mut imports = Vec::new();
        put_u32(&mut imports, self.imports.len() as u32);
        for import in &self.imports {
            put_u32(&mut imports, import.name);
            put_u16(&mut imports, import.arity);
        }
        sections.push((SectionKind::Imports, imports));
        let mut fluents = Vec::new();
        put_u32(&mut fluents, self.fluents.len() as u32);
        for fluent in &self.fluents {
            fluents.push(fluent.initial as u8);
            put_u32(&mut fluents, fluent.functor);
            put_u16(&mut fluents, fluent.args.len() as u16);
            for arg in &fluent.args {
                arg.encode(&mut fluents, &offsets);
            }
        }
        sections.push((SectionKind::Fluents, fluents));
        let mut code = Vec::new();
        put_u32(&mut code, offsets.get(self.root.0 as usize).copied().unwrap_or(0));
        put_u32(&mut code, self.events);
        put_u32(&mut code, self.time_scale);
        for node in &self.nodes {
            node.encode(&mut code, &offsets);
        }
        sections.push((SectionKind::Code, code));
        if let Some(debug) = &self.debug {
            let mut bytes = Vec::new();
            put_u32(&mut bytes, debug.files.len() as u32);
            for &f in &debug.files {
                put_u32(&mut bytes, f);
            }
            put_u32(&mut bytes, debug.entries.len() as u32);
            for e in &debug.entries {
                put_u32(&mut bytes, offsets[e.node.0 as usize]);
                for v in [e.file, e.line, e.column, e.label] {
                    put_u32(&mut bytes, v);
                }
            }
            sections.push((SectionKind::Debug, bytes));
        }
        if !self.refinements.is_empty() {
            let mut bytes = Vec::new();
            put_u32(&mut bytes, self.refinements.len() as u32);
            for r in &self.refinements {
                put_u32(&mut bytes, offsets[r.node.0 as usize]);
                put_u32(&mut bytes, r.steps.len() as u32);
                for step in &r.steps {
                    put_u32(&mut bytes, step.import.0);
                    put_u32(&mut bytes, step.args.len() as u32);
                    for arg in &step.args {
                        arg.encode(&mut bytes, &offsets);
                    }
                }
            }
            sections.push((SectionKind::Refinements, bytes));
        }
        let mut out = Vec::new();
        out.extend_from_slice(&MAGIC);
        put_u16(&mut out, FORMAT_VERSION);
        put_u16(&mut out, 0);
        put_u32(&mut out, sections.len() as u32);
        put_u32(&mut out, 0);
        let mut offset = (HEADER_SIZE + SECTION_ENTRY_SIZE * sections.len()) as u32;
        for (kind, bytes) in &sections {
            put_u32(&mut out, *kind as u32);
            put_u32(&mut out, offset);
            put_u32(&mut out, bytes.len() as u32);
            offset += bytes.len() as u32;
        }
        for (_, bytes) in &sections {
            out.extend_from_slice(bytes);
        }
        out
    }

    /// Reads and verifies a file; any violation of docs/bytecode.md is a [`LoadError`] with
    /// the byte offset. Never panics, and allocates no more than the input's size justifies.
    pub fn decode(bytes: &[u8]) -> Result<Module, LoadError> {
        let mut header = Reader::new(bytes, 0);
        if header.take(4).map_err(|_| LoadError::new(0, LoadErrorKind::BadMagic))? != MAGIC {
            return Err(LoadError::new(0, LoadErrorKind::BadMagic));
        }
        let version = header.u16()?;
        if version != FORMAT_VERSION {
            return Err(LoadError::new(4, LoadErrorKind::UnsupportedVersion(version)));
        }
        if header.u16()? != 0 {
            return Err(LoadError::new(6, LoadErrorKind::Reserved));
        }
        let count = header.u32()? as usize;
        if count > MAX_SECTIONS {
            return Err(LoadError::new(8, LoadErrorKind::TooManySections(count)));
        }
        if header.u32()? != 0 {
            return Err(LoadError::new(12, LoadErrorKind::Reserved));
        }
        // The section table: known kinds, each once, in order, back to back, up to the end.
        let mut sections: [Option<(usize, usize)>; 7] = [None; 7];
        let mut expected_offset = HEADER_SIZE + SECTION_ENTRY_SIZE * count;
        let mut previous_kind = 0u32;
        for _ in 0..count {
            let at = header.position();
            let kind_raw = header.u32()?;
            let offset = header.u32()? as usize;
            let length = header.u32()? as usize;
            let kind =
                SectionKind::from_u32(kind_raw).ok_or(LoadError::new(at, LoadErrorKind::UnknownSection(kind_raw)))?;
            if sections[kind as usize].is_some() {
                return Err(LoadError::new(at, LoadErrorKind::DuplicateSection(kind)));
            }
            if kind_raw < previous_kind
                || offset != expected_offset
                || offset.checked_add(length).is_none_or(|end| end > bytes.len())
            {
                return Err(LoadError::new(at, LoadErrorKind::BadSectionBounds));
            }
            previous_kind = kind_raw;
            sections[kind as usize] = Some((offset, length));
            expected_offset = offset + length;
        }
        if expected_offset != bytes.len() {
            return Err(LoadError::new(expected_offset.min(bytes.len()), LoadErrorKind::TrailingBytes));
        }
        let section = |kind: SectionKind| -> Result<Reader<'_>, LoadError> {
            let (offset, length) =
                sections[kind as usize].ok_or(LoadError::new(8, LoadErrorKind::MissingSection(kind)))?;
            Ok(Reader::new(&bytes[offset..offset + length], offset))
        };
        let finished = |r: &Reader<'_>| {
            if r.is_at_end() { Ok(()) } else { Err(LoadError::new(r.position(), LoadErrorKind::TrailingBytes)) }
        };

        let mut r = section(SectionKind::Symbols)?;
        let n = r.count(4)?;
        let mut symbols = Vec::with_capacity(n);
        for _ in 0..n {
            let at = r.position();
            let len = r.count(1)?;
            let text = std::str::from_utf8(r.take(len)?).map_err(|_| LoadError::new(at, LoadErrorKind::BadUtf8))?;
            symbols.push(text.to_string());
        }
        finished(&r)?;

        let mut r = section(SectionKind::Imports)?;
        let n = r.count(6)?;
        let mut imports = Vec::with_capacity(n);
        for _ in 0..n {
            let at = r.position();
            let name = r.u32()?;
            check_index(at, "symbol", name, symbols.len())?;
            imports.push(Import { name, arity: r.u16()? });
        }
        finished(&r)?;

        let mut cx = Context { symbols: symbols.len(), fluents: 0, imports, events: 0, node_starts: Vec::new() };
        let mut r = section(SectionKind::Fluents)?;
        let n = r.count(7)?;
        let mut fluents = Vec::with_capacity(n);
        for _ in 0..n {
            let at = r.position();
            let initial = match r.u8()? {
                0 => false,
                1 => true,
                _ => return Err(LoadError::new(at, LoadErrorKind::Reserved)),
            };
            let functor = r.u32()?;
            check_index(at + 1, "symbol", functor, symbols.len())?;
            let arity = r.u16()? as usize;
            if arity.saturating_mul(Value::MIN_SIZE) > r.remaining() {
                return Err(LoadError::new(
                    r.position(),
                    LoadErrorKind::CountTooLarge { count: arity, available: r.remaining() },
                ));
            }
            let mut args = Vec::with_capacity(arity);
            for _ in 0..arity {
                let at = r.position();
                let mut value = Value::decode(&mut r)?;
                value.check(&cx, at)?;
                args.push(value);
            }
            fluents.push(Fluent { functor, args, initial });
        }
        finished(&r)?;
        cx.fluents = fluents.len();

        // The code: decode every node in file order, then check operands against the tables.
        let mut r = section(SectionKind::Code)?;
        let code_base = r.position();
        let root_offset = r.u32()?;
        let events_at = r.position();
        let events = r.u32()?;
        let scale_at = r.position();
        let time_scale = r.u32()?;
        if time_scale == 0 {
            return Err(LoadError::new(scale_at, LoadErrorKind::BadTimeScale));
        }
        let mut nodes = Vec::new();
        let mut node_file_offsets = Vec::new();
        while !r.is_at_end() {
            cx.node_starts.push((r.position() - code_base) as u32);
            node_file_offsets.push(r.position());
            nodes.push(Instr::decode(&mut r)?);
        }
        if events as usize > nodes.len() {
            // Every event is recorded by its own node.
            return Err(LoadError::new(events_at, LoadErrorKind::BadEvent("more events than nodes", events)));
        }
        cx.events = events as usize;
        for (node, &at) in nodes.iter_mut().zip(&node_file_offsets) {
            node.check(&cx, at)?;
        }
        let root = cx
            .node_at(root_offset)
            .ok_or(LoadError::new(code_base, LoadErrorKind::NotANode { offset: root_offset }))?;
        verify_tree(&nodes, root as usize, &node_file_offsets, code_base)?;
        verify_actions(&nodes, &cx, &node_file_offsets)?;

        let debug = match sections[SectionKind::Debug as usize] {
            None => None,
            Some(_) => {
                let mut r = section(SectionKind::Debug)?;
                let n = r.count(4)?;
                let mut files = Vec::with_capacity(n);
                for _ in 0..n {
                    let at = r.position();
                    let f = r.u32()?;
                    check_index(at, "symbol", f, symbols.len())?;
                    files.push(f);
                }
                let n = r.count(20)?;
                let mut entries = Vec::with_capacity(n);
                for _ in 0..n {
                    let at = r.position();
                    let offset = r.u32()?;
                    let node = cx.node_at(offset).ok_or(LoadError::new(at, LoadErrorKind::NotANode { offset }))?;
                    let (file, line, column, label) = (r.u32()?, r.u32()?, r.u32()?, r.u32()?);
                    check_index(at + 4, "file", file, files.len())?;
                    check_index(at + 16, "symbol", label, symbols.len())?;
                    entries.push(DebugEntry { node: NodeRef(node), file, line, column, label });
                }
                finished(&r)?;
                Some(DebugInfo { files, entries })
            }
        };
        let refinements = match sections[SectionKind::Refinements as usize] {
            None => Vec::new(),
            Some(_) => {
                let mut r = section(SectionKind::Refinements)?;
                let refinements = decode_refinements(&mut r, &cx, &nodes)?;
                finished(&r)?;
                refinements
            }
        };
        Ok(Module {
            symbols,
            imports: cx.imports,
            fluents,
            events,
            time_scale,
            root: NodeRef(root),
            nodes,
            debug,
            refinements,
        })
    }

    /// A readable listing of the module (`kbc disasm`).
    #[cfg(feature = "disasm")]
    pub fn disassemble(&self) -> String {
        disasm::listing(self)
    }

    /// The text of `value`.
    pub fn value_text(&self, value: Value) -> String {
        match value {
            Value::Atom(s) => self.symbols.get(s as usize).cloned().unwrap_or_else(|| format!("#{s}")),
            Value::Int(i) => i.to_string(),
        }
    }

    /// A host call as text: `grip(a1, b2)`, or the bare name without arguments.
    pub fn call_text(&self, import: ImportId, args: &[Value]) -> String {
        let name = match self.imports.get(import.0 as usize) {
            Some(i) => self.value_text(Value::Atom(i.name)),
            None => format!("#{}", import.0),
        };
        if args.is_empty() {
            return name;
        }
        let args: Vec<String> = args.iter().map(|&v| self.value_text(v)).collect();
        format!("{name}({})", args.join(", "))
    }

    /// The text of a fluent: `on(b1, b2, 1, 1)`.
    pub fn fluent_text(&self, fluent: FluentId) -> String {
        let Some(f) = self.fluents.get(fluent.0 as usize) else { return format!("#{}", fluent.0) };
        let name = self.symbols.get(f.functor as usize).map_or("?", String::as_str);
        if f.args.is_empty() {
            return name.to_string();
        }
        let args: Vec<String> = f.args.iter().map(|&a| self.value_text(a)).collect();
        format!("{name}({})", args.join(", "))
    }

    /// The children of a node (none for a leaf).
    pub fn children(node: &Instr) -> &[NodeRef] {
        match node {
            Instr::Sequence { children } | Instr::Parallel { children } => children,
            _ => &[],
        }
    }
}

/// The refinements section: entries on action nodes, in ascending node order (so each
/// node at most once), each with at least one step whose arguments match its import.
fn decode_refinements(r: &mut Reader<'_>, cx: &Context, nodes: &[Instr]) -> Result<Vec<Refinement>, LoadError> {
    let n = r.count(8)?;
    let mut refinements = Vec::with_capacity(n);
    let mut previous: Option<u32> = None;
    for _ in 0..n {
        let at = r.position();
        let offset = r.u32()?;
        let node = cx.node_at(offset).ok_or(LoadError::new(at, LoadErrorKind::NotANode { offset }))?;
        if !matches!(nodes[node as usize], Instr::Start { .. } | Instr::End { .. } | Instr::Act { .. }) {
            return Err(LoadError::new(at, LoadErrorKind::BadRefinement("refines a node that is not an action")));
        }
        if previous.is_some_and(|p| p >= node) {
            return Err(LoadError::new(at, LoadErrorKind::BadRefinement("entries out of node order")));
        }
        previous = Some(node);
        let steps_at = r.position();
        let count = r.count(8)?;
        if count == 0 {
            return Err(LoadError::new(steps_at, LoadErrorKind::BadRefinement("a refinement without steps")));
        }
        let mut steps = Vec::with_capacity(count);
        for _ in 0..count {
            let at = r.position();
            let import = r.u32()?;
            check_index(at, "import", import, cx.imports.len())?;
            let declared = &cx.imports[import as usize];
            let arity = r.count(Value::MIN_SIZE)?;
            if arity != declared.arity as usize {
                return Err(LoadError::new(
                    at,
                    LoadErrorKind::ArityMismatch { expected: declared.arity, found: arity },
                ));
            }
            let mut args = Vec::with_capacity(arity);
            for _ in 0..arity {
                let at = r.position();
                let mut value = Value::decode(r)?;
                value.check(cx, at)?;
                args.push(value);
            }
            steps.push(Call { import: ImportId(import), args });
        }
        refinements.push(Refinement { node: NodeRef(node), steps });
    }
    Ok(refinements)
}

/// Every node but the root has exactly one parent, the root has none, every node is reached
/// from the root, and no path is deeper than [`MAX_DEPTH`].
fn verify_tree(nodes: &[Instr], root: usize, offsets: &[usize], code_base: usize) -> Result<(), LoadError> {
    let mut parents = vec![0u8; nodes.len()];
    for (i, node) in nodes.iter().enumerate() {
        for child in Module::children(node) {
            let c = child.0 as usize;
            if c == root {
                return Err(LoadError::new(offsets[i], LoadErrorKind::NotATree("a node refers to the root")));
            }
            if parents[c] == 1 {
                return Err(LoadError::new(offsets[i], LoadErrorKind::NotATree("a node has two parents")));
            }
            parents[c] = 1;
        }
    }
    // With one parent each and the root parentless, a node the root does not reach sits on a
    // cycle or under one: count what the root reaches, with depths, iteratively.
    let mut reached = 0usize;
    let mut stack = vec![(root, 1usize)];
    while let Some((node, depth)) = stack.pop() {
        if depth > MAX_DEPTH {
            return Err(LoadError::new(offsets[node], LoadErrorKind::TooDeep));
        }
        reached += 1;
        for child in Module::children(&nodes[node]) {
            stack.push((child.0 as usize, depth + 1));
        }
    }
    if reached != nodes.len() {
        return Err(LoadError::new(code_base, LoadErrorKind::NotATree("some nodes are not under the root")));
    }
    Ok(())
}

/// Every event is recorded by exactly one action node; an end ends a start node's action,
/// and each start is ended once; argument counts match the imports; least durations are
/// not above greatest ones.
fn verify_actions(nodes: &[Instr], cx: &Context, offsets: &[usize]) -> Result<(), LoadError> {
    let mut recorder: Vec<Option<usize>> = vec![None; cx.events];
    for (i, node) in nodes.iter().enumerate() {
        let calls = |import: &ImportId, args: &[Value]| {
            let expected = cx.imports[import.0 as usize].arity;
            if args.len() == expected as usize {
                Ok(())
            } else {
                Err(LoadError::new(offsets[i], LoadErrorKind::ArityMismatch { expected, found: args.len() }))
            }
        };
        let event = match node {
            Instr::Start { event, import, args, min, max, .. } => {
                calls(import, args)?;
                if max.0.is_some_and(|m| m < min.0) {
                    return Err(LoadError::new(offsets[i], LoadErrorKind::BadTime(min.0)));
                }
                event
            }
            Instr::Act { event, import, args, .. } => {
                calls(import, args)?;
                event
            }
            Instr::End { event, .. } => event,
            _ => continue,
        };
        if recorder[event.0 as usize].replace(i).is_some() {
            return Err(LoadError::new(offsets[i], LoadErrorKind::BadEvent("recorded by two nodes", event.0)));
        }
    }
    if let Some(e) = recorder.iter().position(Option::is_none) {
        return Err(LoadError::new(
            offsets.first().copied().unwrap_or(0),
            LoadErrorKind::BadEvent("recorded by no node", e as u32),
        ));
    }
    let mut ended = vec![false; cx.events];
    for (i, node) in nodes.iter().enumerate() {
        if let Instr::End { start, .. } = node {
            let starter = recorder[start.0 as usize].map(|n| &nodes[n]);
            if !matches!(starter, Some(Instr::Start { .. })) {
                return Err(LoadError::new(
                    offsets[i],
                    LoadErrorKind::BadEvent("ended, but not recorded by a start node", start.0),
                ));
            }
            if std::mem::replace(&mut ended[start.0 as usize], true) {
                return Err(LoadError::new(offsets[i], LoadErrorKind::BadEvent("ended twice", start.0)));
            }
        }
    }
    for (i, node) in nodes.iter().enumerate() {
        if matches!(node, Instr::Start { event, .. } if !ended[event.0 as usize]) {
            let Instr::Start { event, .. } = node else { continue };
            return Err(LoadError::new(offsets[i], LoadErrorKind::BadEvent("started but never ended", event.0)));
        }
    }
    Ok(())
}
