//! Where each name of a checked KB occurs, and in which role.
//!
//! The index is built from the HIR the front end produced (plus the AST for the one thing the
//! HIR does not keep a span for: the action named by a `duration/3` clause), so it sees the
//! KB exactly as the compiler does: a predicate is a name and an arity, an action schema is a
//! name, a durative action's `_start` and `_end` share a base name, a problem is a name.
//! Occurrences are sorted by position, so finding what is under the cursor is a binary search.

use crate::intern::{Interner, Symbol, sym};
use crate::ir::hir::{EffectKind, Kb, Literal};
use crate::passes::load::Loaded;
use crate::source::{FileId, Span};

/// What a name refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Key {
    /// A predicate, by name and arity.
    Predicate(Symbol, usize),
    /// An action schema (high-level or arm-level), by its full name (`grip_start`).
    Action(Symbol),
    /// A durative action by its base name, as `duration/3` names it (`grip`).
    Durative(Symbol),
    /// A problem.
    Problem(Symbol),
}

/// The part a name plays where it occurs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Role {
    /// The head of a static clause.
    ClauseHead,
    /// A `:- dynamic` or `:- discontiguous` declaration.
    Declared,
    /// Added by an action's effects.
    Added,
    /// Deleted by an action's effects.
    Deleted,
    /// A fact of a problem's initial state.
    Init,
    /// A literal of a problem's goal.
    Goal,
    /// A Valid, Invalid or InvalidAtEnd condition of an action.
    Condition,
    /// Called from a rule body or an OnKB slot.
    Call,
    /// A `resources/1` template.
    Resource,
    /// The name of an action schema or a problem where it is declared.
    Declaration,
    /// The high-level action a `mapping/2` refines.
    Mapped,
    /// An arm-level step of a mapping.
    Step,
    /// The action a `duration/3` clause is about.
    Duration,
}

impl Role {
    /// True where the name is defined rather than used.
    pub fn defines(self) -> bool {
        matches!(self, Role::ClauseHead | Role::Declaration)
    }
}

/// One occurrence of a name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Occurrence {
    /// The name's text.
    pub span: Span,
    /// What it names.
    pub key: Key,
    /// Its part there.
    pub role: Role,
}

/// Every occurrence of every name in one analysed unit, sorted by position.
#[derive(Debug, Default)]
pub struct Index {
    occurrences: Vec<Occurrence>,
}

impl Index {
    /// Indexes a resolved KB.
    pub fn build(kb: &Kb, loaded: &Loaded) -> Index {
        let mut occurrences = Vec::new();
        // `extra`: the arguments a call appends to a closure (`maplist(P, L)` calls `P/1`).
        let mut add_called = |literal: &Literal, extra: usize, role: Role| {
            if let Some((name, arity)) = literal.term.callable() {
                let key = Key::Predicate(name, arity + extra);
                occurrences.push(Occurrence { span: literal.name_span, key, role });
            }
        };
        for clause in &kb.clauses {
            add_called(&clause.head, 0, Role::ClauseHead);
            if let Some(body) = &clause.body {
                body.for_each_called(&mut |l, extra| add_called(l, extra, Role::Call));
            }
        }
        for action in &kb.actions {
            for literal in &action.valid {
                add_called(literal, 0, Role::Condition);
            }
            for literal in action.invalid.iter().chain(&action.invalid_at_end) {
                add_called(literal, 0, Role::Condition);
            }
            for goal in &action.on_kb {
                goal.for_each_called(&mut |l, extra| add_called(l, extra, Role::Call));
            }
            for effect in &action.effects {
                let role = if effect.kind == EffectKind::Add { Role::Added } else { Role::Deleted };
                add_called(&effect.literal, 0, role);
            }
        }
        for resource in &kb.resources {
            add_called(&resource.template, 0, Role::Resource);
        }
        for problem in &kb.problems {
            for literal in problem.initial_facts() {
                add_called(literal, 0, Role::Init);
            }
            for literal in &problem.goal {
                add_called(literal, 0, Role::Goal);
            }
        }
        for action in &kb.actions {
            occurrences.push(Occurrence {
                span: action.name.name_span,
                key: Key::Action(action.name.name()),
                role: Role::Declaration,
            });
        }
        for mapping in &kb.mappings {
            occurrences.push(Occurrence {
                span: mapping.high.name_span,
                key: Key::Action(mapping.high.name()),
                role: Role::Mapped,
            });
            for step in &mapping.steps {
                occurrences.push(Occurrence { span: step.name_span, key: Key::Action(step.name()), role: Role::Step });
            }
        }
        for problem in &kb.problems {
            occurrences.push(Occurrence {
                span: problem.name_span,
                key: Key::Problem(problem.name),
                role: Role::Declaration,
            });
        }
        for declaration in &kb.declarations {
            occurrences.push(Occurrence {
                span: declaration.span,
                key: Key::Predicate(declaration.name, declaration.arity),
                role: Role::Declared,
            });
        }
        // `duration(grip(_, _), 1, 2)`: the HIR keeps the clause, the AST the span of `grip`.
        for clause in loaded.clauses() {
            let head = match clause.term.as_compound(sym::NECK, 2) {
                Some(rule) => &rule.args[0],
                None => &clause.term,
            };
            if let Some(duration) = head.as_compound(sym::DURATION, 3)
                && let Some((name, _)) = duration.args[0].callable()
            {
                occurrences.push(Occurrence {
                    span: duration.args[0].name_span(),
                    key: Key::Durative(name),
                    role: Role::Duration,
                });
            }
        }
        occurrences.sort_by_key(|o| (o.span.file, o.span.start, o.span.end, o.role));
        occurrences.dedup_by_key(|o| (o.span, o.key));
        Index { occurrences }
    }

    /// The occurrence under byte `offset` of `file` (the cursor may sit just after the name).
    pub fn at(&self, file: FileId, offset: u32) -> Option<&Occurrence> {
        let after = self.occurrences.partition_point(|o| (o.span.file, o.span.start) <= (file, offset));
        self.occurrences[..after].iter().rev().take_while(|o| o.span.file == file).find(|o| o.span.end >= offset)
    }

    /// Every occurrence, in position order.
    pub fn occurrences(&self) -> &[Occurrence] {
        &self.occurrences
    }

    /// The occurrences that refer to the same thing as `key`: for an action, also the
    /// `duration/3` clauses of its base; for a durative base, also its schemas.
    pub fn related<'a>(&'a self, kb: &'a Kb, key: Key) -> impl Iterator<Item = &'a Occurrence> + 'a {
        self.occurrences.iter().filter(move |o| same_thing(kb, key, o.key))
    }

    /// Where `key` is defined: clause heads and declarations of schemas and problems; for a
    /// state predicate without clauses, the effects that add it and the initial states that
    /// hold it; failing those, its `dynamic` declarations.
    pub fn definitions(&self, kb: &Kb, key: Key) -> Vec<Occurrence> {
        let related: Vec<Occurrence> = self.related(kb, key).copied().collect();
        let tiers: [&dyn Fn(Role) -> bool; 3] =
            [&|r: Role| r.defines(), &|r: Role| matches!(r, Role::Added | Role::Init), &|r: Role| r == Role::Declared];
        for tier in tiers {
            let found: Vec<Occurrence> = related.iter().filter(|o| tier(o.role)).copied().collect();
            if !found.is_empty() {
                return found;
            }
        }
        Vec::new()
    }
}

/// True when occurrences keyed `a` and `b` name the same thing.
fn same_thing(kb: &Kb, a: Key, b: Key) -> bool {
    let base_of = |name: Symbol| kb.actions.iter().find(|action| action.name.name() == name).map(|action| action.base);
    match (a, b) {
        (Key::Action(name), Key::Durative(base)) | (Key::Durative(base), Key::Action(name)) => {
            base_of(name) == Some(base)
        }
        _ => a == b,
    }
}

/// `name/arity` as text.
pub fn indicator(interner: &Interner, name: Symbol, arity: usize) -> String {
    format!("{}/{arity}", interner.resolve(name))
}
