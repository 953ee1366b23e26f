//! Simulated arms: a [`Host`] that carries out a program's actions in a rigid-body world
//! (feature `sim`).
//!
//! The world ([`World`]) holds a table, blocks and one arm per `available/1` fact of the
//! initial state. The host provides the arm-level primitives of std/arms.pl ([`PRIMITIVES`]):
//! a high-level action runs as the steps its refinement lists ([`Invocation::steps`]), one
//! after another on the arm named by their first argument, and succeeds when the last one
//! does. A primitive fails on its physical precondition: nothing to grip, the wrong block on
//! top, a point out of reach, two grippers closer than the safety distance.
//!
//! Time is virtual: the world advances in fixed steps to the `now` of each host call, and
//! [`SimHost::next_step`] says when it next has news, so a run loop never sleeps. The same
//! program and configuration give the same run.

mod arm;
mod fault;
mod world;

pub use fault::{Fault, FaultKind, FaultKindSpec, FaultSpec, FaultSyntaxError, Rng, When};
pub use world::{Misplaced, Misplacement, World};

use crate::blocks::{ON, ONTABLE};
use crate::bytecode::Call;
use crate::{Host, HostError, Invocation, Poll, Value};
use world::{Placement, Primitive, Task};

/// The arm-level actions the simulated arms provide: name and arity.
pub const PRIMITIVES: &[(&str, usize)] =
    &[("reach", 2), ("move_over", 3), ("descend", 1), ("close", 2), ("lift", 1), ("open", 2), ("home", 1)];

/// The world's dimensions, speeds and time step. Lengths are metres, speeds per second.
#[derive(Clone, Debug)]
pub struct SimConfig {
    /// The side of a table cell: cell (X, Y) is centred at (X * cell_size, Y * cell_size).
    pub cell_size: f64,
    /// The side of a (cubic) block.
    pub block_size: f64,
    /// The shoulder joint's height above the table.
    pub shoulder_height: f64,
    /// Link length beyond what reaching the farthest cell needs (both links share it).
    pub reach_margin: f64,
    /// Joint speed limit, radians per second.
    pub joint_speed: f64,
    /// Gripper speed limit, metres per second.
    pub linear_speed: f64,
    /// Room above the tallest stack when travelling with a block.
    pub clearance: f64,
    /// How much higher each arm travels than the previous one.
    pub layer_spacing: f64,
    /// No gripper moves closer than this to another; a motion held back by another gripper
    /// waits, and fails after `blocked_seconds`.
    pub safety_distance: f64,
    /// How long a motion may be held back before its primitive fails, seconds.
    pub blocked_seconds: f64,
    /// Time to close or open a gripper, seconds.
    pub gripper_seconds: f64,
    /// Program time units per physics step.
    pub step_units: i64,
    /// Program time units per second of simulated time (the program's time scale if one KB
    /// time unit is a second).
    pub units_per_second: i64,
}

impl Default for SimConfig {
    fn default() -> SimConfig {
        SimConfig {
            cell_size: 0.1,
            block_size: 0.05,
            shoulder_height: 0.35,
            reach_margin: 0.15,
            joint_speed: 3.0,
            linear_speed: 1.0,
            clearance: 0.03,
            layer_spacing: 0.06,
            safety_distance: 0.04,
            blocked_seconds: 2.0,
            gripper_seconds: 0.1,
            step_units: 10,
            units_per_second: 1000,
        }
    }
}

impl SimConfig {
    /// Seconds per physics step.
    pub fn step_seconds(&self) -> f64 {
        self.step_units as f64 / self.units_per_second as f64
    }

    fn gripper_steps(&self) -> u32 {
        (self.gripper_seconds / self.step_seconds()).ceil() as u32
    }
}

/// A world that cannot be built from the facts given.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SimError(pub String);

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SimError {}

/// An argument of a [`Fact`].
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Arg {
    /// An atom.
    Atom(String),
    /// An integer.
    Int(i64),
}

/// A ground fact, as the world is described in and read back.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Fact {
    /// The predicate.
    pub name: String,
    /// The arguments.
    pub args: Vec<Arg>,
}

impl Fact {
    /// A fact.
    pub fn new(name: &str, args: Vec<Arg>) -> Fact {
        Fact { name: name.to_string(), args }
    }
}

impl std::fmt::Display for Fact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.name)?;
        for (i, arg) in self.args.iter().enumerate() {
            f.write_str(if i == 0 { "(" } else { ", " })?;
            match arg {
                Arg::Atom(a) => f.write_str(a)?,
                Arg::Int(n) => write!(f, "{n}")?,
            }
        }
        if !self.args.is_empty() {
            f.write_str(")")?;
        }
        Ok(())
    }
}

/// The facts of a program's initial state, for [`World::new`].
pub fn initial_facts(program: &crate::Program) -> Vec<Fact> {
    let m = program.module();
    m.fluents
        .iter()
        .filter(|f| f.initial)
        .map(|f| Fact {
            name: m.symbols[f.functor as usize].clone(),
            args: f.args.iter().map(|&v| arg(program, v)).collect(),
        })
        .collect()
}

/// Every cell (X, Y) the program's fluents mention in `ontable/3` or `on/4`.
pub fn program_cells(program: &crate::Program) -> Vec<(i64, i64)> {
    let m = program.module();
    let mut cells = Vec::new();
    for f in &m.fluents {
        let name = m.symbols[f.functor as usize].as_str();
        let xy = match (name, &f.args[..]) {
            (name, [_, Value::Int(x), Value::Int(y)]) if name == ONTABLE.name => (*x, *y),
            (name, [_, _, Value::Int(x), Value::Int(y)]) if name == ON.name => (*x, *y),
            _ => continue,
        };
        cells.push(xy);
    }
    cells.sort();
    cells.dedup();
    cells
}

fn arg(program: &crate::Program, value: Value) -> Arg {
    match value {
        Value::Int(i) => Arg::Int(i),
        Value::Atom(_) => Arg::Atom(program.value_text(value)),
    }
}

/// The simulated arms as a [`Host`], with the faults to inject.
///
/// One host can run several programs one after another in the same world (a recovery runs
/// the replanned program where the first one stopped): each program's time starts at 0 when
/// [`SimHost::start_program`] is called; [`SimHost::time`] is the world's own clock.
pub struct SimHost {
    world: World,
    /// Program time units the world has been advanced to, from the world's start.
    now: i64,
    /// The world's time when the current program started.
    offset: i64,
    /// Faults not injected yet, in the order given.
    pending: Vec<Fault>,
    /// Faults injected: the world's time and what happened.
    injected: Vec<(i64, String)>,
    rng: Rng,
    /// Sample the poses every this many steps (0: do not record).
    record_every: u64,
    frames: Vec<Frame>,
}

/// The poses of the world at one moment, as [`SimHost::record`] samples them.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Seconds of simulated time.
    pub time: f64,
    /// Each block's position (metres) and rotation (quaternion x, y, z, w), in the order of
    /// [`World::block_names`].
    pub blocks: Vec<[f64; 7]>,
    /// Each gripper's position, in the order of [`World::arm_names`].
    pub grippers: Vec<[f64; 3]>,
    /// Each arm's elbow (the joint between its two links), in the same order.
    pub elbows: Vec<[f64; 3]>,
}

impl SimHost {
    /// A host over `world`, at time 0, without faults.
    pub fn new(world: World) -> SimHost {
        SimHost::with_faults(world, Vec::new(), 0)
    }

    /// A host over `world` that injects `faults`; `seed` draws what a fault leaves open when
    /// it happens (the cell a block is nudged onto).
    pub fn with_faults(world: World, faults: Vec<Fault>, seed: u64) -> SimHost {
        SimHost {
            world,
            now: 0,
            offset: 0,
            pending: faults,
            injected: Vec::new(),
            rng: Rng::new(seed ^ 0x5eed),
            record_every: 0,
            frames: Vec::new(),
        }
    }

    /// Samples the poses of blocks and grippers every `seconds` of simulated time from now on
    /// (rounded to whole physics steps), and once now.
    pub fn record(&mut self, seconds: f64) {
        self.record_every = ((seconds / self.world.config.step_seconds()).round() as u64).max(1);
        self.frames.push(self.world.frame());
    }

    /// The poses sampled so far.
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// The world.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The world's clock, in program time units since it was built.
    pub fn time(&self) -> i64 {
        self.now
    }

    /// Starts counting program time from now: the next program's time 0 is the world's
    /// current time.
    pub fn start_program(&mut self) {
        self.offset = self.now;
    }

    /// The faults injected so far: when (the world's clock) and what happened.
    pub fn injected(&self) -> &[(i64, String)] {
        &self.injected
    }

    /// Steps the world up to program time `now`.
    pub fn advance_to(&mut self, now: i64) {
        self.advance_world_to(self.offset + now);
    }

    fn advance_world_to(&mut self, until: i64) {
        let step = self.world.config.step_units;
        while self.now + step <= until {
            self.inject_due();
            self.world.step();
            self.now += step;
            if self.record_every > 0 && self.world.steps % self.record_every == 0 {
                self.frames.push(self.world.frame());
            }
        }
    }

    /// The time of the next physics step (program time) if an arm is busy (the earliest an
    /// action can finish), else `None`.
    pub fn next_step(&self) -> Option<i64> {
        // Busy: a task is under way, or has failed and the tree has yet to hear of it.
        let busy = self.world.arms.iter().any(|a| a.task.as_ref().is_some_and(|t| !matches!(t.outcome, Some(Ok(())))));
        busy.then_some(self.now - self.offset + self.world.config.step_units)
    }

    /// Injects every pending fault whose moment has come and that can happen now.
    fn inject_due(&mut self) {
        let seconds = self.now as f64 / self.world.config.units_per_second as f64;
        let mut i = 0;
        while i < self.pending.len() {
            let due = matches!(self.pending[i].when, When::At(t) | When::Started(_, t) if t <= seconds + 1e-9);
            match due.then(|| self.inject(&self.pending[i].kind.clone())).flatten() {
                Some(what) => {
                    let fault = self.pending.remove(i);
                    self.injected.push((self.now, format!("{fault}: {what}")));
                }
                None => i += 1,
            }
        }
    }

    /// Makes a fault happen; `None` when it cannot happen now (nothing carried, the block
    /// held) and must wait.
    fn inject(&mut self, kind: &FaultKind) -> Option<String> {
        let world = &mut self.world;
        let unknown_arm = |name: &str| format!("nothing happens: there is no arm `{name}`");
        match kind {
            FaultKind::Drop(arm) => {
                let arm = match arm {
                    Some(name) => match world.arm_index(name) {
                        Some(a) => a,
                        None => return Some(unknown_arm(name)),
                    },
                    None => (0..world.arms.len()).find(|&a| world.carrying(a))?,
                };
                if !world.carrying(arm) {
                    return None;
                }
                world.drop_held(arm)
            }
            FaultKind::Stall(name, seconds) => match world.arm_index(name) {
                Some(a) => {
                    world.stall(a, *seconds);
                    Some(format!("{name} freezes for {seconds:.1} s"))
                }
                None => Some(unknown_arm(name)),
            },
            FaultKind::Stop(name) => match world.arm_index(name) {
                Some(a) => {
                    world.stop(a);
                    Some(format!("{name} stops for good"))
                }
                None => Some(unknown_arm(name)),
            },
            FaultKind::Nudge(name, cell) => {
                let Some(block) = world.block_index(name) else {
                    return Some(format!("nothing happens: there is no block `{name}`"));
                };
                if matches!(world.placement(block), Placement::Held(_)) {
                    return None;
                }
                let top = world.top_of_stack(block);
                let cell = match cell {
                    Some((x, y)) if !world.free_cells().contains(&(*x, *y)) => {
                        return Some(format!("nothing happens: cell ({x}, {y}) is not a free cell of the table"));
                    }
                    Some(cell) => *cell,
                    None => {
                        let free = world.free_cells();
                        if free.is_empty() {
                            return Some("nothing happens: no cell is free".to_string());
                        }
                        free[self.rng.below(free.len())]
                    }
                };
                let what = world.nudge(top, cell);
                Some(if top == block { what } else { format!("{what} (the top of `{name}`'s stack)") })
            }
        }
    }

    /// Brings the world to rest after a program stopped on a fault, so that it can be read
    /// back and planned from: every task is dropped; stalled arms are waited for; idle arms
    /// go to their resting points; each arm still holding a block lifts it to its resting
    /// point (out of the other arms' way), then puts it down on the free cell nearest to where
    /// it held it; a block lying on the table between cells is carried to the free
    /// cell nearest to it by the nearest idle arm. Stopped arms do nothing. Returns a line
    /// for each thing done or that could not be done.
    pub fn recover(&mut self) -> Vec<String> {
        let mut report = Vec::new();
        for arm in &mut self.world.arms {
            arm.task = None;
        }
        let step = self.world.config.step_units;
        while self.world.any_stalled() {
            self.advance_world_to(self.now + step);
        }
        self.settle(0.3);
        let working = |w: &World, a: usize| !w.arms[a].stopped;
        for a in 0..self.world.arms.len() {
            let arm = &self.world.arms[a];
            if working(&self.world, a)
                && arm.holding.is_none()
                && (self.world.gripper_position(a) - arm.rest).norm() > 1e-3
            {
                if let Err(why) = self.run_task(a, vec![Primitive::Home]) {
                    report.push(format!("{} could not go to its resting point: {why}", self.world.arms[a].name));
                }
            }
        }
        // Arms holding a block first take it up to their resting points, out of each other's
        // way: two arms that stopped over one cell would block each other's put-downs there.
        // Each then puts its block down on the free cell nearest to where it held it.
        let mut holding = Vec::new();
        for a in 0..self.world.arms.len() {
            let Some((block, _)) = self.world.arms[a].holding.filter(|_| working(&self.world, a)) else { continue };
            let here = self.world.gripper_position(a);
            holding.push((a, block, (here.x, here.y)));
        }
        for &(a, block, _) in &holding {
            if let Err(why) = self.run_task(a, vec![Primitive::Lift, Primitive::Home]) {
                let (arm, name) = (&self.world.arms[a].name, &self.world.blocks[block].name);
                report.push(format!("{arm} could not take `{name}` to its resting point: {why}"));
            }
        }
        for (a, block, (hx, hy)) in holding {
            if self.world.arms[a].holding.is_none() {
                continue;
            }
            let (arm, name) = (self.world.arms[a].name.clone(), self.world.blocks[block].name.clone());
            let Some((x, y)) = self.world.nearest_free_cell(hx, hy) else {
                report.push(format!("{arm} keeps `{name}`: no cell is free to put it down"));
                continue;
            };
            report.push(match self.run_task(a, put_down(block, (x, y))) {
                Ok(()) => format!("{arm} put `{name}` down on cell ({x}, {y})"),
                Err(why) => format!("{arm} could not put `{name}` down on cell ({x}, {y}): {why}"),
            });
        }
        for block in 0..self.world.blocks.len() {
            if self.world.placement(block) != Placement::Loose {
                continue;
            }
            let name = self.world.blocks[block].name.clone();
            let p = self.world.block_position(block);
            let idle =
                (0..self.world.arms.len()).filter(|&a| working(&self.world, a) && self.world.arms[a].holding.is_none());
            let nearest = idle.min_by(|&a, &b| {
                let d = |i: usize| (self.world.arms[i].model.shoulder - p).xy().norm();
                d(a).total_cmp(&d(b))
            });
            let (Some(a), Some((x, y))) = (nearest, self.world.nearest_free_cell(p.x, p.y)) else {
                report.push(format!("`{name}` stays between cells: no idle arm or no free cell"));
                continue;
            };
            let arm = self.world.arms[a].name.clone();
            let mut steps = vec![Primitive::Reach(block), Primitive::Descend, Primitive::Close(block), Primitive::Lift];
            steps.extend(put_down(block, (x, y)));
            report.push(match self.run_task(a, steps) {
                Ok(()) => format!("{arm} put `{name}`, found between cells, on cell ({x}, {y})"),
                Err(why) => format!("{arm} could not move `{name}` onto cell ({x}, {y}): {why}"),
            });
        }
        self.settle(0.5);
        report
    }

    /// Runs the world for `seconds` with no arm moving, so that falling blocks come to rest.
    fn settle(&mut self, seconds: f64) {
        let units = (seconds * self.world.config.units_per_second as f64) as i64;
        self.advance_world_to(self.now + units);
    }

    /// Runs `steps` on arm `arm` to their end (a minute of simulated time at most).
    fn run_task(&mut self, arm: usize, steps: Vec<Primitive>) -> Result<(), String> {
        self.world.arms[arm].task = Some(Task::new(u32::MAX, steps));
        self.world.begin_next(arm);
        let limit = self.now + 60 * self.world.config.units_per_second;
        loop {
            if let Some(outcome) = self.world.arms[arm].task.as_ref().and_then(|t| t.outcome.clone()) {
                self.world.arms[arm].task = None;
                return outcome;
            }
            if self.now >= limit {
                self.world.arms[arm].task = None;
                return Err("it took more than a minute".to_string());
            }
            self.advance_world_to(self.now + self.world.config.step_units);
        }
    }

    /// The primitives of an invocation: its refinement's steps, or the action itself if it
    /// is a primitive; and the arm that runs them.
    fn primitives(&self, action: &Invocation<'_>, steps: &[Call]) -> Result<(usize, Vec<Primitive>), HostError> {
        let program = action.program();
        let calls: Vec<(String, Vec<Arg>)> = if steps.is_empty() {
            let args = action.args().iter().map(|&v| arg(program, v)).collect();
            vec![(action.name().to_string(), args)]
        } else {
            steps
                .iter()
                .map(|c| (program.import_name(c.import).to_string(), c.args.iter().map(|&v| arg(program, v)).collect()))
                .collect()
        };
        let mut arm = None;
        let mut primitives = Vec::new();
        for (name, args) in calls {
            let text = Fact { name: name.clone(), args: args.clone() }.to_string();
            let Some(Arg::Atom(arm_name)) = args.first() else {
                return Err(not_provided(&text, action));
            };
            let Some(a) = self.world.arm_index(arm_name) else {
                return Err(HostError::Unknown { call: text, what: "arm", name: arm_name.clone() });
            };
            if arm.is_some_and(|b| b != a) {
                return Err(HostError::BadRefinement(format!("`{}` refines into steps of two arms", action.text())));
            }
            arm = Some(a);
            let block = |i: usize| match args.get(i) {
                Some(Arg::Atom(b)) => self.world.block_index(b).ok_or_else(|| HostError::Unknown {
                    call: text.clone(),
                    what: "block",
                    name: b.clone(),
                }),
                _ => Err(not_provided(&text, action)),
            };
            let primitive = match (name.as_str(), &args[1..]) {
                ("reach", [_]) => Primitive::Reach(block(1)?),
                ("move_over", [Arg::Int(x), Arg::Int(y)]) => Primitive::MoveOver(*x, *y),
                ("descend", []) => Primitive::Descend,
                ("close", [_]) => Primitive::Close(block(1)?),
                ("lift", []) => Primitive::Lift,
                ("home", []) => Primitive::Home,
                ("open", [_]) => Primitive::Open(block(1)?),
                _ => return Err(not_provided(&text, action)),
            };
            primitives.push(primitive);
        }
        Ok((arm.expect("at least one step"), primitives))
    }
}

/// The steps that put a held `block` down on `cell` and take the arm home.
fn put_down(block: usize, (x, y): (i64, i64)) -> Vec<Primitive> {
    vec![Primitive::MoveOver(x, y), Primitive::Descend, Primitive::Open(block), Primitive::Lift, Primitive::Home]
}

fn not_provided(text: &str, action: &Invocation<'_>) -> HostError {
    let known: Vec<String> = PRIMITIVES.iter().map(|(n, a)| format!("{n}/{a}")).collect();
    let what = if action.steps().is_empty() {
        format!("`{text}` has no refinement into arm-level steps and is not")
    } else {
        format!("`{text}` (a step of `{}`) is not", action.text())
    };
    HostError::NotProvided(format!("{what} a primitive of the simulated arms ({})", known.join(", ")))
}

impl Host for SimHost {
    fn runs(&self, name: &str, arity: usize) -> bool {
        PRIMITIVES.contains(&(name, arity))
    }

    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), HostError> {
        self.advance_to(now);
        let (arm, queue) = self.primitives(action, action.steps())?;
        let end_steps = match action.end_steps() {
            [] => None,
            steps => {
                let (end_arm, steps) = self.primitives(action, steps)?;
                if end_arm != arm {
                    return Err(HostError::BadRefinement(format!(
                        "`{}` starts on one arm and ends on another",
                        action.text()
                    )));
                }
                Some(steps)
            }
        };
        let a = &mut self.world.arms[arm];
        if let Some(task) = a.task.as_ref().filter(|t| t.outcome.is_none()) {
            return Err(HostError::Busy { resource: a.name.clone(), holder: crate::bytecode::EventId(task.id) });
        }
        a.task = Some(Task { end_steps, ..Task::new(action.id.0, queue) });
        self.world.begin_next(arm);
        // Faults due when this action starts happen now.
        let text = action.text();
        let seconds = self.now as f64 / self.world.config.units_per_second as f64;
        for fault in &mut self.pending {
            if let When::OnStart(prefix) = &fault.when
                && text.starts_with(prefix.as_str())
            {
                fault.when = When::Started(prefix.clone(), seconds);
            }
        }
        self.inject_due();
        Ok(())
    }

    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll {
        self.advance_to(now);
        let Some(index) = self.world.arms.iter().position(|a| a.task.as_ref().is_some_and(|t| t.id == action.id.0))
        else {
            return Poll::Failure(HostError::NotRunning(format!("`{}` is not running on any arm", action.text())));
        };
        let task = self.world.arms[index].task.as_mut().expect("found by its task");
        if task.outcome == Some(Ok(())) && task.end_steps.is_some() {
            // The tree polls: the action may end now. Run the end's steps (which may fail at
            // once, on a stopped arm).
            task.queue = task.end_steps.take().expect("checked").into();
            task.outcome = None;
            self.world.begin_next(index);
        }
        let arm = &mut self.world.arms[index];
        match arm.task.as_ref().and_then(|t| t.outcome.clone()) {
            None => Poll::Running,
            Some(Ok(())) => {
                arm.task = None;
                Poll::Success
            }
            Some(Err(why)) => {
                arm.task = None;
                Poll::Failure(HostError::Failed(why))
            }
        }
    }

    fn halt(&mut self, action: &Invocation<'_>, now: i64) {
        self.advance_to(now);
        for arm in &mut self.world.arms {
            if arm.task.as_ref().is_some_and(|t| t.id == action.id.0) {
                arm.task = None;
            }
        }
    }
}

impl crate::run::VirtualHost for SimHost {
    fn next_completion(&self, now: i64) -> Option<i64> {
        self.next_step().map(|t| t.max(now + 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn atom(s: &str) -> Arg {
        Arg::Atom(s.to_string())
    }

    #[test]
    fn recovery_puts_down_blocks_held_by_arms_in_each_others_way() {
        // Two arms stop holding blocks over the same part of the table, each in the other's
        // way (as after a move that one of them could not finish): recovery must still put
        // both blocks down and free both arms.
        let facts = vec![
            Fact::new("ontable", vec![atom("b1"), Arg::Int(1), Arg::Int(1)]),
            Fact::new("ontable", vec![atom("b2"), Arg::Int(3), Arg::Int(3)]),
            Fact::new("available", vec![atom("a1")]),
            Fact::new("available", vec![atom("a2")]),
        ];
        let cells = [(1, 1), (2, 2), (3, 3), (2, 1)];
        let world = World::new(SimConfig::default(), &facts, &cells).expect("a world");
        let mut host = SimHost::new(world);
        let (b1, b2) = (host.world.block_index("b1").unwrap(), host.world.block_index("b2").unwrap());
        let grip = |b: usize| vec![Primitive::Reach(b), Primitive::Descend, Primitive::Close(b), Primitive::Lift];
        assert_eq!(host.run_task(0, grip(b1)), Ok(()));
        assert_eq!(host.run_task(1, grip(b2)), Ok(()));
        assert_eq!(host.run_task(0, vec![Primitive::MoveOver(2, 2)]), Ok(()));
        // a2 stops with its gripper 3 cm from a1's, as two arms that blocked each other do.
        let spot = host.world.gripper_position(0) + nalgebra::Vector3::new(0.03, 0.0, 0.0);
        host.world.arms[1].joints = host.world.arms[1].model.inverse(spot).expect("reachable");
        host.advance_world_to(host.now + host.world.config.step_units);
        let report = host.recover();
        for block in ["b1", "b2"] {
            let put = format!("put `{block}` down on cell");
            assert!(report.iter().any(|line| line.contains(&put)), "{report:?}");
        }
        let (facts, unaccounted) = host.world.facts();
        assert!(unaccounted.is_empty(), "{unaccounted:?}");
        let texts: Vec<String> = facts.iter().map(Fact::to_string).collect();
        for fact in ["available(a1)", "available(a2)", "clear(b1)", "clear(b2)"] {
            assert!(texts.iter().any(|t| t == fact), "{fact} after {report:?}: {texts:?}");
        }
    }
}
