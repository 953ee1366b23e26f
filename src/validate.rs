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
//! running start, and a start may not begin an action that is already running. A plan file
//! does not give the values of variables a step's name leaves out, so a step may lead to
//! several states; the replay follows each (up to a bound). The plan is valid when some way of
//! applying its steps reaches a final state that satisfies the goal (its literals, sharing
//! variables, all match facts) with no durative action still running.

use std::collections::BTreeSet;

use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::engine::{Cell, Machine, Next, Program};
use crate::intern::{Interner, Symbol, sym};
use crate::ir::hir::VarId;
use crate::ir::hir::{self, Action, EffectKind, Kb, Level, Snap, Term};
use crate::ir::plan::{Plan, Step};
use crate::ir::unify::{substitute, unifiable, unify_in};
use crate::source::{FileId, Span};
use crate::syntax::ast;
use rustc_hash::FxHashMap;

/// A step read from a plan file.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanStep {
    /// The ground action name: a snap action (`grip_start(a1, b2)`) in a total-order plan, the
    /// action (`grip(a1, b2)`) in a timed one.
    pub name: Term,
    /// Where it is written.
    pub span: Span,
    /// In a timed plan, when it starts and (for a durative action) how long it lasts, in STN
    /// time (thousandths of a time unit).
    pub timing: Option<(i64, Option<i64>)>,
    /// The same in millionths of a time unit, as written (`None`: as `timing`). Only the order
    /// of happenings uses it: other planners separate happenings by less than a thousandth
    /// (LPG by 0.0002), and rounding would make them simultaneous.
    pub fine_timing: Option<(i64, Option<i64>)>,
    /// Values of schema variables the name leaves out, by variable name, from a trailing
    /// `% with V = t, ...` comment (`kbc plan` writes one where such a variable reaches an
    /// effect): a schema with a variable of that name applies only with that value.
    pub with: Vec<(Symbol, Term)>,
}

impl PlanStep {
    /// A step with only a name.
    pub fn named(name: Term, span: Span) -> PlanStep {
        PlanStep { name, span, timing: None, fine_timing: None, with: Vec::new() }
    }

    /// The steps of an in-memory plan, with the values of their hidden variables, for
    /// [`validate`].
    pub fn of_plan(kb: &Kb, plan: &Plan, span: Span) -> Vec<PlanStep> {
        plan.steps
            .iter()
            .map(|step| PlanStep {
                with: crate::ir::plan::hidden_bindings(kb, step),
                ..PlanStep::named(step.name.clone(), span)
            })
            .collect()
    }
}

/// A time as PDDL plans write it (`12`, `1.5`, `0.001`, `0.0030` as LPG prints it), in
/// thousandths, rounded to the nearest (kbc keeps times to a thousandth); `None` if it is not
/// a non-negative decimal number.
fn parse_time(text: &str) -> Option<i64> {
    parse_fixed(text, 3)
}

/// A non-negative decimal number in units of 10^-`decimals`, rounded half up.
fn parse_fixed(text: &str, decimals: usize) -> Option<i64> {
    let (whole, fraction) = text.split_once('.').unwrap_or((text, ""));
    if whole.is_empty() && fraction.is_empty()
        || !whole.bytes().all(|b| b.is_ascii_digit())
        || !fraction.bytes().all(|b| b.is_ascii_digit())
    {
        return None;
    }
    let whole: i64 = if whole.is_empty() { 0 } else { whole.parse().ok()? };
    let (kept, rest) = fraction.split_at(fraction.len().min(decimals));
    let mut parts: i64 = if kept.is_empty() { 0 } else { format!("{kept:0<decimals$}").parse().ok()? };
    if rest.as_bytes().first().is_some_and(|&d| d >= b'5') {
        parts += 1; // round half up on the first digit dropped
    }
    whole.checked_mul(10i64.checked_pow(decimals as u32)?)?.checked_add(parts)
}

/// The decimals of [`PlanStep::fine_timing`] (millionths), and millionths per STN time unit.
const FINE_DECIMALS: usize = 6;
const FINE_PER_UNIT: i64 = 1000;

/// A timed line's start and duration: in STN time (thousandths) and in millionths.
struct LineTimes {
    time: i64,
    duration: Option<i64>,
    fine: (i64, Option<i64>),
}

/// A line of a timed plan, `0.000: (grip a1 b2) [1.000]`: the start, the action as a term's
/// text (`grip(a1, b2)`), its offset in the line, and the duration. `None` if the line is
/// not of that shape.
fn timed_line(line: &str) -> Option<(LineTimes, String, usize)> {
    // A `;` comment after the step (outside quotes), as other planners write them.
    let mut quoted = false;
    let end = line
        .char_indices()
        .find(|&(_, c)| {
            if c == '\'' {
                quoted = !quoted;
            }
            c == ';' && !quoted
        })
        .map_or(line.len(), |(i, _)| i);
    let line = line[..end].trim_end();
    let (time, rest) = line.split_once(':')?;
    let (time, fine_time) = (parse_time(time.trim())?, parse_fixed(time.trim(), FINE_DECIMALS)?);
    let open = rest.find('(')?;
    let close = open + crate::syntax::text::closing_bracket(&rest[open..])?;
    let inner = rest.get(open + 1..close)?.trim();
    let after = rest[close + 1..].trim();
    // LPG-td 1.4 ends its lines with a stray `)` after the duration: `[1.0000])`.
    let after = after.strip_suffix(')').filter(|a| a.ends_with(']')).unwrap_or(after);
    let (duration, fine_duration) = match after.strip_prefix('[').and_then(|d| d.strip_suffix(']')) {
        Some(d) => (Some(parse_time(d.trim())?), Some(parse_fixed(d.trim(), FINE_DECIMALS)?)),
        None if after.is_empty() => (None, None),
        None => return None,
    };
    // Split at top-level spaces: arguments may be compound terms written without spaces.
    let mut words = crate::syntax::text::split_top_level(inner, char::is_whitespace);
    // PDDL names are case-insensitive, and planners print them in either case (LPG in upper
    // case); the KB's names are lower case. A quoted atom keeps its case.
    for word in &mut words {
        if !word.starts_with('\'') {
            *word = word.to_lowercase();
        }
    }
    let (name, args) = words.split_first()?;
    let text = if args.is_empty() { name.clone() } else { format!("{name}({})", args.join(", ")) };
    let offset = line.len() - rest.len() + open;
    Some((LineTimes { time, duration, fine: (fine_time, fine_duration) }, text, offset))
}

/// Reads a plan file: one step per line, optionally numbered and ended by `.`; lines starting
/// with `%` or `;` and blank lines are skipped. A timed plan has lines such as
/// `0.000: (grip a1 b2) [1.000]` instead (the PDDL 2.1 plan format that `kbc plan --schedule`
/// prints, and other planners in any case, with any number of decimals and `;` comments); a
/// file is one or the other.
pub fn read_plan(file: FileId, text: &str, interner: &mut Interner, diags: &mut Diagnostics) -> Vec<PlanStep> {
    let mut steps: Vec<PlanStep> = Vec::new();
    let mut offset = 0usize;
    for line in text.split_inclusive('\n') {
        let line_start = offset;
        offset += line.len();
        let trimmed = line.trim();
        // `%` comments (kbc's) and `;` comments (PDDL planners').
        if trimmed.is_empty() || trimmed.starts_with('%') || trimmed.starts_with(';') {
            continue;
        }
        if let Some((times, term_text, at)) = timed_line(line.trim_end()) {
            let span = Span::new(file, (line_start + at) as u32, (line_start + line.trim_end().len()) as u32);
            if steps.first().is_some_and(|s| s.timing.is_none()) {
                diags.push(
                    Diagnostic::error(codes::BAD_PLAN_FILE, "a timed step in a total-order plan")
                        .primary(span, "this line has a time")
                        .with_note("a plan file lists snap actions in order, or timed actions; not both"),
                );
                continue;
            }
            match parse_step(&term_text, interner) {
                Some(name) if name.callable().is_some() => steps.push(PlanStep {
                    timing: Some((times.time, times.duration)),
                    fine_timing: Some(times.fine),
                    ..PlanStep::named(name, span)
                }),
                _ => diags.push(
                    Diagnostic::error(codes::BAD_PLAN_FILE, "expected a ground action such as `(grip a1 b2)`")
                        .primary(span, "this action is not ground")
                        .with_note("a timed plan line is `TIME: (ACTION ARGS...) [DURATION]`"),
                ),
            }
            continue;
        }
        // A trailing `% with V = t, ...` gives values of variables the name leaves out.
        let (trimmed, with) = match trimmed.split_once("% with ") {
            Some((step, with)) => match parse_with(with, interner) {
                Some(with) => (step.trim_end(), with),
                None => {
                    let at = line_start + (with.as_ptr() as usize - line.as_ptr() as usize);
                    diags.push(
                        Diagnostic::error(codes::BAD_PLAN_FILE, "expected `% with Var = value, ...`")
                            .primary(Span::new(file, at as u32, (at + with.len()) as u32), "not variable bindings")
                            .with_note("the comment gives values of variables the action's name leaves out"),
                    );
                    continue;
                }
            },
            None => (trimmed, Vec::new()),
        };
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
        if steps.first().is_some_and(|s| s.timing.is_some()) {
            diags.push(
                Diagnostic::error(codes::BAD_PLAN_FILE, "expected a timed step such as `0.000: (grip a1 b2) [1.000]`")
                    .primary(span, "this line has no time")
                    .with_note("a plan file lists snap actions in order, or timed actions; not both"),
            );
            continue;
        }
        match parse_step(term_text, interner) {
            Some(name) if name.callable().is_some() => steps.push(PlanStep { with, ..PlanStep::named(name, span) }),
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

/// Parses `V = t, W = u` (the text after `% with `): variable names and ground values.
fn parse_with(text: &str, interner: &mut Interner) -> Option<Vec<(Symbol, Term)>> {
    let mut diags = Diagnostics::new();
    let ast = crate::syntax::parse_source(FileId(u32::MAX), &format!("with([{text}])."), interner, &mut diags);
    if diags.has_errors() || ast.clauses.len() != 1 {
        return None;
    }
    let ast::TermKind::Compound(with) = &ast.clauses[0].term.kind else { return None };
    let ast::TermKind::List(list) = &with.args.first()?.kind else { return None };
    list.items
        .iter()
        .map(|item| match &item.kind {
            ast::TermKind::Compound(eq) if eq.functor == sym::EQ && eq.args.len() == 2 => match &eq.args[0].kind {
                ast::TermKind::Var(name) => Some((*name, lower_ground(&eq.args[1])?)),
                _ => None,
            },
            _ => None,
        })
        .collect()
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
        // A flat chain is the right-nested binary term it stands for.
        ast::TermKind::Compound(c) if c.notation == ast::Notation::Chain => {
            Term::xfy(c.functor, c.args.iter().map(lower_ground).collect::<Option<_>>()?)
        }
        ast::TermKind::Compound(c) => {
            Term::Compound(c.functor, c.args.iter().map(lower_ground).collect::<Option<_>>()?)
        }
        ast::TermKind::List(l) => {
            let mut list = match &l.tail {
                Some(tail) => lower_ground(tail)?,
                None => Term::Atom(sym::NIL),
            };
            for item in l.items.iter().rev() {
                list = Term::Compound(sym::CONS, hir::Args::from([lower_ground(item)?, list]));
            }
            list
        }
        ast::TermKind::Var(_) | ast::TermKind::Error => return None,
    })
}

/// A substitution for one schema's variables.
type Bindings = Vec<Option<Term>>;

/// Variables of the initial state (an arm-level problem may have them: `ll_arm_at(a1, 0, 0,
/// _)`) are numbered from here, apart from every schema's variables. As in Prolog, such a
/// variable unifies: a pattern variable can take it and carry it into an added fact, and a
/// Valid literal or the goal that gives it a value binds it in the state from then on
/// ([`bind_state_vars`]).
const STATE_VARS: u32 = 1 << 24;

/// When `pattern` (a schema term under `bindings`) unifies with `fact` only by giving values
/// to variables of the initial state in `fact`: the extended bindings and those values.
fn bind_state_vars(pattern: &Term, fact: &Term, bindings: &Bindings) -> Option<(Bindings, FxHashMap<VarId, Term>)> {
    let mut has_state_var = false;
    fact.for_each_var(&mut |v| has_state_var |= v.0 >= STATE_VARS);
    if !has_state_var {
        return None;
    }
    let mut subst = FxHashMap::default();
    if !unify_in(&resolve(pattern, bindings), fact, &mut subst) {
        return None;
    }
    let mut extended = bindings.clone();
    let mut bound = FxHashMap::default();
    for (var, value) in &subst {
        let value = substitute(value, &subst);
        match (var.0 >= STATE_VARS, &value) {
            // A state variable met an unbound schema variable: the schema variable takes it.
            (true, Term::Var(schema)) if schema.0 < STATE_VARS => extended[schema.0 as usize] = Some(Term::Var(*var)),
            (true, _) => {
                bound.insert(*var, value);
            }
            (false, _) => extended[var.0 as usize] = Some(value),
        }
    }
    // Schema variables bound to a state variable that is now bound take its value.
    for slot in extended.iter_mut().flatten() {
        *slot = substitute(slot, &bound);
    }
    Some((extended, bound))
}

/// True if `term` has a variable of the schema (not one of the initial state's).
fn has_schema_var(term: &Term) -> bool {
    let mut found = false;
    term.for_each_var(&mut |v| found |= v.0 < STATE_VARS);
    found
}

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
        // A variable of the initial state inside a value: it stands for itself.
        Term::Var(v) if v.0 >= STATE_VARS => pattern == ground,
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
    /// The schema and bindings of the step that led here (not part of the state's identity).
    via: Option<(usize, Bindings)>,
}

impl State {
    /// The state with variables of the initial state replaced by their values.
    fn instantiated(&self, interner: &Interner, bound: &FxHashMap<VarId, Term>) -> State {
        let mut next = State { facts: BTreeSet::new(), terms: Vec::new(), running: self.running.clone(), via: None };
        for term in &self.terms {
            let term = substitute(term, bound);
            if next.facts.insert(key(interner, &term)) {
                next.terms.push(term);
            }
        }
        next
    }

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
    /// The steps that applied, with the schema and the values of its variables each one used:
    /// the plan for the later passes.
    pub plan: Plan,
}

struct Replayer<'a, 'p> {
    kb: &'a Kb,
    interner: &'a Interner,
    problem: usize,
    machine: Machine<'p>,
}

/// The key of a ground term for the state's sets (its printed form: canonical and ordered).
fn key(interner: &Interner, term: &Term) -> String {
    // Variables of the initial state print from `_G0` on, not from `_G16777216`.
    fn unshifted(term: &Term) -> Term {
        match term {
            Term::Var(v) if v.0 >= STATE_VARS => Term::Var(VarId(v.0 - STATE_VARS)),
            Term::Compound(f, args) => Term::Compound(*f, args.iter().map(unshifted).collect()),
            other => other.clone(),
        }
    }
    hir::term_to_string(interner, &unshifted(term), &hir::VarTable::default())
}

/// Why a candidate schema did not apply, for the message.
struct Miss {
    action: usize,
    reason: String,
    span: Span,
    /// The label at `span`.
    label: &'static str,
}

/// One schema tried on one state: what stays fixed while its conditions are matched.
#[derive(Clone, Copy)]
struct Attempt<'a> {
    state: &'a State,
    action: &'a Action,
    /// The schema's index in `Kb::actions`.
    index: usize,
    /// For an end, the running start it ends.
    ends: Option<&'a str>,
}

/// What trying a step's schemas found: the states it leads to, and the first reason a schema
/// did not apply.
#[derive(Default)]
struct Found {
    results: Vec<State>,
    miss: Option<Miss>,
}

impl Replayer<'_, '_> {
    fn initial_state(&self) -> State {
        let problem = &self.kb.problems[self.problem];
        let mut state = State { facts: BTreeSet::new(), terms: Vec::new(), running: Vec::new(), via: None };
        for literal in &problem.init {
            let term = literal.term.shift_vars(STATE_VARS);
            if state.facts.insert(key(self.interner, &term)) {
                state.terms.push(term);
            }
        }
        state
    }

    /// Every state `step` can lead to, or why it leads nowhere.
    /// `with` gives values of variables the name leaves out (see [`PlanStep::with`]).
    fn successors(&mut self, state: &State, step: &Term, with: &[(Symbol, Term)]) -> Result<Vec<State>, Option<Miss>> {
        let mut found = Found::default();
        for (index, action) in self.kb.actions.iter().enumerate() {
            if action.level != self.kb.problems[self.problem].level {
                continue;
            }
            let mut bindings: Bindings = vec![None; action.vars.len()];
            if !matches(&action.name.term, step, &mut bindings) {
                continue;
            }
            let agrees = with.iter().all(|(name, value)| {
                match action.vars.vars.iter().position(|v| v.name == *name && self.interner.resolve(*name) != "_") {
                    None => true,
                    Some(v) => match &bindings[v] {
                        Some(bound) => resolve(bound, &bindings) == *value,
                        None => {
                            bindings[v] = Some(value.clone());
                            true
                        }
                    },
                }
            });
            if !agrees {
                continue;
            }
            let running = if action.snap == Snap::End {
                let started = start_key(self.interner, action, &bindings);
                if !state.running.contains(&started) {
                    found.miss.get_or_insert(Miss {
                        action: index,
                        reason: format!("it ends `{started}`, which is not running"),
                        span: action.name.span,
                        label: "this schema",
                    });
                    continue;
                }
                Some(started)
            } else {
                if action.snap == Snap::Start {
                    let started = start_key(self.interner, action, &bindings);
                    if state.running.contains(&started) {
                        found.miss.get_or_insert(Miss {
                            action: index,
                            reason: format!(
                                "it starts `{started}`, which is already running (an action does not overlap itself)"
                            ),
                            span: action.name.span,
                            label: "this schema",
                        });
                        continue;
                    }
                }
                None
            };
            let before = found.results.len();
            let attempt = Attempt { state, action, index, ends: running.as_deref() };
            self.valid(&attempt, 0, &mut bindings, &mut found);
            if found.results.len() == before && found.miss.as_ref().is_none_or(|m| m.action != index) {
                found.miss.get_or_insert(Miss {
                    action: index,
                    reason: "its conditions do not hold".into(),
                    span: action.name.span,
                    label: "this schema",
                });
            }
        }
        let Found { mut results, miss } = found;
        if results.is_empty() {
            return Err(miss);
        }
        results.sort_by(|a, b| a.identity().cmp(&b.identity()));
        results.dedup_by(|a, b| a.identity() == b.identity());
        Ok(results)
    }

    /// Matches the Valid literals of `at.action` from `position` on against the state.
    fn valid(&mut self, at: &Attempt<'_>, position: usize, bindings: &mut Bindings, found: &mut Found) {
        let Attempt { state, action, index, .. } = *at;
        let Some(literal) = action.valid.get(position) else {
            return self.on_kb(at, bindings, found);
        };
        let mut matched = false;
        for fact in &state.terms {
            let mut attempt = bindings.clone();
            if matches(&literal.term, fact, &mut attempt) {
                matched = true;
                self.valid(at, position + 1, &mut attempt, found);
            } else if let Some((mut attempt, bound)) = bind_state_vars(&literal.term, fact, bindings) {
                // The fact has a variable of the initial state that the literal gives a value:
                // as in Prolog, the state keeps that value from here on.
                matched = true;
                let instantiated = state.instantiated(self.interner, &bound);
                self.valid(&Attempt { state: &instantiated, ..*at }, position + 1, &mut attempt, found);
            }
        }
        if !matched {
            let shown = hir::term_to_string(self.interner, &resolve(&literal.term, bindings), &action.vars);
            found.miss.get_or_insert(Miss {
                action: index,
                reason: format!("its Valid condition `{shown}` is not in the state"),
                span: literal.span,
                label: "this condition fails",
            });
        }
    }

    /// Proves the OnKB goals of `at.action`, one `finish` per solution.
    fn on_kb(&mut self, at: &Attempt<'_>, bindings: &Bindings, found: &mut Found) {
        let Attempt { action, index, .. } = *at;
        let mut solutions: Vec<Bindings> = Vec::new();
        if action.on_kb.is_empty() {
            solutions.push(bindings.clone());
        } else {
            // The goals run as the planner runs them: a start or an instantaneous action is
            // generated, so the values its step names (and its `with` bindings) are not known
            // to them unless a Valid literal bound them; each solution must then give those
            // values. (A goal such as `S2 \== S1` run before `S2` is bound holds.) An end
            // takes its running start's values before its conditions.
            let mut known = vec![action.snap == Snap::End; action.vars.len()];
            for literal in &action.valid {
                literal.term.for_each_var(&mut |v| {
                    if let Some(slot) = known.get_mut(v.0 as usize) {
                        *slot = true;
                    }
                });
            }
            self.machine.reset();
            let mut cells: Vec<Option<Cell>> = vec![None; action.vars.len()];
            for (v, value) in bindings.iter().enumerate() {
                if let Some(value) = value
                    && known[v]
                {
                    cells[v] = Some(self.machine.put_term(value, &mut []));
                }
            }
            let goal = self.machine.put_conjunction(&action.on_kb, &mut cells);
            let outcome = self.machine.solve(goal, |m| {
                let mut solution = bindings.clone();
                for (v, cell) in cells.iter().enumerate() {
                    let value = cell.map(|cell| m.read(cell, &mut Vec::new())).filter(Term::is_ground);
                    match (&solution[v], value) {
                        (None, Some(value)) => solution[v] = Some(value),
                        // A value the step names that the goals did not give: not this solution.
                        (Some(named), value) if !known[v] && value.as_ref() != Some(named) => return Next::More,
                        _ => {}
                    }
                }
                solutions.push(solution);
                Next::More
            });
            if let Err(error) = outcome {
                found.miss.get_or_insert(Miss {
                    action: index,
                    reason: format!("proving its OnKB goals failed: {}", error.message(self.interner)),
                    span: action.slots[4],
                    label: "this condition fails",
                });
                return;
            }
            if solutions.is_empty() {
                found.miss.get_or_insert(Miss {
                    action: index,
                    reason: "its OnKB goals are not provable".into(),
                    span: action.slots[4],
                    label: "this condition fails",
                });
            }
        }
        for solution in solutions {
            self.finish(at, &solution, found);
        }
    }

    /// Checks the Invalid and InvalidAtEnd lists, then applies the effects.
    fn finish(&mut self, at: &Attempt<'_>, bindings: &Bindings, found: &mut Found) {
        let Attempt { state, action, index, ends } = *at;
        for literal in &action.invalid {
            let forbidden = resolve(&literal.term, bindings);
            if let Some(fact) = state.terms.iter().find(|f| unifiable(&forbidden, f)) {
                let shown = key(self.interner, fact);
                found.miss.get_or_insert(Miss {
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
                found.miss.get_or_insert(Miss {
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
            if has_schema_var(&fact) && effect.kind == EffectKind::Del {
                // Every fact that unifies goes, as SWI-Prolog's delete/3 removes them.
                let gone: Vec<String> =
                    next.terms.iter().filter(|t| unifiable(&fact, t)).map(|t| key(self.interner, t)).collect();
                next.terms.retain(|t| !unifiable(&fact, t));
                for g in gone {
                    next.facts.remove(&g);
                }
                continue;
            }
            if has_schema_var(&fact) {
                found.miss.get_or_insert(Miss {
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
        next.via = Some((index, bindings.clone()));
        found.results.push(next);
    }

    fn goal_reached(&self, state: &State) -> bool {
        let problem = &self.kb.problems[self.problem];
        fn from(goal: &[hir::Literal], state: &State, bindings: &mut Bindings) -> bool {
            let Some((first, rest)) = goal.split_first() else { return true };
            state.terms.iter().any(|fact| {
                let mut attempt = bindings.clone();
                if matches(&first.term, fact, &mut attempt) {
                    return from(rest, state, &mut attempt);
                }
                // A variable of the initial state unifies with the goal's value.
                bind_state_vars(&first.term, fact, bindings)
                    .is_some_and(|(mut attempt, _)| from(rest, state, &mut attempt))
            })
        }
        from(&problem.goal, state, &mut vec![None; problem.vars.len()])
    }
}

/// `base(args)` of a durative action's start or end under `bindings`.
fn start_key(interner: &Interner, action: &Action, bindings: &Bindings) -> String {
    key(interner, &action.instance(&resolve(&action.name.term, bindings)))
}

/// The most states a replay follows at once: a plan file names each step but not the values
/// of the variables its name leaves out (`i` for `action(i, [q(C)], ...)`), so a step can lead
/// to several states, and the replay follows each of them.
const MAX_BRANCHES: usize = 256;

/// Replays `steps` on problem `problem` of `kb`.
///
/// A step that several schemas or bindings apply to with different effects leads to several
/// states: the plan is valid when some way of applying its steps reaches the goal, and the
/// verdict's plan is the first such way (states in a fixed order, so the choice is
/// deterministic).
pub fn validate(kb: &Kb, interner: &Interner, program: &Program, problem: usize, steps: &[PlanStep]) -> Verdict {
    let mut replayer = Replayer { kb, interner, problem, machine: Machine::new(program, 1_000_000) };
    let mut diagnostics = Diagnostics::new();
    // Each branch: a state and the steps that led to it.
    let mut branches: Vec<(State, Vec<Step>)> = vec![(replayer.initial_state(), Vec::new())];
    let no_vars = hir::VarTable::default();
    for (i, step) in steps.iter().enumerate() {
        let shown = hir::term_to_string(interner, &step.name, &no_vars);
        let mut next_branches: Vec<(State, Vec<Step>)> = Vec::new();
        let mut first_miss = None;
        for (state, taken) in &branches {
            match replayer.successors(state, &step.name, &step.with) {
                Ok(next) => {
                    for mut next in next {
                        let mut taken = taken.clone();
                        if let Some((action, bindings)) = next.via.take() {
                            taken.push(Step { action, name: step.name.clone(), bindings });
                        }
                        if !next_branches.iter().any(|(s, _)| s.identity() == next.identity()) {
                            next_branches.push((next, taken));
                        }
                    }
                }
                Err(miss) => {
                    if first_miss.is_none() {
                        first_miss = Some((miss, state.clone()));
                    }
                }
            }
        }
        if next_branches.len() > MAX_BRANCHES {
            diagnostics.push(
                Diagnostic::error(codes::INVALID_PLAN, format!("step {} `{shown}` is too ambiguous to replay", i + 1))
                    .primary(step.span, format!("{} different states can follow", next_branches.len()))
                    .with_note(format!(
                        "the plan file does not say which values this step's variables take, and more than \
                         {MAX_BRANCHES} states are possible after it"
                    ))
                    .with_help("give the schemas distinct names, or name the variables that matter in the action"),
            );
            return Verdict { diagnostics, applied: i, plan: Plan { problem, steps: Vec::new() } };
        }
        if next_branches.is_empty() {
            let (miss, state) = first_miss.expect("every branch failed");
            let mut diagnostic = Diagnostic::error(
                codes::INVALID_PLAN,
                format!("step {} `{shown}` does not apply", i + 1),
            )
            .primary(
                step.span,
                if i == 0 { "not applicable in the initial state" } else { "not applicable after the steps before it" },
            );
            match miss {
                Some(miss) => {
                    let action = interner.resolve(kb.actions[miss.action].name.name());
                    diagnostic =
                        diagnostic.secondary(miss.span, miss.label).with_note(format!("`{action}`: {}", miss.reason));
                }
                None => diagnostic = diagnostic.with_note("no action schema has this name and arity"),
            }
            let facts: Vec<&String> = state.facts.iter().collect();
            let listed: Vec<String> = facts.iter().take(12).map(|f| f.to_string()).collect();
            let more = if facts.len() > 12 { format!(", and {} more", facts.len() - 12) } else { String::new() };
            diagnostics.push(diagnostic.with_note(format!("the state is [{}{more}]", listed.join(", "))));
            let taken = branches.swap_remove(0).1;
            return Verdict { diagnostics, applied: i, plan: Plan { problem, steps: taken } };
        }
        next_branches.sort_by(|a, b| a.0.identity().cmp(&b.0.identity()));
        branches = next_branches;
    }
    if let Some(done) = branches.iter().position(|(state, _)| state.running.is_empty() && replayer.goal_reached(state))
    {
        let taken = branches.swap_remove(done).1;
        return Verdict { diagnostics, applied: steps.len(), plan: Plan { problem, steps: taken } };
    }
    // No branch reaches the goal: explain with the first.
    let (state, taken) = branches.swap_remove(0);
    let plan = Plan { problem, steps: taken };
    let problem = &kb.problems[problem];
    let problem_name = interner.resolve(problem.name);
    if !state.running.is_empty() {
        diagnostics.push(
            Diagnostic::error(codes::INVALID_PLAN, format!("the plan leaves {} running", state.running.join(", ")))
                .with_note("every durative action started must end")
                .with_help("add the missing `_end` steps"),
        );
    } else {
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
    Verdict { diagnostics, applied: steps.len(), plan }
}

/// One event of a timed plan: a snap action at a time.
struct Event {
    time: i64,
    /// The time in millionths, as written: the order of happenings.
    fine: i64,
    /// 0 for an end, 1 for an instantaneous action, 2 for a start: at equal times ends happen
    /// first, as in PDDL 2.1.
    order: u8,
    name: Term,
    /// The timed step it comes from.
    step: usize,
}

/// The snap-action name `X_start(args)` or `X_end(args)` of a durative action `X(args)`, if
/// the KB has that durative action.
fn snap_name(kb: &Kb, level: Level, action: &Term, snap: Snap) -> Option<Term> {
    let (name, arity) = action.callable()?;
    let schema =
        kb.actions.iter().find(|a| a.level == level && a.snap == snap && a.base == name && a.name.arity() == arity)?;
    let functor = schema.name.name();
    Some(match action {
        Term::Compound(_, args) => Term::Compound(functor, args.clone()),
        _ => Term::Atom(functor),
    })
}

/// The bounds `duration(X(args), Min, Max)` gives, in STN time, or the default.
fn duration_bounds(machine: &mut Machine<'_>, action: &Term) -> Result<(i64, i64), String> {
    use crate::ir::stn::{DEFAULT_DURATION, UNITS};
    machine.reset();
    let mut vars = [None, None];
    let query = Term::Compound(
        sym::DURATION,
        hir::Args::from([action.clone(), Term::Var(hir::VarId(0)), Term::Var(hir::VarId(1))]),
    );
    let goal = machine.put_term(&query, &mut vars);
    let (Some(min), Some(max)) = (vars[0], vars[1]) else { return Err("the query has no variables".into()) };
    let mut found = None;
    let to_time = |m: &Machine<'_>, cell: Cell| match m.deref(cell) {
        Cell::Atom(sym::INF) => Some(i64::MAX),
        Cell::Int(i) => i.checked_mul(UNITS),
        Cell::Float(f) if f.is_finite() && f.abs() < 1e12 => Some((f * UNITS as f64).round() as i64),
        _ => None,
    };
    machine
        .solve(goal, |m| {
            found = Some((to_time(m, min), to_time(m, max)));
            Next::Stop
        })
        .map_err(|e| format!("{e:?}"))?;
    match found {
        None => Ok((DEFAULT_DURATION * UNITS, i64::MAX)),
        Some((Some(min), Some(max))) => Ok((min, max)),
        Some(_) => Err("its bounds are not numbers".into()),
    }
}

/// Replays a timed plan event by event, as PDDL 2.1 defines its execution: each durative
/// action starts at its time and ends its duration later, at equal times ends happen before
/// instantaneous actions and those before starts, and the events of one instant must not
/// depend on each other (each group is replayed in both orders and must give the same state).
/// Every duration must lie within the action's `duration/3` bounds (or the default).
pub fn validate_timed(kb: &Kb, interner: &Interner, program: &Program, problem: usize, steps: &[PlanStep]) -> Verdict {
    use crate::ir::stn::format_time;
    let mut replayer = Replayer { kb, interner, problem, machine: Machine::new(program, 1_000_000) };
    let mut diagnostics = Diagnostics::new();
    let plan = Plan { problem, steps: Vec::new() };
    let no_vars = hir::VarTable::default();
    let mut events: Vec<Event> = Vec::new();
    for (i, step) in steps.iter().enumerate() {
        let shown = hir::term_to_string(interner, &step.name, &no_vars);
        let Some((time, duration)) = step.timing else {
            diagnostics
                .push(Diagnostic::error(codes::BAD_PLAN_FILE, "expected a timed step").primary(step.span, "no time"));
            return Verdict { diagnostics, applied: 0, plan };
        };
        let level = kb.problems[problem].level;
        let start = snap_name(kb, level, &step.name, Snap::Start);
        let end = snap_name(kb, level, &step.name, Snap::End);
        match (start, end, duration) {
            (Some(start), Some(end), Some(duration)) => {
                match duration_bounds(&mut replayer.machine, &step.name) {
                    Ok((min, max)) if duration < min || duration > max => {
                        diagnostics.push(
                            Diagnostic::error(
                                codes::INVALID_SCHEDULE,
                                format!("`{shown}` lasts {}, outside its bounds", format_time(duration)),
                            )
                            .primary(
                                step.span,
                                format!(
                                    "between {} and {} time units",
                                    format_time(min),
                                    if max == i64::MAX { "inf".to_string() } else { format_time(max) }
                                ),
                            )
                            .with_note("the bounds come from `duration/3` (or the default of 1 time unit)"),
                        );
                        return Verdict { diagnostics, applied: 0, plan };
                    }
                    Ok(_) => {}
                    Err(why) => {
                        diagnostics.push(
                            Diagnostic::error(
                                codes::BAD_DURATION_VALUE,
                                format!("cannot read the duration of `{shown}`: {why}"),
                            )
                            .primary(step.span, "this action"),
                        );
                        return Verdict { diagnostics, applied: 0, plan };
                    }
                }
                let (fine, fine_end) = match step.fine_timing {
                    Some((t, Some(d))) => (t, t + d),
                    _ => (time * FINE_PER_UNIT, (time + duration) * FINE_PER_UNIT),
                };
                events.push(Event { time, fine, order: 2, name: start, step: i });
                events.push(Event { time: time + duration, fine: fine_end, order: 0, name: end, step: i });
            }
            (Some(_), Some(_), None) => {
                diagnostics.push(
                    Diagnostic::error(codes::INVALID_SCHEDULE, format!("`{shown}` is durative but has no duration"))
                        .primary(step.span, "add `[DURATION]` after the action"),
                );
                return Verdict { diagnostics, applied: 0, plan };
            }
            _ => {
                let fine = step.fine_timing.map_or(time * FINE_PER_UNIT, |(t, _)| t);
                events.push(Event { time, fine, order: 1, name: step.name.clone(), step: i })
            }
        }
    }
    events.sort_by_key(|e| (e.fine, e.order, e.step));
    let mut state = replayer.initial_state();
    let mut at = 0;
    while at < events.len() {
        let group_end = events[at..]
            .iter()
            .position(|e| (e.fine, e.order) != (events[at].fine, events[at].order))
            .map_or(events.len(), |n| at + n);
        let group = &events[at..group_end];
        let mut results = Vec::new();
        for order in [false, true] {
            let mut current = state.clone();
            let sequence: Vec<&Event> = if order { group.iter().rev().collect() } else { group.iter().collect() };
            for event in sequence {
                match replayer.successors(&current, &event.name, &[]) {
                    Ok(mut next) if next.len() == 1 => current = next.remove(0),
                    outcome => {
                        let shown = hir::term_to_string(interner, &event.name, &no_vars);
                        let mut diagnostic = Diagnostic::error(
                            codes::INVALID_SCHEDULE,
                            format!("`{shown}` cannot happen at {}", format_time(event.time)),
                        )
                        .primary(steps[event.step].span, "scheduled here");
                        diagnostic = match outcome {
                            Err(Some(miss)) => diagnostic.secondary(miss.span, miss.label).with_note(miss.reason),
                            Ok(next) => diagnostic.with_note(format!("{} different states can follow", next.len())),
                            Err(None) => diagnostic.with_note("no action schema has this name and arity"),
                        };
                        if order && group.len() > 1 {
                            diagnostic = diagnostic.with_note(
                                "it depends on another action at the same time; separate them by a thousandth",
                            );
                        }
                        diagnostics.push(diagnostic);
                        return Verdict { diagnostics, applied: at, plan };
                    }
                }
            }
            results.push(current);
        }
        if results[0].identity() != results[1].identity() {
            diagnostics.push(
                Diagnostic::error(
                    codes::INVALID_SCHEDULE,
                    format!("actions at {} interfere with each other", format_time(group[0].time)),
                )
                .primary(steps[group[0].step].span, "one of them")
                .with_note("their effects depend on the order they happen in"),
            );
            return Verdict { diagnostics, applied: at, plan };
        }
        state = results.swap_remove(0);
        at = group_end;
    }
    let problem_name = interner.resolve(kb.problems[problem].name);
    if !state.running.is_empty() {
        diagnostics.push(
            Diagnostic::error(codes::INVALID_SCHEDULE, format!("the plan leaves {} running", state.running.join(", ")))
                .with_note("every durative action started must end"),
        );
    } else if !replayer.goal_reached(&state) {
        diagnostics.push(Diagnostic::error(
            codes::INVALID_SCHEDULE,
            format!("the timed plan does not reach the goal of `{problem_name}`"),
        ));
    }
    Verdict { diagnostics, applied: events.len(), plan }
}

#[cfg(test)]
mod tests {
    #[test]
    fn times_have_any_number_of_decimals_and_are_rounded_to_thousandths() {
        let times = ["12", "1.5", "0.001", "0.0015", "1.2344", "1.2345", ".5", "3."].map(super::parse_time);
        assert_eq!(
            times,
            [Some(12_000), Some(1_500), Some(1), Some(2), Some(1_234), Some(1_235), Some(500), Some(3_000)]
        );
        assert_eq!(["", ".", "-1", "1e3", "1.2.3"].map(super::parse_time), [None; 5]);
    }

    #[test]
    fn an_lpg_line_keeps_its_fine_times_and_loses_its_stray_parenthesis() {
        let (times, text, at) = super::timed_line("1.0008:   (GRIP_1 A3 B1 N2 N1) [1.0000])").expect("a timed line");
        assert_eq!(text, "grip_1(a3, b1, n2, n1)");
        assert_eq!(at, 10, "the action's offset");
        assert_eq!((times.time, times.duration), (1_001, Some(1_000)));
        assert_eq!(times.fine, (1_000_800, Some(1_000_000)), "the order of happenings keeps 0.0008");
        // A parenthesis inside a quoted atom does not end the action; anything else after the
        // duration is not a timed line.
        let (_, text, _) = super::timed_line("0: (go 'a)b') [1]").expect("a timed line");
        assert_eq!(text, "go('a)b')");
        assert!(super::timed_line("0: (go a) [1] x").is_none());
    }
}
