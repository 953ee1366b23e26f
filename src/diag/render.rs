//! Rendering diagnostics for people (codespan-reporting, rustc's layout) and for tools (JSON).
//!
//! Rendering is pure: it writes into any `io::Write` or returns a `String`. Whether to use
//! colour is the caller's decision (the CLI checks that stderr is a terminal).

use std::io;

use codespan_reporting::diagnostic as cs;
use codespan_reporting::term;

use super::{Diagnostic, Diagnostics, Severity, plural};
use crate::source::{SourceDb, Span};

fn to_codespan(diagnostic: &Diagnostic) -> cs::Diagnostic<crate::source::FileId> {
    let severity = match diagnostic.severity {
        Severity::Error => cs::Severity::Error,
        Severity::Warning => cs::Severity::Warning,
        Severity::Note => cs::Severity::Note,
    };
    let mut out = cs::Diagnostic::new(severity).with_message(&diagnostic.message);
    if let Some(code) = diagnostic.code {
        out = out.with_code(code.as_str());
    }
    let labels = diagnostic
        .labels
        .iter()
        .map(|label| {
            let style = if label.primary { cs::LabelStyle::Primary } else { cs::LabelStyle::Secondary };
            cs::Label::new(style, label.span.file, label.span.range()).with_message(&label.message)
        })
        .collect();
    let mut notes: Vec<String> = diagnostic.notes.iter().map(|n| format!("note: {n}")).collect();
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
    term::emit_into_string(&config(), db, &to_codespan(diagnostic))
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
        if term::emit_to_write_style(&mut writer, &config(), db, &to_codespan(diagnostic)).is_err() {
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
