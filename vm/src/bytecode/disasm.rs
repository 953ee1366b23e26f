//! A readable listing of a module: its tables, then the tree, one node a line, indented by
//! depth, with operands by name and the KB location from the debug info.

use std::fmt::Write;

use super::operand::Names;
use super::{FORMAT_VERSION, FluentId, Module, Value};

struct ModuleNames<'a>(&'a Module);

impl Names for ModuleNames<'_> {
    fn symbol(&self, index: u32) -> String {
        self.0.value_text(Value::Atom(index))
    }
    fn fluent(&self, index: u32) -> String {
        self.0.fluent_text(FluentId(index))
    }
    fn import(&self, index: u32) -> String {
        match self.0.imports.get(index as usize) {
            Some(import) => format!("{}/{}", self.symbol(import.name), import.arity),
            None => format!("#{index}"),
        }
    }
}

pub(super) fn listing(module: &Module) -> String {
    let names = ModuleNames(module);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "; kbc bytecode, format version {FORMAT_VERSION}: {} nodes, {} events, {} fluents, {} imports, {} symbols; {} time units per KB time unit",
        module.nodes.len(),
        module.events,
        module.fluents.len(),
        module.imports.len(),
        module.symbols.len(),
        module.time_scale
    );
    let _ = writeln!(out, "\n.imports");
    for (i, _) in module.imports.iter().enumerate() {
        let _ = writeln!(out, "  {i:<4} {}", names.import(i as u32));
    }
    let _ = writeln!(out, "\n.fluents");
    for (i, fluent) in module.fluents.iter().enumerate() {
        let initial = if fluent.initial { "  (initial)" } else { "" };
        let _ = writeln!(out, "  {i:<4} {}{initial}", names.fluent(i as u32));
    }
    let mut location = vec![None; module.nodes.len()];
    if let Some(debug) = &module.debug {
        for e in &debug.entries {
            let file = debug.files.get(e.file as usize).map_or("?".to_string(), |&f| names.symbol(f));
            location[e.node.0 as usize] = Some(format!("{}  ; {file}:{}:{}", names.symbol(e.label), e.line, e.column));
        }
    }
    let _ = writeln!(out, "\n.tree");
    let mut stack = vec![(module.root.0 as usize, 0usize)];
    while let Some((node, depth)) = stack.pop() {
        let Some(instr) = module.nodes.get(node) else { continue };
        let operands: Vec<String> = instr
            .operands(&names)
            .into_iter()
            .filter(|(name, _)| *name != "children")
            .map(|(name, text)| format!("{name}={text}"))
            .collect();
        let _ = write!(out, "  @{node:<5} {:indent$}{}", "", instr.mnemonic(), indent = depth * 2);
        if !operands.is_empty() {
            let _ = write!(out, " {}", operands.join(" "));
        }
        if let Some(text) = &location[node] {
            let _ = write!(out, "  ; {text}");
        }
        out.push('\n');
        for child in Module::children(instr).iter().rev() {
            stack.push((child.0 as usize, depth + 1));
        }
    }
    if !module.refinements.is_empty() {
        let _ = writeln!(out, "\n.refinements");
        for r in &module.refinements {
            let steps: Vec<String> = r.steps.iter().map(|call| module.call_text(call.import, &call.args)).collect();
            let _ = writeln!(out, "  @{:<5} {}", r.node.0, steps.join(", "));
        }
    }
    out
}
