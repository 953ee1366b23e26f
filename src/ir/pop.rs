//! The partial-order plan: each snap action of a total-order plan with its achievers, and the
//! orderings every execution must respect.
//!
//! For each condition of each step the *candidates* are the earlier steps (or the initial
//! state) that could establish it: the disjunction of the paper's disjunctive temporal network.
//! The *last* candidate is the one the paper keeps when it lowers the DTN to an STN. Orderings
//! are the links from those last achievers, each end after its start, and the threat
//! orderings the paper leaves out: a step that deletes a fact a link protects comes before the
//! link's producer or after its consumer, and a step that adds a fact an Invalid condition
//! forbids comes after that condition's step (or before the step that deletes it again).
//! With them, every linearisation of the partial order is a valid plan.

use std::fmt::Write;

use crate::intern::Interner;
use crate::ir::hir::{self, Kb, Snap, Term, VarTable};
use crate::source::Span;

/// Who establishes a condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Achiever {
    /// The initial state (the paper's `a0`).
    Init,
    /// A step, by its index in the plan.
    Step(usize),
}

/// What kind of condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConditionKind {
    /// A Valid literal: a fact that must hold.
    Valid,
    /// An Invalid literal: no fact may match it.
    Invalid,
    /// A goal literal, at the end of the plan.
    Goal,
}

/// One condition of a step (or of the goal), instantiated.
#[derive(Clone, Debug, PartialEq)]
pub struct Condition {
    /// What kind.
    pub kind: ConditionKind,
    /// The literal under the step's bindings; an Invalid literal keeps its existential
    /// variables (numbered as in `vars`).
    pub literal: Term,
    /// The literal's variables (existential ones only).
    pub vars: VarTable,
    /// Where the literal is written in the KB.
    pub span: Span,
    /// Every earlier step (or the initial state) that could establish it, in plan order: for a
    /// Valid or goal literal, those that add the fact; for an Invalid literal, those that
    /// delete a fact it forbids.
    pub candidates: Vec<Achiever>,
    /// The last candidate, kept for the STN; `Init` when the condition holds initially and
    /// nothing re-establishes it.
    pub last: Achiever,
}

/// One step of the partial-order plan.
#[derive(Clone, Debug, PartialEq)]
pub struct PopStep {
    /// The schema's index in `Kb::actions`.
    pub action: usize,
    /// The ground action name.
    pub name: Term,
    /// Start, end or instantaneous.
    pub snap: Snap,
    /// For an end, the step that started it.
    pub start: Option<usize>,
    /// Its conditions: Valid literals, then Invalid ones, in schema order.
    pub conditions: Vec<Condition>,
}

/// Why one step must come before another. (Ordered only so that lists of reasons sort
/// deterministically.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Reason {
    /// `before` is the last achiever of condition `condition` of `after`.
    Achiever {
        /// The condition's index in the consumer's `conditions`.
        condition: usize,
    },
    /// `before` is the start that `after` ends.
    StartEnd,
    /// Arm-level steps ordered by their refinement: consecutive steps of one mapping, or the
    /// last step of a high-level action's mapping and the first of one the high-level partial
    /// order puts after it.
    Refinement,
    /// Both steps are arm-level actions of one unit of a renewable resource (one arm), which
    /// does one thing at a time: they keep their plan order.
    SameUnit,
    /// `before` deletes a fact protected by a link from `producer` to `consumer`'s condition
    /// `condition`, or adds a fact that condition forbids.
    Threat {
        /// The step whose condition is protected (`usize::MAX` for the goal).
        consumer: usize,
        /// The condition's index in the consumer's `conditions` (or in `Pop::goal`).
        condition: usize,
    },
}

/// `before` must happen before `after`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ordering {
    /// The earlier step.
    pub before: usize,
    /// The later step.
    pub after: usize,
    /// Why.
    pub reason: Reason,
}

/// A partial-order plan.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Pop {
    /// The problem's index in `Kb::problems`.
    pub problem: usize,
    /// The steps, in the order of the total-order plan.
    pub steps: Vec<PopStep>,
    /// The goal literals, matched against the final state, with their achievers.
    pub goal: Vec<Condition>,
    /// The orderings, without repeats, sorted by (after, before): one per pair of steps, with
    /// its strongest reason.
    pub orderings: Vec<Ordering>,
    /// The other reasons for pairs in `orderings`, sorted the same way. A pass that discards
    /// orderings for some reasons (`reassign` drops those through a unit's resource fact) must
    /// look here too: one step can both give an arm back and make a block clear for it.
    pub other_reasons: Vec<Ordering>,
}

impl Pop {
    /// The achiever list of step `i` as the paper's table shows it: the last achiever of each
    /// condition, without repeats, in plan order (`Init` first).
    pub fn achievers(&self, i: usize) -> Vec<Achiever> {
        let mut list: Vec<Achiever> = self.steps[i].conditions.iter().map(|c| c.last).collect();
        if let Some(start) = self.steps[i].start {
            list.push(Achiever::Step(start));
        }
        list.sort();
        list.dedup();
        if list.len() > 1 {
            list.retain(|a| *a != Achiever::Init);
        }
        list
    }
}

fn achiever_name(a: Achiever) -> String {
    match a {
        Achiever::Init => "a0".to_string(),
        Achiever::Step(i) => format!("a{}", i + 1),
    }
}

/// The text form (`--dump-after pop`): the paper's table of achievers, then the orderings.
pub fn print(interner: &Interner, pop: &Pop) -> String {
    let mut out = String::new();
    let no_vars = VarTable::default();
    let _ = writeln!(out, "% partial-order plan: {} steps, {} orderings", pop.steps.len(), pop.orderings.len());
    for (i, step) in pop.steps.iter().enumerate() {
        let achievers: Vec<String> = pop.achievers(i).into_iter().map(achiever_name).collect();
        let _ = writeln!(
            out,
            "a{:<3} {:<40} [{}]",
            i + 1,
            hir::term_to_string(interner, &step.name, &no_vars),
            achievers.join(", ")
        );
        for condition in &step.conditions {
            let candidates: Vec<String> = condition.candidates.iter().map(|&a| achiever_name(a)).collect();
            let _ = writeln!(
                out,
                "       {} {}  candidates [{}]",
                match condition.kind {
                    ConditionKind::Valid => "valid  ",
                    ConditionKind::Invalid => "invalid",
                    ConditionKind::Goal => "goal   ",
                },
                hir::term_to_string(interner, &condition.literal, &condition.vars),
                candidates.join(", ")
            );
        }
    }
    for condition in &pop.goal {
        let _ = writeln!(
            out,
            "goal {}  [{}]",
            hir::term_to_string(interner, &condition.literal, &condition.vars),
            achiever_name(condition.last)
        );
    }
    for ordering in &pop.orderings {
        let why = match ordering.reason {
            Reason::Achiever { .. } => "achiever",
            Reason::StartEnd => "start-end",
            Reason::Threat { .. } => "threat",
            Reason::Refinement => "refinement",
            Reason::SameUnit => "same unit",
        };
        let _ = writeln!(out, "order a{} < a{}  ({why})", ordering.before + 1, ordering.after + 1);
    }
    out
}

/// Checks the invariants: indices in range, every ordering agrees with the total order (so the
/// orderings are acyclic), every last achiever is among the candidates and before its step,
/// ends know their starts, every other reason is for an ordering's pair. A failure is a
/// compiler bug.
pub fn verify(kb: &Kb, pop: &Pop) -> Result<(), String> {
    let n = pop.steps.len();
    let check_condition = |step: Option<usize>, c: &Condition| -> Result<(), String> {
        if c.last != Achiever::Init && !c.candidates.contains(&c.last) {
            return Err(format!("{step:?}: last achiever {:?} is not a candidate", c.last));
        }
        for candidate in &c.candidates {
            if let Achiever::Step(j) = candidate
                && (*j >= n || step.is_some_and(|i| *j >= i))
            {
                return Err(format!("{step:?}: candidate a{} does not come earlier", j + 1));
            }
        }
        Ok(())
    };
    for (i, step) in pop.steps.iter().enumerate() {
        if step.action >= kb.actions.len() {
            return Err(format!("step {}: action out of range", i + 1));
        }
        match (step.snap, step.start) {
            (Snap::End, Some(s)) if s < i && pop.steps[s].snap == Snap::Start => {}
            (Snap::End, other) => return Err(format!("step {}: an end with start {other:?}", i + 1)),
            (_, None) => {}
            (_, Some(_)) => return Err(format!("step {}: only ends have starts", i + 1)),
        }
        step.conditions.iter().try_for_each(|c| check_condition(Some(i), c))?;
    }
    pop.goal.iter().try_for_each(|c| check_condition(None, c))?;
    for o in &pop.orderings {
        if o.before >= o.after || o.after >= n {
            return Err(format!("ordering a{} < a{} is against the total order", o.before + 1, o.after + 1));
        }
    }
    if pop.orderings.windows(2).any(|w| (w[0].after, w[0].before) >= (w[1].after, w[1].before)) {
        return Err("orderings are not sorted without repeats".to_string());
    }
    for o in &pop.other_reasons {
        let pair = |p: &Ordering| (p.after, p.before);
        match pop.orderings.binary_search_by_key(&pair(o), pair) {
            Ok(i) if pop.orderings[i] != *o => {}
            _ => {
                return Err(format!(
                    "reason {:?} for a{} < a{} is not another reason of an ordering",
                    o.reason,
                    o.before + 1,
                    o.after + 1
                ));
            }
        }
    }
    Ok(())
}
