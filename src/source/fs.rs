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

/// The most bytes a KB file may have, 64 MiB (the largest KB written by hand or generated
/// for the benchmarks is a few MB): a larger file is refused with a reason that names the
/// limit, before it is read.
pub const MAX_KB_FILE: u64 = 64 << 20;

/// A file's text: a regular file (never a directory, device, FIFO or socket, which could block
/// or never end), of at most [`MAX_KB_FILE`] bytes, in UTF-8.
pub fn read_text(path: &Path) -> Result<String, String> {
    use std::io::Read;
    let metadata = std::fs::metadata(path).map_err(|e| io_reason(&e))?;
    let kind = metadata.file_type();
    if kind.is_dir() {
        return Err("it is a directory, not a file".to_string());
    }
    if !kind.is_file() {
        return Err(format!("it is {}, not a regular file: kbc reads KB files only", special_kind(&kind)));
    }
    let limit = MAX_KB_FILE.min(MAX_FILE_LEN as u64);
    let too_large =
        |size: u64| format!("the file has {size} bytes, more than the {} MiB a KB file may have", limit >> 20);
    if metadata.len() > limit {
        return Err(too_large(metadata.len()));
    }
    // Read at most one byte past the limit: a file that grows while it is read stops there.
    let file = std::fs::File::open(path).map_err(|e| io_reason(&e))?;
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| io_reason(&e))?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| format!("not valid UTF-8 (byte {})", e.utf8_error().valid_up_to()))
}

/// What a file that is neither a regular file nor a directory is.
fn special_kind(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO (a named pipe)";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    let _ = kind;
    "a special file"
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_over_the_limit_is_refused_before_it_is_read() {
        let path = std::env::temp_dir().join(format!("kbc-large-{}.pl", std::process::id()));
        let file = std::fs::File::create(&path).expect("a temporary file");
        file.set_len(MAX_KB_FILE + 1).expect("a sparse file"); // no disk space used
        let error = read_text(&path).expect_err("too large");
        std::fs::remove_file(&path).expect("removed");
        assert!(error.contains("more than the 64 MiB a KB file may have"), "{error}");
    }

    #[test]
    fn devices_and_directories_are_refused_without_reading_them() {
        assert!(read_text(Path::new("/dev/zero")).expect_err("a device").contains("a device"));
        assert!(read_text(&std::env::temp_dir()).expect_err("a directory").contains("a directory"));
    }
}
