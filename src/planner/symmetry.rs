//! Interchangeable constants, so the heuristic search expands one of each set of symmetric
//! successors (Fox and Long's symmetry of objects, applied per state as in stabiliser-based
//! pruning).
//!
//! At 100 blocks and 10 idle arms, a state has 1,000 grip starts: ten copies of each, one per
//! arm, whose subtrees are the same up to renaming the arms. Two constants `c` and `d` are
//! *interchangeable in a state* when swapping them throughout maps the task and the state to
//! themselves; then a plan from the state through an action that uses `d` becomes, with `c`
//! and `d` swapped from there on, a plan through the action that uses `c`, with the same
//! steps and durations. So of successors that differ only by a permutation of interchangeable
//! constants the search needs one, and keeps what it can reach: any goal reachable from a
//! state stays reachable through the successors kept (by induction on the plan's length, the
//! goal being invariant).
//!
//! What makes a constant a *candidate* ([`Symmetry::new`]) is decided once, conservatively,
//! from the KB's text: an atom (never a number: arithmetic tells numbers apart) that appears
//! in no action schema of either level, no mapping, no `resources/1` template, no arm-level
//! state, no rule planning runs and no problem fact with a variable; only in the problem's
//! initial facts and in ground facts (static unit clauses of predicates planning reads, and the
//! problem's ground goal literals), and there once, as a whole argument. (Facts and rules no
//! OnKB goal or `duration/3` reaches, such as a test's own data or a KB's own planner, tell
//! nothing apart.) Two candidates with the same facts up to the candidate itself
//! (`agent(_)`, `available(_)` in the goal) are alike in the task. Facts are clauses of the
//! program the engine proves OnKB goals with, and swapping two constants reorders those
//! clauses; solutions are then the same set in another order, which only matters where the
//! first solution is all that is used: so a candidate may appear in such facts only if the KB
//! has no cut, no if-then-else and no built-in whose answer depends on the order of solutions
//! (`findall/3`, `once/1`: `Reads::Order` in `src/builtins.rs`), and `duration/3` (of which
//! the first answer counts) cannot reach their predicates. A KB that calls a built-in that
//! compares atoms by name (`compare/3`, `sort/2`, `@<`: `Reads::Names`) anywhere, its library
//! clauses included, or calls a goal only known at run time (`call(G)`, `findall(X, G, L)`),
//! has no candidates at all: nothing bounds what such a call tells apart.
//!
//! In a state ([`Symmetry::classes`]), each candidate's *signature* is what the task says of
//! it (above) and what the state's facts and running actions say of it, each with the
//! candidate replaced by a hole; candidates with equal signatures are interchangeable. A fact
//! that holds a candidate more than once, or inside a compound, or holds two, leaves the
//! candidates in it on their own (no pruning there).

use hashbrown::HashMap;
use rustc_hash::{FxBuildHasher, FxHashMap, FxHashSet};

use super::successors::Applicable;
use crate::intern::{Symbol, sym};
use crate::ir::hir::{Goal, Kb, Literal, Term};
use crate::ir::task::{Const, ConstId, FactId, Task};

/// A template: where a candidate sits in a fact, the fact with a hole there.
#[derive(Clone, PartialEq, Eq, Hash)]
struct Template {
    /// 0: a state fact (`head` is its predicate id); 1: a running action (`head` is its base
    /// name); 2: a static fact of the KB, 3: a ground goal literal (`head` is its name).
    kind: u8,
    head: u32,
    /// The arguments, with [`HOLE`] where the candidate is.
    args: Box<[ConstId]>,
}

const HOLE: ConstId = ConstId(u32::MAX);

/// An action up to a permutation of interchangeable candidates: its schema and its bindings,
/// each interchangeable candidate written as its class and its rank among the action's
/// candidates of that class.
type OrbitKey = (usize, Box<[u64]>);

/// What one fact says of the candidates.
#[derive(Clone)]
enum Mention {
    /// Nothing.
    None,
    /// One candidate (its index), once, as a whole argument: the fact's template id.
    One(u32, u32),
    /// Candidates it leaves on their own.
    Fixes(Box<[u32]>),
}

/// The candidates of a task and what the task says of each.
pub struct Symmetry {
    /// The candidates, by index.
    candidates: Vec<ConstId>,
    /// Candidate index by constant id (`u32::MAX`: not a candidate).
    index: Vec<u32>,
    templates: HashMap<Template, u32, FxBuildHasher>,
    /// Per fact id: what it says, once looked at.
    facts: Vec<Option<Mention>>,
    /// Per running-action constant: what it says.
    running: FxHashMap<ConstId, Mention>,
    /// Per candidate: its class by the task's signature alone.
    task_class: Vec<u32>,
    /// Scratch for [`Symmetry::classes`].
    pairs: Vec<(u32, u32)>,
}

/// The interchangeable candidates of one state: a class per candidate (`u32::MAX` for a
/// candidate alone in its class).
pub struct Classes {
    class: Vec<u32>,
}

/// Calls `f` on every atom in `term`, with whether it is a whole argument of the term (depth
/// one) or deeper; iterative, so a long list costs no stack.
fn atoms_of(term: &Term, mut f: impl FnMut(Symbol, bool)) {
    let mut stack: Vec<(&Term, usize)> = vec![(term, 0)];
    while let Some((t, depth)) = stack.pop() {
        match t {
            Term::Atom(s) if depth > 0 => f(*s, depth == 1),
            Term::Compound(_, args) => stack.extend(args.iter().map(|a| (a, depth + 1))),
            _ => {}
        }
    }
}

fn goal_literals<'a>(goal: &'a Goal, out: &mut Vec<&'a Literal>) {
    goal.for_each_call(&mut |l| out.push(l));
}

/// True if `goal` has a cut or an if-then-else anywhere, the goals a built-in calls included.
fn commits(goal: &Goal) -> bool {
    match goal {
        Goal::Call(l) => l.term == Term::Atom(sym::CUT),
        Goal::And(goals) => goals.iter().any(commits),
        Goal::Or(branches) => branches.iter().any(|b| !b.conditions.is_empty() || commits(&b.goal)),
        Goal::Not(g) => commits(g),
        Goal::Meta(meta) => {
            let mut found = false;
            let mut pending = vec![&meta.call.term];
            while let Some(term) = pending.pop() {
                match term {
                    Term::Atom(s) => found |= *s == sym::CUT,
                    Term::Compound(f, args) => {
                        found |= *f == sym::ARROW && args.len() == 2;
                        pending.extend(args.iter());
                    }
                    _ => {}
                }
            }
            found
        }
    }
}

/// What the built-ins `goal` calls can tell apart: whether one depends on the order of
/// solutions, and whether one compares atoms by name or (where `dynamic_counts`) calls a goal
/// known only at run time. The library's clauses call such goals only as they are given them,
/// by a call of the KB's that names them or holds a variable there, so for them it does not.
fn reads(goal: &Goal, interner: &crate::intern::Interner, dynamic_counts: bool, order: &mut bool, names: &mut bool) {
    goal.for_each_called(&mut |literal, extra| {
        let Some(builtin) = crate::builtins::lookup(interner, literal.name(), literal.arity() + extra) else { return };
        *order |= builtin.reads == crate::builtins::Reads::Order;
        *names |= builtin.reads == crate::builtins::Reads::Names;
        *names |= dynamic_counts && crate::builtins::calls_run_time_goal(interner, literal, extra);
    });
}

impl Symmetry {
    /// The candidates of `task`, a problem of `kb` (see the module's documentation).
    pub fn new(kb: &Kb, interner: &crate::intern::Interner, task: &mut Task) -> Symmetry {
        let problem = &kb.problems[task.problem];
        // Built-ins that tell atoms apart or depend on the order of solutions.
        // Only the rules planning can call matter: a rule nothing kbc runs calls (a KB's own
        // planner, a test wrapper) never tells anything apart.
        let run = kb.predicates_run();
        let runs = |clause: &&crate::ir::hir::Clause| run.contains(&(clause.head.name(), clause.head.arity()));
        let (mut order, mut names) = (false, false);
        for action in &kb.actions {
            action.on_kb.iter().for_each(|g| reads(g, interner, true, &mut order, &mut names));
        }
        for clause in kb.clauses.iter().filter(runs) {
            if let Some(body) = &clause.body {
                reads(body, interner, true, &mut order, &mut names);
            }
        }
        for clause in &kb.library {
            if let Some(body) = &clause.body {
                reads(body, interner, false, &mut order, &mut names);
            }
        }
        if names {
            return Symmetry::none(task);
        }
        // Atoms written anywhere they could be told apart.
        let mut excluded: FxHashSet<Symbol> = FxHashSet::default();
        let mut exclude = |literal: &Literal| atoms_of(&literal.term, |s, _| _ = excluded.insert(s));
        let mut literals: Vec<&Literal> = Vec::new();
        for action in &kb.actions {
            literals.push(&action.name);
            literals.extend(action.valid.iter().chain(&action.invalid).chain(&action.invalid_at_end));
            action.on_kb.iter().for_each(|g| goal_literals(g, &mut literals));
            literals.extend(action.effects.iter().map(|e| &e.literal));
        }
        for mapping in &kb.mappings {
            literals.push(&mapping.high);
            literals.extend(&mapping.steps);
        }
        literals.extend(kb.resources.iter().map(|r| &r.template));
        for state in &kb.arm_states {
            literals.extend(state.init.iter().chain(&state.goal));
        }
        literals.extend(&problem.open_init);
        // Ground facts of the task: static unit clauses and ground goal literals.
        let mut facts: Vec<(u8, &Literal)> = Vec::new();
        let mut commit = order || kb.actions.iter().any(|a| a.on_kb.iter().any(commits));
        commit |= kb.library.iter().any(|c| c.body.as_deref().is_some_and(commits));
        for clause in &kb.clauses {
            match &clause.body {
                Some(_) if !runs(&clause) => {}
                // A fact planning never reads tells nothing apart: the problems' states (a test
                // may read them before its `go` call), the facts of a test's own goals.
                None if !runs(&clause) => {}
                Some(body) => {
                    commit |= commits(body);
                    literals.push(&clause.head);
                    goal_literals(body, &mut literals);
                }
                None if clause.vars.is_empty() => facts.push((2, &clause.head)),
                None => literals.push(&clause.head),
            }
        }
        for literal in &problem.goal {
            let mut ground = true;
            literal.term.for_each_var(&mut |_| ground = false);
            if ground { facts.push((3, literal)) } else { literals.push(literal) }
        }
        literals.into_iter().for_each(&mut exclude);
        // A fact that holds an atom deeper than an argument, or twice, or two atoms that
        // could be candidates, excludes them.
        for (_, literal) in &facts {
            let mut whole: Vec<Symbol> = Vec::new();
            let mut deep = Vec::new();
            atoms_of(&literal.term, |s, top| if top { whole.push(s) } else { deep.push(s) });
            whole.retain(|s| !excluded.contains(s));
            if whole.len() > 1 {
                excluded.extend(whole.iter().copied());
            }
            excluded.extend(deep);
        }
        if !facts.is_empty() {
            // Facts with candidates must not be where only a first solution counts.
            // `duration/3`'s clauses and what they call (a goal known only at run time reaches
            // nothing there: `Symmetry::new` has left such a KB without candidates).
            let reached = kb.predicates_reached(vec![(sym::DURATION, 3)]);
            for (_, literal) in &facts {
                if commit || reached.contains(&literal.term.callable().unwrap_or((sym::ANON, 0))) {
                    atoms_of(&literal.term, |s, _| _ = excluded.insert(s));
                }
            }
        }
        // The candidates: atoms of the initial state (and facts) not excluded, as constants.
        let mut candidates: Vec<ConstId> = Vec::new();
        let mut index: Vec<u32> = vec![u32::MAX; task.consts.len()];
        let mut consider = |s: Symbol, task: &Task, candidates: &mut Vec<ConstId>| {
            if excluded.contains(&s) {
                return;
            }
            if let Some(id) = task.consts.find_term(&Term::Atom(s))
                && index[id.0 as usize] == u32::MAX
            {
                index[id.0 as usize] = candidates.len() as u32;
                candidates.push(id);
            }
        };
        for literal in problem.init.iter().chain(facts.iter().map(|(_, l)| *l)) {
            let mut atoms = Vec::new();
            atoms_of(&literal.term, |s, _| atoms.push(s));
            atoms.into_iter().for_each(|s| consider(s, task, &mut candidates));
        }
        // Per candidate: the templates of the task's facts about it.
        let mut task_signature: Vec<Vec<u32>> = vec![Vec::new(); candidates.len()];
        let mut symmetry = Symmetry {
            candidates,
            index,
            templates: HashMap::default(),
            facts: Vec::new(),
            running: FxHashMap::default(),
            task_class: Vec::new(),
            pairs: Vec::new(),
        };
        for (kind, literal) in facts {
            let Some((name, _)) = literal.term.callable() else { continue };
            let args: Option<Vec<ConstId>> = literal.term.args().iter().map(|a| task.consts.from_term(a)).collect();
            let Some(args) = args else { continue };
            if let Mention::One(candidate, template) = symmetry.mention(kind, name.0, &args, task) {
                task_signature[candidate as usize].push(template);
            }
        }
        task_signature.iter_mut().for_each(|s| s.sort_unstable());
        let mut ids: FxHashMap<&[u32], u32> = FxHashMap::default();
        symmetry.task_class = task_signature
            .iter()
            .map(|s| {
                let next = ids.len() as u32;
                *ids.entry(s.as_slice()).or_insert(next)
            })
            .collect();
        symmetry
    }

    /// No candidates: the search prunes nothing.
    fn none(task: &Task) -> Symmetry {
        Symmetry {
            candidates: Vec::new(),
            index: vec![u32::MAX; task.consts.len()],
            templates: HashMap::default(),
            facts: Vec::new(),
            running: FxHashMap::default(),
            task_class: Vec::new(),
            pairs: Vec::new(),
        }
    }

    /// True when no constant is a candidate (the search then prunes nothing).
    pub fn is_empty(&self) -> bool {
        self.candidates.is_empty()
    }

    /// The candidates, as constants.
    pub fn candidates(&self) -> &[ConstId] {
        &self.candidates
    }

    /// True if `a` and `b` are interchangeable in the state of `classes` (two candidates
    /// with the same signature there, or one constant).
    pub fn interchangeable(&self, classes: &Classes, a: ConstId, b: ConstId) -> bool {
        if a == b {
            return true;
        }
        match (self.candidate(a), self.candidate(b)) {
            (Some(a), Some(b)) => {
                let class = classes.class[a as usize];
                class != u32::MAX && class == classes.class[b as usize]
            }
            _ => false,
        }
    }

    fn candidate(&self, id: ConstId) -> Option<u32> {
        self.index.get(id.0 as usize).copied().filter(|&i| i != u32::MAX)
    }

    /// What a fact `head(args)` of this `kind` says of the candidates.
    fn mention(&mut self, kind: u8, head: u32, args: &[ConstId], task: &Task) -> Mention {
        let mut found: Vec<(usize, u32)> = Vec::new();
        let mut deep: Vec<u32> = Vec::new();
        let mut stack: Vec<ConstId> = Vec::new();
        for (position, &arg) in args.iter().enumerate() {
            if let Some(c) = self.candidate(arg) {
                found.push((position, c));
                continue;
            }
            stack.push(arg);
            while let Some(id) = stack.pop() {
                if let Some(c) = self.candidate(id) {
                    deep.push(c);
                } else if let Const::Compound(_, inner) = task.consts.get(id) {
                    stack.extend(inner.iter().copied());
                }
            }
        }
        match (found.as_slice(), deep.is_empty()) {
            ([], true) => Mention::None,
            (&[(position, c)], true) => {
                let mut holed: Box<[ConstId]> = args.into();
                holed[position] = HOLE;
                let next = self.templates.len() as u32;
                let template = *self.templates.entry(Template { kind, head, args: holed }).or_insert(next);
                Mention::One(c, template)
            }
            _ => Mention::Fixes(found.iter().map(|&(_, c)| c).chain(deep).collect()),
        }
    }

    fn fact_mention(&mut self, task: &Task, fact: FactId) -> &Mention {
        let at = fact.0 as usize;
        if self.facts.get(at).is_none_or(Option::is_none) {
            let pred = task.facts.pred_of(fact);
            let mention = self.mention(0, pred.0, task.facts.args(fact), task);
            if self.facts.len() <= at {
                self.facts.resize(at + 1, None);
            }
            self.facts[at] = Some(mention);
        }
        self.facts[at].as_ref().expect("set above")
    }

    fn running_mention(&mut self, task: &Task, running: ConstId) -> &Mention {
        if !self.running.contains_key(&running) {
            let mention = match task.consts.get(running) {
                Const::Compound(base, args) => {
                    let args = args.clone();
                    self.mention(1, base.0, &args, task)
                }
                _ => Mention::None,
            };
            self.running.insert(running, mention);
        }
        &self.running[&running]
    }

    /// The classes of interchangeable candidates in `state`.
    pub fn classes(&mut self, task: &Task, state: &crate::ir::task::State) -> Classes {
        let n = self.candidates.len();
        // (candidate, template) for every mention in the state, then sorted: each
        // candidate's state signature is one run.
        let mut pairs = std::mem::take(&mut self.pairs);
        pairs.clear();
        let mut alone = vec![false; n];
        let mut note = |mention: &Mention| match mention {
            Mention::None => {}
            Mention::One(c, template) => pairs.push((*c, *template)),
            Mention::Fixes(cs) => cs.iter().for_each(|&c| alone[c as usize] = true),
        };
        for fact in state.facts() {
            note(self.fact_mention(task, fact));
        }
        for &running in state.running.iter() {
            note(self.running_mention(task, running));
        }
        pairs.sort_unstable();
        let mut class = vec![u32::MAX; n];
        {
            let mut ids: FxHashMap<(u32, &[u32]), (u32, u32)> = FxHashMap::default();
            let mut templates: Vec<u32> = Vec::with_capacity(pairs.len());
            templates.extend(pairs.iter().map(|&(_, t)| t));
            let mut at = 0;
            for c in 0..n {
                let from = at;
                while at < pairs.len() && pairs[at].0 == c as u32 {
                    at += 1;
                }
                if alone[c] {
                    continue;
                }
                let key = (self.task_class[c], &templates[from..at]);
                let next = ids.len() as u32;
                let entry = ids.entry(key).or_insert((next, 0));
                entry.1 += 1;
                class[c] = entry.0;
            }
            // A class of one is no class.
            let mut size = vec![0u32; ids.len()];
            ids.values().for_each(|&(id, count)| size[id as usize] = count);
            class.iter_mut().filter(|k| **k != u32::MAX && size[**k as usize] < 2).for_each(|k| *k = u32::MAX);
        }
        self.pairs = pairs;
        Classes { class }
    }

    /// Which of `actions` to keep: one of each set that differ only by a permutation of
    /// candidates interchangeable in the state of `classes` (the least by `rank`, then the
    /// first), and every action that binds no interchangeable candidate. (An end's running
    /// action is named by its bindings, so it is permuted with them.)
    pub fn keep<K: Ord>(
        &self,
        classes: &Classes,
        actions: &[Applicable],
        mut rank: impl FnMut(usize) -> K,
    ) -> Vec<bool> {
        let mut keep = vec![true; actions.len()];
        if classes.class.iter().all(|&c| c == u32::MAX) {
            return keep;
        }
        // Per (schema, bindings up to the permutation): the best rank and its action.
        let mut best: FxHashMap<OrbitKey, (K, usize)> = FxHashMap::default();
        // The action's interchangeable candidates in order of first appearance, with their
        // classes: the key numbers each by its rank among those of its class.
        let mut seen: Vec<(u32, u32)> = Vec::new();
        let interchangeable = |value: &Option<ConstId>| {
            value.and_then(|id| self.candidate(id)).is_some_and(|c| classes.class[c as usize] != u32::MAX)
        };
        for (i, action) in actions.iter().enumerate() {
            if !action.bindings.iter().any(interchangeable) {
                continue;
            }
            seen.clear();
            let mut key: Vec<u64> = Vec::with_capacity(action.bindings.len());
            for value in action.bindings.iter() {
                let candidate = value.and_then(|id| self.candidate(id));
                let class = candidate.map_or(u32::MAX, |c| classes.class[c as usize]);
                let (Some(c), true) = (candidate, class != u32::MAX) else {
                    key.push(value.map_or(u64::MAX, |id| u64::from(id.0)));
                    continue;
                };
                let position = seen.iter().position(|&(_, other)| other == c).unwrap_or_else(|| {
                    seen.push((class, c));
                    seen.len() - 1
                });
                let order = seen[..position].iter().filter(|&&(k, _)| k == class).count() as u64;
                key.push((1 << 63) | (u64::from(class) << 32) | order);
            }
            let value = rank(i);
            match best.entry((action.schema, key.into_boxed_slice())) {
                std::collections::hash_map::Entry::Vacant(v) => {
                    v.insert((value, i));
                }
                std::collections::hash_map::Entry::Occupied(mut o) => {
                    if value < o.get().0 {
                        keep[o.get().1] = false;
                        o.insert((value, i));
                    } else {
                        keep[i] = false;
                    }
                }
            }
        }
        keep
    }
}
