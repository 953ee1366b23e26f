//! The lexer: KB text to [`Token`]s, in two steps.
//!
//! 1. A logos DFA splits the text into raw tokens (names, variables, numbers, quoted atoms,
//!    symbol-character sequences, punctuation) and skips layout and comments.
//! 2. "Cooking" resolves what Prolog decides by adjacency and context, which a DFA cannot see:
//!    a name immediately followed by `(` is a functor (`f(` versus `f (`); a `-` directly
//!    before a number in prefix position is a negative literal; a `.` followed by layout is the
//!    end of a clause; a symbol sequence is an operator of the fixed table or a plain atom.
//!    Cooking also turns foreign operators (`!=`, `<=`, `&&`) into diagnostics with a fix and
//!    recovers as if the fix had been applied, so one slip does not hide the rest of the file.
//!
//! Tokens carry byte offsets plus two layout facts the parser's recovery needs: whether the
//! token starts a line, and whether it starts in column 0 (where a new clause usually begins).

use logos::Logos;

use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::intern::{Interner, Symbol, sym};
use crate::source::{FileId, Span};

/// A 64-bit number stored as two 32-bit halves, so that a [`Tok`] is 4-byte aligned: 12 bytes,
/// and a [`Token`] 24 rather than 32 (a clause of three million tokens holds them all at once).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Word64([u32; 2]);

impl Word64 {
    /// An integer's bits.
    pub fn int(value: i64) -> Word64 {
        let bits = value as u64;
        Word64([bits as u32, (bits >> 32) as u32])
    }

    /// A float's bits.
    pub fn float(value: f64) -> Word64 {
        let bits = value.to_bits();
        Word64([bits as u32, (bits >> 32) as u32])
    }

    fn bits(self) -> u64 {
        u64::from(self.0[0]) | (u64::from(self.0[1]) << 32)
    }

    /// The integer.
    pub fn as_int(self) -> i64 {
        self.bits() as i64
    }

    /// The float.
    pub fn as_float(self) -> f64 {
        f64::from_bits(self.bits())
    }
}

/// A cooked token, as the grammar sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tok {
    /// A name atom: `foo`, `'a b'`, `!`.
    Name(Symbol),
    /// An atom of symbol characters that is not an operator of the table, such as `@<`.
    /// Unlike a name it never counts as a term beside another term, so `X @< Y` is reported as
    /// an unsupported operator rather than as missing commas.
    SymbolAtom(Symbol),
    /// A name immediately followed by `(`: the start of a compound term.
    Functor(Symbol),
    /// A variable, including `_`.
    Var(Symbol),
    /// An integer.
    Int(Word64),
    /// A float.
    Float(Word64),
    /// A double-quoted string (its contents, unescaped).
    Str(Symbol),
    /// `(`
    Open,
    /// `)`
    Close,
    /// `[`
    OpenList,
    /// `]`
    CloseList,
    /// `|` inside a list.
    Bar,
    /// `,`
    Comma,
    /// An operator of the fixed table (other than `,`), by its symbol.
    Op(Symbol),
    /// The `.` that ends a clause.
    End,
}

impl Tok {
    /// True if this token can be the last token of a term (so a term cannot start right after).
    pub fn ends_term(&self) -> bool {
        matches!(
            self,
            Tok::Name(_) | Tok::Var(_) | Tok::Int(_) | Tok::Float(_) | Tok::Str(_) | Tok::Close | Tok::CloseList
        )
    }

    /// True if this token always starts a new term: two terms side by side with nothing
    /// between them is never valid, which is how a missing `,` or `.` is recognised.
    pub fn starts_term(&self) -> bool {
        matches!(
            self,
            Tok::Name(_) | Tok::Functor(_) | Tok::Var(_) | Tok::Int(_) | Tok::Float(_) | Tok::Str(_) | Tok::OpenList
        )
    }

    /// A short description for "expected X, found Y" messages.
    pub fn describe(&self, interner: &Interner) -> String {
        match self {
            Tok::Name(s) => format!("atom `{}`", interner.resolve(*s)),
            Tok::SymbolAtom(s) => format!("`{}`", interner.resolve(*s)),
            Tok::Functor(s) => format!("`{}(`", interner.resolve(*s)),
            Tok::Var(s) => format!("variable `{}`", interner.resolve(*s)),
            Tok::Int(i) => format!("integer `{}`", i.as_int()),
            Tok::Float(f) => format!("number `{:?}`", f.as_float()),
            Tok::Str(_) => "a string".to_string(),
            Tok::Open => "`(`".to_string(),
            Tok::Close => "`)`".to_string(),
            Tok::OpenList => "`[`".to_string(),
            Tok::CloseList => "`]`".to_string(),
            Tok::Bar => "`|`".to_string(),
            Tok::Comma => "`,`".to_string(),
            Tok::Op(s) => format!("operator `{}`", interner.resolve(*s)),
            Tok::End => "`.`".to_string(),
        }
    }
}

/// A token with its position and layout facts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Token {
    /// What it is.
    pub tok: Tok,
    /// Byte offset of its first character.
    pub start: u32,
    /// Byte offset one past its last character.
    pub end: u32,
    /// True if it is the first token on its line.
    pub line_start: bool,
    /// True if it starts in column 0.
    pub column0: bool,
    /// True if the parser's recovery inserted it; it has no text.
    pub virtual_: bool,
}

impl Token {
    /// An inserted token at `offset`, covering no text.
    pub fn inserted(tok: Tok, offset: u32) -> Token {
        Token { tok, start: offset, end: offset, line_start: false, column0: false, virtual_: true }
    }
}

/// Errors the raw lexer reports; cooked into diagnostics.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
enum RawError {
    #[default]
    UnexpectedCharacter,
    UnterminatedComment,
}

#[derive(Logos, Clone, Copy, Debug, PartialEq)]
#[logos(error = RawError)]
#[logos(skip r"[ \t\r\n\x0C]+")]
#[logos(skip(r"%[^\n]*", allow_greedy = true))]
enum Raw {
    #[token("/*", block_comment)]
    BlockComment,
    #[regex(r"[a-z][a-zA-Z0-9_]*")]
    Name,
    #[regex(r"[A-Z_][a-zA-Z0-9_]*")]
    Var,
    // SWI-Prolog's digit groups: `1_000_000` is 1000000.
    #[regex(r"[0-9]+(_[0-9]+)*")]
    Int,
    #[regex(r"0x[0-9a-fA-F]+|0o[0-7]+|0b[01]+")]
    RadixInt,
    #[regex(r"0'([^\\'\n]|\\[ntr\\'0]|'')")]
    CharCode,
    #[regex(r"[0-9]+\.[0-9]+([eE][+-]?[0-9]+)?|[0-9]+[eE][+-]?[0-9]+")]
    Float,
    #[regex(r"'([^'\\\n]|\\[^\n]|'')*'")]
    Quoted,
    #[regex(r"'([^'\\\n]|\\[^\n]|'')*", allow_greedy = true)]
    UnterminatedQuoted,
    #[regex(r#""([^"\\\n]|\\[^\n]|"")*""#)]
    Str,
    #[regex(r#""([^"\\\n]|\\[^\n]|"")*"#, allow_greedy = true)]
    UnterminatedStr,
    #[regex(r"[+\-*/\\^<>=~:.?@#&$]", symbol_run)]
    Symbolic,
    #[token("!=")]
    BangEq,
    #[token("!")]
    Cut,
    #[token(",")]
    Comma,
    #[token("|")]
    Bar,
    #[token(";")]
    Semi,
    #[token("(")]
    Open,
    #[token(")")]
    Close,
    #[token("[")]
    OpenList,
    #[token("]")]
    CloseList,
    #[token("{")]
    OpenCurly,
    #[token("}")]
    CloseCurly,
}

/// Skips a block comment; an unterminated one is an error covering the rest of the file.
fn block_comment(lex: &mut logos::Lexer<Raw>) -> logos::FilterResult<(), RawError> {
    match lex.remainder().find("*/") {
        Some(end) => {
            lex.bump(end + 2);
            logos::FilterResult::Skip
        }
        None => {
            lex.bump(lex.remainder().len());
            logos::FilterResult::Error(RawError::UnterminatedComment)
        }
    }
}

fn is_symbol_char(c: u8) -> bool {
    matches!(
        c,
        b'+' | b'-'
            | b'*'
            | b'/'
            | b'\\'
            | b'^'
            | b'<'
            | b'>'
            | b'='
            | b'~'
            | b':'
            | b'.'
            | b'?'
            | b'@'
            | b'#'
            | b'&'
            | b'$'
    )
}

/// Extends a symbol-character run greedily, stopping before a `/*` that starts a comment.
fn symbol_run(lex: &mut logos::Lexer<Raw>) {
    let rest = lex.remainder().as_bytes();
    let mut n = 0;
    while n < rest.len() && is_symbol_char(rest[n]) {
        if rest[n] == b'/' && rest.get(n + 1) == Some(&b'*') {
            break;
        }
        n += 1;
    }
    lex.bump(n);
}

/// The result of lexing one file.
pub struct Lexed {
    /// The cooked tokens, `End` included.
    pub tokens: Vec<Token>,
}

#[derive(Clone, Copy)]
struct RawToken<'a> {
    raw: Result<Raw, RawError>,
    start: u32,
    end: u32,
    /// The token's text, as logos sliced it.
    text: &'a str,
}

/// Lexes and cooks all of `text` at once. The parser streams tokens through [`Lexer`] instead,
/// so a large file never holds all its tokens in memory.
pub fn lex(file: FileId, text: &str, interner: &mut Interner, diags: &mut Diagnostics) -> Lexed {
    Lexed { tokens: Lexer::new(file, text, interner, diags).collect() }
}

fn raw_tokens(text: &str, offset: u32) -> Vec<RawToken<'_>> {
    Raw::lexer(text)
        .spanned()
        .map(|(raw, range)| RawToken {
            raw,
            start: offset + range.start as u32,
            end: offset + range.end as u32,
            text: &text[range],
        })
        .collect()
}

/// Ends an unterminated quoted atom or string before the closing brackets and `.` that end
/// its line, and lexes those again: in `name(a1, 'left arm).` the quote was surely meant to
/// close before `).`, and reading it that way leaves one error instead of three.
fn recover_unterminated_quote<'a>(text: &'a str, raw: RawToken<'a>, out: &mut Vec<RawToken<'a>>) {
    let body = raw.text;
    let kept = body.trim_end_matches([')', ']', ',', '.', ' ', '\t', '\r']).len();
    if kept <= 1 || kept == body.len() {
        out.push(raw);
        return;
    }
    let cut = raw.start + kept as u32;
    out.push(RawToken { end: cut, text: &body[..kept], ..raw });
    out.extend(raw_tokens(&text[cut as usize..raw.end as usize], cut));
}

/// The cooking lexer: an iterator of [`Token`]s over one file's text.
///
/// It reads raw tokens from the logos DFA into a small look-ahead window (one token is enough
/// except for `{...}` groups) and cooks them one at a time.
pub struct Lexer<'a> {
    file: FileId,
    text: &'a str,
    interner: &'a mut Interner,
    diags: &'a mut Diagnostics,
    source: logos::SpannedIter<'a, Raw>,
    /// Raw tokens to read before the source's next ones, the next one last: pieces of an
    /// unterminated quote lexed again, and tokens looked at in vain for a `}`.
    stash: Vec<RawToken<'a>>,
    /// The last token produced and where it ended.
    previous: Option<Tok>,
    previous_end: u32,
}

impl<'a> Lexer<'a> {
    /// A lexer over `text`, reporting lexical problems into `diags`.
    pub fn new(file: FileId, text: &'a str, interner: &'a mut Interner, diags: &'a mut Diagnostics) -> Lexer<'a> {
        // Most tokens of a large KB are names; reserving ahead avoids rehashing as it grows.
        interner.reserve(text.len() / 8, text.len() / 2);
        Lexer {
            file,
            text,
            interner,
            diags,
            source: Raw::lexer(text).spanned(),
            stash: Vec::new(),
            previous: None,
            previous_end: 0,
        }
    }

    /// The next raw token.
    #[inline]
    fn raw(&mut self) -> Option<RawToken<'a>> {
        if let Some(token) = self.stash.pop() {
            return Some(token);
        }
        let (raw, range) = self.source.next()?;
        let token = RawToken { raw, start: range.start as u32, end: range.end as u32, text: self.source.slice() };
        if matches!(raw, Ok(Raw::UnterminatedQuoted | Raw::UnterminatedStr)) {
            let mut pieces = Vec::new();
            recover_unterminated_quote(self.text, token, &mut pieces);
            let first = pieces.remove(0);
            self.stash.extend(pieces.into_iter().rev());
            return Some(first);
        }
        Some(token)
    }

    /// The byte at `offset`, if the text is that long.
    #[inline]
    fn byte_at(&self, offset: u32) -> Option<u8> {
        self.text.as_bytes().get(offset as usize).copied()
    }
}

impl Lexer<'_> {
    /// The interner and the diagnostics sink, for the parser to use between tokens.
    pub fn parts(&mut self) -> (&Interner, &mut Diagnostics) {
        (self.interner, self.diags)
    }
}

impl Iterator for Lexer<'_> {
    type Item = Token;

    fn next(&mut self) -> Option<Token> {
        loop {
            let current = self.raw()?;
            if let Some(token) = self.cook(current) {
                return Some(token);
            }
        }
    }
}

impl Lexer<'_> {
    fn span(&self, start: u32, end: u32) -> Span {
        Span::new(self.file, start, end)
    }

    /// The token `tok` at `start..end`, remembered as the previous one.
    ///
    /// Tokens are returned by value all the way out of `next`: storing one in the lexer and
    /// reading it back at once stalled store-to-load forwarding (narrow stores, wide loads)
    /// and cost a fifth of the front end's time on large KBs.
    #[inline]
    fn push(&mut self, tok: Tok, start: u32, end: u32) -> Option<Token> {
        let bytes = self.text.as_bytes();
        let line_start = self.previous.is_none() || bytes[self.previous_end as usize..start as usize].contains(&b'\n');
        let column0 = start == 0 || bytes[start as usize - 1] == b'\n';
        self.previous = Some(tok);
        self.previous_end = end;
        Some(Token { tok, start, end, line_start, column0, virtual_: false })
    }

    /// True if a `(` follows the token ending at `end` with no layout between.
    #[inline]
    fn directly_followed_by_open(&self, end: u32) -> bool {
        self.byte_at(end) == Some(b'(')
    }

    /// Where a `(` follows the token ending at `end` after some spaces or line breaks.
    fn followed_by_open_after_layout(&self, end: u32) -> Option<u32> {
        let rest = &self.text.as_bytes()[end as usize..];
        let layout = rest.iter().take_while(|b| matches!(b, b' ' | b'\t' | b'\r' | b'\n')).count();
        (layout > 0 && rest.get(layout) == Some(&b'(')).then_some(end + layout as u32)
    }

    fn previous_ends_term(&self) -> bool {
        self.previous.is_some_and(|t| t.ends_term())
    }

    /// The token for a name directly followed by `(`: the functor of a compound, except for an
    /// infix operator right after a term, which SWI-Prolog reads as the operator before a
    /// parenthesised operand (`2*(3+4)`, `a-(b)`).
    fn before_open(&self, symbol: Symbol) -> Tok {
        if self.previous_ends_term() && crate::syntax::ops::infix(symbol).is_some() {
            Tok::Op(symbol)
        } else {
            Tok::Functor(symbol)
        }
    }

    /// The token for an operator of the table not followed by `(`: the operator, or the atom it
    /// names where it stands alone as an operand (`f(+)`, `X = (-)`, `[mod]`): no term comes
    /// before it and a `,`, `)`, `]`, `|` or the clause's end comes after it.
    fn operator(&self, symbol: Symbol, end: u32) -> Tok {
        if self.previous_ends_term() {
            return Tok::Op(symbol);
        }
        let rest = &self.text.as_bytes()[end as usize..];
        let layout = rest.iter().take_while(|b| matches!(b, b' ' | b'\t' | b'\r' | b'\n')).count();
        let alone = match rest.get(layout) {
            Some(b',' | b')' | b']' | b'|') => true,
            Some(b'.') => matches!(rest.get(layout + 1), None | Some(b' ' | b'\t' | b'\r' | b'\n' | b'%')),
            _ => false,
        };
        if alone { Tok::Name(symbol) } else { Tok::Op(symbol) }
    }

    /// Cooks one raw token (and any it looks ahead at), leaving the token in `produced` unless
    /// the raw token is skipped.
    fn cook(&mut self, current: RawToken<'_>) -> Option<Token> {
        let RawToken { raw, start, end, text } = current;
        // The common tokens first; everything rare (errors, recovery) is out of line.
        match raw {
            Ok(Raw::Name) => self.name(text, start, end),
            Ok(Raw::Var) => self.variable(text, start, end),
            Ok(Raw::Int) => self.integer(text, 10, start, end, false),
            Ok(Raw::Comma) => self.push(Tok::Comma, start, end),
            Ok(Raw::Open) => self.push(Tok::Open, start, end),
            Ok(Raw::Close) => self.push(Tok::Close, start, end),
            Ok(Raw::OpenList) => self.push(Tok::OpenList, start, end),
            Ok(Raw::CloseList) => self.push(Tok::CloseList, start, end),
            Ok(Raw::Symbolic) => self.symbolic(text, start, end),
            Ok(Raw::Float) => self.float(text, start, end, false),
            Ok(Raw::Quoted) => {
                let body = self.unescape(&text[1..text.len() - 1], '\'', start + 1);
                let symbol = self.interner.intern(&body);
                let tok = if self.directly_followed_by_open(end) { Tok::Functor(symbol) } else { Tok::Name(symbol) };
                self.push(tok, start, end)
            }
            Ok(Raw::Str) => {
                let body = self.unescape(&text[1..text.len() - 1], '"', start + 1);
                let symbol = self.interner.intern(&body);
                self.push(Tok::Str(symbol), start, end)
            }
            Ok(Raw::Cut) => self.push(Tok::Name(sym::CUT), start, end),
            Ok(Raw::Semi) => {
                let tok = if self.directly_followed_by_open(end) {
                    self.before_open(sym::SEMI)
                } else {
                    self.operator(sym::SEMI, end)
                };
                self.push(tok, start, end)
            }
            Ok(Raw::BlockComment) => None,
            _ => self.cook_unusual(raw, start, end, text),
        }
    }

    /// Cooks the raw tokens that are rare in a KB: numbers in other notations, `|`, and every
    /// kind of lexical error.
    #[cold]
    #[inline(never)]
    fn cook_unusual(&mut self, raw: Result<Raw, RawError>, start: u32, end: u32, text: &str) -> Option<Token> {
        match raw {
            Err(RawError::UnterminatedComment) => {
                self.diags.push(
                    Diagnostic::error(codes::UNTERMINATED_COMMENT, "unterminated block comment")
                        .primary(self.span(start, start + 2), "this comment is never closed")
                        .with_note("block comments do not nest; the first `*/` closes one")
                        .with_help("close the comment with `*/`"),
                );
                None
            }
            Err(RawError::UnexpectedCharacter) => {
                self.unexpected_character(start, end, text);
                None
            }
            Ok(Raw::RadixInt) => {
                let radix = match &text[..2] {
                    "0x" => 16,
                    "0o" => 8,
                    _ => 2,
                };
                self.integer(&text[2..], radix, start, end, false)
            }
            Ok(Raw::CharCode) => {
                let body = &text[2..];
                let code = match body {
                    "''" => '\'' as i64,
                    "\\n" => '\n' as i64,
                    "\\t" => '\t' as i64,
                    "\\r" => '\r' as i64,
                    "\\\\" => '\\' as i64,
                    "\\'" => '\'' as i64,
                    "\\0" => 0,
                    _ => body.chars().next().map_or(0, |c| c as i64),
                };
                self.push(Tok::Int(Word64::int(code)), start, end)
            }
            Ok(Raw::UnterminatedQuoted) | Ok(Raw::UnterminatedStr) => {
                let quoted_atom = raw == Ok(Raw::UnterminatedQuoted);
                let (what, quote) = if quoted_atom { ("quoted atom", '\'') } else { ("string", '"') };
                self.diags.push(
                    Diagnostic::error(codes::UNTERMINATED_QUOTED, format!("unterminated {what}"))
                        .primary(self.span(start, start + 1), format!("this {what} is never closed"))
                        .secondary(self.span(end, end), format!("add `{quote}` here"))
                        .with_note(format!("a {what} must end on the line it starts; write `\\n` for a line break"))
                        .with_fix(format!("close the {what}"), self.span(end, end), quote.to_string())
                        .with_help(format!("add the closing `{quote}`")),
                );
                let body = self.unescape(&text[1..], quote, start + 1);
                let symbol = self.interner.intern(&body);
                self.push(if quoted_atom { Tok::Name(symbol) } else { Tok::Str(symbol) }, start, end)
            }
            Ok(Raw::BangEq) => {
                self.foreign_operator(
                    text,
                    "\\=",
                    start,
                    end,
                    "`\\=` means \"does not unify\"; for arithmetic inequality use `=\\=`",
                );
                self.push(Tok::Op(sym::NOT_UNIFY), start, end)
            }
            Ok(Raw::Bar) => {
                if self.byte_at(end) == Some(b'|') {
                    self.raw(); // the second `|`
                    self.foreign_operator("||", ";", start, end + 1, "in Prolog, `;` is disjunction");
                    self.push(Tok::Op(sym::SEMI), start, end + 1)
                } else {
                    self.push(Tok::Bar, start, end)
                }
            }
            Ok(Raw::OpenCurly) => {
                // Read the whole `{...}` group as one placeholder atom, so one diagnostic
                // covers it and the clause around it still parses.
                let group_end = self.skip_curly_group().unwrap_or(end);
                self.diags.push(
                    Diagnostic::error(
                        codes::UNEXPECTED_CHARACTER,
                        "unexpected `{`: curly-brace terms are not supported",
                    )
                    .primary(self.span(start, group_end), "not part of the KB language")
                    .with_help("use a compound term or a list instead, e.g. `config(arms(2))`"),
                );
                let symbol = self.interner.intern("{}");
                self.push(Tok::Name(symbol), start, group_end)
            }
            Ok(Raw::CloseCurly) => {
                self.diags.push(
                    Diagnostic::error(codes::UNEXPECTED_CHARACTER, "unexpected `}`")
                        .primary(self.span(start, end), "no `{` is open here")
                        .with_fix("remove it", self.span(start, end), ""),
                );
                None
            }
            // Cooked by `cook`; listed so this match stays exhaustive without a panic.
            Ok(
                Raw::Name | Raw::Var | Raw::Int | Raw::Comma | Raw::Open | Raw::Close | Raw::OpenList | Raw::CloseList,
            )
            | Ok(Raw::Symbolic | Raw::Float | Raw::Quoted | Raw::Str | Raw::Cut | Raw::Semi | Raw::BlockComment) => {
                None
            }
        }
    }

    /// Skips the raw tokens of a `{...}` group whose `{` was just read and returns where its
    /// `}` ends; without a matching `}` nothing is skipped.
    fn skip_curly_group(&mut self) -> Option<u32> {
        let mut depth = 1usize;
        let mut seen = Vec::new();
        while let Some(raw) = self.raw() {
            seen.push(raw);
            match raw.raw {
                Ok(Raw::OpenCurly) => depth += 1,
                Ok(Raw::CloseCurly) => {
                    depth -= 1;
                    if depth == 0 {
                        return Some(raw.end);
                    }
                }
                _ => {}
            }
        }
        self.stash.extend(seen.into_iter().rev());
        None
    }

    #[cold]
    #[inline(never)]
    fn unexpected_character(&mut self, start: u32, end: u32, text: &str) {
        let c = text.chars().next().unwrap_or('?');
        let mut diagnostic =
            Diagnostic::error(codes::UNEXPECTED_CHARACTER, format!("unexpected character `{}`", c.escape_debug()))
                .primary(self.span(start, end), "not valid in a KB here");
        if c.is_alphabetic() {
            diagnostic = diagnostic
                .with_note("unquoted atoms and variables use ASCII letters, digits and `_`")
                .with_help("quote the atom: 'café'");
        } else if c == '`' {
            diagnostic = diagnostic.with_help("quote atoms with `'`, strings with `\"`");
        }
        self.diags.push(diagnostic);
    }

    fn name(&mut self, text: &str, start: u32, end: u32) -> Option<Token> {
        let symbol = self.interner.intern(text);
        let operator =
            matches!(symbol, sym::IS | sym::MOD | sym::REM | sym::DIV | sym::XOR | sym::DYNAMIC | sym::DISCONTIGUOUS);
        if self.directly_followed_by_open(end) {
            return self.push(self.before_open(symbol), start, end);
        }
        if operator {
            return self.push(self.operator(symbol, end), start, end);
        }
        if let Some(open) = self.followed_by_open_after_layout(end) {
            self.diags.push(
                Diagnostic::error(codes::SPACE_BEFORE_PAREN, format!("space between `{text}` and its `(`"))
                    .primary(self.span(end, open), "remove this space")
                    .secondary(self.span(start, end), "the functor")
                    .with_note("in Prolog, `f (a)` is not the compound `f(a)`: the `(` must follow the name directly")
                    .with_fix("remove the space", self.span(end, open), "")
                    .with_help(format!("write `{text}(`")),
            );
            return self.push(Tok::Functor(symbol), start, end);
        }
        self.push(Tok::Name(symbol), start, end)
    }

    fn variable(&mut self, text: &str, start: u32, end: u32) -> Option<Token> {
        if text != "_" && self.directly_followed_by_open(end) {
            let mut lowered = text.to_string();
            if let Some(first) = lowered.get_mut(0..1) {
                first.make_ascii_lowercase();
            }
            let lowered = lowered.trim_start_matches('_').to_string();
            let suggestion = if lowered.is_empty() || !lowered.as_bytes()[0].is_ascii_lowercase() {
                "p".to_string()
            } else {
                lowered
            };
            self.diags.push(
                Diagnostic::error(
                    codes::VARIABLE_FUNCTOR,
                    format!("`{text}` is a variable, so it cannot name a predicate"),
                )
                .primary(self.span(start, end), "starts with an upper-case letter or `_`")
                .with_note(
                    "predicate and functor names start with a lower-case letter; capitalised names are variables",
                )
                .with_fix(format!("rename to `{suggestion}`"), self.span(start, end), suggestion.clone())
                .with_help(format!("write `{suggestion}(`")),
            );
            let symbol = self.interner.intern(&suggestion);
            return self.push(Tok::Functor(symbol), start, end);
        }
        let symbol = self.interner.intern(text);
        self.push(Tok::Var(symbol), start, end)
    }

    fn integer(&mut self, digits: &str, radix: u32, start: u32, end: u32, negative: bool) -> Option<Token> {
        let grouped;
        let digits = if digits.contains('_') {
            grouped = digits.replace('_', "");
            grouped.as_str()
        } else {
            digits
        };
        // Up to 18 decimal digits cannot overflow an i64: add them up directly.
        if radix == 10 && digits.len() <= 18 {
            let value = digits.bytes().fold(0i64, |v, b| v * 10 + i64::from(b - b'0'));
            return self.push(Tok::Int(Word64::int(if negative { -value } else { value })), start, end);
        }
        let parsed = if negative {
            i64::from_str_radix(&format!("-{digits}"), radix)
        } else {
            i64::from_str_radix(digits, radix)
        };
        match parsed {
            Ok(value) => self.push(Tok::Int(Word64::int(value)), start, end),
            Err(_) => {
                self.diags.push(
                    Diagnostic::error(codes::BAD_NUMBER, "integer literal out of range")
                        .primary(self.span(start, end), "does not fit in 64 bits")
                        .with_note("kbc integers are 64-bit: from -9223372036854775808 to 9223372036854775807"),
                );
                self.push(Tok::Int(Word64::int(0)), start, end)
            }
        }
    }

    fn float(&mut self, text: &str, start: u32, end: u32, negative: bool) -> Option<Token> {
        match text.parse::<f64>() {
            Ok(value) if value.is_finite() => {
                self.push(Tok::Float(Word64::float(if negative { -value } else { value })), start, end)
            }
            _ => {
                self.diags.push(
                    Diagnostic::error(codes::BAD_NUMBER, "float literal out of range")
                        .primary(self.span(start, end), "too large for a 64-bit float"),
                );
                self.push(Tok::Float(Word64::float(0.0)), start, end)
            }
        }
    }

    /// Cooks a symbol-character run; returns true if it consumed the following raw token too.
    fn symbolic(&mut self, text: &str, start: u32, end: u32) -> Option<Token> {
        if text == "." {
            let next = self.text.as_bytes().get(end as usize).copied();
            if matches!(next, None | Some(b' ' | b'\t' | b'\r' | b'\n' | b'\x0C' | b'%')) {
                return self.push(Tok::End, start, end);
            }
            let symbol = self.interner.intern(".");
            return self.push(Tok::SymbolAtom(symbol), start, end);
        }
        // A `-` directly before a number, where no operand precedes, is part of the literal.
        if text == "-"
            && self.byte_at(end).is_some_and(|b| b.is_ascii_digit())
            && !self.previous_ends_term()
            && let Some(next) = self.raw()
        {
            let digits = next.text;
            match next.raw {
                Ok(Raw::Int) => return self.integer(digits, 10, start, next.end, true),
                Ok(Raw::Float) => return self.float(digits, start, next.end, true),
                _ => self.stash.push(next),
            }
        }
        let operator = match text {
            "@<" => Some(sym::AT_LT),
            "@>" => Some(sym::AT_GT),
            "@=<" => Some(sym::AT_LE),
            "@>=" => Some(sym::AT_GE),
            "=.." => Some(sym::UNIV),
            "=@=" => Some(sym::VARIANT),
            "\\=@=" => Some(sym::NOT_VARIANT),
            "/\\" => Some(sym::BIT_AND),
            "\\/" => Some(sym::BIT_OR),
            "<<" => Some(sym::SHIFT_LEFT),
            ">>" => Some(sym::SHIFT_RIGHT),
            "**" => Some(sym::POWER),
            "^" => Some(sym::CARET),
            ":" => Some(sym::COLON),
            "\\" => Some(sym::BACKSLASH),
            ":-" => Some(sym::NECK),
            "->" => Some(sym::ARROW),
            "\\+" => Some(sym::NOT_PROVABLE),
            "=" => Some(sym::EQ),
            "\\=" => Some(sym::NOT_UNIFY),
            "==" => Some(sym::IDENTICAL),
            "\\==" => Some(sym::NOT_IDENTICAL),
            "<" => Some(sym::LT),
            ">" => Some(sym::GT),
            "=<" => Some(sym::LE),
            ">=" => Some(sym::GE),
            "=:=" => Some(sym::ARITH_EQ),
            "=\\=" => Some(sym::ARITH_NE),
            "+" => Some(sym::PLUS),
            "-" => Some(sym::MINUS),
            "*" => Some(sym::STAR),
            "/" => Some(sym::SLASH),
            "//" => Some(sym::INT_DIV),
            "<=" => {
                self.foreign_operator(text, "=<", start, end, "Prolog writes less-or-equal as `=<`");
                Some(sym::LE)
            }
            "<>" => {
                self.foreign_operator(
                    text,
                    "\\=",
                    start,
                    end,
                    "`\\=` means \"does not unify\"; for arithmetic inequality use `=\\=`",
                );
                Some(sym::NOT_UNIFY)
            }
            "&&" => {
                self.foreign_operator(text, ",", start, end, "in Prolog, `,` is conjunction");
                return self.push(Tok::Comma, start, end);
            }
            _ => None,
        };
        let symbol = operator.unwrap_or_else(|| self.interner.intern(text));
        if self.directly_followed_by_open(end) {
            self.push(self.before_open(symbol), start, end)
        } else if operator.is_some() {
            self.push(self.operator(symbol, end), start, end)
        } else {
            self.push(Tok::SymbolAtom(symbol), start, end)
        }
    }

    #[cold]
    #[inline(never)]
    fn foreign_operator(&mut self, found: &str, replacement: &str, start: u32, end: u32, note: &str) {
        self.diags.push(
            Diagnostic::error(codes::NOT_AN_OPERATOR, format!("`{found}` is not a Prolog operator"))
                .primary(self.span(start, end), format!("use `{replacement}` here"))
                .with_note(note)
                .with_fix(format!("replace `{found}` with `{replacement}`"), self.span(start, end), replacement)
                .with_help(format!("write `{replacement}`")),
        );
    }

    /// Unescapes the body of a quoted atom or string starting at byte `offset`.
    fn unescape(&mut self, body: &str, quote: char, offset: u32) -> String {
        if !body.contains('\\') && !body.contains(quote) {
            return body.to_string();
        }
        let mut out = String::with_capacity(body.len());
        let mut chars = body.char_indices().peekable();
        while let Some((at, c)) = chars.next() {
            if c == quote {
                // A doubled quote stands for one quote character.
                if chars.peek().map(|&(_, n)| n) == Some(quote) {
                    chars.next();
                }
                out.push(quote);
                continue;
            }
            if c != '\\' {
                out.push(c);
                continue;
            }
            let Some((_, escape)) = chars.next() else { break };
            let simple = match escape {
                'n' => Some('\n'),
                't' => Some('\t'),
                'r' => Some('\r'),
                'a' => Some('\x07'),
                'b' => Some('\x08'),
                'f' => Some('\x0C'),
                'v' => Some('\x0B'),
                '0' if chars.peek().is_none_or(|&(_, n)| !n.is_ascii_digit()) => Some('\0'),
                'e' => Some('\x1B'),
                's' => Some(' '),
                '\\' | '\'' | '"' | '`' => Some(escape),
                _ => None,
            };
            if let Some(c) = simple {
                out.push(c);
                continue;
            }
            // \xHH..\ and \NNN\ (octal), each closed by a backslash.
            let (radix, first) = if escape == 'x' { (16, None) } else { (8, Some(escape)) };
            let mut digits = String::new();
            digits.extend(first.filter(|c| c.is_digit(8)));
            let mut closed = false;
            if escape == 'x' || first.is_some_and(|c| c.is_digit(8)) {
                while let Some(&(_, d)) = chars.peek() {
                    if d.is_digit(radix) {
                        digits.push(d);
                        chars.next();
                    } else {
                        if d == '\\' {
                            chars.next();
                            closed = true;
                        }
                        break;
                    }
                }
            }
            let decoded = u32::from_str_radix(&digits, radix).ok().and_then(char::from_u32);
            match decoded {
                Some(c) if !digits.is_empty() && closed => out.push(c),
                _ => {
                    let escape_start = offset + at as u32;
                    let escape_end = chars.peek().map_or(offset + body.len() as u32, |&(next, _)| offset + next as u32);
                    self.diags.push(
                        Diagnostic::error(codes::BAD_ESCAPE, format!("unknown escape sequence `\\{escape}`"))
                            .primary(self.span(escape_start, escape_end.max(escape_start + 1)), "not a valid escape")
                            .with_note("valid escapes: \\n \\t \\r \\\\ \\' \\\" \\xHEX\\ \\OCTAL\\")
                            .with_help("write `\\\\` for a backslash"),
                    );
                    out.push(escape);
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cook(text: &str) -> (Vec<Tok>, Vec<String>, Interner) {
        let mut interner = Interner::new();
        let mut diags = Diagnostics::new();
        let lexed = lex(FileId(0), text, &mut interner, &mut diags);
        let codes = diags.iter().map(|d| d.code.map(|c| c.to_string()).unwrap_or_default()).collect();
        (lexed.tokens.into_iter().map(|t| t.tok).collect(), codes, interner)
    }

    #[test]
    fn functor_needs_the_paren_adjacent() {
        let (toks, codes, mut interner) = cook("f(a) g (b)");
        let f = interner.intern("f");
        let g = interner.intern("g");
        assert_eq!(toks[0], Tok::Functor(f));
        assert_eq!(toks[4], Tok::Functor(g));
        assert_eq!(codes, vec!["E0108"]);
    }

    #[test]
    fn minus_before_number_is_negative_only_in_prefix_position() {
        let (toks, _, _) = cook("p(-1, X-1, X - -2.5)");
        assert!(toks.contains(&Tok::Int(Word64::int(-1))));
        assert!(toks.contains(&Tok::Int(Word64::int(1))));
        assert!(toks.contains(&Tok::Op(sym::MINUS)));
        assert!(toks.contains(&Tok::Float(Word64::float(-2.5))));
    }

    #[test]
    fn digit_groups_read_as_one_integer() {
        let (toks, codes, _) = cook("p(1_000_000, -2_5, 10_000_000_000_000_000_000)");
        assert_eq!(toks[2], Tok::Int(Word64::int(1_000_000)));
        assert_eq!(toks[4], Tok::Int(Word64::int(-25)));
        assert_eq!(codes, vec!["E0112"], "twenty digits do not fit in 64 bits");
    }

    #[test]
    fn end_needs_layout_after_the_period() {
        let (toks, _, _) = cook("a. b.c");
        assert_eq!(toks[1], Tok::End);
        assert!(matches!(toks[3], Tok::SymbolAtom(_)));
    }

    #[test]
    fn symbol_runs_stop_before_comments() {
        let (toks, codes, _) = cook("X =/* c */ 1.");
        assert_eq!(toks[1], Tok::Op(sym::EQ));
        assert!(codes.is_empty());
    }

    #[test]
    fn foreign_operators_are_diagnosed_and_replaced() {
        let (toks, codes, _) = cook("X != Y, A <= B, C <> D");
        assert_eq!(codes, vec!["E0107", "E0107", "E0107"]);
        assert_eq!(toks[1], Tok::Op(sym::NOT_UNIFY));
        assert_eq!(toks[5], Tok::Op(sym::LE));
    }

    #[test]
    fn quoted_atoms_unescape() {
        let (toks, codes, interner) = cook(r"'it''s' 'a\nb' 'x\x41\y'");
        assert!(codes.is_empty(), "{codes:?}");
        let names: Vec<&str> = toks
            .iter()
            .map(|t| match t {
                Tok::Name(s) => interner.resolve(*s),
                _ => "",
            })
            .collect();
        assert_eq!(names, vec!["it's", "a\nb", "xAy"]);
    }

    #[test]
    fn unterminated_things_are_reported() {
        assert_eq!(cook("'abc\n").1, vec!["E0105"]);
        assert_eq!(cook("\"abc").1, vec!["E0105"]);
        assert_eq!(cook("a. /* b").1, vec!["E0106"]);
        assert_eq!(cook("a § b").1, vec!["E0111"]);
        assert_eq!(cook("99999999999999999999").1, vec!["E0112"]);
    }

    #[test]
    fn line_layout_is_recorded() {
        let mut interner = Interner::new();
        let mut diags = Diagnostics::new();
        let lexed = lex(FileId(0), "a(x)\n  b\nc", &mut interner, &mut diags);
        let layout: Vec<(bool, bool)> = lexed.tokens.iter().map(|t| (t.line_start, t.column0)).collect();
        assert_eq!(
            layout,
            vec![(true, true), (false, false), (false, false), (false, false), (true, false), (true, true)]
        );
    }
}

#[cfg(test)]
mod size_tests {
    use super::*;

    /// A clause's tokens are held at once (three million for `X = - - ... 1`): the size is a
    /// budget, not an accident.
    #[test]
    fn a_token_takes_24_bytes() {
        assert_eq!(std::mem::size_of::<Tok>(), 12);
        assert_eq!(std::mem::size_of::<Token>(), 24);
    }

    #[test]
    fn numbers_survive_the_split_into_halves() {
        for i in [0, 1, -1, i64::MIN, i64::MAX, 0x1234_5678_9abc_def0] {
            assert_eq!(Word64::int(i).as_int(), i);
        }
        for f in [0.0, -0.0, 2.5, -1e300, f64::MIN_POSITIVE] {
            assert_eq!(Word64::float(f).as_float().to_bits(), f.to_bits());
        }
    }
}
