//! A loaded, verified program and the tables the VM derives from it once.

use crate::bytecode::{Call, EventId, FluentId, ImportId, Instr, LoadError, Module, NodeRef, Value};

/// A verified program, ready to run. Loading checks the whole file ([`Module::decode`]);
/// nothing the VM does afterwards can index out of bounds.
#[derive(Clone, Debug)]
pub struct Program {
    pub(crate) module: Module,
    /// For each node, its debug entry, if any.
    pub(crate) location: Vec<Option<u32>>,
    /// The tree's depth (the root at 1).
    pub(crate) depth: usize,
    /// Per event of a start or act node: what the host is asked to run, ready-made, so a
    /// tick builds an [`crate::Invocation`] without decoding the node again.
    pub(crate) actions: Vec<Action>,
    /// The arguments of every action, back to back.
    pub(crate) args: Vec<Value>,
    /// The blackboard's bits at the start: the fluents marked initial.
    pub(crate) initial_blackboard: Vec<u64>,
}

/// The host call of a start or act node.
#[derive(Clone, Debug, Default)]
pub(crate) struct Action {
    pub(crate) import: u32,
    /// The import's name, a symbol.
    pub(crate) name: u32,
    /// Where its arguments are in `Program::args`.
    pub(crate) args: (u32, u32),
    pub(crate) min: i64,
    pub(crate) max: Option<i64>,
    /// Its refinement's index in `Module::refinements`, if it has one.
    pub(crate) refinement: Option<u32>,
    /// For a durative action: the refinement of its end node, if it has one.
    pub(crate) end_refinement: Option<u32>,
}

/// A program action the host cannot run ([`Program::link`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LinkError {
    /// The action, as text.
    pub action: String,
    /// What the host lacks: `name/arity`.
    pub missing: String,
    /// Whether `missing` is a step of the action's refinement (else the action itself).
    pub refined: bool,
}

impl std::fmt::Display for LinkError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.refined {
            write!(f, "`{}` is refined into `{}`, which the host does not run", self.action, self.missing)
        } else {
            write!(
                f,
                "the host does not run `{}` (`{}`), and the program has no refinement of it",
                self.missing, self.action
            )
        }
    }
}

impl std::error::Error for LinkError {}

/// Where a node comes from in the KB, from the debug info.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Location<'p> {
    /// The snap action's text, e.g. `grip_start(a1, b2)`.
    pub label: &'p str,
    /// The KB file.
    pub file: &'p str,
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub column: u32,
}

impl Program {
    /// Reads and verifies a bytecode file.
    pub fn load(bytes: &[u8]) -> Result<Program, LoadError> {
        Ok(Program::from_module(Module::decode(bytes)?))
    }

    /// Wraps a module that came from [`Module::decode`] (or that its encoding would pass).
    pub(crate) fn from_module(module: Module) -> Program {
        let mut location = vec![None; module.nodes.len()];
        if let Some(debug) = &module.debug {
            for (i, e) in debug.entries.iter().enumerate() {
                location[e.node.0 as usize] = Some(i as u32);
            }
        }
        let mut depth = 0;
        let mut stack = vec![(module.root.0 as usize, 1usize)];
        while let Some((node, d)) = stack.pop() {
            depth = depth.max(d);
            stack.extend(Module::children(&module.nodes[node]).iter().map(|c| (c.0 as usize, d + 1)));
        }
        let mut actions = vec![Action::default(); module.events as usize];
        let mut all_args = Vec::new();
        let mut refinement_of = vec![None; module.nodes.len()];
        for (i, r) in module.refinements.iter().enumerate() {
            refinement_of[r.node.0 as usize] = Some(i as u32);
        }
        for (node_index, node) in module.nodes.iter().enumerate() {
            let (event, import, args, min, max) = match node {
                Instr::Start { event, import, args, min, max, .. } => (event, import, args, min.0, max.0),
                Instr::Act { event, import, args, .. } => (event, import, args, 0, None),
                _ => continue,
            };
            let from = all_args.len() as u32;
            all_args.extend_from_slice(args);
            actions[event.0 as usize] = Action {
                import: import.0,
                name: module.imports[import.0 as usize].name,
                args: (from, all_args.len() as u32),
                min,
                max,
                refinement: refinement_of[node_index],
                end_refinement: None,
            };
        }
        for (node_index, node) in module.nodes.iter().enumerate() {
            if let Instr::End { start, .. } = node {
                actions[start.0 as usize].end_refinement = refinement_of[node_index];
            }
        }
        let mut initial_blackboard = vec![0u64; module.fluents.len().div_ceil(64)];
        for (i, f) in module.fluents.iter().enumerate() {
            if f.initial {
                initial_blackboard[i / 64] |= 1 << (i % 64);
            }
        }
        Program { module, location, depth, actions, args: all_args, initial_blackboard }
    }

    /// Links the program against a host, as a linker would, before anything runs: every
    /// action it starts must be one the host runs, or be refined into steps that all are.
    /// The first that is not is the error.
    pub fn link(&self, host: &dyn crate::Host) -> Result<(), LinkError> {
        for node in &self.module.nodes {
            let (Instr::Start { event, .. } | Instr::Act { event, .. }) = node else { continue };
            let steps: Vec<&Call> = self.steps(*event).iter().chain(self.end_steps(*event)).collect();
            let action = &self.actions[event.0 as usize];
            let calls: Vec<ImportId> =
                if steps.is_empty() { vec![ImportId(action.import)] } else { steps.iter().map(|c| c.import).collect() };
            for import in calls {
                let arity = usize::from(self.module.imports[import.0 as usize].arity);
                let name = self.import_name(import);
                if !host.runs(name, arity) {
                    return Err(LinkError {
                        action: self.action_text(*event),
                        missing: format!("{name}/{arity}"),
                        refined: !steps.is_empty(),
                    });
                }
            }
        }
        Ok(())
    }

    /// The decoded module: tables and nodes.
    pub fn module(&self) -> &Module {
        &self.module
    }

    /// The name of a host action.
    pub fn import_name(&self, import: ImportId) -> &str {
        &self.module.symbols[self.module.imports[import.0 as usize].name as usize]
    }

    /// The text of an argument.
    pub fn value_text(&self, value: Value) -> String {
        self.module.value_text(value)
    }

    /// The text of a fluent.
    pub fn fluent_text(&self, fluent: FluentId) -> String {
        self.module.fluent_text(fluent)
    }

    /// The call a start or act node's event stands for, as text: `grip(a1, b2)`.
    pub fn action_text(&self, event: EventId) -> String {
        let Some(action) = self.actions.get(event.0 as usize) else { return format!("e{}", event.0) };
        self.module.call_text(ImportId(action.import), &self.args[action.args.0 as usize..action.args.1 as usize])
    }

    /// The arm-level steps an action node's event is refined into (empty without a refinement).
    pub fn steps(&self, event: EventId) -> &[Call] {
        self.actions
            .get(event.0 as usize)
            .and_then(|a| a.refinement)
            .map_or(&[], |r| &self.module.refinements[r as usize].steps)
    }

    /// The arm-level steps of the end of the durative action started at `start` (empty
    /// without a refinement of its end node). A host runs them when the end node first
    /// polls the action, which is when the tree allows the action to end.
    pub fn end_steps(&self, start: EventId) -> &[Call] {
        self.actions
            .get(start.0 as usize)
            .and_then(|a| a.end_refinement)
            .map_or(&[], |r| &self.module.refinements[r as usize].steps)
    }

    /// A time in program units as KB time units: `2001` at 1000 units per KB unit (the scale
    /// kbc writes) is `2.001`; at one unit per KB unit, `2001`.
    pub fn time_text(&self, t: i64) -> String {
        let scale = i64::from(self.module().time_scale.max(1));
        if scale == 1 {
            return t.to_string();
        }
        let sign = if t < 0 { "-" } else { "" };
        let digits = scale.ilog10() as usize;
        let fraction = (t.abs() % scale) * 10i64.pow(digits as u32) / scale;
        format!("{sign}{}.{fraction:0digits$}", t.abs() / scale)
    }

    /// A step as text: `move_over(a1, 3, 3)`.
    pub fn call_text(&self, call: &Call) -> String {
        self.module.call_text(call.import, &call.args)
    }

    /// Where `node` comes from, if the program keeps debug info for it.
    pub fn location(&self, node: NodeRef) -> Option<Location<'_>> {
        let debug = self.module.debug.as_ref()?;
        let entry = &debug.entries[(*self.location.get(node.0 as usize)?)? as usize];
        Some(Location {
            label: &self.module.symbols[entry.label as usize],
            file: &self.module.symbols[debug.files[entry.file as usize] as usize],
            line: entry.line,
            column: entry.column,
        })
    }
}
