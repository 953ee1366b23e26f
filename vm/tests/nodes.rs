//! Node contracts, tick by tick, with scripted host actions that succeed, fail, and never
//! finish.

use kbvm::bytecode::{
    Check, Delay, Effect, EventId, Fluent, FluentId, Import, ImportId, Instr, MaxTime, Module, NodeRef, Time,
};
use kbvm::{Host, Invocation, Poll, Program, Reason, Status, Vm};

/// What a scripted action does: finish at a time after its start, fail then, or never end.
#[derive(Clone, Copy)]
enum Script {
    SucceedAfter(i64),
    FailAfter(i64),
    Never,
}

/// A host playing a script per action (by start event), logging every call.
struct Scripted {
    scripts: Vec<Script>,
    started: Vec<Option<i64>>,
    log: Vec<String>,
}

impl Scripted {
    fn new(scripts: &[Script]) -> Scripted {
        Scripted { scripts: scripts.to_vec(), started: vec![None; 16], log: Vec::new() }
    }
}

impl Host for Scripted {
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), kbvm::HostError> {
        self.started[action.id.0 as usize] = Some(now);
        self.log.push(format!("start {} {}", action.text(), now));
        Ok(())
    }
    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll {
        let started = self.started[action.id.0 as usize].expect("polled after start");
        match self.scripts[action.id.0 as usize] {
            Script::SucceedAfter(d) if now >= started + d => Poll::Success,
            Script::FailAfter(d) if now >= started + d => {
                Poll::Failure(kbvm::HostError::Failed("gripper slipped".into()))
            }
            _ => Poll::Running,
        }
    }
    fn halt(&mut self, action: &Invocation<'_>, now: i64) {
        self.log.push(format!("halt {} {}", action.text(), now));
    }
}

fn start(event: u32, min: i64, max: Option<i64>) -> Instr {
    Instr::Start {
        event: EventId(event),
        import: ImportId(0),
        args: vec![],
        min: Time(min),
        max: MaxTime(max),
        check: Check::default(),
        effects: vec![],
    }
}

fn end(event: u32, of: u32) -> Instr {
    Instr::End { event: EventId(event), start: EventId(of), check: Check::default(), effects: vec![] }
}

fn program(nodes: Vec<Instr>, events: u32, fluents: Vec<Fluent>) -> Program {
    let module = Module {
        symbols: vec!["work".into(), "holding".into()],
        imports: vec![Import { name: 0, arity: 0 }],
        fluents,
        events,
        time_scale: 1,
        root: NodeRef(0),
        nodes,
        debug: None,
        refinements: Vec::new(),
    };
    Program::load(&module.encode()).expect("a valid program")
}

/// seq(start e0 [min 2, max 5], end e1)
fn one_action(max: Option<i64>) -> Program {
    program(vec![Instr::Sequence { children: vec![NodeRef(1), NodeRef(2)] }, start(0, 2, max), end(1, 0)], 2, vec![])
}

#[test]
fn an_action_ends_when_the_host_says_and_its_least_duration_has_passed() {
    let p = one_action(Some(5));
    let mut host = Scripted::new(&[Script::SucceedAfter(1)]);
    let mut vm = Vm::new(&p);
    assert_eq!(vm.tick(&mut host, 0), Status::Running); // started, host still busy
    assert_eq!(vm.event_time(EventId(0)), Some(0));
    assert_eq!(vm.tick(&mut host, 1), Status::Running); // host done, but the least duration is 2
    assert_eq!(vm.next_deadline(), Some(2));
    assert_eq!(vm.event_time(EventId(1)), None);
    assert_eq!(vm.tick(&mut host, 2), Status::Success);
    assert_eq!(vm.event_time(EventId(1)), Some(2));
    assert_eq!(vm.tick(&mut host, 3), Status::Success, "a finished tree stays finished");
    assert_eq!(host.log, vec!["start work 0"]);
}

#[test]
fn an_action_that_never_finishes_fails_at_its_greatest_duration_and_is_halted() {
    let p = one_action(Some(5));
    let mut host = Scripted::new(&[Script::Never]);
    let mut vm = Vm::new(&p);
    assert_eq!(vm.tick(&mut host, 0), Status::Running);
    assert_eq!(vm.tick(&mut host, 5), Status::Running, "exactly at the bound is allowed");
    assert_eq!(vm.next_deadline(), Some(6));
    assert_eq!(vm.tick(&mut host, 6), Status::Failure);
    let failure = vm.failure().expect("a failure");
    assert_eq!(failure.reason, Reason::Overran { max: 5 });
    assert_eq!(failure.node, NodeRef(2));
    assert_eq!(host.log, vec!["start work 0", "halt work 6"]);
}

#[test]
fn without_a_greatest_duration_an_action_may_run_forever() {
    let p = one_action(None);
    let mut host = Scripted::new(&[Script::Never]);
    let mut vm = Vm::new(&p);
    for now in [0, 10, 1_000_000] {
        assert_eq!(vm.tick(&mut host, now), Status::Running);
    }
}

#[test]
fn a_host_failure_fails_the_end_node() {
    let p = one_action(Some(5));
    let mut host = Scripted::new(&[Script::FailAfter(1)]);
    let mut vm = Vm::new(&p);
    assert_eq!(vm.tick(&mut host, 0), Status::Running);
    assert_eq!(vm.tick(&mut host, 1), Status::Failure);
    assert_eq!(
        vm.failure().map(|f| f.reason.clone()),
        Some(Reason::HostFailed(kbvm::HostError::Failed("gripper slipped".into())))
    );
}

/// par(seq(start e0, end e1), seq(start e2, end e3))
fn two_in_parallel() -> Program {
    program(
        vec![
            Instr::Parallel { children: vec![NodeRef(1), NodeRef(4)] },
            Instr::Sequence { children: vec![NodeRef(2), NodeRef(3)] },
            start(0, 0, Some(100)),
            end(1, 0),
            Instr::Sequence { children: vec![NodeRef(5), NodeRef(6)] },
            start(2, 0, Some(100)),
            end(3, 2),
        ],
        4,
        vec![],
    )
}

#[test]
fn a_parallel_succeeds_when_all_children_have() {
    let p = two_in_parallel();
    let mut host = Scripted::new(&[Script::SucceedAfter(3), Script::SucceedAfter(0), Script::SucceedAfter(1)]);
    let mut vm = Vm::new(&p);
    assert_eq!(vm.tick(&mut host, 0), Status::Running);
    assert_eq!(host.log, vec!["start work 0", "start work 0"], "both branches start in the first tick");
    assert_eq!(vm.tick(&mut host, 1), Status::Running);
    assert_eq!(vm.event_time(EventId(3)), Some(1), "the second branch finished alone");
    assert_eq!(vm.tick(&mut host, 3), Status::Success);
}

#[test]
fn a_parallel_fails_as_soon_as_one_child_fails_and_halts_the_others() {
    let p = two_in_parallel();
    let mut host = Scripted::new(&[Script::Never, Script::SucceedAfter(0), Script::FailAfter(2)]);
    let mut vm = Vm::new(&p);
    assert_eq!(vm.tick(&mut host, 0), Status::Running);
    assert_eq!(vm.tick(&mut host, 2), Status::Failure);
    assert_eq!(host.log.last().map(String::as_str), Some("halt work 2"), "the first branch's action is halted");
}

#[test]
fn a_wait_holds_its_sequence_until_the_event_and_delay() {
    // par(seq(start e0 [min 4], end e1), seq(wait e1+2, start e2, end e3))
    let p = program(
        vec![
            Instr::Parallel { children: vec![NodeRef(1), NodeRef(4)] },
            Instr::Sequence { children: vec![NodeRef(2), NodeRef(3)] },
            start(0, 4, None),
            end(1, 0),
            Instr::Sequence { children: vec![NodeRef(5), NodeRef(6), NodeRef(7)] },
            Instr::Wait { after: vec![Delay { event: EventId(1), after: Time(2) }] },
            start(2, 0, None),
            end(3, 2),
        ],
        4,
        vec![],
    );
    let mut host = Scripted::new(&[Script::SucceedAfter(0), Script::SucceedAfter(0), Script::SucceedAfter(0)]);
    let mut vm = Vm::new(&p);
    assert_eq!(vm.tick(&mut host, 0), Status::Running);
    assert_eq!(vm.event_time(EventId(2)), None, "waiting for an event not yet recorded");
    assert_eq!(vm.tick(&mut host, 4), Status::Running);
    assert_eq!(vm.event_time(EventId(1)), Some(4));
    // The wait was ticked before the end in this tick: the next tick sees the event.
    assert_eq!(vm.tick(&mut host, 4), Status::Running);
    assert_eq!(vm.next_deadline(), Some(6));
    assert_eq!(vm.tick(&mut host, 5), Status::Running);
    assert_eq!(vm.tick(&mut host, 6), Status::Success);
    assert_eq!(vm.event_time(EventId(2)), Some(6));
}

#[test]
fn conditions_and_effects_work_on_the_blackboard() {
    // seq(act e0 requiring not holding, adding holding; act e1 requiring not holding)
    let holding = Fluent { functor: 1, args: vec![], initial: false };
    let act = |event: u32, effects: Vec<Effect>| Instr::Act {
        event: EventId(event),
        import: ImportId(0),
        args: vec![],
        check: Check { require: vec![], forbid: vec![FluentId(0)], any: vec![] },
        effects,
    };
    let p = program(
        vec![
            Instr::Sequence { children: vec![NodeRef(1), NodeRef(2)] },
            act(0, vec![Effect { add: true, fluent: FluentId(0) }]),
            act(1, vec![]),
        ],
        2,
        vec![holding],
    );
    let mut host = Scripted::new(&[Script::SucceedAfter(1), Script::SucceedAfter(1)]);
    let mut vm = Vm::new(&p);
    assert_eq!(vm.tick(&mut host, 0), Status::Running);
    assert!(!vm.fluent_holds(FluentId(0)), "effects apply when the host reports back");
    assert_eq!(vm.tick(&mut host, 1), Status::Failure);
    assert!(vm.fluent_holds(FluentId(0)));
    let failure = vm.failure().expect("a failure");
    assert_eq!(failure.reason, Reason::Forbidden(FluentId(0)));
    assert_eq!(failure.describe(&p), "node @2 failed at program time 1: `holding` holds, and the action forbids it");
    vm.reset();
    assert!(!vm.fluent_holds(FluentId(0)), "reset restores the initial blackboard");
    assert_eq!(vm.event_time(EventId(0)), None);
}

#[test]
fn the_tick_budget_bounds_a_tick() {
    let p = two_in_parallel();
    let mut host = Scripted::new(&[Script::Never, Script::Never, Script::Never]);
    let mut vm = Vm::new(&p);
    vm.set_tick_budget(3);
    assert_eq!(vm.tick(&mut host, 0), Status::Failure);
    assert_eq!(vm.failure().map(|f| f.reason.clone()), Some(Reason::Budget));
}

#[test]
fn halt_stops_every_running_action() {
    let p = two_in_parallel();
    let mut host = Scripted::new(&[Script::Never, Script::Never, Script::Never]);
    let mut vm = Vm::new(&p);
    assert_eq!(vm.tick(&mut host, 0), Status::Running);
    vm.halt(&mut host, 7);
    assert_eq!(host.log.iter().filter(|l| l.starts_with("halt")).count(), 2);
    assert_eq!(vm.tick(&mut host, 8), Status::Failure);
    assert_eq!(vm.failure().map(|f| f.reason.clone()), Some(Reason::Halted));
}

/// A host that runs only the actions it names.
struct Picky {
    inner: kbvm::run::TraceHost,
    runs: &'static [(&'static str, usize)],
}

impl Host for Picky {
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), kbvm::HostError> {
        self.inner.start(action, now)
    }
    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll {
        self.inner.poll(action, now)
    }
    fn halt(&mut self, action: &Invocation<'_>, now: i64) {
        self.inner.halt(action, now);
    }
    fn runs(&self, name: &str, arity: usize) -> bool {
        self.runs.contains(&(name, arity))
    }
}

impl kbvm::run::VirtualHost for Picky {
    fn next_completion(&self, now: i64) -> Option<i64> {
        self.inner.next_completion(now)
    }
}

#[test]
fn a_run_links_the_program_with_the_host_before_the_first_tick() {
    use kbvm::run::{Outcome, run};
    let program = program(
        vec![Instr::Sequence { children: vec![NodeRef(1), NodeRef(2)] }, start(0, 2, None), end(1, 0)],
        2,
        vec![],
    );
    // A host that runs `work/0` links and runs it to the end.
    let mut fine = Picky { inner: Default::default(), runs: &[("work", 0)] };
    assert!(program.link(&fine).is_ok());
    assert_eq!(run(&program, &mut fine, 100, 100).outcome, Outcome::Success);
    // One that does not is refused before anything starts, naming what it lacks.
    let mut other = Picky { inner: Default::default(), runs: &[("work", 1)] };
    let error = program.link(&other).expect_err("`work/0` is missing");
    assert_eq!((error.action.as_str(), error.missing.as_str(), error.refined), ("work", "work/0", false));
    let ran = run(&program, &mut other, 100, 100);
    assert_eq!(ran.outcome, Outcome::Unlinked(error));
    assert_eq!((ran.ticks, ran.events), (0, vec![None, None]), "nothing ran");
}
