//! Pass `task`: one problem of the HIR becomes a planning task ([`Task`]).
//!
//! The high-level action schemas are compiled into patterns over their variables, with every
//! ground subterm interned; the initial state's facts are interned into a [`State`]; the goal
//! becomes a conjunction of patterns over its own variables. Nothing else is grounded: which
//! actions apply is decided lifted, state by state, by `planner::successors`.

use crate::ir::hir::{Kb, Level, Literal, Snap, Term};
use crate::ir::task::{Const, ConstId, Consts, Facts, LiteralPattern, Pattern, Schema, State, Task};

/// Compiles problem number `problem` of `kb`, with the KB's `resources/1` templates.
pub fn build(kb: &Kb, problem: usize) -> Task {
    let templates: Vec<Term> = kb.resources.iter().map(|r| r.template.term.clone()).collect();
    build_with(kb, problem, &templates)
}

/// Compiles problem number `problem` of `kb`, with `resources` as its renewable resources'
/// templates (`available(_)`): the KB's own, or one its actions imply
/// (`Session::task` decides).
pub fn build_with(kb: &Kb, problem: usize, resources: &[Term]) -> Task {
    let is_resource =
        |term: &Term| resources.iter().any(|r| r.callable() == term.callable() && crate::ir::unify::unifiable(r, term));
    let mut consts = Consts::default();
    let mut facts = Facts::default();
    let mut schemas = Vec::new();
    for (index, action) in kb.actions.iter().enumerate() {
        if action.level != Level::High {
            continue;
        }
        let mut literal = |l: &Literal| compile_literal(&mut consts, &mut facts, l);
        let valid = action.valid.iter().map(&mut literal).collect();
        let invalid = action.invalid.iter().map(&mut literal).collect();
        let effects = action.effects.iter().map(|e| (e.kind, literal(&e.literal))).collect();
        let mut resource_vars = Vec::new();
        let mut resource_valid = Vec::new();
        for valid in &action.valid {
            resource_valid.push(is_resource(&valid.term));
            for template in resources {
                if template.callable() != valid.term.callable() {
                    continue;
                }
                for (slot, value) in template.args().iter().zip(valid.term.args()) {
                    if let (Term::Var(_), Term::Var(v)) = (slot, value)
                        && !resource_vars.contains(&v.0)
                    {
                        resource_vars.push(v.0);
                    }
                }
            }
        }
        // The running literal of a durative snap action: the name's arguments. (A start and
        // an end of one action with different arities are unrelated actions: they get
        // different running predicates, and an end whose start is missing never applies.)
        let running = (action.snap != Snap::Instant).then(|| {
            let args: Box<[Pattern]> = action.name.term.args().iter().map(|a| compile(&mut consts, a)).collect();
            LiteralPattern { pred: facts.running_pred(action.base, args.len()), args, span: action.name.span }
        });
        schemas.push(Schema {
            action: index,
            name: compile(&mut consts, &action.name.term),
            base: action.base,
            snap: action.snap,
            vars: action.vars.len(),
            valid,
            invalid,
            invalid_at_end: action.invalid_at_end.iter().map(|l| l.term.clone()).collect(),
            on_kb: action.on_kb.clone().into_boxed_slice(),
            effects,
            resource_vars: resource_vars.into_boxed_slice(),
            resource_valid: resource_valid.into_boxed_slice(),
            running,
        });
    }
    // The relaxation needs the running literal only where an end's name has a variable its
    // Valid list does not bind: that variable takes the start's value. Elsewhere the end's
    // Valid literals already say everything the running start would, and leaving the literal
    // out keeps the relaxation as small as the KB.
    let mut needed: Vec<(crate::intern::Symbol, usize)> = Vec::new();
    for schema in schemas.iter().filter(|s| s.snap == Snap::End) {
        let Some(running) = &schema.running else { continue };
        let mut bound = Vec::new();
        for literal in schema.valid.iter() {
            literal.args.iter().for_each(|a| a.vars(&mut bound));
        }
        let mut own = Vec::new();
        running.args.iter().for_each(|a| a.vars(&mut own));
        if own.iter().any(|v| !bound.contains(v)) {
            needed.push((schema.base, running.args.len()));
        }
    }
    for schema in &mut schemas {
        if schema.running.as_ref().is_some_and(|r| !needed.contains(&(schema.base, r.args.len()))) {
            schema.running = None;
        }
    }
    let problem_hir = &kb.problems[problem];
    let init: Vec<_> = problem_hir
        .init
        .iter()
        .filter_map(|l| {
            let pred = facts.pred(l.name(), l.arity());
            let args: Option<Vec<_>> = l.term.args().iter().map(|a| consts.from_term(a)).collect();
            // Lowering keeps only ground init facts; a non-ground one is skipped defensively.
            args.map(|args| facts.intern(pred, &args))
        })
        .collect();
    let init = State::new(&facts, init, []);
    let goal = problem_hir.goal.iter().map(|l| compile_literal(&mut consts, &mut facts, l)).collect();
    Task {
        problem,
        consts,
        facts,
        schemas,
        init,
        goal,
        goal_vars: problem_hir.vars.len(),
        resource_goal: problem_hir.goal.iter().map(|g| is_resource(&g.term)).collect(),
        goal_terms: problem_hir.goal.iter().map(|l| l.term.clone()).collect(),
        max_depth: problem_hir.max_depth,
    }
}

fn compile(consts: &mut Consts, term: &Term) -> Pattern {
    let constant = match term {
        Term::Var(v) => return Pattern::Var(v.0),
        Term::Atom(s) => Const::Atom(*s),
        Term::Int(i) => Const::Int(*i),
        Term::Float(f) => Const::Float(f.to_bits()),
        Term::Str(s) => Const::Str(*s),
        Term::Compound(f, args) => {
            let args: Vec<Pattern> = args.iter().map(|a| compile(consts, a)).collect();
            let ids: Option<Box<[ConstId]>> =
                args.iter().map(|a| if let Pattern::Const(c) = a { Some(*c) } else { None }).collect();
            match ids {
                Some(ids) => Const::Compound(*f, ids),
                None => return Pattern::Compound(*f, args.into_boxed_slice()),
            }
        }
    };
    Pattern::Const(consts.intern(constant))
}

fn compile_literal(consts: &mut Consts, facts: &mut Facts, literal: &Literal) -> LiteralPattern {
    let pred = facts.pred(literal.name(), literal.arity());
    let args = literal.term.args().iter().map(|a| compile(consts, a)).collect();
    LiteralPattern { pred, args, span: literal.span }
}
