//! The planning task: one problem of a KB, compiled for search.
//!
//! Ground terms are interned as [`ConstId`]s and ground facts as [`FactId`]s, so states are
//! small arrays of integers that hash and compare fast. Action schemas stay lifted: their
//! literals are [`Pattern`]s over schema-local variables, matched against a state's facts when
//! the search asks which actions apply (see `planner::successors`). Nothing here is grounded
//! ahead of time except what the problem itself states (its initial facts).
//!
//! A [`State`] is its facts, sorted by predicate so each predicate's facts form one range, plus
//! the durative actions started and not yet ended.

use std::hash::BuildHasher;

use hashbrown::HashTable;
use rustc_hash::FxBuildHasher;

use crate::intern::{Interner, Symbol};
use crate::ir::hir::{self, EffectKind, Goal, Snap, Term};
use crate::source::Span;

/// An interned ground term.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ConstId(pub u32);

/// A ground term, with compound arguments interned.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Const {
    /// An atom.
    Atom(Symbol),
    /// An integer.
    Int(i64),
    /// A float, by its bits (so constants can be hashed).
    Float(u64),
    /// A string.
    Str(Symbol),
    /// A compound term.
    Compound(Symbol, Box<[ConstId]>),
}

/// The constant a ground term stands for, its arguments first, each looked up (or interned)
/// by `id_of`; `None` if the term has a variable or `id_of` gives none.
fn constant_of(term: &Term, id_of: &mut dyn FnMut(Const) -> Option<ConstId>) -> Option<ConstId> {
    let value = match term {
        Term::Var(_) => return None,
        Term::Atom(s) => Const::Atom(*s),
        Term::Int(i) => Const::Int(*i),
        Term::Float(f) => Const::Float(f.to_bits()),
        Term::Str(s) => Const::Str(*s),
        Term::Compound(f, args) => {
            Const::Compound(*f, args.iter().map(|a| constant_of(a, id_of)).collect::<Option<Box<[ConstId]>>>()?)
        }
    };
    id_of(value)
}

/// The table of ground terms.
#[derive(Clone, Debug, Default)]
pub struct Consts {
    items: Vec<Const>,
    map: rustc_hash::FxHashMap<Const, ConstId>,
}

impl Consts {
    /// The id of `value`, interning it if new.
    pub fn intern(&mut self, value: Const) -> ConstId {
        if let Some(&id) = self.map.get(&value) {
            return id;
        }
        let id = ConstId(self.items.len() as u32);
        self.items.push(value.clone());
        self.map.insert(value, id);
        id
    }

    /// The id of `value` if it has been interned.
    pub fn find(&self, value: &Const) -> Option<ConstId> {
        self.map.get(value).copied()
    }

    /// The term behind an id.
    pub fn get(&self, id: ConstId) -> &Const {
        &self.items[id.0 as usize]
    }

    /// Interns a ground HIR term; `None` if it has a variable.
    pub fn from_term(&mut self, term: &Term) -> Option<ConstId> {
        constant_of(term, &mut |value| Some(self.intern(value)))
    }

    /// The id of a ground HIR term if it has been interned; `None` otherwise (or if it has a
    /// variable).
    pub fn find_term(&self, term: &Term) -> Option<ConstId> {
        constant_of(term, &mut |value| self.map.get(&value).copied())
    }

    /// The HIR term of a constant.
    pub fn to_term(&self, id: ConstId) -> Term {
        match self.get(id) {
            Const::Atom(s) => Term::Atom(*s),
            Const::Int(i) => Term::Int(*i),
            Const::Float(bits) => Term::Float(f64::from_bits(*bits)),
            Const::Str(s) => Term::Str(*s),
            Const::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| self.to_term(*a)).collect()),
        }
    }

    /// The number of constants.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True when no constant is interned.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
}

/// An interned predicate: name and arity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PredId(pub u32);

/// An interned ground fact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FactId(pub u32);

/// The table of predicates and ground facts.
///
/// Fact arguments are stored end to end in one vector; the hash table holds fact ids and
/// compares a probed fact's stored arguments with the ones looked up, so interning allocates
/// nothing per fact.
#[derive(Clone, Default)]
pub struct Facts {
    preds: Vec<(Symbol, u32)>,
    pred_map: rustc_hash::FxHashMap<(Symbol, u32), PredId>,
    /// The running-action predicates (see [`Facts::running_pred`]), by base name and arity.
    running_map: rustc_hash::FxHashMap<(Symbol, u32), PredId>,
    /// Per fact: predicate, start of its arguments in `args`.
    facts: Vec<(PredId, u32)>,
    args: Vec<ConstId>,
    table: HashTable<FactId>,
    hasher: FxBuildHasher,
}

impl std::fmt::Debug for Facts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Facts").field("preds", &self.preds.len()).field("facts", &self.facts.len()).finish()
    }
}

impl Facts {
    /// The id of predicate `name/arity`, interning it if new.
    pub fn pred(&mut self, name: Symbol, arity: usize) -> PredId {
        Facts::intern_pred(&mut self.preds, &mut self.pred_map, (name, arity as u32))
    }

    fn intern_pred(
        preds: &mut Vec<(Symbol, u32)>,
        map: &mut rustc_hash::FxHashMap<(Symbol, u32), PredId>,
        key: (Symbol, u32),
    ) -> PredId {
        *map.entry(key).or_insert_with(|| {
            preds.push(key);
            PredId(preds.len() as u32 - 1)
        })
    }

    /// The predicate that says "durative action `base` is running with these arguments",
    /// interning it if new. It is apart from every fluent (a fluent may share the name), and
    /// no state holds its facts: states keep running actions in [`State::running`]. The
    /// relaxation reads it, so that a start adds `base(Args)` and an end needs it, which is
    /// how an end's head takes the values of the start it closes.
    pub fn running_pred(&mut self, base: Symbol, arity: usize) -> PredId {
        Facts::intern_pred(&mut self.preds, &mut self.running_map, (base, arity as u32))
    }

    /// True for a running-action predicate (see [`Facts::running_pred`]).
    pub fn is_running_pred(&self, pred: PredId) -> bool {
        self.running_map.values().any(|&p| p == pred)
    }

    /// The predicates of state facts: every predicate but the running-action ones.
    pub fn fluent_preds(&self) -> impl Iterator<Item = PredId> + '_ {
        (0..self.preds.len() as u32).map(PredId).filter(|&p| !self.is_running_pred(p))
    }

    /// The running-action predicate of `base/arity`, if interned.
    pub fn find_running_pred(&self, base: Symbol, arity: usize) -> Option<PredId> {
        self.running_map.get(&(base, arity as u32)).copied()
    }

    /// The predicate `name/arity` if it has been interned.
    pub fn find_pred(&self, name: Symbol, arity: usize) -> Option<PredId> {
        self.pred_map.get(&(name, arity as u32)).copied()
    }

    /// The name and arity of a predicate.
    pub fn pred_info(&self, pred: PredId) -> (Symbol, usize) {
        let (name, arity) = self.preds[pred.0 as usize];
        (name, arity as usize)
    }

    /// The number of predicates.
    pub fn pred_count(&self) -> usize {
        self.preds.len()
    }

    fn hash(hasher: &FxBuildHasher, pred: PredId, args: &[ConstId]) -> u64 {
        hasher.hash_one((pred, args))
    }

    /// The id of the fact `pred(args)`, interning it if new.
    pub fn intern(&mut self, pred: PredId, args: &[ConstId]) -> FactId {
        let Facts { facts, args: store, table, hasher, .. } = self;
        let hash = Facts::hash(hasher, pred, args);
        let arity = args.len();
        let found = table.find(hash, |&f| {
            let (p, start) = facts[f.0 as usize];
            p == pred && &store[start as usize..start as usize + arity] == args
        });
        if let Some(&id) = found {
            return id;
        }
        let id = FactId(facts.len() as u32);
        facts.push((pred, store.len() as u32));
        store.extend_from_slice(args);
        let preds = &self.preds;
        table.insert_unique(hash, id, |&f| {
            let (p, start) = facts[f.0 as usize];
            let n = preds[p.0 as usize].1 as usize;
            Facts::hash(hasher, p, &store[start as usize..start as usize + n])
        });
        id
    }

    /// The fact `pred(args)` if it has been interned.
    pub fn find(&self, pred: PredId, args: &[ConstId]) -> Option<FactId> {
        let hash = Facts::hash(&self.hasher, pred, args);
        self.table
            .find(hash, |&f| {
                let (p, start) = self.facts[f.0 as usize];
                p == pred && &self.args[start as usize..start as usize + args.len()] == args
            })
            .copied()
    }

    /// A fact's predicate.
    pub fn pred_of(&self, fact: FactId) -> PredId {
        self.facts[fact.0 as usize].0
    }

    /// A fact's arguments.
    pub fn args(&self, fact: FactId) -> &[ConstId] {
        let (pred, start) = self.facts[fact.0 as usize];
        let arity = self.preds[pred.0 as usize].1 as usize;
        &self.args[start as usize..start as usize + arity]
    }

    /// The number of facts interned.
    pub fn len(&self) -> usize {
        self.facts.len()
    }

    /// True when no fact is interned.
    pub fn is_empty(&self) -> bool {
        self.facts.is_empty()
    }

    /// A fact as a HIR term.
    pub fn to_term(&self, consts: &Consts, fact: FactId) -> Term {
        let (name, arity) = self.pred_info(self.pred_of(fact));
        if arity == 0 {
            return Term::Atom(name);
        }
        Term::Compound(name, self.args(fact).iter().map(|a| consts.to_term(*a)).collect())
    }
}

/// A term with schema variables, matched against ground facts.
#[derive(Clone, Debug, PartialEq)]
pub enum Pattern {
    /// A ground term.
    Const(ConstId),
    /// Schema variable number `n`.
    Var(u32),
    /// A compound with at least one variable inside.
    Compound(Symbol, Box<[Pattern]>),
}

impl Pattern {
    /// Appends the pattern's variables, in order, repeats included.
    pub fn vars(&self, out: &mut Vec<u32>) {
        match self {
            Pattern::Const(_) => {}
            Pattern::Var(v) => out.push(*v),
            Pattern::Compound(_, args) => args.iter().for_each(|a| a.vars(out)),
        }
    }
}

/// A literal: a predicate applied to patterns.
#[derive(Clone, Debug, PartialEq)]
pub struct LiteralPattern {
    /// The predicate.
    pub pred: PredId,
    /// The arguments.
    pub args: Box<[Pattern]>,
    /// Where it is written.
    pub span: Span,
}

/// An action schema compiled for matching.
#[derive(Clone, Debug)]
pub struct Schema {
    /// Its index in the HIR's `Kb::actions`.
    pub action: usize,
    /// The name pattern, e.g. `grip_start(A, B)`.
    pub name: Pattern,
    /// The durative action's base name.
    pub base: Symbol,
    /// Start, end or instantaneous.
    pub snap: Snap,
    /// The number of schema variables.
    pub vars: usize,
    /// Literals that must match state facts.
    pub valid: Box<[LiteralPattern]>,
    /// Literals no state fact may match.
    pub invalid: Box<[LiteralPattern]>,
    /// Literals no goal literal may unify with (HIR terms, unified with the goal's).
    pub invalid_at_end: Box<[Term]>,
    /// Goals proven against the KB.
    pub on_kb: Box<[Goal]>,
    /// Effects, in order.
    pub effects: Box<[(EffectKind, LiteralPattern)]>,
    /// The variables that name a unit of a renewable resource (`resources/1`): those a Valid
    /// literal matching a resource template binds where the template has a variable, such as
    /// `A` in `available(A)` under `resources(available(_))`. Units of a resource are
    /// interchangeable, which the heuristic search uses to spread work across them.
    pub resource_vars: Box<[u32]>,
    /// For each Valid literal, whether it takes a unit of a renewable resource (it unifies
    /// with a `resources/1` template, as `available(A)` does).
    pub resource_valid: Box<[bool]>,
    /// For a start or end of a durative pair whose end has a name variable its Valid list
    /// does not bind: the running-action literal (on [`Facts::running_pred`]) with the name's
    /// arguments, which the relaxation has the start add and the end need, so the end's name
    /// takes the start's values. `None` for instantaneous actions and for pairs whose ends
    /// bind their whole name themselves. (The search matches ends against
    /// [`State::running`] in every case.)
    pub running: Option<LiteralPattern>,
}

impl Schema {
    /// The variables whose values only a choice gives a start or an instantaneous action:
    /// bound by no Valid literal (so by an OnKB goal, such as a move's destination, or by the
    /// name alone) and naming no unit of a resource. None for an end (its running start binds
    /// it).
    pub fn chosen_vars(&self) -> Box<[u32]> {
        if self.snap == Snap::End {
            return Box::default();
        }
        let mut bound = Vec::new();
        self.valid.iter().for_each(|l| l.args.iter().for_each(|a| a.vars(&mut bound)));
        (0..self.vars as u32).filter(|v| !bound.contains(v) && !self.resource_vars.contains(v)).collect()
    }

    /// The variables bound by the time effects apply: by the name, the Valid literals and
    /// the OnKB goals (an end's name by its running start).
    pub fn bound_vars(&self) -> Vec<u32> {
        let mut bound = Vec::new();
        self.name.vars(&mut bound);
        self.valid.iter().for_each(|l| l.args.iter().for_each(|a| a.vars(&mut bound)));
        for goal in self.on_kb.iter() {
            goal.for_each_call(&mut |l| l.term.for_each_var(&mut |v| bound.push(v.0)));
        }
        bound
    }

    /// The indices of the effects with a variable [`Schema::bound_vars`] leaves unbound: an
    /// open `add` never applies (W0010), an open `del` removes every fact that unifies (W0009).
    pub fn open_effects(&self) -> Vec<usize> {
        let bound = self.bound_vars();
        (0..self.effects.len())
            .filter(|&e| {
                let mut own = Vec::new();
                self.effects[e].1.args.iter().for_each(|a| a.vars(&mut own));
                own.iter().any(|v| !bound.contains(v))
            })
            .collect()
    }
}

/// A state: facts (sorted by predicate, then fact id) and running durative actions.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Default)]
pub struct State {
    /// `(pred << 32) | fact` for each fact, sorted and without repeats.
    keys: Box<[u64]>,
    /// The running durative actions, as `base(args)` constants, sorted and without repeats.
    pub running: Box<[ConstId]>,
}

fn key(pred: PredId, fact: FactId) -> u64 {
    (u64::from(pred.0) << 32) | u64::from(fact.0)
}

impl State {
    /// A state of `facts` (any order, repeats allowed) with `running` actions.
    pub fn new(
        facts: &Facts,
        fact_ids: impl IntoIterator<Item = FactId>,
        running: impl IntoIterator<Item = ConstId>,
    ) -> State {
        let mut keys: Vec<u64> = fact_ids.into_iter().map(|f| key(facts.pred_of(f), f)).collect();
        keys.sort_unstable();
        keys.dedup();
        let mut running: Vec<ConstId> = running.into_iter().collect();
        running.sort_unstable();
        running.dedup();
        State { keys: keys.into_boxed_slice(), running: running.into_boxed_slice() }
    }

    /// Every fact, grouped by predicate.
    pub fn facts(&self) -> impl Iterator<Item = FactId> + '_ {
        self.keys.iter().map(|k| FactId(*k as u32))
    }

    /// The facts of one predicate.
    pub fn facts_of(&self, pred: PredId) -> impl Iterator<Item = FactId> + '_ {
        let low = u64::from(pred.0) << 32;
        let start = self.keys.partition_point(|&k| k < low);
        self.keys[start..].iter().take_while(move |&&k| k >> 32 == u64::from(pred.0)).map(|k| FactId(*k as u32))
    }

    /// True if the state holds `fact`.
    pub fn contains(&self, facts: &Facts, fact: FactId) -> bool {
        self.keys.binary_search(&key(facts.pred_of(fact), fact)).is_ok()
    }

    /// The number of facts.
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// True when the state holds no fact.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Bytes this state occupies, for the memory ceiling.
    pub fn footprint(&self) -> usize {
        std::mem::size_of::<State>() + self.keys.len() * 8 + self.running.len() * 4
    }
}

/// One problem of a KB, compiled for search.
#[derive(Clone, Debug)]
pub struct Task {
    /// The problem's index in `Kb::problems`.
    pub problem: usize,
    /// Ground terms.
    pub consts: Consts,
    /// Predicates and ground facts.
    pub facts: Facts,
    /// The high-level action schemas, in clause order.
    pub schemas: Vec<Schema>,
    /// The initial state.
    pub init: State,
    /// The goal: literals over `goal_vars` variables shared between them.
    pub goal: Vec<LiteralPattern>,
    /// The number of goal variables.
    pub goal_vars: usize,
    /// For each goal literal, whether it is a unit of a renewable resource (it matches a
    /// `resources/1` template), such as `available(a1)`: a unit is taken and given back by
    /// the actions that use it.
    pub resource_goal: Vec<bool>,
    /// The goal as HIR terms (for InvalidAtEnd checks and messages), with its variables.
    pub goal_terms: Vec<Term>,
    /// The depth limit the problem asks for (`go/5`).
    pub max_depth: Option<u32>,
}

impl Task {
    /// A running action `base(args)` as a fact of its running-action predicate; `None` if no
    /// schema starts such an action.
    pub fn running_fact(&self, running: ConstId) -> Option<(PredId, &[ConstId])> {
        match self.consts.get(running) {
            Const::Atom(base) => Some((self.facts.find_running_pred(*base, 0)?, &[])),
            Const::Compound(base, args) => Some((self.facts.find_running_pred(*base, args.len())?, args)),
            _ => None,
        }
    }

    /// Writes a pattern with variables named by `vars`.
    pub fn pattern_to_term(&self, pattern: &Pattern) -> Term {
        match pattern {
            Pattern::Const(c) => self.consts.to_term(*c),
            Pattern::Var(v) => Term::Var(hir::VarId(*v)),
            Pattern::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| self.pattern_to_term(a)).collect()),
        }
    }

    /// A literal pattern as a HIR term.
    pub fn literal_to_term(&self, literal: &LiteralPattern) -> Term {
        let (name, arity) = self.facts.pred_info(literal.pred);
        if arity == 0 {
            return Term::Atom(name);
        }
        Term::Compound(name, literal.args.iter().map(|a| self.pattern_to_term(a)).collect())
    }
}

/// The task's text form, for `--dump-after=task`: schemas, initial state and goal.
pub fn print(interner: &Interner, kb: &hir::Kb, task: &Task) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let problem = &kb.problems[task.problem];
    let _ = writeln!(out, "% task for problem {}", interner.resolve(problem.name));
    let _ = writeln!(
        out,
        "% {} schemas, {} constants, {} facts interned",
        task.schemas.len(),
        task.consts.len(),
        task.facts.len()
    );
    for schema in &task.schemas {
        let vars = &kb.actions[schema.action].vars;
        let show = |l: &LiteralPattern| hir::term_to_string(interner, &task.literal_to_term(l), vars);
        let list = |ls: &[LiteralPattern]| ls.iter().map(show).collect::<Vec<_>>().join(", ");
        let _ = writeln!(out, "schema {}", hir::term_to_string(interner, &task.pattern_to_term(&schema.name), vars));
        let _ = writeln!(out, "  valid [{}] invalid [{}]", list(&schema.valid), list(&schema.invalid));
        let effects: Vec<String> = schema
            .effects
            .iter()
            .map(|(kind, l)| format!("{}({})", if *kind == EffectKind::Add { "add" } else { "del" }, show(l)))
            .collect();
        let _ = writeln!(out, "  effects [{}]", effects.join(", "));
        if !schema.resource_vars.is_empty() {
            let units: Vec<String> = schema
                .resource_vars
                .iter()
                .map(|&v| hir::term_to_string(interner, &Term::Var(hir::VarId(v)), vars))
                .collect();
            let _ = writeln!(out, "  resource units {}", units.join(", "));
        }
    }
    out.push_str("init:");
    let no_vars = hir::VarTable::default();
    let mut facts: Vec<String> = task
        .init
        .facts()
        .map(|f| hir::term_to_string(interner, &task.facts.to_term(&task.consts, f), &no_vars))
        .collect();
    facts.sort();
    for fact in facts {
        let _ = write!(out, " {fact}");
    }
    out.push_str("\ngoal:");
    for literal in &task.goal {
        let _ = write!(out, " {}", hir::term_to_string(interner, &task.literal_to_term(literal), &problem.vars));
    }
    out.push('\n');
    out
}

/// Checks the task's invariants: every id in range, every pattern variable below its schema's
/// count, states sorted. A failure is a compiler bug.
pub fn verify(task: &Task) -> Result<(), String> {
    fn pattern(p: &Pattern, vars: usize, consts: usize) -> Result<(), String> {
        match p {
            Pattern::Const(c) if (c.0 as usize) < consts => Ok(()),
            Pattern::Const(c) => Err(format!("constant {c:?} out of range")),
            Pattern::Var(v) if (*v as usize) < vars => Ok(()),
            Pattern::Var(v) => Err(format!("variable {v} out of {vars}")),
            Pattern::Compound(_, args) => args.iter().try_for_each(|a| pattern(a, vars, consts)),
        }
    }
    let consts = task.consts.len();
    for (i, schema) in task.schemas.iter().enumerate() {
        let check = |l: &LiteralPattern| -> Result<(), String> {
            if l.pred.0 as usize >= task.facts.pred_count() {
                return Err(format!("schema #{i}: predicate out of range"));
            }
            l.args.iter().try_for_each(|a| pattern(a, schema.vars, consts)).map_err(|e| format!("schema #{i}: {e}"))
        };
        pattern(&schema.name, schema.vars, consts).map_err(|e| format!("schema #{i} name: {e}"))?;
        schema.valid.iter().chain(schema.invalid.iter()).try_for_each(&check)?;
        if schema.resource_valid.len() != schema.valid.len() {
            return Err(format!("schema #{i}: a resource flag per Valid literal expected"));
        }
        schema.effects.iter().try_for_each(|(_, l)| check(l))?;
        if let Some(running) = &schema.running {
            check(running)?;
            if (schema.snap == Snap::Instant)
                || task.facts.find_running_pred(schema.base, running.args.len()) != Some(running.pred)
            {
                return Err(format!("schema #{i}: running literal on the wrong predicate"));
            }
        }
    }
    for literal in &task.goal {
        literal.args.iter().try_for_each(|a| pattern(a, task.goal_vars, consts))?;
    }
    if task.init.keys.windows(2).any(|w| w[0] >= w[1]) {
        return Err("the initial state is not sorted".to_string());
    }
    Ok(())
}
