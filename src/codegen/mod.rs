//! Back end: a behaviour tree to a bytecode module, through kbvm's encoder (the format is
//! defined once, in `vm/src/bytecode`).
//!
//! Tables are filled in a fixed order (symbols and fluents as first met: the initial state,
//! then each step's conditions and effects in plan order; imports as first started), so the
//! same plan always gives the same bytes. Every fact the plan can make true is a fluent; a
//! condition with free variables (an Invalid literal such as `on(_, B, _, _)`) becomes the
//! fluents it unifies with.

use std::collections::HashMap;

use kbvm::bytecode::{
    Call, Check, DebugEntry, DebugInfo, Delay, Effect, EventId, Fluent, FluentId, Import, ImportId, Instr, MaxTime,
    Module, NodeRef, Refinement, Time, Value,
};

use crate::diag::{Diagnostic, codes};
use crate::intern::Interner;
use crate::ir::bt::{Bt, Node};
use crate::ir::hir::{self, EffectKind, Kb, Snap, Term, VarTable};
use crate::ir::plan::Plan;
use crate::ir::pop::{ConditionKind, Pop};
use crate::ir::stn::{Stn, UNITS};
use crate::ir::unify::{match_ground, unifiable};
use crate::passes::pop::instantiate;
use crate::source::SourceDb;

struct Tables<'a> {
    interner: &'a Interner,
    symbols: Vec<String>,
    symbol_index: HashMap<String, u32>,
    fluents: Vec<Fluent>,
    fluent_terms: Vec<Term>,
    fluent_index: HashMap<String, u32>,
    imports: Vec<Import>,
    import_index: HashMap<(u32, u16), u32>,
}

impl Tables<'_> {
    fn symbol(&mut self, text: &str) -> u32 {
        if let Some(&i) = self.symbol_index.get(text) {
            return i;
        }
        let i = self.symbols.len() as u32;
        self.symbols.push(text.to_string());
        self.symbol_index.insert(text.to_string(), i);
        i
    }

    fn text(&self, term: &Term) -> String {
        hir::term_to_string(self.interner, term, &VarTable::default())
    }

    /// An argument: atoms and integers as themselves, anything else as the atom of its text.
    fn value(&mut self, term: &Term) -> Value {
        match term {
            Term::Int(i) => Value::Int(*i),
            Term::Atom(a) => {
                let text = self.interner.resolve(*a).to_string();
                Value::Atom(self.symbol(&text))
            }
            other => {
                let text = self.text(other);
                Value::Atom(self.symbol(&text))
            }
        }
    }

    fn fluent(&mut self, term: &Term, initial: bool) -> FluentId {
        let key = self.text(term);
        if let Some(&i) = self.fluent_index.get(&key) {
            self.fluents[i as usize].initial |= initial;
            return FluentId(i);
        }
        let (name, args) = match term {
            Term::Compound(f, args) => (*f, &args[..]),
            Term::Atom(a) => (*a, &[][..]),
            _ => (crate::intern::sym::ANON, &[][..]),
        };
        let functor = self.symbol(self.interner.resolve(name));
        let args = args.iter().map(|a| self.value(a)).collect();
        let i = self.fluents.len() as u32;
        self.fluents.push(Fluent { functor, args, initial });
        self.fluent_terms.push(term.clone());
        self.fluent_index.insert(key, i);
        FluentId(i)
    }

    /// The fluents a literal with free variables unifies with.
    fn matching(&self, pattern: &Term) -> Vec<FluentId> {
        (0..self.fluents.len())
            .filter(|&i| unifiable(pattern, &self.fluent_terms[i]))
            .map(|i| FluentId(i as u32))
            .collect()
    }

    fn import(&mut self, name: &str, arity: u16) -> ImportId {
        let name = self.symbol(name);
        let next = self.imports.len() as u32;
        let i = *self.import_index.entry((name, arity)).or_insert(next);
        if i == next {
            self.imports.push(Import { name, arity });
        }
        ImportId(i)
    }
}

/// The arm-level steps of each step of the partial order (a snap action): the steps of the first `mapping/2` (in clause order) whose head matches its ground
/// name, with the head's bindings substituted; `None` without a mapping.
///
/// A mapping step left with a variable the head does not bind is E0504.
pub fn refinements(kb: &Kb, interner: &Interner, pop: &Pop) -> Result<Vec<Option<Vec<Term>>>, Box<Diagnostic>> {
    let mut out = Vec::with_capacity(pop.steps.len());
    for step in &pop.steps {
        let found = kb.mappings.iter().find_map(|m| Some((m, match_ground(&m.high.term, &step.name)?)));
        let Some((mapping, bindings)) = found else {
            out.push(None);
            continue;
        };
        let mut values = vec![None; mapping.vars.len()];
        for (var, value) in bindings {
            if let Some(slot) = values.get_mut(var.0 as usize) {
                *slot = Some(value);
            }
        }
        let mut steps = Vec::with_capacity(mapping.steps.len());
        for literal in &mapping.steps {
            let term = instantiate(&literal.term, &values);
            if !term.is_ground() {
                let mut unbound = None;
                literal.term.for_each_var(&mut |v| {
                    if unbound.is_none() && values.get(v.0 as usize).is_none_or(Option::is_none) {
                        unbound = Some(v);
                    }
                });
                let name = unbound.map_or("_", |v| interner.resolve(mapping.vars.get(v).name)).to_string();
                let step_text = hir::term_to_string(interner, &step.name, &VarTable::default());
                return Err(Box::new(
                    Diagnostic::error(
                        codes::UNBOUND_MAPPING,
                        format!("the mapping for `{step_text}` leaves `{name}` unbound"),
                    )
                    .primary(literal.span, format!("`{name}` has no value when refining `{step_text}`"))
                    .secondary(mapping.high.span, "only variables of the high-level action get values")
                    .with_help(format!("use a variable of the high-level action in place of `{name}`")),
                ));
            }
            steps.push(term);
        }
        out.push(Some(steps));
    }
    Ok(out)
}

/// With a host profile (the primitives a host provides): every start or instantaneous action
/// must either refine into primitives or be one itself. E0503 names the first that does not.
pub fn check_host_profile(
    kb: &Kb,
    interner: &Interner,
    pop: &Pop,
    refinements: &[Option<Vec<Term>>],
    host: &str,
    primitives: &[(&str, usize)],
) -> Result<(), Box<Diagnostic>> {
    let provided = |term: &Term| match term {
        Term::Compound(f, args) => primitives.contains(&(interner.resolve(*f), args.len())),
        Term::Atom(a) => primitives.contains(&(interner.resolve(*a), 0)),
        _ => false,
    };
    let list = primitives.iter().map(|(n, a)| format!("{n}/{a}")).collect::<Vec<_>>().join(", ");
    for (s, step) in pop.steps.iter().enumerate() {
        if step.snap == Snap::End && refinements[s].is_none() {
            continue; // the start's refinement (or the action itself) covers it
        }
        let action = &kb.actions[step.action];
        let text = hir::term_to_string(interner, &step.name, &VarTable::default());
        let problem = match &refinements[s] {
            None if provided(&step.name) => continue,
            None => format!("`{text}` has no mapping, and the {host} host does not provide it"),
            Some(steps) => match steps.iter().find(|t| !provided(t)) {
                None => continue,
                Some(t) => format!(
                    "`{text}` maps to `{}`, which the {host} host does not provide",
                    hir::term_to_string(interner, t, &VarTable::default())
                ),
            },
        };
        let base = interner.resolve(action.base);
        return Err(Box::new(
            Diagnostic::error(codes::NOT_PROVIDED, problem)
                .primary(action.slots[0], "the plan uses this action")
                .with_note(format!("the {host} host provides {list}"))
                .with_help(format!(
                    "add `mapping({}, [...])` with steps among those primitives",
                    hir::term_to_string(interner, &action.name.term, &action.vars)
                ))
                .with_note(format!("`{base}` is refined when its start matches a mapping's head")),
        ));
    }
    Ok(())
}

/// The bytecode module of a behaviour tree; `plan` is the total-order plan the partial
/// order was made from (for the effects' bindings); `refinements` come from [`refinements`].
#[allow(clippy::too_many_arguments)]
pub fn generate(
    kb: &Kb,
    interner: &Interner,
    db: &SourceDb,
    plan: &Plan,
    pop: &Pop,
    stn: &Stn,
    bt: &Bt,
    refinements: &[Option<Vec<Term>>],
) -> Module {
    let mut t = Tables {
        interner,
        symbols: Vec::new(),
        symbol_index: HashMap::new(),
        fluents: Vec::new(),
        fluent_terms: Vec::new(),
        fluent_index: HashMap::new(),
        imports: Vec::new(),
        import_index: HashMap::new(),
    };
    for literal in &kb.problems[pop.problem].init {
        t.fluent(&literal.term, true);
    }
    // Each step's effects, ground, in order; then every ground condition.
    let effects: Vec<Vec<(bool, FluentId)>> = plan
        .steps
        .iter()
        .map(|step| {
            kb.actions[step.action]
                .effects
                .iter()
                .map(|e| (e.kind == EffectKind::Add, t.fluent(&instantiate(&e.literal.term, &step.bindings), false)))
                .collect()
        })
        .collect();
    for step in &pop.steps {
        for c in &step.conditions {
            if c.literal.is_ground() {
                t.fluent(&c.literal, false);
            }
        }
    }
    let checks: Vec<Check> = pop
        .steps
        .iter()
        .map(|step| {
            let mut check = Check::default();
            for c in &step.conditions {
                match (c.kind, c.literal.is_ground()) {
                    (ConditionKind::Valid, true) => check.require.push(t.fluent(&c.literal, false)),
                    (ConditionKind::Valid, false) => check.any.push(t.matching(&c.literal)),
                    (ConditionKind::Invalid, true) => check.forbid.push(t.fluent(&c.literal, false)),
                    (ConditionKind::Invalid, false) => check.forbid.extend(t.matching(&c.literal)),
                    (ConditionKind::Goal, _) => {}
                }
            }
            check
        })
        .collect();

    // The nodes, in depth-first order from the root.
    let mut emitter = Emitter {
        kb,
        db,
        pop,
        stn,
        effects: &effects,
        checks: &checks,
        nodes: Vec::new(),
        debug: DebugInfo::default(),
        file_index: HashMap::new(),
    };
    let root = emitter.lower(&bt.root, &mut t);
    // Refinements, by node (ascending, as the format wants): each step an import.
    let mut refined = Vec::new();
    for (i, node) in emitter.nodes.iter().enumerate() {
        let event = match node {
            Instr::Start { event, .. } | Instr::End { event, .. } | Instr::Act { event, .. } => event.0 as usize,
            _ => continue,
        };
        let Some(steps) = &refinements[event] else { continue };
        let steps = steps
            .iter()
            .map(|term| {
                let (name, args) = match term {
                    Term::Compound(f, args) => (*f, &args[..]),
                    Term::Atom(a) => (*a, &[][..]),
                    _ => (crate::intern::sym::ANON, &[][..]),
                };
                let import = t.import(interner.resolve(name), args.len() as u16);
                Call { import, args: args.iter().map(|a| t.value(a)).collect() }
            })
            .collect();
        refined.push(Refinement { node: NodeRef(i as u32), steps });
    }
    Module {
        symbols: t.symbols,
        imports: t.imports,
        fluents: t.fluents,
        events: pop.steps.len() as u32,
        time_scale: UNITS as u32,
        root: NodeRef(root),
        nodes: emitter.nodes,
        debug: Some(emitter.debug),
        refinements: refined,
    }
}

/// Lowers tree nodes to instructions, depth first, with a debug entry per action node.
struct Emitter<'a> {
    kb: &'a Kb,
    db: &'a SourceDb,
    pop: &'a Pop,
    stn: &'a Stn,
    effects: &'a [Vec<(bool, FluentId)>],
    checks: &'a [Check],
    nodes: Vec<Instr>,
    debug: DebugInfo,
    /// Source file to index in `debug.files`.
    file_index: HashMap<u32, u32>,
}

impl Emitter<'_> {
    /// Lowers `node` and everything under it; returns its index.
    fn lower(&mut self, node: &Node, t: &mut Tables<'_>) -> u32 {
        let index = self.nodes.len() as u32;
        self.nodes.push(Instr::Sequence { children: Vec::new() }); // filled in below
        let instr = match node {
            Node::Sequence(children) | Node::Parallel(children) => {
                let refs: Vec<NodeRef> = children.iter().map(|c| NodeRef(self.lower(c, t))).collect();
                match node {
                    Node::Parallel(_) => Instr::Parallel { children: refs },
                    _ => Instr::Sequence { children: refs },
                }
            }
            Node::Wait(after) => Instr::Wait {
                after: after.iter().map(|&(s, d)| Delay { event: EventId(s as u32), after: Time(d) }).collect(),
            },
            Node::Action(s) => self.action(*s, index, t),
        };
        self.nodes[index as usize] = instr;
        index
    }

    /// The start, end or act node of step `s`, at node `index`.
    fn action(&mut self, s: usize, index: u32, t: &mut Tables<'_>) -> Instr {
        let step = &self.pop.steps[s];
        let action = &self.kb.actions[step.action];
        let name = t.interner.resolve(action.base).to_string();
        let args: Vec<Value> = step.name.args().iter().map(|a| t.value(a)).collect();
        let effects = self.effects[s].iter().map(|&(add, fluent)| Effect { add, fluent }).collect();
        let check = self.checks[s].clone();
        let event = EventId(s as u32);
        let span = action.span;
        let next = self.debug.files.len() as u32;
        let file = *self.file_index.entry(span.file.0).or_insert(next);
        if file == next {
            let symbol = t.symbol(self.db.file(span.file).name());
            self.debug.files.push(symbol);
        }
        let at = self.db.file(span.file).line_col(span.start);
        let label = t.symbol(&t.text(&step.name));
        self.debug.entries.push(DebugEntry { node: NodeRef(index), file, line: at.line, column: at.column, label });
        match step.snap {
            Snap::Start => {
                let bounds = self.stn.durations.get(s).copied().flatten();
                let import = t.import(&name, args.len() as u16);
                Instr::Start {
                    event,
                    import,
                    args,
                    min: Time(bounds.map_or(0, |b| b.min)),
                    max: MaxTime(bounds.and_then(|b| b.max)),
                    check,
                    effects,
                }
            }
            Snap::End => Instr::End { event, start: EventId(step.start.unwrap_or(s) as u32), check, effects },
            Snap::Instant => {
                let import = t.import(&name, args.len() as u16);
                Instr::Act { event, import, args, check, effects }
            }
        }
    }
}
