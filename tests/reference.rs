//! A reference semantics for the planner: random KBs, an exhaustive breadth-first planner
//! written here from docs/dsl.md alone, and kbc held against it.
//!
//! The generator writes small KBs (a few fluents of arity 0-3, a few constants, instantaneous
//! actions and durative pairs whose ends take their start's values, `_` and variables in every
//! list, OnKB goals over static facts and `\=`, effects in any order, sometimes a
//! `resources/1` declaration) both as text for kbc and as values for the reference. The
//! reference shares no code with kbc: it has its own terms, matching, OnKB evaluation, states
//! and search. On every KB:
//!
//! - kbc refuses the KB (an error) only if the reference finds no plan either;
//! - when the reference has a plan, both of kbc's searches find one (unless a budget runs
//!   out), and no analysis calls a goal unreachable;
//! - when the reference proves there is none, kbc finds none;
//! - every plan kbc prints replays in the reference, and kbc's validator accepts it and the
//!   reference's plan.
//!
//! `cargo test` runs a thousand seeds; `KBC_REFERENCE_KBS=20000` runs more, and
//! `KBC_REFERENCE_SEED=N` one seed (its KB is printed on failure).

mod common;

use std::collections::{BTreeSet, HashSet, VecDeque};
use std::fmt::Write;
use std::time::{Duration, Instant};

use kbc::ir::hir;
use kbc::planner::{self, Budget, Failure, Options, SearchKind, Silent};
use kbc::session::{Frontend, PlanSettings, Session};
use kbc::source::SourceDb;
use kbc::source::fs::FsLoader;
use kbc::validate::{self, PlanStep};

// ---------------------------------------------------------------------------------------------
// The KB model, as the reference sees it.

/// The constants; the generator uses the first two or three. The last is the value kbc gives a
/// variable `V` of the initial state of its own (docs/dsl.md, "Problems"): it equals nothing
/// else.
const CONSTS: [&str; 4] = ["a", "b", "c", "'_V'"];
/// The index of `'_V'` in `CONSTS`.
const OWN_VALUE: usize = 3;

/// A term of a schema: a variable (by number), a constant (by index in `CONSTS`) or `_`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum T {
    Var(usize),
    Const(usize),
    Anon,
}

#[derive(Clone, Debug)]
struct Lit {
    pred: usize,
    args: Vec<T>,
}

#[derive(Clone, Debug)]
enum OnKb {
    /// A static fact `k<pred>(args)`.
    Static(usize, Vec<T>),
    /// `X \= Y`.
    Differ(T, T),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Snap {
    Instant,
    Start,
    End,
}

#[derive(Clone, Debug)]
struct Schema {
    /// The base name (`i0`, `d1`).
    base: String,
    snap: Snap,
    params: Vec<T>,
    valid: Vec<Lit>,
    invalid: Vec<Lit>,
    invalid_at_end: Vec<Lit>,
    on_kb: Vec<OnKb>,
    /// (add?, literal), in order.
    effects: Vec<(bool, Lit)>,
    vars: usize,
}

#[derive(Clone, Debug)]
struct Kb {
    /// Static predicates `k0/1`, `k1/2` and their facts.
    statics: Vec<Vec<Vec<usize>>>,
    schemas: Vec<Schema>,
    resources: Option<usize>,
    init: Vec<(usize, Vec<usize>)>,
    /// The goal's literals; `T::Var` are goal variables shared between literals.
    goal: Vec<Lit>,
    /// Places of the initial state (fact, argument) that hold the variable `V` instead of
    /// their constant (warning W0015); empty for most KBs.
    open: Vec<(usize, usize)>,
}

// ---------------------------------------------------------------------------------------------
// The generator.

/// xorshift64*: small, seeded, and the same everywhere.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }
}

fn generate(seed: u64) -> Kb {
    let mut rng = Rng::new(seed);
    let consts = 2 + rng.below(2);
    let fluents: Vec<usize> = (0..2 + rng.below(3)).map(|_| rng.below(4)).collect();
    let statics: Vec<Vec<Vec<usize>>> = (0..2)
        .map(|k| {
            let arity = k + 1;
            let mut facts: Vec<Vec<usize>> = Vec::new();
            for _ in 0..1 + rng.below(3) {
                let fact: Vec<usize> = (0..arity).map(|_| rng.below(consts)).collect();
                if !facts.contains(&fact) {
                    facts.push(fact);
                }
            }
            facts
        })
        .collect();
    let random_lit = |rng: &mut Rng, vars: usize, bound: Option<&[usize]>, anon: bool| -> Lit {
        let pred = rng.below(fluents.len());
        let args = (0..fluents[pred])
            .map(|_| match rng.below(10) {
                0..=2 => T::Const(rng.below(consts)),
                3 if anon => T::Anon,
                _ => match bound {
                    Some(bound) if !bound.is_empty() => T::Var(bound[rng.below(bound.len())]),
                    Some(_) => T::Const(rng.below(consts)),
                    None => T::Var(rng.below(vars)),
                },
            })
            .collect();
        Lit { pred, args }
    };
    let mut schemas = Vec::new();
    let count = 2 + rng.below(4);
    let mut index = 0;
    while schemas.len() < count {
        let durative = rng.chance(45);
        let vars = 1 + rng.below(3);
        let base = if durative { format!("d{index}") } else { format!("i{index}") };
        index += 1;
        let mut start = blank(&base, if durative { Snap::Start } else { Snap::Instant }, vars);
        fill(&mut rng, &mut start, &random_lit, consts, statics.len(), None);
        schemas.push(start.clone());
        if durative {
            let end_vars = start.params.len() + rng.below(2);
            let mut end = blank(&base, Snap::End, end_vars.max(1));
            // The end's name has the start's arity; its arguments are its own variables
            // (bound from the running start), now and then a constant.
            end.params = (0..start.params.len())
                .map(|i| if rng.chance(10) { T::Const(rng.below(consts)) } else { T::Var(i) })
                .collect();
            let name = end.params.clone();
            fill(&mut rng, &mut end, &random_lit, consts, statics.len(), Some(&name));
            schemas.push(end);
        }
    }
    let resources = if rng.chance(25) { fluents.iter().position(|&a| a == 1) } else { None };
    let mut init: Vec<(usize, Vec<usize>)> = Vec::new();
    for _ in 0..1 + rng.below(4) {
        let pred = rng.below(fluents.len());
        let fact = (pred, (0..fluents[pred]).map(|_| rng.below(consts)).collect());
        if !init.contains(&fact) {
            init.push(fact);
        }
    }
    // Goals mostly ask for an instance of what some action adds, and for something the
    // initial state does not already have, so that most problems are worth planning.
    let added: Vec<Lit> = schemas
        .iter()
        .flat_map(|s: &Schema| s.effects.iter().filter(|(add, _)| *add).map(|(_, l)| l.clone()))
        .collect();
    let mut goal: Vec<Lit> = Vec::new();
    // Often, a fact a random walk from the initial state reaches (ending its durative actions
    // is left to the planner): such goals are reachable ignoring the running actions.
    if rng.chance(60) {
        let mut kb = Kb {
            statics: statics.clone(),
            schemas: schemas.clone(),
            resources,
            init: init.clone(),
            goal: Vec::new(),
            open: Vec::new(),
        };
        let mut state = initial(&kb);
        for _ in 0..1 + rng.below(6) {
            let next = successors(&kb, &state);
            if next.is_empty() {
                break;
            }
            state = next[rng.below(next.len())].1.clone();
        }
        let new: Vec<&Fact> = state.facts.iter().filter(|f| !kb.init.contains(f)).collect();
        if !new.is_empty() {
            let (pred, args) = new[rng.below(new.len())].clone();
            let args = args.iter().map(|&c| if rng.chance(10) { T::Anon } else { T::Const(c) }).collect();
            kb.goal = vec![Lit { pred, args }];
            return kb;
        }
    }
    for _attempt in 0..10 {
        goal = (0..1 + rng.below(2))
            .map(|_| {
                if !added.is_empty() && rng.chance(80) {
                    let effect = &added[rng.below(added.len())];
                    let args = effect
                        .args
                        .iter()
                        .map(|t| match t {
                            T::Const(c) => T::Const(*c),
                            _ if rng.chance(10) => T::Anon,
                            _ => T::Const(rng.below(consts)),
                        })
                        .collect();
                    return Lit { pred: effect.pred, args };
                }
                let pred = rng.below(fluents.len());
                let args = (0..fluents[pred])
                    .map(|_| match rng.below(10) {
                        0 => T::Anon,
                        1 => T::Var(0),
                        _ => T::Const(rng.below(consts)),
                    })
                    .collect();
                Lit { pred, args }
            })
            .collect();
        let start = State { facts: init.iter().cloned().collect(), running: BTreeSet::new() };
        let probe = Kb {
            statics: Vec::new(),
            schemas: Vec::new(),
            resources: None,
            init: Vec::new(),
            goal: goal.clone(),
            open: Vec::new(),
        };
        if !goal_holds(&probe, &start) {
            break;
        }
    }
    Kb { statics, schemas, resources, init, goal, open: Vec::new() }
}

fn blank(base: &str, snap: Snap, vars: usize) -> Schema {
    Schema {
        base: base.to_string(),
        snap,
        params: Vec::new(),
        valid: Vec::new(),
        invalid: Vec::new(),
        invalid_at_end: Vec::new(),
        on_kb: Vec::new(),
        effects: Vec::new(),
        vars,
    }
}

type LitMaker<'a> = dyn Fn(&mut Rng, usize, Option<&[usize]>, bool) -> Lit + 'a;

/// Fills a schema's lists; `name` is an end's name (its variables are bound by the start).
fn fill(rng: &mut Rng, schema: &mut Schema, lit: &LitMaker<'_>, consts: usize, statics: usize, name: Option<&[T]>) {
    let vars = schema.vars;
    let mut bound: Vec<usize> = Vec::new();
    if let Some(name) = name {
        for t in name {
            if let T::Var(v) = t
                && !bound.contains(v)
            {
                bound.push(*v);
            }
        }
    }
    for _ in 0..rng.below(3) {
        let l = lit(rng, vars, None, true);
        for t in &l.args {
            if let T::Var(v) = t
                && !bound.contains(v)
            {
                bound.push(*v);
            }
        }
        schema.valid.push(l);
    }
    for _ in 0..rng.below(3) {
        if rng.chance(50) {
            let arity = 1 + rng.below(statics);
            let args: Vec<T> = (0..arity)
                .map(|_| if rng.chance(20) { T::Const(rng.below(consts)) } else { T::Var(rng.below(vars)) })
                .collect();
            for t in &args {
                if let T::Var(v) = t
                    && !bound.contains(v)
                {
                    bound.push(*v);
                }
            }
            schema.on_kb.push(OnKb::Static(arity - 1, args));
        } else {
            let pick =
                |rng: &mut Rng| if rng.chance(25) { T::Const(rng.below(consts)) } else { T::Var(rng.below(vars)) };
            let (x, y) = (pick(rng), pick(rng));
            schema.on_kb.push(OnKb::Differ(x, y));
        }
    }
    if rng.chance(35) {
        schema.invalid.push(lit(rng, vars, None, true));
    }
    if rng.chance(15) {
        schema.invalid_at_end.push(lit(rng, vars, Some(&bound), true));
    }
    for _ in 0..1 + rng.below(3) {
        let add = rng.chance(60);
        // A deletion may leave a variable open (`_`): it removes every fact that unifies.
        schema.effects.push((add, lit(rng, vars, Some(&bound), !add)));
    }
    if name.is_none() {
        // A start's or an instant's name: bound variables only, so it is ground when it applies.
        let mut params: Vec<T> = Vec::new();
        for _ in 0..rng.below(3) {
            if bound.is_empty() {
                break;
            }
            params.push(T::Var(bound[rng.below(bound.len())]));
        }
        schema.params = params;
    }
}

// ---------------------------------------------------------------------------------------------
// The KB as text.

fn show_t(t: &T) -> String {
    match t {
        T::Var(v) => format!("V{v}"),
        T::Const(c) => CONSTS[*c].to_string(),
        T::Anon => "_".to_string(),
    }
}

fn show_lit(l: &Lit) -> String {
    if l.args.is_empty() {
        format!("f{}", l.pred)
    } else {
        format!("f{}({})", l.pred, l.args.iter().map(show_t).collect::<Vec<_>>().join(", "))
    }
}

fn show_name(s: &Schema) -> String {
    let name = match s.snap {
        Snap::Instant => s.base.clone(),
        Snap::Start => format!("{}_start", s.base),
        Snap::End => format!("{}_end", s.base),
    };
    if s.params.is_empty() {
        name
    } else {
        format!("{name}({})", s.params.iter().map(show_t).collect::<Vec<_>>().join(", "))
    }
}

fn kb_text(kb: &Kb) -> String {
    let mut out = String::new();
    if let Some(r) = kb.resources {
        let _ = writeln!(out, "resources(f{r}(_)).");
    }
    for (k, facts) in kb.statics.iter().enumerate() {
        for fact in facts {
            let args: Vec<&str> = fact.iter().map(|&c| CONSTS[c]).collect();
            let _ = writeln!(out, "k{k}({}).", args.join(", "));
        }
    }
    for s in &kb.schemas {
        let list = |ls: &[Lit]| ls.iter().map(show_lit).collect::<Vec<_>>().join(", ");
        let on_kb: Vec<String> = s
            .on_kb
            .iter()
            .map(|g| match g {
                OnKb::Static(k, args) => format!("k{k}({})", args.iter().map(show_t).collect::<Vec<_>>().join(", ")),
                OnKb::Differ(x, y) => format!("{} \\= {}", show_t(x), show_t(y)),
            })
            .collect();
        let effects: Vec<String> =
            s.effects.iter().map(|(add, l)| format!("{}({})", if *add { "add" } else { "del" }, show_lit(l))).collect();
        let _ = writeln!(
            out,
            "action({}, [{}], [{}], [{}], [{}], [{}]).",
            show_name(s),
            list(&s.valid),
            list(&s.invalid),
            list(&s.invalid_at_end),
            on_kb.join(", "),
            effects.join(", ")
        );
    }
    let init: Vec<String> = kb
        .init
        .iter()
        .enumerate()
        .map(|(f, (p, args))| {
            let shown: Vec<String> = args
                .iter()
                .enumerate()
                .map(|(a, &c)| if kb.open.contains(&(f, a)) { "V".to_string() } else { CONSTS[c].to_string() })
                .collect();
            if shown.is_empty() { format!("f{p}") } else { format!("f{p}({})", shown.join(", ")) }
        })
        .collect();
    let goal: Vec<String> = kb.goal.iter().map(show_lit).collect();
    let _ = writeln!(out, "prob :- go([{}], [{}]).", init.join(", "), goal.join(", "));
    out
}

// ---------------------------------------------------------------------------------------------
// The reference semantics (docs/dsl.md, "Action schemas", "Problems", "Planning").

/// A ground fact: predicate and constants.
type Fact = (usize, Vec<usize>);
/// A running durative action: base index into the KB's schemas (its start) and arguments.
type Running = (String, Vec<usize>);

#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct State {
    facts: BTreeSet<Fact>,
    running: BTreeSet<Running>,
}

type Env = Vec<Option<usize>>;

/// Unifies a schema term with a constant under `env`.
fn bind(t: &T, value: usize, env: &mut Env) -> bool {
    match t {
        T::Anon => true,
        T::Const(c) => *c == value,
        T::Var(v) => match env[*v] {
            Some(b) => b == value,
            None => {
                env[*v] = Some(value);
                true
            }
        },
    }
}

fn match_fact(l: &Lit, fact: &Fact, env: &mut Env) -> bool {
    l.pred == fact.0 && l.args.len() == fact.1.len() && l.args.iter().zip(&fact.1).all(|(t, &v)| bind(t, v, env))
}

fn value(t: &T, env: &Env) -> Option<usize> {
    match t {
        T::Const(c) => Some(*c),
        T::Var(v) => env[*v],
        T::Anon => None,
    }
}

/// Every way of proving the OnKB goals from `i` on, Prolog's order, each a completed `env`.
fn prove(kb: &Kb, goals: &[OnKb], env: &Env, out: &mut Vec<Env>) {
    let Some((first, rest)) = goals.split_first() else {
        out.push(env.clone());
        return;
    };
    match first {
        OnKb::Static(k, args) => {
            for fact in &kb.statics[*k] {
                let mut e = env.clone();
                if args.iter().zip(fact).all(|(t, &v)| bind(t, v, &mut e)) {
                    prove(kb, rest, &e, out);
                }
            }
        }
        OnKb::Differ(x, y) => {
            // `X \= Y` succeeds when X and Y do not unify; an unbound variable unifies.
            let differ = matches!((value(x, env), value(y, env)), (Some(a), Some(b)) if a != b);
            if differ {
                prove(kb, rest, env, out);
            }
        }
    }
}

/// A goal literal and an InvalidAtEnd literal unify (goal variables are the goal's own).
fn unify_with_goal(forbidden: &Lit, env: &Env, goal: &[Lit]) -> bool {
    goal.iter().any(|g| {
        g.pred == forbidden.pred && {
            // Bindings of the goal's variables (shared between its literals, but one literal
            // at a time is enough here: the check is per literal).
            let mut goal_env: Vec<Option<usize>> = vec![None; 4];
            let mut own: Env = env.clone();
            g.args.iter().zip(&forbidden.args).all(|(gt, ft)| {
                let f = match ft {
                    T::Var(v) => own[*v],
                    T::Const(c) => Some(*c),
                    T::Anon => None,
                };
                let gv = match gt {
                    T::Var(v) => goal_env[*v],
                    T::Const(c) => Some(*c),
                    T::Anon => None,
                };
                match (f, gv) {
                    (Some(a), Some(b)) => a == b,
                    (Some(a), None) => {
                        if let T::Var(v) = gt {
                            goal_env[*v] = Some(a);
                        }
                        true
                    }
                    (None, Some(b)) => {
                        if let T::Var(v) = ft {
                            own[*v] = Some(b);
                        }
                        true
                    }
                    // Two unbound variables unify (their later occurrences are not tracked
                    // against each other; the generator's literals rarely repeat one).
                    (None, None) => true,
                }
            })
        }
    })
}

/// A successor: the action's ground name and the state it leads to.
fn successors(kb: &Kb, state: &State) -> Vec<(String, State)> {
    let mut out = Vec::new();
    for s in &kb.schemas {
        let mut starts: Vec<(Env, Option<Running>)> = Vec::new();
        if s.snap == Snap::End {
            for r in &state.running {
                if r.0 != s.base || r.1.len() != s.params.len() {
                    continue;
                }
                let mut env = vec![None; s.vars];
                if s.params.iter().zip(&r.1).all(|(t, &v)| bind(t, v, &mut env)) {
                    starts.push((env, Some(r.clone())));
                }
            }
        } else {
            starts.push((vec![None; s.vars], None));
        }
        for (env, ends) in starts {
            let mut valid = Vec::new();
            valid_from(s, 0, state, &env, &mut valid);
            for env in valid {
                let mut proven = Vec::new();
                prove(kb, &s.on_kb, &env, &mut proven);
                for env in proven {
                    if let Some(next) = finish(kb, s, state, &env, ends.as_ref()) {
                        out.push(next);
                    }
                }
            }
        }
    }
    out
}

fn valid_from(s: &Schema, i: usize, state: &State, env: &Env, out: &mut Vec<Env>) {
    let Some(l) = s.valid.get(i) else {
        out.push(env.clone());
        return;
    };
    for fact in &state.facts {
        let mut e = env.clone();
        if match_fact(l, fact, &mut e) {
            valid_from(s, i + 1, state, &e, out);
        }
    }
}

fn finish(kb: &Kb, s: &Schema, state: &State, env: &Env, ends: Option<&Running>) -> Option<(String, State)> {
    let params: Vec<usize> = s.params.iter().map(|t| value(t, env)).collect::<Option<_>>()?;
    // Added facts must be ground; a deletion removes every fact that unifies with it.
    let mut effects: Vec<(bool, Lit)> = Vec::new();
    for (add, l) in &s.effects {
        let args: Vec<T> = l
            .args
            .iter()
            .map(|t| match value(t, env) {
                Some(c) => Some(T::Const(c)),
                None if *add => None,
                None => Some(T::Anon),
            })
            .collect::<Option<_>>()?;
        effects.push((*add, Lit { pred: l.pred, args }));
    }
    if s.snap == Snap::Start && state.running.contains(&(s.base.clone(), params.clone())) {
        return None; // no self-overlap
    }
    for l in &s.invalid {
        if state.facts.iter().any(|f| match_fact(l, f, &mut env.clone())) {
            return None;
        }
    }
    for l in &s.invalid_at_end {
        if unify_with_goal(l, env, &kb.goal) {
            return None;
        }
    }
    let mut next = state.clone();
    for (add, l) in effects {
        if add {
            let args = l.args.iter().map(|t| if let T::Const(c) = t { *c } else { unreachable!("ground") }).collect();
            next.facts.insert((l.pred, args));
        } else {
            next.facts.retain(|f| !match_fact(&l, f, &mut vec![None; s.vars]));
        }
    }
    match s.snap {
        Snap::Start => {
            next.running.insert((s.base.clone(), params.clone()));
        }
        Snap::End => {
            next.running.remove(ends.expect("an end closes a start"));
        }
        Snap::Instant => {}
    }
    let mut shown = show_name(&Schema { params: params.iter().map(|&c| T::Const(c)).collect(), ..s.clone() });
    shown.retain(|c| c != ' ');
    Some((shown, next))
}

fn goal_holds(kb: &Kb, state: &State) -> bool {
    fn from(goal: &[Lit], state: &State, env: &Env) -> bool {
        let Some((first, rest)) = goal.split_first() else { return true };
        state.facts.iter().any(|f| {
            let mut e = env.clone();
            match_fact(first, f, &mut e) && from(rest, state, &e)
        })
    }
    state.running.is_empty() && from(&kb.goal, state, &vec![None; 4])
}

fn initial(kb: &Kb) -> State {
    State { facts: kb.init.iter().cloned().collect(), running: BTreeSet::new() }
}

enum Reference {
    /// A shortest plan.
    Plan(Vec<String>),
    /// Every reachable state was visited.
    Unsolvable,
    /// Too many states to tell.
    Unknown,
}

fn reference_plan(kb: &Kb, max_states: usize) -> Reference {
    let start = initial(kb);
    let mut parents: Vec<(usize, String)> = vec![(usize::MAX, String::new())];
    let mut states: Vec<State> = vec![start.clone()];
    let mut seen: HashSet<State> = HashSet::from([start]);
    let mut queue = VecDeque::from([0usize]);
    while let Some(at) = queue.pop_front() {
        if goal_holds(kb, &states[at]) {
            let mut plan = Vec::new();
            let mut i = at;
            while parents[i].0 != usize::MAX {
                plan.push(parents[i].1.clone());
                i = parents[i].0;
            }
            plan.reverse();
            return Reference::Plan(plan);
        }
        for (name, next) in successors(kb, &states[at].clone()) {
            if seen.insert(next.clone()) {
                if states.len() >= max_states {
                    return Reference::Unknown;
                }
                states.push(next);
                parents.push((at, name));
                queue.push_back(states.len() - 1);
            }
        }
    }
    Reference::Unsolvable
}

/// Replays named steps: some way of applying them must reach the goal.
fn reference_accepts(kb: &Kb, steps: &[String]) -> bool {
    let mut states: BTreeSet<State> = BTreeSet::from([initial(kb)]);
    for step in steps {
        let wanted: String = step.chars().filter(|c| *c != ' ').collect();
        states = states
            .iter()
            .flat_map(|s| successors(kb, s))
            .filter(|(name, _)| *name == wanted)
            .map(|(_, next)| next)
            .collect();
        if states.is_empty() {
            return false;
        }
    }
    states.iter().any(|s| goal_holds(kb, s))
}

/// `kb` with its open places (the variable `V`) given `value`.
fn grounded(kb: &Kb, value: usize) -> Kb {
    let mut ground = kb.clone();
    for &(fact, arg) in &kb.open {
        ground.init[fact].1[arg] = value;
    }
    ground.open.clear();
    ground
}

/// The values `V` may take: its own, then every constant (docs/dsl.md, "Problems"; kbc tries
/// only the constants the KB writes, but one it does not write behaves as `V`'s own value).
fn values_of_v(kb: &Kb) -> Vec<usize> {
    if kb.open.is_empty() { vec![0] } else { std::iter::once(OWN_VALUE).chain(0..OWN_VALUE).collect() }
}

/// The reference plan of a KB whose initial state may have the variable `V`: a plan for some
/// value of it.
fn reference_plan_open(kb: &Kb, max_states: usize) -> Reference {
    let mut unknown = false;
    for value in values_of_v(kb) {
        match reference_plan(&grounded(kb, value), max_states) {
            Reference::Plan(plan) => return Reference::Plan(plan),
            Reference::Unknown => unknown = true,
            Reference::Unsolvable => {}
        }
    }
    if unknown { Reference::Unknown } else { Reference::Unsolvable }
}

/// True if the steps reach the goal for some value of `V`.
fn reference_accepts_open(kb: &Kb, steps: &[String]) -> bool {
    values_of_v(kb).into_iter().any(|value| reference_accepts(&grounded(kb, value), steps))
}

// ---------------------------------------------------------------------------------------------
// kbc against the reference.

#[derive(Default, Debug)]
struct Counts {
    kbs: usize,
    refused: usize,
    solvable: usize,
    unsolvable: usize,
    unknown: usize,
    budget: usize,
    /// KBs with an end whose effect uses a name variable its Valid list does not bind.
    end_takes_start: usize,
}

/// True if some end adds a fact with a variable only its name (so its start) binds.
fn end_takes_start(kb: &Kb) -> bool {
    kb.schemas.iter().filter(|s| s.snap == Snap::End).any(|s| {
        s.params.iter().any(|p| {
            matches!(p, T::Var(_))
                && !s.valid.iter().any(|l| l.args.contains(p))
                && s.effects.iter().any(|(add, l)| *add && l.args.contains(p))
        })
    })
}

/// Counts the reference's verdict and, when it has a plan, has kbc's validator check that plan
/// (`validate` gets the plan file's text and the step names).
fn tally(
    reference: &Reference,
    counts: &mut Counts,
    validate: impl FnOnce(String, &[String]) -> Result<(), String>,
) -> Result<(), String> {
    match reference {
        Reference::Plan(plan) => {
            counts.solvable += 1;
            validate(plan.iter().map(|n| format!("{n}\n")).collect(), plan)
        }
        Reference::Unsolvable => {
            counts.unsolvable += 1;
            Ok(())
        }
        Reference::Unknown => {
            counts.unknown += 1;
            Ok(())
        }
    }
}

/// Checks one seed; `Err` describes a disagreement.
fn check(seed: u64, counts: &mut Counts) -> Result<(), String> {
    let kb = generate(seed);
    let text = kb_text(&kb);
    counts.kbs += 1;
    counts.end_takes_start += usize::from(end_takes_start(&kb));
    let reference = reference_plan(&kb, 20_000);
    let mut db = SourceDb::new();
    let root = db.add(format!("seed{seed}.pl"), None, text.clone());
    let (_, frontend, diagnostics) = kbc::session::Session::open(db, &[root], &mut FsLoader).into_parts();
    let context = |what: String| format!("seed {seed}: {what}\n{text}");
    if diagnostics.has_errors() {
        counts.refused += 1;
        if let Reference::Plan(plan) = &reference {
            let messages = common::messages(&diagnostics);
            return Err(context(format!("kbc refuses a KB the reference plans ({plan:?}): {messages:?}")));
        }
        return Ok(());
    }
    let problem = 0;
    let program = planner::program_for(&frontend.kb, &frontend.interner, problem);
    let validate_text = |plan_text: String, names: &[String]| -> Result<(), String> {
        let mut interner = frontend.interner.clone();
        let mut db = SourceDb::new();
        let file = db.add("plan.txt", None, plan_text.clone());
        let mut diags = kbc::diag::Diagnostics::new();
        let steps: Vec<PlanStep> = validate::read_plan(file, &plan_text, &mut interner, &mut diags);
        if diags.has_errors() {
            return Err(format!("kbc cannot read the plan {names:?}: {:?}", common::messages(&diags)));
        }
        let verdict = validate::validate(&frontend.kb, &interner, &program, problem, &steps);
        if verdict.diagnostics.has_errors() {
            return Err(format!("kbc validate rejects {names:?}: {:?}", common::messages(&verdict.diagnostics)));
        }
        Ok(())
    };
    tally(&reference, counts, validate_text).map_err(&context)?;
    for search in [SearchKind::Heuristic, SearchKind::Paper] {
        let mut task = kbc::passes::task::build(&frontend.kb, problem);
        let budget = Budget {
            max_states: 200_000,
            deadline: Some(Instant::now() + Duration::from_secs(10)),
            ..Budget::default()
        };
        let max_depth = match &reference {
            Reference::Plan(plan) => Some((plan.len() as u32).max(12)),
            _ => Some(12),
        };
        let options = Options { search, max_depth, budget, plans: 1, improve: None, ..Options::default() };
        let outcome = planner::search(&frontend.kb, &frontend.interner, &mut task, &options, &mut Silent);
        match (outcome.result, &reference) {
            (Ok(plan), _) => {
                let names: Vec<String> = plan
                    .steps
                    .iter()
                    .map(|s| hir::term_to_string(&frontend.interner, &s.name, &hir::VarTable::default()))
                    .collect();
                if !reference_accepts(&kb, &names) {
                    return Err(context(format!("{search:?} search plan {names:?} is not valid in the reference")));
                }
                // As `kbc plan` prints it (with `% with` values) and kbc validate reads it.
                let printed = kbc::ir::plan::print(&frontend.interner, &frontend.kb, &plan);
                validate_text(printed, &names).map_err(&context)?;
            }
            (Err(Failure::Budget(_)), _) => counts.budget += 1,
            (Err(failure), Reference::Plan(plan)) => {
                let failure = match failure {
                    Failure::Unsolvable(d) => {
                        format!("{}: {}", d.code.map(|c| c.to_string()).unwrap_or_default(), d.message)
                    }
                    other => format!("{other:?}"),
                };
                return Err(context(format!(
                    "{search:?} search finds no plan ({failure}); the reference has {plan:?}"
                )));
            }
            (Err(_), _) => {}
        }
    }
    Ok(())
}

/// The KB of `seed` with the variable `V` in place of one or two constants of its initial
/// state; `None` when no initial fact has an argument. The places come from a second stream of
/// random numbers, so the KB is otherwise the one `check` tests.
fn with_open_init(seed: u64) -> Option<Kb> {
    let mut kb = generate(seed);
    let mut rng = Rng::new(seed ^ 0x0be1_17a1);
    let places: Vec<(usize, usize)> =
        kb.init.iter().enumerate().flat_map(|(f, (_, args))| (0..args.len()).map(move |a| (f, a))).collect();
    if places.is_empty() {
        return None;
    }
    kb.open.push(places[rng.below(places.len())]);
    let second = places[rng.below(places.len())];
    if rng.chance(30) && !kb.open.contains(&second) {
        kb.open.push(second);
    }
    Some(kb)
}

/// Checks the KB of `seed` with a variable in its initial state, through the session (which
/// tries the variable's values) as `kbc plan` and `kbc validate` run it.
fn check_open_init(seed: u64, counts: &mut Counts) -> Result<(), String> {
    let Some(kb) = with_open_init(seed) else { return Ok(()) };
    let text = kb_text(&kb);
    counts.kbs += 1;
    let reference = reference_plan_open(&kb, 20_000);
    let context = |what: String| format!("seed {seed} (open init): {what}\n{text}");
    let mut session = Session::from_text(&format!("seed{seed}.pl"), text.clone());
    if session.has_errors() {
        counts.refused += 1;
        if let Reference::Plan(plan) = &reference {
            let messages = common::messages(session.diagnostics());
            return Err(context(format!("kbc refuses a KB the reference plans ({plan:?}): {messages:?}")));
        }
        return Ok(());
    }
    let validate_text = |session: &mut Session, plan_text: String, names: &[String]| -> Result<(), String> {
        let file = session.add_text("plan.txt", plan_text);
        let steps = session.read_plan_steps(file).ok_or_else(|| format!("kbc cannot read the plan {names:?}"))?;
        let verdict = session.validate(0, &steps);
        if verdict.diagnostics.has_errors() {
            return Err(format!("kbc validate rejects {names:?}: {:?}", common::messages(&verdict.diagnostics)));
        }
        Ok(())
    };
    tally(&reference, counts, |text, names| validate_text(&mut session, text, names)).map_err(&context)?;
    for search in [SearchKind::Heuristic, SearchKind::Paper] {
        let max_depth = match &reference {
            Reference::Plan(plan) => Some((plan.len() as u32).max(12)),
            _ => Some(12),
        };
        let settings = PlanSettings {
            search,
            max_depth,
            max_states: 200_000,
            timeout: Some(Duration::from_secs(10)),
            ..PlanSettings::default()
        };
        match (session.search(0, &settings, &mut Silent), &reference) {
            (Ok(found), _) => {
                let plan = found.plans[0].clone();
                let (kb_hir, interner) = (session.kb(), session.interner());
                let names: Vec<String> = plan
                    .steps
                    .iter()
                    .map(|s| hir::term_to_string(interner, &s.name, &hir::VarTable::default()))
                    .collect();
                if !reference_accepts_open(&kb, &names) {
                    return Err(context(format!("{search:?} search plan {names:?} is not valid in the reference")));
                }
                let printed = kbc::ir::plan::print(interner, kb_hir, &plan);
                validate_text(&mut session, printed, &names).map_err(&context)?;
            }
            (Err(failed), _) if matches!(failed.failure, Failure::Budget(_)) => counts.budget += 1,
            (Err(failed), Reference::Plan(plan)) => {
                return Err(context(format!(
                    "{search:?} search finds no plan ({:?}); the reference has {plan:?}",
                    failed.failure
                )));
            }
            (Err(_), _) => {}
        }
    }
    Ok(())
}

#[test]
fn kbc_agrees_with_the_reference_on_kbs_with_a_variable_in_the_initial_state() {
    let count = std::env::var("KBC_REFERENCE_KBS").ok().and_then(|n| n.parse().ok()).unwrap_or(300u64);
    let mut counts = Counts::default();
    let mut failures = Vec::new();
    for seed in 1..=count {
        if let Err(message) = check_open_init(seed, &mut counts) {
            failures.push(message);
        }
    }
    eprintln!("{counts:?}");
    assert!(counts.solvable * 8 > counts.kbs, "too few solvable KBs: {counts:?}");
    assert!(
        failures.is_empty(),
        "{} of {} KBs disagree with the reference:\n\n{}",
        failures.len(),
        counts.kbs,
        failures.iter().take(5).cloned().collect::<Vec<_>>().join("\n\n")
    );
}

#[test]
fn kbc_agrees_with_the_reference_planner_on_random_kbs() {
    let (first, count) = match std::env::var("KBC_REFERENCE_SEED") {
        Ok(seed) => (seed.parse::<u64>().expect("a seed"), 1),
        Err(_) => (1, std::env::var("KBC_REFERENCE_KBS").ok().and_then(|n| n.parse().ok()).unwrap_or(1000u64)),
    };
    let mut counts = Counts::default();
    let mut failures = Vec::new();
    for seed in first..first + count {
        if let Err(message) = check(seed, &mut counts) {
            failures.push(message);
        }
    }
    eprintln!("{counts:?}");
    // The generator must exercise both outcomes, or the test says little.
    assert!(counts.solvable * 8 > counts.kbs, "too few solvable KBs: {counts:?}");
    assert!(counts.unsolvable > 0 || count < 50, "no unsolvable KB: {counts:?}");
    assert!(
        failures.is_empty(),
        "{} of {} KBs disagree with the reference:\n\n{}",
        failures.len(),
        counts.kbs,
        failures.iter().take(5).cloned().collect::<Vec<_>>().join("\n\n")
    );
}

/// Seeds that once disagreed, run on every `cargo test` whatever the count.
const REGRESSION_SEEDS: &[u64] = &[
    13361, // a plan whose steps leave variables out of their names: too ambiguous to replay
];

#[test]
fn seeds_that_once_disagreed_agree() {
    let mut counts = Counts::default();
    for &seed in REGRESSION_SEEDS {
        check(seed, &mut counts).unwrap_or_else(|message| panic!("{message}"));
    }
}

/// Plans `text`'s only problem with `search`; the plan as `kbc plan` prints it, or why not.
fn plan_of(text: &str, search: SearchKind) -> Result<(Vec<String>, String), String> {
    let mut db = SourceDb::new();
    let root = db.add("case.pl", None, text.to_string());
    let (_, frontend, diagnostics) = kbc::session::Session::open(db, &[root], &mut FsLoader).into_parts();
    if diagnostics.has_errors() {
        return Err(format!("refused: {:?}", common::messages(&diagnostics)));
    }
    let mut task = kbc::passes::task::build(&frontend.kb, 0);
    let options = Options { search, ..Options::default() };
    let outcome = planner::search(&frontend.kb, &frontend.interner, &mut task, &options, &mut Silent);
    let plan = outcome.result.map_err(|failure| match failure {
        Failure::Unsolvable(d) => d.message,
        other => format!("{other:?}"),
    })?;
    let names = plan
        .steps
        .iter()
        .map(|s| hir::term_to_string(&frontend.interner, &s.name, &hir::VarTable::default()))
        .collect();
    let printed = kbc::ir::plan::print(&frontend.interner, &frontend.kb, &plan);
    // kbc validate reads what kbc plan prints.
    let mut interner = frontend.interner.clone();
    let mut db = SourceDb::new();
    let file = db.add("plan.txt", None, printed.clone());
    let mut diags = kbc::diag::Diagnostics::new();
    let steps = validate::read_plan(file, &printed, &mut interner, &mut diags);
    let program = planner::program_for(&frontend.kb, &frontend.interner, 0);
    let verdict = validate::validate(&frontend.kb, &interner, &program, 0, &steps);
    if diags.has_errors() || verdict.diagnostics.has_errors() {
        return Err(format!(
            "kbc validate rejects its own plan:\n{printed}{:?}",
            common::messages(&verdict.diagnostics)
        ));
    }
    Ok((names, printed))
}

/// The minimal KBs of the disagreements the first random-KB tester found (issue 19), each with
/// the plan both searches must find.
#[test]
fn the_minimal_disagreements_plan() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "an end takes a variable its start bound",
            "thing(a). thing(b).
             action(p_start(X), [idle], [], [], [thing(X)], [del(idle), add(busy)]).
             action(p_end(X), [busy], [], [], [], [del(busy), add(idle), add(done(X))]).
             t1 :- go([idle], [idle, done(b)]).",
            &["p_start(b)", "p_end(b)"],
        ),
        (
            "a resource unit read by a Valid literal and added by name",
            "resources(p(_)).
             action(i(A), [p(A)], [], [], [], [add(r(A))]).
             prob :- go([p(b)], [r(b)]).",
            &["i(b)"],
        ),
        (
            "two unit variables, one of them added",
            "resources(q(_)).
             action(ia(A, B), [q(A), q(B)], [], [], [], [add(p(B))]).
             prob :- go([q(b)], [p(b)]).",
            &["ia(b, b)"],
        ),
        (
            "a unit an action creates",
            "resources(p(_)). k(b).
             action(mk(A), [], [], [], [k(A)], [add(p(A))]).
             prob :- go([], [p(b)]).",
            &["mk(b)"],
        ),
        (
            "a goal literal and its generalisation",
            "k1(b, b).
             action(ia(A, B), [q(A, C)], [], [], [k1(B, B)], [del(q(A, C)), add(q(A, B))]).
             prob :- go([q(a, a)], [q(a, b), q(a, _)]).",
            &["ia(a, b)"],
        ),
        (
            "a start of a running action does not apply again",
            "action(t_start(A), [q(A)], [], [], [], [add(s)]).
             action(t_end(A), [f], [], [], [], [add(g), del(s)]).
             action(i, [s], [], [], [], [del(s), add(f)]).
             prob :- go([q(a)], [g]).",
            &["t_start(a)", "i", "t_end(a)"],
        ),
        (
            "a variable the name leaves out",
            "action(i, [q(C)], [], [], [], [add(r(C))]).
             prob :- go([q(a), q(b)], [r(b)]).",
            &["i"],
        ),
    ];
    for (what, text, expected) in cases {
        let (heuristic, printed) = plan_of(text, SearchKind::Heuristic).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(heuristic, *expected, "{what}: heuristic search");
        let (paper, _) = plan_of(text, SearchKind::Paper).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!(paper.len() >= expected.len(), "{what}: the paper's search {paper:?}");
        if *what == "a variable the name leaves out" {
            assert!(printed.contains("i  % with C = b"), "{what}: the hidden value is printed:\n{printed}");
        }
    }
}

/// Runs `swipl` on `goal` with a wall-clock limit (the child is killed beyond it); its
/// standard output, or `None` if it failed or ran out of time.
fn swipl(goal: &str, limit: Duration) -> Option<String> {
    use std::io::Read;
    use std::process::{Command, Stdio};
    let mut child = Command::new("swipl")
        .args(["-q", "-g", goal, "-t", "halt(1)"])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .ok()?;
    let deadline = Instant::now() + limit;
    let status = loop {
        if let Some(status) = child.try_wait().ok()? {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut out = String::new();
    child.stdout.take()?.read_to_string(&mut out).ok()?;
    status.success().then_some(out)
}

/// `--search paper` against the paper's Algorithm 1 written in Prolog
/// (tests/support/paper_search.pl): on random KBs, the same first plan, or no plan for both.
/// Skips, saying so, without `swipl` (`.ci/run` installs it).
/// The first plan of kbc's paper search for problem 0 of `frontend`, its steps printed without
/// spaces as Algorithm 1 in Prolog prints them.
fn first_paper_plan(frontend: &Frontend, depth: u32) -> Result<Vec<String>, Failure> {
    let mut task = kbc::passes::task::build(&frontend.kb, 0);
    let budget = Budget { max_states: 100_000, ..Budget::default() };
    let options = Options { search: SearchKind::Paper, max_depth: Some(depth), budget, plans: 1, ..Options::default() };
    let plan = planner::search(&frontend.kb, &frontend.interner, &mut task, &options, &mut Silent).result?;
    Ok(plan
        .steps
        .iter()
        .map(|s| hir::term_to_string(&frontend.interner, &s.name, &hir::VarTable::default()).replace(' ', ""))
        .collect())
}

/// The first plan tests/support/paper_search.pl prints in swipl for problem `prob` of `file`
/// (`no plan` when it finds none), or `None` if swipl fails or takes more than 30 s.
fn prolog_first_plan(file: &std::path::Path, support: &std::path::Path, depth: u32) -> Option<Vec<String>> {
    let goal = format!("consult('{}'), consult('{}'), run(prob, {depth}), halt", file.display(), support.display());
    let stdout = swipl(&goal, Duration::from_secs(30))?;
    Some(stdout.lines().map(str::to_string).collect())
}

#[test]
fn the_paper_search_finds_the_same_first_plan_as_algorithm_1_in_prolog() {
    if std::process::Command::new("swipl").arg("--version").output().is_err() {
        eprintln!("skipped: swipl is not installed");
        return;
    }
    let count: u64 = std::env::var("KBC_PAPER_KBS").ok().and_then(|n| n.parse().ok()).unwrap_or(150);
    let dir = std::env::temp_dir().join(format!("kbc-paper-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let support = std::fs::canonicalize("tests/support/paper_search.pl").expect("the Prolog planner");
    const DEPTH: u32 = 6;
    let (mut compared, mut with_plan) = (0, 0);
    let mut failures = Vec::new();
    for seed in 1..=count {
        let kb = generate(seed);
        let text = kb_text(&kb);
        let mut db = SourceDb::new();
        let root = db.add(format!("seed{seed}.pl"), None, text.clone());
        let (_, frontend, diagnostics) = kbc::session::Session::open(db, &[root], &mut FsLoader).into_parts();
        if diagnostics.has_errors() {
            continue;
        }
        let ours = match first_paper_plan(&frontend, DEPTH) {
            Ok(plan) => plan,
            Err(Failure::Exhausted { .. } | Failure::Unsolvable(_)) => vec!["no plan".to_string()],
            Err(_) => continue,
        };
        let file = dir.join(format!("seed{seed}.pl"));
        std::fs::write(&file, &text).expect("a scratch file");
        let Some(theirs) = prolog_first_plan(&file, &support, DEPTH) else {
            failures.push(format!("seed {seed}: swipl failed or took more than 30 s"));
            continue;
        };
        compared += 1;
        with_plan += usize::from(ours != ["no plan"]);
        if ours != theirs {
            failures.push(format!("seed {seed}: kbc {ours:?}, Algorithm 1 in Prolog {theirs:?}\n{text}"));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!("compared {compared} KBs, {with_plan} with a plan");
    assert!(with_plan * 10 > compared, "too few plans to compare: {with_plan} of {compared}");
    assert!(
        failures.is_empty(),
        "{} differ:\n\n{}",
        failures.len(),
        failures.iter().take(4).cloned().collect::<Vec<_>>().join("\n\n")
    );
}

/// KBs whose OnKB goals call SWI-Prolog's built-ins and library predicates, in the order of
/// whose solutions the paper's depth-first search finds its first plan.
const LIBRARY_KBS: &[&str] = &[
    // A grid from between/3; moves that climb by one diagonal.
    "cell(X, Y) :- between(1, 3, X), between(1, 2, Y).
action(move(R, X1, Y1, X2, Y2), [at(R, X1, Y1)], [], [], [cell(X2, Y2), X2 + Y2 =:= X1 + Y1 + 1], [del(at(R, X1, Y1)), add(at(R, X2, Y2))]).
prob :- go([at(r, 1, 1)], [at(r, 3, 2)]).
",
    // Items ranked by findall/3, msort/2 and nth1/3.
    "item(c). item(a). item(b).
ranked(I, K) :- findall(X, item(X), L), msort(L, S), nth1(K, S, I).
action(pick(I), [free], [picked(I)], [], [ranked(I, K), K =< 2], [add(picked(I))]).
action(done, [picked(a), picked(b)], [], [], [], [del(free), add(finished)]).
prob :- go([free], [finished]).
",
    // Loads checked with length/2, forall/2 and aggregate_all/3, merged with append/3.
    "load(t2, [p3]). load(t1, [p1, p2]).
action(ship(T), [ready(T)], [shipped(T)], [], [load(T, Ps), length(Ps, N), N > 0, forall(member(P, Ps), atom(P)), aggregate_all(count, load(_, _), 2)], [del(ready(T)), add(shipped(T))]).
action(merge(T1, T2), [shipped(T1), shipped(T2)], [merged(_)], [], [T1 @< T2, load(T1, A), load(T2, B), append(A, B, All), length(All, 3)], [add(merged(All))]).
prob :- go([ready(t1), ready(t2)], [merged([p1, p2, p3])]).
",
    // A durative step counted with succ/2.
    "action(step_start(R, N), [at(R, N)], [], [], [succ(N, M), M =< 3], [del(at(R, N)), add(stepping(R, N))]).
action(step_end(R, N), [stepping(R, N)], [], [], [succ(N, M)], [del(stepping(R, N)), add(at(R, M))]).
prob :- go([at(r, 1)], [at(r, 3)]).
",
    // Cities from setof/3 and bagof/3, a tour closed with last/2 and reverse/2.
    "road(b, c). road(a, b). road(c, a). road(a, c).
action(visit(C), [todo], [visited(C)], [], [setof(X, Y^road(X, Y), Cs), member(C, Cs)], [add(visited(C))]).
action(close, [visited(a), visited(b), visited(c)], [], [], [bagof(Y, road(a, Y), Ys), reverse(Ys, [Last|_]), last([a, b, Last], c)], [del(todo), add(toured)]).
prob :- go([todo], [toured]).
",
    // Keys from pairs, sorted with sort/4 and keysort/2; a fold with foldl/4 and plus/3.
    "cost(x, 3). cost(y, 1). cost(z, 2).
cheapest(K) :- findall(C-K0, cost(K0, C), Ps), keysort(Ps, [_-K|_]).
total(T) :- findall(C, cost(_, C), Cs), foldl(plus, Cs, 0, T).
action(buy(K), [money(M)], [bought(K)], [], [cost(K, C), total(T), C < T, sort(0, @>=, [C, 1], [Top|_]), Top >= C, M >= C, M1 is M - C], [del(money(M)), add(money(M1)), add(bought(K))]).
action(finish, [bought(K)], [], [], [cheapest(K)], [add(finished)]).
prob :- go([money(4)], [finished]).
",
];

/// KBs whose test computes `go`'s states in goals before the call (and calls more after it,
/// which neither planner runs).
const PRELUDE_KBS: &[&str] = &[
    // The states named by facts.
    "start_state([at(r, a), parcel(p, a)]).
end_state([parcel(p, c)]).
road(a, b). road(b, c). road(b, a).
action(drive(R, X, Y), [at(R, X)], [], [], [road(X, Y)], [del(at(R, X)), add(at(R, Y))]).
action(carry(R, P, X, Y), [at(R, X), parcel(P, X)], [], [], [road(X, Y)], [del(at(R, X)), del(parcel(P, X)), add(at(R, Y)), add(parcel(P, Y))]).
prob :- start_state(I), end_state(G), go(I, G).
",
    // An initial state built with findall/3 and append/3; the goal written out; output after.
    "block(b2). block(b1).
action(stack(X, Y), [clear(X), clear(Y)], [on(X, _)], [], [block(X), block(Y), X \\== Y], [del(clear(Y)), add(on(X, Y))]).
action(finish, [on(b1, b2)], [], [], [], [add(done)]).
prob :- findall(clear(B), block(B), Clear), append(Clear, [ready], Init), go(Init, [done]), write(planned), nl.
",
    // A durative pair whose states come from a rule with an if-then-else, and a goal with a
    // variable bound through `=/2`.
    "size(3).
start(I) :- size(N), ( N > 2 -> I = [at(r, 1), big] ; I = [at(r, 1)] ).
action(step_start(R, N), [at(R, N)], [], [], [succ(N, M), M =< 3], [del(at(R, N)), add(stepping(R, N))]).
action(step_end(R, N), [stepping(R, N)], [], [], [succ(N, M)], [del(stepping(R, N)), add(at(R, M))]).
prob :- start(I), Last = 3, G = [at(r, Last), big], go(I, G).
",
];

#[test]
fn the_paper_search_with_library_predicates_finds_the_same_first_plan_as_algorithm_1_in_prolog() {
    same_first_plans_as_algorithm_1(LIBRARY_KBS, "library");
}

#[test]
fn tests_that_compute_their_states_find_the_same_first_plan_as_algorithm_1_in_prolog() {
    same_first_plans_as_algorithm_1(PRELUDE_KBS, "prelude");
}

/// Each of `kbs` checks, has a plan under `--search paper`, and it is the first plan
/// tests/support/paper_search.pl finds in swipl.
fn same_first_plans_as_algorithm_1(kbs: &[&str], label: &str) {
    if std::process::Command::new("swipl").arg("--version").output().is_err() {
        eprintln!("skipped: swipl is not installed");
        return;
    }
    let dir = std::env::temp_dir().join(format!("kbc-paper-{label}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let support = std::fs::canonicalize("tests/support/paper_search.pl").expect("the Prolog planner");
    const DEPTH: u32 = 8;
    let mut failures = Vec::new();
    let mut with_plan = 0;
    for (index, text) in kbs.iter().enumerate() {
        let mut db = SourceDb::new();
        let root = db.add(format!("{label}{index}.pl"), None, text.to_string());
        let (_, frontend, diagnostics) = kbc::session::Session::open(db, &[root], &mut FsLoader).into_parts();
        assert!(!diagnostics.has_errors(), "KB {index} checks: {:?}", common::messages(&diagnostics));
        let ours =
            first_paper_plan(&frontend, DEPTH).unwrap_or_else(|failure| panic!("KB {index}: no plan: {failure:?}"));
        with_plan += 1;
        let file = dir.join(format!("{label}{index}.pl"));
        std::fs::write(&file, text).expect("a scratch file");
        let theirs = prolog_first_plan(&file, &support, DEPTH).expect("swipl runs the KB");
        if ours != theirs {
            failures.push(format!("KB {index}: kbc {ours:?}, Algorithm 1 in Prolog {theirs:?}\n{text}"));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(with_plan, kbs.len());
    assert!(failures.is_empty(), "{} differ:\n\n{}", failures.len(), failures.join("\n\n"));
}
