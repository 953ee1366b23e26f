//! The Prolog resolution engine: proves OnKB goals, `duration/3` and the KB's rules.
//!
//! SLD resolution with clause order, backtracking and cut, over a program compiled from the
//! HIR's static clauses, the library predicates they call (std/library.pl, `Kb::library`)
//! and, while planning a problem, the facts of its goal. The built-ins are those of
//! `crate::builtins`: control, unification and arithmetic in [`Machine::step`]'s dispatch,
//! the rest as natives (`native.rs`: type tests, the standard order of terms, `findall/3`,
//! `call/N`, `length/2`, sorting, ...), found through the predicate table like any predicate
//! so that a KB's own definition of a library predicate replaces the native one.
//!
//! # Design
//!
//! Terms live in one heap of [`Cell`]s, as in the WAM: a variable is a cell that refers to
//! itself until bound, a compound is a `Functor` header followed by its arguments. Clauses are
//! stored as position-independent cell templates and copied onto the heap when used (structure
//! copying), which renames their variables. Bindings are trailed; a choicepoint records the
//! heap, trail and continuation lengths, and backtracking truncates all three, so nothing is
//! allocated per goal. The continuation (the goals still to prove) is a linked list stored in a
//! vector, shared by choicepoints and truncated on backtracking too.
//!
//! Every query runs under a step budget: running out is an [`EngineError`], which callers
//! turn into a diagnostic, never a hang.

mod arith;
mod native;

use rustc_hash::FxHashMap;

use crate::builtins::{self, Native};
use crate::intern::{Interner, Symbol, sym};
use crate::ir::hir::{self, Goal, Kb, Literal, Term, VarId};

/// One heap cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cell {
    /// A reference to heap cell `i`; the cell at `i` refers to itself when unbound.
    Ref(u32),
    /// An atom.
    Atom(Symbol),
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A string.
    Str(Symbol),
    /// A compound whose header is at heap index `i`.
    Struct(u32),
    /// A compound's header: functor and arity; the arguments follow it.
    Functor(Symbol, u32),
}

/// Why a query stopped without finishing.
#[derive(Clone, Debug, PartialEq)]
pub enum EngineError {
    /// The step budget ran out.
    Budget {
        /// The budget that ran out.
        steps: u64,
    },
    /// A goal or arithmetic needed a bound value and found a variable.
    Instantiation {
        /// What needed it, e.g. "`is/2`".
        context: String,
    },
    /// A value of the wrong type, e.g. an atom in arithmetic.
    Type {
        /// What was expected, e.g. "a number".
        expected: &'static str,
        /// The value found instead.
        found: Term,
    },
    /// Arithmetic whose result cannot be represented (an integer overflow, say).
    Evaluation {
        /// What went wrong.
        message: String,
    },
    /// Division by zero.
    ZeroDivisor,
    /// A goal that is not callable (a number, say).
    NotCallable {
        /// The goal.
        found: Term,
    },
    /// A value of the right type outside the values allowed, e.g. a negative length.
    Domain {
        /// What was expected, e.g. "a non-negative integer".
        expected: &'static str,
        /// The value found instead.
        found: Term,
    },
    /// `findall/3` and the other predicates that collect solutions nested deeper than the
    /// engine allows.
    Nesting,
}

impl EngineError {
    /// The error as a sentence, with terms printed by name.
    pub fn message(&self, interner: &Interner) -> String {
        let show = |term: &Term| hir::term_to_string(interner, term, &hir::VarTable::default());
        match self {
            EngineError::Budget { steps } => format!("the query ran out of its budget of {steps} resolution steps"),
            EngineError::Instantiation { context } => format!("{context} needs a bound value but found a variable"),
            EngineError::Type { expected, found } => format!("expected {expected}, found `{}`", show(found)),
            EngineError::Evaluation { message } => message.clone(),
            EngineError::ZeroDivisor => "division by zero".to_string(),
            EngineError::NotCallable { found } => format!("`{}` cannot be called as a goal", show(found)),
            EngineError::Domain { expected, found } => format!("expected {expected}, found `{}`", show(found)),
            EngineError::Nesting => {
                format!("calls that collect solutions (`findall/3`, ...) nested more than {MAX_COLLECTORS} deep")
            }
        }
    }
}

/// A clause compiled to a cell template: `nvars` variable cells first, then the head and
/// body. `Ref` and `Struct` indices are relative to the template's start.
#[derive(Clone, Debug)]
struct ClauseTemplate {
    cells: Vec<Cell>,
    head: Cell,
    /// The body, or `None` for a fact.
    body: Option<Cell>,
}

/// The first-argument key used to skip clauses that cannot match.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum IndexKey {
    Atom(Symbol),
    Int(i64),
    Float(u64),
    Str(Symbol),
    Functor(Symbol, u32),
}

/// A predicate's clauses, in order, with an index on each argument: the first built as the
/// clauses are added, the others when a call first needs them.
#[derive(Clone, Debug, Default)]
struct Predicate {
    clauses: Vec<u32>,
    first: ArgIndex,
    /// The indexes on the second argument onwards (position - 1), built on first use: a call
    /// whose first argument is unbound is narrowed by another bound argument (as SWI-Prolog's
    /// just-in-time indexes do). std/blocks.pl asks `\+ on(_, _, X, Y)` of every cell, once
    /// for each block, over the goal's 100 `on/4` facts of a 100-block rung.
    others: Vec<std::cell::OnceCell<ArgIndex>>,
    /// The native that implements it, for a built-in the engine runs in Rust (then it has no
    /// clauses).
    native: Option<Native>,
}

impl Predicate {
    /// A predicate of `arity` arguments, with no clauses yet.
    fn new(arity: u32) -> Predicate {
        Predicate { others: (1..arity).map(|_| std::cell::OnceCell::new()).collect(), ..Predicate::default() }
    }
}

/// A predicate's clauses by the key of their argument at one position.
#[derive(Clone, Debug, Default)]
struct ArgIndex {
    /// For each key, the clauses whose argument there has that key or is a variable, in
    /// clause order.
    by_key: FxHashMap<IndexKey, Vec<u32>>,
    /// The clauses whose argument there is a variable, in order (for keys not in `by_key`).
    var_at: Vec<u32>,
}

impl ArgIndex {
    /// Adds clause `id`, whose argument at this position has `key` (None: a variable).
    fn add(&mut self, id: u32, key: Option<IndexKey>) {
        match key {
            Some(key) => {
                if !self.by_key.contains_key(&key) {
                    // A new key starts with every earlier variable clause, in order.
                    let earlier = self.var_at.clone();
                    self.by_key.insert(key, earlier);
                }
                self.by_key.get_mut(&key).expect("inserted above").push(id);
            }
            None => {
                self.var_at.push(id);
                for list in self.by_key.values_mut() {
                    list.push(id);
                }
            }
        }
    }

    /// The clauses a call whose argument here has `key` may match.
    fn list(&self, key: &IndexKey) -> &[u32] {
        self.by_key.get(key).map_or(&self.var_at[..], |l| &l[..])
    }
}

/// Fewer clauses than this are tried in turn rather than looked up by an argument after the
/// first. (A guess, not measured against other values: below it, building and asking an
/// index buys at most a few failed head unifications.)
const INDEX_OTHERS_FROM: usize = 8;

/// A compiled program: the static KB.
#[derive(Clone, Debug, Default)]
pub struct Program {
    clauses: Vec<ClauseTemplate>,
    predicates: FxHashMap<(Symbol, u32), Predicate>,
    /// The arithmetic functions beyond those of the `sym` module, by name and arity.
    functions: FxHashMap<(Symbol, u32), arith::Function>,
    /// Each symbol's rank in the standard order of atoms (their text, character by
    /// character), for the comparisons that need it; empty when nothing in the program can
    /// compare atoms (see [`Program::new`]).
    rank: Box<[u32]>,
    /// The symbol of `infinite`, which `between/3` takes for `inf`, if the session has one.
    infinite: Option<Symbol>,
    /// The types `must_be/2` knows, by the symbols of their names and their arities.
    types: FxHashMap<(Symbol, u32), TypeName>,
}

/// A type `must_be/2` checks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TypeName {
    Integer,
    PositiveInteger,
    Nonneg,
    Atom,
    Atomic,
    Callable,
    Var,
    Boolean,
    List,
    Number,
    Float,
    Compound,
    Ground,
    OneOf,
}

/// Converts HIR terms into cell templates.
struct TemplateBuilder {
    cells: Vec<Cell>,
}

impl TemplateBuilder {
    fn new(nvars: usize) -> TemplateBuilder {
        TemplateBuilder { cells: (0..nvars as u32).map(Cell::Ref).collect() }
    }

    fn term(&mut self, term: &Term) -> Cell {
        match term {
            Term::Var(v) => Cell::Ref(v.0),
            Term::Atom(s) => Cell::Atom(*s),
            Term::Int(i) => Cell::Int(*i),
            Term::Float(f) => Cell::Float(*f),
            Term::Str(s) => Cell::Str(*s),
            Term::Compound(f, args) => {
                let cells: Vec<Cell> = args.iter().map(|a| self.term(a)).collect();
                self.compound(*f, &cells)
            }
        }
    }

    fn compound(&mut self, functor: Symbol, args: &[Cell]) -> Cell {
        let at = self.cells.len() as u32;
        self.cells.push(Cell::Functor(functor, args.len() as u32));
        self.cells.extend_from_slice(args);
        Cell::Struct(at)
    }

    fn goal(&mut self, goal: &Goal) -> Cell {
        goal_term(self, goal)
    }
}

impl GoalBuilder for TemplateBuilder {
    fn call(&mut self, term: &Term) -> Cell {
        self.term(term)
    }

    fn compound(&mut self, functor: Symbol, args: &[Cell]) -> Cell {
        TemplateBuilder::compound(self, functor, args)
    }
}

/// Where a goal's control term is built: a clause template, or the machine's heap.
trait GoalBuilder {
    /// The term of a called literal.
    fn call(&mut self, term: &Term) -> Cell;
    /// A compound of `args`.
    fn compound(&mut self, functor: Symbol, args: &[Cell]) -> Cell;
}

/// A goal as the control term Prolog reads: `','/2`, `;/2` and `->/2` nested to the right,
/// `\+/1`, and the literals' terms, built left to right (the order variables are met in).
fn goal_term(builder: &mut impl GoalBuilder, goal: &Goal) -> Cell {
    match goal {
        Goal::Call(literal) => builder.call(&literal.term),
        Goal::And(goals) => {
            let mut cells: Vec<Cell> = goals.iter().map(|g| goal_term(builder, g)).collect();
            let last = cells.pop().unwrap_or(Cell::Atom(sym::TRUE));
            nest_right(builder, sym::COMMA, cells, last)
        }
        Goal::Or(branches) => {
            let mut cells: Vec<Cell> = branches
                .iter()
                .map(|branch| {
                    let conditions: Vec<Cell> = branch.conditions.iter().map(|c| goal_term(builder, c)).collect();
                    let goal = goal_term(builder, &branch.goal);
                    nest_right(builder, sym::ARROW, conditions, goal)
                })
                .collect();
            let last = cells.pop().expect("a disjunction has a branch");
            nest_right(builder, sym::SEMI, cells, last)
        }
        Goal::Not(g) => {
            let g = goal_term(builder, g);
            builder.compound(sym::NOT_PROVABLE, &[g])
        }
        Goal::Meta(meta) => builder.call(&meta.call.term),
    }
}

/// `op(b1, op(b2, ... op(bn, last)))` for `before` = b1 ... bn.
fn nest_right(builder: &mut impl GoalBuilder, op: Symbol, before: Vec<Cell>, last: Cell) -> Cell {
    before.into_iter().rev().fold(last, |nested, left| builder.compound(op, &[left, nested]))
}

/// The machine's heap as a [`GoalBuilder`], with the query's variables.
struct OnHeap<'m, 'p, 'v> {
    machine: &'m mut Machine<'p>,
    vars: &'v mut [Option<Cell>],
}

impl GoalBuilder for OnHeap<'_, '_, '_> {
    fn call(&mut self, term: &Term) -> Cell {
        self.machine.put_term(term, self.vars)
    }

    fn compound(&mut self, functor: Symbol, args: &[Cell]) -> Cell {
        self.machine.new_compound(functor, args)
    }
}

fn index_key(cells: &[Cell], cell: Cell) -> Option<IndexKey> {
    match cell {
        Cell::Atom(s) => Some(IndexKey::Atom(s)),
        Cell::Int(i) => Some(IndexKey::Int(i)),
        Cell::Float(f) => Some(IndexKey::Float(f.to_bits())),
        Cell::Str(s) => Some(IndexKey::Str(s)),
        Cell::Struct(at) => match cells[at as usize] {
            Cell::Functor(f, n) => Some(IndexKey::Functor(f, n)),
            _ => None,
        },
        _ => None,
    }
}

impl Program {
    /// The program of a KB's static clauses, plus `extra_facts` (a problem's goal literals,
    /// which OnKB goals may ask about), plus the library predicates the KB calls
    /// (`Kb::library`) and `member/2`, each unless the KB or the extra facts define it, plus
    /// the natives of `crate::builtins` (a library native only where nothing defines it).
    ///
    /// The standard order of atoms is computed (from `interner`, every name the session has
    /// seen) only if the program can compare atoms ([`Program::compares_atoms`]).
    pub fn new(kb: &Kb, interner: &Interner, extra_facts: &[(&Literal, &hir::VarTable)]) -> Program {
        let mut program = Program::default();
        let compile = |program: &mut Program, clause: &hir::Clause| {
            let mut builder = TemplateBuilder::new(clause.vars.len());
            let head = builder.term(&clause.head.term);
            let body = clause.body.as_deref().map(|b| builder.goal(b));
            program.add(ClauseTemplate { cells: builder.cells, head, body });
        };
        for clause in &kb.clauses {
            compile(&mut program, clause);
        }
        // (`passes::library` has left out the predicates a problem's goal facts define.)
        for clause in &kb.library {
            compile(&mut program, clause);
        }
        for (literal, vars) in extra_facts {
            let mut builder = TemplateBuilder::new(vars.len());
            let head = builder.term(&literal.term);
            program.add(ClauseTemplate { cells: builder.cells, head, body: None });
        }
        if !program.predicates.contains_key(&(sym::MEMBER, 2)) {
            program.add_member();
        }
        for builtin in builtins::PREDICATES {
            let builtins::Imp::Native(native) = builtin.imp else { continue };
            let Some(name) = interner.get(builtin.name) else { continue };
            let key = (name, builtin.arity as u32);
            let defined = program.predicates.get(&key).is_some_and(|p| !p.clauses.is_empty());
            if builtin.kind == builtins::Kind::Library && defined {
                continue;
            }
            program.predicates.entry(key).or_insert_with(|| Predicate::new(key.1)).native = Some(native);
        }
        program.functions = arith::functions(interner);
        if program.compares_atoms(kb, interner) {
            let mut symbols: Vec<u32> = (0..interner.len() as u32).collect();
            symbols.sort_by(|&a, &b| interner.resolve(Symbol(a)).cmp(interner.resolve(Symbol(b))));
            let mut rank = vec![0; symbols.len()];
            for (position, symbol) in symbols.into_iter().enumerate() {
                rank[symbol as usize] = position as u32;
            }
            program.rank = rank.into_boxed_slice();
        }
        program.infinite = interner.get("infinite");
        const TYPES: &[(&str, u32, TypeName)] = &[
            ("integer", 0, TypeName::Integer),
            ("positive_integer", 0, TypeName::PositiveInteger),
            ("nonneg", 0, TypeName::Nonneg),
            ("atom", 0, TypeName::Atom),
            ("atomic", 0, TypeName::Atomic),
            ("callable", 0, TypeName::Callable),
            ("var", 0, TypeName::Var),
            ("boolean", 0, TypeName::Boolean),
            ("list", 0, TypeName::List),
            ("proper_list", 0, TypeName::List),
            ("number", 0, TypeName::Number),
            ("float", 0, TypeName::Float),
            ("compound", 0, TypeName::Compound),
            ("ground", 0, TypeName::Ground),
            ("oneof", 1, TypeName::OneOf),
        ];
        program.types = TYPES.iter().filter_map(|&(n, a, t)| Some(((interner.get(n)?, a), t))).collect();
        program
    }

    /// True if a term the engine can meet names a built-in that compares atoms
    /// (`Reads::Names`: `compare/3`, `@<`, `msort/2`, ...): one of the program's clauses (the
    /// library's and the goal facts included), an OnKB goal, or a problem's fact (an OnKB goal
    /// may call a name it binds from the state). The engine makes no atoms, so no call reaches
    /// such a built-in without its name written in one of these.
    fn compares_atoms(&self, kb: &Kb, interner: &Interner) -> bool {
        let names: rustc_hash::FxHashSet<Symbol> = builtins::PREDICATES
            .iter()
            .filter(|b| b.reads == builtins::Reads::Names)
            .filter_map(|b| interner.get(b.name))
            .collect();
        let in_cells = self.clauses.iter().flat_map(|c| &c.cells).any(|cell| match *cell {
            Cell::Atom(s) | Cell::Functor(s, _) => names.contains(&s),
            _ => false,
        });
        let names_it = |term: &Term| {
            let mut pending = vec![term];
            while let Some(term) = pending.pop() {
                match term {
                    Term::Atom(s) if names.contains(s) => return true,
                    Term::Compound(f, _) if names.contains(f) => return true,
                    Term::Compound(_, args) => pending.extend(args.iter()),
                    _ => {}
                }
            }
            false
        };
        in_cells
            || kb.actions.iter().any(|a| {
                let mut found = false;
                a.on_kb.iter().for_each(|g| g.for_each_call(&mut |l| found |= names_it(&l.term)));
                found
            })
            || kb.problems.iter().any(|p| p.initial_facts().chain(&p.goal).any(|l| names_it(&l.term)))
    }

    /// The rank of `symbol` in the standard order of atoms: symbols named after the program
    /// was made come after every other, in the order they were named.
    fn rank(&self, symbol: Symbol) -> u64 {
        match self.rank.get(symbol.0 as usize) {
            Some(&rank) => rank as u64,
            None => self.rank.len() as u64 + symbol.0 as u64,
        }
    }

    /// `member(X, [X|_]).` and `member(X, [_|T]) :- member(X, T).`
    fn add_member(&mut self) {
        let mut first = TemplateBuilder::new(2);
        let list = first.compound(sym::CONS, &[Cell::Ref(0), Cell::Ref(1)]);
        let head = first.compound(sym::MEMBER, &[Cell::Ref(0), list]);
        self.add(ClauseTemplate { cells: first.cells, head, body: None });
        let mut second = TemplateBuilder::new(3);
        let list = second.compound(sym::CONS, &[Cell::Ref(1), Cell::Ref(2)]);
        let head = second.compound(sym::MEMBER, &[Cell::Ref(0), list]);
        let body = second.compound(sym::MEMBER, &[Cell::Ref(0), Cell::Ref(2)]);
        self.add(ClauseTemplate { cells: second.cells, head, body: Some(body) });
    }

    fn add(&mut self, clause: ClauseTemplate) {
        let (name, arity, first) = match clause.head {
            Cell::Atom(s) => (s, 0, None),
            Cell::Struct(at) => match clause.cells[at as usize] {
                Cell::Functor(f, n) => (f, n, (n > 0).then(|| clause.cells[at as usize + 1])),
                _ => return,
            },
            _ => return,
        };
        let id = self.clauses.len() as u32;
        let key = first.and_then(|c| index_key(&clause.cells, c));
        self.clauses.push(clause);
        let predicate = self.predicates.entry((name, arity)).or_insert_with(|| Predicate::new(arity));
        predicate.clauses.push(id);
        predicate.first.add(id, key);
    }

    /// The index of `predicate` on argument `position` (from 1; 0 is `first`), built from its
    /// clauses the first time it is asked for.
    fn index_at<'a>(&'a self, predicate: &'a Predicate, position: usize) -> &'a ArgIndex {
        predicate.others[position - 1].get_or_init(|| {
            let mut index = ArgIndex::default();
            for &id in &predicate.clauses {
                let clause = &self.clauses[id as usize];
                let key = match clause.head {
                    Cell::Struct(at) => index_key(&clause.cells, clause.cells[at as usize + 1 + position]),
                    _ => None,
                };
                index.add(id, key);
            }
            index
        })
    }

    /// True if the program has clauses for `name/arity`.
    pub fn defines(&self, name: Symbol, arity: usize) -> bool {
        self.predicates.get(&(name, arity as u32)).is_some_and(|p| !p.clauses.is_empty())
    }

    /// The number of clauses of `name/arity`.
    pub fn clause_count(&self, name: Symbol, arity: usize) -> usize {
        self.predicates.get(&(name, arity as u32)).map_or(0, |p| p.clauses.len())
    }

    /// True if `name/arity` has clauses and every one is a fact: calling it only matches
    /// clause heads, so it has a solution with some arguments bound only if it has one
    /// that agrees with them when they are left unbound.
    pub fn facts_only(&self, name: Symbol, arity: usize) -> bool {
        self.predicates.get(&(name, arity as u32)).is_some_and(|p| {
            !p.clauses.is_empty() && p.clauses.iter().all(|&c| self.clauses[c as usize].body.is_none())
        })
    }
}

/// What to do after a solution.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Next {
    /// Look for another solution.
    More,
    /// Stop: this one is enough.
    Stop,
}

/// How a query ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every solution was produced.
    Exhausted,
    /// The caller stopped after a solution.
    Stopped,
}

/// A goal still to prove, in the continuation list.
#[derive(Clone, Copy, Debug)]
struct Cont {
    goal: Cell,
    /// The choicepoint height a `!` in this goal cuts back to.
    cut: u32,
    /// The rest of the continuation (`NIL` at the end).
    next: u32,
}

const NIL: u32 = u32::MAX;

/// What a choicepoint retries.
#[derive(Clone, Copy, Debug)]
enum Alternative {
    /// The remaining clauses of a call: the goal, its clause list, the next position in it.
    Clauses { goal: Cell, predicate: (Symbol, u32), key: Option<(u32, IndexKey)>, next: u32, cut: u32 },
    /// The other branch of a disjunction.
    Goal { goal: Cell, cut: u32 },
    /// The end of a `findall/3` goal's solutions: make the list of what `collectors[frame]`
    /// holds, ending in `tail`, and unify it with `list`.
    Collected { frame: u32, list: Cell, tail: Cell },
}

#[derive(Clone, Copy, Debug)]
struct Choicepoint {
    alternative: Alternative,
    /// The continuation to resume with.
    cont: u32,
    heap: u32,
    trail: u32,
    conts: u32,
    /// How many `dif/2` constraints were pending.
    difs: u32,
}

/// A special goal: cut back to the given choicepoint height (if-then-else, negation).
const CUT_TO: Symbol = Symbol(u32::MAX - 1);
/// A special goal of `findall/3`: `COLLECT(Frame, Template)` copies the template into a
/// collector and fails.
const COLLECT: Symbol = Symbol(u32::MAX - 2);
/// A special goal of `arg/3` with an unbound position: `ARG_FROM(K, N, Term, Arg)` gives the
/// arguments from position K on.
const ARG_FROM: Symbol = Symbol(u32::MAX - 3);
/// A special goal of `length/2` on a partial list and an unbound length:
/// `LENGTH_FROM(Tail, K, N)` gives the lengths from K on.
const LENGTH_FROM: Symbol = Symbol(u32::MAX - 4);

/// How deep calls that collect solutions may nest. Nothing of theirs is on the Rust stack,
/// but each level holds a collector and a choicepoint, and a recursion through `findall/3`
/// (`p :- findall(x, p, _).`) would grow them with every step the budget allows: bounding the
/// depth makes it an error at once.
pub const MAX_COLLECTORS: usize = 10_000;

/// The solutions a `findall/3` has collected so far: copies of its template, in cells that
/// refer to one another by their index in `cells`, as clause templates do.
#[derive(Clone, Debug, Default)]
struct Collector {
    cells: Vec<Cell>,
    roots: Vec<Cell>,
}

/// An abstract machine that proves queries against a [`Program`].
pub struct Machine<'p> {
    program: &'p Program,
    heap: Vec<Cell>,
    trail: Vec<u32>,
    conts: Vec<Cont>,
    choicepoints: Vec<Choicepoint>,
    steps: u64,
    budget: u64,
    /// Whether a unification of the current query failed by the occurs check alone.
    occurs_failed: bool,
    /// Whether a unification of the current query failed only because it made the terms of a
    /// pending `dif/2` identical.
    dif_failed: bool,
    /// Scratch space for [`Machine::unify`]'s pairs still to unify.
    unify_pending: Vec<(Cell, Cell)>,
    /// The solutions of the `findall/3` calls under way, innermost last.
    collectors: Vec<Collector>,
    /// The `dif/2` constraints whose terms could still become identical, oldest first: each
    /// unification that succeeds checks them again ([`Machine::difs_hold`]), and fails if it
    /// made one identical. Backtracking drops those added since the choicepoint; one found to
    /// hold for good stays (it keeps holding, terms only ever get more bound).
    difs: Vec<(Cell, Cell)>,
}

impl<'p> Machine<'p> {
    /// A machine over `program`; each query may take up to `budget` resolution steps.
    pub fn new(program: &'p Program, budget: u64) -> Machine<'p> {
        Machine {
            program,
            heap: Vec::new(),
            trail: Vec::new(),
            conts: Vec::new(),
            choicepoints: Vec::new(),
            steps: 0,
            budget,
            occurs_failed: false,
            dif_failed: false,
            unify_pending: Vec::new(),
            collectors: Vec::new(),
            difs: Vec::new(),
        }
    }

    /// Whether some unification since the last [`Machine::reset`] failed only by the occurs
    /// check (a variable against a term containing it, `X = f(X)`), where SWI-Prolog would
    /// have made a cyclic term and gone on: diagnostics say so when a proof fails.
    pub fn occurs_check_failed(&self) -> bool {
        self.occurs_failed
    }

    /// Whether some unification since the last [`Machine::reset`] failed only because its
    /// bindings made the two terms of a pending `dif/2` identical: diagnostics name the
    /// constraint, not the goal whose proof it stopped, as the reason.
    pub fn dif_check_failed(&self) -> bool {
        self.dif_failed
    }

    /// The program the machine runs.
    pub fn program(&self) -> &'p Program {
        self.program
    }

    /// Clears the heap and every other stack, for a new query.
    pub fn reset(&mut self) {
        self.heap.clear();
        self.trail.clear();
        self.conts.clear();
        self.choicepoints.clear();
        self.collectors.clear();
        self.difs.clear();
        self.steps = 0;
        self.occurs_failed = false;
        self.dif_failed = false;
    }

    /// The steps the last query took.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// A fresh unbound variable.
    pub fn new_var(&mut self) -> Cell {
        let at = self.heap.len() as u32;
        self.heap.push(Cell::Ref(at));
        Cell::Ref(at)
    }

    /// A compound built from already-placed argument cells.
    pub fn new_compound(&mut self, functor: Symbol, args: &[Cell]) -> Cell {
        let at = self.heap.len() as u32;
        self.heap.push(Cell::Functor(functor, args.len() as u32));
        self.heap.extend_from_slice(args);
        Cell::Struct(at)
    }

    /// Places a HIR term on the heap; `vars` maps its variables to cells, creating fresh ones
    /// for those still `None`.
    pub fn put_term(&mut self, term: &Term, vars: &mut [Option<Cell>]) -> Cell {
        match term {
            Term::Var(v) => match vars.get(v.0 as usize).copied().flatten() {
                Some(cell) => cell,
                None => {
                    let cell = self.new_var();
                    if let Some(slot) = vars.get_mut(v.0 as usize) {
                        *slot = Some(cell);
                    }
                    cell
                }
            },
            Term::Atom(s) => Cell::Atom(*s),
            Term::Int(i) => Cell::Int(*i),
            Term::Float(f) => Cell::Float(*f),
            Term::Str(s) => Cell::Str(*s),
            Term::Compound(f, args) => {
                let cells: Vec<Cell> = args.iter().map(|a| self.put_term(a, vars)).collect();
                self.new_compound(*f, &cells)
            }
        }
    }

    /// Places the conjunction of `goals` on the heap (`true` for none), as
    /// [`Machine::put_goal`] places one: how an action's OnKB list is asked.
    pub fn put_conjunction(&mut self, goals: &[Goal], vars: &mut [Option<Cell>]) -> Cell {
        let mut conjunction = Cell::Atom(sym::TRUE);
        for goal in goals.iter().rev() {
            let cell = self.put_goal(goal, vars);
            conjunction = if conjunction == Cell::Atom(sym::TRUE) {
                cell
            } else {
                self.new_compound(sym::COMMA, &[cell, conjunction])
            };
        }
        conjunction
    }

    /// Places a goal on the heap, as [`Machine::put_term`] does for terms.
    pub fn put_goal(&mut self, goal: &Goal, vars: &mut [Option<Cell>]) -> Cell {
        goal_term(&mut OnHeap { machine: self, vars }, goal)
    }

    /// Follows variable bindings to the cell a term stands for.
    pub fn deref(&self, mut cell: Cell) -> Cell {
        while let Cell::Ref(at) = cell {
            let bound = self.heap[at as usize];
            if bound == Cell::Ref(at) {
                return cell;
            }
            cell = bound;
        }
        cell
    }

    /// The functor and arguments of a compound cell (after deref), or `None`.
    pub fn compound(&self, cell: Cell) -> Option<(Symbol, &[Cell])> {
        match self.deref(cell) {
            Cell::Struct(at) => match self.heap[at as usize] {
                Cell::Functor(f, n) => Some((f, &self.heap[at as usize + 1..at as usize + 1 + n as usize])),
                _ => None,
            },
            _ => None,
        }
    }

    /// Reads a cell back as a HIR term; unbound variables become variables numbered by first
    /// occurrence (their table is `vars`).
    pub fn read(&self, cell: Cell, vars: &mut Vec<u32>) -> Term {
        match self.deref(cell) {
            Cell::Ref(at) => {
                let index = vars.iter().position(|&v| v == at).unwrap_or_else(|| {
                    vars.push(at);
                    vars.len() - 1
                });
                Term::Var(VarId(index as u32))
            }
            Cell::Atom(s) => Term::Atom(s),
            Cell::Int(i) => Term::Int(i),
            Cell::Float(f) => Term::Float(f),
            Cell::Str(s) => Term::Str(s),
            Cell::Struct(_) => {
                let (f, args) = self.compound(cell).expect("a struct cell points at a functor");
                let args: Vec<Cell> = args.to_vec();
                Term::Compound(f, args.iter().map(|a| self.read(*a, vars)).collect())
            }
            Cell::Functor(..) => Term::Atom(sym::ANON),
        }
    }

    fn bind(&mut self, var: u32, value: Cell) {
        self.heap[var as usize] = value;
        self.trail.push(var);
    }

    /// Whether the variable `var` occurs in the term `cell` (iteratively: terms may be deep).
    fn occurs(&self, var: u32, cell: Cell) -> bool {
        let mut pending = vec![cell];
        while let Some(cell) = pending.pop() {
            match self.deref(cell) {
                Cell::Ref(x) if x == var => return true,
                Cell::Struct(x) => {
                    if let Cell::Functor(_, n) = self.heap[x as usize] {
                        pending.extend((1..=n).map(|i| self.heap[(x + i) as usize]));
                    }
                }
                _ => {}
            }
        }
        false
    }

    /// Unifies two cells, recording bindings on the trail, with the occurs check (as
    /// `unify_with_occurs_check/2`): a variable never binds to a term that contains it, so
    /// `X = f(X)` fails and no term is cyclic (SWI-Prolog would make a rational tree; kbc's
    /// comparison, copying and printing need not handle one).
    pub fn unify(&mut self, a: Cell, b: Cell) -> bool {
        let mut pending = std::mem::take(&mut self.unify_pending);
        pending.clear();
        pending.push((a, b));
        let unified = self.unify_pairs(&mut pending);
        self.unify_pending = pending;
        if !unified || self.difs.is_empty() || self.difs_hold() {
            return unified;
        }
        self.dif_failed = true;
        false
    }

    /// Whether `a` and `b` could unify, leaving nothing bound (nor the occurs-check flag set).
    pub(super) fn unifiable(&mut self, a: Cell, b: Cell) -> bool {
        let (mark, occurs) = (self.trail.len() as u32, self.occurs_failed);
        let mut pending = std::mem::take(&mut self.unify_pending);
        pending.clear();
        pending.push((a, b));
        let unifies = self.unify_pairs(&mut pending);
        self.unify_pending = pending;
        self.undo_to(mark);
        self.occurs_failed = occurs;
        unifies
    }

    /// Whether every pending `dif/2` constraint still holds: no two of its terms are identical
    /// after the bindings made since it was checked. (Kept, whether they could still unify or
    /// not: a constraint is rarely pending and the list is short.)
    fn difs_hold(&self) -> bool {
        self.difs.iter().all(|&(a, b)| !self.identical(a, b))
    }

    /// Unifies the pairs in `pending` (emptying it unless it fails).
    fn unify_pairs(&mut self, pending: &mut Vec<(Cell, Cell)>) -> bool {
        while let Some((a, b)) = pending.pop() {
            let a = self.deref(a);
            let b = self.deref(b);
            match (a, b) {
                (Cell::Ref(x), Cell::Ref(y)) => {
                    if x != y {
                        // Bind the younger variable to the older one.
                        if x < y { self.bind(y, a) } else { self.bind(x, b) }
                    }
                }
                (Cell::Ref(x), other) | (other, Cell::Ref(x)) => {
                    if matches!(other, Cell::Struct(_)) && self.occurs(x, other) {
                        self.occurs_failed = true;
                        return false;
                    }
                    self.bind(x, other)
                }
                (Cell::Struct(x), Cell::Struct(y)) => {
                    if x == y {
                        continue;
                    }
                    let (Cell::Functor(f, n), Cell::Functor(g, m)) = (self.heap[x as usize], self.heap[y as usize])
                    else {
                        return false;
                    };
                    if f != g || n != m {
                        return false;
                    }
                    for i in 1..=n {
                        pending.push((self.heap[(x + i) as usize], self.heap[(y + i) as usize]));
                    }
                }
                (Cell::Float(x), Cell::Float(y)) => {
                    if x.to_bits() != y.to_bits() {
                        return false;
                    }
                }
                (x, y) => {
                    if x != y {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// Standard-order identity (`==`): same structure, same variables.
    fn identical(&self, a: Cell, b: Cell) -> bool {
        let a = self.deref(a);
        let b = self.deref(b);
        match (a, b) {
            (Cell::Struct(_), Cell::Struct(_)) => {
                let (Some((f, xs)), Some((g, ys))) = (self.compound(a), self.compound(b)) else { return false };
                f == g && xs.len() == ys.len() && xs.iter().zip(ys).all(|(x, y)| self.identical(*x, *y))
            }
            (Cell::Float(x), Cell::Float(y)) => x.to_bits() == y.to_bits(),
            (x, y) => x == y,
        }
    }

    fn undo_to(&mut self, trail: u32) {
        while self.trail.len() as u32 > trail {
            let var = self.trail.pop().expect("checked length");
            self.heap[var as usize] = Cell::Ref(var);
        }
    }

    /// Copies a clause template onto the heap and returns its head and body.
    fn rename(&mut self, clause: u32) -> (Cell, Option<Cell>) {
        let template = &self.program.clauses[clause as usize];
        let offset = self.heap.len() as u32;
        self.heap.extend(template.cells.iter().map(|c| relocate(*c, offset)));
        (relocate(template.head, offset), template.body.map(|b| relocate(b, offset)))
    }

    fn push_goal(&mut self, goal: Cell, cut: u32, next: u32) -> u32 {
        self.conts.push(Cont { goal, cut, next });
        self.conts.len() as u32 - 1
    }

    /// Proves `goal`, calling `on_solution` for each solution in order until it returns
    /// [`Next::Stop`] or there are no more. Bindings are visible to `on_solution` (read them
    /// with [`Machine::deref`] and [`Machine::read`]); they are undone afterwards.
    pub fn solve(
        &mut self,
        goal: Cell,
        mut on_solution: impl FnMut(&Machine<'p>) -> Next,
    ) -> Result<Outcome, EngineError> {
        let base_choicepoints = self.choicepoints.len() as u32;
        let base_trail = self.trail.len() as u32;
        let base_collectors = self.collectors.len();
        let base_difs = self.difs.len();
        let mut current = self.push_goal(goal, base_choicepoints, NIL);
        let result = loop {
            if current == NIL {
                if on_solution(self) == Next::Stop {
                    break Ok(Outcome::Stopped);
                }
                match self.backtrack(base_choicepoints) {
                    Some(next) => {
                        current = next;
                        continue;
                    }
                    None => break Ok(Outcome::Exhausted),
                }
            }
            self.steps += 1;
            if self.steps > self.budget {
                break Err(EngineError::Budget { steps: self.budget });
            }
            let Cont { goal, cut, next } = self.conts[current as usize];
            match self.step(goal, cut, next) {
                Ok(Some(next)) => current = next,
                Ok(None) => match self.backtrack(base_choicepoints) {
                    Some(next) => current = next,
                    None => break Ok(Outcome::Exhausted),
                },
                Err(error) => break Err(error),
            }
        };
        self.choicepoints.truncate(base_choicepoints as usize);
        self.collectors.truncate(base_collectors);
        self.difs.truncate(base_difs);
        self.undo_to(base_trail);
        result
    }

    /// Resumes the youngest choicepoint above `base`; `None` when there is none.
    fn backtrack(&mut self, base: u32) -> Option<u32> {
        loop {
            if self.choicepoints.len() as u32 <= base {
                return None;
            }
            let index = self.choicepoints.len() - 1;
            let cp = self.choicepoints[index];
            self.undo_to(cp.trail);
            self.heap.truncate(cp.heap as usize);
            self.conts.truncate(cp.conts as usize);
            self.difs.truncate(cp.difs as usize);
            match cp.alternative {
                Alternative::Goal { goal, cut } => {
                    self.choicepoints.pop();
                    return Some(self.push_goal(goal, cut, cp.cont));
                }
                Alternative::Collected { frame, list, tail } => {
                    self.choicepoints.pop();
                    debug_assert_eq!(frame as usize + 1, self.collectors.len(), "collectors nest");
                    let collector = self.collectors.pop().unwrap_or_default();
                    let solutions = self.thaw(&collector);
                    let made = self.make_list(&solutions, tail);
                    if self.unify(list, made) {
                        return Some(cp.cont);
                    }
                }
                Alternative::Clauses { goal, predicate, key, next, cut } => {
                    let list = self.clause_list(predicate, key);
                    let Some(&clause) = list.get(next as usize) else {
                        self.choicepoints.pop();
                        continue;
                    };
                    if next as usize + 1 < list.len() {
                        if let Alternative::Clauses { next: slot, .. } = &mut self.choicepoints[index].alternative {
                            *slot = next + 1;
                        }
                    } else {
                        self.choicepoints.pop();
                    }
                    if let Some(resumed) = self.try_clause(goal, clause, cut, cp.cont) {
                        return Some(resumed);
                    }
                }
            }
        }
    }

    /// The clauses a call of `predicate` may match, by the key of its argument at a position
    /// (none: all of them).
    fn clause_list(&self, predicate: (Symbol, u32), key: Option<(u32, IndexKey)>) -> &'p [u32] {
        let program: &'p Program = self.program;
        let Some(p) = program.predicates.get(&predicate) else { return &[] };
        match key {
            Some((0, key)) => p.first.list(&key),
            Some((position, key)) => program.index_at(p, position as usize).list(&key),
            None => &p.clauses,
        }
    }

    /// The argument a call of `predicate` with `args` is looked up by, and the clauses it may
    /// match: by the first argument when it is bound (to an atom, a number, a string or a
    /// compound); else, where the predicate has enough clauses, by the bound argument with the
    /// fewest clauses to try (the leftmost among equals); else all of them, by none.
    #[cfg(test)]
    fn lookup(&self, predicate: (Symbol, u32), args: &[Cell]) -> (Option<(u32, IndexKey)>, &'p [u32]) {
        let program: &'p Program = self.program;
        let Some(p) = program.predicates.get(&predicate) else { return (None, &[]) };
        self.lookup_in(p, args)
    }

    /// [`Machine::lookup`] in the predicate's own entry.
    fn lookup_in(&self, p: &'p Predicate, args: &[Cell]) -> (Option<(u32, IndexKey)>, &'p [u32]) {
        let program: &'p Program = self.program;
        let key_at = |machine: &Self, at: usize| index_key(&machine.heap, machine.deref(args[at]));
        if let Some(key) = args.first().and_then(|_| key_at(self, 0)) {
            return (Some((0, key)), p.first.list(&key));
        }
        if p.clauses.len() < INDEX_OTHERS_FROM {
            return (None, &p.clauses);
        }
        let mut best: (Option<(u32, IndexKey)>, &'p [u32]) = (None, &p.clauses);
        for at in 1..args.len() {
            let Some(key) = key_at(self, at) else { continue };
            let list = program.index_at(p, at).list(&key);
            if best.0.is_none() || list.len() < best.1.len() {
                best = (Some((at as u32, key)), list);
            }
        }
        best
    }

    /// Renames `clause`, unifies its head with `goal`, and returns the continuation with its
    /// body pushed; `None` if the head does not unify.
    fn try_clause(&mut self, goal: Cell, clause: u32, cut: u32, next: u32) -> Option<u32> {
        let (head, body) = self.rename(clause);
        if !self.unify(head, goal) {
            return None;
        }
        Some(match body {
            Some(body) => self.push_goal(body, cut, next),
            None => next,
        })
    }

    /// Takes one step on `goal`: returns the next continuation, `None` to backtrack.
    fn step(&mut self, goal: Cell, cut: u32, next: u32) -> Result<Option<u32>, EngineError> {
        let goal = self.deref(goal);
        let (name, args): (Symbol, Vec<Cell>) = match goal {
            Cell::Atom(s) => (s, Vec::new()),
            Cell::Struct(_) => {
                let (f, args) = self.compound(goal).expect("a struct cell points at a functor");
                (f, args.to_vec())
            }
            Cell::Ref(_) => return Err(EngineError::Instantiation { context: "a goal".to_string() }),
            other => return Err(EngineError::NotCallable { found: self.read(other, &mut Vec::new()) }),
        };
        match (name, args.len()) {
            (sym::TRUE, 0) => Ok(Some(next)),
            (sym::FAIL | sym::FALSE, 0) => Ok(None),
            (sym::CUT, 0) => {
                self.choicepoints.truncate(cut as usize);
                Ok(Some(next))
            }
            (CUT_TO, 1) => {
                if let Cell::Int(height) = self.deref(args[0]) {
                    self.choicepoints.truncate(height as usize);
                }
                Ok(Some(next))
            }
            (COLLECT, 2) => {
                if let Cell::Int(frame) = self.deref(args[0]) {
                    self.collect(frame as usize, args[1]);
                }
                Ok(None)
            }
            (ARG_FROM, 4) => self.arg_from(&args, cut, next),
            (LENGTH_FROM, 3) => self.length_from(&args, cut, next),
            (sym::COMMA, 2) => {
                let rest = self.push_goal(args[1], cut, next);
                Ok(Some(self.push_goal(args[0], cut, rest)))
            }
            (sym::SEMI, 2) => {
                let if_then = match self.compound(args[0]) {
                    Some((sym::ARROW, [condition, then])) => Some((*condition, *then)),
                    _ => None,
                };
                if let Some((condition, then)) = if_then {
                    return Ok(Some(self.if_then_else(condition, then, Some(args[1]), cut, next)));
                }
                self.push_choicepoint(Alternative::Goal { goal: args[1], cut }, next);
                Ok(Some(self.push_goal(args[0], cut, next)))
            }
            (sym::ARROW, 2) => Ok(Some(self.if_then_else(args[0], args[1], None, cut, next))),
            // `Module:Goal`: kbc has no modules; the goal is the KB's or the library's.
            (sym::COLON, 2) if matches!(self.deref(args[0]), Cell::Atom(_)) => {
                Ok(Some(self.push_goal(args[1], cut, next)))
            }
            (sym::NOT_PROVABLE | sym::NOT, 1) => {
                // \+ G is (G -> fail ; true).
                Ok(Some(self.if_then_else(args[0], Cell::Atom(sym::FAIL), Some(Cell::Atom(sym::TRUE)), cut, next)))
            }
            (sym::EQ, 2) => Ok(self.unify(args[0], args[1]).then_some(next)),
            (sym::NOT_UNIFY, 2) => {
                let mark = self.trail.len() as u32;
                let unifies = self.unify(args[0], args[1]);
                self.undo_to(mark);
                Ok((!unifies).then_some(next))
            }
            (sym::IDENTICAL, 2) => Ok(self.identical(args[0], args[1]).then_some(next)),
            (sym::NOT_IDENTICAL, 2) => Ok((!self.identical(args[0], args[1])).then_some(next)),
            (sym::IS, 2) => {
                let value = arith::eval(self, args[1])?;
                Ok(self.unify(args[0], value.cell()).then_some(next))
            }
            (sym::LT | sym::GT | sym::LE | sym::GE | sym::ARITH_EQ | sym::ARITH_NE, 2) => {
                let a = arith::eval(self, args[0])?;
                let b = arith::eval(self, args[1])?;
                let ordering = a.compare(b);
                let holds = match name {
                    sym::LT => ordering.is_lt(),
                    sym::GT => ordering.is_gt(),
                    sym::LE => ordering.is_le(),
                    sym::GE => ordering.is_ge(),
                    sym::ARITH_EQ => ordering.is_eq(),
                    _ => ordering.is_ne(),
                };
                Ok(holds.then_some(next))
            }
            _ => self.call(goal, name, &args, cut, next),
        }
    }

    /// `(C -> T ; E)`: remember the choicepoint height, push the else branch (if any) as an
    /// alternative, and prove C followed by a cut back to that height, then T.
    fn if_then_else(&mut self, condition: Cell, then: Cell, otherwise: Option<Cell>, cut: u32, next: u32) -> u32 {
        let height = self.choicepoints.len() as u32;
        if let Some(otherwise) = otherwise {
            self.push_choicepoint(Alternative::Goal { goal: otherwise, cut }, next);
        }
        let then = self.push_goal(then, cut, next);
        let marker = self.new_compound(CUT_TO, &[Cell::Int(height as i64)]);
        let after_condition = self.push_goal(marker, cut, then);
        let condition_cut = self.choicepoints.len() as u32;
        self.push_goal(condition, condition_cut, after_condition)
    }

    fn push_choicepoint(&mut self, alternative: Alternative, cont: u32) {
        self.choicepoints.push(Choicepoint {
            alternative,
            cont,
            heap: self.heap.len() as u32,
            trail: self.trail.len() as u32,
            conts: self.conts.len() as u32,
            difs: self.difs.len() as u32,
        });
    }

    /// Calls a predicate: runs its native, or tries its clauses in order, leaving a
    /// choicepoint for the rest.
    fn call(
        &mut self,
        goal: Cell,
        name: Symbol,
        args: &[Cell],
        cut: u32,
        next: u32,
    ) -> Result<Option<u32>, EngineError> {
        let predicate = (name, args.len() as u32);
        let program: &'p Program = self.program;
        let Some(entry) = program.predicates.get(&predicate) else { return Ok(None) };
        if let Some(native) = entry.native {
            return self.native(native, name, args, cut, next);
        }
        Ok(self.call_clauses(goal, predicate, entry, args, next))
    }

    /// Tries the clauses of `predicate` (whose entry is `entry`) in order, leaving a
    /// choicepoint for the rest.
    fn call_clauses(
        &mut self,
        goal: Cell,
        predicate: (Symbol, u32),
        entry: &'p Predicate,
        args: &[Cell],
        next: u32,
    ) -> Option<u32> {
        let (key, list) = self.lookup_in(entry, args);
        let cut = self.choicepoints.len() as u32;
        for (position, &clause) in list.iter().enumerate() {
            if position + 1 < list.len() {
                self.push_choicepoint(
                    Alternative::Clauses { goal, predicate, key, next: position as u32 + 1, cut },
                    next,
                );
            }
            let mark = (self.heap.len(), self.trail.len() as u32);
            if let Some(resumed) = self.try_clause(goal, clause, cut, next) {
                return Some(resumed);
            }
            // The head did not unify: drop the choicepoint just pushed and try the next clause
            // here, rather than going through backtracking.
            if position + 1 < list.len() {
                self.choicepoints.pop();
            }
            self.undo_to(mark.1);
            self.heap.truncate(mark.0);
        }
        None
    }
}

fn relocate(cell: Cell, offset: u32) -> Cell {
    match cell {
        Cell::Ref(i) => Cell::Ref(i + offset),
        Cell::Struct(i) => Cell::Struct(i + offset),
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn program(text: &str) -> (Program, crate::session::Frontend) {
        let (_, frontend, _) = crate::session::Session::from_text("t.pl", text).into_parts();
        (Program::new(&frontend.kb, &frontend.interner, &[]), frontend)
    }

    fn atom(frontend: &mut crate::session::Frontend, name: &str) -> Cell {
        Cell::Atom(frontend.interner.intern(name))
    }

    #[test]
    fn atoms_are_ranked_only_for_a_program_that_can_compare_them() {
        // `@<` and the like are interned for every KB, so what counts is a term naming one.
        assert!(program("c(1).\nd(X) :- c(X).\n").0.rank.is_empty());
        assert!(!program("s(L, S) :- msort(L, S).\n").0.rank.is_empty());
        assert!(!program("b(X, Y) :- X @< Y.\n").0.rank.is_empty());
    }

    #[test]
    fn an_infinite_loop_runs_out_of_budget() {
        let (program, mut frontend) = program("loop :- loop.\n");
        let mut machine = Machine::new(&program, 10_000);
        let goal = atom(&mut frontend, "loop");
        assert_eq!(machine.solve(goal, |_| Next::More), Err(EngineError::Budget { steps: 10_000 }));
        assert!(machine.steps() > 10_000);
    }

    #[test]
    fn left_recursion_without_a_base_case_also_stops() {
        // p :- p, q. grows the continuation on every step: the budget bounds memory as well.
        let (program, mut frontend) = program("p :- p, q.\nq.\n");
        let mut machine = Machine::new(&program, 50_000);
        let goal = atom(&mut frontend, "p");
        assert!(matches!(machine.solve(goal, |_| Next::More), Err(EngineError::Budget { .. })));
    }

    #[test]
    fn a_machine_answers_query_after_query() {
        let (program, mut frontend) = program("c(1).\nc(2).\nc(3).\n");
        let mut machine = Machine::new(&program, 1_000);
        let c = frontend.interner.intern("c");
        for _ in 0..3 {
            machine.reset();
            let x = machine.new_var();
            let goal = machine.new_compound(c, &[x]);
            let mut seen = Vec::new();
            let outcome = machine.solve(goal, |m| {
                seen.push(m.deref(x));
                Next::More
            });
            assert_eq!(outcome, Ok(Outcome::Exhausted));
            assert_eq!(seen, vec![Cell::Int(1), Cell::Int(2), Cell::Int(3)]);
        }
    }

    #[test]
    fn stopping_early_undoes_the_bindings() {
        let (program, mut frontend) = program("c(1).\nc(2).\n");
        let mut machine = Machine::new(&program, 1_000);
        let c = frontend.interner.intern("c");
        let x = machine.new_var();
        let goal = machine.new_compound(c, &[x]);
        assert_eq!(machine.solve(goal, |_| Next::Stop), Ok(Outcome::Stopped));
        assert!(matches!(machine.deref(x), Cell::Ref(_)), "bindings are undone after the query");
    }

    #[test]
    fn first_argument_indexing_keeps_clause_order() {
        // Clauses with a variable first argument stay in their place among indexed ones.
        let (program, mut frontend) = program("k(a, 1).\nk(X, 2) :- X = a.\nk(b, 3).\nk(a, 4).\n");
        let mut machine = Machine::new(&program, 1_000);
        let k = frontend.interner.intern("k");
        let a = atom(&mut frontend, "a");
        let n = machine.new_var();
        let goal = machine.new_compound(k, &[a, n]);
        let mut seen = Vec::new();
        machine
            .solve(goal, |m| {
                seen.push(m.deref(n));
                Next::More
            })
            .expect("no error");
        assert_eq!(seen, vec![Cell::Int(1), Cell::Int(2), Cell::Int(4)]);
    }

    /// Every answer of `name(X, second, Y)` with `X` and `Y` unbound, in order, and how many
    /// clauses the call tries.
    fn answers_by_second(text: &str, name: &str, second: i64) -> (Vec<(Cell, Cell)>, usize) {
        let (program, mut frontend) = program(text);
        let mut machine = Machine::new(&program, 100_000);
        let name = frontend.interner.intern(name);
        let (x, y) = (machine.new_var(), machine.new_var());
        let args = [x, Cell::Int(second), y];
        let (key, list) = machine.lookup((name, 3), &args);
        assert_eq!(machine.clause_list((name, 3), key), list, "a choicepoint finds the same clauses");
        let tried = list.len();
        let goal = machine.new_compound(name, &args);
        let mut seen = Vec::new();
        machine
            .solve(goal, |m| {
                seen.push((m.deref(x), m.deref(y)));
                Next::More
            })
            .expect("no error");
        (seen, tried)
    }

    #[test]
    fn a_call_with_an_unbound_first_argument_is_narrowed_by_another() {
        // Clauses whose second argument is a variable or a compound stay in their place.
        let mut text: String = (0..40).map(|i| format!("r(c{i}, {}, {i}).\n", i % 4)).collect();
        text.insert_str(text.find("r(c10,").expect("a tenth clause"), "r(v, _, 100).\nr(w, f(1), 101).\n");
        text += "r(X, 2, 102) :- X = last.\n";
        let (seen, tried) = answers_by_second(&text, "r", 2);
        let values: Vec<i64> = seen
            .iter()
            .map(|(_, y)| match y {
                Cell::Int(i) => *i,
                other => panic!("an integer, not {other:?}"),
            })
            .collect();
        // What Prolog answers: every clause in order whose second argument unifies with 2.
        let mut expected: Vec<i64> = (0..40).filter(|i| i % 4 == 2).collect();
        let at = expected.iter().position(|&i| i >= 10).expect("one from 10 on");
        expected.insert(at, 100);
        expected.push(102);
        assert_eq!(values, expected);
        // Only the clauses whose second argument is 2 or a variable are tried (not the one
        // whose second argument is `f(1)`), also among four times as many clauses.
        assert_eq!(tried, expected.len());
        let mut more = text.clone();
        more += &(40..160).map(|i| format!("r(c{i}, {}, {i}).\n", 5 + i % 3)).collect::<String>();
        assert_eq!(answers_by_second(&more, "r", 2), (seen, tried));
    }
}
