//! The parser: cooked tokens to clauses, recovering from every error it can name.
//!
//! Parsing one file goes clause by clause, and each clause is repaired before the LR(1)
//! parser generated from grammar/kb.lalrpop sees it:
//!
//! 1. **Clause boundaries.** Tokens are split at each end `.`. A missing `.` is recognised
//!    where a term ends and another term starts in column 0 of a new line, which is how KBs are
//!    laid out; the clause is split there and the `.` reported where it belongs.
//! 2. **Bracket balance.** A closing bracket that does not match is either a typo for the
//!    expected one or the sign of a missing closer; both readings are tried on the rest of the
//!    clause and the one that leaves fewer errors wins. Openers still open at the `.` are
//!    reported with the opener labelled, and closed.
//! 3. **Missing commas.** Two terms side by side inside brackets (or in a rule body) are
//!    missing a `,`; one is inserted.
//!
//! Each repair inserts or replaces tokens, reports one precise diagnostic, and lets parsing
//! continue as if the user had written the fix. What is left (a stray operator, say) the LR
//! parser reports, recovering at argument and list-element level through the grammar's `!`
//! rules. The result is a clause list with `Error` terms where something could not be read.

use lalrpop_util::ParseError;

use super::ast::{Clause, SourceAst, Term, TermKind};
use super::lexer::{self, Tok, Token};
use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::intern::{Interner, Symbol, sym};
use crate::source::{FileId, Span};

lalrpop_util::lalrpop_mod!(
    #[allow(clippy::all, clippy::pedantic, unused_qualifications, unused_parens)]
    grammar,
    "/kb.rs"
);

/// An xfy operator chain `a op b op c ...` as the grammar reads it: the operands, and the
/// first operator (name and span). A chain of one operator is kept flat ([`flatten_xfy`]), so
/// a body of a million goals need not hold a million spans.
pub struct XfyChain {
    operands: Vec<Term>,
    op: (Symbol, Span),
}

impl XfyChain {
    /// The chain `a op b`.
    pub fn new(a: Term, op: (Symbol, Span), b: Term) -> XfyChain {
        XfyChain { operands: vec![a, b], op }
    }

    /// The chain with `op b` after it (the same operator: a level has one xfy operator).
    pub fn push(mut self, op: (Symbol, Span), b: Term) -> XfyChain {
        debug_assert_eq!(op.0, self.op.0, "a chain has one operator");
        self.operands.push(b);
        self
    }
}

/// An [`XfyChain`] as a term: `a op b` for two operands, and for three or more one compound
/// with [`Notation::Chain`] (see there) instead of a nest of binary ones. A body of a million
/// goals is then one node with a million arguments, not a million nodes a million deep; the
/// same for `;` and `->` chains.
///
/// [`Notation::Chain`]: super::ast::Notation::Chain
pub fn flatten_xfy(chain: XfyChain) -> Term {
    let XfyChain { mut operands, op: (functor, functor_span) } = chain;
    if operands.len() == 2 {
        let b = operands.pop().expect("two operands");
        let a = operands.pop().expect("two operands");
        return Term::infix(functor, functor_span, a, b);
    }
    let span = operands[0].span.to(operands[operands.len() - 1].span);
    Term::compound(functor, functor_span, operands, super::ast::Notation::Chain, span)
}

/// The lexer error type the grammar declares; never produced, since lexical problems are
/// reported while cooking tokens.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NoLexError;

/// Parses one file's text into clauses, reporting every syntax problem into `diags`.
///
/// Tokens stream from the lexer through [`ClauseStream`], which repairs each clause. Clauses
/// made only of canonical terms (most facts) are built directly by [`canonical_clause`]; the
/// others go, as one token stream, through one run of the LR parser generated from the
/// grammar, and the two are merged back in file order.
pub fn parse_source(file: FileId, text: &str, interner: &mut Interner, diags: &mut Diagnostics) -> SourceAst {
    parse(file, text, interner, diags, true)
}

/// [`parse_source`] with every clause parsed by the grammar: the reference the fast path is
/// tested against.
#[doc(hidden)]
pub fn parse_source_by_grammar_only(
    file: FileId,
    text: &str,
    interner: &mut Interner,
    diags: &mut Diagnostics,
) -> SourceAst {
    parse(file, text, interner, diags, false)
}

fn parse(file: FileId, text: &str, interner: &mut Interner, diags: &mut Diagnostics, fast_path: bool) -> SourceAst {
    let mut stream = ClauseStream {
        fast_path,
        file,
        text_len: text.len() as u32,
        lexer: lexer::Lexer::new(file, text, interner, diags),
        buffer: Vec::with_capacity(64),
        next: 0,
        carried: None,
        order: Vec::new(),
    };
    let mut errors = Vec::new();
    let tokens = stream.by_ref().map(|t| Ok((t.start, t.tok, t.end)));
    let result = grammar::FileParser::new().parse(file, &mut errors, tokens);
    let (interner, diags) = stream.lexer.parts();
    for recovery in errors {
        report_parse_error(file, recovery.error, interner, diags);
    }
    let mut parsed = match result {
        Ok(items) => items.into_iter(),
        Err(error) => {
            // Recovery only fails without a `.` to resynchronise on, and the stream ends every
            // clause with one; report it all the same rather than lose the message.
            report_parse_error(file, error, interner, diags);
            Vec::new().into_iter()
        }
    };
    let clauses = stream
        .order
        .into_iter()
        .map(|entry| {
            let (term, span) = match entry {
                Parsed::Directly(term, span) => return Clause { term, span, recovered: false },
                // Each clause handed to the grammar yields exactly one item, parsed or not. The
                // clause's span is the stream's: where the parser's error recovery began
                // depends on what it parsed before, so an error item's own span is not.
                Parsed::ByGrammar(span) => match parsed.next() {
                    Some((term, _)) if term.kind != TermKind::Error => (term, span),
                    _ => (Term::error(span), span),
                },
            };
            let recovered = term.has_error();
            Clause { term, span, recovered }
        })
        .collect();
    SourceAst { file, clauses }
}

/// How a clause was parsed, in file order.
enum Parsed {
    /// By [`canonical_clause`], with the clause's span.
    Directly(Term, Span),
    /// By the grammar; the span is the clause's, for the error term if it yields none.
    ByGrammar(Span),
}

/// The tokens of a file, a clause at a time, each clause repaired and ended by a `.`.
///
/// A clause ends at its `.`, or where a `.` is missing: where a term ends and another starts
/// in column 0 of a new line, and at the end of the file. Each clause's tokens are collected in
/// a reused buffer and repaired if they need it. A clause of canonical terms only is parsed on
/// the spot; the others are handed out to the LR parser, followed by an end token (an inserted
/// one where the `.` was missing).
struct ClauseStream<'a> {
    /// Whether clauses of canonical terms are parsed by [`canonical_clause`].
    fast_path: bool,
    file: FileId,
    text_len: u32,
    lexer: lexer::Lexer<'a>,
    /// The current clause's tokens, its end token last.
    buffer: Vec<Token>,
    /// The next token of `buffer` to hand out.
    next: usize,
    /// A token read ahead that starts the next clause (after a missing `.`).
    carried: Option<Token>,
    /// Every clause so far, in file order.
    order: Vec<Parsed>,
}

impl Iterator for ClauseStream<'_> {
    type Item = Token;

    fn next(&mut self) -> Option<Token> {
        if self.next == self.buffer.len() && !self.fill() {
            return None;
        }
        self.next += 1;
        let token = self.buffer[self.next - 1];
        if self.next == self.buffer.len() && self.buffer.capacity() > 1 << 16 {
            // The clause's last token: the parser reduces the clause after reading it, and a
            // huge clause's tokens (a body of a million goals: 64 MB) need not stay allocated
            // while it builds the tree.
            self.buffer = Vec::with_capacity(64);
            self.next = 0;
        }
        Some(token)
    }
}

impl ClauseStream<'_> {
    /// Reads the next clause into the buffer; false at the end of the file.
    fn fill(&mut self) -> bool {
        let file = self.file;
        loop {
            self.buffer.clear();
            // A huge clause's tokens (a body of a million goals) need not stay allocated while
            // the rest of the file and the later passes run.
            self.buffer.shrink_to(4096);
            self.next = 0;
            self.buffer.extend(self.carried.take());
            let mut end = None;
            for token in self.lexer.by_ref() {
                if token.tok == Tok::End {
                    end = Some(token);
                    break;
                }
                if let Some(previous) = self.buffer.last()
                    && previous.tok.ends_term()
                    && token.tok.starts_term()
                    && token.line_start
                    && token.column0
                {
                    self.carried = Some(token);
                    break;
                }
                self.buffer.push(token);
            }
            let (_, diags) = self.lexer.parts();
            if self.buffer.len() > max_clause_tokens() {
                // Every pass walks terms recursively, and a term nests at most as deep as it
                // has tokens: this bounds the depth of that recursion.
                let first = self.buffer[0];
                let limit = crate::diag::group_thousands(max_clause_tokens());
                diags.push(
                    Diagnostic::error(
                        codes::CLAUSE_TOO_LONG,
                        format!("this clause has {} tokens, more than the {limit} a clause may have", crate::diag::group_thousands(self.buffer.len())),
                    )
                    .primary(Span::new(file, first.start, first.end), "the clause starts here")
                    .with_note("the limit bounds how deeply a term can nest, and so the recursion of every pass over it")
                    .with_help(format!(
                        "split the data into several clauses, or raise the limit with the environment variable {MAX_CLAUSE_TOKENS_VAR}"
                    )),
                );
                self.buffer = Vec::new(); // give the memory back
                if end.is_none() && self.carried.is_none() {
                    return false;
                }
                continue;
            }
            let Some(last) = self.buffer.last() else {
                match end {
                    Some(end) => {
                        let span = Span::new(file, end.start, end.end);
                        diags.push(
                            Diagnostic::error(codes::UNEXPECTED_TOKEN, "expected a clause, found `.`")
                                .primary(span, "this `.` ends nothing")
                                .with_fix("remove the `.`", span, ""),
                        );
                        continue;
                    }
                    None => return false,
                }
            };
            let end = end.unwrap_or_else(|| {
                let next = self.carried.as_ref().map(|t| Span::new(file, t.start, t.end));
                let diagnostic = missing_period(file, last.end, next);
                diags.push(match next {
                    Some(_) => diagnostic,
                    None => diagnostic.secondary(Span::point(file, self.text_len), "the file ends here"),
                });
                Token::inserted(Tok::End, last.end)
            });
            // Most clauses need no repair and are handed out as read.
            if needs_repair(&self.buffer) {
                let written_end = Some(&end).filter(|e| !e.virtual_);
                let balanced = balance_brackets(file, &self.buffer, end.start, written_end, diags);
                self.buffer = insert_missing_commas(file, balanced, diags);
            }
            // Repairs can leave nothing (a stray `)` is dropped): then only the `.` remains.
            let first = self.buffer.first().map_or(end.start, |t| t.start);
            let span = Span::new(file, first, end.end.max(first));
            if let Some(term) = canonical_clause(file, &self.buffer).filter(|_| self.fast_path) {
                self.order.push(Parsed::Directly(term, span));
                continue;
            }
            self.order.push(Parsed::ByGrammar(span));
            self.buffer.push(end);
            return true;
        }
    }
}

/// The environment variable with which the `kbc` command raises (or lowers) the limit of
/// [`max_clause_tokens`] (read by the command, which calls [`set_max_clause_tokens`]).
pub const MAX_CLAUSE_TOKENS_VAR: &str = "KBC_MAX_CLAUSE_TOKENS";

static MAX_CLAUSE_TOKENS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(2_500_000);

/// The most tokens a clause may have: 2,500,000 (a body of a million goals has two million)
/// unless [`set_max_clause_tokens`] said otherwise. A term nests at most as deep as it has
/// tokens, and `kbc` gives its passes a 2 GiB stack, which held a unary chain 4,000,000 deep
/// (the shape with the largest frames measured; release build).
pub fn max_clause_tokens() -> usize {
    MAX_CLAUSE_TOKENS.load(std::sync::atomic::Ordering::Relaxed)
}

/// Sets [`max_clause_tokens`] for the process (an embedder with a smaller stack lowers it).
pub fn set_max_clause_tokens(limit: usize) {
    MAX_CLAUSE_TOKENS.store(limit, std::sync::atomic::Ordering::Relaxed);
}

/// How deeply [`canonical_clause`] nests before leaving a clause to the LR parser, whose
/// stack is on the heap: deep terms must not overflow the native stack.
const CANONICAL_DEPTH: u32 = 48;

/// Parses a clause made only of canonical terms (atoms, numbers, strings, variables,
/// `f(...)` and lists; no operators, no parentheses), the shape of almost every fact of a
/// large KB, without the LR machine. Returns `None` for any other clause, which the grammar
/// then parses. It builds exactly the tree the grammar builds; `tests/frontend_robustness.rs`
/// checks that on random inputs.
pub(crate) fn canonical_clause(file: FileId, tokens: &[Token]) -> Option<Term> {
    let mut position = 0;
    let term = canonical_term(file, tokens, &mut position, 0)?;
    (position == tokens.len()).then_some(term)
}

fn canonical_term(file: FileId, tokens: &[Token], position: &mut usize, depth: u32) -> Option<Term> {
    use super::ast::{List, Notation};
    let token = tokens.get(*position)?;
    *position += 1;
    let span = Span::new(file, token.start, token.end);
    let kind = match token.tok {
        Tok::Name(s) | Tok::SymbolAtom(s) => TermKind::Atom(s),
        Tok::Var(s) => TermKind::Var(s),
        Tok::Int(i) => TermKind::Int(i.as_int()),
        Tok::Float(f) => TermKind::Float(f.as_float()),
        Tok::Str(s) => TermKind::Str(s),
        Tok::Functor(functor) if depth < CANONICAL_DEPTH => {
            if tokens.get(*position)?.tok != Tok::Open {
                return None;
            }
            *position += 1;
            let mut args = Vec::new();
            if tokens.get(*position)?.tok != Tok::Close {
                loop {
                    args.push(canonical_term(file, tokens, position, depth + 1)?);
                    let separator = tokens.get(*position)?;
                    *position += 1;
                    match separator.tok {
                        Tok::Comma => {}
                        Tok::Close => break,
                        _ => return None,
                    }
                }
            } else {
                *position += 1;
            }
            let end = tokens[*position - 1].end;
            return Some(Term::compound(functor, span, args, Notation::Canonical, Span::new(file, token.start, end)));
        }
        Tok::OpenList if depth < CANONICAL_DEPTH => {
            let mut items = Vec::new();
            let mut tail = None;
            if tokens.get(*position)?.tok != Tok::CloseList {
                loop {
                    items.push(canonical_term(file, tokens, position, depth + 1)?);
                    let separator = tokens.get(*position)?;
                    *position += 1;
                    match separator.tok {
                        Tok::Comma => {}
                        Tok::CloseList => break,
                        Tok::Bar => {
                            tail = Some(Box::new(canonical_term(file, tokens, position, depth + 1)?));
                            if tokens.get(*position)?.tok != Tok::CloseList {
                                return None;
                            }
                            *position += 1;
                            break;
                        }
                        _ => return None,
                    }
                }
            } else {
                *position += 1;
            }
            let end = tokens[*position - 1].end;
            return Some(Term::new(TermKind::List(Box::new(List { items, tail })), Span::new(file, token.start, end)));
        }
        _ => return None,
    };
    Some(Term::new(kind, span))
}

/// True if a clause's brackets do not balance or two terms stand side by side: the cases
/// [`balance_brackets`] and [`insert_missing_commas`] repair.
fn needs_repair(tokens: &[Token]) -> bool {
    let mut open: u64 = 0; // a stack of bracket kinds, one bit each, up to 64 deep
    let mut depth = 0u32;
    let mut previous_ends_term = false;
    for token in tokens {
        if previous_ends_term && token.tok.starts_term() {
            return true;
        }
        previous_ends_term = token.tok.ends_term();
        match token.tok {
            Tok::Open | Tok::OpenList => {
                if depth == 64 {
                    return true;
                }
                open = (open << 1) | u64::from(token.tok == Tok::OpenList);
                depth += 1;
            }
            Tok::Close | Tok::CloseList => {
                if depth == 0 || (open & 1 == 1) != (token.tok == Tok::CloseList) {
                    return true;
                }
                open >>= 1;
                depth -= 1;
            }
            _ => {}
        }
    }
    depth != 0
}

fn missing_period(file: FileId, at: u32, next: Option<Span>) -> Diagnostic {
    let mut diagnostic = Diagnostic::error(codes::MISSING_PERIOD, "missing `.` at the end of the clause")
        .primary(Span::point(file, at), "add `.` here")
        .with_fix("add `.`", Span::point(file, at), ".")
        .with_help("every clause ends with `.`");
    if let Some(next) = next {
        diagnostic = diagnostic.secondary(next, "the next clause starts here");
    }
    diagnostic
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Bracket {
    Paren,
    List,
}

impl Bracket {
    fn of_opener(tok: &Tok) -> Option<Bracket> {
        match tok {
            Tok::Open => Some(Bracket::Paren),
            Tok::OpenList => Some(Bracket::List),
            _ => None,
        }
    }

    fn of_closer(tok: &Tok) -> Option<Bracket> {
        match tok {
            Tok::Close => Some(Bracket::Paren),
            Tok::CloseList => Some(Bracket::List),
            _ => None,
        }
    }

    fn open_text(self) -> &'static str {
        match self {
            Bracket::Paren => "(",
            Bracket::List => "[",
        }
    }

    fn close_text(self) -> &'static str {
        match self {
            Bracket::Paren => ")",
            Bracket::List => "]",
        }
    }

    fn closer(self) -> Tok {
        match self {
            Bracket::Paren => Tok::Close,
            Bracket::List => Tok::CloseList,
        }
    }
}

/// How many mismatched closers in one clause get a look at the rest of the clause to choose
/// between a typo and missing closers (each look is linear in the clause).
const MAX_LOOKAHEADS: usize = 32;

/// How many other unclosed brackets an unclosed-delimiter diagnostic labels; a note counts
/// the rest.
const MAX_UNCLOSED_LABELS: usize = 8;

/// Labels the other unclosed brackets, innermost first, up to [`MAX_UNCLOSED_LABELS`].
fn also_unclosed<'a>(mut diagnostic: Diagnostic, others: impl Iterator<Item = &'a (Bracket, Span)>) -> Diagnostic {
    let mut more = 0usize;
    for (i, (b, s)) in others.enumerate() {
        if i < MAX_UNCLOSED_LABELS {
            diagnostic = diagnostic.secondary(*s, format!("this `{}` is not closed either", b.open_text()));
        } else {
            more += 1;
        }
    }
    if more > 0 {
        diagnostic = diagnostic.with_note(format!("and {} more unclosed brackets", crate::diag::group_thousands(more)));
    }
    diagnostic
}

/// How many bracket errors the tokens after a decision would still produce.
fn count_bracket_errors(mut stack: Vec<Bracket>, rest: &[Token]) -> usize {
    let mut errors = 0;
    for token in rest {
        if let Some(b) = Bracket::of_opener(&token.tok) {
            stack.push(b);
        } else if let Some(b) = Bracket::of_closer(&token.tok) {
            match stack.last() {
                Some(&top) if top == b => {
                    stack.pop();
                }
                Some(_) => {
                    errors += 1;
                    stack.pop();
                }
                None => errors += 1,
            }
        }
    }
    errors + stack.len()
}

fn balance_brackets(
    file: FileId,
    tokens: &[Token],
    end_offset: u32,
    end: Option<&Token>,
    diags: &mut Diagnostics,
) -> Vec<Token> {
    let mut out = Vec::with_capacity(tokens.len() + 2);
    // Open brackets: kind and the span of the opener.
    let mut stack: Vec<(Bracket, Span)> = Vec::new();
    let mut lookaheads = 0usize;
    for (i, token) in tokens.iter().enumerate() {
        let span = Span::new(file, token.start, token.end);
        if let Some(b) = Bracket::of_opener(&token.tok) {
            stack.push((b, span));
            out.push(*token);
            continue;
        }
        let Some(closer) = Bracket::of_closer(&token.tok) else {
            out.push(*token);
            continue;
        };
        let Some(&(top, top_span)) = stack.last() else {
            diags.push(
                Diagnostic::error(
                    codes::MISMATCHED_DELIMITER,
                    format!("unexpected closing delimiter `{}`", closer.close_text()),
                )
                .primary(span, "no bracket is open here")
                .with_fix("remove it", span, ""),
            );
            continue;
        };
        if top == closer {
            stack.pop();
            out.push(*token);
            continue;
        }
        // Mismatch: either this closer is a typo for `top`'s closer, or the brackets opened
        // since the one it matches were never closed. Try both on the rest of the clause.
        // Each choice looks at the rest of the clause; past a few dozen mismatches in one
        // clause (generated or corrupted input) the choice is the typo, so that recovery
        // stays linear in the input.
        lookaheads += 1;
        let kinds: Vec<Bracket> = stack.iter().map(|(b, _)| *b).collect();
        let rest = &tokens[i + 1..];
        let (missing_closers, typo_errors) = if lookaheads <= MAX_LOOKAHEADS {
            let missing = kinds.iter().rposition(|&b| b == closer).map(|depth| {
                let remaining = kinds[..depth].to_vec();
                (depth, count_bracket_errors(remaining, rest))
            });
            (missing, count_bracket_errors(kinds[..kinds.len() - 1].to_vec(), rest))
        } else {
            (None, 0)
        };
        match missing_closers {
            Some((depth, errors)) if errors < typo_errors => {
                let unclosed: Vec<(Bracket, Span)> = stack.drain(depth + 1..).collect();
                stack.pop();
                let (inner, inner_span) = *unclosed.last().expect("a mismatch means something is open above");
                let insertion = out.last().map_or(token.start, |t: &Token| t.end);
                let closers: String = unclosed.iter().rev().map(|(b, _)| b.close_text()).collect();
                let mut diagnostic =
                    Diagnostic::error(codes::UNCLOSED_DELIMITER, format!("unclosed delimiter `{}`", inner.open_text()))
                        .primary(inner_span, format!("this `{}` is never closed", inner.open_text()))
                        .secondary(span, format!("`{}` closes an outer bracket here", closer.close_text()))
                        .with_fix(format!("insert `{closers}`"), Span::point(file, insertion), closers.clone())
                        .with_help(format!("insert `{closers}` before this `{}`", closer.close_text()));
                diagnostic = also_unclosed(diagnostic, unclosed.iter().rev().skip(1));
                diags.push(diagnostic);
                for (b, _) in unclosed.iter().rev() {
                    out.push(Token::inserted(b.closer(), insertion));
                }
                out.push(*token);
            }
            _ => {
                diags.push(
                    Diagnostic::error(
                        codes::MISMATCHED_DELIMITER,
                        format!(
                            "mismatched closing delimiter: expected `{}`, found `{}`",
                            top.close_text(),
                            closer.close_text()
                        ),
                    )
                    .primary(span, format!("expected `{}`", top.close_text()))
                    .secondary(top_span, format!("this `{}` is closed by `{}`", top.open_text(), closer.close_text()))
                    .with_fix(
                        format!("replace with `{}`", top.close_text()),
                        span,
                        top.close_text(),
                    ),
                );
                stack.pop();
                out.push(Token { tok: top.closer(), ..*token });
            }
        }
    }
    if let Some(&(inner, inner_span)) = stack.last() {
        let closers: String = stack.iter().rev().map(|(b, _)| b.close_text()).collect();
        let insertion = out.last().map_or(end_offset, |t| t.end);
        let mut diagnostic =
            Diagnostic::error(codes::UNCLOSED_DELIMITER, format!("unclosed delimiter `{}`", inner.open_text()))
                .primary(inner_span, format!("this `{}` is never closed", inner.open_text()));
        diagnostic = also_unclosed(diagnostic, stack.iter().rev().skip(1));
        if let Some(end) = end {
            diagnostic = diagnostic.secondary(Span::new(file, end.start, end.end), "the clause ends here");
        }
        diags.push(
            diagnostic
                .with_fix(format!("insert `{closers}`"), Span::point(file, insertion), closers.clone())
                .with_help(format!("insert `{closers}` before the end of the clause")),
        );
        for (b, _) in stack.iter().rev() {
            out.push(Token::inserted(b.closer(), insertion));
        }
    }
    out
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Group {
    Arguments,
    List,
    Parenthesised,
}

fn insert_missing_commas(file: FileId, tokens: Vec<Token>, diags: &mut Diagnostics) -> Vec<Token> {
    let mut out: Vec<Token> = Vec::with_capacity(tokens.len());
    let mut groups: Vec<Group> = Vec::new();
    let mut rule_body = false;
    for token in tokens {
        if let Some(previous) = out.last()
            && previous.tok.ends_term()
            && token.tok.starts_term()
        {
            let inside = groups.last().copied();
            let what = match inside {
                Some(Group::List) => Some("list elements"),
                Some(Group::Arguments) => Some("arguments"),
                Some(Group::Parenthesised) => Some("goals"),
                None if rule_body => Some("goals"),
                None => None,
            };
            if let Some(what) = what {
                let at = previous.end;
                let next = Span::new(file, token.start, token.end);
                diags.push(
                    Diagnostic::error(codes::MISSING_COMMA, format!("missing `,` between {what}"))
                        .primary(Span::point(file, at), "add `,` here")
                        .secondary(next, "the next one starts here")
                        .with_fix("add `,`", Span::point(file, at), ",")
                        .with_help(format!("separate {what} with `,`")),
                );
                out.push(Token::inserted(Tok::Comma, at));
            }
        }
        match token.tok {
            Tok::Open => {
                let after_functor = out.last().is_some_and(|t| matches!(t.tok, Tok::Functor(_)));
                groups.push(if after_functor { Group::Arguments } else { Group::Parenthesised });
            }
            Tok::OpenList => groups.push(Group::List),
            Tok::Close | Tok::CloseList => {
                groups.pop();
            }
            Tok::Op(sym::NECK) if groups.is_empty() && !out.is_empty() => rule_body = true,
            _ => {}
        }
        out.push(token);
    }
    out
}

/// Turns the grammar's terminal names into words for messages.
fn describe_expected(expected: &[String]) -> String {
    let mut punctuation: Vec<&str> = Vec::new();
    let mut term = false;
    let mut operator = false;
    for name in expected {
        let name = name.trim_matches('"');
        match name {
            "name" | "symbol" | "functor" | "variable" | "integer" | "float" | "string" | "(" | "[" => term = true,
            ")" | "]" | "|" | "," => punctuation.push(match name {
                ")" => "`)`",
                "]" => "`]`",
                "|" => "`|`",
                _ => "`,`",
            }),
            _ => operator = true,
        }
    }
    let mut parts: Vec<String> = Vec::new();
    if term {
        parts.push("a term".to_string());
    }
    parts.extend(punctuation.iter().map(|p| p.to_string()));
    if operator && !term {
        parts.push("an operator".to_string());
    }
    match parts.len() {
        0 => "the end of the clause".to_string(),
        1 => parts.remove(0),
        n => format!("{} or {}", parts[..n - 1].join(", "), parts[n - 1]),
    }
}

fn report_parse_error(
    file: FileId,
    error: ParseError<u32, Tok, NoLexError>,
    interner: &Interner,
    diags: &mut Diagnostics,
) {
    match error {
        ParseError::UnrecognizedToken { token: (start, tok, stop), expected } => {
            let span = Span::new(file, start, stop);
            if let Tok::SymbolAtom(symbol) = tok {
                let text = interner.resolve(symbol);
                if text != "." {
                    diags.push(
                        Diagnostic::error(
                            codes::UNSUPPORTED_OPERATOR,
                            format!("`{text}` is not an operator in kbc's operator table"),
                        )
                        .primary(span, "used as an operator here")
                        .with_note(
                            "kbc reads a fixed operator table (docs/dsl.md, \"Operators\"); SWI-Prolog operators outside it are not supported",
                        )
                        .with_help(format!("write it in canonical form: `'{text}'(A, B)`")),
                    );
                    return;
                }
                diags.push(
                    Diagnostic::error(
                        codes::UNEXPECTED_TOKEN,
                        "expected an operator or the end of the clause, found `.`",
                    )
                    .primary(span, "a `.` followed directly by text does not end a clause")
                    .with_fix("add a space after the `.`", Span::point(file, stop), " ")
                    .with_help("end the clause with `.` followed by a space or a new line"),
                );
                return;
            }
            // An inserted end token stands where a `.` was missing: the clause just stops.
            let found = match tok {
                Tok::End if start == stop => "the end of the clause".to_string(),
                other => other.describe(interner),
            };
            let label = if tok == Tok::End { "the clause ends too early" } else { "unexpected here" };
            let mut diagnostic = Diagnostic::error(
                codes::UNEXPECTED_TOKEN,
                format!("expected {}, found {found}", describe_expected(&expected)),
            )
            .primary(span, label);
            if tok.starts_term() && !expected.iter().any(|e| e == "\"name\"") {
                diagnostic = diagnostic
                    .with_help("a term cannot follow another term directly: is a `,` or an operator missing?");
            }
            diags.push(diagnostic);
        }
        ParseError::UnrecognizedEof { location, expected } => {
            diags.push(
                Diagnostic::error(
                    codes::UNEXPECTED_TOKEN,
                    format!("expected {}, found the end of the file", describe_expected(&expected)),
                )
                .primary(Span::point(file, location), "the file ends too early"),
            );
        }
        ParseError::ExtraToken { token: (start, tok, stop) } => {
            diags.push(
                Diagnostic::error(
                    codes::UNEXPECTED_TOKEN,
                    format!("expected the end of the clause, found {}", tok.describe(interner)),
                )
                .primary(Span::new(file, start, stop), "unexpected here"),
            );
        }
        // The tokens come from our own lexer, which reports its errors while cooking.
        ParseError::InvalidToken { location } => {
            diags.push(
                Diagnostic::error(codes::UNEXPECTED_TOKEN, "invalid token")
                    .primary(Span::point(file, location), "not valid here"),
            );
        }
        ParseError::User { error: NoLexError } => {}
    }
}
