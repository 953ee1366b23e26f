//! Checking one answer of a model: the code is extracted, read by the front end together with
//! the KB, its states checked ([`super::state`]) and, for a test case, planned. The result is
//! the diagnostics that concern the draft, which the repair loop feeds back to the model.

use std::path::PathBuf;
use std::time::Duration;

use super::Want;
use super::extract::extract_code;
use super::state::{self, Vocabulary};
use crate::diag::{Diagnostic, Diagnostics, codes, plural};
use crate::intern::Interner;
use crate::ir::hir::{self, Kb, Problem};
use crate::passes::load::SourceLoader;
use crate::planner::{SearchKind, Silent};
use crate::session::{Frontend, PlanSettings, Session};
use crate::source::{FileId, SourceDb, Span};
use crate::stdlib;

/// A file of the KB a draft is checked against.
#[derive(Clone, Debug)]
pub struct KbFile {
    /// The name diagnostics show.
    pub name: String,
    /// Where it is, for resolving its includes.
    pub path: Option<PathBuf>,
    /// Its text.
    pub text: String,
}

/// A state fact, printed: its predicate and its arguments.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Fact {
    /// The predicate's name.
    pub name: String,
    /// Each argument as Prolog text.
    pub args: Vec<String>,
}

/// A test case's two states as facts, in the order written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct States {
    /// The initial state.
    pub init: Vec<Fact>,
    /// The goal.
    pub goal: Vec<Fact>,
}

/// What checking one answer found.
pub struct Checked {
    /// The KB's files and the draft (the draft last), for rendering the diagnostics.
    pub db: SourceDb,
    /// The code found in the answer.
    pub code: Option<String>,
    /// The problems found in the draft (none in the KB alone: the KB is checked before).
    pub diagnostics: Diagnostics,
    /// The drafted test case's states, when the front end could read one (even with errors).
    pub states: Option<States>,
    /// The length of the plan found for the test case, when it was planned.
    pub plan_steps: Option<usize>,
}

impl Checked {
    /// Whether the draft passed every check (an answer without code has E0610).
    pub fn passed(&self) -> bool {
        !self.diagnostics.has_errors()
    }
}

/// How much work checking an answer may do.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// The most states the planner expands to show a test case solvable.
    pub max_states: u64,
    /// The longest the planner searches.
    pub plan_time: Duration,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits { max_states: 200_000, plan_time: Duration::from_secs(10) }
    }
}

/// Checks answers against one KB.
pub struct Checker<'a> {
    kb: &'a [KbFile],
    loader: &'a mut dyn SourceLoader,
    want: Want,
    limits: Limits,
    /// Drafted actions over a KB that relies on the standard blocks world (it has no actions
    /// of its own) extend that world instead of replacing it.
    extends_std: bool,
}

impl<'a> Checker<'a> {
    /// A checker for drafts of `want` against the KB files `kb` (their includes read through
    /// `loader`).
    pub fn new(kb: &'a [KbFile], loader: &'a mut dyn SourceLoader, want: Want, limits: Limits) -> Checker<'a> {
        let mut checker = Checker { kb, loader, want, limits, extends_std: false };
        if checker.want == Want::Actions {
            checker.extends_std = checker.kb_alone().kb().uses_std_domain;
        }
        checker
    }

    /// What is asked for.
    pub fn want(&self) -> &Want {
        &self.want
    }

    /// Runs the front end on the KB alone: the KB must be free of errors before a model is
    /// asked to extend it.
    pub fn kb_alone(&mut self) -> Session {
        let mut db = SourceDb::new();
        let roots = self.add_kb(&mut db);
        Session::open(db, &roots, self.loader)
    }

    fn add_kb(&self, db: &mut SourceDb) -> Vec<FileId> {
        self.kb.iter().map(|f| db.add(f.name.clone(), f.path.clone(), f.text.clone())).collect()
    }

    /// The KB's files for checking a draft: the standard blocks world's files first when
    /// drafted actions extend it (a file with actions of its own would otherwise stand in for
    /// it).
    fn add_kb_for_draft(&self, db: &mut SourceDb) -> Vec<FileId> {
        let mut roots = Vec::new();
        if self.extends_std {
            roots.push(db.add(stdlib::STD_ARMS_NAME, None, stdlib::STD_ARMS));
            roots.push(db.add(stdlib::STD_BLOCKS_NAME, None, stdlib::STD_BLOCKS));
        }
        roots.extend(self.add_kb(db));
        roots
    }

    /// Checks one answer.
    pub fn check(&mut self, answer: &str) -> Checked {
        let mut db = SourceDb::new();
        let mut diagnostics = Diagnostics::new();
        let Some(extracted) = extract_code(answer) else {
            diagnostics.push(
                Diagnostic::error(codes::NO_CODE, "the answer holds no Prolog code")
                    .with_note(format!("the answer begins: {}", excerpt(answer)))
                    .with_help("answer with Prolog clauses only, in a ```prolog fence or bare"),
            );
            return Checked { db, code: None, diagnostics, states: None, plan_steps: None };
        };
        let mut roots = self.add_kb_for_draft(&mut db);
        let draft = db.add(self.want.file_name(), None, extracted.code.clone());
        roots.push(draft);
        let mut session = Session::open(db, &roots, self.loader);
        for diagnostic in session.diagnostics().iter() {
            let in_draft = diagnostic.labels.iter().any(|l| l.span.file == draft);
            if diagnostic.code.is_some() && (in_draft || diagnostic.labels.is_empty() && diagnostic.is_error()) {
                let mut diagnostic = diagnostic.clone();
                // A condition that never matches, or a duration nothing reads, runs in Prolog,
                // so `kbc check` only warns; in a draft it is a mistake the model must fix.
                if matches!(
                    diagnostic.code,
                    Some(codes::NEVER_PRODUCED | codes::ARITY_NEVER_MATCHES | codes::UNUSED_DURATION)
                ) {
                    diagnostic.severity = crate::diag::Severity::Error;
                }
                diagnostics.push(diagnostic);
            }
        }
        let (mut states, mut plan_steps) = (None, None);
        match &self.want {
            Want::TestCase { name } => {
                let (kb, interner) = (session.kb(), session.interner());
                let problem = the_problem(kb, interner, draft, name, &mut diagnostics);
                only_test_cases(session.hir(), kb, draft, &mut diagnostics);
                if let Some(index) = problem {
                    states = Some(states_of(interner, &kb.problems[index]));
                    if !diagnostics.has_errors() {
                        let program = session.program(index);
                        let (kb, interner) = (session.kb(), session.interner());
                        if let Some(vocabulary) = Vocabulary::of(kb, interner) {
                            state::check_problem(
                                &vocabulary,
                                &kb.problems[index],
                                &program,
                                interner,
                                &mut diagnostics,
                            );
                        }
                    }
                    if !diagnostics.has_errors() {
                        plan_steps = self.plan(&mut session, index, &mut diagnostics);
                    }
                }
            }
            Want::Actions => {
                let count = session.kb().actions.iter().filter(|a| a.span.file == draft).count();
                if count == 0 && !diagnostics.has_errors() {
                    diagnostics.push(
                        Diagnostic::error(codes::NOT_ASKED_FOR, "the answer defines no action schema")
                            .primary(Span::point(draft, 0), "the answer's code starts here")
                            .with_help(
                                "write each action as `action(Name, Valid, Invalid, InvalidAtEnd, OnKB, Effects).`",
                            ),
                    );
                }
            }
        }
        diagnostics.sort_by_position();
        let (db, _, _) = session.into_parts();
        Checked { db, code: Some(extracted.code), diagnostics, states, plan_steps }
    }

    /// Plans the test case (the search only); a failure becomes the planner's diagnostic.
    fn plan(&self, session: &mut Session, index: usize, diagnostics: &mut Diagnostics) -> Option<usize> {
        let settings = PlanSettings {
            search: SearchKind::Heuristic,
            max_states: self.limits.max_states,
            timeout: Some(self.limits.plan_time),
            ..PlanSettings::default()
        };
        match session.search(index, &settings, &mut Silent) {
            Ok(searched) => Some(searched.plans[0].steps.len()),
            Err(failed) => {
                let stats = &failed.stats;
                let figures =
                    format!("expanded {}, generated {}", plural(stats.expanded as usize, "state"), stats.generated);
                let diagnostic = session.search_failure(index, &failed, &figures, &settings);
                // A budget or exhaustion message has no place of its own: point at the case.
                diagnostics.push(if diagnostic.labels.is_empty() {
                    diagnostic.primary(session.kb().problems[index].span, "this test case")
                } else {
                    diagnostic
                });
                None
            }
        }
    }
}

/// The drafted test case: the one problem of the draft file, named `name`.
fn the_problem(
    kb: &Kb,
    interner: &Interner,
    draft: FileId,
    name: &str,
    diagnostics: &mut Diagnostics,
) -> Option<usize> {
    let drafted: Vec<usize> = (0..kb.problems.len()).filter(|&i| kb.problems[i].span.file == draft).collect();
    let start = Span::point(draft, 0);
    match drafted.as_slice() {
        [] => {
            if !diagnostics.has_errors() {
                diagnostics.push(
                    Diagnostic::error(codes::NOT_ASKED_FOR, format!("the answer defines no test case `{name}`"))
                        .primary(start, "the answer's code starts here")
                        .with_help(format!("write it as `{name} :- go(InitialState, GoalState).`")),
                );
            }
            None
        }
        [index] => {
            let problem = &kb.problems[*index];
            let written = interner.resolve(problem.name);
            if written != name {
                diagnostics.push(
                    Diagnostic::error(
                        codes::NOT_ASKED_FOR,
                        format!("the test case is named `{written}`, not `{name}` as asked"),
                    )
                    .primary(problem.name_span, "this name")
                    .with_fix(format!("rename it `{name}`"), problem.name_span, name),
                );
            }
            Some(*index)
        }
        [first, rest @ ..] => {
            let mut diagnostic = Diagnostic::error(
                codes::NOT_ASKED_FOR,
                format!("the answer defines {}; one was asked for", plural(drafted.len(), "test case")),
            )
            .primary(kb.problems[rest[0]].name_span, "another test case");
            diagnostic = diagnostic.secondary(kb.problems[*first].name_span, "the first");
            diagnostics.push(diagnostic.with_help(format!("answer with the one test case `{name}` only")));
            drafted.iter().copied().find(|&i| interner.resolve(kb.problems[i].name) == name).or(Some(*first))
        }
    }
}

/// A test case answer holds test cases and nothing else: no facts, rules or directives that
/// would change the KB (or run something when the file is consulted by a Prolog system).
fn only_test_cases(frontend: &Frontend, kb: &Kb, draft: FileId, diagnostics: &mut Diagnostics) {
    let Some(ast) = frontend.loaded.files.iter().find(|f| f.file == draft) else { return };
    for clause in &ast.clauses {
        let is_problem =
            kb.problems.iter().any(|p| p.span.file == draft && clause.span.range().contains(&(p.span.start as usize)));
        if !is_problem && !clause.recovered {
            diagnostics.push(
                Diagnostic::error(codes::NOT_ASKED_FOR, "the answer holds more than the test case")
                    .primary(clause.span, "not part of a test case")
                    .with_fix("remove this clause", clause.span, "")
                    .with_help(
                        "answer with the test case clause only: the KB already has its facts, rules and directives",
                    ),
            );
        }
    }
}

/// The problem's states as printed facts.
pub fn states_of(interner: &Interner, problem: &Problem) -> States {
    let facts = |literals: &mut dyn Iterator<Item = &hir::Literal>| {
        literals
            .map(|l| {
                let name = interner.resolve(l.name()).to_string();
                let args = l.term.args().iter().map(|a| hir::term_to_string(interner, a, &problem.vars)).collect();
                Fact { name, args }
            })
            .collect()
    };
    States { init: facts(&mut problem.initial_facts()), goal: facts(&mut problem.goal.iter()) }
}

/// The first line of `text`, shortened.
fn excerpt(text: &str) -> String {
    let Some(line) = text.trim().lines().next() else {
        return "(nothing: the answer is empty)".to_string();
    };
    let short: String = line.chars().take(60).collect();
    if short.len() < line.len() { format!("\"{short}...\"") } else { format!("\"{short}\"") }
}
