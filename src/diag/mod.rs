//! Diagnostics as data.
//!
//! Every phase reports problems as [`Diagnostic`] values: a stable [`Code`], a severity, a
//! message saying what was expected and what was found, labelled spans, notes, a help line,
//! and machine-applicable [`Fix`]es where the fix is clear. Nothing here prints; rendering for
//! terminals and JSON lives in [`render`], and the language server converts the same values
//! for editors. Phases push into a [`Diagnostics`] sink and keep going: one run reports every
//! problem it can find.
//!
//! Message style, as rustc's: start lower-case, no final period, name the thing in backticks.

pub mod codes;
pub mod render;

use crate::source::Span;

pub use codes::Code;

/// How serious a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Informational: what the compiler decided on the user's behalf.
    Note,
    /// Probably a mistake, but the input is usable.
    Warning,
    /// The input cannot be used as written.
    Error,
}

/// A span with a message; the primary label says where the problem is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Label {
    /// The text the label points at (may be empty: an insertion point).
    pub span: Span,
    /// What this place has to do with the problem; may be empty.
    pub message: String,
    /// True for the place the diagnostic is about, false for related places.
    pub primary: bool,
}

/// One text replacement.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edit {
    /// The text to replace (empty for an insertion).
    pub span: Span,
    /// The new text.
    pub replacement: String,
}

/// A machine-applicable fix: applying every edit resolves the diagnostic.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fix {
    /// What the fix does, as a short imperative ("replace `!=` with `\=`").
    pub message: String,
    /// The edits, in any order; they never overlap.
    pub edits: Vec<Edit>,
}

/// A problem found in the input.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// The stable code, or `None` for plain notes.
    pub code: Option<Code>,
    /// How serious it is.
    pub severity: Severity,
    /// One line: what was expected and what was found.
    pub message: String,
    /// Where, with the primary label first.
    pub labels: Vec<Label>,
    /// Further explanation, one line each.
    pub notes: Vec<String>,
    /// How to fix it, when that is clear.
    pub help: Option<String>,
    /// Fixes a tool may apply.
    pub fixes: Vec<Fix>,
}

impl Diagnostic {
    fn new(code: Option<Code>, severity: Severity, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            code,
            severity,
            message: message.into(),
            labels: Vec::new(),
            notes: Vec::new(),
            help: None,
            fixes: Vec::new(),
        }
    }

    /// An error with a code.
    pub fn error(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic::new(Some(code), Severity::Error, message)
    }

    /// A warning with a code.
    pub fn warning(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic::new(Some(code), Severity::Warning, message)
    }

    /// A note without a code: information, not a problem.
    pub fn note(message: impl Into<String>) -> Diagnostic {
        Diagnostic::new(None, Severity::Note, message)
    }

    /// Adds the primary label.
    pub fn primary(mut self, span: Span, message: impl Into<String>) -> Diagnostic {
        self.labels.insert(0, Label { span, message: message.into(), primary: true });
        self
    }

    /// Adds a secondary label.
    pub fn secondary(mut self, span: Span, message: impl Into<String>) -> Diagnostic {
        self.labels.push(Label { span, message: message.into(), primary: false });
        self
    }

    /// Adds a note line.
    pub fn with_note(mut self, note: impl Into<String>) -> Diagnostic {
        self.notes.push(note.into());
        self
    }

    /// Sets the help line.
    pub fn with_help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    /// Adds a fix made of a single edit.
    pub fn with_fix(mut self, message: impl Into<String>, span: Span, replacement: impl Into<String>) -> Diagnostic {
        self.fixes.push(Fix { message: message.into(), edits: vec![Edit { span, replacement: replacement.into() }] });
        self
    }

    /// Adds a fix made of several edits.
    pub fn with_fix_edits(mut self, message: impl Into<String>, edits: Vec<Edit>) -> Diagnostic {
        self.fixes.push(Fix { message: message.into(), edits });
        self
    }

    /// The primary label's span, if the diagnostic has one.
    pub fn primary_span(&self) -> Option<Span> {
        self.labels.iter().find(|l| l.primary).map(|l| l.span)
    }

    /// True for errors.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// Where phases put what they find.
#[derive(Debug, Default, Clone)]
pub struct Diagnostics {
    items: Vec<Diagnostic>,
    /// Errors left out by [`Diagnostics::cap_repeats`], still counted.
    dropped_errors: usize,
}

impl Diagnostics {
    /// An empty sink.
    pub fn new() -> Diagnostics {
        Diagnostics::default()
    }

    /// Records a diagnostic.
    pub fn push(&mut self, diagnostic: Diagnostic) {
        self.items.push(diagnostic);
    }

    /// True if any error was recorded.
    pub fn has_errors(&self) -> bool {
        self.items.iter().any(Diagnostic::is_error)
    }

    /// Turns every warning into an error (`-D warnings`), with a note that says why, as rustc
    /// does for `#[deny(warnings)]`. Notes stay notes.
    pub fn deny_warnings(&mut self) {
        let mut first = true;
        for diagnostic in self.items.iter_mut().filter(|d| d.severity == Severity::Warning) {
            diagnostic.severity = Severity::Error;
            if first {
                diagnostic.notes.push("`-D warnings` turns every warning into an error".to_string());
                first = false;
            }
        }
    }

    /// The number of errors, with those [`Diagnostics::cap_repeats`] left out.
    pub fn error_count(&self) -> usize {
        self.items.iter().filter(|d| d.is_error()).count() + self.dropped_errors
    }

    /// The number of warnings.
    pub fn warning_count(&self) -> usize {
        self.items.iter().filter(|d| d.severity == Severity::Warning).count()
    }

    /// Everything recorded, in the order it was found.
    pub fn iter(&self) -> std::slice::Iter<'_, Diagnostic> {
        self.items.iter()
    }

    /// The number of diagnostics.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Moves everything from `other` into `self`.
    pub fn extend(&mut self, other: Diagnostics) {
        self.items.extend(other.items);
        self.dropped_errors += other.dropped_errors;
    }

    /// Sorts diagnostics by file and position (stable for equal positions), so output does not
    /// depend on the order in which passes happened to find problems.
    pub fn sort_by_position(&mut self) {
        self.items.sort_by_key(|d| d.primary_span().map(|s| (s.file, s.start, s.end)));
    }

    /// Keeps the first `limit` diagnostics of each code in each file and replaces the rest by
    /// one note that counts them ("and 9,990 more E0104 in `a.pl`"): a file of ten thousand
    /// stray brackets gets a readable report, rendered in time proportional to the input.
    /// The count of errors stays exact ([`Diagnostics::error_count`] counts the dropped ones).
    pub fn cap_repeats(&mut self, limit: usize) {
        use std::collections::BTreeMap;
        let mut seen: BTreeMap<(Code, u32), (usize, usize, Severity)> = BTreeMap::new();
        let mut kept = Vec::with_capacity(self.items.len().min(limit * 8));
        for diagnostic in std::mem::take(&mut self.items) {
            let key = diagnostic.code.zip(diagnostic.primary_span().map(|s| s.file.0));
            let Some(key) = key else {
                kept.push(diagnostic);
                continue;
            };
            let entry = seen.entry(key).or_insert((0, 0, diagnostic.severity));
            entry.0 += 1;
            if entry.0 <= limit {
                kept.push(diagnostic);
            } else {
                entry.1 += 1;
            }
        }
        for ((code, _), (_, dropped, severity)) in seen {
            if dropped > 0 {
                let what = match severity {
                    Severity::Error => "errors",
                    Severity::Warning => "warnings",
                    Severity::Note => "notes",
                };
                self.dropped_errors += if severity == Severity::Error { dropped } else { 0 };
                kept.push(Diagnostic::note(format!(
                    "{} more {what} {} in the same file are not shown (the first {limit} are)",
                    group_thousands(dropped),
                    code.as_str()
                )));
            }
        }
        self.items = kept;
    }

    /// Takes the diagnostics out.
    pub fn into_vec(self) -> Vec<Diagnostic> {
        self.items
    }
}

impl IntoIterator for Diagnostics {
    type Item = Diagnostic;
    type IntoIter = std::vec::IntoIter<Diagnostic>;

    fn into_iter(self) -> Self::IntoIter {
        self.items.into_iter()
    }
}

/// `n` with a comma between each group of three digits: `9,990`.
pub fn group_thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A count and its noun for messages: "1 argument", "2 arguments".
pub fn plural(n: usize, word: &str) -> String {
    if n == 1 { format!("1 {word}") } else { format!("{n} {word}s") }
}

/// Damerau-Levenshtein edit distance (optimal string alignment), for did-you-mean suggestions.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut previous2 = vec![0usize; b.len() + 1];
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut current = vec![0usize; b.len() + 1];
    for i in 1..=a.len() {
        current[0] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (previous[j] + 1).min(current[j - 1] + 1).min(previous[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(previous2[j - 2] + 1);
            }
            current[j] = best;
        }
        std::mem::swap(&mut previous2, &mut previous);
        std::mem::swap(&mut previous, &mut current);
    }
    previous[b.len()]
}

/// The candidate closest to `name`, if it is close enough to be a plausible misspelling.
///
/// The threshold follows rustc's: at most a third of the name's length, and at least one.
/// Ties go to the candidate listed first, so callers pass candidates in a deterministic order.
pub fn best_match<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.chars().count() / 3).max(1);
    let mut best: Option<(usize, &str)> = None;
    for candidate in candidates {
        if candidate == name {
            continue;
        }
        let distance = if candidate.eq_ignore_ascii_case(name) { 0 } else { edit_distance(name, candidate) };
        if distance <= limit && best.is_none_or(|(d, _)| distance < d) {
            best = Some((distance, candidate));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use crate::source::{FileId, Span};

    #[test]
    fn repeated_diagnostics_are_capped_per_code_and_file_and_still_counted() {
        let mut diagnostics = Diagnostics::new();
        for i in 0..250u32 {
            let span = Span::new(FileId(i % 2), i, i + 1);
            diagnostics.push(Diagnostic::error(codes::MISMATCHED_DELIMITER, "stray").primary(span, "here"));
        }
        diagnostics
            .push(Diagnostic::warning(codes::SINGLETON_VARIABLE, "once").primary(Span::point(FileId(0), 0), "x"));
        diagnostics.cap_repeats(100);
        let shown = diagnostics.iter().filter(|d| d.code == Some(codes::MISMATCHED_DELIMITER)).count();
        assert_eq!(shown, 200, "the first 100 of each file");
        let notes: Vec<&str> =
            diagnostics.iter().filter(|d| d.severity == Severity::Note).map(|d| d.message.as_str()).collect();
        assert_eq!(notes, ["25 more errors E0104 in the same file are not shown (the first 100 are)"; 2]);
        assert_eq!(diagnostics.error_count(), 250, "the errors left out still count");
        assert_eq!(diagnostics.warning_count(), 1, "other codes are untouched");
    }

    #[test]
    fn thousands_are_grouped() {
        assert_eq!(
            [0, 999, 1_000, 9_990, 1_234_567].map(group_thousands),
            ["0", "999", "1,000", "9,990", "1,234,567"].map(String::from)
        );
    }

    use super::*;

    #[test]
    fn edit_distance_counts_transpositions_as_one() {
        assert_eq!(edit_distance("ontable", "ontable"), 0);
        assert_eq!(edit_distance("ontabel", "ontable"), 1);
        assert_eq!(edit_distance("ontble", "ontable"), 1);
        assert_eq!(edit_distance("clear", "gripped"), 7);
        assert_eq!(edit_distance("", "abc"), 3);
    }

    #[test]
    fn best_match_prefers_the_closest_and_rejects_the_far() {
        let candidates = ["ontable", "on", "clear", "available"];
        assert_eq!(best_match("ontabel", candidates), Some("ontable"));
        assert_eq!(best_match("avaliable", candidates), Some("available"));
        assert_eq!(best_match("Clear", candidates), Some("clear"));
        assert_eq!(best_match("gripped", candidates), None);
    }
}
