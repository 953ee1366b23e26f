//! Source text and positions: the only way text enters the compiler.
//!
//! A [`SourceDb`] owns every file the compiler has read, addressed by a small [`FileId`].
//! Positions are [`Span`]s of byte offsets into one file's text, so they are cheap to copy
//! into every node of every IR. Line and column numbers are computed on demand from a line
//! index built once per file; they are for people (diagnostics, JSON) and never used by passes.
//!
//! The session fills the database (from disk through [`fs`], or from the editor's buffers);
//! passes only read it, and reach included files through `passes::load::SourceLoader`.

pub mod fs;

use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Identifies one file in a [`SourceDb`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FileId(pub u32);

/// A half-open byte range `start..end` in one file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Span {
    /// The file the bytes belong to.
    pub file: FileId,
    /// Offset of the first byte.
    pub start: u32,
    /// Offset one past the last byte.
    pub end: u32,
}

impl Span {
    /// A span from `start` to `end` in `file`.
    pub fn new(file: FileId, start: u32, end: u32) -> Span {
        debug_assert!(start <= end, "span start {start} after end {end}");
        Span { file, start, end }
    }

    /// An empty span at `offset`, used for insertion points ("add `.` here").
    pub fn point(file: FileId, offset: u32) -> Span {
        Span { file, start: offset, end: offset }
    }

    /// The smallest span covering both `self` and `other` (same file).
    pub fn to(self, other: Span) -> Span {
        debug_assert_eq!(self.file, other.file, "joining spans of different files");
        Span { file: self.file, start: self.start.min(other.start), end: self.end.max(other.end) }
    }

    /// The byte range as `usize`, for slicing text.
    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }

    /// True when the span covers no bytes.
    pub fn is_empty(self) -> bool {
        self.start == self.end
    }
}

/// A 1-based line and column; the column counts Unicode scalar values, as rustc's does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct LineCol {
    /// Line number, starting at 1.
    pub line: u32,
    /// Column number, starting at 1, in characters.
    pub column: u32,
}

/// One file's name, text and line index.
#[derive(Debug)]
pub struct SourceFile {
    name: String,
    path: Option<PathBuf>,
    text: Arc<str>,
    line_starts: Vec<u32>,
}

impl SourceFile {
    fn new(name: String, path: Option<PathBuf>, text: Arc<str>) -> SourceFile {
        let line_starts = line_starts(&text);
        SourceFile { name, path, text, line_starts }
    }

    /// The name shown to people: the path as given on the command line, or `<std>/blocks.pl`.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The file's location on disk, when it has one; includes are resolved relative to it.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The whole text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The text shared, for callers that keep it beyond the database's borrow.
    pub fn text_arc(&self) -> Arc<str> {
        self.text.clone()
    }

    /// Byte offsets at which each line starts; the first is always 0.
    pub fn line_starts(&self) -> &[u32] {
        &self.line_starts
    }

    /// The 0-based line index containing `offset` (offsets past the end map to the last line).
    pub fn line_index(&self, offset: u32) -> usize {
        match self.line_starts.binary_search(&offset) {
            Ok(line) => line,
            Err(next) => next - 1,
        }
    }

    /// The byte range of the 0-based line `line`, including its line terminator.
    pub fn line_range(&self, line: usize) -> std::ops::Range<usize> {
        let start = self.line_starts.get(line).copied().unwrap_or(self.text.len() as u32) as usize;
        let end = self.line_starts.get(line + 1).copied().unwrap_or(self.text.len() as u32) as usize;
        start..end
    }

    /// The 1-based line and character column of `offset`.
    pub fn line_col(&self, offset: u32) -> LineCol {
        let offset = offset.min(self.text.len() as u32);
        let line = self.line_index(offset);
        let line_start = self.line_starts[line] as usize;
        let offset = floor_char_boundary(&self.text, offset as usize);
        let column = self.text[line_start..offset].chars().count() as u32 + 1;
        LineCol { line: line as u32 + 1, column }
    }
}

fn floor_char_boundary(text: &str, mut offset: usize) -> usize {
    while offset > 0 && !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

fn line_starts(text: &str) -> Vec<u32> {
    let mut starts = vec![0];
    starts.extend(text.bytes().enumerate().filter(|&(_, b)| b == b'\n').map(|(i, _)| i as u32 + 1));
    starts
}

/// Every file the compiler has seen in this session.
#[derive(Debug, Default)]
pub struct SourceDb {
    files: Vec<SourceFile>,
}

/// The largest file the compiler accepts: spans are 32-bit byte offsets.
pub const MAX_FILE_LEN: usize = u32::MAX as usize - 1;

impl SourceDb {
    /// An empty database.
    pub fn new() -> SourceDb {
        SourceDb::default()
    }

    /// Adds a file and returns its id. `path` is where it lives on disk, if anywhere.
    ///
    /// # Panics
    /// If the text is longer than [`MAX_FILE_LEN`]; callers check the length first and report
    /// an over-long file as a diagnostic.
    pub fn add(&mut self, name: impl Into<String>, path: Option<PathBuf>, text: impl Into<Arc<str>>) -> FileId {
        let text = text.into();
        assert!(text.len() <= MAX_FILE_LEN, "source file longer than 4 GiB");
        let id = FileId(self.files.len() as u32);
        self.files.push(SourceFile::new(name.into(), path, text));
        id
    }

    /// Replaces a file's text (an editor buffer changed), keeping its id.
    pub fn set_text(&mut self, file: FileId, text: impl Into<Arc<str>>) {
        let entry = &mut self.files[file.0 as usize];
        *entry = SourceFile::new(std::mem::take(&mut entry.name), entry.path.take(), text.into());
    }

    /// The file behind `id`.
    pub fn file(&self, id: FileId) -> &SourceFile {
        &self.files[id.0 as usize]
    }

    /// The text of `id`.
    pub fn text(&self, id: FileId) -> &str {
        self.file(id).text()
    }

    /// The text a span covers.
    pub fn snippet(&self, span: Span) -> &str {
        &self.text(span.file)[span.range()]
    }

    /// Looks a file up by its on-disk path.
    pub fn find_path(&self, path: &Path) -> Option<FileId> {
        self.files.iter().position(|f| f.path.as_deref() == Some(path)).map(|i| FileId(i as u32))
    }

    /// All file ids, in the order they were added.
    pub fn ids(&self) -> impl Iterator<Item = FileId> + '_ {
        (0..self.files.len() as u32).map(FileId)
    }

    /// The number of files.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// True when no file has been added.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }
}

impl<'a> codespan_reporting::files::Files<'a> for SourceDb {
    type FileId = FileId;
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, id: FileId) -> Result<&'a str, codespan_reporting::files::Error> {
        self.files.get(id.0 as usize).map(|f| f.name.as_str()).ok_or(codespan_reporting::files::Error::FileMissing)
    }

    fn source(&'a self, id: FileId) -> Result<&'a str, codespan_reporting::files::Error> {
        self.files.get(id.0 as usize).map(|f| f.text()).ok_or(codespan_reporting::files::Error::FileMissing)
    }

    fn line_index(&'a self, id: FileId, byte_index: usize) -> Result<usize, codespan_reporting::files::Error> {
        let file = self.files.get(id.0 as usize).ok_or(codespan_reporting::files::Error::FileMissing)?;
        Ok(file.line_index(byte_index.min(u32::MAX as usize) as u32))
    }

    fn line_range(
        &'a self,
        id: FileId,
        line_index: usize,
    ) -> Result<std::ops::Range<usize>, codespan_reporting::files::Error> {
        let file = self.files.get(id.0 as usize).ok_or(codespan_reporting::files::Error::FileMissing)?;
        if line_index >= file.line_starts.len() {
            return Err(codespan_reporting::files::Error::LineTooLarge {
                given: line_index,
                max: file.line_starts.len() - 1,
            });
        }
        Ok(file.line_range(line_index))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_characters_not_bytes() {
        let mut db = SourceDb::new();
        let id = db.add("t.pl", None, "ab\nçé x\n");
        let file = db.file(id);
        assert_eq!(file.line_col(0), LineCol { line: 1, column: 1 });
        assert_eq!(file.line_col(3), LineCol { line: 2, column: 1 });
        // `x` is at byte 3 + 2 + 2 + 1 = 8, the fourth character of line 2.
        assert_eq!(file.line_col(8), LineCol { line: 2, column: 4 });
        // An offset inside a multi-byte character maps to that character.
        assert_eq!(file.line_col(4), LineCol { line: 2, column: 1 });
    }

    #[test]
    fn offsets_past_the_end_map_to_the_last_line() {
        let mut db = SourceDb::new();
        let id = db.add("t.pl", None, "a.\nb.");
        assert_eq!(db.file(id).line_col(100), LineCol { line: 2, column: 3 });
    }
}
