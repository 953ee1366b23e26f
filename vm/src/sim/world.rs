//! The rigid-body world: a table, blocks as dynamic cuboids, and one kinematic gripper per
//! arm that carries a gripped block through a fixed joint. The world is built from the
//! program's initial facts (`ontable/3`, `on/4`, `available/1`) and read back into facts at
//! the end, from the bodies' poses alone.
//!
//! Frames: metres, z up, the table's top at z = 0. Cell (X, Y) is centred at
//! (X * cell_size, Y * cell_size). Physics runs in f32 (rapier's glam vectors); kinematics in
//! f64 (nalgebra); [`to_glam`] and [`from_glam`] convert at the boundary.

use std::collections::BTreeMap;

use nalgebra::Vector3;
use rapier3d::prelude::{
    ColliderBuilder, FixedJointBuilder, ImpulseJointHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle, Vector,
};

use super::arm::{ArmModel, Joints, Line};
use super::{Arg, Fact, SimConfig, SimError};
use crate::blocks::{AVAILABLE, CLEAR, GRIPPED, ON, ONTABLE};

pub(crate) fn to_glam(v: Vector3<f64>) -> Vector {
    Vector::new(v.x as f32, v.y as f32, v.z as f32)
}

pub(crate) fn from_glam(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// A block of the world.
pub(crate) struct Block {
    pub(crate) name: String,
    pub(crate) body: RigidBodyHandle,
}

/// One arm-level step being carried out, or queued.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Primitive {
    /// Move the gripper above block `.0` at a safe height (the arm sees where it is).
    Reach(usize),
    /// Move the gripper above cell (x, y) at a safe height.
    MoveOver(i64, i64),
    /// Lower the gripper onto whatever stands under it (with a held block: until the block
    /// rests on it).
    Descend,
    /// Close the gripper on block `.0`, which must be the top block right under it.
    Close(usize),
    /// Raise the gripper to a safe height.
    Lift,
    /// Go to the arm's resting point beside the table, at a safe height.
    Home,
    /// Open the gripper, letting go of block `.0`.
    Open(usize),
}

/// What an arm is doing.
pub(crate) struct Task {
    /// The invocation it serves (the start event's number).
    pub(crate) id: u32,
    /// Steps not started yet.
    pub(crate) queue: std::collections::VecDeque<Primitive>,
    /// The steps of the action's end, run once the tree polls for it.
    pub(crate) end_steps: Option<Vec<Primitive>>,
    /// The motion of the current step: lines to follow, then steps to wait.
    pub(crate) lines: std::collections::VecDeque<Line>,
    pub(crate) wait_steps: u32,
    /// Consecutive steps the motion has been held back by another gripper.
    pub(crate) blocked: u32,
    /// Set when the task ends.
    pub(crate) outcome: Option<Result<(), String>>,
}

impl Task {
    /// A task that runs `steps`.
    pub(crate) fn new(id: u32, steps: Vec<Primitive>) -> Task {
        Task {
            id,
            queue: steps.into(),
            end_steps: None,
            lines: Default::default(),
            wait_steps: 0,
            blocked: 0,
            outcome: None,
        }
    }
}

pub(crate) struct Arm {
    pub(crate) name: String,
    pub(crate) model: ArmModel,
    pub(crate) joints: Joints,
    /// Where the gripper rests when the arm is idle, beside the table in front of the base.
    pub(crate) rest: Vector3<f64>,
    pub(crate) gripper: RigidBodyHandle,
    pub(crate) holding: Option<(usize, ImpulseJointHandle)>,
    pub(crate) task: Option<Task>,
    /// A stall fault: the arm does not move before this step.
    pub(crate) stalled_until: u64,
    /// A stop fault: the arm never moves again.
    pub(crate) stopped: bool,
    /// A block that slipped from the gripper, not yet reported to a task.
    pub(crate) lost: Option<usize>,
}

/// The simulated world.
pub struct World {
    pub(crate) physics: PhysicsWorld,
    pub(crate) config: SimConfig,
    pub(crate) blocks: Vec<Block>,
    pub(crate) arms: Vec<Arm>,
    /// The cells the program mentions, for the read-back.
    pub(crate) cells: Vec<(i64, i64)>,
    /// Physics steps taken.
    pub(crate) steps: u64,
}

/// A block the blocks-world facts cannot describe, as [`World::facts`] reports it.
#[derive(Clone, Debug, PartialEq)]
pub struct Misplaced {
    /// The block's name.
    pub block: String,
    /// Where its centre is, in metres.
    pub position: [f64; 3],
    /// Why no fact describes it.
    pub why: Misplacement,
}

/// Why a block is [`Misplaced`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Misplacement {
    /// Flat on the table but between cells: an arm can still pick it up.
    BetweenCells,
    /// Off the table, leaning, or on nothing: why.
    Lost(String),
}

impl std::fmt::Display for Misplaced {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [x, y, z] = self.position;
        write!(f, "`{}` is at ({x:.3}, {y:.3}, {z:.3}) m, ", self.block)?;
        match &self.why {
            Misplacement::BetweenCells => f.write_str("on the table between cells"),
            Misplacement::Lost(why) => f.write_str(why),
        }
    }
}

/// Where a block is, as the read-back sees it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Placement {
    /// Held by an arm.
    Held(usize),
    /// Resting flat on the table, on a cell.
    OnTable(i64, i64),
    /// Resting flat on another block, on a cell.
    On(usize, i64, i64),
    /// Resting flat on the table, but not on a cell: an arm can pick it up.
    Loose,
    /// Anywhere else (off the table, leaning, on nothing): why.
    Lost(String),
}

impl World {
    /// Builds the world from facts: `ontable(B, X, Y)` and `on(B, B1, X, Y)` place blocks,
    /// `available(A)` adds an arm; `cells` are every cell the task mentions (the table covers
    /// them all).
    pub fn new(config: SimConfig, facts: &[Fact], cells: &[(i64, i64)]) -> Result<World, SimError> {
        let mut physics = PhysicsWorld::new();
        physics.gravity = Vector::new(0.0, 0.0, -9.81);
        physics.integration_parameters.dt = config.step_seconds() as f32;
        let mut cells: Vec<(i64, i64)> = cells.to_vec();
        let mut on_table: BTreeMap<String, (i64, i64)> = BTreeMap::new();
        let mut on_block: BTreeMap<String, String> = BTreeMap::new();
        let mut arm_names: Vec<String> = Vec::new();
        for fact in facts {
            match (fact.name.as_str(), &fact.args[..]) {
                (name, [Arg::Atom(b), Arg::Int(x), Arg::Int(y)]) if name == ONTABLE.name => {
                    on_table.insert(b.clone(), (*x, *y));
                    cells.push((*x, *y));
                }
                (name, [Arg::Atom(b), Arg::Atom(below), Arg::Int(x), Arg::Int(y)]) if name == ON.name => {
                    on_block.insert(b.clone(), below.clone());
                    cells.push((*x, *y));
                }
                (name, [Arg::Atom(a)]) if name == AVAILABLE.name && !arm_names.contains(a) => arm_names.push(a.clone()),
                _ => {}
            }
        }
        cells.sort();
        cells.dedup();
        if cells.is_empty() {
            return Err(SimError("no block stands on a cell: the world needs `ontable/3` facts".into()));
        }
        if arm_names.is_empty() {
            return Err(SimError("no arm: the world needs `available/1` facts".into()));
        }
        let c = config.cell_size;
        let (min_x, max_x) = (cells.iter().map(|p| p.0).min().unwrap(), cells.iter().map(|p| p.0).max().unwrap());
        let (min_y, max_y) = (cells.iter().map(|p| p.1).min().unwrap(), cells.iter().map(|p| p.1).max().unwrap());
        let centre = Vector3::new((min_x + max_x) as f64 * c / 2.0, (min_y + max_y) as f64 * c / 2.0, 0.0);
        let half = Vector3::new((max_x - min_x + 1) as f64 * c / 2.0, (max_y - min_y + 1) as f64 * c / 2.0, 0.0);
        // The table: a slab under the cells, wide enough to reach under the arms' resting
        // points (so a block that slips there lands on the table, not the floor).
        let table = half.norm() + 0.1;
        physics.insert(
            RigidBodyBuilder::fixed().translation(to_glam(centre - Vector3::new(0.0, 0.0, 0.05))),
            ColliderBuilder::cuboid(table as f32, table as f32, 0.05).friction(0.8),
        );
        // Blocks, stack by stack: the stack on each table block, bottom up.
        let h = config.block_size / 2.0;
        let mut blocks = Vec::new();
        let mut placed: BTreeMap<String, usize> = BTreeMap::new();
        for (bottom, &(x, y)) in &on_table {
            let mut level = 0;
            let mut name = bottom.clone();
            loop {
                if placed.contains_key(&name) {
                    return Err(SimError(format!("block `{name}` is in two places in the initial state")));
                }
                let at = Vector3::new(x as f64 * c, y as f64 * c, h + level as f64 * 2.0 * h);
                let (body, _) = physics.insert(
                    RigidBodyBuilder::dynamic().translation(to_glam(at)),
                    ColliderBuilder::cuboid(h as f32, h as f32, h as f32).friction(0.8).density(500.0),
                );
                placed.insert(name.clone(), blocks.len());
                blocks.push(Block { name: name.clone(), body });
                match on_block.iter().find(|(_, below)| **below == name) {
                    Some((above, _)) => name = above.clone(),
                    None => break,
                }
                level += 1;
            }
        }
        if let Some(lost) = on_block.keys().find(|b| !placed.contains_key(*b)) {
            return Err(SimError(format!("block `{lost}` stands on a stack with no bottom on the table")));
        }
        // Arms around the table, evenly spread on a circle outside it, their links long
        // enough to reach every cell from the table top up to a tall stack.
        let radius = half.norm() + 0.12;
        let n = arm_names.len();
        let mut arms = Vec::new();
        for (i, name) in arm_names.into_iter().enumerate() {
            let angle = std::f64::consts::TAU * i as f64 / n as f64 + std::f64::consts::FRAC_PI_4;
            let shoulder = centre + Vector3::new(radius * angle.cos(), radius * angle.sin(), config.shoulder_height);
            let far = radius + half.norm();
            let link = ((far * far + config.shoulder_height.powi(2)).sqrt() + config.reach_margin) / 2.0;
            let model = ArmModel {
                shoulder,
                upper: link,
                fore: link,
                joint_speed: config.joint_speed,
                linear_speed: config.linear_speed,
            };
            // Rest: just outside the table's cells, between the base and the table, at the
            // shoulder's height; an idle arm (or one waiting with a block) is out of the way.
            let outward = Vector3::new(angle.cos(), angle.sin(), 0.0);
            let rest = centre + outward * (half.norm() + 0.03) + Vector3::new(0.0, 0.0, config.shoulder_height);
            let joints = model.inverse(rest).ok_or_else(|| SimError(format!("arm `{name}` cannot reach its rest")))?;
            let gripper = physics.insert_body(RigidBodyBuilder::kinematic_position_based().translation(to_glam(rest)));
            arms.push(Arm {
                name,
                model,
                joints,
                rest,
                gripper,
                holding: None,
                task: None,
                stalled_until: 0,
                stopped: false,
                lost: None,
            });
        }
        Ok(World { physics, config, blocks, arms, cells, steps: 0 })
    }

    /// Adds cells to the table beyond those the world was built with (the KB's other cells):
    /// the table grows under them, the read-back recognises blocks on them, and a recovery
    /// may put blocks down there. The arms keep their places (reaching a far cell is checked
    /// when a motion starts).
    pub fn add_cells(&mut self, cells: &[(i64, i64)]) {
        let new: Vec<(i64, i64)> = cells.iter().copied().filter(|c| !self.cells.contains(c)).collect();
        if new.is_empty() {
            return;
        }
        let c = self.config.cell_size;
        let (min_x, max_x) = (new.iter().map(|p| p.0).min().unwrap(), new.iter().map(|p| p.0).max().unwrap());
        let (min_y, max_y) = (new.iter().map(|p| p.1).min().unwrap(), new.iter().map(|p| p.1).max().unwrap());
        let centre = Vector3::new((min_x + max_x) as f64 * c / 2.0, (min_y + max_y) as f64 * c / 2.0, -0.05);
        let half =
            Vector3::new((max_x - min_x + 1) as f64 * c / 2.0 + c, (max_y - min_y + 1) as f64 * c / 2.0 + c, 0.05);
        self.physics.insert(
            RigidBodyBuilder::fixed().translation(to_glam(centre)),
            ColliderBuilder::cuboid(half.x as f32, half.y as f32, half.z as f32).friction(0.8),
        );
        self.cells.extend(new);
        self.cells.sort();
    }

    /// The world's dimensions, speeds and time step.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// The poses now.
    pub(crate) fn frame(&self) -> super::Frame {
        let blocks = self
            .blocks
            .iter()
            .map(|b| {
                let body = &self.physics.bodies[b.body];
                let (p, q) = (body.translation(), body.rotation());
                [p.x, p.y, p.z, q.x, q.y, q.z, q.w].map(|v| (v as f64 * 1e4).round() / 1e4)
            })
            .collect();
        let round = |p: Vector3<f64>| [p.x, p.y, p.z].map(|v| (v * 1e4).round() / 1e4);
        let grippers = (0..self.arms.len()).map(|a| round(self.gripper_position(a))).collect();
        let elbows = self.arms.iter().map(|arm| round(arm.model.elbow(arm.joints))).collect();
        super::Frame { time: self.steps as f64 * self.config.step_seconds(), blocks, grippers, elbows }
    }

    /// Each arm's shoulder joint (metres), in the order of [`World::arm_names`]: the base an
    /// arm turns about, fixed for the whole run.
    pub fn arm_shoulders(&self) -> Vec<[f64; 3]> {
        self.arms.iter().map(|a| [a.model.shoulder.x, a.model.shoulder.y, a.model.shoulder.z]).collect()
    }

    /// The table's cells, sorted.
    pub fn cells(&self) -> &[(i64, i64)] {
        &self.cells
    }

    /// The names of the arms that have stopped for good.
    pub fn stopped_arms(&self) -> Vec<String> {
        self.arms.iter().filter(|a| a.stopped).map(|a| a.name.clone()).collect()
    }

    /// The names of the arms, in the order of the initial state's `available/1` facts.
    pub fn arm_names(&self) -> Vec<String> {
        self.arms.iter().map(|a| a.name.clone()).collect()
    }

    /// The names of the blocks.
    pub fn block_names(&self) -> Vec<String> {
        self.blocks.iter().map(|b| b.name.clone()).collect()
    }

    pub(crate) fn block_index(&self, name: &str) -> Option<usize> {
        self.blocks.iter().position(|b| b.name == name)
    }

    pub(crate) fn arm_index(&self, name: &str) -> Option<usize> {
        self.arms.iter().position(|a| a.name == name)
    }

    pub(crate) fn block_position(&self, block: usize) -> Vector3<f64> {
        from_glam(self.physics.bodies[self.blocks[block].body].translation())
    }

    pub(crate) fn gripper_position(&self, arm: usize) -> Vector3<f64> {
        self.arms[arm].model.forward(self.arms[arm].joints)
    }

    fn held(&self, block: usize) -> bool {
        self.arms.iter().any(|a| a.holding.is_some_and(|(b, _)| b == block))
    }

    /// The top surface under the point (x, y): the highest block top within a block's width,
    /// or the table (0). Held blocks do not count.
    pub(crate) fn surface_under(&self, x: f64, y: f64) -> (f64, Option<usize>) {
        let reach = self.config.block_size * 0.9;
        let h = self.config.block_size / 2.0;
        let mut best = (0.0, None);
        for i in 0..self.blocks.len() {
            if self.held(i) {
                continue;
            }
            let p = self.block_position(i);
            if (p.x - x).abs() < reach && (p.y - y).abs() < reach && p.z + h > best.0 {
                best = (p.z + h, Some(i));
            }
        }
        best
    }

    /// A safe height for arm `arm` to travel at: above the tallest stack with room for a held
    /// block, each arm a layer higher than the previous so that arms in transit do not meet.
    pub(crate) fn travel_height(&self, arm: usize) -> f64 {
        let h = self.config.block_size / 2.0;
        let tallest =
            (0..self.blocks.len()).filter(|&i| !self.held(i)).map(|i| self.block_position(i).z + h).fold(0.0, f64::max);
        tallest + self.config.block_size + self.config.clearance + arm as f64 * self.config.layer_spacing
    }

    /// Starts the next primitive of arm `arm`'s task (its motion lines or its wait), or ends
    /// the task when none is left.
    pub(crate) fn begin_next(&mut self, arm: usize) {
        if self.arms[arm].task.is_none() {
            return;
        }
        let refusal = if self.arms[arm].stopped {
            Some(format!("{} has stopped: its controller reports a fault", self.arms[arm].name))
        } else {
            self.arms[arm].lost.take().map(|b| self.slipped(arm, b))
        };
        let task = self.arms[arm].task.as_mut().expect("checked above");
        if let Some(why) = refusal {
            task.outcome = Some(Err(why));
            return;
        }
        let Some(primitive) = task.queue.pop_front() else {
            task.outcome = Some(Ok(()));
            return;
        };
        match self.plan_primitive(arm, &primitive) {
            Ok((lines, wait)) => {
                let task = self.arms[arm].task.as_mut().expect("checked above");
                task.lines = lines.into();
                task.wait_steps = wait;
            }
            Err(why) => {
                let task = self.arms[arm].task.as_mut().expect("checked above");
                task.outcome = Some(Err(why));
            }
        }
    }

    /// The motion (lines) and the wait (steps) of a primitive, with its physical checks.
    fn plan_primitive(&mut self, arm: usize, primitive: &Primitive) -> Result<(Vec<Line>, u32), String> {
        let here = self.gripper_position(arm);
        let name = self.arms[arm].name.clone();
        let h = self.config.block_size / 2.0;
        let c = self.config.cell_size;
        let via_travel = |world: &World, target_xy: Vector3<f64>| {
            let z = world.travel_height(arm);
            let up = Vector3::new(here.x, here.y, z);
            let over = Vector3::new(target_xy.x, target_xy.y, z);
            vec![Line::new(here, up), Line::new(up, over)]
        };
        let lines = match *primitive {
            Primitive::Reach(block) => {
                let p = self.block_position(block);
                if p.z < -self.config.block_size {
                    return Err(format!("{name} cannot reach `{}`: it is off the table", self.blocks[block].name));
                }
                via_travel(self, p)
            }
            Primitive::MoveOver(x, y) => via_travel(self, Vector3::new(x as f64 * c, y as f64 * c, 0.0)),
            Primitive::Descend => {
                let (top, _) = self.surface_under(here.x, here.y);
                let z = if self.arms[arm].holding.is_some() { top + 2.0 * h + 0.002 } else { top };
                vec![Line::new(here, Vector3::new(here.x, here.y, z))]
            }
            Primitive::Home => {
                let rest = self.arms[arm].rest;
                via_travel(self, rest)
            }
            Primitive::Lift => {
                let z = self.travel_height(arm);
                vec![Line::new(here, Vector3::new(here.x, here.y, z))]
            }
            Primitive::Close(block) => {
                if let Some((held, _)) = self.arms[arm].holding {
                    return Err(format!("{name} already holds `{}`", self.blocks[held].name));
                }
                let (top, under) = self.surface_under(here.x, here.y);
                match under {
                    None => return Err(format!("{name} has nothing to grip: the table is bare under it")),
                    Some(b) if (top - here.z).abs() > 0.01 => {
                        return Err(format!(
                            "{name} is not touching `{}` ({:.3} m above it)",
                            self.blocks[b].name,
                            here.z - top
                        ));
                    }
                    Some(b) if b != block => {
                        return Err(format!(
                            "{name} finds `{}` on top, not `{}`",
                            self.blocks[b].name, self.blocks[block].name
                        ));
                    }
                    Some(_) => {}
                }
                let bp = self.block_position(block);
                let rotation = *self.physics.bodies[self.blocks[block].body].rotation();
                let anchor = rotation.inverse() * to_glam(here - bp);
                let joint = self.physics.insert_impulse_joint(
                    self.arms[arm].gripper,
                    self.blocks[block].body,
                    FixedJointBuilder::new().local_anchor1(Vector::ZERO).local_anchor2(anchor),
                );
                self.arms[arm].holding = Some((block, joint));
                return Ok((Vec::new(), self.config.gripper_steps()));
            }
            Primitive::Open(block) => {
                match self.arms[arm].holding {
                    Some((held, joint)) if held == block => {
                        self.physics.remove_impulse_joint(joint);
                        self.arms[arm].holding = None;
                    }
                    Some((held, _)) => {
                        return Err(format!(
                            "{name} holds `{}`, not `{}`",
                            self.blocks[held].name, self.blocks[block].name
                        ));
                    }
                    None => return Err(format!("{name} holds nothing to release")),
                }
                return Ok((Vec::new(), self.config.gripper_steps()));
            }
        };
        let mut from = here;
        for line in &lines {
            let to = line.target();
            if !self.arms[arm].model.reaches_line(from, to) {
                return Err(format!("({:.3}, {:.3}, {:.3}) m is out of {name}'s reach", to.x, to.y, to.z));
            }
            from = to;
        }
        Ok((lines, 0))
    }

    /// Advances arm `arm` one step along `line`, the front of its motion. A step that would
    /// bring its gripper closer to another one, within the safety distance, is held back; held back
    /// for `blocked_seconds`, the primitive fails.
    fn follow(&mut self, arm: usize, mut line: Line, dt: f64) {
        let Some((next, done)) = line.step(&self.arms[arm].model, self.arms[arm].joints, dt) else {
            let why = format!("{} left its reach", self.arms[arm].name);
            self.arms[arm].task.as_mut().expect("a running task").outcome = Some(Err(why));
            return;
        };
        let at = self.arms[arm].model.forward(next);
        let here = self.gripper_position(arm);
        // A step that does not close in on the other gripper is never held back: an arm may
        // always back away (two arms stopped close together could otherwise never part).
        let blocker = (0..self.arms.len())
            .filter(|&b| b != arm)
            .map(|b| (b, (self.gripper_position(b) - at).norm(), (self.gripper_position(b) - here).norm()))
            .find(|&(_, d, now)| d < self.config.safety_distance && d < now)
            .map(|(b, d, _)| (b, d));
        let patience = (self.config.blocked_seconds / dt).ceil() as u32;
        let why = blocker.map(|(b, d)| {
            format!(
                "{} was blocked for {:.1} s by {}'s gripper ({d:.3} m away{})",
                self.arms[arm].name,
                self.config.blocked_seconds,
                self.arms[b].name,
                if self.arms[b].stopped { ", stopped for good" } else { "" }
            )
        });
        let Arm { joints, task, .. } = &mut self.arms[arm];
        let task = task.as_mut().expect("a running task");
        match why {
            Some(why) => {
                task.blocked += 1;
                if task.blocked > patience {
                    task.outcome = Some(Err(why));
                }
            }
            None => {
                task.blocked = 0;
                *joints = next;
                if done {
                    task.lines.pop_front();
                } else {
                    task.lines[0] = line;
                }
            }
        }
    }

    /// One physics step: every arm with a task moves along its motion (unless that would
    /// bring its gripper within the safety distance of another), then the bodies move.
    pub(crate) fn step(&mut self) {
        let dt = self.config.step_seconds();
        for arm in 0..self.arms.len() {
            let frozen = self.arms[arm].stopped || self.steps < self.arms[arm].stalled_until;
            if let Some(task) = self.arms[arm].task.as_ref().filter(|t| t.outcome.is_none() && !frozen) {
                match task.lines.front() {
                    Some(line) => self.follow(arm, line.clone(), dt),
                    None if task.wait_steps > 0 => {
                        self.arms[arm].task.as_mut().expect("checked above").wait_steps -= 1;
                    }
                    None => self.begin_next(arm),
                }
            }
            let target = to_glam(self.gripper_position(arm));
            self.physics.bodies[self.arms[arm].gripper].set_next_kinematic_translation(target);
        }
        self.physics.step();
        self.steps += 1;
    }

    fn slipped(&self, arm: usize, block: usize) -> String {
        format!("`{}` slipped from {}'s gripper", self.blocks[block].name, self.arms[arm].name)
    }

    /// Whether arm `arm` carries a block and is moving it.
    pub(crate) fn carrying(&self, arm: usize) -> bool {
        let a = &self.arms[arm];
        a.holding.is_some() && a.task.as_ref().is_some_and(|t| t.outcome.is_none() && !t.lines.is_empty())
    }

    /// A drop fault: arm `arm`'s gripper lets go of its block, which falls. The gripper's
    /// sensor notices: the running task fails, or else the next one the arm starts.
    pub(crate) fn drop_held(&mut self, arm: usize) -> Option<String> {
        let (block, joint) = self.arms[arm].holding.take()?;
        self.physics.remove_impulse_joint(joint);
        self.physics.bodies[self.blocks[block].body].wake_up(true);
        let why = self.slipped(arm, block);
        match self.arms[arm].task.as_mut().filter(|t| t.outcome.is_none()) {
            Some(task) => task.outcome = Some(Err(why.clone())),
            None => self.arms[arm].lost = Some(block),
        }
        let p = self.block_position(block);
        Some(format!("{why} at ({:.3}, {:.3}, {:.3}) m", p.x, p.y, p.z))
    }

    /// A stall fault: arm `arm` does not move for `seconds`.
    pub(crate) fn stall(&mut self, arm: usize, seconds: f64) {
        self.arms[arm].stalled_until = self.steps + (seconds / self.config.step_seconds()).ceil() as u64;
    }

    /// Whether any arm is stalled now.
    pub(crate) fn any_stalled(&self) -> bool {
        self.arms.iter().any(|a| !a.stopped && self.steps < a.stalled_until)
    }

    /// A stop fault: arm `arm` never moves again; its running task fails.
    pub(crate) fn stop(&mut self, arm: usize) {
        self.arms[arm].stopped = true;
        let why = format!("{} has stopped: its controller reports a fault", self.arms[arm].name);
        if let Some(task) = self.arms[arm].task.as_mut().filter(|t| t.outcome.is_none()) {
            task.outcome = Some(Err(why));
        }
    }

    /// The top block of the stack `block` belongs to.
    pub(crate) fn top_of_stack(&self, block: usize) -> usize {
        let mut top = block;
        while let Some(above) =
            (0..self.blocks.len()).find(|&j| matches!(self.placement(j), Placement::On(b, ..) if b == top))
        {
            top = above;
        }
        top
    }

    /// The cells with nothing on them (no block within half a cell of the centre), in order.
    pub(crate) fn free_cells(&self) -> Vec<(i64, i64)> {
        let c = self.config.cell_size;
        self.cells
            .iter()
            .copied()
            .filter(|&(x, y)| {
                (0..self.blocks.len()).all(|i| {
                    let p = self.block_position(i);
                    self.held(i) || (p.x - x as f64 * c).abs() >= c / 2.0 || (p.y - y as f64 * c).abs() >= c / 2.0
                })
            })
            .collect()
    }

    /// The free cell nearest to the point (x, y), the first in order among equals.
    pub(crate) fn nearest_free_cell(&self, x: f64, y: f64) -> Option<(i64, i64)> {
        let c = self.config.cell_size;
        let distance = |&(cx, cy): &(i64, i64)| (cx as f64 * c - x).hypot(cy as f64 * c - y);
        self.free_cells().into_iter().min_by(|a, b| distance(a).total_cmp(&distance(b)))
    }

    /// A nudge fault: `block` is pushed onto the centre of `cell`, upright and at rest.
    pub(crate) fn nudge(&mut self, block: usize, (x, y): (i64, i64)) -> String {
        let c = self.config.cell_size;
        let before = self.block_position(block);
        let at = Vector3::new(x as f64 * c, y as f64 * c, self.config.block_size / 2.0 + 0.001);
        let body = &mut self.physics.bodies[self.blocks[block].body];
        body.set_translation(to_glam(at), true);
        body.set_rotation(rapier3d::math::Rotation::IDENTITY, true);
        body.set_linvel(Vector::ZERO, true);
        body.set_angvel(Vector::ZERO, true);
        format!(
            "`{}` was pushed from ({:.3}, {:.3}) m onto cell ({x}, {y})",
            self.blocks[block].name, before.x, before.y
        )
    }

    /// Where block `i` is: held, on a cell (on the table or on a block), loose on the table
    /// between cells, or lost (with why).
    pub(crate) fn placement(&self, i: usize) -> Placement {
        if let Some(arm) = self.arms.iter().position(|a| a.holding.is_some_and(|(b, _)| b == i)) {
            return Placement::Held(arm);
        }
        let h = self.config.block_size / 2.0;
        let c = self.config.cell_size;
        let p = self.block_position(i);
        let rotation = self.physics.bodies[self.blocks[i].body].rotation();
        // A cube lies flat on any face: one of its axes is vertical.
        let flat = [Vector::X, Vector::Y, Vector::Z].iter().any(|&axis| (rotation * axis).z.abs() > 0.99);
        if p.z < 0.0 {
            return Placement::Lost("off the table".to_string());
        }
        if !flat {
            return Placement::Lost("tipped over".to_string());
        }
        let (cx, cy) = ((p.x / c).round() as i64, (p.y / c).round() as i64);
        let off_cell = (p.x - cx as f64 * c).abs().max((p.y - cy as f64 * c).abs());
        let on_cell = off_cell <= c / 3.0 && self.cells.contains(&(cx, cy));
        if (p.z - h).abs() < 0.01 {
            return if on_cell { Placement::OnTable(cx, cy) } else { Placement::Loose };
        }
        let below = (0..self.blocks.len()).find(|&j| {
            let q = self.block_position(j);
            j != i
                && !self.held(j)
                && (q.x - p.x).abs() < h
                && (q.y - p.y).abs() < h
                && (p.z - q.z - 2.0 * h).abs() < 0.01
        });
        match below {
            Some(j) if on_cell => Placement::On(j, cx, cy),
            Some(_) => Placement::Lost("on a block that is not on a cell".to_string()),
            None => Placement::Lost("resting on nothing".to_string()),
        }
    }

    /// The world as facts: `ontable/3`, `on/4`, `clear/1` for every block that rests flat on
    /// a cell (within a third of a cell) on the table or on another block (within 1 cm),
    /// `available/1` for every arm that holds nothing and has not stopped, `gripped/2` for
    /// held blocks; and a line for each block that is none of these (loose between cells,
    /// fallen off the table, tipped over).
    pub fn facts(&self) -> (Vec<Fact>, Vec<Misplaced>) {
        let atom = |s: &str| Arg::Atom(s.to_string());
        let mut facts = Vec::new();
        let mut unaccounted = Vec::new();
        let mut covered = vec![false; self.blocks.len()];
        let mut resting = Vec::new();
        for (i, block) in self.blocks.iter().enumerate() {
            let p = self.block_position(i);
            let misplaced = |why: Misplacement| Misplaced { block: block.name.clone(), position: [p.x, p.y, p.z], why };
            match self.placement(i) {
                Placement::Held(arm) => {
                    facts.push(Fact::new(GRIPPED.name, vec![atom(&self.arms[arm].name), atom(&block.name)]));
                }
                Placement::OnTable(x, y) => {
                    facts.push(Fact::new(ONTABLE.name, vec![atom(&block.name), Arg::Int(x), Arg::Int(y)]));
                    resting.push(i);
                }
                Placement::On(j, x, y) => {
                    covered[j] = true;
                    let args = vec![atom(&block.name), atom(&self.blocks[j].name), Arg::Int(x), Arg::Int(y)];
                    facts.push(Fact::new(ON.name, args));
                    resting.push(i);
                }
                Placement::Loose => unaccounted.push(misplaced(Misplacement::BetweenCells)),
                Placement::Lost(why) => unaccounted.push(misplaced(Misplacement::Lost(why))),
            }
        }
        for i in resting {
            if !covered[i] {
                facts.push(Fact::new(CLEAR.name, vec![atom(&self.blocks[i].name)]));
            }
        }
        for arm in &self.arms {
            if arm.holding.is_none() && !arm.stopped {
                facts.push(Fact::new(AVAILABLE.name, vec![atom(&arm.name)]));
            }
        }
        (facts, unaccounted)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn atom(s: &str) -> Arg {
        Arg::Atom(s.to_string())
    }

    /// b1 at (1, 1) with b2 on it, b3 at (3, 3), arms a1 and a2.
    fn world() -> World {
        let facts = vec![
            Fact::new("ontable", vec![atom("b1"), Arg::Int(1), Arg::Int(1)]),
            Fact::new("on", vec![atom("b2"), atom("b1"), Arg::Int(1), Arg::Int(1)]),
            Fact::new("ontable", vec![atom("b3"), Arg::Int(3), Arg::Int(3)]),
            Fact::new("available", vec![atom("a1")]),
            Fact::new("available", vec![atom("a2")]),
        ];
        World::new(SimConfig::default(), &facts, &[(1, 1), (2, 2), (3, 3)]).expect("a world")
    }

    #[test]
    fn a_frame_puts_each_elbow_one_link_from_the_shoulder_and_the_gripper() {
        let world = world();
        let frame = world.frame();
        for (a, arm) in world.arms.iter().enumerate() {
            let elbow = Vector3::from(frame.elbows[a]);
            let gripper = Vector3::from(frame.grippers[a]);
            let shoulder = Vector3::from(world.arm_shoulders()[a]);
            assert!(((elbow - shoulder).norm() - arm.model.upper).abs() < 1e-3, "upper link of arm {a}");
            assert!(((gripper - elbow).norm() - arm.model.fore).abs() < 1e-3, "forearm of arm {a}");
            // Elbow up: above the straight line from the shoulder to the gripper.
            let along = shoulder + (gripper - shoulder) * 0.5;
            assert!(elbow.z > along.z, "arm {a} holds its elbow up");
        }
    }

    /// Runs `steps` on arm 0 until they finish (or 20 simulated seconds pass).
    fn run(world: &mut World, steps: Vec<Primitive>) -> Result<(), String> {
        world.arms[0].task = Some(Task::new(0, steps));
        world.begin_next(0);
        for _ in 0..2000 {
            if let Some(outcome) = world.arms[0].task.as_ref().and_then(|t| t.outcome.clone()) {
                world.arms[0].task = None;
                // Let the blocks settle before anyone reads the world back.
                for _ in 0..50 {
                    world.step();
                }
                return outcome;
            }
            world.step();
        }
        panic!("the steps never finished");
    }

    fn texts(world: &World) -> Vec<String> {
        let (facts, unaccounted) = world.facts();
        assert!(unaccounted.is_empty(), "{unaccounted:?}");
        let mut texts: Vec<String> = facts.iter().map(Fact::to_string).collect();
        texts.sort();
        texts
    }

    #[test]
    fn the_initial_world_reads_back_as_its_facts() {
        let mut w = world();
        for _ in 0..100 {
            w.step();
        }
        assert_eq!(
            texts(&w),
            [
                "available(a1)",
                "available(a2)",
                "clear(b2)",
                "clear(b3)",
                "on(b2, b1, 1, 1)",
                "ontable(b1, 1, 1)",
                "ontable(b3, 3, 3)"
            ]
        );
    }

    #[test]
    fn an_arm_carries_a_block_to_another_cell() {
        let mut w = world();
        let b2 = w.block_index("b2").unwrap();
        let steps = vec![
            Primitive::Reach(b2),
            Primitive::Descend,
            Primitive::Close(b2),
            Primitive::Lift,
            Primitive::MoveOver(3, 3),
            Primitive::Descend,
            Primitive::Open(b2),
            Primitive::Lift,
            Primitive::Home,
        ];
        assert_eq!(run(&mut w, steps), Ok(()));
        let world = texts(&w);
        assert!(world.contains(&"on(b2, b3, 3, 3)".to_string()), "{world:?}");
        assert!(world.contains(&"clear(b1)".to_string()) && !world.contains(&"clear(b3)".to_string()));
    }

    #[test]
    fn closing_on_a_covered_block_fails() {
        let mut w = world();
        let b1 = w.block_index("b1").unwrap();
        let outcome = run(&mut w, vec![Primitive::Reach(b1), Primitive::Descend, Primitive::Close(b1)]);
        assert_eq!(outcome, Err("a1 finds `b2` on top, not `b1`".to_string()));
    }

    #[test]
    fn closing_over_the_bare_table_fails_and_far_cells_are_out_of_reach() {
        let mut w = world();
        let b1 = w.block_index("b1").unwrap();
        let outcome = run(&mut w, vec![Primitive::MoveOver(2, 2), Primitive::Descend, Primitive::Close(b1)]);
        assert_eq!(outcome, Err("a1 has nothing to grip: the table is bare under it".to_string()));
        let outcome = run(&mut w, vec![Primitive::MoveOver(40, 40)]);
        assert!(outcome.as_ref().is_err_and(|e| e.contains("out of a1's reach")), "{outcome:?}");
    }

    #[test]
    fn an_arm_waits_for_a_gripper_in_its_way_then_gives_up() {
        let mut w = world();
        // Park a2's gripper exactly where a1 must pass: above cell (2, 2) at a1's travel height.
        let z = w.travel_height(0);
        let spot = Vector3::new(0.2, 0.2, z);
        w.arms[1].joints = w.arms[1].model.inverse(spot).expect("reachable");
        let outcome = run(&mut w, vec![Primitive::MoveOver(2, 2)]);
        assert!(outcome.as_ref().is_err_and(|e| e.contains("blocked for 2.0 s by a2's gripper")), "{outcome:?}");
    }
}
