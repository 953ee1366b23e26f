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

/// An arm-level plan: the `ll_action` steps a high-level plan refines into (pass `refine`).
#[derive(Clone, Debug, PartialEq)]
pub struct ArmPlan {
    /// The arm-level steps, in order; `plan.problem` is the arm-level problem.
    pub plan: Plan,
    /// For each arm-level step, the index of the high-level step whose mapping it comes from.
    pub origin: Vec<usize>,
    /// The arm-level problem's initial facts with the values the refinement gave their
    /// variables (a variable no step binds stays one).
    pub init: Vec<Term>,
}

/// The arm-level plan as numbered lines, each high-level step's arm-level steps under a
/// `%` comment naming it (which `kbc validate` skips):
///
/// ```text
/// % 1  move_start(a1, b1, 1, 1, 3, 3)
///   1  ll_reach(a1, 1, 1)
///   2  ll_grip(a1)
/// ```
pub fn print_arm(interner: &Interner, kb: &Kb, high: &Plan, arm: &Plan, origin: &[usize]) -> String {
    let mut out = String::new();
    let width = arm.steps.len().max(high.steps.len()).to_string().len();
    let no_vars = VarTable::default();
    let numbered = print(interner, kb, arm);
    let mut last = None;
    for (line, origin) in numbered.lines().zip(origin) {
        if last != Some(*origin) {
            let name = hir::term_to_string(interner, &high.steps[*origin].name, &no_vars);
            let _ = writeln!(out, "% {:>width$}  {name}", origin + 1);
            last = Some(*origin);
        }
        let (number, rest) = line.trim_start().split_once("  ").unwrap_or((line, ""));
        let _ = writeln!(out, "  {number:>width$}  {rest}");
    }
    out
}

/// Checks an arm-level plan: a valid plan of arm-level actions, one origin per step, each a
/// step of the high-level plan, in order. A failure is a compiler bug.
pub fn verify_arm(kb: &Kb, high: &Plan, arm: &ArmPlan) -> Result<(), String> {
    verify(kb, &arm.plan)?;
    if arm.origin.len() != arm.plan.steps.len() {
        return Err(format!("{} origins for {} steps", arm.origin.len(), arm.plan.steps.len()));
    }
    if arm.origin.iter().any(|&o| o >= high.steps.len()) || arm.origin.windows(2).any(|w| w[0] > w[1]) {
        return Err("origins out of range or out of order".to_string());
    }
    if let Some(step) = arm.plan.steps.iter().find(|s| kb.actions[s.action].level != hir::Level::Low) {
        return Err(format!("step `{:?}` is not an arm-level action", step.name));
    }
    if arm.init.len() != kb.problems[arm.plan.problem].init.len() {
        return Err("the instantiated initial state does not match the problem's".to_string());
    }
    Ok(())
}
