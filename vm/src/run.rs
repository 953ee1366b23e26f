//! Running a program in virtual time: the loop that ticks the VM against a host, for any
//! embedder (`kbc run` uses it, and `examples/embed.rs`).
//!
//! The loop never sleeps and never reads a clock: it ticks the VM at `now`, ticks again at
//! the same time while events keep being recorded (a node may wait for an event another
//! branch recorded later in the same tick), then jumps to the earliest time anything can
//! change: the VM's next deadline or the host's next completion. So a run is reproducible,
//! and as fast as the host.

use crate::bytecode::EventId;
use crate::{Failure, Host, HostError, Invocation, LinkError, Poll, Program, Status, Vm};

/// A host in virtual time: it can say when it will next have news.
pub trait VirtualHost: Host {
    /// The earliest time after `now` at which a running action will complete (or fail).
    fn next_completion(&self, now: i64) -> Option<i64>;
}

/// A host that completes each action after its nominal duration (its least duration).
#[derive(Default)]
pub struct TraceHost {
    /// Running actions: id, start time, completion time.
    running: Vec<(EventId, i64, i64)>,
}

impl VirtualHost for TraceHost {
    fn next_completion(&self, now: i64) -> Option<i64> {
        self.running.iter().map(|&(_, _, done)| done).filter(|&done| done > now).min()
    }
}

impl Host for TraceHost {
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), HostError> {
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
            None => Poll::Failure(HostError::NotRunning(format!("`{}` was never started", action.text()))),
        }
    }

    fn halt(&mut self, action: &Invocation<'_>, _: i64) {
        self.running.retain(|&(id, _, _)| id != action.id);
    }
}

/// What happened to a host action, for the timeline.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum HostEvent {
    /// Started.
    Start,
    /// Finished successfully.
    Done,
    /// Refused or failed, with the host's reason.
    Failed(HostError),
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
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), HostError> {
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

    fn runs(&self, name: &str, arity: usize) -> bool {
        self.host.runs(name, arity)
    }
}

impl<H: VirtualHost> VirtualHost for Logged<H> {
    fn next_completion(&self, now: i64) -> Option<i64> {
        self.host.next_completion(now)
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
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
    /// The program starts an action the host does not run: found when linking, before the
    /// first tick.
    Unlinked(LinkError),
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

/// Links `program` against `host` ([`Program::link`]), then ticks it from time 0 until it
/// finishes, gets stuck, or passes `max_time` (program units) or `max_ticks`.
pub fn run(program: &Program, host: &mut dyn VirtualHost, max_time: i64, max_ticks: u64) -> Run {
    if let Err(error) = program.link(&*host) {
        let events = vec![None; program.module().events as usize];
        return Run { outcome: Outcome::Unlinked(error), end: 0, ticks: 0, events };
    }
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
