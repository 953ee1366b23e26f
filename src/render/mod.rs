//! Pictures for people: Graphviz for the partial order and the temporal network, SVG for the
//! schedule. Every function returns text; the CLI decides where it goes.

pub mod bt;
pub mod dot;
pub mod gantt;
pub mod pddl;
pub mod view;

/// Text as XML (SVG, BehaviorTree.CPP XML) or HTML content or attribute value: the five
/// characters XML reserves, escaped.
pub fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}
