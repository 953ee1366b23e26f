//! The bytecode format: every node kind and opcode round-trips, corrupted files are refused
//! with the right error, and thousands of mutated files never make the loader panic.

use kbvm::Program;
use kbvm::bytecode::{
    Call, Check, DebugEntry, DebugInfo, Delay, Effect, EventId, Fluent, FluentId, Import, ImportId, Instr,
    LoadErrorKind, MaxTime, Module, NodeRef, Refinement, Time, Value,
};
use proptest::prelude::*;

/// A module using every opcode: par(seq(start, wait, end), act).
fn sample() -> Module {
    let check =
        Check { require: vec![FluentId(0)], forbid: vec![FluentId(1)], any: vec![vec![FluentId(0), FluentId(1)]] };
    Module {
        symbols: vec![
            "grip".into(),
            "a1".into(),
            "beep".into(),
            "free".into(),
            "kb.pl".into(),
            "grip_start(a1, 3)".into(),
        ],
        imports: vec![Import { name: 0, arity: 2 }, Import { name: 2, arity: 0 }],
        fluents: vec![
            Fluent { functor: 3, args: vec![Value::Atom(1)], initial: true },
            Fluent { functor: 3, args: vec![Value::Int(-7)], initial: false },
        ],
        events: 3,
        time_scale: 1000,
        root: NodeRef(0),
        nodes: vec![
            Instr::Parallel { children: vec![NodeRef(1), NodeRef(5)] },
            Instr::Sequence { children: vec![NodeRef(2), NodeRef(3), NodeRef(4)] },
            Instr::Start {
                event: EventId(0),
                import: ImportId(0),
                args: vec![Value::Atom(1), Value::Int(3)],
                min: Time(1000),
                max: MaxTime(Some(2000)),
                check: check.clone(),
                effects: vec![Effect { add: false, fluent: FluentId(0) }, Effect { add: true, fluent: FluentId(1) }],
            },
            Instr::Wait { after: vec![Delay { event: EventId(0), after: Time(1) }] },
            Instr::End { event: EventId(1), start: EventId(0), check: Check::default(), effects: vec![] },
            Instr::Act { event: EventId(2), import: ImportId(1), args: vec![], check, effects: vec![] },
        ],
        debug: Some(DebugInfo {
            files: vec![4],
            entries: vec![DebugEntry { node: NodeRef(2), file: 0, line: 3, column: 1, label: 5 }],
        }),
        refinements: vec![
            Refinement {
                node: NodeRef(2),
                steps: vec![
                    Call { import: ImportId(1), args: vec![] },
                    Call { import: ImportId(0), args: vec![Value::Atom(1), Value::Int(-2)] },
                ],
            },
            Refinement { node: NodeRef(5), steps: vec![Call { import: ImportId(1), args: vec![] }] },
        ],
    }
}

#[test]
fn the_sample_uses_every_opcode_and_round_trips() {
    let module = sample();
    let mut used: Vec<u8> = module.nodes.iter().map(Instr::opcode).collect();
    used.sort();
    used.dedup();
    let all: Vec<u8> = Instr::OPCODES.iter().map(|&(op, _)| op).collect();
    assert_eq!(used, all, "the sample must use every opcode");
    let bytes = module.encode();
    assert_eq!(Module::decode(&bytes), Ok(module.clone()));
    assert_eq!(bytes, Module::decode(&bytes).expect("loads").encode(), "encoding is canonical");
}

fn kind(bytes: &[u8]) -> LoadErrorKind {
    Module::decode(bytes).expect_err("must be refused").kind
}

#[test]
fn corrupted_files_are_refused_with_the_right_error() {
    let good = sample().encode();
    // Truncations: at every length the file is refused.
    for len in 0..good.len() {
        assert!(Module::decode(&good[..len]).is_err(), "truncated to {len} bytes");
    }
    assert_eq!(kind(b"KBB"), LoadErrorKind::BadMagic);
    assert_eq!(kind(b"ELF\x7f\x01\x00"), LoadErrorKind::BadMagic);
    let mut wrong_version = good.clone();
    wrong_version[4] = 9;
    assert_eq!(kind(&wrong_version), LoadErrorKind::UnsupportedVersion(9));
    let mut trailing = good.clone();
    trailing.push(0);
    assert_eq!(kind(&trailing), LoadErrorKind::TrailingBytes);
    let mut sections = good.clone();
    sections[8] = 200;
    assert_eq!(kind(&sections), LoadErrorKind::TooManySections(200));

    // Out-of-range indices, through modules that encode but must not load.
    let mut m = sample();
    m.fluents[0].functor = 99;
    assert!(matches!(kind(&m.encode()), LoadErrorKind::IndexOutOfRange { what: "symbol", index: 99, .. }));
    let mut m = sample();
    if let Instr::Start { import, .. } = &mut m.nodes[2] {
        *import = ImportId(7);
    }
    assert!(matches!(kind(&m.encode()), LoadErrorKind::IndexOutOfRange { what: "import", index: 7, .. }));
    let mut m = sample();
    if let Instr::Wait { after } = &mut m.nodes[3] {
        after[0].event = EventId(3);
    }
    assert!(matches!(kind(&m.encode()), LoadErrorKind::IndexOutOfRange { what: "event", index: 3, .. }));
    let mut m = sample();
    if let Instr::Start { effects, .. } = &mut m.nodes[2] {
        effects[0].fluent = FluentId(2);
    }
    assert!(matches!(kind(&m.encode()), LoadErrorKind::IndexOutOfRange { what: "fluent", index: 2, .. }));
    // Not a tree: a node with two parents, and the root as a child.
    let mut m = sample();
    m.nodes[0] = Instr::Parallel { children: vec![NodeRef(1), NodeRef(5), NodeRef(5)] };
    assert!(matches!(kind(&m.encode()), LoadErrorKind::NotATree(_)));
    let mut m = sample();
    m.nodes[1] = Instr::Sequence { children: vec![NodeRef(2), NodeRef(3), NodeRef(4), NodeRef(0)] };
    assert!(matches!(kind(&m.encode()), LoadErrorKind::NotATree(_)));
    // Arity, durations, events.
    let mut m = sample();
    if let Instr::Start { args, .. } = &mut m.nodes[2] {
        args.pop();
    }
    assert_eq!(kind(&m.encode()), LoadErrorKind::ArityMismatch { expected: 2, found: 1 });
    let mut m = sample();
    if let Instr::Start { max, .. } = &mut m.nodes[2] {
        *max = MaxTime(Some(10));
    }
    assert_eq!(kind(&m.encode()), LoadErrorKind::BadTime(1000));
    let mut m = sample();
    if let Instr::End { start, .. } = &mut m.nodes[4] {
        *start = EventId(2);
    }
    assert!(matches!(kind(&m.encode()), LoadErrorKind::BadEvent(_, 2)));
    let mut m = sample();
    m.events = 4;
    assert!(matches!(kind(&m.encode()), LoadErrorKind::BadEvent("recorded by no node", 3)));
}

#[test]
fn a_child_reference_must_land_on_a_node() {
    let mut bytes = sample().encode();
    // Find the code section from the section table (kind 4) and corrupt the root offset.
    let count = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes")) as usize;
    let entry = (0..count).map(|i| 16 + 12 * i).find(|&at| bytes[at] == 4).expect("a code section");
    let code_at = u32::from_le_bytes(bytes[entry + 4..entry + 8].try_into().expect("4 bytes")) as usize;
    bytes[code_at] = 13; // the root offset now points into the middle of a node
    assert!(matches!(kind(&bytes), LoadErrorKind::NotANode { offset: 13 }));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4000, ..ProptestConfig::default() })]

    /// Flipped, overwritten, inserted and removed bytes: an error or a program, never a panic;
    /// and what loads runs a few ticks without panicking either.
    #[test]
    fn mutated_files_never_panic(edits in proptest::collection::vec((any::<usize>(), any::<u8>(), 0u8..4), 1..6)) {
        let mut bytes = sample().encode();
        for (at, value, how) in edits {
            let at = at % (bytes.len() + 1);
            match how {
                0 if at < bytes.len() => bytes[at] ^= value | 1,
                1 if at < bytes.len() => bytes[at] = value,
                2 => bytes.insert(at, value),
                _ if at < bytes.len() => { bytes.remove(at); }
                _ => {}
            }
        }
        if let Ok(program) = Program::load(&bytes) {
            let mut vm = kbvm::Vm::new(&program);
            let mut host = Always;
            for now in 0..5 {
                vm.tick(&mut host, now * 1000);
            }
        }
    }

    /// Random modules built from the sample's parts round-trip exactly.
    #[test]
    fn random_waits_and_values_round_trip(delays in proptest::collection::vec((0u32..3, 0i64..1_000_000), 0..8), int in any::<i64>()) {
        let mut m = sample();
        if let Instr::Wait { after } = &mut m.nodes[3] {
            *after = delays.iter().map(|&(e, d)| Delay { event: EventId(e), after: Time(d) }).collect();
        }
        m.fluents[1].args = vec![Value::Int(int), Value::Atom(0)];
        prop_assert_eq!(Module::decode(&m.encode()), Ok(m));
    }
}

/// A host whose actions always succeed at once.
struct Always;

impl kbvm::Host for Always {
    fn start(&mut self, _: &kbvm::Invocation<'_>, _: i64) -> Result<(), kbvm::HostError> {
        Ok(())
    }
    fn poll(&mut self, _: &kbvm::Invocation<'_>, _: i64) -> kbvm::Poll {
        kbvm::Poll::Success
    }
    fn halt(&mut self, _: &kbvm::Invocation<'_>, _: i64) {}
}

/// A random well-formed module from `seed`: a root parallel of branches, each a sequence of
/// durative actions (start and end), instantaneous actions, waits on earlier events and
/// nested parallels; random arguments, conditions and effects.
fn random_module(seed: u64) -> Module {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = move |n: u64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n.max(1)
    };
    let fluents: Vec<Fluent> = (0..1 + next(6))
        .map(|i| Fluent { functor: (i % 3) as u32, args: vec![Value::Int(i as i64 - 2)], initial: next(2) == 0 })
        .collect();
    let mut m = Module {
        symbols: vec!["on".into(), "clear".into(), "grip".into(), "a1".into()],
        imports: vec![Import { name: 2, arity: 1 }, Import { name: 1, arity: 0 }],
        fluents,
        events: 0,
        time_scale: 1 + next(1000) as u32,
        root: NodeRef(0),
        nodes: vec![Instr::Parallel { children: vec![] }],
        debug: Some(DebugInfo { files: vec![3], entries: vec![] }),
        refinements: Vec::new(),
    };
    let nf = m.fluents.len() as u64;
    fn branch(m: &mut Module, next: &mut dyn FnMut(u64) -> u64, nf: u64, depth: u32) -> NodeRef {
        let at = m.nodes.len();
        m.nodes.push(Instr::Sequence { children: vec![] });
        let mut children = Vec::new();
        for _ in 0..1 + next(4) {
            let fluent = |next: &mut dyn FnMut(u64) -> u64| FluentId(next(nf) as u32);
            let check = Check {
                require: (0..next(3)).map(|_| fluent(next)).collect(),
                forbid: (0..next(2)).map(|_| fluent(next)).collect(),
                any: (0..next(2)).map(|_| (0..1 + next(2)).map(|_| fluent(next)).collect()).collect(),
            };
            let effects: Vec<Effect> =
                (0..next(3)).map(|_| Effect { add: next(2) == 0, fluent: fluent(next) }).collect();
            let event = m.events;
            match next(4) {
                0 if depth < 3 => {
                    let par = m.nodes.len();
                    m.nodes.push(Instr::Parallel { children: vec![] });
                    let kids = (0..2).map(|_| branch(m, next, nf, depth + 1)).collect();
                    m.nodes[par] = Instr::Parallel { children: kids };
                    children.push(NodeRef(par as u32));
                }
                1 if event > 0 => {
                    children.push(NodeRef(m.nodes.len() as u32));
                    let after = (0..1 + next(3))
                        .map(|_| Delay { event: EventId(next(event as u64) as u32), after: Time(next(50) as i64) })
                        .collect();
                    m.nodes.push(Instr::Wait { after });
                }
                2 => {
                    m.events += 1;
                    children.push(NodeRef(m.nodes.len() as u32));
                    m.nodes.push(Instr::Act {
                        event: EventId(event),
                        import: ImportId(1),
                        args: vec![],
                        check,
                        effects,
                    });
                }
                _ => {
                    m.events += 2;
                    let min = next(100) as i64;
                    let max = if next(2) == 0 { MaxTime(None) } else { MaxTime(Some(min + next(100) as i64)) };
                    let start_at = m.nodes.len() as u32;
                    let arg = if next(2) == 0 { Value::Atom(3) } else { Value::Int(next(9) as i64) };
                    m.nodes.push(Instr::Start {
                        event: EventId(event),
                        import: ImportId(0),
                        args: vec![arg],
                        min: Time(min),
                        max,
                        check: check.clone(),
                        effects: effects.clone(),
                    });
                    m.nodes.push(Instr::End { event: EventId(event + 1), start: EventId(event), check, effects });
                    if next(2) == 0 {
                        let steps = (0..1 + next(3))
                            .map(|_| match next(2) {
                                0 => Call { import: ImportId(1), args: vec![] },
                                _ => Call { import: ImportId(0), args: vec![Value::Int(next(9) as i64)] },
                            })
                            .collect();
                        m.refinements.push(Refinement { node: NodeRef(start_at), steps });
                    }
                    children.push(NodeRef(start_at));
                    children.push(NodeRef(start_at + 1));
                    if let Some(debug) = &mut m.debug {
                        debug.entries.push(DebugEntry {
                            node: NodeRef(start_at),
                            file: 0,
                            line: 1 + next(99) as u32,
                            column: 1,
                            label: 2,
                        });
                    }
                }
            }
        }
        m.nodes[at] = Instr::Sequence { children };
        NodeRef(at as u32)
    }
    let branches = (0..1 + next(3)).map(|_| branch(&mut m, &mut next, nf, 0)).collect();
    m.nodes[0] = Instr::Parallel { children: branches };
    m
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    /// Random modules with every node kind round-trip exactly, and re-encode to the same bytes.
    #[test]
    fn random_modules_round_trip(seed in any::<u64>()) {
        let m = random_module(seed);
        let bytes = m.encode();
        let decoded = Module::decode(&bytes);
        prop_assert_eq!(decoded.as_ref(), Ok(&m));
        prop_assert_eq!(decoded.map(|d| d.encode()), Ok(bytes));
    }
}

#[test]
fn random_modules_use_every_opcode() {
    let mut used = std::collections::BTreeSet::new();
    for seed in 0..200 {
        used.extend(random_module(seed).nodes.iter().map(Instr::opcode));
    }
    let all: std::collections::BTreeSet<u8> = Instr::OPCODES.iter().map(|&(op, _)| op).collect();
    assert_eq!(used, all);
}

#[test]
fn refinements_are_verified() {
    let refused = |change: &dyn Fn(&mut Module)| {
        let mut m = sample();
        change(&mut m);
        kind(&m.encode())
    };
    assert_eq!(
        refused(&|m| m.refinements[0].node = NodeRef(1)),
        LoadErrorKind::BadRefinement("refines a node that is not an action")
    );
    assert_eq!(refused(&|m| m.refinements.swap(0, 1)), LoadErrorKind::BadRefinement("entries out of node order"));
    assert_eq!(
        refused(&|m| m.refinements[1].steps.clear()),
        LoadErrorKind::BadRefinement("a refinement without steps")
    );
    assert_eq!(
        refused(&|m| m.refinements[0].steps[1].args.pop().map_or((), drop)),
        LoadErrorKind::ArityMismatch { expected: 2, found: 1 }
    );
    assert!(matches!(
        refused(&|m| m.refinements[0].steps[0].import = ImportId(7)),
        LoadErrorKind::IndexOutOfRange { what: "import", index: 7, .. }
    ));
}

#[test]
fn a_program_gives_each_action_its_steps() {
    let program = Program::load(&sample().encode()).expect("loads");
    let steps = program.steps(EventId(0));
    let texts: Vec<String> = steps.iter().map(|c| program.call_text(c)).collect();
    assert_eq!(texts, ["beep", "grip(a1, -2)"]);
    assert!(program.steps(EventId(1)).is_empty(), "an end event has no steps");
    assert_eq!(program.steps(EventId(2)).len(), 1);
}
