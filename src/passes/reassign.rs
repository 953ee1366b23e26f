//! Pass `reassign`: a scheduled plan is rearranged into candidate plans with a shorter
//! makespan, by giving each *job* to the unit of its resource that can do it soonest.
//!
//! The search decides what happens to the world (which block goes where, through which buffer
//! cell) and also, step by step, which unit of a renewable resource (`resources/1`: an arm)
//! does it and in which order. The second choice is made for a total order, with little idea
//! of time, and wastes parallelism: an arm grips a block long before the place it goes to is
//! ready, while a job that others wait for queues behind it. This pass keeps the first
//! decision and remakes the second:
//!
//! - a *job* is what one unit does from the step that takes it (a step whose effects delete
//!   the unit's resource fact, `available(a1)`) to the step that gives it back (one that adds
//!   the fact again), with every step between them that names the unit: for std/blocks.pl,
//!   the grip, the move and the release of one block. When no action changes the template's
//!   facts (`resources(agent(_))` over the KB's `agent(a1).`), the unit's one-argument facts
//!   that effects delete and add (`free(a1)`) take and give it back;
//! - what each step waits for apart from its unit is the partial order without the orderings
//!   that come from resource facts, plus each durative action's minimum duration;
//! - list scheduling in simulated time then starts the steps in time order, and gives a free
//!   unit to a waiting job: the most urgent first (the longest path from it to the end of the
//!   plan), started *just in time* (no earlier than needed for its steps that other jobs wait
//!   for, and its last, to happen when they could anyway), so an arm does not hold a block in
//!   the air while another job could use it. Variants of the rule (without just-in-time
//!   starts, in the plan's order) make further candidates;
//! - a job whose steps wait for a job not started yet (a block lifted so that another can take
//!   its cell, which must be lifted first itself) holds its unit until that other job gets
//!   one. Given out greedily, such jobs can take every unit but one or two, and their partners
//!   queue for those (reverse_b50_a8_s1: six of eight arms held a block about 30 time units
//!   each). One more candidate *reserves*: such a job starts only if it leaves a free unit for
//!   its partner and for each started job still waiting so (when no step can be placed that
//!   way, the simulation places one without reserving). Measured on the ladder (`kbc bench
//!   --search heuristic`, one run per seed, the three rules against the four): the sum of
//!   makespans over the 52 rungs 2647 -> 2467 (seed 1), 2586 -> 2419 (seed 2), 2681 -> 2518
//!   (seed 3); reverse_b50_a8_s1 88 -> 63, reverse_b100_a10_s1 151 -> 118.
//!
//! - *variants* of the two urgent just-in-time rules (with and without reserving) scale each
//!   step's urgency by a factor from 1 to 1.4 drawn from a hash of the step and the variant's
//!   number: steps the simulation could place at the same time and of about the same urgency
//!   come in other orders, and so other jobs take the free units. The driver asks for them
//!   where a plan is first rearranged and in a last pass over the finished plan (see
//!   `session::temporal::reassign`, which also tries small plans without them). Measured on
//!   the ladder (`kbc bench --search heuristic`, one run per seed, eight variants in both
//!   places against none): the sum of makespans over the 52 rungs 2332 -> 2310 (seed 1),
//!   2257 -> 2235 (seed 2), 2357 -> 2326 (seed 3); build_b50_a8_s3 67 -> 61,
//!   reverse_b20_a4_s3 52 -> 47; the slowest rung 3.5-4.0 s before, 3.5-4.5 s after (the
//!   simulation now recomputes its lower bounds only when they change, which paid for most
//!   of the variants' time).
//!
//! - each of the four fixed rules also runs *backwards* ([`Problem::reversed`]): the plan
//!   simulated from its end, every ordering turned round and every job taking its unit at its
//!   last step, and the times read from the end. Forwards, a free unit goes to a job that can
//!   start at once rather than to one that must wait a little, and a job whose step a long
//!   chain waits for but which itself ends soon ranks low (its tail is short: the chain's long
//!   steps come before the step that waits for it); the plan's last jobs then queue at the
//!   end while the other units idle. Backwards, the last jobs are laid out first, from the
//!   end, and the jobs they wait for are placed as late as that allows: a right-justified
//!   schedule, which the STN then starts as early as it can (as in the forward-backward
//!   improvement of schedules in project scheduling). On build_b100_a10_s2 the last tower's
//!   base waited for a block that left its cell only at 112 of 135, going straight to its
//!   own tower; six of ten arms idled the last 17 time units: 135 -> 122 with them. Measured on
//!   the ladder (`kbc bench --search heuristic`, one run per seed, against the forward rules
//!   alone): the sums of makespans over the 52 rungs of seeds 1/2/3 2274/2221/2301 ->
//!   2193/2131/2209, of the unseen seeds 4-8 2187/2302/2256/2222/2237 ->
//!   2119/2210/2169/2142/2142; over the 416 rungs of seeds 1-8, 169 shorter and 18 longer
//!   (reverse_b100_a10_s5 92 -> 102: its first rearrangement was shorter, 300 -> 171 rather
//!   than 193, and the relocations found less after it), within 1.15x of the bound 290 -> 342
//!   and within 1.3x 409 -> 413; build_b100_a8_s1 174 -> 149 (bound 146); the sums of rung
//!   times within noise. The backward rule in plan order alone gives most of it (seeds 1/2/3
//!   2206/2155/2221); backwards only in the last `polish`, no rung was longer but the gain was
//!   smaller (seeds 1/5: 2223/2236 against 2193/2210); the urgent variants backwards as well
//!   gave no more (2191/2136/2202) in 5-16% more time than the fixed rules backwards alone.
//!
//! Each candidate is a total-order plan: the steps sorted by their simulated times (ends
//! before starts at equal times), each job's steps naming its new unit. The simulation is an
//! estimate; the driver keeps a candidate only if the search's semantics accept it step by
//! step and its own STN schedule is shorter (see `driver::reassign`).
//!
//! A KB that declares no resource gets the one its actions imply ([`jobs`]: a `p/1` fact that
//! only starts needing it delete and only ends add, `free(R)` in a pick-and-place KB). Measured
//! with `kbc plan --schedule` on the warehouse KBs of `benches/other_domains` (no
//! `resources/1`; robots that travel, so not interchangeable, which the candidates' checks
//! enforce): makespans 84 -> 70 (`warehouse_c20_r2_s25`), 97 -> 85 (`_c20_r3_s30`), 108 -> 90
//! (`_c25_r3_s30`), in the same time. (Where the units are interchangeable, the search takes
//! the resource too: `session::resources_of`.)
//!
//! The pass does nothing (no candidates) when the KB declares and implies no resource, when a
//! resource template has other than one variable (a unit is one value), when a step takes or
//! names two units, or when a unit is used outside a job (held in the initial state).

use crate::ir::hir::{EffectKind, Kb, Snap, Term};
use crate::ir::plan::{Plan, Step};
use crate::ir::pop::{ConditionKind, Pop, Reason};
use crate::ir::stn::Stn;
use crate::ir::unify::unifiable;
use crate::passes::pop::instantiate;

/// The candidates of a plan ([`candidates`]): for each, the makespan the simulation estimates
/// and, when asked for, the rearranged plan. The plans are made only when asked for: the
/// driver looks at the best few (`session::temporal::rearrange` stops at the first that is
/// shorter), and making all of them took 5% of `kbc plan`'s instructions on
/// reverse_b06_a3_s1.
pub struct Candidates<'a> {
    plan: &'a Plan,
    /// What the plans are made from (`None` when the pass does not apply).
    problem: Option<Problem>,
    /// The simulations that gave a plan not given already, best estimate first.
    found: Vec<Simulated>,
}

/// One simulation's result: its estimate, the steps in its order and each job's unit.
struct Simulated {
    estimate: i64,
    order: Vec<usize>,
    units: Vec<usize>,
}

/// A candidate of [`Candidates`].
pub struct Candidate<'c> {
    /// The simulated makespan, in STN units.
    pub estimate: i64,
    of: &'c Candidates<'c>,
    index: usize,
}

impl Candidate<'_> {
    /// The rearranged plan.
    pub fn plan(&self) -> Plan {
        let found = &self.of.found[self.index];
        let problem = self.of.problem.as_ref().expect("a candidate comes from a problem");
        rearranged(self.of.plan, problem, &found.order, &found.units)
    }
}

impl Candidates<'_> {
    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.found.is_empty()
    }

    /// The candidates, best estimate first.
    pub fn iter(&self) -> impl Iterator<Item = Candidate<'_>> {
        (0..self.found.len()).map(|index| Candidate { estimate: self.found[index].estimate, of: self, index })
    }
}

/// The rules the simulation is run with, one candidate each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Rule {
    /// Start a job as late as its exported steps and last step allow.
    just_in_time: bool,
    /// Rank waiting jobs by urgency (else by plan order).
    urgency: bool,
    /// Keep a unit free for each started job that waits for a job not started yet.
    reserve: bool,
    /// 0, or the number of a variant: urgencies scaled step by step (see [`varied`]).
    variant: u64,
    /// Simulate the plan backwards from its end (see [`Problem::reversed`]).
    backward: bool,
}

const RULES: [Rule; 4] = [
    Rule { just_in_time: true, urgency: true, reserve: false, variant: 0, backward: false },
    Rule { just_in_time: false, urgency: true, reserve: false, variant: 0, backward: false },
    Rule { just_in_time: true, urgency: false, reserve: false, variant: 0, backward: false },
    Rule { just_in_time: true, urgency: true, reserve: true, variant: 0, backward: false },
];

/// The fixed rules: the four of [`RULES`] forwards, then each backwards.
fn fixed() -> impl Iterator<Item = Rule> {
    [false, true].into_iter().flat_map(|backward| RULES.into_iter().map(move |rule| Rule { backward, ..rule }))
}

/// Which rules [`candidates`] simulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rules {
    /// The four fixed rules of the module docs, forwards and backwards ([`fixed`]).
    Fixed,
    /// The fixed rules, then `n` variants of the two urgent just-in-time ones (with and
    /// without reserving): `2 n` more candidates.
    WithVariants(u64),
    /// Only the `2 n` candidates of the variants.
    Variants(u64),
}

impl Rules {
    fn list(self) -> Vec<Rule> {
        let variants = |n: u64| {
            (1..=n).flat_map(|variant| {
                let greedy = Rule { just_in_time: true, urgency: true, reserve: false, variant, backward: false };
                [greedy, Rule { reserve: true, ..greedy }]
            })
        };
        match self {
            Rules::Fixed => fixed().collect(),
            Rules::WithVariants(n) => fixed().chain(variants(n)).collect(),
            Rules::Variants(n) => variants(n).collect(),
        }
    }
}

/// Step `step`'s urgency (`tail`) in variant `variant` of a rule: scaled by a factor from 1
/// to 1.4 drawn from a hash of the two (0: unscaled). The simulation breaks ties in time by
/// urgency; steps of about the same urgency then come in other orders, and so do the jobs that
/// take the units, which gives other list schedules to choose from. The same plan gives the
/// same variants.
fn varied(tail: i64, step: usize, variant: u64) -> i64 {
    if variant == 0 {
        return tail;
    }
    // A 64-bit mix (splitmix64's finaliser) of the step and the variant.
    let mut h = (step as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ variant.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 29;
    h = h.wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^= h >> 32;
    tail * (1000 + (h % 400) as i64) / 1000
}

/// One unit's resource: the template (`available(_)`) and the argument position of its unit.
struct Template {
    term: Term,
    position: usize,
    /// Whether some action adds or deletes facts that match it. When none does (`agent(_)`,
    /// with the KB's `agent(a1).` facts), a unit is taken and given back through the one-argument
    /// facts of the unit that effects delete and add (`free(a1)`).
    dynamic: bool,
}

/// A job: a unit's steps from taking it to giving it back, in plan order.
struct Job {
    /// Which template the unit belongs to.
    template: usize,
    /// The unit the plan gave it.
    unit: usize,
    steps: Vec<usize>,
}

/// What the simulation works on.
struct Problem {
    /// Each step's kind.
    snaps: Vec<Snap>,
    /// For each step, the steps it waits for and the least separation from each.
    preds: Vec<Vec<(usize, i64)>>,
    /// For each step, whether a step of another job (or none) waits for it.
    exported: Vec<bool>,
    /// For each step, its job.
    job_of: Vec<Option<usize>>,
    jobs: Vec<Job>,
    /// Units: (template, term).
    units: Vec<(usize, Term)>,
    /// The longest path from each step to the end of the plan, in time.
    tail: Vec<i64>,
    /// For each job, what its steps wait for in other jobs: (its step, the step waited for,
    /// that step's job) (see [`waits_on`]).
    waits_on: Vec<Vec<(usize, usize, usize)>>,
}

/// For each job of `jobs`, the steps of other jobs its own steps wait for (`preds`): (its step,
/// the step waited for, that step's job).
fn waits_on(jobs: &[Job], preds: &[Vec<(usize, i64)>], job_of: &[Option<usize>]) -> Vec<Vec<(usize, usize, usize)>> {
    let others = |j: usize, s: usize| {
        preds[s].iter().filter_map(move |&(p, _)| job_of[p].filter(|&q| q != j).map(|q| (s, p, q)))
    };
    jobs.iter().enumerate().map(|(j, job)| job.steps.iter().flat_map(|&s| others(j, s)).collect()).collect()
}

/// Candidate plans for `plan`, one per rule of `rules` that gives a plan not given already,
/// best estimate first; `pop` and `stn` are its partial order and temporal network. Empty
/// when the pass does not apply (see the module docs) or when no rule gives a schedule (the
/// simulation can deadlock: every unit held by a job that waits for a job without one).
pub fn candidates<'a>(kb: &Kb, plan: &'a Plan, pop: &Pop, stn: &Stn, rules: Rules) -> Candidates<'a> {
    let Some(problem) = analyse(kb, plan, pop, stn) else {
        return Candidates { plan, problem: None, found: Vec::new() };
    };
    let mut found: Vec<Simulated> = Vec::new();
    let given: Vec<usize> = problem.jobs.iter().map(|j| j.unit).collect();
    let mut reversed = None;
    for rule in rules.list() {
        let Some((times, units)) = simulated(&problem, &mut reversed, rule) else { continue };
        let estimate = times.iter().copied().max().unwrap_or(0);
        let order = order_of(&problem, &times);
        // (A plan is its steps' order and its jobs' units: the same ones make the same plan.)
        let unchanged = units == given && order.iter().enumerate().all(|(k, &i)| k == i);
        if !unchanged && !found.iter().any(|f| f.order == order && f.units == units) {
            found.push(Simulated { estimate, order, units });
        }
    }
    found.sort_by_key(|f| f.estimate);
    Candidates { plan, problem: Some(problem), found }
}

/// The simulation of `problem` under `rule` ([`simulate`]) in the plan's time: each step's
/// time and each job's unit. A backward rule simulates `reversed` (made the first time one
/// asks, [`Problem::reversed`]) and reads its times from its end.
fn simulated(problem: &Problem, reversed: &mut Option<Problem>, rule: Rule) -> Option<(Vec<i64>, Vec<usize>)> {
    if !rule.backward {
        return simulate(problem, rule);
    }
    let (times, units) = simulate(reversed.get_or_insert_with(|| problem.reversed()), rule)?;
    let end = times.iter().copied().max().unwrap_or(0);
    Some((times.into_iter().map(|t| end - t).collect(), units))
}

/// True if `term` is `unit` or contains it.
fn mentions(term: &Term, unit: &Term) -> bool {
    term == unit || term.args().iter().any(|a| mentions(a, unit))
}

/// The unit a ground fact is of, if it is a resource fact: one that matches a resource
/// template that effects change, or, for a template they do not (`agent(_)`), a one-argument
/// fact of one of its units (`free(a1)`).
fn unit_of(templates: &[Template], units: &[(usize, Term)], fact: &Term) -> Option<usize> {
    templates.iter().enumerate().find_map(|(t, template)| {
        let value = if template.dynamic {
            if !unifiable(&template.term, fact) {
                return None;
            }
            fact.args().get(template.position)?
        } else {
            match fact.args() {
                [value] if fact.callable() != template.term.callable() => value,
                _ => return None,
            }
        };
        units.iter().position(|(ut, term)| *ut == t && term == value)
    })
}

/// The jobs of a plan: each unit's steps from the step that takes it to the one that gives it
/// back, in plan order (see the module docs), with the units and each step's job.
pub struct Jobs {
    templates: Vec<Template>,
    /// Units: (template, term).
    units: Vec<(usize, Term)>,
    jobs: Vec<Job>,
    /// For each step, its job.
    job_of: Vec<Option<usize>>,
}

impl Jobs {
    /// Each job's steps, in plan order.
    pub fn steps(&self) -> impl Iterator<Item = &[usize]> {
        self.jobs.iter().map(|j| j.steps.as_slice())
    }

    /// The job of step `i`, if it is in one.
    pub fn job_of(&self, i: usize) -> Option<usize> {
        self.job_of[i]
    }

    /// Job `j`'s steps, in plan order.
    pub fn job(&self, j: usize) -> &[usize] {
        &self.jobs[j].steps
    }

    /// The unit the plan gave job `j`.
    pub fn unit(&self, j: usize) -> &Term {
        &self.units[self.jobs[j].unit].1
    }

    /// The units of job `j`'s resource, in the order first met (the initial state, then the
    /// plan's effects).
    pub fn units_like(&self, j: usize) -> impl Iterator<Item = &Term> {
        let template = self.jobs[j].template;
        self.units.iter().filter(move |(t, _)| *t == template).map(|(_, term)| term)
    }
}

/// The jobs of `plan`, or `None` when the pass does not apply to it (see the module docs):
/// those of the KB's `resources/1` templates, or, when it declares none, of the first
/// resource its actions imply ([`implied`]) that gives the plan jobs.
pub fn jobs(kb: &Kb, plan: &Plan) -> Option<Jobs> {
    if kb.resources.is_empty() {
        return implied(kb).into_iter().find_map(|template| jobs_of(kb, plan, vec![template]));
    }
    // Templates with exactly one variable position.
    let mut templates = Vec::new();
    for resource in &kb.resources {
        let args = resource.template.term.args();
        let vars: Vec<usize> = (0..args.len()).filter(|&i| matches!(args[i], Term::Var(_))).collect();
        if vars.len() != 1 {
            return None;
        }
        let term = resource.template.term.clone();
        let dynamic = kb.actions.iter().flat_map(|a| &a.effects).any(|e| unifiable(&term, &e.literal.term));
        templates.push(Template { term, position: vars[0], dynamic });
    }
    jobs_of(kb, plan, templates)
}

/// [`implied_resources`] as the pass's templates.
fn implied(kb: &Kb) -> Vec<Template> {
    implied_resources(kb).into_iter().map(|term| Template { term, position: 0, dynamic: true }).collect()
}

/// The templates (`p(_)`) of the resources `kb`'s actions imply, whether it declares resources
/// or not, in the order its actions first delete them: each one-argument predicate `p/1`
/// (`free/1`, `available/1`) that actions both delete and add, where every action that deletes
/// a `p(X)` is the start of a durative action with `p(X)` among its Valid literals (it takes a
/// unit it needs), and every action that adds one is an end (it gives the unit back).
/// `clear/1` in the blocks world is not one: an end deletes it (`grip_end`). This pass's jobs
/// of them are checked as any plan is ([`candidates`] only proposes), so a predicate that is
/// not a resource costs time, never a wrong plan.
pub fn implied_resources(kb: &Kb) -> Vec<Term> {
    let unary = |term: &Term| match term {
        Term::Compound(name, args) if args.len() == 1 => Some(*name),
        _ => None,
    };
    let mut found: Vec<crate::intern::Symbol> = Vec::new();
    let mut refused: Vec<crate::intern::Symbol> = Vec::new();
    let mut added: Vec<crate::intern::Symbol> = Vec::new();
    for action in &kb.actions {
        for effect in &action.effects {
            let Some(name) = unary(&effect.literal.term) else { continue };
            match effect.kind {
                EffectKind::Del => {
                    let needed = action.valid.iter().any(|v| v.term == effect.literal.term);
                    if action.snap == Snap::Start && needed {
                        if !found.contains(&name) {
                            found.push(name);
                        }
                    } else if !refused.contains(&name) {
                        refused.push(name);
                    }
                }
                EffectKind::Add => {
                    if action.snap != Snap::End && !refused.contains(&name) {
                        refused.push(name);
                    }
                    if !added.contains(&name) {
                        added.push(name);
                    }
                }
            }
        }
    }
    found
        .into_iter()
        .filter(|name| added.contains(name) && !refused.contains(name))
        .map(|name| Term::Compound(name, crate::ir::args::Args::from([Term::Var(crate::ir::hir::VarId(0))])))
        .collect()
}

/// [`jobs`] with the given resource templates.
fn jobs_of(kb: &Kb, plan: &Plan, templates: Vec<Template>) -> Option<Jobs> {
    let n = plan.steps.len();
    if templates.is_empty() {
        return None;
    }
    // Each step's effects, and the units: the values of facts that match a template in the
    // initial state, the KB's facts and effects.
    let effects: Vec<Vec<(EffectKind, Term)>> = plan
        .steps
        .iter()
        .map(|step| {
            let action = &kb.actions[step.action];
            action.effects.iter().map(|e| (e.kind, instantiate(&e.literal.term, &step.bindings))).collect()
        })
        .collect();
    let init = kb.problems[plan.problem].init.iter().map(|l| &l.term);
    let mut units: Vec<(usize, Term)> = Vec::new();
    let kb_facts = kb.static_facts().map(|l| &l.term);
    for fact in init.chain(kb_facts).chain(effects.iter().flatten().map(|(_, fact)| fact)) {
        for (t, template) in templates.iter().enumerate() {
            if unifiable(&template.term, fact)
                && let Some(value) = fact.args().get(template.position)
                && !units.iter().any(|(ut, v)| *ut == t && v == value)
            {
                units.push((t, value.clone()));
            }
        }
    }
    // Jobs, by scanning the plan.
    let mut open: Vec<Option<usize>> = vec![None; units.len()];
    let mut jobs: Vec<Job> = Vec::new();
    let mut job_of: Vec<Option<usize>> = vec![None; n];
    for (i, step) in plan.steps.iter().enumerate() {
        let mut takes = Vec::new();
        let mut gives = Vec::new();
        for (kind, fact) in &effects[i] {
            if let Some(unit) = unit_of(&templates, &units, fact) {
                let list = match kind {
                    EffectKind::Del => &mut takes,
                    EffectKind::Add => &mut gives,
                };
                if !list.contains(&unit) {
                    list.push(unit);
                }
            }
        }
        let named: Vec<usize> = (0..units.len()).filter(|&u| mentions(&step.name, &units[u].1)).collect();
        if takes.len() > 1 || gives.len() > 1 || named.len() > 1 {
            return None;
        }
        if let Some(&unit) = takes.first() {
            if open[unit].is_some() {
                return None;
            }
            open[unit] = Some(jobs.len());
            jobs.push(Job { template: units[unit].0, unit, steps: Vec::new() });
        }
        let unit = takes.first().or(gives.first()).or(named.first()).copied();
        if let Some(unit) = unit {
            let job = open[unit]?; // a unit used outside a job
            jobs[job].steps.push(i);
            job_of[i] = Some(job);
        }
        if let Some(&unit) = gives.first() {
            open[unit] = None;
        }
    }
    if open.iter().any(Option::is_some) {
        return None; // a job that never gives its unit back
    }
    Some(Jobs { templates, units, jobs, job_of })
}

fn analyse(kb: &Kb, plan: &Plan, pop: &Pop, stn: &Stn) -> Option<Problem> {
    let n = plan.steps.len();
    if n == 0 || pop.steps.len() != n {
        return None;
    }
    let Jobs { templates, units, jobs, job_of } = jobs(kb, plan)?;
    if units.len() < 2 {
        return None; // nothing to choose between
    }
    // Orderings, without those that come from resource facts.
    let through_resource = |literal: &Term| unit_of(&templates, &units, literal).is_some();
    let snaps: Vec<Snap> = pop.steps.iter().map(|s| s.snap).collect();
    let mut preds: Vec<Vec<(usize, i64)>> = vec![Vec::new(); n];
    // A pair kept for a resource fact may have other reasons too (`release_end(a1, b1)` gives
    // the arm back and makes b1 clear for the arm's next grip): any one of them keeps it.
    for ordering in pop.orderings.iter().chain(&pop.other_reasons) {
        let literal = match ordering.reason {
            Reason::Achiever { condition } => pop.steps[ordering.after].conditions.get(condition).map(|c| &c.literal),
            Reason::Threat { consumer, condition } if consumer < n => {
                pop.steps[consumer].conditions.get(condition).map(|c| &c.literal)
            }
            Reason::Threat { condition, .. } => {
                pop.goal.get(condition).filter(|c| c.kind == ConditionKind::Goal).map(|c| &c.literal)
            }
            Reason::StartEnd | Reason::Refinement | Reason::SameUnit => None,
        };
        if literal.is_some_and(through_resource) {
            continue;
        }
        preds[ordering.after].push((ordering.before, stn.epsilon));
    }
    for list in &mut preds {
        list.sort_unstable();
        list.dedup();
    }
    for (end, step) in pop.steps.iter().enumerate() {
        if let Some(start) = step.start {
            let min = stn.durations[start].map_or(stn.epsilon, |b| b.min.max(stn.epsilon));
            preds[end].push((start, min));
        }
    }
    Some(Problem::new(snaps, preds, job_of, jobs, units, false))
}

impl Problem {
    /// The problem of steps of kinds `snaps`, each waiting for `preds` (step, least
    /// separation), in jobs of units, with what follows: the steps another job waits for, the
    /// urgencies (tails) and what each job waits for. Every ordering goes forward in plan
    /// order, or with `backward` every one goes backward.
    fn new(
        snaps: Vec<Snap>,
        preds: Vec<Vec<(usize, i64)>>,
        job_of: Vec<Option<usize>>,
        jobs: Vec<Job>,
        units: Vec<(usize, Term)>,
        backward: bool,
    ) -> Problem {
        let n = snaps.len();
        let mut exported = vec![false; n];
        for (after, list) in preds.iter().enumerate() {
            for &(before, _) in list {
                if job_of[before] != job_of[after] {
                    exported[before] = true;
                }
            }
        }
        // Tails: one sweep against the orderings' direction, a step's successors first.
        let mut tail = vec![0i64; n];
        let sweep: Box<dyn Iterator<Item = usize>> = if backward { Box::new(0..n) } else { Box::new((0..n).rev()) };
        for after in sweep {
            for &(before, separation) in &preds[after] {
                tail[before] = tail[before].max(tail[after] + separation);
            }
        }
        let waits_on = waits_on(&jobs, &preds, &job_of);
        Problem { snaps, preds, exported, job_of, jobs, units, tail, waits_on }
    }

    /// The same problem backwards in time: each ordering turned round (a step's successors
    /// become its predecessors, with the same separations) and each job's steps in reverse
    /// order (it takes its unit at its last step and gives it back at its first). A list
    /// schedule of it, read from its end, lays the plan out from its end: each job as late
    /// as what comes after it allows, so that the jobs the last ones wait for come first.
    fn reversed(&self) -> Problem {
        let mut preds: Vec<Vec<(usize, i64)>> = vec![Vec::new(); self.snaps.len()];
        for (after, list) in self.preds.iter().enumerate() {
            for &(before, separation) in list {
                preds[before].push((after, separation));
            }
        }
        let reversed = |job: &Job| Job {
            template: job.template,
            unit: job.unit,
            steps: job.steps.iter().rev().copied().collect(),
        };
        let jobs = self.jobs.iter().map(reversed).collect();
        Problem::new(self.snaps.clone(), preds, self.job_of.clone(), jobs, self.units.clone(), true)
    }
}

/// List scheduling of `problem` under `rule`: each step's time and each job's unit, or `None`
/// when the simulation deadlocks.
fn simulate(problem: &Problem, rule: Rule) -> Option<(Vec<i64>, Vec<usize>)> {
    let n = problem.snaps.len();
    let mut time: Vec<Option<i64>> = vec![None; n];
    let mut unit_of_job: Vec<usize> = problem.jobs.iter().map(|j| j.unit).collect();
    // When each unit is free, and whether a job holds it.
    let mut free_at: Vec<i64> = vec![0; problem.units.len()];
    let mut held: Vec<bool> = vec![false; problem.units.len()];
    let mut started: Vec<bool> = vec![false; problem.jobs.len()];
    let mut bounds = Bounds::new(n);
    let mut now = 0i64;
    // The steps whose predecessors are all placed (the only ones that can be placed next),
    // kept up to date from each step's successors and how many of its predecessors are not
    // placed yet: choosing a step looks at these, not at every step (the choice is the least
    // of a total order, so the order of the list does not matter).
    let mut succs: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut missing: Vec<usize> = problem.preds.iter().map(Vec::len).collect();
    for (s, preds) in problem.preds.iter().enumerate() {
        for &(p, _) in preds {
            succs[p].push(s);
        }
    }
    let mut ready: Vec<usize> = (0..n).filter(|&i| missing[i] == 0).collect();
    for _ in 0..n {
        // The step to place next: the one that can happen first (with `reserve`, among
        // those that leave a unit for each started job waiting for a job not started; if
        // none does, among all).
        let waiting = if rule.reserve {
            (0..problem.jobs.len())
                .filter(|&j| started[j] && held[unit_of_job[j]] && waits_for_unstarted(problem, &time, &started, j))
                .count()
        } else {
            0
        };
        let units = Units { free_at: &free_at, held: &held, started: &started };
        let mut best = None;
        for reserving in [rule.reserve, false] {
            let placed = Placed { time: &time, now, ready: &ready };
            best = next_step(problem, rule, placed, &mut bounds, units, reserving.then_some(waiting));
            if best.is_some() || !reserving {
                break;
            }
        }
        let ((at, _, i), unit) = best?; // deadlock: nothing can be placed
        // (The bounds change only when `now` moves on or a step is placed later than its
        // bound.)
        if at != now || at != bounds.get(problem, Placed { time: &time, now, ready: &ready }, i) {
            bounds.forget();
        }
        time[i] = Some(at);
        ready.retain(|&r| r != i);
        for &s in &succs[i] {
            missing[s] -= 1;
            if missing[s] == 0 {
                ready.push(s);
            }
        }
        now = at;
        if let (Some(j), Some(unit)) = (problem.job_of[i], unit) {
            started[j] = true;
            held[unit] = true;
            unit_of_job[j] = unit;
        }
        if let Some(j) = problem.job_of[i]
            && problem.jobs[j].steps.last() == Some(&i)
        {
            let unit = unit_of_job[j];
            held[unit] = false;
            free_at[unit] = at;
        }
    }
    Some((time.into_iter().map(|t| t.unwrap_or(0)).collect(), unit_of_job))
}

/// Where a simulation stands: the times of the steps placed, the time it has reached, and the
/// steps whose predecessors are all placed.
#[derive(Clone, Copy)]
struct Placed<'a> {
    time: &'a [Option<i64>],
    now: i64,
    ready: &'a [usize],
}

/// Lower bounds on the times of a simulation's steps not placed yet: no earlier than now, nor
/// than their predecessors allow. Each is worked out when first asked for and kept until
/// [`Bounds::forget`]; the simulation asks for those of the steps it could place next and of
/// the steps a job's later steps wait for, a few of them, where working out all of them
/// after each placement cost `kbc plan` of reverse_b06_a3_s1 4% more instructions (264 ->
/// 254 M under callgrind with this).
struct Bounds {
    value: Vec<i64>,
    /// `value[i]` holds while `stamp[i]` is `epoch`.
    stamp: Vec<u32>,
    epoch: u32,
    /// Steps waiting for their predecessors' bounds.
    stack: Vec<usize>,
}

impl Bounds {
    fn new(n: usize) -> Bounds {
        Bounds { value: vec![0; n], stamp: vec![0; n], epoch: 1, stack: Vec::new() }
    }

    /// Forgets every bound worked out: the time reached or a step's placement moved them.
    fn forget(&mut self) {
        self.epoch += 1;
    }

    /// The lower bound of step `i`, one of `placed.ready` (all its predecessors placed): the
    /// simulation asks this of every ready step after every placement, where [`Bounds::get`]
    /// would check its predecessors first.
    fn ready(&mut self, problem: &Problem, placed: Placed<'_>, i: usize) -> i64 {
        if self.stamp[i] == self.epoch {
            return self.value[i];
        }
        let time = placed.time;
        let bound = problem.preds[i].iter().fold(placed.now, |acc, &(p, separation)| {
            acc.max(time[p].expect("a ready step's predecessors are placed") + separation)
        });
        self.value[i] = bound;
        self.stamp[i] = self.epoch;
        bound
    }

    /// The lower bound of step `i` (its time, if placed).
    fn get(&mut self, problem: &Problem, placed: Placed<'_>, i: usize) -> i64 {
        let time = placed.time;
        if let Some(t) = time[i] {
            return t;
        }
        let epoch = self.epoch;
        if self.stamp[i] == epoch {
            return self.value[i];
        }
        // (Most steps asked about can be placed next: their predecessors are all placed.)
        if problem.preds[i].iter().all(|&(p, _)| time[p].is_some()) {
            return self.ready(problem, placed, i);
        }
        self.stack.push(i);
        while let Some(&s) = self.stack.last() {
            if self.stamp[s] == epoch {
                self.stack.pop();
                continue;
            }
            let before = self.stack.len();
            for &(p, _) in &problem.preds[s] {
                if time[p].is_none() && self.stamp[p] != epoch {
                    self.stack.push(p);
                }
            }
            if self.stack.len() > before {
                continue; // its predecessors first
            }
            self.stack.pop();
            let value = &self.value;
            let bound = problem.preds[s]
                .iter()
                .fold(placed.now, |acc, &(p, separation)| acc.max(time[p].unwrap_or(value[p]) + separation));
            self.value[s] = bound;
            self.stamp[s] = epoch;
        }
        self.value[i]
    }
}

/// The units in a simulation: when each is free, whether a job holds it, and which jobs have
/// started.
#[derive(Clone, Copy)]
struct Units<'a> {
    free_at: &'a [i64],
    held: &'a [bool],
    started: &'a [bool],
}

/// The step of [`simulate`] to place next (of the `ready` ones, whose predecessors are all
/// placed), with the unit it takes if it starts a job: the one
/// that can happen first, then the most urgent (or first in plan order), given the placed
/// steps' times and the others' lower bounds. With `reserve` (how many started jobs wait for a
/// job not started yet), a job that would wait so too starts only if it leaves a free unit for
/// each of those and for its own.
fn next_step(
    problem: &Problem,
    rule: Rule,
    placed: Placed<'_>,
    bounds: &mut Bounds,
    units: Units<'_>,
    reserve: Option<usize>,
) -> Option<((i64, i64, usize), Option<usize>)> {
    let time = placed.time;
    let mut best: Option<((i64, i64, usize), Option<usize>)> = None; // ((time, rank, step), unit)
    for &i in placed.ready {
        debug_assert!(time[i].is_none() && problem.preds[i].iter().all(|&(p, _)| time[p].is_some()));
        let ready = bounds.ready(problem, placed, i);
        let job = problem.job_of[i];
        let (at, unit) = match job {
            Some(j) if !units.started[j] => {
                let template = problem.jobs[j].template;
                // (Counted and searched in place, not collected into a list for every ready
                // step after every placement: swap_b100_a10_s1's simulations 3991 -> 3860 M
                // instructions.)
                let free = || (0..problem.units.len()).filter(|&u| !units.held[u] && problem.units[u].0 == template);
                if let Some(waiting) = reserve
                    && free().nth(waiting + 1).is_none()
                    && waits_for_unstarted(problem, time, units.started, j)
                {
                    continue;
                }
                let Some(unit) = free().min_by_key(|&u| (units.free_at[u].max(ready), u != problem.jobs[j].unit, u))
                else {
                    continue;
                };
                let mut at = units.free_at[unit].max(ready);
                if rule.just_in_time {
                    at += delay(problem, (placed, bounds), j, at);
                }
                (at, Some(unit))
            }
            _ => (ready, None),
        };
        let rank = match (rule.urgency, job) {
            (true, _) => -varied(problem.tail[i], i, rule.variant),
            // (Backwards, the plan's order from its end.)
            (false, Some(j)) if rule.backward => -(problem.jobs[j].steps[0] as i64),
            (false, Some(j)) => problem.jobs[j].steps[0] as i64,
            (false, None) if rule.backward => -(i as i64),
            (false, None) => i as i64,
        };
        if best.is_none_or(|(key, _)| (at, rank, i) < key) {
            best = Some(((at, rank, i), unit));
        }
    }
    best
}

/// Whether a step of job `j` not placed yet waits for a step not placed yet of a job not
/// `started` (another job's).
fn waits_for_unstarted(problem: &Problem, time: &[Option<i64>], started: &[bool], j: usize) -> bool {
    problem.waits_on[j].iter().any(|&(s, p, q)| time[s].is_none() && time[p].is_none() && !started[q])
}

/// How long job `j`, if it started at `at`, could start later without delaying its last step
/// or any step another job waits for: the waiting its steps would do before the first such
/// step, given the lower bounds on everything else.
fn delay(problem: &Problem, (placed, bounds): (Placed<'_>, &mut Bounds), j: usize, at: i64) -> i64 {
    let steps = &problem.jobs[j].steps;
    // Each step's (time, offset) so far, by its position in `steps` (a job has a few steps).
    let mut local: Vec<(i64, i64)> = Vec::with_capacity(steps.len());
    let mut slack = i64::MAX;
    for (k, &s) in steps.iter().enumerate() {
        let (mut t, mut offset) = if k == 0 { (at, 0) } else { (i64::MIN, 0) };
        for &(p, separation) in &problem.preds[s] {
            match steps[..k].iter().position(|&q| q == p).map(|q| local[q]) {
                Some((pt, po)) => {
                    t = t.max(pt + separation);
                    offset = offset.max(po + separation);
                }
                None => t = t.max(bounds.get(problem, placed, p) + separation),
            }
        }
        let t = t.max(at + offset);
        local.push((t, offset));
        if problem.exported[s] || k + 1 == steps.len() {
            slack = slack.min(t - at - offset);
        }
    }
    if slack == i64::MAX { 0 } else { slack.max(0) }
}

/// The plan in simulated time order, each job naming its unit.
fn rearranged(plan: &Plan, problem: &Problem, order: &[usize], units: &[usize]) -> Plan {
    let steps = order
        .iter()
        .map(|&i| {
            let step = &plan.steps[i];
            match problem.job_of[i] {
                Some(j) if units[j] != problem.jobs[j].unit => {
                    let (from, to) = (&problem.units[problem.jobs[j].unit].1, &problem.units[units[j]].1);
                    Step {
                        action: step.action,
                        name: replace(&step.name, from, to),
                        bindings: step.bindings.iter().map(|b| b.as_ref().map(|t| replace(t, from, to))).collect(),
                    }
                }
                _ => step.clone(),
            }
        })
        .collect();
    Plan { problem: plan.problem, steps }
}

/// The steps in simulated time order (ends before starts at equal times, then plan order).
fn order_of(problem: &Problem, times: &[i64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..problem.snaps.len()).collect();
    order.sort_by_key(|&i| (times[i], problem.snaps[i] != Snap::End, i));
    order
}

/// `term` with every `from` replaced by `to`.
pub(crate) fn replace(term: &Term, from: &Term, to: &Term) -> Term {
    if term == from {
        return to.clone();
    }
    match term {
        Term::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| replace(a, from, to)).collect()),
        other => other.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three units and `waiting + 3` jobs, each a start and an end two units apart. The first
    /// `waiting` jobs each end only after the start of a partner, job `waiting + j`, later in
    /// the plan (a block lifted so that another can take its cell).
    fn pairs(waiting: usize) -> Problem {
        let mut problem = Problem {
            snaps: Vec::new(),
            preds: Vec::new(),
            exported: Vec::new(),
            job_of: Vec::new(),
            jobs: Vec::new(),
            units: (0..3).map(|u| (0, Term::Int(u))).collect(),
            tail: Vec::new(),
            waits_on: Vec::new(),
        };
        let jobs = 3 + waiting;
        for j in 0..jobs {
            let (start, end) = (2 * j, 2 * j + 1);
            problem.snaps.extend([Snap::Start, Snap::End]);
            problem.preds.extend([Vec::new(), vec![(start, 2)]]);
            problem.exported.extend([j >= waiting, false]);
            problem.job_of.extend([Some(j), Some(j)]);
            problem.jobs.push(Job { template: 0, unit: j % 3, steps: vec![start, end] });
            problem.tail.extend([2, 0]);
        }
        for j in 0..waiting {
            problem.preds[2 * j + 1].push((2 * (waiting + j), 1));
        }
        problem.waits_on = waits_on(&problem.jobs, &problem.preds, &problem.job_of);
        problem
    }

    #[test]
    fn each_variant_ranks_steps_of_equal_urgency_in_its_own_order_and_the_same_each_time() {
        for step in 0..16 {
            assert_eq!(varied(100, step, 0), 100);
            for variant in 1..=8 {
                let scaled = varied(100, step, variant);
                assert!((100..140).contains(&scaled), "{scaled}");
                assert_eq!(scaled, varied(100, step, variant));
            }
        }
        // Sixteen steps of equal urgency: the simulation takes the most urgent first, and
        // among equals the first in plan order.
        let order = |variant| {
            let mut steps: Vec<usize> = (0..16).collect();
            steps.sort_by_key(|&s| (-varied(100, s, variant), s));
            steps
        };
        let mut orders: Vec<Vec<usize>> = (0..=8).map(order).collect();
        assert_eq!(orders[0], (0..16).collect::<Vec<_>>());
        orders.sort();
        orders.dedup();
        assert_eq!(orders.len(), 9, "every variant its own order");
        assert_eq!(Rules::Fixed.list()[..4], RULES);
        assert!(
            Rules::Fixed.list()[4..].iter().zip(RULES).all(|(b, f)| b.backward && *b == Rule { backward: true, ..f })
        );
        assert_eq!(Rules::WithVariants(3).list().len(), 14);
        let variants = Rules::Variants(3).list();
        assert_eq!(variants.len(), 6);
        assert!(variants.iter().all(|r| r.just_in_time && r.urgency && r.variant > 0));
    }

    /// Panics unless `times` and `units` keep every ordering of `problem` and give no unit
    /// two jobs at once.
    fn assert_schedule(problem: &Problem, (times, units): &(Vec<i64>, Vec<usize>)) {
        for (after, list) in problem.preds.iter().enumerate() {
            for &(before, separation) in list {
                assert!(times[after] >= times[before] + separation, "{before} -> {after} in {times:?}");
            }
        }
        let span = |j: usize| {
            let steps = &problem.jobs[j].steps;
            let (first, last) = (steps.iter().map(|&s| times[s]).min(), steps.iter().map(|&s| times[s]).max());
            (first.expect("a job has steps"), last.expect("a job has steps"))
        };
        for a in 0..problem.jobs.len() {
            for b in a + 1..problem.jobs.len() {
                let ((a0, a1), (b0, b1)) = (span(a), span(b));
                assert!(units[a] != units[b] || a1 <= b0 || b1 <= a0, "jobs {a} and {b} share a unit: {times:?}");
            }
        }
    }

    #[test]
    fn backwards_the_simulation_lays_out_first_the_jobs_the_end_waits_for() {
        // Four jobs on two units, each a start and an end: A (6 long), B (4), C (3) and D
        // (5), where D starts one after C ends and ends one after A starts. Steps in plan
        // order: A, B start; A, B end; C start, end; D start, end.
        let preds = vec![
            vec![],
            vec![],
            vec![(0, 6)],
            vec![(1, 4)],
            vec![],
            vec![(4, 3)],
            vec![(4, 1), (5, 1)],
            vec![(6, 5), (0, 1)],
        ];
        let snaps = [Snap::Start, Snap::Start, Snap::End, Snap::End, Snap::Start, Snap::End, Snap::Start, Snap::End];
        let steps = [vec![4, 5], vec![6, 7], vec![1, 3], vec![0, 2]]; // C, D, B, A
        let mut job_of = vec![None; 8];
        for (j, list) in steps.iter().enumerate() {
            for &s in list {
                job_of[s] = Some(j);
            }
        }
        let jobs = steps.iter().enumerate().map(|(j, s)| Job { template: 0, unit: j % 2, steps: s.clone() }).collect();
        let units = (0..2).map(|u| (0, Term::Int(u))).collect();
        let problem = Problem::new(snaps.to_vec(), preds, job_of, jobs, units, false);
        let mut reversed = None;
        let makespan = |(times, _): &(Vec<i64>, Vec<usize>)| times.iter().copied().max().unwrap_or(0);
        // Forwards, when C ends at 3 its unit goes to B, which can start at once, and D waits
        // for A's unit until 6: 11 at best.
        for rule in fixed().filter(|r| !r.backward) {
            let schedule = simulated(&problem, &mut reversed, rule).expect("a schedule");
            assert_schedule(&problem, &schedule);
            assert!(makespan(&schedule) >= 11, "{rule:?}: {schedule:?}");
        }
        // Backwards, D is laid out from the end with B before it on one unit, and A with C
        // before it on the other: 9, the least there is (18 units of work on two units).
        let urgent = Rule { backward: true, ..RULES[0] };
        let schedule = simulated(&problem, &mut reversed, urgent).expect("a schedule");
        assert_schedule(&problem, &schedule);
        assert_eq!(makespan(&schedule), 9, "{schedule:?}");
        for rule in fixed().filter(|r| r.backward) {
            assert_schedule(&problem, &simulated(&problem, &mut reversed, rule).expect("a schedule"));
        }
    }

    #[test]
    fn reserving_leaves_units_for_the_jobs_others_wait_for() {
        let greedy = Rule { just_in_time: true, urgency: true, reserve: false, variant: 0, backward: false };
        let reserving = Rule { reserve: true, ..greedy };
        // Three waiting jobs take the three units first, and no partner gets one: greedily,
        // the simulation deadlocks; reserving, it starts a partner before a second waiting job.
        let problem = pairs(3);
        assert_eq!(simulate(&problem, greedy), None);
        let (times, units) = simulate(&problem, reserving).expect("a schedule");
        for j in 0..3 {
            let (waiting, partner) = (2 * j, 2 * (3 + j));
            assert!(times[waiting + 1] > times[partner], "job {j} ends after its partner starts");
            assert_ne!(units[j], units[3 + j], "a pair holds two units");
        }
        // (Never more than three units held at once.)
        let mut events: Vec<(i64, i64)> = Vec::new();
        for j in 0..6 {
            events.extend([(times[2 * j], 1), (times[2 * j + 1], -1)]);
        }
        events.sort_by_key(|&(t, d)| (t, d));
        let mut held = 0;
        for (_, d) in events {
            held += d;
            assert!(held <= 3, "{times:?}");
        }
        // Where units are enough, reserving changes nothing.
        let few = pairs(1);
        assert_eq!(simulate(&few, greedy), simulate(&few, reserving));
    }
}
