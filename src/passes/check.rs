//! Pass `check`: whole-KB checks on the HIR, reported as diagnostics.
//!
//! Lowering checked the shape of each item on its own; these checks need the whole KB:
//!
//! - durative actions: every `X_start` has an `X_end` of the same arity, and the reverse;
//! - duplicate action schemas (equal up to variable renaming);
//! - mappings refer to known high-level and arm-level actions;
//! - names: every predicate used in a condition, effect, goal or OnKB goal is defined by the
//!   KB, produced by an effect, or present in an init state (with did-you-mean suggestions,
//!   arity mismatches, and the common mix-up of state fluents and static KB facts);
//! - goal literals that no effect can add and no init state holds;
//! - effect variables that neither the action's name, its Valid list nor OnKB binds;
//! - `duration/3` declarations for actions that exist, with numeric bounds;
//! - clauses of one predicate spread over a file (as SWI-Prolog warns).
//!
//! Every check reports and continues; none depends on another having passed.

use std::collections::{BTreeMap, BTreeSet};

use crate::builtins;
use crate::diag::plural;
use crate::diag::{Diagnostic, Diagnostics, best_match, codes};
use crate::intern::{Interner, Symbol, sym};
use crate::ir::hir::{self, Action, DeclarationKind, EffectKind, Goal, Kb, Level, Literal, Snap, Term, VarId};
use crate::ir::unify::unifiable;
use crate::passes::lower::join_and;
use crate::source::Span;

/// Runs every whole-KB check.
pub fn check(kb: &Kb, interner: &Interner, diags: &mut Diagnostics) {
    let vocabulary = Vocabulary::new(kb);
    let mut checker = Checker { kb, interner, diags, vocabulary, never_run: None };
    checker.durative_pairs();
    checker.duplicate_actions();
    checker.mappings();
    checker.names();
    checker.unreachable_goals();
    checker.effect_variables();
    checker.durations();
    checker.discontiguous();
    checker.misspelt_declarations();
}

type Key = (Symbol, usize);

/// Which predicates exist, and where.
struct Vocabulary {
    /// Heads of static clauses, and predicates declared `dynamic` (defined, with no clauses).
    static_defined: BTreeSet<Key>,
    /// Predicates of goal literals (goal facts are part of the KB for OnKB goals).
    goal_facts: BTreeSet<Key>,
    /// Predicates some effect adds.
    produced: BTreeSet<Key>,
    /// Predicates in some init state.
    init: BTreeSet<Key>,
    /// Predicates some action mentions in a condition or effect.
    used_by_actions: BTreeSet<Key>,
    /// Predicates named in clauses that failed to parse or lower.
    recovered: BTreeSet<Key>,
    /// Predicates of the library the KB calls (std/library.pl).
    library: BTreeSet<Key>,
}

/// Drops each key equal to the one before it. The clauses of a predicate usually come
/// together, so this makes building a set from 100,000 clause heads cost 100,000 comparisons
/// rather than as many tree insertions.
fn distinct(keys: impl Iterator<Item = Key>) -> impl Iterator<Item = Key> {
    let mut previous = None;
    keys.filter(move |&k| previous.replace(k) != Some(k))
}

impl Vocabulary {
    fn new(kb: &Kb) -> Vocabulary {
        let key = |l: &Literal| (l.name(), l.arity());
        let mut v = Vocabulary {
            static_defined: distinct(kb.clauses.iter().map(|c| key(&c.head)))
                .chain(kb.declarations.iter().filter(|d| d.kind == DeclarationKind::Dynamic).map(|d| (d.name, d.arity)))
                .collect(),
            goal_facts: kb.problems.iter().flat_map(|p| p.goal.iter().map(key)).collect(),
            produced: BTreeSet::new(),
            init: kb
                .problems
                .iter()
                .flat_map(|p| p.initial_facts().map(key))
                .chain(kb.arm_level_state_preds.iter().copied())
                .collect(),
            used_by_actions: BTreeSet::new(),
            recovered: kb.recovered_names.iter().copied().collect(),
            library: kb.library.iter().map(|c| key(&c.head)).collect(),
        };
        for action in &kb.actions {
            for e in &action.effects {
                if e.kind == EffectKind::Add {
                    v.produced.insert(key(&e.literal));
                }
                v.used_by_actions.insert(key(&e.literal));
            }
            for l in action.valid.iter().chain(&action.invalid).chain(&action.invalid_at_end) {
                v.used_by_actions.insert(key(l));
            }
        }
        v
    }

    fn state_known(&self, key: Key) -> bool {
        self.produced.contains(&key) || self.init.contains(&key) || self.recovered.contains(&key)
    }

    fn kb_known(&self, key: Key) -> bool {
        builtins::is_builtin_predicate(key.0, key.1)
            || self.library.contains(&key)
            || self.static_defined.contains(&key)
            || self.goal_facts.contains(&key)
            || self.recovered.contains(&key)
    }

    fn state_names(&self) -> BTreeSet<Key> {
        self.produced.iter().chain(&self.init).copied().collect()
    }

    fn kb_names(&self) -> BTreeSet<Key> {
        self.static_defined.iter().chain(&self.goal_facts).copied().collect()
    }
}

/// The facts kbc reads as declarations, and whether it reads them as data only: all of them
/// but `duration/3`, whose clauses are also the KB's program (the engine proves it), and the
/// states, which are also facts a rule may read (`test :- init_state(I), ..., go(I, G).`).
const DECLARATIONS: &[(&str, usize, bool)] = &[
    ("action", 6, true),
    ("ll_action", 6, true),
    ("mapping", 2, true),
    ("resources", 1, true),
    ("duration", 3, false),
    ("init_state", 1, false),
    ("goal_state", 1, false),
    ("hl_init", 1, false),
    ("hl_goal", 1, false),
    ("ll_init", 1, false),
    ("ll_goal", 1, false),
];

/// True if kbc reads `name/arity` facts as data, never as clauses a goal can call.
fn data_declaration(name: &str, arity: usize) -> bool {
    DECLARATIONS.iter().any(|&(n, a, data)| data && n == name && a == arity)
}

/// Where a literal is used, for messages and severities.
#[derive(Clone, Copy, PartialEq, Eq)]
enum StateUse {
    Valid,
    Invalid,
    InvalidAtEnd,
    Delete,
    Goal,
}

impl StateUse {
    fn describe(self) -> &'static str {
        match self {
            StateUse::Valid => "a Valid condition",
            StateUse::Invalid => "an Invalid condition",
            StateUse::InvalidAtEnd => "an InvalidAtEnd condition",
            StateUse::Delete => "a `del` effect",
            StateUse::Goal => "a goal",
        }
    }

    /// A goal on a predicate no state holds makes the problem impossible; a condition or a
    /// deletion on one only never matches (a Valid condition: its action never applies),
    /// which Prolog runs without complaint, so it is a warning.
    fn is_error(self) -> bool {
        matches!(self, StateUse::Goal)
    }
}

struct Checker<'a> {
    kb: &'a Kb,
    interner: &'a Interner,
    diags: &'a mut Diagnostics,
    vocabulary: Vocabulary,
    /// While the body of a rule that planning never runs is checked: the rule's predicate
    /// (its calls of undefined predicates are then W0020, not E0210).
    never_run: Option<Key>,
}

impl Checker<'_> {
    fn name(&self, s: Symbol) -> &str {
        self.interner.resolve(s)
    }

    fn indicator(&self, key: Key) -> String {
        format!("{}/{}", self.name(key.0), key.1)
    }

    fn show(&self, literal: &Literal, vars: &hir::VarTable) -> String {
        hir::term_to_string(self.interner, &literal.term, vars)
    }

    /// Did-you-mean over `candidates`: same arity first, then any arity.
    fn suggest(&self, key: Key, candidates: &BTreeSet<Key>) -> Option<Key> {
        let name = self.name(key.0);
        let same_arity: Vec<&str> = candidates.iter().filter(|c| c.1 == key.1).map(|c| self.name(c.0)).collect();
        if let Some(found) = best_match(name, same_arity.iter().copied()) {
            return candidates.iter().find(|c| c.1 == key.1 && self.name(c.0) == found).copied();
        }
        let any: Vec<&str> = candidates.iter().map(|c| self.name(c.0)).collect();
        let found = best_match(name, any.iter().copied())?;
        candidates.iter().find(|c| self.name(c.0) == found).copied()
    }

    /// The problems' predicates: `test1 :- go(Init, Goal).` is `test1/0`, a `go/4` or `go/5`
    /// test `test3(Actions, Times)` is `test3/2`.
    fn problem_keys(&self) -> BTreeSet<Key> {
        let arity = |problem: &hir::Problem| match problem.form {
            hir::ProblemForm::Go(2) | hir::ProblemForm::InitGoalState => 0,
            hir::ProblemForm::Go(_) => 2,
        };
        self.kb.problems.iter().map(|p| (p.name, arity(p))).collect()
    }

    fn other_arities(&self, key: Key, candidates: &BTreeSet<Key>) -> Vec<usize> {
        candidates.iter().filter(|c| c.0 == key.0 && c.1 != key.1).map(|c| c.1).collect()
    }

    // ---- durative pairs -------------------------------------------------------------------

    fn durative_pairs(&mut self) {
        // For each durative action: its start schemas and its end schemas.
        type StartsAndEnds<'k> = (Vec<&'k Action>, Vec<&'k Action>);
        let mut by_base: BTreeMap<(Level, Symbol), StartsAndEnds> = BTreeMap::new();
        for action in &self.kb.actions {
            match action.snap {
                Snap::Start => by_base.entry((action.level, action.base)).or_default().0.push(action),
                Snap::End => by_base.entry((action.level, action.base)).or_default().1.push(action),
                Snap::Instant => {}
            }
        }
        for ((_, base), (starts, ends)) in by_base {
            let base_text = self.name(base).to_string();
            match (starts.first(), ends.first()) {
                (Some(start), None) => {
                    let (end_name, skeleton) = missing_end(self.interner, start, &base_text);
                    self.diags.push(
                        Diagnostic::error(
                            codes::UNPAIRED_DURATIVE,
                            format!("durative action `{base_text}` has a start but no end"),
                        )
                        .primary(start.name.name_span, format!("`{base_text}_start` declared here"))
                        .with_note(
                            "a durative action is a pair `X_start(Args)` and `X_end(Args)` with the same arguments",
                        )
                        .with_fix(
                            format!("declare `{end_name}`"),
                            Span::point(start.span.file, start.span.end),
                            skeleton,
                        )
                        .with_help(format!(
                            "declare `{end_name}`, or rename the action without `_start` to make it instantaneous"
                        )),
                    );
                }
                (None, Some(end)) => {
                    self.diags.push(
                        Diagnostic::error(
                            codes::UNPAIRED_DURATIVE,
                            format!("durative action `{base_text}` has an end but no start"),
                        )
                        .primary(end.name.name_span, format!("`{base_text}_end` declared here"))
                        .with_note(
                            "a durative action is a pair `X_start(Args)` and `X_end(Args)` with the same arguments",
                        )
                        .with_help(format!("declare `{base_text}_start` with the same arguments")),
                    );
                }
                (Some(start), Some(_)) => {
                    let arity = start.name.arity();
                    for end in ends.iter().filter(|e| e.name.arity() != arity) {
                        self.diags.push(
                            Diagnostic::error(
                                codes::DURATIVE_ARITY,
                                format!(
                                    "`{base_text}_end` takes {} but `{base_text}_start` takes {arity}",
                                    plural(end.name.arity(), "argument")
                                ),
                            )
                            .primary(end.name.span, plural(end.name.arity(), "argument"))
                            .secondary(start.name.span, plural(arity, "argument"))
                            .with_note("the end of a durative action must name the same arguments as its start")
                            .with_help("give both the same arguments"),
                        );
                    }
                    for start in starts.iter().skip(1).filter(|s| s.name.arity() != arity) {
                        self.diags.push(
                            Diagnostic::error(
                                codes::DURATIVE_ARITY,
                                format!(
                                    "this `{base_text}_start` takes {} but another takes {arity}",
                                    plural(start.name.arity(), "argument")
                                ),
                            )
                            .primary(start.name.span, plural(start.name.arity(), "argument"))
                            .with_help("give every schema of one durative action the same arguments"),
                        );
                    }
                }
                (None, None) => {}
            }
        }
    }

    fn duplicate_actions(&mut self) {
        let mut seen: BTreeMap<String, &Action> = BTreeMap::new();
        for action in &self.kb.actions {
            let text = hir::action_to_canonical_string(self.interner, action);
            match seen.get(&text) {
                Some(first) => {
                    let shown = self.show(&action.name, &action.vars);
                    self.diags.push(
                        Diagnostic::error(codes::DUPLICATE_ACTION, format!("duplicate action schema `{shown}`"))
                            .primary(action.name.span, "declared again here")
                            .secondary(first.name.span, "first declared here")
                            .with_note("the two schemas are the same up to variable names, so the planner would try each twice")
                            .with_fix("remove the duplicate", action.span, "")
                            .with_help("remove one of them"),
                    );
                }
                None => {
                    seen.insert(text, action);
                }
            }
        }
    }

    fn mappings(&mut self) {
        let high: BTreeSet<Key> = self
            .kb
            .actions
            .iter()
            .filter(|a| a.level == Level::High)
            .map(|a| (a.name.name(), a.name.arity()))
            .collect();
        let low: BTreeSet<Key> =
            self.kb.actions.iter().filter(|a| a.level == Level::Low).map(|a| (a.name.name(), a.name.arity())).collect();
        for mapping in &self.kb.mappings {
            let key = (mapping.high.name(), mapping.high.arity());
            if !high.contains(&key) {
                self.unknown_in_mapping(&mapping.high, &high, "high-level action", "action/6");
            }
            for step in &mapping.steps {
                let key = (step.name(), step.arity());
                if !low.contains(&key) {
                    self.unknown_in_mapping(step, &low, "arm-level action", "ll_action/6");
                }
            }
        }
    }

    fn unknown_in_mapping(&mut self, literal: &Literal, known: &BTreeSet<Key>, what: &str, declared_by: &str) {
        let key = (literal.name(), literal.arity());
        let indicator = self.indicator(key);
        let mut diagnostic =
            Diagnostic::error(codes::UNKNOWN_MAPPED_ACTION, format!("mapping refers to unknown {what} `{indicator}`"))
                .primary(literal.name_span, format!("no {declared_by} declares `{indicator}`"));
        if let Some(found) = self.suggest(key, known) {
            let found_text = self.name(found.0).to_string();
            diagnostic = diagnostic.with_help(format!("did you mean `{}`?", self.indicator(found)));
            if found.1 == key.1 {
                diagnostic = diagnostic.with_fix(format!("replace with `{found_text}`"), literal.name_span, found_text);
            }
        } else {
            diagnostic = diagnostic.with_help(format!("declare it with {declared_by}"));
        }
        self.diags.push(diagnostic);
    }

    /// Clauses whose predicate is one edit away from a declaration kbc reads (`mappings/2`
    /// for `mapping/2`) with the same arity, and that no OnKB goal or rule calls: a KB fact
    /// nothing reads, most likely meant as the declaration.
    fn misspelt_declarations(&mut self) {
        let mut called: BTreeSet<Key> = BTreeSet::new();
        let mut note_calls = |goal: &Goal| {
            goal.for_each_called(&mut |l, extra| {
                called.insert((l.name(), l.arity() + extra));
            })
        };
        for action in &self.kb.actions {
            action.on_kb.iter().for_each(&mut note_calls);
        }
        for clause in &self.kb.clauses {
            if let Some(body) = &clause.body {
                note_calls(body);
            }
        }
        for problem in &self.kb.problems {
            problem.prelude.iter().flat_map(|p| &p.goals).for_each(&mut note_calls);
        }
        let mut reported: BTreeSet<Key> = BTreeSet::new();
        for clause in &self.kb.clauses {
            let key = (clause.head.name(), clause.head.arity());
            if called.contains(&key) || reported.contains(&key) {
                continue;
            }
            let name = self.name(key.0).to_string();
            if DECLARATIONS.contains(&(name.as_str(), key.1, false)) {
                continue; // a declaration whose facts are also clauses (`duration/3`, the states)
            }
            if let Some(&(_, arity, _)) = DECLARATIONS.iter().find(|d| d.0 == name && d.1 != key.1) {
                // The declaration's name with another number of arguments (`duration(wait, 2)`).
                reported.insert(key);
                let example = match clause.head.term.args().first() {
                    Some(action) if name == "duration" => {
                        format!("duration({}, Min, Max)", hir::term_to_string(self.interner, action, &clause.vars))
                    }
                    _ => format!("{name}([...])"),
                };
                self.diags.push(
                    Diagnostic::warning(
                        codes::MISSPELT_DECLARATION,
                        format!(
                            "`{name}/{}` is not a kbc declaration: `{name}` takes {}",
                            key.1,
                            plural(arity, "argument")
                        ),
                    )
                    .primary(clause.head.span, "read as a plain KB fact, which nothing uses")
                    .with_note(format!("kbc reads `{name}/{arity}` facts; these are facts of another predicate"))
                    .with_help(format!("write it as `{example}`")),
                );
                continue;
            }
            let candidates: Vec<&str> = DECLARATIONS.iter().filter(|d| d.1 == key.1).map(|d| d.0).collect();
            let Some(found) = best_match(&name, candidates) else { continue };
            reported.insert(key);
            self.diags.push(
                Diagnostic::warning(
                    codes::MISSPELT_DECLARATION,
                    format!("`{name}/{}` is not a kbc declaration: did you mean `{found}/{}`?", key.1, key.1),
                )
                .primary(clause.head.name_span, "read as a plain KB fact, which nothing uses")
                .with_note(format!(
                    "kbc reads `{found}/{}` facts; `{name}` facts only serve OnKB goals, and none calls them",
                    key.1
                ))
                .with_fix(format!("replace with `{found}`"), clause.head.name_span, found.to_string())
                .with_help(format!("rename it `{found}`")),
            );
        }
    }

    // ---- names ----------------------------------------------------------------------------

    /// The rules (indices into `Kb::clauses`) that only run tests, as older KBs write them:
    /// `testCase(A, T) :- test3(A, T).`, `testTrace :- leash(-all), trace, testCase(_, _).`,
    /// `testCase(1, T) :- test1, T = ok.`, `main :- test1, halt.` Their bodies call nothing
    /// but problems, other such rules, SWI-Prolog's debugger, output predicates and `halt`,
    /// and built-ins that call no goal (`=/2`, `is/2`), none of which planning uses.
    fn test_wrappers(&self) -> BTreeSet<usize> {
        // Output a wrapper may print around a test, besides the debugger, and SWI-Prolog's
        // way to stop after it (`main :- test1, halt.`).
        const OUTPUT: &[(&str, usize)] = &[
            ("write", 1),
            ("writeln", 1),
            ("print", 1),
            ("nl", 0),
            ("format", 1),
            ("format", 2),
            ("time", 1),
            ("halt", 0),
            ("halt", 1),
        ];
        let problems = self.problem_keys();
        let mut wrappers: BTreeSet<usize> = BTreeSet::new();
        let mut names: BTreeSet<Key> = problems;
        loop {
            let mut changed = false;
            for (index, clause) in self.kb.clauses.iter().enumerate() {
                let Some(body) = &clause.body else { continue };
                if wrappers.contains(&index) {
                    continue;
                }
                let mut calls_a_test = false;
                let mut only_tests = true;
                body.for_each_call(&mut |l| {
                    let key = (l.name(), l.arity());
                    if names.contains(&key) {
                        calls_a_test = true;
                    } else if !builtins::is_debugger(self.name(key.0), key.1)
                        && !OUTPUT.contains(&(self.name(key.0), key.1))
                        && !builtins::lookup(self.interner, key.0, key.1).is_some_and(|b| b.calls.is_empty())
                    {
                        only_tests = false;
                    }
                });
                if calls_a_test && only_tests {
                    wrappers.insert(index);
                    names.insert((clause.head.name(), clause.head.arity()));
                    changed = true;
                }
            }
            if !changed {
                return wrappers;
            }
        }
    }

    /// The predicates of a planner the KB brings along, as the paper's authors ship it: its
    /// `go/N` rules and the rules that read what kbc reads as declarations (`action/6`,
    /// `mapping/2`, ...) as facts, with every predicate they call, but those planning calls
    /// too ([`Kb::predicates_run`]). kbc plans the problems itself, so it runs none of these.
    fn own_planner(&self) -> BTreeSet<Key> {
        let mut roots: Vec<Key> = Vec::new();
        let mut rules: BTreeSet<Key> = BTreeSet::new();
        for clause in &self.kb.clauses {
            let Some(body) = &clause.body else { continue };
            let key = (clause.head.name(), clause.head.arity());
            rules.insert(key);
            let mut reads_declarations = false;
            body.for_each_called(&mut |l, extra| {
                reads_declarations |= data_declaration(self.name(l.name()), l.arity() + extra);
            });
            if key.0 == sym::GO || reads_declarations {
                roots.push(key);
            }
        }
        let run = self.kb.predicates_run();
        let mut planner = self.kb.predicates_reached(roots);
        planner.retain(|key| rules.contains(key) && !run.contains(key));
        planner
    }

    fn names(&mut self) {
        let kb = self.kb;
        for action in &kb.actions {
            for l in &action.valid {
                self.state_literal(l, StateUse::Valid);
            }
            for l in &action.invalid {
                self.state_literal(l, StateUse::Invalid);
            }
            for l in &action.invalid_at_end {
                self.state_literal(l, StateUse::InvalidAtEnd);
            }
            for e in &action.effects {
                match e.kind {
                    EffectKind::Del => self.state_literal(&e.literal, StateUse::Delete),
                    EffectKind::Add => self.added_literal(&e.literal),
                }
            }
            for goal in &action.on_kb {
                self.kb_goal(goal);
            }
        }
        let wrappers = self.test_wrappers();
        let planner = self.own_planner();
        // What planning runs: OnKB goals, `duration/3`, and the goals of tests before `go`.
        let mut run = kb.predicates_run();
        let preludes = || kb.problems.iter().flat_map(|p| p.prelude.iter().flat_map(|p| &p.goals));
        let mut prelude_calls: Vec<Key> = Vec::new();
        for goal in preludes() {
            goal.for_each_called(&mut |l, extra| prelude_calls.push((l.name(), l.arity() + extra)));
        }
        run.extend(kb.predicates_reached(prelude_calls));
        // A goal known only at run time (`call(G)`) may call any rule: then none is said to
        // be never run.
        let mut dynamic = false;
        let run_goals = kb.actions.iter().flat_map(|a| &a.on_kb).chain(
            kb.clauses
                .iter()
                .filter(|c| run.contains(&(c.head.name(), c.head.arity())))
                .filter_map(|c| c.body.as_deref()),
        );
        for goal in run_goals.chain(preludes()) {
            goal.for_each_called(&mut |literal, extra| {
                dynamic |= builtins::calls_run_time_goal(self.interner, literal, extra);
            });
        }
        if let Some(first) = kb.clauses.iter().find(|c| planner.contains(&(c.head.name(), c.head.arity()))) {
            let mut shown: Vec<String> = planner.iter().map(|&key| format!("`{}`", self.indicator(key))).collect();
            let more = shown.len().saturating_sub(6);
            shown.truncate(6);
            let list = if more > 0 { format!("{} and {more} more", shown.join(", ")) } else { shown.join(", ") };
            self.diags.push(
                Diagnostic::note(
                    "the KB brings a planner of its own: kbc plans the problems itself and runs none of it",
                )
                .primary(first.head.span, "its first clause")
                .with_note(format!(
                    "the planner's predicates, which nothing kbc runs calls (OnKB goals, `duration/3`): {list}"
                ))
                .with_help("choose a problem with `--problem NAME`; `--search paper` is the paper's search"),
            );
        }
        for (index, clause) in kb.clauses.iter().enumerate() {
            if planner.contains(&(clause.head.name(), clause.head.arity())) {
                continue;
            }
            if wrappers.contains(&index) {
                let shown = self.indicator((clause.head.name(), clause.head.arity()));
                self.diags.push(
                    Diagnostic::note(format!("`{shown}` is a test wrapper: kbc ignores it"))
                        .primary(clause.head.span, "runs problems or the debugger")
                        .with_note(
                            "its body only calls problems (`go/2`, `go/4`, `go/5` tests), other wrappers, \
                             SWI-Prolog's debugger, output predicates or `halt`, and built-ins that call no \
                             goal; kbc plans the problems themselves",
                        )
                        .with_help("choose a problem with `--problem NAME`"),
                );
                continue;
            }
            if let Some(body) = &clause.body {
                let key = (clause.head.name(), clause.head.arity());
                self.never_run = (!dynamic && !run.contains(&key)).then_some(key);
                self.kb_goal(body);
                self.never_run = None;
            }
        }
        for problem in &kb.problems {
            for goal in problem.prelude.iter().flat_map(|p| &p.goals) {
                self.kb_goal(goal);
            }
            for l in &problem.goal {
                self.state_literal(l, StateUse::Goal);
            }
            for l in problem.initial_facts() {
                self.init_literal(l);
            }
        }
    }

    fn state_literal(&mut self, literal: &Literal, used: StateUse) {
        let key = (literal.name(), literal.arity());
        let indicator = self.indicator(key);
        if builtins::is_builtin_predicate(key.0, key.1) {
            let help = match used {
                StateUse::Valid => "move it to the OnKB slot, where goals are proven".to_string(),
                StateUse::Invalid | StateUse::InvalidAtEnd => {
                    "to require that it fails, write `\\+ Test` in the OnKB slot".to_string()
                }
                _ => "state facts are atoms or compounds such as `clear(b1)`".to_string(),
            };
            // Prolog gives it a meaning (a state fact of that name, which no state holds unless
            // an effect adds one), so only a goal that can never hold is an error.
            let message = format!("`{indicator}` is a built-in test, not a state fact");
            let diagnostic = if used == StateUse::Goal {
                Diagnostic::error(codes::UNKNOWN_PREDICATE, message)
            } else {
                Diagnostic::warning(codes::NEVER_PRODUCED, message)
            };
            let mut diagnostic = diagnostic.primary(literal.span, format!("used as {}", used.describe())).with_note(
                "conditions of this kind are matched against the facts of the state, which never hold built-ins",
            );
            if used == StateUse::Valid {
                diagnostic = diagnostic.with_note("so this action can never apply");
            }
            self.diags.push(diagnostic.with_help(help));
            return;
        }
        if self.vocabulary.state_known(key) {
            return;
        }
        if self.kb.problems.iter().any(|p| p.prelude.as_ref().is_some_and(|p| !p.resolved)) {
            return; // a test whose goals before `go` gave it no states (an error): unknown
        }
        if self.kb.problems.is_empty() {
            // Without a problem the initial states are unknown, so any fluent may come from
            // one; only a name close to another fluent's is worth a warning.
            self.possible_misspelling(literal, key, used);
            return;
        }
        let state_names = self.vocabulary.state_names();
        let arities = self.other_arities(key, &state_names);
        if !arities.is_empty() {
            // A goal literal of that arity can never hold: no plan exists. A condition or a
            // deletion of that arity never matches, which Prolog runs without complaint.
            let note = match used {
                StateUse::Goal => None,
                StateUse::Valid => {
                    Some(format!("no state fact is `{indicator}`, so this never matches and the action never applies"))
                }
                _ => Some(format!("no state fact is `{indicator}`, so this never matches")),
            };
            self.wrong_arity(literal, key, &arities, "initial states and effects use", note);
            return;
        }
        let message = match used {
            StateUse::Goal => format!("unknown predicate `{indicator}` in a goal"),
            _ => format!("unknown predicate `{indicator}`"),
        };
        let mut diagnostic = if used.is_error() {
            Diagnostic::error(codes::UNKNOWN_PREDICATE, message)
        } else {
            Diagnostic::warning(
                codes::NEVER_PRODUCED,
                format!("`{indicator}` is never in any state, so this condition never matches"),
            )
        }
        .primary(literal.name_span, format!("used in {}", used.describe()))
        .with_note("state facts come from init states and `add` effects; no init state holds it and no action adds it");
        if used == StateUse::Valid {
            diagnostic = diagnostic.with_note("so this action can never apply");
        }
        if self.vocabulary.static_defined.contains(&key) {
            diagnostic = diagnostic
                .with_note(format!(
                    "`{indicator}` is a static fact of the KB, and {} is matched against the state",
                    used.describe()
                ))
                .with_help("static facts belong in the OnKB slot, which is proven against the KB");
        } else {
            diagnostic = self.with_suggestion(diagnostic, literal, key, &state_names);
        }
        self.diags.push(diagnostic);
    }

    fn possible_misspelling(&mut self, literal: &Literal, key: Key, used: StateUse) {
        let mut candidates = self.vocabulary.state_names();
        candidates.extend(self.vocabulary.used_by_actions.iter().copied());
        candidates.remove(&key);
        let Some(found) = self.suggest(key, &candidates).filter(|f| f.1 == key.1) else { return };
        let indicator = self.indicator(key);
        let found_text = self.name(found.0).to_string();
        self.diags.push(
            Diagnostic::warning(codes::NEVER_PRODUCED, format!("no action adds `{indicator}`: is it a misspelling?"))
                .primary(literal.name_span, format!("used in {}", used.describe()))
                .with_note(
                    "no problem is loaded, so this could still come from an initial state; check with the goal file",
                )
                .with_fix(format!("replace with `{found_text}`"), literal.name_span, found_text)
                .with_help(format!("did you mean `{}`?", self.indicator(found))),
        );
    }

    fn added_literal(&mut self, literal: &Literal) {
        // An added fact defines its predicate; only an arity clash with other uses is suspect.
        let key = (literal.name(), literal.arity());
        if builtins::is_builtin_predicate(key.0, key.1) {
            let indicator = self.indicator(key);
            self.diags.push(
                Diagnostic::warning(codes::NEVER_PRODUCED, format!("`{indicator}` is a built-in, not a state fact"))
                    .primary(literal.span, "added by an effect")
                    .with_note(format!("this adds a state fact named `{indicator}`, which only a condition can read"))
                    .with_help("effects add facts such as `clear(B)`"),
            );
        }
    }

    fn init_literal(&mut self, literal: &Literal) {
        let key = (literal.name(), literal.arity());
        if self.vocabulary.used_by_actions.contains(&key)
            || self.vocabulary.goal_facts.contains(&key)
            || self.kb.actions.is_empty()
        {
            return;
        }
        let arities = self.other_arities(key, &self.vocabulary.used_by_actions);
        if !arities.is_empty() {
            let note = format!("no action reads `{}` facts, so this one is never used", self.indicator(key));
            self.wrong_arity(literal, key, &arities, "the actions use", Some(note));
            return;
        }
        let indicator = self.indicator(key);
        if let Some(found) = self.suggest(key, &self.vocabulary.used_by_actions) {
            let found_text = self.name(found.0).to_string();
            let mut diagnostic = Diagnostic::warning(
                codes::NEVER_PRODUCED,
                format!("`{indicator}` is in the initial state but no action uses it"),
            )
            .primary(literal.name_span, "no action reads or changes this fact")
            .with_help(format!("did you mean `{}`?", self.indicator(found)));
            if found.1 == key.1 {
                diagnostic = diagnostic.with_fix(format!("replace with `{found_text}`"), literal.name_span, found_text);
            }
            self.diags.push(diagnostic);
        }
    }

    /// A literal whose predicate is used elsewhere with other arities: an error (E0211)
    /// where it makes the KB fail (a goal, a call Prolog would find undefined); a warning
    /// (W0008) with `warning_note` saying what it does where it only never matches (a state
    /// condition, a deletion, an unused fact).
    fn wrong_arity(
        &mut self,
        literal: &Literal,
        key: Key,
        arities: &[usize],
        where_: &str,
        warning_note: Option<String>,
    ) {
        let name = self.name(key.0).to_string();
        let list = arities.iter().map(|a| format!("`{name}/{a}`")).collect::<Vec<_>>();
        let message = format!(
            "`{name}` is used with {} here, but elsewhere with {}",
            plural(key.1, "argument"),
            join_or(arities)
        );
        let diagnostic = match warning_note {
            None => Diagnostic::error(codes::WRONG_ARITY, message),
            Some(note) => Diagnostic::warning(codes::ARITY_NEVER_MATCHES, message).with_note(note),
        };
        let unit = if arities == [1] { "argument" } else { "arguments" };
        self.diags.push(
            diagnostic
                .primary(literal.span, plural(key.1, "argument"))
                .with_note(format!("{where_} {}", join_and(&list)))
                .with_help(format!("write `{name}` with {} {unit}", join_or(arities))),
        );
    }

    fn with_suggestion(
        &self,
        diagnostic: Diagnostic,
        literal: &Literal,
        key: Key,
        candidates: &BTreeSet<Key>,
    ) -> Diagnostic {
        match self.suggest(key, candidates) {
            Some(found) => {
                let found_text = self.name(found.0).to_string();
                let diagnostic = diagnostic.with_help(format!("did you mean `{}`?", self.indicator(found)));
                if found.1 == key.1 {
                    diagnostic.with_fix(format!("replace with `{found_text}`"), literal.name_span, found_text)
                } else {
                    diagnostic
                }
            }
            None => diagnostic,
        }
    }

    fn kb_goal(&mut self, goal: &Goal) {
        let mut calls = Vec::new();
        goal.for_each_called(&mut |l, extra| calls.push((l, extra)));
        for (literal, extra) in calls {
            self.kb_call(literal, extra);
        }
    }

    /// Checks a call of `literal` with `extra` more arguments (a closure's).
    fn kb_call(&mut self, literal: &Literal, extra: usize) {
        let key = (literal.name(), literal.arity() + extra);
        if let Some(builtin) = builtins::lookup(self.interner, key.0, key.1)
            && builtin.reads == builtins::Reads::Output
            && !self.vocabulary.static_defined.contains(&key)
        {
            let indicator = self.indicator(key);
            self.diags.push(
                Diagnostic::warning(codes::OUTPUT_NOT_PRINTED, format!("`{indicator}` prints nothing in kbc"))
                    .primary(literal.span, "succeeds without output")
                    .with_note(
                        "SWI-Prolog would print here; kbc proves OnKB goals and rules many times while it plans, \
                         in an order no reader could follow, and prints none of it",
                    )
                    .with_help("to see what a plan does, use `kbc plan --trace`; to see a KB's answers, `swipl`"),
            );
            return;
        }
        if self.vocabulary.kb_known(key) || builtins::is_engine_predicate(self.interner, key.0, key.1) {
            return;
        }
        let mut kb_names = self.vocabulary.kb_names();
        let builtin_keys: BTreeSet<Key> =
            [(sym::MEMBER, 2), (sym::TRUE, 0), (sym::FAIL, 0), (sym::NOT, 1)].into_iter().collect();
        let arities = self.other_arities(key, &kb_names.union(&builtin_keys).copied().collect());
        if !arities.is_empty() && self.never_run.is_none() {
            self.wrong_arity(literal, key, &arities, "the KB defines", None);
            return;
        }
        if let Some(rule) = self.never_run {
            // (A problem, `test1 :- go(...)`, is a predicate to Prolog too: a rule that
            // calls one runs the test.)
            let problems = self.problem_keys();
            if !problems.contains(&key) {
                let names = kb_names.union(&builtin_keys).chain(&problems).copied().collect();
                self.never_run_call(literal, key, rule, &arities, names);
            }
            return;
        }
        let indicator = self.indicator(key);
        let mut diagnostic = Diagnostic::error(codes::UNKNOWN_PREDICATE, format!("unknown predicate `{indicator}`"))
            .primary(literal.name_span, "no clause defines it and it is not a built-in");
        if data_declaration(self.name(key.0), key.1) {
            diagnostic = diagnostic
                .with_note(format!(
                    "kbc reads the `{indicator}` facts as declarations, not as clauses that OnKB goals and the rules \
                     they call could read"
                ))
                .with_help(
                    "a rule kbc runs cannot look the KB's declarations up; name what it needs in facts of its own",
                );
        } else if self.vocabulary.state_known(key) {
            diagnostic = diagnostic
                .with_note(format!(
                    "`{indicator}` is a state fact, but OnKB goals and rule bodies are proven against the KB"
                ))
                .with_help("conditions on the state belong in the Valid slot (or Invalid, to forbid them)");
        } else if let Some(why) = builtins::not_provided(self.name(key.0)) {
            diagnostic = diagnostic
                .with_note(format!(
                    "`{}` is an SWI-Prolog predicate that kbc does not provide: {why}",
                    self.name(key.0)
                ))
                .with_help("see docs/dsl.md for the built-ins kbc's resolution engine supports");
        } else {
            kb_names.extend(builtin_keys);
            diagnostic = self.with_suggestion(diagnostic, literal, key, &kb_names);
        }
        self.diags.push(diagnostic);
    }

    /// A call of `key`, which nothing defines (with this arity), in a rule of `rule` that
    /// planning never runs: SWI-Prolog loads it and raises an existence error only if the
    /// rule is called, so it is warning W0020.
    fn never_run_call(&mut self, literal: &Literal, key: Key, rule: Key, arities: &[usize], names: BTreeSet<Key>) {
        let indicator = self.indicator(key);
        let name = self.name(key.0).to_string();
        let mut diagnostic = Diagnostic::warning(
            codes::UNDEFINED_IN_RULE_NEVER_RUN,
            format!("unknown predicate `{indicator}`, in a rule planning never runs"),
        )
        .primary(literal.name_span, "no clause defines it and it is not a built-in")
        .with_note(format!(
            "nothing kbc runs (OnKB goals, `duration/3`, the goals of a test before `go`) calls `{}`, so kbc \
             plans without it; SWI-Prolog loads it too, and raises an existence error only if it is called",
            self.indicator(rule)
        ));
        if !arities.is_empty() {
            let list = arities.iter().map(|a| format!("`{name}/{a}`")).collect::<Vec<_>>();
            let unit = if arities == [1] { "argument" } else { "arguments" };
            diagnostic = diagnostic
                .with_note(format!("the KB defines {}", join_and(&list)))
                .with_help(format!("write `{name}` with {} {unit}", join_or(arities)));
        } else if let Some(why) = builtins::not_provided(&name) {
            diagnostic =
                diagnostic.with_note(format!("`{name}` is an SWI-Prolog predicate that kbc does not provide: {why}"));
        } else {
            diagnostic = self.with_suggestion(diagnostic, literal, key, &names);
        }
        self.diags.push(diagnostic);
    }

    // ---- goals ----------------------------------------------------------------------------

    fn unreachable_goals(&mut self) {
        let adds: Vec<&Literal> = self
            .kb
            .actions
            .iter()
            .flat_map(|a| a.effects.iter().filter(|e| e.kind == EffectKind::Add).map(|e| &e.literal))
            .collect();
        for problem in &self.kb.problems {
            for goal in &problem.goal {
                let key = (goal.name(), goal.arity());
                if !self.vocabulary.state_known(key) || self.vocabulary.recovered.contains(&key) {
                    continue; // reported as an unknown predicate, or hidden by a syntax error
                }
                let in_init = problem.initial_facts().any(|fact| unifiable(&goal.term, &fact.term));
                let added = adds.iter().any(|effect| unifiable(&goal.term, &effect.term));
                if in_init || added {
                    continue;
                }
                let shown = self.show(goal, &problem.vars);
                let problem_name = self.name(problem.name).to_string();
                self.diags.push(
                    Diagnostic::error(codes::UNREACHABLE_GOAL, format!("goal `{shown}` can never be reached"))
                        .primary(goal.span, "no action adds a fact like this, and the initial state lacks it")
                        .secondary(problem.name_span, format!("in problem `{problem_name}`"))
                        .with_note(format!(
                            "`{}` facts exist, but none unifies with this one: check the arguments",
                            self.indicator(key)
                        ))
                        .with_help("correct the goal, or add the fact to the initial state"),
                );
            }
        }
    }

    // ---- variables ------------------------------------------------------------------------

    fn effect_variables(&mut self) {
        for action in &self.kb.actions {
            // The variables the Valid and OnKB lists bind.
            let mut conditions: BTreeSet<VarId> = BTreeSet::new();
            for l in &action.valid {
                l.term.for_each_var(&mut |v| {
                    conditions.insert(v);
                });
            }
            for g in &action.on_kb {
                g.for_each_call(&mut |l| {
                    l.term.for_each_var(&mut |v| {
                        conditions.insert(v);
                    })
                });
            }
            // A start's or an instant's name must be ground when it applies (an end's name
            // takes its start's values; an arm-level action's, its mapping's).
            if action.snap != Snap::End && action.level == Level::High {
                let mut free: Vec<VarId> = Vec::new();
                action.name.term.for_each_var(&mut |v| {
                    if !conditions.contains(&v) && !free.contains(&v) {
                        free.push(v);
                    }
                });
                for v in free {
                    let info = action.vars.get(v);
                    let name = self.name(info.name).to_string();
                    let at = info.occurrences.first().copied().unwrap_or(action.name.span);
                    self.diags.push(
                        Diagnostic::warning(codes::OPEN_ADD, format!("variable `{name}` in the action's name is never bound"))
                            .primary(at, "not bound when the action applies")
                            .with_note("a plan names ground actions, so kbc never applies this one; Prolog would leave the variable unbound in the plan")
                            .with_help(format!("bind `{name}` in the Valid list or an OnKB goal")),
                    );
                }
            }
            // Effects may also use the name's variables.
            let mut bound = conditions;
            action.name.term.for_each_var(&mut |v| {
                bound.insert(v);
            });
            let mut reported: BTreeSet<VarId> = BTreeSet::new();
            for effect in &action.effects {
                let mut free = Vec::new();
                effect.literal.term.for_each_var(&mut |v| {
                    if !bound.contains(&v) && !free.contains(&v) {
                        free.push(v);
                    }
                });
                for v in free {
                    if !reported.insert(v) {
                        continue;
                    }
                    let info = action.vars.get(v);
                    let name = self.name(info.name).to_string();
                    let at = info
                        .occurrences
                        .iter()
                        .find(|s| effect.span.start <= s.start && s.end <= effect.span.end)
                        .copied()
                        .unwrap_or(effect.span);
                    let shown_name = if name == "_" { "`_`".to_string() } else { format!("`{name}`") };
                    // Prolog runs both: a deletion removes the facts that unify, an addition
                    // would put a non-ground fact in the state, which kbc does not do.
                    let diagnostic = match effect.kind {
                        EffectKind::Del => Diagnostic::warning(
                            codes::OPEN_DELETE,
                            format!("variable {shown_name} in a `del` effect is never bound"),
                        )
                        .primary(at, "matches any value")
                        .secondary(action.name.span, "the action")
                        .with_note("the deletion removes every fact of the state that unifies with it, as SWI-Prolog's `delete/3` does")
                        .with_help("to delete one particular fact, bind the variable in Valid"),
                        EffectKind::Add => Diagnostic::warning(
                            codes::OPEN_ADD,
                            format!("variable {shown_name} in an `add` effect is never bound"),
                        )
                        .primary(at, "not bound when the effect applies")
                        .secondary(action.name.span, "the action")
                        .with_note("a state holds ground facts only, so this action never applies; a plan that needs it is not found"),
                    };
                    let diagnostic = diagnostic.with_note(
                        "effect variables are bound by the action's name, its Valid list or OnKB; Invalid conditions bind nothing",
                    );
                    self.diags.push(if effect.kind == EffectKind::Add {
                        diagnostic.with_help(format!(
                            "add {shown_name} to the action's arguments, or bind it in Valid or OnKB"
                        ))
                    } else {
                        diagnostic
                    });
                }
            }
        }
    }

    // ---- durations ------------------------------------------------------------------------

    fn durations(&mut self) {
        let durative: BTreeSet<Key> =
            self.kb.actions.iter().filter(|a| a.snap != Snap::Instant).map(|a| (a.base, a.name.arity())).collect();
        let instant: BTreeSet<Key> =
            self.kb.actions.iter().filter(|a| a.snap == Snap::Instant).map(|a| (a.base, a.name.arity())).collect();
        for clause in &self.kb.clauses {
            if (clause.head.name(), clause.head.arity()) != (sym::DURATION, 3) {
                continue;
            }
            let args = clause.head.term.args();
            let Some(key) = args[0].callable() else {
                self.diags.push(
                    Diagnostic::error(
                        codes::BAD_DURATION,
                        "the first argument of `duration/3` must name a durative action",
                    )
                    .primary(clause.head.span, "expected a term such as `grip(A, B)`")
                    .with_help("write `duration(grip(_, _), 2, 4).`"),
                );
                continue;
            };
            if durative.contains(&key) {
                if clause.body.is_none() {
                    self.duration_bounds(clause, &args[1..]);
                }
                continue;
            }
            // Prolog loads the fact and nothing reads it: a warning, since the durations it
            // was meant to give are lost (the action gets the default).
            let indicator = self.indicator(key);
            let mut diagnostic = Diagnostic::warning(
                codes::UNUSED_DURATION,
                format!("duration for unknown durative action `{indicator}`"),
            )
            .primary(
                clause.head.span,
                format!("no `{0}_start` and `{0}_end` with {1}", self.name(key.0), plural(key.1, "argument")),
            );
            let base = self.name(key.0);
            let unpaired = self.kb.actions.iter().any(|a| {
                let name = self.name(a.name.name());
                a.snap == Snap::Instant
                    && a.name.arity() == key.1
                    && (name.strip_suffix("_start") == Some(base) || name.strip_suffix("_end") == Some(base))
            });
            if unpaired {
                diagnostic = diagnostic.with_note(format!(
                    "`{base}_start` and `{base}_end` take different numbers of arguments, so they are not one durative action (W0011)"
                ));
            } else if instant.contains(&key) {
                diagnostic =
                    diagnostic.with_note(format!("`{indicator}` is instantaneous: it has no `_start`/`_end` pair"));
            } else if let Some(found) = self.suggest(key, &durative) {
                diagnostic = diagnostic.with_help(format!("did you mean `{}`?", self.indicator(found)));
            } else {
                diagnostic = diagnostic
                    .with_note("`duration(X(Args), Min, Max)` names the durative action without `_start` or `_end`");
            }
            self.diags.push(diagnostic);
        }
    }

    fn duration_bounds(&mut self, clause: &hir::Clause, bounds: &[Term]) {
        let number = |t: &Term| match t {
            Term::Int(i) => Some(*i as f64),
            Term::Float(f) => Some(*f),
            _ => None,
        };
        if let (Some(min), Some(max)) = (number(&bounds[0]), number(&bounds[1]))
            && min > max
            && max >= 0.0
        {
            let shown = |t: &Term| hir::term_to_string(self.interner, t, &clause.vars);
            let (low, high) = (shown(&bounds[0]), shown(&bounds[1]));
            self.diags.push(
                Diagnostic::warning(codes::EMPTY_DURATION, format!("the least duration, `{low}`, is above the greatest, `{high}`"))
                    .primary(clause.head.span, "no duration lies between these bounds")
                    .with_note("Prolog's planner, which does not schedule, plans the action; no schedule of a plan that uses it exists (E0401)")
                    .with_help(format!("write the least duration first: `{high}, {low}`")),
            );
        }
        for (bound, which) in bounds.iter().zip(["minimum", "maximum"]) {
            let ok = match bound {
                Term::Int(i) => *i >= 0,
                Term::Float(f) => *f >= 0.0,
                Term::Atom(sym::INF) => which == "maximum",
                _ => false,
            };
            if !ok {
                let shown = hir::term_to_string(self.interner, bound, &clause.vars);
                self.diags.push(
                    Diagnostic::error(codes::BAD_DURATION, format!("expected a non-negative number as the {which} duration, found `{shown}`"))
                        .primary(clause.head.span, format!("the {which} is not a number"))
                        .with_help("write numbers, or a rule that computes them with `is`: `duration(move(_, X), D, D) :- D is X * 2.`"),
                );
            }
        }
    }

    // ---- layout ---------------------------------------------------------------------------

    fn discontiguous(&mut self) {
        let declared: BTreeSet<(crate::source::FileId, Symbol, usize)> = self
            .kb
            .declarations
            .iter()
            .filter(|d| matches!(d.kind, DeclarationKind::Discontiguous | DeclarationKind::Dynamic))
            .map(|d| (d.span.file, d.name, d.arity))
            .collect();
        let mut closed: BTreeMap<(crate::source::FileId, Symbol, usize), Span> = BTreeMap::new();
        let mut warned: BTreeSet<(crate::source::FileId, Symbol, usize)> = BTreeSet::new();
        let mut previous: Option<(crate::source::FileId, Symbol, usize, Span)> = None;
        for site in &self.kb.head_sites {
            let key = (site.file, site.name, site.arity);
            if let Some((file, name, arity, span)) = previous
                && (file, name, arity) != key
            {
                closed.insert((file, name, arity), span);
            }
            if previous.is_none_or(|(f, n, a, _)| (f, n, a) != key)
                && let Some(&last) = closed.get(&key)
                && !declared.contains(&key)
                && warned.insert(key)
            {
                let indicator = self.indicator((site.name, site.arity));
                self.diags.push(
                    Diagnostic::warning(
                        codes::DISCONTIGUOUS,
                        format!("clauses of `{indicator}` are not together in the file"),
                    )
                    .primary(site.span, "this clause is separated from the others")
                    .secondary(last, "the previous clause is here")
                    .with_note("SWI-Prolog warns about this too: it usually means a clause was misplaced or misspelt")
                    .with_help(format!("move the clauses together, or declare `:- discontiguous {indicator}.`")),
                );
            }
            previous = Some((site.file, site.name, site.arity, site.span));
        }
    }
}

pub(crate) fn join_or(arities: &[usize]) -> String {
    match arities {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
    }
}

/// The end a durative action's start `start` (of base name `base`) lacks: its name, written as
/// the start's with `_end` for `_start` (`push_end(A, B)`), and the clause that declares it
/// with empty lists, as a fix's text to insert after the start. (Error E0204 for arm-level
/// actions, warning W0019 from `lower` for high-level ones.)
pub(crate) fn missing_end(interner: &Interner, start: &Action, base: &str) -> (String, String) {
    let end_name = hir::term_to_string(interner, &start.name.term, &start.vars).replacen(
        &format!("{base}_start"),
        &format!("{base}_end"),
        1,
    );
    let head = if start.level == Level::High { "action" } else { "ll_action" };
    let skeleton = format!("\n\n{head}({end_name},\n    [], [], [], [],\n    []).");
    (end_name, skeleton)
}
