//! The diagnostic codes, their explanation pages and their UI tests stay in step:
//! every registered code has a page (enforced at compile time by `include_str!`) and a UI test
//! whose expected output shows it; every page in docs/diagnostics/ is registered.

use std::collections::BTreeSet;

use kbc::diag::codes::{ALL, RETIRED};

#[test]
fn every_page_is_registered() {
    let registered: BTreeSet<&str> = ALL.iter().map(|info| info.code).collect();
    for entry in std::fs::read_dir("docs/diagnostics").expect("docs/diagnostics exists") {
        let path = entry.expect("readable entry").path();
        let stem = path.file_stem().and_then(|s| s.to_str()).expect("UTF-8 file name");
        assert!(registered.contains(stem), "{} has no entry in src/diag/codes.rs", path.display());
    }
}

#[test]
fn every_code_has_a_ui_test() {
    let mut expectations = String::new();
    for phase in std::fs::read_dir("tests/ui").expect("tests/ui exists") {
        let phase = phase.expect("readable entry").path();
        if !phase.is_dir() {
            continue;
        }
        for entry in std::fs::read_dir(&phase).expect("readable phase") {
            let path = entry.expect("readable entry").path();
            if path.extension().is_some_and(|e| e == "stderr") {
                expectations.push_str(&std::fs::read_to_string(&path).expect("readable expectation"));
            }
        }
    }
    let untested: Vec<&str> = ALL
        .iter()
        .map(|info| info.code)
        .filter(|code| !RETIRED.contains(code) && !expectations.contains(&format!("[{code}]")))
        .collect();
    assert!(untested.is_empty(), "codes without a UI test showing them: {untested:?}");
    let shown: Vec<&&str> = RETIRED.iter().filter(|code| expectations.contains(&format!("[{code}]"))).collect();
    assert!(shown.is_empty(), "retired codes a UI test still shows: {shown:?}");
}

#[test]
fn every_page_has_an_example_and_its_title() {
    for info in ALL {
        assert!(
            info.explanation.starts_with(&format!("# {}: {}\n", info.code, info.title)),
            "{}: title line",
            info.code
        );
        assert!(info.explanation.contains("```prolog"), "{}: the page shows no example", info.code);
    }
}
