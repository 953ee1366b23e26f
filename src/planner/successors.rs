//! Which actions apply in a state, and what applying one gives: the paper's action semantics,
//! evaluated lifted.
//!
//! For each schema, in clause order:
//! 1. an end `X_end(Args)` only applies to a running `X_start(Args)`: its arguments are bound
//!    from each running instance in turn;
//! 2. the Valid literals are joined against the state's facts, in order, binding variables
//!    (a nested-loop join over each literal's predicate range, backtracking on mismatch);
//! 3. the OnKB goals are proven by the resolution engine against the KB and the goal's facts,
//!    each solution binding more variables;
//! 4. no state fact may match an Invalid literal (its unbound variables are existential), and
//!    no goal literal may unify with an InvalidAtEnd literal; a start does not apply while the
//!    same ground action is running (no self-overlap).
//!
//! Solutions come out in a fixed order (schemas in clause order, facts in state order, engine
//! solutions in Prolog order), which the paper's depth-first search relies on and which makes
//! every search deterministic.

use crate::engine::{Cell, EngineError, Machine, Next};
use crate::intern::sym;
use crate::ir::hir::{EffectKind, Goal, Snap, Term};
use crate::ir::task::{Const, ConstId, Consts, FactId, Facts, LiteralPattern, Pattern, Schema, State, Task};
use crate::ir::unify::unifiable;

/// An applicable action: a schema and the values of its variables (`None` where a variable
/// only occurs in Invalid conditions).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Applicable {
    /// The schema's index in `Task::schemas`.
    pub schema: usize,
    /// A value per schema variable.
    pub bindings: Box<[Option<ConstId>]>,
    /// For an end, the running start it ends.
    pub ends: Option<ConstId>,
}

/// A failure of the engine while proving an OnKB goal of a schema.
#[derive(Clone, Debug, PartialEq)]
pub struct ConditionError {
    /// The schema whose OnKB goals failed.
    pub schema: usize,
    /// What went wrong.
    pub error: EngineError,
    /// Whether it was the schema's `duration/3` query that failed, not its OnKB goals.
    pub duration: bool,
}

/// Binds a pattern to a ground constant, recording new bindings on `trail`.
pub fn match_pattern(
    pattern: &Pattern,
    value: ConstId,
    consts: &Consts,
    bindings: &mut [Option<ConstId>],
    trail: &mut Vec<u32>,
) -> bool {
    match pattern {
        Pattern::Const(c) => *c == value,
        Pattern::Var(v) => match bindings[*v as usize] {
            Some(bound) => bound == value,
            None => {
                bindings[*v as usize] = Some(value);
                trail.push(*v);
                true
            }
        },
        Pattern::Compound(f, args) => match consts.get(value) {
            Const::Compound(g, values) if g == f && values.len() == args.len() => {
                let values = values.clone();
                args.iter().zip(values.iter()).all(|(a, v)| match_pattern(a, *v, consts, bindings, trail))
            }
            _ => false,
        },
    }
}

/// Undoes the bindings recorded on `trail` after `mark`.
pub fn undo(bindings: &mut [Option<ConstId>], trail: &mut Vec<u32>, mark: usize) {
    for v in trail.drain(mark..) {
        bindings[v as usize] = None;
    }
}

/// Matches a literal's arguments against a fact's.
pub fn match_literal(
    literal: &LiteralPattern,
    fact: FactId,
    consts: &Consts,
    facts: &Facts,
    bindings: &mut [Option<ConstId>],
    trail: &mut Vec<u32>,
) -> bool {
    let values = facts.args(fact);
    literal.args.iter().zip(values).all(|(p, v)| match_pattern(p, *v, consts, bindings, trail))
}

/// Instantiates a pattern whose variables are all bound.
pub fn instantiate(pattern: &Pattern, consts: &mut Consts, bindings: &[Option<ConstId>]) -> Option<ConstId> {
    match pattern {
        Pattern::Const(c) => Some(*c),
        Pattern::Var(v) => bindings[*v as usize],
        Pattern::Compound(f, args) => {
            let values = args.iter().map(|a| instantiate(a, consts, bindings)).collect::<Option<Box<[ConstId]>>>()?;
            Some(consts.intern(Const::Compound(*f, values)))
        }
    }
}

/// A term with bound schema variables replaced by their values.
pub(crate) fn substitute(pattern_term: &Term, consts: &Consts, bindings: &[Option<ConstId>]) -> Term {
    match pattern_term {
        Term::Var(v) => match bindings.get(v.0 as usize).copied().flatten() {
            Some(c) => consts.to_term(c),
            None => Term::Var(*v),
        },
        Term::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| substitute(a, consts, bindings)).collect()),
        other => other.clone(),
    }
}

/// Places a constant on the engine's heap.
pub fn const_to_cell(machine: &mut Machine<'_>, consts: &Consts, value: ConstId) -> Cell {
    match consts.get(value) {
        Const::Atom(s) => Cell::Atom(*s),
        Const::Int(i) => Cell::Int(*i),
        Const::Float(bits) => Cell::Float(f64::from_bits(*bits)),
        Const::Str(s) => Cell::Str(*s),
        Const::Compound(f, args) => {
            let (f, args) = (*f, args.clone());
            let cells: Vec<Cell> = args.iter().map(|a| const_to_cell(machine, consts, *a)).collect();
            machine.new_compound(f, &cells)
        }
    }
}

/// Reads a ground cell back as a constant; `None` if it holds a variable.
pub fn cell_to_const(machine: &Machine<'_>, consts: &mut Consts, cell: Cell) -> Option<ConstId> {
    let value = match machine.deref(cell) {
        Cell::Ref(_) | Cell::Functor(..) => return None,
        Cell::Atom(s) => Const::Atom(s),
        Cell::Int(i) => Const::Int(i),
        Cell::Float(f) => Const::Float(f.to_bits()),
        Cell::Str(s) => Const::Str(s),
        Cell::Struct(_) => {
            let (f, args) = machine.compound(cell)?;
            let args: Vec<Cell> = args.to_vec();
            let values = args.iter().map(|a| cell_to_const(machine, consts, *a)).collect::<Option<Box<[ConstId]>>>()?;
            Const::Compound(f, values)
        }
    };
    Some(consts.intern(value))
}

/// The solutions of one OnKB query, kept in the cache that proved them: for each, the values
/// of the OnKB variables it binds (the same number for every solution), read with
/// [`OnKbCache::solution`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OnKbSolutions {
    count: usize,
    width: usize,
    /// Where the first solution's values start in the cache's arena.
    start: usize,
}

impl OnKbSolutions {
    /// The number of solutions.
    pub fn len(&self) -> usize {
        self.count
    }

    /// True when the query has no solution.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }
}

/// One remembered query: a schema (and for one goal alone, the goal's index plus one; zero
/// for the conjunction), the values of the variables (`None` for unbound) at `key..key + len`
/// of the cache's key arena, and its solutions (`None` where a goal cannot be proven apart).
#[derive(Clone, Copy)]
struct Entry {
    schema: u32,
    goal: u32,
    key: usize,
    len: usize,
    solutions: Option<OnKbSolutions>,
}

/// For each OnKB goal of a schema, the positions of its variables among the schema's.
type GoalPositions = std::rc::Rc<[Box<[u32]>]>;

/// Solutions of the schemas' OnKB goals, remembered across states.
///
/// The KB does not change during a search, so the solutions of a schema's OnKB goals depend
/// only on the values of their variables that are already bound: each such combination is
/// proven once by the engine and then looked up. A solution gives a value (or `None`, if the
/// engine left it unbound) to each OnKB variable that was unbound.
///
/// A schema with several OnKB goals (and no cut among them) is proven goal by goal, each goal
/// remembered under the values of its own variables: `destination(B, X2, Y2), (X1 \== X2 ;
/// Y1 \== Y2)` is then proven once per block for the first goal, not once per block and
/// source cell, which is what the relaxed exploration asks for (every cell a block can reach).
/// The KB is pure, so a goal whose variables are bound to constants by the goals before it
/// has the same solutions, in the same order, as it has inside the conjunction. A variable a
/// goal leaves unbound (or bound to a term with variables) stays so in the conjunction too,
/// unless a later goal reads it or it shares a variable with another one the goal leaves
/// unbound; in those cases, and when the engine stops with an error, the conjunction is
/// proven whole instead, so the answers (and errors) are always the conjunction's.
///
/// Keys and solutions live in two arenas, so a cache of millions of queries (the relaxed
/// exploration of 100 blocks asks that many) is a few large allocations, freed at once.
#[derive(Clone, Default)]
pub struct OnKbCache {
    /// Per schema: its OnKB variables, in order.
    vars: Vec<Box<[u32]>>,
    /// Per schema, when its goals are proven one at a time: for each goal, the positions of
    /// its variables in the schema's `vars`.
    split: Vec<Option<GoalPositions>>,
    /// The queries proven so far, both conjunctions and single goals.
    table: hashbrown::HashTable<Entry>,
    /// The keys' values, end to end.
    keys: Vec<Option<ConstId>>,
    /// The solutions' values, end to end.
    values: Vec<Option<ConstId>>,
    hasher: rustc_hash::FxBuildHasher,
    /// Scratch space for a key.
    key: Vec<Option<ConstId>>,
}

/// The variables of `goal`, in order of first occurrence, appended to `vars` if not there.
fn goal_vars(goal: &Goal, vars: &mut Vec<u32>) {
    goal.for_each_call(&mut |l| {
        l.term.for_each_var(&mut |v| {
            if !vars.contains(&v.0) {
                vars.push(v.0);
            }
        })
    });
}

/// Places `goals` (OnKB goals of `schema`) on the engine's heap as one query, after a reset,
/// with each variable of `bound` set to its value; returns the query and the cell of every
/// schema variable (`_` for those the goals do not name).
fn put_query(
    machine: &mut Machine<'_>,
    consts: &Consts,
    schema: &Schema,
    goals: &[Goal],
    bound: impl Iterator<Item = (u32, ConstId)>,
) -> (Cell, Vec<Cell>) {
    machine.reset();
    let mut cells: Vec<Option<Cell>> = vec![None; schema.vars];
    for (v, value) in bound {
        cells[v as usize] = Some(const_to_cell(machine, consts, value));
    }
    let goal = machine.put_conjunction(goals, &mut cells);
    (goal, cells.into_iter().map(|cell| cell.unwrap_or(Cell::Atom(sym::ANON))).collect())
}

/// The values the variables `vars` take in the solutions of `goal` (an OnKB goal of `schema`
/// that calls one predicate), asked with every variable unbound; `None` if a solution leaves
/// one of them unbound, there are more than `limit` solutions, or the engine fails. For a
/// predicate defined by facts alone ([`crate::engine::Program::facts_only`]), the goal has a
/// solution with some of `vars` bound only if these values include theirs.
pub fn fact_tuples(
    machine: &mut Machine<'_>,
    consts: &mut Consts,
    schema: &Schema,
    goal: &Goal,
    vars: &[u32],
    limit: usize,
) -> Option<rustc_hash::FxHashSet<Box<[ConstId]>>> {
    let (goal, cells) = put_query(machine, consts, schema, std::slice::from_ref(goal), std::iter::empty());
    let cells: Vec<Cell> = vars.iter().map(|&v| cells[v as usize]).collect();
    let mut tuples = rustc_hash::FxHashSet::default();
    let mut complete = true;
    machine
        .solve(goal, |m| {
            let tuple: Option<Box<[ConstId]>> = cells.iter().map(|&cell| cell_to_const(m, consts, cell)).collect();
            match tuple {
                Some(tuple) if tuples.len() < limit || tuples.contains(&tuple) => {
                    tuples.insert(tuple);
                    Next::More
                }
                _ => {
                    complete = false;
                    Next::Stop
                }
            }
        })
        .ok()?;
    complete.then_some(tuples)
}

/// The hash of a remembered query (schema, goal, key), the same whether the key is looked up
/// or read back from the arena.
fn entry_hash(hasher: &rustc_hash::FxBuildHasher, schema: u32, goal: u32, key: &[Option<ConstId>]) -> u64 {
    use std::hash::BuildHasher;
    hasher.hash_one((schema, goal, key))
}

/// What one engine query found: the number of solutions and their values, end to end.
type Found = (usize, Vec<Option<ConstId>>);

impl OnKbCache {
    /// A cache for `task`'s schemas.
    pub fn new(task: &Task) -> OnKbCache {
        let mut cache = OnKbCache::default();
        for schema in task.schemas.iter() {
            let mut vars = Vec::new();
            for goal in schema.on_kb.iter() {
                goal_vars(goal, &mut vars);
            }
            let mut cut = false;
            for goal in schema.on_kb.iter() {
                goal.for_each_call(&mut |l| cut |= l.term.callable() == Some((sym::CUT, 0)));
            }
            let split = (schema.on_kb.len() > 1 && !cut).then(|| {
                schema
                    .on_kb
                    .iter()
                    .map(|goal| {
                        let mut own = Vec::new();
                        goal_vars(goal, &mut own);
                        own.iter().map(|v| vars.iter().position(|w| w == v).expect("an OnKB variable") as u32).collect()
                    })
                    .collect()
            });
            cache.vars.push(vars.into_boxed_slice());
            cache.split.push(split);
        }
        cache
    }

    /// A cache for `task`'s schemas that proves every conjunction of OnKB goals in one query,
    /// never goal by goal: the reference the split proofs are tested against.
    pub fn whole(task: &Task) -> OnKbCache {
        let mut cache = OnKbCache::new(task);
        cache.split.iter_mut().for_each(|split| *split = None);
        cache
    }

    /// The OnKB variables of schema `index`.
    pub fn vars(&self, index: usize) -> &[u32] {
        &self.vars[index]
    }

    /// Solution `i` of `solutions` (which this cache gave): the values of the OnKB variables
    /// that were unbound, in the order of [`OnKbCache::vars`].
    pub fn solution(&self, solutions: OnKbSolutions, i: usize) -> &[Option<ConstId>] {
        let at = solutions.start + i * solutions.width;
        &self.values[at..at + solutions.width]
    }

    /// The remembered query (schema, goal, key), if any.
    fn find(&self, schema: u32, goal: u32, key: &[Option<ConstId>]) -> Option<Option<OnKbSolutions>> {
        let keys = &self.keys;
        self.table
            .find(entry_hash(&self.hasher, schema, goal, key), |e| {
                e.schema == schema && e.goal == goal && &keys[e.key..e.key + e.len] == key
            })
            .map(|e| e.solutions)
    }

    /// Stores what a query found in the arena, each distinct solution once, in the order
    /// first found. A solution found again gives the action the same values, so it would be
    /// the same action again: `(X1 \== X2 ; Y1 \== Y2)` holds twice for a move that changes
    /// both coordinates, and the relaxed exploration of a 100-block problem met ~40% of its
    /// moves twice before this.
    fn store(&mut self, width: usize, (count, values): Found) -> OnKbSolutions {
        let start = self.values.len();
        let count = if count < 2 {
            self.values.extend_from_slice(&values);
            count
        } else if width == 0 {
            1
        } else {
            let mut seen: rustc_hash::FxHashSet<&[Option<ConstId>]> = rustc_hash::FxHashSet::default();
            let mut kept = 0;
            for row in values.chunks_exact(width) {
                if seen.insert(row) {
                    self.values.extend_from_slice(row);
                    kept += 1;
                }
            }
            kept
        };
        OnKbSolutions { count, width, start }
    }

    /// Remembers the query (schema, goal, key), which is not yet in the table.
    fn remember(&mut self, schema: u32, goal: u32, key: &[Option<ConstId>], solutions: Option<OnKbSolutions>) {
        let hash = entry_hash(&self.hasher, schema, goal, key);
        let entry = Entry { schema, goal, key: self.keys.len(), len: key.len(), solutions };
        self.keys.extend_from_slice(key);
        let OnKbCache { table, keys, hasher, .. } = self;
        table.insert_unique(hash, entry, |e| entry_hash(hasher, e.schema, e.goal, &keys[e.key..e.key + e.len]));
    }

    /// The solutions of schema `index`'s OnKB goals under `bindings`: for each, the values of
    /// the OnKB variables unbound in `bindings`, in the order of [`OnKbCache::vars`] (read
    /// them with [`OnKbCache::solution`]).
    pub fn solutions(
        &mut self,
        machine: &mut Machine<'_>,
        consts: &mut Consts,
        schema: &Schema,
        index: usize,
        bindings: &[Option<ConstId>],
    ) -> Result<OnKbSolutions, EngineError> {
        let mut key = std::mem::take(&mut self.key);
        key.clear();
        key.extend(self.vars[index].iter().map(|&v| bindings[v as usize]));
        let solutions = match self.find(index as u32, 0, &key) {
            Some(found) => found.expect("a conjunction always has its solutions"),
            None => {
                // Each solution gives a value to every OnKB variable unbound in the key.
                let width = key.iter().filter(|v| v.is_none()).count();
                let solutions = match self.solve_split(machine, consts, schema, index, &key, width) {
                    Some(solutions) => solutions,
                    None => {
                        let found = self.solve_whole(machine, consts, schema, index, bindings)?;
                        self.store(width, found)
                    }
                };
                self.remember(index as u32, 0, &key, Some(solutions));
                solutions
            }
        };
        self.key = key;
        Ok(solutions)
    }

    /// Proves the conjunction of schema `index`'s OnKB goals in one engine query.
    fn solve_whole(
        &self,
        machine: &mut Machine<'_>,
        consts: &mut Consts,
        schema: &Schema,
        index: usize,
        bindings: &[Option<ConstId>],
    ) -> Result<Found, EngineError> {
        let vars = &self.vars[index];
        let bound = vars.iter().filter_map(|&v| Some((v, bindings[v as usize]?)));
        let (goal, cells) = put_query(machine, consts, schema, &schema.on_kb, bound);
        let unbound: Vec<Cell> =
            vars.iter().filter(|&&v| bindings[v as usize].is_none()).map(|&v| cells[v as usize]).collect();
        let (mut count, mut values) = (0, Vec::new());
        machine.solve(goal, |m| {
            values.extend(unbound.iter().map(|cell| cell_to_const(m, consts, *cell)));
            count += 1;
            Next::More
        })?;
        Ok((count, values))
    }

    /// Proves schema `index`'s OnKB goals one at a time (see [`OnKbCache`]), from the values
    /// `key` of its OnKB variables (`unbound` of them `None`); `None` where the conjunction
    /// must be proven whole.
    fn solve_split(
        &mut self,
        machine: &mut Machine<'_>,
        consts: &mut Consts,
        schema: &Schema,
        index: usize,
        key: &[Option<ConstId>],
        unbound: usize,
    ) -> Option<OnKbSolutions> {
        let split = self.split[index].clone()?;
        // Partial solutions, one after the other, each a value per OnKB variable (in the
        // order of `vars`).
        let width = key.len();
        let (mut partial, mut count): (Vec<Option<ConstId>>, usize) = (key.to_vec(), 1);
        let mut next = Vec::new();
        let mut own = Vec::new();
        for (g, positions) in split.iter().enumerate() {
            next.clear();
            let mut next_count = 0;
            for i in 0..count {
                let values = &partial[i * width..(i + 1) * width];
                own.clear();
                own.extend(positions.iter().map(|&p| values[p as usize]));
                let goal = (g + 1) as u32;
                let solutions = match self.find(index as u32, goal, &own) {
                    Some(found) => found?,
                    None => {
                        let solved = self
                            .solve_goal(machine, consts, schema, index, g, &own)
                            .map(|found| self.store(positions.len(), found));
                        self.remember(index as u32, goal, &own, solved);
                        solved?
                    }
                };
                for s in 0..solutions.count {
                    let at = next.len();
                    next.extend_from_slice(values);
                    for (&p, &value) in positions.iter().zip(self.solution(solutions, s)) {
                        next[at + p as usize] = value;
                    }
                    next_count += 1;
                }
            }
            std::mem::swap(&mut partial, &mut next);
            count = next_count;
        }
        let mut values = Vec::new();
        for i in 0..count {
            let solution = &partial[i * width..(i + 1) * width];
            values.extend(key.iter().zip(solution).filter(|(bound, _)| bound.is_none()).map(|(_, &v)| v));
        }
        Some(self.store(unbound, (count, values)))
    }

    /// The solutions of goal `g` of schema `index` alone, from the values `own` of its
    /// variables; `None` if it cannot be proven apart (see [`OnKbCache`]) or the engine stops
    /// with an error (the whole conjunction then reports it).
    fn solve_goal(
        &self,
        machine: &mut Machine<'_>,
        consts: &mut Consts,
        schema: &Schema,
        index: usize,
        g: usize,
        own: &[Option<ConstId>],
    ) -> Option<Found> {
        let split = self.split[index].as_ref().expect("a split schema");
        let vars = &self.vars[index];
        let bound = split[g].iter().zip(own.iter()).filter_map(|(&p, value)| Some((vars[p as usize], (*value)?)));
        let (goal, cells) = put_query(machine, consts, schema, &schema.on_kb[g..=g], bound);
        let read: Vec<Cell> = split[g].iter().map(|&p| cells[vars[p as usize] as usize]).collect();
        // The positions later goals read.
        let later: Vec<u32> = split[g + 1..].iter().flat_map(|own| own.iter().copied()).collect();
        let (mut count, mut values) = (0, Vec::new());
        let mut apart = true;
        let outcome = machine.solve(goal, |m| {
            let at = values.len();
            values.extend(read.iter().map(|cell| cell_to_const(m, consts, *cell)));
            let mut open = split[g].iter().zip(&values[at..]).filter(|(_, value)| value.is_none());
            apart = match (open.next(), open.next()) {
                (None, _) => true,
                (Some((p, _)), None) => !later.contains(p),
                (Some(_), Some(_)) => false,
            };
            count += 1;
            if apart { Next::More } else { Next::Stop }
        });
        (outcome.is_ok() && apart).then_some((count, values))
    }
}

/// Finds applicable actions; owns the scratch space the search reuses state after state.
pub struct Successors<'p> {
    machine: Machine<'p>,
    cache: OnKbCache,
    bindings: Vec<Option<ConstId>>,
    trail: Vec<u32>,
    /// Skip Invalid conditions (for the delete relaxation, see [`relaxed_reachable`]).
    ignore_invalid: bool,
    /// Per schema, once asked for: for each of its InvalidAtEnd terms, the goal terms it may
    /// unify with (no functor or constant of theirs differs), the only ones a ground instance
    /// of it is checked against. (Checked against each of the 128 goal terms, `kbc plan` of
    /// reverse_b100_a8_s1 tried 4.7 M unifications here, 373 M instructions; so 2.5 M, 291 M.)
    forbidden_goals: Vec<Option<GoalLists>>,
}

/// Per InvalidAtEnd term of a schema, the indices of the goal terms it may unify with.
type GoalLists = Box<[Box<[u32]>]>;

impl<'p> Successors<'p> {
    /// A generator for `task`, proving OnKB goals with `machine`.
    pub fn new(task: &Task, machine: Machine<'p>) -> Successors<'p> {
        Successors::with_cache(machine, OnKbCache::new(task))
    }

    /// A generator that starts with the OnKB answers of `cache` (made for the same task).
    pub fn with_cache(machine: Machine<'p>, cache: OnKbCache) -> Successors<'p> {
        Successors {
            machine,
            cache,
            bindings: Vec::new(),
            trail: Vec::new(),
            ignore_invalid: false,
            forbidden_goals: Vec::new(),
        }
    }

    /// The engine and the OnKB cache, for the heuristic's relaxed exploration.
    pub fn parts(&mut self) -> (&mut Machine<'p>, &mut OnKbCache) {
        (&mut self.machine, &mut self.cache)
    }

    /// Whether `action` would apply in `state` but for its Invalid conditions (and its
    /// InvalidAtEnd ones, and a running instance of itself): its Valid literals hold in
    /// `state` and its OnKB goals hold. What some later state, without the facts that stand
    /// in its way, may allow.
    pub fn applies_but_for_invalid(
        &mut self,
        task: &mut Task,
        action: &Applicable,
        state: &State,
    ) -> Result<bool, ConditionError> {
        self.ignore_invalid = true;
        let applies = self.applies(task, action, state);
        self.ignore_invalid = false;
        applies
    }

    /// Every action applicable in `state`, in the fixed order described in the module docs.
    pub fn applicable(
        &mut self,
        task: &mut Task,
        state: &State,
        out: &mut Vec<Applicable>,
    ) -> Result<(), ConditionError> {
        out.clear();
        for index in 0..task.schemas.len() {
            self.schema_in(task, index, state, (None, None, &[]), out)?;
        }
        Ok(())
    }

    /// [`Successors::applicable`], with Valid literals matched against the state's facts, and
    /// ends against its running actions, in the orders of `order` (the paper's lists) instead
    /// of the state's own order.
    pub fn applicable_in_order(
        &mut self,
        task: &mut Task,
        state: &State,
        order: &PaperOrder,
        out: &mut Vec<Applicable>,
    ) -> Result<(), ConditionError> {
        out.clear();
        for index in 0..task.schemas.len() {
            self.schema_in(task, index, state, (Some(order), None, &[]), out)?;
        }
        Ok(())
    }

    /// The applicable instances of one schema.
    pub fn schema(
        &mut self,
        task: &mut Task,
        index: usize,
        state: &State,
        out: &mut Vec<Applicable>,
    ) -> Result<(), ConditionError> {
        self.schema_in(task, index, state, (None, None, &[]), out)
    }

    /// The applicable instances of end schema `index` that end the running action `running`:
    /// those of [`Successors::schema`] whose `ends` is `running`, without trying the others.
    pub fn ending(
        &mut self,
        task: &mut Task,
        index: usize,
        state: &State,
        running: ConstId,
        out: &mut Vec<Applicable>,
    ) -> Result<(), ConditionError> {
        debug_assert_eq!(task.schemas[index].snap, Snap::End);
        self.schema_in(task, index, state, (None, Some(running), &[]), out)
    }

    /// The applicable instances of schema `index` that may be named `name` (with its values
    /// for the variables of Valid literals bound before matching, as [`Successors::applies`]
    /// binds them): those of [`Successors::schema`] named `name`, in the same order, without
    /// matching the state's other facts. Others (named otherwise through a variable bound
    /// only by an OnKB goal) may be among them; callers filter by name.
    pub fn named(
        &mut self,
        task: &mut Task,
        index: usize,
        state: &State,
        name: ConstId,
        out: &mut Vec<Applicable>,
    ) -> Result<(), ConditionError> {
        let schema = &task.schemas[index];
        let mut preset = vec![None; schema.vars];
        let mut trail = Vec::new();
        if !match_pattern(&schema.name, name, &task.consts, &mut preset, &mut trail) {
            return Ok(());
        }
        let in_valid = valid_vars(schema);
        for (v, value) in preset.iter_mut().enumerate() {
            if !in_valid.contains(&(v as u32)) {
                *value = None;
            }
        }
        self.schema_in(task, index, state, (None, None, &preset), out)
    }

    /// Whether `action` applies in `state`: the applicable instances of its schema include it.
    /// Its values for the variables of Valid literals are bound before matching (each literal
    /// is then looked up rather than matched against every fact), so OnKB goals are proven
    /// with the same arguments bound as when every instance is listed.
    pub fn applies(&mut self, task: &mut Task, action: &Applicable, state: &State) -> Result<bool, ConditionError> {
        let Task { consts, facts, schemas, goal_terms, .. } = task;
        let schema = &schemas[action.schema];
        self.bindings.clear();
        self.bindings.resize(schema.vars, None);
        self.trail.clear();
        for v in valid_vars(schema) {
            self.bindings[v as usize] = action.bindings.get(v as usize).copied().flatten();
        }
        let mut found = Vec::new();
        let mut context =
            Context { consts, facts, goal_terms, schema, index: action.schema, state, order: None, out: &mut found };
        if schema.snap == Snap::End {
            let Some(running) = action.ends.filter(|r| state.running.contains(r)) else { return Ok(false) };
            if name_matches_running(schema, running, context.consts, &mut self.bindings, &mut self.trail) {
                self.valid(&mut context, 0, Some(running))?;
            }
        } else {
            self.valid(&mut context, 0, None)?;
        }
        Ok(found.contains(action))
    }

    /// The applicable instances of schema `index`, with Valid literals matched in `order`'s
    /// order if given; for an end, only those that end `only` if given; with the values of
    /// `preset` (by variable; empty for none) bound before matching.
    fn schema_in(
        &mut self,
        task: &mut Task,
        index: usize,
        state: &State,
        (order, only, preset): (Option<&PaperOrder>, Option<ConstId>, &[Option<ConstId>]),
        out: &mut Vec<Applicable>,
    ) -> Result<(), ConditionError> {
        let Task { consts, facts, schemas, goal_terms, .. } = task;
        let schema = &schemas[index];
        self.bindings.clear();
        self.bindings.resize(schema.vars, None);
        self.trail.clear();
        self.bindings[..preset.len()].copy_from_slice(preset);
        let mut context = Context { consts, facts, goal_terms, schema, index, state, order, out };
        if schema.snap == Snap::End {
            let running: &[ConstId] = match order {
                Some(order) => &order.running,
                None => &state.running,
            };
            for &running in running.iter().filter(|&&r| only.is_none_or(|only| only == r)) {
                let mark = self.trail.len();
                if name_matches_running(schema, running, context.consts, &mut self.bindings, &mut self.trail) {
                    self.valid(&mut context, 0, Some(running))?;
                }
                undo(&mut self.bindings, &mut self.trail, mark);
            }
            return Ok(());
        }
        self.valid(&mut context, 0, None)
    }

    fn valid(&mut self, cx: &mut Context<'_>, position: usize, ends: Option<ConstId>) -> Result<(), ConditionError> {
        let Some(literal) = cx.schema.valid.get(position) else {
            return self.on_kb(cx, ends);
        };
        // A literal whose arguments are all bound (an end's literals often are, by its running
        // start) matches at most one fact: look it up rather than scan the predicate's facts.
        if let Some(args) = bound_args(literal, &self.bindings) {
            if cx.facts.find(literal.pred, &args).is_some_and(|fact| cx.state.contains(cx.facts, fact)) {
                self.valid(cx, position + 1, ends)?;
            }
            return Ok(());
        }
        let candidates: Vec<FactId> = match cx.order {
            Some(order) => order.facts.iter().copied().filter(|&f| cx.facts.pred_of(f) == literal.pred).collect(),
            None => cx.state.facts_of(literal.pred).collect(),
        };
        for fact in candidates {
            let mark = self.trail.len();
            if match_literal(literal, fact, cx.consts, cx.facts, &mut self.bindings, &mut self.trail) {
                self.valid(cx, position + 1, ends)?;
            }
            undo(&mut self.bindings, &mut self.trail, mark);
        }
        Ok(())
    }

    fn on_kb(&mut self, cx: &mut Context<'_>, ends: Option<ConstId>) -> Result<(), ConditionError> {
        if cx.schema.on_kb.is_empty() {
            self.finish(cx, ends);
            return Ok(());
        }
        let solutions = self
            .cache
            .solutions(&mut self.machine, cx.consts, cx.schema, cx.index, &self.bindings)
            .map_err(|error| ConditionError { schema: cx.index, error, duration: false })?;
        let unbound: Vec<u32> =
            self.cache.vars(cx.index).iter().copied().filter(|&v| self.bindings[v as usize].is_none()).collect();
        for i in 0..solutions.len() {
            let mark = self.trail.len();
            for (&v, value) in unbound.iter().zip(self.cache.solution(solutions, i)) {
                if let Some(value) = value {
                    self.bindings[v as usize] = Some(*value);
                    self.trail.push(v);
                }
            }
            self.finish(cx, ends);
            undo(&mut self.bindings, &mut self.trail, mark);
        }
        Ok(())
    }

    /// Checks Invalid and InvalidAtEnd and records the action.
    fn finish(&mut self, cx: &mut Context<'_>, ends: Option<ConstId>) {
        // The name and the added facts must be ground to be applied (a deletion with an
        // unbound variable removes every fact that unifies with it).
        if !pattern_bound(&cx.schema.name, &self.bindings)
            || cx
                .schema
                .effects
                .iter()
                .any(|(kind, l)| *kind == EffectKind::Add && !l.args.iter().all(|a| pattern_bound(a, &self.bindings)))
        {
            return;
        }
        // A ground durative action does not overlap itself: its start does not apply while
        // it runs (docs/dsl.md, "Durative actions").
        if !self.ignore_invalid
            && cx.schema.snap == Snap::Start
            && !cx.state.running.is_empty()
            && let Some(instance) = known_running_instance(cx.schema, cx.consts, &self.bindings)
            && cx.state.running.binary_search(&instance).is_ok()
        {
            return;
        }
        let invalid: &[LiteralPattern] = if self.ignore_invalid { &[] } else { &cx.schema.invalid };
        for literal in invalid {
            for fact in cx.state.facts_of(literal.pred) {
                let mark = self.trail.len();
                let matches = match_literal(literal, fact, cx.consts, cx.facts, &mut self.bindings, &mut self.trail);
                undo(&mut self.bindings, &mut self.trail, mark);
                if matches {
                    return;
                }
            }
        }
        if !cx.schema.invalid_at_end.is_empty() {
            let goals = forbidden_goals(&mut self.forbidden_goals, cx);
            for (forbidden, goals) in cx.schema.invalid_at_end.iter().zip(goals) {
                if goals.is_empty() {
                    continue;
                }
                let forbidden = substitute(forbidden, cx.consts, &self.bindings);
                if goals.iter().any(|&g| unifiable(&forbidden, &cx.goal_terms[g as usize])) {
                    return;
                }
            }
        }
        cx.out.push(Applicable { schema: cx.index, bindings: self.bindings.clone().into_boxed_slice(), ends });
    }
}

/// The goal terms each InvalidAtEnd term of `cx`'s schema may unify with (see
/// `Successors::forbidden_goals`), found in `known` the first time they are asked for.
fn forbidden_goals<'k>(known: &'k mut Vec<Option<GoalLists>>, cx: &Context<'_>) -> &'k [Box<[u32]>] {
    if known.len() <= cx.index {
        known.resize(cx.index + 1, None);
    }
    known[cx.index].get_or_insert_with(|| {
        cx.schema
            .invalid_at_end
            .iter()
            .map(|term| {
                (0..cx.goal_terms.len() as u32)
                    .filter(|&g| !crate::ir::unify::clash(term, &cx.goal_terms[g as usize]))
                    .collect()
            })
            .collect()
    })
}

/// What one schema's matching needs, borrowed from the task.
struct Context<'a> {
    consts: &'a mut Consts,
    facts: &'a Facts,
    goal_terms: &'a [Term],
    schema: &'a Schema,
    index: usize,
    state: &'a State,
    /// The order to match Valid literals in (the paper's state list), if not the state's.
    order: Option<&'a PaperOrder>,
    out: &'a mut Vec<Applicable>,
}

/// The variables of a schema's Valid literals (those bound once its Valid literals match).
fn valid_vars(schema: &Schema) -> Vec<u32> {
    let mut vars = Vec::new();
    schema.valid.iter().for_each(|l| l.args.iter().for_each(|a| a.vars(&mut vars)));
    vars
}

/// The values of a literal's arguments when each is a constant or a bound variable.
fn bound_args(literal: &LiteralPattern, bindings: &[Option<ConstId>]) -> Option<Vec<ConstId>> {
    literal
        .args
        .iter()
        .map(|a| match a {
            Pattern::Const(c) => Some(*c),
            Pattern::Var(v) => bindings[*v as usize],
            Pattern::Compound(..) => None,
        })
        .collect()
}

fn pattern_bound(pattern: &Pattern, bindings: &[Option<ConstId>]) -> bool {
    match pattern {
        Pattern::Const(_) => true,
        Pattern::Var(v) => bindings[*v as usize].is_some(),
        Pattern::Compound(_, args) => args.iter().all(|a| pattern_bound(a, bindings)),
    }
}

/// Binds an end's name arguments from a running start `base(args)`.
fn name_matches_running(
    schema: &Schema,
    running: ConstId,
    consts: &Consts,
    bindings: &mut [Option<ConstId>],
    trail: &mut Vec<u32>,
) -> bool {
    let name_args: &[Pattern] = match &schema.name {
        Pattern::Compound(_, args) => args,
        _ => &[],
    };
    match consts.get(running) {
        Const::Atom(base) => *base == schema.base && name_args.is_empty(),
        Const::Compound(base, values) if *base == schema.base && values.len() == name_args.len() => {
            let values = values.clone();
            name_args.iter().zip(values.iter()).all(|(p, v)| match_pattern(p, *v, consts, bindings, trail))
        }
        // A ground name pattern (a start with constant arguments) compiled to a constant.
        Const::Compound(base, values) if *base == schema.base => match &schema.name {
            Pattern::Const(c) => match consts.get(*c) {
                Const::Compound(_, own) => own[..] == values[..],
                _ => false,
            },
            _ => false,
        },
        _ => false,
    }
}

/// The running-action constant `base(args)` of a start.
pub fn running_instance(schema: &Schema, consts: &mut Consts, bindings: &[Option<ConstId>]) -> Option<ConstId> {
    let value = running_value(schema, consts, bindings)?;
    Some(consts.intern(value))
}

/// [`running_instance`] if that constant exists already, without making it (a compound
/// inside the name's arguments is interned as [`instantiate`] does): a start whose running
/// constant was never made is not running. (Checking each candidate start of a state
/// against the running ones this way, not by interning every candidate's constant, took the
/// check from 3.3% of the instructions of `kbc plan` on reverse_b100_a8_s1 to under 0.1%.)
fn known_running_instance(schema: &Schema, consts: &mut Consts, bindings: &[Option<ConstId>]) -> Option<ConstId> {
    let value = running_value(schema, consts, bindings)?;
    consts.find(&value)
}

/// The value of the running-action constant of a start; `None` if a name argument is unbound.
fn running_value(schema: &Schema, consts: &mut Consts, bindings: &[Option<ConstId>]) -> Option<Const> {
    let args: Vec<ConstId> = match &schema.name {
        Pattern::Compound(_, args) => args.iter().map(|a| instantiate(a, consts, bindings)).collect::<Option<_>>()?,
        Pattern::Const(c) => match consts.get(*c) {
            Const::Compound(_, args) => args.to_vec(),
            _ => Vec::new(),
        },
        Pattern::Var(_) => return None,
    };
    Some(if args.is_empty() { Const::Atom(schema.base) } else { Const::Compound(schema.base, args.into_boxed_slice()) })
}

/// What the delete relaxation reaches from the initial state: every fact, and every action
/// instance whose Valid, OnKB and InvalidAtEnd conditions hold in some relaxed state (Invalid
/// conditions and deletions ignored). A superset of what any plan can reach, computed to a
/// fixpoint with the same matching as the search.
pub struct Reachable {
    /// The facts, in the order reached.
    pub facts: Vec<FactId>,
    /// The action instances, in the order of the last round (schemas in clause order).
    pub actions: Vec<Applicable>,
}

/// Why [`relaxed_reachable`] stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum ReachError {
    /// An OnKB goal failed with an engine error.
    Condition(ConditionError),
    /// More action instances than the limit.
    TooMany(usize),
}

/// Computes [`Reachable`] for `task`, giving up beyond `limit` action instances.
pub fn relaxed_reachable(task: &mut Task, machine: Machine<'_>, limit: usize) -> Result<Reachable, ReachError> {
    let mut successors = Successors::new(task, machine);
    successors.ignore_invalid = true;
    let mut facts: Vec<FactId> = task.init.facts().collect();
    let mut known: rustc_hash::FxHashSet<FactId> = facts.iter().copied().collect();
    let mut running: Vec<ConstId> = Vec::new();
    let mut running_known: rustc_hash::FxHashSet<ConstId> = Default::default();
    let mut out = Vec::new();
    loop {
        let state = State::new(&task.facts, facts.iter().copied(), running.iter().copied());
        successors.applicable(task, &state, &mut out).map_err(ReachError::Condition)?;
        if out.len() > limit {
            return Err(ReachError::TooMany(out.len()));
        }
        let before = (facts.len(), running.len());
        for action in &out {
            let Task { consts, facts: table, schemas, .. } = &mut *task;
            let schema = &schemas[action.schema];
            for (kind, literal) in schema.effects.iter() {
                if *kind != EffectKind::Add {
                    continue;
                }
                let args: Option<Vec<ConstId>> =
                    literal.args.iter().map(|a| instantiate(a, consts, &action.bindings)).collect();
                let Some(args) = args else { continue };
                let fact = table.intern(literal.pred, &args);
                if known.insert(fact) {
                    facts.push(fact);
                }
            }
            if schema.snap == Snap::Start
                && let Some(instance) = running_instance(schema, consts, &action.bindings)
                && running_known.insert(instance)
            {
                running.push(instance);
            }
        }
        if (facts.len(), running.len()) == before {
            return Ok(Reachable { facts, actions: out });
        }
    }
}

/// A state as the paper's planner keeps it: lists, the newest addition first. The same facts
/// and running actions as the [`State`] beside it, in the order the paper's search enumerates
/// them.
#[derive(Clone, Debug, Default)]
pub struct PaperOrder {
    /// The facts.
    pub facts: Vec<FactId>,
    /// The running durative actions (`base(args)`).
    pub running: Vec<ConstId>,
}

/// The paper's lists after applying `action`: effects in list order, an added fact not yet in
/// the list put first (the newest addition first, as the paper's planner conses it), a deleted
/// one taken out; a start's running action put first, an end's taken out.
pub fn apply_to_order(task: &mut Task, order: &PaperOrder, action: &Applicable) -> PaperOrder {
    let Task { consts, facts, schemas, .. } = task;
    let schema = &schemas[action.schema];
    let mut list: Vec<FactId> = order.facts.clone();
    apply_effects(consts, facts, schema, &action.bindings, &mut list, true);
    let mut running = order.running.clone();
    apply_running(consts, schema, action, &mut running, true);
    PaperOrder { facts: list, running }
}

/// Applies `schema`'s effects under `bindings` to the facts `list`, in list order: an added
/// fact not yet there is put last, or first with `newest_first` (the paper's list); a deleted
/// one is taken out, and a deletion with an unbound variable takes out every fact that
/// unifies with it (as SWI-Prolog's delete/3).
fn apply_effects(
    consts: &mut Consts,
    facts: &mut Facts,
    schema: &Schema,
    bindings: &[Option<ConstId>],
    list: &mut Vec<FactId>,
    newest_first: bool,
) {
    for (kind, literal) in schema.effects.iter() {
        let args: Option<Vec<ConstId>> = literal.args.iter().map(|a| instantiate(a, consts, bindings)).collect();
        match (kind, args) {
            (EffectKind::Add, Some(args)) => {
                let fact = facts.intern(literal.pred, &args);
                if !list.contains(&fact) {
                    if newest_first {
                        list.insert(0, fact);
                    } else {
                        list.push(fact);
                    }
                }
            }
            (EffectKind::Add, None) => {}
            (EffectKind::Del, Some(args)) => {
                let fact = facts.intern(literal.pred, &args);
                list.retain(|f| *f != fact);
            }
            (EffectKind::Del, None) => {
                let mut scratch = bindings.to_vec();
                let mut trail = Vec::new();
                list.retain(|&f| {
                    let unifies = facts.pred_of(f) == literal.pred
                        && match_literal(literal, f, consts, facts, &mut scratch, &mut trail);
                    undo(&mut scratch, &mut trail, 0);
                    !unifies
                });
            }
        }
    }
}

/// The state after applying `action` to `state`: effects in list order, then the running
/// set updated (a start begins, an end finishes its start).
pub fn apply(task: &mut Task, state: &State, action: &Applicable) -> State {
    let Task { consts, facts, schemas, .. } = task;
    let schema = &schemas[action.schema];
    let mut current: Vec<FactId> = state.facts().collect();
    apply_effects(consts, facts, schema, &action.bindings, &mut current, false);
    let mut running: Vec<ConstId> = state.running.to_vec();
    apply_running(consts, schema, action, &mut running, false);
    State::new(facts, current, running)
}

/// Updates the running actions for `action`: a start adds its `base(args)` (last, or first
/// with `newest_first`), an end removes the start it closes.
fn apply_running(
    consts: &mut Consts,
    schema: &Schema,
    action: &Applicable,
    running: &mut Vec<ConstId>,
    newest_first: bool,
) {
    match schema.snap {
        Snap::Start => {
            if let Some(instance) = running_instance(schema, consts, &action.bindings) {
                if newest_first {
                    running.insert(0, instance);
                } else {
                    running.push(instance);
                }
            }
        }
        Snap::End => {
            if let Some(position) = action.ends.and_then(|e| running.iter().position(|r| *r == e)) {
                running.remove(position);
            }
        }
        Snap::Instant => {}
    }
}

/// True if every goal literal matches a fact of `state` (with the goal's variables shared
/// between literals) and no durative action is still running.
pub fn goal_reached(task: &Task, state: &State) -> bool {
    if !state.running.is_empty() {
        return false;
    }
    let mut bindings = vec![None; task.goal_vars];
    let mut trail = Vec::new();
    goal_from(task, state, 0, &mut bindings, &mut trail)
}

fn goal_from(
    task: &Task,
    state: &State,
    position: usize,
    bindings: &mut [Option<ConstId>],
    trail: &mut Vec<u32>,
) -> bool {
    let Some(literal) = task.goal.get(position) else { return true };
    for fact in state.facts_of(literal.pred) {
        let mark = trail.len();
        if match_literal(literal, fact, &task.consts, &task.facts, bindings, trail)
            && goal_from(task, state, position + 1, bindings, trail)
        {
            undo(bindings, trail, mark);
            return true;
        }
        undo(bindings, trail, mark);
    }
    false
}

/// The ground name of an applicable action, as a HIR term.
pub fn action_name(task: &Task, action: &Applicable) -> Term {
    let schema = &task.schemas[action.schema];
    substitute(&task.pattern_to_term(&schema.name), &task.consts, &action.bindings)
}

/// The values of an action's variables as HIR terms (`None` for unbound ones).
pub fn action_bindings(task: &Task, action: &Applicable) -> Vec<Option<Term>> {
    action.bindings.iter().map(|b| b.map(|c| task.consts.to_term(c))).collect()
}
