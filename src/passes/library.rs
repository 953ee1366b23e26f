//! The library a KB calls: the clauses of std/library.pl (`crate::stdlib::STD_LIBRARY`) for the
//! predicates the KB's text names, directly or through those clauses, and does not define
//! itself.
//!
//! A predicate is reached by name alone, whatever arity it is named with and wherever the name
//! stands (a goal, an argument of `maplist/2`, an atom in a fact a goal is built from with
//! `=..`), so no call the engine can make misses its clauses; a KB that names none loads
//! nothing. The names of the `sym` module are interned for every KB, so for those (`include`,
//! a directive's name too) the KB's terms are searched instead. As with SWI-Prolog's
//! autoloader, a predicate the KB defines (a clause, a `dynamic` declaration, a problem's goal
//! fact, which the paper's planner asserts) is the KB's own.

use rustc_hash::{FxHashMap, FxHashSet};

use super::load::{self, NoIncludes};
use super::lower;
use crate::builtins::{self, Imp};
use crate::diag::Diagnostics;
use crate::intern::{Interner, Symbol};
use crate::ir::hir::{Clause, DeclarationKind, Goal, Kb, Term};
use crate::source::SourceDb;
use crate::stdlib;

/// The library predicates (by name) the KB names: those whose names the KB's files interned
/// (`named`: how many symbols the interner held once the KB was lowered), and, for the names
/// the `sym` module interns for every KB, those that some term of the KB holds (looked for
/// only where a file's text has the name). `texts` are the files' texts.
pub fn roots<'t>(kb: &Kb, named: usize, texts: impl Iterator<Item = &'t str>, interner: &Interner) -> Vec<Symbol> {
    let names: Vec<(Symbol, &str)> = builtins::PREDICATES
        .iter()
        .filter(|b| b.imp == Imp::Prolog)
        .filter_map(|b| Some((interner.get(b.name)?, b.name)))
        .collect();
    let mut roots: Vec<Symbol> =
        names.iter().map(|&(s, _)| s).filter(|s| (s.0 as usize) < named && !Interner::is_well_known(*s)).collect();
    let texts: Vec<&str> = texts.collect();
    let maybe: FxHashSet<Symbol> = names
        .iter()
        .filter(|(s, name)| Interner::is_well_known(*s) && texts.iter().any(|t| t.contains(name)))
        .map(|&(s, _)| s)
        .collect();
    if !maybe.is_empty() {
        let mut found: Vec<Symbol> = Vec::new();
        kb_names(kb, &mut found);
        roots.extend(found.into_iter().filter(|s| maybe.contains(s)));
    }
    roots.sort();
    roots.dedup();
    roots
}

/// Every atom and functor name of the KB's clauses, actions and problems.
fn kb_names(kb: &Kb, out: &mut Vec<Symbol>) {
    for clause in &kb.clauses {
        term_names(&clause.head.term, out);
        if let Some(body) = &clause.body {
            goal_names(body, out);
        }
    }
    for action in &kb.actions {
        for literal in action.valid.iter().chain(&action.invalid).chain(&action.invalid_at_end) {
            term_names(&literal.term, out);
        }
        action.on_kb.iter().for_each(|g| goal_names(g, out));
        action.effects.iter().for_each(|e| term_names(&e.literal.term, out));
    }
    for problem in &kb.problems {
        problem.initial_facts().chain(&problem.goal).for_each(|l| term_names(&l.term, out));
        if let Some(prelude) = &problem.prelude {
            prelude.goals.iter().for_each(|g| goal_names(g, out));
            [&prelude.init, &prelude.goal].into_iter().for_each(|t| term_names(t, out));
        }
    }
}

/// The library clauses `kb` calls, from the predicates `roots` names (see [`roots`]), in the
/// library's order.
pub fn library(kb: &Kb, roots: Vec<Symbol>, db: &mut SourceDb, interner: &mut Interner) -> Vec<Clause> {
    let file = db.add(stdlib::STD_LIBRARY_NAME, None, stdlib::STD_LIBRARY);
    let mut diags = Diagnostics::new();
    let loaded = load::load(&[file], db, interner, &mut NoIncludes, &mut diags);
    let library = lower::lower_library(&loaded, db, interner, &mut diags);
    if diags.has_errors() {
        // Only a clause-length limit lowered far below the default (`KBC_MAX_CLAUSE_TOKENS`)
        // can make the library fail to read; half a library would answer wrongly, so none is
        // loaded and its predicates are reported unknown.
        return Vec::new();
    }
    debug_assert!(diags.is_empty(), "std/library.pl is clean: {diags:?}");
    let mut defined: FxHashSet<(Symbol, usize)> = kb.clauses.iter().map(|c| (c.head.name(), c.head.arity())).collect();
    defined.extend(kb.declarations.iter().filter(|d| d.kind == DeclarationKind::Dynamic).map(|d| (d.name, d.arity)));
    defined.extend(kb.problems.iter().flat_map(|p| p.goal.iter().map(|l| (l.name(), l.arity()))));
    // The library's clauses by the name of their head.
    let mut by_name: FxHashMap<Symbol, Vec<usize>> = FxHashMap::default();
    for (index, clause) in library.clauses.iter().enumerate() {
        by_name.entry(clause.head.name()).or_default().push(index);
    }
    let mut reached: FxHashSet<Symbol> = FxHashSet::default();
    let mut pending: Vec<Symbol> = roots.into_iter().filter(|s| by_name.contains_key(s)).collect();
    while let Some(name) = pending.pop() {
        if !reached.insert(name) {
            continue;
        }
        for &index in &by_name[&name] {
            let clause = &library.clauses[index];
            let mut names = Vec::new();
            if let Some(body) = &clause.body {
                goal_names(body, &mut names);
            }
            pending.extend(names.into_iter().filter(|s| by_name.contains_key(s) && !reached.contains(s)));
        }
    }
    library
        .clauses
        .into_iter()
        .filter(|c| reached.contains(&c.head.name()) && !defined.contains(&(c.head.name(), c.head.arity())))
        .collect()
}

/// Every atom and functor name in the terms a goal calls.
fn goal_names(goal: &Goal, out: &mut Vec<Symbol>) {
    goal.for_each_call(&mut |l| term_names(&l.term, out));
}

fn term_names(term: &Term, out: &mut Vec<Symbol>) {
    let mut pending = vec![term];
    while let Some(term) = pending.pop() {
        match term {
            Term::Atom(s) => out.push(*s),
            Term::Compound(f, args) => {
                out.push(*f);
                pending.extend(args.iter());
            }
            _ => {}
        }
    }
}
