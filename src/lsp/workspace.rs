//! The editor's open documents and the units they are checked in.
//!
//! A KB is usually several files checked together (the domain, the goal files, the parts it
//! includes), as `kbc check a.pl b.pl` would. The server's unit of checking is therefore the
//! folder: the `.pl` files of one directory (open buffers in place of their disk contents)
//! are the roots of one unit, except those another file includes, which are checked where
//! they are included (an included file in a subdirectory belongs to the unit of the folder
//! that includes it). std is implicit, as on the command line. With the initialisation option
//! `"grouping": "file"`, every file is a unit of its own instead (for folders of unrelated
//! examples). Documents that are not files (`untitled:`) are always units of their own.
//!
//! A change marks the units that read the document; the server re-checks them after a short
//! quiet period and publishes the diagnostics of every file they read, merged over all units
//! that read it, including empty sets for files whose problems went away.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use lsp_types::{Diagnostic as LspDiagnostic, TextDocumentContentChangeEvent, Url};

use super::analysis::{Analysis, OverlayLoader, RootText};
use super::position::apply_edit;
use crate::passes::load::SourceLoader;
use crate::source::FileId;

/// How files are grouped into units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grouping {
    /// The files of a folder are checked together (the default).
    Folder,
    /// Every file is checked alone.
    File,
}

/// What a unit is.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum UnitId {
    /// The `.pl` files of a directory.
    Folder(PathBuf),
    /// One document.
    Single(Url),
}

/// An open document.
pub struct Document {
    /// The buffer's text.
    pub text: String,
    /// The version the client gave with the last change.
    pub version: i32,
    /// Its file path, canonical where the file exists; `None` for other schemes.
    path: Option<PathBuf>,
}

/// One file's diagnostics, ready to publish.
pub struct Published {
    /// The file.
    pub uri: Url,
    /// The open document's version, when it is open.
    pub version: Option<i32>,
    /// Every diagnostic on it, over all units that read it.
    pub diagnostics: Vec<LspDiagnostic>,
}

/// Open documents and units.
pub struct Workspace {
    root: Option<PathBuf>,
    grouping: Grouping,
    documents: BTreeMap<Url, Document>,
    /// Each unit's last check; `None` for a unit checked with no roots (nothing to read).
    units: BTreeMap<UnitId, Option<Analysis>>,
}

impl Workspace {
    /// A workspace on the folder `root` (`None` when the client opened single files).
    pub fn new(root: Option<PathBuf>, grouping: Grouping) -> Workspace {
        let root = root.map(|r| std::fs::canonicalize(&r).unwrap_or(r));
        Workspace { root, grouping, documents: BTreeMap::new(), units: BTreeMap::new() }
    }

    /// An open document.
    pub fn document(&self, uri: &Url) -> Option<&Document> {
        self.documents.get(uri)
    }

    /// Opens a document; returns the units to check (with the folders above it checked for
    /// the first time, whose diagnostics are not published yet).
    pub fn open(&mut self, uri: Url, text: String, version: i32) -> Vec<UnitId> {
        let path = uri.to_file_path().ok().map(|p| std::fs::canonicalize(&p).unwrap_or(p));
        self.documents.insert(uri.clone(), Document { text, version, path });
        let mut units = self.discover_owners(&uri);
        for unit in self.units_reading(&uri) {
            if !units.contains(&unit) {
                units.push(unit);
            }
        }
        units
    }

    /// Applies a client's changes in order; returns the units to check.
    pub fn change(
        &mut self,
        uri: &Url,
        version: i32,
        changes: Vec<TextDocumentContentChangeEvent>,
    ) -> Result<Vec<UnitId>, String> {
        let Some(document) = self.documents.get_mut(uri) else {
            return Err(format!("`{uri}` is not open"));
        };
        for change in changes {
            document.text = match change.range {
                Some(range) => apply_edit(&document.text, range, &change.text),
                None => change.text,
            };
        }
        document.version = version;
        Ok(self.units_reading(uri))
    }

    /// Closes a document: from now on its disk contents count. Returns the units to check.
    pub fn close(&mut self, uri: &Url) -> Vec<UnitId> {
        let units = self.units_reading(uri);
        self.documents.remove(uri);
        units
    }

    /// The units to re-check when `uri` changes: those that read it at their last check, or
    /// the unit it belongs to when none has yet.
    pub fn units_reading(&self, uri: &Url) -> Vec<UnitId> {
        let mut units: Vec<UnitId> = self
            .units
            .iter()
            .filter(|(_, analysis)| analysis.as_ref().is_some_and(|a| a.file_of(uri).is_some()))
            .map(|(id, _)| id.clone())
            .collect();
        let home = self.home_unit(uri);
        if !units.contains(&home) {
            units.push(home);
        }
        units
    }

    /// The unit a document belongs to by its place.
    fn home_unit(&self, uri: &Url) -> UnitId {
        let path = self.documents.get(uri).and_then(|d| d.path.clone()).or_else(|| uri.to_file_path().ok());
        match (self.grouping, path.as_deref().and_then(Path::parent)) {
            (Grouping::Folder, Some(folder)) => UnitId::Folder(folder.to_path_buf()),
            _ => UnitId::Single(uri.clone()),
        }
    }

    /// Checks the folders above a newly opened file, up to the workspace root, once each, so a
    /// file included from a parent folder is checked where it is included. Returns the folders
    /// checked for the first time that have files.
    fn discover_owners(&mut self, uri: &Url) -> Vec<UnitId> {
        let mut discovered = Vec::new();
        let (Some(root), Grouping::Folder) = (self.root.clone(), self.grouping) else {
            return discovered;
        };
        let Some(path) = self.documents.get(uri).and_then(|d| d.path.clone()) else {
            return discovered;
        };
        let mut folder = path.parent().and_then(Path::parent);
        while let Some(dir) = folder.filter(|d| d.starts_with(&root)) {
            let id = UnitId::Folder(dir.to_path_buf());
            if !self.units.contains_key(&id) {
                self.check(std::slice::from_ref(&id));
                if self.units.get(&id).is_some_and(Option::is_some) {
                    discovered.push(id.clone());
                }
            }
            if self.units.get(&id).and_then(Option::as_ref).is_some_and(|a| a.included_paths().contains(&path)) {
                break;
            }
            folder = dir.parent();
        }
        discovered
    }

    /// Re-checks `ids`; returns the diagnostics to publish.
    pub fn check(&mut self, ids: &[UnitId]) -> Vec<Published> {
        let mut touched: BTreeSet<Url> = BTreeSet::new();
        let mut recheck: BTreeSet<UnitId> = BTreeSet::new();
        for id in ids {
            let previous = self.units.get(id).and_then(Option::as_ref);
            touched.extend(previous.into_iter().flat_map(Analysis::uris).cloned());
            let included_before: BTreeSet<PathBuf> =
                previous.map(Analysis::included_paths).unwrap_or_default().into_iter().collect();
            let analysis = self.analyse(id);
            touched.extend(analysis.iter().flat_map(Analysis::uris).cloned());
            let included: BTreeSet<PathBuf> =
                analysis.as_ref().map(Analysis::included_paths).unwrap_or_default().into_iter().collect();
            self.units.insert(id.clone(), analysis);
            // A file no longer included here becomes a root of its own folder again.
            for dropped in included_before.difference(&included) {
                if let Some(folder) = dropped.parent() {
                    recheck.insert(UnitId::Folder(folder.to_path_buf()));
                }
            }
        }
        for id in recheck {
            if !ids.contains(&id) && self.units.contains_key(&id) {
                let more = self.check(std::slice::from_ref(&id));
                touched.extend(more.into_iter().map(|p| p.uri));
            }
        }
        touched.into_iter().map(|uri| self.published(uri)).collect()
    }

    /// One file's diagnostics over every unit that read it.
    fn published(&self, uri: Url) -> Published {
        let mut diagnostics = Vec::new();
        for analysis in self.units.values().flatten() {
            if let Some(file) = analysis.file_of(&uri) {
                for diagnostic in analysis.diagnostics_in(file) {
                    let converted = analysis.to_lsp(diagnostic);
                    if !diagnostics.contains(&converted) {
                        diagnostics.push(converted);
                    }
                }
            }
        }
        let version = self.documents.get(&uri).map(|d| d.version);
        Published { uri, version, diagnostics }
    }

    /// Runs the front end on a unit's roots; `None` when it has none.
    fn analyse(&self, id: &UnitId) -> Option<Analysis> {
        let mut excluded: BTreeSet<PathBuf> = BTreeSet::new();
        for (other, analysis) in &self.units {
            if other != id
                && let Some(analysis) = analysis
            {
                excluded.extend(analysis.included_paths());
            }
        }
        let open =
            |path: &Path| self.documents.values().find(|d| d.path.as_deref() == Some(path)).map(|d| d.text.clone());
        let base = self.root.as_deref();
        let run = |roots: &[PathBuf]| {
            let texts = roots.iter().filter_map(|path| self.root_text(id, path)).collect();
            Analysis::run(texts, &mut OverlayLoader { open: &open }, base)
        };
        let mut roots = self.root_paths(id, &excluded);
        if roots.is_empty() {
            return None;
        }
        let first = run(&roots);
        // A root that another root includes is read where it is included: check again without.
        let included = first.included_paths();
        if !roots.iter().any(|r| included.contains(r)) {
            return Some(first);
        }
        roots.retain(|r| !included.contains(r));
        (!roots.is_empty()).then(|| run(&roots))
    }

    /// A unit's root files, sorted, without those `excluded`.
    fn root_paths(&self, id: &UnitId, excluded: &BTreeSet<PathBuf>) -> Vec<PathBuf> {
        match id {
            UnitId::Single(uri) => match self.documents.get(uri) {
                Some(document) => vec![document.path.clone().unwrap_or_default()],
                None => Vec::new(),
            },
            UnitId::Folder(folder) => {
                let mut paths: BTreeSet<PathBuf> = BTreeSet::new();
                if let Ok(entries) = std::fs::read_dir(folder) {
                    for entry in entries.flatten() {
                        let path = entry.path();
                        if path.extension().is_some_and(|e| e == "pl") && path.is_file() {
                            paths.insert(std::fs::canonicalize(&path).unwrap_or(path));
                        }
                    }
                }
                for document in self.documents.values() {
                    if let Some(path) = &document.path
                        && path.parent() == Some(folder.as_path())
                    {
                        paths.insert(path.clone());
                    }
                }
                paths.into_iter().filter(|p| !excluded.contains(p)).collect()
            }
        }
    }

    /// A root's text: the open buffer's, else the disk's (unreadable files are left out).
    fn root_text(&self, id: &UnitId, path: &Path) -> Option<RootText> {
        if let UnitId::Single(uri) = id {
            let document = self.documents.get(uri)?;
            return Some(RootText { uri: uri.clone(), path: document.path.clone(), text: document.text.clone() });
        }
        let owned = Some(path.to_path_buf());
        if let Some((uri, document)) = self.documents.iter().find(|(_, d)| d.path == owned) {
            return Some(RootText { uri: uri.clone(), path: owned, text: document.text.clone() });
        }
        let text = crate::source::fs::FsLoader.load(path).ok()?.text;
        Some(RootText { uri: Url::from_file_path(path).ok()?, path: owned, text })
    }

    /// The latest check that read `uri`, and the file's id in it. The document's home unit
    /// comes first, then the others in order.
    pub fn analysis_of(&self, uri: &Url) -> Option<(&Analysis, FileId)> {
        let home = self.home_unit(uri);
        let others = self.units.iter().filter(|(id, _)| **id != home).map(|(_, analysis)| analysis);
        let home_first = self.units.get(&home).into_iter().chain(others);
        home_first.flatten().find_map(|a| a.file_of(uri).map(|f| (a, f)))
    }

    /// Every check, for workspace-wide requests.
    pub fn analyses(&self) -> impl Iterator<Item = &Analysis> {
        self.units.values().flatten()
    }
}
