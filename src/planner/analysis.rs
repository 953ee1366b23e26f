//! Proofs that a problem has no solution, and why.
//!
//! Two analyses, both sound (they never call a solvable problem unsolvable):
//!
//! - [`exclusive_goals`]: invariant synthesis, a simplified form of Helmert's ("Concise
//!   finite-domain representations for PDDL planning tasks", 2009). A group of predicates,
//!   each with one *counted* argument, is an invariant when every action that adds a group
//!   atom for some value of the counted argument also deletes a group atom for the same value
//!   that its Valid list requires, and the initial state holds at most one atom per value. A
//!   state then never holds two atoms of the group with the same value, so a goal that asks for
//!   two (a block on the table at two cells, or both on the table and on a block) is
//!   unreachable. In the standard blocks world the analysis finds that each block is in one of
//!   `ontable/3`, `on/4` and `moving/6`, and each arm in one of its six states.
//! - [`explain_unreachable`]: the delete relaxation explored to its fixpoint. A goal literal
//!   it never reaches is unreachable however the actions are ordered. The explanation follows
//!   the literal back through the schemas that could add it to the first condition that never
//!   holds: a Valid literal itself unreachable (explained in turn), an OnKB goal that is not
//!   provable, or an InvalidAtEnd condition that meets the goal.

use super::relaxed::Relaxation;
use super::successors::{OnKbCache, const_to_cell, match_pattern, substitute};
use crate::diag::{Diagnostic, codes};
use crate::engine::{Machine, Program};
use crate::intern::Interner;
use crate::ir::hir::{self, EffectKind, Kb, Term};
use crate::ir::task::{ConstId, LiteralPattern, Pattern, PredId, Task};
use crate::ir::unify::unifiable;

/// A predicate with one counted argument position.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Member {
    pred: PredId,
    position: usize,
}

/// Why a candidate group is not balanced: an action adds an atom with counted term `term`
/// without deleting a required group atom for it.
struct Unbalanced {
    schema: usize,
    term: Pattern,
}

fn counted<'a>(group: &[Member], literal: &'a LiteralPattern) -> Option<&'a Pattern> {
    group.iter().find(|m| m.pred == literal.pred).and_then(|m| literal.args.get(m.position))
}

/// Checks the balance condition of `group` on every schema.
fn balance(task: &Task, group: &[Member]) -> Result<(), Option<Unbalanced>> {
    for (index, schema) in task.schemas.iter().enumerate() {
        let mut added: Vec<&Pattern> = Vec::new();
        for (kind, literal) in schema.effects.iter() {
            if *kind != EffectKind::Add {
                continue;
            }
            let Some(term) = counted(group, literal) else { continue };
            if added.contains(&term) {
                return Err(None); // two atoms for one value: cannot be balanced by refinement
            }
            added.push(term);
            let balanced = schema.effects.iter().any(|(k, deleted)| {
                *k == EffectKind::Del
                    && counted(group, deleted) == Some(term)
                    && schema.valid.iter().any(|v| v.pred == deleted.pred && v.args == deleted.args)
            });
            if !balanced {
                return Err(Some(Unbalanced { schema: index, term: term.clone() }));
            }
        }
    }
    Ok(())
}

/// True if the initial state holds at most one atom of `group` per counted value.
fn holds_initially(task: &Task, group: &[Member]) -> bool {
    let mut seen: Vec<ConstId> = Vec::new();
    for fact in task.init.facts() {
        let pred = task.facts.pred_of(fact);
        if let Some(member) = group.iter().find(|m| m.pred == pred) {
            let value = task.facts.args(fact)[member.position];
            if seen.contains(&value) {
                return false;
            }
            seen.push(value);
        }
    }
    true
}

/// The invariant groups of `task`, found by refining candidates from each added predicate.
fn invariants(task: &Task) -> Vec<Vec<Member>> {
    const MAX_GROUP: usize = 6;
    let mut queue: Vec<Vec<Member>> = Vec::new();
    for schema in &task.schemas {
        for (kind, literal) in schema.effects.iter() {
            if *kind == EffectKind::Add {
                for position in 0..literal.args.len() {
                    let seed = vec![Member { pred: literal.pred, position }];
                    if !queue.contains(&seed) {
                        queue.push(seed);
                    }
                }
            }
        }
    }
    let mut tried: Vec<Vec<Member>> = Vec::new();
    let mut found: Vec<Vec<Member>> = Vec::new();
    while let Some(group) = queue.pop() {
        let mut key = group.clone();
        key.sort();
        if tried.contains(&key) || found.iter().any(|f| key.iter().all(|m| f.contains(m))) {
            continue;
        }
        tried.push(key);
        match balance(task, &group) {
            Ok(()) => {
                if holds_initially(task, &group) {
                    found.push(group);
                }
            }
            Err(Some(Unbalanced { schema, term })) if group.len() < MAX_GROUP => {
                // Refine: add a deleted predicate whose argument carries the same term.
                for (kind, deleted) in task.schemas[schema].effects.iter() {
                    if *kind != EffectKind::Del || group.iter().any(|m| m.pred == deleted.pred) {
                        continue;
                    }
                    for (position, arg) in deleted.args.iter().enumerate() {
                        if *arg == term {
                            let mut refined = group.clone();
                            refined.push(Member { pred: deleted.pred, position });
                            queue.push(refined);
                        }
                    }
                }
            }
            Err(_) => {}
        }
    }
    found
}

fn describe_group(interner: &Interner, task: &Task, group: &[Member]) -> String {
    let mut parts: Vec<String> = group
        .iter()
        .map(|m| {
            let (name, arity) = task.facts.pred_info(m.pred);
            format!("`{}/{arity}` (argument {})", interner.resolve(name), m.position + 1)
        })
        .collect();
    parts.sort();
    crate::passes::lower::join_and(&parts)
}

/// Two goal literals that an invariant forbids together, as an E0307 diagnostic.
pub fn exclusive_goals(kb: &Kb, task: &Task, interner: &Interner) -> Option<Diagnostic> {
    let problem = &kb.problems[task.problem];
    let groups = invariants(task);
    for group in &groups {
        for (i, a) in task.goal.iter().enumerate() {
            let Some(Pattern::Const(x)) = counted(group, a) else { continue };
            for (j, b) in task.goal.iter().enumerate().skip(i + 1) {
                let Some(Pattern::Const(y)) = counted(group, b) else { continue };
                // One fact can satisfy two literals of one predicate that unify (`q(a, b)` and
                // its generalisation `q(a, _)`): only literals no single atom satisfies clash.
                if x != y || (a.pred == b.pred && unifiable(&problem.goal[i].term, &problem.goal[j].term)) {
                    continue;
                }
                let show = |k: usize| hir::term_to_string(interner, &problem.goal[k].term, &problem.vars);
                let value = hir::term_to_string(interner, &task.consts.to_term(*x), &hir::VarTable::default());
                return Some(
                    Diagnostic::error(
                        codes::EXCLUSIVE_GOALS,
                        format!("goal literals `{}` and `{}` can never hold together", show(i), show(j)),
                    )
                    .primary(problem.goal[j].span, "this one")
                    .secondary(problem.goal[i].span, "excludes this one")
                    .with_note(format!(
                        "every action keeps `{value}` in at most one of {}, and so does the initial state",
                        describe_group(interner, task, group)
                    ))
                    .with_help("correct the goal: these facts are alternatives"),
                );
            }
        }
    }
    None
}

/// A goal literal that asks for a unit of a renewable resource (`available(a2)` under
/// `resources(available(_))`) the task never has: no initial fact names it and no action can
/// add a fact of its predicate with that value (an effect with the value, or a variable, at
/// that position). The relaxation (which treats units as interchangeable) cannot see this, so
/// it is checked here instead, as E0306.
pub fn missing_units(kb: &Kb, task: &Task, interner: &Interner) -> Option<Diagnostic> {
    let problem = &kb.problems[task.problem];
    let in_init = |c: ConstId| task.init.facts().any(|f| task.facts.args(f).contains(&c));
    let open = open_positions(task);
    let in_effects =
        |c: ConstId| task.schemas.iter().any(|s| s.effects.iter().any(|(_, l)| l.args.contains(&Pattern::Const(c))));
    let may_add = |pred: PredId, position: usize| open.contains(&(pred, position));
    for (g, literal) in task.goal.iter().enumerate() {
        if !task.resource_goal[g] {
            continue;
        }
        for (position, arg) in literal.args.iter().enumerate() {
            let Pattern::Const(c) = *arg else { continue };
            if in_init(c) || in_effects(c) || may_add(literal.pred, position) {
                continue;
            }
            let shown = hir::term_to_string(interner, &problem.goal[g].term, &problem.vars);
            let unit = hir::term_to_string(interner, &task.consts.to_term(c), &hir::VarTable::default());
            return Some(
                Diagnostic::error(codes::UNREACHABLE_GOAL_RELAXED, format!("goal `{shown}` can never be reached"))
                    .primary(problem.goal[g].span, format!("`{unit}` is not a unit of the resource"))
                    .with_note(format!(
                        "`{shown}` is a unit of a renewable resource (`resources/1`); no fact of the initial state \
                         names `{unit}`, and no action adds one"
                    ))
                    .with_help(format!("add `{shown}` to the initial state, or remove it from the goal")),
            );
        }
    }
    None
}

/// The argument positions that may hold a value neither the initial state nor an effect's
/// constants name: an `add` effect puts a variable there that OnKB or the name binds (not a
/// Valid literal), or that a Valid literal reads from such a position, or a compound. Any
/// other position only ever holds values of the initial state or constants of effects.
fn open_positions(task: &Task) -> Vec<(PredId, usize)> {
    fn vars_of(pattern: &Pattern, out: &mut Vec<u32>) {
        match pattern {
            Pattern::Const(_) => {}
            Pattern::Var(v) => out.push(*v),
            Pattern::Compound(_, args) => args.iter().for_each(|a| vars_of(a, out)),
        }
    }
    let mut open: Vec<(PredId, usize)> = Vec::new();
    loop {
        let mut changed = false;
        for schema in &task.schemas {
            let mut read = Vec::new();
            let mut from_open = Vec::new();
            for literal in schema.valid.iter() {
                for (i, a) in literal.args.iter().enumerate() {
                    vars_of(a, &mut read);
                    if open.contains(&(literal.pred, i)) || matches!(a, Pattern::Compound(..)) {
                        vars_of(a, &mut from_open);
                    }
                }
            }
            for (kind, literal) in schema.effects.iter() {
                if *kind != EffectKind::Add {
                    continue;
                }
                for (i, a) in literal.args.iter().enumerate() {
                    let is_open = match a {
                        Pattern::Const(_) => false,
                        Pattern::Var(v) => !read.contains(v) || from_open.contains(v),
                        Pattern::Compound(..) => true,
                    };
                    if is_open && !open.contains(&(literal.pred, i)) {
                        open.push((literal.pred, i));
                        changed = true;
                    }
                }
            }
        }
        if !changed {
            return open;
        }
    }
}

/// Binds a schema's add literal to a target fact: ground arguments of the target constrain the
/// schema's variables; variables of the target constrain nothing.
fn bind_head(task: &Task, head: &LiteralPattern, target: &[Term], bindings: &mut [Option<ConstId>]) -> bool {
    let mut trail = Vec::new();
    for (pattern, wanted) in head.args.iter().zip(target) {
        if !wanted.is_ground() {
            continue;
        }
        let Some(value) = task.consts.find_term(wanted) else { return false };
        if !match_pattern(pattern, value, &task.consts, bindings, &mut trail) {
            return false;
        }
    }
    true
}

struct Explainer<'a, 'p> {
    /// Whether the explanation found an `add` with a variable nothing binds (then the
    /// diagnostic is E0213, naming the action).
    open_add: bool,
    kb: &'a Kb,
    interner: &'a Interner,
    relaxation: Relaxation,
    machine: Machine<'p>,
    cache: OnKbCache,
    notes: Vec<String>,
    labels: Vec<(crate::source::Span, String)>,
}

impl Explainer<'_, '_> {
    /// Adds a label, once: two explanation chains through the same condition with the same
    /// instance would otherwise label it twice.
    fn label(&mut self, span: crate::source::Span, message: String) {
        if !self.labels.iter().any(|(s, m)| *s == span && *m == message) {
            self.labels.push((span, message));
        }
    }

    /// Explains why no reachable fact matches `pred(target)`, whose variables are named by
    /// `vars`; `depth` bounds the recursion.
    fn why(&mut self, task: &mut Task, pred: PredId, target: &[Term], vars: &hir::VarTable, depth: usize) {
        let (name, arity) = task.facts.pred_info(pred);
        let shown = if arity == 0 {
            self.interner.resolve(name).to_string()
        } else {
            hir::term_to_string(self.interner, &Term::Compound(name, hir::Args::from(target.to_vec())), vars)
        };
        let producers: Vec<(usize, usize)> = task
            .schemas
            .iter()
            .enumerate()
            .flat_map(|(s, schema)| {
                schema
                    .effects
                    .iter()
                    .enumerate()
                    .filter(move |(_, (k, l))| *k == EffectKind::Add && l.pred == pred)
                    .map(move |(e, _)| (s, e))
            })
            .collect();
        if producers.is_empty() {
            let predicate = self.interner.resolve(name);
            self.notes
                .push(format!("no action adds `{predicate}/{arity}` facts, and the initial state has no `{shown}`"));
            return;
        }
        for (s, e) in producers.into_iter().take(3) {
            let schema = task.schemas[s].clone();
            let action = &self.kb.actions[schema.action];
            let action_name = self.interner.resolve(action.name.name()).to_string();
            let mut bindings = vec![None; schema.vars];
            if !bind_head(task, &schema.effects[e].1, target, &mut bindings) {
                continue;
            }
            // An `add` with a variable nothing binds (W0010) never applies: this is the reason.
            let effect_span = action
                .effects
                .iter()
                .filter(|ef| ef.kind == EffectKind::Add)
                .nth(schema.effects[..e].iter().filter(|(k, _)| *k == EffectKind::Add).count())
                .map(|ef| ef.span);
            if let Some(span) = effect_span
                && schema.open_effects().contains(&e)
            {
                self.notes.push(format!(
                    "`{action_name}` would add `{shown}`, but a variable of that effect is bound by nothing, so \
                     `{action_name}` never applies: a state holds ground facts only"
                ));
                self.label(span, "a variable here is bound by nothing".to_string());
                self.open_add = true;
                return;
            }
            let blocked = schema.valid.iter().find(|l| !self.relaxation.reached(task, l, &bindings)).cloned();
            if let Some(literal) = blocked {
                let term = substitute(&task.literal_to_term(&literal), &task.consts, &bindings);
                let literal_shown = hir::term_to_string(self.interner, &term, &action.vars);
                self.notes.push(format!(
                    "`{action_name}` would add `{shown}`, but needs `{literal_shown}`, which no reachable state has"
                ));
                self.label(literal.span, format!("`{literal_shown}` is never reached"));
                if depth > 0 {
                    let args: Vec<Term> = term.args().to_vec();
                    let vars = action.vars.clone();
                    self.why(task, literal.pred, &args, &vars, depth - 1);
                }
                return;
            }
            if let Some(FailingGoal { literal: goal, negated, occurs_check, dif }) =
                self.failing_on_kb_goal(task, s, &bindings)
            {
                let goal_shown =
                    hir::term_to_string(self.interner, &substitute(&goal.term, &task.consts, &bindings), &action.vars);
                if negated {
                    self.notes.push(format!(
                        "`{action_name}` would add `{shown}`, but its OnKB goal `\\+ {goal_shown}` fails: the KB \
                         proves `{goal_shown}`"
                    ));
                    self.label(goal.span, format!("`{goal_shown}` is provable, so its negation fails"));
                    return;
                }
                self.notes.push(format!(
                    "`{action_name}` would add `{shown}`, but its OnKB goal `{goal_shown}` is not provable from the KB"
                ));
                if occurs_check {
                    self.notes.push(
                        "a unification in that proof failed by the occurs check (a variable against a term \
                         that contains it, as `X = f(X)`): kbc builds no cyclic terms, where SWI-Prolog makes \
                         one and goes on (docs/dsl.md, \"Built-ins\")"
                            .to_string(),
                    );
                }
                if dif {
                    self.notes.push(
                        "that proof binds values which a `dif/2` goal before it keeps apart: the constraint \
                         rejects them"
                            .to_string(),
                    );
                }
                self.label(goal.span, format!("`{goal_shown}` is not provable"));
                return;
            }
            // InvalidAtEnd is checked against the goal: a literal that meets it rules the action
            // out for the whole problem (the paper's meaning), which is why it never applies.
            let problem = &self.kb.problems[task.problem];
            for (term, literal) in schema.invalid_at_end.iter().zip(&action.invalid_at_end) {
                let forbidden = substitute(term, &task.consts, &bindings);
                if let Some(goal) = problem.goal.iter().find(|g| unifiable(&forbidden, &g.term)) {
                    let forbidden_shown = hir::term_to_string(self.interner, &forbidden, &action.vars);
                    let goal_shown = hir::term_to_string(self.interner, &goal.term, &problem.vars);
                    self.notes.push(format!(
                        "`{action_name}` would add `{shown}`, but its InvalidAtEnd condition `{forbidden_shown}` \
                         meets the goal literal `{goal_shown}`, so it never applies in this problem"
                    ));
                    self.notes.push(
                        "an InvalidAtEnd literal is checked against the goal, not the state: it keeps an action \
                         from undoing part of the goal"
                            .to_string(),
                    );
                    self.label(literal.span, format!("`{forbidden_shown}` is in the goal"));
                    return;
                }
            }
            self.notes
                .push(format!("`{action_name}` would add `{shown}`, but its conditions never hold together for it"));
            self.label(action.name.span, "never applicable for this".to_string());
            return;
        }
    }

    /// The first OnKB goal of schema `s` that no solution of the goals before it satisfies,
    /// under `bindings` (see [`FailingGoal`]); `None` if they all have solutions (or the
    /// engine fails).
    fn failing_on_kb_goal(&mut self, task: &Task, s: usize, bindings: &[Option<ConstId>]) -> Option<FailingGoal> {
        use crate::engine::{Cell, Next};
        let schema = &task.schemas[s];
        for k in 1..=schema.on_kb.len() {
            self.machine.reset();
            let mut cells: Vec<Option<Cell>> = vec![None; schema.vars];
            for (v, value) in bindings.iter().enumerate() {
                if let Some(value) = value {
                    cells[v] = Some(const_to_cell(&mut self.machine, &task.consts, *value));
                }
            }
            let goal = self.machine.put_conjunction(&schema.on_kb[..k], &mut cells);
            let mut found = false;
            let solved = self.machine.solve(goal, |_| {
                found = true;
                Next::Stop
            });
            if solved.is_err() {
                return None;
            }
            if !found {
                let failing = &schema.on_kb[k - 1];
                let (negated, called) = match failing {
                    hir::Goal::Not(inner) if matches!(**inner, hir::Goal::Call(_)) => (true, &**inner),
                    _ => (false, failing),
                };
                let mut first = None;
                called.for_each_call(&mut |l| {
                    first.get_or_insert_with(|| l.clone());
                });
                return first.map(|literal| FailingGoal {
                    literal,
                    negated,
                    occurs_check: self.machine.occurs_check_failed(),
                    dif: self.machine.dif_check_failed(),
                });
            }
        }
        None
    }
}

/// An OnKB goal that fails ([`Explainer::failing_on_kb_goal`]).
struct FailingGoal {
    /// The goal's first call: the goal itself, or what a negation `\+ G` negates.
    literal: hir::Literal,
    /// Whether the goal is `\+ literal`, which fails because `literal` is provable.
    negated: bool,
    /// Whether the occurs check failed a unification while the goal was tried.
    occurs_check: bool,
    /// Whether a `dif/2` constraint rejected a binding while the goal was tried.
    dif: bool,
}

/// A goal literal unreachable even ignoring deletions, as an E0306 diagnostic with the reason;
/// `None` if every goal literal is reachable that way, or if the exploration does not fit
/// `budget`'s time and memory.
pub fn explain_unreachable(
    kb: &Kb,
    task: &mut Task,
    program: &Program,
    interner: &Interner,
    budget: &super::Budget,
) -> Option<Diagnostic> {
    let mut explainer = Explainer {
        open_add: false,
        kb,
        interner,
        relaxation: Relaxation::unprojected(task),
        machine: Machine::new(program, budget.engine_steps),
        cache: OnKbCache::new(task),
        notes: Vec::new(),
        labels: Vec::new(),
    };
    let init = task.init.clone();
    let Explainer { relaxation, machine, cache, .. } = &mut explainer;
    relaxation.limit(budget);
    relaxation.evaluate_all(task, &init, machine, cache).ok()?;
    let unreached = explainer.relaxation.unreached_goals().to_vec();
    let &first = unreached.first()?;
    let problem = &kb.problems[task.problem];
    let goal = &problem.goal[first];
    let shown = hir::term_to_string(interner, &goal.term, &problem.vars);
    let literal = task.goal[first].clone();
    let target: Vec<Term> = goal.term.args().to_vec();
    explainer.why(task, literal.pred, &target, &problem.vars, 3);
    let code = if explainer.open_add { codes::UNBOUND_EFFECT_VARIABLE } else { codes::UNREACHABLE_GOAL_RELAXED };
    let mut diagnostic = Diagnostic::error(code, format!("goal `{shown}` can never be reached"))
        .primary(goal.span, "no sequence of actions makes this true")
        .with_note("even ignoring every deletion, the actions never produce it from the initial state");
    for note in explainer.notes {
        diagnostic = diagnostic.with_note(note);
    }
    for (span, label) in explainer.labels {
        diagnostic = diagnostic.secondary(span, label);
    }
    if unreached.len() > 1 {
        let others: Vec<String> = unreached[1..]
            .iter()
            .map(|&g| format!("`{}`", hir::term_to_string(interner, &problem.goal[g].term, &problem.vars)))
            .collect();
        diagnostic = diagnostic.with_note(format!("also unreachable: {}", crate::passes::lower::join_and(&others)));
    }
    Some(diagnostic.with_help("correct the goal, or the actions and KB facts it depends on"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn task(goals: &str) -> (crate::session::Frontend, Task) {
        let (_, frontend, diagnostics) = crate::session::Session::from_text("goals.pl", goals).into_parts();
        assert!(!diagnostics.has_errors(), "{diagnostics:?}");
        let task = crate::passes::task::build(&frontend.kb, 0);
        (frontend, task)
    }

    #[test]
    fn the_blocks_world_keeps_each_block_in_one_place() {
        let (frontend, task) = task("t :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2)]).\n");
        let groups = invariants(&task);
        let names = |g: &Vec<Member>| {
            let mut n: Vec<String> = g
                .iter()
                .map(|m| format!("{}@{}", frontend.interner.resolve(task.facts.pred_info(m.pred).0), m.position))
                .collect();
            n.sort();
            n.join(",")
        };
        let found: Vec<String> = groups.iter().map(names).collect();
        assert!(found.contains(&"moving@1,on@0,ontable@0".to_string()), "{found:?}");
    }
}
