//! Pass `pop`: a total-order plan becomes a partial-order plan ([`Pop`]).
//!
//! The plan is replayed on ground facts (the KB semantics: effects in list order) while a
//! history of which step added and deleted each fact is kept; the conditions of every step
//! are then matched against that history:
//!
//! - a Valid literal's candidates are the earlier steps that add its fact (and the initial
//!   state if the fact is there); the last of them before the step is its achiever;
//! - an Invalid literal's candidates are the earlier steps that delete a fact it forbids; the
//!   step must follow the last deletion of *every* such fact (the paper keeps only the last
//!   candidate, which is not enough when several facts were removed), so each of those
//!   deletions is ordered before it;
//! - threats: a step that deletes a fact a link protects is ordered before the link's
//!   producer or after its consumer, as the total order has it; a step that adds a fact an
//!   Invalid literal forbids is ordered after that literal's step, or before the deletion that
//!   removes the fact again;
//! - each end follows its start; the goal literals are matched against the final state and
//!   protected the same way.
//!
//! The plan must be valid (the search's plans are; plan files go through `validate` first).

use std::hash::{Hash, Hasher};

use hashbrown::HashTable;
use rustc_hash::{FxHashMap, FxHasher};

use crate::intern::Interner;
use crate::ir::hir::{self, EffectKind, Kb, Snap, Term, VarId, VarTable};
use crate::ir::plan::Plan;
use crate::ir::pop::{Achiever, Condition, ConditionKind, Ordering, Pop, PopStep, Reason};
use crate::ir::unify::unifiable;

/// A term with the step's bindings put in; variables without a value stay.
pub(crate) fn instantiate(term: &Term, bindings: &[Option<Term>]) -> Term {
    match term {
        Term::Var(v) => match bindings.get(v.0 as usize).cloned().flatten() {
            Some(value) => value,
            None => term.clone(),
        },
        Term::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| instantiate(a, bindings)).collect()),
        other => other.clone(),
    }
}

/// Hashes `term` structurally, floats by their bits (so a term is found again exactly when
/// it is written the same way, as the replay needs).
fn hash_term(term: &Term, hasher: &mut impl Hasher) {
    match term {
        Term::Var(v) => (0u8, v.0).hash(hasher),
        Term::Atom(s) => (1u8, s.0).hash(hasher),
        Term::Int(i) => (2u8, *i).hash(hasher),
        Term::Float(f) => (3u8, f.to_bits()).hash(hasher),
        Term::Str(s) => (4u8, s.0).hash(hasher),
        Term::Compound(f, args) => {
            (5u8, f.0, args.len()).hash(hasher);
            for arg in args.iter() {
                hash_term(arg, hasher);
            }
        }
    }
}

/// True if `a` and `b` are written the same way: [`Term`]'s equality, but floats by their
/// bits (`0.0` and `-0.0` differ, a NaN equals itself), as [`hash_term`] hashes them.
fn same(a: &Term, b: &Term) -> bool {
    match (a, b) {
        (Term::Float(x), Term::Float(y)) => x.to_bits() == y.to_bits(),
        (Term::Compound(f, xs), Term::Compound(g, ys)) => {
            f == g && xs.len() == ys.len() && xs.iter().zip(ys.iter()).all(|(x, y)| same(x, y))
        }
        _ => a == b,
    }
}

/// Terms numbered in the order first seen, each stored once: the facts of the replay, the
/// running instances. (Not [`crate::ir::task::Consts`]: it interns ground terms only, and the
/// facts of an arm-level plan, which keep Prolog's unification, may have variables.)
#[derive(Default)]
struct Terms {
    terms: Vec<Term>,
    /// Indices into `terms`, by hash.
    table: HashTable<u32>,
}

impl Terms {
    fn hash(term: &Term) -> u64 {
        let mut hasher = FxHasher::default();
        hash_term(term, &mut hasher);
        hasher.finish()
    }

    /// The number of `term`, if it was seen.
    fn find(&self, term: &Term) -> Option<usize> {
        let terms = &self.terms;
        self.table.find(Terms::hash(term), |&i| same(&terms[i as usize], term)).map(|&i| i as usize)
    }

    /// The number of `term`, given one the first time it is seen; and whether it is new.
    fn add(&mut self, term: &Term) -> (usize, bool) {
        let hash = Terms::hash(term);
        let terms = &self.terms;
        if let Some(&i) = self.table.find(hash, |&i| same(&terms[i as usize], term)) {
            return (i as usize, false);
        }
        let i = self.terms.len();
        self.terms.push(term.clone());
        let terms = &self.terms;
        self.table.insert_unique(hash, i as u32, |&j| Terms::hash(&terms[j as usize]));
        (i, true)
    }
}

/// What happened to one ground fact along the plan.
#[derive(Default)]
struct History {
    initially: bool,
    /// True while the replay has it.
    holds: bool,
    /// Steps that add it, in plan order.
    adds: Vec<usize>,
    /// Steps that delete it (while it holds), in plan order.
    dels: Vec<usize>,
}

struct Builder {
    /// Every fact the replay met, numbered as in `histories`.
    facts: Terms,
    histories: Vec<History>,
    /// Fact numbers by predicate name and arity, in first-seen order (for Invalid patterns).
    by_pred: FxHashMap<(crate::intern::Symbol, usize), Vec<usize>>,
    orderings: Vec<Ordering>,
}

/// Orders `before` before `after` when it comes first in the plan.
fn order(orderings: &mut Vec<Ordering>, before: usize, after: usize, reason: Reason) {
    if before < after {
        orderings.push(Ordering { before, after, reason });
    }
}

impl Builder {
    /// The history of the fact `term`, started the first time it is met.
    fn history(&mut self, term: &Term) -> &mut History {
        let (i, new) = self.facts.add(term);
        if new {
            if let Some((name, arity)) = term.callable() {
                self.by_pred.entry((name, arity)).or_default().push(i);
            }
            self.histories.push(History::default());
        }
        &mut self.histories[i]
    }

    /// The last step before `at` (exclusive) that adds the fact, else `Init` if it holds
    /// initially; and every candidate.
    fn establishers(&self, fact: Option<usize>, at: usize) -> (Vec<Achiever>, Achiever) {
        let Some(history) = fact.map(|i| &self.histories[i]) else { return (Vec::new(), Achiever::Init) };
        let mut candidates: Vec<Achiever> = Vec::new();
        if history.initially {
            candidates.push(Achiever::Init);
        }
        candidates.extend(history.adds.iter().filter(|&&j| j < at).map(|&j| Achiever::Step(j)));
        let last = candidates.last().copied().unwrap_or(Achiever::Init);
        (candidates, last)
    }

    /// Orders the deleters of `fact` around a link from `last` to consumer `at` (`n` for the
    /// goal), condition `condition`.
    fn protect(&mut self, fact: Option<usize>, last: Achiever, at: usize, consumer: usize, condition: usize) {
        let Some(history) = fact.map(|i| &self.histories[i]) else { return };
        let reason = Reason::Threat { consumer, condition };
        for &d in &history.dels {
            if d == at {
                continue; // a step may consume the fact it needs
            }
            match last {
                Achiever::Step(j) if d < j => order(&mut self.orderings, d, j, reason),
                _ if d > at => order(&mut self.orderings, at, d, reason),
                _ => {}
            }
        }
    }
}

/// A term's written form in words, to order terms the same way on every run (floats by their
/// bits): a tag word, then the symbol, the value or the arguments.
fn encode(term: &Term, out: &mut Vec<u64>) {
    match term {
        Term::Var(v) => out.extend([0, u64::from(v.0)]),
        Term::Atom(s) => out.extend([1, u64::from(s.0)]),
        Term::Int(i) => out.extend([2, *i as u64]),
        Term::Float(f) => out.extend([3, f.to_bits()]),
        Term::Str(s) => out.extend([4, u64::from(s.0)]),
        Term::Compound(f, args) => {
            out.extend([5, u64::from(f.0), args.len() as u64]);
            for arg in args.iter() {
                encode(arg, out);
            }
        }
    }
}

/// Builds the partial-order plan of `plan`, which must be valid for its problem.
pub fn build(kb: &Kb, interner: &Interner, plan: &Plan) -> Pop {
    let problem = &kb.problems[plan.problem];
    let mut builder = Builder {
        facts: Terms::default(),
        histories: Vec::new(),
        by_pred: FxHashMap::default(),
        orderings: Vec::new(),
    };
    for literal in &problem.init {
        let history = builder.history(&literal.term);
        history.initially = true;
        history.holds = true;
    }
    // Replay, recording every change.
    for (i, step) in plan.steps.iter().enumerate() {
        for effect in &kb.actions[step.action].effects {
            let fact = instantiate(&effect.literal.term, &step.bindings);
            match effect.kind {
                EffectKind::Add => {
                    let history = builder.history(&fact);
                    history.adds.push(i);
                    history.holds = true;
                }
                EffectKind::Del if !fact.is_ground() => {
                    // A variable nothing binds: every fact that unifies goes (docs/dsl.md), in
                    // the order of their written forms.
                    let mut gone: Vec<(Vec<u64>, usize)> = (0..builder.histories.len())
                        .filter(|&f| builder.histories[f].holds && unifiable(&fact, &builder.facts.terms[f]))
                        .map(|f| {
                            let mut key = Vec::new();
                            encode(&builder.facts.terms[f], &mut key);
                            (key, f)
                        })
                        .collect();
                    gone.sort();
                    for (_, f) in gone {
                        let history = &mut builder.histories[f];
                        history.holds = false;
                        history.dels.push(i);
                    }
                }
                EffectKind::Del => {
                    if let Some(f) = builder.facts.find(&fact)
                        && builder.histories[f].holds
                    {
                        let history = &mut builder.histories[f];
                        history.holds = false;
                        history.dels.push(i);
                    }
                }
            }
        }
    }
    // Starts, by the running instance they begin: each end takes the latest open one.
    let mut instances = Terms::default();
    let mut open: Vec<Vec<usize>> = Vec::new();
    let mut steps: Vec<PopStep> = Vec::with_capacity(plan.steps.len());
    for (i, step) in plan.steps.iter().enumerate() {
        let action = &kb.actions[step.action];
        let start = match action.snap {
            Snap::Start => {
                let (instance, new) = instances.add(&action.instance(&step.name));
                if new {
                    open.push(Vec::new());
                }
                open[instance].push(i);
                None
            }
            Snap::End => instances.find(&action.instance(&step.name)).and_then(|instance| open[instance].pop()),
            Snap::Instant => None,
        };
        if let Some(s) = start {
            order(&mut builder.orderings, s, i, Reason::StartEnd);
        }
        let mut conditions = Vec::new();
        for literal in &action.valid {
            let fact = instantiate(&literal.term, &step.bindings);
            let found = builder.facts.find(&fact);
            let (candidates, last) = builder.establishers(found, i);
            let index = conditions.len();
            if let Achiever::Step(j) = last {
                order(&mut builder.orderings, j, i, Reason::Achiever { condition: index });
            }
            builder.protect(found, last, i, i, index);
            conditions.push(Condition {
                kind: ConditionKind::Valid,
                literal: fact,
                vars: VarTable::default(),
                span: literal.span,
                candidates,
                last,
            });
        }
        for literal in &action.invalid {
            let pattern = instantiate(&literal.term, &step.bindings);
            let index = conditions.len();
            let facts = pattern.callable().and_then(|(name, arity)| builder.by_pred.get(&(name, arity)));
            let mut candidates = Vec::new();
            for &f in facts.into_iter().flatten() {
                if !unifiable(&pattern, &builder.facts.terms[f]) {
                    continue;
                }
                let history = &builder.histories[f];
                let (adds, dels) = (&history.adds, &history.dels);
                let reason = Reason::Threat { consumer: i, condition: index };
                // Absent at `i`: its last deletion before `i`, if it ever held, comes first.
                let ever_before = history.initially || adds.iter().any(|&a| a < i);
                if let Some(&d) = dels.iter().rfind(|&&d| d < i)
                    && ever_before
                {
                    candidates.push(Achiever::Step(d));
                    order(&mut builder.orderings, d, i, Reason::Achiever { condition: index });
                }
                for &a in adds {
                    if a > i {
                        order(&mut builder.orderings, i, a, reason);
                    } else if let Some(&d) = dels.iter().find(|&&d| d > a && d < i) {
                        order(&mut builder.orderings, a, d, reason);
                    }
                }
            }
            candidates.sort();
            candidates.dedup();
            let last = candidates.last().copied().unwrap_or(Achiever::Init);
            conditions.push(Condition {
                kind: ConditionKind::Invalid,
                literal: pattern,
                vars: action.vars.clone(),
                span: literal.span,
                candidates,
                last,
            });
        }
        steps.push(PopStep { action: step.action, name: step.name.clone(), snap: action.snap, start, conditions });
    }
    // The goal, matched against the final state. (A goal with variables matches the final
    // facts in the order of their text, so that it matches the same facts whatever the
    // replay's order; a ground goal is its own match.)
    let n = plan.steps.len();
    let mut goal = Vec::new();
    let matched = match problem.goal.iter().all(|literal| literal.term.is_ground()) {
        true => None,
        false => {
            let mut finals: Vec<(String, &Term)> = (0..builder.histories.len())
                .filter(|&f| builder.histories[f].holds)
                .map(|f| &builder.facts.terms[f])
                .map(|t| (hir::term_to_string(interner, t, &VarTable::default()), t))
                .collect();
            finals.sort_by(|a, b| a.0.cmp(&b.0));
            let finals: Vec<Term> = finals.into_iter().map(|(_, t)| t.clone()).collect();
            match_goal(&problem.goal, &finals, &mut vec![None; problem.vars.len()])
        }
    };
    for (g, literal) in problem.goal.iter().enumerate() {
        let fact = matched.as_ref().map_or_else(|| literal.term.clone(), |m| instantiate(&literal.term, m));
        let found = builder.facts.find(&fact);
        let (candidates, last) = builder.establishers(found, n);
        builder.protect(found, last, n, usize::MAX, g);
        goal.push(Condition {
            kind: ConditionKind::Goal,
            literal: fact,
            vars: problem.vars.clone(),
            span: literal.span,
            candidates,
            last,
        });
    }
    let mut pop = Pop { problem: plan.problem, steps, goal, orderings: builder.orderings, other_reasons: Vec::new() };
    sort_orderings(&mut pop);
    pop
}

/// One ordering per pair in `pop.orderings`, with its strongest reason: an achiever link, then
/// a start and its end, then a threat, then a shared unit; the pair's other reasons, without
/// repeats, in `pop.other_reasons`.
fn sort_orderings(pop: &mut Pop) {
    let rank = |reason: &Reason| match reason {
        Reason::Achiever { .. } => 0,
        Reason::StartEnd => 1,
        Reason::Threat { .. } => 2,
        Reason::Refinement => 3,
        Reason::SameUnit => 4,
    };
    let mut all = std::mem::take(&mut pop.orderings);
    all.append(&mut pop.other_reasons);
    // Stable: of reasons of one rank, the first made is kept.
    all.sort_by_key(|o| (o.after, o.before, rank(&o.reason)));
    for ordering in all {
        match pop.orderings.last() {
            Some(last) if (last.after, last.before) == (ordering.after, ordering.before) => {
                if *last != ordering {
                    pop.other_reasons.push(ordering)
                }
            }
            _ => pop.orderings.push(ordering),
        }
    }
    pop.other_reasons.sort_by_key(|o| (o.after, o.before, o.reason));
    pop.other_reasons.dedup();
}

/// Values for the goal's variables under which every goal literal is a fact of `facts`.
fn match_goal(goal: &[hir::Literal], facts: &[Term], bindings: &mut [Option<Term>]) -> Option<Vec<Option<Term>>> {
    let Some((first, rest)) = goal.split_first() else { return Some(bindings.to_vec()) };
    for fact in facts {
        let mut attempt = bindings.to_vec();
        if bind(&first.term, fact, &mut attempt)
            && let Some(found) = match_goal(rest, facts, &mut attempt)
        {
            return Some(found);
        }
    }
    None
}

/// Matches a pattern against a ground term, extending `bindings`.
fn bind(pattern: &Term, ground: &Term, bindings: &mut [Option<Term>]) -> bool {
    match pattern {
        Term::Var(VarId(v)) => match bindings[*v as usize].clone() {
            Some(bound) => &bound == ground,
            None => {
                bindings[*v as usize] = Some(ground.clone());
                true
            }
        },
        Term::Compound(f, args) => match ground {
            Term::Compound(g, values) if f == g && args.len() == values.len() => {
                args.iter().zip(values.iter()).all(|(a, v)| bind(a, v, bindings))
            }
            _ => false,
        },
        other => other == ground,
    }
}

/// Orders the steps that name the same resource unit (an atom among `units`, such as an arm
/// `a1`, anywhere in the step's name) in plan order, one after the other. An arm-level plan
/// needs this: a mapping's steps for one arm are not linked by its fluents alone (`lift(a1)`
/// needs nothing), yet the arm does one at a time.
pub fn order_units(pop: &mut Pop, units: &[Term]) {
    if units.is_empty() {
        return;
    }
    let mut last: Vec<Option<usize>> = vec![None; units.len()];
    for (i, step) in pop.steps.iter().enumerate() {
        for (u, unit) in units.iter().enumerate() {
            if !mentions(&step.name, unit) {
                continue;
            }
            if let Some(before) = last[u] {
                pop.orderings.push(Ordering { before, after: i, reason: Reason::SameUnit });
            }
            last[u] = Some(i);
        }
    }
    sort_orderings(pop);
}

fn mentions(term: &Term, unit: &Term) -> bool {
    term == unit || term.args().iter().any(|a| mentions(a, unit))
}

/// Orders an arm-level plan's steps as their refinement does (`origin` gives each step's
/// high-level step; `high` is the high-level plan's partial order): each mapping's steps in
/// sequence, and for each high-level ordering `b < a`, the last arm-level step of `b` (or of
/// the nearest high-level steps before `b` that have some, when `b` has none) before the
/// first of `a`. So an arm-level schedule never runs a step before what the high level said
/// must come first (a block placed before another goes on it), even when no arm-level fluent
/// links them.
pub fn order_by_refinement(pop: &mut Pop, origin: &[usize], high: &Pop) {
    let n = high.steps.len();
    let mut first: Vec<Option<usize>> = vec![None; n];
    let mut last: Vec<Option<usize>> = vec![None; n];
    for (i, &h) in origin.iter().enumerate() {
        if let Some(previous) = last[h] {
            pop.orderings.push(Ordering { before: previous, after: i, reason: Reason::Refinement });
        }
        first[h].get_or_insert(i);
        last[h] = Some(i);
    }
    let mut before: Vec<Vec<usize>> = vec![Vec::new(); n];
    for ordering in &high.orderings {
        if ordering.after < n && ordering.before < n {
            before[ordering.after].push(ordering.before);
        }
    }
    for a in 0..n {
        let Some(start) = first[a] else { continue };
        // The nearest predecessors with arm-level steps, through those without.
        let mut pending: Vec<usize> = before[a].clone();
        let mut seen = vec![false; n];
        while let Some(b) = pending.pop() {
            if std::mem::replace(&mut seen[b], true) {
                continue;
            }
            match last[b] {
                Some(end) if end < start => {
                    pop.orderings.push(Ordering { before: end, after: start, reason: Reason::Refinement })
                }
                Some(_) => {}
                None => pending.extend(before[b].iter().copied()),
            }
        }
    }
    sort_orderings(pop);
}
