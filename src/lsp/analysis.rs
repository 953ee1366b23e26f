//! One check of a set of files, kept for answering requests until the next.
//!
//! An [`Analysis`] is the front end's result over a unit's root files (open buffers in place
//! of their disk contents), the [`Index`] of its names, and the conversions between its spans
//! and protocol locations. It owns its copy of every text it checked, so its positions stay
//! consistent even after the editor's buffers move on.

use std::path::{Path, PathBuf};

use lsp_types::{
    Diagnostic as LspDiagnostic, DiagnosticRelatedInformation, DiagnosticSeverity, DiagnosticTag, Location,
    NumberOrString, Position, Range, Url,
};

use crate::diag::{Diagnostic, Diagnostics, Severity, codes};
use crate::passes::load::{LoadedText, SourceLoader};
use crate::session::{Frontend, Session};
use crate::source::fs::FsLoader;
use crate::source::{FileId, SourceDb, Span};

use super::index::Index;
use super::position::{self, Lines};

/// A checked unit.
pub struct Analysis {
    /// Every file read, including std's when the unit uses it.
    pub db: SourceDb,
    /// The front end's output.
    pub frontend: Frontend,
    /// The front end's diagnostics, sorted by position.
    pub diagnostics: Diagnostics,
    /// Where each name occurs.
    pub index: Index,
    /// The root files, in the order they were given.
    pub roots: Vec<FileId>,
    /// Each file's URI, for files that have a path.
    uris: Vec<Option<Url>>,
    /// Each file's protocol line starts.
    line_starts: Vec<Vec<u32>>,
}

/// A root file to check.
pub struct RootText {
    /// The document.
    pub uri: Url,
    /// Its path (canonical where the file exists); `None` for documents that are not files.
    pub path: Option<PathBuf>,
    /// The text: the open buffer's, or the disk's.
    pub text: String,
}

impl Analysis {
    /// Checks `roots` together; included files come from `loader` (which prefers open buffers).
    /// `base` shortens file names in messages (paths relative to the workspace folder).
    pub fn run(roots: Vec<RootText>, loader: &mut dyn SourceLoader, base: Option<&Path>) -> Analysis {
        let mut db = SourceDb::new();
        let mut root_uris = Vec::new();
        let root_ids: Vec<FileId> = roots
            .into_iter()
            .map(|root| {
                let name = match &root.path {
                    Some(path) => display_name(path, base),
                    None => root.uri.to_string(),
                };
                root_uris.push(root.uri);
                db.add(name, root.path, root.text)
            })
            .collect();
        let (db, frontend, diagnostics) = Session::open(db, &root_ids, loader).into_parts();
        let index = Index::build(&frontend.kb, &frontend.loaded);
        let uris = db
            .ids()
            .map(|id| match root_ids.iter().position(|&r| r == id) {
                Some(i) => Some(root_uris[i].clone()),
                None => db.file(id).path().and_then(|p| Url::from_file_path(p).ok()),
            })
            .collect();
        let line_starts = db.ids().map(|id| position::line_starts(db.text(id))).collect();
        Analysis { db, frontend, diagnostics, index, roots: root_ids, uris, line_starts }
    }

    /// The file with this URI, if the unit read it.
    pub fn file_of(&self, uri: &Url) -> Option<FileId> {
        self.uris.iter().position(|u| u.as_ref() == Some(uri)).map(|i| FileId(i as u32))
    }

    /// The URI of a file that has a path.
    pub fn uri(&self, file: FileId) -> Option<&Url> {
        self.uris.get(file.0 as usize).and_then(Option::as_ref)
    }

    /// Every file with a URI.
    pub fn uris(&self) -> impl Iterator<Item = &Url> {
        self.uris.iter().flatten()
    }

    /// Paths this unit read through `include`/`ensure_loaded` (a root included by another root
    /// counts), so the workspace does not check them again as roots of their own.
    pub fn included_paths(&self) -> Vec<PathBuf> {
        let mut visits = vec![0usize; self.db.len()];
        for ast in &self.frontend.loaded.files {
            visits[ast.file.0 as usize] += 1;
        }
        self.db
            .ids()
            .filter(|&id| visits[id.0 as usize] > usize::from(self.roots.contains(&id)))
            .filter_map(|id| self.db.file(id).path().map(Path::to_path_buf))
            .collect()
    }

    /// Position conversions for one file.
    pub fn lines(&self, file: FileId) -> Lines<'_> {
        Lines::new(self.db.text(file), &self.line_starts[file.0 as usize])
    }

    /// The protocol range of a span.
    pub fn range(&self, span: Span) -> Range {
        self.lines(span.file).range(span.range())
    }

    /// The byte offset of a protocol position in `file`.
    pub fn offset(&self, file: FileId, position: Position) -> u32 {
        self.lines(file).offset(position) as u32
    }

    /// The location of a span, for files that have a URI.
    pub fn location(&self, span: Span) -> Option<Location> {
        Some(Location { uri: self.uri(span.file)?.clone(), range: self.range(span) })
    }

    /// The compiler's diagnostics whose primary label is in `file`, plus, for the first root,
    /// the errors and warnings that point nowhere.
    pub fn diagnostics_in(&self, file: FileId) -> impl Iterator<Item = &Diagnostic> {
        let first_root = self.roots.first() == Some(&file);
        self.diagnostics.iter().filter(move |d| match d.primary_span() {
            Some(span) => span.file == file,
            None => first_root && d.severity != Severity::Note,
        })
    }

    /// A compiler diagnostic as the protocol's.
    pub fn to_lsp(&self, diagnostic: &Diagnostic) -> LspDiagnostic {
        let range = diagnostic.primary_span().map_or_else(Range::default, |span| self.range(span));
        let mut message = diagnostic.message.clone();
        if let Some(label) = diagnostic.labels.iter().find(|l| l.primary && !l.message.is_empty()) {
            message.push_str(&format!("\n{}", label.message));
        }
        for note in &diagnostic.notes {
            message.push_str(&format!("\nnote: {note}"));
        }
        if let Some(help) = &diagnostic.help {
            message.push_str(&format!("\nhelp: {help}"));
        }
        let related: Vec<DiagnosticRelatedInformation> = diagnostic
            .labels
            .iter()
            .filter(|l| !l.primary)
            .filter_map(|l| {
                let message = if l.message.is_empty() { "related".to_string() } else { l.message.clone() };
                Some(DiagnosticRelatedInformation { location: self.location(l.span)?, message })
            })
            .collect();
        let unused = matches!(diagnostic.code, Some(code) if code == codes::SINGLETON_VARIABLE);
        LspDiagnostic {
            range,
            severity: Some(match diagnostic.severity {
                Severity::Error => DiagnosticSeverity::ERROR,
                Severity::Warning => DiagnosticSeverity::WARNING,
                Severity::Note => DiagnosticSeverity::INFORMATION,
            }),
            code: diagnostic.code.map(|c| NumberOrString::String(c.as_str().to_string())),
            code_description: None,
            source: Some("kbc".to_string()),
            message,
            related_information: (!related.is_empty()).then_some(related),
            tags: unused.then(|| vec![DiagnosticTag::UNNECESSARY]),
            data: None,
        }
    }
}

/// A path as messages show it: relative to the workspace folder when inside it.
fn display_name(path: &Path, base: Option<&Path>) -> String {
    base.and_then(|b| path.strip_prefix(b).ok()).unwrap_or(path).display().to_string()
}

/// Serves included files from the editor's open buffers, and from disk otherwise.
pub struct OverlayLoader<'a> {
    /// Open buffers by canonical path.
    pub open: &'a dyn Fn(&Path) -> Option<String>,
}

impl SourceLoader for OverlayLoader<'_> {
    fn load(&mut self, path: &Path) -> Result<LoadedText, String> {
        let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        if let Some(text) = (self.open)(&canonical) {
            return Ok(LoadedText { canonical, text });
        }
        FsLoader.load(path)
    }
}
