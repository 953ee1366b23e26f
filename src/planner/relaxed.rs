//! The delete relaxation, evaluated lifted: h_add, h_FF and FF's helpful actions.
//!
//! Ignoring deletions (and Invalid conditions, which deletions would make true), an action
//! schema becomes a Datalog rule: its Valid literals are the body, its `add` effects the
//! heads, and its OnKB and InvalidAtEnd conditions filters on the bindings. From a state's
//! facts, the rules are applied to a fixpoint in order of cost (a generalised Dijkstra over
//! facts, which yields h_add): a tuple is settled at its cheapest cost, and every rule
//! instantiation is found exactly when the last of its body tuples settles, by joining that
//! tuple with the settled tuples of the other body literals. Exploration stops once every goal
//! literal is reached. Best supporters then give FF's relaxed plan: its length is h_FF and the
//! actions in it applicable in the state itself are the helpful ones.
//!
//! Nothing is grounded ahead of time. What keeps the exploration small is projection: a
//! variable that occurs in one body literal only, and nowhere else (not in a head, an OnKB or
//! InvalidAtEnd condition), only asks that *some* value exists, so that literal is matched
//! against a *view* of its predicate without that argument. In the standard blocks world,
//! `moving(A, B, X1, Y1, X2, Y2)` is read by the ends of moves as a view on `(A, B, X2, Y2)`:
//! with 20 blocks and 22 cells this takes the joins from hundreds of thousands of
//! instantiations per evaluation to tens of thousands.
//!
//! The joins also drop an instantiation as soon as its body binds the variables of a leading
//! OnKB goal that calls a predicate defined by facts alone to values no fact has (see
//! [`FactFilter`]): the engine would refuse it, so nothing changes but the work. Grounding
//! build_b100_a10 took 3.3 s and 243 MB of peak memory before, 2.1 s and 163 MB after.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::hash::BuildHasher;

use hashbrown::HashTable;
use rustc_hash::{FxBuildHasher, FxHashMap, FxHashSet};

use super::BudgetKind;
use super::ground::{Auxiliary, GroundTask, RecordedAction, Source};
use super::landmarks::{Accepted, Landmarks};
use super::successors::{ConditionError, OnKbCache, fact_tuples, instantiate, match_pattern, substitute, undo};
use crate::engine::{Machine, Program};
use crate::intern::sym;
use crate::ir::hir::{EffectKind, Goal, Snap, Term};
use crate::ir::task::{ConstId, LiteralPattern, Pattern, PredId, Schema, State, Task};
use crate::ir::unify::unifiable;

/// A relation read by a rule or a goal: a predicate, restricted to some argument positions.
#[derive(Clone, Debug)]
struct View {
    /// The argument positions kept, ascending.
    keep: Box<[u32]>,
}

/// A body literal: a view and the patterns at its kept positions.
#[derive(Clone, Debug)]
struct BodyLiteral {
    view: u32,
    args: Box<[Pattern]>,
}

/// One step of a join: which body literal, and which of its table's indexes (if any) looks
/// up the tuples that agree with it on every kept position bound by then.
#[derive(Debug, Clone, Copy)]
struct JoinStep {
    literal: u32,
    lookup: Option<u32>,
}

/// Settled tuples by their values at some kept positions (all those a join step has bound),
/// under the hash of those values: a join step looks up its candidates whole rather than by
/// one position and then matching the rest. Tuples whose values merely share a hash land in
/// one list too, which is harmless, since the join matches every candidate in full. On the
/// end of a move onto a table block (`moving`, `ontable(B2, X2, Y2)`, `clear(B2)`), looking
/// up `ontable` by both coordinates instead of the first alone took the 100-block set-up
/// from 13.8 million candidates to 0.8 million.
#[derive(Clone, Default)]
struct Index {
    positions: Box<[u32]>,
    tuples: FxHashMap<u64, Vec<u32>>,
}

/// The hash an [`Index`] files values under.
fn index_key(hasher: &FxBuildHasher, values: impl Iterator<Item = ConstId>) -> u64 {
    use std::hash::{BuildHasher, Hasher};
    let mut state = hasher.build_hasher();
    for value in values {
        state.write_u32(value.0);
    }
    state.finish()
}

/// A schema as a relaxed rule.
#[derive(Clone, Debug)]
struct Rule {
    schema: u32,
    vars: usize,
    body: Box<[BodyLiteral]>,
    heads: Box<[LiteralPattern]>,
    /// For each body position as the trigger, the join order of the other literals.
    orders: Box<[Box<[JoinStep]>]>,
    /// The schema's Invalid literals, for the ground task's negative conditions.
    invalid: Box<[LiteralPattern]>,
    /// Its `del` effects on predicates some Invalid literal reads.
    dels: Box<[LiteralPattern]>,
    /// A body literal the ground task reads through an exclusion node (see [`Exclusion`]).
    exclusion: Option<Exclusion>,
    /// Necessary conditions of its OnKB goals that the join checks early (see
    /// [`FactFilter`]); found at the first exploration, which has an engine to ask.
    filters: Vec<FactFilter>,
    /// Per trigger position, per step of its join order (and one past the last): the
    /// filters whose variables are all bound by then.
    checks: Box<[FilterSteps]>,
}

/// For one join order, per step: the numbers of the filters checked there.
type FilterSteps = Box<[Box<[u32]>]>;

/// A call to a predicate defined by facts alone, among the first OnKB goals of a schema
/// (before any other goal, so nothing runs before it): an instantiation whose body binds its
/// variables to values no fact has cannot pass the goals, and the join drops it as soon as
/// those variables are bound, instead of enumerating the rest of the body and asking the
/// engine for each. In the standard blocks world, the end of a move onto a block asks
/// `on(B, B2, X, Y)` of the problem's goal: 820,200 instantiations on a 100-block problem,
/// of which 20 pass.
#[derive(Clone, Debug)]
struct FactFilter {
    /// The goal's variables the body binds, in order.
    vars: Box<[u32]>,
    /// Their values in the predicate's facts.
    tuples: FxHashSet<Box<[ConstId]>>,
}

/// The most solutions a [`FactFilter`] keeps; a predicate with more facts is not used as one.
const FACT_FILTER_LIMIT: usize = 100_000;

/// A body literal whose variables, beyond those it shares, matter only to one disequality.
///
/// In the standard blocks world a move starts from where the block stands and goes anywhere
/// else: `gripped(A, B), ontable(B, X1, Y1)` with `(X1 \== X2 ; Y1 \== Y2)`, where the source
/// cell `(X1, Y1)` occurs nowhere else that the relaxation reads (the head `moving(A, B, X1,
/// Y1, X2, Y2)` is only read at `(B, X2, Y2)`). Grounding every pair of source and destination
/// makes blocks x cells x cells actions, nearly all of a large task. The ground task instead
/// instantiates the rule without the source: its precondition is the node "some tuple of the
/// literal in this group (the same block), whose excluded variables differ from these values
/// (the destination)", whose h_add cost is the cheapest such tuple's, exactly the minimum the
/// lifted relaxation takes over the instantiations it joins (see
/// [`Relaxation::exclusion_nodes`]). The rule's deletions that read the excluded variables
/// (the block leaving its source cell, which Invalid conditions wait for) go to a second
/// ground action, instantiated over the body's variables without the destination, which
/// costs what the cheapest instantiation that deletes the same facts costs. So every node's
/// h_add is what it was. The relaxed plan also stays the one over whole instantiations: it
/// takes for an exclusion node the tuple the first whole instantiation to reach it read, and
/// a part it chooses handles what the other part of that instantiation adds
/// (`GroundTask::relaxed_plan`). On reverse_b50_a8 the ground task goes from 97,142 actions
/// (96,860 rule instantiations) to 25,052 (12,090 parts of instantiations, the rest zero-cost
/// links and Invalid conjunctions), with the same plans.
///
/// The disequality must be one OnKB condition, `E \== O` or a disjunction of them, each pair
/// with one excluded variable `E` and one other variable `O` that is bound when the condition
/// runs (it occurs in the body or an earlier OnKB condition, and in no later one): then the
/// condition says "the tuple of the `E`s differs from the tuple of the `O`s".
#[derive(Clone, Debug)]
struct Exclusion {
    /// The body literal (an index into the rule's body).
    literal: u32,
    /// The positions of its view not holding excluded variables: tuples that agree there
    /// form one group.
    group: Box<[u32]>,
    /// Per pair of the disequality: the view position of the excluded variable and the
    /// variable it must differ from.
    pairs: Box<[(u32, u32)]>,
    /// Per variable of the rule: whether it is excluded (unbound in the action that adds).
    excluded: Box<[bool]>,
    /// The rule's deletions (indices into `Rule::dels`) that read excluded variables.
    dels: Box<[u32]>,
    /// Per variable of the rule: whether the deleting action is instantiated over it (those
    /// of the body, of those deletions and of the Invalid literals). (Flags rather than lists:
    /// the keys of the two parts are built from them for every instantiation recorded; with
    /// each variable looked up in a list, reverse_b100_a8_s1's grounding took 3892 M
    /// instructions, 3619 M so.)
    deleting: Box<[bool]>,
}

/// Why a tuple has its cost.
#[derive(Debug, Clone, Copy)]
enum Support {
    /// It holds in the state.
    State,
    /// A rule instantiation produced it; its bindings are at `bindings` in the arena.
    Rule { rule: u32, bindings: u32 },
}

/// The tuples of one view during an evaluation.
#[derive(Clone, Default)]
struct Table {
    arity: usize,
    values: Vec<ConstId>,
    lookup: HashTable<u32>,
    cost: Vec<u32>,
    done: Vec<bool>,
    support: Vec<Support>,
    settled: Vec<u32>,
    /// The indexes join steps look this table's settled tuples up in.
    indexes: Vec<Index>,
}

impl Table {
    fn clear(&mut self) {
        self.values.clear();
        self.lookup.clear();
        self.cost.clear();
        self.done.clear();
        self.support.clear();
        self.settled.clear();
        for index in &mut self.indexes {
            index.tuples.clear();
        }
    }

    /// The bytes this table holds, counting capacity (what the allocator gave it).
    fn footprint(&self) -> usize {
        use std::mem::size_of;
        let index: usize = self
            .indexes
            .iter()
            .map(|index| {
                index.tuples.capacity() * (size_of::<u64>() + size_of::<Vec<u32>>() + 1)
                    + index.tuples.values().map(|v| v.capacity() * 4).sum::<usize>()
            })
            .sum();
        self.values.capacity() * size_of::<ConstId>()
            + self.lookup.capacity() * (size_of::<u32>() + 1)
            + self.cost.capacity() * 4
            + self.done.capacity()
            + self.support.capacity() * size_of::<Support>()
            + self.settled.capacity() * 4
            + index
    }

    fn tuple(&self, t: u32) -> &[ConstId] {
        &self.values[t as usize * self.arity..(t as usize + 1) * self.arity]
    }

    fn find_or_insert(&mut self, hasher: &FxBuildHasher, values: &[ConstId]) -> (u32, bool) {
        let hash = hasher.hash_one(values);
        let Table { values: store, lookup, arity, .. } = self;
        let arity = *arity;
        if let Some(&t) = lookup.find(hash, |&t| &store[t as usize * arity..(t as usize + 1) * arity] == values) {
            return (t, false);
        }
        let t = self.cost.len() as u32;
        store.extend_from_slice(values);
        lookup.insert_unique(hash, t, |&u| hasher.hash_one(&store[u as usize * arity..(u as usize + 1) * arity]));
        self.cost.push(u32::MAX);
        self.done.push(false);
        self.support.push(Support::State);
        (t, true)
    }

    fn find(&self, hasher: &FxBuildHasher, values: &[ConstId]) -> Option<u32> {
        let hash = hasher.hash_one(values);
        self.lookup.find(hash, |&t| self.tuple(t) == values).copied()
    }
}

/// A helpful action: a schema and the values of its variables in the relaxed plan (`None`
/// for projected-away ones, which match anything).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Helpful {
    /// The schema's index in `Task::schemas`.
    pub schema: usize,
    /// The values.
    pub bindings: Box<[Option<ConstId>]>,
}

/// The heuristic's verdict on a state.
#[derive(Debug, Clone, Default)]
pub struct Estimate {
    /// h_add: the sum of the goal literals' relaxed costs; `None` if some goal literal is
    /// unreachable even ignoring deletions (a dead end).
    pub h_add: Option<u32>,
    /// h_FF: the length of the relaxed plan.
    pub h_ff: Option<u32>,
    /// Relaxed-plan actions applicable in the state.
    pub helpful: Vec<Helpful>,
    /// FF's first-layer subgoals, when the task is ground: the nodes the relaxed plan's
    /// applicable actions were chosen to achieve, sorted. Any applicable action that achieves
    /// one is helpful too (see [`Relaxation::achieves_subgoal`]).
    pub subgoals: Vec<u32>,
    /// The whole relaxed plan, when the task is ground and [`Relaxation::keep_relaxed_plans`]
    /// asked for it: its actions (but the deleting parts of split instantiations, see
    /// [`Exclusion`]), those that lead to the goals due soonest first, then cheapest first by
    /// the sum of their preconditions' costs (ties in the order the plan chose them).
    pub plan: Vec<PlanAction>,
}

/// An action of the whole relaxed plan ([`Estimate::plan`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlanAction {
    pub action: Helpful,
    /// The fact node the plan chose it for.
    pub purpose: u32,
    /// Whether that fact is a stop on a detour (see `GroundTask::detours`).
    pub detour: bool,
    /// Its variables whose values only a choice made it take: bound by no Valid literal
    /// (by an OnKB goal, such as a move's destination), where their values are not in the
    /// fact it was chosen for, or that fact is a stop on a detour. A move that clears the
    /// block below is chosen for `clear(B1)`, and a block's trip aside ends in a cell its next
    /// move only has to leave; the cell is the relaxation's cheapest pick, which every such
    /// move shares, and another free cell does as well.
    pub loose: Box<[u32]>,
    /// All its variables bound by no Valid literal (a superset of `loose`): those a careful
    /// lookahead may give other values when the plan's would hold an arm waiting.
    pub chosen: Box<[u32]>,
}

/// The relaxed task and the scratch space to evaluate it, state after state.
#[derive(Clone)]
pub struct Relaxation {
    views: Vec<View>,
    views_of_pred: FxHashMap<PredId, Vec<u32>>,
    rules: Vec<Rule>,
    triggers: Vec<Vec<(u32, u32)>>,
    /// Goal literals: the full view of their predicate and their patterns.
    goal: Vec<BodyLiteral>,
    tables: Vec<Table>,
    queue: BinaryHeap<Reverse<(u32, u32, u32)>>,
    arena: Vec<Option<ConstId>>,
    hasher: FxBuildHasher,
    /// The goal literals the last exploration did not reach.
    unreached: Vec<usize>,
    /// For each of `goal`, its index in `Task::goal` (resource goals are left out).
    goal_index: Vec<usize>,
    /// While grounding: every rule instantiation fired so far.
    recorder: Option<Recorder>,
    /// Scratch space for the keys of a split instantiation's two parts while recording.
    key: Vec<Option<ConstId>>,
    /// Scratch space for a fact offered to a view ([`Relaxation::offer`]).
    projected: Vec<ConstId>,
    /// Scratch space for the values of a rule's head ([`Relaxation::fire`]).
    head_values: Vec<ConstId>,
    /// The ground relaxed task, once [`Relaxation::ground`] has built it; evaluations then
    /// use it instead of the lifted rules.
    ground: Option<GroundTask>,
    /// The whole-fact views of the predicates Invalid literals read.
    negated_views: Vec<u32>,
    /// Per predicate, the argument positions that only ever hold a unit of a resource (or an
    /// anonymous variable): every view leaves them out (see [`resource_positions`]).
    dropped: FxHashMap<PredId, Box<[bool]>>,
    /// The ground task's landmarks, found when it is built.
    landmarks: Option<Landmarks>,
    /// The search's budget: every exploration (grounding included) stops with
    /// [`Stop::Budget`] at `deadline`, or once its tables take more than `max_bytes`.
    limits: Limits,
    /// Whether the rules' [`FactFilter`]s have been looked for.
    filtered: bool,
    /// Per schema (but ends), the variables no Valid literal binds (nor a resource's unit):
    /// those its OnKB goals choose (see [`PlanAction::loose`]).
    chosen_vars: Vec<Box<[u32]>>,
}

/// The time and memory an exploration may take; see [`Relaxation::limit`].
#[derive(Clone, Copy, Debug)]
struct Limits {
    deadline: Option<std::time::Instant>,
    max_bytes: usize,
    /// Join steps since the last look at the clock.
    ticks: u32,
    /// Set when a table would have grown beyond `max_bytes` (memory), or when growing one
    /// would take past the deadline (time).
    exhausted: Option<BudgetKind>,
    /// The time one entry of a lookup table took to move when the last one grew, in
    /// nanoseconds: growing a table of tens of millions of entries takes seconds, so the next
    /// growth is predicted from it and not begun if it would end past the deadline.
    rehash_ns: f64,
    /// The most values one exploration may add to the task's ([`MAX_NEW_CONSTANTS`] unless
    /// the budget says otherwise).
    max_new_constants: usize,
}

impl Limits {
    fn new(deadline: Option<std::time::Instant>, max_bytes: usize) -> Limits {
        // A guess until a growth is measured; a rehash moves an entry in some tens of ns.
        Limits { deadline, max_bytes, ticks: 0, exhausted: None, rehash_ns: 20.0, max_new_constants: MAX_NEW_CONSTANTS }
    }
}

/// How often (in join steps) an exploration checks its budget: a few microseconds of work
/// between two looks at the clock.
const CHECK_EVERY: u32 = 4096;

/// The most values (constants) one exploration may add to the task's, by default, before it
/// stops with [`BudgetKind::Constants`]: an exploration ignores deletions, so OnKB arithmetic that
/// nothing bounds (`X1 is X + 1` in a counter) makes new values for ever. A bounded task
/// makes few (grounding a 100-block rung of the ladder adds 8, the KBs of
/// benches/other_domains at most 4). On an unbounded push counter (release build), the
/// search for a goal it never reaches stops with this in 1.6 s, where it ran for minutes; the
/// set-up for one it reaches takes 1.1 s, where grounding to a million instantiations took
/// 3.2 s and 870 MB.
pub const MAX_NEW_CONSTANTS: usize = 250_000;

/// The most values the exploration that grounds the relaxation ([`Relaxation::ground`]) may
/// add to the task's, or as many as the task has if that is more: beyond, evaluation stays
/// lifted. A bounded task makes few (see [`MAX_NEW_CONSTANTS`]); one that builds terms, such
/// as stacks kept as lists in the state (`stack(S, [X|Rest])`), makes new ones at every step
/// of the exploration, and its instantiations grow with the square of them: on a 3-block
/// stack-of-lists KB, grounding until a million instantiations took the set-up 1.2-2.4 s and
/// 293 MB (twice: the second search grounds again), against 40 ms and 41 MB with this limit
/// (`kbc plan -v`, release build).
pub const GROUND_NEW_CONSTANTS: usize = 256;

/// Why an exploration stopped without an answer.
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// An OnKB goal failed in the engine.
    Condition(ConditionError),
    /// The search's time or memory budget ran out.
    Budget(BudgetKind),
}

impl From<ConditionError> for Stop {
    fn from(error: ConditionError) -> Stop {
        Stop::Condition(error)
    }
}

/// An Invalid literal instance: rule, literal, and the values of the literal's variables.
type InstanceKey = (u32, u32, Box<[Option<ConstId>]>);
/// An exclusion node: its group's number, and the values to differ from.
type ExclusionKey = (u32, Option<Box<[ConstId]>>);
/// A group of tuples exclusion nodes choose from: the rule, and the values of the excluded
/// literal's other positions.
type GroupKey = (u32, Box<[ConstId]>);

/// Which part of a rule instantiation a ground action stands for (see [`Exclusion`]).
#[derive(Clone, Copy)]
enum Part {
    /// All of it.
    Whole,
    /// Its heads and the deletions that do not read excluded variables; the excluded literal
    /// is read through exclusion node `node` (a number of the recorder's).
    Adds { node: u32 },
    /// The deletions that read excluded variables; `pair` is the action recorded as the
    /// adding part of the same instantiation.
    Deletes { pair: u32 },
}

/// Distinct keys numbered in order of first use: the map to their numbers, and the keys by
/// number.
#[derive(Clone)]
struct Numbered<K> {
    numbers: FxHashMap<K, u32>,
    list: Vec<K>,
}

impl<K: std::hash::Hash + Eq + Clone> Numbered<K> {
    fn new() -> Self {
        Numbered { numbers: FxHashMap::default(), list: Vec::new() }
    }

    /// The number of `key`, numbering it if new.
    fn number(&mut self, key: K) -> u32 {
        let Numbered { numbers, list } = self;
        let next = list.len() as u32;
        *numbers.entry(key).or_insert_with_key(|key| {
            list.push(key.clone());
            next
        })
    }
}

/// The rule instantiations of a full exploration, recorded to build a [`GroundTask`].
#[derive(Clone)]
struct Recorder {
    /// The instantiations recorded so far, as indices into `actions` hashed by their rule and
    /// bindings (the bindings are stored once, in the action).
    seen: HashTable<u32>,
    actions: Vec<RecordedAction>,
    /// Distinct Invalid literal instances: (rule, literal, values of the rule's variables
    /// with only the literal's own kept).
    instances: Numbered<InstanceKey>,
    /// Distinct groups and exclusion nodes (see [`Exclusion`]).
    groups: Numbered<GroupKey>,
    exclusions: Numbered<ExclusionKey>,
    /// The most instantiations, and the most bytes (an estimate), to record before giving
    /// up on grounding.
    limit: usize,
    max_bytes: usize,
    bytes: usize,
    overflowed: bool,
}

/// A schema's literals as a relaxed rule reads them: the body (its Valid literals and, for an
/// end, the running start it closes) and the heads (its `add` effects and, for a start, the
/// running action it opens). So an end's name takes its start's values, as in the search.
fn relaxed_literals(schema: &Schema) -> (Vec<LiteralPattern>, Vec<LiteralPattern>) {
    let mut valid = schema.valid.to_vec();
    let mut heads: Vec<LiteralPattern> =
        schema.effects.iter().filter(|(kind, _)| *kind == EffectKind::Add).map(|(_, l)| l.clone()).collect();
    if let Some(running) = &schema.running {
        match schema.snap {
            Snap::End => valid.push(running.clone()),
            Snap::Start => heads.push(running.clone()),
            Snap::Instant => {}
        }
    }
    (valid, heads)
}

/// The facts of `state` as the relaxation reads them: its facts, and its running actions as
/// facts of their running-action predicates.
fn for_each_relaxed_fact(task: &Task, state: &State, mut f: impl FnMut(PredId, &[ConstId])) {
    for fact in state.facts() {
        f(task.facts.pred_of(fact), task.facts.args(fact));
    }
    for &running in state.running.iter() {
        if let Some((pred, args)) = task.running_fact(running) {
            f(pred, args);
        }
    }
}

fn var_occurrences(pattern: &Pattern, out: &mut Vec<u32>) {
    match pattern {
        Pattern::Const(_) => {}
        Pattern::Var(v) => out.push(*v),
        Pattern::Compound(_, args) => args.iter().for_each(|a| var_occurrences(a, out)),
    }
}

fn term_vars(term: &Term, out: &mut Vec<u32>) {
    term.for_each_var(&mut |v| out.push(v.0));
}

impl Relaxation {
    /// The relaxed rules of `task`'s schemas, with single-use variables projected away.
    pub fn new(task: &Task) -> Relaxation {
        Relaxation::build(task, true)
    }

    /// The relaxed rules without projection: every body literal reads whole facts, so after
    /// [`Relaxation::evaluate_all`] every reachable fact can be queried with
    /// [`Relaxation::reached`]. Slower; for explaining why a goal is unreachable.
    pub fn unprojected(task: &Task) -> Relaxation {
        Relaxation::build(task, false)
    }

    fn build(task: &Task, project: bool) -> Relaxation {
        let mut relaxation = Relaxation {
            views: Vec::new(),
            views_of_pred: FxHashMap::default(),
            rules: Vec::new(),
            triggers: Vec::new(),
            goal: Vec::new(),
            tables: Vec::new(),
            queue: BinaryHeap::new(),
            arena: Vec::new(),
            hasher: FxBuildHasher,
            unreached: Vec::new(),
            goal_index: Vec::new(),
            recorder: None,
            key: Vec::new(),
            projected: Vec::new(),
            head_values: Vec::new(),
            ground: None,
            negated_views: Vec::new(),
            landmarks: None,
            limits: Limits::new(None, usize::MAX),
            dropped: if project { resource_positions(task) } else { FxHashMap::default() },
            filtered: false,
            chosen_vars: task.schemas.iter().map(Schema::chosen_vars).collect(),
        };
        // Predicates some Invalid literal reads: their deletions can matter to the ground task.
        // A predicate some action deletes with an unbound variable (every fact that unifies
        // goes) is left out: the ground task could not say which facts that deletion removes,
        // and a relaxation that knows less stays sound.
        let mut open_deletes: Vec<PredId> = Vec::new();
        for schema in &task.schemas {
            for e in schema.open_effects() {
                if let (EffectKind::Del, literal) = &schema.effects[e] {
                    open_deletes.push(literal.pred);
                }
            }
        }
        let mut negated: Vec<PredId> = Vec::new();
        for schema in &task.schemas {
            for literal in schema.invalid.iter() {
                if !negated.contains(&literal.pred) && !open_deletes.contains(&literal.pred) {
                    negated.push(literal.pred);
                }
            }
        }
        // Per view, the positions each of its indexes looks tuples up by (see [`Index`]).
        let mut index_positions: FxHashMap<u32, Vec<Box<[u32]>>> = FxHashMap::default();
        for (index, schema) in task.schemas.iter().enumerate() {
            let (valid, heads) = relaxed_literals(schema);
            // Variables needed beyond the body: in heads, OnKB and InvalidAtEnd conditions,
            // deletions of negated predicates, and the non-existential variables of Invalid
            // literals (those that occur elsewhere in the schema).
            let mut needed = Vec::new();
            let dels: Vec<LiteralPattern> = schema
                .effects
                .iter()
                .filter(|(kind, l)| *kind == EffectKind::Del && negated.contains(&l.pred))
                .map(|(_, l)| l.clone())
                .collect();
            for del in &dels {
                for (i, a) in del.args.iter().enumerate() {
                    if !relaxation.is_dropped(del.pred, i) {
                        var_occurrences(a, &mut needed);
                    }
                }
            }
            let mut elsewhere = Vec::new();
            var_occurrences(&schema.name, &mut elsewhere);
            for literal in valid.iter().chain(schema.effects.iter().map(|(_, l)| l)).chain(&schema.running) {
                literal.args.iter().for_each(|a| var_occurrences(a, &mut elsewhere));
            }
            for goal in schema.on_kb.iter() {
                goal.for_each_call(&mut |l| term_vars(&l.term, &mut elsewhere));
            }
            for literal in schema.invalid.iter() {
                let mut own = Vec::new();
                for (i, a) in literal.args.iter().enumerate() {
                    if !relaxation.is_dropped(literal.pred, i) {
                        var_occurrences(a, &mut own);
                    }
                }
                needed.extend(own.into_iter().filter(|v| elsewhere.contains(v)));
            }
            for head in &heads {
                for (i, a) in head.args.iter().enumerate() {
                    if !relaxation.is_dropped(head.pred, i) {
                        var_occurrences(a, &mut needed);
                    }
                }
            }
            for goal in schema.on_kb.iter() {
                goal.for_each_call(&mut |l| term_vars(&l.term, &mut needed));
            }
            for term in schema.invalid_at_end.iter() {
                term_vars(term, &mut needed);
            }
            let mut in_body = Vec::new();
            for literal in valid.iter() {
                literal.args.iter().for_each(|a| var_occurrences(a, &mut in_body));
            }
            let body: Vec<BodyLiteral> = valid
                .iter()
                .map(|literal| {
                    let keep: Vec<u32> = (0..literal.args.len() as u32)
                        .filter(|&i| !relaxation.is_dropped(literal.pred, i as usize))
                        .filter(|&i| match &literal.args[i as usize] {
                            Pattern::Var(v) => {
                                !project || needed.contains(v) || in_body.iter().filter(|&&w| w == *v).count() > 1
                            }
                            _ => true,
                        })
                        .collect();
                    let args = keep.iter().map(|&i| literal.args[i as usize].clone()).collect();
                    BodyLiteral { view: relaxation.view(literal.pred, &keep), args }
                })
                .collect();
            let orders = (0..body.len()).map(|trigger| join_order(&body, trigger, &mut index_positions)).collect();
            relaxation.rules.push(Rule {
                schema: index as u32,
                vars: schema.vars,
                body: body.into_boxed_slice(),
                heads: heads.into_boxed_slice(),
                orders,
                invalid: schema.invalid.clone(),
                dels: dels.into_boxed_slice(),
                exclusion: None,
                filters: Vec::new(),
                checks: Box::default(),
            });
        }
        // A view of whole facts for each negated predicate: the facts a negative condition
        // may have to wait for the deletion of.
        for pred in negated {
            let keep = relaxation.kept(task, pred);
            let view = relaxation.view(pred, &keep);
            relaxation.negated_views.push(view);
        }
        for (g, literal) in task.goal.iter().enumerate() {
            if project && task.resource_goal[g] {
                continue;
            }
            let keep = relaxation.kept(task, literal.pred);
            let view = relaxation.view(literal.pred, &keep);
            let args = keep.iter().map(|&i| literal.args[i as usize].clone()).collect();
            relaxation.goal.push(BodyLiteral { view, args });
            relaxation.goal_index.push(g);
        }
        if project {
            for (r, schema) in task.schemas.iter().enumerate() {
                let exclusion = find_exclusion(&relaxation, schema, &relaxation.rules[r]);
                relaxation.rules[r].exclusion = exclusion;
            }
        }
        relaxation.triggers = vec![Vec::new(); relaxation.views.len()];
        for (r, rule) in relaxation.rules.iter().enumerate() {
            for (position, literal) in rule.body.iter().enumerate() {
                relaxation.triggers[literal.view as usize].push((r as u32, position as u32));
            }
        }
        relaxation.tables = relaxation
            .views
            .iter()
            .enumerate()
            .map(|(view, v)| {
                let positions = index_positions.remove(&(view as u32)).unwrap_or_default();
                let indexes = positions.into_iter().map(|positions| Index { positions, tuples: FxHashMap::default() });
                Table { arity: v.keep.len(), indexes: indexes.collect(), ..Table::default() }
            })
            .collect();
        relaxation
    }

    /// Leaves the join without [`Index`]es: each step scans every settled tuple of its
    /// literal, the reference the tests hold the indexed joins to.
    pub fn without_join_indexes(&mut self) {
        for order in self.rules.iter_mut().flat_map(|rule| rule.orders.iter_mut()) {
            order.iter_mut().for_each(|step| step.lookup = None);
        }
    }

    /// Leaves the join without [`FactFilter`]s: every instantiation asks the engine, the
    /// reference the tests hold the filtered joins to.
    pub fn without_fact_filters(&mut self) {
        self.filtered = true;
    }

    /// The number of [`FactFilter`]s the rules have (found at the first exploration).
    pub fn fact_filters(&self) -> usize {
        self.rules.iter().map(|r| r.filters.len()).sum()
    }

    /// Grounds every rule instantiation as one action, with no exclusion nodes (see
    /// [`Exclusion`]): the reference the tests hold the smaller ground task to.
    pub fn ground_every_instantiation(&mut self) {
        for rule in &mut self.rules {
            rule.exclusion = None;
        }
    }

    /// The number of rules the ground task reads through exclusion nodes.
    pub fn exclusions(&self) -> usize {
        self.rules.iter().filter(|r| r.exclusion.is_some()).count()
    }

    /// The goal literals (indices into `Task::goal`) the last exploration did not reach.
    pub fn unreached_goals(&self) -> &[usize] {
        &self.unreached
    }

    fn is_dropped(&self, pred: PredId, position: usize) -> bool {
        self.dropped.get(&pred).is_some_and(|d| d.get(position).copied().unwrap_or(false))
    }

    /// The positions of `pred` every view keeps.
    fn kept(&self, task: &Task, pred: PredId) -> Vec<u32> {
        let arity = task.facts.pred_info(pred).1;
        (0..arity as u32).filter(|&i| !self.is_dropped(pred, i as usize)).collect()
    }

    /// The values of a literal's arguments under `bindings`, with [`DROPPED`] at the dropped
    /// positions left unbound; `false` if another position is unbound.
    fn literal_values(
        &self,
        literal: &LiteralPattern,
        task: &mut Task,
        bindings: &[Option<ConstId>],
        out: &mut Vec<ConstId>,
    ) -> bool {
        out.clear();
        for (i, a) in literal.args.iter().enumerate() {
            match instantiate(a, &mut task.consts, bindings) {
                Some(value) => out.push(value),
                None if self.is_dropped(literal.pred, i) => out.push(DROPPED),
                None => return false,
            }
        }
        true
    }

    /// The whole-fact (negated) view of `pred`.
    fn negated_view(&self, pred: PredId) -> Option<u32> {
        let views = self.views_of_pred.get(&pred)?;
        self.negated_views.iter().copied().find(|v| views.contains(v))
    }

    fn view(&mut self, pred: PredId, keep: &[u32]) -> u32 {
        let views = self.views_of_pred.entry(pred).or_default();
        if let Some(&v) = views.iter().find(|&&v| &*self.views[v as usize].keep == keep) {
            return v;
        }
        let id = self.views.len() as u32;
        self.views.push(View { keep: keep.into() });
        views.push(id);
        id
    }

    fn relax(&mut self, view: u32, values: &[ConstId], cost: u32, support: Support) -> bool {
        if self.limits.exhausted.is_some() {
            return false;
        }
        let table = &self.tables[view as usize];
        if table.cost.len() == table.cost.capacity() || self.queue.len() == self.queue.capacity() {
            // About to grow: a table or the queue roughly doubles, so check the memory budget
            // before the allocation rather than after it. While a vector moves to its doubled
            // allocation, the old one is still held: twice its size more, for a moment.
            let queue = self.queue.capacity() * std::mem::size_of::<Reverse<(u32, u32, u32)>>();
            let growth = 2 * (table.footprint() + queue);
            if self.footprint() + growth > self.limits.max_bytes {
                self.limits.exhausted = Some(BudgetKind::Memory);
                return false;
            }
        }
        if table.lookup.len() == table.lookup.capacity() && !self.grow_lookup(view) {
            self.limits.exhausted = Some(BudgetKind::Time);
            return false;
        }
        let table = &mut self.tables[view as usize];
        let (t, _) = table.find_or_insert(&self.hasher, values);
        if table.done[t as usize] || cost >= table.cost[t as usize] {
            return false;
        }
        table.cost[t as usize] = cost;
        table.support[t as usize] = support;
        self.queue.push(Reverse((cost, view, t)));
        true
    }

    /// Doubles the lookup table of `view`, which is full, unless the time that takes (predicted
    /// from the last growth) would end past the deadline: then `false`. Growing it here rather
    /// than inside an insertion is what lets the budget see it coming.
    fn grow_lookup(&mut self, view: u32) -> bool {
        let Some(deadline) = self.limits.deadline else { return true };
        let table = &mut self.tables[view as usize];
        let entries = table.lookup.len();
        if entries < 1 << 16 {
            return true; // milliseconds at most
        }
        let now = std::time::Instant::now();
        let predicted = std::time::Duration::from_nanos((self.limits.rehash_ns * entries as f64) as u64);
        if now + predicted >= deadline {
            return false;
        }
        let (hasher, arity, store) = (&self.hasher, table.arity, &table.values);
        table.lookup.reserve(entries, |&u| hasher.hash_one(&store[u as usize * arity..(u as usize + 1) * arity]));
        self.limits.rehash_ns = now.elapsed().as_nanos() as f64 / entries as f64;
        true
    }

    /// Frees the relaxation, a large one on another thread. One that ran out of budget may hold a gigabyte
    /// in millions of allocations, and freeing them can take a second: past the deadline, the
    /// caller should not wait for it. (A process that exits first just leaves it to the OS.)
    pub fn discard(self) {
        if self.footprint() < 64 << 20 {
            return; // dropped here, quickly
        }
        let _ = std::thread::Builder::new().name("kbc-free".into()).spawn(move || drop(self));
    }

    /// Offers a full fact to every view of its predicate.
    fn offer(&mut self, pred: PredId, values: &[ConstId], cost: u32, support: Support) -> bool {
        let Some(count) = self.views_of_pred.get(&pred).map(Vec::len) else { return false };
        // (The projection in scratch space: offers come by the hundred thousand while
        // grounding. With a fresh vector and a copy of the view list for each, and the heads
        // cloned in `fire`, reverse_b100_a8_s1's grounding took 4557 M instructions; 3892 M
        // without.)
        let mut projected = std::mem::take(&mut self.projected);
        let mut supported = false;
        for k in 0..count {
            let view = self.views_of_pred[&pred][k];
            projected.clear();
            projected.extend(self.views[view as usize].keep.iter().map(|&i| values[i as usize]));
            supported |= self.relax(view, &projected, cost, support);
        }
        self.projected = projected;
        supported
    }

    /// Evaluates `state`. With `plan`, also extracts the relaxed plan (h_FF, helpful actions).
    pub fn evaluate(
        &mut self,
        task: &mut Task,
        state: &State,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        plan: bool,
    ) -> Result<Estimate, Stop> {
        if self.ground.is_some() {
            return Ok(self.evaluate_ground(task, state, plan));
        }
        self.explore(task, state, machine, cache, plan, true)
    }

    /// Grounds the relaxed task: explores everything reachable from the initial state ignoring
    /// deletions, recording every rule instantiation, and from then on evaluates states on
    /// the ground actions, which is many times faster than joining lifted rules again for each
    /// state. Everything reachable from a reachable state is reachable from the initial state,
    /// so the ground task serves every state the search meets. Gives up (returns `false`, and
    /// evaluation stays lifted) beyond `limit` instantiations.
    ///
    /// With `negative`, the ground task also keeps the Invalid conditions the lifted
    /// relaxation drops: an action waits until every fact its Invalid literal forbids is either
    /// absent from the state or deleted by some action of the relaxed plan. Relaxed
    /// reachability still follows from real reachability, so dead ends stay sound, and the
    /// estimate sees, for instance, that a cell must be emptied before a block can stand there.
    pub fn ground(
        &mut self,
        task: &mut Task,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        limit: usize,
        negative: bool,
    ) -> Result<bool, Stop> {
        self.recorder = Some(Recorder {
            seen: HashTable::new(),
            actions: Vec::new(),
            instances: Numbered::new(),
            groups: Numbered::new(),
            exclusions: Numbered::new(),
            limit,
            max_bytes: self.limits.max_bytes / 2,
            bytes: 0,
            overflowed: false,
        });
        let init = task.init.clone();
        // (Grounding stops early where the exploration makes many new values, see
        // [`GROUND_NEW_CONSTANTS`].)
        let limit_constants = self.limits.max_new_constants;
        self.limits.max_new_constants = limit_constants.min(GROUND_NEW_CONSTANTS.max(task.consts.len()));
        let explored = self.explore(task, &init, machine, cache, false, false);
        self.limits.max_new_constants = limit_constants;
        let recorder = self.recorder.take().expect("set above");
        // An exploration without end cannot be grounded; evaluated lifted, a state's stops at
        // its goals, if it reaches them.
        if recorder.overflowed || matches!(explored, Err(Stop::Budget(BudgetKind::Constants))) {
            return Ok(false);
        }
        explored?;
        let sizes: Vec<usize> = self.tables.iter().map(|t| t.cost.len()).collect();
        let goals: Vec<Vec<(u32, u32)>> = self
            .goal
            .iter()
            .map(|goal| {
                let table = &self.tables[goal.view as usize];
                let mut scratch = vec![None; task.goal_vars];
                let mut trail = Vec::new();
                (0..table.cost.len() as u32)
                    .filter(|&t| {
                        let ok = goal
                            .args
                            .iter()
                            .zip(table.tuple(t))
                            .all(|(p, v)| match_pattern(p, *v, &task.consts, &mut scratch, &mut trail));
                        undo(&mut scratch, &mut trail, 0);
                        ok
                    })
                    .map(|t| (goal.view, t))
                    .collect()
            })
            .collect();
        let schemas: Vec<u32> = self.rules.iter().map(|r| r.schema).collect();
        // The facts each Invalid literal instance forbids: the reachable whole facts of its
        // predicate that match it.
        let mut scratch = Vec::new();
        let mut trail = Vec::new();
        let candidates: Vec<Vec<(u32, u32)>> = recorder
            .instances
            .list
            .iter()
            .map(|(rule, literal, bindings)| {
                let literal = &self.rules[*rule as usize].invalid[*literal as usize];
                let Some(view) = self.negated_view(literal.pred) else { return Vec::new() };
                let table = &self.tables[view as usize];
                let keep = &self.views[view as usize].keep;
                (0..table.cost.len() as u32)
                    .filter(|&t| {
                        scratch.clear();
                        scratch.extend_from_slice(bindings);
                        let ok = keep
                            .iter()
                            .map(|&i| &literal.args[i as usize])
                            .zip(table.tuple(t))
                            .all(|(p, v)| match_pattern(p, *v, &task.consts, &mut scratch, &mut trail));
                        trail.clear();
                        ok
                    })
                    .map(|t| (view, t))
                    .collect()
            })
            .collect();
        let negative = if negative { Some((self.negated_views.as_slice(), candidates.as_slice())) } else { None };
        let auxiliary = self.exclusion_nodes(&recorder.groups.list, &recorder.exclusions.list);
        let mut ground = GroundTask::new(&sizes, recorder.actions, &schemas, &goals, negative, auxiliary);
        let start = self.state_tuples(task, &init);
        self.landmarks = Some(Landmarks::compute(&mut ground, &start));
        self.ground = Some(ground);
        Ok(true)
    }

    /// The ground task's exclusion nodes (see [`Exclusion`]), one per number of `list`.
    ///
    /// A group's tuples are sorted by the values of their excluded variables, into runs of
    /// equal values. Prefix nodes `P_j` (the cheapest tuple of runs `0..=j`) and suffix nodes
    /// `S_j` (of runs `j..`) are each achieved, at no cost, by the tuples of their run and by
    /// the previous prefix or the next suffix. The node excluding the values of run `j` is
    /// achieved by `P_{j-1}` and `S_{j+1}`; one excluding values no tuple has (or nothing) is
    /// the last prefix. So each node costs the cheapest tuple of the group not excluded, as an
    /// action reading it directly would, in a number of nodes and links linear in the group.
    fn exclusion_nodes(&self, groups: &[GroupKey], list: &[ExclusionKey]) -> Auxiliary {
        let mut auxiliary = Auxiliary {
            exclusion_node: vec![0; list.len()],
            choices: vec![[0; 4]; list.len()],
            ..Auxiliary::default()
        };
        let group_ids: FxHashMap<(u32, &[ConstId]), u32> =
            groups.iter().enumerate().map(|(id, (rule, values))| ((*rule, &values[..]), id as u32)).collect();
        let mut exclusions_of: Vec<Vec<usize>> = vec![Vec::new(); groups.len()];
        for (i, (group, _)) in list.iter().enumerate() {
            exclusions_of[*group as usize].push(i);
        }
        // Each group's tuples, with the values of their excluded variables.
        let mut members: Vec<Vec<(Box<[ConstId]>, u32)>> = vec![Vec::new(); groups.len()];
        let mut rules: Vec<u32> = groups.iter().map(|(rule, _)| *rule).collect();
        rules.sort_unstable();
        rules.dedup();
        let mut values = Vec::new();
        for rule in rules {
            let exclusion = self.rules[rule as usize].exclusion.as_ref().expect("recorded by a rule with one");
            let table = &self.tables[self.excluded_view(rule) as usize];
            for t in 0..table.cost.len() as u32 {
                let tuple = table.tuple(t);
                values.clear();
                values.extend(exclusion.group.iter().map(|&i| tuple[i as usize]));
                if let Some(&id) = group_ids.get(&(rule, values.as_slice())) {
                    let key = exclusion.pairs.iter().map(|&(i, _)| tuple[i as usize]).collect();
                    members[id as usize].push((key, t));
                }
            }
        }
        let groups = groups.iter().map(|(rule, _)| *rule).zip(exclusions_of);
        for ((rule, exclusions), mut members) in groups.zip(members) {
            let view = self.excluded_view(rule);
            members.sort_unstable();
            let mut runs: Vec<(&[ConstId], std::ops::Range<usize>)> = Vec::new();
            for (m, (key, _)) in members.iter().enumerate() {
                match runs.last_mut() {
                    Some((last, range)) if *last == &key[..] => range.end = m + 1,
                    _ => runs.push((key, m..m + 1)),
                }
            }
            let k = runs.len() as u32;
            let first = auxiliary.members.len() as u32;
            let end = first + members.len() as u32;
            auxiliary.members.extend(members.iter().map(|&(_, t)| (view, t)));
            let prefix = auxiliary.count;
            let suffix = prefix + k;
            auxiliary.count += 2 * k;
            for (j, (_, range)) in runs.iter().enumerate() {
                let j = j as u32;
                for (_, t) in &members[range.clone()] {
                    auxiliary.links.push((Source::Tuple(view, *t), prefix + j));
                    auxiliary.links.push((Source::Tuple(view, *t), suffix + j));
                }
                if j > 0 {
                    auxiliary.links.push((Source::Aux(prefix + j - 1), prefix + j));
                }
                if j + 1 < k {
                    auxiliary.links.push((Source::Aux(suffix + j + 1), suffix + j));
                }
            }
            for i in exclusions {
                let run = list[i].1.as_ref().and_then(|key| runs.binary_search_by(|(r, _)| (*r).cmp(key)).ok());
                let skip = run.map_or(0..0, |j| runs[j].1.clone());
                auxiliary.choices[i] = [first, end, first + skip.start as u32, first + skip.end as u32];
                auxiliary.exclusion_node[i] = match run {
                    Some(j) => {
                        let j = j as u32;
                        let node = auxiliary.count;
                        auxiliary.count += 1;
                        if j > 0 {
                            auxiliary.links.push((Source::Aux(prefix + j - 1), node));
                        }
                        if j + 1 < k {
                            auxiliary.links.push((Source::Aux(suffix + j + 1), node));
                        }
                        node
                    }
                    // Every tuple of the group qualifies (it has one: an instantiation read it).
                    None => prefix + k - 1,
                };
            }
        }
        auxiliary
    }

    /// The view of the literal `rule` reads through exclusion nodes.
    fn excluded_view(&self, rule: u32) -> u32 {
        let rule = &self.rules[rule as usize];
        let exclusion = rule.exclusion.as_ref().expect("recorded by a rule with one");
        rule.body[exclusion.literal as usize].view
    }

    /// Bounds every exploration by the search's budget: one stops with [`Stop::Budget`] at
    /// `deadline` or once its tables take more than `max_bytes`. [`Relaxation::ground`] also
    /// gives up grounding once its recorded instantiations would take more than half of
    /// `max_bytes`, and evaluation stays lifted (slower per state, but within memory).
    pub fn limit(&mut self, budget: &super::Budget) {
        self.limits = Limits::new(budget.deadline, budget.max_bytes);
        self.limits.max_new_constants = budget.max_new_constants;
    }

    /// The bytes the exploration tables, and while grounding the recorded instantiations, hold.
    fn footprint(&self) -> usize {
        self.recorder.as_ref().map_or(0, |r| r.bytes)
            + self.tables.iter().map(Table::footprint).sum::<usize>()
            + self.arena.capacity() * std::mem::size_of::<Option<ConstId>>()
            + self.queue.capacity() * std::mem::size_of::<Reverse<(u32, u32, u32)>>()
    }

    /// Counts one step of work and, every [`CHECK_EVERY`] steps, checks the budget. Grounding
    /// that has given up also stops the exploration: the rest of it would be wasted.
    fn tick(&mut self) -> Result<(), Stop> {
        if let Some(kind) = self.limits.exhausted {
            return Err(Stop::Budget(kind));
        }
        self.limits.ticks += 1;
        if self.limits.ticks < CHECK_EVERY {
            return Ok(());
        }
        self.limits.ticks = 0;
        if self.recorder.as_ref().is_some_and(|r| r.overflowed) {
            return Err(Stop::Budget(BudgetKind::Memory));
        }
        if self.limits.deadline.is_some_and(|d| std::time::Instant::now() >= d) {
            return Err(Stop::Budget(BudgetKind::Time));
        }
        Ok(())
    }

    /// Makes evaluations of the ground task fill in [`Estimate::plan`] (or stop doing so).
    pub fn keep_relaxed_plans(&mut self, keep: bool) {
        if let Some(ground) = self.ground.as_mut() {
            ground.keep_plan = keep;
        }
    }

    /// The number of ground actions, when grounded.
    pub fn ground_actions(&self) -> Option<usize> {
        self.ground.as_ref().map(GroundTask::action_count)
    }

    /// True if `action` achieves one of `subgoals` (an [`Estimate::subgoals`] of the ground
    /// task): it adds a fact that projects onto one, or deletes a fact whose absence is one.
    pub fn achieves_subgoal(&self, task: &mut Task, action: &super::successors::Applicable, subgoals: &[u32]) -> bool {
        let Some(ground) = &self.ground else { return false };
        if subgoals.is_empty() {
            return false;
        }
        let schema = &task.schemas[action.schema];
        let effects: Vec<(EffectKind, LiteralPattern)> = schema.effects.to_vec();
        let mut full = Vec::new();
        let mut projected = Vec::new();
        for (kind, literal) in &effects {
            if !self.literal_values(literal, task, &action.bindings, &mut full) {
                continue;
            }
            let negated = self.negated_view(literal.pred);
            let views: &[u32] = match kind {
                EffectKind::Add => self.views_of_pred.get(&literal.pred).map_or(&[], Vec::as_slice),
                EffectKind::Del => negated.as_slice(),
            };
            for &view in views {
                projected.clear();
                projected.extend(self.views[view as usize].keep.iter().map(|&i| full[i as usize]));
                let Some(t) = self.tables[view as usize].find(&self.hasher, &projected) else { continue };
                let node = match kind {
                    EffectKind::Add => ground.offsets[view as usize] + t,
                    EffectKind::Del => match ground.negation_base[view as usize] {
                        u32::MAX => continue,
                        base => base + t,
                    },
                };
                if subgoals.binary_search(&node).is_ok() {
                    return true;
                }
            }
        }
        false
    }

    /// The number of landmarks, when grounded.
    pub fn landmark_count(&self) -> Option<usize> {
        self.landmarks.as_ref().map(Landmarks::len)
    }

    /// The view tuples of `state`'s facts.
    fn state_tuples(&self, task: &Task, state: &State) -> Vec<(u32, u32)> {
        let mut start = Vec::with_capacity(state.len() * 2);
        let mut projected = Vec::new();
        for_each_relaxed_fact(task, state, |pred, values| {
            let Some(views) = self.views_of_pred.get(&pred) else { return };
            for &view in views {
                projected.clear();
                projected.extend(self.views[view as usize].keep.iter().map(|&i| values[i as usize]));
                if let Some(t) = self.tables[view as usize].find(&self.hasher, &projected) {
                    start.push((view, t));
                }
            }
        });
        start
    }

    fn evaluate_ground(&mut self, task: &Task, state: &State, plan: bool) -> Estimate {
        let start = self.state_tuples(task, state);
        let ground = self.ground.as_mut().expect("called only when grounded");
        let estimate = ground.evaluate(&start, plan);
        self.unreached = ground.unreached().iter().map(|&g| self.goal_index[g]).collect();
        estimate
    }

    /// Evaluates `state` for the search: the estimate with its relaxed plan and, when the
    /// task is grounded, the landmarks accepted on the path to it (from its parent's set,
    /// `None` at the root) and the landmark count.
    pub fn evaluate_for_search(
        &mut self,
        task: &mut Task,
        state: &State,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        parent: Option<&[u64]>,
    ) -> Result<(Estimate, Option<(Accepted, u32)>), Stop> {
        if self.ground.is_none() || self.landmarks.is_none() {
            return Ok((self.explore(task, state, machine, cache, true, true)?, None));
        }
        let start = self.state_tuples(task, state);
        let ground = self.ground.as_mut().expect("checked above");
        let mut estimate = ground.evaluate(&start, true);
        self.unreached = ground.unreached().iter().map(|&g| self.goal_index[g]).collect();
        for step in &mut estimate.plan {
            let chosen = &self.chosen_vars[step.action.schema];
            if chosen.is_empty() {
                continue;
            }
            // The values of the fact it was chosen for (none for a negation or auxiliary
            // node: then every chosen value is kept).
            let purpose = step.purpose;
            let values: &[ConstId] = if (purpose as usize) < ground.tuples {
                let view = ground.offsets.partition_point(|&o| o <= purpose) - 1;
                self.tables[view].tuple(purpose - ground.offsets[view])
            } else {
                &[]
            };
            let bindings = &step.action.bindings;
            step.chosen = chosen.iter().copied().filter(|&v| bindings[v as usize].is_some()).collect();
            let matters = chosen.iter().any(|&v| bindings[v as usize].is_some_and(|c| values.contains(&c)));
            if (!matters || step.detour) && (purpose as usize) < ground.tuples {
                step.loose = chosen.iter().copied().filter(|&v| bindings[v as usize].is_some()).collect();
            }
        }
        for &(view, t) in &start {
            ground.present[(ground.offsets[view as usize] + t) as usize] = true;
        }
        let progress = self.landmarks.as_ref().expect("checked above").progress(parent, &ground.present);
        for &(view, t) in &start {
            ground.present[(ground.offsets[view as usize] + t) as usize] = false;
        }
        Ok((estimate, Some(progress)))
    }

    /// Explores everything reachable from `state` ignoring deletions, not stopping at the
    /// goal; afterwards [`Relaxation::reached`] answers for any fact.
    pub fn evaluate_all(
        &mut self,
        task: &mut Task,
        state: &State,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
    ) -> Result<Estimate, Stop> {
        self.explore(task, state, machine, cache, false, false)
    }

    /// True if, in the last exploration, some reached fact of `literal`'s predicate matches it
    /// under `bindings`. Only meaningful for a relaxation built with
    /// [`Relaxation::unprojected`], whose views hold whole facts.
    pub fn reached(&self, task: &Task, literal: &LiteralPattern, bindings: &[Option<ConstId>]) -> bool {
        let Some(views) = self.views_of_pred.get(&literal.pred) else { return false };
        let Some(&view) = views.iter().find(|&&v| self.views[v as usize].keep.len() == literal.args.len()) else {
            return false;
        };
        let table = &self.tables[view as usize];
        let mut scratch = bindings.to_vec();
        let mut trail = Vec::new();
        table.settled.iter().any(|&t| {
            let ok = literal
                .args
                .iter()
                .zip(table.tuple(t))
                .all(|(p, v)| match_pattern(p, *v, &task.consts, &mut scratch, &mut trail));
            undo(&mut scratch, &mut trail, 0);
            ok
        })
    }

    /// Finds each rule's [`FactFilter`]s, and the step of each join order where all of a
    /// filter's variables are bound.
    fn find_filters(&mut self, task: &mut Task, machine: &mut Machine<'_>) {
        self.filtered = true;
        let program = machine.program();
        for r in 0..self.rules.len() {
            let Task { schemas, consts, .. } = &mut *task;
            let schema = &schemas[self.rules[r].schema as usize];
            let mut leading = Vec::new();
            leading_fact_calls(&schema.on_kb, program, &mut leading);
            let mut in_body = Vec::new();
            for literal in self.rules[r].body.iter() {
                literal.args.iter().for_each(|a| var_occurrences(a, &mut in_body));
            }
            let mut filters = Vec::new();
            for goal in leading {
                let mut vars = Vec::new();
                goal.for_each_call(&mut |l| term_vars(&l.term, &mut vars));
                let mut kept: Vec<u32> = Vec::new();
                for v in vars {
                    if in_body.contains(&v) && !kept.contains(&v) {
                        kept.push(v);
                    }
                }
                if kept.is_empty() {
                    continue;
                }
                if let Some(tuples) = fact_tuples(machine, consts, schema, &goal, &kept, FACT_FILTER_LIMIT) {
                    filters.push(FactFilter { vars: kept.into_boxed_slice(), tuples });
                }
            }
            if filters.is_empty() {
                continue;
            }
            let rule = &self.rules[r];
            let checks = (0..rule.body.len())
                .map(|trigger| {
                    let order = &rule.orders[trigger];
                    let mut bound = Vec::new();
                    rule.body[trigger].args.iter().for_each(|a| var_occurrences(a, &mut bound));
                    let mut placed = vec![false; filters.len()];
                    (0..=order.len())
                        .map(|step| {
                            if step > 0 {
                                let literal = &rule.body[order[step - 1].literal as usize];
                                literal.args.iter().for_each(|a| var_occurrences(a, &mut bound));
                            }
                            let ready: Box<[u32]> = (0..filters.len())
                                .filter(|&f| {
                                    let ready = !placed[f] && filters[f].vars.iter().all(|v| bound.contains(v));
                                    placed[f] |= ready;
                                    ready
                                })
                                .map(|f| f as u32)
                                .collect();
                            ready
                        })
                        .collect()
                })
                .collect();
            self.rules[r].filters = filters;
            self.rules[r].checks = checks;
        }
    }

    fn explore(
        &mut self,
        task: &mut Task,
        state: &State,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        plan: bool,
        stop_at_goal: bool,
    ) -> Result<Estimate, Stop> {
        self.limits.exhausted = None;
        if !self.filtered {
            self.find_filters(task, machine);
        }
        for table in &mut self.tables {
            table.clear();
        }
        self.queue.clear();
        self.arena.clear();
        let mut initial: Vec<(PredId, Vec<ConstId>)> = Vec::new();
        for_each_relaxed_fact(task, state, |pred, values| initial.push((pred, values.to_vec())));
        for (pred, values) in initial {
            self.offer(pred, &values, 0, Support::State);
        }
        let mut reached: Vec<Option<(u32, u32)>> = vec![None; self.goal.len()];
        let mut remaining = self.goal.len();
        let mut h_add: u32 = 0;
        // Rules with an empty body fire once, from nothing.
        for r in 0..self.rules.len() {
            if self.rules[r].body.is_empty() {
                let vars = self.rules[r].vars;
                let mut bindings = vec![None; vars];
                self.fire(task, machine, cache, r, &mut bindings, 0)?;
            }
        }
        let mut goal_bindings: Vec<Option<ConstId>> = vec![None; task.goal_vars];
        let mut trail = Vec::new();
        let most_constants = task.consts.len().saturating_add(self.limits.max_new_constants);
        while remaining > 0 || !stop_at_goal {
            let Some(Reverse((cost, view, t))) = self.queue.pop() else { break };
            self.tick()?;
            if task.consts.len() > most_constants {
                return Err(Stop::Budget(BudgetKind::Constants));
            }
            let table = &mut self.tables[view as usize];
            if table.done[t as usize] || cost > table.cost[t as usize] {
                continue;
            }
            table.done[t as usize] = true;
            table.settled.push(t);
            let arity = table.arity;
            let values = &table.values[t as usize * arity..(t as usize + 1) * arity];
            for index in &mut table.indexes {
                let key = index_key(&self.hasher, index.positions.iter().map(|&p| values[p as usize]));
                index.tuples.entry(key).or_default().push(t);
            }
            for (g, goal) in self.goal.iter().enumerate() {
                if reached[g].is_some() || goal.view != view {
                    continue;
                }
                let values = self.tables[view as usize].tuple(t);
                let ok = goal
                    .args
                    .iter()
                    .zip(values)
                    .all(|(p, v)| match_pattern(p, *v, &task.consts, &mut goal_bindings, &mut trail));
                undo(&mut goal_bindings, &mut trail, 0);
                if ok {
                    reached[g] = Some((view, t));
                    remaining -= 1;
                    h_add = h_add.saturating_add(cost);
                }
            }
            if remaining == 0 && stop_at_goal {
                break;
            }
            let triggers = self.triggers[view as usize].clone();
            for (rule, position) in triggers {
                self.join_from(task, machine, cache, rule as usize, position as usize, t)?;
            }
        }
        self.unreached =
            reached.iter().enumerate().filter(|(_, r)| r.is_none()).map(|(g, _)| self.goal_index[g]).collect();
        if remaining > 0 {
            return Ok(Estimate::default());
        }
        let mut estimate = Estimate { h_add: Some(h_add), ..Estimate::default() };
        if plan {
            self.relaxed_plan(task, &reached, &mut estimate);
        }
        Ok(estimate)
    }

    /// Joins settled tuple `t`, as body literal `position` of `rule`, with the settled tuples
    /// of the rule's other body literals, and fires every complete instantiation.
    fn join_from(
        &mut self,
        task: &mut Task,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        rule: usize,
        position: usize,
        t: u32,
    ) -> Result<(), Stop> {
        let vars = self.rules[rule].vars;
        let mut bindings = vec![None; vars];
        let mut trail = Vec::new();
        let literal = &self.rules[rule].body[position];
        let table = &self.tables[literal.view as usize];
        let values = table.tuple(t).to_vec();
        let cost = table.cost[t as usize];
        if !literal.args.iter().zip(&values).all(|(p, v)| match_pattern(p, *v, &task.consts, &mut bindings, &mut trail))
        {
            return Ok(());
        }
        let order: Box<[JoinStep]> = self.rules[rule].orders[position].clone();
        self.join(task, machine, cache, (rule, position), &order, 0, &mut bindings, &mut trail, cost)
    }

    /// True unless one of the filters of `rule` checked at `step` of the join order of
    /// trigger `position` rules out `bindings`.
    fn passes(&self, rule: usize, position: usize, step: usize, bindings: &[Option<ConstId>]) -> bool {
        let rule = &self.rules[rule];
        let Some(checks) = rule.checks.get(position).and_then(|steps| steps.get(step)) else { return true };
        let mut values = Vec::new();
        checks.iter().all(|&f| {
            let filter = &rule.filters[f as usize];
            values.clear();
            values.extend(filter.vars.iter().map(|&v| bindings[v as usize].expect("bound by this step")));
            filter.tuples.contains(values.as_slice())
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn join(
        &mut self,
        task: &mut Task,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        (rule, position): (usize, usize),
        order: &[JoinStep],
        step: usize,
        bindings: &mut Vec<Option<ConstId>>,
        trail: &mut Vec<u32>,
        cost: u32,
    ) -> Result<(), Stop> {
        if !self.passes(rule, position, step, bindings) {
            return Ok(());
        }
        let Some(&JoinStep { literal, lookup }) = order.get(step) else {
            return self.fire(task, machine, cache, rule, bindings, cost);
        };
        let view = self.rules[rule].body[literal as usize].view as usize;
        let candidates: Vec<u32> = match lookup {
            Some(number) => {
                let args = &self.rules[rule].body[literal as usize].args;
                let index = &self.tables[view].indexes[number as usize];
                let values = index.positions.iter().map(|&p| match &args[p as usize] {
                    Pattern::Const(c) => *c,
                    Pattern::Var(v) => bindings[*v as usize].expect("bound before this step"),
                    Pattern::Compound(..) => unreachable!("an index has no compound position"),
                });
                let key = index_key(&self.hasher, values);
                index.tuples.get(&key).cloned().unwrap_or_default()
            }
            None => self.tables[view].settled.clone(),
        };
        for u in candidates {
            self.tick()?;
            let mark = trail.len();
            let table = &self.tables[view];
            let args = &self.rules[rule].body[literal as usize].args;
            let ok = args.iter().zip(table.tuple(u)).all(|(p, v)| match_pattern(p, *v, &task.consts, bindings, trail));
            let extra = table.cost[u as usize];
            if ok {
                let at = (rule, position);
                self.join(task, machine, cache, at, order, step + 1, bindings, trail, cost.saturating_add(extra))?;
            }
            undo(bindings, trail, mark);
        }
        Ok(())
    }

    /// Applies the filters to a complete instantiation and offers its heads.
    fn fire(
        &mut self,
        task: &mut Task,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        rule: usize,
        bindings: &mut [Option<ConstId>],
        cost: u32,
    ) -> Result<(), Stop> {
        let schema_index = self.rules[rule].schema as usize;
        let solutions = if task.schemas[schema_index].on_kb.is_empty() {
            None
        } else {
            let Task { consts, schemas, .. } = task;
            Some(
                cache
                    .solutions(machine, consts, &schemas[schema_index], schema_index, bindings)
                    .map_err(|error| ConditionError { schema: schema_index, error, duration: false })?,
            )
        };
        let unbound: Vec<u32> =
            cache.vars(schema_index).iter().copied().filter(|&v| bindings[v as usize].is_none()).collect();
        let cost = cost.saturating_add(1);
        let offer = |relaxation: &mut Relaxation, task: &mut Task, bindings: &[Option<ConstId>]| {
            let schema = &task.schemas[schema_index];
            for term in schema.invalid_at_end.iter() {
                let forbidden = substitute(term, &task.consts, bindings);
                if task.goal_terms.iter().any(|g| unifiable(&forbidden, g)) {
                    return;
                }
            }
            if relaxation.recorder.is_some() {
                relaxation.record(task, rule, bindings);
            }
            // The bindings go into the arena only when some fact takes this instantiation as
            // its support (most offers come too late): at the arena's end, where nothing else
            // is added meanwhile. (Stored for every offer, the arena of reverse_b100_a10_s1
            // held about half the process's peak memory, and its reallocations and page
            // faults took 7% of the run's perf samples.)
            let at = relaxation.arena.len() as u32;
            let support = Support::Rule { rule: rule as u32, bindings: at };
            let mut values = std::mem::take(&mut relaxation.head_values);
            let mut supports = false;
            for h in 0..relaxation.rules[rule].heads.len() {
                let head = &relaxation.rules[rule].heads[h];
                let pred = head.pred;
                if relaxation.literal_values(head, task, bindings, &mut values) {
                    supports |= relaxation.offer(pred, &values, cost, support);
                }
            }
            relaxation.head_values = values;
            if supports {
                relaxation.arena.extend_from_slice(bindings);
            }
        };
        match solutions {
            None => offer(self, task, bindings),
            Some(solutions) => {
                let mut extended = bindings.to_vec();
                for i in 0..solutions.len() {
                    for (&v, value) in unbound.iter().zip(cache.solution(solutions, i)) {
                        extended[v as usize] = *value;
                    }
                    offer(self, task, &extended);
                }
            }
        }
        Ok(())
    }

    /// Records one rule instantiation that passed its filters, for grounding: as one ground
    /// action or, for a rule with an [`Exclusion`], as the two parts it describes.
    fn record(&mut self, task: &mut Task, rule: usize, bindings: &[Option<ConstId>]) {
        let Some(exclusion) = &self.rules[rule].exclusion else {
            self.record_part(task, rule, bindings, bindings, Part::Whole);
            return;
        };
        // Both parts' keys, in scratch space: most instantiations of a rule with an exclusion
        // (a move to each of 80 destinations) share both parts with one recorded before,
        // which is checked before anything is allocated.
        let width = bindings.len();
        let has_deletes = !exclusion.dels.is_empty();
        let mut keys = std::mem::take(&mut self.key);
        keys.clear();
        for (mask, keep) in [(&exclusion.excluded, false), (&exclusion.deleting, true)] {
            keys.extend(bindings.iter().zip(mask.iter()).map(|(&b, &m)| if m == keep { b } else { None }));
        }
        let (adds, deletes) = keys.split_at(width);
        let known = self.recorded(rule, adds).is_some() && (!has_deletes || self.recorded(rule, deletes).is_some());
        if !known {
            self.record_split(task, rule, bindings, adds, has_deletes.then_some(deletes));
        }
        self.key = keys;
    }

    /// Records the two parts of an instantiation of `rule`, which has an [`Exclusion`]: the
    /// one that adds, known by `adds`, and the one that deletes, known by `deletes` (none if
    /// the rule deletes nothing an Invalid literal reads).
    fn record_split(
        &mut self,
        task: &mut Task,
        rule: usize,
        bindings: &[Option<ConstId>],
        adds: &[Option<ConstId>],
        deletes: Option<&[Option<ConstId>]>,
    ) {
        let exclusion = self.rules[rule].exclusion.as_ref().expect("a rule with an exclusion");
        // The exclusion node: the group's values and the values the excluded ones must differ
        // from (none if one of those is unbound: then `E \== O` holds for every tuple).
        let literal = &self.rules[rule].body[exclusion.literal as usize];
        let group: Option<Box<[ConstId]>> = exclusion
            .group
            .iter()
            .map(|&i| instantiate(&literal.args[i as usize], &mut task.consts, bindings))
            .collect();
        let Some(group) = group else { return };
        let excluded: Option<Box<[ConstId]>> = exclusion.pairs.iter().map(|&(_, o)| bindings[o as usize]).collect();
        let Some(recorder) = self.recorder.as_mut() else { return };
        let group = recorder.groups.number((rule as u32, group));
        let node = recorder.exclusions.number((group, excluded));
        let adding = self.record_part(task, rule, adds, bindings, Part::Adds { node });
        if let (Some(deletes), Some(adding)) = (deletes, adding) {
            self.record_part(task, rule, deletes, bindings, Part::Deletes { pair: adding });
        }
    }

    /// The number of the ground action of `rule` known by `key`, if it is recorded.
    fn recorded(&self, rule: usize, key: &[Option<ConstId>]) -> Option<u32> {
        let recorder = self.recorder.as_ref()?;
        let hash = self.hasher.hash_one((rule as u32, key));
        let actions = &recorder.actions;
        recorder
            .seen
            .find(hash, |&a| actions[a as usize].rule == rule as u32 && actions[a as usize].key() == key)
            .copied()
    }

    /// Records one ground action of `rule`, known by its rule and `key` (its bindings, some
    /// perhaps left unbound), its tuples taken from the instantiation `bindings`; returns its
    /// number, new or not (`None` once grounding has given up).
    fn record_part(
        &mut self,
        task: &mut Task,
        rule: usize,
        key: &[Option<ConstId>],
        bindings: &[Option<ConstId>],
        part: Part,
    ) -> Option<u32> {
        if self.recorder.as_ref()?.overflowed {
            return None;
        }
        if let Some(found) = self.recorded(rule, key) {
            return Some(found);
        }
        let recorder = self.recorder.as_mut().expect("checked above");
        if recorder.actions.len() >= recorder.limit || recorder.bytes > recorder.max_bytes {
            recorder.overflowed = true;
            return None;
        }
        let exclusion = self.rules[rule].exclusion.as_ref();
        let mut pre = Vec::new();
        for (l, literal) in self.rules[rule].body.iter().enumerate() {
            if matches!(part, Part::Adds { .. }) && exclusion.is_some_and(|e| e.literal as usize == l) {
                continue;
            }
            let tuple: Option<Vec<ConstId>> =
                literal.args.iter().map(|a| instantiate(a, &mut task.consts, bindings)).collect();
            if let Some(t) = tuple.and_then(|tuple| self.tables[literal.view as usize].find(&self.hasher, &tuple)) {
                pre.push((literal.view, t));
            }
        }
        let mut add = Vec::new();
        let mut projected = Vec::new();
        let mut full = Vec::new();
        let heads = if matches!(part, Part::Deletes { .. }) { 0 } else { self.rules[rule].heads.len() };
        for h in 0..heads {
            let head = self.rules[rule].heads[h].clone();
            if !self.literal_values(&head, task, bindings, &mut full) {
                continue;
            }
            let Some(views) = self.views_of_pred.get(&head.pred) else { continue };
            for &view in views {
                projected.clear();
                projected.extend(self.views[view as usize].keep.iter().map(|&i| full[i as usize]));
                let (t, _) = self.tables[view as usize].find_or_insert(&self.hasher, &projected);
                add.push((view, t));
            }
        }
        let mut deletes = Vec::new();
        for d in 0..self.rules[rule].dels.len() {
            let reads_excluded = exclusion.is_some_and(|e| e.dels.contains(&(d as u32)));
            let wanted = match part {
                Part::Whole => true,
                Part::Adds { .. } => !reads_excluded,
                Part::Deletes { .. } => reads_excluded,
            };
            if !wanted {
                continue;
            }
            let del = self.rules[rule].dels[d].clone();
            let Some(view) = self.negated_view(del.pred) else { continue };
            if !self.literal_values(&del, task, bindings, &mut full) {
                continue;
            }
            projected.clear();
            projected.extend(self.views[view as usize].keep.iter().map(|&i| full[i as usize]));
            if let Some(t) = self.tables[view as usize].find(&self.hasher, &projected) {
                deletes.push((view, t));
            }
        }
        let recorder = self.recorder.as_mut().expect("checked above");
        let mut invalid = Vec::new();
        for (l, literal) in self.rules[rule].invalid.iter().enumerate() {
            let mut own = Vec::new();
            literal.args.iter().for_each(|a| var_occurrences(a, &mut own));
            let values: Box<[Option<ConstId>]> =
                (0..bindings.len()).map(|v| if own.contains(&(v as u32)) { bindings[v] } else { None }).collect();
            invalid.push(recorder.instances.number((rule as u32, l as u32, values)));
        }
        // What the instantiation holds: the action (its vector may have grown to twice its
        // length), its bindings, its slot in `seen` (which may have grown to twice its size),
        // and five buffers, each with the allocator's overhead.
        const ALLOC: usize = 16;
        let binding_bytes = std::mem::size_of_val(key) + ALLOC;
        recorder.bytes += 2 * std::mem::size_of::<RecordedAction>()
            + binding_bytes
            + 2 * (std::mem::size_of::<u32>() + 1)
            + 4 * ALLOC
            + 8 * (pre.len() + add.len() + deletes.len())
            + 4 * invalid.len();
        let index = recorder.actions.len() as u32;
        recorder.actions.push(RecordedAction {
            rule: rule as u32,
            // The part that deletes is named as its first instantiation, destination and
            // all: a helpful action then is that move, as the ground action of the whole
            // instantiation that first reached the deletion was.
            bindings: if matches!(part, Part::Deletes { .. }) { bindings.into() } else { key.into() },
            key: matches!(part, Part::Deletes { .. }).then(|| key.into()),
            pre,
            exclusion: match part {
                Part::Adds { node } => Some(node),
                _ => None,
            },
            pair: match part {
                Part::Deletes { pair } => Some(pair),
                _ => None,
            },
            add,
            invalid,
            deletes,
        });
        let hasher = self.hasher;
        let hash = hasher.hash_one((rule as u32, key));
        let Recorder { seen, actions, .. } = recorder;
        seen.insert_unique(hash, index, |&a| hasher.hash_one((actions[a as usize].rule, actions[a as usize].key())));
        Some(index)
    }

    /// FF's relaxed plan from the goal tuples back through best supporters.
    ///
    /// Tuples are processed from the most to the least costly, and the heads of every action
    /// chosen count as achieved from then on, so a cheaper tuple that a chosen action already
    /// adds gets no second supporter. This is FF's marking of facts added by the relaxed plan's
    /// actions; without it, a block that is both stacked where the goal wants it and needed
    /// clear afterwards would be counted as moved twice, once by each cheapest route.
    fn relaxed_plan(&mut self, task: &mut Task, reached: &[Option<(u32, u32)>], estimate: &mut Estimate) {
        let mut pending: BinaryHeap<(u32, u32, u32)> = BinaryHeap::new();
        let push = |pending: &mut BinaryHeap<(u32, u32, u32)>, tables: &[Table], view: u32, t: u32| {
            pending.push((tables[view as usize].cost[t as usize], view, t));
        };
        for &(view, t) in reached.iter().flatten() {
            push(&mut pending, &self.tables, view, t);
        }
        let mut seen: FxHashSet<(u32, u32)> = FxHashSet::default();
        let mut actions: FxHashSet<(u32, Vec<Option<ConstId>>)> = FxHashSet::default();
        let mut projected = Vec::new();
        while let Some((_, view, t)) = pending.pop() {
            if !seen.insert((view, t)) {
                continue;
            }
            let Support::Rule { rule, bindings } = self.tables[view as usize].support[t as usize] else { continue };
            let vars = self.rules[rule as usize].vars;
            let values: Vec<Option<ConstId>> = self.arena[bindings as usize..bindings as usize + vars].to_vec();
            if !actions.insert((rule, values.clone())) {
                continue;
            }
            // Everything this action adds is achieved from now on.
            let mut full = Vec::new();
            for h in 0..self.rules[rule as usize].heads.len() {
                let head = self.rules[rule as usize].heads[h].clone();
                if !self.literal_values(&head, task, &values, &mut full) {
                    continue;
                }
                let Some(views) = self.views_of_pred.get(&head.pred) else { continue };
                for &other in views {
                    projected.clear();
                    projected.extend(self.views[other as usize].keep.iter().map(|&i| full[i as usize]));
                    if let Some(u) = self.tables[other as usize].find(&self.hasher, &projected) {
                        seen.insert((other, u));
                    }
                }
            }
            let mut first_layer = true;
            for literal in self.rules[rule as usize].body.iter() {
                let tuple: Option<Vec<ConstId>> =
                    literal.args.iter().map(|a| instantiate(a, &mut task.consts, &values)).collect();
                let Some(tuple) = tuple else { continue };
                let table = &self.tables[literal.view as usize];
                if let Some(u) = table.find(&self.hasher, &tuple) {
                    first_layer &= table.cost[u as usize] == 0;
                    push(&mut pending, &self.tables, literal.view, u);
                }
            }
            if first_layer {
                estimate.helpful.push(Helpful {
                    schema: self.rules[rule as usize].schema as usize,
                    bindings: values.into_boxed_slice(),
                });
            }
        }
        estimate.h_ff = Some(actions.len() as u32);
    }
}

/// The pairs `(A, B)` of a disequality condition: `A \== B`, or a disjunction of such
/// comparisons between variables.
fn disequality_pairs(goal: &Goal) -> Option<Vec<(u32, u32)>> {
    let pair = |goal: &Goal| match goal {
        Goal::Call(literal) => match &literal.term {
            Term::Compound(name, args) if *name == sym::NOT_IDENTICAL && args.len() == 2 => {
                match (&args[0], &args[1]) {
                    (Term::Var(a), Term::Var(b)) if a != b => Some((a.0, b.0)),
                    _ => None,
                }
            }
            _ => None,
        },
        _ => None,
    };
    match goal {
        Goal::Or(branches) => {
            branches.iter().map(|branch| if branch.conditions.is_empty() { pair(&branch.goal) } else { None }).collect()
        }
        goal => pair(goal).map(|p| vec![p]),
    }
}

/// The body literal of `rule` (built from `schema`, in `relaxation` whose views are complete)
/// the ground task can read through an exclusion node, if any: see [`Exclusion`].
fn find_exclusion(relaxation: &Relaxation, schema: &Schema, rule: &Rule) -> Option<Exclusion> {
    let (valid, _) = relaxed_literals(schema);
    let mut in_body = Vec::new();
    for literal in &valid {
        literal.args.iter().for_each(|a| var_occurrences(a, &mut in_body));
    }
    let goal_vars: Vec<Vec<u32>> = schema
        .on_kb
        .iter()
        .map(|goal| {
            let mut vars = Vec::new();
            goal.for_each_call(&mut |l| term_vars(&l.term, &mut vars));
            vars
        })
        .collect();
    // Variables read anywhere but the body, OnKB conditions and deletions: heads at the
    // positions some view reads, Invalid literals, InvalidAtEnd terms.
    let mut read = Vec::new();
    for head in rule.heads.iter() {
        let Some(views) = relaxation.views_of_pred.get(&head.pred) else { continue };
        for (i, a) in head.args.iter().enumerate() {
            if views.iter().any(|&v| relaxation.views[v as usize].keep.contains(&(i as u32))) {
                var_occurrences(a, &mut read);
            }
        }
    }
    let mut invalid_vars = Vec::new();
    for literal in schema.invalid.iter() {
        literal.args.iter().for_each(|a| var_occurrences(a, &mut invalid_vars));
    }
    read.extend_from_slice(&invalid_vars);
    for term in schema.invalid_at_end.iter() {
        term_vars(term, &mut read);
    }
    for (l, literal) in rule.body.iter().enumerate() {
        // Candidates: variables at kept positions of this literal that occur once in the body.
        let candidates: Vec<(u32, u32)> = literal
            .args
            .iter()
            .enumerate()
            .filter_map(|(i, a)| match a {
                Pattern::Var(v) if in_body.iter().filter(|&&w| w == *v).count() == 1 && !read.contains(v) => {
                    Some((i as u32, *v))
                }
                _ => None,
            })
            .collect();
        let is_candidate = |v: u32| candidates.iter().any(|&(_, c)| c == v);
        let mentions: Vec<usize> =
            (0..goal_vars.len()).filter(|&g| goal_vars[g].iter().any(|&v| is_candidate(v))).collect();
        let [d] = mentions[..] else { continue };
        let Some(pairs) = disequality_pairs(&schema.on_kb[d]) else { continue };
        let oriented: Option<Vec<(u32, u32)>> = pairs
            .iter()
            .map(|&(a, b)| match (is_candidate(a), is_candidate(b)) {
                (true, false) => Some((a, b)),
                (false, true) => Some((b, a)),
                _ => None,
            })
            .collect();
        let Some(oriented) = oriented else { continue };
        // Each other variable is bound when the condition runs, and stays as it was then.
        let bound = oriented.iter().all(|&(_, o)| {
            (in_body.contains(&o) || goal_vars[..d].iter().any(|vars| vars.contains(&o)))
                && !goal_vars[d + 1..].iter().any(|vars| vars.contains(&o))
        });
        if !bound {
            continue;
        }
        let mut vars: Vec<u32> = oriented.iter().map(|&(e, _)| e).collect();
        vars.sort_unstable();
        vars.dedup();
        let position = |v: u32| candidates.iter().find(|&&(_, c)| c == v).map(|&(i, _)| i).expect("a candidate");
        let excluded: Vec<u32> = vars.iter().map(|&v| position(v)).collect();
        let group = (0..literal.args.len() as u32).filter(|i| !excluded.contains(i)).collect();
        let mut dels = Vec::new();
        let mut delete_vars = in_body.clone();
        for (k, del) in rule.dels.iter().enumerate() {
            let mut own = Vec::new();
            del.args.iter().for_each(|a| var_occurrences(a, &mut own));
            if own.iter().any(|v| vars.contains(v)) {
                dels.push(k as u32);
                delete_vars.extend(own);
            }
        }
        delete_vars.extend_from_slice(&invalid_vars);
        delete_vars.sort_unstable();
        delete_vars.dedup();
        let mask = |of: &[u32]| (0..rule.vars as u32).map(|v| of.contains(&v)).collect();
        return Some(Exclusion {
            literal: l as u32,
            group,
            pairs: oriented.iter().map(|&(e, o)| (position(e), o)).collect(),
            excluded: mask(&vars),
            dels: dels.into_boxed_slice(),
            deleting: mask(&delete_vars),
        });
    }
    None
}

/// A placeholder value at a dropped position; no view reads it.
const DROPPED: ConstId = ConstId(u32::MAX);

/// The argument positions that name a unit of a renewable resource and nothing else: position
/// `i` of a predicate qualifies when, in every literal of every schema (Valid, Invalid,
/// effects) and every goal literal the relaxation reads, it holds a resource variable of the
/// schema (`A` in `available(A)` under `resources(available(_))`) or a variable that occurs
/// nowhere else, and a resource variable at least once.
///
/// Units of a resource are interchangeable, so the relaxation can forget which unit a fact is
/// about: `gripped(A, B)` becomes "some arm grips B". Every real transition maps onto a
/// transition of this abstraction, so whatever is reachable stays reachable (dead ends stay
/// sound), and the relaxed task shrinks by the number of units: four times fewer ground
/// actions with four arms.
fn resource_positions(task: &Task) -> FxHashMap<PredId, Box<[bool]>> {
    // Each schema's literals as the relaxation reads them: (body, heads, the rest).
    let literals: Vec<(Vec<LiteralPattern>, Vec<LiteralPattern>)> = task.schemas.iter().map(relaxed_literals).collect();
    // Resource units flow: a schema variable bound by a resource template, or read from a
    // position that holds units, holds a unit, and so does every position it is added at.
    let mut unit_positions: FxHashSet<(PredId, usize)> = FxHashSet::default();
    let mut unit_vars: Vec<Vec<u32>> = task.schemas.iter().map(|s| s.resource_vars.to_vec()).collect();
    loop {
        let mut changed = false;
        for ((body, heads), vars) in literals.iter().zip(unit_vars.iter_mut()) {
            for literal in body {
                for (i, a) in literal.args.iter().enumerate() {
                    if let Pattern::Var(v) = a
                        && unit_positions.contains(&(literal.pred, i))
                        && !vars.contains(v)
                    {
                        vars.push(*v);
                        changed = true;
                    }
                }
            }
            for literal in heads {
                for (i, a) in literal.args.iter().enumerate() {
                    if matches!(a, Pattern::Var(v) if vars.contains(v)) && unit_positions.insert((literal.pred, i)) {
                        changed = true;
                    }
                }
            }
        }
        if !changed {
            break;
        }
    }
    // Every literal of each schema the relaxation reads, with the variables the KB reasons
    // about (in OnKB or InvalidAtEnd), which must stay visible.
    let all: Vec<(Vec<&LiteralPattern>, Vec<u32>)> = task
        .schemas
        .iter()
        .zip(&literals)
        .map(|(schema, (body, heads))| {
            let mut list: Vec<&LiteralPattern> = body.iter().chain(heads.iter()).collect();
            list.extend(schema.invalid.iter());
            list.extend(schema.effects.iter().filter(|(kind, _)| *kind == EffectKind::Del).map(|(_, l)| l));
            let mut reasoned = Vec::new();
            for goal in schema.on_kb.iter() {
                goal.for_each_call(&mut |l| term_vars(&l.term, &mut reasoned));
            }
            for term in schema.invalid_at_end.iter() {
                term_vars(term, &mut reasoned);
            }
            (list, reasoned)
        })
        .collect();
    // Per predicate and position: (every occurrence qualifies, some occurrence is a unit).
    let mut status: FxHashMap<PredId, Vec<(bool, bool)>> = FxHashMap::default();
    let mut note = |pred: PredId, i: usize, arity: usize, qualifies: bool, unit: bool| {
        let entry = status.entry(pred).or_insert_with(|| vec![(true, false); arity]);
        entry[i].0 &= qualifies;
        entry[i].1 |= unit;
    };
    for (((list, reasoned), vars), schema) in all.iter().zip(&unit_vars).zip(&task.schemas) {
        let mut occurrences = Vec::new();
        var_occurrences(&schema.name, &mut occurrences);
        for literal in list {
            literal.args.iter().for_each(|a| var_occurrences(a, &mut occurrences));
        }
        occurrences.extend_from_slice(reasoned);
        for literal in list {
            for (i, a) in literal.args.iter().enumerate() {
                let (qualifies, unit) = match a {
                    Pattern::Var(v) if vars.contains(v) => (!reasoned.contains(v), true),
                    Pattern::Var(v) => (occurrences.iter().filter(|&&w| w == *v).count() == 1, false),
                    _ => (false, false),
                };
                note(literal.pred, i, literal.args.len(), qualifies, unit);
            }
        }
    }
    let mut goal_occurrences = Vec::new();
    task.goal.iter().for_each(|l| l.args.iter().for_each(|a| var_occurrences(a, &mut goal_occurrences)));
    for (g, literal) in task.goal.iter().enumerate() {
        if task.resource_goal[g] {
            continue;
        }
        for (i, a) in literal.args.iter().enumerate() {
            let qualifies = matches!(a, Pattern::Var(v) if goal_occurrences.iter().filter(|&&w| w == *v).count() == 1);
            note(literal.pred, i, literal.args.len(), qualifies, false);
        }
    }
    let mut dropped: FxHashMap<PredId, Vec<bool>> = status
        .into_iter()
        .filter(|(_, positions)| positions.iter().any(|&(q, u)| q && u))
        .map(|(pred, positions)| (pred, positions.iter().map(|&(q, u)| q && u).collect()))
        .collect();
    // A unit variable a schema also holds at a position that is kept (a goal names the unit
    // there, say) must be kept everywhere in that schema, or the kept position could not be
    // instantiated; keeping one position can keep others, so repeat until nothing changes.
    let is_dropped = |dropped: &FxHashMap<PredId, Vec<bool>>, pred: PredId, i: usize| {
        dropped.get(&pred).is_some_and(|d| d.get(i).copied().unwrap_or(false))
    };
    loop {
        let mut keep: Vec<(PredId, usize)> = Vec::new();
        for (list, _) in &all {
            let mut kept_vars = Vec::new();
            for literal in list {
                for (i, a) in literal.args.iter().enumerate() {
                    if !is_dropped(&dropped, literal.pred, i) {
                        var_occurrences(a, &mut kept_vars);
                    }
                }
            }
            for literal in list {
                for (i, a) in literal.args.iter().enumerate() {
                    if let Pattern::Var(v) = a
                        && kept_vars.contains(v)
                        && is_dropped(&dropped, literal.pred, i)
                    {
                        keep.push((literal.pred, i));
                    }
                }
            }
        }
        if keep.is_empty() {
            break;
        }
        for (pred, i) in keep {
            if let Some(d) = dropped.get_mut(&pred) {
                d[i] = false;
            }
        }
    }
    dropped.into_iter().filter(|(_, d)| d.iter().any(|&x| x)).map(|(pred, d)| (pred, d.into_boxed_slice())).collect()
}

/// The OnKB goals at the head of `goals` (a conjunction, read left to right into nested
/// conjunctions) that call predicates defined by facts alone, up to the first goal that does
/// not (nothing runs before them, so a failure of theirs is the whole conjunction's).
/// Returns false once it has met such a goal.
fn leading_fact_calls(goals: &[Goal], program: &Program, out: &mut Vec<Goal>) -> bool {
    for goal in goals {
        match goal {
            Goal::Call(literal)
                if !crate::builtins::is_builtin_predicate(literal.name(), literal.arity())
                    && program.facts_only(literal.name(), literal.arity()) =>
            {
                out.push(goal.clone());
            }
            Goal::And(inner) => {
                if !leading_fact_calls(inner, program, out) {
                    return false;
                }
            }
            _ => return false,
        }
    }
    true
}

/// The kept positions of `args` whose values are known once the variables `bound` are:
/// constants and bound variables.
fn bound_positions<'a>(args: &'a [Pattern], bound: &'a [u32]) -> impl Iterator<Item = u32> + 'a {
    args.iter().enumerate().filter_map(move |(i, a)| {
        let known = match a {
            Pattern::Const(_) => true,
            Pattern::Var(v) => bound.contains(v),
            Pattern::Compound(..) => false,
        };
        known.then_some(i as u32)
    })
}

/// The join order for a rule triggered by body literal `trigger`: the other literals, most
/// bound first, each looked up on every kept position bound by then, in the index of its view
/// for those positions (`indexes`: per view, the positions of each index, numbered in order).
fn join_order(body: &[BodyLiteral], trigger: usize, indexes: &mut FxHashMap<u32, Vec<Box<[u32]>>>) -> Box<[JoinStep]> {
    let mut bound: Vec<u32> = Vec::new();
    body[trigger].args.iter().for_each(|a| var_occurrences(a, &mut bound));
    let mut remaining: Vec<usize> = (0..body.len()).filter(|&i| i != trigger).collect();
    let mut order = Vec::new();
    while !remaining.is_empty() {
        let score = |i: usize| bound_positions(&body[i].args, &bound).count();
        let (pick, _) =
            remaining.iter().enumerate().max_by_key(|&(k, &i)| (score(i), std::cmp::Reverse(k))).expect("not empty");
        let literal = remaining.remove(pick);
        let positions: Box<[u32]> = bound_positions(&body[literal].args, &bound).collect();
        let lookup = (!positions.is_empty()).then(|| {
            let list = indexes.entry(body[literal].view).or_default();
            let number = list.iter().position(|p| *p == positions).unwrap_or_else(|| {
                list.push(positions);
                list.len() - 1
            });
            number as u32
        });
        body[literal].args.iter().for_each(|a| var_occurrences(a, &mut bound));
        order.push(JoinStep { literal: literal as u32, lookup });
    }
    order.into_boxed_slice()
}
