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

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::hash::BuildHasher;

use hashbrown::HashTable;
use rustc_hash::{FxBuildHasher, FxHashMap, FxHashSet};

use super::successors::{ConditionError, OnKbCache, instantiate, match_pattern, substitute, undo};
use crate::engine::Machine;
use crate::ir::hir::{EffectKind, Term};
use crate::ir::task::{ConstId, LiteralPattern, Pattern, PredId, State, Task};
use crate::ir::unify::unifiable;

/// A relation read by a rule or a goal: a predicate, restricted to some argument positions.
#[derive(Debug)]
struct View {
    /// The argument positions kept, ascending.
    keep: Box<[u32]>,
}

/// A body literal: a view and the patterns at its kept positions.
#[derive(Debug)]
struct BodyLiteral {
    view: u32,
    args: Box<[Pattern]>,
}

/// One step of a join: which body literal, and which kept position (if any) is bound by then
/// and can be looked up in an index.
#[derive(Debug, Clone, Copy)]
struct JoinStep {
    literal: u32,
    lookup: Option<u32>,
}

/// A schema as a relaxed rule.
#[derive(Debug)]
struct Rule {
    schema: u32,
    vars: usize,
    body: Box<[BodyLiteral]>,
    heads: Box<[LiteralPattern]>,
    /// For each body position as the trigger, the join order of the other literals.
    orders: Box<[Box<[JoinStep]>]>,
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
#[derive(Default)]
struct Table {
    arity: usize,
    values: Vec<ConstId>,
    lookup: HashTable<u32>,
    cost: Vec<u32>,
    done: Vec<bool>,
    support: Vec<Support>,
    settled: Vec<u32>,
    /// For each kept position that joins look up: value to settled tuples.
    index: Vec<Option<FxHashMap<ConstId, Vec<u32>>>>,
}

impl Table {
    fn clear(&mut self) {
        self.values.clear();
        self.lookup.clear();
        self.cost.clear();
        self.done.clear();
        self.support.clear();
        self.settled.clear();
        for index in self.index.iter_mut().flatten() {
            index.clear();
        }
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
}

/// The relaxed task and the scratch space to evaluate it, state after state.
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
        };
        for (index, schema) in task.schemas.iter().enumerate() {
            // Variables needed beyond the body: in heads, OnKB and InvalidAtEnd conditions.
            let mut needed = Vec::new();
            let heads: Vec<LiteralPattern> =
                schema.effects.iter().filter(|(kind, _)| *kind == EffectKind::Add).map(|(_, l)| l.clone()).collect();
            for head in &heads {
                head.args.iter().for_each(|a| var_occurrences(a, &mut needed));
            }
            for goal in schema.on_kb.iter() {
                goal.for_each_call(&mut |l| term_vars(&l.term, &mut needed));
            }
            for term in schema.invalid_at_end.iter() {
                term_vars(term, &mut needed);
            }
            let mut in_body = Vec::new();
            for literal in schema.valid.iter() {
                literal.args.iter().for_each(|a| var_occurrences(a, &mut in_body));
            }
            let body: Vec<BodyLiteral> = schema
                .valid
                .iter()
                .map(|literal| {
                    let keep: Vec<u32> = (0..literal.args.len() as u32)
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
            let orders = (0..body.len()).map(|trigger| join_order(&body, trigger)).collect();
            relaxation.rules.push(Rule {
                schema: index as u32,
                vars: schema.vars,
                body: body.into_boxed_slice(),
                heads: heads.into_boxed_slice(),
                orders,
            });
        }
        for literal in &task.goal {
            let arity = task.facts.pred_info(literal.pred).1;
            let keep: Vec<u32> = (0..arity as u32).collect();
            let view = relaxation.view(literal.pred, &keep);
            relaxation.goal.push(BodyLiteral { view, args: literal.args.clone() });
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
            .map(|v| Table { arity: v.keep.len(), index: vec![None; v.keep.len()], ..Table::default() })
            .collect();
        for rule in &relaxation.rules {
            for order in rule.orders.iter() {
                for step in order.iter() {
                    if let Some(position) = step.lookup {
                        let view = rule.body[step.literal as usize].view as usize;
                        relaxation.tables[view].index[position as usize].get_or_insert_with(FxHashMap::default);
                    }
                }
            }
        }
        relaxation
    }

    /// The goal literals (indices into `Task::goal`) the last exploration did not reach.
    pub fn unreached_goals(&self) -> &[usize] {
        &self.unreached
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

    fn relax(&mut self, view: u32, values: &[ConstId], cost: u32, support: Support) {
        let table = &mut self.tables[view as usize];
        let (t, _) = table.find_or_insert(&self.hasher, values);
        if table.done[t as usize] || cost >= table.cost[t as usize] {
            return;
        }
        table.cost[t as usize] = cost;
        table.support[t as usize] = support;
        self.queue.push(Reverse((cost, view, t)));
    }

    /// Offers a full fact to every view of its predicate.
    fn offer(&mut self, pred: PredId, values: &[ConstId], cost: u32, support: Support) {
        let Some(views) = self.views_of_pred.get(&pred) else { return };
        let views = views.clone();
        let mut projected = Vec::new();
        for view in views {
            projected.clear();
            projected.extend(self.views[view as usize].keep.iter().map(|&i| values[i as usize]));
            self.relax(view, &projected, cost, support);
        }
    }

    /// Evaluates `state`. With `plan`, also extracts the relaxed plan (h_FF, helpful actions).
    pub fn evaluate(
        &mut self,
        task: &mut Task,
        state: &State,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        plan: bool,
    ) -> Result<Estimate, ConditionError> {
        self.explore(task, state, machine, cache, plan, true)
    }

    /// Explores everything reachable from `state` ignoring deletions, not stopping at the
    /// goal; afterwards [`Relaxation::reached`] answers for any fact.
    pub fn evaluate_all(
        &mut self,
        task: &mut Task,
        state: &State,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
    ) -> Result<Estimate, ConditionError> {
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

    fn explore(
        &mut self,
        task: &mut Task,
        state: &State,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        plan: bool,
        stop_at_goal: bool,
    ) -> Result<Estimate, ConditionError> {
        for table in &mut self.tables {
            table.clear();
        }
        self.queue.clear();
        self.arena.clear();
        for fact in state.facts() {
            let pred = task.facts.pred_of(fact);
            let values: Vec<ConstId> = task.facts.args(fact).to_vec();
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
        while remaining > 0 || !stop_at_goal {
            let Some(Reverse((cost, view, t))) = self.queue.pop() else { break };
            let table = &mut self.tables[view as usize];
            if table.done[t as usize] || cost > table.cost[t as usize] {
                continue;
            }
            table.done[t as usize] = true;
            table.settled.push(t);
            let arity = table.arity;
            for position in 0..arity {
                let value = table.values[t as usize * arity + position];
                if let Some(index) = &mut table.index[position] {
                    index.entry(value).or_default().push(t);
                }
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
        self.unreached = reached.iter().enumerate().filter(|(_, r)| r.is_none()).map(|(g, _)| g).collect();
        if remaining > 0 {
            return Ok(Estimate::default());
        }
        let mut estimate = Estimate { h_add: Some(h_add), h_ff: None, helpful: Vec::new() };
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
    ) -> Result<(), ConditionError> {
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
        self.join(task, machine, cache, rule, &order, 0, &mut bindings, &mut trail, cost)
    }

    #[allow(clippy::too_many_arguments)]
    fn join(
        &mut self,
        task: &mut Task,
        machine: &mut Machine<'_>,
        cache: &mut OnKbCache,
        rule: usize,
        order: &[JoinStep],
        step: usize,
        bindings: &mut Vec<Option<ConstId>>,
        trail: &mut Vec<u32>,
        cost: u32,
    ) -> Result<(), ConditionError> {
        let Some(&JoinStep { literal, lookup }) = order.get(step) else {
            return self.fire(task, machine, cache, rule, bindings, cost);
        };
        let view = self.rules[rule].body[literal as usize].view as usize;
        let candidates: Vec<u32> = match lookup {
            Some(position) => {
                let pattern = &self.rules[rule].body[literal as usize].args[position as usize];
                let key = match pattern {
                    Pattern::Const(c) => Some(*c),
                    Pattern::Var(v) => bindings[*v as usize],
                    Pattern::Compound(..) => None,
                };
                match (key, &self.tables[view].index[position as usize]) {
                    (Some(key), Some(index)) => index.get(&key).cloned().unwrap_or_default(),
                    _ => self.tables[view].settled.clone(),
                }
            }
            None => self.tables[view].settled.clone(),
        };
        for u in candidates {
            let mark = trail.len();
            let table = &self.tables[view];
            let args = &self.rules[rule].body[literal as usize].args;
            let ok = args.iter().zip(table.tuple(u)).all(|(p, v)| match_pattern(p, *v, &task.consts, bindings, trail));
            let extra = table.cost[u as usize];
            if ok {
                self.join(task, machine, cache, rule, order, step + 1, bindings, trail, cost.saturating_add(extra))?;
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
    ) -> Result<(), ConditionError> {
        let schema_index = self.rules[rule].schema as usize;
        let solutions = if task.schemas[schema_index].on_kb.is_empty() {
            None
        } else {
            let Task { consts, schemas, .. } = task;
            Some(
                cache
                    .solutions(machine, consts, &schemas[schema_index], schema_index, bindings)
                    .map_err(|error| ConditionError { schema: schema_index, error })?,
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
            let at = relaxation.arena.len() as u32;
            relaxation.arena.extend_from_slice(bindings);
            let support = Support::Rule { rule: rule as u32, bindings: at };
            for h in 0..relaxation.rules[rule].heads.len() {
                let head = &relaxation.rules[rule].heads[h];
                let pred = head.pred;
                let values: Option<Vec<ConstId>> =
                    head.args.iter().map(|a| instantiate(a, &mut task.consts, bindings)).collect();
                if let Some(values) = values {
                    relaxation.offer(pred, &values, cost, support);
                }
            }
        };
        match solutions {
            None => offer(self, task, bindings),
            Some(solutions) => {
                for solution in solutions.iter() {
                    let mut extended = bindings.to_vec();
                    for (&v, value) in unbound.iter().zip(solution.iter()) {
                        extended[v as usize] = *value;
                    }
                    offer(self, task, &extended);
                }
            }
        }
        Ok(())
    }

    /// FF's relaxed plan from the goal tuples back through best supporters.
    fn relaxed_plan(&mut self, task: &mut Task, reached: &[Option<(u32, u32)>], estimate: &mut Estimate) {
        let mut pending: Vec<(u32, u32)> = reached.iter().flatten().copied().collect();
        let mut seen: FxHashSet<(u32, u32)> = FxHashSet::default();
        let mut actions: FxHashSet<(u32, Vec<Option<ConstId>>)> = FxHashSet::default();
        while let Some((view, t)) = pending.pop() {
            if !seen.insert((view, t)) {
                continue;
            }
            let Support::Rule { rule, bindings } = self.tables[view as usize].support[t as usize] else { continue };
            let vars = self.rules[rule as usize].vars;
            let values: Vec<Option<ConstId>> = self.arena[bindings as usize..bindings as usize + vars].to_vec();
            if !actions.insert((rule, values.clone())) {
                continue;
            }
            let mut first_layer = true;
            for literal in self.rules[rule as usize].body.iter() {
                let tuple: Option<Vec<ConstId>> =
                    literal.args.iter().map(|a| instantiate(a, &mut task.consts, &values)).collect();
                let Some(tuple) = tuple else { continue };
                let table = &self.tables[literal.view as usize];
                if let Some(u) = table.find(&self.hasher, &tuple) {
                    first_layer &= table.cost[u as usize] == 0;
                    pending.push((literal.view, u));
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

/// The join order for a rule triggered by body literal `trigger`: the other literals, most
/// bound first, each looked up on its first kept position bound by then.
fn join_order(body: &[BodyLiteral], trigger: usize) -> Box<[JoinStep]> {
    let mut bound: Vec<u32> = Vec::new();
    body[trigger].args.iter().for_each(|a| var_occurrences(a, &mut bound));
    let mut remaining: Vec<usize> = (0..body.len()).filter(|&i| i != trigger).collect();
    let mut order = Vec::new();
    while !remaining.is_empty() {
        let score = |i: usize| {
            body[i]
                .args
                .iter()
                .filter(|a| match a {
                    Pattern::Const(_) => true,
                    Pattern::Var(v) => bound.contains(v),
                    Pattern::Compound(..) => false,
                })
                .count()
        };
        let (pick, _) =
            remaining.iter().enumerate().max_by_key(|&(k, &i)| (score(i), std::cmp::Reverse(k))).expect("not empty");
        let literal = remaining.remove(pick);
        let lookup = body[literal].args.iter().position(|a| match a {
            Pattern::Const(_) => true,
            Pattern::Var(v) => bound.contains(v),
            Pattern::Compound(..) => false,
        });
        body[literal].args.iter().for_each(|a| var_occurrences(a, &mut bound));
        order.push(JoinStep { literal: literal as u32, lookup: lookup.map(|p| p as u32) });
    }
    order.into_boxed_slice()
}
