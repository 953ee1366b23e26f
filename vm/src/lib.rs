//! `kbvm` runs behaviour-tree bytecode produced by the `kbc` compiler.
//!
//! This crate is the single definition of the bytecode format (module [`bytecode`]; the
//! normative text is docs/bytecode.md): the compiler depends on it to encode programs, and
//! the VM never depends on the compiler. A program is loaded and verified once
//! ([`Program::load`]), then a [`Vm`] ticks it against a [`Host`] that starts, polls and
//! halts the robot's actions. Time is the `now` argument of [`Vm::tick`]: the VM never reads
//! a clock.
//!
//! The API on one screen:
//!
//! - [`Program::load`] reads and verifies a file; [`Program::link`] checks that a host runs
//!   every action the program starts (or every step of its refinement), like a linker.
//! - [`Vm::new`] and [`Vm::tick`] run it: each tick takes the time and returns a [`Status`];
//!   [`Vm::failure`] says which node failed and why ([`Reason`]).
//! - [`Host`] is the robot side: `start`, `poll` ([`Poll`]), `halt`, and `runs` (what it runs).
//! - [`run::run`] drives a program in virtual time against a [`run::VirtualHost`] (one that
//!   can say when it next has news), jumping from event to event; [`run::TraceHost`] completes
//!   every action after its least duration and [`run::Logged`] records a timeline.
//! - Features: `encode` (writing bytecode) and `disasm` (listings) are on by default; an
//!   embedder that only loads and runs programs can turn them off. `sim` adds the simulated
//!   arms (module `sim`).
//!
//! ```
//! use kbvm::bytecode::{Check, EventId, Import, ImportId, Instr, MaxTime, Module, NodeRef, Time};
//! use kbvm::{Host, HostError, Invocation, Poll, Program, Status, Vm};
//!
//! // A program with one durative action `wave`, taking 2 to 5 time units.
//! let module = Module {
//!     symbols: vec!["wave".into()],
//!     imports: vec![Import { name: 0, arity: 0 }],
//!     fluents: vec![],
//!     events: 2,
//!     time_scale: 1,
//!     root: NodeRef(0),
//!     nodes: vec![
//!         Instr::Sequence { children: vec![NodeRef(1), NodeRef(2)] },
//!         Instr::Start { event: EventId(0), import: ImportId(0), args: vec![], min: Time(2),
//!                        max: MaxTime(Some(5)), check: Check::default(), effects: vec![] },
//!         Instr::End { event: EventId(1), start: EventId(0), check: Check::default(), effects: vec![] },
//!     ],
//!     debug: None,
//!     refinements: Vec::new(),
//! };
//! let program = Program::load(&module.encode()).expect("a valid program");
//!
//! // A host whose actions finish 3 time units after they start.
//! struct Robot { started: i64 }
//! impl Host for Robot {
//!     fn start(&mut self, _: &Invocation<'_>, now: i64) -> Result<(), HostError> {
//!         self.started = now;
//!         Ok(())
//!     }
//!     fn poll(&mut self, _: &Invocation<'_>, now: i64) -> Poll {
//!         if now >= self.started + 3 { Poll::Success } else { Poll::Running }
//!     }
//!     fn halt(&mut self, _: &Invocation<'_>, _: i64) {}
//! }
//!
//! let mut vm = Vm::new(&program);
//! let mut robot = Robot { started: 0 };
//! let mut now = 0;
//! while vm.tick(&mut robot, now) == Status::Running {
//!     now += 1;
//! }
//! assert_eq!(vm.tick(&mut robot, now), Status::Success);
//! assert_eq!(now, 3);
//! ```

#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod blocks;
pub mod bytecode;
mod program;
pub mod rng;
pub mod run;
mod vm;

#[cfg(feature = "sim")]
pub mod sim;

pub use bytecode::{LoadError, Value};
pub use program::{LinkError, Location, Program};
pub use vm::{Failure, Host, HostError, Invocation, Poll, Reason, Status, Vm};
