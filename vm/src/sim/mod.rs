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
mod world;

pub use world::World;

use crate::bytecode::Call;
use crate::{Host, Invocation, Poll, Value};
use world::{Primitive, Task};

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
            ("ontable", [_, Value::Int(x), Value::Int(y)]) | ("on", [_, _, Value::Int(x), Value::Int(y)]) => (*x, *y),
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

/// The simulated arms as a [`Host`].
pub struct SimHost {
    world: World,
    /// Program time units the world has been advanced to.
    now: i64,
}

impl SimHost {
    /// A host over `world`, at time 0.
    pub fn new(world: World) -> SimHost {
        SimHost { world, now: 0 }
    }

    /// The world.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// Steps the world up to `now` (program time units).
    pub fn advance_to(&mut self, now: i64) {
        let step = self.world.config.step_units;
        while self.now + step <= now {
            self.world.step();
            self.now += step;
        }
    }

    /// The time of the next physics step if an arm is busy (the earliest an action can
    /// finish), else `None`.
    pub fn next_step(&self) -> Option<i64> {
        let busy = self.world.arms.iter().any(|a| a.task.as_ref().is_some_and(|t| t.outcome.is_none()));
        busy.then_some(self.now + self.world.config.step_units)
    }

    /// The primitives of an invocation: its refinement's steps, or the action itself if it
    /// is a primitive; and the arm that runs them.
    fn primitives(&self, action: &Invocation<'_>, steps: &[Call]) -> Result<(usize, Vec<Primitive>), String> {
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
                return Err(format!("`{text}`: there is no arm `{arm_name}` in the world"));
            };
            if arm.is_some_and(|b| b != a) {
                return Err(format!("`{}` refines into steps of two arms", action.text()));
            }
            arm = Some(a);
            let block = |i: usize| match args.get(i) {
                Some(Arg::Atom(b)) => {
                    self.world.block_index(b).ok_or_else(|| format!("`{text}`: there is no block `{b}` in the world"))
                }
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

fn not_provided(text: &str, action: &Invocation<'_>) -> String {
    let known: Vec<String> = PRIMITIVES.iter().map(|(n, a)| format!("{n}/{a}")).collect();
    let what = if action.steps().is_empty() {
        format!("`{text}` has no refinement into arm-level steps and is not")
    } else {
        format!("`{text}` (a step of `{}`) is not", action.text())
    };
    format!("{what} a primitive of the simulated arms ({})", known.join(", "))
}

impl Host for SimHost {
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), String> {
        self.advance_to(now);
        let (arm, queue) = self.primitives(action, action.steps())?;
        let end_steps = match action.end_steps() {
            [] => None,
            steps => {
                let (end_arm, steps) = self.primitives(action, steps)?;
                if end_arm != arm {
                    return Err(format!("`{}` starts on one arm and ends on another", action.text()));
                }
                Some(steps)
            }
        };
        let a = &mut self.world.arms[arm];
        if let Some(task) = a.task.as_ref().filter(|t| t.outcome.is_none()) {
            return Err(format!("{} is busy with another action (e{})", a.name, task.id));
        }
        a.task = Some(Task {
            id: action.id.0,
            queue: queue.into(),
            end_steps,
            lines: Default::default(),
            wait_steps: 0,
            blocked: 0,
            outcome: None,
        });
        self.world.begin_next(arm);
        Ok(())
    }

    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll {
        self.advance_to(now);
        let Some(index) = self.world.arms.iter().position(|a| a.task.as_ref().is_some_and(|t| t.id == action.id.0))
        else {
            return Poll::Failure(format!("`{}` is not running on any arm", action.text()));
        };
        let task = self.world.arms[index].task.as_mut().expect("found by its task");
        if task.outcome == Some(Ok(())) && task.end_steps.is_some() {
            // The tree polls: the action may end now. Run the end's steps.
            task.queue = task.end_steps.take().expect("checked").into();
            task.outcome = None;
            self.world.begin_next(index);
            return Poll::Running;
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
                Poll::Failure(why)
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
