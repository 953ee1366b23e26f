//! Arithmetic for `is/2` and the comparisons, with SWI-Prolog's default semantics.
//!
//! Integers are 64-bit: where SWI-Prolog would move to big integers, kbc reports an overflow
//! instead of guessing. `/` on two integers gives an integer when the division is exact and a
//! float otherwise; `//` truncates towards zero; `mod` takes the sign of the divisor.

use std::cmp::Ordering;

use super::{Cell, EngineError, Machine};
use crate::intern::sym;
use crate::ir::hir::Term;

/// A number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Number {
    Int(i64),
    Float(f64),
}

impl Number {
    pub(super) fn cell(self) -> Cell {
        match self {
            Number::Int(i) => Cell::Int(i),
            Number::Float(f) => Cell::Float(f),
        }
    }

    fn as_float(self) -> f64 {
        match self {
            Number::Int(i) => i as f64,
            Number::Float(f) => f,
        }
    }

    /// Numeric comparison, integers and floats together (`1 =:= 1.0`).
    pub(super) fn compare(self, other: Number) -> Ordering {
        match (self, other) {
            (Number::Int(a), Number::Int(b)) => a.cmp(&b),
            (a, b) => a.as_float().partial_cmp(&b.as_float()).unwrap_or(Ordering::Equal),
        }
    }
}

fn overflow() -> EngineError {
    EngineError::Evaluation { message: "the result does not fit in a 64-bit integer".to_string() }
}

fn float(value: f64) -> Result<Number, EngineError> {
    if value.is_finite() {
        Ok(Number::Float(value))
    } else {
        Err(EngineError::Evaluation { message: format!("the result is not a finite number ({value})") })
    }
}

/// What an integer-only operator expects, for its type error.
fn integer_operand(name: &str) -> &'static str {
    if name == "mod" { "an integer operand of `mod`" } else { "an integer operand of `//`" }
}

fn integer_only(name: &str, n: Number) -> Result<i64, EngineError> {
    match n {
        Number::Int(i) => Ok(i),
        Number::Float(f) => Err(EngineError::Type { expected: integer_operand(name), found: Term::Float(f) }),
    }
}

/// Evaluates an arithmetic expression.
pub(super) fn eval(machine: &Machine<'_>, cell: Cell) -> Result<Number, EngineError> {
    match machine.deref(cell) {
        Cell::Int(i) => Ok(Number::Int(i)),
        Cell::Float(f) => Ok(Number::Float(f)),
        Cell::Ref(_) => Err(EngineError::Instantiation { context: "arithmetic".to_string() }),
        Cell::Atom(_) | Cell::Str(_) | Cell::Functor(..) => {
            Err(EngineError::Type { expected: "a number", found: machine.read(cell, &mut Vec::new()) })
        }
        Cell::Struct(_) => {
            let (name, args) = machine.compound(cell).expect("a struct cell points at a functor");
            match (name, args) {
                (sym::MINUS, [a]) => match eval(machine, *a)? {
                    Number::Int(i) => i.checked_neg().map(Number::Int).ok_or_else(overflow),
                    Number::Float(f) => Ok(Number::Float(-f)),
                },
                (sym::PLUS, [a]) => eval(machine, *a),
                (sym::ABS, [a]) => match eval(machine, *a)? {
                    Number::Int(i) => i.checked_abs().map(Number::Int).ok_or_else(overflow),
                    Number::Float(f) => Ok(Number::Float(f.abs())),
                },
                (
                    sym::PLUS | sym::MINUS | sym::STAR | sym::SLASH | sym::INT_DIV | sym::MOD | sym::MIN | sym::MAX,
                    [a, b],
                ) => {
                    let a = eval(machine, *a)?;
                    let b = eval(machine, *b)?;
                    binary(name, a, b)
                }
                _ => Err(EngineError::Type {
                    expected: "an arithmetic function",
                    found: machine.read(cell, &mut Vec::new()),
                }),
            }
        }
    }
}

fn binary(name: crate::intern::Symbol, a: Number, b: Number) -> Result<Number, EngineError> {
    use Number::{Float, Int};
    match name {
        sym::PLUS => match (a, b) {
            (Int(x), Int(y)) => x.checked_add(y).map(Int).ok_or_else(overflow),
            _ => float(a.as_float() + b.as_float()),
        },
        sym::MINUS => match (a, b) {
            (Int(x), Int(y)) => x.checked_sub(y).map(Int).ok_or_else(overflow),
            _ => float(a.as_float() - b.as_float()),
        },
        sym::STAR => match (a, b) {
            (Int(x), Int(y)) => x.checked_mul(y).map(Int).ok_or_else(overflow),
            _ => float(a.as_float() * b.as_float()),
        },
        sym::SLASH => match (a, b) {
            (_, Int(0)) => Err(EngineError::ZeroDivisor),
            (Int(x), Int(y)) if x.checked_rem(y) == Some(0) => x.checked_div(y).map(Int).ok_or_else(overflow),
            _ if b.as_float() == 0.0 => Err(EngineError::ZeroDivisor),
            _ => float(a.as_float() / b.as_float()),
        },
        sym::INT_DIV => {
            let (x, y) = (integer_only("//", a)?, integer_only("//", b)?);
            if y == 0 {
                return Err(EngineError::ZeroDivisor);
            }
            x.checked_div(y).map(Int).ok_or_else(overflow)
        }
        sym::MOD => {
            let (x, y) = (integer_only("mod", a)?, integer_only("mod", b)?);
            if y == 0 {
                return Err(EngineError::ZeroDivisor);
            }
            // The result takes the sign of the divisor.
            x.checked_rem_euclid(y).map(|r| if y < 0 && r != 0 { r + y } else { r }).map(Int).ok_or_else(overflow)
        }
        // On a tie between an integer and a float, SWI-Prolog returns the float.
        sym::MIN => Ok(match b.compare(a) {
            Ordering::Less => b,
            Ordering::Equal if matches!(b, Float(_)) => b,
            _ => a,
        }),
        _ => Ok(match b.compare(a) {
            Ordering::Greater => b,
            Ordering::Equal if matches!(b, Float(_)) => b,
            _ => a,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ints(name: crate::intern::Symbol, a: i64, b: i64) -> Result<Number, EngineError> {
        binary(name, Number::Int(a), Number::Int(b))
    }

    #[test]
    fn division_follows_swi_prolog() {
        assert_eq!(ints(sym::SLASH, 6, 3), Ok(Number::Int(2)));
        assert_eq!(ints(sym::SLASH, 7, 2), Ok(Number::Float(3.5)));
        assert_eq!(ints(sym::SLASH, -7, 2), Ok(Number::Float(-3.5)));
        assert_eq!(ints(sym::INT_DIV, -7, 2), Ok(Number::Int(-3)));
        assert_eq!(ints(sym::SLASH, 1, 0), Err(EngineError::ZeroDivisor));
    }

    #[test]
    fn mod_takes_the_sign_of_the_divisor() {
        assert_eq!(ints(sym::MOD, 7, 2), Ok(Number::Int(1)));
        assert_eq!(ints(sym::MOD, -7, 2), Ok(Number::Int(1)));
        assert_eq!(ints(sym::MOD, 7, -2), Ok(Number::Int(-1)));
        assert_eq!(ints(sym::MOD, -7, -2), Ok(Number::Int(-1)));
        assert_eq!(ints(sym::MOD, 6, -3), Ok(Number::Int(0)));
    }

    #[test]
    fn overflow_is_an_error_not_a_wrap() {
        assert!(ints(sym::PLUS, i64::MAX, 1).is_err());
        assert!(ints(sym::STAR, i64::MAX, 2).is_err());
    }
}
