//! The built-in predicates the engine implements in Rust (`builtins::Native`), with what they
//! share: lists on the heap, the standard order of terms, and copies of terms kept off the heap
//! (`findall/3`'s solutions, `copy_term/2`).
//!
//! Each follows SWI-Prolog 9's behaviour, errors included (`tests/engine_vs_swipl.rs` holds
//! them against it). A native that has more than one solution leaves a choicepoint whose
//! alternative is a goal for the rest (`between(L+1, H, X)`), so backtracking needs nothing
//! of its own. Every walk over a term is iterative: terms may be as deep as a list is long.

use std::cmp::Ordering;

use rustc_hash::FxHashMap;

use super::{ARG_FROM, Alternative, COLLECT, Cell, Collector, EngineError, LENGTH_FROM, MAX_COLLECTORS, Machine, NIL};
use crate::builtins::Native;
use crate::intern::{Symbol, sym};

/// The standard order's classes: variables, numbers, strings, atoms, compounds (SWI-Prolog 9
/// puts strings before atoms).
fn class(cell: Cell) -> u8 {
    match cell {
        Cell::Ref(_) => 0,
        Cell::Int(_) | Cell::Float(_) => 1,
        Cell::Str(_) => 2,
        Cell::Atom(_) => 3,
        Cell::Struct(_) | Cell::Functor(..) => 4,
    }
}

/// Two numbers in the standard order: by value (as floats when one is a float), and a float
/// before an integer of the same value.
fn compare_numbers(a: Cell, b: Cell) -> Ordering {
    match (a, b) {
        (Cell::Int(x), Cell::Int(y)) => x.cmp(&y),
        (Cell::Float(x), Cell::Float(y)) => x.total_cmp(&y),
        (Cell::Int(x), Cell::Float(y)) => (x as f64).total_cmp(&y).then(Ordering::Greater),
        (Cell::Float(x), Cell::Int(y)) => x.total_cmp(&(y as f64)).then(Ordering::Less),
        _ => Ordering::Equal,
    }
}

impl<'p> Machine<'p> {
    /// Runs `native`, called as `name` with `args`: the next continuation, `None` to backtrack.
    pub(super) fn native(
        &mut self,
        native: Native,
        name: Symbol,
        args: &[Cell],
        cut: u32,
        next: u32,
    ) -> Result<Option<u32>, EngineError> {
        let holds = |yes: bool| Ok(yes.then_some(next));
        let a = args.first().map(|&c| self.deref(c));
        match native {
            Native::Var => holds(matches!(a, Some(Cell::Ref(_)))),
            Native::Nonvar => holds(!matches!(a, Some(Cell::Ref(_)))),
            // `[]` is no atom in SWI-Prolog 7 and later, but a constant of its own.
            Native::Atom => holds(matches!(a, Some(Cell::Atom(s)) if s != sym::NIL)),
            Native::Number => holds(matches!(a, Some(Cell::Int(_) | Cell::Float(_)))),
            Native::Integer => holds(matches!(a, Some(Cell::Int(_)))),
            Native::Float => holds(matches!(a, Some(Cell::Float(_)))),
            Native::Atomic => holds(matches!(a, Some(Cell::Atom(_) | Cell::Int(_) | Cell::Float(_) | Cell::Str(_)))),
            Native::Compound => holds(matches!(a, Some(Cell::Struct(_)))),
            Native::Callable => {
                holds(matches!(a, Some(Cell::Struct(_))) || matches!(a, Some(Cell::Atom(s)) if s != sym::NIL))
            }
            Native::IsList => holds(self.proper_list(args[0]).is_some()),
            Native::Ground => holds(self.is_ground(args[0])),
            Native::Compare => {
                match self.deref(args[0]) {
                    Cell::Ref(_) => {}
                    Cell::Atom(s) if [sym::LT, sym::EQ, sym::GT].contains(&s) => {}
                    Cell::Atom(_) => return Err(self.domain_error("an order: `<`, `=` or `>`", args[0])),
                    _ => return Err(self.type_error("an atom", args[0])),
                }
                let order = match self.compare_terms(args[1], args[2]) {
                    Ordering::Less => sym::LT,
                    Ordering::Equal => sym::EQ,
                    Ordering::Greater => sym::GT,
                };
                holds(self.unify(args[0], Cell::Atom(order)))
            }
            Native::Before => holds(self.compare_terms(args[0], args[1]).is_lt()),
            Native::After => holds(self.compare_terms(args[0], args[1]).is_gt()),
            Native::NotAfter => holds(self.compare_terms(args[0], args[1]).is_le()),
            Native::NotBefore => holds(self.compare_terms(args[0], args[1]).is_ge()),
            Native::Variant => holds(self.variant(args[0], args[1])),
            Native::NotVariant => holds(!self.variant(args[0], args[1])),
            // Identical terms: fails. Terms that cannot unify: holds for good. Otherwise it
            // waits, pending, for bindings that might make them identical.
            Native::Dif => {
                if self.identical(args[0], args[1]) {
                    return holds(false);
                }
                if self.unifiable(args[0], args[1]) {
                    self.difs.push((args[0], args[1]));
                }
                holds(true)
            }
            Native::Functor => self.functor(args, next),
            Native::Arg => self.arg(args, cut, next),
            Native::Univ => self.univ(args, next),
            Native::CopyTerm => {
                let copy = self.copy(args[0]);
                holds(self.unify(args[1], copy))
            }
            Native::TermVariables => {
                let vars = self.term_variables(args[0]);
                let list = self.make_list(&vars, Cell::Atom(sym::NIL));
                holds(self.unify(args[1], list))
            }
            Native::Length => self.length(args, cut, next),
            Native::Between => self.between(name, args, cut, next),
            Native::Succ => self.succ(args, next),
            Native::Plus => self.plus(args, next),
            Native::MustBe => self.must_be(args, next),
            Native::Msort | Native::Sort | Native::Keysort => {
                let mut items = self.list_items(args[0])?;
                if native == Native::Keysort {
                    for &item in &items {
                        match self.deref(item) {
                            Cell::Ref(_) => {
                                return Err(EngineError::Instantiation { context: "a pair of keysort/2".into() });
                            }
                            pair if self.compound(pair).is_some_and(|(f, a)| f == sym::MINUS && a.len() == 2) => {}
                            _ => return Err(self.type_error("a pair `Key-Value`", item)),
                        }
                    }
                    items.sort_by(|&x, &y| self.compare_terms(self.pair_key(x), self.pair_key(y)));
                } else {
                    items.sort_by(|&x, &y| self.compare_terms(x, y));
                    if native == Native::Sort {
                        items.dedup_by(|x, y| self.compare_terms(*x, *y).is_eq());
                    }
                }
                let list = self.make_list(&items, Cell::Atom(sym::NIL));
                holds(self.unify(args[1], list))
            }
            Native::Sort4 => self.sort4(args, next),
            Native::Findall => self.findall(args[0], args[1], args[2], Cell::Atom(sym::NIL), next),
            Native::Findall4 => self.findall(args[0], args[1], args[2], args[3], next),
            Native::Call => {
                let goal = self.add_args(args[0], &args[1..])?;
                let barrier = self.choicepoints.len() as u32;
                Ok(Some(self.push_goal(goal, barrier, next)))
            }
            Native::Caret => {
                let barrier = self.choicepoints.len() as u32;
                Ok(Some(self.push_goal(args[1], barrier, next)))
            }
            Native::Once => Ok(Some(self.if_then_else(args[0], Cell::Atom(sym::TRUE), None, cut, next))),
            Native::Ignore => {
                Ok(Some(self.if_then_else(args[0], Cell::Atom(sym::TRUE), Some(Cell::Atom(sym::TRUE)), cut, next)))
            }
            Native::Output => Ok(Some(next)),
            Native::BagofSplit => self.bagof_split(args, next),
            Native::BagofGroups => {
                let mut pairs = self.list_items(args[0])?;
                pairs.sort_by(|&x, &y| self.compare_terms(self.pair_key(x), self.pair_key(y)));
                let mut groups: Vec<Cell> = Vec::new();
                let mut start = 0;
                while start < pairs.len() {
                    let key = self.pair_key(pairs[start]);
                    let mut end = start + 1;
                    while end < pairs.len() && self.variant(key, self.pair_key(pairs[end])) {
                        end += 1;
                    }
                    let values: Vec<Cell> = pairs[start..end].iter().map(|&p| self.pair_value(p)).collect();
                    let list = self.make_list(&values, Cell::Atom(sym::NIL));
                    groups.push(self.new_compound(sym::MINUS, &[key, list]));
                    start = end;
                }
                let list = self.make_list(&groups, Cell::Atom(sym::NIL));
                holds(self.unify(args[1], list))
            }
        }
    }

    // ---- errors ------------------------------------------------------------------------------

    /// Counts `cells` more steps against the query's budget before a native makes that many
    /// cells at once (`length(L, 1000000000)`), so the budget bounds memory as it bounds time.
    fn charge(&mut self, cells: i64) -> Result<(), EngineError> {
        self.steps = self.steps.saturating_add(cells.max(0) as u64);
        if self.steps > self.budget { Err(EngineError::Budget { steps: self.budget }) } else { Ok(()) }
    }

    fn type_error(&self, expected: &'static str, cell: Cell) -> EngineError {
        EngineError::Type { expected, found: self.read(cell, &mut Vec::new()) }
    }

    fn domain_error(&self, expected: &'static str, cell: Cell) -> EngineError {
        EngineError::Domain { expected, found: self.read(cell, &mut Vec::new()) }
    }

    fn instantiation(context: &str) -> EngineError {
        EngineError::Instantiation { context: context.to_string() }
    }

    /// An integer argument, `None` when it is unbound, a type error otherwise.
    fn integer_or_var(&self, cell: Cell) -> Result<Option<i64>, EngineError> {
        match self.deref(cell) {
            Cell::Int(i) => Ok(Some(i)),
            Cell::Ref(_) => Ok(None),
            _ => Err(self.type_error("an integer", cell)),
        }
    }

    // ---- lists -------------------------------------------------------------------------------

    /// The number of list cells at the front of `cell`, and what follows them (dereferenced).
    fn list_prefix(&self, cell: Cell) -> (i64, Cell) {
        let mut count = 0;
        let mut cell = self.deref(cell);
        while let Some((sym::CONS, [_, tail])) = self.compound(cell) {
            count += 1;
            cell = self.deref(*tail);
        }
        (count, cell)
    }

    /// The items of a proper list, or `None`.
    fn proper_list(&self, cell: Cell) -> Option<Vec<Cell>> {
        let mut items = Vec::new();
        let mut cell = self.deref(cell);
        while let Some((sym::CONS, [item, tail])) = self.compound(cell) {
            items.push(*item);
            cell = self.deref(*tail);
        }
        (cell == Cell::Atom(sym::NIL)).then_some(items)
    }

    /// The items of a list a predicate needs whole: an instantiation error for a partial list,
    /// a type error for anything else.
    fn list_items(&self, cell: Cell) -> Result<Vec<Cell>, EngineError> {
        match self.proper_list(cell) {
            Some(items) => Ok(items),
            None => match self.list_prefix(cell).1 {
                Cell::Ref(_) => Err(Self::instantiation("a list")),
                _ => Err(self.type_error("a list", cell)),
            },
        }
    }

    /// The list of `items` ending in `tail`, built on the heap.
    pub(super) fn make_list(&mut self, items: &[Cell], tail: Cell) -> Cell {
        items.iter().rev().fold(tail, |rest, &item| self.new_compound(sym::CONS, &[item, rest]))
    }

    fn pair_key(&self, cell: Cell) -> Cell {
        self.compound(cell).map_or(cell, |(_, args)| args[0])
    }

    fn pair_value(&self, cell: Cell) -> Cell {
        self.compound(cell).map_or(cell, |(_, args)| args[args.len() - 1])
    }

    // ---- the standard order of terms -----------------------------------------------------------

    /// The standard order of terms: variables (oldest first) before numbers (by value) before
    /// strings before atoms (both by their text) before compounds (by arity, then name, then the
    /// arguments from the left).
    pub(super) fn compare_terms(&self, a: Cell, b: Cell) -> Ordering {
        let mut pending = vec![(a, b)];
        while let Some((a, b)) = pending.pop() {
            let (a, b) = (self.deref(a), self.deref(b));
            let order = class(a).cmp(&class(b)).then_with(|| match (a, b) {
                (Cell::Ref(x), Cell::Ref(y)) => x.cmp(&y),
                // `[]` comes before every atom.
                (Cell::Atom(x), Cell::Atom(y)) => {
                    (x != sym::NIL).cmp(&(y != sym::NIL)).then_with(|| self.program.rank(x).cmp(&self.program.rank(y)))
                }
                (Cell::Str(x), Cell::Str(y)) => self.program.rank(x).cmp(&self.program.rank(y)),
                (Cell::Struct(_), Cell::Struct(_)) => {
                    let (Some((f, xs)), Some((g, ys))) = (self.compound(a), self.compound(b)) else {
                        return Ordering::Equal;
                    };
                    let order = xs.len().cmp(&ys.len()).then_with(|| self.program.rank(f).cmp(&self.program.rank(g)));
                    if order.is_eq() {
                        pending.extend(xs.iter().copied().zip(ys.iter().copied()).rev());
                    }
                    order
                }
                (x, y) => compare_numbers(x, y),
            });
            if order.is_ne() {
                return order;
            }
        }
        Ordering::Equal
    }

    /// Whether two terms are variants: equal up to a one-to-one renaming of their variables.
    fn variant(&self, a: Cell, b: Cell) -> bool {
        let mut forward: FxHashMap<u32, u32> = FxHashMap::default();
        let mut backward: FxHashMap<u32, u32> = FxHashMap::default();
        let mut pending = vec![(a, b)];
        while let Some((a, b)) = pending.pop() {
            match (self.deref(a), self.deref(b)) {
                (Cell::Ref(x), Cell::Ref(y)) => {
                    if *forward.entry(x).or_insert(y) != y || *backward.entry(y).or_insert(x) != x {
                        return false;
                    }
                }
                (x @ Cell::Struct(_), y @ Cell::Struct(_)) => {
                    let (Some((f, xs)), Some((g, ys))) = (self.compound(x), self.compound(y)) else { return false };
                    if f != g || xs.len() != ys.len() {
                        return false;
                    }
                    pending.extend(xs.iter().copied().zip(ys.iter().copied()));
                }
                (Cell::Float(x), Cell::Float(y)) => {
                    if x.to_bits() != y.to_bits() {
                        return false;
                    }
                }
                (x, y) => {
                    if x != y || matches!(x, Cell::Ref(_)) {
                        return false;
                    }
                }
            }
        }
        true
    }

    fn is_ground(&self, cell: Cell) -> bool {
        let mut pending = vec![cell];
        while let Some(cell) = pending.pop() {
            match self.deref(cell) {
                Cell::Ref(_) => return false,
                c @ Cell::Struct(_) => pending.extend(self.compound(c).map_or(&[][..], |(_, args)| args)),
                _ => {}
            }
        }
        true
    }

    /// The variables of a term, each once, in depth-first, left-to-right order.
    fn term_variables(&self, cell: Cell) -> Vec<Cell> {
        let mut vars = Vec::new();
        let mut seen: rustc_hash::FxHashSet<u32> = rustc_hash::FxHashSet::default();
        let mut pending = vec![cell];
        while let Some(cell) = pending.pop() {
            match self.deref(cell) {
                v @ Cell::Ref(at) if seen.insert(at) => vars.push(v),
                c @ Cell::Struct(_) => {
                    pending.extend(self.compound(c).map_or(&[][..], |(_, args)| args).iter().rev());
                }
                _ => {}
            }
        }
        vars
    }

    // ---- copies off the heap -------------------------------------------------------------------

    /// Copies `cell` to the end of `out` with its own variables, as cells that refer to each
    /// other by their index in `out`; returns the copy's root.
    fn freeze(&self, cell: Cell, out: &mut Vec<Cell>) -> Cell {
        let mut vars: FxHashMap<u32, u32> = FxHashMap::default();
        let mut pending: Vec<(usize, Cell)> = Vec::new();
        let root = self.freeze_cell(cell, out, &mut vars, &mut pending);
        while let Some((slot, cell)) = pending.pop() {
            out[slot] = self.freeze_cell(cell, out, &mut vars, &mut pending);
        }
        root
    }

    fn freeze_cell(
        &self,
        cell: Cell,
        out: &mut Vec<Cell>,
        vars: &mut FxHashMap<u32, u32>,
        pending: &mut Vec<(usize, Cell)>,
    ) -> Cell {
        match self.deref(cell) {
            Cell::Ref(v) => {
                let at = *vars.entry(v).or_insert_with(|| {
                    out.push(Cell::Ref(out.len() as u32));
                    out.len() as u32 - 1
                });
                Cell::Ref(at)
            }
            Cell::Struct(x) => {
                let Cell::Functor(f, n) = self.heap[x as usize] else { return Cell::Atom(sym::NIL) };
                let at = out.len();
                out.push(Cell::Functor(f, n));
                for i in 1..=n as usize {
                    out.push(Cell::Atom(sym::NIL));
                    pending.push((at + i, self.heap[x as usize + i]));
                }
                Cell::Struct(at as u32)
            }
            other => other,
        }
    }

    /// Places frozen copies on the heap; returns their roots.
    pub(super) fn thaw(&mut self, collector: &Collector) -> Vec<Cell> {
        let offset = self.heap.len() as u32;
        self.heap.extend(collector.cells.iter().map(|&c| super::relocate(c, offset)));
        collector.roots.iter().map(|&c| super::relocate(c, offset)).collect()
    }

    /// A copy of `cell` on the heap, with fresh variables.
    fn copy(&mut self, cell: Cell) -> Cell {
        let mut collector = Collector::default();
        let root = self.freeze(cell, &mut collector.cells);
        collector.roots.push(root);
        self.thaw(&collector)[0]
    }

    /// Copies `template` into the collector of `findall/3` call `frame`.
    pub(super) fn collect(&mut self, frame: usize, template: Cell) {
        let Some(mut collector) = self.collectors.get_mut(frame).map(std::mem::take) else { return };
        let root = self.freeze(template, &mut collector.cells);
        collector.roots.push(root);
        self.collectors[frame] = collector;
    }

    /// `findall(Template, Goal, List, Tail)`: `Goal` runs to its last solution behind a cut
    /// barrier, each solution's template copied into a collector of its own; the choicepoint
    /// below it then makes the list (see `Alternative::Collected`).
    fn findall(
        &mut self,
        template: Cell,
        goal: Cell,
        list: Cell,
        tail: Cell,
        next: u32,
    ) -> Result<Option<u32>, EngineError> {
        if self.collectors.len() >= MAX_COLLECTORS {
            return Err(EngineError::Nesting);
        }
        let frame = self.collectors.len() as u32;
        self.collectors.push(Collector::default());
        self.push_choicepoint(Alternative::Collected { frame, list, tail }, next);
        let marker = self.new_compound(COLLECT, &[Cell::Int(frame as i64), template]);
        let barrier = self.choicepoints.len() as u32;
        let collect = self.push_goal(marker, barrier, NIL);
        Ok(Some(self.push_goal(goal, barrier, collect)))
    }

    /// A goal with `extra` arguments appended (`call/N`).
    fn add_args(&mut self, goal: Cell, extra: &[Cell]) -> Result<Cell, EngineError> {
        // `Module:Closure` (kbc has no modules): the closure, with the arguments added.
        if !extra.is_empty()
            && let Some((sym::COLON, &[module, closure])) = self.compound(goal)
            && matches!(self.deref(module), Cell::Atom(_))
        {
            return self.add_args(closure, extra);
        }
        match self.deref(goal) {
            g if extra.is_empty() => Ok(g),
            Cell::Atom(f) => Ok(self.new_compound(f, extra)),
            c @ Cell::Struct(_) => {
                let (f, args) = self.compound(c).expect("a struct cell points at a functor");
                let mut all = args.to_vec();
                all.extend_from_slice(extra);
                Ok(self.new_compound(f, &all))
            }
            Cell::Ref(_) => Err(Self::instantiation("the goal of call/N")),
            _ => Err(self.type_error("a callable term", goal)),
        }
    }

    /// `'$bagof_split'(Template^Goal, Stripped, Witness)`: the goal without its `V^` marks,
    /// and the list of its variables neither in the template nor marked (bagof/3's witness).
    fn bagof_split(&mut self, args: &[Cell], next: u32) -> Result<Option<u32>, EngineError> {
        let split = |machine: &Self, cell: Cell| -> Option<(Cell, Cell)> {
            match machine.compound(cell) {
                Some((sym::CARET, &[left, right])) => Some((left, right)),
                _ => None,
            }
        };
        let Some((template, mut goal)) = split(self, args[0]) else {
            return Err(self.type_error("`Template^Goal`", args[0]));
        };
        let mut bound = self.term_variables(template);
        while let Some((marked, inner)) = split(self, goal) {
            bound.extend(self.term_variables(marked));
            goal = inner;
        }
        let witness: Vec<Cell> = self.term_variables(goal).into_iter().filter(|v| !bound.contains(v)).collect();
        let list = self.make_list(&witness, Cell::Atom(sym::NIL));
        Ok((self.unify(args[1], goal) && self.unify(args[2], list)).then_some(next))
    }

    // ---- terms ---------------------------------------------------------------------------------

    fn functor(&mut self, args: &[Cell], next: u32) -> Result<Option<u32>, EngineError> {
        let term = self.deref(args[0]);
        match term {
            Cell::Ref(_) => {
                let name = self.deref(args[1]);
                let Some(arity) = self.integer_or_var(args[2])? else { return Err(Self::instantiation("functor/3")) };
                if matches!(name, Cell::Ref(_)) {
                    return Err(Self::instantiation("functor/3"));
                }
                if arity < 0 {
                    return Err(self.domain_error("a non-negative integer", args[2]));
                }
                if arity == 0 {
                    if matches!(name, Cell::Struct(_)) {
                        return Err(self.type_error("an atomic term", args[1]));
                    }
                    return Ok(self.unify(args[0], name).then_some(next));
                }
                let Cell::Atom(f) = name else {
                    return Err(self.type_error(
                        if matches!(name, Cell::Struct(_)) { "an atomic term" } else { "an atom" },
                        args[1],
                    ));
                };
                let arity = u32::try_from(arity).map_err(|_| self.domain_error("a smaller arity", args[2]))?;
                self.charge(arity as i64)?;
                let vars: Vec<Cell> = (0..arity).map(|_| self.new_var()).collect();
                let made = self.new_compound(f, &vars);
                Ok(self.unify(args[0], made).then_some(next))
            }
            Cell::Struct(_) => {
                let (f, term_args) = self.compound(term).expect("a struct cell points at a functor");
                let arity = term_args.len() as i64;
                Ok((self.unify(args[1], Cell::Atom(f)) && self.unify(args[2], Cell::Int(arity))).then_some(next))
            }
            atomic => Ok((self.unify(args[1], atomic) && self.unify(args[2], Cell::Int(0))).then_some(next)),
        }
    }

    fn arg(&mut self, args: &[Cell], cut: u32, next: u32) -> Result<Option<u32>, EngineError> {
        let term = self.deref(args[1]);
        let Some((_, term_args)) = self.compound(term) else {
            return Err(match term {
                Cell::Ref(_) => Self::instantiation("arg/3"),
                _ => self.type_error("a compound", args[1]),
            });
        };
        let arity = term_args.len() as i64;
        match self.integer_or_var(args[0])? {
            Some(n) if (1..=arity).contains(&n) => {
                let value = term_args[n as usize - 1];
                Ok(self.unify(args[2], value).then_some(next))
            }
            Some(_) => Ok(None),
            None => self.arg_from(&[Cell::Int(1), args[0], args[1], args[2]], cut, next),
        }
    }

    /// `ARG_FROM(K, N, Term, Arg)`: position K, leaving the positions after it to backtracking.
    pub(super) fn arg_from(&mut self, args: &[Cell], cut: u32, next: u32) -> Result<Option<u32>, EngineError> {
        let (Cell::Int(k), Some((_, term_args))) = (self.deref(args[0]), self.compound(args[2])) else {
            return Ok(None);
        };
        let arity = term_args.len() as i64;
        if k > arity {
            return Ok(None);
        }
        let value = term_args[k as usize - 1];
        if k < arity {
            let again = self.new_compound(ARG_FROM, &[Cell::Int(k + 1), args[1], args[2], args[3]]);
            self.push_choicepoint(Alternative::Goal { goal: again, cut }, next);
        }
        Ok((self.unify(args[1], Cell::Int(k)) && self.unify(args[3], value)).then_some(next))
    }

    fn univ(&mut self, args: &[Cell], next: u32) -> Result<Option<u32>, EngineError> {
        let term = self.deref(args[0]);
        let list = match term {
            Cell::Ref(_) => {
                let items = self.list_items(args[1])?;
                let Some(&head) = items.first() else {
                    return Err(self.domain_error("a non-empty list", args[1]));
                };
                let made = match self.deref(head) {
                    Cell::Ref(_) => return Err(Self::instantiation("=../2")),
                    h if items.len() == 1 => {
                        if matches!(h, Cell::Struct(_)) {
                            return Err(self.type_error("an atomic term", head));
                        }
                        h
                    }
                    Cell::Atom(f) => self.new_compound(f, &items[1..]),
                    _ => return Err(self.type_error("an atom", head)),
                };
                return Ok(self.unify(args[0], made).then_some(next));
            }
            Cell::Struct(_) => {
                let (f, term_args) = self.compound(term).expect("a struct cell points at a functor");
                let mut items = vec![Cell::Atom(f)];
                items.extend_from_slice(term_args);
                self.make_list(&items, Cell::Atom(sym::NIL))
            }
            atomic => self.make_list(&[atomic], Cell::Atom(sym::NIL)),
        };
        Ok(self.unify(args[1], list).then_some(next))
    }

    // ---- numbers and lists ---------------------------------------------------------------------

    fn between(&mut self, name: Symbol, args: &[Cell], cut: u32, next: u32) -> Result<Option<u32>, EngineError> {
        let Some(low) = self.integer_or_var(args[0])? else { return Err(Self::instantiation("between/3")) };
        let high = match self.deref(args[1]) {
            Cell::Int(i) => Some(i),
            Cell::Atom(s) if s == sym::INF || Some(s) == self.program.infinite => None,
            Cell::Ref(_) => return Err(Self::instantiation("between/3")),
            _ => return Err(self.type_error("an integer", args[1])),
        };
        match self.integer_or_var(args[2])? {
            Some(x) => Ok((x >= low && high.is_none_or(|h| x <= h)).then_some(next)),
            None => {
                if high.is_some_and(|h| low > h) {
                    return Ok(None);
                }
                if high != Some(low) && low < i64::MAX {
                    let again = self.new_compound(name, &[Cell::Int(low + 1), args[1], args[2]]);
                    self.push_choicepoint(Alternative::Goal { goal: again, cut }, next);
                }
                Ok(self.unify(args[2], Cell::Int(low)).then_some(next))
            }
        }
    }

    fn succ(&mut self, args: &[Cell], next: u32) -> Result<Option<u32>, EngineError> {
        let natural = |machine: &Self, cell: Cell| -> Result<Option<i64>, EngineError> {
            match machine.integer_or_var(cell)? {
                Some(i) if i < 0 => Err(machine.domain_error("a non-negative integer", cell)),
                other => Ok(other),
            }
        };
        match (natural(self, args[0])?, natural(self, args[1])?) {
            (Some(x), _) => {
                let y = x.checked_add(1).ok_or_else(|| EngineError::Evaluation {
                    message: "the result does not fit in a 64-bit integer".to_string(),
                })?;
                Ok(self.unify(args[1], Cell::Int(y)).then_some(next))
            }
            (None, Some(0)) => Ok(None),
            (None, Some(y)) => Ok(self.unify(args[0], Cell::Int(y - 1)).then_some(next)),
            (None, None) => Err(Self::instantiation("succ/2")),
        }
    }

    fn plus(&mut self, args: &[Cell], next: u32) -> Result<Option<u32>, EngineError> {
        let overflow =
            || EngineError::Evaluation { message: "the result does not fit in a 64-bit integer".to_string() };
        let values = [self.integer_or_var(args[0])?, self.integer_or_var(args[1])?, self.integer_or_var(args[2])?];
        let (at, value) = match values {
            [Some(x), Some(y), _] => (2, x.checked_add(y).ok_or_else(overflow)?),
            [Some(x), None, Some(z)] => (1, z.checked_sub(x).ok_or_else(overflow)?),
            [None, Some(y), Some(z)] => (0, z.checked_sub(y).ok_or_else(overflow)?),
            _ => return Err(Self::instantiation("plus/3")),
        };
        Ok(self.unify(args[at], Cell::Int(value)).then_some(next))
    }

    fn length(&mut self, args: &[Cell], cut: u32, next: u32) -> Result<Option<u32>, EngineError> {
        let (count, tail) = self.list_prefix(args[0]);
        let wanted = self.integer_or_var(args[1])?;
        match tail {
            Cell::Atom(sym::NIL) => Ok(match wanted {
                Some(n) => (n == count).then_some(next),
                None => self.unify(args[1], Cell::Int(count)).then_some(next),
            }),
            Cell::Ref(_) => match wanted {
                Some(n) if n < 0 => Err(self.domain_error("a non-negative integer", args[1])),
                Some(n) if n < count => Ok(None),
                Some(n) => {
                    self.charge(n - count)?;
                    let items: Vec<Cell> = (count..n).map(|_| self.new_var()).collect();
                    let list = self.make_list(&items, Cell::Atom(sym::NIL));
                    Ok(self.unify(tail, list).then_some(next))
                }
                None => self.length_from(&[tail, Cell::Int(count), args[1]], cut, next),
            },
            _ => Err(self.type_error("a list", args[0])),
        }
    }

    /// `LENGTH_FROM(Tail, K, N)`: the open tail ends here, length K; backtracking adds a cell.
    pub(super) fn length_from(&mut self, args: &[Cell], cut: u32, next: u32) -> Result<Option<u32>, EngineError> {
        let Cell::Int(k) = self.deref(args[1]) else { return Ok(None) };
        let (item, rest) = (self.new_var(), self.new_var());
        let cons = self.new_compound(sym::CONS, &[item, rest]);
        let extend = self.new_compound(sym::EQ, &[args[0], cons]);
        let more = self.new_compound(LENGTH_FROM, &[rest, Cell::Int(k + 1), args[2]]);
        let again = self.new_compound(sym::COMMA, &[extend, more]);
        self.push_choicepoint(Alternative::Goal { goal: again, cut }, next);
        Ok((self.unify(args[0], Cell::Atom(sym::NIL)) && self.unify(args[2], Cell::Int(k))).then_some(next))
    }

    /// `sort(Key, Order, List, Sorted)`: on the whole elements (Key 0) or their argument Key,
    /// ascending (`@<`, `@=<`) or descending (`@>`, `@>=`), stably; the strict orders keep the
    /// first of the elements with equal keys.
    fn sort4(&mut self, args: &[Cell], next: u32) -> Result<Option<u32>, EngineError> {
        let Some(key) = self.integer_or_var(args[0])? else { return Err(Self::instantiation("sort/4")) };
        if key < 0 {
            return Err(self.domain_error("a non-negative integer", args[0]));
        }
        let (descending, strict) = match self.deref(args[1]) {
            Cell::Atom(sym::AT_LT) => (false, true),
            Cell::Atom(sym::AT_LE) => (false, false),
            Cell::Atom(sym::AT_GT) => (true, true),
            Cell::Atom(sym::AT_GE) => (true, false),
            Cell::Ref(_) => return Err(Self::instantiation("sort/4")),
            _ => return Err(self.domain_error("an order: `@<`, `@=<`, `@>` or `@>=`", args[1])),
        };
        let items = self.list_items(args[2])?;
        let mut keyed: Vec<(Cell, Cell)> = Vec::with_capacity(items.len());
        for item in items {
            let k = if key == 0 {
                item
            } else {
                match self.compound(item) {
                    Some((_, a)) if a.len() as i64 >= key => a[key as usize - 1],
                    _ => return Err(self.type_error("a compound with enough arguments", item)),
                }
            };
            keyed.push((k, item));
        }
        keyed.sort_by(|x, y| {
            let order = self.compare_terms(x.0, y.0);
            if descending { order.reverse() } else { order }
        });
        if strict {
            keyed.dedup_by(|x, y| self.compare_terms(x.0, y.0).is_eq());
        }
        let items: Vec<Cell> = keyed.into_iter().map(|(_, item)| item).collect();
        let list = self.make_list(&items, Cell::Atom(sym::NIL));
        Ok(self.unify(args[3], list).then_some(next))
    }

    /// `must_be(Type, Value)`, for the types of SWI-Prolog's library(error) a KB is likely to
    /// name.
    fn must_be(&mut self, args: &[Cell], next: u32) -> Result<Option<u32>, EngineError> {
        let ty = self.deref(args[0]);
        let value = self.deref(args[1]);
        let Some((name, ty_args)) = (match ty {
            Cell::Atom(s) => Some((s, &[][..])),
            Cell::Struct(_) => self.compound(ty),
            _ => None,
        }) else {
            return Err(match ty {
                Cell::Ref(_) => Self::instantiation("must_be/2"),
                _ => self.domain_error("a type that must_be/2 knows", args[0]),
            });
        };
        let Some(&kind) = self.program.types.get(&(name, ty_args.len() as u32)) else {
            return Err(self.domain_error("a type that must_be/2 knows", args[0]));
        };
        let ty_args = ty_args.to_vec();
        use super::TypeName as T;
        if kind == T::Var {
            return if matches!(value, Cell::Ref(_)) {
                Ok(Some(next))
            } else {
                Err(self.type_error("a variable", value))
            };
        }
        if kind == T::List {
            return self.list_items(value).map(|_| Some(next));
        }
        if kind == T::Ground {
            return if self.is_ground(value) { Ok(Some(next)) } else { Err(Self::instantiation("must_be/2")) };
        }
        if matches!(value, Cell::Ref(_)) {
            return Err(Self::instantiation("must_be/2"));
        }
        let fits = match kind {
            T::Integer => matches!(value, Cell::Int(_)),
            T::PositiveInteger | T::Nonneg => {
                let Cell::Int(i) = value else { return Err(self.type_error("an integer", value)) };
                if (kind == T::PositiveInteger && i <= 0) || (kind == T::Nonneg && i < 0) {
                    let expected =
                        if kind == T::PositiveInteger { "a positive integer" } else { "a non-negative integer" };
                    return Err(self.type_error(expected, value));
                }
                true
            }
            T::Atom => matches!(value, Cell::Atom(s) if s != sym::NIL),
            T::Atomic => matches!(value, Cell::Atom(_) | Cell::Int(_) | Cell::Float(_) | Cell::Str(_)),
            T::Callable => matches!(value, Cell::Struct(_)) || matches!(value, Cell::Atom(s) if s != sym::NIL),
            T::Number => matches!(value, Cell::Int(_) | Cell::Float(_)),
            T::Float => matches!(value, Cell::Float(_)),
            T::Compound => matches!(value, Cell::Struct(_)),
            T::Boolean => matches!(value, Cell::Atom(sym::TRUE) | Cell::Atom(sym::FALSE)),
            T::OneOf => {
                let options = self.list_items(ty_args[0])?;
                if options.iter().any(|&o| self.compare_terms(o, value).is_eq()) {
                    return Ok(Some(next));
                }
                return Err(self.type_error("one of the values listed", value));
            }
            T::Var | T::List | T::Ground => true,
        };
        if fits {
            Ok(Some(next))
        } else {
            let expected = match kind {
                T::Integer => "an integer",
                T::Atom => "an atom",
                T::Atomic => "an atomic term",
                T::Callable => "a callable term",
                T::Number => "a number",
                T::Float => "a float",
                T::Compound => "a compound",
                _ => "a boolean",
            };
            Err(self.type_error(expected, value))
        }
    }
}
