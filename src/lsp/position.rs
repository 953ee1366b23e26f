//! Positions as the protocol counts them: zero-based lines and UTF-16 code units.
//!
//! The compiler's spans are byte offsets into UTF-8 text; the Language Server Protocol
//! addresses text by line and UTF-16 column (its default, and the only encoding every client
//! supports). [`Lines`] converts both ways. Lines end as the protocol says: at `\n`, `\r\n`
//! or a lone `\r`, and a line's length excludes its terminator, so a position past the last
//! character of a CRLF line lands before the `\r`. Positions the client sends that are out of range are clamped (past the
//! end of a line to its end, past the last line to the end of the text, inside a surrogate
//! pair to the start of its character), as the protocol asks servers to do.

use lsp_types::{Position, Range};

/// One text and the start of each of its lines, for conversions between byte offsets and
/// protocol positions.
#[derive(Clone, Copy, Debug)]
pub struct Lines<'a> {
    text: &'a str,
    /// Byte offset of the start of each line; the first is 0.
    starts: &'a [u32],
}

impl<'a> Lines<'a> {
    /// `text` with its line starts (from [`line_starts`]).
    pub fn new(text: &'a str, starts: &'a [u32]) -> Lines<'a> {
        Lines { text, starts }
    }

    /// The protocol position of byte `offset`. An offset inside a character counts as that
    /// character's start.
    pub fn position(&self, offset: usize) -> Position {
        let offset = offset.min(self.text.len());
        let line = self.starts.partition_point(|&start| start as usize <= offset) - 1;
        let start = self.starts[line] as usize;
        let mut column = 0u32;
        for (at, c) in self.text[start..].char_indices() {
            if start + at + c.len_utf8() > offset {
                break;
            }
            column += c.len_utf16() as u32;
        }
        Position { line: line as u32, character: column }
    }

    /// The byte offset of `position`, clamped as the module header says.
    pub fn offset(&self, position: Position) -> usize {
        let line = position.line as usize;
        if line >= self.starts.len() {
            return self.text.len();
        }
        let start = self.starts[line] as usize;
        let end = self.line_end(line);
        let mut column = 0u32;
        for (at, c) in self.text[start..end].char_indices() {
            let width = c.len_utf16() as u32;
            if column + width > position.character {
                return start + at;
            }
            column += width;
        }
        end
    }

    /// The byte range of a protocol range (its ends clamped; a reversed range is emptied).
    pub fn offsets(&self, range: Range) -> std::ops::Range<usize> {
        let start = self.offset(range.start);
        let end = self.offset(range.end).max(start);
        start..end
    }

    /// The protocol range of a byte range.
    pub fn range(&self, bytes: std::ops::Range<usize>) -> Range {
        Range { start: self.position(bytes.start), end: self.position(bytes.end) }
    }

    /// Where line `line`'s text ends: before its terminator.
    fn line_end(&self, line: usize) -> usize {
        let Some(&next) = self.starts.get(line + 1) else {
            return self.text.len();
        };
        let start = self.starts[line] as usize;
        let bytes = self.text.as_bytes();
        let mut end = next as usize - 1;
        if bytes[end] == b'\n' && end > start && bytes[end - 1] == b'\r' {
            end -= 1;
        }
        end
    }
}

/// The byte offset at which each protocol line of `text` starts (after `\n`, `\r\n` or a lone
/// `\r`); the first is 0.
pub fn line_starts(text: &str) -> Vec<u32> {
    let bytes = text.as_bytes();
    let mut starts = vec![0];
    for (at, &byte) in bytes.iter().enumerate() {
        if byte == b'\n' || (byte == b'\r' && bytes.get(at + 1) != Some(&b'\n')) {
            starts.push(at as u32 + 1);
        }
    }
    starts
}

/// Applies one `textDocument/didChange` edit: the text between the range's ends becomes
/// `replacement`. Returns the new text.
pub fn apply_edit(text: &str, range: Range, replacement: &str) -> String {
    let starts = line_starts(text);
    let bytes = Lines::new(text, &starts).offsets(range);
    let mut out = String::with_capacity(text.len() - bytes.len() + replacement.len());
    out.push_str(&text[..bytes.start]);
    out.push_str(replacement);
    out.push_str(&text[bytes.end..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pos(line: u32, character: u32) -> Position {
        Position { line, character }
    }

    #[test]
    fn ascii_offsets_and_positions_agree() {
        let text = "on(a, b).\nclear(a).\n";
        let starts = line_starts(text);
        let index = Lines::new(text, &starts);
        assert_eq!(index.position(0), pos(0, 0));
        assert_eq!(index.position(3), pos(0, 3));
        assert_eq!(index.position(10), pos(1, 0));
        assert_eq!(index.position(text.len()), pos(2, 0));
        for offset in 0..=text.len() {
            assert_eq!(index.offset(index.position(offset)), offset);
        }
    }

    #[test]
    fn columns_count_utf16_units_not_bytes() {
        // `é` is 2 bytes and 1 UTF-16 unit; `🤖` is 4 bytes and 2 units (a surrogate pair).
        let text = "% é🤖x\nfoo.";
        let starts = line_starts(text);
        let index = Lines::new(text, &starts);
        let x = text.find('x').unwrap();
        assert_eq!(x, 8);
        assert_eq!(index.position(x), pos(0, 5));
        assert_eq!(index.offset(pos(0, 5)), x);
        let robot = text.find('🤖').unwrap();
        assert_eq!(index.position(robot), pos(0, 3));
        // Inside the surrogate pair: the start of the character.
        assert_eq!(index.offset(pos(0, 4)), robot);
        // Inside the character's bytes: its start.
        assert_eq!(index.position(robot + 2), pos(0, 3));
    }

    #[test]
    fn out_of_range_positions_are_clamped() {
        let text = "ab\r\ncd";
        let starts = line_starts(text);
        let index = Lines::new(text, &starts);
        // Past the end of a CRLF line: before the `\r`.
        assert_eq!(index.offset(pos(0, 99)), 2);
        assert_eq!(index.offset(pos(1, 99)), text.len());
        assert_eq!(index.offset(pos(7, 0)), text.len());
        assert_eq!(index.position(99), pos(1, 2));
        let reversed = Range { start: pos(1, 1), end: pos(0, 0) };
        assert_eq!(index.offsets(reversed), 5..5);
    }

    #[test]
    fn a_lone_carriage_return_ends_a_line() {
        let text = "a\rb\r\nc\nd";
        assert_eq!(line_starts(text), [0, 2, 5, 7]);
        let starts = line_starts(text);
        let index = Lines::new(text, &starts);
        assert_eq!(index.position(2), pos(1, 0));
        assert_eq!(index.offset(pos(0, 9)), 1);
        assert_eq!(index.offset(pos(1, 9)), 3);
        assert_eq!(index.offset(pos(2, 9)), 6);
    }

    #[test]
    fn edits_replace_the_range() {
        let text = "on(a, b).\nclaer(a).\n";
        let fixed = apply_edit(text, Range { start: pos(1, 2), end: pos(1, 4) }, "ea");
        assert_eq!(fixed, "on(a, b).\nclear(a).\n");
        let inserted = apply_edit("é.", Range { start: pos(0, 1), end: pos(0, 1) }, "x");
        assert_eq!(inserted, "éx.");
        assert_eq!(apply_edit("", Range { start: pos(0, 0), end: pos(0, 0) }, "a."), "a.");
    }
}
