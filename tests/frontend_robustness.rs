//! No input crashes or hangs the front end.
//!
//! Two generators feed it thousands of inputs per run: random soups of KB tokens (including
//! broken ones: unterminated quotes, stray brackets, foreign operators), and real KB files
//! (the examples, std/blocks.pl) with random edits. For every input the front end must return,
//! and what it returns must be well formed:
//!
//! - every label and fix of every diagnostic lies inside its file, on character boundaries;
//! - every diagnostic renders for terminals and as JSON;
//! - when the input has no syntax error, printing the syntax tree and reading the printout
//!   again gives the same printout (the printer and the parser agree);
//! - the parser's fast path for clauses of canonical terms builds exactly what the grammar
//!   builds: the whole file parses to the same tree and the same diagnostics with and without
//!   it.

mod common;

use kbc::diag::{Diagnostic, render};
use kbc::intern::Interner;
use kbc::passes::load::MemoryLoader;
use kbc::source::{SourceDb, Span};
use kbc::syntax::parser::parse_source_by_grammar_only;
use kbc::syntax::{parse_source, printer};
use proptest::prelude::*;

const FRAGMENTS: &[&str] = &[
    "foo",
    "bar",
    "b1",
    "a1",
    "X",
    "Y",
    "_",
    "_Z",
    "(",
    ")",
    "[",
    "]",
    "|",
    ",",
    ".",
    ". ",
    ".\n",
    " ",
    "\n",
    "\n\n",
    ":-",
    "->",
    ";",
    "\\+",
    "=",
    "\\=",
    "==",
    "is",
    "<",
    "=<",
    ">=",
    "=:=",
    "+",
    "-",
    "*",
    "/",
    "//",
    "mod",
    "!=",
    "<=",
    "&&",
    "||",
    "'q",
    "'quoted atom'",
    "'it''s'",
    "\"str",
    "\"a string\"",
    "% comment\n",
    "/*",
    "*/",
    "/* c */",
    "0",
    "1",
    "-2",
    "3.5",
    "1e3",
    "0x1F",
    "0'a",
    "99999999999999999999",
    "go",
    "action",
    "ll_action",
    "mapping",
    "resources",
    "duration",
    "init_state",
    "goal_state",
    "add",
    "del",
    "op",
    "include",
    "dynamic",
    "discontiguous",
    "{",
    "}",
    "@<",
    "=..",
    "é",
    "`",
    "\t",
    "!",
    "f(",
    "g (",
    "Ontable(",
    "'\\q'",
    "'\\x41\\'",
];

fn soup() -> impl Strategy<Value = String> {
    proptest::collection::vec(proptest::sample::select(FRAGMENTS), 0..60).prop_map(|parts| parts.concat())
}

fn corpus() -> Vec<String> {
    let mut texts = vec![kbc::stdlib::STD_BLOCKS.to_string()];
    for path in [
        "examples/01_paper_tests/tests.pl",
        "examples/02_llm_stacking/test_case.pl",
        "examples/03_paper_schema/kb.pl",
        "examples/04_split_kb/parts/actions.pl",
        "examples/05_arm_refinement/kb.pl",
    ] {
        texts.push(std::fs::read_to_string(path).expect("example exists"));
    }
    // And every UI case: each was written to hit one corner of the language.
    let cases = common::files_under("tests/ui", "pl");
    texts.extend(cases.iter().map(|p| std::fs::read_to_string(p).expect("a readable UI case")));
    texts
}

/// How many cases each property runs: 2,000, or `KBC_FUZZ_CASES`.
fn fuzz_cases() -> u32 {
    std::env::var("KBC_FUZZ_CASES").ok().and_then(|n| n.parse().ok()).unwrap_or(2000)
}

#[derive(Debug, Clone)]
enum Edit {
    Delete { at: usize, len: usize },
    Insert { at: usize, fragment: &'static str },
    Duplicate { at: usize, len: usize },
    Swap { at: usize },
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), 1usize..12).prop_map(|(at, len)| Edit::Delete { at, len }),
        (any::<usize>(), proptest::sample::select(FRAGMENTS)).prop_map(|(at, fragment)| Edit::Insert { at, fragment }),
        (any::<usize>(), 1usize..40).prop_map(|(at, len)| Edit::Duplicate { at, len }),
        any::<usize>().prop_map(|at| Edit::Swap { at }),
    ]
}

/// Applies an edit on character positions, so the text stays valid UTF-8.
fn apply(text: &str, edit: &Edit) -> String {
    let chars: Vec<char> = text.chars().collect();
    if chars.is_empty() {
        return text.to_string();
    }
    let n = chars.len();
    let mut out: Vec<char> = chars.clone();
    match *edit {
        Edit::Delete { at, len } => {
            let at = at % n;
            out.drain(at..(at + len).min(n));
        }
        Edit::Insert { at, fragment } => {
            let at = at % (n + 1);
            out.splice(at..at, fragment.chars());
        }
        Edit::Duplicate { at, len } => {
            let at = at % n;
            let piece: Vec<char> = chars[at..(at + len).min(n)].to_vec();
            out.splice(at..at, piece);
        }
        Edit::Swap { at } => {
            let at = at % n;
            if at + 1 < n {
                out.swap(at, at + 1);
            }
        }
    }
    out.into_iter().collect()
}

fn check_span(db: &SourceDb, span: Span, what: &str) -> Result<(), TestCaseError> {
    prop_assert!((span.file.0 as usize) < db.len(), "{what}: unknown file");
    let text = db.text(span.file);
    prop_assert!(span.start <= span.end && span.end as usize <= text.len(), "{what}: {span:?} outside {}", text.len());
    prop_assert!(
        text.is_char_boundary(span.start as usize) && text.is_char_boundary(span.end as usize),
        "{what}: not on a char boundary"
    );
    Ok(())
}

fn check_diagnostic(db: &SourceDb, diagnostic: &Diagnostic) -> Result<(), TestCaseError> {
    for label in &diagnostic.labels {
        check_span(db, label.span, &diagnostic.message)?;
    }
    for fix in &diagnostic.fixes {
        for edit in &fix.edits {
            check_span(db, edit.span, &fix.message)?;
        }
    }
    prop_assert!(diagnostic.code.is_some() || diagnostic.severity == kbc::diag::Severity::Note);
    let rendered = render::to_string(db, diagnostic);
    prop_assert!(rendered.contains(&diagnostic.message), "rendering fell back: {rendered}");
    let json: serde_json::Value =
        serde_json::from_str(&render::to_json(db, diagnostic)).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(json["message"].as_str(), Some(diagnostic.message.as_str()));
    Ok(())
}

fn run_frontend(text: &str) -> Result<(), TestCaseError> {
    let mut db = SourceDb::new();
    let id = db.add("input.pl", Some("input.pl".into()), text.to_string());
    let session = kbc::session::Session::open(db, &[id], &mut MemoryLoader::default());
    for diagnostic in session.diagnostics().iter() {
        check_diagnostic(session.db(), diagnostic)?;
    }
    fast_path_agrees_with_the_grammar(text)?;
    let syntax_error = session.diagnostics().iter().any(|d| d.code.is_some_and(|c| c.as_str().starts_with("E01")));
    if !syntax_error {
        round_trip(text)?;
    }
    Ok(())
}

fn fast_path_agrees_with_the_grammar(text: &str) -> Result<(), TestCaseError> {
    let file = kbc::source::FileId(0);
    let (mut fast_interner, mut fast_diags) = (Interner::new(), kbc::diag::Diagnostics::new());
    let fast = parse_source(file, text, &mut fast_interner, &mut fast_diags);
    let (mut slow_interner, mut slow_diags) = (Interner::new(), kbc::diag::Diagnostics::new());
    let slow = parse_source_by_grammar_only(file, text, &mut slow_interner, &mut slow_diags);
    prop_assert_eq!(fast.clauses.len(), slow.clauses.len(), "clause counts differ on\n{}", text);
    for (a, b) in fast.clauses.iter().zip(&slow.clauses) {
        prop_assert!(
            a == b,
            "the fast path and the grammar disagree on clause {:?} of\n{}\nfast: {:?}\ngrammar: {:?}",
            &text[a.span.start as usize..a.span.end as usize],
            text,
            a,
            b
        );
    }
    fast_diags.sort_by_position();
    slow_diags.sort_by_position();
    prop_assert_eq!(fast_diags.into_vec(), slow_diags.into_vec(), "diagnostics differ on\n{}", text);
    Ok(())
}

/// Printing an error-free parse and reading it back gives the same printout.
fn round_trip(text: &str) -> Result<(), TestCaseError> {
    let mut interner = Interner::new();
    let mut diags = kbc::diag::Diagnostics::new();
    let ast = parse_source(kbc::source::FileId(0), text, &mut interner, &mut diags);
    let printed = printer::print_source(&interner, &ast);
    let mut interner2 = Interner::new();
    let mut diags2 = kbc::diag::Diagnostics::new();
    let reparsed = parse_source(kbc::source::FileId(0), &printed, &mut interner2, &mut diags2);
    prop_assert!(diags2.is_empty(), "the printout of\n{text}\ndoes not read back:\n{printed}\n{diags2:?}");
    prop_assert_eq!(printer::print_source(&interner2, &reparsed), printed);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: fuzz_cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn token_soup_never_breaks_the_front_end(text in soup()) {
        run_frontend(&text)?;
    }

    #[test]
    fn edited_kb_files_never_break_the_front_end(which in 0usize..100_000, edits in proptest::collection::vec(edit(), 1..6)) {
        let corpus = corpus();
        let mut text = corpus[which % corpus.len()].clone();
        for edit in &edits {
            text = apply(&text, edit);
        }
        run_frontend(&text)?;
    }
}

/// A `,` chain of three or more is kept flat in the syntax tree (a body of a million goals is
/// one node); it must mean exactly the right-nested term Prolog reads: as data, as a body, in
/// a declaration, and printed back.
#[test]
fn a_flat_comma_chain_means_the_nested_term() {
    let text = "p((a, b, c, d)).\n\
                p((a, (b, (c, d)))).\n\
                s :- a, (b, c), d.\n\
                v :- a, ((b, c), d).\n\
                u :- a, b, c, d.\n\
                a. b. c. d.\n\
                :- dynamic e/1, f/2, g/3.\n";
    let session = kbc::session::Session::from_text("chain.pl", text);
    assert!(!session.has_errors(), "{:?}", common::messages(session.diagnostics()));
    let kb = session.kb();
    let named = |name: &str| -> Vec<&kbc::ir::hir::Clause> {
        kb.clauses.iter().filter(|c| session.interner().resolve(c.head.name()) == name).collect()
    };
    let facts = named("p");
    assert_eq!(facts.len(), 2);
    assert_eq!(facts[0].head.term, facts[1].head.term, "a flat chain as data is the nested term");
    // The shape of a body: its conjunctions and calls, without spans.
    fn shape(goal: &kbc::ir::hir::Goal) -> String {
        match goal {
            kbc::ir::hir::Goal::And(goals) => format!("and({})", goals.iter().map(shape).collect::<Vec<_>>().join(",")),
            kbc::ir::hir::Goal::Call(_) => "call".into(),
            other => format!("{other:?}"),
        }
    }
    let body = |name: &str| shape(named(name)[0].body.as_deref().expect("a rule"));
    assert_eq!(body("s"), body("v"), "a chain with a parenthesised conjunction in it");
    assert_eq!(body("s"), "and(call,and(call,call),call)");
    assert_eq!(body("u"), "and(call,call,call,call)");
    let declared: Vec<&str> = kb.declarations.iter().map(|d| session.interner().resolve(d.name)).collect();
    assert_eq!(declared, ["e", "f", "g"]);
    let mut interner = Interner::new();
    let mut diags = kbc::diag::Diagnostics::new();
    let ast = parse_source(kbc::source::FileId(0), "x :- a, b, (c ; d), e.\n", &mut interner, &mut diags);
    assert_eq!(printer::print_source(&interner, &ast).trim(), "x :- a, b, (c ; d), e.");
}

/// `;` and `->` chains are flat too, in the syntax tree and in the HIR (a disjunction of
/// 100,000 branches is one node); they must mean the right-nested terms Prolog reads, with
/// if-then-else branches where `->` stands left of `;`.
#[test]
fn flat_disjunctions_and_if_then_chains_mean_the_nested_terms() {
    let text = "p((a ; b ; c ; d)).\n\
                p((a ; (b ; (c ; d)))).\n\
                q((a -> b -> c)).\n\
                q((a -> (b -> c))).\n\
                s :- ( a ; b -> c ; d ; e -> f -> g ).\n\
                v :- ( a ; ((b -> c) ; (d ; (e -> (f -> g))))).\n\
                w :- ( (a ; b) ; (c -> d ; e) ; f ).\n\
                a. b. c. d. e. f. g.\n";
    let session = kbc::session::Session::from_text("chains.pl", text);
    assert!(!session.has_errors(), "{:?}", common::messages(session.diagnostics()));
    let kb = session.kb();
    let named = |name: &str| -> Vec<&kbc::ir::hir::Clause> {
        kb.clauses.iter().filter(|c| session.interner().resolve(c.head.name()) == name).collect()
    };
    for data in ["p", "q"] {
        let facts = named(data);
        assert_eq!(facts.len(), 2);
        assert_eq!(facts[0].head.term, facts[1].head.term, "a flat `{data}` chain as data is the nested term");
    }
    // The shape of a body: its disjunctions (branches as `conditions->goal`) and calls.
    fn shape(goal: &kbc::ir::hir::Goal) -> String {
        use kbc::ir::hir::Goal;
        match goal {
            Goal::Or(branches) => {
                let branch = |b: &kbc::ir::hir::Branch| {
                    b.conditions.iter().map(|c| format!("{}->", shape(c))).collect::<String>() + &shape(&b.goal)
                };
                format!("or({})", branches.iter().map(branch).collect::<Vec<_>>().join(","))
            }
            Goal::Call(_) => "call".into(),
            other => format!("{other:?}"),
        }
    }
    let body = |name: &str| shape(named(name)[0].body.as_deref().expect("a rule"));
    assert_eq!(body("s"), "or(call,call->call,call,call->call->call)");
    assert_eq!(body("s"), body("v"), "the same disjunction, nested to the right");
    // A parenthesised disjunction left of `;` is a branch of its own: `f` is still tried
    // after `c -> d ; e` has committed to `d`.
    assert_eq!(body("w"), "or(or(call,call),or(call->call,call),call)");
    let mut interner = Interner::new();
    let mut diags = kbc::diag::Diagnostics::new();
    let source = "x :- (a ; b -> c ; d), (e -> f -> g), ((h ; i) ; j).\n";
    let ast = parse_source(kbc::source::FileId(0), source, &mut interner, &mut diags);
    assert_eq!(printer::print_source(&interner, &ast).trim(), source.trim());
}
