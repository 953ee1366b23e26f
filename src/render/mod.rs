//! Pictures for people: Graphviz for the partial order and the temporal network, SVG for the
//! schedule. Every function returns text; the CLI decides where it goes.

pub mod bt;
pub mod dot;
pub mod gantt;
pub mod pddl;
