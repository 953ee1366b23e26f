//! Running a bytecode program in virtual time: the run loop, the trace host, and the
//! executed timeline as a timed plan (which `validate::validate_timed` checks).
//!
//! The loop never sleeps and never reads a clock: it ticks the VM at `now`, ticks again at
//! the same time while events keep being recorded (a node may wait for an event another
//! branch recorded later in the same tick), then jumps to the earliest time anything can
//! change: the VM's next deadline or the host's next completion.

use std::fmt::Write;

use kbvm::bytecode::{EventId, Instr};
#[cfg(feature = "sim")]
use kbvm::sim::{Arg, SimConfig, SimError, SimHost, World, initial_facts, program_cells};
use kbvm::{Failure, Host, Invocation, Poll, Program, Status, Vm};

#[cfg(feature = "sim")]
use crate::intern::Interner;
use crate::ir::hir::Term;
use crate::ir::unify::unifiable;

/// A host that completes each action after its nominal duration (its least duration).
#[derive(Default)]
pub struct TraceHost {
    /// Running actions: id, start time, completion time.
    running: Vec<(EventId, i64, i64)>,
}

/// A host in virtual time: it can say when it will next have news.
pub trait VirtualHost: Host {
    /// The earliest time after `now` at which a running action will complete (or fail).
    fn next_completion(&self, now: i64) -> Option<i64>;
}

#[cfg(feature = "sim")]
impl VirtualHost for SimHost {
    fn next_completion(&self, now: i64) -> Option<i64> {
        self.next_step().map(|t| t.max(now + 1))
    }
}

/// What happened to a host action, for the timeline.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum HostEvent {
    /// Started.
    Start,
    /// Finished successfully.
    Done,
    /// Refused or failed, with the host's reason.
    Failed(String),
    /// Stopped by the tree.
    Halted,
}

/// Wraps a host and records every start, completion, failure and halt with its time.
pub struct Logged<H> {
    /// The host.
    pub host: H,
    /// (time, action, what happened), in order.
    pub log: Vec<(i64, EventId, HostEvent)>,
}

impl<H> Logged<H> {
    /// Starts logging `host`.
    pub fn new(host: H) -> Logged<H> {
        Logged { host, log: Vec::new() }
    }
}

impl<H: Host> Host for Logged<H> {
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), String> {
        let result = self.host.start(action, now);
        let event = match &result {
            Ok(()) => HostEvent::Start,
            Err(why) => HostEvent::Failed(why.clone()),
        };
        self.log.push((now, action.id, event));
        result
    }

    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll {
        let poll = self.host.poll(action, now);
        match &poll {
            Poll::Running => {}
            Poll::Success => self.log.push((now, action.id, HostEvent::Done)),
            Poll::Failure(why) => self.log.push((now, action.id, HostEvent::Failed(why.clone()))),
        }
        poll
    }

    fn halt(&mut self, action: &Invocation<'_>, now: i64) {
        self.log.push((now, action.id, HostEvent::Halted));
        self.host.halt(action, now);
    }
}

impl<H: VirtualHost> VirtualHost for Logged<H> {
    fn next_completion(&self, now: i64) -> Option<i64> {
        self.host.next_completion(now)
    }
}

/// The simulated world built from a program's initial state, laid out around the cells the
/// program mentions; its table also covers `cells` (where a recovery may put blocks down).
#[cfg(feature = "sim")]
pub fn sim_world(program: &Program, config: SimConfig, cells: &[(i64, i64)]) -> Result<World, SimError> {
    let mut world = World::new(config, &initial_facts(program), &program_cells(program))?;
    world.add_cells(cells);
    Ok(world)
}

/// The cells of the table a problem's KB declares: the answers to `pos(X, Y)` (std/blocks.pl's
/// cells: the `cell/2` facts, or the paper's 5 x 5 grid), at most 10,000 of them; none when
/// the KB has no `pos/2`. The simulated table covers them, and a recovery puts blocks down
/// on them.
pub fn kb_cells(session: &mut crate::session::Session, problem: usize) -> Vec<(i64, i64)> {
    use crate::engine::{Cell, Machine, Next};
    let Some(pos) = session.interner().get("pos") else { return Vec::new() };
    let program = session.program(problem);
    let mut machine = Machine::new(&program, 1_000_000);
    let (x, y) = (machine.new_var(), machine.new_var());
    let goal = machine.new_compound(pos, &[x, y]);
    let mut cells = Vec::new();
    let _ = machine.solve(goal, |m| {
        if let (Cell::Int(x), Cell::Int(y)) = (m.deref(x), m.deref(y)) {
            cells.push((x, y));
        }
        if cells.len() >= 10_000 { Next::Stop } else { Next::More }
    });
    cells.sort();
    cells.dedup();
    cells
}

/// The world read back as HIR terms, and the blocks it cannot place.
#[cfg(feature = "sim")]
pub fn world_facts(world: &World, interner: &mut Interner) -> (Vec<Term>, Vec<String>) {
    let (facts, unaccounted) = world.facts();
    let terms = facts
        .iter()
        .map(|f| {
            let args = f
                .args
                .iter()
                .map(|a| match a {
                    Arg::Atom(text) => Term::Atom(interner.intern(text)),
                    Arg::Int(i) => Term::Int(*i),
                })
                .collect();
            Term::Compound(interner.intern(&f.name), args)
        })
        .collect();
    (terms, unaccounted)
}

/// The goal literals no fact of the world unifies with.
pub fn unmet_goals<'g>(goal: &'g [Term], world: &[Term]) -> Vec<&'g Term> {
    goal.iter().filter(|g| !world.iter().any(|f| unifiable(g, f))).collect()
}

impl VirtualHost for TraceHost {
    fn next_completion(&self, now: i64) -> Option<i64> {
        self.running.iter().map(|&(_, _, done)| done).filter(|&done| done > now).min()
    }
}

impl Host for TraceHost {
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), String> {
        self.running.push((action.id, now, now + action.min()));
        Ok(())
    }

    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll {
        match self.running.iter().position(|&(id, _, _)| id == action.id) {
            Some(i) if now >= self.running[i].2 => {
                self.running.swap_remove(i);
                Poll::Success
            }
            Some(_) => Poll::Running,
            None => Poll::Failure(format!("`{}` was never started", action.text())),
        }
    }

    fn halt(&mut self, action: &Invocation<'_>, _: i64) {
        self.running.retain(|&(id, _, _)| id != action.id);
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The tree succeeded.
    Success,
    /// A node failed.
    Failure(Failure),
    /// Nothing can happen any more, yet the tree has not finished (a wait for an event no
    /// node will record).
    Stuck,
    /// The time or tick budget ran out.
    Budget,
}

/// A finished run.
pub struct Run {
    /// How it ended.
    pub outcome: Outcome,
    /// The time of the last tick.
    pub end: i64,
    /// Ticks made.
    pub ticks: u64,
    /// When each event was recorded (`None` if it never was).
    pub events: Vec<Option<i64>>,
}

/// Ticks `program` against `host` from time 0 until it finishes, gets stuck, or passes
/// `max_time` (program units) or `max_ticks`.
pub fn run(program: &Program, host: &mut dyn VirtualHost, max_time: i64, max_ticks: u64) -> Run {
    let mut vm = Vm::new(program);
    let mut now = 0i64;
    let mut ticks = 0u64;
    let outcome = loop {
        let before = vm.events_recorded();
        let status = vm.tick(host, now);
        ticks += 1;
        match status {
            Status::Success => break Outcome::Success,
            Status::Failure => break vm.failure().cloned().map_or(Outcome::Stuck, Outcome::Failure),
            Status::Running => {}
        }
        if ticks >= max_ticks {
            break Outcome::Budget;
        }
        if vm.events_recorded() != before {
            continue; // tick again at the same time
        }
        let next = [vm.next_deadline(), host.next_completion(now)].into_iter().flatten().filter(|&t| t > now).min();
        match next {
            Some(t) if t > max_time => break Outcome::Budget,
            Some(t) => now = t,
            None => break Outcome::Stuck,
        }
    };
    let events = (0..program.module().events).map(|e| vm.event_time(EventId(e))).collect();
    Run { outcome, end: now, ticks, events }
}

/// The executed timeline as a timed plan in the PDDL 2.1 format (`kbc validate` reads it):
/// each action at its start's recorded time, with the time to its end's.
pub fn timed_plan(program: &Program, run: &Run) -> String {
    let m = program.module();
    let mut lines: Vec<(i64, usize, String)> = Vec::new();
    let time = |t: i64| program.time_text(t);
    let call = |import: &kbvm::bytecode::ImportId, args: &[kbvm::bytecode::Value]| {
        let mut text = format!("({}", program.import_name(*import));
        for &a in args {
            let _ = write!(text, " {}", program.value_text(a));
        }
        text.push(')');
        text
    };
    // The end event of each start event.
    let mut end_of = vec![None; m.events as usize];
    for node in &m.nodes {
        if let Instr::End { event, start, .. } = node {
            end_of[start.0 as usize] = Some(*event);
        }
    }
    for (i, node) in m.nodes.iter().enumerate() {
        match node {
            Instr::Start { event, import, args, .. } => {
                let Some(start) = run.events[event.0 as usize] else { continue };
                if let Some(end) = end_of[event.0 as usize].and_then(|e| run.events[e.0 as usize]) {
                    lines.push((start, i, format!("{}: {} [{}]", time(start), call(import, args), time(end - start))));
                }
            }
            Instr::Act { event, import, args, .. } => {
                if let Some(at) = run.events[event.0 as usize] {
                    lines.push((at, i, format!("{}: {}", time(at), call(import, args))));
                }
            }
            _ => {}
        }
    }
    lines.sort();
    let mut out = String::new();
    for (_, _, line) in lines {
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// The executed timeline of a run checked on the KB of `problem` by the timed validator; an
/// error here is a compiler bug, and a note says so.
pub fn check_timeline(
    session: &mut crate::session::Session,
    problem: usize,
    program: &Program,
    run: &Run,
) -> crate::diag::Diagnostics {
    let mut diagnostics = crate::diag::Diagnostics::new();
    let text = timed_plan(program, run);
    let file = session.add_text("<executed timeline>", text.clone());
    let steps = crate::validate::read_plan(file, &text, session.interner_mut(), &mut diagnostics);
    let kb_program = session.program(problem);
    let verdict = crate::validate::validate_timed(session.kb(), session.interner(), &kb_program, problem, &steps);
    diagnostics.extend(verdict.diagnostics);
    if diagnostics.has_errors() {
        diagnostics.push(crate::diag::Diagnostic::note("the executed timeline breaks the KB: this is a compiler bug"));
    }
    diagnostics
}
