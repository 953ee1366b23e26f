//! The tick engine: a behaviour tree run against a [`Host`], one `tick` at a time.
//!
//! All state lives in flat vectors allocated by [`Vm::new`]: a status and a cursor per node,
//! a time per event, a running flag per host action, the blackboard as a bit set, and the
//! traversal stack (as deep as the tree). A tick walks the tree iteratively from the root,
//! skipping finished subtrees, so it allocates nothing and cannot overflow the host's stack;
//! the only allocations after `new` are a failure's reason text, once.
//!
//! Node contracts (each is tested tick by tick in `tests/nodes.rs`):
//!
//! - **seq**: ticks the current child; on Success moves to the next one in the same tick;
//!   Running and Failure are its own status. Success when every child has succeeded.
//! - **par**: ticks, in order, every child that has not succeeded. Failure as soon as one
//!   fails; Success when all have succeeded; else Running.
//! - **wait**: Success once every listed event has been recorded and `now` is at least its
//!   time plus the delay; Running before (and the VM's next deadline is the earliest such time).
//! - **start**: checks its conditions on the blackboard, applies its effects, asks the host to
//!   start the action and records its event at `now`: Success in one tick. Failure if a
//!   condition fails or the host refuses.
//! - **end**: waits for its start's event, then polls the host: Running while the action
//!   runs; Failure if the host reports failure or the action runs past its greatest duration
//!   (the host action is halted); once the host reports success and the least duration has
//!   passed, checks its conditions, applies its effects, records its event: Success.
//! - **act**: an instantaneous action: checks, starts, polls until the host reports back,
//!   then applies its effects and records its event.
//!
//! Any Failure reaches the root (no node recovers from one); the VM then halts every host
//! action still running and stays in Failure until [`Vm::reset`].

use crate::bytecode::{Check, Effect, EventId, FluentId, ImportId, Instr, NodeRef, Value};
use crate::program::{Action, Program};

/// What a tick returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Status {
    /// Not finished: tick again.
    Running,
    /// The whole tree succeeded.
    Success,
    /// A node failed; [`Vm::failure`] says which and why.
    Failure,
}

/// What the host says of an action it runs.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Poll {
    /// Still going.
    Running,
    /// Done.
    Success,
    /// Failed, with the reason.
    Failure(HostError),
}

/// An action the VM asks the host to start, poll or halt.
#[derive(Clone, Copy, Debug)]
pub struct Invocation<'p> {
    /// Identifies this action instance: the event of its start node.
    pub id: EventId,
    action: &'p Action,
    program: &'p Program,
}

impl<'p> Invocation<'p> {
    /// The import table entry.
    pub fn import(&self) -> ImportId {
        ImportId(self.action.import)
    }

    /// The action's name.
    pub fn name(&self) -> &'p str {
        &self.program.module.symbols[self.action.name as usize]
    }

    /// Its ground arguments (atoms as symbols: see [`Invocation::arg_text`]).
    pub fn args(&self) -> &'p [Value] {
        &self.program.args[self.action.args.0 as usize..self.action.args.1 as usize]
    }

    /// Its least duration in program time units (0 for an instantaneous action).
    pub fn min(&self) -> i64 {
        self.action.min
    }

    /// Its greatest duration, if bounded.
    pub fn max(&self) -> Option<i64> {
        self.action.max
    }

    /// The text of argument `i`.
    pub fn arg_text(&self, i: usize) -> String {
        self.args().get(i).map_or_else(String::new, |&v| self.program.value_text(v))
    }

    /// The call as text: `move_block(a1, b2, 1, 1, 3, 3)`.
    pub fn text(&self) -> String {
        self.program.action_text(self.id)
    }

    /// The arm-level steps the action is refined into, in order (empty if the program has no
    /// refinement for it). A host that runs the steps rather than the action itself names
    /// them with [`Program::call_text`] and [`Program::import_name`].
    pub fn steps(&self) -> &'p [crate::bytecode::Call] {
        self.program.steps(self.id)
    }

    /// The arm-level steps of the action's end: the host runs them once the end node polls
    /// (the tree polls an action only when every step ordered before its end is done).
    pub fn end_steps(&self) -> &'p [crate::bytecode::Call] {
        self.program.end_steps(self.id)
    }

    /// The program the action belongs to.
    pub fn program(&self) -> &'p Program {
        self.program
    }
}

/// Why a host refused or failed an action.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum HostError {
    /// The host does not run the call (an action without a refinement, or a step of one);
    /// the text says what it runs instead.
    NotProvided(String),
    /// A call names something the host does not have.
    Unknown {
        /// The call, as text.
        call: String,
        /// What kind of thing: `arm`, `block`, ...
        what: &'static str,
        /// Its name.
        name: String,
    },
    /// The resource the action needs is busy with another action.
    Busy {
        /// The resource (an arm, say).
        resource: String,
        /// The action that holds it.
        holder: EventId,
    },
    /// The action's refinement cannot run on this host (its steps need two arms, say).
    BadRefinement(String),
    /// The action was polled or halted without running.
    NotRunning(String),
    /// The action failed while running: the host's account of what happened.
    Failed(String),
}

impl std::fmt::Display for HostError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            HostError::NotProvided(text)
            | HostError::BadRefinement(text)
            | HostError::NotRunning(text)
            | HostError::Failed(text) => f.write_str(text),
            HostError::Unknown { call, what, name } => write!(f, "`{call}`: there is no {what} `{name}` in the world"),
            HostError::Busy { resource, holder } => {
                write!(f, "{resource} is busy with another action (e{})", holder.0)
            }
        }
    }
}

impl std::error::Error for HostError {}

/// The robot side: runs the actions the tree starts. Times are program time units.
pub trait Host {
    /// Starts `action`; an error refuses it (its node fails with the message).
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), HostError>;
    /// Reports on an action started earlier.
    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll;
    /// Stops an action started earlier that is no longer wanted.
    fn halt(&mut self, action: &Invocation<'_>, now: i64);
    /// Whether the host runs actions named `name` with `arity` arguments (checked when a
    /// program is linked, [`Program::link`]); by default it takes any.
    fn runs(&self, name: &str, arity: usize) -> bool {
        let _ = (name, arity);
        true
    }
}

/// Why a node failed.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Reason {
    /// A fluent the node requires does not hold on the blackboard.
    Missing(FluentId),
    /// A fluent the node forbids holds.
    Forbidden(FluentId),
    /// None of a group of fluents holds (the group's first is given).
    NoneHolds(FluentId),
    /// The host refused to start the action.
    Refused(HostError),
    /// The host reported the action failed.
    HostFailed(HostError),
    /// The action ran longer than its greatest duration.
    Overran {
        /// The greatest duration.
        max: i64,
    },
    /// The tick visited more nodes than its budget.
    Budget,
    /// [`Vm::halt`] stopped the tree.
    Halted,
}

/// A failed node and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    /// The node.
    pub node: NodeRef,
    /// When.
    pub time: i64,
    /// Why.
    pub reason: Reason,
}

impl Failure {
    /// A sentence for people: the node, the reason, and the KB location if known.
    pub fn describe(&self, program: &Program) -> String {
        let what = match &self.reason {
            Reason::Missing(f) => format!("`{}` does not hold", program.fluent_text(*f)),
            Reason::Forbidden(f) => format!("`{}` holds, and the action forbids it", program.fluent_text(*f)),
            Reason::NoneHolds(f) => format!("no fact like `{}` holds", program.fluent_text(*f)),
            Reason::Refused(m) => format!("the host refused to start it: {m}"),
            Reason::HostFailed(m) => format!("the host reports it failed: {m}"),
            Reason::Overran { max } => {
                format!("it ran longer than its greatest duration ({} time units)", program.time_text(*max))
            }
            Reason::Budget => "the tick ran out of its node budget".to_string(),
            Reason::Halted => "the tree was halted".to_string(),
        };
        match program.location(self.node) {
            Some(at) => {
                let time = program.time_text(self.time);
                format!("{} failed at program time {time}: {what} ({}:{}:{})", at.label, at.file, at.line, at.column)
            }
            None => format!("node @{} failed at program time {}: {what}", self.node.0, program.time_text(self.time)),
        }
    }
}

const IDLE: u8 = 0;
const SUCCEEDED: u8 = 2;
const FAILED: u8 = 3;
/// An event not yet recorded.
const NEVER: i64 = i64::MIN;

#[derive(Clone, Copy)]
struct Frame {
    node: u32,
    /// For a parallel: the child being ticked.
    next: u32,
    /// For a parallel: a child returned Running this tick.
    running: bool,
}

/// A running behaviour tree.
pub struct Vm<'p> {
    program: &'p Program,
    status: Vec<u8>,
    /// Sequence: the current child; end and act: 1 once the host reported success.
    cursor: Vec<u32>,
    event_time: Vec<i64>,
    /// Per event of a start or act node: its host action is running.
    running: Vec<bool>,
    blackboard: Vec<u64>,
    stack: Vec<Frame>,
    budget: usize,
    finished: Option<Status>,
    failure: Option<Failure>,
    deadline: Option<i64>,
    /// How many events have been recorded since the start.
    recorded: usize,
}

impl<'p> Vm<'p> {
    /// A VM at the start of `program`: nothing ticked, the blackboard at the initial state.
    pub fn new(program: &'p Program) -> Vm<'p> {
        let m = &program.module;
        Vm {
            program,
            status: vec![IDLE; m.nodes.len()],
            cursor: vec![0; m.nodes.len()],
            event_time: vec![NEVER; m.events as usize],
            running: vec![false; m.events as usize],
            blackboard: program.initial_blackboard.clone(),
            stack: Vec::with_capacity(program.depth + 1),
            budget: m.nodes.len(),
            finished: None,
            failure: None,
            deadline: None,
            recorded: 0,
        }
    }

    /// Limits how many nodes one tick may visit (default: every node, which a tree never
    /// exceeds). A tick over budget fails the tree with [`Reason::Budget`].
    pub fn set_tick_budget(&mut self, nodes: usize) {
        self.budget = nodes;
    }

    /// Ticks the tree at time `now` (program time units, never decreasing).
    pub fn tick(&mut self, host: &mut dyn Host, now: i64) -> Status {
        if let Some(status) = self.finished {
            return status;
        }
        let program: &'p Program = self.program;
        let nodes = &program.module.nodes;
        self.deadline = None;
        self.stack.clear();
        let root = program.module.root.0;
        let mut visits = 1usize;
        let mut returned: Option<Status> = match &nodes[root as usize] {
            Instr::Sequence { .. } | Instr::Parallel { .. } => {
                self.stack.push(Frame { node: root, next: 0, running: false });
                None
            }
            leaf => Some(self.tick_leaf(root as usize, leaf, host, now)),
        };
        // Composites are frames on the stack; their leaf children are ticked in place, which
        // keeps a leaf tick to a status check, the leaf's own work and the host call.
        'walk: while let Some(frame) = self.stack.last() {
            let node = frame.node as usize;
            let (mut next, mut running) = (frame.next as usize, frame.running);
            let children = match &nodes[node] {
                Instr::Sequence { children } | Instr::Parallel { children } => children,
                _ => unreachable!("only composites are pushed"),
            };
            let sequence = matches!(nodes[node], Instr::Sequence { .. });
            if sequence {
                next = self.cursor[node] as usize;
            }
            match returned.take() {
                Some(Status::Failure) => {
                    self.status[node] = FAILED;
                    self.stack.pop();
                    returned = Some(Status::Failure);
                    continue;
                }
                Some(Status::Running) if sequence => {
                    self.stack.pop();
                    returned = Some(Status::Running);
                    continue;
                }
                Some(Status::Running) => {
                    running = true;
                    next += 1;
                }
                Some(Status::Success) => next += 1,
                None => {}
            }
            let mut descend = None;
            let mut outcome = None;
            while let Some(child) = children.get(next) {
                let c = child.0 as usize;
                if self.status[c] == SUCCEEDED {
                    next += 1;
                    continue;
                }
                visits += 1;
                if visits > self.budget {
                    returned = Some(self.fail(c, now, Reason::Budget));
                    break 'walk;
                }
                let status = match &nodes[c] {
                    // A parallel's sequence child (one per branch in kbc's trees) is run in
                    // place up to its first composite child, without a frame of its own.
                    Instr::Sequence { children: inner } if !sequence => {
                        let mut inner_status = None;
                        while let Some(grandchild) = inner.get(self.cursor[c] as usize) {
                            let g = grandchild.0 as usize;
                            let leaf = match &nodes[g] {
                                Instr::Sequence { .. } | Instr::Parallel { .. } => break,
                                leaf => leaf,
                            };
                            visits += 1;
                            if visits > self.budget {
                                returned = Some(self.fail(g, now, Reason::Budget));
                                break 'walk;
                            }
                            match self.tick_leaf(g, leaf, host, now) {
                                Status::Success => self.cursor[c] += 1,
                                other => {
                                    inner_status = Some(other);
                                    break;
                                }
                            }
                        }
                        match inner_status {
                            Some(status) => {
                                if status == Status::Failure {
                                    self.status[c] = FAILED;
                                }
                                status
                            }
                            None if self.cursor[c] as usize == inner.len() => {
                                self.status[c] = SUCCEEDED;
                                Status::Success
                            }
                            None => {
                                descend = Some(child.0);
                                break;
                            }
                        }
                    }
                    Instr::Sequence { .. } | Instr::Parallel { .. } => {
                        descend = Some(child.0);
                        break;
                    }
                    leaf => self.tick_leaf(c, leaf, host, now),
                };
                match status {
                    Status::Success => next += 1,
                    Status::Running if !sequence => {
                        running = true;
                        next += 1;
                    }
                    other => {
                        outcome = Some(other);
                        break;
                    }
                }
            }
            if sequence {
                self.cursor[node] = next as u32;
            } else if let Some(top) = self.stack.last_mut() {
                top.next = next as u32;
                top.running = running;
            }
            if let Some(child) = descend {
                self.stack.push(Frame { node: child, next: 0, running: false });
                continue;
            }
            let status = match outcome {
                Some(status) => status,
                None if running => Status::Running,
                None => Status::Success,
            };
            match status {
                Status::Success => self.status[node] = SUCCEEDED,
                Status::Failure => self.status[node] = FAILED,
                Status::Running => {}
            }
            self.stack.pop();
            returned = Some(status);
        }
        let status = returned.unwrap_or(Status::Failure);
        if status != Status::Running {
            self.finished = Some(status);
            if status == Status::Failure {
                self.halt_actions(host, now);
            }
        }
        status
    }

    /// An end node: the hot path of a running tree, inlined into the walk.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn tick_end(
        &mut self,
        node: usize,
        event: EventId,
        start: EventId,
        check: &Check,
        effects: &[Effect],
        host: &mut dyn Host,
        now: i64,
    ) -> Status {
        let started = self.event_time[start.0 as usize];
        if started == NEVER {
            return Status::Running; // its start has not happened yet
        }
        let action = &self.program.actions[start.0 as usize];
        let (min, max) = (action.min, action.max);
        if self.cursor[node] == 0 {
            let invocation = self.invocation(start.0 as usize);
            let overran = |now: i64| max.filter(|&m| now > started.saturating_add(m));
            match host.poll(&invocation, now) {
                Poll::Running => {
                    if let Some(max) = overran(now) {
                        host.halt(&invocation, now);
                        self.running[start.0 as usize] = false;
                        return self.fail(node, now, Reason::Overran { max });
                    }
                    if let Some(max) = max {
                        self.wake_at(started.saturating_add(max).saturating_add(1));
                    }
                    return Status::Running;
                }
                Poll::Failure(message) => {
                    self.running[start.0 as usize] = false;
                    return self.fail(node, now, Reason::HostFailed(message));
                }
                Poll::Success => {
                    self.running[start.0 as usize] = false;
                    if let Some(max) = overran(now) {
                        return self.fail(node, now, Reason::Overran { max });
                    }
                    self.cursor[node] = 1;
                }
            }
        }
        let earliest = started.saturating_add(min);
        if now < earliest {
            self.wake_at(earliest);
            return Status::Running;
        }
        if let Err(reason) = self.check(check) {
            return self.fail(node, now, reason);
        }
        self.apply(effects);
        self.event_time[event.0 as usize] = now;
        self.recorded += 1;
        self.status[node] = SUCCEEDED;
        Status::Success
    }

    /// Ticks a leaf. End nodes, polled for every running action on every tick, are inlined
    /// into the walk; the other leaves run once or twice each and stay out of line (inlining
    /// them too costs 6 more instructions per leaf tick in `benches/tick.rs`).
    #[inline(always)]
    fn tick_leaf(&mut self, node: usize, instr: &'p Instr, host: &mut dyn Host, now: i64) -> Status {
        match instr {
            Instr::End { event, start, check, effects } => {
                self.tick_end(node, *event, *start, check, effects, host, now)
            }
            other => self.tick_other_leaf(node, other, host, now),
        }
    }

    fn tick_other_leaf(&mut self, node: usize, instr: &'p Instr, host: &mut dyn Host, now: i64) -> Status {
        match instr {
            Instr::Wait { after } => {
                for delay in after {
                    let t = self.event_time[delay.event.0 as usize];
                    if t == NEVER {
                        return Status::Running;
                    }
                    let ready = t.saturating_add(delay.after.0);
                    if now < ready {
                        self.wake_at(ready);
                        return Status::Running;
                    }
                }
                self.status[node] = SUCCEEDED;
                Status::Success
            }
            Instr::Start { event, check, effects, .. } => {
                if let Err(reason) = self.check(check) {
                    return self.fail(node, now, reason);
                }
                self.apply(effects);
                let invocation = self.invocation(event.0 as usize);
                if let Err(message) = host.start(&invocation, now) {
                    return self.fail(node, now, Reason::Refused(message));
                }
                self.event_time[event.0 as usize] = now;
                self.recorded += 1;
                self.running[event.0 as usize] = true;
                self.status[node] = SUCCEEDED;
                Status::Success
            }
            Instr::Act { event, check, effects, .. } => {
                let invocation = self.invocation(event.0 as usize);
                if self.cursor[node] == 0 {
                    if let Err(reason) = self.check(check) {
                        return self.fail(node, now, reason);
                    }
                    if let Err(message) = host.start(&invocation, now) {
                        return self.fail(node, now, Reason::Refused(message));
                    }
                    self.running[event.0 as usize] = true;
                    self.cursor[node] = 1;
                }
                match host.poll(&invocation, now) {
                    Poll::Running => Status::Running,
                    Poll::Failure(message) => {
                        self.running[event.0 as usize] = false;
                        self.fail(node, now, Reason::HostFailed(message))
                    }
                    Poll::Success => {
                        self.running[event.0 as usize] = false;
                        self.apply(effects);
                        self.event_time[event.0 as usize] = now;
                        self.recorded += 1;
                        self.status[node] = SUCCEEDED;
                        Status::Success
                    }
                }
            }
            Instr::End { .. } | Instr::Sequence { .. } | Instr::Parallel { .. } => {
                unreachable!("`tick_leaf` ticks ends, the walk composites")
            }
        }
    }

    /// The host call of the action whose start (or act) node records `event`.
    fn invocation(&self, event: usize) -> Invocation<'p> {
        let program: &'p Program = self.program;
        Invocation { id: EventId(event as u32), action: &program.actions[event], program }
    }

    fn holds(&self, fluent: FluentId) -> bool {
        let i = fluent.0 as usize;
        self.blackboard[i / 64] & (1 << (i % 64)) != 0
    }

    fn check(&self, check: &Check) -> Result<(), Reason> {
        if let Some(&f) = check.require.iter().find(|&&f| !self.holds(f)) {
            return Err(Reason::Missing(f));
        }
        if let Some(&f) = check.forbid.iter().find(|&&f| self.holds(f)) {
            return Err(Reason::Forbidden(f));
        }
        if let Some(group) = check.any.iter().find(|g| !g.iter().any(|&f| self.holds(f))) {
            return Err(Reason::NoneHolds(group.first().copied().unwrap_or(FluentId(0))));
        }
        Ok(())
    }

    fn apply(&mut self, effects: &[Effect]) {
        for effect in effects {
            let i = effect.fluent.0 as usize;
            if effect.add {
                self.blackboard[i / 64] |= 1 << (i % 64);
            } else {
                self.blackboard[i / 64] &= !(1 << (i % 64));
            }
        }
    }

    fn wake_at(&mut self, time: i64) {
        self.deadline = Some(self.deadline.map_or(time, |d| d.min(time)));
    }

    fn fail(&mut self, node: usize, now: i64, reason: Reason) -> Status {
        self.status[node] = FAILED;
        if self.failure.is_none() {
            self.failure = Some(Failure { node: NodeRef(node as u32), time: now, reason });
        }
        Status::Failure
    }

    fn halt_actions(&mut self, host: &mut dyn Host, now: i64) {
        for event in 0..self.running.len() {
            if std::mem::replace(&mut self.running[event], false) {
                let invocation = self.invocation(event);
                host.halt(&invocation, now);
            }
        }
    }

    /// Stops the tree: halts every host action still running; the VM stays in Failure
    /// ([`Reason::Halted`]) until [`Vm::reset`].
    pub fn halt(&mut self, host: &mut dyn Host, now: i64) {
        self.halt_actions(host, now);
        if self.finished.is_none() {
            self.finished = Some(Status::Failure);
            let root = self.program.module.root.0 as usize;
            self.fail(root, now, Reason::Halted);
        }
    }

    /// Back to the start: every node idle, no event recorded, the blackboard at the initial
    /// state. Host actions still running are forgotten, not halted: call [`Vm::halt`] first.
    pub fn reset(&mut self) {
        self.status.fill(IDLE);
        self.cursor.fill(0);
        self.event_time.fill(NEVER);
        self.running.fill(false);
        self.blackboard.copy_from_slice(&self.program.initial_blackboard);
        self.finished = None;
        self.failure = None;
        self.deadline = None;
        self.recorded = 0;
    }

    /// How many events (snap actions) have happened: a host that sees this change after a
    /// tick ticks again at the same time, since other nodes may be waiting for them.
    pub fn events_recorded(&self) -> usize {
        self.recorded
    }

    /// The failed node and the reason, once the tree has failed.
    pub fn failure(&self) -> Option<&Failure> {
        self.failure.as_ref()
    }

    /// The earliest time after the last tick at which a wait or a duration bound changes
    /// something (host actions finishing aside): a host with virtual time can jump there.
    pub fn next_deadline(&self) -> Option<i64> {
        self.deadline
    }

    /// When `event` was recorded, if it has been.
    pub fn event_time(&self, event: EventId) -> Option<i64> {
        self.event_time.get(event.0 as usize).copied().filter(|&t| t != NEVER)
    }

    /// True if `fluent` holds on the blackboard.
    pub fn fluent_holds(&self, fluent: FluentId) -> bool {
        (fluent.0 as usize) < self.program.module.fluents.len() && self.holds(fluent)
    }
}
