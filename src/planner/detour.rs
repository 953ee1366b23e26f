//! Detours: a plan step that holds a unit of a resource waiting is sent aside and finished
//! later.
//!
//! The search orders steps, not time, so it takes a block straight to its goal place even
//! where that place is ready only much later: the arm grips the block and starts the move,
//! and the move's end waits, the arm held, until the place is ready. On the ladder's larger
//! rungs most arms spend most of the plan like that (build_b50_a8: seven of eight arms held
//! about 140 time units each while one works). `reassign` cannot help: it keeps what happens
//! to the world and only remakes who does it.
//!
//! A detour remakes that one decision. For a *held* start (its end waits long after its
//! minimum duration; the caller picks them from the schedule) of a job (a unit's steps from
//! taking it to giving it back, see `passes::reassign`):
//!
//! - at the start's place in the plan, the same start with other values for its *chosen*
//!   variables ([`crate::ir::task::Schema::chosen_vars`], such as a move's destination) whose
//!   end applies at once, then that end and the job's steps after the original end (for
//!   std/blocks.pl: the block goes to a free cell and the arm lets it go);
//! - at the original end's place, the job's steps before the start again (the grip), the
//!   start with its original chosen values from where the first part left things (the move
//!   from the free cell to the goal place) and its end; the job's later steps follow as before.
//!
//! Every step is taken from the actions applicable in the state reached, under the search's
//! own semantics, so the result is a valid plan or no plan: a step of the original plan that
//! the detours make inapplicable (the free cell was another step's destination) fails the
//! rewrite and names the detour to blame, which the caller drops before trying again. Among
//! the alternatives for the chosen values, those no other step of the same action chooses
//! while this one is aside are tried first, cheapest first by `cost` (the least duration).
//! Nothing here is specific to the blocks world: the chosen variables, jobs and applicable
//! actions come from the KB.

use rustc_hash::FxHashMap;

use super::successors::{self, Applicable, Successors};
use super::{path_of, plan_from};
use crate::ir::hir::{Snap, Term};
use crate::ir::plan::Plan;
use crate::ir::task::{Pattern, State, Task};

/// A held start to send aside: plan indices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Held {
    /// The start that waits for its end.
    pub start: usize,
    /// Its end.
    pub end: usize,
    /// The job's steps before the start (taking the unit), repeated before the end.
    pub head: Vec<usize>,
    /// The job's steps after the end (giving the unit back), also taken right after the
    /// start's aside end.
    pub tail: Vec<usize>,
}

/// What a rewrite gave.
#[derive(Clone, Debug, PartialEq)]
pub struct Rewritten {
    /// The plan.
    pub plan: Plan,
    /// The indices (in the list given) of the detours it takes, in order; the others found
    /// no alternative and left their starts as they were.
    pub taken: Vec<usize>,
}

/// Why a rewrite gave no plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// The detour at this index of the list given made a later step inapplicable, or could
    /// not be finished.
    Detour(usize),
    /// The plan is not one the search's semantics accept (before any detour).
    Plan,
}

/// How many alternatives of a held start are tried before it is left as it is.
const ALTERNATIVES: usize = 128;

/// `plan` with the detours `held` (each at its own start, distinct jobs); `cost` is the least
/// duration of a start's durative action, given the start's action (its index in
/// `Kb::actions`) and name. `successors` is the task's (its OnKB cache is kept from one
/// rewrite to the next).
pub fn rewrite(
    successors: &mut Successors<'_>,
    task: &mut Task,
    plan: &Plan,
    held: &[Held],
    cost: &mut dyn FnMut(usize, &Term) -> i64,
) -> Result<Rewritten, Failure> {
    let path = path_of(task, plan);
    if path.len() != plan.steps.len() {
        return Err(Failure::Plan);
    }
    let mut rewriter = Rewriter {
        successors,
        names: path.iter().map(|a| successors::action_name(task, a)).collect(),
        end_index: end_index(task, &path),
        families: families(task),
        scratch: Vec::new(),
    };
    let start_of: FxHashMap<usize, usize> = held.iter().enumerate().map(|(d, h)| (h.start, d)).collect();
    let end_of: FxHashMap<usize, usize> = held.iter().enumerate().map(|(d, h)| (h.end, d)).collect();
    let mut state = task.init.clone();
    let mut out: Vec<Applicable> = Vec::with_capacity(path.len() + 6 * held.len());
    // The detours taken and not yet finished, in the order taken, with the chosen values they
    // took instead.
    let mut aside: Vec<(usize, Vec<Term>)> = Vec::new();
    let mut taken = Vec::new();
    for (k, action) in path.iter().enumerate() {
        if let Some(&d) = start_of.get(&k)
            && let Some((steps, next, values)) = rewriter.aside(task, &path, &held[d], &state, cost)
        {
            out.extend(steps);
            state = next;
            aside.push((d, values));
            taken.push(d);
            continue;
        }
        if let Some(&d) = end_of.get(&k)
            && let Some(position) = aside.iter().position(|(a, _)| *a == d)
        {
            let (steps, next) = rewriter.back(task, &path, &held[d], &state).ok_or(Failure::Detour(d))?;
            out.extend(steps);
            state = next;
            aside.remove(position);
            continue;
        }
        if !rewriter.applicable(task, &state, action) {
            return Err(blame(&aside, &rewriter.names[k]));
        }
        state = successors::apply(task, &state, action);
        out.push(action.clone());
    }
    if !successors::goal_reached(task, &state) {
        return Err(Failure::Plan);
    }
    Ok(Rewritten { plan: plan_from(task, &out), taken })
}

/// The detour to blame for the step named `failed` no longer applying: the latest of those
/// aside whose values the step's name holds, in a row (it goes where the detour left
/// something), or else the latest aside.
fn blame(aside: &[(usize, Vec<Term>)], failed: &Term) -> Failure {
    let args = failed.args();
    let holds = |values: &[Term]| !values.is_empty() && args.windows(values.len()).any(|w| w == values);
    let named = aside.iter().rev().find(|(_, values)| holds(values));
    named.or(aside.last()).map_or(Failure::Plan, |(d, _)| Failure::Detour(*d))
}

/// For each start of `path`, the index of the end that ends it (the first after it that ends
/// its running instance).
fn end_index(task: &mut Task, path: &[Applicable]) -> Vec<Option<usize>> {
    let mut found = vec![None; path.len()];
    let mut open: FxHashMap<crate::ir::task::ConstId, Vec<usize>> = FxHashMap::default();
    for (k, action) in path.iter().enumerate() {
        match task.schemas[action.schema].snap {
            Snap::Start => {
                let Task { schemas, consts, .. } = task;
                if let Some(running) = successors::running_instance(&schemas[action.schema], consts, &action.bindings) {
                    open.entry(running).or_default().push(k);
                }
            }
            Snap::End => {
                if let Some(starts) = action.ends.and_then(|r| open.get_mut(&r))
                    && !starts.is_empty()
                {
                    found[starts.remove(0)] = Some(k);
                }
            }
            Snap::Instant => {}
        }
    }
    found
}

/// For each schema, the schemas of the same snap whose names have its functor and arity (the
/// clauses of one action).
fn families(task: &Task) -> Vec<Vec<usize>> {
    let key = |i: usize| {
        let schema = &task.schemas[i];
        let functor = match &schema.name {
            Pattern::Compound(f, args) => Some((*f, args.len())),
            Pattern::Const(_) | Pattern::Var(_) => None,
        };
        (schema.snap, functor, schema.base)
    };
    (0..task.schemas.len()).map(|i| (0..task.schemas.len()).filter(|&j| key(j) == key(i)).collect()).collect()
}

struct Rewriter<'s, 'p> {
    successors: &'s mut Successors<'p>,
    /// The name of each step of the original plan.
    names: Vec<Term>,
    /// For each start of the original plan, the index of its end.
    end_index: Vec<Option<usize>>,
    families: Vec<Vec<usize>>,
    scratch: Vec<Applicable>,
}

impl Rewriter<'_, '_> {
    fn applicable(&mut self, task: &mut Task, state: &State, action: &Applicable) -> bool {
        self.successors.applies(task, action, state) == Ok(true)
    }

    /// The applicable actions of `schema`'s family in `state` whose names satisfy `keep`.
    fn family(
        &mut self,
        task: &mut Task,
        schema: usize,
        state: &State,
        keep: impl Fn(&Term) -> bool,
    ) -> Vec<Applicable> {
        let mut found = Vec::new();
        for member in self.families[schema].clone() {
            self.scratch.clear();
            if self.successors.schema(task, member, state, &mut self.scratch).is_err() {
                continue;
            }
            found.extend(self.scratch.drain(..).filter(|a| keep(&successors::action_name(task, a))));
        }
        found
    }

    /// The applicable action of step `k`'s family named as step `k` is.
    fn same(&mut self, task: &mut Task, path: &[Applicable], k: usize, state: &State) -> Option<Applicable> {
        let name = self.names[k].clone();
        self.family(task, path[k].schema, state, |n| *n == name).into_iter().next()
    }

    /// The end of the running start `start` applicable in `state`, in the family of `end`.
    fn end_of(&mut self, task: &mut Task, start: &Applicable, end: &Applicable, state: &State) -> Option<Applicable> {
        let Task { schemas, consts, .. } = task;
        let running = successors::running_instance(&schemas[start.schema], consts, &start.bindings)?;
        for member in self.families[end.schema].clone() {
            self.scratch.clear();
            if self.successors.ending(task, member, state, running, &mut self.scratch).is_ok()
                && let Some(found) = self.scratch.first()
            {
                return Some(found.clone());
            }
        }
        None
    }

    /// The first part of detour `h` in `state`: the start with other chosen values, its end
    /// and the job's tail, and the state after them; `None` when no alternative works.
    fn aside(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        h: &Held,
        state: &State,
        cost: &mut dyn FnMut(usize, &Term) -> i64,
    ) -> Option<(Vec<Applicable>, State, Vec<Term>)> {
        let start = &path[h.start];
        let positions = chosen_positions(task, start.schema);
        if positions.is_empty() {
            return None;
        }
        let wanted = self.names[h.start].args().to_vec();
        let alternatives = self.family(task, start.schema, state, |name| {
            let a = name.args();
            a.len() == wanted.len()
                && (0..a.len()).all(|p| positions.contains(&p) || a[p] == wanted[p])
                && positions.iter().any(|&p| a[p] != wanted[p])
        });
        // The chosen values other steps of this family take while this one would be aside
        // (starts between the held start and its end, and starts running across the start).
        let taken: Vec<Vec<Term>> = (0..self.names.len())
            .filter(|&k| k != h.start && self.families[start.schema].contains(&path[k].schema))
            .filter(|&k| k < h.end && (k > h.start || self.end_index[k].is_some_and(|e| e > h.start)))
            .map(|k| positions.iter().map(|&p| self.names[k].args()[p].clone()).collect())
            .collect();
        let mut ranked: Vec<(i64, usize, Applicable)> = alternatives
            .into_iter()
            .enumerate()
            .filter_map(|(i, a)| {
                let name = successors::action_name(task, &a);
                let values: Vec<Term> = positions.iter().map(|&p| name.args()[p].clone()).collect();
                (!taken.contains(&values)).then(|| (cost(task.schemas[a.schema].action, &name), i, a))
            })
            .collect();
        ranked.sort_by_key(|(cost, i, _)| (*cost, *i));
        let end = &path[h.end];
        for (_, _, alternative) in ranked.into_iter().take(ALTERNATIVES) {
            let mut next = successors::apply(task, state, &alternative);
            let Some(finish) = self.end_of(task, &alternative, end, &next) else { continue };
            next = successors::apply(task, &next, &finish);
            let mut steps = vec![alternative, finish];
            if self.again(task, path, &h.tail, &mut next, &mut steps) {
                let name = successors::action_name(task, &steps[0]);
                let values = positions.iter().map(|&p| name.args()[p].clone()).collect();
                return Some((steps, next, values));
            }
        }
        None
    }

    /// Takes the plan's steps `ks` again from `state`, each the applicable action named as
    /// it is, onto `steps`; false when one does not apply.
    fn again(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        ks: &[usize],
        state: &mut State,
        steps: &mut Vec<Applicable>,
    ) -> bool {
        for &k in ks {
            let Some(step) = self.same(task, path, k, state) else { return false };
            *state = successors::apply(task, state, &step);
            steps.push(step);
        }
        true
    }

    /// The second part of detour `h` in `state`, at the original end's place: the job's head
    /// again, the start with its original chosen values, and its end.
    fn back(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        h: &Held,
        state: &State,
    ) -> Option<(Vec<Applicable>, State)> {
        let mut next = state.clone();
        let mut steps = Vec::new();
        if !self.again(task, path, &h.head, &mut next, &mut steps) {
            return None;
        }
        let start = &path[h.start];
        let positions = chosen_positions(task, start.schema);
        let wanted = self.names[h.start].args().to_vec();
        let candidates = self.family(task, start.schema, &next, |name| {
            let a = name.args();
            a.len() == wanted.len() && positions.iter().all(|&p| a[p] == wanted[p])
        });
        // The most positions alike, the first found among equals.
        let (_, again) = candidates.into_iter().enumerate().max_by_key(|(i, a)| {
            let name = successors::action_name(task, a);
            (name.args().iter().zip(&wanted).filter(|(x, y)| x == y).count(), std::cmp::Reverse(*i))
        })?;
        next = successors::apply(task, &next, &again);
        let finish = self.end_of(task, &again, &path[h.end], &next)?;
        next = successors::apply(task, &next, &finish);
        steps.push(again);
        steps.push(finish);
        Some((steps, next))
    }
}

/// The argument positions of schema `index`'s name that are its chosen variables.
fn chosen_positions(task: &Task, index: usize) -> Vec<usize> {
    let schema = &task.schemas[index];
    let chosen = schema.chosen_vars();
    match &schema.name {
        Pattern::Compound(_, args) => {
            (0..args.len()).filter(|&p| matches!(args[p], Pattern::Var(v) if chosen.contains(&v))).collect()
        }
        Pattern::Const(_) | Pattern::Var(_) => Vec::new(),
    }
}
