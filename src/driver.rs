//! The pipeline, written once: which passes run, in which order, with which inputs.
//!
//! The CLI and the language server call these functions and only differ in where text comes
//! from and where diagnostics go.

use crate::diag::{Diagnostic, Diagnostics};
use crate::intern::{Interner, sym};
use crate::ir::hir::{self, Kb};
use crate::passes::load::{self, Loaded, NoIncludes, SourceLoader};
use crate::passes::{check, lower};
use crate::source::{FileId, SourceDb};
use crate::syntax::ast::TermKind;

/// The standard library's multi-arm blocks world, used when the given files declare no actions.
pub const STD_BLOCKS: &str = include_str!("../std/blocks.pl");

/// The arm-level actions of the simulated arms, loaded with [`STD_BLOCKS`].
pub const STD_ARMS: &str = include_str!("../std/arms.pl");

/// The name diagnostics show for [`STD_ARMS`].
pub const STD_ARMS_NAME: &str = "<std>/arms.pl";

/// The name diagnostics show for [`STD_BLOCKS`].
pub const STD_BLOCKS_NAME: &str = "<std>/blocks.pl";

/// What the front end produced.
pub struct Frontend {
    /// Every name seen.
    pub interner: Interner,
    /// The parsed files, in load order.
    pub loaded: Loaded,
    /// The resolved KB.
    pub kb: Kb,
    /// Every problem found, sorted by position.
    pub diagnostics: Diagnostics,
}

/// Runs the front end on `roots` (KB and goal files already in `db`).
///
/// When the files declare problems but no `action/6` or `ll_action/6` at all (goal files
/// only), the standard blocks world (std/blocks.pl, with the arm-level actions of
/// std/arms.pl it maps onto) is loaded first as the domain, and a note says so. Files with
/// `mapping/2` facts but no `ll_action/6` of their own get std/arms.pl.
pub fn frontend(db: &mut SourceDb, roots: &[FileId], loader: &mut dyn SourceLoader) -> Frontend {
    let mut interner = Interner::new();
    let mut diags = Diagnostics::new();
    let user = load::load(roots, db, &mut interner, loader, &mut diags);
    let mut declares_actions = false;
    let mut declares_problems = false;
    let mut declares_ll_actions = false;
    let mut declares_mappings = false;
    for clause in user.clauses() {
        let (head, body) = match &clause.term.kind {
            TermKind::Compound(rule) if rule.functor == sym::NECK && rule.args.len() == 2 => {
                (&rule.args[0], Some(&rule.args[1]))
            }
            _ => (&clause.term, None),
        };
        declares_actions |= matches!(head.callable(), Some((sym::ACTION | sym::LL_ACTION, _)));
        declares_ll_actions |= matches!(head.callable(), Some((sym::LL_ACTION, _)));
        declares_mappings |= matches!(head.callable(), Some((sym::MAPPING, _)));
        declares_problems |=
            matches!(head.callable(), Some((sym::INIT_STATE | sym::GOAL_STATE | sym::HL_INIT | sym::HL_GOAL, 1)))
                || body.is_some_and(|b| matches!(b.callable(), Some((sym::GO, _))));
    }
    let mut uses_std_domain = false;
    let loaded = if declares_mappings && !declares_ll_actions {
        // Mappings onto arm-level steps the files do not declare: the simulated arms' own.
        let arms_file = db.add(STD_ARMS_NAME, None, STD_ARMS);
        let arms = load::load(&[arms_file], db, &mut interner, &mut NoIncludes, &mut diags);
        prepend(arms, user)
    } else if declares_actions || !declares_problems {
        user
    } else {
        uses_std_domain = true;
        diags.push(Diagnostic::note(
            "no action schemas given: using the standard multi-arm blocks world (std/blocks.pl)",
        ));
        let arms_file = db.add(STD_ARMS_NAME, None, STD_ARMS);
        let std_file = db.add(STD_BLOCKS_NAME, None, STD_BLOCKS);
        let std = load::load(&[arms_file, std_file], db, &mut interner, &mut NoIncludes, &mut diags);
        prepend(std, user)
    };
    let mut kb = lower::lower(&loaded, db, &mut interner, &mut diags);
    kb.uses_std_domain = uses_std_domain;
    verify_hir(&kb, db, &interner);
    check::check(&kb, &interner, &mut diags);
    diags.sort_by_position();
    Frontend { interner, loaded, kb, diagnostics: diags }
}

/// Runs the HIR verifier in debug builds and tests; a failure is a compiler bug.
fn verify_hir(kb: &Kb, db: &SourceDb, interner: &Interner) {
    if cfg!(debug_assertions) {
        let result = hir::verify(kb, db.len()).and_then(|()| hir::verify_names(kb, interner));
        if let Err(message) = result {
            panic!("internal compiler error: the HIR verifier failed after `lower`: {message}");
        }
    }
}

/// `first`'s clauses, then `second`'s, as one program.
fn prepend(first: Loaded, second: Loaded) -> Loaded {
    let offset = first.files.len();
    let mut files = first.files;
    files.extend(second.files);
    let mut order = first.order;
    order.extend(second.order.into_iter().map(|r| load::ClauseRef { file: r.file + offset, clause: r.clause }));
    Loaded { files, order }
}

/// Chooses the problem a command works on: the one named `name`, or the only one.
///
/// Fails with a diagnostic when the name is unknown (listing the problems), when there is no
/// problem, or when there are several and no name (listing them).
pub fn select_problem(kb: &Kb, interner: &Interner, name: Option<&str>) -> Result<usize, Box<Diagnostic>> {
    use crate::diag::codes;
    let names = || kb.problems.iter().map(|p| format!("`{}`", interner.resolve(p.name))).collect::<Vec<_>>().join(", ");
    let diagnostic = match name {
        Some(name) => {
            if let Some(index) = interner.get(name).and_then(|s| kb.problems.iter().position(|p| p.name == s)) {
                return Ok(index);
            }
            let unknown = Diagnostic::error(codes::UNKNOWN_PROBLEM, format!("no problem named `{name}`"));
            if kb.problems.is_empty() {
                unknown.with_note("the files define no problem at all")
            } else {
                unknown.with_note(format!("the problems are {}", names())).with_help("pass one of them to `--problem`")
            }
        }
        None => match kb.problems.len() {
            1 => return Ok(0),
            0 => Diagnostic::error(codes::NO_PROBLEM, "no problem to plan")
                .with_note("a problem is a test `name :- go(Init, Goal).` or an `init_state`/`goal_state` pair")
                .with_help("add a goal file to the command line"),
            n => Diagnostic::error(codes::AMBIGUOUS_PROBLEM, format!("{n} problems and no `--problem` to choose one"))
                .with_note(format!("the problems are {}", names()))
                .with_help("choose one with `--problem NAME`"),
        },
    };
    Err(Box::new(diagnostic))
}

/// What the temporal passes produced for one plan.
pub struct Timed {
    /// The partial-order plan.
    pub pop: crate::ir::pop::Pop,
    /// Its simple temporal network.
    pub stn: crate::ir::stn::Stn,
    /// The earliest-start schedule.
    pub schedule: crate::ir::schedule::Schedule,
}

/// Runs the temporal passes on a valid plan: achievers and the partial order, the STN with
/// durations, consistency and the schedule. Warnings (default durations) and errors go to
/// `diags`; an inconsistent network is an error whose labels mark each constraint of the
/// negative cycle, and the result is `None`.
pub fn schedule(
    kb: &Kb,
    interner: &Interner,
    program: &crate::engine::Program,
    plan: &crate::ir::plan::Plan,
    diags: &mut Diagnostics,
) -> Option<Timed> {
    use crate::ir::{pop, schedule, stn};
    use crate::passes;
    let pop = passes::pop::build(kb, interner, plan);
    internal_check("pop", pop::verify(kb, &pop));
    let errors_before = diags.error_count();
    let stn = passes::stn::build(kb, interner, program, &pop, diags);
    internal_check("stn", stn::verify(&pop, &stn));
    if diags.error_count() > errors_before {
        return None;
    }
    match passes::schedule::solve(&stn) {
        Ok(schedule) => {
            internal_check("schedule", schedule::verify(&pop, &schedule));
            Some(Timed { pop, stn, schedule })
        }
        Err(cycle) => {
            diags.push(negative_cycle_diagnostic(kb, interner, &pop, &stn, &cycle));
            None
        }
    }
}

/// How many times [`reassign`] rearranges a plan it has just improved.
const REASSIGN_ROUNDS: usize = 4;

/// Runs the `reassign` pass on a scheduled plan and keeps what it gains: each candidate, best
/// estimate first, is checked step by step under the search's semantics
/// ([`crate::planner::is_solution`]) and scheduled by the temporal passes; the first whose
/// makespan is shorter replaces the plan, and the pass runs again on it, up to
/// [`REASSIGN_ROUNDS`] times. Returns the plan and schedule kept (the given ones when nothing
/// was shorter).
pub fn reassign(
    kb: &Kb,
    interner: &Interner,
    program: &crate::engine::Program,
    task: &mut crate::ir::task::Task,
    plan: crate::ir::plan::Plan,
    timed: Timed,
) -> (crate::ir::plan::Plan, Timed) {
    let (mut plan, mut timed) = (plan, timed);
    for _ in 0..REASSIGN_ROUNDS {
        let candidates = crate::passes::reassign::candidates(kb, &plan, &timed.pop, &timed.stn);
        let mut improved = false;
        for candidate in candidates {
            if candidate.estimate >= timed.schedule.makespan
                || !crate::planner::is_solution(task, program, &candidate.plan)
            {
                continue;
            }
            let mut diags = Diagnostics::new();
            if let Some(scheduled) = schedule(kb, interner, program, &candidate.plan, &mut diags)
                && scheduled.schedule.makespan < timed.schedule.makespan
            {
                (plan, timed) = (candidate.plan, scheduled);
                improved = true;
                break;
            }
        }
        if !improved {
            break;
        }
    }
    (plan, timed)
}

/// The makespan `kbc plan` gives a plan the heuristic search found: scheduled by the temporal
/// passes, then rearranged by [`reassign`]. The search's improvement phase scores its plans
/// with it, since `reassign` can shorten a plan a lot more than the search can tell.
pub struct ReassignedMakespan<'a> {
    /// The KB.
    pub kb: &'a Kb,
    /// Its names.
    pub interner: &'a Interner,
    /// The problem's program (see [`crate::planner::program_for`]).
    pub program: &'a crate::engine::Program,
}

impl crate::planner::Score for ReassignedMakespan<'_> {
    fn score(&mut self, task: &mut crate::ir::task::Task, plan: &crate::ir::plan::Plan) -> Option<i64> {
        let timed = schedule(self.kb, self.interner, self.program, plan, &mut Diagnostics::new())?;
        let (_, timed) = reassign(self.kb, self.interner, self.program, task, plan.clone(), timed);
        Some(timed.schedule.makespan)
    }
}

/// The back end: the behaviour tree of a scheduled plan, and its bytecode module.
pub fn build_bytecode(
    kb: &Kb,
    interner: &Interner,
    db: &SourceDb,
    plan: &crate::ir::plan::Plan,
    timed: &Timed,
    host: Option<(&str, &[(&str, usize)])>,
) -> Result<(crate::ir::bt::Bt, kbvm::bytecode::Module), Box<Diagnostic>> {
    let bt = crate::passes::bt::build(&timed.pop, &timed.stn, &timed.schedule);
    internal_check("bt", crate::ir::bt::verify(&timed.pop, &timed.stn, &bt));
    let refinements = crate::codegen::refinements(kb, interner, &timed.pop)?;
    if let Some((host, primitives)) = host {
        crate::codegen::check_host_profile(kb, interner, &timed.pop, &refinements, host, primitives)?;
    }
    let module = crate::codegen::generate(kb, interner, db, plan, &timed.pop, &timed.stn, &bt, &refinements);
    if cfg!(debug_assertions) {
        // The loader's verifier is the codegen's verifier: what it writes must load back.
        let bytes = module.encode();
        match kbvm::bytecode::Module::decode(&bytes) {
            Ok(decoded) => {
                assert!(decoded == module, "internal compiler error: the bytecode does not decode to itself")
            }
            Err(e) => panic!("internal compiler error: the generated bytecode does not load: {e}"),
        }
    }
    Ok((bt, module))
}

fn internal_check(pass: &str, result: Result<(), String>) {
    if cfg!(debug_assertions)
        && let Err(message) = result
    {
        panic!("internal compiler error: the verifier failed after `{pass}`: {message}");
    }
}

/// E0401, with a label on each constraint of the cycle.
fn negative_cycle_diagnostic(
    kb: &Kb,
    interner: &Interner,
    pop: &crate::ir::pop::Pop,
    stn: &crate::ir::stn::Stn,
    cycle: &crate::passes::schedule::NegativeCycle,
) -> Diagnostic {
    use crate::diag::codes;
    use crate::ir::pop::Reason;
    use crate::ir::stn::{DurationSource, EdgeKind, format_time};
    let no_vars = hir::VarTable::default();
    let step_name = |i: usize| format!("a{} `{}`", i + 1, hir::term_to_string(interner, &pop.steps[i].name, &no_vars));
    let action_span = |i: usize| kb.actions[pop.steps[i].action].name.span;
    let mut diagnostic = Diagnostic::error(
        codes::INCONSISTENT_STN,
        "no schedule satisfies the plan's durations and orderings".to_string(),
    );
    let mut chain = Vec::new();
    for (k, &edge) in cycle.edges.iter().enumerate() {
        let weight = stn.graph[edge];
        let (span, message) = match weight.kind {
            EdgeKind::Precedence { before, after, reason } => {
                let span = match reason {
                    Reason::Achiever { condition } => pop.steps[after].conditions.get(condition).map(|c| c.span),
                    Reason::Threat { consumer, condition } if consumer < pop.steps.len() => {
                        pop.steps[consumer].conditions.get(condition).map(|c| c.span)
                    }
                    Reason::Threat { condition, .. } => pop.goal.get(condition).map(|c| c.span),
                    Reason::StartEnd => None,
                }
                .unwrap_or_else(|| action_span(after));
                chain.push(format!("{} after {}", step_name(after), step_name(before)));
                (span, format!("{} must wait for {}", step_name(after), step_name(before)))
            }
            EdgeKind::MinDuration { start, source } | EdgeKind::MaxDuration { start, source } => {
                let bounds = stn.durations[start].expect("a start has bounds");
                let is_max = matches!(weight.kind, EdgeKind::MaxDuration { .. });
                let what = if is_max {
                    format!("at most {}", bounds.max.map_or("inf".to_string(), format_time))
                } else {
                    format!("at least {}", format_time(bounds.min))
                };
                let running = crate::passes::stn::running_term(kb, &pop.steps[start]);
                let shown = hir::term_to_string(interner, &running, &no_vars);
                chain.push(format!("`{shown}` lasts {what}"));
                let span = match source {
                    DurationSource::Clause(span) => span,
                    DurationSource::Default => action_span(start),
                };
                (span, format!("`{shown}` lasts {what}"))
            }
            EdgeKind::AfterOrigin => {
                chain.push("nothing happens before time 0".to_string());
                continue;
            }
        };
        diagnostic = if k == 0 { diagnostic.primary(span, message) } else { diagnostic.secondary(span, message) };
    }
    diagnostic
        .with_note(format!("these constraints form a cycle: {}", chain.join("; ")))
        .with_note(format!(
            "together they ask a time point to come {} time units before itself",
            format_time(-cycle.weight)
        ))
        .with_help("correct the `duration/3` bounds, or ask for other plans with `--retries N`")
}
