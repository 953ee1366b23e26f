//! Faults the simulated world can suffer, for testing how a program copes when the world
//! stops agreeing with the KB: a carried block slips from its gripper, an arm stalls for a
//! while or stops for good, a block is nudged to another cell.
//!
//! A fault is written `KIND[:ARG...][@WHEN]` ([`FaultSpec`], parsed with `str::parse`):
//!
//! - `drop[:ARM]`: the block the arm carries (any arm if none is named) slips while it moves;
//! - `stall[:ARM[:SECONDS]]`: the arm freezes for that long, then carries on;
//! - `stop[:ARM]`: the arm stops for good (its controller reports the fault when polled);
//! - `nudge[:BLOCK[:X:Y]]`: the block is pushed onto the cell (X, Y) (a free one if none is
//!   given); a block with others on it is not nudged, the top of its stack is.
//!
//! `WHEN` is a time in seconds of simulated time (`@4.5`) or the start of the first action
//! whose text begins with it (`@move_block_start(a2`). What is left out is drawn from a seed
//! ([`FaultSpec::resolve`]): the target among the world's arms or blocks, the time within
//! the horizon given, a stall's length between 1 and 4 seconds. A fault whose moment comes
//! while it cannot happen (nothing carried for `drop`, the block held for `nudge`) waits
//! until it can.

use std::fmt;

pub use crate::rng::Rng;

/// The kinds of fault, with what the specification names.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FaultKindSpec {
    /// A carried block slips.
    Drop {
        /// The arm that carries it.
        arm: Option<String>,
    },
    /// An arm freezes for a while.
    Stall {
        /// The arm.
        arm: Option<String>,
        /// For how long.
        seconds: Option<f64>,
    },
    /// An arm stops for good.
    Stop {
        /// The arm.
        arm: Option<String>,
    },
    /// A block is pushed to another cell.
    Nudge {
        /// The block.
        block: Option<String>,
        /// The cell it is pushed onto.
        cell: Option<(i64, i64)>,
    },
}

/// When a fault happens, as specified.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum When {
    /// At this many seconds of simulated time.
    At(f64),
    /// When the first action whose text starts with this starts.
    OnStart(String),
    /// An [`When::OnStart`] fault whose action started at this many seconds.
    Started(String, f64),
}

/// A fault as written on the command line; unnamed parts are drawn by [`FaultSpec::resolve`].
#[derive(Clone, Debug, PartialEq)]
pub struct FaultSpec {
    /// What happens.
    pub kind: FaultKindSpec,
    /// When, if given.
    pub when: Option<When>,
}

/// A fault with every part decided.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FaultKind {
    /// The block arm `.0` carries slips (any arm when `None`).
    Drop(Option<String>),
    /// Arm `.0` freezes for `.1` seconds.
    Stall(String, f64),
    /// Arm `.0` stops for good.
    Stop(String),
    /// Block `.0` (or the top of its stack) is pushed onto cell `.1` (a free cell when `None`).
    Nudge(String, Option<(i64, i64)>),
}

/// A fault ready to inject.
#[derive(Clone, Debug, PartialEq)]
pub struct Fault {
    /// What happens.
    pub kind: FaultKind,
    /// When.
    pub when: When,
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            FaultKind::Drop(Some(arm)) => write!(f, "drop:{arm}")?,
            FaultKind::Drop(None) => write!(f, "drop")?,
            FaultKind::Stall(arm, seconds) => write!(f, "stall:{arm}:{seconds:.1}")?,
            FaultKind::Stop(arm) => write!(f, "stop:{arm}")?,
            FaultKind::Nudge(block, Some((x, y))) => write!(f, "nudge:{block}:{x}:{y}")?,
            FaultKind::Nudge(block, None) => write!(f, "nudge:{block}")?,
        }
        match &self.when {
            When::At(t) => write!(f, "@{t:.3}"),
            When::OnStart(prefix) | When::Started(prefix, _) => write!(f, "@{prefix}"),
        }
    }
}

/// A fault specification that does not parse.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaultSyntaxError(pub String);

impl fmt::Display for FaultSyntaxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for FaultSyntaxError {}

impl std::str::FromStr for FaultSpec {
    type Err = FaultSyntaxError;

    fn from_str(text: &str) -> Result<FaultSpec, FaultSyntaxError> {
        fn error<T>(what: String) -> Result<T, FaultSyntaxError> {
            Err(FaultSyntaxError(what))
        }
        let (what, when) = match text.split_once('@') {
            Some((what, "")) => return error(format!("`{what}@` lacks the time or action")),
            Some((what, when)) => match when.parse::<f64>() {
                Ok(t) if t.is_finite() && t >= 0.0 => (what, Some(When::At(t))),
                Ok(_) => return error(format!("`{when}` is not a time: times are seconds from 0")),
                Err(_) => (what, Some(When::OnStart(when.to_string()))),
            },
            None => (text, None),
        };
        let parts: Vec<&str> = what.split(':').collect();
        let name = |i: usize| parts.get(i).filter(|s| !s.is_empty()).map(|s| s.to_string());
        let number = |i: usize, what: &str| -> Result<Option<f64>, FaultSyntaxError> {
            match parts.get(i) {
                None => Ok(None),
                Some(s) => match s.parse::<f64>() {
                    Ok(v) if v.is_finite() && v >= 0.0 => Ok(Some(v)),
                    _ => Err(FaultSyntaxError(format!("`{s}` is not {what}"))),
                },
            }
        };
        let most = |n: usize| {
            if parts.len() > n {
                error(format!("`{what}` has too many parts: `{}` takes at most {}", parts[0], n - 1))
            } else {
                Ok(())
            }
        };
        let kind = match parts[0] {
            "drop" => {
                most(2)?;
                FaultKindSpec::Drop { arm: name(1) }
            }
            "stall" => {
                most(3)?;
                FaultKindSpec::Stall { arm: name(1), seconds: number(2, "a number of seconds")? }
            }
            "stop" => {
                most(2)?;
                FaultKindSpec::Stop { arm: name(1) }
            }
            "nudge" => {
                most(4)?;
                let cell = match (parts.get(2), parts.get(3)) {
                    (None, None) => None,
                    (Some(x), Some(y)) => match (x.parse::<i64>(), y.parse::<i64>()) {
                        (Ok(x), Ok(y)) => Some((x, y)),
                        _ => return error(format!("`{x}:{y}` is not a cell: write two integers, `X:Y`")),
                    },
                    _ => return error("a cell is two integers, `nudge:BLOCK:X:Y`".to_string()),
                };
                FaultKindSpec::Nudge { block: name(1), cell }
            }
            other => {
                return error(format!("`{other}` is not a fault: the faults are `drop`, `stall`, `stop` and `nudge`"));
            }
        };
        Ok(FaultSpec { kind, when })
    }
}

impl FaultSpec {
    /// Decides what the specification leaves out: a target among `arms` or `blocks`, a time in
    /// `[0, horizon)` seconds, a stall's length. The same generator state gives the same fault.
    pub fn resolve(&self, arms: &[String], blocks: &[String], horizon: f64, rng: &mut Rng) -> Fault {
        let mut pick = |names: &[String], given: &Option<String>| {
            given
                .clone()
                .unwrap_or_else(|| if names.is_empty() { String::new() } else { names[rng.below(names.len())].clone() })
        };
        let kind = match &self.kind {
            FaultKindSpec::Drop { arm } => FaultKind::Drop(arm.clone()),
            FaultKindSpec::Stall { arm, seconds } => {
                let arm = pick(arms, arm);
                FaultKind::Stall(arm, seconds.unwrap_or_else(|| (rng.between(1.0, 4.0) * 10.0).round() / 10.0))
            }
            FaultKindSpec::Stop { arm } => FaultKind::Stop(pick(arms, arm)),
            FaultKindSpec::Nudge { block, cell } => FaultKind::Nudge(pick(blocks, block), *cell),
        };
        let when = self
            .when
            .clone()
            .unwrap_or_else(|| When::At((rng.between(0.0, horizon.max(0.0)) * 1000.0).round() / 1000.0));
        Fault { kind, when }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specifications_parse_and_resolve() {
        let spec: FaultSpec = "stall:a2:1.5@move_block_start(a2".parse().unwrap();
        assert_eq!(spec.kind, FaultKindSpec::Stall { arm: Some("a2".into()), seconds: Some(1.5) });
        assert_eq!(spec.when, Some(When::OnStart("move_block_start(a2".into())));
        let spec: FaultSpec = "nudge:b3:4:5@2".parse().unwrap();
        assert_eq!(spec.kind, FaultKindSpec::Nudge { block: Some("b3".into()), cell: Some((4, 5)) });
        assert_eq!(spec.when, Some(When::At(2.0)));
        let arms = vec!["a1".to_string(), "a2".to_string()];
        let blocks = vec!["b1".to_string()];
        let spec: FaultSpec = "stop".parse().unwrap();
        let a = spec.resolve(&arms, &blocks, 10.0, &mut Rng::new(7));
        let b = spec.resolve(&arms, &blocks, 10.0, &mut Rng::new(7));
        assert_eq!(a, b, "the same seed gives the same fault");
        let When::At(t) = a.when else { panic!("a drawn time") };
        assert!((0.0..10.0).contains(&t));
        let times: std::collections::BTreeSet<String> =
            (0..20).map(|s| spec.resolve(&arms, &blocks, 10.0, &mut Rng::new(s)).to_string()).collect();
        assert!(times.len() > 10, "seeds draw different faults: {times:?}");
    }

    #[test]
    fn bad_specifications_say_what_is_wrong() {
        let error = |text: &str| text.parse::<FaultSpec>().unwrap_err().0;
        assert!(error("wobble").contains("the faults are `drop`, `stall`, `stop` and `nudge`"));
        assert!(error("stall:a1:soon").contains("`soon` is not a number of seconds"));
        assert!(error("nudge:b1:3").contains("`nudge:BLOCK:X:Y`"));
        assert!(error("stop:a1:a2").contains("too many parts"));
        assert!(error("drop@").contains("lacks the time or action"));
        assert!(error("drop@-3").contains("not a time"));
    }
}
