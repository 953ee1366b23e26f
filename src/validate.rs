//! An independent plan validator: replays a plan on the KB's semantics.
//!
//! This is deliberately a separate code path from the search (`planner::successors`): states
//! are plain sets of ground HIR terms, conditions are checked by unification with full
//! backtracking, and nothing is interned or indexed. It is slow and simple so it can judge the
//! search's plans. Only the resolution engine is shared, for OnKB goals, since it *is* the
//! definition of "provable from the KB".
//!
//! A step applies when some schema whose name unifies with the step has, under some bindings,
//! its Valid literals in the state, its OnKB goals provable, no state fact matching an Invalid
//! literal and no goal literal unifying with an InvalidAtEnd literal; an end must end a
//! running start. Every such way of applying the step must lead to the same state, or the step
//! is ambiguous. The plan is valid when every step applies, the final state satisfies the goal
//! (its literals, sharing variables, all match facts) and no durative action is still running.

use std::collections::BTreeSet;

use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::engine::{Cell, Machine, Next, Program};
use crate::intern::{Interner, sym};
use crate::ir::hir::{self, Action, EffectKind, Kb, Level, Snap, Term};
use crate::ir::unify::unifiable;
use crate::source::{FileId, Span};
use crate::syntax::ast;

/// A step read from a plan file.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanStep {
    /// The ground action name.
    pub name: Term,
    /// Where it is written.
    pub span: Span,
}

/// Reads a plan file: one step per line, optionally numbered and ended by `.`; lines starting
/// with `%` and blank lines are skipped.
pub fn read_plan(file: FileId, text: &str, interner: &mut Interner, diags: &mut Diagnostics) -> Vec<PlanStep> {
    let mut steps = Vec::new();
    let mut offset = 0usize;
    for line in text.split_inclusive('\n') {
        let line_start = offset;
        offset += line.len();
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('%') {
            continue;
        }
        // Skip a step number such as `12 ` and a final `.`.
        let after_number = trimmed.trim_start_matches(|c: char| c.is_ascii_digit());
        let term_text = match after_number.strip_prefix(char::is_whitespace) {
            Some(rest) if after_number.len() < trimmed.len() => rest.trim_start(),
            _ => trimmed,
        };
        let term_text = term_text.strip_suffix('.').unwrap_or(term_text).trim_end();
        // `term_text` is a subslice of `line`, so its offset is a pointer difference.
        let term_start = line_start + (term_text.as_ptr() as usize - line.as_ptr() as usize);
        let span = Span::new(file, term_start as u32, (term_start + term_text.len()) as u32);
        match parse_step(term_text, interner) {
            Some(name) if name.callable().is_some() => steps.push(PlanStep { name, span }),
            Some(_) => diags.push(
                Diagnostic::error(codes::BAD_PLAN_FILE, "expected an action, found a term that is not one")
                    .primary(span, "not an atom or compound term"),
            ),
            None => diags.push(
                Diagnostic::error(codes::BAD_PLAN_FILE, "expected a ground action such as `grip_start(a1, b2)`")
                    .primary(span, "this line is not a ground term")
                    .with_note("a plan file has one action per line, optionally numbered; `%` starts a comment"),
            ),
        }
    }
    steps
}

/// Parses one step as a ground term; `None` if it is not one.
fn parse_step(text: &str, interner: &mut Interner) -> Option<Term> {
    let mut diags = Diagnostics::new();
    let ast = crate::syntax::parse_source(FileId(u32::MAX), &format!("{text}."), interner, &mut diags);
    if diags.has_errors() || ast.clauses.len() != 1 {
        return None;
    }
    lower_ground(&ast.clauses[0].term)
}

fn lower_ground(term: &ast::Term) -> Option<Term> {
    Some(match &term.kind {
        ast::TermKind::Atom(s) => Term::Atom(*s),
        ast::TermKind::Int(i) => Term::Int(*i),
        ast::TermKind::Float(f) => Term::Float(*f),
        ast::TermKind::Str(s) => Term::Str(*s),
        ast::TermKind::Compound(c) => {
            Term::Compound(c.functor, c.args.iter().map(lower_ground).collect::<Option<_>>()?)
        }
        ast::TermKind::List(l) => {
            let mut list = match &l.tail {
                Some(tail) => lower_ground(tail)?,
                None => Term::Atom(sym::NIL),
            };
            for item in l.items.iter().rev() {
                list = Term::Compound(sym::CONS, Box::new([lower_ground(item)?, list]));
            }
            list
        }
        ast::TermKind::Var(_) | ast::TermKind::Error => return None,
    })
}

/// A substitution for one schema's variables.
type Bindings = Vec<Option<Term>>;

fn resolve(term: &Term, bindings: &Bindings) -> Term {
    match term {
        Term::Var(v) => match bindings.get(v.0 as usize).cloned().flatten() {
            Some(value) => resolve(&value, bindings),
            None => term.clone(),
        },
        Term::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| resolve(a, bindings)).collect()),
        other => other.clone(),
    }
}

/// Matches a schema term (with variables) against a ground term, extending `bindings`.
fn matches(pattern: &Term, ground: &Term, bindings: &mut Bindings) -> bool {
    match pattern {
        Term::Var(v) => match bindings[v.0 as usize].clone() {
            Some(bound) => matches(&bound, ground, bindings),
            None => {
                bindings[v.0 as usize] = Some(ground.clone());
                true
            }
        },
        Term::Compound(f, args) => match ground {
            Term::Compound(g, values) if f == g && args.len() == values.len() => {
                args.iter().zip(values.iter()).all(|(a, v)| matches(a, v, bindings))
            }
            _ => false,
        },
        Term::Float(x) => matches!(ground, Term::Float(y) if x.to_bits() == y.to_bits()),
        other => other == ground,
    }
}

/// A state: facts and running durative actions (`base(args)`). `facts` holds each fact's
/// printed form, which identifies it; `terms` holds the same facts as terms for matching.
#[derive(Clone, Debug)]
struct State {
    facts: BTreeSet<String>,
    terms: Vec<Term>,
    running: Vec<String>,
}

impl State {
    fn identity(&self) -> (&BTreeSet<String>, &[String]) {
        (&self.facts, &self.running)
    }
}

/// The replay's verdict.
pub struct Verdict {
    /// Problems found; empty when the plan is valid.
    pub diagnostics: Diagnostics,
    /// The number of steps that applied.
    pub applied: usize,
}

struct Replayer<'a, 'p> {
    kb: &'a Kb,
    interner: &'a Interner,
    problem: usize,
    machine: Machine<'p>,
}

/// The key of a ground term for the state's sets (its printed form: canonical and ordered).
fn key(interner: &Interner, term: &Term) -> String {
    hir::term_to_string(interner, term, &hir::VarTable::default())
}

/// Why a candidate schema did not apply, for the message.
struct Miss {
    action: usize,
    reason: String,
    span: Span,
    /// The label at `span`.
    label: &'static str,
}

impl Replayer<'_, '_> {
    fn initial_state(&self) -> State {
        let problem = &self.kb.problems[self.problem];
        let mut state = State { facts: BTreeSet::new(), terms: Vec::new(), running: Vec::new() };
        for literal in &problem.init {
            if state.facts.insert(key(self.interner, &literal.term)) {
                state.terms.push(literal.term.clone());
            }
        }
        state
    }

    /// Every state `step` can lead to, or why it leads nowhere.
    fn successors(&mut self, state: &State, step: &Term) -> Result<Vec<State>, Option<Miss>> {
        let mut results: Vec<State> = Vec::new();
        let mut miss: Option<Miss> = None;
        for (index, action) in self.kb.actions.iter().enumerate() {
            if action.level != Level::High {
                continue;
            }
            let mut bindings: Bindings = vec![None; action.vars.len()];
            if !matches(&action.name.term, step, &mut bindings) {
                continue;
            }
            let running = if action.snap == Snap::End {
                let started = start_key(self.interner, action, &bindings);
                if !state.running.contains(&started) {
                    miss.get_or_insert(Miss {
                        action: index,
                        reason: format!("it ends `{started}`, which is not running"),
                        span: action.name.span,
                        label: "this schema",
                    });
                    continue;
                }
                Some(started)
            } else {
                None
            };
            let before = results.len();
            self.valid(state, action, index, 0, &mut bindings, &mut results, &mut miss, running.as_deref());
            if results.len() == before && miss.as_ref().is_none_or(|m| m.action != index) {
                miss.get_or_insert(Miss {
                    action: index,
                    reason: "its conditions do not hold".into(),
                    span: action.name.span,
                    label: "this schema",
                });
            }
        }
        if results.is_empty() {
            return Err(miss);
        }
        results.sort_by(|a, b| a.identity().cmp(&b.identity()));
        results.dedup_by(|a, b| a.identity() == b.identity());
        Ok(results)
    }

    #[allow(clippy::too_many_arguments)]
    fn valid(
        &mut self,
        state: &State,
        action: &Action,
        index: usize,
        position: usize,
        bindings: &mut Bindings,
        results: &mut Vec<State>,
        miss: &mut Option<Miss>,
        ends: Option<&str>,
    ) {
        let Some(literal) = action.valid.get(position) else {
            return self.on_kb(state, action, index, bindings, results, miss, ends);
        };
        let mut matched = false;
        for fact in &state.terms {
            let mut attempt = bindings.clone();
            if matches(&literal.term, fact, &mut attempt) {
                matched = true;
                self.valid(state, action, index, position + 1, &mut attempt, results, miss, ends);
            }
        }
        if !matched {
            let shown = hir::term_to_string(self.interner, &resolve(&literal.term, bindings), &action.vars);
            miss.get_or_insert(Miss {
                action: index,
                reason: format!("its Valid condition `{shown}` is not in the state"),
                span: literal.span,
                label: "this condition fails",
            });
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn on_kb(
        &mut self,
        state: &State,
        action: &Action,
        index: usize,
        bindings: &Bindings,
        results: &mut Vec<State>,
        miss: &mut Option<Miss>,
        ends: Option<&str>,
    ) {
        let mut solutions: Vec<Bindings> = Vec::new();
        if action.on_kb.is_empty() {
            solutions.push(bindings.clone());
        } else {
            self.machine.reset();
            let mut cells: Vec<Option<Cell>> = vec![None; action.vars.len()];
            for (v, value) in bindings.iter().enumerate() {
                if let Some(value) = value {
                    cells[v] = Some(self.machine.put_term(value, &mut []));
                }
            }
            let mut goal = Cell::Atom(sym::TRUE);
            for g in action.on_kb.iter().rev() {
                let cell = self.machine.put_goal(g, &mut cells);
                goal = if goal == Cell::Atom(sym::TRUE) {
                    cell
                } else {
                    self.machine.new_compound(sym::COMMA, &[cell, goal])
                };
            }
            let outcome = self.machine.solve(goal, |m| {
                let mut solution = bindings.clone();
                for (v, cell) in cells.iter().enumerate() {
                    if solution[v].is_none()
                        && let Some(cell) = cell
                    {
                        let value = m.read(*cell, &mut Vec::new());
                        if value.is_ground() {
                            solution[v] = Some(value);
                        }
                    }
                }
                solutions.push(solution);
                Next::More
            });
            if let Err(error) = outcome {
                miss.get_or_insert(Miss {
                    action: index,
                    reason: format!("proving its OnKB goals failed: {}", error.message(self.interner)),
                    span: action.slots[4],
                    label: "this condition fails",
                });
                return;
            }
            if solutions.is_empty() {
                miss.get_or_insert(Miss {
                    action: index,
                    reason: "its OnKB goals are not provable".into(),
                    span: action.slots[4],
                    label: "this condition fails",
                });
            }
        }
        for solution in solutions {
            self.finish(state, action, index, &solution, results, miss, ends);
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn finish(
        &mut self,
        state: &State,
        action: &Action,
        index: usize,
        bindings: &Bindings,
        results: &mut Vec<State>,
        miss: &mut Option<Miss>,
        ends: Option<&str>,
    ) {
        for literal in &action.invalid {
            let forbidden = resolve(&literal.term, bindings);
            if let Some(fact) = state.terms.iter().find(|f| unifiable(&forbidden, f)) {
                let shown = key(self.interner, fact);
                miss.get_or_insert(Miss {
                    action: index,
                    reason: format!("the state has `{shown}`, which its Invalid list forbids"),
                    span: literal.span,
                    label: "this condition fails",
                });
                return;
            }
        }
        let problem = &self.kb.problems[self.problem];
        for literal in &action.invalid_at_end {
            let forbidden = resolve(&literal.term, bindings);
            if problem.goal.iter().any(|g| unifiable(&forbidden, &g.term)) {
                miss.get_or_insert(Miss {
                    action: index,
                    reason: "its InvalidAtEnd list meets a goal literal".into(),
                    span: literal.span,
                    label: "this condition fails",
                });
                return;
            }
        }
        let mut next = state.clone();
        for effect in &action.effects {
            let fact = resolve(&effect.literal.term, bindings);
            if !fact.is_ground() {
                miss.get_or_insert(Miss {
                    action: index,
                    reason: "an effect is not ground".into(),
                    span: effect.span,
                    label: "this condition fails",
                });
                return;
            }
            let fact_key = key(self.interner, &fact);
            match effect.kind {
                EffectKind::Add => {
                    if next.facts.insert(fact_key) {
                        next.terms.push(fact);
                    }
                }
                EffectKind::Del => {
                    if next.facts.remove(&fact_key) {
                        next.terms.retain(|t| key(self.interner, t) != fact_key);
                    }
                }
            }
        }
        match action.snap {
            Snap::Start => next.running.push(start_key(self.interner, action, bindings)),
            Snap::End => {
                if let Some(ended) = ends
                    && let Some(position) = next.running.iter().position(|r| r == ended)
                {
                    next.running.remove(position);
                }
            }
            Snap::Instant => {}
        }
        next.terms.sort_by_key(|t| key(self.interner, t));
        next.running.sort();
        results.push(next);
    }

    fn goal_reached(&self, state: &State) -> bool {
        let problem = &self.kb.problems[self.problem];
        fn from(goal: &[hir::Literal], state: &State, bindings: &mut Bindings) -> bool {
            let Some((first, rest)) = goal.split_first() else { return true };
            state.terms.iter().any(|fact| {
                let mut attempt = bindings.clone();
                matches(&first.term, fact, &mut attempt) && from(rest, state, &mut attempt)
            })
        }
        from(&problem.goal, state, &mut vec![None; problem.vars.len()])
    }
}

/// `base(args)` of a durative action's start or end under `bindings`.
fn start_key(interner: &Interner, action: &Action, bindings: &Bindings) -> String {
    let name = resolve(&action.name.term, bindings);
    let running = match name {
        Term::Compound(_, args) => Term::Compound(action.base, args),
        _ => Term::Atom(action.base),
    };
    key(interner, &running)
}

/// Replays `steps` on problem `problem` of `kb`.
pub fn validate(kb: &Kb, interner: &Interner, program: &Program, problem: usize, steps: &[PlanStep]) -> Verdict {
    let mut replayer = Replayer { kb, interner, problem, machine: Machine::new(program, 1_000_000) };
    let mut diagnostics = Diagnostics::new();
    let mut state = replayer.initial_state();
    let no_vars = hir::VarTable::default();
    for (i, step) in steps.iter().enumerate() {
        let shown = hir::term_to_string(interner, &step.name, &no_vars);
        match replayer.successors(&state, &step.name) {
            Ok(mut next) if next.len() == 1 => state = next.remove(0),
            Ok(next) => {
                diagnostics.push(
                    Diagnostic::error(codes::INVALID_PLAN, format!("step {} `{shown}` is ambiguous", i + 1))
                        .primary(step.span, format!("{} different states can follow", next.len()))
                        .with_note("several schemas or bindings apply to this step with different effects")
                        .with_help("give the schemas distinct names, or make their conditions exclusive"),
                );
                return Verdict { diagnostics, applied: i };
            }
            Err(miss) => {
                let mut diagnostic =
                    Diagnostic::error(codes::INVALID_PLAN, format!("step {} `{shown}` does not apply", i + 1)).primary(
                        step.span,
                        if i == 0 {
                            "not applicable in the initial state"
                        } else {
                            "not applicable after the steps before it"
                        },
                    );
                match miss {
                    Some(miss) => {
                        let action = interner.resolve(kb.actions[miss.action].name.name());
                        diagnostic = diagnostic
                            .secondary(miss.span, miss.label)
                            .with_note(format!("`{action}`: {}", miss.reason));
                    }
                    None => diagnostic = diagnostic.with_note("no action schema has this name and arity"),
                }
                let facts: Vec<&String> = state.facts.iter().collect();
                let listed: Vec<String> = facts.iter().take(12).map(|f| f.to_string()).collect();
                let more = if facts.len() > 12 { format!(", and {} more", facts.len() - 12) } else { String::new() };
                diagnostics.push(diagnostic.with_note(format!("the state is [{}{more}]", listed.join(", "))));
                return Verdict { diagnostics, applied: i };
            }
        }
    }
    let problem = &kb.problems[problem];
    let problem_name = interner.resolve(problem.name);
    if !state.running.is_empty() {
        diagnostics.push(
            Diagnostic::error(codes::INVALID_PLAN, format!("the plan leaves {} running", state.running.join(", ")))
                .with_note("every durative action started must end")
                .with_help("add the missing `_end` steps"),
        );
    } else if !replayer.goal_reached(&state) {
        let missing: Vec<String> = problem
            .goal
            .iter()
            .filter(|g| !state.terms.iter().any(|f| unifiable(&g.term, f)))
            .map(|g| format!("`{}`", hir::term_to_string(interner, &g.term, &problem.vars)))
            .collect();
        let mut diagnostic =
            Diagnostic::error(codes::INVALID_PLAN, format!("the plan does not reach the goal of `{problem_name}`"));
        if let Some(first) = problem.goal.iter().find(|g| !state.terms.iter().any(|f| unifiable(&g.term, f))) {
            diagnostic = diagnostic.secondary(first.span, "not true at the end");
        }
        diagnostic = if missing.is_empty() {
            diagnostic.with_note("each goal literal holds, but not with the same values for the variables they share")
        } else {
            diagnostic.with_note(format!("missing at the end: {}", crate::passes::lower::join_and(&missing)))
        };
        diagnostics.push(diagnostic);
    }
    Verdict { diagnostics, applied: steps.len() }
}
