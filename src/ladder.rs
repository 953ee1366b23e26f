//! The scaling ladder: generated multi-arm blocks-world problems of growing size, written as
//! goal files for the standard blocks world (std/blocks.pl), and a runner that plans each with
//! a chosen search under a budget and checks every plan with the independent validator.
//!
//! Three families of the standard blocks world, from the paper's cases upwards:
//! - `build`: every block alone on the table; the goal stacks them into towers of at most five;
//! - `reverse`: towers of at most five; the goal is each tower upside down, on the same cell;
//! - `swap`: at least two towers; the goal moves each tower, in the same order, to the next
//!   tower's cell (a rotation), so blocks must wait on free cells.
//!
//! And a fourth in the style other authors write their KBs (`grid`, [`grid`]): a domain of its
//! own, with agents as `agent/1` and positions as `pos/2` facts, one `move` durative action
//! whose end takes its destination from the start, and blocks rearranged among the cells.
//!
//! The table is a grid five cells wide with two more cells than blocks (`cell/2` facts), so a
//! 20-block problem has 22 cells, as in the issue that asked for the ladder. Which block goes
//! where is drawn from a seeded generator (SplitMix64, `kbvm::rng::Rng`), so a rung is the same problem on every
//! machine. Nothing here does IO; `kbc bench` prints the rows and can write the goal files.

use std::time::{Duration, Instant};

use crate::ir::stn::UNITS;
use crate::planner::{Budget, Failure, SearchKind, Silent};
use crate::session::{PlanError, PlanSettings, Planned, Session};
use crate::source::SourceDb;
use crate::validate;
use kbvm::rng::Rng;

mod exhaustive;

/// A family of ladder problems.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Blocks alone on the table, stacked into towers.
    Build,
    /// Towers turned upside down in place.
    Reverse,
    /// Towers moved, order kept, each to the next tower's cell.
    Swap,
    /// Blocks rearranged among the cells of a grid, in a KB written in other authors' style
    /// (`agent/1`, `pos/2`, `at/3`, `move_start`/`move_end`), not the standard blocks world.
    Grid,
}

impl Family {
    /// The family's name, as used in problem names.
    pub fn name(self) -> &'static str {
        match self {
            Family::Build => "build",
            Family::Reverse => "reverse",
            Family::Swap => "swap",
            Family::Grid => "grid",
        }
    }
}

/// One problem of the ladder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rung {
    /// What kind of rearrangement.
    pub family: Family,
    /// The number of blocks.
    pub blocks: usize,
    /// The number of arms.
    pub arms: usize,
    /// The generator's seed.
    pub seed: u64,
}

/// The sizes of the standard ladder: (blocks, arms), from the paper's cases (2 and 3 blocks
/// with 3 arms, its 4-block 3-arm stacking case) up to 100 blocks and 10 arms.
pub const SIZES: [(usize, usize); 16] = [
    (2, 3),
    (3, 3),
    (4, 3),
    (5, 3),
    (6, 3),
    (8, 3),
    (10, 4),
    (12, 4),
    (15, 4),
    (20, 4),
    (25, 6),
    (30, 6),
    (50, 8),
    (75, 10),
    (100, 8),
    (100, 10),
];

/// The sizes of the grid rungs (blocks, agents): the 10-20 blocks and 2-3 agents that KBs in
/// other authors' style use.
pub const GRID_SIZES: [(usize, usize); 4] = [(6, 2), (10, 2), (15, 3), (20, 3)];

/// The grid rungs ([`Family::Grid`]) at every size of [`GRID_SIZES`], seed 1. They are not
/// in [`standard`], whose rungs are problems of the standard blocks world.
pub fn grid() -> Vec<Rung> {
    GRID_SIZES.iter().map(|&(blocks, arms)| Rung { family: Family::Grid, blocks, arms, seed: 1 }).collect()
}

/// Every rung `kbc bench` runs: the standard ladder, then the grid rungs.
pub fn all() -> Vec<Rung> {
    let mut rungs = standard();
    rungs.extend(grid());
    rungs
}

/// The standard ladder: every family of the standard blocks world at every size, seed 1.
pub fn standard() -> Vec<Rung> {
    let mut rungs = Vec::new();
    for family in [Family::Build, Family::Reverse, Family::Swap] {
        for (blocks, arms) in SIZES {
            rungs.push(Rung { family, blocks, arms, seed: 1 });
        }
    }
    rungs
}

/// A duration's least and greatest values in STN time (`Session::duration_bounds`).
type DurationBounds = (i64, Option<i64>);

/// Where each block stands: its cell, and the block it is on (`None`: the table).
type Places = std::collections::BTreeMap<usize, ((usize, usize), Option<usize>)>;

/// A tower: its cell and its blocks (numbers: `b3` is 3), bottom first.
pub type Tower = ((usize, usize), Vec<usize>);

/// A rung's table and towers, as its goal file states them ([`Rung::layout`]); a test may
/// write one of its own and ask for its goal file and bound ([`Rung::source_of`],
/// [`Rung::lower_bound_of`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// The cells of the table.
    pub cells: Vec<(usize, usize)>,
    /// The towers at the start.
    pub init: Vec<Tower>,
    /// The towers of the goal.
    pub goal: Vec<Tower>,
}

/// The cycles of a grid rung's moves ([`LowerBound`]): blocks each of whose goal cells
/// the next one's start cell is, round to the first, in the order of their first block
/// (the least block of each).
fn grid_cycles(
    from: &std::collections::BTreeMap<usize, (usize, usize)>,
    to: &std::collections::BTreeMap<usize, (usize, usize)>,
) -> Vec<Vec<usize>> {
    let standing: std::collections::BTreeMap<(usize, usize), usize> = from.iter().map(|(&b, &c)| (c, b)).collect();
    // The block on `b`'s goal cell at the start, if it must move too.
    let next = |b: usize| standing.get(&to[&b]).copied().filter(|&n| n != b && from[&n] != to[&n]);
    let mut seen = std::collections::BTreeSet::new();
    let mut cycles = Vec::new();
    for &b in to.keys() {
        if seen.contains(&b) || from[&b] == to[&b] {
            continue;
        }
        // Follow the chain from b until it ends or meets a block seen before.
        let mut chain = vec![b];
        seen.insert(b);
        while let Some(n) = next(*chain.last().expect("not empty")) {
            if let Some(at) = chain.iter().position(|&c| c == n) {
                cycles.push(chain[at..].to_vec());
                break;
            }
            if !seen.insert(n) {
                break;
            }
            chain.push(n);
        }
    }
    cycles
}

impl Rung {
    /// The problem's name, e.g. `build_b08_a3_s1`.
    pub fn name(&self) -> String {
        format!("{}_b{:02}_a{}_s{}", self.family.name(), self.blocks, self.arms, self.seed)
    }

    /// The table's cells: a grid five wide, two more cells than blocks.
    pub fn cells(&self) -> Vec<(usize, usize)> {
        (0..self.blocks + 2).map(|i| (i % 5 + 1, i / 5 + 1)).collect()
    }

    /// The initial and goal towers.
    fn towers(&self) -> (Vec<Tower>, Vec<Tower>) {
        let mut random = Rng::new(self.seed ^ (self.blocks as u64) << 32 ^ (self.arms as u64) << 48);
        let mut cells = self.cells();
        random.shuffle(&mut cells);
        let mut blocks: Vec<usize> = (1..=self.blocks).collect();
        random.shuffle(&mut blocks);
        let minimum_towers = if self.family == Family::Swap { 2 } else { 1 };
        let count = self.blocks.div_ceil(5).max(minimum_towers).min(self.blocks.max(1));
        let split = |blocks: &[usize]| -> Vec<Vec<usize>> {
            let mut towers = vec![Vec::new(); count];
            for (i, block) in blocks.iter().enumerate() {
                towers[i * count / blocks.len().max(1)].push(*block);
            }
            towers
        };
        match self.family {
            Family::Build => {
                let init = blocks.iter().zip(&cells).map(|(b, c)| (*c, vec![*b])).collect();
                let mut goal_cells = cells.clone();
                random.shuffle(&mut goal_cells);
                let goal = split(&blocks).into_iter().zip(goal_cells).map(|(t, c)| (c, t)).collect();
                (init, goal)
            }
            Family::Reverse => {
                let init: Vec<Tower> =
                    split(&blocks).into_iter().zip(cells.iter().copied()).map(|(t, c)| (c, t)).collect();
                let goal = init.iter().map(|(c, t)| (*c, t.iter().rev().copied().collect())).collect();
                (init, goal)
            }
            Family::Swap => {
                let init: Vec<Tower> =
                    split(&blocks).into_iter().zip(cells.iter().copied()).map(|(t, c)| (c, t)).collect();
                let goal = (0..init.len()).map(|i| (init[(i + 1) % init.len()].0, init[i].1.clone())).collect();
                (init, goal)
            }
            // One block per cell, at the start and in the goal, each drawn independently.
            Family::Grid => {
                let init = blocks.iter().zip(&cells).map(|(b, c)| (*c, vec![*b])).collect();
                let mut goal_cells = cells.clone();
                random.shuffle(&mut goal_cells);
                let goal = blocks.iter().zip(&goal_cells).map(|(b, c)| (*c, vec![*b])).collect();
                (init, goal)
            }
        }
    }

    /// The grid rung's KB: its own domain in other authors' style and one test.
    fn grid_source(&self) -> String {
        let (init, goal) = self.towers();
        let mut out = format!(
            "% The kbc scaling ladder: family grid, {} blocks, {} agents, seed {} (written by `kbc bench`).\n",
            self.blocks, self.arms, self.seed
        );
        out.push_str("% A KB in the style other authors write: agents, blocks and positions as facts.\n");
        for a in 1..=self.arms {
            out.push_str(&format!("agent(a{a}).\n"));
        }
        for b in 1..=self.blocks {
            out.push_str(&format!("block(b{b}).\n"));
        }
        for (x, y) in self.cells() {
            out.push_str(&format!("pos({x}, {y}).\n"));
        }
        out.push_str(GRID_DOMAIN);
        let arms: Vec<String> = (1..=self.arms).map(|a| format!("free(a{a})")).collect();
        let placed = |towers: &[Tower]| -> Vec<String> {
            towers.iter().flat_map(|((x, y), t)| t.iter().map(move |b| format!("at(b{b}, {x}, {y})"))).collect()
        };
        let init = [arms, placed(&init)].concat();
        out.push_str(&format!(
            "{} :- go(\n  [\n    {}\n  ],\n  [\n    {}\n  ]\n).\n",
            self.name(),
            init.join(",\n    "),
            placed(&goal).join(",\n    ")
        ));
        out
    }

    /// The rung's table and towers.
    pub fn layout(&self) -> Layout {
        let (init, goal) = self.towers();
        Layout { cells: self.cells(), init, goal }
    }

    /// The goal file: the table's `cell/2` facts and one test `name :- go(Init, Goal).`, for
    /// the standard blocks world (a whole KB of its own for a grid rung). Arms are `a1`..;
    /// blocks `b1`...
    pub fn source(&self) -> String {
        if self.family == Family::Grid {
            return self.grid_source();
        }
        self.source_of(&self.layout())
    }

    /// The goal file of `layout` on the standard blocks world, with this rung's name and
    /// arms (not for a grid rung, whose KB is its own).
    pub fn source_of(&self, layout: &Layout) -> String {
        let Layout { cells, init, goal } = layout;
        let mut out = format!(
            "% The kbc scaling ladder: family {}, {} blocks, {} arms, seed {} (written by `kbc bench`).\n",
            self.family.name(),
            self.blocks,
            self.arms,
            self.seed
        );
        if *cells == self.cells() {
            out.push_str("% The table: a grid five cells wide, two more cells than blocks.\n");
        }
        for (x, y) in cells {
            out.push_str(&format!("cell({x}, {y}).\n"));
        }
        let arms: Vec<String> = (1..=self.arms).map(|a| format!("available(a{a})")).collect();
        let state = |towers: &[Tower]| -> String {
            let mut facts = arms.clone();
            for ((x, y), tower) in towers {
                for (level, block) in tower.iter().enumerate() {
                    if level == 0 {
                        facts.push(format!("ontable(b{block}, {x}, {y})"));
                    } else {
                        facts.push(format!("on(b{block}, b{}, {x}, {y})", tower[level - 1]));
                    }
                }
                if let Some(top) = tower.last() {
                    facts.push(format!("clear(b{top})"));
                }
            }
            format!("[\n    {}\n  ]", facts.join(",\n    "))
        };
        out.push_str(&format!("{} :- go(\n  {},\n  {}\n).\n", self.name(), state(init), state(goal)));
        out
    }
}

/// The domain of the grid rungs, in the style of the paper's authors' KBs: the move's end
/// names its destination only in its head (it takes the start's values).
const GRID_DOMAIN: &str = "resources(agent(_)).
action(move_start(A, B, X1, Y1, X2, Y2),
    [free(A), at(B, X1, Y1)],
    [at(_, X2, Y2), moving(_, _, _, _, X2, Y2)],
    [],
    [agent(A), block(B), pos(X2, Y2)],
    [del(free(A)), del(at(B, X1, Y1)), add(moving(A, B, X1, Y1, X2, Y2))]).
action(move_end(A, B, X1, Y1, X2, Y2),
    [moving(A, B, X1, Y1, _, _)],
    [],
    [],
    [],
    [del(moving(A, B, X1, Y1, X2, Y2)), add(at(B, X2, Y2)), add(free(A))]).
duration(move(_, _, X1, Y1, X2, Y2), D, Max) :- D is abs(X2 - X1) + abs(Y2 - Y1), Max is 2 * D + 2.
";

/// A lower bound on the makespan of every plan of a rung, in STN time: the largest of three
/// arguments (`analytic`) and, on small rungs, of a search of the rung's schedules
/// (`searched`, see `ladder/exhaustive.rs`). The three arguments (for a grid rung: the work and the longest block's move;
/// no chain; the work counts, as `aside`, one stop on a third cell for each cycle of blocks
/// that must take each other's cells: the first of a cycle to move finds its goal cell
/// taken). Each uses the least durations the KB's `duration/3` gives
/// (asked of the engine, as the STN pass does), and holds for any plan of the standard
/// blocks world:
///
/// - `work`: every block whose goal fact is not in the initial state is moved at least once,
///   by one arm, in a cycle of grip, move and release that holds the arm from the grip's start
///   to the release's end (`available/1` is the arm's resource). A move ends only on the
///   block's goal cell or on a buffer cell (one the goal leaves empty), so a block stands
///   nowhere else on its way. A block that must end on its own cell but on another block
///   leaves the cell and comes back (a move changes the cell): two cycles or more, at least
///   the least work of such a round trip through the buffer cells (shortest paths whose
///   stops are buffer cells, each step a cycle). (A block whose goal support starts below it and
///   must move too needs only one: its move can lift it before the support is gripped and
///   put it down after the support is placed.) Blocks that must leave before any goal tower
///   can start and cannot all stay in the arms are put down on their way, each on a buffer
///   cell of its own, and move again (`aside`, see `Rung::put_aside`). A block above another
///   both at the start and in the goal, where the one below moves, is lifted before that
///   one's first grip (and the grips of the blocks between them) and put in its goal place
///   after its last release, so it is either held through all of that or moves twice,
///   through a buffer cell of its own when the one below is gripped (`waiting`, see
///   `Rung::waiting`). `aside` counts what `waiting` proves of the blocks it does not count
///   itself. A cell whose goal tower has another bottom block empties at some moment, when
///   the blocks that stood on it are each on a buffer cell of its own or in the air
///   (`emptying`, see `Rung::emptying`). The sum takes the largest of the three. The arms share the sum, and more
///   (`idle`): an arm is idle before its first grip and after its last release. A block
///   with k blocks above it at the start is gripped no earlier than k grips after the start
///   (each one above must be gripped and lifted first, one after another); one with k blocks
///   above it in its goal tower is released for the last time k releases before the end at
///   the latest (each one above is put on the one below only once that one is released).
///   Each arm's first cycle is a block's (a second arm's first cycle of the same block comes
///   a whole cycle later at least), and so is its last; so the u arms that work are idle at
///   least the u least of those times at either end. The makespan is at least
///   `ceil((sum + idle) / u)`, the least of it over every u from 1 to the arms (the others
///   idle throughout).
/// - `block`: one block's cycles run one after another (with what `waiting` proves of them),
///   after its first grip can start and before the blocks above it in its goal tower are
///   placed: the longest of these.
/// - `chain`: a goal tower is built bottom up (a block is put on another only once that one
///   is released, `clear/1`), so the first block that must move in a tower ends its cycle, and
///   every block above it needs at least one more release after that. And the arms are few:
///   each block's last cycle in the tower (grip to release, on one arm) comes from another
///   cell where the block stood: its start cell, where it is from the start, or a buffer
///   cell, where it is only once a cycle from its start there (or a path of them, each a
///   whole cycle) has ended. Of any `arms + 1` consecutive blocks from the first that moves
///   up, two have their last cycles on one arm, the upper one's after the lower one's release
///   (the upper is released later, and an arm does one cycle at a time): the upper one's last
///   cycle starts no earlier than the lower one's last release and its time at the cell it
///   leaves from, and the top one of the `arms + 1` is released at least a release a level
///   after it. Whichever two they are: the top one's last release is no earlier than the
///   least of this over the pairs (with each block's cheapest cell to leave from).
///
/// When every duration the bound asks the KB for, least and greatest, is a whole number of
/// time units (as in `std/blocks.pl` and the grid KBs), `analytic` is rounded up to a whole
/// unit. The arguments above never need one happening strictly after another, so they hold
/// as well with no separation (ε) between happenings. Without it, the earliest schedule of a
/// plan's order (the shortest makespan of that order) is a longest path over the durations'
/// bounds alone, a whole number of units at least the bound; with the separations back, no
/// time is earlier.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LowerBound {
    /// The bound: the largest of `analytic` and `searched`.
    pub makespan: i64,
    /// The largest of `work`, `block` and `chain` (rounded up to a whole time unit when the
    /// durations are whole units): what the arguments about moments of any plan prove.
    pub analytic: i64,
    /// The total minimal work and idle time divided among the arms.
    pub work: i64,
    /// The most minimal work of one block, with the grips before it and the releases after it.
    pub block: i64,
    /// The longest chain a goal tower forces.
    pub chain: i64,
    /// The least work, included in `work`, that blocks put down on their way add: those that
    /// must leave before any goal tower can start and cannot all stay in the arms (with what
    /// `waiting` proves of the others).
    pub aside: i64,
    /// The least work that blocks lifted before a block below them moves add (held in the air
    /// through its move, or put down and moved again); `work` counts the largest of this,
    /// `aside` and `emptying`.
    pub waiting: i64,
    /// The least work, beyond their round trips, that the blocks of cells that must empty add
    /// (see `Rung::emptying`): at the moment such a cell is empty its blocks stand on buffer
    /// cells of their own, which may be far, or are in the air, which they have been since
    /// they left.
    pub emptying: i64,
    /// The least time, included in `work`, the arms spend idle before their first grip and
    /// after their last release, when every arm works.
    pub idle: i64,
    /// What a search of the rung's schedules proves (`ladder/exhaustive.rs`): their least
    /// makespan when it finished within [`SEARCH_LIMIT`] states (`optimal`), else the least
    /// estimate over the states it left open; 0 when it did not run (more than
    /// [`SEARCH_BLOCKS`] blocks, the grid family, durations that are not whole time units).
    pub searched: i64,
    /// Whether `searched` is the optimum: no plan is shorter, and one as short exists (with
    /// the separation of ordered snap actions taken as zero).
    pub optimal: bool,
}

/// The states the search of [`LowerBound::searched`] stores at most on one rung (about 80 MB
/// on an 8-block rung: `kbc bench`'s peak on the 8-block rungs of seed 1 was 94-97 MB, where
/// `kbc plan` of the same rungs peaks at 19 MB).
pub const SEARCH_LIMIT: usize = 300_000;

/// The most blocks of a rung the search of [`LowerBound::searched`] runs on. Within
/// [`SEARCH_LIMIT`] it finds the optimum of most rungs of up to six blocks; what it proves
/// beyond was more than the analytic bound on two 8-block rungs of seeds 1-3 (build_b08_a3_s1
/// 19 against 18, build_b08_a3_s3 17 against 15) and on none of 10 to 100 blocks of seed 1
/// or of 10 to 15 blocks of seeds 2 and 3 (measured with `kbc bench`), where its states are
/// large and have many successors, for nothing.
pub const SEARCH_BLOCKS: usize = 8;

/// What [`Rung::waiting`] proves of the blocks lifted before a block below them moves.
#[derive(Default)]
struct Waiting {
    /// Each group (one per block below them, g): its blocks and their least extra work.
    groups: Vec<(Vec<usize>, i64)>,
    /// Each block's least work alone, also when it is in the air at some moment before its
    /// goal place is ready: held through g's cycles, or moved twice.
    occupied: std::collections::BTreeMap<usize, i64>,
    /// Each block's least extra work, however the others fare.
    least: std::collections::BTreeMap<usize, i64>,
}

impl Waiting {
    /// The least extra work of all of them: the sum of the groups'.
    fn extra(&self) -> i64 {
        self.groups.iter().map(|(_, cost)| cost).sum()
    }
}

impl Rung {
    /// The lower bound on the makespan of this rung's plans (see [`LowerBound`]), with the
    /// durations of the KB `session` holds (the rung's problem 0).
    pub fn lower_bound(&self, session: &mut Session) -> LowerBound {
        self.lower_bound_of(&self.layout(), session)
    }

    /// The lower bound on the makespan of `layout`'s plans with this rung's family and arms.
    pub fn lower_bound_of(&self, layout: &Layout, session: &mut Session) -> LowerBound {
        use crate::ir::hir::{Args, Term};
        let (init, goal) = (layout.init.clone(), layout.goal.clone());
        let atom = |session: &mut Session, name: &str| Term::Atom(session.intern(name));
        let (arm, block) = (atom(session, "a1"), atom(session, "b1"));
        // Each least duration the bound uses, noting whether every duration it asks for (least
        // and greatest) is a whole number of time units (see `LowerBound`: the bound is then
        // rounded up to one).
        let whole = std::cell::Cell::new(true);
        let bounds = |session: &mut Session, instance: &Term| -> DurationBounds {
            let (min, max) = session.duration_bounds(0, instance);
            if min % UNITS != 0 || max.is_some_and(|max| max % UNITS != 0) {
                whole.set(false);
            }
            (min, max)
        };
        let least = |session: &mut Session, instance: &Term| -> i64 { bounds(session, instance).0 };
        let rounded = |bound: i64| if whole.get() { (bound + UNITS - 1) / UNITS * UNITS } else { bound };
        if self.family == Family::Grid {
            // Each block not on its goal cell moves at least once; no block stands on another,
            // so nothing chains.
            let move_symbol = session.intern("move");
            let mut works = Vec::new();
            let at = |towers: &[Tower]| -> std::collections::BTreeMap<usize, (usize, usize)> {
                towers.iter().flat_map(|(c, t)| t.iter().map(move |b| (*b, *c))).collect()
            };
            let (from, to) = (at(&init), at(&goal));
            let moving = |session: &mut Session, start: (usize, usize), target: (usize, usize)| -> i64 {
                let cell = |v: usize| Term::Int(v as i64);
                let args = [arm.clone(), block.clone(), cell(start.0), cell(start.1), cell(target.0), cell(target.1)];
                least(session, &Term::Compound(move_symbol, Args::from(args)))
            };
            for (b, target) in &to {
                let start = from[b];
                if start != *target {
                    works.push(moving(session, start, *target));
                }
            }
            // A cycle's first block to move finds its goal cell taken (the next block has not
            // started, and a move may start only towards a cell nothing stands on or heads
            // for), so it stops on a third cell first: at least the least such stop adds.
            let mut aside = 0;
            let cells = layout.cells.clone();
            for cycle in grid_cycles(&from, &to) {
                let mut least_extra = i64::MAX;
                for &b in &cycle {
                    let (start, target) = (from[&b], to[&b]);
                    let direct = moving(session, start, target);
                    for &stop in cells.iter().filter(|&&c| c != start && c != target) {
                        let via = moving(session, start, stop) + moving(session, stop, target);
                        least_extra = least_extra.min(via - direct);
                    }
                }
                if least_extra != i64::MAX {
                    aside += least_extra.max(0);
                }
            }
            let arms = self.arms.max(1) as i64;
            let work = (works.iter().sum::<i64>() + aside + arms - 1) / arms;
            let block = works.iter().copied().max().unwrap_or(0);
            return LowerBound {
                makespan: rounded(work.max(block)),
                analytic: rounded(work.max(block)),
                work,
                block,
                chain: 0,
                aside,
                waiting: 0,
                emptying: 0,
                idle: 0,
                searched: 0,
                optimal: false,
            };
        }
        let grip = Term::Compound(session.intern("grip"), Args::from([arm.clone(), block.clone()]));
        let release = Term::Compound(session.intern("release"), Args::from([arm.clone(), block.clone()]));
        let (grip_bounds, release_bounds) = (bounds(session, &grip), bounds(session, &release));
        let (grip, release) = (grip_bounds.0, release_bounds.0);
        let move_symbol = session.intern("move_block");
        let move_bounds = |session: &mut Session, from: (usize, usize), to: (usize, usize)| {
            let cell = |v: usize| Term::Int(v as i64);
            let args = [arm.clone(), block.clone(), cell(from.0), cell(from.1), cell(to.0), cell(to.1)];
            bounds(session, &Term::Compound(move_symbol, Args::from(args)))
        };
        let moving = |session: &mut Session, from: (usize, usize), to: (usize, usize)| -> i64 {
            grip + move_bounds(session, from, to).0 + release
        };
        // Where each block is, and what it stands on (None: the table).
        let place = |towers: &[Tower]| -> std::collections::BTreeMap<usize, ((usize, usize), Option<usize>)> {
            let mut at = std::collections::BTreeMap::new();
            for (cell, tower) in towers {
                for (level, &b) in tower.iter().enumerate() {
                    at.insert(b, (*cell, level.checked_sub(1).map(|l| tower[l])));
                }
            }
            at
        };
        let (from, to) = (place(&init), place(&goal));
        // Where a block may stand on its way: std/blocks.pl ends a move only on the block's goal
        // cell or on a buffer cell (one the goal leaves empty, on its table).
        let cells = layout.cells.clone();
        let n = cells.len();
        let buffers: Vec<(usize, usize)> =
            cells.iter().copied().filter(|c| !to.values().any(|(t, _)| t == c)).collect();
        let is_buffer: Vec<bool> = cells.iter().map(|c| buffers.contains(c)).collect();
        // The least work from one cell to another, each step a whole cycle with the KB's least
        // durations and every stop between them a buffer cell: shortest paths whose
        // intermediate cells are buffers (Floyd-Warshall over those alone), rather than
        // assuming a neighbour is the cheapest cell or that a block may stop anywhere.
        // (Each move's bounds kept too, from cell i to cell j at `i * n + j`, for the search.)
        let mut path = vec![i64::MAX; n * n];
        let mut moves = vec![(0, None); n * n];
        for (i, &a) in cells.iter().enumerate() {
            for (j, &b) in cells.iter().enumerate() {
                if i != j {
                    moves[i * n + j] = move_bounds(session, a, b);
                    path[i * n + j] = grip + moves[i * n + j].0 + release;
                }
            }
        }
        let cycle = path.clone();
        for k in (0..n).filter(|&k| is_buffer[k]) {
            for i in (0..n).filter(|&i| i != k) {
                let ik = path[i * n + k];
                if ik == i64::MAX {
                    continue;
                }
                for j in (0..n).filter(|&j| j != i && j != k) {
                    let kj = path[k * n + j];
                    if kj != i64::MAX && ik + kj < path[i * n + j] {
                        path[i * n + j] = ik + kj;
                    }
                }
            }
        }
        // The least work of a round trip from a block's goal cell back to it (each move changes
        // the cell, so its first stop is a buffer cell). (No buffer cell: no round trip, and 0
        // is still a bound.)
        let round_trip = |cell: (usize, usize)| -> i64 {
            let s = cells.iter().position(|&c| c == cell).expect("a cell of the table");
            (0..n)
                .filter(|&m| m != s && is_buffer[m])
                .map(|m| cycle[s * n + m].saturating_add(path[m * n + s]))
                .min()
                .filter(|&w| w != i64::MAX)
                .unwrap_or(0)
        };
        let mut works = std::collections::BTreeMap::new();
        for (&b, &(target, below)) in &to {
            let (start, was_below) = from[&b];
            let work = if (start, was_below) == (target, below) {
                0
            } else if start == target {
                // Off the cell and back: two cycles at least.
                round_trip(start)
            } else {
                moving(session, start, target)
            };
            works.insert(b, work);
        }
        let total: i64 = works.values().sum();
        // The least work of reaching the target from a first move elsewhere than the target
        // (two moves or more, every stop on the way a buffer cell; None when there is none).
        let via = |start: (usize, usize), target: (usize, usize)| -> Option<i64> {
            let (s, t) = (cells.iter().position(|&c| c == start)?, cells.iter().position(|&c| c == target)?);
            (0..n)
                .filter(|&p| p != s && (p == t || is_buffer[p]))
                .map(|p| {
                    let rest = if p == t { round_trip(target) } else { path[p * n + t] };
                    cycle[s * n + p].saturating_add(rest)
                })
                .min()
                .filter(|&w| w != i64::MAX)
        };
        // A block put down on its way to its goal stands alone on a buffer cell (std/blocks.pl
        // stacks a block only where the goal does): its moves reach that cell from its start
        // (two at least when it is its start cell) and go on to its goal cell.
        let through = |b: usize, buffer: (usize, usize)| -> i64 {
            let [s, t, c] = [from[&b].0, to[&b].0, buffer].map(|x| cells.iter().position(|&y| y == x).expect("a cell"));
            let reach = if s == c { round_trip(buffer) } else { path[s * n + c] };
            reach.saturating_add(path[c * n + t])
        };
        let waiting = self.waiting(
            &init,
            &goal,
            &works,
            &buffers,
            |b, below, k, j| {
                let (start, target) = (from[&b].0, to[&b].0);
                let twice = via(start, target).unwrap_or(i64::MAX);
                if start == target {
                    return (None, twice.min(round_trip(start)));
                }
                let once = moving(session, start, target) - grip - release;
                let held = grip + once.max(j * grip + works[&below] + k * release) + release;
                (Some(held), twice)
            },
            through,
        );
        let aside = self.put_aside(&init, &goal, &works, &buffers, &waiting, through);
        let emptying = Self::emptying(
            (&init, &goal, &to),
            (&cells, &is_buffer),
            (&cycle, &path),
            (grip, release, self.arms.max(1)),
            round_trip,
        );
        // Idle at the ends: how long each block waits at least before its first grip (one
        // grip per block above it at the start) and is done at least before the end (one
        // release per block above it in its goal tower).
        let least_cycle = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| cycle[i * n + j])
            .min();
        let levels = |towers: &[Tower], unit: i64| -> std::collections::BTreeMap<usize, i64> {
            towers
                .iter()
                .flat_map(|(_, t)| t.iter().enumerate().map(move |(l, &b)| (b, (t.len() - 1 - l) as i64 * unit)))
                .collect()
        };
        let (before, after) = (levels(&init, grip), levels(&goal, release));
        let firsts = Self::least_idle(before.values().copied(), least_cycle.unwrap_or(0), self.arms.max(1));
        let lasts = Self::least_idle(after.values().copied(), least_cycle.unwrap_or(0), self.arms.max(1));
        let idle = firsts.iter().chain(&lasts).sum();
        // With u arms at work (the others idle throughout), u * makespan covers the work and
        // the u least idle times at either end; the least over u.
        let work = (1..=self.arms.max(1))
            .map(|u| {
                let idle: i64 = firsts[..u].iter().chain(&lasts[..u]).sum();
                (total + aside.max(waiting.extra()).max(emptying) + idle + u as i64 - 1) / u as i64
            })
            .min()
            .unwrap_or(0);
        // One block's cycles, after its first grip can start and before the blocks above it
        // in its goal tower are placed.
        let block = works
            .iter()
            .filter(|(_, w)| **w > 0)
            .map(|(b, w)| before[b] + waiting.occupied.get(b).copied().unwrap_or(*w).max(*w) + after[b])
            .max()
            .unwrap_or(0);
        // The last cycle of a block of a goal tower comes from another cell, where the block
        // stood: its start cell (there from the start) or a buffer cell (there once a cycle
        // from its start at least has ended: `path`). Each such cell with that time and the
        // least cycle from there into the tower's cell.
        let origins = |b: usize, cell: (usize, usize)| -> Vec<(i64, i64)> {
            let [s, t] = [from[&b].0, cell].map(|x| cells.iter().position(|&y| y == x).expect("a cell"));
            (0..n)
                .filter(|&o| o != t && (o == s || is_buffer[o]))
                .map(|o| (if o == s { 0 } else { path[s * n + o] }, cycle[o * n + t]))
                .filter(|&(there, into)| there != i64::MAX && into != i64::MAX)
                .collect()
        };
        let arms = self.arms.max(1);
        let mut chain = 0;
        for (cell, tower) in &goal {
            let Some(first) = tower.iter().position(|b| works[b] > 0) else { continue };
            // The least time of each last release, from the first block that moves up: one
            // release after the one below, and, from the (arms + 1)th block on, the least
            // over the pairs of the arms + 1 that may share an arm of the upper one's last
            // cycle after the lower one's last release (see `LowerBound::chain`).
            let moving = &tower[first..];
            let into: Vec<Vec<(i64, i64)>> = moving.iter().map(|&b| origins(b, *cell)).collect();
            let mut ends: Vec<i64> = vec![works[&moving[0]]];
            for level in 1..moving.len() {
                let mut end = ends[level - 1] + release;
                if let Some(bottom) = level.checked_sub(arms) {
                    let shared = (bottom..level)
                        .flat_map(|i| (i + 1..=level).map(move |j| (i, j)))
                        .map(|(i, j)| {
                            let last = into[j].iter().map(|&(there, cycle)| ends[i].max(there) + cycle).min();
                            last.map_or(i64::MAX, |last| last + (level - j) as i64 * release)
                        })
                        .min()
                        .unwrap_or(i64::MAX);
                    if shared != i64::MAX {
                        end = end.max(shared);
                    }
                }
                ends.push(end);
            }
            chain = chain.max(*ends.last().expect("the first block's"));
        }
        let searched = if whole.get() && from.len() <= SEARCH_BLOCKS {
            let durations = (grip_bounds, release_bounds, moves.as_slice());
            Self::searched(durations, (&cells, &is_buffer, &path), (&from, &to), self.arms)
        } else {
            None
        };
        let (searched, optimal) = match searched {
            Some(exhaustive::Searched::Optimum(t)) => (t * UNITS, true),
            Some(exhaustive::Searched::AtLeast(t)) => (t * UNITS, false),
            None => (0, false),
        };
        let analytic = rounded(work.max(block).max(chain));
        LowerBound {
            makespan: analytic.max(searched),
            analytic,
            work,
            block,
            chain,
            aside,
            waiting: waiting.extra(),
            emptying,
            idle,
            searched,
            optimal,
        }
    }

    /// [`LowerBound::searched`]: the search of `ladder/exhaustive.rs` on these places, with
    /// the KB's durations (least and greatest, in STN time and whole units, as the caller
    /// checked: a grip, a release, and the move between each two cells) and `path`, the least
    /// work between two cells through buffer cells. None when the goal cannot be reached or
    /// the rung is too large to index with bytes.
    fn searched(
        (grip, release, moves): (DurationBounds, DurationBounds, &[DurationBounds]),
        (cells, is_buffer, path): (&[(usize, usize)], &[bool], &[i64]),
        (from, to): (&Places, &Places),
        arms: usize,
    ) -> Option<exhaustive::Searched> {
        use exhaustive::{Bounds, Spot};
        if cells.len() > u8::MAX as usize || from.len() > u8::MAX as usize {
            return None;
        }
        let whole = |(least, most): DurationBounds| Bounds { least: least / UNITS, most: most.map(|m| m / UNITS) };
        let blocks: Vec<usize> = from.keys().copied().collect();
        let index = |b: usize| blocks.iter().position(|&x| x == b).expect("a block of the rung") as u8;
        let cell = |c: (usize, usize)| cells.iter().position(|&x| x == c).expect("a cell of the table") as u8;
        let spots = |places: &Places| -> Vec<Spot> {
            blocks
                .iter()
                .map(|b| match places[b] {
                    (c, None) => Spot::Table(cell(c)),
                    (c, Some(below)) => Spot::On { below: index(below), cell: cell(c) },
                })
                .collect()
        };
        let problem = exhaustive::Problem {
            cells: cells.len(),
            arms,
            start: spots(from),
            goal: spots(to),
            buffer: is_buffer.to_vec(),
            grip: whole(grip),
            release: whole(release),
            moves: moves.iter().copied().map(whole).collect(),
            path: path.iter().map(|&w| if w == i64::MAX { w } else { w / UNITS }).collect(),
        };
        problem.search(SEARCH_LIMIT)
    }

    /// The least work, beyond each block's least round trip, that the blocks of a cell that
    /// must empty add (see `LowerBound::emptying`). `cycle` and `path` are the least work of
    /// one cycle and of a path of cycles through buffer cells between two cells (indices into
    /// `cells`), `round_trip` a block's least work off a cell and back.
    ///
    /// A cell s counts when its goal tower's bottom block is not the one at the bottom at the
    /// start (so s is empty at some moment T: when its first block's last move from it
    /// starts), and every goal `on(X, Y)` at s with Y at s at the start has X below Y at the
    /// start. Then no block is put on s's stack before T (the first to be would be some X on a
    /// Y that has not left, with X still below it), so the blocks leave s once each, from the
    /// top: a block with i blocks below it leaves at T - i grips at the latest (a block is
    /// gripped only once the one on it is lifted). At T, each block of s above the bottom whose
    /// goal is on s is off s and on no other goal cell (std/blocks.pl stands a block only on
    /// its goal cell or a buffer cell): alone on a buffer cell c, at least
    /// `path(s, c) + path(c, s)` in all; or in the air, on its first move (which lasts i grips
    /// at least, and lands on a buffer c from which it must come back) or on a later one (three
    /// cycles at least: out, on, back), held by an arm of its own (and the bottom block's arm
    /// is gripping it, so `arms - 1` blocks at most are in the air). The extra is the least
    /// over which blocks take which buffer cells (one each).
    fn emptying(
        (init, goal, to): (&[Tower], &[Tower], &Places),
        (cells, is_buffer): (&[(usize, usize)], &[bool]),
        (cycle, path): (&[i64], &[i64]),
        (grip, release, arms): (i64, i64, usize),
        round_trip: impl Fn((usize, usize)) -> i64,
    ) -> i64 {
        let n = cells.len();
        let add = |a: i64, b: i64| if a == i64::MAX || b == i64::MAX { i64::MAX } else { a + b };
        let mut extra = 0;
        for (cell, tower) in init {
            let Some((_, goal_tower)) = goal.iter().find(|(c, _)| c == cell) else { continue };
            if tower.is_empty() || goal_tower.first() == tower.first() {
                continue;
            }
            let level = |b: &usize| tower.iter().position(|x| x == b);
            let nothing_put_back = goal_tower
                .windows(2)
                .all(|w| level(&w[0]).is_none_or(|below| level(&w[1]).is_some_and(|above| above < below)));
            let Some(s) = cells.iter().position(|c| c == cell) else { continue };
            if !nothing_put_back {
                continue;
            }
            let base = round_trip(*cell);
            let buffers: Vec<usize> = (0..n).filter(|&c| c != s && is_buffer[c]).collect();
            // Each buffer cell's extra, for a block standing on it at T, cheapest first.
            let mut on_buffer: Vec<i64> = buffers
                .iter()
                .map(|&c| add(path[s * n + c], path[c * n + s]))
                .filter(|&w| w != i64::MAX)
                .map(|w| (w - base).max(0))
                .collect();
            on_buffer.sort_unstable();
            // Three cycles at least (out, on to another buffer, back): the least extra of a
            // block in the air at T on a later move than its first.
            let later = buffers
                .iter()
                .flat_map(|&a| buffers.iter().filter(move |&&b| b != a).map(move |&b| (a, b)))
                .map(|(a, b)| add(add(path[s * n + a], cycle[a * n + b]), path[b * n + s]))
                .min()
                .unwrap_or(i64::MAX);
            // Each block's extra in the air at T, most first.
            let mut in_air: Vec<i64> = Vec::new();
            for (below, b) in tower.iter().enumerate().skip(1) {
                if to.get(b).is_none_or(|(target, _)| target != cell) {
                    continue;
                }
                let held = grip.saturating_mul(below as i64);
                let first = buffers
                    .iter()
                    .filter(|&&c| cycle[s * n + c] != i64::MAX)
                    .map(|&c| add(grip + (cycle[s * n + c] - grip - release).max(held) + release, path[c * n + s]))
                    .min()
                    .unwrap_or(i64::MAX);
                let least = first.min(later);
                if least == i64::MAX {
                    continue;
                }
                in_air.push((least - base).max(0));
            }
            in_air.sort_unstable_by(|a, b| b.cmp(a));
            // The m blocks of most extra in the air take the m cheapest buffer cells; the
            // others, `arms - 1` at most, are in the air.
            let fewest = in_air.len().saturating_sub(arms - 1);
            let best = (fewest..=in_air.len().min(on_buffer.len()))
                .map(|m| on_buffer[..m].iter().sum::<i64>() + in_air[m..].iter().sum::<i64>())
                .min()
                .unwrap_or(0);
            extra += best;
        }
        extra
    }

    /// The `arms` least of the times `offsets` (one per block), each also repeated `cycle`
    /// later, again and again: how long the arms wait at least before their first cycles (or
    /// after their last), when each arm's first (last) cycle is one block's and two arms'
    /// first (last) cycles of the same block are a whole cycle apart. Padded with zeros to
    /// `arms` when there are fewer blocks, as if an arm started at once.
    fn least_idle(offsets: impl Iterator<Item = i64>, cycle: i64, arms: usize) -> Vec<i64> {
        let mut all: Vec<i64> =
            offsets.flat_map(|o| (0..arms as i64).map(move |r| o.saturating_add(r.saturating_mul(cycle)))).collect();
        all.sort_unstable();
        all.resize(arms, 0);
        all
    }

    /// The least work that blocks which must be lifted before a block below them moves add,
    /// beyond each block's own least work (`works`), and each such block's least work alone.
    ///
    /// Let b stand above g at the start and above g in its goal tower, with g moving at least
    /// once, k blocks between them in the goal tower and j between them at the start.
    /// Everything above g is lifted before g is gripped (a grip wants `clear/1`, which only
    /// lifting the block on top gives), one after another from the top: each of the j blocks
    /// between b and g is gripped only once the one on it is lifted, and lifted a whole grip
    /// later at least. So b's first lift comes j grips before g's first grip at least. b's
    /// last move ends on a block that is in its goal place for good, so after that block's
    /// release (the only thing that gives `clear/1` back after its grip), which comes after
    /// the release of the block below it, and so on down to g's last release: k releases
    /// after g's last cycle. So b either moves twice or more (`twice`: at least the least work
    /// of reaching its goal from a first move elsewhere), or moves once, held by one arm from
    /// its grip to its release, through the j grips, every cycle of g (one after another, from
    /// its first grip to its last release: g's least work at least) and the k releases
    /// (`held`). A block whose goal is on its own cell cannot move once.
    ///
    /// And when g's first grip starts, every such b of g is either in the air, holding an arm
    /// (not the one gripping g), or down on a buffer cell (a cell the goal leaves empty: its
    /// goal place is not ready, and std/blocks.pl puts a block elsewhere only on the table of
    /// such a cell), one block to a cell, from where it moves again (`through(b, cell)`: its
    /// least work through that cell). So the least extra work of g's blocks is an assignment
    /// problem (`least_assignment`): a column per buffer cell, and one per arm that may hold a
    /// block, at `held` (or `twice`, should it be put down later) more than its own work.
    ///
    /// `occupancy(b, g, k, j)` gives b's `(held, twice)`, `held` None when b cannot move once.
    /// Every b is counted with the lowest such g, so in one group only.
    fn waiting(
        &self,
        init: &[Tower],
        goal: &[Tower],
        works: &std::collections::BTreeMap<usize, i64>,
        buffers: &[(usize, usize)],
        mut occupancy: impl FnMut(usize, usize, i64, i64) -> (Option<i64>, i64),
        through: impl Fn(usize, (usize, usize)) -> i64,
    ) -> Waiting {
        let start_of = |b: usize| -> (&Vec<usize>, usize) {
            let (_, tower) = init.iter().find(|(_, t)| t.contains(&b)).expect("every block starts somewhere");
            (tower, tower.iter().position(|&x| x == b).expect("b is in its tower"))
        };
        let mut out = Waiting::default();
        // For each g, its blocks and a row of the assignment for each.
        let mut groups: std::collections::BTreeMap<usize, Vec<(usize, Vec<i64>)>> = std::collections::BTreeMap::new();
        for (_, tower) in goal {
            for (level, &b) in tower.iter().enumerate() {
                let (start, start_level) = start_of(b);
                let below = tower[..level].iter().position(|g| works[g] > 0 && start[..start_level].contains(g));
                let Some(g_level) = below else { continue };
                let g = tower[g_level];
                let k = (level - g_level - 1) as i64;
                let g_start = start[..start_level].iter().position(|&x| x == g).expect("g is below b");
                let j = (start_level - g_start - 1) as i64;
                let (held, twice) = occupancy(b, g, k, j);
                let own = works[&b];
                let in_the_air = held.map_or(twice, |held| held.min(twice));
                out.occupied.insert(b, in_the_air);
                let air = extra(in_the_air, own);
                let row = self.assignment_row(buffers, |c| extra(through(b, c), own), air);
                out.least.insert(b, row.iter().copied().fold(air, i64::min));
                groups.entry(g).or_default().push((b, row));
            }
        }
        for members in groups.into_values() {
            let (blocks, rows): (Vec<usize>, Vec<Vec<i64>>) = members.into_iter().unzip();
            let cost = least_assignment(&rows);
            out.groups.push((blocks, cost));
        }
        out
    }

    /// A block's row of an assignment of `waiting` or `put_aside`: its extra work through
    /// each of the `buffers` (`through`), then `air` for each arm that may hold it (all but
    /// the one the argument is about).
    fn assignment_row(
        &self,
        buffers: &[(usize, usize)],
        through: impl Fn((usize, usize)) -> i64,
        air: i64,
    ) -> Vec<i64> {
        let mut row: Vec<i64> = buffers.iter().map(|&c| through(c)).collect();
        row.extend(std::iter::repeat_n(air, self.arms.saturating_sub(1)));
        row
    }

    /// The least work that blocks put down before their goal places add, beyond each block's
    /// own least work (`works`, 0 for a block in its goal place at the start);
    /// `through(b, buffer)` is block `b`'s least work when it stands on `buffer` (one of
    /// `buffers`, the cells the goal leaves empty) on its way.
    ///
    /// Let t* be the first time a goal tower's bottom that is not in place at the start is put
    /// on its goal cell, and f that bottom. Its cell was empty then: every block that started
    /// on it had been lifted; so had every block that started above f (f is gripped only when
    /// clear). Each of those (but f) whose goal tower's bottom is not in place at the start
    /// cannot be at its goal place at t* (its tower has no bottom yet), so it is either in the
    /// air, holding one of the arms but f's, or down on a buffer cell, to move again. A block
    /// stands on a buffer cell only on the table (the goal stacks nothing there), so those
    /// down at t* stand on as many different buffer cells. The least extra work over every
    /// way of choosing which of them are down (all but `arms - 1` at most) and on which cells
    /// is an assignment problem (`least_assignment`, with one column per arm that may hold a
    /// block: at no cost, or what `waiting` proves of a block held). Every other block's
    /// extra work adds to that (the extra works of different blocks are different arm time):
    /// what `waiting` proves of the groups none of whose blocks are counted here, and of the
    /// rest of each other group each block's least alone. f is unknown, so the least over
    /// every goal tower. (Were there more such blocks than buffer cells and free arms, f could
    /// not be first; the ones beyond count nothing rather than make that claim.)
    fn put_aside(
        &self,
        init: &[Tower],
        goal: &[Tower],
        works: &std::collections::BTreeMap<usize, i64>,
        buffers: &[(usize, usize)],
        waiting: &Waiting,
        through: impl Fn(usize, (usize, usize)) -> i64,
    ) -> i64 {
        let start_of = |b: usize| init.iter().find(|(_, t)| t.contains(&b)).map(|(c, t)| (*c, t));
        let goal_of = |b: usize| goal.iter().find(|(_, t)| t.contains(&b)).map(|(c, t)| (*c, t[0]));
        let in_place = |b: usize| works[&b] == 0;
        let mut least: Option<i64> = None;
        for (cell, tower) in goal {
            let f = tower[0];
            if in_place(f) {
                continue;
            }
            let Some((_, f_tower)) = start_of(f) else { continue };
            let level = f_tower.iter().position(|&b| b == f).expect("f is in its tower");
            let mut lifted: Vec<usize> = f_tower[level + 1..].to_vec();
            if let Some((_, on_cell)) = init.iter().find(|(c, _)| c == cell) {
                lifted.extend(on_cell.iter().copied().filter(|&b| b != f));
            }
            lifted.sort_unstable();
            lifted.dedup();
            // Those that cannot be at their goal places at t*, a row each; a column for each
            // buffer cell and for each arm that may hold one of them.
            let counted: Vec<usize> =
                lifted.into_iter().filter(|&b| goal_of(b).is_some_and(|(_, bottom)| !in_place(bottom))).collect();
            let rows: Vec<Vec<i64>> = counted
                .iter()
                .map(|&b| {
                    let own = works[&b];
                    let air = waiting.occupied.get(&b).map_or(0, |&held| extra(held, own));
                    self.assignment_row(buffers, |c| extra(through(b, c), own), air)
                })
                .collect();
            // The blocks of `waiting`'s groups not counted here add what their group's
            // assignment proves when none of them is, else each its least alone.
            let others: i64 = waiting
                .groups
                .iter()
                .map(|(blocks, cost)| {
                    if blocks.iter().all(|b| !counted.contains(b)) {
                        *cost
                    } else {
                        blocks.iter().filter(|b| !counted.contains(b)).map(|b| waiting.least[b]).sum()
                    }
                })
                .sum();
            let sum = least_assignment(&rows) + others;
            least = Some(least.map_or(sum, |l| l.min(sum)));
        }
        least.unwrap_or(0)
    }
}

/// What a block's least `work` is more than its own least work `own`, capped far below
/// overflow (the assignment adds and subtracts these).
fn extra(work: i64, own: i64) -> i64 {
    work.saturating_sub(own).clamp(0, i64::MAX / 4)
}

/// The least total cost of giving each row of `costs` (each as long as the others) a column
/// of its own: the assignment problem, solved exactly by growing the assignment a row at a
/// time along a cheapest augmenting path, with dual potentials on rows and columns that keep
/// the reduced costs non-negative (the Hungarian method, O(rows² × columns)). Where the rows
/// outnumber the columns, the rows left over cost nothing (for the bound: more blocks than
/// cells and arms would make the moment argued about impossible, a claim it does not make).
fn least_assignment(costs: &[Vec<i64>]) -> i64 {
    let rows = costs.len();
    let Some(width) = costs.first().map(Vec::len) else { return 0 };
    assert!(costs.iter().all(|r| r.len() == width), "rows of one length");
    let columns = width.max(rows);
    let cost = |r: usize, c: usize| costs[r].get(c).copied().unwrap_or(0);
    const NONE: usize = usize::MAX;
    // Column `columns` is a virtual one the row being added starts from.
    let (mut row_potential, mut column_potential) = (vec![0i64; rows], vec![0i64; columns + 1]);
    let mut owner = vec![NONE; columns + 1];
    for row in 0..rows {
        owner[columns] = row;
        let mut slack = vec![i64::MAX; columns];
        let mut came_from = vec![columns; columns];
        let mut visited = vec![false; columns + 1];
        let mut at = columns;
        // Dijkstra over the columns, in reduced costs, until a free column is reached.
        while owner[at] != NONE {
            visited[at] = true;
            let from = owner[at];
            let (mut step, mut next) = (i64::MAX, NONE);
            for c in (0..columns).filter(|&c| !visited[c]) {
                let reduced = cost(from, c) - row_potential[from] - column_potential[c];
                if reduced < slack[c] {
                    slack[c] = reduced;
                    came_from[c] = at;
                }
                if slack[c] < step {
                    (step, next) = (slack[c], c);
                }
            }
            for c in 0..=columns {
                if visited[c] {
                    row_potential[owner[c]] += step;
                    column_potential[c] -= step;
                } else {
                    slack[c] -= step;
                }
            }
            at = next;
        }
        // Flip the path back to the virtual column.
        while at != columns {
            let previous = came_from[at];
            owner[at] = owner[previous];
            at = previous;
        }
    }
    (0..columns).filter(|&c| owner[c] != NONE).map(|c| cost(owner[c], c)).sum()
}

/// What planning one rung gave.
#[derive(Clone, Debug)]
pub struct Row {
    /// The rung.
    pub rung: Rung,
    /// The search used.
    pub search: SearchKind,
    /// `Ok(plan length)` when a plan was found (and validated, and its schedule too), or why
    /// not.
    pub result: Result<usize, String>,
    /// The schedule's makespan and the time the plan would take one action at a time (each
    /// at its minimum duration), in STN time.
    pub makespan: Option<(i64, i64)>,
    /// A lower bound on any plan's makespan (see [`LowerBound`]).
    pub lower_bound: Option<LowerBound>,
    /// States expanded, by every search the plan ran (the second search with the lookahead
    /// too, which may be the one whose plan was kept).
    pub expanded: u64,
    /// Wall-clock time of planning and scheduling, as `kbc plan` does them: the search (and
    /// the second one `Session::plan` may run), the temporal passes and `reassign` with its
    /// detours.
    pub elapsed: Duration,
}

/// Plans `rung` with `search` under `budget` (`max_depth` for the paper's search) in a
/// session (which schedules the plan and, for the heuristic search, runs `reassign` on it),
/// then validates the plan kept with [`validate`] and its schedule with
/// [`validate::validate_timed`]. An invalid plan or schedule is a bug, reported in the row's
/// result rather than hidden.
pub fn run(rung: &Rung, search: SearchKind, budget: Budget, max_depth: Option<u32>) -> Row {
    run_with(rung, search, budget, max_depth, &PlanSettings::default())
}

/// [`run`], with the rest of the search's settings (such as `lookahead`) taken from `base`.
pub fn run_with(rung: &Rung, search: SearchKind, budget: Budget, max_depth: Option<u32>, base: &PlanSettings) -> Row {
    let started = Instant::now();
    let mut db = SourceDb::new();
    let root = db.add(format!("{}.pl", rung.name()), None, rung.source());
    let mut session = Session::open(db, &[root], &mut crate::passes::load::NoIncludes);
    if session.has_errors() {
        let why = "the generated problem does not check".to_string();
        return Row {
            rung: *rung,
            search,
            result: Err(why),
            makespan: None,
            lower_bound: None,
            expanded: 0,
            elapsed: started.elapsed(),
        };
    }
    let lower_bound = Some(rung.lower_bound(&mut session));
    let failed = |message: String, expanded: u64, elapsed: Duration| Row {
        rung: *rung,
        search,
        result: Err(message),
        makespan: None,
        lower_bound,
        expanded,
        elapsed,
    };
    let settings = PlanSettings {
        search,
        max_depth,
        max_states: budget.max_states,
        timeout: budget.deadline.map(|d| d.saturating_duration_since(Instant::now())),
        max_bytes: budget.max_bytes,
        ..base.clone()
    };
    // The time of planning and scheduling, every pass `kbc plan` runs (not the bound, nor the
    // validation below).
    let planning = Instant::now();
    let planned = session.plan(0, &settings, &mut Silent);
    let elapsed = planning.elapsed();
    let planned = match planned {
        Ok(planned) => planned,
        Err(PlanError::Search(failed_search)) => {
            let why = match &failed_search.failure {
                Failure::Exhausted { depth_limit: Some(limit) } => format!("no plan within depth {limit}"),
                Failure::Exhausted { depth_limit: None } => "no plan exists".to_string(),
                Failure::Budget(kind) => format!("{kind:?} budget ran out").to_lowercase(),
                Failure::Condition(error) => format!("OnKB error in schema {}", error.schema),
                Failure::Unsolvable(diagnostic) => diagnostic.message.clone(),
            };
            return failed(why, failed_search.stats.expanded, elapsed);
        }
        Err(PlanError::Unschedulable | PlanError::PlanFile | PlanError::Refinement) => {
            let why = format!("no schedule: {}", first_error(session.diagnostics()));
            let stats = session.search(0, &settings, &mut Silent).map(|s| s.stats).unwrap_or_default();
            return failed(why, stats.expanded, elapsed);
        }
    };
    let length = planned.plan().steps.len();
    let result = check(&mut session, &planned);
    Row {
        rung: *rung,
        search,
        makespan: result.as_ref().ok().copied(),
        result: result.map(|_| length),
        lower_bound,
        expanded: session.states_expanded(0),
        elapsed,
    }
}

/// The first error's message.
fn first_error(diagnostics: &crate::diag::Diagnostics) -> String {
    diagnostics.iter().find(|d| d.severity == crate::diag::Severity::Error).map_or(String::new(), |d| d.message.clone())
}

/// Validates the plan kept with [`validate`] and its schedule with
/// [`validate::validate_timed`]: the makespan and the sequential time, or what went wrong.
fn check(session: &mut Session, planned: &Planned) -> Result<(i64, i64), String> {
    let (plan, timed) = (planned.plan(), &planned.timed);
    let span = session.kb().problems[plan.problem].span;
    let steps = validate::PlanStep::of_plan(session.kb(), plan, span);
    let verdict = session.validate(plan.problem, &steps);
    if verdict.diagnostics.has_errors() {
        return Err(format!("INVALID PLAN (a planner bug): {}", first_error(&verdict.diagnostics)));
    }
    let timed_steps: Vec<validate::PlanStep> =
        crate::ir::schedule::timed_actions(session.kb(), &timed.pop, &timed.schedule)
            .into_iter()
            .map(|a| validate::PlanStep {
                timing: Some((a.time, a.duration)),
                ..validate::PlanStep::named(a.name, span)
            })
            .collect();
    let verdict = session.validate(plan.problem, &timed_steps);
    if verdict.diagnostics.has_errors() {
        return Err(format!("INVALID SCHEDULE (a scheduler bug): {}", first_error(&verdict.diagnostics)));
    }
    let sequential = timed.stn.durations.iter().flatten().map(|b| b.min).sum();
    Ok((timed.schedule.makespan, sequential))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The least assignment by trying every one: each row in turn takes each column still free.
    fn every_assignment(costs: &[Vec<i64>], row: usize, taken: &mut Vec<bool>) -> i64 {
        if row == costs.len() {
            return 0;
        }
        let mut best = i64::MAX;
        for c in 0..taken.len() {
            if !taken[c] {
                taken[c] = true;
                best = best.min(costs[row][c] + every_assignment(costs, row + 1, taken));
                taken[c] = false;
            }
        }
        best
    }

    #[test]
    fn the_least_assignment_is_the_least_of_every_assignment() {
        let mut random = Rng::new(7);
        for round in 0..400 {
            let rows = round % 6;
            let columns = rows + random.below(4);
            // Small costs make ties, and zero columns (as for the arms) are common.
            let costs: Vec<Vec<i64>> =
                (0..rows).map(|_| (0..columns).map(|_| random.below(9) as i64).collect()).collect();
            let expected = every_assignment(&costs, 0, &mut vec![false; columns]);
            assert_eq!(least_assignment(&costs), expected, "costs {costs:?}");
        }
    }
}
