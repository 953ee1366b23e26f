//! Every example checks clean: no errors and no warnings. The top-level `.pl` files of each
//! `examples/NN_name/` directory are checked together, as `kbc check DIR/*.pl` would.

use std::path::{Path, PathBuf};

use kbc::diag::render;
use kbc::source::SourceDb;
use kbc::source::fs::FsLoader;

fn example_dirs() -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir("examples")
        .expect("examples/ exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    dirs
}

fn roots(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("readable example")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "pl"))
        .collect();
    files.sort();
    files
}

/// The front end on `files` read together, as `kbc check FILES` would; panics with the
/// rendered diagnostics, naming `what`, unless it checks clean (no finding with a code).
fn checked_clean(files: &[&Path], what: &Path) -> kbc::session::Frontend {
    let mut db = SourceDb::new();
    let ids: Vec<_> = files
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(p).expect("readable KB file");
            db.add(p.display().to_string(), Some(std::fs::canonicalize(p).expect("exists")), text)
        })
        .collect();
    let (db, frontend, diagnostics) = kbc::session::Session::open(db, &ids, &mut FsLoader).into_parts();
    let problems: Vec<_> = diagnostics.iter().filter(|d| d.code.is_some()).collect();
    assert!(
        problems.is_empty(),
        "{} does not check clean:\n{}",
        what.display(),
        render::all_to_string(&db, &diagnostics)
    );
    frontend
}

#[test]
fn every_example_checks_clean() {
    let dirs = example_dirs();
    assert!(dirs.len() >= 5, "expected the numbered examples, found {dirs:?}");
    for dir in dirs {
        let files = roots(&dir);
        assert!(!files.is_empty(), "{} has no .pl file", dir.display());
        let files: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
        let frontend = checked_clean(&files, &dir);
        assert!(!frontend.kb.problems.is_empty(), "{} defines no problem", dir.display());
    }
}

#[test]
fn the_benchmarks_kbs_of_other_domains_check_clean() {
    // Each warehouse, logistics and pick-and-place problem with the domain file it is measured
    // with (see the README), the sliding puzzle alone: what `kbc plan` reads when those figures
    // are taken.
    let dir = Path::new("benches/other_domains");
    let domains: Vec<(&str, PathBuf)> =
        ["warehouse", "logistics", "pick_place"].iter().map(|d| (*d, dir.join(format!("{d}_domain.pl")))).collect();
    let mut checked = 0;
    for file in roots(dir).iter().filter(|f| !domains.iter().any(|(_, d)| d == *f)) {
        let name = file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let set: Vec<&Path> = match domains.iter().find(|(d, _)| name.starts_with(&format!("{d}_"))) {
            Some((_, domain)) => vec![domain, file],
            None => vec![file],
        };
        let frontend = checked_clean(&set, file);
        assert_eq!(frontend.kb.problems.len(), 1, "{}", file.display());
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} KBs checked");
}

#[test]
fn the_paper_tests_use_the_standard_domain_and_keep_their_names() {
    let path = Path::new("examples/01_paper_tests/tests.pl");
    let session = kbc::session::Session::open_files(&[path.to_path_buf()]);
    let frontend = session.hir();
    assert!(frontend.kb.uses_std_domain);
    let names: Vec<&str> = frontend.kb.problems.iter().map(|p| frontend.interner.resolve(p.name)).collect();
    assert_eq!(names, ["test1", "test2", "test3"]);
    let test3 = &frontend.kb.problems[2];
    assert_eq!((test3.init.len(), test3.goal.len()), (8, 7));
}
