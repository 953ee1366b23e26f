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
/// only), the standard blocks world (std/blocks.pl) is loaded first as the domain, and a note
/// says so.
pub fn frontend(db: &mut SourceDb, roots: &[FileId], loader: &mut dyn SourceLoader) -> Frontend {
    let mut interner = Interner::new();
    let mut diags = Diagnostics::new();
    let user = load::load(roots, db, &mut interner, loader, &mut diags);
    let mut declares_actions = false;
    let mut declares_problems = false;
    for clause in user.clauses() {
        let (head, body) = match &clause.term.kind {
            TermKind::Compound(rule) if rule.functor == sym::NECK && rule.args.len() == 2 => {
                (&rule.args[0], Some(&rule.args[1]))
            }
            _ => (&clause.term, None),
        };
        declares_actions |= matches!(head.callable(), Some((sym::ACTION | sym::LL_ACTION, _)));
        declares_problems |= matches!(head.callable(), Some((sym::INIT_STATE | sym::GOAL_STATE, 1)))
            || body.is_some_and(|b| matches!(b.callable(), Some((sym::GO, _))));
    }
    let mut uses_std_domain = false;
    let loaded = if declares_actions || !declares_problems {
        user
    } else {
        uses_std_domain = true;
        diags.push(Diagnostic::note(
            "no action schemas given: using the standard multi-arm blocks world (std/blocks.pl)",
        ));
        let std_file = db.add(STD_BLOCKS_NAME, None, STD_BLOCKS);
        let std = load::load(&[std_file], db, &mut interner, &mut NoIncludes, &mut diags);
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
