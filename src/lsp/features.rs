//! The answers to editor requests, computed from one [`Analysis`].
//!
//! Each function takes the analysis and a byte offset (the server converts positions) and
//! returns protocol values. Nothing here does IO or keeps state.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::sync::OnceLock;

use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOrCommand, CompletionItem, CompletionItemKind, CompletionItemLabelDetails,
    DocumentSymbol, Hover, HoverContents, Location, MarkupContent, MarkupKind, SymbolInformation, SymbolKind, TextEdit,
    Url, WorkspaceEdit,
};

use super::analysis::Analysis;
use super::index::{Index, Key, Role, indicator};
use crate::builtins;
use crate::diag::{codes, plural};
use crate::intern::{Interner, Symbol};
use crate::ir::hir::{self, Action, EffectKind, Kb, Level, Snap};
use crate::passes::load::NoIncludes;
use crate::session::Session;
use crate::source::{FileId, SourceDb, Span};
use crate::stdlib;

/// Hover: what the name under the cursor is, and the explanation of a diagnostic there.
pub fn hover(analysis: &Analysis, file: FileId, offset: u32) -> Option<Hover> {
    let occurrence = analysis.index.at(file, offset);
    let mut sections = Vec::new();
    if let Some(occurrence) = occurrence {
        sections.push(describe(analysis, occurrence.key));
    }
    let mut explained = BTreeSet::new();
    for diagnostic in analysis.diagnostics_in(file) {
        if let (Some(code), Some(span)) = (diagnostic.code, diagnostic.primary_span())
            && span.start <= offset
            && offset <= span.end
            && explained.insert(code.as_str())
        {
            sections.push(code.info().explanation.trim_end().to_string());
        }
    }
    let word = word_at(analysis.db.text(file), offset as usize);
    if let Some(info) = codes::lookup(word.text)
        && word.text.len() == 5
        && explained.insert(info.code)
    {
        sections.push(info.explanation.trim_end().to_string());
    }
    if sections.is_empty() {
        return None;
    }
    let range = occurrence.map(|o| analysis.range(o.span));
    Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value: sections.join("\n\n---\n\n"),
        }),
        range,
    })
}

/// Markdown describing what `key` names.
fn describe(analysis: &Analysis, key: Key) -> String {
    let kb = &analysis.frontend.kb;
    let interner = &analysis.frontend.interner;
    let name = |s: Symbol| interner.resolve(s).to_string();
    match key {
        Key::Predicate(predicate, arity) => describe_predicate(analysis, predicate, arity),
        Key::Action(action) => {
            let schemas: Vec<&Action> = kb.actions.iter().filter(|a| a.name.name() == action).collect();
            if schemas.is_empty() {
                return format!("```prolog\n{}\n```\nno action schema has this name", name(action));
            }
            schemas.iter().map(|a| describe_action(analysis, a)).collect::<Vec<_>>().join("\n\n")
        }
        Key::Durative(base) => {
            let schemas: Vec<&Action> =
                kb.actions.iter().filter(|a| a.base == base && a.snap != Snap::Instant).collect();
            let mut text = format!("```prolog\n{}\n```\ndurative action", name(base));
            if schemas.is_empty() {
                text.push_str(": no `_start`/`_end` schema has this base name");
            }
            for schema in schemas {
                text.push_str(&format!("\n- `{}`", hir::term_to_string(interner, &schema.name.term, &schema.vars)));
            }
            text
        }
        Key::Problem(problem) => {
            let Some(p) = kb.problem(problem) else { return String::new() };
            let form = match p.form {
                hir::ProblemForm::Go(arity) => format!("a test, `go/{arity}`"),
                hir::ProblemForm::InitGoalState => "`init_state` and `goal_state`".to_string(),
            };
            let mut text = format!(
                "```prolog\n{}\n```\nproblem ({form}): {}, {}",
                name(problem),
                plural(p.initial_facts().count(), "initial fact"),
                plural(p.goal.len(), "goal literal"),
            );
            if let Some(depth) = p.max_depth {
                text.push_str(&format!(", depth limit {depth}"));
            }
            let goal: Vec<String> = p.goal.iter().map(|l| hir::term_to_string(interner, &l.term, &p.vars)).collect();
            text.push_str(&format!("\n\ngoal: `{}`", goal.join(", ")));
            text
        }
    }
}

fn describe_predicate(analysis: &Analysis, predicate: Symbol, arity: usize) -> String {
    let kb = &analysis.frontend.kb;
    let interner = &analysis.frontend.interner;
    let shown = indicator(interner, predicate, arity);
    let text = interner.resolve(predicate);
    if let Some(builtin) = builtins::find(text, arity) {
        return format!("```prolog\n{shown}\n```\nbuilt-in: {}", builtin.what);
    }
    let matches = |l: &hir::Literal| l.name() == predicate && l.arity() == arity;
    let action_names = |filter: &dyn Fn(&Action) -> bool| -> Vec<String> {
        let names: BTreeSet<String> =
            kb.actions.iter().filter(|a| filter(a)).map(|a| format!("`{}`", interner.resolve(a.name.name()))).collect();
        names.into_iter().collect()
    };
    let added = action_names(&|a| a.effects.iter().any(|e| e.kind == EffectKind::Add && matches(&e.literal)));
    let deleted = action_names(&|a| a.effects.iter().any(|e| e.kind == EffectKind::Del && matches(&e.literal)));
    let conditions = action_names(&|a| a.valid.iter().chain(&a.invalid).chain(&a.invalid_at_end).any(matches));
    let problems = |pick: &dyn Fn(&hir::Problem) -> bool| -> Vec<String> {
        kb.problems.iter().filter(|p| pick(p)).map(|p| format!("`{}`", interner.resolve(p.name))).collect()
    };
    let init = problems(&|p| p.initial_facts().any(matches));
    let goal = problems(&|p| p.goal.iter().any(matches));
    let clauses: Vec<&hir::Clause> = kb.clauses.iter().filter(|c| matches(&c.head)).collect();
    let mut lines = Vec::new();
    let kind = if !added.is_empty() || !deleted.is_empty() || !init.is_empty() {
        "state predicate (a fluent: actions add and delete it)"
    } else if !clauses.is_empty() {
        "static predicate (facts and rules of the KB)"
    } else {
        "predicate with no clauses and no action that adds it"
    };
    if !clauses.is_empty() {
        let rules = clauses.iter().filter(|c| c.body.is_some()).count();
        let places: Vec<String> = clauses.iter().take(5).map(|c| place(&analysis.db, c.span)).collect();
        let more = if clauses.len() > 5 { ", ..." } else { "" };
        lines.push(format!(
            "- {} ({}, {}): {}{more}",
            plural(clauses.len(), "clause"),
            plural(clauses.len() - rules, "fact"),
            plural(rules, "rule"),
            places.join(", ")
        ));
    }
    for (label, list) in [
        ("added by", added),
        ("deleted by", deleted),
        ("a condition of", conditions),
        ("in the initial state of", init),
        ("in the goal of", goal),
    ] {
        if !list.is_empty() {
            lines.push(format!("- {label} {}", list.join(", ")));
        }
    }
    format!("```prolog\n{shown}\n```\n{kind}\n\n{}", lines.join("\n"))
}

fn describe_action(analysis: &Analysis, action: &Action) -> String {
    let kb = &analysis.frontend.kb;
    let interner = &analysis.frontend.interner;
    let head = if action.level == Level::High { "action" } else { "ll_action" };
    let name = hir::term_to_string(interner, &action.name.term, &action.vars);
    let base = interner.resolve(action.base);
    let what = match action.snap {
        Snap::Start => format!("the start of durative action `{base}`"),
        Snap::End => format!("the end of durative action `{base}`"),
        Snap::Instant => "an instantaneous action".to_string(),
    };
    let mut text = format!("```prolog\n{head}({name}, ...)\n```\n{what}, {}\n", place(&analysis.db, action.span));
    for (slot, span) in hir::SLOT_NAMES.iter().zip(action.slots).skip(1) {
        text.push_str(&format!("\n- {slot}: `{}`", one_line(analysis.db.snippet(span))));
    }
    let durations: Vec<String> = kb
        .clauses
        .iter()
        .filter(|c| {
            c.head.name() == crate::intern::sym::DURATION
                && c.head.arity() == 3
                && c.head.term.args()[0].callable().is_some_and(|(n, _)| n == action.base)
        })
        .map(|c| format!("`{}`", one_line(analysis.db.snippet(c.span))))
        .collect();
    if action.snap != Snap::Instant {
        if durations.is_empty() {
            text.push_str("\n- duration: none given (the default, at least 1 time unit, with warning W0006)");
        } else {
            text.push_str(&format!("\n- duration: {}", durations.join(" ")));
        }
    }
    for mapping in kb.mappings.iter().filter(|m| m.high.name() == action.name.name()) {
        text.push_str(&format!("\n- refined by `{}`", one_line(analysis.db.snippet(mapping.span))));
    }
    text
}

/// `file:line` of a span's start.
fn place(db: &SourceDb, span: Span) -> String {
    let file = db.file(span.file);
    format!("{}:{}", file.name(), file.line_col(span.start).line)
}

/// Source text on one line, runs of layout collapsed to a space.
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Go to definition.
pub fn definition(analysis: &Analysis, file: FileId, offset: u32) -> Vec<Location> {
    let Some(occurrence) = analysis.index.at(file, offset) else { return Vec::new() };
    let definitions = analysis.index.definitions(&analysis.frontend.kb, occurrence.key);
    definitions.iter().filter_map(|o| analysis.location(o.span)).collect()
}

/// Find references: every occurrence of the thing under the cursor.
pub fn references(analysis: &Analysis, file: FileId, offset: u32, include_declaration: bool) -> Vec<Location> {
    let Some(occurrence) = analysis.index.at(file, offset) else { return Vec::new() };
    analysis
        .index
        .related(&analysis.frontend.kb, occurrence.key)
        .filter(|o| include_declaration || !o.role.defines())
        .filter_map(|o| analysis.location(o.span))
        .collect()
}

/// The outline of one file: actions, mappings, problems, and facts grouped by predicate.
#[allow(deprecated)] // `DocumentSymbol::deprecated` must be written to build the struct.
pub fn document_symbols(analysis: &Analysis, file: FileId) -> Vec<DocumentSymbol> {
    let kb = &analysis.frontend.kb;
    let interner = &analysis.frontend.interner;
    let symbol = |name: String, detail: Option<String>, kind, span: Span, selection: Span, children| DocumentSymbol {
        name,
        detail,
        kind,
        tags: None,
        deprecated: None,
        range: analysis.range(span),
        selection_range: analysis.range(selection),
        children,
    };
    let mut symbols: Vec<(u32, DocumentSymbol)> = Vec::new();
    for action in kb.actions.iter().filter(|a| a.span.file == file) {
        let head = if action.level == Level::High { "action" } else { "ll_action" };
        let name = indicator(interner, action.name.name(), action.name.arity());
        let symbol =
            symbol(name, Some(head.to_string()), SymbolKind::FUNCTION, action.span, action.name.name_span, None);
        symbols.push((action.span.start, symbol));
    }
    for mapping in kb.mappings.iter().filter(|m| m.span.file == file) {
        let name = format!("mapping {}", indicator(interner, mapping.high.name(), mapping.high.arity()));
        let detail = plural(mapping.steps.len(), "step");
        let symbol = symbol(name, Some(detail), SymbolKind::INTERFACE, mapping.span, mapping.high.name_span, None);
        symbols.push((mapping.span.start, symbol));
    }
    for problem in kb.problems.iter().filter(|p| p.span.file == file) {
        let detail = format!(
            "{}, {}",
            plural(problem.initial_facts().count(), "initial fact"),
            plural(problem.goal.len(), "goal literal")
        );
        let name = interner.resolve(problem.name).to_string();
        symbols.push((
            problem.span.start,
            symbol(name, Some(detail), SymbolKind::EVENT, problem.span, problem.name_span, None),
        ));
    }
    let mut groups: BTreeMap<(Symbol, usize), Vec<&hir::Clause>> = BTreeMap::new();
    for clause in kb.clauses.iter().filter(|c| c.span.file == file) {
        groups.entry((clause.head.name(), clause.head.arity())).or_default().push(clause);
    }
    for ((name, arity), clauses) in groups {
        let children: Vec<DocumentSymbol> = clauses
            .iter()
            .map(|c| {
                let text = hir::term_to_string(interner, &c.head.term, &c.vars);
                let kind = if c.body.is_some() { SymbolKind::FUNCTION } else { SymbolKind::CONSTANT };
                symbol(text, None, kind, c.span, c.head.name_span, None)
            })
            .collect();
        let first = clauses[0].span;
        let whole = clauses.iter().fold(first, |span, c| span.to(c.span));
        let detail = plural(clauses.len(), "clause");
        let group = symbol(
            indicator(interner, name, arity),
            Some(detail),
            SymbolKind::STRUCT,
            whole,
            clauses[0].head.name_span,
            Some(children),
        );
        symbols.push((first.start, group));
    }
    symbols.sort_by_key(|(start, _)| *start);
    symbols.into_iter().map(|(_, s)| s).collect()
}

/// Workspace symbols: actions, problems and predicates with clauses, over every check, whose
/// name contains the query's characters in order (case-insensitive).
#[allow(deprecated)] // `SymbolInformation::deprecated` must be written to build the struct.
pub fn workspace_symbols<'a>(analyses: impl Iterator<Item = &'a Analysis>, query: &str) -> Vec<SymbolInformation> {
    let mut seen = BTreeSet::new();
    let mut out = Vec::new();
    for analysis in analyses {
        let kb = &analysis.frontend.kb;
        let interner = &analysis.frontend.interner;
        let mut candidates: Vec<(String, SymbolKind, Span)> = Vec::new();
        for action in &kb.actions {
            candidates.push((
                interner.resolve(action.name.name()).to_string(),
                SymbolKind::FUNCTION,
                action.name.name_span,
            ));
        }
        for problem in &kb.problems {
            candidates.push((interner.resolve(problem.name).to_string(), SymbolKind::EVENT, problem.name_span));
        }
        let mut predicates = BTreeSet::new();
        for clause in &kb.clauses {
            if predicates.insert((clause.head.name(), clause.head.arity())) {
                let name = indicator(interner, clause.head.name(), clause.head.arity());
                candidates.push((name, SymbolKind::STRUCT, clause.head.name_span));
            }
        }
        for (name, kind, span) in candidates {
            let Some(location) = analysis.location(span) else { continue };
            if !fuzzy_match(query, &name) || !seen.insert((location.uri.to_string(), span.start, name.clone())) {
                continue;
            }
            out.push(SymbolInformation { name, kind, tags: None, deprecated: None, location, container_name: None });
        }
    }
    out
}

/// True when `name` contains `query`'s characters in order, ignoring case.
fn fuzzy_match(query: &str, name: &str) -> bool {
    let mut name = name.chars().flat_map(char::to_lowercase);
    query.chars().flat_map(char::to_lowercase).all(|q| name.any(|n| n == q))
}

/// What a completed name is, most specific first (the order picks one description per name).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum NameKind {
    Action,
    ArmAction,
    StatePredicate,
    StaticPredicate,
    Predicate,
    Builtin,
    ClauseForm,
}

impl NameKind {
    fn describe(self) -> &'static str {
        match self {
            NameKind::Action => "action",
            NameKind::ArmAction => "arm-level action",
            NameKind::StatePredicate => "state predicate",
            NameKind::StaticPredicate => "static predicate",
            NameKind::Predicate => "predicate",
            NameKind::Builtin => "built-in",
            NameKind::ClauseForm => "KB clause form",
        }
    }

    fn item_kind(self) -> CompletionItemKind {
        match self {
            NameKind::Action | NameKind::ArmAction => CompletionItemKind::METHOD,
            NameKind::Builtin | NameKind::ClauseForm => CompletionItemKind::KEYWORD,
            _ => CompletionItemKind::FUNCTION,
        }
    }
}

/// A name to complete.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Candidate {
    name: String,
    arity: usize,
    kind: NameKind,
}

/// Completion of predicate and action names at `offset` of `text` (the open buffer): the
/// names the last check knows, std's, the built-ins and the KB's own clause forms, those that
/// start with the word before the cursor. Inside a variable or a comment, nothing.
pub fn completion(analysis: Option<&Analysis>, text: &str, offset: usize) -> Vec<CompletionItem> {
    let word = word_at(text, offset);
    let prefix = &text[word.start..offset.min(word.end).max(word.start)];
    if prefix.starts_with(|c: char| c.is_uppercase() || c == '_') || in_comment(text, offset) {
        return Vec::new();
    }
    let mut candidates: BTreeSet<Candidate> = BTreeSet::new();
    if let Some(analysis) = analysis {
        candidates.extend(names(&analysis.index, &analysis.frontend.kb, &analysis.frontend.interner));
    }
    candidates.extend(std_names().iter().cloned());
    for &builtins::Builtin { name, arity, .. } in builtins::PREDICATES {
        if name.starts_with(|c: char| c.is_ascii_lowercase()) {
            candidates.insert(Candidate { name: name.to_string(), arity, kind: NameKind::Builtin });
        }
    }
    for (name, arity) in [
        ("action", 6),
        ("ll_action", 6),
        ("mapping", 2),
        ("resources", 1),
        ("init_state", 1),
        ("goal_state", 1),
        ("go", 2),
        ("duration", 3),
    ] {
        candidates.insert(Candidate { name: name.to_string(), arity, kind: NameKind::ClauseForm });
    }
    // Sorted by name, arity, then kind: the first of each name and arity is the most specific.
    let mut seen: Option<(String, usize)> = None;
    let mut items = Vec::new();
    for Candidate { name, arity, kind } in candidates {
        if seen.as_ref() == Some(&(name.clone(), arity)) || !name.starts_with(prefix) || name == prefix {
            continue;
        }
        seen = Some((name.clone(), arity));
        let what = kind.describe();
        items.push(CompletionItem {
            label: name.clone(),
            label_details: Some(CompletionItemLabelDetails {
                detail: Some(format!("/{arity}")),
                description: Some(what.to_string()),
            }),
            kind: Some(kind.item_kind()),
            detail: Some(format!("{name}/{arity}: {what}")),
            insert_text: Some(name),
            ..CompletionItem::default()
        });
    }
    items
}

/// The names an index knows, described.
fn names(index: &Index, kb: &Kb, interner: &Interner) -> Vec<Candidate> {
    let mut out = Vec::new();
    for occurrence in index.occurrences() {
        let candidate = match (occurrence.key, occurrence.role) {
            (Key::Predicate(name, arity), role) => {
                let kind = match role {
                    Role::Added | Role::Deleted | Role::Init => NameKind::StatePredicate,
                    Role::ClauseHead => NameKind::StaticPredicate,
                    _ => NameKind::Predicate,
                };
                Candidate { name: interner.resolve(name).to_string(), arity, kind }
            }
            (Key::Action(name), Role::Declaration) => {
                let Some(action) = kb.actions.iter().find(|a| a.name.name() == name) else { continue };
                let kind = if action.level == Level::High { NameKind::Action } else { NameKind::ArmAction };
                Candidate { name: interner.resolve(name).to_string(), arity: action.name.arity(), kind }
            }
            _ => continue,
        };
        if builtins::find(&candidate.name, candidate.arity).is_none() {
            out.push(candidate);
        }
    }
    out
}

/// The names std/blocks.pl and std/arms.pl define, computed once.
fn std_names() -> &'static [Candidate] {
    static NAMES: OnceLock<Vec<Candidate>> = OnceLock::new();
    NAMES.get_or_init(|| {
        let mut db = SourceDb::new();
        let arms = db.add(stdlib::STD_ARMS_NAME, None, stdlib::STD_ARMS);
        let blocks = db.add(stdlib::STD_BLOCKS_NAME, None, stdlib::STD_BLOCKS);
        let session = Session::open(db, &[arms, blocks], &mut NoIncludes);
        let frontend = session.hir();
        let index = Index::build(&frontend.kb, &frontend.loaded);
        names(&index, &frontend.kb, &frontend.interner)
    })
}

/// A word of a name's characters around an offset.
struct Word<'a> {
    text: &'a str,
    start: usize,
    end: usize,
}

fn word_at(text: &str, offset: usize) -> Word<'_> {
    let offset = offset.min(text.len());
    let is_name = |c: char| c.is_alphanumeric() || c == '_';
    let start = text[..offset].char_indices().rev().take_while(|&(_, c)| is_name(c)).last().map_or(offset, |(i, _)| i);
    let end = text[offset..].char_indices().find(|&(_, c)| !is_name(c)).map_or(text.len(), |(i, _)| offset + i);
    Word { text: &text[start..end], start, end }
}

/// True when `offset` is inside a `%` line comment (a `%` outside quotes earlier on the line).
fn in_comment(text: &str, offset: usize) -> bool {
    let offset = offset.min(text.len());
    let line = &text[text[..offset].rfind('\n').map_or(0, |i| i + 1)..offset];
    let mut quote = None;
    for c in line.chars() {
        match (quote, c) {
            (None, '%') => return true,
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            _ => {}
        }
    }
    false
}

/// Code actions: the fixes of the diagnostics whose primary span meets the byte range.
pub fn code_actions(analysis: &Analysis, file: FileId, start: u32, end: u32) -> Vec<CodeActionOrCommand> {
    let mut actions = Vec::new();
    for diagnostic in analysis.diagnostics_in(file) {
        let Some(span) = diagnostic.primary_span() else { continue };
        if span.end < start || span.start > end {
            continue;
        }
        for fix in &diagnostic.fixes {
            let mut changes: HashMap<Url, Vec<TextEdit>> = HashMap::new();
            let mapped = fix.edits.iter().all(|edit| match analysis.uri(edit.span.file) {
                Some(uri) => {
                    let text_edit = TextEdit { range: analysis.range(edit.span), new_text: edit.replacement.clone() };
                    changes.entry(uri.clone()).or_default().push(text_edit);
                    true
                }
                None => false,
            });
            if !mapped {
                continue;
            }
            actions.push(CodeActionOrCommand::CodeAction(CodeAction {
                title: fix.message.clone(),
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: Some(vec![analysis.to_lsp(diagnostic)]),
                edit: Some(WorkspaceEdit { changes: Some(changes), ..WorkspaceEdit::default() }),
                is_preferred: Some(diagnostic.fixes.len() == 1),
                ..CodeAction::default()
            }));
        }
    }
    actions
}
