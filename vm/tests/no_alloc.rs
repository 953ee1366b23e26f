//! The VM allocates nothing per tick in the steady state: a counting global allocator watches
//! a thousand ticks of a running tree.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use kbvm::bytecode::{Check, Delay, EventId, Import, ImportId, Instr, MaxTime, Module, NodeRef, Time};
use kbvm::{Host, Invocation, Poll, Program, Status, Vm};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: forwards the caller's layout to the system allocator unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `alloc` above with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Actions finish 5 units after they start, so the tree keeps changing for a while.
struct Timer;

impl Host for Timer {
    fn start(&mut self, _: &Invocation<'_>, _: i64) -> Result<(), kbvm::HostError> {
        Ok(())
    }
    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll {
        if now >= 5 * (action.id.0 as i64 + 1) { Poll::Success } else { Poll::Running }
    }
    fn halt(&mut self, _: &Invocation<'_>, _: i64) {}
}

#[test]
fn ticking_a_running_tree_allocates_nothing() {
    // par(seq(start e0, end e1), seq(wait e1+3, start e2, end e3), seq(start e4, end e5))
    let start = |e: u32| Instr::Start {
        event: EventId(e),
        import: ImportId(0),
        args: vec![],
        min: Time(1),
        max: MaxTime(Some(10_000)),
        check: Check::default(),
        effects: vec![],
    };
    let end =
        |e: u32, s: u32| Instr::End { event: EventId(e), start: EventId(s), check: Check::default(), effects: vec![] };
    let module = Module {
        symbols: vec!["work".into()],
        imports: vec![Import { name: 0, arity: 0 }],
        fluents: vec![],
        events: 6,
        time_scale: 1,
        root: NodeRef(0),
        nodes: vec![
            Instr::Parallel { children: vec![NodeRef(1), NodeRef(4), NodeRef(8)] },
            Instr::Sequence { children: vec![NodeRef(2), NodeRef(3)] },
            start(0),
            end(1, 0),
            Instr::Sequence { children: vec![NodeRef(5), NodeRef(6), NodeRef(7)] },
            Instr::Wait { after: vec![Delay { event: EventId(1), after: Time(3) }] },
            start(2),
            end(3, 2),
            Instr::Sequence { children: vec![NodeRef(9), NodeRef(10)] },
            start(4),
            end(5, 4),
        ],
        debug: None,
        refinements: Vec::new(),
    };
    let program = Program::load(&module.encode()).expect("valid");
    let mut vm = Vm::new(&program);
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    let mut last = Status::Running;
    for now in 0..1000 {
        last = vm.tick(&mut Timer, now);
    }
    let during = ALLOCATIONS.load(Ordering::Relaxed) - before;
    assert_eq!(last, Status::Success, "the tree ran to the end");
    assert_eq!(during, 0, "allocations while ticking");
}
