//! `kbc export pddl`: one problem of a KB as an equivalent PDDL 2.1 domain and problem, for
//! other planners (and for checking kbc against them).
//!
//! The translation:
//! - each durative action `X` (a `X_start` and a `X_end` schema) becomes a durative action per
//!   pair of start and end alternatives (`grip_1`, `grip_2`, ...), whose parameters are the
//!   name's arguments first, then the other variables of the two schemas; an instantaneous
//!   schema becomes an `:action`;
//! - Valid literals become conditions (`at start` for the start schema, `at end` for the end),
//!   Invalid literals negative conditions, their unbound variables existential
//!   (`(not (exists (?v) (gripping ?v ?b)))`); effects become effects at the same end;
//! - OnKB goals and InvalidAtEnd literals depend only on the KB and the goal, so they become
//!   one static predicate per schema (`onkb_move_block_start_1`) over their variables, whose
//!   facts are the solutions the resolution engine gives on every binding the delete
//!   relaxation reaches from the initial state (a superset of what any plan meets, so nothing
//!   a plan needs is missing);
//! - `duration/3` becomes the action's duration: a number when it is the same for every
//!   instance, else a function over the name arguments it depends on, with a value per
//!   reachable instance. With [`Durations::Bounded`] there are no numeric fluents: the action
//!   is written once per distinct duration (`move_block_1_1`, `move_block_1_2`, ...), each
//!   with a static condition (`duration_move_block_1 ?x1 ?y1 ?x2 ?y2`) whose facts are the
//!   reachable instances of that duration (unified-planning wants every function defined
//!   everywhere; LPG's local search does worse on the copies, so the others keep functions).
//!   `[min, max]` becomes `(and (>= ?duration min) (<= ?duration max))`, `(>= ?duration min)`
//!   for an `inf` maximum (with [`Durations::Bounded`], [`BOUNDED_MAX`] instead), or
//!   `(= ?duration min)` with [`Durations::Min`] for planners without duration inequalities;
//! - with `negative_preconditions` off, every predicate an Invalid literal reads gets a
//!   complement `not_p`, kept true exactly when `p` is false by every effect on `p`, and an
//!   existential negative condition becomes one complement literal per value its variables
//!   can take (the values that position holds in reachable facts).
//!
//! Terms become PDDL names: atoms stay as they are where PDDL allows it, numbers get a letter
//! (`3` is `n3`, `-3` is `m3`), compounds join their parts (`pos(1, 2)` is `pos_n1_n2`).
//! `names.json` maps every name back to the KB's term and every PDDL action to the kbc snap
//! actions it stands for, so a plan found by another planner can be checked by `kbc validate`.
//!
//! What PDDL cannot express is an error that names the construct (E0404): a variable inside a
//! compound argument, name arguments that are not distinct variables, a deletion that follows
//! an addition of the same fact in one effect list (PDDL applies deletions first). What the
//! export leaves out is a warning (W0007): arm-level actions and mappings, `resources/1`.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write;

use rustc_hash::{FxHashMap, FxHashSet};

use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::engine::{Machine, Program};
use crate::intern::{Interner, Symbol};
use crate::ir::hir::{self, EffectKind, Kb, Snap, VarTable};
use crate::ir::task::{Const, ConstId, FactId, LiteralPattern, Pattern, PredId, Schema, Task};
use crate::planner::successors::{self, Applicable, ReachError};

/// How durations with a range are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Durations {
    /// `[min, max]` as duration inequalities (`:duration-inequalities`).
    Exact,
    /// The minimum only, `(= ?duration min)`: what a makespan-minimising planner picks anyway,
    /// for planners without duration inequalities.
    Min,
    /// As [`Durations::Exact`], but no maximum is written as [`BOUNDED_MAX`], so every
    /// duration is a closed interval, and a duration that varies is one action per duration
    /// rather than a numeric fluent: what unified-planning reads.
    Bounded,
}

/// The maximum [`Durations::Bounded`] writes for a duration with none, in KB time units:
/// longer than any plan kbc's budgets let it find.
pub const BOUNDED_MAX: f64 = 1_000_000.0;

/// What to write.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Keep negative conditions (`:negative-preconditions`); off compiles them away.
    pub negative_preconditions: bool,
    /// How durations with a range are written.
    pub durations: Durations,
    /// The most action instances the relaxed exploration may reach, and the most complement
    /// facts or expanded conditions the export may write.
    pub limit: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options { negative_preconditions: true, durations: Durations::Exact, limit: 2_000_000 }
    }
}

/// The three files of an export.
#[derive(Clone, Debug, PartialEq)]
pub struct Export {
    /// `domain.pddl`.
    pub domain: String,
    /// `problem.pddl`.
    pub problem: String,
    /// `names.json`: PDDL names back to KB terms and snap actions.
    pub names: String,
}

const RESERVED: &[&str] = &[
    "and",
    "or",
    "not",
    "imply",
    "exists",
    "forall",
    "when",
    "at",
    "over",
    "start",
    "end",
    "all",
    "either",
    "object",
    "define",
    "domain",
    "problem",
    "number",
    "increase",
    "decrease",
    "assign",
    "minimize",
    "maximize",
    "total-time",
];

/// Makes unique PDDL names (case-insensitively: PDDL is, and LPG prints upper case).
#[derive(Default)]
struct Names {
    taken: FxHashSet<String>,
}

impl Names {
    fn fresh(&mut self, wanted: &str) -> String {
        let mut base: String = wanted
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() || c == '_' || c == '-' { c.to_ascii_lowercase() } else { '_' })
            .collect();
        if !base.starts_with(|c: char| c.is_ascii_lowercase()) || RESERVED.contains(&base.as_str()) {
            base = format!("o_{base}");
        }
        let mut name = base.clone();
        let mut n = 2;
        while !self.taken.insert(name.clone()) {
            name = format!("{base}_{n}");
            n += 1;
        }
        name
    }
}

/// Everything the writer needs, built up front.
struct Exporter<'a> {
    kb: &'a Kb,
    interner: &'a Interner,
    task: &'a Task,
    options: Options,
    objects: FxHashMap<ConstId, String>,
    object_names: Names,
    predicate_names: FxHashMap<PredId, String>,
    /// Per predicate, per argument position, the values reachable facts hold there.
    domains: FxHashMap<PredId, Vec<BTreeSet<ConstId>>>,
    /// Predicates with a complement (`not_p`), when negative conditions are compiled away.
    complemented: BTreeMap<PredId, String>,
    diags: &'a mut Diagnostics,
}

/// Exports problem `task.problem` of `kb`. Errors and warnings go to `diags`; `None` when an
/// error means there is nothing faithful to write.
pub fn export(
    kb: &Kb,
    interner: &Interner,
    program: &Program,
    task: &mut Task,
    options: Options,
    diags: &mut Diagnostics,
) -> Option<Export> {
    let problem_span = kb.problems[task.problem].span;
    if kb.actions.iter().any(|a| a.level == hir::Level::Low) || !kb.mappings.is_empty() {
        diags.push(
            Diagnostic::warning(codes::EXPORT_LEAVES_OUT, "the export leaves out the arm-level actions and mappings")
                .primary(problem_span, "this problem is exported at the level of `action/6`")
                .with_note("PDDL has no refinement of one action into others; `kbc plan` plans at this level too"),
        );
    }
    let machine = Machine::new(program, 1_000_000);
    let reachable = match successors::relaxed_reachable(task, machine, options.limit) {
        Ok(reachable) => reachable,
        Err(ReachError::Condition(error)) => {
            let schema = &task.schemas[error.schema];
            let action = &kb.actions[schema.action];
            diags.push(
                Diagnostic::error(codes::CONDITION_ERROR, "an OnKB goal failed while the export explored the task")
                    .primary(action.slots[4], "these goals")
                    .with_note(format!("{:?}", error.error)),
            );
            return None;
        }
        Err(ReachError::TooMany(count)) => {
            diags.push(
                Diagnostic::error(codes::EXPORT_TOO_LARGE, "the exported task would be too large")
                    .primary(problem_span, "exporting this problem")
                    .with_note(format!(
                        "the delete relaxation reaches {count} action instances, more than the limit of {}",
                        options.limit
                    ))
                    .with_help("raise `--limit`, or narrow the OnKB goals that choose where things may go"),
            );
            return None;
        }
    };
    let mut exporter = Exporter {
        kb,
        interner,
        task,
        options,
        objects: FxHashMap::default(),
        object_names: Names::default(),
        predicate_names: FxHashMap::default(),
        domains: FxHashMap::default(),
        complemented: BTreeMap::new(),
        diags,
    };
    exporter.check_expressible()?;
    exporter.collect(&reachable.facts, &reachable.actions);
    exporter.write(&reachable.actions, program)
}

/// A durative action of the export: a start and an end alternative, or an instant.
struct PddlAction<'s> {
    name: String,
    start: &'s Schema,
    start_index: usize,
    end: Option<(&'s Schema, usize)>,
    /// For a durative action whose duration varies: which of its duration classes
    /// ([`DurationSpec::classes`]) this copy is for.
    class: Option<usize>,
}

/// A schema's variables as PDDL variables: the name arguments' own names, `None` for the
/// existential variables of Invalid literals.
type VarNames = Vec<Option<String>>;

impl Exporter<'_> {
    fn error(&mut self, span: crate::source::Span, label: &str, what: String, help: &str) -> Option<()> {
        self.diags.push(
            Diagnostic::error(codes::EXPORT_INEXPRESSIBLE, what)
                .primary(span, label.to_string())
                .with_help(help.to_string()),
        );
        None
    }

    /// Refuses what PDDL cannot say.
    fn check_expressible(&mut self) -> Option<()> {
        let mut ok = true;
        for schema in self.task.schemas.iter() {
            let literals =
                schema.valid.iter().chain(schema.invalid.iter()).chain(schema.effects.iter().map(|(_, l)| l));
            let compound = literals.clone().find(|l| l.args.iter().any(|a| matches!(a, Pattern::Compound(..))));
            if let Some(literal) = compound {
                ok = false;
                self.error(
                    literal.span,
                    "PDDL cannot match inside this argument",
                    "a compound argument with variables cannot be exported".into(),
                    "write the compound's parts as arguments of the literal: `at(B, X, Y)` for `at(B, pos(X, Y))`",
                );
                continue;
            }
            let action = &self.kb.actions[schema.action];
            if schema.snap != Snap::Instant {
                let distinct = match &schema.name {
                    Pattern::Compound(_, args) => {
                        let mut seen = Vec::new();
                        args.iter().all(|a| match a {
                            Pattern::Var(v) if !seen.contains(v) => {
                                seen.push(*v);
                                true
                            }
                            _ => false,
                        })
                    }
                    _ => true,
                };
                if !distinct {
                    let span = action.name.span;
                    ok = false;
                    self.error(
                        span,
                        "a constant or a repeated variable here",
                        "the export needs the arguments of a durative action's name to be distinct variables".into(),
                        "a PDDL durative action has one parameter list for its start and its end; \
                             move the constant into a Valid literal or an OnKB goal (`A == a1`)",
                    );
                    continue;
                }
            }
            // A deletion with a variable nothing binds removes every fact that unifies; a PDDL
            // 2.1 effect deletes one atom.
            let open = schema
                .open_effects()
                .into_iter()
                .map(|e| &schema.effects[e])
                .find(|(kind, _)| *kind == EffectKind::Del);
            if let Some((_, literal)) = open {
                ok = false;
                self.error(
                    literal.span,
                    "deletes every fact that unifies",
                    "a deletion with a variable nothing binds cannot be exported".into(),
                    "bind the variable in a Valid literal, so the action deletes one fact",
                );
                continue;
            }
            // PDDL applies deletions before additions: `[add(p), del(p)]` would leave p true.
            for (i, (kind, added)) in schema.effects.iter().enumerate() {
                if *kind != EffectKind::Add {
                    continue;
                }
                let clash = schema.effects[i + 1..]
                    .iter()
                    .find(|(k, deleted)| *k == EffectKind::Del && patterns_may_meet(added, deleted));
                if let Some((_, deleted)) = clash {
                    let (added_span, deleted_span) = (added.span, deleted.span);
                    self.diags.push(
                        Diagnostic::error(
                            codes::EXPORT_INEXPRESSIBLE,
                            "a deletion after an addition of the same fact cannot be exported",
                        )
                        .primary(deleted_span, "this deletion may remove the fact added before it")
                        .secondary(added_span, "added here")
                        .with_note(
                            "kbc applies effects in list order; PDDL applies every deletion before every addition",
                        )
                        .with_help("put the deletion first if the fact should end up true"),
                    );
                    ok = false;
                    break;
                }
            }
        }
        ok.then_some(())
    }

    /// Names the objects and predicates, and the domains of predicate arguments.
    fn collect(&mut self, facts: &[FactId], instances: &[Applicable]) {
        let mut predicate_names = Names::default();
        let mut arities: FxHashMap<Symbol, usize> = FxHashMap::default();
        let fluents: Vec<PredId> = self.task.facts.fluent_preds().collect();
        for &pred in &fluents {
            let (name, _) = self.task.facts.pred_info(pred);
            *arities.entry(name).or_default() += 1;
        }
        for pred in fluents {
            let (name, arity) = self.task.facts.pred_info(pred);
            let text = self.interner.resolve(name);
            let wanted = if arities[&name] > 1 { format!("{text}_{arity}") } else { text.to_string() };
            self.predicate_names.insert(pred, predicate_names.fresh(&wanted));
        }
        for &fact in facts {
            let pred = self.task.facts.pred_of(fact);
            let args = self.task.facts.args(fact);
            let domains = self.domains.entry(pred).or_insert_with(|| vec![BTreeSet::new(); args.len()]);
            for (domain, &value) in domains.iter_mut().zip(args) {
                domain.insert(value);
            }
        }
        // The values negative conditions ask about, where a fact never holds them: its
        // complement must be there too (true).
        for instance in instances {
            for literal in self.task.schemas[instance.schema].invalid.iter() {
                let domains =
                    self.domains.entry(literal.pred).or_insert_with(|| vec![BTreeSet::new(); literal.args.len()]);
                for (domain, arg) in domains.iter_mut().zip(literal.args.iter()) {
                    match arg {
                        Pattern::Const(c) => {
                            domain.insert(*c);
                        }
                        Pattern::Var(v) => {
                            if let Some(c) = instance.bindings[*v as usize] {
                                domain.insert(c);
                            }
                        }
                        Pattern::Compound(..) => {}
                    }
                }
            }
        }
        if !self.options.negative_preconditions {
            let mut negated: Vec<PredId> =
                self.task.schemas.iter().flat_map(|s| s.invalid.iter().map(|l| l.pred)).collect();
            negated.sort();
            negated.dedup();
            for pred in negated {
                let name = predicate_names.fresh(&format!("not_{}", self.predicate_names[&pred]));
                self.complemented.insert(pred, name);
            }
        }
        // Keep predicate names from clashing with the static predicates named later.
        self.object_names.taken.extend(predicate_names.taken.iter().cloned());
    }

    fn object(&mut self, value: ConstId) -> String {
        if let Some(name) = self.objects.get(&value) {
            return name.clone();
        }
        let wanted = self.const_name(value);
        let name = self.object_names.fresh(&wanted);
        self.objects.insert(value, name.clone());
        name
    }

    fn const_name(&self, value: ConstId) -> String {
        match self.task.consts.get(value) {
            Const::Atom(s) | Const::Str(s) => self.interner.resolve(*s).to_string(),
            Const::Int(i) if *i < 0 => format!("m{}", i.unsigned_abs()),
            Const::Int(i) => format!("n{i}"),
            Const::Float(bits) => format!("f{}", f64::from_bits(*bits)).replace('.', "_").replace('-', "m"),
            Const::Compound(f, args) => {
                let mut name = self.interner.resolve(*f).to_string();
                for &arg in args.iter() {
                    name.push('_');
                    name.push_str(&self.const_name(arg));
                }
                name
            }
        }
    }

    fn term_text(&self, value: ConstId) -> String {
        hir::term_to_string(self.interner, &self.task.consts.to_term(value), &VarTable::default())
    }

    /// `(pred arg ...)` for a literal pattern under `vars`.
    fn literal(&mut self, literal: &LiteralPattern, vars: &VarNames, pred_name: Option<&str>) -> String {
        let mut text = format!("({}", pred_name.unwrap_or(&self.predicate_names[&literal.pred]));
        for arg in literal.args.iter() {
            text.push(' ');
            match arg {
                Pattern::Const(c) => text.push_str(&self.object(*c)),
                Pattern::Var(v) => text.push_str(vars[*v as usize].as_deref().unwrap_or("?_")),
                Pattern::Compound(..) => unreachable!("refused by check_expressible"),
            }
        }
        text.push(')');
        text
    }

    /// The conditions of an Invalid literal: one negative condition, or complement literals.
    fn invalid_conditions(&mut self, literal: &LiteralPattern, vars: &VarNames, out: &mut Vec<String>) -> Option<()> {
        let mut existential: Vec<u32> = Vec::new();
        for arg in literal.args.iter() {
            if let Pattern::Var(v) = arg
                && vars[*v as usize].is_none()
                && !existential.contains(v)
            {
                existential.push(*v);
            }
        }
        if self.options.negative_preconditions {
            let mut local = vars.clone();
            let mut names = Vec::new();
            for (i, &v) in existential.iter().enumerate() {
                let name = format!("?e{}", i + 1);
                local[v as usize] = Some(name.clone());
                names.push(name);
            }
            let atom = self.literal(literal, &local, None);
            out.push(if names.is_empty() {
                format!("(not {atom})")
            } else {
                format!("(not (exists ({}) {atom}))", names.join(" "))
            });
            return Some(());
        }
        // Complements: every value each existential variable can take where it stands.
        let complement = self.complemented[&literal.pred].clone();
        let empty = Vec::new();
        let domains = self.domains.get(&literal.pred).unwrap_or(&empty);
        let mut choices: Vec<Vec<ConstId>> = Vec::new();
        for &v in &existential {
            let mut values: Option<BTreeSet<ConstId>> = None;
            for (position, arg) in literal.args.iter().enumerate() {
                if *arg == Pattern::Var(v) {
                    let here = domains.get(position).cloned().unwrap_or_default();
                    values = Some(match values {
                        None => here,
                        Some(before) => before.intersection(&here).copied().collect(),
                    });
                }
            }
            choices.push(values.unwrap_or_default().into_iter().collect());
        }
        let combinations: usize = choices.iter().map(Vec::len).product();
        if combinations > self.options.limit {
            let span = literal.span;
            self.diags.push(
                Diagnostic::error(codes::EXPORT_TOO_LARGE, "the exported task would be too large")
                    .primary(span, "this Invalid literal")
                    .with_note(format!("without negative conditions it becomes {combinations} conditions")),
            );
            return None;
        }
        // No combination when a variable has no value: nothing reachable can match, and the
        // condition always holds.
        for_each_tuple(&choices, &mut |values| {
            let mut local = vars.clone();
            for (&v, &value) in existential.iter().zip(values) {
                local[v as usize] = Some(self.object(value));
            }
            out.push(self.literal(literal, &local, Some(&complement)));
        });
        Some(())
    }

    /// Effects, with the complements kept in step; each wrapped in `(when ...)` for a durative
    /// action, bare for an instant.
    fn effects(&mut self, schema: &Schema, vars: &VarNames, when: Option<&str>, out: &mut Vec<String>) {
        let timed = |effect: String| match when {
            Some(when) => format!("({when} {effect})"),
            None => effect,
        };
        for (kind, literal) in schema.effects.iter() {
            let atom = self.literal(literal, vars, None);
            let complement = self.complemented.get(&literal.pred).cloned();
            let complement_atom = complement.map(|name| self.literal(literal, vars, Some(&name)));
            match kind {
                EffectKind::Add => {
                    out.push(timed(atom));
                    if let Some(c) = complement_atom {
                        out.push(timed(format!("(not {c})")));
                    }
                }
                EffectKind::Del => {
                    out.push(timed(format!("(not {atom})")));
                    if let Some(c) = complement_atom {
                        out.push(timed(c));
                    }
                }
            }
        }
    }

    fn write(&mut self, instances: &[Applicable], program: &Program) -> Option<Export> {
        let kb = self.kb;
        let task = self.task;
        let problem = &kb.problems[task.problem];
        let problem_name = self.interner.resolve(problem.name).to_string();
        // The actions: start alternatives times end alternatives, per durative base.
        let mut actions: Vec<PddlAction<'_>> = Vec::new();
        for (index, schema) in task.schemas.iter().enumerate() {
            match schema.snap {
                Snap::Instant => {
                    actions.push(PddlAction {
                        name: String::new(),
                        start: schema,
                        start_index: index,
                        end: None,
                        class: None,
                    });
                }
                Snap::Start => {
                    let ends: Vec<(usize, &Schema)> = task
                        .schemas
                        .iter()
                        .enumerate()
                        .filter(|(_, s)| s.snap == Snap::End && s.base == schema.base)
                        .collect();
                    for (end_index, end) in ends {
                        let end = Some((end, end_index));
                        actions.push(PddlAction {
                            name: String::new(),
                            start: schema,
                            start_index: index,
                            end,
                            class: None,
                        });
                    }
                }
                Snap::End => {}
            }
        }
        // Renumber names per base: grip_1, grip_2, ... in clause order.
        let mut per_base: FxHashMap<Symbol, usize> = FxHashMap::default();
        let mut renamed = Names::default();
        renamed.taken.extend(self.predicate_names.values().cloned());
        for action in &mut actions {
            let base = action.start.base;
            let count = per_base.entry(base).or_default();
            *count += 1;
            let text = self.interner.resolve(base);
            action.name =
                if action.end.is_some() { renamed.fresh(&format!("{text}_{count}")) } else { renamed.fresh(text) };
        }

        // Static predicates: OnKB and InvalidAtEnd, per schema.
        let mut statics: Vec<Option<(String, Vec<u32>)>> = vec![None; task.schemas.len()];
        let mut static_names = Names::default();
        static_names.taken.extend(self.predicate_names.values().cloned());
        static_names.taken.extend(renamed.taken.iter().cloned());
        let mut alternative: FxHashMap<Symbol, usize> = FxHashMap::default();
        for (index, schema) in task.schemas.iter().enumerate() {
            let schema_name = kb.actions[schema.action].name.name();
            let count = alternative.entry(schema_name).or_default();
            *count += 1;
            if schema.on_kb.is_empty() && schema.invalid_at_end.is_empty() {
                continue;
            }
            let mut vars: Vec<u32> = Vec::new();
            for goal in schema.on_kb.iter() {
                goal.for_each_call(&mut |l| l.term.for_each_var(&mut |v| vars.push(v.0)));
            }
            for term in schema.invalid_at_end.iter() {
                term.for_each_var(&mut |v| vars.push(v.0));
            }
            let bound = bound_vars(schema);
            vars.retain(|v| bound.contains(v));
            let mut seen = FxHashSet::default();
            vars.retain(|v| seen.insert(*v));
            let name = static_names.fresh(&format!("onkb_{}_{count}", self.interner.resolve(schema_name)));
            statics[index] = Some((name, vars));
        }
        let mut static_facts: BTreeSet<(String, Vec<ConstId>)> = BTreeSet::new();
        for instance in instances {
            if let Some((name, vars)) = &statics[instance.schema] {
                let values: Option<Vec<ConstId>> = vars.iter().map(|&v| instance.bindings[v as usize]).collect();
                match values {
                    Some(values) => {
                        static_facts.insert((name.clone(), values));
                    }
                    None => {
                        let span = kb.actions[task.schemas[instance.schema].action].slots[4];
                        self.error(
                            span,
                            "these goals succeed without binding a variable",
                            "an OnKB goal leaves a variable unbound".into(),
                            "the export lists OnKB solutions as facts, which must be ground; bind every variable",
                        );
                        return None;
                    }
                }
            }
        }

        // Durations, per durative base, from the reachable starts.
        let mut durations: FxHashMap<Symbol, DurationSpec> = FxHashMap::default();
        let mut machine = Machine::new(program, 1_000_000);
        for action in &actions {
            let Some(_) = action.end else { continue };
            let base = action.start.base;
            if durations.contains_key(&base) {
                continue;
            }
            let starts: BTreeSet<Vec<ConstId>> = instances
                .iter()
                .filter(|i| task.schemas[i.schema].snap == Snap::Start && task.schemas[i.schema].base == base)
                .filter_map(|i| name_args(&task.schemas[i.schema], &i.bindings))
                .collect();
            let mut spec = self.duration_spec(base, &starts, &mut machine)?;
            // Duration classes where a numeric function cannot say it exactly (some instances
            // with a maximum, some without) or the reader wants none.
            let mixed = spec.values.values().any(|(_, max)| max.is_none())
                && spec.values.values().any(|(_, max)| max.is_some());
            let classes = match self.options.durations {
                Durations::Bounded => true,
                Durations::Exact => mixed,
                Durations::Min => false,
            };
            if let Some((name, _)) = &spec.function
                && classes
            {
                // One static predicate per distinct duration, named after the function.
                let mut bounds: Vec<(f64, Option<f64>)> = spec.values.values().copied().collect();
                bounds.sort_by(|a, b| {
                    a.0.total_cmp(&b.0).then(a.1.unwrap_or(f64::INFINITY).total_cmp(&b.1.unwrap_or(f64::INFINITY)))
                });
                bounds.dedup();
                spec.classes = bounds
                    .into_iter()
                    .enumerate()
                    .map(|(k, b)| (b, static_names.fresh(&format!("{name}_{}", k + 1))))
                    .collect();
            }
            durations.insert(base, spec);
        }
        // A durative action whose duration varies: one copy per duration class.
        let mut expanded: Vec<PddlAction<'_>> = Vec::new();
        for action in actions {
            let classes = action.end.and_then(|_| durations.get(&action.start.base)).map_or(0, |d| d.classes.len());
            if classes == 0 {
                expanded.push(action);
                continue;
            }
            for k in 0..classes {
                let name = renamed.fresh(&format!("{}_{}", action.name, k + 1));
                let (start, start_index, end) = (action.start, action.start_index, action.end);
                expanded.push(PddlAction { name, start, start_index, end, class: Some(k) });
            }
        }
        let actions = expanded;

        let mut domain = String::new();
        // (A problem's name may be any atom, `'test 1'` or `test(1)`: written as a PDDL name.)
        let domain_name = self.object_names.fresh(&format!("kbc-{problem_name}"));
        let mut requirements = vec![":durative-actions"];
        if self.options.negative_preconditions && task.schemas.iter().any(|s| !s.invalid.is_empty()) {
            requirements.push(":negative-preconditions");
        }
        if self.options.negative_preconditions
            && task.schemas.iter().any(|s| s.invalid.iter().any(|l| has_existential(s, l)))
        {
            requirements.push(":existential-preconditions");
        }
        if task.goal_vars > 0 {
            requirements.push(":existential-preconditions");
        }
        requirements.dedup();
        if durations.values().any(DurationSpec::is_function) {
            requirements.push(":numeric-fluents");
        }
        if self.options.durations != Durations::Min && durations.values().any(DurationSpec::has_inequality) {
            requirements.push(":duration-inequalities");
        }
        requirements.sort_unstable();
        requirements.dedup();
        writeln!(domain, "; Written by kbc export pddl from problem `{problem_name}` of the KB.").unwrap();
        writeln!(domain, "; names.json maps these names back to the KB's terms and snap actions.").unwrap();
        writeln!(domain, "(define (domain {domain_name})").unwrap();
        writeln!(domain, "  (:requirements {})", requirements.join(" ")).unwrap();
        writeln!(domain, "  (:predicates").unwrap();
        let mut preds: Vec<(String, usize)> = task
            .facts
            .fluent_preds()
            .map(|pred| (self.predicate_names[&pred].clone(), task.facts.pred_info(pred).1))
            .collect();
        for (pred, name) in &self.complemented {
            preds.push((name.clone(), task.facts.pred_info(*pred).1));
        }
        for (name, vars) in statics.iter().flatten() {
            preds.push((name.clone(), vars.len()));
        }
        let mut specs: Vec<&DurationSpec> = durations.values().collect();
        specs.sort_by(|a, b| a.function.cmp(&b.function));
        for spec in &specs {
            if let Some((_, positions)) = &spec.function {
                preds.extend(spec.classes.iter().map(|(_, name)| (name.clone(), positions.len())));
            }
        }
        for (name, arity) in &preds {
            let args: String = (1..=*arity).map(|i| format!(" ?x{i}")).collect();
            writeln!(domain, "    ({name}{args})").unwrap();
        }
        writeln!(domain, "  )").unwrap();
        let mut function_lines = Vec::new();
        for spec in specs.iter().filter(|s| s.is_function()) {
            let (name, positions) = spec.function.as_ref().expect("a function");
            let args: String = (1..=positions.len()).map(|i| format!(" ?x{i}")).collect();
            function_lines.push(format!("    ({name}{args})"));
            if spec.writes_max(self.options.durations) {
                function_lines.push(format!("    ({name}_max{args})"));
            }
        }
        if !function_lines.is_empty() {
            writeln!(domain, "  (:functions\n{}\n  )", function_lines.join("\n")).unwrap();
        }

        let mut names_actions = serde_json::Map::new();
        for action in &actions {
            let text = self.action_text(action, &durations, &statics, &mut names_actions)?;
            domain.push_str(&text);
        }
        writeln!(domain, ")").unwrap();

        // The problem.
        let mut init: Vec<String> = Vec::new();
        let init_facts: Vec<FactId> = task.init.facts().collect();
        for &fact in &init_facts {
            init.push(self.fact_text(fact, None));
        }
        if !self.complemented.is_empty() {
            let complemented: Vec<(PredId, String)> = self.complemented.iter().map(|(p, n)| (*p, n.clone())).collect();
            let present: FxHashSet<FactId> = init_facts.iter().copied().collect();
            let mut written = 0usize;
            for (pred, name) in complemented {
                let Some(domains) = self.domains.get(&pred).cloned() else {
                    continue; // nothing reachable: the complement is never read as false
                };
                let lists: Vec<Vec<ConstId>> = domains.iter().map(|d| d.iter().copied().collect()).collect();
                let total: usize = lists.iter().map(Vec::len).product();
                written += total;
                if written > self.options.limit {
                    self.diags.push(
                        Diagnostic::error(codes::EXPORT_TOO_LARGE, "the exported task would be too large")
                            .primary(problem.span, "exporting this problem without negative conditions")
                            .with_note(format!("the complement facts number more than {}", self.options.limit)),
                    );
                    return None;
                }
                for_each_tuple(&lists, &mut |tuple| {
                    let fact = task.facts.find(pred, tuple);
                    if fact.is_none_or(|f| !present.contains(&f)) {
                        let args: Vec<String> = tuple.iter().map(|&c| self.object(c)).collect();
                        init.push(format!("({name} {})", args.join(" ")));
                    }
                });
            }
        }
        for (name, values) in &static_facts {
            let args: Vec<String> = values.iter().map(|&c| self.object(c)).collect();
            init.push(if args.is_empty() { format!("({name})") } else { format!("({name} {})", args.join(" ")) });
        }
        for spec in specs {
            let Some((name, _)) = &spec.function else { continue };
            let writes_max = spec.writes_max(self.options.durations);
            for (args, bounds) in &spec.values {
                let args: Vec<String> = args.iter().map(|&c| self.object(c)).collect();
                if !spec.is_function() {
                    let Some((_, class)) = spec.classes.iter().find(|(b, _)| b == bounds) else { continue };
                    init.push(format!("({class} {})", args.join(" ")));
                    continue;
                }
                init.push(format!("(= ({name} {}) {})", args.join(" "), number(bounds.0)));
                if writes_max {
                    let max = bounds.1.expect("a function with a maximum has one for every instance");
                    init.push(format!("(= ({name}_max {}) {})", args.join(" "), number(max)));
                }
            }
        }
        let goal_vars: VarNames = (0..task.goal_vars).map(|v| Some(format!("?g{}", v + 1))).collect();
        let goal: Vec<String> = task.goal.clone().iter().map(|l| self.literal(l, &goal_vars, None)).collect();
        let mut objects: Vec<(String, ConstId)> = self.objects.iter().map(|(c, n)| (n.clone(), *c)).collect();
        objects.sort();
        // Objects the domain's actions name (the complements of an Invalid literal with an
        // anonymous argument expand over them) are the domain's constants: declared there, and
        // not again among the problem's objects.
        let in_domain: BTreeSet<&str> =
            domain.split(|c: char| c.is_whitespace() || c == '(' || c == ')').filter(|w| !w.is_empty()).collect();
        let constants: Vec<&str> = objects.iter().map(|(n, _)| n.as_str()).filter(|n| in_domain.contains(n)).collect();
        if !constants.is_empty() {
            let mut lines = String::from("  (:constants\n");
            for chunk in constants.chunks(12) {
                lines.push_str(&format!("    {}\n", chunk.join(" ")));
            }
            lines.push_str("  )\n");
            let at = domain.find("  (:predicates").expect("the domain declares its predicates");
            domain.insert_str(at, &lines);
        }
        let constants: BTreeSet<String> = constants.into_iter().map(str::to_string).collect();
        let mut text = String::new();
        writeln!(text, "; Written by kbc export pddl from problem `{problem_name}` of the KB.").unwrap();
        writeln!(text, "(define (problem {})", self.object_names.fresh(&problem_name)).unwrap();
        writeln!(text, "  (:domain {domain_name})").unwrap();
        writeln!(text, "  (:objects").unwrap();
        let problem_objects: Vec<&str> =
            objects.iter().map(|(n, _)| n.as_str()).filter(|n| !constants.contains(*n)).collect();
        for chunk in problem_objects.chunks(12) {
            writeln!(text, "    {}", chunk.join(" ")).unwrap();
        }
        writeln!(text, "  )").unwrap();
        writeln!(text, "  (:init").unwrap();
        for line in &init {
            writeln!(text, "    {line}").unwrap();
        }
        writeln!(text, "  )").unwrap();
        let body =
            if goal.is_empty() { "(and)".to_string() } else { format!("(and\n    {}\n  )", goal.join("\n    ")) };
        if task.goal_vars > 0 {
            let vars: Vec<String> = goal_vars.iter().flatten().cloned().collect();
            writeln!(text, "  (:goal (exists ({}) {body}))", vars.join(" ")).unwrap();
        } else {
            writeln!(text, "  (:goal {body})").unwrap();
        }
        writeln!(text, "  (:metric minimize (total-time))").unwrap();
        writeln!(text, ")").unwrap();

        let mut names_objects = serde_json::Map::new();
        for (name, value) in &objects {
            names_objects.insert(name.clone(), serde_json::Value::String(self.term_text(*value)));
        }
        let names = serde_json::json!({
            "format": "kbc-pddl-names/1",
            "problem": problem_name,
            "objects": names_objects,
            "actions": names_actions,
        });
        let names = serde_json::to_string_pretty(&names).expect("JSON of strings") + "\n";
        Some(Export { domain, problem: text, names })
    }

    fn fact_text(&mut self, fact: FactId, name: Option<&str>) -> String {
        let pred = self.task.facts.pred_of(fact);
        let pred_name = name.map_or_else(|| self.predicate_names[&pred].clone(), str::to_string);
        let args: Vec<ConstId> = self.task.facts.args(fact).to_vec();
        if args.is_empty() {
            return format!("({pred_name})");
        }
        let args: Vec<String> = args.into_iter().map(|c| self.object(c)).collect();
        format!("({pred_name} {})", args.join(" "))
    }

    /// The PDDL variable names of a schema: `?` and the KB name in lower case (name arguments
    /// of an end take the start's names), unique within the action.
    fn var_names(&self, schema: &Schema, taken: &mut Names, shared: Option<(&Schema, &VarNames)>) -> VarNames {
        let action = &self.kb.actions[schema.action];
        let bound = bound_vars(schema);
        let mut names: VarNames = vec![None; schema.vars];
        if let (Some((start, start_names)), Pattern::Compound(_, args)) = (shared, &schema.name)
            && let Pattern::Compound(_, start_args) = &start.name
        {
            for (arg, start_arg) in args.iter().zip(start_args.iter()) {
                if let (Pattern::Var(v), Pattern::Var(s)) = (arg, start_arg) {
                    names[*v as usize] = start_names[*s as usize].clone();
                }
            }
        }
        for v in 0..schema.vars as u32 {
            if names[v as usize].is_some() || !bound.contains(&v) {
                continue;
            }
            let written = self.interner.resolve(action.vars.get(hir::VarId(v)).name);
            let wanted = if written.starts_with('_') { format!("v{v}") } else { written.to_ascii_lowercase() };
            names[v as usize] = Some(format!("?{}", taken.fresh(&wanted)));
        }
        names
    }

    fn action_text(
        &mut self,
        action: &PddlAction<'_>,
        durations: &FxHashMap<Symbol, DurationSpec>,
        statics: &[Option<(String, Vec<u32>)>],
        names_actions: &mut serde_json::Map<String, serde_json::Value>,
    ) -> Option<String> {
        let mut taken = Names::default();
        let start_vars = self.var_names(action.start, &mut taken, None);
        let end_vars = action.end.map(|(end, _)| self.var_names(end, &mut taken, Some((action.start, &start_vars))));
        // Parameters: the name's arguments, then the rest in order of first occurrence; each
        // with the snap action and schema variable it comes from (for writing plans in
        // these names).
        let mut parameters: Vec<String> = Vec::new();
        let mut sources: Vec<serde_json::Value> = Vec::new();
        let mut push = |name: &Option<String>, snap: &str, var: usize| {
            if let Some(name) = name
                && !parameters.contains(name)
            {
                parameters.push(name.clone());
                sources.push(serde_json::json!([snap, var]));
            }
        };
        if let Pattern::Compound(_, args) = &action.start.name {
            for arg in args.iter() {
                if let Pattern::Var(v) = arg {
                    push(&start_vars[*v as usize], "start", *v as usize);
                }
            }
        }
        for (v, name) in start_vars.iter().enumerate() {
            push(name, "start", v);
        }
        if let Some(end_vars) = &end_vars {
            for (v, name) in end_vars.iter().enumerate() {
                push(name, "end", v);
            }
        }
        let mut conditions: Vec<String> = Vec::new();
        let mut effects: Vec<String> = Vec::new();
        let durative = action.end.is_some();
        let mut snap_parts = vec![(action.start, action.start_index, &start_vars, "at start")];
        if let (Some((end, end_index)), Some(end_vars)) = (action.end, &end_vars) {
            snap_parts.push((end, end_index, end_vars, "at end"));
        }
        // The facts the start adds, for dropping end conditions they already guarantee.
        let start_adds: Vec<String> = action
            .start
            .effects
            .iter()
            .filter(|(kind, _)| *kind == EffectKind::Add)
            .map(|(_, l)| l.clone())
            .collect::<Vec<_>>()
            .iter()
            .map(|l| self.literal(l, &start_vars, None))
            .collect();
        for (schema, index, vars, when) in snap_parts {
            let mut local: Vec<String> = Vec::new();
            for literal in schema.valid.iter() {
                let atom = self.literal(literal, vars, None);
                // An end condition on a fact its own start adds, which nothing but the ends of
                // this durative action deletes, holds at the end of every execution: it says
                // nothing, and planners that check end conditions for reachability before the
                // action starts (LPG does) would find the action unreachable.
                if schema.snap == Snap::End
                    && start_adds.contains(&atom)
                    && !self.deleted_elsewhere(literal.pred, schema.base)
                {
                    continue;
                }
                local.push(atom);
            }
            for literal in schema.invalid.iter() {
                self.invalid_conditions(literal, vars, &mut local)?;
            }
            if let Some((name, static_vars)) = &statics[index] {
                let args: Vec<&str> =
                    static_vars.iter().map(|&v| vars[v as usize].as_deref().unwrap_or("?_")).collect();
                local.push(if args.is_empty() { format!("({name})") } else { format!("({name} {})", args.join(" ")) });
            }
            if schema.snap == Snap::Start
                && let Some(k) = action.class
            {
                local.push(self.duration_class_condition(&durations[&schema.base], k, schema, vars));
            }
            if durative {
                conditions.extend(local.into_iter().map(|c| format!("({when} {c})")));
                self.effects(schema, vars, Some(when), &mut effects);
            } else {
                conditions.extend(local);
                self.effects(schema, vars, None, &mut effects);
            }
        }
        let mut text = String::new();
        let start_name = self.pattern_text(&action.start.name, &start_vars);
        let mut entry = serde_json::Map::new();
        entry.insert("parameters".into(), serde_json::json!(parameters));
        entry.insert("sources".into(), serde_json::json!(sources));
        entry.insert("start_schema".into(), serde_json::json!(action.start.action));
        if let Some((end, _)) = action.end {
            entry.insert("end_schema".into(), serde_json::json!(end.action));
        }
        if let (Some((end, _)), Some(end_vars)) = (action.end, &end_vars) {
            let end_name = self.pattern_text(&end.name, end_vars);
            writeln!(text, "\n  ; {start_name} ... {end_name}").unwrap();
            writeln!(text, "  (:durative-action {}", action.name).unwrap();
            writeln!(text, "    :parameters ({})", parameters.join(" ")).unwrap();
            let spec = &durations[&action.start.base];
            if spec.is_function() {
                writeln!(text, "    :duration {}", self.function_duration_text(spec, action.start, &start_vars))
                    .unwrap();
            } else {
                let (min, max) = spec.bounds(action.class);
                writeln!(text, "    :duration {}", self.duration_text(min, max)).unwrap();
                entry.insert("duration".into(), serde_json::json!([min, max]));
            }
            entry.insert("start".into(), serde_json::json!(start_name));
            entry.insert("end".into(), serde_json::json!(end_name));
        } else {
            writeln!(text, "\n  ; {start_name}").unwrap();
            writeln!(text, "  (:action {}", action.name).unwrap();
            writeln!(text, "    :parameters ({})", parameters.join(" ")).unwrap();
            entry.insert("instant".into(), serde_json::json!(start_name));
        }
        names_actions.insert(action.name.clone(), serde_json::Value::Object(entry));
        let (condition_key, effect_key) =
            if durative { (":condition", ":effect") } else { (":precondition", ":effect") };
        writeln!(text, "    {condition_key} (and\n      {}\n    )", conditions.join("\n      ")).unwrap();
        writeln!(text, "    {effect_key} (and\n      {}\n    )", effects.join("\n      ")).unwrap();
        writeln!(text, "  )").unwrap();
        Some(text)
    }

    /// Whether a schema other than an end of durative action `base` deletes facts of `pred`.
    fn deleted_elsewhere(&self, pred: PredId, base: Symbol) -> bool {
        self.task.schemas.iter().any(|s| {
            !(s.snap == Snap::End && s.base == base)
                && s.effects.iter().any(|(kind, l)| *kind == EffectKind::Del && l.pred == pred)
        })
    }

    /// The name pattern with PDDL variables: `grip_start(?a, ?b)`.
    fn pattern_text(&mut self, pattern: &Pattern, vars: &VarNames) -> String {
        match pattern {
            Pattern::Const(c) => self.term_text(*c),
            Pattern::Var(v) => vars[*v as usize].clone().unwrap_or_else(|| "_".into()),
            Pattern::Compound(f, args) => {
                let args: Vec<String> = args.iter().map(|a| self.pattern_text(a, vars)).collect();
                format!("{}({})", self.interner.resolve(*f), args.join(", "))
            }
        }
    }

    /// The `:duration` of an action whose duration is `[min, max]` (`None`: no maximum).
    fn duration_text(&self, min: f64, max: Option<f64>) -> String {
        let exact = self.options.durations != Durations::Min;
        let max = match self.options.durations {
            Durations::Bounded => Some(max.unwrap_or(BOUNDED_MAX.max(min))),
            _ => max,
        };
        match max {
            Some(max) if max == min || !exact => format!("(= ?duration {})", number(min)),
            Some(max) => format!("(and (>= ?duration {}) (<= ?duration {}))", number(min), number(max)),
            None if exact => format!("(>= ?duration {})", number(min)),
            None => format!("(= ?duration {})", number(min)),
        }
    }

    /// The `:duration` of an action whose duration is a numeric function of its name's
    /// arguments (with a second function for the maximum when there is one).
    fn function_duration_text(&self, spec: &DurationSpec, start: &Schema, vars: &VarNames) -> String {
        let (name, _) = spec.function.as_ref().expect("a function");
        let args = self.duration_args(spec, start, vars).join(" ");
        let min = format!("({name} {args})");
        let fixed = spec.values.values().all(|(min, max)| *max == Some(*min));
        if fixed || self.options.durations == Durations::Min {
            format!("(= ?duration {min})")
        } else if spec.writes_max(self.options.durations) {
            format!("(and (>= ?duration {min}) (<= ?duration ({name}_max {args})))")
        } else {
            format!("(>= ?duration {min})")
        }
    }

    /// The PDDL variables of the name arguments `spec`'s duration depends on.
    fn duration_args<'v>(&self, spec: &DurationSpec, start: &Schema, vars: &'v VarNames) -> Vec<&'v str> {
        let positions = spec.function.as_ref().map(|(_, p)| p.as_slice()).unwrap_or_default();
        match &start.name {
            Pattern::Compound(_, args) => positions
                .iter()
                .map(|&p| match &args[p] {
                    Pattern::Var(v) => vars[*v as usize].as_deref().unwrap_or("?_"),
                    _ => "?_",
                })
                .collect(),
            _ => Vec::new(),
        }
    }

    /// The condition that picks duration class `k` of `spec` for a start schema's instance:
    /// the class's static predicate over the name arguments the duration depends on.
    fn duration_class_condition(&self, spec: &DurationSpec, k: usize, start: &Schema, vars: &VarNames) -> String {
        format!("({} {})", spec.classes[k].1, self.duration_args(spec, start, vars).join(" "))
    }

    /// The durations of a durative base over its reachable starts.
    fn duration_spec(
        &mut self,
        base: Symbol,
        starts: &BTreeSet<Vec<ConstId>>,
        machine: &mut Machine<'_>,
    ) -> Option<DurationSpec> {
        let mut values: BTreeMap<Vec<ConstId>, (f64, Option<f64>)> = BTreeMap::new();
        let mut defaulted = false;
        for args in starts {
            let term = if args.is_empty() {
                hir::Term::Atom(base)
            } else {
                hir::Term::Compound(base, args.iter().map(|&c| self.task.consts.to_term(c)).collect())
            };
            let bounds = match crate::passes::stn::query_duration(machine, &term) {
                Ok(Some((min, max))) if min >= 0.0 && max.is_none_or(|m| m >= min) => (min, max),
                Ok(Some((min, max))) => {
                    let shown = hir::term_to_string(self.interner, &term, &VarTable::default());
                    self.diags.push(
                        Diagnostic::error(
                            codes::BAD_DURATION_VALUE,
                            format!("the duration of `{shown}` is out of range"),
                        )
                        .with_note(format!(
                            "`duration/3` gave [{min}, {}] time units",
                            max.map_or("inf".to_string(), |m| m.to_string())
                        )),
                    );
                    return None;
                }
                Ok(None) => {
                    defaulted = true;
                    (crate::ir::stn::DEFAULT_DURATION as f64, None)
                }
                Err(why) => {
                    let shown = hir::term_to_string(self.interner, &term, &VarTable::default());
                    self.diags.push(
                        Diagnostic::error(codes::BAD_DURATION_VALUE, format!("the duration of `{shown}` is unusable"))
                            .with_note(why),
                    );
                    return None;
                }
            };
            values.insert(args.clone(), bounds);
        }
        if defaulted {
            let text = self.interner.resolve(base);
            let span = self.task.schemas.iter().find(|s| s.base == base).map(|s| self.kb.actions[s.action].name.span);
            let mut diagnostic = Diagnostic::warning(
                codes::DEFAULT_DURATION,
                format!("`{text}` has no duration: it takes at least {} time unit", crate::ir::stn::DEFAULT_DURATION),
            );
            if let Some(span) = span {
                diagnostic = diagnostic.primary(span, "this durative action");
            }
            self.diags.push(diagnostic);
        }
        let distinct: BTreeSet<(u64, Option<u64>)> =
            values.values().map(|(a, b)| (a.to_bits(), b.map(f64::to_bits))).collect();
        if distinct.len() <= 1 {
            let single = values.values().next().copied().unwrap_or((1.0, Some(1.0)));
            let mut one = BTreeMap::new();
            one.insert(Vec::new(), single);
            return Some(DurationSpec { function: None, values: one, classes: Vec::new() });
        }
        // The name positions the bounds depend on: drop each position the bounds stay a
        // function of the others without.
        let arity = starts.iter().next().map_or(0, Vec::len);
        let mut kept: Vec<usize> = (0..arity).collect();
        for position in 0..arity {
            let trial: Vec<usize> = kept.iter().copied().filter(|&p| p != position).collect();
            let mut seen: BTreeMap<Vec<ConstId>, (u64, Option<u64>)> = BTreeMap::new();
            let functional = values.iter().all(|(args, (min, max))| {
                let key: Vec<ConstId> = trial.iter().map(|&p| args[p]).collect();
                let value = (min.to_bits(), max.map(f64::to_bits));
                *seen.entry(key).or_insert(value) == value
            });
            if functional {
                kept = trial;
            }
        }
        let mut projected: BTreeMap<Vec<ConstId>, (f64, Option<f64>)> = BTreeMap::new();
        for (args, bounds) in values {
            projected.insert(kept.iter().map(|&p| args[p]).collect(), bounds);
        }
        let name = self.object_names.fresh(&format!("duration_{}", self.interner.resolve(base)));
        Some(DurationSpec { function: Some((name, kept)), values: projected, classes: Vec::new() })
    }
}

/// The durations of one durative action: one value, or a function over some name positions.
struct DurationSpec {
    /// The function's name and the name positions it takes; `None` for one value for all.
    function: Option<(String, Vec<usize>)>,
    /// Bounds per tuple of the kept positions (one entry, with no arguments, for a constant).
    values: BTreeMap<Vec<ConstId>, (f64, Option<f64>)>,
    /// For a function: its distinct bounds, shortest first, each with the static predicate
    /// that holds for the tuples of that duration.
    classes: Vec<((f64, Option<f64>), String)>,
}

impl DurationSpec {
    /// The bounds of duration class `class`, or the one value.
    fn bounds(&self, class: Option<usize>) -> (f64, Option<f64>) {
        match class {
            Some(k) => self.classes[k].0,
            None => self.values.values().next().copied().unwrap_or((1.0, Some(1.0))),
        }
    }

    /// Whether the duration is written as a numeric function: it varies, and is not split
    /// into duration classes.
    fn is_function(&self) -> bool {
        self.function.is_some() && self.classes.is_empty()
    }

    /// Whether a function's maximum is written as a second function: every instance has a
    /// finite maximum, some above its minimum, and the durations are written exactly.
    fn writes_max(&self, durations: Durations) -> bool {
        durations != Durations::Min
            && self.values.values().all(|(_, max)| max.is_some())
            && self.values.values().any(|(min, max)| max.is_some_and(|m| m > *min))
    }

    /// Whether some instance's duration is not one number: a maximum above its minimum, or
    /// none (written as duration inequalities in [`Durations::Exact`]).
    fn has_inequality(&self) -> bool {
        self.values.values().any(|(min, max)| max.is_none_or(|m| m > *min))
    }
}

fn number(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e15 { format!("{}", value as i64) } else { format!("{value}") }
}

/// The variables a schema binds (name, Valid, OnKB, effects): everything but the existential
/// variables of Invalid literals.
fn bound_vars(schema: &Schema) -> BTreeSet<u32> {
    let mut vars = BTreeSet::new();
    let mut add = |p: &Pattern| pattern_vars(p, &mut vars);
    add(&schema.name);
    for literal in schema.valid.iter().chain(schema.effects.iter().map(|(_, l)| l)) {
        literal.args.iter().for_each(&mut add);
    }
    for goal in schema.on_kb.iter() {
        goal.for_each_call(&mut |l| {
            l.term.for_each_var(&mut |v| {
                vars.insert(v.0);
            })
        });
    }
    vars
}

fn pattern_vars(pattern: &Pattern, vars: &mut BTreeSet<u32>) {
    match pattern {
        Pattern::Const(_) => {}
        Pattern::Var(v) => {
            vars.insert(*v);
        }
        Pattern::Compound(_, args) => args.iter().for_each(|a| pattern_vars(a, vars)),
    }
}

fn has_existential(schema: &Schema, literal: &LiteralPattern) -> bool {
    let bound = bound_vars(schema);
    let mut vars = BTreeSet::new();
    literal.args.iter().for_each(|a| pattern_vars(a, &mut vars));
    vars.iter().any(|v| !bound.contains(v))
}

/// The values of a start's name arguments.
fn name_args(schema: &Schema, bindings: &[Option<ConstId>]) -> Option<Vec<ConstId>> {
    match &schema.name {
        Pattern::Compound(_, args) => args
            .iter()
            .map(|a| match a {
                Pattern::Var(v) => bindings[*v as usize],
                Pattern::Const(c) => Some(*c),
                Pattern::Compound(..) => None,
            })
            .collect(),
        _ => Some(Vec::new()),
    }
}

/// Whether two literal patterns of one schema could stand for the same fact: same predicate,
/// and no position with two different constants (variables may take any value).
fn patterns_may_meet(a: &LiteralPattern, b: &LiteralPattern) -> bool {
    a.pred == b.pred
        && a.args.iter().zip(b.args.iter()).all(|(x, y)| match (x, y) {
            (Pattern::Const(p), Pattern::Const(q)) => p == q,
            _ => true,
        })
}

/// Calls `f` on every tuple of the product of `lists`.
fn for_each_tuple(lists: &[Vec<ConstId>], f: &mut impl FnMut(&[ConstId])) {
    if lists.iter().any(Vec::is_empty) {
        return;
    }
    let mut index = vec![0usize; lists.len()];
    let mut tuple: Vec<ConstId> = lists.iter().map(|l| l[0]).collect();
    loop {
        f(&tuple);
        let mut k = 0;
        loop {
            if k == lists.len() {
                return;
            }
            index[k] += 1;
            if index[k] < lists[k].len() {
                tuple[k] = lists[k][index[k]];
                break;
            }
            index[k] = 0;
            tuple[k] = lists[k][0];
            k += 1;
        }
    }
}

/// A timed plan another planner found for an exported problem, written back in the KB's
/// terms through `names.json`: in each line `TIME: (ACTION ARGS...) [DURATION]`, the action
/// and the objects are replaced by the KB action they stand for (`(grip_1 a1 b2 n1 n1)`
/// becomes `(grip a1 b2)`, the format `kbc plan --schedule` prints and `kbc validate` reads).
/// Blank and comment lines are kept. A line whose action or object `names` does not know is
/// an error: its index (from 0) and why.
pub fn plan_from_pddl(text: &str, names: &serde_json::Value) -> Result<String, (usize, String)> {
    let mut out = String::with_capacity(text.len());
    for (index, line) in text.lines().enumerate() {
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with(';') || trimmed.starts_with('%') {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        let fail = |why: String| (index, why);
        let (time, rest) = trimmed.split_once(':').ok_or_else(|| fail("expected `TIME: (ACTION ...)`".into()))?;
        let open = rest.find('(').ok_or_else(|| fail("expected `(` before the action".into()))?;
        let close = rest.find(')').ok_or_else(|| fail("expected `)` after the action".into()))?;
        let words: Vec<String> = rest[open + 1..close].split_whitespace().map(str::to_lowercase).collect();
        let (action, objects) = words.split_first().ok_or_else(|| fail("the action has no name".into()))?;
        let entry = &names["actions"][action.as_str()];
        let parameters: Vec<&str> = entry["parameters"]
            .as_array()
            .ok_or_else(|| fail(format!("names.json has no action `{action}`")))?
            .iter()
            .filter_map(serde_json::Value::as_str)
            .collect();
        if parameters.len() != objects.len() {
            return Err(fail(format!(
                "`{action}` takes {} arguments in names.json, the line gives {}",
                parameters.len(),
                objects.len()
            )));
        }
        let mut values: Vec<(&str, &str)> = Vec::with_capacity(objects.len());
        for (parameter, object) in parameters.iter().zip(objects) {
            let value = names["objects"][object.as_str()]
                .as_str()
                .ok_or_else(|| fail(format!("names.json has no object `{object}`")))?;
            values.push((parameter, value));
        }
        // Longer parameter names first, so `?x2` is not read as `?x` followed by `2`.
        values.sort_by_key(|(p, _)| std::cmp::Reverse(p.len()));
        let (template, durative) = match (entry["start"].as_str(), entry["instant"].as_str()) {
            (Some(start), _) => (start, true),
            (None, Some(instant)) => (instant, false),
            _ => return Err(fail(format!("names.json gives no KB action for `{action}`"))),
        };
        let mut term = template.to_string();
        for (parameter, value) in &values {
            term = term.replace(parameter, value);
        }
        let (functor, arguments) = match term.split_once('(') {
            Some((f, a)) => (f.to_string(), a.strip_suffix(')').unwrap_or(a).to_string()),
            None => (term.clone(), String::new()),
        };
        let base = if durative { functor.strip_suffix("_start").unwrap_or(&functor).to_string() } else { functor };
        use crate::syntax::text::{split_top_level, without_layout};
        let arguments: Vec<String> =
            split_top_level(&arguments, |c| c == ',').iter().map(|a| without_layout(a)).collect();
        let call = if arguments.is_empty() { format!("({base})") } else { format!("({base} {})", arguments.join(" ")) };
        let after = &rest[close + 1..];
        out.push_str(&format!("{}: {call}{after}\n", time.trim()));
    }
    Ok(out)
}

/// A scheduled kbc plan written as a PDDL 2.1 timed plan in the names of an export
/// (`names.json` of [`export`] for the same problem): each action as the PDDL action that
/// stands for its start and end schemas, with its parameters' values (hidden variables
/// included) as the export's objects, so that other tools (Kairos, VAL, unified-planning) can
/// validate kbc's plans against the exported domain and problem. `Err` names what `names`
/// does not know.
pub fn plan_to_pddl(
    names: &serde_json::Value,
    kb: &Kb,
    interner: &Interner,
    plan: &crate::ir::plan::Plan,
    pop: &crate::ir::pop::Pop,
    stn: &crate::ir::stn::Stn,
    schedule: &crate::ir::schedule::Schedule,
) -> Result<String, String> {
    let no_vars = VarTable::default();
    let objects: FxHashMap<&str, &str> = names["objects"]
        .as_object()
        .map(|o| o.iter().filter_map(|(name, text)| Some((text.as_str()?, name.as_str()))).collect())
        .unwrap_or_default();
    let actions = names["actions"].as_object().ok_or("names.json has no actions")?;
    let mut out = String::new();
    for timed in crate::ir::schedule::timed_actions(kb, pop, schedule) {
        let start = &plan.steps[timed.step];
        let end = timed.end.map(|e| &plan.steps[e]);
        let shown = hir::term_to_string(interner, &timed.name, &no_vars);
        // The action of these schemas; for a duration that varies, the copy of this step's
        // duration (names.json gives each durative action's `[min, max]`).
        let bounds = stn.durations.get(timed.step).copied().flatten();
        let same_duration = |entry: &serde_json::Value| {
            let Some(bounds) = bounds else { return true };
            let units = |v: &serde_json::Value| v.as_f64().and_then(crate::passes::stn::to_stn_time);
            units(&entry["duration"][0]) == Some(bounds.min) && units(&entry["duration"][1]) == bounds.max
        };
        let (name, entry) = actions
            .iter()
            .find(|(_, entry)| {
                entry["start_schema"].as_u64() == Some(start.action as u64)
                    && entry["end_schema"].as_u64() == end.map(|e| e.action as u64)
                    && (entry.get("duration").is_none() || same_duration(entry))
            })
            .ok_or_else(|| format!("names.json has no action for `{shown}`"))?;
        let mut words = vec![name.clone()];
        for source in entry["sources"].as_array().into_iter().flatten() {
            let step = match source[0].as_str() {
                Some("end") => end.ok_or_else(|| format!("`{shown}` has no end"))?,
                _ => start,
            };
            let var = source[1].as_u64().unwrap_or(u64::MAX) as usize;
            let value = step
                .bindings
                .get(var)
                .cloned()
                .flatten()
                .ok_or_else(|| format!("`{shown}` leaves a parameter of `{name}` without a value"))?;
            let text = hir::term_to_string(interner, &value, &no_vars);
            let object = objects.get(text.as_str()).ok_or_else(|| format!("names.json has no object for `{text}`"))?;
            words.push((*object).to_string());
        }
        let time = crate::ir::stn::format_time(timed.time);
        match timed.duration {
            Some(duration) => {
                let _ = writeln!(out, "{time}: ({}) [{}]", words.join(" "), crate::ir::stn::format_time(duration));
            }
            None => {
                let _ = writeln!(out, "{time}: ({})", words.join(" "));
            }
        }
    }
    Ok(out)
}
