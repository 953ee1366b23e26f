//! Unification of HIR terms from two different items (each with its own variables).
//!
//! The front end asks questions such as "can some effect of some action ever produce this
//! goal literal?", which is unifiability of two terms whose variables belong to different
//! clauses. The right-hand term's variables are renamed apart before unifying. The resolution
//! engine of the planner has its own, faster machinery; this one favours clarity.

use rustc_hash::FxHashMap;

use super::hir::{Term, VarId};

/// True if `a` and `b` unify, treating their variables as distinct even when ids coincide.
pub fn unifiable(a: &Term, b: &Term) -> bool {
    if clash(a, b) {
        return false;
    }
    let offset = max_var(a).map_or(0, |v| v.0 + 1);
    let b = b.shift_vars(offset);
    let mut bindings = FxHashMap::default();
    unify(a, &b, &mut bindings)
}

/// True if `a` and `b` differ where neither has a variable (a functor, an arity or a
/// constant), so that no bindings can make them equal. It allocates nothing, which makes it
/// the cheap first test of [`unifiable`]: most pairs asked about differ at their functor.
pub fn clash(a: &Term, b: &Term) -> bool {
    match (a, b) {
        (Term::Var(_), _) | (_, Term::Var(_)) => false,
        (Term::Compound(f, xs), Term::Compound(g, ys)) => {
            f != g || xs.len() != ys.len() || xs.iter().zip(ys.iter()).any(|(x, y)| clash(x, y))
        }
        (Term::Float(x), Term::Float(y)) => x.to_bits() != y.to_bits(),
        (x, y) => x != y,
    }
}

/// The bindings that make `pattern` equal to the ground term `ground`, if any.
pub fn match_ground(pattern: &Term, ground: &Term) -> Option<FxHashMap<VarId, Term>> {
    let mut bindings = FxHashMap::default();
    unify(pattern, ground, &mut bindings).then_some(bindings)
}

/// Unifies `a` and `b` (their variables shared: one numbering), extending `bindings`; on
/// failure `bindings` may hold part of the attempt, so callers unify on a copy.
pub fn unify_in(a: &Term, b: &Term, bindings: &mut FxHashMap<VarId, Term>) -> bool {
    unify(a, b, bindings)
}

/// `t` with every bound variable replaced by its value, through chains of bindings.
pub fn substitute(t: &Term, bindings: &FxHashMap<VarId, Term>) -> Term {
    match resolve(t, bindings) {
        Term::Compound(f, args) => Term::Compound(*f, args.iter().map(|a| substitute(a, bindings)).collect()),
        other => other.clone(),
    }
}

fn max_var(t: &Term) -> Option<VarId> {
    let mut max = None;
    t.for_each_var(&mut |v| {
        if max.is_none_or(|m: VarId| v > m) {
            max = Some(v);
        }
    });
    max
}

fn resolve<'a>(mut t: &'a Term, bindings: &'a FxHashMap<VarId, Term>) -> &'a Term {
    while let Term::Var(v) = t {
        match bindings.get(v) {
            Some(bound) => t = bound,
            None => break,
        }
    }
    t
}

fn occurs(v: VarId, t: &Term, bindings: &FxHashMap<VarId, Term>) -> bool {
    match resolve(t, bindings) {
        Term::Var(w) => *w == v,
        Term::Compound(_, args) => args.iter().any(|a| occurs(v, a, bindings)),
        _ => false,
    }
}

fn unify(a: &Term, b: &Term, bindings: &mut FxHashMap<VarId, Term>) -> bool {
    let a = resolve(a, bindings).clone();
    let b = resolve(b, bindings).clone();
    match (&a, &b) {
        (Term::Var(x), Term::Var(y)) if x == y => true,
        (Term::Var(x), other) | (other, Term::Var(x)) => {
            if occurs(*x, other, bindings) {
                return false;
            }
            bindings.insert(*x, other.clone());
            true
        }
        (Term::Compound(f, xs), Term::Compound(g, ys)) => {
            f == g && xs.len() == ys.len() && xs.iter().zip(ys.iter()).all(|(x, y)| unify(x, y, bindings))
        }
        (Term::Float(x), Term::Float(y)) => x.to_bits() == y.to_bits(),
        (x, y) => x == y,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::intern::Symbol;

    fn c(f: u32, args: Vec<Term>) -> Term {
        Term::Compound(Symbol(f), args.into())
    }
    fn v(i: u32) -> Term {
        Term::Var(VarId(i))
    }
    fn a(i: u32) -> Term {
        Term::Atom(Symbol(i))
    }

    #[test]
    fn variables_of_the_two_sides_are_distinct() {
        // p(X, b) against p(a, X): the X on each side is a different variable.
        assert!(unifiable(&c(100, vec![v(0), a(2)]), &c(100, vec![a(1), v(0)])));
    }

    #[test]
    fn repeated_variables_constrain() {
        // p(X, X) does not unify with p(a, b).
        assert!(!unifiable(&c(100, vec![v(0), v(0)]), &c(100, vec![a(1), a(2)])));
        assert!(unifiable(&c(100, vec![v(0), v(0)]), &c(100, vec![a(1), a(1)])));
    }

    #[test]
    fn functor_and_arity_must_agree() {
        assert!(!unifiable(&c(100, vec![v(0)]), &c(101, vec![v(0)])));
        assert!(!unifiable(&c(100, vec![v(0)]), &c(100, vec![v(0), v(1)])));
        assert!(!unifiable(&Term::Int(1), &Term::Float(1.0)));
    }

    /// Every term of depth at most 2 over a small vocabulary (two atoms, an integer, two
    /// variables, a functor of arity one and one of arity two).
    fn small_terms() -> Vec<Term> {
        let leaves = vec![a(1), a(2), Term::Int(1), v(0), v(1)];
        let mut terms = leaves.clone();
        for x in &leaves {
            terms.push(c(100, vec![x.clone()]));
            for y in &leaves {
                terms.push(c(101, vec![x.clone(), y.clone()]));
            }
        }
        terms
    }

    #[test]
    fn the_quick_clash_test_agrees_with_unification() {
        // Against full unification (without the quick test): a clash is never found where the
        // terms unify, and it is found for most pairs that do not.
        let terms = small_terms();
        let (mut clashes, mut apart) = (0, 0);
        for x in &terms {
            for y in &terms {
                let offset = max_var(x).map_or(0, |v| v.0 + 1);
                let unifies = unify(x, &y.shift_vars(offset), &mut FxHashMap::default());
                assert_eq!(unifiable(x, y), unifies, "{x:?} and {y:?}");
                if clash(x, y) {
                    assert!(!unifies, "{x:?} and {y:?} unify but were said to clash");
                    clashes += 1;
                }
                apart += usize::from(!unifies);
            }
        }
        assert!(clashes * 10 >= apart * 9, "{clashes} clashes of {apart} pairs that do not unify");
    }

    #[test]
    fn occurs_check_rejects_cyclic_bindings() {
        // X against f(X) on the same side cannot unify.
        let left = c(100, vec![v(0), v(0)]);
        let right = c(100, vec![v(1), c(101, vec![v(1)])]);
        assert!(!unifiable(&left, &right));
    }
}
