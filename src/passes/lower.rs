//! Pass `lower`: the clauses of the loaded files become a resolved KB ([`hir::Kb`]).
//!
//! Each clause is sorted by what it means in the paper's model: `action/6` and `ll_action/6`
//! schemas, `mapping/2`, `resources/1`, problems (`init_state/1` with `goal_state/1`, and
//! tests `Name :- go(Init, Goal)` with `go/4` and `go/5`), directives, and everything else as
//! the static program. Lowering reports what is wrong with the *shape* of each item (an action
//! with five slots, a slot that is not a list, an effect that is not `add`/`del`, a problem
//! without a goal, a non-ground init fact) and the per-clause variable warnings that
//! SWI-Prolog gives (singletons). Checks that need the whole KB (names, pairing of `_start`
//! and `_end`) are in `passes::check`.
//!
//! Variables are numbered per clause in order of first occurrence, so items that are equal up
//! to renaming lower to equal terms.

use rustc_hash::{FxHashMap, FxHashSet};

use super::load::Loaded;
use crate::diag::{Diagnostic, Diagnostics, Edit, codes, plural};
use crate::intern::{Interner, Symbol, sym};
use crate::ir::hir::{
    self, Action, Args, Branch, Clause, Declaration, DeclarationKind, Effect, EffectKind, Goal, HeadSite, Kb, Level,
    Literal, Mapping, MetaCall, Prelude, Problem, ProblemForm, Resource, SLOT_NAMES, Snap, Term, VarId, VarInfo,
    VarTable,
};
use crate::source::{FileId, SourceDb, Span};
use crate::syntax::ast::{self, Notation, TermKind};
use crate::syntax::printer::term_to_string;

/// Lowers the loaded clauses (in program order) into a KB.
pub fn lower(loaded: &Loaded, db: &SourceDb, interner: &mut Interner, diags: &mut Diagnostics) -> Kb {
    lower_as(loaded, db, interner, diags, false)
}

/// Lowers std/library.pl, which defines built-ins a KB may not (`bagof/3`, `setof/3`): its
/// clauses are the KB's [`Kb::clauses`] of the result.
pub fn lower_library(loaded: &Loaded, db: &SourceDb, interner: &mut Interner, diags: &mut Diagnostics) -> Kb {
    lower_as(loaded, db, interner, diags, true)
}

fn lower_as(loaded: &Loaded, db: &SourceDb, interner: &mut Interner, diags: &mut Diagnostics, library: bool) -> Kb {
    let mut lowerer = Lowerer {
        interner,
        diags,
        db,
        kb: Kb::default(),
        state_files: Vec::new(),
        arm_state_files: Vec::new(),
        library,
        defined: FxHashSet::default(),
    };
    // The predicates the files define: a library predicate they define is theirs, so a call
    // of it is a plain call, whatever the library's version calls.
    for clause in loaded.clauses() {
        let head = match clause.term.as_compound(sym::NECK, 2) {
            Some(rule) => &rule.args[0],
            None if clause.term.as_compound(sym::NECK, 1).is_some() => continue,
            None => &clause.term,
        };
        if let Some(key) = head.callable() {
            lowerer.defined.insert(key);
        }
    }
    for clause in loaded.clauses() {
        lowerer.clause(clause);
    }
    lowerer.finish_init_goal_states();
    lowerer.finish_arm_states();
    lowerer.check_open_init();
    lowerer.unpair_mismatched_arities();
    lowerer.kb
}

/// The variables of the clause being lowered.
#[derive(Default)]
struct Scope {
    table: VarTable,
    by_name: FxHashMap<Symbol, VarId>,
}

impl Scope {
    fn var(&mut self, name: Symbol, span: Span) -> VarId {
        if name != sym::ANON
            && let Some(&id) = self.by_name.get(&name)
        {
            self.table.vars[id.0 as usize].occurrences.push(span);
            return id;
        }
        let id = VarId(self.table.vars.len() as u32);
        self.table.vars.push(VarInfo { name, occurrences: vec![span] });
        if name != sym::ANON {
            self.by_name.insert(name, id);
        }
        id
    }
}

/// Parts of an `init_state`/`goal_state` problem, collected per file.
struct StateFile {
    file: FileId,
    init: Option<(Vec<Literal>, Span)>,
    goal: Option<(Vec<Literal>, Span)>,
    scope: Scope,
}

struct Lowerer<'a> {
    interner: &'a mut Interner,
    diags: &'a mut Diagnostics,
    db: &'a SourceDb,
    kb: Kb,
    state_files: Vec<StateFile>,
    /// The same for `ll_init/1` and `ll_goal/1`.
    arm_state_files: Vec<StateFile>,
    /// Whether this is std/library.pl, which may define the built-ins it implements.
    library: bool,
    /// The predicates the files define (clause heads).
    defined: FxHashSet<(Symbol, usize)>,
}

impl Lowerer<'_> {
    fn show(&self, term: &ast::Term) -> String {
        let text = term_to_string(self.interner, term);
        if text.chars().count() > 60 {
            let cut: String = text.chars().take(57).collect();
            format!("{cut}...")
        } else {
            text
        }
    }

    fn clause(&mut self, clause: &ast::Clause) {
        let term = &clause.term;
        if clause.recovered {
            self.record_recovered_names(term);
            return;
        }
        if let Some(c) = term.as_compound(sym::NECK, 1)
            && c.notation == Notation::Prefix
        {
            self.directive(&c.args[0]);
            return;
        }
        if let Some(c) = term.as_compound(sym::NECK, 2) {
            self.rule(&c.args[0], &c.args[1], clause.span);
            return;
        }
        self.fact(term, clause.span);
    }

    /// Remembers every predicate named in a clause that failed to parse.
    fn record_recovered_names(&mut self, term: &ast::Term) {
        if let Some(callable) = term.callable() {
            self.kb.recovered_names.push(callable);
        }
        match &term.kind {
            TermKind::Compound(c) => c.args.iter().for_each(|a| self.record_recovered_names(a)),
            TermKind::List(l) => l.items.iter().for_each(|a| self.record_recovered_names(a)),
            _ => {}
        }
    }

    fn head_site(&mut self, head: &ast::Term) {
        if let Some((name, arity)) = head.callable() {
            self.kb.head_sites.push(HeadSite { file: head.span.file, name, arity, span: head.name_span() });
        }
    }

    // ---- terms ----------------------------------------------------------------------------

    fn term(&mut self, t: &ast::Term, scope: &mut Scope) -> hir::Term {
        match &t.kind {
            TermKind::Atom(s) => hir::Term::Atom(*s),
            TermKind::Var(s) => hir::Term::Var(scope.var(*s, t.span)),
            TermKind::Int(i) => hir::Term::Int(*i),
            TermKind::Float(f) => hir::Term::Float(*f),
            TermKind::Str(s) => hir::Term::Str(*s),
            // A flat chain is the right-nested binary term it stands for.
            TermKind::Compound(c) if c.notation == ast::Notation::Chain => {
                hir::Term::xfy(c.functor, c.args.iter().map(|a| self.term(a, scope)).collect())
            }
            TermKind::Compound(c) => {
                hir::Term::Compound(c.functor, c.args.iter().map(|a| self.term(a, scope)).collect())
            }
            TermKind::List(l) => {
                // Cell by cell from the front, in source order (variables are numbered as they
                // occur), without a second list of the items: a list of a million is 48 MB of
                // cells already.
                let mut list = hir::Term::Atom(sym::NIL);
                let mut slot = &mut list;
                for item in &l.items {
                    let item = self.term(item, scope);
                    *slot = hir::Term::Compound(sym::CONS, hir::Args::from([item, hir::Term::Atom(sym::NIL)]));
                    let hir::Term::Compound(_, cell) = slot else { unreachable!("just made a cell") };
                    slot = &mut cell[1];
                }
                if let Some(tail) = &l.tail {
                    *slot = self.term(tail, scope);
                }
                list
            }
            // Clauses with errors are not lowered.
            TermKind::Error => hir::Term::Atom(sym::ANON),
        }
    }

    /// A literal: an atom or compound. Reports anything else.
    fn literal(&mut self, t: &ast::Term, scope: &mut Scope, what: &str) -> Option<Literal> {
        if t.callable().is_none() {
            let found = describe_non_callable(t);
            let mut diagnostic = Diagnostic::error(codes::NOT_CALLABLE, format!("expected {what}, found {found}"))
                .primary(t.span, "not an atom or compound term");
            if matches!(t.kind, TermKind::Var(_)) {
                diagnostic = diagnostic
                    .with_note("a variable cannot stand for a literal: kbc does not call terms built at run time");
            }
            self.diags.push(diagnostic);
            return None;
        }
        let term = self.term(t, scope);
        Some(Literal { term, span: t.span, name_span: t.name_span() })
    }

    /// The items of a proper list, or a diagnostic naming `what` the list is.
    fn list<'t>(&mut self, t: &'t ast::Term, what: impl Fn() -> String) -> Option<&'t [ast::Term]> {
        match &t.kind {
            TermKind::List(l) if l.tail.is_none() => Some(&l.items),
            TermKind::List(l) => {
                let tail = l.tail.as_ref().expect("checked above");
                self.diags.push(
                    Diagnostic::error(codes::SLOT_NOT_LIST, format!("{} must be a proper list", what()))
                        .primary(tail.span, "a list with an open tail")
                        .with_help("list the elements without `|Tail`"),
                );
                None
            }
            _ => {
                let found = self.show(t);
                self.diags.push(
                    Diagnostic::error(codes::SLOT_NOT_LIST, format!("{} must be a list, found `{found}`", what()))
                        .primary(t.span, "expected a list `[...]`")
                        .with_help(format!("write `[{found}]`, or `[]` for none")),
                );
                None
            }
        }
    }

    /// A branch of a disjunction: `G`, or the if-then `C1 -> C2 -> ... -> G`.
    fn branch(&mut self, t: &ast::Term, scope: &mut Scope) -> Option<Branch> {
        let mut parts: Vec<Option<Goal>> =
            t.xfy_operands(sym::ARROW).into_iter().map(|g| self.goal(g, scope)).collect();
        let goal = parts.pop().flatten();
        let conditions = parts.into_iter().collect::<Option<Vec<_>>>();
        Some(Branch { conditions: conditions?, goal: goal? })
    }

    fn goal(&mut self, t: &ast::Term, scope: &mut Scope) -> Option<Goal> {
        if let TermKind::Compound(c) = &t.kind {
            match (c.functor, t.callable().map_or(0, |(_, arity)| arity)) {
                (sym::COMMA, 2) => {
                    // However the conjunction is written (flat, nested to the right): its goals.
                    let goals: Vec<Option<Goal>> =
                        t.xfy_operands(sym::COMMA).into_iter().map(|g| self.goal(g, scope)).collect();
                    return goals.into_iter().collect::<Option<Vec<_>>>().map(Goal::And);
                }
                (sym::SEMI | sym::ARROW, 2) => {
                    // However the disjunction is written (flat, nested to the right): its
                    // branches, each `G` or `C1 -> ... -> G`. Every branch is lowered, so
                    // every error in them is reported.
                    let branches: Vec<Option<Branch>> =
                        t.xfy_operands(sym::SEMI).into_iter().map(|b| self.branch(b, scope)).collect();
                    return branches.into_iter().collect::<Option<Vec<_>>>().map(Goal::Or);
                }
                (sym::NOT_PROVABLE | sym::NOT, 1) => {
                    return self.goal(&c.args[0], scope).map(|g| Goal::Not(Box::new(g)));
                }
                // A module-qualified goal (`lists:append(A, B, C)`): kbc has no modules, so
                // every predicate is the KB's or the library's, which is what the goal calls.
                (sym::COLON, 2) if matches!(c.args[0].kind, TermKind::Atom(_)) => {
                    return self.goal(&c.args[1], scope);
                }
                _ => {}
            }
        }
        if let TermKind::Var(_) = t.kind {
            // A variable as a goal is called: Prolog reads `G` in a body as `call(G)`.
            let call = self.interner.intern("call");
            let term = Term::Compound(call, Args::from([self.term(t, scope)]));
            let call = Literal { term, span: t.span, name_span: t.span };
            return Some(Goal::Meta(Box::new(MetaCall { call, called: Vec::new() })));
        }
        let literal = self.literal(t, scope, "a goal")?;
        Some(match self.meta_call(&literal, t) {
            Some(meta) => Goal::Meta(Box::new(meta)),
            None => Goal::Call(literal),
        })
    }

    /// The built-in a call of `name/arity` calls: none for a library predicate the files
    /// define themselves.
    fn builtin_called(&self, name: Symbol, arity: usize) -> Option<&'static crate::builtins::Builtin> {
        let builtin = crate::builtins::lookup(self.interner, name, arity)?;
        let own = builtin.kind == crate::builtins::Kind::Library && self.defined.contains(&(name, arity));
        (!own).then_some(builtin)
    }

    /// A call of a built-in that calls some of its arguments (`findall/3`, `maplist/2`, ...)
    /// with the literals it may call ([`MetaCall`]); `None` for any other literal. `t` is the
    /// literal's syntax, for the spans of the literals called (the call's own spans where the
    /// two do not line up).
    fn meta_call(&self, literal: &Literal, t: &ast::Term) -> Option<MetaCall> {
        let builtin = self.builtin_called(literal.name(), literal.arity())?;
        if builtin.calls.is_empty() || builtin.imp == crate::builtins::Imp::Engine {
            return None; // not a meta call, or a control construct, lowered as such
        }
        let mut pending: Vec<(&Term, Option<&ast::Term>, usize)> = Vec::new();
        for c in builtin.calls.iter().rev() {
            pending.push((&literal.term.args()[c.arg], t.args().get(c.arg), c.extra));
        }
        let mut called = Vec::new();
        while let Some((term, syntax, extra)) = pending.pop() {
            // A variable or a number: what is called is known only at run time.
            let Some((name, arity)) = term.callable() else { continue };
            let syntax = syntax.filter(|s| s.callable() == Some((name, arity)));
            // `Module:Goal` calls the goal (kbc has no modules), with the arguments appended.
            if (name, arity) == (sym::COLON, 2) && matches!(term.args()[0], Term::Atom(_)) {
                pending.push((&term.args()[1], syntax.and_then(|s| s.args().get(1)), extra));
                continue;
            }
            if extra == 0 {
                let operands: Option<Vec<&Term>> = match (name, arity) {
                    (sym::COMMA | sym::SEMI | sym::ARROW, 2) => Some(term.xfy_operands(name)),
                    (sym::NOT_PROVABLE | sym::NOT, 1) => Some(vec![&term.args()[0]]),
                    _ => None,
                };
                if let Some(operands) = operands {
                    let syntax: Option<Vec<&ast::Term>> = syntax.map(|s| match arity {
                        2 => s.xfy_operands(name),
                        _ => s.args().iter().collect(),
                    });
                    let syntax = syntax.filter(|s| s.len() == operands.len());
                    for (i, operand) in operands.into_iter().enumerate().rev() {
                        pending.push((operand, syntax.as_ref().map(|s| s[i]), 0));
                    }
                    continue;
                }
            }
            let (span, name_span) = syntax.map_or((literal.span, literal.name_span), |s| (s.span, s.name_span()));
            called.push((Literal { term: term.clone(), span, name_span }, extra));
            if let Some(inner) = self.builtin_called(name, arity + extra) {
                for c in inner.calls.iter().rev().filter(|c| c.arg < arity) {
                    pending.push((&term.args()[c.arg], syntax.and_then(|s| s.args().get(c.arg)), c.extra));
                }
            }
        }
        Some(MetaCall { call: literal.clone(), called })
    }

    // ---- clauses --------------------------------------------------------------------------

    fn directive(&mut self, goal: &ast::Term) {
        let Some((name, arity)) = goal.callable() else {
            self.diags.push(
                Diagnostic::warning(codes::IGNORED_DIRECTIVE, "directive ignored: it is not a goal")
                    .primary(goal.span, "not an atom or compound term"),
            );
            return;
        };
        match (name, arity) {
            (sym::DYNAMIC, 1) | (sym::DISCONTIGUOUS, 1) => {
                let kind = if name == sym::DYNAMIC { DeclarationKind::Dynamic } else { DeclarationKind::Discontiguous };
                self.declarations(kind, &goal.args()[0]);
            }
            (sym::OP, 3) => {
                self.diags.push(
                    Diagnostic::error(codes::UNSUPPORTED_OPERATOR, "user-defined operators are not supported")
                        .primary(goal.span, "`op/3` changes how the rest of the file reads")
                        .with_note("kbc reads a fixed operator table, so every KB reads the same way in every tool (docs/dsl.md)")
                        .with_help("remove the directive and write the terms in canonical form, e.g. `holds(A, B)`"),
                );
            }
            // The SWI-Prolog libraries whose predicates kbc provides (src/builtins.rs).
            (sym::USE_MODULE, 1 | 2)
                if goal.args()[0].as_compound(sym::LIBRARY, 1).is_some_and(|l| match l.args[0].kind {
                    TermKind::Atom(name) => ["lists", "apply", "aggregate", "pairs", "ordsets", "error"]
                        .contains(&self.interner.resolve(name)),
                    _ => false,
                }) => {}
            (sym::MODULE, 2) => {
                // A file of a KB split into modules: its clauses are the KB's all the same.
                let shown = self.show(&goal.args()[0]);
                self.diags.push(
                    Diagnostic::note(format!("module `{shown}` read as plain clauses"))
                        .primary(goal.span, "kbc has no modules: every file's clauses are one KB")
                        .with_note("`use_module/1` of a file loads it once, as `ensure_loaded/1` does"),
                );
            }
            _ if crate::builtins::is_debugger(self.interner.resolve(name), goal.args().len()) => {
                // Nothing to do with planning, so a note rather than a warning.
                let shown = self.show(goal);
                self.diags.push(
                    Diagnostic::note(format!("debugger directive `{shown}` ignored"))
                        .primary(goal.span, "SWI-Prolog's debugger; kbc does not run directives"),
                );
            }
            _ => {
                let shown = self.show(goal);
                let mut diagnostic =
                    Diagnostic::warning(codes::IGNORED_DIRECTIVE, format!("directive `{shown}` ignored"))
                        .primary(goal.span, "kbc reads KBs; it does not run directives");
                if name == sym::MODULE || name == sym::USE_MODULE {
                    diagnostic = diagnostic.with_note("modules are not supported: files are read as plain clauses");
                }
                self.diags
                    .push(diagnostic.with_help("remove it, or see docs/dsl.md for the directives kbc understands"));
            }
        }
    }

    fn declarations(&mut self, kind: DeclarationKind, spec: &ast::Term) {
        match &spec.kind {
            _ if spec.callable() == Some((sym::COMMA, 2)) => {
                for item in spec.xfy_operands(sym::COMMA) {
                    self.declarations(kind, item);
                }
            }
            TermKind::List(l) if l.tail.is_none() => l.items.iter().for_each(|item| self.declarations(kind, item)),
            TermKind::Compound(c) if c.functor == sym::SLASH && c.args.len() == 2 => {
                match (&c.args[0].kind, &c.args[1].kind) {
                    (TermKind::Atom(name), TermKind::Int(arity)) if *arity >= 0 => {
                        self.kb.declarations.push(Declaration {
                            kind,
                            name: *name,
                            arity: *arity as usize,
                            span: spec.span,
                        });
                    }
                    _ => self.bad_declaration(spec),
                }
            }
            _ => self.bad_declaration(spec),
        }
    }

    fn bad_declaration(&mut self, spec: &ast::Term) {
        let shown = self.show(spec);
        self.diags.push(
            Diagnostic::error(codes::BAD_DECLARATION, format!("expected `Name/Arity`, found `{shown}`"))
                .primary(spec.span, "not a predicate indicator")
                .with_help("write `:- dynamic ontable/3.`"),
        );
    }

    fn rule(&mut self, head: &ast::Term, body: &ast::Term, span: Span) {
        if let Some(test) = problem_in_body(body, self.interner) {
            self.head_site(head);
            self.go_problem(head, &test, span);
            return;
        }
        if contains_go_call(body, self.interner) {
            self.diags.push(
                Diagnostic::error(codes::BAD_PROBLEM, "kbc cannot tell when this test runs its `go` call")
                    .primary(body.span, "`go/N` in a negation, after another goal of a branch, or called twice")
                    .with_note(
                        "kbc reads a test as goals that give `go/2`, `go/4` or `go/5` its states, then the \
                         `go` call (alone, or first in an if-then-else, a disjunction or `once/1`), then goals \
                         it does not run",
                    )
                    .with_help("write `name :- go([...], [...]).`, or one test per `go` call"),
            );
            return;
        }
        if let Some((name, _)) = head.callable()
            && matches!(
                name,
                sym::ACTION
                    | sym::LL_ACTION
                    | sym::MAPPING
                    | sym::RESOURCES
                    | sym::INIT_STATE
                    | sym::GOAL_STATE
                    | sym::HL_INIT
                    | sym::HL_GOAL
            )
        {
            self.diags.push(
                Diagnostic::error(
                    codes::BAD_CLAUSE_HEAD,
                    format!("`{}` must be a fact, not a rule", self.interner.resolve(name)),
                )
                .primary(head.name_span(), "defined by a rule")
                .with_note("kbc reads these declarations as data; it does not run rules to produce them")
                .with_help("write the declaration as a fact"),
            );
            return;
        }
        if !self.check_definable_head(head) {
            return;
        }
        self.head_site(head);
        let mut scope = Scope::default();
        let head_literal = self.literal(head, &mut scope, "a clause head");
        let goal = self.goal(body, &mut scope);
        self.singletons(&scope, &[]);
        if let (Some(head), Some(body)) = (head_literal, goal) {
            self.kb.clauses.push(Clause { head, body: Some(Box::new(body)), vars: scope.table, span });
        }
    }

    fn fact(&mut self, term: &ast::Term, span: Span) {
        if !self.check_definable_head(term) {
            return;
        }
        self.head_site(term);
        let (name, arity) = term.callable().expect("checked by check_definable_head");
        match (name, arity) {
            (sym::ACTION, 6) => self.action(Level::High, term, span),
            (sym::LL_ACTION, 6) => self.action(Level::Low, term, span),
            (sym::ACTION | sym::LL_ACTION, n) => self.action_arity(term, n),
            (sym::MAPPING, 2) => self.mapping(term, span),
            (sym::RESOURCES, 1) => self.resource(term, span),
            (sym::MAPPING | sym::RESOURCES, _) => {
                let expected = if name == sym::MAPPING {
                    "mapping(HighLevelStart, [ArmLevel, ...])"
                } else {
                    "resources(Template)"
                };
                self.diags.push(
                    Diagnostic::error(
                        codes::BAD_DECLARATION,
                        format!(
                            "`{}` takes {}, found {arity}",
                            self.interner.resolve(name),
                            plural(if name == sym::MAPPING { 2 } else { 1 }, "argument")
                        ),
                    )
                    .primary(term.name_span(), "wrong number of arguments")
                    .with_help(format!("write `{expected}`")),
                );
            }
            (sym::INIT_STATE, 1) | (sym::GOAL_STATE, 1) => {
                self.state_fact(name, term, span);
                self.plain_fact(term, span, false);
            }
            // The authors' two-level KBs spell the high-level problem `hl_init`/`hl_goal`.
            (sym::HL_INIT, 1) => {
                self.state_fact(sym::INIT_STATE, term, span);
                self.plain_fact(term, span, false);
            }
            (sym::HL_GOAL, 1) => {
                self.state_fact(sym::GOAL_STATE, term, span);
                self.plain_fact(term, span, false);
            }
            (sym::LL_INIT | sym::LL_GOAL, 1) => {
                self.plain_fact(term, span, false);
                if let TermKind::List(list) = &term.args()[0].kind {
                    for item in &list.items {
                        if let Some(key) = item.callable()
                            && !self.kb.arm_level_state_preds.contains(&key)
                        {
                            self.kb.arm_level_state_preds.push(key);
                        }
                    }
                }
                self.arm_state_fact(name, term, span);
            }
            _ => self.plain_fact(term, span, true),
        }
    }

    /// A fact of the static KB, which OnKB goals and rules may read: every fact that is not a
    /// declaration, and the states (`init_state([...])`, which Prolog lets a rule read too;
    /// their singletons are reported where they are read as a problem, so not with
    /// `singletons`).
    fn plain_fact(&mut self, term: &ast::Term, span: Span, singletons: bool) {
        let mut scope = Scope::default();
        let head = self.literal(term, &mut scope, "a fact");
        if singletons {
            self.singletons(&scope, &[]);
        }
        if let Some(head) = head {
            self.kb.clauses.push(Clause { head, body: None, vars: scope.table, span });
        }
    }

    /// Reports heads that cannot be defined; returns false for them.
    fn check_definable_head(&mut self, head: &ast::Term) -> bool {
        let Some((name, arity)) = head.callable() else {
            let found = describe_non_callable(head);
            self.diags.push(
                Diagnostic::error(codes::NOT_CALLABLE, format!("expected a clause head, found {found}"))
                    .primary(head.span, "a clause must start with an atom or compound term"),
            );
            return false;
        };
        // `:-` itself, and the built-ins SWI-Prolog protects (src/builtins.rs), but in
        // std/library.pl those it implements (`bagof/3`, `setof/3`).
        let protected = matches!((name, arity), (sym::NECK, 1 | 2))
            || crate::builtins::lookup(self.interner, name, arity).is_some_and(|b| {
                b.kind == crate::builtins::Kind::Protected && !(self.library && b.imp == crate::builtins::Imp::Prolog)
            });
        if !protected {
            return true;
        }
        if name == sym::COMMA && self.ends_line(head.name_span()) {
            // `a(1),\nb(2).` reads as one clause `(a(1), b(2))`: a `,` typed for a `.`.
            let comma = head.name_span();
            let shown = self.show(head);
            self.diags.push(
                Diagnostic::error(codes::MISSING_PERIOD, "missing `.` at the end of the clause")
                    .primary(comma, "this `,` should be `.`")
                    .with_note(format!("with the `,` the two clauses read as one term `{shown}`"))
                    .with_fix("replace the `,` with `.`", comma, ".")
                    .with_help("end the clause with `.`"),
            );
            return false;
        }
        let indicator = format!("{}/{arity}", self.interner.resolve(name));
        self.diags.push(
            Diagnostic::error(codes::BAD_CLAUSE_HEAD, format!("cannot redefine the built-in `{indicator}`"))
                .primary(head.name_span(), "a built-in cannot be defined by clauses")
                .with_help("choose another name for the predicate"),
        );
        false
    }

    /// True if only layout and comments follow `span` up to the end of its line.
    fn ends_line(&self, span: Span) -> bool {
        let text = self.db.text(span.file);
        let rest = &text[span.end as usize..];
        let line = rest.split('\n').next().unwrap_or("");
        let code = line.split('%').next().unwrap_or("");
        code.trim().is_empty()
    }

    fn action_arity(&mut self, term: &ast::Term, arity: usize) {
        let name = self.interner.resolve(term.callable().map_or(sym::ACTION, |c| c.0)).to_string();
        let mut diagnostic =
            Diagnostic::error(codes::ACTION_ARITY, format!("`{name}` takes 6 arguments, found {arity}"))
                .primary(term.name_span(), format!("{name}/{arity}"))
                .with_note(format!("an action is {name}(Name, Valid, Invalid, InvalidAtEnd, OnKB, Effects)"));
        if arity == 5 {
            // Older KBs have no OnKB slot: insert `[]` before the effects.
            let effects = &term.args()[4];
            diagnostic = diagnostic
                .with_fix(
                    "add an empty OnKB slot before the effects",
                    Span::point(effects.span.file, effects.span.start),
                    "[], ",
                )
                .with_help("older KBs omit the OnKB list: add `[]` as the fifth argument");
        }
        self.diags.push(diagnostic);
        self.record_recovered_names(term);
    }

    fn action(&mut self, level: Level, term: &ast::Term, span: Span) {
        let args = term.args();
        let mut scope = Scope::default();
        let slots: [Span; 6] = std::array::from_fn(|i| args[i].span);
        let Some(name) = self.literal(&args[0], &mut scope, "an action name") else {
            self.record_recovered_names(term);
            return;
        };
        let name_text = self.interner.resolve(name.name()).to_string();
        let mut ok = true;
        let mut condition_lists: [Vec<Literal>; 3] = Default::default();
        for (slot, list) in condition_lists.iter_mut().enumerate() {
            let slot_name = SLOT_NAMES[slot + 1];
            match self.list(&args[slot + 1], || format!("the {slot_name} slot of `{name_text}`")) {
                Some(items) => {
                    for item in items {
                        match self.literal(item, &mut scope, &format!("a {slot_name} literal")) {
                            Some(literal) => list.push(literal),
                            None => ok = false,
                        }
                    }
                }
                None => ok = false,
            }
        }
        let on_kb_items = self.list(&args[4], || format!("the OnKB slot of `{name_text}`"));
        let effect_items = self.list(&args[5], || format!("the Effects slot of `{name_text}`"));
        let swapped = on_kb_items.is_some_and(|items| !items.is_empty() && items.iter().all(is_effect_term))
            && effect_items.is_some_and(|items| !items.is_empty() && !items.iter().all(is_effect_term));
        let mut on_kb = Vec::new();
        match on_kb_items {
            Some(items) if swapped => {
                // Reported below with the effects; lower the variables for singleton checks.
                for item in items {
                    self.term(item, &mut scope);
                }
                ok = false;
            }
            Some(items) => {
                for item in items {
                    match self.goal(item, &mut scope) {
                        Some(goal) => on_kb.push(goal),
                        None => ok = false,
                    }
                }
            }
            None => ok = false,
        }
        let mut effects = Vec::new();
        match effect_items {
            Some(_) if swapped => {
                let (on_kb_span, effects_span) = (args[4].span, args[5].span);
                let effects_text = term_to_string(self.interner, &args[4]);
                let on_kb_text = term_to_string(self.interner, &args[5]);
                self.diags.push(
                    Diagnostic::error(codes::BAD_EFFECT, format!("the OnKB and Effects slots of `{name_text}` look swapped"))
                        .primary(effects_span, "these are conditions, not `add`/`del` effects")
                        .secondary(on_kb_span, "and these are effects")
                        .with_note("kbc reads action(Name, Valid, Invalid, InvalidAtEnd, OnKB, Effects); some older KBs put Effects fifth")
                        .with_fix_edits(
                            "swap the two slots",
                            vec![Edit { span: on_kb_span, replacement: on_kb_text }, Edit { span: effects_span, replacement: effects_text }],
                        )
                        .with_help("swap the fifth and sixth arguments"),
                );
                for item in args[5].args() {
                    self.term(item, &mut scope);
                }
            }
            Some(items) => {
                for item in items {
                    match self.effect(item, &mut scope) {
                        Some(effect) => effects.push(effect),
                        None => ok = false,
                    }
                }
            }
            None => ok = false,
        }
        // A variable that occurs once, in an effect, is unbound: `check` reports that error.
        self.singletons(&scope, &[slots[5]]);
        if !ok {
            self.record_recovered_names(term);
            return;
        }
        let (base, snap) = split_snap(self.interner, name.name());
        let [valid, invalid, invalid_at_end] = condition_lists;
        self.kb.actions.push(Action {
            level,
            name,
            base,
            snap,
            valid,
            invalid,
            invalid_at_end,
            on_kb,
            effects,
            vars: scope.table,
            span,
            slots,
        });
    }

    fn effect(&mut self, t: &ast::Term, scope: &mut Scope) -> Option<Effect> {
        let kind = match t.callable() {
            Some((sym::ADD, 1)) => Some(EffectKind::Add),
            Some((sym::DEL, 1)) => Some(EffectKind::Del),
            _ => None,
        };
        let Some(kind) = kind else {
            let found = self.show(t);
            let mut diagnostic =
                Diagnostic::error(codes::BAD_EFFECT, format!("expected `add(L)` or `del(L)`, found `{found}`"))
                    .primary(t.span, "not an effect");
            let replacement = match t.callable().map(|(n, a)| (self.interner.resolve(n).to_string(), a)) {
                Some((n, 1)) if matches!(n.as_str(), "assert" | "assertz" | "asserta" | "insert" | "plus") => {
                    Some("add")
                }
                Some((n, 1)) if matches!(n.as_str(), "retract" | "delete" | "remove" | "minus" | "rem") => Some("del"),
                _ => None,
            };
            if let Some(replacement) = replacement {
                diagnostic = diagnostic
                    .with_fix(format!("write `{replacement}`"), t.name_span(), replacement)
                    .with_help(format!("effects are written `{replacement}(...)`"));
            } else if t.callable().is_some_and(|(n, a)| matches!(n, sym::ADD | sym::DEL) && a != 1) {
                diagnostic =
                    diagnostic.with_help("`add` and `del` take exactly one literal: write one effect per literal");
            } else {
                diagnostic = diagnostic.with_help(format!("to add the fact, write `add({found})`"));
            }
            self.diags.push(diagnostic);
            return None;
        };
        let literal = self.literal(&t.args()[0], scope, "a literal to add or delete")?;
        Some(Effect { kind, literal, span: t.span })
    }

    fn mapping(&mut self, term: &ast::Term, span: Span) {
        let args = term.args();
        let mut scope = Scope::default();
        let high = self.literal(&args[0], &mut scope, "a high-level action start");
        let mut steps = Vec::new();
        let mut ok = high.is_some();
        match self.list(&args[1], || "the arm-level steps of a mapping".to_string()) {
            Some(items) => {
                if items.is_empty() {
                    self.diags.push(
                        Diagnostic::error(codes::BAD_DECLARATION, "a mapping needs at least one arm-level step")
                            .primary(args[1].span, "no steps")
                            .with_help("list the `ll_action`s the high-level action is refined into"),
                    );
                    ok = false;
                }
                for item in items {
                    match self.literal(item, &mut scope, "an arm-level action") {
                        Some(l) => steps.push(l),
                        None => ok = false,
                    }
                }
            }
            None => ok = false,
        }
        self.singletons(&scope, &[]);
        if let (true, Some(high)) = (ok, high) {
            self.kb.mappings.push(Mapping { high, steps, vars: scope.table, span });
        }
    }

    fn resource(&mut self, term: &ast::Term, span: Span) {
        let mut scope = Scope::default();
        if let Some(template) = self.literal(&term.args()[0], &mut scope, "a resource template such as `agent(_)`") {
            self.kb.resources.push(Resource { template, vars: scope.table, span });
        }
    }

    // ---- problems -------------------------------------------------------------------------

    fn go_problem(&mut self, head: &ast::Term, test: &TestBody<'_>, span: Span) {
        let Some((functor, _)) = head.callable() else {
            self.check_definable_head(head);
            return;
        };
        // `test(1) :- go(...)`, `test(2) :- go(...)`: Prolog runs `?- test(1).` and
        // `?- test(2).` apart, so each head with arguments and no variable in them is a problem
        // of its own, named as the head is written (`--problem 'test(1)'`). A head with
        // variables (`test1(Plan, Times)`) is named by its functor.
        let mut open = false;
        head.for_each_var(&mut |_, _| open = true);
        let name = if head.args().is_empty() || open {
            functor
        } else {
            let text = crate::syntax::printer::term_to_string(&*self.interner, head);
            self.interner.intern(&text)
        };
        let go = test.go;
        let args = go.args();
        let mut scope = Scope::default();
        // Head arguments (`test1(Actions, Times)`) share variables with go/4's outputs.
        for arg in head.args() {
            self.term(arg, &mut scope);
        }
        // Goals before `go` that give it its states: lowered as a rule body, run by the
        // `prelude` pass once the whole KB is known.
        let mut prelude = None;
        if let (Some(first), Some(last)) = (test.before.first(), test.before.last()) {
            let goals: Option<Vec<Goal>> = test.before.iter().map(|g| self.goal(g, &mut scope)).collect();
            let spans = |t: &ast::Term| -> (Span, Vec<Span>) {
                match &t.kind {
                    TermKind::List(l) if l.tail.is_none() => (t.span, l.items.iter().map(|i| i.span).collect()),
                    _ => (t.span, Vec::new()),
                }
            };
            let (init, goal) = (self.term(&args[0], &mut scope), self.term(&args[1], &mut scope));
            prelude = goals.map(|goals| Prelude {
                goals,
                init,
                goal,
                init_spans: spans(&args[0]),
                goal_spans: spans(&args[1]),
                span: first.span.to(last.span),
                resolved: false,
            });
        }
        if let (Some(first), Some(last)) = (test.after.first(), test.after.last()) {
            self.diags.push(
                Diagnostic::warning(codes::GOALS_AFTER_GO, "kbc does not run the goals after `go`")
                    .primary(first.span.to(last.span), "not run")
                    .secondary(go.span, "kbc plans this call")
                    .with_note(
                        "Prolog runs them after `go` (an else branch when it finds no plan), and asks `go` \
                         for another plan if they fail; kbc gives the first plan and runs none of them",
                    )
                    .with_help("to print or check the plan, run kbc's output (`kbc plan`, `kbc validate`)"),
            );
        }
        if prelude.is_none() && !test.before.is_empty() {
            return; // a goal before `go` that does not lower (reported)
        }
        // Without a prelude, the states as written; with one, empty until the `prelude` pass.
        let (init, goal) = match prelude {
            Some(_) => (Some(Vec::new()), Some(Vec::new())),
            None => (
                self.state_list(&args[0], &mut scope, "the initial state"),
                self.state_list(&args[1], &mut scope, "the goal state"),
            ),
        };
        for arg in args.iter().skip(2).take(2) {
            self.term(arg, &mut scope);
        }
        let max_depth = self.max_depth(args);
        let quiet: Vec<Span> = init.iter().flatten().filter(|l| !l.term.is_ground()).map(|l| l.span).collect();
        self.singletons(&scope, &quiet);
        let (Some(init), Some(goal)) = (init, goal) else { return };
        let (init, open_init) = Lowerer::ground_init(init);
        self.add_problem(Problem {
            name,
            name_span: head.name_span(),
            init,
            goal,
            max_depth,
            form: ProblemForm::Go(args.len() as u8),
            vars: scope.table,
            span,
            level: Level::High,
            open_init,
            prelude: prelude.map(Box::new),
        });
    }

    /// The depth limit of `go/5` (its fifth argument), or none; E0215 when it is not a
    /// positive integer.
    fn max_depth(&mut self, args: &[ast::Term]) -> Option<u32> {
        let limit = args.get(4)?;
        match limit.kind {
            TermKind::Int(depth) if depth > 0 && depth <= u32::MAX as i64 => Some(depth as u32),
            _ => {
                let found = self.show(limit);
                self.diags.push(
                    Diagnostic::error(
                        codes::BAD_PROBLEM,
                        format!("expected a positive integer depth limit, found `{found}`"),
                    )
                    .primary(limit.span, "the fifth argument of `go/5` is the maximum plan depth")
                    .with_help("write a number such as `25`"),
                );
                None
            }
        }
    }

    fn state_list(&mut self, t: &ast::Term, scope: &mut Scope, what: &str) -> Option<Vec<Literal>> {
        let items = self.list(t, || what.to_string())?;
        let mut literals = Vec::with_capacity(items.len());
        let mut ok = true;
        for item in items {
            match self.literal(item, scope, "a fact") {
                Some(l) => literals.push(l),
                None => ok = false,
            }
        }
        ok.then_some(literals)
    }

    /// Splits init facts into the ground ones and those with variables (`open_init`).
    fn ground_init(init: Vec<Literal>) -> (Vec<Literal>, Vec<Literal>) {
        init.into_iter().partition(|l| l.term.is_ground())
    }

    /// Warns about init facts with variables on predicates the arm level does not read (W0015),
    /// once every `ll_action` is known. They stay in `open_init`: the planner gives their
    /// variables values ([`crate::passes::open_init`]); the arm level matches its own by
    /// unification.
    fn check_open_init(&mut self) {
        let arm = self.kb.arm_level_preds();
        for p in 0..self.kb.problems.len() {
            let problem = &self.kb.problems[p];
            let high: Vec<Literal> =
                crate::passes::open_init::high_level_open_facts(problem, &arm).into_iter().cloned().collect();
            let vars = problem.vars.clone();
            for literal in high {
                self.open_init_warning(&literal, &vars);
            }
        }
    }

    /// W0015 on `literal`.
    fn open_init_warning(&mut self, literal: &Literal, vars: &VarTable) {
        let mut diagnostic = Diagnostic::warning(codes::OPEN_INIT, "an initial state fact with a variable")
            .primary(literal.span, "this fact has a variable");
        let mut seen = Vec::new();
        literal.term.for_each_var(&mut |v| {
            if !seen.contains(&v) {
                seen.push(v)
            }
        });
        let mut names = Vec::new();
        for v in seen {
            let info = vars.get(v);
            let name = self.interner.resolve(info.name).to_string();
            if let Some(&at) =
                info.occurrences.iter().find(|s| literal.span.start <= s.start && s.end <= literal.span.end)
            {
                diagnostic = diagnostic.secondary(at, format!("`{name}` is a variable"));
            }
            names.push(name);
        }
        let them = if names.len() == 1 { "it" } else { "each" };
        self.diags.push(
            with_open_init_notes(diagnostic, them)
                .with_help("replace the variable with a value; atoms start with a lower-case letter"),
        );
    }

    fn add_problem(&mut self, problem: Problem) {
        if let Some(previous) = self.kb.problem(problem.name) {
            let name = self.interner.resolve(problem.name);
            self.diags.push(
                Diagnostic::error(codes::BAD_PROBLEM, format!("problem `{name}` is defined more than once"))
                    .primary(problem.name_span, "defined again here")
                    .secondary(previous.name_span, "first defined here")
                    .with_help("give each problem its own name"),
            );
            return;
        }
        self.kb.problems.push(problem);
    }

    /// `init_state`/`goal_state` (and `hl_init`/`hl_goal`, read as them): one pair per file.
    fn state_fact(&mut self, name: Symbol, term: &ast::Term, span: Span) {
        let what = if name == sym::INIT_STATE { "the initial state" } else { "the goal state" };
        let help = "put one problem per file, or name them: `test1 :- go(Init, Goal).`";
        self.record_state(false, name == sym::INIT_STATE, name, term, span, (what, help));
    }

    /// `ll_init([...])` or `ll_goal([...])`: one pair per file.
    fn arm_state_fact(&mut self, name: Symbol, term: &ast::Term, span: Span) {
        let what = if name == sym::LL_INIT { "the arm-level initial state" } else { "the arm-level goal" };
        self.record_state(true, name == sym::LL_INIT, name, term, span, (what, "give one arm-level state per file"));
    }

    /// Records one list of a file's pair of states (the arm level's with `arm`), whose two
    /// lists share one variable scope; a list given twice in a file is E0215. `text` is what
    /// the list is, for messages, and the help for the repeat.
    fn record_state(&mut self, arm: bool, init: bool, name: Symbol, term: &ast::Term, span: Span, text: (&str, &str)) {
        let (what, help) = text;
        let file = span.file;
        let files = if arm { &mut self.arm_state_files } else { &mut self.state_files };
        let index = match files.iter().position(|s| s.file == file) {
            Some(i) => i,
            None => {
                files.push(StateFile { file, init: None, goal: None, scope: Scope::default() });
                files.len() - 1
            }
        };
        let mut scope = std::mem::take(&mut files[index].scope);
        let list = self.state_list(&term.args()[0], &mut scope, what);
        let files = if arm { &mut self.arm_state_files } else { &mut self.state_files };
        let entry = &mut files[index];
        entry.scope = scope;
        let slot = if init { &mut entry.init } else { &mut entry.goal };
        if let Some((_, first)) = slot {
            let first = *first;
            let shown = self.interner.resolve(name).to_string();
            self.diags.push(
                Diagnostic::error(codes::BAD_PROBLEM, format!("`{shown}` is given more than once in this file"))
                    .primary(term.name_span(), "given again here")
                    .secondary(first, "first given here")
                    .with_help(help.to_string()),
            );
            return;
        }
        if let Some(list) = list {
            *slot = Some((list, term.name_span()));
        }
    }

    /// A high-level `X_start` or `X_end` whose counterpart exists only with another arity
    /// does not pair: the paper's planner treats the two as unrelated actions and finds its
    /// plan, so kbc plans each as an instantaneous action under its full name, with warning
    /// W0011. (Arm-level pairs keep error E0205.)
    fn unpair_mismatched_arities(&mut self) {
        let snaps: Vec<(Level, Symbol, Snap, usize)> =
            self.kb.actions.iter().map(|a| (a.level, a.base, a.snap, a.name.arity())).collect();
        for index in 0..self.kb.actions.len() {
            let (level, base, snap, arity) = snaps[index];
            if level != Level::High || snap == Snap::Instant {
                continue;
            }
            let other = if snap == Snap::Start { Snap::End } else { Snap::Start };
            let counterparts: Vec<usize> =
                snaps.iter().filter(|s| s.0 == level && s.1 == base && s.2 == other).map(|s| s.3).collect();
            if counterparts.is_empty() {
                self.unpair_alone(index, other);
                continue;
            }
            if counterparts.contains(&arity) {
                continue;
            }
            let action = &mut self.kb.actions[index];
            action.snap = Snap::Instant;
            action.base = action.name.name();
            let own = self.interner.resolve(action.name.name()).to_string();
            let base_text = self.interner.resolve(base).to_string();
            let suffix = if other == Snap::Start { "start" } else { "end" };
            let mut counterparts = counterparts;
            counterparts.sort_unstable();
            counterparts.dedup();
            let others = crate::passes::check::join_or(&counterparts);
            self.diags.push(
                Diagnostic::warning(
                    codes::UNPAIRED_ARITIES,
                    format!("`{own}` takes {} but `{base_text}_{suffix}` takes {others}: they do not pair", plural(arity, "argument")),
                )
                .primary(action.name.span, plural(arity, "argument"))
                .with_note(format!(
                    "kbc plans `{own}` as an instantaneous action, unrelated to `{base_text}_{suffix}`, as the paper's planner does; \
                     the schedule gives it no duration, and `duration({base_text}(...), ...)` does not apply to it"
                ))
                .with_help("give the start and the end the same arguments to make them one durative action"),
            );
        }
    }

    /// A high-level `X_start` with no `X_end` of any arity, or the reverse (`other` is the
    /// snap missing): the paper's planner applies it as any other action, so kbc plans it as an
    /// instantaneous action under its full name, with warning W0019 and, for a start, the end
    /// it may have meant as a fix. (Arm-level ones keep error E0204, see `check`.)
    fn unpair_alone(&mut self, index: usize, other: Snap) {
        let action = &mut self.kb.actions[index];
        let base = action.base;
        action.snap = Snap::Instant;
        action.base = action.name.name();
        let action = &self.kb.actions[index];
        let own = self.interner.resolve(action.name.name()).to_string();
        let base_text = self.interner.resolve(base).to_string();
        let note = format!(
            "kbc plans `{own}` as an instantaneous action, as the paper's planner applies it: the schedule gives it no \
             duration, and `duration({base_text}(...), ...)` does not apply to it"
        );
        let diagnostic = if other == Snap::End {
            let (end_name, skeleton) = crate::passes::check::missing_end(self.interner, action, &base_text);
            Diagnostic::warning(codes::UNPAIRED_SNAP, format!("durative action `{base_text}` has a start but no end"))
                .primary(action.name.name_span, format!("`{base_text}_start` declared here"))
                .with_note(note)
                .with_fix(format!("declare `{end_name}`"), Span::point(action.span.file, action.span.end), skeleton)
                .with_help(format!(
                    "declare `{end_name}` to make `{base_text}` durative, or rename the action without `_start`"
                ))
        } else {
            Diagnostic::warning(codes::UNPAIRED_SNAP, format!("durative action `{base_text}` has an end but no start"))
                .primary(action.name.name_span, format!("`{base_text}_end` declared here"))
                .with_note(note)
                .with_help(format!(
                    "declare `{base_text}_start` with the same arguments to make `{base_text}` durative, or rename the \
                     action without `_end`"
                ))
        };
        self.diags.push(diagnostic);
    }

    fn finish_init_goal_states(&mut self) {
        for state in std::mem::take(&mut self.state_files) {
            let stem = std::path::Path::new(self.db.file(state.file).name())
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("problem")
                .to_string();
            match (state.init, state.goal) {
                (Some((init, init_span)), Some((goal, goal_span))) => {
                    let quiet: Vec<Span> = init.iter().filter(|l| !l.term.is_ground()).map(|l| l.span).collect();
                    self.singletons(&state.scope, &quiet);
                    let (init, open_init) = Lowerer::ground_init(init);
                    let name = self.interner.intern(&stem);
                    self.add_problem(Problem {
                        name,
                        name_span: init_span,
                        init,
                        goal,
                        max_depth: None,
                        form: ProblemForm::InitGoalState,
                        vars: state.scope.table,
                        span: init_span.to(goal_span),
                        level: Level::High,
                        open_init,
                        prelude: None,
                    });
                }
                (Some((_, span)), None) => self.incomplete_problem(span, "goal_state"),
                (None, Some((_, span))) => self.incomplete_problem(span, "init_state"),
                (None, None) => {}
            }
        }
    }

    fn finish_arm_states(&mut self) {
        for state in std::mem::take(&mut self.arm_state_files) {
            // Variables of an arm-level initial state are meant: `_` is "any value".
            let quiet: Vec<Span> =
                state.init.iter().flat_map(|(l, _)| l.iter()).filter(|l| !l.term.is_ground()).map(|l| l.span).collect();
            self.singletons(&state.scope, &quiet);
            self.kb.arm_states.push(hir::ArmState {
                file: state.file,
                init: state.init.map(|(l, _)| l).unwrap_or_default(),
                goal: state.goal.map(|(l, _)| l).unwrap_or_default(),
                vars: state.scope.table,
            });
        }
    }

    fn incomplete_problem(&mut self, span: Span, missing: &str) {
        let present = if missing == "goal_state" { "init_state" } else { "goal_state" };
        self.diags.push(
            Diagnostic::error(codes::INCOMPLETE_PROBLEM, format!("`{present}` without `{missing}`"))
                .primary(span, format!("this file has no `{missing}`"))
                .with_note("a problem needs both an initial state and a goal state")
                .with_help(format!("add `{missing}([...]).` to this file")),
        );
    }

    // ---- variables ------------------------------------------------------------------------

    /// SWI-Prolog's variable warnings for one clause. Variables inside `quiet` spans are left
    /// out of the singleton warning because an error already covers them (a variable in an
    /// init fact, an effect variable nothing binds).
    fn singletons(&mut self, scope: &Scope, quiet: &[Span]) {
        let mut singles = Vec::new();
        for info in &scope.table.vars {
            if info.occurrences.iter().all(|at| quiet.iter().any(|q| q.start <= at.start && at.end <= q.end)) {
                continue;
            }
            let name = self.interner.resolve(info.name);
            if name == "_" {
                continue;
            }
            if name.starts_with('_') {
                if info.occurrences.len() > 1 {
                    let mut diagnostic = Diagnostic::warning(
                        codes::MARKED_SINGLETON_REUSED,
                        format!("variable `{name}` is marked unused but appears {} times", info.occurrences.len()),
                    )
                    .primary(info.occurrences[0], "the `_` prefix says it is used once");
                    for &at in &info.occurrences[1..] {
                        diagnostic = diagnostic.secondary(at, "used again here");
                    }
                    let plain = name.trim_start_matches('_');
                    let help = if plain.is_empty() || !plain.as_bytes()[0].is_ascii_uppercase() {
                        "drop the leading `_` and start the name with an upper-case letter".to_string()
                    } else {
                        format!("rename it `{plain}`")
                    };
                    self.diags.push(diagnostic.with_help(help));
                }
            } else if info.occurrences.len() == 1 {
                singles.push((name.to_string(), info.occurrences[0]));
            }
        }
        if singles.is_empty() {
            return;
        }
        let names: Vec<String> = singles.iter().map(|(n, _)| format!("`{n}`")).collect();
        let message = if singles.len() == 1 {
            format!("singleton variable {}", names[0])
        } else {
            format!("singleton variables {}", join_and(&names))
        };
        let mut diagnostic = Diagnostic::warning(codes::SINGLETON_VARIABLE, message);
        for (i, (_, at)) in singles.iter().enumerate() {
            diagnostic = if i == 0 {
                diagnostic.primary(*at, "used only once")
            } else {
                diagnostic.secondary(*at, "used only once")
            };
        }
        let edits = singles.iter().map(|(n, at)| Edit { span: *at, replacement: format!("_{n}") }).collect();
        self.diags.push(
            diagnostic
                .with_note("a variable used once binds nothing; it is often a misspelling of another variable")
                .with_fix_edits("mark as intentionally unused", edits)
                .with_help(if singles.len() == 1 {
                    format!("if it is meant to be unused, write `_{}`", singles[0].0)
                } else {
                    "if they are meant to be unused, start their names with `_`".to_string()
                }),
        );
    }
}

/// Joins `a`, `b` and `c` as "a, b and c".
pub fn join_and(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

fn describe_non_callable(t: &ast::Term) -> String {
    match &t.kind {
        TermKind::Var(_) => "a variable".to_string(),
        TermKind::Int(i) => format!("the number `{i}`"),
        TermKind::Float(f) => format!("the number `{f}`"),
        TermKind::Str(_) => "a string".to_string(),
        TermKind::List(_) => "a list".to_string(),
        _ => "a term".to_string(),
    }
}

fn is_effect_term(t: &ast::Term) -> bool {
    matches!(t.callable(), Some((sym::ADD | sym::DEL, 1)))
}

/// The `go/2`, `go/4` or `go/5` call if `body` is exactly one.
/// W0015's notes on an initial fact with variables, `them` being how to name them (`it`,
/// `each`).
pub fn with_open_init_notes(diagnostic: Diagnostic, them: &str) -> Diagnostic {
    diagnostic.with_note("the initial state lists what is true, so every argument is usually known").with_note(format!(
        "as in Prolog, the plan may give {them} a value: kbc tries a value of its own first (the variable left \
         unbound), then each atom and integer of the KB"
    ))
}

/// A test's body read as a problem: the goals before its `go/N` call, the call, and the goals
/// after it.
pub struct TestBody<'a> {
    /// The goals that give `go` its states.
    pub before: Vec<&'a ast::Term>,
    /// The `go/2`, `go/4` or `go/5` call.
    pub go: &'a ast::Term,
    /// Goals kbc does not run (warning W0017): those after the call, and the branches of an
    /// if-then-else or a disjunction the call is the condition or first branch of.
    pub after: Vec<&'a ast::Term>,
}

/// `body` as a test: a conjunction with one goal that calls `go/N`, either the call or one
/// that runs it first (see [`leading_go`]), and no other goal that calls `go`.
pub fn problem_in_body<'a>(body: &'a ast::Term, interner: &Interner) -> Option<TestBody<'a>> {
    let goals = body.xfy_operands(sym::COMMA);
    let mut calls = goals.iter().enumerate().filter(|(_, g)| contains_go_call(g, interner));
    let (at, first) = calls.next()?;
    if calls.next().is_some() {
        return None;
    }
    let mut after = Vec::new();
    let go = leading_go(first, interner, &mut after)?;
    after.extend(goals[at + 1..].iter().copied());
    Some(TestBody { before: goals[..at].to_vec(), go, after })
}

/// The `go/N` call that goal `t` runs before anything else, if it does: the call itself, or
/// the first goal of `(G -> T ; E)`, `(G -> T)`, `(G ; E)`, `(G, R)`, `once(G)`, `call(G)`
/// or `ignore(G)` that is such a goal. What runs only after the call, or instead of it (`T`,
/// `E`, `R`), is added to `rest`, in source order.
fn leading_go<'a>(t: &'a ast::Term, interner: &Interner, rest: &mut Vec<&'a ast::Term>) -> Option<&'a ast::Term> {
    let wrapper = |name| calls_its_argument_once(name, interner);
    match t.callable()? {
        (sym::GO, 2 | 4 | 5) => Some(t),
        (sym::SEMI | sym::ARROW | sym::COMMA, 2) => {
            let go = leading_go(&t.args()[0], interner, rest)?;
            rest.push(&t.args()[1]);
            Some(go)
        }
        (name, 1) if wrapper(name) => leading_go(&t.args()[0], interner, rest),
        _ => None,
    }
}

/// Whether `name/1` is `once/1`, `call/1` or `ignore/1`, which run their argument as a goal.
fn calls_its_argument_once(name: Symbol, interner: &Interner) -> bool {
    ["once", "call", "ignore"].iter().any(|w| interner.get(w) == Some(name))
}

/// Whether goal `t` calls `go/N` anywhere in its control constructs (`,`, `;`, `->`, `\+`)
/// or in `once/1`, `call/1` or `ignore/1`.
fn contains_go_call(t: &ast::Term, interner: &Interner) -> bool {
    let wrapper = |name| calls_its_argument_once(name, interner);
    match t.callable() {
        Some((sym::COMMA | sym::SEMI | sym::ARROW, 2) | (sym::NOT_PROVABLE | sym::NOT, 1)) => {
            t.args().iter().any(|a| contains_go_call(a, interner))
        }
        Some((name, 1)) if wrapper(name) => contains_go_call(&t.args()[0], interner),
        Some((sym::GO, 2 | 4 | 5)) => true,
        _ => false,
    }
}

/// `grip_start` is the start of `grip`; `grip_end` its end; `wait` is instantaneous.
pub fn split_snap(interner: &mut Interner, name: Symbol) -> (Symbol, Snap) {
    let text = interner.resolve(name);
    if let Some(base) = text.strip_suffix("_start").filter(|b| !b.is_empty()) {
        let base = base.to_string();
        (interner.intern(&base), Snap::Start)
    } else if let Some(base) = text.strip_suffix("_end").filter(|b| !b.is_empty()) {
        let base = base.to_string();
        (interner.intern(&base), Snap::End)
    } else {
        (name, Snap::Instant)
    }
}
