//! A total-order plan: snap actions in order, each a schema and the values of its variables.
//!
//! The plan is independent of the search's interning tables: names and values are HIR terms,
//! so later stages (achievers, the temporal network) and the validator read it directly.

use std::fmt::Write;

use crate::intern::{Interner, Symbol};
use crate::ir::hir::{self, Kb, Term, VarTable};

/// One step of a plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// The schema's index in `Kb::actions`.
    pub action: usize,
    /// The ground action name, e.g. `grip_start(a1, b2)`.
    pub name: Term,
    /// The value of each schema variable; `None` for variables only Invalid conditions use.
    pub bindings: Vec<Option<Term>>,
}

/// A total-order plan for one problem.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Plan {
    /// The problem's index in `Kb::problems`.
    pub problem: usize,
    /// The steps, in order.
    pub steps: Vec<Step>,
}

/// The plan as numbered lines, the paper's table style: `  1  grip_start(a1, b2)`. A step
/// whose schema has a variable that its name leaves out and an effect uses gets its value in
/// a comment, `  3  i  % with C = b`, which `kbc validate` reads: without it the line would
/// not say which state change the step makes.
pub fn print(interner: &Interner, kb: &Kb, plan: &Plan) -> String {
    let mut out = String::new();
    let width = plan.steps.len().to_string().len();
    let no_vars = VarTable::default();
    for (i, step) in plan.steps.iter().enumerate() {
        let _ = write!(out, "{:>width$}  {}", i + 1, hir::term_to_string(interner, &step.name, &no_vars));
        let hidden = hidden_bindings(kb, step);
        if !hidden.is_empty() {
            let shown: Vec<String> = hidden
                .iter()
                .map(|(name, value)| {
                    format!("{} = {}", interner.resolve(*name), hir::term_to_string(interner, value, &no_vars))
                })
                .collect();
            let _ = write!(out, "  % with {}", shown.join(", "));
        }
        out.push('\n');
    }
    out
}

/// The variables of a step's schema that its name leaves out but an effect uses, with their
/// values: what a plan file must say for the step to mean one state change.
pub fn hidden_bindings(kb: &Kb, step: &Step) -> Vec<(Symbol, Term)> {
    let action = &kb.actions[step.action];
    let mut in_name = Vec::new();
    action.name.term.for_each_var(&mut |v| in_name.push(v));
    let mut out: Vec<(Symbol, Term)> = Vec::new();
    for effect in &action.effects {
        effect.literal.term.for_each_var(&mut |v| {
            let name = action.vars.get(v).name;
            if !in_name.contains(&v)
                && !out.iter().any(|(n, _)| *n == name)
                && let Some(Some(value)) = step.bindings.get(v.0 as usize)
            {
                out.push((name, value.clone()));
            }
        });
    }
    out
}

/// Checks that every step names an action of the KB with a ground name and one value slot per
/// schema variable. A failure is a compiler bug.
pub fn verify(kb: &Kb, plan: &Plan) -> Result<(), String> {
    if plan.problem >= kb.problems.len() {
        return Err(format!("problem #{} does not exist", plan.problem));
    }
    for (i, step) in plan.steps.iter().enumerate() {
        let Some(action) = kb.actions.get(step.action) else {
            return Err(format!("step {}: action #{} does not exist", i + 1, step.action));
        };
        if !step.name.is_ground() {
            return Err(format!("step {}: the name is not ground", i + 1));
        }
        if step.bindings.len() != action.vars.len() {
            return Err(format!("step {}: {} values for {} variables", i + 1, step.bindings.len(), action.vars.len()));
        }
    }
    Ok(())
}
