//! Rendering diagnostics for people (codespan-reporting, rustc's layout) and for tools (JSON).
//!
//! Rendering is pure: it writes into any `io::Write` or returns a `String`. Whether to use
//! colour is the caller's decision (the CLI checks that stderr is a terminal).

use std::io;

use codespan_reporting::diagnostic as cs;
use codespan_reporting::term;

use super::{Diagnostic, Diagnostics, Severity, plural};
use crate::source::{SourceDb, Span};

/// The longest line a snippet shows, in bytes. A label on a longer line (or beside one, as
/// context) is given as a note with its position instead: a generated KB can hold a clause of
/// megabytes on one line, and nobody reads that in a terminal.
pub const MAX_SNIPPET_LINE: usize = 1_000;

/// The length of the longest line a snippet of `span` would show (its lines and one line of
/// context on either side).
fn widest_shown_line(db: &SourceDb, span: Span) -> usize {
    let file = db.file(span.file);
    let first = file.line_index(span.start).saturating_sub(1);
    let last = file.line_index(span.end) + 1;
    let lines = file.line_starts().len();
    [first, first + 1, first + 2, last.saturating_sub(1), last]
        .into_iter()
        .filter(|&l| l < lines)
        .map(|l| file.line_range(l).len())
        .max()
        .unwrap_or(0)
}

fn to_codespan(db: &SourceDb, diagnostic: &Diagnostic) -> cs::Diagnostic<crate::source::FileId> {
    let severity = match diagnostic.severity {
        Severity::Error => cs::Severity::Error,
        Severity::Warning => cs::Severity::Warning,
        Severity::Note => cs::Severity::Note,
    };
    let mut out = cs::Diagnostic::new(severity).with_message(&diagnostic.message);
    if let Some(code) = diagnostic.code {
        out = out.with_code(code.as_str());
    }
    let mut labels = Vec::new();
    let mut far: Vec<String> = Vec::new();
    for label in &diagnostic.labels {
        let width = widest_shown_line(db, label.span);
        if width > MAX_SNIPPET_LINE {
            let file = db.file(label.span.file);
            let at = file.line_col(label.span.start);
            let message = if label.message.is_empty() { String::new() } else { format!(": {}", label.message) };
            far.push(format!(
                "at {}:{}:{}{message} (the line is not shown: it is {} bytes long)",
                file.name(),
                at.line,
                at.column,
                super::group_thousands(width)
            ));
            continue;
        }
        let style = if label.primary { cs::LabelStyle::Primary } else { cs::LabelStyle::Secondary };
        labels.push(cs::Label::new(style, label.span.file, label.span.range()).with_message(&label.message));
    }
    let mut notes: Vec<String> = far;
    notes.extend(diagnostic.notes.iter().map(|n| format!("note: {n}")));
    if let Some(help) = &diagnostic.help {
        notes.push(format!("help: {help}"));
    }
    out.with_labels(labels).with_notes(notes)
}

fn config() -> term::Config {
    term::Config { start_context_lines: 1, end_context_lines: 1, ..term::Config::default() }
}

/// Renders one diagnostic without colour.
pub fn to_string(db: &SourceDb, diagnostic: &Diagnostic) -> String {
    // Rendering only fails when a span points outside its file, which is a compiler bug; the
    // message is still worth showing, so fall back to the bare text rather than losing it.
    term::emit_into_string(&config(), db, &to_codespan(db, diagnostic))
        .unwrap_or_else(|_| format!("{}: {}\n", severity_word(diagnostic.severity), diagnostic.message))
}

/// Renders every diagnostic without colour, followed by the summary line.
pub fn all_to_string(db: &SourceDb, diagnostics: &Diagnostics) -> String {
    let mut out = String::new();
    for diagnostic in diagnostics.iter() {
        out.push_str(&to_string(db, diagnostic));
    }
    if let Some(summary) = summary(diagnostics) {
        out.push_str(&summary);
        out.push('\n');
    }
    out
}

fn severity_word(severity: Severity) -> &'static str {
    match severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Note => "note",
    }
}

/// The closing line: "error: could not check the KB due to 2 errors; 1 warning emitted".
pub fn summary(diagnostics: &Diagnostics) -> Option<String> {
    let errors = diagnostics.error_count();
    let warnings = diagnostics.warning_count();
    match (errors, warnings) {
        (0, 0) => None,
        (0, w) => Some(format!("warning: {} emitted", plural(w, "warning"))),
        (e, 0) => Some(format!("error: aborting due to {}", plural(e, "error"))),
        (e, w) => Some(format!("error: aborting due to {}; {} emitted", plural(e, "error"), plural(w, "warning"))),
    }
}

/// Writes every diagnostic and the summary to a terminal stream, in colour if `color`.
pub fn emit_to_terminal(db: &SourceDb, diagnostics: &Diagnostics, color: bool) -> io::Result<()> {
    use std::io::Write;
    use term::termcolor::{BufferedStandardStream, ColorChoice, WriteColor};
    let choice = if color { ColorChoice::Always } else { ColorChoice::Never };
    // Buffered: codespan writes a snippet a character at a time, a system call each on a
    // bare stderr (4 s for one diagnostic on a line of 6 MB).
    let mut stream = BufferedStandardStream::stderr(choice);
    let styles = term::Styles::default();
    for diagnostic in diagnostics.iter() {
        let mut writer = term::StylesWriter::new(&mut stream, &styles);
        if term::emit_to_write_style(&mut writer, &config(), db, &to_codespan(db, diagnostic)).is_err() {
            writeln!(stream, "{}: {}", severity_word(diagnostic.severity), diagnostic.message)?;
        }
    }
    if let Some(summary) = summary(diagnostics) {
        if color {
            let spec =
                if diagnostics.has_errors() { styles.header_error.clone() } else { styles.header_warning.clone() };
            let (head, rest) = summary.split_once(':').unwrap_or((&summary, ""));
            stream.set_color(&spec)?;
            write!(stream, "{head}")?;
            stream.reset()?;
            writeln!(stream, ":{rest}")?;
        } else {
            writeln!(stream, "{summary}")?;
        }
    }
    stream.flush()
}

/// A position in the JSON form.
#[derive(serde::Serialize)]
struct JsonRange<'a> {
    file: &'a str,
    byte_start: u32,
    byte_end: u32,
    line_start: u32,
    column_start: u32,
    line_end: u32,
    column_end: u32,
}

impl<'a> JsonRange<'a> {
    fn new(db: &'a SourceDb, span: Span) -> JsonRange<'a> {
        let file = db.file(span.file);
        let start = file.line_col(span.start);
        let end = file.line_col(span.end);
        JsonRange {
            file: file.name(),
            byte_start: span.start,
            byte_end: span.end,
            line_start: start.line,
            column_start: start.column,
            line_end: end.line,
            column_end: end.column,
        }
    }
}

#[derive(serde::Serialize)]
struct JsonLabel<'a> {
    #[serde(flatten)]
    range: JsonRange<'a>,
    message: &'a str,
    primary: bool,
}

#[derive(serde::Serialize)]
struct JsonEdit<'a> {
    #[serde(flatten)]
    range: JsonRange<'a>,
    replacement: &'a str,
}

#[derive(serde::Serialize)]
struct JsonFix<'a> {
    message: &'a str,
    edits: Vec<JsonEdit<'a>>,
}

#[derive(serde::Serialize)]
struct JsonDiagnostic<'a> {
    /// What the line is: always `"diagnostic"` (results of a command are other types), so a
    /// tool reading `--message-format json` can tell them apart, as cargo's `reason` does.
    #[serde(rename = "type")]
    kind: &'static str,
    code: Option<&'a str>,
    severity: Severity,
    message: &'a str,
    #[serde(flatten)]
    range: Option<JsonRange<'a>>,
    labels: Vec<JsonLabel<'a>>,
    notes: &'a [String],
    help: Option<&'a str>,
    fixes: Vec<JsonFix<'a>>,
    rendered: String,
}

/// One diagnostic as a single-line JSON object.
///
/// Fields: `code`, `severity`, `message`, the primary label's `file`, `byte_start`,
/// `byte_end`, `line_start`, `column_start`, `line_end`, `column_end` (1-based, columns in
/// characters), `labels` (each with the same range fields, `message` and `primary`), `notes`,
/// `help`, `fixes` (each a `message` and `edits` with ranges and a `replacement`) and
/// `rendered`, the human form.
pub fn to_json(db: &SourceDb, diagnostic: &Diagnostic) -> String {
    let json = JsonDiagnostic {
        kind: "diagnostic",
        code: diagnostic.code.map(|c| c.as_str()),
        severity: diagnostic.severity,
        message: &diagnostic.message,
        range: diagnostic.primary_span().map(|span| JsonRange::new(db, span)),
        labels: diagnostic
            .labels
            .iter()
            .map(|l| JsonLabel { range: JsonRange::new(db, l.span), message: &l.message, primary: l.primary })
            .collect(),
        notes: &diagnostic.notes,
        help: diagnostic.help.as_deref(),
        fixes: diagnostic
            .fixes
            .iter()
            .map(|f| JsonFix {
                message: &f.message,
                edits: f
                    .edits
                    .iter()
                    .map(|e| JsonEdit { range: JsonRange::new(db, e.span), replacement: &e.replacement })
                    .collect(),
            })
            .collect(),
        rendered: to_string(db, diagnostic),
    };
    serde_json::to_string(&json).expect("diagnostics always serialise")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_label_on_a_very_long_line_becomes_a_note_with_its_position() {
        let mut db = SourceDb::new();
        let long = format!("p :- {}a.\nq.\n", "a, ".repeat(MAX_SNIPPET_LINE));
        let width = crate::diag::group_thousands(long.find('\n').expect("a line") + 1);
        let file = db.add("long.pl", None, long);
        let diagnostic = Diagnostic::error(crate::diag::codes::UNKNOWN_PREDICATE, "unknown predicate `a/0`")
            .primary(Span::new(file, 5, 6), "no clause defines it");
        let text = to_string(&db, &diagnostic);
        assert!(text.contains("at long.pl:1:6: no clause defines it"), "{text}");
        let shown = format!("{width} bytes long");
        assert!(text.contains(&shown) && !text.contains("a, a, a"), "the line is left out:\n{text}");
        // A short line keeps its snippet.
        let short = db.add("short.pl", None, "p :- a.\n".to_string());
        let diagnostic = Diagnostic::error(crate::diag::codes::UNKNOWN_PREDICATE, "unknown predicate `a/0`")
            .primary(Span::new(short, 5, 6), "no clause defines it");
        assert!(to_string(&db, &diagnostic).contains("p :- a."));
    }
}
