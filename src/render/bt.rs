//! The behaviour tree for people and other tools: BehaviorTree.CPP v4 XML and Graphviz, both
//! written from the bytecode module, so a `.kbb` file and its pictures always agree.
//!
//! In the XML, each start of a durative action `X` is an action node `X_start`, each end
//! `X_end`, an instantaneous action `X`; their ground arguments are ports `arg0`, `arg1`, ...,
//! and every node also carries its `event`. Waits are `WaitEvents` nodes whose `after` port
//! lists `eN+delay` (delays in program units). The `TreeNodesModel` declares each of these
//! node types once with its ports, as Groot2 needs.

use std::collections::BTreeMap;
use std::fmt::Write;

use kbvm::bytecode::{Instr, Module, Value};

use super::xml_escape as escape;

/// For each event, the start node that records it (ends name their action after it).
fn start_nodes(module: &Module) -> Vec<Option<&Instr>> {
    let mut starts = vec![None; module.events as usize];
    for node in &module.nodes {
        if let Instr::Start { event, .. } = node {
            starts[event.0 as usize] = Some(node);
        }
    }
    starts
}

/// A leaf's node type and its attributes; `None` for composites.
fn leaf(module: &Module, starts: &[Option<&Instr>], node: &Instr) -> Option<(String, Vec<(String, String)>)> {
    let args = |args: &[Value]| -> Vec<(String, String)> {
        args.iter().enumerate().map(|(i, &a)| (format!("arg{i}"), module.value_text(a))).collect()
    };
    let import = |i: kbvm::bytecode::ImportId| module.value_text(Value::Atom(module.imports[i.0 as usize].name));
    Some(match node {
        Instr::Sequence { .. } | Instr::Parallel { .. } => return None,
        Instr::Wait { after } => {
            let list: Vec<String> = after.iter().map(|d| format!("e{}+{}", d.event.0, d.after.0)).collect();
            ("WaitEvents".to_string(), vec![("after".to_string(), list.join(";"))])
        }
        Instr::Start { event, import: i, args: a, min, max, .. } => {
            let mut attrs = vec![("event".to_string(), format!("e{}", event.0))];
            attrs.extend(args(a));
            attrs.push(("min".to_string(), min.0.to_string()));
            attrs.push(("max".to_string(), max.0.map_or("inf".to_string(), |m| m.to_string())));
            (format!("{}_start", import(*i)), attrs)
        }
        Instr::End { event, start, .. } => {
            let starter = match starts[start.0 as usize] {
                Some(Instr::Start { import: i, args: a, .. }) => Some((import(*i), args(a))),
                _ => None,
            };
            let (name, a) = starter.unwrap_or_else(|| ("action".to_string(), Vec::new()));
            let mut attrs =
                vec![("event".to_string(), format!("e{}", event.0)), ("start".to_string(), format!("e{}", start.0))];
            attrs.extend(a);
            (format!("{name}_end"), attrs)
        }
        Instr::Act { event, import: i, args: a, .. } => {
            let mut attrs = vec![("event".to_string(), format!("e{}", event.0))];
            attrs.extend(args(a));
            (import(*i), attrs)
        }
        // An instruction of a later format version than this writer knows.
        _ => ("UnknownNode".to_string(), Vec::new()),
    })
}

/// Writes the tree's nodes and collects each leaf type's ports for the `TreeNodesModel`.
struct XmlTree<'a> {
    module: &'a Module,
    starts: Vec<Option<&'a Instr>>,
    out: String,
    models: BTreeMap<String, Vec<String>>,
}

impl XmlTree<'_> {
    fn node(&mut self, index: usize, depth: usize) {
        let indent = "  ".repeat(depth + 2);
        let node = &self.module.nodes[index];
        match node {
            Instr::Sequence { children } | Instr::Parallel { children } => {
                let tag = if matches!(node, Instr::Sequence { .. }) {
                    "<Sequence>".to_string()
                } else {
                    format!("<Parallel success_count=\"{}\" failure_count=\"1\">", children.len())
                };
                let _ = writeln!(self.out, "{indent}{tag}");
                for child in children {
                    self.node(child.0 as usize, depth + 1);
                }
                let close = if matches!(node, Instr::Sequence { .. }) { "</Sequence>" } else { "</Parallel>" };
                let _ = writeln!(self.out, "{indent}{close}");
            }
            _ => {
                let Some((id, attrs)) = leaf(self.module, &self.starts, node) else { return };
                let _ = write!(self.out, "{indent}<{}", escape(&id));
                for (k, v) in &attrs {
                    let _ = write!(self.out, " {k}=\"{}\"", escape(v));
                }
                self.out.push_str("/>\n");
                let ports = self.models.entry(id).or_default();
                for (k, _) in attrs {
                    if !ports.contains(&k) {
                        ports.push(k);
                    }
                }
            }
        }
    }
}

/// BehaviorTree.CPP v4 XML.
pub fn xml(module: &Module) -> String {
    let out = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<root BTCPP_format=\"4\" main_tree_to_execute=\"Plan\">\n  <BehaviorTree ID=\"Plan\">\n",
    );
    let mut writer = XmlTree { module, starts: start_nodes(module), out, models: BTreeMap::new() };
    if let Some(Instr::Sequence { children }) = module.nodes.get(module.root.0 as usize)
        && children.is_empty()
    {
        writer.out.push_str("    <AlwaysSuccess/>\n");
    } else {
        writer.node(module.root.0 as usize, 0);
    }
    let XmlTree { mut out, models, .. } = writer;
    out.push_str("  </BehaviorTree>\n  <TreeNodesModel>\n");
    for (id, ports) in &models {
        let _ = writeln!(out, "    <Action ID=\"{}\">", escape(id));
        for port in ports {
            let _ = writeln!(out, "      <input_port name=\"{port}\"/>");
        }
        out.push_str("    </Action>\n");
    }
    out.push_str("  </TreeNodesModel>\n</root>\n");
    out
}

/// Graphviz DOT: composites as boxes, waits as diamonds, actions as ellipses.
pub fn dot(module: &Module) -> String {
    let starts = start_nodes(module);
    // Left to right: a plan's tree is much wider than deep, and reads as a timeline this way.
    let mut out = String::from("digraph behaviour_tree {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n");
    let legend = "boxes: sequences (\u{2192}, in order) and parallels (\u{21c9}, together); ellipses: actions, \
                  eN the event each records; diamonds: waits until the events named have happened";
    let _ = writeln!(out, "  labelloc=t;\n  fontname=\"Helvetica\";\n  label={};", super::dot::quote(legend));
    for (i, node) in module.nodes.iter().enumerate() {
        let (label, shape) = match node {
            Instr::Sequence { .. } => ("sequence \u{2192}".to_string(), "box"),
            Instr::Parallel { .. } => ("parallel \u{21c9}".to_string(), "box"),
            other => {
                let (id, attrs) = leaf(module, &starts, other).unwrap_or_default();
                let args: Vec<&str> =
                    attrs.iter().filter(|(k, _)| k.starts_with("arg")).map(|(_, v)| v.as_str()).collect();
                let event = attrs.iter().find(|(k, _)| k == "event").map(|(_, v)| v.as_str());
                let text = match (other, event) {
                    (Instr::Wait { .. }, _) => format!("wait {}", attrs.first().map_or("", |(_, v)| v.as_str())),
                    (_, Some(event)) => format!("{event}: {id}({})", args.join(", ")),
                    (_, None) => format!("{id}({})", args.join(", ")),
                };
                (text, if matches!(other, Instr::Wait { .. }) { "diamond" } else { "ellipse" })
            }
        };
        let _ = writeln!(out, "  n{i} [label={}, shape={shape}];", super::dot::quote(&label));
    }
    for (i, node) in module.nodes.iter().enumerate() {
        for child in Module::children(node) {
            let _ = writeln!(out, "  n{i} -> n{};", child.0);
        }
    }
    out.push_str("}\n");
    out
}
