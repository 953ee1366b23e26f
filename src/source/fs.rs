//! Reading from the file system: the one place the compiler library opens files (sources, and
//! the process's peak memory for the search's figures); the shells, `src/cli` and `src/lsp`,
//! print and write.

use std::path::{Path, PathBuf};

use super::{FileId, MAX_FILE_LEN, SourceDb};
use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::passes::load::{LoadedText, SourceLoader};

/// Reads included files from disk.
pub struct FsLoader;

impl SourceLoader for FsLoader {
    fn load(&mut self, path: &Path) -> Result<LoadedText, String> {
        let canonical = std::fs::canonicalize(path).map_err(|e| io_reason(&e))?;
        let text = read_text(&canonical)?;
        Ok(LoadedText { canonical, text })
    }
}

/// An IO error's reason, without the errno: "No such file or directory (os error 2)" reads
/// better as "No such file or directory".
pub fn io_reason(error: &std::io::Error) -> String {
    let text = error.to_string();
    match text.find(" (os error") {
        Some(at) => text[..at].to_string(),
        None => text,
    }
}

/// A file's text: UTF-8, at most [`MAX_FILE_LEN`] bytes.
pub fn read_text(path: &Path) -> Result<String, String> {
    let bytes = std::fs::read(path).map_err(|e| io_reason(&e))?;
    if bytes.len() > MAX_FILE_LEN {
        return Err("the file is larger than 4 GiB".to_string());
    }
    String::from_utf8(bytes).map_err(|e| format!("not valid UTF-8 (byte {})", e.utf8_error().valid_up_to()))
}

/// Reads `paths` into `db`, named as given; an unreadable one becomes a diagnostic.
pub fn read_roots(paths: &[PathBuf], db: &mut SourceDb, diags: &mut Diagnostics) -> Vec<FileId> {
    let mut roots = Vec::new();
    for path in paths {
        match read_text(path) {
            Ok(text) => {
                let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
                roots.push(db.add(path.display().to_string(), Some(canonical), text));
            }
            Err(reason) => diags.push(unreadable(path, &reason)),
        }
    }
    roots
}

/// The diagnostic for a file that cannot be read.
pub fn unreadable(path: &Path, reason: &str) -> Diagnostic {
    Diagnostic::error(codes::UNREADABLE_FILE, format!("cannot read `{}`: {reason}", path.display()))
}

/// The process's peak resident memory in bytes (`VmHWM` in `/proc/self/status`), where the
/// system reports it.
pub fn process_peak_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kilobytes: u64 = line.trim_start_matches("VmHWM:").trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kilobytes * 1024)
}
