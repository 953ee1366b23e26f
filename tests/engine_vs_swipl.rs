//! The resolution engine against SWI-Prolog on a corpus of queries.
//!
//! Both load tests/engine/program.pl; for each `q(N, Template, Goal)` of
//! tests/engine/queries.pl both produce every solution of `Goal` as `Template`, in order, or
//! the kind of error (`instantiation_error`, `type_error`, `domain_error`, `evaluation_error`). The answers
//! are compared as terms, with variables renamed by first occurrence and floats compared to
//! twelve significant digits. Skips, saying so, where `swipl` is absent (`.ci/run` installs it).

use std::collections::BTreeMap;
use std::process::Command;

use kbc::diag::Diagnostics;
use kbc::engine::{EngineError, Machine, Next, Program};
use kbc::intern::Interner;
use kbc::ir::hir::Term;
use kbc::passes::load::MemoryLoader;
use kbc::source::{FileId, SourceDb};
use kbc::syntax::printer::TermView;

/// An answer, normalised for comparison.
#[derive(Debug, PartialEq)]
enum Answer {
    Solutions(Vec<String>),
    Error(String),
}

/// Prints a term with floats rounded and variables renamed `_V0`, `_V1`, ... in order.
fn normalise(interner: &Interner, term: &Term) -> String {
    fn walk(interner: &Interner, term: &Term, names: &mut Vec<u32>, out: &mut String) {
        match term {
            Term::Var(v) => {
                let index = names.iter().position(|&n| n == v.0).unwrap_or_else(|| {
                    names.push(v.0);
                    names.len() - 1
                });
                out.push_str(&format!("_V{index}"));
            }
            Term::Float(f) => out.push_str(&format!("{:.12e}", f)),
            Term::Compound(f, args) => {
                out.push_str(interner.resolve(*f));
                out.push('(');
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    walk(interner, a, names, out);
                }
                out.push(')');
            }
            Term::Int(i) => out.push_str(&i.to_string()),
            Term::Atom(s) | Term::Str(s) => out.push_str(interner.resolve(*s)),
        }
    }
    let mut out = String::new();
    walk(interner, term, &mut Vec::new(), &mut out);
    out
}

/// Lowers a syntax-tree term to a HIR term (variables numbered by first occurrence).
fn lower(term: &kbc::syntax::ast::Term, names: &mut Vec<kbc::intern::Symbol>, interner: &Interner) -> Term {
    use kbc::syntax::printer::View;
    match term.view(interner) {
        View::Var(_) => {
            let kbc::syntax::ast::TermKind::Var(name) = term.kind else { unreachable!() };
            // `_` alone is anonymous; SWI-Prolog prints other variables as `_123`, the same name
            // for the same variable.
            let anonymous = interner.resolve(name) == "_";
            let index = if anonymous { None } else { names.iter().position(|&n| n == name) };
            let index = index.unwrap_or_else(|| {
                names.push(name);
                names.len() - 1
            });
            Term::Var(kbc::ir::hir::VarId(index as u32))
        }
        View::Atom(s) => Term::Atom(s),
        View::Int(i) => Term::Int(i),
        View::Float(f) => Term::Float(f),
        View::Str(s) => Term::Str(s),
        View::Compound(f, args) => Term::Compound(f, args.iter().map(|a| lower(a, names, interner)).collect()),
        View::Chain(f, operands) => Term::xfy(f, operands.iter().map(|a| lower(a, names, interner)).collect()),
        View::List(items, tail) => {
            let mut list = match tail {
                Some(t) => lower(t, names, interner),
                None => Term::Atom(kbc::intern::sym::NIL),
            };
            for item in items.iter().rev() {
                let item = lower(item, names, interner);
                list = Term::Compound(kbc::intern::sym::CONS, kbc::ir::hir::Args::from([item, list]));
            }
            list
        }
        View::Error => panic!("SWI-Prolog printed something kbc cannot read"),
    }
}

fn kbc_answers() -> (BTreeMap<i64, Answer>, Interner) {
    let mut db = SourceDb::new();
    let program = db.add("program.pl", None, std::fs::read_to_string("tests/engine/program.pl").expect("corpus"));
    let queries = db.add("queries.pl", None, std::fs::read_to_string("tests/engine/queries.pl").expect("corpus"));
    let (_, frontend, _) =
        kbc::session::Session::open(db, &[program, queries], &mut MemoryLoader::default()).into_parts();
    let program = Program::new(&frontend.kb, &frontend.interner, &[]);
    let mut machine = Machine::new(&program, 1_000_000);
    let mut answers = BTreeMap::new();
    for clause in &frontend.kb.clauses {
        let Term::Compound(name, args) = &clause.head.term else { continue };
        if frontend.interner.resolve(*name) != "q" || args.len() != 3 {
            continue;
        }
        let Term::Int(number) = args[0] else { panic!("q/3 needs a number") };
        machine.reset();
        let mut vars = vec![None; clause.vars.len()];
        let template = machine.put_term(&args[1], &mut vars);
        let goal = machine.put_term(&args[2], &mut vars);
        let mut solutions = Vec::new();
        let result = machine.solve(goal, |m| {
            let mut names = Vec::new();
            solutions.push(normalise(&frontend.interner, &m.read(template, &mut names)));
            Next::More
        });
        let answer = match result {
            Ok(_) => Answer::Solutions(solutions),
            Err(EngineError::Instantiation { .. }) => Answer::Error("instantiation_error".into()),
            Err(EngineError::Type { .. } | EngineError::NotCallable { .. }) => Answer::Error("type_error".into()),
            Err(EngineError::ZeroDivisor | EngineError::Evaluation { .. }) => Answer::Error("evaluation_error".into()),
            Err(EngineError::Domain { .. }) => Answer::Error("domain_error".into()),
            Err(EngineError::Budget { .. } | EngineError::Nesting) => Answer::Error("budget".into()),
        };
        answers.insert(number, answer);
    }
    (answers, frontend.interner)
}

fn swipl_answers(interner: &mut Interner) -> BTreeMap<i64, Answer> {
    let output = Command::new("swipl")
        .args(["-q", "tests/engine/program.pl", "tests/engine/queries.pl", "tests/engine/driver.pl"])
        .output()
        .expect("swipl runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let mut answers = BTreeMap::new();
    for line in stdout.lines() {
        let mut parts = line.splitn(3, ' ');
        let (Some(number), Some(kind), Some(rest)) = (parts.next(), parts.next(), parts.next()) else { continue };
        let number: i64 = number.parse().expect("query number");
        if kind == "error" {
            answers.insert(number, Answer::Error(rest.to_string()));
            continue;
        }
        let mut diags = Diagnostics::new();
        let ast = kbc::syntax::parse_source(FileId(0), &format!("a({rest})."), interner, &mut diags);
        assert!(diags.is_empty(), "cannot read SWI-Prolog's answer {rest}: {diags:?}");
        let list = &ast.clauses[0].term.args()[0];
        let kbc::syntax::ast::TermKind::List(items) = &list.kind else { panic!("findall gives a list") };
        let solutions = items
            .items
            .iter()
            .map(|item| {
                let mut names = Vec::new();
                normalise(interner, &lower(item, &mut names, interner))
            })
            .collect();
        answers.insert(number, Answer::Solutions(solutions));
    }
    answers
}

#[test]
fn the_engine_answers_every_query_as_swi_prolog_does() {
    if Command::new("swipl").arg("--version").output().is_err() {
        eprintln!("skipped: swipl is not installed (apt-get install swi-prolog-nox)");
        return;
    }
    let (ours, mut interner) = kbc_answers();
    let theirs = swipl_answers(&mut interner);
    assert!(ours.len() >= 70, "the corpus has {} queries", ours.len());
    assert_eq!(ours.keys().collect::<Vec<_>>(), theirs.keys().collect::<Vec<_>>(), "both answer the same queries");
    let differences: Vec<String> = ours
        .iter()
        .filter(|(n, answer)| theirs.get(n) != Some(answer))
        .map(|(n, answer)| format!("query {n}: kbc {answer:?}, swipl {:?}", theirs[n]))
        .collect();
    assert!(differences.is_empty(), "the engine and SWI-Prolog disagree:\n{}", differences.join("\n"));
}
