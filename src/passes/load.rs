//! Pass `load`: parse the given files and everything they include, in clause order.
//!
//! `:- include(F)` splices F's clauses in at the directive, as SWI-Prolog does, and
//! `:- ensure_loaded(F)` does the same; a file already loaded is not loaded again (for an
//! `include`, warning W0014: SWI-Prolog would insert its clauses twice), so every file is read
//! and parsed once. Paths resolve relative to
//! the including file (`f` also tries `f.pl`). A file that includes itself, directly or
//! through others, is a cycle: reported with a label on every directive in the loop.
//!
//! This pass does no IO: file contents come through a [`SourceLoader`], which the CLI
//! implements with the file system, the language server with its open buffers, and tests
//! with a map.

use std::path::{Component, Path, PathBuf};

use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::intern::{Interner, sym};
use crate::source::{FileId, SourceDb, Span};
use crate::syntax::ast::{Clause, SourceAst, Term, TermKind};
use crate::syntax::parse_source;

/// A file's text and the path that identifies it.
pub struct LoadedText {
    /// The path in canonical form, so two spellings of one file are recognised as one.
    pub canonical: PathBuf,
    /// The text.
    pub text: String,
}

/// Supplies the text of included files.
pub trait SourceLoader {
    /// Reads `path`; on failure returns a short reason ("No such file or directory").
    fn load(&mut self, path: &Path) -> Result<LoadedText, String>;
}

/// A loader that refuses everything; for inputs that must not include files.
pub struct NoIncludes;

impl SourceLoader for NoIncludes {
    fn load(&mut self, _path: &Path) -> Result<LoadedText, String> {
        Err("including files is not available here".to_string())
    }
}

/// A clause of some parsed file, in load order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClauseRef {
    /// Index into [`Loaded::files`].
    pub file: usize,
    /// Index into that file's clauses.
    pub clause: usize,
}

/// Every parsed file and the order of their clauses after includes are spliced in.
#[derive(Debug, Default)]
pub struct Loaded {
    /// The parsed files, in the order they were first read.
    pub files: Vec<SourceAst>,
    /// All clauses in program order, load directives removed.
    pub order: Vec<ClauseRef>,
}

impl Loaded {
    /// The clause behind a reference.
    pub fn clause(&self, r: ClauseRef) -> &Clause {
        &self.files[r.file].clauses[r.clause]
    }

    /// The clauses in program order.
    pub fn clauses(&self) -> impl Iterator<Item = &Clause> {
        self.order.iter().map(|&r| self.clause(r))
    }
}

struct Loader<'a> {
    db: &'a mut SourceDb,
    interner: &'a mut Interner,
    source_loader: &'a mut dyn SourceLoader,
    diags: &'a mut Diagnostics,
    loaded: Loaded,
    /// Canonical paths of files loaded so far, for `ensure_loaded`.
    seen_paths: Vec<PathBuf>,
    /// The chain of files being loaded: (file, the directive that included it).
    stack: Vec<(FileId, Option<Span>)>,
}

/// Parses `roots` (already in `db`) and the files they include.
pub fn load(
    roots: &[FileId],
    db: &mut SourceDb,
    interner: &mut Interner,
    source_loader: &mut dyn SourceLoader,
    diags: &mut Diagnostics,
) -> Loaded {
    let mut loader = Loader {
        db,
        interner,
        source_loader,
        diags,
        loaded: Loaded::default(),
        seen_paths: Vec::new(),
        stack: Vec::new(),
    };
    for &root in roots {
        if let Some(path) = loader.db.file(root).path() {
            loader.seen_paths.push(path.to_path_buf());
        }
        loader.visit(root, None);
    }
    loader.loaded
}

#[derive(Clone, Copy)]
enum LoadKind {
    Include,
    EnsureLoaded,
}

impl Loader<'_> {
    fn visit(&mut self, file: FileId, via: Option<Span>) {
        let text = self.db.file(file).text_arc();
        let ast = parse_source(file, &text, self.interner, self.diags);
        let index = self.loaded.files.len();
        let clause_count = ast.clauses.len();
        self.loaded.files.push(ast);
        self.stack.push((file, via));
        for clause in 0..clause_count {
            let term = &self.loaded.files[index].clauses[clause].term;
            match load_directive(term) {
                Some((kind, arguments)) => {
                    // Load directives are rare; copy their arguments out of the borrowed file.
                    let span = term.span;
                    let arguments: Vec<Term> = arguments.into_iter().cloned().collect();
                    for argument in &arguments {
                        self.follow(file, kind, argument, span);
                    }
                }
                None => self.loaded.order.push(ClauseRef { file: index, clause }),
            }
        }
        self.stack.pop();
    }

    /// A file name written as SWI-Prolog reads one: an atom or string, or path segments joined
    /// by `/` (`kb/actions`, `'..'/shared`).
    fn file_name(&self, term: &Term) -> Option<String> {
        match &term.kind {
            TermKind::Atom(s) | TermKind::Str(s) => Some(self.interner.resolve(*s).to_string()),
            TermKind::Compound(c) if c.functor == sym::SLASH && c.args.len() == 2 => {
                Some(format!("{}/{}", self.file_name(&c.args[0])?, self.file_name(&c.args[1])?))
            }
            _ => None,
        }
    }

    fn follow(&mut self, from: FileId, kind: LoadKind, argument: &Term, directive: Span) {
        let name = match self.file_name(argument) {
            Some(name) => name,
            None => {
                self.diags.push(
                    Diagnostic::error(codes::BAD_LOAD_DIRECTIVE, "expected a file name")
                        .primary(argument.span, "not a file name")
                        .with_note("library(...) and other path aliases are not supported")
                        .with_help("write the path as a quoted atom: include('kb/actions.pl')"),
                );
                return;
            }
        };
        let base = self.db.file(from).path().and_then(Path::parent).map(Path::to_path_buf).unwrap_or_default();
        // Diagnostics name files as the user would: relative to how the includer was named.
        let display_base = Path::new(self.db.file(from).name()).parent().map(Path::to_path_buf).unwrap_or_default();
        let display = display_path(&display_base, &name);
        let candidates = candidate_paths(&base, &name);
        let mut last_error = String::new();
        let mut found = None;
        for candidate in &candidates {
            match self.source_loader.load(candidate) {
                Ok(loaded) => {
                    found = Some(loaded);
                    break;
                }
                Err(reason) => last_error = reason,
            }
        }
        let Some(loaded) = found else {
            let tried = candidate_paths(&display_base, &name)
                .iter()
                .map(|p| format!("`{}`", p.display()))
                .collect::<Vec<_>>()
                .join(" and ");
            self.diags.push(
                Diagnostic::error(codes::UNREADABLE_FILE, format!("cannot read `{name}`: {last_error}"))
                    .primary(argument.span, "included here")
                    .with_note(format!("tried {tried}, relative to the including file")),
            );
            return;
        };
        // A file already on the stack would include itself forever.
        if let Some(position) =
            self.stack.iter().position(|(f, _)| self.db.file(*f).path() == Some(loaded.canonical.as_path()))
        {
            let cyclic = self.stack[position].0;
            let mut diagnostic =
                Diagnostic::error(codes::LOAD_CYCLE, format!("`{}` includes itself", self.db.file(cyclic).name()))
                    .primary(directive, "this directive closes the cycle");
            for (f, via) in self.stack[position + 1..].iter().rev() {
                if let Some(via) = via {
                    diagnostic = diagnostic.secondary(*via, format!("which includes `{}`", self.db.file(*f).name()));
                }
            }
            self.diags.push(diagnostic.with_help("remove one of the directives in the cycle"));
            return;
        }
        if self.seen_paths.contains(&loaded.canonical) {
            // Loaded already, along another path: once is enough. (SWI-Prolog's include/1
            // would splice the clauses in again; a diamond of includes would then grow the
            // program exponentially.)
            if matches!(kind, LoadKind::Include) {
                self.diags.push(
                    Diagnostic::warning(codes::INCLUDED_AGAIN, format!("`{display}` is already loaded"))
                        .primary(directive, "included again here")
                        .with_note(
                            "SWI-Prolog's include/1 would insert its clauses again, so each fact and rule would be \
                             there twice; kbc loads a file once, as ensure_loaded/1 does",
                        )
                        .with_help(
                            "write `:- ensure_loaded(...)` to load it wherever it is needed, or remove this directive",
                        ),
                );
            }
            return;
        }
        self.seen_paths.push(loaded.canonical.clone());
        let id = match self.db.find_path(&loaded.canonical) {
            Some(id) => {
                self.db.set_text(id, loaded.text);
                id
            }
            None => self.db.add(display, Some(loaded.canonical), loaded.text),
        };
        self.visit(id, Some(directive));
    }
}

/// Recognises `:- include(F)`, `:- ensure_loaded(F)`, `:- consult(F)`, `:- load_files(F, _)`
/// and SWI's consult list `:- [F, ...]` (all but `include` loaded like `ensure_loaded`: SWI
/// reloads a file consulted twice, replacing its clauses, which leaves them once; each of
/// them also takes a list of files).
fn load_directive(term: &Term) -> Option<(LoadKind, Vec<&Term>)> {
    let directive = term.as_compound(sym::NECK, 1)?;
    let goal = &directive.args[0];
    match &goal.kind {
        TermKind::Compound(c) if c.functor == sym::INCLUDE && c.args.len() == 1 => {
            Some((LoadKind::Include, vec![&c.args[0]]))
        }
        TermKind::Compound(c)
            if (matches!(c.functor, sym::ENSURE_LOADED | sym::CONSULT) && c.args.len() == 1)
                || (c.functor == sym::LOAD_FILES && matches!(c.args.len(), 1 | 2)) =>
        {
            Some((LoadKind::EnsureLoaded, files(&c.args[0])))
        }
        // `use_module(File)` and `use_module(File, Imports)` of a file of the KB's own (not
        // `library(...)`): loaded once, as SWI-Prolog loads it, its clauses read as plain
        // clauses (kbc has no modules).
        TermKind::Compound(c)
            if c.functor == sym::USE_MODULE
                && matches!(c.args.len(), 1 | 2)
                && c.args[0].as_compound(sym::LIBRARY, 1).is_none() =>
        {
            Some((LoadKind::EnsureLoaded, vec![&c.args[0]]))
        }
        TermKind::List(list) if !list.items.is_empty() && list.tail.is_none() => {
            Some((LoadKind::EnsureLoaded, list.items.iter().collect()))
        }
        _ => None,
    }
}

/// The files a load directive's argument names: each item of a list, or the one file.
fn files(t: &Term) -> Vec<&Term> {
    match &t.kind {
        TermKind::List(list) if list.tail.is_none() => list.items.iter().collect(),
        _ => vec![t],
    }
}

fn candidate_paths(base: &Path, name: &str) -> Vec<PathBuf> {
    let path = normalize(&base.join(name));
    if path.extension().is_some() {
        vec![path]
    } else {
        let mut with_extension = path.clone().into_os_string();
        with_extension.push(".pl");
        vec![PathBuf::from(with_extension), path]
    }
}

fn display_path(base: &Path, name: &str) -> String {
    normalize(&base.join(name)).display().to_string()
}

/// Removes `.` and `a/..` components without touching the file system.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir if out.components().next_back().is_some_and(|c| matches!(c, Component::Normal(_))) => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// A loader over an in-memory map of paths to texts, for tests and the language server.
#[derive(Default)]
pub struct MemoryLoader {
    /// Path to text.
    pub files: std::collections::BTreeMap<PathBuf, String>,
}

impl SourceLoader for MemoryLoader {
    fn load(&mut self, path: &Path) -> Result<LoadedText, String> {
        let path = normalize(path);
        self.files
            .get(&path)
            .map(|text| LoadedText { canonical: path.clone(), text: text.clone() })
            .ok_or_else(|| "No such file or directory".to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(files: &[(&str, &str)], root: &str) -> (Loaded, Diagnostics, SourceDb, Interner) {
        let mut memory = MemoryLoader::default();
        for (path, text) in files {
            memory.files.insert(PathBuf::from(path), text.to_string());
        }
        let mut db = SourceDb::new();
        let root_text = memory.files[&PathBuf::from(root)].clone();
        let id = db.add(root, Some(PathBuf::from(root)), root_text);
        let mut interner = Interner::new();
        let mut diags = Diagnostics::new();
        let loaded = load(&[id], &mut db, &mut interner, &mut memory, &mut diags);
        (loaded, diags, db, interner)
    }

    fn heads(loaded: &Loaded, interner: &Interner) -> Vec<String> {
        loaded.clauses().map(|c| crate::syntax::printer::term_to_string(interner, &c.term)).collect()
    }

    #[test]
    fn include_splices_clauses_at_the_directive() {
        let (loaded, diags, _, interner) = run(
            &[("kb/main.pl", "a.\n:- include('parts/b.pl').\nc.\n"), ("kb/parts/b.pl", "b1.\nb2.\n")],
            "kb/main.pl",
        );
        assert!(diags.is_empty(), "{diags:?}");
        assert_eq!(heads(&loaded, &interner), vec!["a", "b1", "b2", "c"]);
    }

    #[test]
    fn ensure_loaded_loads_once_and_adds_the_extension() {
        let (loaded, diags, _, interner) =
            run(&[("m.pl", ":- ensure_loaded(lib).\n:- ensure_loaded('lib.pl').\nx.\n"), ("lib.pl", "l.\n")], "m.pl");
        assert!(diags.is_empty(), "{diags:?}");
        assert_eq!(heads(&loaded, &interner), vec!["l", "x"]);
    }

    #[test]
    fn consult_and_load_files_load_as_ensure_loaded_does_lists_included() {
        let files = [
            ("m.pl", ":- consult(a).\n:- load_files([b, 'a.pl'], [if(not_loaded)]).\n:- ensure_loaded([c]).\nx.\n"),
            ("a.pl", "a.\n"),
            ("b.pl", ":- consult('c.pl').\nb.\n"),
            ("c.pl", "c.\n"),
        ];
        let (loaded, diags, _, interner) = run(&files, "m.pl");
        assert!(diags.is_empty(), "{diags:?}");
        assert_eq!(heads(&loaded, &interner), vec!["a", "c", "b", "x"]);
    }

    #[test]
    fn cycles_are_reported_once_with_every_directive() {
        let (_, diags, _, _) = run(&[("a.pl", ":- include(b).\n"), ("b.pl", ":- include(a).\n")], "a.pl");
        let cycle: Vec<_> = diags.iter().filter(|d| d.code == Some(codes::LOAD_CYCLE)).collect();
        assert_eq!(cycle.len(), 1);
        assert_eq!(cycle[0].labels.len(), 2, "{:?}", cycle[0]);
    }

    #[test]
    fn missing_files_are_reported_at_the_directive() {
        let (_, diags, _, _) = run(&[("a.pl", ":- include('nope.pl').\n")], "a.pl");
        assert_eq!(diags.iter().map(|d| d.code).collect::<Vec<_>>(), vec![Some(codes::UNREADABLE_FILE)]);
    }
}
