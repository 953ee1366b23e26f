//! Scoring drafted test cases against reference answers, in the columns of the paper's Table
//! "Large Language Model Evaluation".
//!
//! The paper does not define its columns; kbc reads them as follows, which fits the Table (the
//! first two columns are equal for every model, so they describe the reference answers):
//!
//! - *predicates*: the facts of the reference's two states;
//! - *literals*: the arguments of those facts;
//! - *errors in predicates*: per state and predicate, the facts of the answer and of the
//!   reference that have no equal on the other side, paired up (a wrong fact in place of a
//!   right one is one error; a missing or an extra fact is one too);
//! - *errors in literals*: the arguments that differ within each such pair (each pair matched
//!   so that the fewest differ), plus every argument of an unpaired fact;
//! - *success*: the answer passed every check and its two states hold exactly the reference's
//!   facts (as sets: order does not matter).
//!
//! An answer the front end cannot read as a test case has every reference fact wrong.

use std::collections::BTreeMap;

use super::check::{Fact, States};

/// The score of one answer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Score {
    /// Facts in the reference.
    pub predicates: usize,
    /// Arguments of those facts.
    pub literals: usize,
    /// Wrong, missing and extra facts.
    pub predicate_errors: usize,
    /// Wrong arguments.
    pub literal_errors: usize,
    /// Whether the answer is right.
    pub success: bool,
}

/// Scores `answer` (`None`: no test case could be read) against `reference`; `passed` says
/// whether it passed every check.
pub fn score(reference: &States, answer: Option<&States>, passed: bool) -> Score {
    let predicates = reference.init.len() + reference.goal.len();
    let literals = reference.init.iter().chain(&reference.goal).map(|f| f.args.len()).sum();
    let mut score = Score { predicates, literals, ..Score::default() };
    let empty = States { init: Vec::new(), goal: Vec::new() };
    let answer_states = answer.unwrap_or(&empty);
    for (expected, got) in [(&reference.init, &answer_states.init), (&reference.goal, &answer_states.goal)] {
        let (predicate_errors, literal_errors) = compare(expected, got);
        score.predicate_errors += predicate_errors;
        score.literal_errors += literal_errors;
    }
    score.success = passed && answer.is_some() && score.predicate_errors == 0;
    score
}

/// The errors in predicates and in literals of one state.
fn compare(expected: &[Fact], got: &[Fact]) -> (usize, usize) {
    let mut expected: Vec<&Fact> = dedup(expected);
    let mut got: Vec<&Fact> = dedup(got);
    // Facts on both sides are right.
    expected.retain(|fact| match got.iter().position(|g| g == fact) {
        Some(i) => {
            got.remove(i);
            false
        }
        None => true,
    });
    // Pair the rest by predicate and arity.
    // (predicate, arity) -> (the reference's facts, the answer's facts)
    type Sides<'a> = (Vec<&'a Fact>, Vec<&'a Fact>);
    let mut groups: BTreeMap<(&str, usize), Sides<'_>> = BTreeMap::new();
    for fact in expected {
        groups.entry((&fact.name, fact.args.len())).or_default().0.push(fact);
    }
    for fact in got {
        groups.entry((&fact.name, fact.args.len())).or_default().1.push(fact);
    }
    let (mut predicate_errors, mut literal_errors) = (0, 0);
    for (wanted, written) in groups.values() {
        let (pairs, unpaired) = pair(wanted, written);
        predicate_errors += pairs.len() + unpaired.len();
        literal_errors += pairs.iter().map(|(a, b)| differing(a, b)).sum::<usize>();
        literal_errors += unpaired.iter().map(|f| f.args.len()).sum::<usize>();
    }
    (predicate_errors, literal_errors)
}

/// A state is a set: a fact written twice counts once.
fn dedup(facts: &[Fact]) -> Vec<&Fact> {
    let mut unique: Vec<&Fact> = Vec::new();
    for fact in facts {
        if !unique.contains(&fact) {
            unique.push(fact);
        }
    }
    unique
}

/// Pairs facts of the same predicate so that the fewest arguments differ: repeatedly the
/// closest pair (the first in order on a tie). Returns the pairs and the facts left over.
fn pair<'a>(wanted: &[&'a Fact], written: &[&'a Fact]) -> (Vec<(&'a Fact, &'a Fact)>, Vec<&'a Fact>) {
    let mut wanted: Vec<&Fact> = wanted.to_vec();
    let mut written: Vec<&Fact> = written.to_vec();
    let mut pairs = Vec::new();
    while !wanted.is_empty() && !written.is_empty() {
        let mut best = (usize::MAX, 0, 0);
        for (i, a) in wanted.iter().enumerate() {
            for (j, b) in written.iter().enumerate() {
                let d = differing(a, b);
                if d < best.0 {
                    best = (d, i, j);
                }
            }
        }
        pairs.push((wanted.remove(best.1), written.remove(best.2)));
    }
    wanted.extend(written);
    (pairs, wanted)
}

fn differing(a: &Fact, b: &Fact) -> usize {
    a.args.iter().zip(&b.args).filter(|(x, y)| x != y).count()
}

/// One row of the Table: a model, with or without repair, over a set of cases.
#[derive(Clone, Debug)]
pub struct Row {
    /// The row's label, e.g. `scripted-a` or `scripted-a + repair`.
    pub label: String,
    /// One score per case.
    pub scores: Vec<Score>,
}

impl Row {
    fn average(&self, f: impl Fn(&Score) -> usize) -> f64 {
        if self.scores.is_empty() {
            0.0
        } else {
            self.scores.iter().map(f).sum::<usize>() as f64 / self.scores.len() as f64
        }
    }
}

/// The Table: the paper's columns, averaged over the cases, one row per model and mode.
pub fn table(rows: &[Row]) -> String {
    let headers = [
        ("", ""),
        ("# of predicates", "(avg)"),
        ("# of literals", "(avg)"),
        ("# of errors in", "predicates (avg)"),
        ("# of errors in", "literals (avg)"),
        ("success", "rate"),
    ];
    let mut cells: Vec<[String; 6]> = Vec::new();
    for row in rows {
        let success = row.scores.iter().filter(|s| s.success).count() as f64 / row.scores.len().max(1) as f64;
        cells.push([
            row.label.clone(),
            format!("{:.1}", row.average(|s| s.predicates)),
            format!("{:.1}", row.average(|s| s.literals)),
            format!("{:.1}", row.average(|s| s.predicate_errors)),
            format!("{:.1}", row.average(|s| s.literal_errors)),
            format!("{success:.1}"),
        ]);
    }
    let widths: Vec<usize> = (0..6)
        .map(|c| {
            let header = headers[c].0.len().max(headers[c].1.len());
            cells.iter().map(|r| r[c].len()).max().unwrap_or(0).max(header)
        })
        .collect();
    let line = |values: [&str; 6]| {
        let mut text = format!("{:<w$}", values[0], w = widths[0]);
        for c in 1..6 {
            text.push_str(&format!(" | {:>w$}", values[c], w = widths[c]));
        }
        text.trim_end().to_string() + "\n"
    };
    let mut out = String::new();
    out.push_str(&line(headers.map(|h| h.0)));
    out.push_str(&line(headers.map(|h| h.1)));
    let rule: Vec<String> = widths.iter().map(|w| "-".repeat(*w)).collect();
    out.push_str(&rule.join("-+-"));
    out.push('\n');
    for row in &cells {
        out.push_str(&line([&row[0], &row[1], &row[2], &row[3], &row[4], &row[5]]));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fact(text: &str) -> Fact {
        let (name, rest) = text.split_once('(').unwrap();
        let args = rest.trim_end_matches(')').split(',').map(|a| a.trim().to_string()).collect();
        Fact { name: name.to_string(), args }
    }

    fn states(init: &[&str], goal: &[&str]) -> States {
        States { init: init.iter().map(|f| fact(f)).collect(), goal: goal.iter().map(|f| fact(f)).collect() }
    }

    #[test]
    fn an_equal_answer_in_another_order_has_no_errors() {
        let reference = states(&["available(a1)", "ontable(b1, 1, 1)", "clear(b1)"], &["ontable(b1, 2, 2)"]);
        let answer = states(&["clear(b1)", "ontable(b1, 1, 1)", "available(a1)", "clear(b1)"], &["ontable(b1, 2, 2)"]);
        let s = score(&reference, Some(&answer), true);
        assert_eq!((s.predicates, s.literals, s.predicate_errors, s.literal_errors), (4, 8, 0, 0));
        assert!(s.success);
        assert!(!score(&reference, Some(&answer), false).success, "an answer that failed a check is no success");
    }

    #[test]
    fn a_reversed_stack_counts_each_wrong_fact_and_argument() {
        // The paper's most frequent mistake: the right cell, the wrong order.
        let reference = states(&[], &["ontable(b2, 5, 5)", "on(b1, b2, 5, 5)", "clear(b1)"]);
        let answer = states(&[], &["ontable(b1, 5, 5)", "on(b2, b1, 5, 5)", "clear(b2)"]);
        let s = score(&reference, Some(&answer), true);
        assert_eq!(s.predicate_errors, 3);
        // ontable: 1 argument, on: 2, clear: 1.
        assert_eq!(s.literal_errors, 4);
        assert!(!s.success);
    }

    #[test]
    fn missing_and_extra_facts_count_all_their_arguments() {
        let reference = states(&["clear(b1)", "clear(b2)"], &[]);
        let answer = states(&["clear(b1)", "available(a1)"], &[]);
        let s = score(&reference, Some(&answer), true);
        // clear(b2) paired with nothing, available(a1) with nothing.
        assert_eq!((s.predicate_errors, s.literal_errors), (2, 2));
        let unread = score(&reference, None, false);
        assert_eq!((unread.predicate_errors, unread.literal_errors), (2, 2));
    }

    #[test]
    fn the_table_has_the_papers_columns_and_averages() {
        let good = Score { predicates: 10, literals: 20, predicate_errors: 0, literal_errors: 0, success: true };
        let bad = Score { predicates: 12, literals: 24, predicate_errors: 3, literal_errors: 5, success: false };
        let text = table(&[Row { label: "m".into(), scores: vec![good, bad] }]);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].contains("# of predicates") && lines[1].contains("literals (avg)"));
        let cells: Vec<&str> = lines[3].split('|').map(str::trim).collect();
        assert_eq!(cells, ["m", "11.0", "22.0", "1.5", "2.5", "0.5"]);
    }
}
