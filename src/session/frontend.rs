//! The front end: load the files (and the standard library a KB relies on), lower them to
//! the resolved KB (HIR) and check it.

use crate::diag::plural;
use crate::diag::{Diagnostic, Diagnostics};
use crate::intern::{Interner, sym};
use crate::ir::hir::{self, Kb};
use crate::passes::load::{self, Loaded, NoIncludes, SourceLoader};
use crate::passes::{check, library, lower, prelude};
use crate::source::{FileId, SourceDb};
use crate::stdlib;
use crate::syntax::ast::TermKind;

/// The most diagnostics of one code the front end reports in one file; a note counts the
/// rest (a generated file with ten thousand stray brackets still gets a readable report).
pub const MAX_REPEATS: usize = 100;

/// What the front end produced.
pub struct Frontend {
    /// Every name seen.
    pub interner: Interner,
    /// The parsed files, in load order.
    pub loaded: Loaded,
    /// The resolved KB.
    pub kb: Kb,
}

/// Runs the front end on `roots` (KB and goal files already in `db`); its diagnostics are
/// sorted by position.
///
/// When the files declare problems but no `action/6` or `ll_action/6` at all (goal files
/// only), the standard blocks world (std/blocks.pl, with the arm-level actions of
/// std/arms.pl it maps onto) is loaded first as the domain, and a note says so. Files with
/// `mapping/2` facts but no `ll_action/6` of their own get std/arms.pl.
pub(super) fn run(db: &mut SourceDb, roots: &[FileId], loader: &mut dyn SourceLoader) -> (Frontend, Diagnostics) {
    let mut interner = Interner::new();
    let mut diags = Diagnostics::new();
    let user = super::timing::time(
        "parse",
        || load::load(roots, db, &mut interner, loader, &mut diags),
        |loaded| format!("{}, {}", plural(loaded.files.len(), "file"), plural(loaded.order.len(), "clause")),
    );
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
                || body.is_some_and(|b| lower::problem_in_body(b, &interner).is_some());
    }
    let mut uses_std_domain = false;
    let loaded = if declares_mappings && !declares_ll_actions {
        // Mappings onto arm-level steps the files do not declare: the simulated arms' own.
        let arms_file = db.add(stdlib::STD_ARMS_NAME, None, stdlib::STD_ARMS);
        let arms = load::load(&[arms_file], db, &mut interner, &mut NoIncludes, &mut diags);
        prepend(arms, user)
    } else if declares_actions || !declares_problems {
        user
    } else {
        uses_std_domain = true;
        diags.push(Diagnostic::note(
            "no action schemas given: using the standard multi-arm blocks world (std/blocks.pl)",
        ));
        let arms_file = db.add(stdlib::STD_ARMS_NAME, None, stdlib::STD_ARMS);
        let std_file = db.add(stdlib::STD_BLOCKS_NAME, None, stdlib::STD_BLOCKS);
        let std = load::load(&[arms_file, std_file], db, &mut interner, &mut NoIncludes, &mut diags);
        prepend(std, user)
    };
    let mut kb = super::timing::time(
        "hir",
        || lower::lower(&loaded, db, &mut interner, &mut diags),
        |kb| {
            let (actions, problems) = (plural(kb.actions.len(), "action"), plural(kb.problems.len(), "problem"));
            format!("{actions}, {problems}, {}", plural(kb.mappings.len(), "mapping"))
        },
    );
    kb.uses_std_domain = uses_std_domain;
    let roots = library::roots(&kb, interner.len(), loaded.files.iter().map(|f| db.text(f.file)), &interner);
    if !roots.is_empty() {
        kb.library = super::timing::time(
            "library",
            || library::library(&kb, roots, db, &mut interner),
            |clauses| plural(clauses.len(), "clause"),
        );
    }
    let tests = kb.problems.iter().filter(|p| p.prelude.is_some()).count();
    if tests > 0 {
        super::timing::time(
            "prelude",
            || prelude::resolve(&mut kb, &mut interner, &mut diags),
            |()| plural(tests, "test"),
        );
    }
    verify_hir(&kb, db, &interner);
    let before = (diags.error_count(), diags.len());
    super::timing::time(
        "check",
        || {
            check::check(&kb, &interner, &mut diags);
            (diags.error_count() - before.0, diags.len() - before.1)
        },
        |(errors, all)| format!("{}, {}", plural(*errors, "error"), plural(all - errors, "other finding")),
    );
    diags.sort_by_position();
    diags.cap_repeats(MAX_REPEATS);
    (Frontend { interner, loaded, kb }, diags)
}

/// Runs the HIR verifier in debug builds and tests; a failure is a compiler bug.
fn verify_hir(kb: &Kb, db: &SourceDb, interner: &Interner) {
    super::verify_after("lower", || hir::verify(kb, db.len()).and_then(|()| hir::verify_names(kb, interner)));
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
pub(super) fn select_problem(kb: &Kb, interner: &Interner, name: Option<&str>) -> Result<usize, Box<Diagnostic>> {
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
