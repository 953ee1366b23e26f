//! The HIR: a knowledge base resolved into the paper's model.
//!
//! Lowering (`passes::lower`) sorts every clause of the input into what it means: action
//! schemas (`action/6`, `ll_action/6`), refinements (`mapping/2`), resource declarations,
//! problems (`init_state`/`goal_state` pairs and `go/2,4,5` tests), declarations, and the
//! static program (facts and rules, `duration/3` included). Every item keeps its span.
//!
//! Terms here are plain Prolog terms with clause-local variables: each clause-like item owns a
//! [`VarTable`], and [`VarId`]s are numbered by first occurrence, so two items that are the
//! same up to variable renaming have equal terms. Lists are `'[|]'/2` cells ending in `[]`.
//!
//! The module also holds the HIR's text form ([`print`]) and its verifier ([`verify`]).

use std::fmt::Write;

pub use super::args::Args;
use crate::intern::{Interner, Symbol, sym};
use crate::source::{FileId, Span};
use crate::syntax::printer::{PrintContext, TermView, View, end_clause, write_term};

/// A clause-local variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VarId(pub u32);

/// A term.
#[derive(Clone, Debug, PartialEq)]
pub enum Term {
    /// A variable of the enclosing item's [`VarTable`].
    Var(VarId),
    /// An atom.
    Atom(Symbol),
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A string.
    Str(Symbol),
    /// A compound term with at least one argument, or zero for `f()`.
    Compound(Symbol, Args),
}

impl Term {
    /// The right-nested binary term of an xfy chain: `op(a, op(b, c))` for operands `a, b, c`
    /// (a flat chain of the syntax tree, see [`crate::syntax::ast::Notation::Chain`]). A loop,
    /// so a chain of any length costs no stack.
    pub fn xfy(op: Symbol, mut operands: Vec<Term>) -> Term {
        let mut acc = operands.pop().expect("a chain has operands");
        while let Some(operand) = operands.pop() {
            acc = Term::Compound(op, Args::from([operand, acc]));
        }
        acc
    }

    /// The operands of the right-nested chain `op(a, op(b, c))`: `a`, `b`, `c`; a term that
    /// is no such chain is its own only operand.
    pub fn xfy_operands(&self, op: Symbol) -> Vec<&Term> {
        let mut operands = Vec::new();
        let mut rest = self;
        while let Term::Compound(f, args) = rest
            && *f == op
            && args.len() == 2
        {
            operands.push(&args[0]);
            rest = &args[1];
        }
        operands.push(rest);
        operands
    }

    /// The name and arity of a callable term.
    pub fn callable(&self) -> Option<(Symbol, usize)> {
        match self {
            Term::Atom(s) => Some((*s, 0)),
            Term::Compound(s, args) => Some((*s, args.len())),
            _ => None,
        }
    }

    /// The arguments of a compound; empty for anything else.
    pub fn args(&self) -> &[Term] {
        match self {
            Term::Compound(_, args) => args,
            _ => &[],
        }
    }

    /// True if the term has no variables.
    pub fn is_ground(&self) -> bool {
        match self {
            Term::Var(_) => false,
            Term::Compound(_, args) => args.iter().all(Term::is_ground),
            _ => true,
        }
    }

    /// The term with every variable number raised by `offset`.
    pub fn shift_vars(&self, offset: u32) -> Term {
        match self {
            Term::Var(v) => Term::Var(VarId(v.0 + offset)),
            Term::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| a.shift_vars(offset)).collect()),
            other => other.clone(),
        }
    }

    /// Calls `f` on each variable occurrence, left to right.
    pub fn for_each_var(&self, f: &mut impl FnMut(VarId)) {
        match self {
            Term::Var(v) => f(*v),
            Term::Compound(_, args) => args.iter().for_each(|a| a.for_each_var(f)),
            _ => {}
        }
    }

    /// The elements of a proper list, or `None` if the term is not one.
    pub fn list_items(&self) -> Option<Vec<&Term>> {
        let mut items = Vec::new();
        let mut rest = self;
        loop {
            match rest {
                Term::Atom(s) if *s == sym::NIL => return Some(items),
                Term::Compound(s, args) if *s == sym::CONS && args.len() == 2 => {
                    items.push(&args[0]);
                    rest = &args[1];
                }
                _ => return None,
            }
        }
    }
}

/// One variable of a clause-like item.
#[derive(Clone, Debug, PartialEq)]
pub struct VarInfo {
    /// The name as written (`_` for anonymous variables).
    pub name: Symbol,
    /// Every occurrence, in source order.
    pub occurrences: Vec<Span>,
}

/// The variables of one clause-like item, indexed by [`VarId`].
#[derive(Clone, Debug, PartialEq, Default)]
pub struct VarTable {
    /// The variables, in order of first occurrence.
    pub vars: Vec<VarInfo>,
}

impl VarTable {
    /// The variable behind `id`.
    pub fn get(&self, id: VarId) -> &VarInfo {
        &self.vars[id.0 as usize]
    }

    /// The number of variables.
    pub fn len(&self) -> usize {
        self.vars.len()
    }

    /// True when the item has no variables.
    pub fn is_empty(&self) -> bool {
        self.vars.is_empty()
    }
}

/// A literal (an atom or compound used as a condition, fact or effect) with its spans.
#[derive(Clone, Debug, PartialEq)]
pub struct Literal {
    /// The term; always callable.
    pub term: Term,
    /// The whole literal.
    pub span: Span,
    /// The predicate name.
    pub name_span: Span,
}

impl Literal {
    /// The predicate name.
    pub fn name(&self) -> Symbol {
        self.term.callable().map_or(sym::ANON, |(n, _)| n)
    }

    /// The number of arguments.
    pub fn arity(&self) -> usize {
        self.term.args().len()
    }
}

/// A goal of a rule body or an OnKB slot.
#[derive(Clone, Debug, PartialEq)]
pub enum Goal {
    /// A call to a predicate or built-in.
    Call(Literal),
    /// `A, B, ...`.
    And(Vec<Goal>),
    /// `A ; B ; ...`, whose branches may be if-thens: `C -> T ; E` is two branches, and
    /// `C -> T` alone is one. Flat, however long the chain (a nest of binary disjunctions
    /// would make walking a long one recurse as deep).
    Or(Vec<Branch>),
    /// `\+ G`.
    Not(Box<Goal>),
    /// A call of a built-in that calls goals it is given: `findall/3`, `forall/2`, `call/N`,
    /// `maplist/N`, ... (`crate::builtins::Builtin::calls`).
    Meta(Box<MetaCall>),
}

/// A call of a built-in that calls some of its arguments ([`Goal::Meta`]).
#[derive(Clone, Debug, PartialEq)]
pub struct MetaCall {
    /// The call, as the engine runs it.
    pub call: Literal,
    /// Each literal it may call through those arguments, however deep (through control
    /// constructs and other such calls), with the number of arguments the call appends to it
    /// (`maplist(P, L)` calls `P` with one more). The terms are those of `call`'s arguments,
    /// so their variables are `call`'s; what an argument holds only at run time (a variable)
    /// is not here. For the name checks, the editor index and the analyses.
    pub called: Vec<(Literal, usize)>,
}

/// A branch of a disjunction ([`Goal::Or`]): a goal, or an if-then `C1 -> C2 -> ... -> G`.
///
/// The branches are tried in order. A branch with conditions calls its first; when that
/// succeeds (its first solution only), the disjunction commits to the branch, so the later
/// branches are not tried (Prolog's if-then-else); when it fails, the next branch is tried.
/// Each later condition is then called once too, and failing it fails the disjunction:
/// `C1 -> C2 -> G` is `C1 -> (C2 -> G)`. A branch without conditions is a plain alternative.
#[derive(Clone, Debug, PartialEq)]
pub struct Branch {
    /// The conditions, in order; none for a plain alternative.
    pub conditions: Vec<Goal>,
    /// The goal run after them.
    pub goal: Goal,
}

impl Goal {
    /// Calls `f` on every literal called anywhere in the goal but the closures
    /// [`Goal::for_each_called`] yields with arguments to append: each literal `f` sees is
    /// called as it stands.
    pub fn for_each_call<'a>(&'a self, f: &mut impl FnMut(&'a Literal)) {
        self.for_each_called(&mut |literal, extra| {
            if extra == 0 {
                f(literal)
            }
        });
    }

    /// Calls `f` on every literal called anywhere in the goal, with the number of arguments
    /// the call appends (nonzero for the closures of `maplist/N` and the like, which
    /// [`Goal::for_each_call`] leaves out): the predicate called is the literal's name with
    /// its arity plus that number.
    pub fn for_each_called<'a>(&'a self, f: &mut impl FnMut(&'a Literal, usize)) {
        match self {
            Goal::Meta(meta) => {
                f(&meta.call, 0);
                meta.called.iter().for_each(|(l, extra)| f(l, *extra));
            }
            Goal::And(goals) => goals.iter().for_each(|g| g.for_each_called(f)),
            Goal::Or(branches) => {
                for branch in branches {
                    branch.conditions.iter().for_each(|c| c.for_each_called(f));
                    branch.goal.for_each_called(f);
                }
            }
            Goal::Not(g) => g.for_each_called(f),
            Goal::Call(literal) => f(literal, 0),
        }
    }
}

/// A static clause: a fact (no body) or a rule.
#[derive(Clone, Debug, PartialEq)]
pub struct Clause {
    /// The head.
    pub head: Literal,
    /// The body of a rule (boxed: most clauses of a large KB are facts).
    pub body: Option<Box<Goal>>,
    /// The clause's variables.
    pub vars: VarTable,
    /// The whole clause.
    pub span: Span,
}

/// Whether an action is a high-level `action/6` or an arm-level `ll_action/6`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// `action/6`.
    High,
    /// `ll_action/6`.
    Low,
}

/// Which part of a durative action a schema is, from its name's suffix.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Snap {
    /// `X_start`: the start of durative action `X`.
    Start,
    /// `X_end`: the end of durative action `X`.
    End,
    /// No suffix: an instantaneous action.
    Instant,
}

/// `add(L)` or `del(L)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum EffectKind {
    /// Adds the literal to the state.
    Add,
    /// Removes the literal from the state.
    Del,
}

/// One effect of an action.
#[derive(Clone, Debug, PartialEq)]
pub struct Effect {
    /// Add or delete.
    pub kind: EffectKind,
    /// The literal added or deleted.
    pub literal: Literal,
    /// The whole `add(...)` / `del(...)` term.
    pub span: Span,
}

/// The six slots of an action, by position (for spans and messages).
pub const SLOT_NAMES: [&str; 6] = ["Name", "Valid", "Invalid", "InvalidAtEnd", "OnKB", "Effects"];

/// An action schema: `action(Name, Valid, Invalid, InvalidAtEnd, OnKB, Effects)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Action {
    /// `action/6` or `ll_action/6`.
    pub level: Level,
    /// The name term, e.g. `grip_start(A, B)`.
    pub name: Literal,
    /// The durative action's name without `_start`/`_end` (the name itself for instants).
    pub base: Symbol,
    /// Start, end or instantaneous.
    pub snap: Snap,
    /// Literals that must unify with state facts.
    pub valid: Vec<Literal>,
    /// Literals no state fact may unify with.
    pub invalid: Vec<Literal>,
    /// Literals no goal literal may unify with.
    pub invalid_at_end: Vec<Literal>,
    /// Goals proven against the KB.
    pub on_kb: Vec<Goal>,
    /// Effects, in order.
    pub effects: Vec<Effect>,
    /// The schema's variables.
    pub vars: VarTable,
    /// The whole clause.
    pub span: Span,
    /// The span of each of the six arguments.
    pub slots: [Span; 6],
}

impl Action {
    /// The durative action `base(args)` that `name`, a name of this start or end, stands
    /// for: the snap suffix dropped (`grip(a1, b1)` for `grip_start(a1, b1)`).
    pub fn instance(&self, name: &Term) -> Term {
        match name {
            Term::Compound(_, args) => Term::Compound(self.base, args.clone()),
            _ => Term::Atom(self.base),
        }
    }
}

/// `mapping(HighLevelStart, [ArmLevel, ...])`: refines a high-level start into arm-level steps.
#[derive(Clone, Debug, PartialEq)]
pub struct Mapping {
    /// The high-level action's start, e.g. `grip_start(A, B)`.
    pub high: Literal,
    /// The arm-level actions, in order.
    pub steps: Vec<Literal>,
    /// The mapping's variables.
    pub vars: VarTable,
    /// The whole clause.
    pub span: Span,
}

/// `resources(Template)`: renewable resources, the facts matching the template.
#[derive(Clone, Debug, PartialEq)]
pub struct Resource {
    /// The template, e.g. `agent(_)`.
    pub template: Literal,
    /// Its variables.
    pub vars: VarTable,
    /// The whole clause.
    pub span: Span,
}

/// Where a problem came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProblemForm {
    /// `Name :- go(Init, Goal)` with this arity of `go` (2, 4 or 5).
    Go(u8),
    /// `init_state([...])` with `goal_state([...])` in one file.
    InitGoalState,
}

/// A planning problem.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// Its name: the test's name, or the file's stem for `init_state`/`goal_state`.
    pub name: Symbol,
    /// Where the name is written (or the `init_state` fact).
    pub name_span: Span,
    /// The initial state: ground facts.
    pub init: Vec<Literal>,
    /// The goal: literals that must unify with facts of the final state; may hold variables.
    pub goal: Vec<Literal>,
    /// The search depth limit the problem asks for (`go/5`).
    pub max_depth: Option<u32>,
    /// How it was written.
    pub form: ProblemForm,
    /// Variables of the goal (and of `open_init`).
    pub vars: VarTable,
    /// The whole clause (or the `init_state` fact).
    pub span: Span,
    /// `High` for a problem as written; `Low` for the arm-level problem the refinement pass
    /// derives from one ([`Kb::arm_problem`]), whose plans are sequences of `ll_action`s.
    pub level: Level,
    /// Initial facts with variables. Those on arm-level predicates (`ll_arm_at(a1, 4, 4, _)`)
    /// the arm level matches by unification; for the others the planner tries values
    /// ([`crate::passes::open_init`]), and the high-level task of the problem as written
    /// leaves them out.
    pub open_init: Vec<Literal>,
    /// For a test whose `go` call follows other goals (`test :- start(I), end(G), go(I, G).`):
    /// those goals and `go`'s arguments as written, whose variables are `vars` until the
    /// `prelude` pass runs them and sets `init`, `goal` and `vars` from their first solution.
    pub prelude: Option<Box<Prelude>>,
}

/// The goals of a test before its `go` call, which give `go` its states ([`Problem::prelude`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Prelude {
    /// The goals, in order; their variables are the problem's (`Problem::vars` as lowered).
    pub goals: Vec<Goal>,
    /// `go`'s initial state and goal as written (`I`, `G`, or lists).
    pub init: Term,
    /// See `init`.
    pub goal: Term,
    /// Where `init` and `goal` are written: the argument, and each item's span where the
    /// argument is a list as written.
    pub init_spans: (Span, Vec<Span>),
    /// See `init_spans`.
    pub goal_spans: (Span, Vec<Span>),
    /// The goals before `go`, as written.
    pub span: Span,
    /// Whether the `prelude` pass has set the problem's states from the goals (false when
    /// they failed, stopped with an error, or gave something other than two lists).
    pub resolved: bool,
}

impl Problem {
    /// Every initial fact as written: the ground ones, then those with variables.
    pub fn initial_facts(&self) -> impl Iterator<Item = &Literal> {
        self.init.iter().chain(&self.open_init)
    }
}

/// A file's arm-level state: `ll_init([...])` and `ll_goal([...])`.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmState {
    /// The file that declares it.
    pub file: FileId,
    /// `ll_init/1`'s facts (they may have variables).
    pub init: Vec<Literal>,
    /// `ll_goal/1`'s literals.
    pub goal: Vec<Literal>,
    /// The variables of both lists.
    pub vars: VarTable,
}

/// `:- dynamic P/N` or `:- discontiguous P/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeclarationKind {
    /// `dynamic`.
    Dynamic,
    /// `discontiguous`.
    Discontiguous,
}

/// A predicate declaration.
#[derive(Clone, Debug, PartialEq)]
pub struct Declaration {
    /// Which declaration.
    pub kind: DeclarationKind,
    /// The predicate's name.
    pub name: Symbol,
    /// Its arity.
    pub arity: usize,
    /// The `P/N` term.
    pub span: Span,
}

/// Where a clause head appeared, for checks that depend on source order (discontiguity).
#[derive(Clone, Debug, PartialEq)]
pub struct HeadSite {
    /// The file.
    pub file: FileId,
    /// The head's predicate.
    pub name: Symbol,
    /// Its arity.
    pub arity: usize,
    /// The head's span.
    pub span: Span,
}

/// A resolved knowledge base.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Kb {
    /// Predicates (name, arity) of the arm-level states (`ll_init/1`, `ll_goal/1`): read, not
    /// planned, but state facts for the name checks of arm-level actions.
    pub arm_level_state_preds: Vec<(Symbol, usize)>,
    /// The arm-level states (`ll_init/1`, `ll_goal/1`), one per file that declares them.
    pub arm_states: Vec<ArmState>,
    /// The static program: facts and rules, in clause order.
    pub clauses: Vec<Clause>,
    /// The library predicates the program calls and does not define itself, from
    /// std/library.pl (`passes::library`): clauses of the engine's program, but not the KB's
    /// (no check, dump or editor feature sees them).
    pub library: Vec<Clause>,
    /// Action schemas of both levels, in clause order.
    pub actions: Vec<Action>,
    /// Refinements.
    pub mappings: Vec<Mapping>,
    /// Resource declarations.
    pub resources: Vec<Resource>,
    /// Problems, in clause order.
    pub problems: Vec<Problem>,
    /// `dynamic` and `discontiguous` declarations.
    pub declarations: Vec<Declaration>,
    /// Every clause head in source order, including action and problem clauses.
    pub head_sites: Vec<HeadSite>,
    /// Predicates named anywhere in clauses that failed to parse; name checks treat them as
    /// known so one syntax error does not cascade into "unknown predicate" errors.
    pub recovered_names: Vec<(Symbol, usize)>,
    /// True when the action schemas come from the standard library's blocks world.
    pub uses_std_domain: bool,
}

impl Kb {
    /// The problem named `name`.
    pub fn problem(&self, name: Symbol) -> Option<&Problem> {
        self.problems.iter().find(|p| p.name == name)
    }

    /// The predicates planning can call: those the actions' OnKB goals and the `duration/3`
    /// clauses call, directly or through rules ([`Kb::predicates_reached`]). A goal known only
    /// at run time (`call(G)`) reaches nothing here; an analysis that must account for it
    /// looks for one in these predicates' clauses. Rules outside it never run while kbc plans
    /// (a KB's own planner, test wrappers).
    pub fn predicates_run(&self) -> std::collections::BTreeSet<(Symbol, usize)> {
        let mut roots: Vec<(Symbol, usize)> = vec![(sym::DURATION, 3)];
        for action in &self.actions {
            for goal in &action.on_kb {
                goal.for_each_called(&mut |l, extra| roots.push((l.name(), l.arity() + extra)));
            }
        }
        self.predicates_reached(roots)
    }

    /// `roots` and every predicate their clauses call, directly or not, a closure with the
    /// arity it is called with (`maplist(p, L)` calls `p/1`).
    pub fn predicates_reached(&self, roots: Vec<(Symbol, usize)>) -> std::collections::BTreeSet<(Symbol, usize)> {
        let mut by_head: std::collections::BTreeMap<(Symbol, usize), Vec<&Goal>> = Default::default();
        for clause in &self.clauses {
            if let Some(body) = &clause.body {
                by_head.entry((clause.head.name(), clause.head.arity())).or_default().push(body);
            }
        }
        let mut reached = std::collections::BTreeSet::new();
        let mut pending = roots;
        while let Some(key) = pending.pop() {
            if !reached.insert(key) {
                continue;
            }
            for body in by_head.get(&key).into_iter().flatten() {
                body.for_each_called(&mut |l, extra| pending.push((l.name(), l.arity() + extra)));
            }
        }
        reached
    }

    /// High-level action schemas.
    pub fn high_level_actions(&self) -> impl Iterator<Item = &Action> {
        self.actions.iter().filter(|a| a.level == Level::High)
    }

    /// The units of the renewable resources (`resources/1`) among `facts`, in the order they
    /// appear there: the value at the template's variable position (`a1` of `available(a1)`
    /// under `resources(available(_))`).
    pub fn resource_units<'a>(&self, facts: impl IntoIterator<Item = &'a Literal>) -> Vec<Term> {
        let mut units: Vec<Term> = Vec::new();
        for fact in facts {
            for resource in &self.resources {
                let template = &resource.template;
                if template.name() != fact.name() || template.arity() != fact.arity() {
                    continue;
                }
                let mut unit = None;
                let mut matches = true;
                for (slot, value) in template.term.args().iter().zip(fact.term.args()) {
                    match slot {
                        Term::Var(_) => unit = unit.or(Some(value.clone())),
                        constant => matches &= constant == value,
                    }
                }
                if let (true, Some(unit)) = (matches, unit)
                    && !units.contains(&unit)
                {
                    units.push(unit);
                }
            }
        }
        units
    }

    /// The KB's static facts (clauses without a body).
    pub fn static_facts(&self) -> impl Iterator<Item = &Literal> {
        self.clauses.iter().filter(|c| c.body.is_none()).map(|c| &c.head)
    }

    /// The predicates of the arm level: those an `ll_action` checks, forbids, adds or
    /// deletes, and those of the arm-level states.
    pub fn arm_level_preds(&self) -> Vec<(Symbol, usize)> {
        let mut preds: Vec<(Symbol, usize)> = self.arm_level_state_preds.clone();
        for action in self.actions.iter().filter(|a| a.level == Level::Low) {
            let literals = action.valid.iter().chain(&action.invalid).chain(&action.invalid_at_end);
            for literal in literals.chain(action.effects.iter().map(|e| &e.literal)) {
                if let Some(key) = literal.term.callable()
                    && !preds.contains(&key)
                {
                    preds.push(key);
                }
            }
        }
        preds
    }

    /// The arm-level problem of high-level problem `problem`: its initial facts and goal
    /// literals on arm-level predicates ([`Kb::arm_level_preds`]), its `open_init`, and the
    /// arm-level state of its file (or the KB's only one). Its variables follow the
    /// problem's own.
    pub fn arm_problem(&self, problem: usize) -> Problem {
        let base = &self.problems[problem];
        let preds = self.arm_level_preds();
        let on_arm = |l: &&Literal| l.term.callable().is_some_and(|key| preds.contains(&key));
        let mut init: Vec<Literal> = base.init.iter().filter(on_arm).cloned().collect();
        init.extend(base.open_init.iter().filter(on_arm).cloned());
        let mut goal: Vec<Literal> = base.goal.iter().filter(on_arm).cloned().collect();
        let mut vars = base.vars.clone();
        let state = match self.arm_states.iter().find(|s| s.file == base.span.file) {
            Some(state) => Some(state),
            None if self.arm_states.len() == 1 => self.arm_states.first(),
            None => None,
        };
        if let Some(state) = state {
            let offset = vars.len() as u32;
            let shift = |l: &Literal| Literal { term: l.term.shift_vars(offset), ..l.clone() };
            init.extend(state.init.iter().map(shift));
            goal.extend(state.goal.iter().map(shift));
            vars.vars.extend(state.vars.vars.iter().cloned());
        }
        Problem { init, goal, vars, level: Level::Low, open_init: Vec::new(), ..base.clone() }
    }
}

/// Prints a term with its variables' source names (`_` becomes `_G<n>`).
pub fn term_to_string(interner: &Interner, term: &Term, vars: &VarTable) -> String {
    let mut out = String::new();
    write_named(&mut out, interner, term, vars, 1200);
    out
}

/// Writes a term with variable names at the given maximum priority.
pub fn write_named(out: &mut String, interner: &Interner, term: &Term, vars: &VarTable, max_priority: u16) {
    write_term(out, &Names { interner, vars }, term, max_priority);
}

/// What a HIR term is printed with: the interner, and the variable table naming its variables.
struct Names<'a> {
    interner: &'a Interner,
    vars: &'a VarTable,
}

impl PrintContext for Names<'_> {
    fn interner(&self) -> &Interner {
        self.interner
    }
}

impl<'n> TermView<Names<'n>> for Term {
    fn view<'a>(&'a self, names: &'a Names<'n>) -> View<'a, Self> {
        match self {
            Term::Compound(f, args) => View::Compound(*f, args),
            Term::Var(id) => {
                // A source name, or `_G<n>` for `_` (and for a variable the table lacks).
                let name = names.vars.vars.get(id.0 as usize).map_or(sym::ANON, |v| v.name);
                match names.interner.resolve(name) {
                    "_" => View::Var(format!("_G{}", id.0).into()),
                    text => View::Var(text.into()),
                }
            }
            Term::Atom(s) => View::Atom(*s),
            Term::Int(i) => View::Int(*i),
            Term::Float(f) => View::Float(*f),
            Term::Str(s) => View::Str(*s),
        }
    }
}

fn write_goal(out: &mut String, interner: &Interner, goal: &Goal, vars: &VarTable) {
    match goal {
        Goal::Call(literal) => write_named(out, interner, &literal.term, vars, 999),
        Goal::And(goals) => {
            out.push('(');
            for (i, g) in goals.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                write_goal(out, interner, g, vars);
            }
            out.push(')');
        }
        Goal::Or(branches) => {
            out.push('(');
            for (i, branch) in branches.iter().enumerate() {
                if i > 0 {
                    out.push_str(" ; ");
                }
                for condition in &branch.conditions {
                    write_goal(out, interner, condition, vars);
                    out.push_str(" -> ");
                }
                write_goal(out, interner, &branch.goal, vars);
            }
            out.push(')');
        }
        Goal::Not(g) => {
            out.push_str("\\+ ");
            write_goal(out, interner, g, vars);
        }
        Goal::Meta(meta) => write_named(out, interner, &meta.call.term, vars, 999),
    }
}

fn write_literals(out: &mut String, interner: &Interner, literals: &[Literal], vars: &VarTable) {
    out.push('[');
    for (i, l) in literals.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        write_named(out, interner, &l.term, vars, 999);
    }
    out.push(']');
}

/// The text form of an action schema with anonymous variable names (`_G0`, `_G1`, ...), so
/// two schemas that are equal up to renaming print the same.
pub fn action_to_canonical_string(interner: &Interner, action: &Action) -> String {
    let anonymous = VarTable {
        vars: action
            .vars
            .vars
            .iter()
            .map(|v| VarInfo { name: sym::ANON, occurrences: v.occurrences.clone() })
            .collect(),
    };
    action_to_string(interner, &Action { vars: anonymous, ..action.clone() })
}

/// The text form of an action schema, one slot per line, for `--dump-after=hir`.
pub fn action_to_string(interner: &Interner, action: &Action) -> String {
    let mut out = String::new();
    let head = match action.level {
        Level::High => "action",
        Level::Low => "ll_action",
    };
    let _ = write!(out, "{head} ");
    write_named(&mut out, interner, &action.name.term, &action.vars, 999);
    let snap = match action.snap {
        Snap::Start => "start",
        Snap::End => "end",
        Snap::Instant => "instant",
    };
    let _ = writeln!(out, "  % {snap} of {}", interner.resolve(action.base));
    for (label, literals) in
        [("valid", &action.valid), ("invalid", &action.invalid), ("invalid_at_end", &action.invalid_at_end)]
    {
        let _ = write!(out, "  {label}: ");
        write_literals(&mut out, interner, literals, &action.vars);
        out.push('\n');
    }
    out.push_str("  on_kb: [");
    for (i, g) in action.on_kb.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        write_goal(&mut out, interner, g, &action.vars);
    }
    out.push_str("]\n  effects: [");
    for (i, e) in action.effects.iter().enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        out.push_str(match e.kind {
            EffectKind::Add => "add(",
            EffectKind::Del => "del(",
        });
        write_named(&mut out, interner, &e.literal.term, &action.vars, 999);
        out.push(')');
    }
    out.push_str("]\n");
    out
}

/// The HIR's text form, for `kbc check --dump-after=hir` and pass tests.
pub fn print(interner: &Interner, kb: &Kb) -> String {
    let mut out = String::new();
    if kb.uses_std_domain {
        out.push_str("% domain: std/blocks.pl\n");
    }
    out.push_str("% actions\n");
    for action in &kb.actions {
        out.push_str(&action_to_string(interner, action));
    }
    if !kb.mappings.is_empty() {
        out.push_str("% mappings\n");
        for m in &kb.mappings {
            out.push_str("mapping ");
            write_named(&mut out, interner, &m.high.term, &m.vars, 999);
            out.push_str(" -> ");
            write_literals(&mut out, interner, &m.steps, &m.vars);
            out.push('\n');
        }
    }
    if !kb.resources.is_empty() {
        out.push_str("% resources\n");
        for r in &kb.resources {
            out.push_str("resources ");
            write_named(&mut out, interner, &r.template.term, &r.vars, 999);
            out.push('\n');
        }
    }
    out.push_str("% problems\n");
    for p in &kb.problems {
        let _ = write!(out, "problem {}", interner.resolve(p.name));
        if let Some(depth) = p.max_depth {
            let _ = write!(out, " max_depth={depth}");
        }
        out.push_str("\n  init: ");
        write_literals(&mut out, interner, &p.init, &p.vars);
        out.push_str("\n  goal: ");
        write_literals(&mut out, interner, &p.goal, &p.vars);
        out.push('\n');
    }
    out.push_str("% static clauses\n");
    for clause in &kb.clauses {
        write_named(&mut out, interner, &clause.head.term, &clause.vars, 1199);
        if let Some(body) = &clause.body {
            out.push_str(" :- ");
            write_goal(&mut out, interner, body, &clause.vars);
        }
        end_clause(&mut out);
    }
    out
}

/// Checks the HIR's invariants; a failure is a compiler bug, reported as an internal error.
///
/// Invariants: every variable id is in its item's table; every span lies in one known file
/// with `start <= end`; literals are callable; an action's snap kind agrees with its name's
/// suffix; a problem's init is ground.
pub fn verify(kb: &Kb, files: usize) -> Result<(), String> {
    fn check_span(span: Span, files: usize, what: &str) -> Result<(), String> {
        if (span.file.0 as usize) < files && span.start <= span.end {
            Ok(())
        } else {
            Err(format!("{what}: bad span {span:?}"))
        }
    }
    fn check_term(term: &Term, vars: &VarTable, what: &str) -> Result<(), String> {
        let mut bad = None;
        term.for_each_var(&mut |v| {
            if v.0 as usize >= vars.len() {
                bad = Some(v);
            }
        });
        match bad {
            Some(v) => Err(format!("{what}: variable {v:?} outside its table of {}", vars.len())),
            None => Ok(()),
        }
    }
    fn check_literal(l: &Literal, vars: &VarTable, files: usize, what: &str) -> Result<(), String> {
        if l.term.callable().is_none() {
            return Err(format!("{what}: literal is not callable"));
        }
        check_span(l.span, files, what)?;
        check_term(&l.term, vars, what)
    }
    fn has_empty_or(g: &Goal) -> bool {
        match g {
            Goal::Call(_) => false,
            Goal::And(goals) => goals.iter().any(has_empty_or),
            Goal::Or(branches) => {
                branches.is_empty()
                    || branches.iter().any(|b| b.conditions.iter().any(has_empty_or) || has_empty_or(&b.goal))
            }
            Goal::Not(g) => has_empty_or(g),
            Goal::Meta(_) => false,
        }
    }
    fn check_goal(g: &Goal, vars: &VarTable, files: usize, what: &str) -> Result<(), String> {
        if has_empty_or(g) {
            return Err(format!("{what}: a disjunction without branches"));
        }
        let mut result = Ok(());
        g.for_each_call(&mut |l| {
            if result.is_ok() {
                result = check_literal(l, vars, files, what);
            }
        });
        result
    }
    for (i, a) in kb.actions.iter().enumerate() {
        let what = format!("action #{i}");
        check_span(a.span, files, &what)?;
        check_literal(&a.name, &a.vars, files, &what)?;
        for l in a.valid.iter().chain(&a.invalid).chain(&a.invalid_at_end) {
            check_literal(l, &a.vars, files, &what)?;
        }
        for g in &a.on_kb {
            check_goal(g, &a.vars, files, &what)?;
        }
        for e in &a.effects {
            check_literal(&e.literal, &a.vars, files, &what)?;
        }
    }
    for (i, c) in kb.clauses.iter().enumerate() {
        let what = format!("clause #{i}");
        check_span(c.span, files, &what)?;
        check_literal(&c.head, &c.vars, files, &what)?;
        if let Some(body) = &c.body {
            check_goal(body, &c.vars, files, &what)?;
        }
    }
    for (i, p) in kb.problems.iter().enumerate() {
        let what = format!("problem #{i}");
        check_span(p.span, files, &what)?;
        for l in &p.goal {
            check_literal(l, &p.vars, files, &what)?;
        }
        for l in &p.init {
            check_literal(l, &p.vars, files, &what)?;
            if !l.term.is_ground() {
                return Err(format!("{what}: init literal is not ground"));
            }
        }
    }
    for (i, m) in kb.mappings.iter().enumerate() {
        let what = format!("mapping #{i}");
        check_literal(&m.high, &m.vars, files, &what)?;
        for l in &m.steps {
            check_literal(l, &m.vars, files, &what)?;
        }
    }
    Ok(())
}

/// Checks that each action's snap kind and base name agree with its name; needs the interner.
pub fn verify_names(kb: &Kb, interner: &Interner) -> Result<(), String> {
    for a in &kb.actions {
        let name = interner.resolve(a.name.name());
        let base = interner.resolve(a.base);
        let ok = match a.snap {
            Snap::Start => name.strip_suffix("_start") == Some(base),
            Snap::End => name.strip_suffix("_end") == Some(base),
            Snap::Instant => name == base,
        };
        if !ok {
            return Err(format!("action `{name}` has base `{base}` and snap {:?}", a.snap));
        }
    }
    Ok(())
}
