//! Pass `refine`: a high-level plan becomes an arm-level plan ([`ArmPlan`]), as the authors'
//! two-level framework refines its plans.
//!
//! The high-level plan's snap actions are taken in order. Each one whose ground name unifies
//! with the head of a `mapping/2` is expanded into that mapping's steps, and each step is
//! applied to the arm-level state as an `ll_action/6`: its name is unified with the step, then
//! its Valid literals are matched, its OnKB goals proven, its Invalid and InvalidAtEnd lists
//! checked and its effects applied, exactly as for a high-level action (docs/dsl.md). A step
//! variable the mapping's head leaves open is bound by the step's conditions, as in Prolog.
//!
//! The arm-level state is a list of facts that may hold variables (`ll_arm_at(a1, 4, 4, _)`
//! in `ll_init`): matching is unification, and a binding made along the way holds for the rest
//! of the refinement, as it does for the Prolog planner. Several mappings for one action,
//! several `ll_action` clauses for one step, several facts a Valid literal unifies with, several
//! running arm-level actions an `_end` step can close and several OnKB solutions are
//! alternatives; they are explored depth-first in that order (Prolog's) with backtracking,
//! under a budget of nodes. A high-level action that no mapping matches has no arm-level steps.
//! At the end, the arm-level goal (`ll_goal` and the goal's arm-level literals) must unify with
//! the final state and no arm-level durative action may still run.
//!
//! When no alternative gets through, the diagnostic (E0311) explains the deepest point any
//! alternative reached: which high-level step, which of its mapping's steps, which condition,
//! and the arm-level state there.

use std::rc::Rc;
use std::time::Instant;

use rustc_hash::FxHashMap;

use crate::diag::{Diagnostic, codes};
use crate::engine::{Cell, Machine, Next, Program};
use crate::intern::{Interner, sym};
use crate::ir::hir::{self, Action, EffectKind, Kb, Level, Snap, Term, VarId, VarTable};
use crate::ir::plan::{ArmPlan, Plan, Step};
use crate::ir::unify::{substitute, unify_in};
use crate::source::Span;

type Subst = FxHashMap<VarId, Term>;

/// What a refinement may spend.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    /// The most alternatives (search nodes) to try.
    pub max_nodes: u64,
    /// When to give up.
    pub deadline: Option<Instant>,
    /// The most resolution steps for one OnKB query.
    pub engine_steps: u64,
}

impl Default for Budget {
    fn default() -> Budget {
        Budget { max_nodes: 1_000_000, deadline: None, engine_steps: 1_000_000 }
    }
}

/// Why a refinement failed: a diagnostic, and whether it is a budget that ran out (in which
/// case another high-level plan is not worth trying).
#[derive(Debug)]
pub struct Failed {
    /// E0311, or E0305 for an exhausted budget.
    pub diagnostic: Box<Diagnostic>,
    /// True when the budget ran out before every alternative was tried.
    pub budget: bool,
}

/// An arm-level step applied on the way to the current node.
struct Taken {
    step: Step,
    origin: usize,
    /// Bindings this step made to variables older than it (of the initial state, or left open
    /// by earlier steps), to be put into every step at the end.
    outer: Vec<(VarId, Term)>,
    parent: Option<Rc<Taken>>,
}

/// One point of the depth-first search.
#[derive(Clone)]
struct Node {
    /// The next high-level step to expand.
    next_high: usize,
    /// The high-level step and mapping the pending steps come from.
    origin: Option<(usize, usize)>,
    /// The steps of the current mapping still to apply, with their position in it.
    pending: Vec<(Term, usize)>,
    /// The arm-level facts, newest first; their variables are unbound.
    state: Vec<Term>,
    /// The arm-level durative actions running, as `base(args)`.
    running: Vec<Term>,
    /// The next free variable number.
    fresh: u32,
    /// Arm-level steps applied so far.
    applied: usize,
    path: Option<Rc<Taken>>,
}

/// Where an alternative stopped.
struct Stuck {
    progress: usize,
    diagnostic: Diagnostic,
}

/// Why one `ll_action` clause did not apply.
struct Miss {
    action: usize,
    reason: String,
    span: Span,
}

struct Refiner<'a> {
    kb: &'a Kb,
    interner: &'a Interner,
    high: &'a Plan,
    arm: &'a hir::Problem,
    machine: Machine<'a>,
    nodes: u64,
    budget: Budget,
    stuck: Option<Stuck>,
}

/// True if `a` and `b` unify under `s`, without keeping the bindings.
fn unifies(a: &Term, b: &Term, s: &Subst) -> bool {
    let mut copy = s.clone();
    unify_in(a, b, &mut copy)
}

/// Refines `high`, a valid plan of a high-level problem, into a plan of `arm_problem`, the
/// arm-level problem derived from it ([`Kb::arm_problem`]), proving OnKB goals against
/// `program`.
pub fn refine(
    kb: &Kb,
    interner: &Interner,
    program: &Program,
    high: &Plan,
    arm_problem: usize,
    budget: Budget,
) -> Result<ArmPlan, Failed> {
    let arm = &kb.problems[arm_problem];
    let mut refiner = Refiner {
        kb,
        interner,
        high,
        arm,
        machine: Machine::new(program, budget.engine_steps),
        nodes: 0,
        budget,
        stuck: None,
    };
    let root = Node {
        next_high: 0,
        origin: None,
        pending: Vec::new(),
        state: arm.init.iter().map(|l| l.term.clone()).collect(),
        running: Vec::new(),
        fresh: arm.vars.len() as u32,
        applied: 0,
        path: None,
    };
    let mut stack = vec![root];
    while let Some(node) = stack.pop() {
        refiner.nodes += 1;
        if refiner.nodes > budget.max_nodes || budget.deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(refiner.out_of_budget());
        }
        if node.pending.is_empty() && node.next_high == high.steps.len() {
            if let Some(plan) = refiner.finish(&node, arm_problem) {
                return Ok(plan);
            }
            continue;
        }
        let mut children = if node.pending.is_empty() { refiner.expand(&node) } else { refiner.apply(&node) };
        children.reverse();
        stack.extend(children);
    }
    let stuck = refiner.stuck.take().expect("a failed refinement records where it stopped");
    Err(Failed { diagnostic: Box::new(stuck.diagnostic), budget: false })
}

impl Refiner<'_> {
    fn show(&self, term: &Term) -> String {
        hir::term_to_string(self.interner, term, &self.arm.vars)
    }

    fn high_name(&self, index: usize) -> String {
        hir::term_to_string(self.interner, &self.high.steps[index].name, &VarTable::default())
    }

    fn state_note(&self, state: &[Term]) -> String {
        let mut shown: Vec<String> = state.iter().map(|t| self.show(t)).collect();
        shown.sort();
        let more = shown.len().saturating_sub(12);
        shown.truncate(12);
        let more = if more > 0 { format!(", and {more} more") } else { String::new() };
        format!("the arm-level state there is [{}{more}]", shown.join(", "))
    }

    fn record(&mut self, progress: usize, diagnostic: impl FnOnce(&Self) -> Diagnostic) {
        if self.stuck.as_ref().is_none_or(|s| progress > s.progress) {
            let diagnostic = diagnostic(self);
            self.stuck = Some(Stuck { progress, diagnostic });
        }
    }

    fn out_of_budget(&self) -> Failed {
        let diagnostic = Diagnostic::error(
            codes::SEARCH_BUDGET,
            format!("the refinement into arm-level actions gave up after {} alternatives", self.nodes - 1),
        )
        .with_note(format!(
            "the budget is {} alternatives{}",
            self.budget.max_nodes,
            if self.budget.deadline.is_some() { " and the search's time limit" } else { "" }
        ))
        .with_help(
            "raise `--timeout`, or give the mappings' steps fewer alternatives (fewer `ll_action` clauses per name)",
        );
        Failed { diagnostic: Box::new(diagnostic), budget: true }
    }

    /// The children of a node between two high-level steps: one per mapping whose head
    /// unifies with the next high-level step, or one with no steps if none does.
    fn expand(&mut self, node: &Node) -> Vec<Node> {
        let index = node.next_high;
        let name = &self.high.steps[index].name;
        let mut children = Vec::new();
        for (m, mapping) in self.kb.mappings.iter().enumerate() {
            let head = mapping.high.term.shift_vars(node.fresh);
            let mut s = Subst::default();
            if !unify_in(&head, name, &mut s) {
                continue;
            }
            let pending = mapping
                .steps
                .iter()
                .enumerate()
                .map(|(k, l)| (substitute(&l.term.shift_vars(node.fresh), &s), k))
                .collect();
            children.push(Node {
                next_high: index + 1,
                origin: Some((index, m)),
                pending,
                fresh: node.fresh + mapping.vars.len() as u32,
                ..node.clone()
            });
        }
        if children.is_empty() {
            children.push(Node { next_high: index + 1, origin: None, ..node.clone() });
        }
        children
    }

    /// The children of applying the first pending step: one per way an `ll_action` applies.
    fn apply(&mut self, node: &Node) -> Vec<Node> {
        let (step, position) = node.pending[0].clone();
        let (origin, mapping) = node.origin.expect("pending steps come from a mapping");
        let mut found = Found::default();
        let callable = step.callable();
        for (index, action) in self.kb.actions.iter().enumerate() {
            if action.level != Level::Low || Some(action.name.term.callable().unwrap_or((sym::ANON, 0))) != callable {
                continue;
            }
            let base = node.fresh;
            let mut s = Subst::default();
            if !unify_in(&action.name.term.shift_vars(base), &step, &mut s) {
                continue;
            }
            // An end closes a running start whose arguments unify with its own.
            let closes: Vec<(Subst, Option<usize>)> = if action.snap == Snap::End {
                let key = action.instance(&substitute(&action.name.term.shift_vars(base), &s));
                let closes: Vec<(Subst, Option<usize>)> = (0..node.running.len())
                    .filter_map(|r| {
                        let mut s = s.clone();
                        unify_in(&key, &node.running[r], &mut s).then_some((s, Some(r)))
                    })
                    .collect();
                if closes.is_empty() {
                    let shown = self.show(&substitute(&key, &s));
                    found.miss.get_or_insert(Miss {
                        action: index,
                        reason: format!("it ends `{shown}`, which is not running"),
                        span: action.name.span,
                    });
                }
                closes
            } else {
                vec![(s, None)]
            };
            let before = found.children.len();
            for (s, closed) in closes {
                let at = Attempt { node, action, index, base, origin, closed };
                self.valid(&at, 0, &s, &mut found);
            }
            if found.children.len() == before {
                found.miss.get_or_insert(Miss {
                    action: index,
                    reason: "its conditions do not hold".into(),
                    span: action.name.span,
                });
            }
        }
        let Found { children, miss } = found;
        if children.is_empty() {
            self.record(node.applied * 2 + 1, |r| r.step_failure(node, &step, position, mapping, miss));
        }
        children
    }

    fn step_failure(
        &self,
        node: &Node,
        step: &Term,
        position: usize,
        mapping: usize,
        miss: Option<Miss>,
    ) -> Diagnostic {
        let (origin, _) = node.origin.expect("pending steps come from a mapping");
        let mapping = &self.kb.mappings[mapping];
        let shown = self.show(step);
        let high = self.high_name(origin);
        let mut diagnostic = Diagnostic::error(
            codes::REFINEMENT_FAILED,
            format!(
                "high-level step {} `{high}` does not refine: its arm-level step `{shown}` does not apply",
                origin + 1
            ),
        )
        .primary(
            mapping.steps[position].span,
            format!("step {} of {} of this mapping", position + 1, mapping.steps.len()),
        );
        match miss {
            Some(miss) => {
                let name = self.interner.resolve(self.kb.actions[miss.action].name.name());
                diagnostic = diagnostic
                    .secondary(miss.span, "this condition fails")
                    .with_note(format!("`{name}`: {}", miss.reason));
            }
            None => {
                diagnostic = diagnostic.with_note("no `ll_action/6` has this name and arity");
            }
        }
        diagnostic
            .with_note(self.state_note(&node.state))
            .with_help("the state comes from `ll_init` (or the problem's arm-level facts) and the steps before; fix the mapping's steps or the `ll_action`'s conditions")
    }

    /// Matches the Valid literals from `k` on, then goes on to OnKB.
    fn valid(&mut self, at: &Attempt<'_>, k: usize, s: &Subst, found: &mut Found) {
        let Some(literal) = at.action.valid.get(k) else {
            return self.on_kb(at, s, found);
        };
        let pattern = literal.term.shift_vars(at.base);
        let mut matched = false;
        for fact in &at.node.state {
            let mut attempt = s.clone();
            if unify_in(&pattern, fact, &mut attempt) {
                matched = true;
                self.valid(at, k + 1, &attempt, found);
            }
        }
        if !matched {
            let shown = self.show(&substitute(&pattern, s));
            found.miss.get_or_insert(Miss {
                action: at.index,
                reason: format!("its Valid condition `{shown}` unifies with no fact of the arm-level state"),
                span: literal.span,
            });
        }
    }

    /// Proves the OnKB goals; each solution goes on to the Invalid lists and the effects.
    fn on_kb(&mut self, at: &Attempt<'_>, s: &Subst, found: &mut Found) {
        let action = at.action;
        if action.on_kb.is_empty() {
            return self.finish_step(at, s, found);
        }
        // Each schema variable's value, with the variables inside numbered compactly.
        let mut outer: Vec<VarId> = Vec::new();
        let values: Vec<Term> = (0..action.vars.len() as u32)
            .map(|v| compact(&substitute(&Term::Var(VarId(at.base + v)), s), &mut outer))
            .collect();
        self.machine.reset();
        let mut compact_cells: Vec<Option<Cell>> = vec![None; outer.len()];
        let mut cells: Vec<Option<Cell>> =
            values.iter().map(|value| Some(self.machine.put_term(value, &mut compact_cells))).collect();
        let goal = self.machine.put_conjunction(&action.on_kb, &mut cells);
        let mut solutions: Vec<Subst> = Vec::new();
        let outcome = self.machine.solve(goal, |m| {
            let mut solution = s.clone();
            for (k, var) in outer.iter().enumerate() {
                if let Some(cell) = compact_cells[k] {
                    let value = m.read(cell, &mut Vec::new());
                    if value.is_ground() {
                        solution.insert(*var, value);
                    }
                }
            }
            solutions.push(solution);
            Next::More
        });
        if let Err(error) = outcome {
            found.miss.get_or_insert(Miss {
                action: at.index,
                reason: format!("proving its OnKB goals failed: {}", error.message(self.interner)),
                span: action.slots[4],
            });
            return;
        }
        if solutions.is_empty() {
            found.miss.get_or_insert(Miss {
                action: at.index,
                reason: "its OnKB goals are not provable".into(),
                span: action.slots[4],
            });
        }
        for solution in solutions {
            self.finish_step(at, &solution, found);
        }
    }

    /// Checks Invalid and InvalidAtEnd, applies the effects, and makes the child.
    fn finish_step(&mut self, at: &Attempt<'_>, s: &Subst, found: &mut Found) {
        let Attempt { node, action, index, base, origin, closed } = *at;
        for literal in &action.invalid {
            let pattern = literal.term.shift_vars(base);
            if let Some(fact) = node.state.iter().find(|f| unifies(&pattern, f, s)) {
                let shown = self.show(&substitute(fact, s));
                found.miss.get_or_insert(Miss {
                    action: index,
                    reason: format!("the arm-level state has `{shown}`, which its Invalid list forbids"),
                    span: literal.span,
                });
                return;
            }
        }
        for literal in &action.invalid_at_end {
            let pattern = literal.term.shift_vars(base);
            if self.arm.goal.iter().any(|g| unifies(&pattern, &g.term, s)) {
                found.miss.get_or_insert(Miss {
                    action: index,
                    reason: "its InvalidAtEnd list meets an arm-level goal literal".into(),
                    span: literal.span,
                });
                return;
            }
        }
        let name = substitute(&action.name.term.shift_vars(base), s);
        if !name.is_ground() {
            let shown = self.show(&name);
            found.miss.get_or_insert(Miss {
                action: index,
                reason: format!("its name is `{shown}` after its conditions: a variable of it has no value"),
                span: action.name.span,
            });
            return;
        }
        let mut state: Vec<Term> = node.state.iter().map(|f| substitute(f, s)).collect();
        for effect in &action.effects {
            let fact = substitute(&effect.literal.term.shift_vars(base), s);
            match effect.kind {
                EffectKind::Add => {
                    if !state.contains(&fact) {
                        state.insert(0, fact);
                    }
                }
                // Every fact that unifies goes, as SWI-Prolog's delete/3 removes them.
                EffectKind::Del => state.retain(|f| !unifies(&fact, f, &Subst::default())),
            }
        }
        let mut running: Vec<Term> = node.running.iter().map(|r| substitute(r, s)).collect();
        match action.snap {
            Snap::Start => {
                let key = action.instance(&name);
                if running.contains(&key) {
                    let shown = self.show(&key);
                    found.miss.get_or_insert(Miss {
                        action: index,
                        reason: format!("it starts `{shown}`, which is already running"),
                        span: action.name.span,
                    });
                    return;
                }
                running.push(key);
            }
            Snap::End => {
                if let Some(r) = closed {
                    running.remove(r);
                }
            }
            Snap::Instant => {}
        }
        let bindings: Vec<Option<Term>> = (0..action.vars.len() as u32)
            .map(|v| match substitute(&Term::Var(VarId(base + v)), s) {
                Term::Var(_) => None,
                value => Some(value),
            })
            .collect();
        let outer: Vec<(VarId, Term)> =
            s.iter().filter(|(v, _)| v.0 < base).map(|(v, t)| (*v, substitute(t, s))).collect();
        let taken = Taken { step: Step { action: index, name, bindings }, origin, outer, parent: node.path.clone() };
        found.children.push(Node {
            next_high: node.next_high,
            origin: node.origin,
            pending: node.pending[1..].iter().map(|(t, k)| (substitute(t, s), *k)).collect(),
            state,
            running,
            fresh: base + action.vars.len() as u32,
            applied: node.applied + 1,
            path: Some(Rc::new(taken)),
        });
    }

    /// The goal check at the end of the high-level plan; the arm-level plan if it holds.
    fn finish(&mut self, node: &Node, arm_problem: usize) -> Option<ArmPlan> {
        if !node.running.is_empty() {
            let shown: Vec<String> = node.running.iter().map(|r| format!("`{}`", self.show(r))).collect();
            // The `ll_action` that starts the first of them, to point at.
            let started = node.running[0].callable().and_then(|(base, arity)| {
                self.kb.actions.iter().find(|a| {
                    a.level == Level::Low && a.snap == Snap::Start && a.base == base && a.name.arity() == arity
                })
            });
            self.record(node.applied * 2 + 2, |r| {
                let mut diagnostic = Diagnostic::error(
                    codes::REFINEMENT_FAILED,
                    format!("the arm-level plan leaves {} running", shown.join(", ")),
                );
                if let Some(action) = started {
                    diagnostic =
                        diagnostic.primary(action.name.span, "a mapping starts this, and no later step ends it");
                }
                diagnostic
                    .with_note("every arm-level durative action a mapping starts must end in a later step")
                    .with_note(r.state_note(&node.state))
                    .with_help("add the `_end` step to the mapping that starts it, or to a later action's mapping")
            });
            return None;
        }
        let mut s = Subst::default();
        if !goal_holds(&self.arm.goal, &node.state, &mut s) {
            let missing =
                self.arm.goal.iter().find(|g| !node.state.iter().any(|f| unifies(&g.term, f, &Subst::default())));
            self.record(node.applied * 2 + 2, |r| {
                let mut diagnostic =
                    Diagnostic::error(codes::REFINEMENT_FAILED, "the arm-level plan does not reach the arm-level goal");
                diagnostic = match missing {
                    Some(literal) => diagnostic.primary(literal.span, "not true at the end of the arm-level plan"),
                    None => diagnostic.with_note(
                        "each goal literal holds, but not with the same values for the variables they share",
                    ),
                };
                diagnostic.with_note(r.state_note(&node.state))
            });
            return None;
        }
        // Gather the bindings every step made to older variables, and the goal's.
        let mut taken: Vec<&Taken> = Vec::new();
        let mut at = node.path.as_deref();
        while let Some(t) = at {
            taken.push(t);
            at = t.parent.as_deref();
        }
        taken.reverse();
        for t in &taken {
            for (v, value) in &t.outer {
                s.entry(*v).or_insert_with(|| value.clone());
            }
        }
        let steps: Vec<Step> = taken
            .iter()
            .map(|t| Step {
                action: t.step.action,
                name: substitute(&t.step.name, &s),
                bindings: t
                    .step
                    .bindings
                    .iter()
                    .map(|b| b.as_ref().map(|b| substitute(b, &s)).filter(|b| !matches!(b, Term::Var(_))))
                    .collect(),
            })
            .collect();
        let origin = taken.iter().map(|t| t.origin).collect();
        let init = self.arm.init.iter().map(|l| substitute(&l.term, &s)).collect();
        Some(ArmPlan { plan: Plan { problem: arm_problem, steps }, origin, init })
    }
}

/// The fixed parts of trying one `ll_action` clause on one step.
#[derive(Clone, Copy)]
struct Attempt<'a> {
    node: &'a Node,
    action: &'a Action,
    index: usize,
    base: u32,
    origin: usize,
    /// For an end step, the running arm-level start it closes (its index in `node.running`).
    closed: Option<usize>,
}

/// What applying one step found: the children, and the first reason an `ll_action` clause did
/// not apply.
#[derive(Default)]
struct Found {
    children: Vec<Node>,
    miss: Option<Miss>,
}

/// True if every goal literal unifies with a fact, sharing variables (first way found).
fn goal_holds(goal: &[hir::Literal], state: &[Term], s: &mut Subst) -> bool {
    let Some((first, rest)) = goal.split_first() else { return true };
    for fact in state {
        let mut attempt = s.clone();
        if unify_in(&first.term, fact, &mut attempt) && goal_holds(rest, state, &mut attempt) {
            *s = attempt;
            return true;
        }
    }
    false
}

/// `term` with its variables renumbered 0, 1, ... in order of first occurrence across calls
/// (`order` lists the original variables).
fn compact(term: &Term, order: &mut Vec<VarId>) -> Term {
    match term {
        Term::Var(v) => {
            let k = order.iter().position(|w| w == v).unwrap_or_else(|| {
                order.push(*v);
                order.len() - 1
            });
            Term::Var(VarId(k as u32))
        }
        Term::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| compact(a, order)).collect()),
        other => other.clone(),
    }
}
