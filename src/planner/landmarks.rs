//! Fact landmarks of the ground relaxed task and the landmark-count heuristic, as in LAMA.
//!
//! A landmark is a node of the ground task (a view tuple, the absence of a fact, or an Invalid
//! literal instance holding) that every plan makes true at some point. They are found by Zhu
//! and Givan's propagation over the relaxed task: the landmarks of a node are the node itself
//! and what every action that achieves it needs, `LM(f) = {f} ∪ ⋂_{a adds f} ⋃_{p ∈ pre(a)}
//! LM(p)`, iterated to a fixpoint from the initial state; the task's landmarks are those of its
//! goal literals. `l` is naturally ordered before `l'` when `l ∈ LM(l')`.
//!
//! The heuristic counts, along the path to a state, the landmarks not yet *accepted* (a
//! landmark is accepted when it holds in a state and every landmark ordered before it was
//! accepted earlier), plus the accepted goal landmarks that no longer hold. Where h_FF sits on a
//! plateau, for instance while a block is taken off a stack it must leave before the stack
//! below can move, the landmark count still goes down: clearing the block below is a landmark.
//! Resource goals (`available(a1)`) are left out, as in the relaxation.

use std::collections::VecDeque;

use super::ground::GroundTask;

/// How to tell whether a landmark holds in a state.
#[derive(Clone, Debug)]
enum Truth {
    /// A view tuple: some fact of the state projects onto it.
    Tuple(u32),
    /// The absence of the fact with this view-tuple node.
    Absent(u32),
    /// An Invalid literal instance: none of these view-tuple nodes is present.
    AllAbsent(Box<[u32]>),
}

/// The landmarks of a task and their orderings.
#[derive(Clone)]
pub(super) struct Landmarks {
    truth: Vec<Truth>,
    /// For each landmark, the landmarks naturally ordered before it.
    parents: Vec<Box<[u32]>>,
    /// Whether each is a goal literal's only option (required again when it stops holding).
    goal: Vec<bool>,
}

/// A set of accepted landmarks, one bit each.
pub(super) type Accepted = Box<[u64]>;

fn union_into(into: &mut Vec<u32>, other: &[u32]) {
    if other.is_empty() {
        return;
    }
    let mut merged = Vec::with_capacity(into.len() + other.len());
    let (mut i, mut j) = (0, 0);
    while i < into.len() && j < other.len() {
        match into[i].cmp(&other[j]) {
            std::cmp::Ordering::Less => {
                merged.push(into[i]);
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                merged.push(other[j]);
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                merged.push(into[i]);
                i += 1;
                j += 1;
            }
        }
    }
    merged.extend_from_slice(&into[i..]);
    merged.extend_from_slice(&other[j..]);
    *into = merged;
}

fn intersect(a: &[u32], b: &[u32]) -> Vec<u32> {
    let mut out = Vec::new();
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                out.push(a[i]);
                i += 1;
                j += 1;
            }
        }
    }
    out
}

impl Landmarks {
    /// Finds the landmarks of `ground` from the state whose view tuples are `init`.
    pub fn compute(ground: &mut GroundTask, init: &[(u32, u32)]) -> Landmarks {
        // What holds initially: every node the relaxation reaches at cost 0.
        let _ = ground.evaluate(init, false);
        let nodes = ground.nodes;
        let initially: Vec<bool> = (0..nodes).map(|n| ground.cost[n] == 0).collect();
        let actions = ground.weight.len();
        let (readers_start, readers) = ground.readers();
        let mut lm: Vec<Option<Vec<u32>>> = (0..nodes).map(|n| initially[n].then(|| vec![n as u32])).collect();
        let mut waiting: Vec<u32> = (0..actions)
            .map(|a| {
                ground.pre[ground.pre_start[a] as usize..ground.pre_start[a + 1] as usize]
                    .iter()
                    .filter(|&&p| !initially[p as usize])
                    .count() as u32
            })
            .collect();
        let mut queue: VecDeque<u32> = VecDeque::new();
        let mut queued = vec![false; actions];
        for a in 0..actions {
            if waiting[a] == 0 {
                queue.push_back(a as u32);
                queued[a] = true;
            }
        }
        let mut union = Vec::new();
        while let Some(a) = queue.pop_front() {
            let a = a as usize;
            queued[a] = false;
            union.clear();
            for k in ground.pre_start[a]..ground.pre_start[a + 1] {
                let p = ground.pre[k as usize] as usize;
                if let Some(set) = &lm[p] {
                    union_into(&mut union, set);
                }
            }
            for k in ground.add_start[a]..ground.add_start[a + 1] {
                let f = ground.add[k as usize];
                let mut candidate = union.clone();
                union_into(&mut candidate, &[f]);
                let (changed, first) = match &lm[f as usize] {
                    None => (true, true),
                    Some(old) => {
                        let narrowed = intersect(old, &candidate);
                        let changed = narrowed.len() != old.len();
                        candidate = narrowed;
                        (changed, false)
                    }
                };
                if !changed {
                    continue;
                }
                lm[f as usize] = Some(candidate);
                for u in readers_start[f as usize]..readers_start[f as usize + 1] {
                    let user = readers[u as usize] as usize;
                    if first {
                        waiting[user] -= 1;
                    }
                    if waiting[user] == 0 && !queued[user] {
                        queued[user] = true;
                        queue.push_back(user as u32);
                    }
                }
            }
        }
        // The task's landmarks: those of every goal literal (the intersection over its
        // options), without the ones that hold initially and are not goals.
        let mut all: Vec<u32> = Vec::new();
        let mut goal_nodes: Vec<u32> = Vec::new();
        for options in &ground.goal_options {
            let mut common: Option<Vec<u32>> = None;
            for &option in options {
                if let Some(set) = &lm[option as usize] {
                    common = Some(match common {
                        None => set.clone(),
                        Some(c) => intersect(&c, set),
                    });
                }
            }
            if let [only] = options[..] {
                goal_nodes.push(only);
            }
            if let Some(common) = common {
                union_into(&mut all, &common);
            }
        }
        goal_nodes.sort_unstable();
        // Auxiliary nodes stand for choices among facts, not facts: none is a landmark.
        all.retain(|&n| n < ground.aux_base && (!initially[n as usize] || goal_nodes.binary_search(&n).is_ok()));
        let index = |n: u32| all.binary_search(&n).ok().map(|i| i as u32);
        let negation_of: rustc_hash::FxHashMap<u32, u32> =
            ground.negations.iter().map(|&(fact, negation)| (negation, fact)).collect();
        let truth = all
            .iter()
            .map(|&n| {
                if (n as usize) < ground.tuples {
                    Truth::Tuple(n)
                } else if n < ground.instance_base {
                    Truth::Absent(negation_of[&n])
                } else {
                    let action = ground.instance_actions[(n - ground.instance_base) as usize] as usize;
                    let range = ground.pre_start[action] as usize..ground.pre_start[action + 1] as usize;
                    Truth::AllAbsent(ground.pre[range].iter().map(|p| negation_of[p]).collect())
                }
            })
            .collect();
        let parents = all
            .iter()
            .map(|&n| {
                lm[n as usize].as_deref().unwrap_or(&[]).iter().filter(|&&m| m != n).filter_map(|&m| index(m)).collect()
            })
            .collect();
        let goal = all.iter().map(|n| goal_nodes.binary_search(n).is_ok()).collect();
        Landmarks { truth, parents, goal }
    }

    /// The number of landmarks.
    pub fn len(&self) -> usize {
        self.truth.len()
    }

    fn holds(&self, l: usize, present: &[bool]) -> bool {
        match &self.truth[l] {
            Truth::Tuple(n) => present[*n as usize],
            Truth::Absent(n) => !present[*n as usize],
            Truth::AllAbsent(nodes) => nodes.iter().all(|&n| !present[n as usize]),
        }
    }

    /// The landmarks accepted in a state (whose view-tuple nodes are marked in `present`)
    /// reached from a state with `parent` accepted (`None` at the root), and the landmark
    /// count: landmarks not accepted plus accepted goal landmarks that do not hold.
    pub fn progress(&self, parent: Option<&[u64]>, present: &[bool]) -> (Accepted, u32) {
        let words = self.len().div_ceil(64);
        let mut accepted: Accepted = match parent {
            Some(parent) => parent.into(),
            None => vec![0; words].into(),
        };
        let is = |set: &[u64], l: u32| set[l as usize / 64] & (1 << (l % 64)) != 0;
        let mut count = 0u32;
        for l in 0..self.len() {
            let holds = self.holds(l, present);
            let already = is(&accepted, l as u32);
            if !already && holds && parent.is_none_or(|parent| self.parents[l].iter().all(|&p| is(parent, p))) {
                accepted[l / 64] |= 1 << (l % 64);
            } else if !already || (self.goal[l] && !holds) {
                count += 1;
            }
        }
        (accepted, count)
    }
}
