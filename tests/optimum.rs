//! An exact reference for the ladder's makespans: the least makespan of the small rungs,
//! found by a search of its own over the timed semantics of std/blocks.pl, and kbc's proven
//! lower bound and plans held against it.
//!
//! `kbc bench` prints a lower bound next to every makespan (`ladder::LowerBound`); until now
//! the only check of that bound was that kbc's own plans never beat it, which a bound far
//! above the optimum of a rung kbc plans badly would pass. This file finds the optimum itself.
//!
//! The reference reads the rung's goal file (its `cell/2` facts and the `go/2` lists) and knows
//! std/blocks.pl as its text says, written again here: the arms grip a clear block (not one
//! standing where the goal wants it), move it to another cell (its goal cell, or a buffer cell
//! the goal leaves empty), put it on the table there when no block stands on that cell, or on
//! the top block when the goal stacks it on that block (not one being gripped), and release
//! it. Grip and release take one to two time units, a move the Manhattan distance plus one and
//! more without limit. It shares no code with kbc's planner.
//!
//! The search runs in whole time units with the separation of ordered snap actions taken as
//! zero (events at one instant happen in an order, each seeing the ones before): a state is
//! where every block is and what every arm does and for how long, arms sorted (they are
//! interchangeable); an event costs nothing and a tick of the clock one unit. It is A*: the
//! estimate of the time left is the most any one block still needs an arm for (a whole cycle to
//! its goal cell, two when it must leave its goal cell and come back), or all blocks' needs
//! shared by the arms, whichever is more; both are at most the time left. With whole durations
//! an optimal schedule has whole times, so this finds the optimum with the separation at zero:
//! no plan kbc may output is shorter, and kbc's lower bound, which counts durations only, may
//! not exceed it. kbc's bound includes a search of its own over the same semantics
//! (`src/ladder/exhaustive.rs`: other states, other estimate, its own reading of the rung);
//! where that search finishes, it must find the optimum found here.
//!
//! `cargo test` checks the rungs of 2 to 4 blocks of three seeds (about 11 s in a debug
//! build); `KBC_OPTIMUM_BLOCKS=6 cargo test --release --test optimum -- --nocapture` goes to
//! 6 blocks (about 2 minutes) and prints each rung's optimum, bound and plan;
//! `KBC_OPTIMUM_ONLY=TEXT` keeps the rungs whose name contains TEXT, and
//! `KBC_OPTIMUM_SEEDS=1,5,8` takes other seeds than 1-3.
//!
//! The grid rungs, whose KB is another domain (agents moving blocks between `pos/2` cells,
//! no stacking), have a reference of their own at the end of the file.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::time::{Duration, Instant};

use kbc::ladder::{self, Family, Rung};
use kbc::planner::{Budget, SearchKind};

// ---------------------------------------------------------------------------------------------
// The problem, as the goal file states it.

type Cell = (i64, i64);

/// Where a block stands: on the table at a cell, or on another block (and its cell).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Loc {
    Table(u8),
    On(u8, u8),
    /// In the air: an arm carries it.
    Air,
}

impl Loc {
    fn cell(self) -> Option<u8> {
        match self {
            Loc::Table(c) | Loc::On(_, c) => Some(c),
            Loc::Air => None,
        }
    }
}

struct Problem {
    cells: Vec<Cell>,
    arms: usize,
    init: Vec<Loc>,
    /// Each block's place in the goal (every block of a ladder rung has one).
    goal: Vec<Loc>,
    /// Cells the goal leaves empty: where blocks may be put aside.
    buffer: Vec<bool>,
}

/// The arguments of each `name(...)` fact in `text`, split at commas.
fn facts<'t>(text: &'t str, name: &str) -> Vec<Vec<&'t str>> {
    let pattern = format!("{name}(");
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find(&pattern) {
        let preceded = rest[..at].chars().last().is_some_and(|c| c.is_alphanumeric() || c == '_');
        let args = &rest[at + pattern.len()..];
        let close = args.find(')').expect("a closing parenthesis");
        if !preceded {
            out.push(args[..close].split(',').map(str::trim).collect());
        }
        rest = &args[close..];
    }
    out
}

fn parse(source: &str) -> Problem {
    let number = |s: &str| s.parse::<i64>().expect("a number");
    let block = |s: &str| s.strip_prefix('b').expect("a block").parse::<usize>().expect("a block number") - 1;
    let cells: Vec<Cell> = facts(source, "cell").iter().map(|a| (number(a[0]), number(a[1]))).collect();
    let (_, test) = source.split_once(":- go(").expect("a go/2 test");
    let (init_text, goal_text) = test.split_once("],").expect("two lists");
    let arms = facts(init_text, "available").len();
    let blocks = facts(init_text, "ontable").len() + facts(init_text, "on").len();
    let places = |text: &str| -> Vec<Loc> {
        let mut at = vec![Loc::Air; blocks];
        let cell = |x: &str, y: &str| cells.iter().position(|&c| c == (number(x), number(y))).expect("a cell") as u8;
        for a in facts(text, "ontable") {
            at[block(a[0])] = Loc::Table(cell(a[1], a[2]));
        }
        for a in facts(text, "on") {
            at[block(a[0])] = Loc::On(block(a[1]) as u8, cell(a[2], a[3]));
        }
        assert!(!at.contains(&Loc::Air), "every block placed");
        at
    };
    let (init, goal) = (places(init_text), places(goal_text));
    let buffer = (0..cells.len()).map(|c| !goal.iter().any(|l| l.cell() == Some(c as u8))).collect();
    Problem { cells, arms, init, goal, buffer }
}

// ---------------------------------------------------------------------------------------------
// The timed semantics of std/blocks.pl.

/// What an arm does. `el` is the time elapsed in a grip or release (at most 2); `left` the
/// least time a move still takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Arm {
    Idle,
    Gripping { block: u8, el: u8 },
    Gripped { block: u8 },
    Moving { block: u8, to: u8, left: u8 },
    Placed { block: u8 },
    Releasing { block: u8, el: u8 },
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct State {
    at: Vec<Loc>,
    arms: Vec<Arm>,
}

impl Problem {
    fn distance(&self, a: u8, b: u8) -> i64 {
        let (p, q) = (self.cells[a as usize], self.cells[b as usize]);
        (p.0 - q.0).abs() + (p.1 - q.1).abs()
    }

    /// `clear(B)`: nothing stands on it and no arm holds it (from the grip's end to the
    /// release's end).
    fn clear(&self, s: &State, b: u8) -> bool {
        let on_it = s.at.iter().any(|l| matches!(l, Loc::On(below, _) if *below == b));
        let held = s.arms.iter().any(|a| match *a {
            Arm::Gripped { block }
            | Arm::Moving { block, .. }
            | Arm::Placed { block }
            | Arm::Releasing { block, .. } => block == b,
            _ => false,
        });
        !on_it && !held
    }

    fn gripping(&self, s: &State, b: u8) -> bool {
        s.arms.iter().any(|a| matches!(*a, Arm::Gripping { block, .. } if block == b))
    }

    /// The states one snap action leads to.
    fn events(&self, s: &State, out: &mut Vec<State>) {
        for (i, &arm) in s.arms.iter().enumerate() {
            // Arms in the same situation give the same states: the first of them only.
            if s.arms[..i].contains(&arm) {
                continue;
            }
            let with = |arm: Arm, at: Option<(u8, Loc)>| {
                let mut next = s.clone();
                next.arms[i] = arm;
                if let Some((b, loc)) = at {
                    next.at[b as usize] = loc;
                }
                next.arms.sort_unstable();
                next
            };
            match arm {
                Arm::Idle => {
                    for b in 0..s.at.len() as u8 {
                        let loc = s.at[b as usize];
                        let standing = loc != Loc::Air;
                        let gripped = s.arms.iter().any(|a| matches!(*a, Arm::Gripped { block } if block == b));
                        // (InvalidAtEnd: not a block that stands where the goal wants it.)
                        if standing
                            && self.clear(s, b)
                            && !self.gripping(s, b)
                            && !gripped
                            && loc != self.goal[b as usize]
                        {
                            out.push(with(Arm::Gripping { block: b, el: 0 }, None));
                        }
                    }
                }
                Arm::Gripping { block, el } if el >= 1 => out.push(with(Arm::Gripped { block }, None)),
                Arm::Gripped { block } => {
                    let from = s.at[block as usize].cell().expect("a gripped block stands");
                    for to in 0..self.cells.len() as u8 {
                        let goal_cell = self.goal[block as usize].cell() == Some(to);
                        if to != from && (goal_cell || self.buffer[to as usize]) {
                            let left = (self.distance(from, to) + 1) as u8;
                            out.push(with(Arm::Moving { block, to, left }, Some((block, Loc::Air))));
                        }
                    }
                }
                Arm::Moving { block, to, left: 0 } => {
                    let standing: Vec<u8> =
                        (0..s.at.len() as u8).filter(|&b| s.at[b as usize].cell() == Some(to)).collect();
                    if standing.is_empty() {
                        // On the table: where the goal wants it, or on a buffer cell.
                        let place = Loc::Table(to);
                        if self.goal[block as usize] == place || self.buffer[to as usize] {
                            out.push(with(Arm::Placed { block }, Some((block, place))));
                        }
                    } else if let Some(&top) = standing.iter().find(|&&b| self.clear(s, b)) {
                        // On the top block, where the goal stacks it there.
                        let place = Loc::On(top, to);
                        if !self.gripping(s, top) && self.goal[block as usize] == place {
                            out.push(with(Arm::Placed { block }, Some((block, place))));
                        }
                    }
                }
                Arm::Placed { block } => out.push(with(Arm::Releasing { block, el: 0 }, None)),
                Arm::Releasing { el, .. } if el >= 1 => out.push(with(Arm::Idle, None)),
                _ => {}
            }
        }
    }

    /// The state a time unit later, if nothing overruns its maximum duration (2 for a grip or
    /// a release) and something runs.
    fn tick(&self, s: &State) -> Option<State> {
        let mut next = s.clone();
        let mut runs = false;
        for arm in &mut next.arms {
            match arm {
                Arm::Gripping { el, .. } | Arm::Releasing { el, .. } => {
                    if *el >= 2 {
                        return None;
                    }
                    *el += 1;
                    runs = true;
                }
                Arm::Moving { left, .. } if *left > 0 => {
                    *left -= 1;
                    runs = true;
                }
                _ => {}
            }
        }
        next.arms.sort_unstable();
        runs.then_some(next)
    }

    /// The least time block `b` still needs an arm for, alone: a whole cycle (grip, move,
    /// release) to its goal cell from where it stands, or two, off the cell and back, when it
    /// stands on its goal cell on the wrong block; less what its arm has done of them.
    fn remaining(&self, s: &State, b: u8) -> i64 {
        let goal = self.goal[b as usize];
        let gc = goal.cell().expect("a goal place");
        let cycle = |from: u8| self.distance(from, gc) + 3;
        let round_trip = |c: u8| {
            // Off its goal cell, a block stands on a buffer cell first.
            let nearest = (0..self.cells.len() as u8)
                .filter(|&d| d != c && self.buffer[d as usize])
                .map(|d| self.distance(c, d))
                .min();
            nearest.map_or(0, |d| 2 * d + 6)
        };
        // From a place, standing: what is left to do.
        let from = |loc: Loc| match loc.cell() {
            _ if loc == goal => 0,
            Some(c) if c == gc => round_trip(c),
            Some(c) => cycle(c),
            None => 0,
        };
        for arm in &s.arms {
            match *arm {
                Arm::Gripping { block, el } if block == b => return from(s.at[b as usize]) - i64::from(el.min(1)),
                Arm::Gripped { block } if block == b => return from(s.at[b as usize]) - 1,
                Arm::Moving { block, to, left } if block == b => {
                    return i64::from(left) + 1 + if to == gc { 0 } else { cycle(to) };
                }
                Arm::Placed { block } if block == b => return 1 + from(s.at[b as usize]),
                Arm::Releasing { block, el } if block == b => {
                    return (1 - i64::from(el)).max(0) + from(s.at[b as usize]);
                }
                _ => {}
            }
        }
        from(s.at[b as usize])
    }

    /// A lower bound on the time left from `s` (so the search is A*): the most one block
    /// needs, and all blocks' needs shared by the arms.
    fn estimate(&self, s: &State) -> u32 {
        let needs: Vec<i64> = (0..s.at.len() as u8).map(|b| self.remaining(s, b)).collect();
        let arms = self.arms.max(1) as i64;
        let shared = (needs.iter().sum::<i64>() + arms - 1) / arms;
        needs.iter().copied().max().unwrap_or(0).max(shared) as u32
    }

    fn goal_reached(&self, s: &State) -> bool {
        s.at == self.goal && s.arms.iter().all(|a| *a == Arm::Idle)
    }

    /// The least makespan, in whole time units; None when the goal cannot be reached, or
    /// when more than `limit` states were settled first.
    fn optimum(&self, limit: usize) -> Option<i64> {
        let start = State { at: self.init.clone(), arms: vec![Arm::Idle; self.arms] };
        let mut best: HashMap<State, u32> = HashMap::new();
        let mut open = BinaryHeap::new();
        best.insert(start.clone(), 0);
        open.push(Reverse((self.estimate(&start), 0u32, start)));
        let mut settled = 0;
        let mut next = Vec::new();
        while let Some(Reverse((_, ticks, state))) = open.pop() {
            if best.get(&state).is_some_and(|&known| known < ticks) {
                continue;
            }
            if self.goal_reached(&state) {
                return Some(ticks as i64);
            }
            settled += 1;
            if settled > limit {
                return None;
            }
            next.clear();
            self.events(&state, &mut next);
            let mut push = |s: State, cost: u32| {
                if best.get(&s).is_none_or(|&known| cost < known) {
                    best.insert(s.clone(), cost);
                    open.push(Reverse((cost + self.estimate(&s), cost, s)));
                }
            };
            for s in next.drain(..) {
                push(s, ticks);
            }
            if let Some(s) = self.tick(&state) {
                push(s, ticks + 1);
            }
        }
        None
    }
}

// ---------------------------------------------------------------------------------------------
// The checks.

/// The states the reference may settle on one rung.
const LIMIT: usize = 20_000_000;

fn rungs(most_blocks: usize) -> Vec<Rung> {
    let mut rungs = Vec::new();
    let seeds: Vec<u64> = std::env::var("KBC_OPTIMUM_SEEDS")
        .ok()
        .map(|v| {
            v.split(',').map(|s| s.trim().parse().expect("KBC_OPTIMUM_SEEDS: seeds separated by commas")).collect()
        })
        .unwrap_or(vec![1, 2, 3]);
    for seed in seeds {
        for family in [Family::Build, Family::Reverse, Family::Swap] {
            for (blocks, arms) in ladder::SIZES.iter().copied().filter(|&(b, _)| b <= most_blocks) {
                rungs.push(Rung { family, blocks, arms, seed });
            }
        }
    }
    rungs
}

/// kbc's makespan for `rung` (heuristic search and the passes after it, as `kbc bench` runs
/// it, 60 s budget) and its lower bound.
fn planned(rung: &Rung) -> (i64, ladder::LowerBound) {
    let budget = Budget { deadline: Some(Instant::now() + Duration::from_secs(60)), ..Budget::default() };
    let row = ladder::run(rung, SearchKind::Heuristic, budget, None);
    (row.makespan.expect("solved").0, row.lower_bound.expect("a bound"))
}

#[test]
fn the_reference_finds_the_optimum_of_a_hand_solved_problem() {
    // One block on (1, 1) goes to (3, 1), two cells away, with one arm: grip (1), move (3),
    // release (1). Two blocks swapped between (1, 1) and (2, 1) with a buffer cell (3, 1) and
    // two arms: b1 can only go to its goal once b2 has left (2, 1), and b2 to (1, 1) once b1
    // has left it, so one of them waits aside or in the air. Holding b1 in the air over (2, 1)
    // while b2 moves: b1 gripped at 0-1 and lifted at 1, b2 gripped at 0-1 and lifted at 1; b2
    // reaches (1, 1) at 3 (b1 left it at 1) and b1 reaches (2, 1) at 3: both released at 4.
    let one = "cell(1, 1).\ncell(2, 1).\ncell(3, 1).\nt :- go(\n  [\n    available(a1),\n    ontable(b1, 1, 1),\n    clear(b1)\n  ],\n  [\n    available(a1),\n    ontable(b1, 3, 1),\n    clear(b1)\n  ]\n).\n";
    assert_eq!(parse(one).optimum(LIMIT), Some(5));
    let swap = "cell(1, 1).\ncell(2, 1).\ncell(3, 1).\nt :- go(\n  [\n    available(a1),\n    available(a2),\n    ontable(b1, 1, 1),\n    ontable(b2, 2, 1)\n  ],\n  [\n    available(a1),\n    available(a2),\n    ontable(b1, 2, 1),\n    ontable(b2, 1, 1)\n  ]\n).\n";
    assert_eq!(parse(swap).optimum(LIMIT), Some(4));
    // With one arm, one block goes aside first: to (3, 1) and on to (1, 1), or b1 aside.
    // b2 (2,1)->(3,1): 1 + 2 + 1; b1 (1,1)->(2,1): 1 + 2 + 1; b2 (3,1)->(1,1): 1 + 3 + 1.
    let one_arm = swap.replace("    available(a2),\n", "");
    assert_eq!(parse(&one_arm).optimum(LIMIT), Some(13));
}

#[test]
fn the_proven_bound_never_exceeds_the_optimum_and_no_plan_beats_it() {
    let most: usize = std::env::var("KBC_OPTIMUM_BLOCKS").ok().and_then(|v| v.parse().ok()).unwrap_or(4);
    let unit = kbc::ir::stn::UNITS;
    let (mut below, mut optimal) = (0, 0);
    let only = std::env::var("KBC_OPTIMUM_ONLY").unwrap_or_default();
    let rungs: Vec<Rung> = rungs(most).into_iter().filter(|r| r.name().contains(&only)).collect();
    for rung in &rungs {
        let problem = parse(&rung.source());
        let Some(optimum) = problem.optimum(LIMIT) else {
            panic!("{}: the reference found no optimum within {LIMIT} states", rung.name());
        };
        let (makespan, bound) = planned(rung);
        println!(
            "{:<20} optimum {:>3}  bound {:>7.3}  plan {:>7.3}",
            rung.name(),
            optimum,
            bound.makespan as f64 / unit as f64,
            makespan as f64 / unit as f64
        );
        // The bound counts durations only: it holds with the separation at zero.
        assert!(bound.makespan <= optimum * unit, "{}: bound {bound:?} above the optimum {optimum}", rung.name());
        assert!(makespan >= optimum * unit, "{}: a plan of {makespan} beats the optimum {optimum}", rung.name());
        // kbc's own search of the schedules, where it finishes, finds the same optimum.
        if bound.optimal {
            assert_eq!(bound.searched, optimum * unit, "{}: kbc's search against the reference", rung.name());
            optimal += 1;
        }
        below += usize::from(bound.analytic < optimum * unit);
    }
    // The reference is not the analytic bound again: it finds more on some rungs. And kbc's
    // search finishes on some.
    assert!(below > 0, "the optimum equals the analytic bound on all {} rungs", rungs.len());
    assert!(optimal > 0, "kbc's search found no optimum on {} rungs", rungs.len());
}

#[test]
fn the_bound_on_a_cell_that_must_empty_never_exceeds_the_optimum() {
    // A tower of four on (1, 1), the end of a row of five cells, turned upside down by two
    // arms: when its bottom block leaves, the three above it are on buffer cells of their own
    // or in the air, and only one can be in the air (the other arm lifts the bottom block). So
    // two stand on (2, 1) and (3, 1) at least, one two cells away: the bound counts that
    // block's longer round trip (`LowerBound::emptying`), which the ladder's rungs, with
    // buffer cells all round their towers, never need. The reference must agree it is real.
    let rung = Rung { family: Family::Reverse, blocks: 4, arms: 2, seed: 1 };
    let layout = ladder::Layout {
        cells: (1..=5).map(|x| (x, 1)).collect(),
        init: vec![((1, 1), vec![1, 2, 3, 4])],
        goal: vec![((1, 1), vec![4, 3, 2, 1])],
    };
    let source = rung.source_of(&layout);
    let mut db = kbc::source::SourceDb::new();
    let root = db.add("row.pl", None, source.clone());
    let mut session = kbc::session::Session::open(db, &[root], &mut kbc::passes::load::NoIncludes);
    assert!(!session.has_errors(), "the goal file checks");
    let bound = rung.lower_bound_of(&layout, &mut session);
    let unit = kbc::ir::stn::UNITS;
    // The three blocks above the bottom: (3, 1) costs two units more than (2, 1) there and back.
    assert_eq!(bound.emptying, 2 * unit, "{bound:?}");
    let optimum = parse(&source).optimum(LIMIT).expect("an optimum");
    assert!(bound.makespan <= optimum * unit, "bound {bound:?} above the optimum {optimum}");
    assert!(bound.optimal && bound.searched == optimum * unit, "kbc's search: {bound:?}, the reference: {optimum}");
    println!("row tower: optimum {optimum}, bound {}", bound.makespan as f64 / unit as f64);
    // More towers and arms: the bound stays at most the optimum wherever it counts something.
    let variants = [
        (3, vec![((1, 1), vec![1, 2, 3, 4])], 6),
        (2, vec![((3, 1), vec![1, 2, 3, 4])], 5),
        (2, vec![((1, 1), vec![1, 2, 3]), ((5, 1), vec![4, 5])], 5),
        (3, vec![((1, 1), vec![1, 2, 3, 4, 5])], 7),
    ];
    let mut counted = 0;
    for (arms, init, width) in variants {
        let rung = Rung { family: Family::Reverse, blocks: 5, arms, seed: 1 };
        let goal = init.iter().map(|(c, t)| (*c, t.iter().rev().copied().collect())).collect();
        let layout = ladder::Layout { cells: (1..=width).map(|x| (x, 1)).collect(), init, goal };
        let source = rung.source_of(&layout);
        let mut db = kbc::source::SourceDb::new();
        let root = db.add("row.pl", None, source.clone());
        let mut session = kbc::session::Session::open(db, &[root], &mut kbc::passes::load::NoIncludes);
        let bound = rung.lower_bound_of(&layout, &mut session);
        let optimum = parse(&source).optimum(LIMIT).expect("an optimum");
        println!("{layout:?}, {arms} arms: optimum {optimum}, bound {bound:?}");
        assert!(bound.makespan <= optimum * unit, "{layout:?}: bound {bound:?} above the optimum {optimum}");
        if bound.optimal {
            assert_eq!(bound.searched, optimum * unit, "{layout:?}: kbc's search against the reference");
        }
        counted += usize::from(bound.emptying > 0);
    }
    assert!(counted > 0, "no variant counts a cell that must empty");
}

#[test]
fn a_block_sent_to_a_cell_being_cleared_makes_the_optimum_of_a_corner_tower() {
    // reverse_b03_a3_s3: the tower b3, b1, b2 on (5, 1), the corner of a row of five cells,
    // turned upside down by three arms. Its optimum puts every block down on (4, 1), the one
    // neighbouring cell, in turn: each one's move heads there while the block before it still
    // stands there and arrives as that one leaves. Spread over (4, 1), (3, 1) and (2, 1), as the
    // search and the plain relocations leave it, the plan takes two units more.
    let rung = Rung { family: Family::Reverse, blocks: 3, arms: 3, seed: 3 };
    let optimum = parse(&rung.source()).optimum(LIMIT).expect("an optimum");
    let (makespan, _) = planned(&rung);
    let unit = kbc::ir::stn::UNITS;
    // (Within the separations of ordered snap actions, thousandths of a unit each.)
    assert!(makespan < (optimum + 1) * unit, "a makespan of {makespan} against the optimum {optimum}");
}

// ---------------------------------------------------------------------------------------------
// The grid rungs (`Family::Grid`): their own reference, as the rung's KB says. A move starts
// when its agent is free, towards a `pos/2` cell no block stands on and no move heads for; the
// block leaves its cell at the start and stands on the new one at the end, the Manhattan
// distance later at the least (the KB allows up to twice that and two more, never shorter).
// The search runs in whole units with the separation at zero: at each instant the moves due
// end, then any free agents start moves, one after another (each start sees the ones before,
// so a block may head for a cell another has just left), and the clock ticks. Breadth-first
// over instants: the first instant at which every block stands on its goal cell is the
// optimum.

/// A grid problem: the cells, the agents, and each block's start and goal cell (indices).
struct Grid {
    cells: Vec<(i64, i64)>,
    agents: usize,
    start: Vec<u8>,
    goal: Vec<u8>,
}

fn parse_grid(source: &str) -> Grid {
    // (The `pos/2` facts; the action's conditions name it with variables.)
    let cells: Vec<(i64, i64)> =
        facts(source, "pos").iter().filter_map(|a| Some((a[0].parse().ok()?, a.get(1)?.parse().ok()?))).collect();
    let agents = source.matches("\nagent(").count();
    let body = &source[source.find("go(").expect("a go/2 test")..];
    let (init, goal) = body.split_once("],").expect("two lists");
    let at = |list: &str| -> std::collections::BTreeMap<String, u8> {
        facts(list, "at")
            .iter()
            .map(|a| {
                let cell = (a[1].parse().expect("x"), a[2].parse().expect("y"));
                (a[0].to_string(), cells.iter().position(|&c| c == cell).expect("a cell") as u8)
            })
            .collect()
    };
    let (from, to) = (at(init), at(goal));
    Grid { agents, start: from.values().copied().collect(), goal: from.keys().map(|b| to[b]).collect(), cells }
}

/// Where every block is (a cell, or `IN_TRANSIT`) and the moves under way (time left, block,
/// destination), sorted.
type GridState = (Vec<u8>, Vec<(u8, u8, u8)>);
const IN_TRANSIT: u8 = u8::MAX;

impl Grid {
    fn distance(&self, a: u8, b: u8) -> u8 {
        let ((x1, y1), (x2, y2)) = (self.cells[a as usize], self.cells[b as usize]);
        ((x1 - x2).abs() + (y1 - y2).abs()) as u8
    }

    /// Every state reachable from `state` by starting moves now, `state` itself included.
    fn starts(&self, state: GridState, out: &mut std::collections::HashSet<GridState>) {
        if !out.insert(state.clone()) || state.1.len() >= self.agents {
            return;
        }
        let (at, moving) = &state;
        let taken = |c: u8| at.contains(&c) || moving.iter().any(|&(_, _, d)| d == c);
        for block in 0..at.len() {
            if at[block] == IN_TRANSIT {
                continue;
            }
            for cell in 0..self.cells.len() as u8 {
                if taken(cell) {
                    continue;
                }
                let (mut at, mut moving) = state.clone();
                moving.push((self.distance(at[block], cell), block as u8, cell));
                moving.sort();
                at[block] = IN_TRANSIT;
                self.starts((at, moving), out);
            }
        }
    }

    /// The least makespan in whole units, if at most `horizon`.
    fn optimum(&self, horizon: usize) -> Option<usize> {
        let mut layer: std::collections::HashSet<GridState> = [(self.start.clone(), Vec::new())].into();
        for now in 0..=horizon {
            if layer.iter().any(|(at, moving)| moving.is_empty() && *at == self.goal) {
                return Some(now);
            }
            let mut next = std::collections::HashSet::new();
            for state in layer {
                let mut started = std::collections::HashSet::new();
                self.starts(state, &mut started);
                for (mut at, moving) in started {
                    let mut still = Vec::new();
                    for (left, block, cell) in moving {
                        if left <= 1 {
                            at[block as usize] = cell;
                        } else {
                            still.push((left - 1, block, cell));
                        }
                    }
                    next.insert((at, still));
                }
            }
            layer = next;
        }
        None
    }
}

#[test]
fn the_grid_bound_never_exceeds_the_optimum() {
    // The grid rungs of six blocks, seeds 1-8 (all optimum = bound when written). Their bound
    // counts each block's move and, for each cycle of blocks that must take each other's
    // cells, the least stop one of them makes on a third cell (grid_b06_a2_s6: 4 without it,
    // 5 with it; the optimum is 5).
    // Seeds 4 and 7 take the reference 11 and 2 s in a release build (the others 0.6 s at
    // most): they run with `KBC_OPTIMUM_BLOCKS=6`, as the larger rungs above do.
    let all = std::env::var("KBC_OPTIMUM_BLOCKS").ok().and_then(|v| v.parse::<usize>().ok()).is_some_and(|n| n >= 6);
    let unit = kbc::ir::stn::UNITS;
    let mut counted_a_cycle = false;
    for seed in (1..=8).filter(|&s| all || (s != 4 && s != 7)) {
        let rung = Rung { family: Family::Grid, blocks: 6, arms: 2, seed };
        let optimum = parse_grid(&rung.source()).optimum(30).expect("an optimum") as i64;
        let (makespan, bound) = planned(&rung);
        println!("{:<20} optimum {optimum:>3}  bound {:>7.3}", rung.name(), bound.makespan as f64 / unit as f64);
        assert!(bound.makespan <= optimum * unit, "{}: bound {bound:?} above the optimum {optimum}", rung.name());
        assert!(makespan >= optimum * unit, "{}: a plan of {makespan} beats the optimum {optimum}", rung.name());
        counted_a_cycle |= bound.aside > 0 && bound.makespan == optimum * unit;
    }
    assert!(counted_a_cycle, "no cycle counted where it makes the bound the optimum");
}
