//! The benchmarks' shared workload: a wide tree of durative actions and a host that never
//! finishes them.

use kbvm::bytecode::{
    Check, Effect, EventId, Fluent, FluentId, Import, ImportId, Instr, MaxTime, Module, NodeRef, Time, Value,
};
use kbvm::{Host, Invocation, Poll};

/// par(seq(start a_i, end a_i) for each i), each action with a condition and two effects.
pub fn program(actions: usize) -> Module {
    let mut nodes = vec![Instr::Parallel { children: Vec::new() }];
    let mut branches = Vec::new();
    let mut fluents = Vec::new();
    for i in 0..actions {
        let free = FluentId(2 * i as u32);
        let busy = FluentId(2 * i as u32 + 1);
        fluents.push(Fluent { functor: 1, args: vec![Value::Int(i as i64)], initial: true });
        fluents.push(Fluent { functor: 2, args: vec![Value::Int(i as i64)], initial: false });
        let at = nodes.len() as u32;
        branches.push(NodeRef(at));
        nodes.push(Instr::Sequence { children: vec![NodeRef(at + 1), NodeRef(at + 2)] });
        nodes.push(Instr::Start {
            event: EventId(2 * i as u32),
            import: ImportId(0),
            args: vec![Value::Int(i as i64), Value::Atom(3)],
            min: Time(1000),
            max: MaxTime(None),
            check: Check { require: vec![free], forbid: vec![busy], any: vec![] },
            effects: vec![Effect { add: false, fluent: free }, Effect { add: true, fluent: busy }],
        });
        nodes.push(Instr::End {
            event: EventId(2 * i as u32 + 1),
            start: EventId(2 * i as u32),
            check: Check { require: vec![busy], forbid: vec![], any: vec![] },
            effects: vec![Effect { add: false, fluent: busy }, Effect { add: true, fluent: free }],
        });
    }
    nodes[0] = Instr::Parallel { children: branches };
    Module {
        symbols: vec!["work".into(), "free".into(), "busy".into(), "a1".into()],
        imports: vec![Import { name: 0, arity: 2 }],
        fluents,
        events: 2 * actions as u32,
        time_scale: 1000,
        root: NodeRef(0),
        nodes,
        debug: None,
        refinements: Vec::new(),
    }
}

/// A host whose actions never finish.
pub struct Busy;

impl Host for Busy {
    fn start(&mut self, _: &Invocation<'_>, _: i64) -> Result<(), kbvm::HostError> {
        Ok(())
    }
    fn poll(&mut self, _: &Invocation<'_>, _: i64) -> Poll {
        Poll::Running
    }
    fn halt(&mut self, _: &Invocation<'_>, _: i64) {}
}
