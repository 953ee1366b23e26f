//! Arithmetic for `is/2` and the comparisons, with SWI-Prolog's default semantics.
//!
//! Integers are 64-bit: where SWI-Prolog would move to big integers, kbc reports an overflow
//! instead of guessing. `/` on two integers gives an integer when the division is exact and a
//! float otherwise; `//` truncates towards zero; `mod` takes the sign of the divisor, `rem`
//! the sign of the dividend. `**` on two integers is an integer (as SWI-Prolog's default,
//! `prefer_rationals` off), and so is `^`; a negative exponent gives a float, except that
//! 1 or -1 as the base stays an integer. A float result that is not finite (`inf`,
//! `nan` written out excepted) is an evaluation error, as is `sqrt` or `log` outside their
//! domain.

use std::cmp::Ordering;

use super::{Cell, EngineError, Machine};
use crate::intern::{Interner, Symbol, sym};
use crate::ir::hir::Term;

/// The arithmetic functions beyond the well-known ones [`eval`] matches by symbol.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Function {
    Rem,
    Div,
    Sign,
    Power,
    Caret,
    Sqrt,
    Exp,
    Log,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Sinh,
    Cosh,
    Tanh,
    Floor,
    Ceiling,
    Round,
    Truncate,
    Integer,
    ToFloat,
    IntegerPart,
    FractionalPart,
    Gcd,
    Msb,
    ShiftRight,
    ShiftLeft,
    BitAnd,
    BitOr,
    Xor,
    BitNot,
    Pi,
    E,
    Inf,
    Nan,
    Epsilon,
}

/// The functions of [`Function`] by the symbols `interner` has for their names.
pub(super) fn functions(interner: &Interner) -> rustc_hash::FxHashMap<(Symbol, u32), Function> {
    use Function::*;
    const TABLE: &[(&str, u32, Function)] = &[
        ("rem", 2, Rem),
        ("div", 2, Div),
        ("sign", 1, Sign),
        ("**", 2, Power),
        ("^", 2, Caret),
        ("sqrt", 1, Sqrt),
        ("exp", 1, Exp),
        ("log", 1, Log),
        ("sin", 1, Sin),
        ("cos", 1, Cos),
        ("tan", 1, Tan),
        ("asin", 1, Asin),
        ("acos", 1, Acos),
        ("atan", 1, Atan),
        ("atan", 2, Atan2),
        ("atan2", 2, Atan2),
        ("sinh", 1, Sinh),
        ("cosh", 1, Cosh),
        ("tanh", 1, Tanh),
        ("floor", 1, Floor),
        ("ceiling", 1, Ceiling),
        ("round", 1, Round),
        ("truncate", 1, Truncate),
        ("integer", 1, Integer),
        ("float", 1, ToFloat),
        ("float_integer_part", 1, IntegerPart),
        ("float_fractional_part", 1, FractionalPart),
        ("gcd", 2, Gcd),
        ("msb", 1, Msb),
        (">>", 2, ShiftRight),
        ("<<", 2, ShiftLeft),
        ("/\\", 2, BitAnd),
        ("\\/", 2, BitOr),
        ("xor", 2, Xor),
        ("\\", 1, BitNot),
        ("pi", 0, Pi),
        ("e", 0, E),
        ("inf", 0, Inf),
        ("infinite", 0, Inf),
        ("nan", 0, Nan),
        ("epsilon", 0, Epsilon),
    ];
    TABLE.iter().filter_map(|&(name, arity, f)| Some(((interner.get(name)?, arity), f))).collect()
}

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

/// The integer operand of a function other than `//` and `mod`.
fn integer_of(n: Number) -> Result<i64, EngineError> {
    match n {
        Number::Int(i) => Ok(i),
        Number::Float(f) => Err(EngineError::Type { expected: "an integer operand", found: Term::Float(f) }),
    }
}

/// An evaluation outside a function's domain (SWI-Prolog's `evaluation_error(undefined)`).
fn undefined(what: &str) -> EngineError {
    EngineError::Evaluation { message: format!("{what} is undefined") }
}

/// A float rounded to an integer, or an overflow.
fn to_integer(f: f64) -> Result<Number, EngineError> {
    if f.is_finite() && f >= i64::MIN as f64 && f < i64::MAX as f64 {
        Ok(Number::Int(f as i64))
    } else {
        Err(overflow())
    }
}

/// `base ** exponent` or `base ^ exponent` on two integers: an integer, or for a negative
/// exponent a float (an integer for the bases 1 and -1).
fn int_power(base: i64, exponent: i64) -> Result<Number, EngineError> {
    if exponent < 0 {
        return match base {
            1 => Ok(Number::Int(1)),
            -1 => Ok(Number::Int(if exponent % 2 == 0 { 1 } else { -1 })),
            0 => Err(EngineError::ZeroDivisor),
            _ => float((base as f64).powf(exponent as f64)),
        };
    }
    let exponent = u32::try_from(exponent).map_err(|_| overflow())?;
    base.checked_pow(exponent).map(Number::Int).ok_or_else(overflow)
}

/// A function of [`Function`] on its evaluated arguments.
fn apply(function: Function, args: &[Number]) -> Result<Number, EngineError> {
    use Function::*;
    use Number::{Float, Int};
    let x = args.first().copied().unwrap_or(Int(0));
    let y = args.get(1).copied().unwrap_or(Int(0));
    let unary = |f: fn(f64) -> f64| float(f(x.as_float()));
    match function {
        Rem => {
            let (a, b) = (integer_of(x)?, integer_of(y)?);
            if b == 0 {
                return Err(EngineError::ZeroDivisor);
            }
            a.checked_rem(b).map(Int).ok_or_else(overflow)
        }
        Div => {
            let (a, b) = (integer_of(x)?, integer_of(y)?);
            if b == 0 {
                return Err(EngineError::ZeroDivisor);
            }
            // Floored division: the quotient rounded towards negative infinity.
            let q = a.checked_div(b).ok_or_else(overflow)?;
            Ok(Int(if (a % b != 0) && ((a < 0) != (b < 0)) { q - 1 } else { q }))
        }
        Sign => Ok(match x {
            Int(i) => Int(i.signum()),
            Float(f) => Float(if f > 0.0 {
                1.0
            } else if f < 0.0 {
                -1.0
            } else {
                0.0
            }),
        }),
        Power | Caret => match (x, y) {
            (Int(a), Int(b)) => int_power(a, b),
            _ => {
                if x.as_float() == 0.0 && y.as_float() < 0.0 {
                    return Err(EngineError::ZeroDivisor);
                }
                let result = x.as_float().powf(y.as_float());
                if result.is_nan() { Err(undefined("the power")) } else { float(result) }
            }
        },
        Sqrt => {
            if x.as_float() < 0.0 {
                return Err(undefined("the square root of a negative number"));
            }
            unary(f64::sqrt)
        }
        Exp => unary(f64::exp),
        Log => {
            if x.as_float() <= 0.0 {
                return Err(if x.as_float() == 0.0 {
                    EngineError::Evaluation { message: "the logarithm of 0 is not finite".to_string() }
                } else {
                    undefined("the logarithm of a negative number")
                });
            }
            unary(f64::ln)
        }
        Sin => unary(f64::sin),
        Cos => unary(f64::cos),
        Tan => unary(f64::tan),
        Asin | Acos => {
            if x.as_float().abs() > 1.0 {
                return Err(undefined("the arc sine or cosine of a number beyond 1"));
            }
            unary(if function == Asin { f64::asin } else { f64::acos })
        }
        Atan => unary(f64::atan),
        Atan2 => float(x.as_float().atan2(y.as_float())),
        Sinh => unary(f64::sinh),
        Cosh => unary(f64::cosh),
        Tanh => unary(f64::tanh),
        Floor | Ceiling | Round | Truncate | Integer => match x {
            Int(i) => Ok(Int(i)),
            Float(f) => to_integer(match function {
                Floor => f.floor(),
                Ceiling => f.ceil(),
                Truncate => f.trunc(),
                // Halves away from zero, as SWI-Prolog rounds.
                _ => f.round(),
            }),
        },
        ToFloat => float(x.as_float()),
        IntegerPart => match x {
            Int(i) => float(i as f64),
            Float(f) => float(f.trunc()),
        },
        FractionalPart => match x {
            Int(_) => Ok(Float(0.0)),
            Float(f) => float(f.fract()),
        },
        Gcd => {
            let (mut a, mut b) = (integer_of(x)?.unsigned_abs(), integer_of(y)?.unsigned_abs());
            while b != 0 {
                (a, b) = (b, a % b);
            }
            i64::try_from(a).map(Int).map_err(|_| overflow())
        }
        Msb => {
            let a = integer_of(x)?;
            if a <= 0 {
                return Err(EngineError::Type { expected: "a positive integer", found: Term::Int(a) });
            }
            Ok(Int(63 - a.leading_zeros() as i64))
        }
        ShiftRight | ShiftLeft => {
            let (a, b) = (integer_of(x)?, integer_of(y)?);
            let shift = u32::try_from(b.unsigned_abs().min(64)).unwrap_or(64);
            let right = (function == ShiftRight) == (b >= 0);
            if right {
                Ok(Int(if shift >= 64 { if a < 0 { -1 } else { 0 } } else { a >> shift }))
            } else if shift >= 64 {
                if a == 0 { Ok(Int(0)) } else { Err(overflow()) }
            } else {
                let shifted = a << shift;
                if shifted >> shift == a { Ok(Int(shifted)) } else { Err(overflow()) }
            }
        }
        BitAnd => Ok(Int(integer_of(x)? & integer_of(y)?)),
        BitOr => Ok(Int(integer_of(x)? | integer_of(y)?)),
        Xor => Ok(Int(integer_of(x)? ^ integer_of(y)?)),
        BitNot => Ok(Int(!integer_of(x)?)),
        Pi => Ok(Float(std::f64::consts::PI)),
        E => Ok(Float(std::f64::consts::E)),
        Inf => Ok(Float(f64::INFINITY)),
        Nan => Ok(Float(f64::NAN)),
        Epsilon => Ok(Float(f64::EPSILON)),
    }
}

/// Evaluates an arithmetic expression.
pub(super) fn eval(machine: &Machine<'_>, cell: Cell) -> Result<Number, EngineError> {
    match machine.deref(cell) {
        Cell::Int(i) => Ok(Number::Int(i)),
        Cell::Float(f) => Ok(Number::Float(f)),
        Cell::Ref(_) => Err(EngineError::Instantiation { context: "arithmetic".to_string() }),
        Cell::Atom(name) if machine.program.functions.contains_key(&(name, 0)) => {
            apply(machine.program.functions[&(name, 0)], &[])
        }
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
                _ => {
                    let Some(&function) = machine.program.functions.get(&(name, args.len() as u32)) else {
                        return Err(EngineError::Type {
                            expected: "an arithmetic function",
                            found: machine.read(cell, &mut Vec::new()),
                        });
                    };
                    let args: Vec<Cell> = args.to_vec();
                    let values = args.iter().map(|a| eval(machine, *a)).collect::<Result<Vec<_>, _>>()?;
                    apply(function, &values)
                }
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
