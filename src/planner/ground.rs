//! The ground relaxed task: h_add, h_FF and helpful actions by counting, over the rule
//! instantiations a full relaxed exploration from the initial state recorded.
//!
//! Facts here are the lifted relaxation's *view tuples* (a predicate restricted to the
//! argument positions some rule reads), numbered densely; a ground action is one rule
//! instantiation, with the tuples its body read as preconditions and the tuples its heads
//! produce as effects. Evaluating a state is then the textbook algorithm: every precondition
//! counter starts full, facts of the state cost 0, and a Dijkstra over facts settles each at
//! its h_add cost, firing an action when its last precondition settles, until every goal
//! literal has a settled tuple. The relaxed plan is extracted the same way as on the lifted
//! side (`relaxed::Relaxation::relaxed_plan`): most costly tuples first, with every tuple an
//! already chosen action adds counting as achieved.
//!
//! The two evaluators compute the same h_add on every state; a test checks that they do.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::relaxed::{Estimate, Helpful, PlanAction};
use crate::ir::task::ConstId;

/// One rule instantiation recorded during grounding: tuples as (view, index in view).
#[derive(Clone)]
pub(super) struct RecordedAction {
    pub rule: u32,
    /// Its variables' values, as a helpful action names it.
    pub bindings: Box<[Option<ConstId>]>,
    /// What tells it apart from the rule's other actions, where not its bindings (the part of
    /// an instantiation that deletes: see [`RecordedAction::pair`]).
    pub key: Option<Box<[Option<ConstId>]>>,
    pub pre: Vec<(u32, u32)>,
    /// An exclusion node it also needs (a number of [`Auxiliary::exclusion_node`]).
    pub exclusion: Option<u32>,
    /// For the part of an instantiation split at an exclusion that deletes: the action
    /// recorded as the adding part of the same instantiation (an index into the recorded
    /// actions, which are the ground task's first actions, in order).
    pub pair: Option<u32>,
    pub add: Vec<(u32, u32)>,
    /// The Invalid literal instances it must respect, by number.
    pub invalid: Vec<u32>,
    /// The whole facts of negated predicates it deletes (tuples of their whole-fact views).
    pub deletes: Vec<(u32, u32)>,
}

const NONE: u32 = u32::MAX;

/// What an action has gathered of its preconditions in an evaluation: the sum of the costs of
/// those settled (its h_add cost, less its weight, once all are), and how many are not yet.
/// Kept side by side, so that the evaluation's loop reads and writes one cache line per action
/// it visits, not two (in two arrays, their loads were the loop's hottest instructions under
/// perf on a 55,000-action task).
#[derive(Clone, Copy, Debug)]
struct Counter {
    cost: u32,
    left: u32,
}

/// Counts a settled precondition of cost `cost` in: whether it was the last one.
#[inline]
fn count_in(counter: &mut Counter, cost: u32) -> bool {
    counter.cost = counter.cost.saturating_add(cost);
    counter.left -= 1;
    counter.left == 0
}

/// Marks an entry of [`GroundTask::triggers`] as a group's (the rest of it is the group's number).
const GROUP: u32 = 1 << 31;

/// The least number of preconditions a group shares (see [`Groups`]).
const GROUP_PREFIX: u32 = 2;

/// Runs of consecutive actions whose first preconditions (in each action's sorted list) are
/// the same: the grounding records a rule's instantiations one after another, so the moves of
/// one block by one arm to every free cell share the preconditions that name the arm, the
/// block and where it stands, and differ in those that name the destination. The evaluation
/// counts such a shared prefix once for the group, and when the group has all of it, passes
/// its cost on to each action of the run in order: the same costs, the same actions firing in
/// the same order as when each action counted the prefix itself, for fewer visits. A
/// 20-crate, 3-robot warehouse KB (a robot drives to a crate and carries it to any of 30
/// spots): 54,768 actions with 266,598 preconditions in all, read as 115,398 entries (1,800
/// groups of 29 carries); `kbc plan --schedule` 2.35 -> 1.96 s, the same plan. The ladder's
/// blocks rungs have few groups (a move split at an exclusion has one or two preconditions),
/// and the same times.
#[derive(Clone, Debug, Default)]
struct Groups {
    /// Per group, its actions: `first..end`.
    actions: Vec<(u32, u32)>,
    /// Per group, what it starts each evaluation with (the length of its prefix left), and
    /// what it has gathered.
    fresh: Vec<Counter>,
    counters: Vec<Counter>,
}

impl Groups {
    /// The groups of the actions whose preconditions are `pre` (CSR layout, each sorted), and
    /// per action the length of the prefix its group counts for it (0 outside a group). A run
    /// starts where two actions share [`GROUP_PREFIX`] preconditions or more, and takes the
    /// actions after them while they share as many with the one before.
    fn find(pre_start: &[u32], pre: &[u32]) -> (Groups, Vec<u32>) {
        let count = pre_start.len() - 1;
        let list = |a: usize| &pre[pre_start[a] as usize..pre_start[a + 1] as usize];
        let common = |a: usize| list(a).iter().zip(list(a + 1)).take_while(|(x, y)| x == y).count() as u32;
        let mut groups = Groups::default();
        let mut prefix = vec![0u32; count];
        let mut a = 0;
        while a + 1 < count {
            let shared = common(a);
            if shared < GROUP_PREFIX {
                a += 1;
                continue;
            }
            let mut end = a + 2;
            while end < count && common(end - 1) >= shared {
                end += 1;
            }
            prefix[a..end].fill(shared);
            groups.actions.push((a as u32, end as u32));
            groups.fresh.push(Counter { cost: 0, left: shared });
            a = end;
        }
        groups.counters = groups.fresh.clone();
        (groups, prefix)
    }
}

/// Where an auxiliary node's achiever reads from: a view tuple, or another auxiliary node.
#[derive(Clone, Copy, Debug)]
pub(super) enum Source {
    Tuple(u32, u32),
    Aux(u32),
}

/// Auxiliary nodes of the ground task (the relaxation's exclusion nodes), achieved at no cost
/// by actions of one precondition each: they stand for a choice among tuples, as "some fact
/// of this group other than that one". They are not landmarks and add nothing to h_FF.
#[derive(Clone, Debug, Default)]
pub(super) struct Auxiliary {
    /// The number of auxiliary nodes.
    pub count: u32,
    /// The achievers: (what it reads, the node it achieves).
    pub links: Vec<(Source, u32)>,
    /// Per exclusion number, its node.
    pub exclusion_node: Vec<u32>,
    /// The tuples of every group, a group after another, each sorted by the values of its
    /// excluded variables.
    pub members: Vec<(u32, u32)>,
    /// Per exclusion number, the tuples it chooses from: its group's range of `members`, and
    /// the range within it that it excludes.
    pub choices: Vec<[u32; 4]>,
}

impl RecordedAction {
    /// What tells it apart from the other actions of its rule.
    pub fn key(&self) -> &[Option<ConstId>] {
        self.key.as_deref().unwrap_or(&self.bindings)
    }
}

/// What the ground task needs for Invalid conditions: the whole-fact views of negated
/// predicates, and per Invalid literal instance the tuples it forbids.
pub(super) type Negative<'a> = (&'a [u32], &'a [Vec<(u32, u32)>]);

/// The ground relaxed task and its scratch space.
#[derive(Clone)]
pub(super) struct GroundTask {
    /// The first fact number of each view.
    pub(super) offsets: Vec<u32>,
    /// Per action: the schema, the values of its variables, its cost (1, or 0 for the
    /// conjunctions that stand for Invalid literals), and its ranges in `pre`/`add`.
    schema: Vec<u32>,
    pub(super) weight: Vec<u32>,
    bindings: Vec<Box<[Option<ConstId>]>>,
    /// Per action, the adding part it pairs with ([`RecordedAction::pair`]), or `NONE`.
    pair: Vec<u32>,
    /// Per action, the exclusion number it reads (see [`Auxiliary::choices`]), or `NONE`;
    /// the choices, and the members they index, as fact nodes.
    exclusion_of: Vec<u32>,
    choices: Vec<[u32; 4]>,
    members: Vec<u32>,
    /// View tuples to the deleting parts that read them (CSR layout).
    deleters_start: Vec<u32>,
    deleters: Vec<u32>,
    pub(super) pre_start: Vec<u32>,
    pub(super) pre: Vec<u32>,
    pub(super) add_start: Vec<u32>,
    pub(super) add: Vec<u32>,
    /// Facts to what the evaluation visits when they settle (CSR layout): the actions that
    /// have them as a precondition, each shared prefix of preconditions counted once for its
    /// group (an entry with [`GROUP`] set, see [`Groups`]).
    triggers_start: Vec<u32>,
    triggers: Vec<u32>,
    groups: Groups,
    /// Actions without preconditions.
    pub(super) unconditional: Vec<u32>,
    /// Negation nodes: (the fact node whose absence or deletion they stand for, their node).
    pub(super) negations: Vec<(u32, u32)>,
    /// All nodes: view tuples, then negations, then Invalid literal instances.
    pub(super) nodes: usize,
    /// The number of view-tuple nodes.
    pub(super) tuples: usize,
    /// Per view, its first negation node (`u32::MAX` for views without negations).
    pub(super) negation_base: Vec<u32>,
    /// The first Invalid literal instance node, and per instance the conjunction action that
    /// achieves it.
    pub(super) instance_base: u32,
    pub(super) instance_actions: Vec<u32>,
    /// The first auxiliary node (see [`Auxiliary`]): every node from here on is one.
    pub(super) aux_base: u32,
    /// Per goal literal (of the relaxation), the facts that satisfy it.
    pub(super) goal_options: Vec<Vec<u32>>,
    /// The goal literals by fact, for the check when a fact settles (CSR layout).
    goals_of_start: Vec<u32>,
    goals_of: Vec<u32>,
    // Scratch, per evaluation.
    pub(super) present: Vec<bool>,
    pub(super) cost: Vec<u32>,
    done: Vec<bool>,
    supporter: Vec<u32>,
    /// Per action, what it has gathered of its preconditions (see [`Counter`]), and what it
    /// starts each evaluation with.
    counters: Vec<Counter>,
    fresh: Vec<Counter>,
    queue: BucketQueue,
    unreached: Vec<usize>,
    /// Whether evaluations fill in [`Estimate::plan`].
    pub(super) keep_plan: bool,
    /// Whether relaxed plans come group by group (see [`GroundTask::groups`]): decided on
    /// the first relaxed plan made, by [`PARKING_SHARE`].
    pub(super) grouped: Option<bool>,
}

/// Relaxed plans come group by group ([`GroundTask::groups`]) when one action in this many
/// of the first one made, or more, is a trip aside ([`GroundTask::detours`]). Ordered by due
/// alone, the lookahead lifted the top block of every stack, then the next of every stack,
/// and so on: reverse_b100_a8_s1 had 88 of its 100 blocks parked at once on the 82 free
/// cells, most of them far away (makespan 160.079); stack by stack, 35 (123.093). Where
/// few actions are trips aside (build: 2 of 403), towers built side by side keep the arms
/// busy, and the order is due alone.
const PARKING_SHARE: usize = 4;

/// A fact read by more of a relaxed plan's actions than this links none of them into a
/// group ([`GroundTask::groups`]).
const SHARED_READERS: u32 = 2;

/// A priority queue of facts by cost for the Dijkstra-like evaluation, where every cost pushed
/// is at least the last one popped (a fact's cost is a sum of costs already settled plus a
/// weight): one bucket per cost, popped in order, so that facts of one cost come out lowest id
/// first, exactly as from one binary heap of `(cost, fact)`, but without sifting through every
/// fact of every cost. A bucket is a plain vector until its cost comes up; it is then sorted
/// once and read in order, and what is pushed at that cost meanwhile (through zero-cost
/// actions) goes to a small heap beside it. (On build_b50_a8, perf put about a third of an
/// evaluation's samples in the bucket heaps' sifting.) Costs from [`BucketQueue::BUCKETS`] on go to one binary
/// heap.
#[derive(Clone, Debug, Default)]
struct BucketQueue {
    buckets: Vec<Vec<u32>>,
    /// The lowest bucket that may be non-empty.
    current: usize,
    /// One past the highest bucket used since the last clear.
    used: usize,
    /// While bucket `current` is being popped: its facts, sorted, and how many were popped.
    sorted: Vec<u32>,
    cursor: usize,
    active: bool,
    /// Facts pushed at cost `current` while it is being popped.
    late: BinaryHeap<Reverse<u32>>,
    /// The radix sort's second buffer ([`radix_sort`]).
    scratch: Vec<u32>,
    overflow: BinaryHeap<Reverse<(u32, u32)>>,
}

impl BucketQueue {
    const BUCKETS: usize = 1 << 16;

    fn push(&mut self, cost: u32, fact: u32) {
        let c = cost as usize;
        if c >= Self::BUCKETS {
            self.overflow.push(Reverse((cost, fact)));
            return;
        }
        debug_assert!(c >= self.current, "costs pushed never fall below the last popped");
        if self.active && c == self.current {
            self.late.push(Reverse(fact));
            return;
        }
        if c >= self.buckets.len() {
            self.buckets.resize_with(c + 1, Vec::new);
        }
        self.buckets[c].push(fact);
        self.used = self.used.max(c + 1);
    }

    fn pop(&mut self) -> Option<(u32, u32)> {
        loop {
            if self.active {
                let next = self.sorted.get(self.cursor).copied();
                let late = self.late.peek().map(|&Reverse(f)| f);
                let fact = match (next, late) {
                    (Some(n), Some(l)) if l < n => self.late.pop().map(|Reverse(f)| f),
                    (Some(n), _) => {
                        self.cursor += 1;
                        Some(n)
                    }
                    (None, Some(_)) => self.late.pop().map(|Reverse(f)| f),
                    (None, None) => None,
                };
                if let Some(fact) = fact {
                    return Some((self.current as u32, fact));
                }
                self.active = false;
                self.current += 1;
            }
            while self.current < self.used && self.buckets[self.current].is_empty() {
                self.current += 1;
            }
            if self.current >= self.used {
                return self.overflow.pop().map(|Reverse(entry)| entry);
            }
            std::mem::swap(&mut self.sorted, &mut self.buckets[self.current]);
            self.buckets[self.current].clear();
            if self.sorted.len() < RADIX_FROM {
                self.sorted.sort_unstable();
            } else {
                radix_sort(&mut self.sorted, &mut self.scratch);
            }
            self.cursor = 0;
            self.active = true;
        }
    }

    fn clear(&mut self) {
        for bucket in &mut self.buckets[..self.used] {
            bucket.clear();
        }
        self.current = 0;
        self.used = 0;
        self.sorted.clear();
        self.cursor = 0;
        self.active = false;
        self.late.clear();
        self.overflow.clear();
    }
}

/// Buckets of [`BucketQueue`] with at least so many facts are sorted by [`radix_sort`], smaller
/// ones by comparison. (A bucket can hold most of a large task's facts: every `picking(R, B, X,
/// Y)` of a 100-box, 10-agent pick-and-place KB has one cost; perf put 13% of `kbc plan`'s
/// samples there in `sort_unstable`.)
const RADIX_FROM: usize = 512;

/// Sorts `values` ascending, 11 bits at a time from the lowest (a stable counting sort
/// each, as many passes as the largest value has digits: two for a task of up to four
/// million facts), with `scratch` as the other buffer. The same order as `sort_unstable`, in
/// linear time.
fn radix_sort(values: &mut Vec<u32>, scratch: &mut Vec<u32>) {
    const BITS: u32 = 11;
    const DIGITS: usize = 1 << BITS;
    let largest = values.iter().copied().max().unwrap_or(0);
    scratch.clear();
    scratch.resize(values.len(), 0);
    let mut shift = 0;
    while shift < u32::BITS && (shift == 0 || largest >> shift > 0) {
        let digit = |v: u32| ((v >> shift) as usize) & (DIGITS - 1);
        let mut counts = [0usize; DIGITS];
        for &v in values.iter() {
            counts[digit(v)] += 1;
        }
        let mut at = 0;
        for count in &mut counts {
            let n = *count;
            *count = at;
            at += n;
        }
        for &v in values.iter() {
            let d = digit(v);
            scratch[counts[d]] = v;
            counts[d] += 1;
        }
        std::mem::swap(values, scratch);
        shift += BITS;
    }
}

fn csr(count: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; count + 1];
    for (key, _) in pairs.clone() {
        start[key as usize + 1] += 1;
    }
    for i in 0..count {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut items = vec![0u32; start[count] as usize];
    for (key, value) in pairs {
        items[fill[key as usize] as usize] = value;
        fill[key as usize] += 1;
    }
    (start, items)
}

impl GroundTask {
    /// Builds the task from the view sizes, the recorded instantiations, each rule's schema
    /// and, per goal literal, the tuples that satisfy it. With `negative` (the whole-fact
    /// views of negated predicates, and per Invalid literal instance the tuples it forbids),
    /// actions also wait for their Invalid literals.
    pub fn new(
        sizes: &[usize],
        actions: Vec<RecordedAction>,
        schemas: &[u32],
        goals: &[Vec<(u32, u32)>],
        negative: Option<Negative<'_>>,
        auxiliary: Auxiliary,
    ) -> Self {
        let mut offsets = Vec::with_capacity(sizes.len());
        let mut facts = 0usize;
        for &size in sizes {
            offsets.push(facts as u32);
            facts += size;
        }
        let id = |(view, t): (u32, u32)| offsets[view as usize] + t;
        // Negation nodes follow the view tuples, one per tuple of each negated view.
        let mut negation_base: Vec<u32> = vec![u32::MAX; sizes.len()];
        let mut nodes = facts;
        let mut negations = Vec::new();
        let mut instance_base = facts as u32;
        if let Some((views, candidates)) = negative {
            for &view in views {
                negation_base[view as usize] = nodes as u32;
                for t in 0..sizes[view as usize] as u32 {
                    negations.push((offsets[view as usize] + t, (nodes as u32) + t));
                }
                nodes += sizes[view as usize];
            }
            instance_base = nodes as u32;
            nodes += candidates.len();
        }
        let aux_base = nodes as u32;
        nodes += auxiliary.count as usize;
        let negation = |(view, t): (u32, u32)| negation_base[view as usize] + t;
        let mut task = GroundTask {
            offsets: Vec::new(),

            schema: Vec::with_capacity(actions.len()),
            weight: Vec::with_capacity(actions.len()),
            bindings: Vec::with_capacity(actions.len()),
            pair: Vec::with_capacity(actions.len()),
            deleters_start: Vec::new(),
            deleters: Vec::new(),
            exclusion_of: Vec::with_capacity(actions.len()),
            choices: Vec::new(),
            members: auxiliary.members.iter().map(|&p| id(p)).collect(),
            pre_start: vec![0],
            pre: Vec::new(),
            add_start: vec![0],
            add: Vec::new(),
            triggers_start: Vec::new(),
            triggers: Vec::new(),
            groups: Groups::default(),
            unconditional: Vec::new(),
            negations,
            nodes,
            tuples: facts,
            negation_base: negation_base.clone(),
            instance_base,
            instance_actions: Vec::new(),
            aux_base,
            goal_options: goals.iter().map(|g| g.iter().map(|&p| id(p)).collect()).collect(),
            goals_of_start: Vec::new(),
            goals_of: Vec::new(),
            present: vec![false; nodes],
            cost: vec![u32::MAX; nodes],
            done: vec![false; nodes],
            supporter: vec![NONE; nodes],
            counters: Vec::new(),
            fresh: Vec::new(),
            queue: BucketQueue::default(),
            unreached: Vec::new(),
            keep_plan: false,
            grouped: None,
        };
        // An action: its schema, weight and bindings; its pair and exclusion number (`NONE`
        // for actions not split at an exclusion); its preconditions and effects.
        type Parts = (u32, u32);
        let push = |task: &mut GroundTask,
                    (schema, weight): (u32, u32),
                    bindings,
                    (pair, exclusion): Parts,
                    mut pre: Vec<u32>,
                    mut add: Vec<u32>| {
            let a = task.schema.len() as u32;
            task.schema.push(schema);
            task.weight.push(weight);
            task.bindings.push(bindings);
            task.pair.push(pair);
            task.exclusion_of.push(exclusion);
            pre.sort_unstable();
            pre.dedup();
            if pre.is_empty() {
                task.unconditional.push(a);
            }
            task.pre.extend_from_slice(&pre);
            task.pre_start.push(task.pre.len() as u32);
            add.sort_unstable();
            add.dedup();
            task.add.extend_from_slice(&add);
            task.add_start.push(task.add.len() as u32);
        };
        for action in actions {
            let mut pre: Vec<u32> = action.pre.iter().map(|&p| id(p)).collect();
            pre.extend(action.exclusion.map(|e| aux_base + auxiliary.exclusion_node[e as usize]));
            let mut add: Vec<u32> = action.add.iter().map(|&p| id(p)).collect();
            if negative.is_some() {
                pre.extend(action.invalid.iter().map(|&i| instance_base + i));
                add.extend(action.deletes.iter().map(|&p| negation(p)));
            }
            let parts = (action.pair.unwrap_or(NONE), action.exclusion.unwrap_or(NONE));
            push(&mut task, (schemas[action.rule as usize], 1), action.bindings, parts, pre, add);
        }
        // Each Invalid literal instance holds once every fact it forbids is absent or deleted.
        if let Some((_, candidates)) = negative {
            for (i, forbidden) in candidates.iter().enumerate() {
                task.instance_actions.push(task.schema.len() as u32);
                let pre = forbidden.iter().map(|&p| negation(p)).collect();
                push(&mut task, (u32::MAX, 0), Box::new([]), (NONE, NONE), pre, vec![instance_base + i as u32]);
            }
        }
        for &(source, node) in &auxiliary.links {
            let from = match source {
                Source::Tuple(view, t) => id((view, t)),
                Source::Aux(a) => aux_base + a,
            };
            push(&mut task, (u32::MAX, 0), Box::new([]), (NONE, NONE), vec![from], vec![aux_base + node]);
        }
        task.choices = auxiliary.choices;
        let count = task.schema.len();
        let deleting: Vec<(u32, u32)> = (0..count)
            .filter(|&a| task.pair[a] != NONE)
            .flat_map(|a| {
                let range = task.pre_start[a] as usize..task.pre_start[a + 1] as usize;
                task.pre[range].iter().filter(|&&p| (p as usize) < facts).map(move |&p| (p, a as u32))
            })
            .collect();
        let (deleters_start, deleters) = csr(facts, deleting.into_iter());
        task.deleters_start = deleters_start;
        task.deleters = deleters;
        let (groups, prefix) = Groups::find(&task.pre_start, &task.pre);
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(task.pre.len());
        for (g, &(first, _)) in groups.actions.iter().enumerate() {
            let pre = &task.pre[task.pre_start[first as usize] as usize..];
            pairs.extend(pre[..groups.fresh[g].left as usize].iter().map(|&f| (f, GROUP | g as u32)));
        }
        for (a, &shared) in prefix.iter().enumerate() {
            let range = (task.pre_start[a] + shared) as usize..task.pre_start[a + 1] as usize;
            pairs.extend(task.pre[range].iter().map(|&f| (f, a as u32)));
        }
        // Each fact's entries in the order of the actions they stand for (a group's at its
        // first action's place), as the evaluation visited every action before the groups.
        let first = |entry: u32| if entry & GROUP != 0 { groups.actions[(entry & !GROUP) as usize].0 } else { entry };
        pairs.sort_by_key(|&(f, entry)| (f, first(entry)));
        let (triggers_start, triggers) = csr(nodes, pairs.into_iter());
        task.triggers_start = triggers_start;
        task.triggers = triggers;
        task.fresh = (0..count)
            .map(|a| {
                let own = task.pre_start[a + 1] - task.pre_start[a] - prefix[a];
                Counter { cost: 0, left: own + u32::from(prefix[a] > 0) }
            })
            .collect();
        task.counters = task.fresh.clone();
        task.groups = groups;
        let goal_pairs: Vec<(u32, u32)> = task
            .goal_options
            .iter()
            .enumerate()
            .flat_map(|(g, options)| options.iter().map(move |&f| (f, g as u32)))
            .collect();
        let (goals_of_start, goals_of) = csr(nodes, goal_pairs.into_iter());
        task.goals_of_start = goals_of_start;
        task.goals_of = goals_of;
        task.offsets = offsets;
        task
    }

    /// Each node's readers: the actions that have it as a precondition, in order (CSR layout).
    pub(super) fn readers(&self) -> (Vec<u32>, Vec<u32>) {
        let pairs = (0..self.schema.len()).flat_map(|a| {
            let range = self.pre_start[a] as usize..self.pre_start[a + 1] as usize;
            self.pre[range].iter().map(move |&f| (f, a as u32))
        });
        csr(self.nodes, pairs)
    }

    /// The number of ground actions (without the conjunctions for Invalid literals).
    pub fn action_count(&self) -> usize {
        self.weight.iter().filter(|&&w| w > 0).count()
    }

    /// The goal literals the last evaluation did not reach.
    pub fn unreached(&self) -> &[usize] {
        &self.unreached
    }

    fn relax(&mut self, fact: u32, cost: u32, supporter: u32) {
        relax(&mut self.cost, &self.done, &mut self.supporter, &mut self.queue, fact, cost, supporter);
    }

    /// Evaluates the state whose facts are the view tuples `start`.
    pub fn evaluate(&mut self, start: &[(u32, u32)], plan: bool) -> Estimate {
        self.cost.fill(u32::MAX);
        self.done.fill(false);
        self.supporter.fill(NONE);
        self.queue.clear();
        self.counters.copy_from_slice(&self.fresh);
        self.groups.counters.copy_from_slice(&self.groups.fresh);
        for &(view, t) in start {
            let fact = self.offsets[view as usize] + t;
            self.present[fact as usize] = true;
            self.relax(fact, 0, NONE);
        }
        // A fact absent from the state needs no deletion.
        for i in 0..self.negations.len() {
            let (fact, negation) = self.negations[i];
            if !self.present[fact as usize] {
                self.relax(negation, 0, NONE);
            }
        }
        for &(view, t) in start {
            self.present[(self.offsets[view as usize] + t) as usize] = false;
        }
        for i in 0..self.unconditional.len() {
            let a = self.unconditional[i] as usize;
            for k in self.add_start[a]..self.add_start[a + 1] {
                self.relax(self.add[k as usize], self.weight[a], a as u32);
            }
        }
        let goals = self.goal_options.len();
        let mut reached: Vec<u32> = vec![NONE; goals];
        let mut remaining_goals = goals;
        let mut h_add = 0u32;
        // The loop below is most of the search's time on large tasks: it works on the fields
        // borrowed apart as slices, so that their addresses and lengths stay in registers
        // rather than being read again from the task after every write.
        let GroundTask {
            triggers_start,
            triggers,
            groups,
            add_start,
            add,
            weight,
            goals_of_start,
            goals_of,
            cost: costs,
            done,
            supporter,
            counters,
            queue,
            ..
        } = self;
        let (triggers_start, triggers, add_start, add, weight) =
            (&triggers_start[..], &triggers[..], &add_start[..], &add[..], &weight[..]);
        let (group_actions, group_counters) = (&groups.actions[..], &mut groups.counters[..]);
        let (goals_of_start, goals_of) = (&goals_of_start[..], &goals_of[..]);
        let (costs, done, supporter, counters) = (&mut costs[..], &mut done[..], &mut supporter[..], &mut counters[..]);
        while remaining_goals > 0 {
            let Some((cost, fact)) = queue.pop() else { break };
            let f = fact as usize;
            if done[f] || cost > costs[f] {
                continue;
            }
            done[f] = true;
            for &g in &goals_of[goals_of_start[f] as usize..goals_of_start[f + 1] as usize] {
                let g = g as usize;
                if reached[g] == NONE {
                    reached[g] = fact;
                    remaining_goals -= 1;
                    h_add = h_add.saturating_add(cost);
                }
            }
            if remaining_goals == 0 {
                break;
            }
            for &entry in &triggers[triggers_start[f] as usize..triggers_start[f + 1] as usize] {
                if entry & GROUP == 0 {
                    let a = entry as usize;
                    if count_in(&mut counters[a], cost) {
                        let fired = counters[a].cost.saturating_add(weight[a]);
                        for &added in &add[add_start[a] as usize..add_start[a + 1] as usize] {
                            relax(costs, done, supporter, queue, added, fired, a as u32);
                        }
                    }
                    continue;
                }
                let g = (entry & !GROUP) as usize;
                if !count_in(&mut group_counters[g], cost) {
                    continue;
                }
                let (shared, (first, end)) = (group_counters[g].cost, group_actions[g]);
                for a in first as usize..end as usize {
                    if count_in(&mut counters[a], shared) {
                        let fired = counters[a].cost.saturating_add(weight[a]);
                        for &added in &add[add_start[a] as usize..add_start[a + 1] as usize] {
                            relax(costs, done, supporter, queue, added, fired, a as u32);
                        }
                    }
                }
            }
        }
        self.unreached = reached.iter().enumerate().filter(|(_, r)| **r == NONE).map(|(g, _)| g).collect();
        if remaining_goals > 0 {
            return Estimate::default();
        }
        let mut estimate = Estimate { h_add: Some(h_add), ..Estimate::default() };
        if plan {
            self.relaxed_plan(&reached, &mut estimate);
        }
        estimate
    }

    fn relaxed_plan(&mut self, reached: &[u32], estimate: &mut Estimate) {
        let mut pending: BinaryHeap<(u32, u32)> = BinaryHeap::new();
        for &fact in reached {
            pending.push((self.cost[fact as usize], fact));
        }
        // Facts already handled (or added by a chosen action), and chosen actions.
        let mut handled = vec![false; self.nodes];
        let mut chosen = vec![false; self.schema.len()];
        let mut planned = vec![false; self.schema.len()];
        let mut length = 0u32;
        // The actions for `Estimate::plan`, when asked for.
        let mut plan: Vec<(usize, u32)> = Vec::new();
        // Every action chosen, in order, with the fact it was chosen for.
        let mut picked: Vec<(usize, u32)> = Vec::new();
        while let Some((_, fact)) = pending.pop() {
            let f = fact as usize;
            if std::mem::replace(&mut handled[f], true) {
                continue;
            }
            let a = self.supporter[f];
            if a == NONE {
                continue;
            }
            let a = a as usize;
            if std::mem::replace(&mut chosen[a], true) {
                continue;
            }
            picked.push((a, fact));
            length += self.weight[a];
            for k in self.add_start[a]..self.add_start[a + 1] {
                handled[self.add[k as usize] as usize] = true;
            }
            let member = self.chosen_member(a);
            self.handle_other_part(a, member, &mut handled);
            let mut first_layer = true;
            for (p, _) in self.chosen_preconditions(a, member) {
                first_layer &= self.cost[p as usize] == 0;
                pending.push((self.cost[p as usize], p));
            }
            if first_layer && self.weight[a] > 0 {
                estimate.subgoals.push(fact);
                estimate.helpful.push(Helpful { schema: self.schema[a] as usize, bindings: self.bindings[a].clone() });
            }
            // A part split at an exclusion stands for its whole instantiation, which the
            // plan names by its adding part (a block's move off the cell another needs is
            // chosen for the deletion, through its deleting part).
            let whole = self.whole(a);
            if self.keep_plan && self.weight[a] > 0 && !std::mem::replace(&mut planned[whole], true) {
                plan.push((whole, fact));
            }
        }
        let mut detours = Vec::new();
        if !plan.is_empty() {
            let picked_actions: Vec<usize> = picked.iter().map(|&(a, _)| a).collect();
            let due = self.due(&picked_actions, reached);
            let flags = self.detours(&plan, &picked, reached);
            // Decided once, on the first relaxed plan (the initial state's): where a quarter
            // of it or more is trips aside, the plan comes group by group.
            let parking = flags.iter().filter(|&&detour| detour).count() * PARKING_SHARE >= flags.len();
            let grouped = *self.grouped.get_or_insert(parking);
            let group = if grouped { self.groups(&picked_actions) } else { rustc_hash::FxHashMap::default() };
            // A group comes when its first action is due, and then whole.
            let mut first: rustc_hash::FxHashMap<usize, u32> = rustc_hash::FxHashMap::default();
            for &(a, _) in &plan {
                if let Some(&g) = group.get(&a) {
                    first.entry(g).and_modify(|d| *d = (*d).min(due[&a])).or_insert(due[&a]);
                }
            }
            let key = |a: usize| match group.get(&a) {
                Some(g) => (first[g], *g, due[&a], self.counters[a].cost),
                None => (due[&a], 0, due[&a], self.counters[a].cost),
            };
            let mut ordered: Vec<((usize, u32), bool)> = plan.drain(..).zip(flags).collect();
            // (A stable sort: equal keys stay in the order the plan chose them.)
            ordered.sort_by_key(|&((a, _), _)| key(a));
            (plan, detours) = ordered.into_iter().unzip();
        }
        estimate.plan = plan
            .into_iter()
            .zip(detours)
            .map(|((a, purpose), detour)| PlanAction {
                action: Helpful { schema: self.schema[a] as usize, bindings: self.bindings[a].clone() },
                purpose,
                detour,
                loose: Box::default(),
                chosen: Box::default(),
            })
            .collect();
        estimate.h_ff = Some(length);
        estimate.subgoals.sort_unstable();
        estimate.subgoals.dedup();
    }

    /// For each action of `plan` (with the fact it was chosen for), whether that fact is a
    /// stop on a detour: read by the plan's actions only as a member of an exclusion node
    /// ("somewhere other than here", such as the cell a block leaves on its last move), or
    /// by actions chosen for such facts in turn. A block's trip to a free cell, on the way
    /// to its place in a tower it now stands in, is one: any other free cell would do. Readers
    /// are followed through at most four actions (a detour is a move's start and end, read by
    /// the next move: two), which also ends any cycle of supports.
    fn detours(&self, plan: &[(usize, u32)], picked: &[(usize, u32)], reached: &[u32]) -> Vec<bool> {
        let mut readers: rustc_hash::FxHashMap<u32, Vec<(usize, bool)>> = rustc_hash::FxHashMap::default();
        let mut purpose: rustc_hash::FxHashMap<usize, u32> = rustc_hash::FxHashMap::default();
        for &(b, fact) in picked {
            purpose.insert(b, fact);
            for (p, excluded) in self.chosen_preconditions(b, self.chosen_member(b)) {
                readers.entry(p).or_default().push((b, excluded));
            }
        }
        fn detour(
            fact: u32,
            depth: u32,
            readers: &rustc_hash::FxHashMap<u32, Vec<(usize, bool)>>,
            purpose: &rustc_hash::FxHashMap<usize, u32>,
            reached: &[u32],
        ) -> bool {
            if reached.contains(&fact) {
                return false;
            }
            let Some(by) = readers.get(&fact) else { return false };
            by.iter().all(|&(b, excluded)| {
                excluded
                    || (depth > 0 && purpose.get(&b).is_some_and(|&f| detour(f, depth - 1, readers, purpose, reached)))
            })
        }
        const DEPTH: u32 = 4;
        plan.iter().map(|&(_, fact)| detour(fact, DEPTH, &readers, &purpose, reached)).collect()
    }

    /// For each action a relaxed plan chose (`picked`), when what it leads to is due: the
    /// h_add cost of the cheapest goal literal it helps reach through the chosen actions that
    /// read what it adds, or that wait for what it deletes (`u32::MAX` if it leads to no
    /// goal). A start that takes an arm for a block whose place is not ready (the second
    /// block of a tower whose base is still elsewhere, or a base whose cell another block
    /// holds) leads to a goal due later than the moves that ready it: the lookahead, which
    /// takes the plan's actions in this order, gives its arms to those first.
    fn due(&self, picked: &[usize], reached: &[u32]) -> rustc_hash::FxHashMap<usize, u32> {
        let mut due: rustc_hash::FxHashMap<usize, u32> =
            picked.iter().flat_map(|&a| [a, self.whole(a)]).map(|a| (a, u32::MAX)).collect();
        for &fact in reached {
            let a = self.supporter[fact as usize];
            if let Some(d) = due.get_mut(&(a as usize)) {
                *d = (*d).min(self.cost[fact as usize]);
            }
        }
        // Consumers cost at least what their suppliers do: from the costliest down, each
        // passes its due to the actions that support its preconditions, and a deleting part
        // to its adding part (twice, for the zero-cost links between actions of equal cost).
        let mut order: Vec<usize> = picked.to_vec();
        order.sort_by_key(|&b| std::cmp::Reverse(self.counters[b].cost));
        for _ in 0..2 {
            for &b in &order {
                let at = due[&b];
                if at == u32::MAX {
                    continue;
                }
                let member = self.chosen_member(b);
                let mut pass = |a: u32| {
                    if let Some(d) = due.get_mut(&(a as usize)) {
                        *d = (*d).min(at);
                    }
                };
                if self.pair[b] != NONE {
                    pass(self.pair[b]);
                }
                for (p, _) in self.chosen_preconditions(b, member) {
                    let a = self.supporter[p as usize];
                    if a != NONE {
                        pass(a);
                    }
                }
            }
        }
        due
    }

    /// For each action a relaxed plan chose (`picked`, and each one's whole instantiation),
    /// the group it belongs to: the connected components of the chosen actions linked by
    /// the supports of their chosen preconditions (and a deleting part to its adding part),
    /// each named by its least member. A fact more than [`SHARED_READERS`] of the chosen
    /// actions read (an arm that comes free, which every later grip may take) links none of
    /// them, nor does an exclusion node's member (a free cell). On a reverse rung the groups
    /// are the stacks: a block's trips aside and back, and the moves that clear it.
    fn groups(&self, picked: &[usize]) -> rustc_hash::FxHashMap<usize, usize> {
        // Dense indices for the chosen actions and their other parts, as the sets want.
        let mut index: rustc_hash::FxHashMap<usize, usize> = rustc_hash::FxHashMap::default();
        let mut members: Vec<usize> = Vec::new();
        for a in picked.iter().flat_map(|&a| [a, self.whole(a)]) {
            index.entry(a).or_insert_with(|| {
                members.push(a);
                members.len() - 1
            });
        }
        let mut readers: rustc_hash::FxHashMap<u32, u32> = rustc_hash::FxHashMap::default();
        for &b in picked {
            for (p, _) in self.chosen_preconditions(b, self.chosen_member(b)) {
                *readers.entry(p).or_default() += 1;
            }
        }
        let mut sets = petgraph::unionfind::UnionFind::<usize>::new(members.len());
        for &b in picked {
            let supporters = self
                .chosen_preconditions(b, self.chosen_member(b))
                .filter(|&(p, excluded)| !excluded && readers[&p] <= SHARED_READERS)
                .map(|(p, _)| self.supporter[p as usize])
                .filter(|&a| a != NONE)
                .map(|a| a as usize);
            for a in std::iter::once(self.whole(b)).chain(supporters) {
                if let Some(&other) = index.get(&a) {
                    sets.union(index[&b], other);
                }
            }
        }
        let mut least: rustc_hash::FxHashMap<usize, usize> = rustc_hash::FxHashMap::default();
        for (i, &a) in members.iter().enumerate() {
            least.entry(sets.find_mut(i)).and_modify(|m| *m = (*m).min(a)).or_insert(a);
        }
        members.iter().enumerate().map(|(i, &a)| (a, least[&sets.find_mut(i)])).collect()
    }

    /// The action that names `a`'s whole instantiation: its adding part for the deleting part
    /// of an instantiation split at an exclusion, else `a` itself.
    fn whole(&self, a: usize) -> usize {
        if self.pair[a] == NONE { a } else { self.pair[a] as usize }
    }

    /// For a part of an instantiation split at an exclusion, chosen for the relaxed plan:
    /// marks what the other part of that instantiation adds as handled, as choosing the whole
    /// instantiation did before the split (so the move that takes a block where the plan
    /// wants it also empties the cell it leaves, and counts once). For the deleting part, the
    /// instantiation is the first one recorded (the one the whole action that first reached
    /// the deletion stood for); for the adding part, the one reading `member`, the tuple
    /// [`GroundTask::chosen_member`] took for its exclusion node.
    fn handle_other_part(&self, a: usize, member: u32, handled: &mut [bool]) {
        let mark = |action: usize, handled: &mut [bool]| {
            for k in self.add_start[action]..self.add_start[action + 1] {
                handled[self.add[k as usize] as usize] = true;
            }
        };
        if self.pair[a] != NONE {
            mark(self.pair[a] as usize, handled);
            return;
        }
        if member == NONE {
            return;
        }
        let m = member as usize;
        for &d in &self.deleters[self.deleters_start[m] as usize..self.deleters_start[m + 1] as usize] {
            if self.schema[d as usize] == self.schema[a] {
                mark(d as usize, handled);
            }
        }
    }

    /// The preconditions of action `a` as the relaxed plan reads them, each with whether it
    /// is read through an exclusion node: such a node stands for `member`, the tuple chosen
    /// for it ([`GroundTask::chosen_member`]).
    fn chosen_preconditions(&self, a: usize, member: u32) -> impl Iterator<Item = (u32, bool)> + '_ {
        self.pre[self.pre_start[a] as usize..self.pre_start[a + 1] as usize]
            .iter()
            .map(move |&p| if p >= self.aux_base && member != NONE { (member, true) } else { (p, false) })
    }

    /// For an action that reads an exclusion node, the tuple the relaxed plan takes for it:
    /// of the tuples not excluded, the cheapest, lowest node first (the one that settled
    /// first, whose instantiation the whole ground action was that first reached what this
    /// one adds); `NONE` for other actions.
    fn chosen_member(&self, a: usize) -> u32 {
        let e = self.exclusion_of[a];
        if e == NONE {
            return NONE;
        }
        let [start, end, skip_start, skip_end] = self.choices[e as usize];
        let candidates = self.members[start as usize..skip_start as usize]
            .iter()
            .chain(&self.members[skip_end as usize..end as usize]);
        candidates
            .copied()
            .filter(|&m| self.done[m as usize])
            .min_by_key(|&m| (self.cost[m as usize], m))
            .unwrap_or(NONE)
    }
}

/// Offers `fact` the cost `cost` through the action `by`: taken if the fact is not settled
/// and has no cheaper cost yet. A function of the fields, not of the task, so the evaluation's
/// loop can call it with the task's fields borrowed apart. Always inlined: as a hint only, a
/// change elsewhere in the crate (the backward rules of `passes::reassign`) once left it a
/// call in that loop, and the search of warehouse_c20_r2_s25 took 0.39 -> 0.44 s.
#[inline(always)]
fn relax(
    costs: &mut [u32],
    done: &[bool],
    supporter: &mut [u32],
    queue: &mut BucketQueue,
    fact: u32,
    cost: u32,
    by: u32,
) {
    let f = fact as usize;
    if !done[f] && cost < costs[f] {
        costs[f] = cost;
        supporter[f] = by;
        queue.push(cost, fact);
    }
}

#[cfg(test)]
mod tests {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;

    use super::{Auxiliary, BucketQueue, GroundTask, NONE, RecordedAction, radix_sort};

    /// An evaluation through groups of actions that share their first preconditions gives
    /// every node the cost and the supporter that the plain generalised Dijkstra gives it,
    /// written here apart (a binary heap, each action counting each of its preconditions),
    /// on random tasks whose actions come in runs with shared prefixes (some of them
    /// interleaved with other preconditions once sorted) and with weights 0 and 1.
    #[test]
    fn grouped_preconditions_give_the_costs_and_supporters_of_the_plain_evaluation() {
        let mut random = kbvm::rng::Rng::new(11);
        let mut grouped = 0;
        for _ in 0..300 {
            let facts = 8 + random.below(30);
            let fact = |random: &mut kbvm::rng::Rng| (0u32, random.below(facts) as u32);
            let mut actions = Vec::new();
            for rule in 0..1 + random.below(4) {
                for _ in 0..1 + random.below(4) {
                    let shared: Vec<(u32, u32)> = (0..random.below(4)).map(|_| fact(&mut random)).collect();
                    for _ in 0..1 + random.below(6) {
                        let mut pre = shared.clone();
                        pre.extend((0..random.below(3)).map(|_| fact(&mut random)));
                        let add = (0..1 + random.below(2)).map(|_| fact(&mut random)).collect();
                        actions.push(RecordedAction {
                            rule: rule as u32,
                            bindings: Box::new([]),
                            key: None,
                            pre,
                            exclusion: None,
                            pair: None,
                            add,
                            invalid: Vec::new(),
                            deletes: Vec::new(),
                        });
                    }
                }
            }
            let schemas: Vec<u32> = (0..4).collect();
            // A goal nothing adds: the evaluation runs until the queue is empty.
            let unreachable = facts as u32;
            let mut task =
                GroundTask::new(&[facts + 1], actions, &schemas, &[vec![(0, unreachable)]], None, Auxiliary::default());
            grouped += task.groups.actions.len();
            for a in 0..task.weight.len() {
                task.weight[a] = random.below(2) as u32;
            }
            let start: Vec<(u32, u32)> = (0..random.below(4)).map(|_| fact(&mut random)).collect();
            let _ = task.evaluate(&start, false);
            // The reference, over each action's whole list of preconditions.
            let nodes = task.nodes;
            let (mut cost, mut supporter, mut done) = (vec![u32::MAX; nodes], vec![NONE; nodes], vec![false; nodes]);
            let mut heap = BinaryHeap::new();
            let offer = |heap: &mut BinaryHeap<Reverse<(u32, u32)>>,
                         cost: &mut Vec<u32>,
                         supporter: &mut Vec<u32>,
                         done: &[bool],
                         f: u32,
                         c: u32,
                         by: u32| {
                if !done[f as usize] && c < cost[f as usize] {
                    cost[f as usize] = c;
                    supporter[f as usize] = by;
                    heap.push(Reverse((c, f)));
                }
            };
            for &(_, t) in &start {
                offer(&mut heap, &mut cost, &mut supporter, &done, t, 0, NONE);
            }
            let actions = task.weight.len();
            let list = |a: usize| &task.pre[task.pre_start[a] as usize..task.pre_start[a + 1] as usize];
            let adds = |a: usize| &task.add[task.add_start[a] as usize..task.add_start[a + 1] as usize];
            for a in (0..actions).filter(|&a| list(a).is_empty()) {
                for &f in adds(a) {
                    offer(&mut heap, &mut cost, &mut supporter, &done, f, task.weight[a], a as u32);
                }
            }
            let mut gathered = vec![0u32; actions];
            let mut left: Vec<usize> = (0..actions).map(|a| list(a).len()).collect();
            while let Some(Reverse((c, f))) = heap.pop() {
                if done[f as usize] || c > cost[f as usize] {
                    continue;
                }
                done[f as usize] = true;
                for a in (0..actions).filter(|&a| list(a).contains(&f)) {
                    gathered[a] += c;
                    left[a] -= 1;
                    if left[a] == 0 {
                        for &added in adds(a) {
                            offer(
                                &mut heap,
                                &mut cost,
                                &mut supporter,
                                &done,
                                added,
                                gathered[a] + task.weight[a],
                                a as u32,
                            );
                        }
                    }
                }
            }
            assert_eq!(task.cost, cost);
            assert_eq!(task.supporter, supporter);
        }
        // (The tasks had groups to go through.)
        assert!(grouped > 300, "{grouped} groups");
    }

    /// The bucket queue pops exactly what one binary heap of `(cost, fact)` pops, for pushes
    /// that never fall below the last cost popped (as the evaluation's are), costs past the
    /// buckets included, and buckets large enough for the radix sort (every tenth round).
    #[test]
    fn the_bucket_queue_pops_in_the_order_of_a_binary_heap() {
        let mut random = kbvm::rng::Rng::new(7);
        let mut radix_sorted = 0;
        for round in 0..200 {
            let mut buckets = BucketQueue::default();
            let mut heap: BinaryHeap<Reverse<(u32, u32)>> = BinaryHeap::new();
            let high = if round % 2 == 0 { 40 } else { BucketQueue::BUCKETS as u32 + 40 };
            let (pushes, facts) = if round % 10 == 0 { (20_000, 3_000_000) } else { (300, 50) };
            let mut floor = 0u32;
            for _ in 0..pushes {
                if buckets.sorted.len() >= super::RADIX_FROM {
                    radix_sorted += 1;
                }
                if random.below(3) > 0 {
                    let cost = floor + random.below(8) as u32 * if random.below(4) == 0 { high / 8 } else { 1 };
                    let fact = random.below(facts) as u32;
                    buckets.push(cost, fact);
                    heap.push(Reverse((cost, fact)));
                } else {
                    let expected = heap.pop().map(|Reverse(entry)| entry);
                    assert_eq!(buckets.pop(), expected);
                    match expected {
                        Some((cost, _)) => floor = cost,
                        // Empty: the evaluation stops here too.
                        None => break,
                    }
                }
            }
            while let Some(Reverse(entry)) = heap.pop() {
                assert_eq!(buckets.pop(), Some(entry));
            }
            assert_eq!(buckets.pop(), None);
            buckets.clear();
            assert_eq!(buckets.pop(), None);
        }
        assert!(radix_sorted > 0, "no bucket was large enough for the radix sort");
    }

    /// The radix sort gives `sort_unstable`'s order, on values of one, two and three digits,
    /// with repeats.
    #[test]
    fn radix_sort_sorts_as_sort_unstable() {
        let mut rng = kbvm::rng::Rng::new(7);
        for (len, bound) in [(0usize, 10u64), (1, 10), (600, 50), (5000, 3_000_000), (3000, u64::from(u32::MAX))] {
            let values: Vec<u32> = (0..len).map(|_| (rng.next_u64() % bound) as u32).collect();
            let (mut radix, mut scratch) = (values.clone(), Vec::new());
            radix_sort(&mut radix, &mut scratch);
            let mut expected = values;
            expected.sort_unstable();
            assert_eq!(radix, expected, "{len} values below {bound}");
        }
    }
}
