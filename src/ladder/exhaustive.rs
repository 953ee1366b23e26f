//! A bound on a rung's makespan by search: A* over the timed states of std/blocks.pl's rules
//! ([`LowerBound::searched`](super::LowerBound::searched)).
//!
//! The analytic bound of [`Rung::lower_bound_of`](super::Rung::lower_bound_of) argues about a
//! few moments of any plan; on a small rung it can sit a time unit or two below the optimum
//! (reverse_b03_a3_s2: a corner tower with one buffer cell next to it; bound 10, optimum 12),
//! and then a plan that is optimal looks 20% off. This module searches the rung's schedules
//! themselves, in whole time units, with the separation between ordered snap actions taken as
//! zero (events at one instant happen one after another, each seeing the ones before):
//!
//! - a state is where each block stands and what each arm is doing, with the time it has done
//!   it for (arms sorted: they are interchangeable); a snap action costs nothing and a tick of
//!   the clock one unit;
//! - the rules are std/blocks.pl's, as its text states them: an idle arm grips a clear block
//!   that no arm is gripping and that does not stand where the goal wants it; a gripped block
//!   is carried to another cell, its goal cell or a buffer cell (one the goal leaves empty); it
//!   comes down, after the move's least duration, on the table where no block stands (the goal
//!   cell of a block the goal puts on the table, or a buffer cell) or on the clear top block,
//!   not being gripped, that the goal stacks it on; the arm releases it;
//! - the clock ticks only while some action has not yet run its least duration (a schedule
//!   with a gap where none has can be shifted to close it), and not past any action's greatest
//!   duration;
//! - the estimate of the time left is, for each goal tower, the chain of its blocks not yet in
//!   place (each block's least remaining arm time, and one least release after the block below
//!   it), and all blocks' remaining arm time shared by the arms; both are at most the time left.
//!
//! With whole durations, the least makespan over these schedules is at most that of any plan
//! kbc may output (which separates its ordered snap actions by a positive amount), so the
//! search proves a bound: the optimum when it reaches the goal within its budget, else the
//! least estimate over its open states (A* keeps one of an optimal schedule's states open,
//! reached at its least time). `tests/optimum.rs` holds it against an optimum found by a
//! search written apart from this one.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// Where a block stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(super) enum Spot {
    /// On the table at a cell (an index into the rung's cells).
    Table(u8),
    /// On a block (an index into the blocks), in the stack at a cell.
    On { below: u8, cell: u8 },
    /// Carried by an arm.
    Air,
}

impl Spot {
    fn cell(self) -> Option<u8> {
        match self {
            Spot::Table(cell) | Spot::On { cell, .. } => Some(cell),
            Spot::Air => None,
        }
    }
}

/// What an arm is doing; `done` counts the whole time units of a durative action so far (up to
/// its greatest duration, or its least when it has none).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Job {
    Idle,
    Grip {
        block: u8,
        done: u8,
    },
    /// Gripped, not lifted yet.
    Hold {
        block: u8,
    },
    Carry {
        block: u8,
        from: u8,
        to: u8,
        done: u8,
    },
    /// Put down, not released yet.
    Down {
        block: u8,
    },
    Release {
        block: u8,
        done: u8,
    },
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct State {
    spots: Vec<Spot>,
    jobs: Vec<Job>,
}

/// A durative action's least and greatest durations, in whole time units.
#[derive(Clone, Copy, Debug)]
pub(super) struct Bounds {
    pub least: i64,
    pub most: Option<i64>,
}

impl Bounds {
    /// How far `done` counts: past the least duration only a greatest one matters.
    fn cap(self) -> i64 {
        self.most.unwrap_or(self.least)
    }
}

/// A rung as the search sees it: dense indices for cells and blocks, whole time units.
pub(super) struct Problem {
    /// The number of cells.
    pub cells: usize,
    pub arms: usize,
    pub start: Vec<Spot>,
    pub goal: Vec<Spot>,
    /// Cells the goal leaves empty.
    pub buffer: Vec<bool>,
    pub grip: Bounds,
    pub release: Bounds,
    /// The move from cell i to cell j at `i * cells + j`.
    pub moves: Vec<Bounds>,
    /// The least arm time from one cell to another: whole cycles (grip, move, release), every
    /// stop between a buffer cell; `i64::MAX` when there is no way.
    pub path: Vec<i64>,
}

/// What the search proved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Searched {
    /// The least makespan.
    Optimum(i64),
    /// The budget ran out: every makespan is at least this.
    AtLeast(i64),
}

impl Problem {
    fn clear(&self, s: &State, b: u8) -> bool {
        let covered = s.spots.iter().any(|spot| matches!(spot, Spot::On { below, .. } if *below == b));
        let held = s.jobs.iter().any(|job| {
            matches!(job, Job::Hold { block } | Job::Carry { block, .. } | Job::Down { block } | Job::Release { block, .. } if *block == b)
        });
        !covered && !held
    }

    fn gripping(&self, s: &State, b: u8) -> bool {
        s.jobs.iter().any(|job| matches!(job, Job::Grip { block, .. } if *block == b))
    }

    /// The top block of the stack at `cell` (the one standing there with nothing on it), if
    /// any block stands there.
    fn top(&self, s: &State, cell: u8) -> Option<u8> {
        let covered = |b: u8| s.spots.iter().any(|spot| matches!(spot, Spot::On { below, .. } if *below == b));
        (0..s.spots.len() as u8).find(|&b| s.spots[b as usize].cell() == Some(cell) && !covered(b))
    }

    /// The states one snap action leads to, into `out`.
    fn events(&self, s: &State, out: &mut Vec<State>) {
        for (i, &job) in s.jobs.iter().enumerate() {
            if s.jobs[..i].contains(&job) {
                continue; // an arm doing the same gives the same states
            }
            let then = |job: Job, moved: Option<(u8, Spot)>| {
                let mut next = s.clone();
                next.jobs[i] = job;
                if let Some((b, spot)) = moved {
                    next.spots[b as usize] = spot;
                }
                next.jobs.sort_unstable();
                next
            };
            match job {
                Job::Idle => {
                    for b in 0..s.spots.len() as u8 {
                        let spot = s.spots[b as usize];
                        if spot != Spot::Air
                            && spot != self.goal[b as usize]
                            && self.clear(s, b)
                            && !self.gripping(s, b)
                        {
                            out.push(then(Job::Grip { block: b, done: 0 }, None));
                        }
                    }
                }
                Job::Grip { block, done } if i64::from(done) >= self.grip.least => {
                    out.push(then(Job::Hold { block }, None));
                }
                Job::Hold { block } => {
                    let from = s.spots[block as usize].cell().expect("a gripped block stands");
                    let goal_cell = self.goal[block as usize].cell();
                    for to in 0..self.cells as u8 {
                        if to != from && (goal_cell == Some(to) || self.buffer[to as usize]) {
                            let carry = Job::Carry { block, from, to, done: 0 };
                            out.push(then(carry, Some((block, Spot::Air))));
                        }
                    }
                }
                Job::Carry { block, from, to, done } if i64::from(done) >= self.move_bounds(from, to).least => {
                    let wanted = self.goal[block as usize];
                    let spot = match self.top(s, to) {
                        None if wanted == Spot::Table(to) || self.buffer[to as usize] => Some(Spot::Table(to)),
                        None => None,
                        Some(top) => {
                            let on = Spot::On { below: top, cell: to };
                            (wanted == on && self.clear(s, top) && !self.gripping(s, top)).then_some(on)
                        }
                    };
                    if let Some(spot) = spot {
                        out.push(then(Job::Down { block }, Some((block, spot))));
                    }
                }
                Job::Down { block } => out.push(then(Job::Release { block, done: 0 }, None)),
                Job::Release { done, .. } if i64::from(done) >= self.release.least => {
                    out.push(then(Job::Idle, None));
                }
                _ => {}
            }
        }
    }

    fn move_bounds(&self, from: u8, to: u8) -> Bounds {
        self.moves[from as usize * self.cells + to as usize]
    }

    /// The state one time unit later: None when no action is short of its least duration, or
    /// one has run its greatest.
    fn tick(&self, s: &State) -> Option<State> {
        let mut next = s.clone();
        let mut short = false;
        for job in &mut next.jobs {
            let (done, bounds) = match job {
                Job::Grip { done, .. } => (done, self.grip),
                Job::Release { done, .. } => (done, self.release),
                Job::Carry { from, to, done, .. } => (done, self.move_bounds(*from, *to)),
                _ => continue,
            };
            let d = i64::from(*done);
            if bounds.most.is_some_and(|most| d >= most) {
                return None;
            }
            short |= d < bounds.least;
            if d < bounds.cap() {
                *done += 1;
            }
        }
        short.then(|| {
            next.jobs.sort_unstable();
            next
        })
    }

    /// The least arm time a block standing at `spot` still needs: none in its goal place,
    /// else the cycles to its goal cell (off it and back when it is already there).
    fn standing(&self, b: u8, spot: Spot) -> i64 {
        let goal = self.goal[b as usize];
        let (Some(at), Some(target)) = (spot.cell(), goal.cell()) else { return 0 };
        if spot == goal {
            return 0;
        }
        let n = self.cells;
        if at != target {
            return self.path[at as usize * n + target as usize];
        }
        (0..n)
            .filter(|&c| c != at as usize && self.buffer[c])
            .map(|c| self.path[at as usize * n + c].saturating_add(self.path[c * n + at as usize]))
            .min()
            .unwrap_or(i64::MAX)
    }

    /// Each block's least arm time still needed, less what its arm has done of it.
    fn remaining(&self, s: &State) -> Vec<i64> {
        let mut left: Vec<i64> = (0..s.spots.len() as u8).map(|b| self.standing(b, s.spots[b as usize])).collect();
        for job in &s.jobs {
            match *job {
                Job::Grip { block, done } => left[block as usize] -= i64::from(done).min(self.grip.least),
                Job::Hold { block } => left[block as usize] -= self.grip.least,
                Job::Carry { block, from, to, done } => {
                    let target = self.goal[block as usize].cell().expect("a goal cell");
                    let after = if to == target { 0 } else { self.path[to as usize * self.cells + target as usize] };
                    let moving = (self.move_bounds(from, to).least - i64::from(done)).max(0);
                    left[block as usize] = (moving + self.release.least).saturating_add(after);
                }
                Job::Down { block } => left[block as usize] += self.release.least,
                Job::Release { block, done } => left[block as usize] += (self.release.least - i64::from(done)).max(0),
                Job::Idle => {}
            }
        }
        left
    }

    /// A lower bound on the time left from `s`, None when the goal cannot be reached from it
    /// (a block in its goal place, which no arm may grip again, stands on one that is not).
    fn estimate(&self, s: &State, towers: &[Vec<u8>]) -> Option<i64> {
        let left = self.remaining(s);
        if left.contains(&i64::MAX) {
            return None;
        }
        let mut chain = 0;
        for tower in towers {
            let mut end: Option<i64> = None;
            for &b in tower {
                let in_place = s.spots[b as usize] == self.goal[b as usize] && left[b as usize] == 0;
                match end {
                    None if in_place => continue,
                    None => end = Some(left[b as usize]),
                    Some(below) => {
                        if in_place {
                            return None; // on a block that must still be released or moved
                        }
                        end = Some(left[b as usize].max(below + self.release.least));
                    }
                }
            }
            chain = chain.max(end.unwrap_or(0));
        }
        let arms = self.arms.max(1) as i64;
        let shared = (left.iter().sum::<i64>() + arms - 1) / arms;
        Some(chain.max(shared))
    }

    /// The goal's towers, bottom first (blocks by index).
    fn towers(&self) -> Vec<Vec<u8>> {
        let mut towers = Vec::new();
        for (b, spot) in self.goal.iter().enumerate() {
            if let Spot::Table(_) = spot {
                let mut tower = vec![b as u8];
                while let Some(up) = self
                    .goal
                    .iter()
                    .position(|s| matches!(s, Spot::On { below, .. } if *below == *tower.last().unwrap()))
                {
                    tower.push(up as u8);
                }
                towers.push(tower);
            }
        }
        towers
    }

    /// A* from the start until the goal (every block in its goal place, every arm idle) or
    /// `limit` states stored. None when the goal cannot be reached at all.
    pub(super) fn search(&self, limit: usize) -> Option<Searched> {
        let towers = self.towers();
        let start = State { spots: self.start.clone(), jobs: vec![Job::Idle; self.arms] };
        let mut best: HashMap<State, i64> = HashMap::new();
        let mut open: BinaryHeap<(Reverse<i64>, i64, State)> = BinaryHeap::new();
        let h = self.estimate(&start, &towers)?;
        best.insert(start.clone(), 0);
        open.push((Reverse(h), 0, start));
        let mut next = Vec::new();
        while let Some((Reverse(f), time, state)) = open.pop() {
            if best.get(&state).is_some_and(|&known| known < time) {
                continue;
            }
            if state.spots == self.goal && state.jobs.iter().all(|j| *j == Job::Idle) {
                return Some(Searched::Optimum(time));
            }
            if best.len() >= limit {
                return Some(Searched::AtLeast(f));
            }
            next.clear();
            self.events(&state, &mut next);
            let ticked = self.tick(&state);
            let costs = std::iter::repeat_n(time, next.len()).chain(ticked.is_some().then_some(time + 1));
            for (s, cost) in next.drain(..).chain(ticked).zip(costs) {
                if best.get(&s).is_some_and(|&known| known <= cost) {
                    continue;
                }
                let Some(h) = self.estimate(&s, &towers) else { continue };
                best.insert(s.clone(), cost);
                open.push((Reverse(cost + h), cost, s));
            }
        }
        None
    }
}
