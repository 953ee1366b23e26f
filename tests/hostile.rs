//! Hostile and huge inputs, generated at full size: terms nested 30,000 deep, lists nested
//! 100,000 deep, unary and operator chains 100,000 long, a body of a million goals, a flat
//! list of a million items, ten thousand unbalanced brackets, cyclic terms, includes of
//! devices, FIFOs, directories and a diamond of includes. Each must end with exit status 0 or
//! 1 and a diagnostic (never a stack overflow, a panic or a hang) on `check`, `plan` and
//! `build`, under a memory bound; and through the language server, a document with such
//! content and then an edit that removes it.
//!
//! The binary is run with a virtual-memory limit (`ulimit -v`, 6 GiB: the worker thread
//! reserves 2 GiB of stack address space; the largest of these inputs, the body of a million
//! goals, peaked at 87 MB in a release build, measured by hand) and a
//! wall-clock limit that only catches hangs (a debug build is slow; speed is measured by
//! hand in release builds, see the closing notes of issue 24).

#[path = "support/lsp_client.rs"]
mod lsp_client;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// The inputs, by class: (file name, text).
fn classes() -> Vec<(&'static str, String)> {
    let nested =
        |open: &str, close: &str, n: usize, inner: &str| format!("{}{inner}{}", open.repeat(n), close.repeat(n));
    vec![
        ("deep_fact", format!("p({}).\n", nested("f(", ")", 30_000, "a"))),
        ("deep_rule", format!("p(X) :- X = {}.\n", nested("f(", ")", 30_000, "a"))),
        ("deep_goal", format!("t :- go([{}], [a]).\n", nested("f(", ")", 30_000, "a"))),
        ("deep_list", format!("p({}).\n", nested("[", "]", 100_000, ""))),
        ("unary_minus", format!("p(X) :- X is {}1.\n", "- ".repeat(100_000))),
        ("unary_not", format!("p :- {}q.\nq.\n", "\\+ ".repeat(100_000))),
        ("chain_plus", format!("p(X) :- X = a{}.\n", "+a".repeat(100_000))),
        ("chain_or", format!("p :- a{}.\na.\n", " ; a".repeat(100_000))),
        ("chain_arrow", format!("p :- a{}.\na.\n", " -> a".repeat(100_000))),
        ("chain_if", format!("p :- a{}.\na.\n", " -> a ; a".repeat(100_000))),
        ("chain_minus", format!("p(X) :- X is 1{}.\n", " - 1".repeat(100_000))),
        ("body_1m", format!("p :- a{}.\na.\n", ", a".repeat(1_000_000))),
        ("flat_list_1m", format!("p([a{}]).\n", ",a".repeat(1_000_000))),
        // Past the clause limit (2,500,000 tokens): E0115, then the next clause is read.
        ("minus_3m", format!("p(X) :- X is {}1.\nq.\n", "- ".repeat(3_000_000))),
        ("open_paren", format!("p :- {}\n", "(".repeat(10_000))),
        ("open_bracket", format!("p([{}\n", "[".repeat(10_000))),
        ("close_paren", format!("p :- a{}.\n", ")".repeat(10_000))),
        ("mixed", format!("p :- {}.\n", "([{".repeat(3_334))),
        (
            "cyclic",
            "c :- X = f(X), Y = f(Y), X == Y.\naction(go, [], [], [], [c], [add(done)]).\nt :- go([], [done]).\n"
                .into(),
        ),
        ("loop", "l :- l.\naction(go, [], [], [], [l], [add(done)]).\nt :- go([], [done]).\n".into()),
        // 10^7 ways to fail: the step budget ends it (E0308).
        (
            "exponential",
            "m(1). m(2). m(3). m(4). m(5). m(6). m(7). m(8). m(9). m(10).\n\
             slow :- m(A), m(B), m(C), m(D), m(E), m(F), m(G), A+B+C+D+E+F+G > 100.\n\
             action(go, [], [], [], [slow], [add(done)]).\nt :- go([], [done]).\n"
                .into(),
        ),
        ("inc_urandom", ":- include('/dev/urandom').\n".into()),
        ("inc_zero", ":- include('/dev/zero').\n".into()),
        ("inc_dir", ":- include('/tmp').\n".into()),
        ("inc_fifo", ":- include('fifo').\n".into()),
        ("diamond", ":- include('d1.pl').\n:- include('d1.pl').\n".into()),
    ]
}

/// Writes the inputs (and the FIFO and the diamond's files) into a fresh directory.
fn write_inputs() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("hostile");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    for (name, text) in classes() {
        std::fs::write(dir.join(format!("{name}.pl")), text).expect("written");
    }
    for level in 1..25 {
        let next = format!("d{}.pl", level + 1);
        std::fs::write(
            dir.join(format!("d{level}.pl")),
            format!(":- include('{next}').\n:- include('{next}').\nf{level}.\n"),
        )
        .expect("written");
    }
    std::fs::write(dir.join("d25.pl"), "leaf.\n").expect("written");
    let fifo = Command::new("mkfifo").arg(dir.join("fifo")).status();
    assert!(fifo.is_ok_and(|s| s.success()), "mkfifo makes the FIFO");
    dir
}

/// Runs `kbc ARGS FILE` under the memory limit; the exit status and stderr, or why not.
fn run(dir: &Path, args: &[&str], file: &str) -> Result<(i32, String), String> {
    let kbc = env!("CARGO_BIN_EXE_kbc");
    let command = format!("ulimit -v 6291456 && exec \"{kbc}\" {} \"{file}\"", args.join(" "));
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(&command)
        .current_dir(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run sh: {e}"))?;
    let stderr = child.stderr.take().expect("piped");
    let reader = std::thread::spawn(move || std::io::read_to_string(stderr).unwrap_or_default());
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if started.elapsed() > Duration::from_secs(120) {
            let _ = child.kill();
            return Err("no answer in 120 s: it hangs".into());
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = reader.join().unwrap_or_default();
    Ok((status.code().unwrap_or(-1), stderr))
}

#[test]
fn hostile_inputs_end_with_a_diagnostic_on_every_command() {
    let dir = write_inputs();
    let mut failures = Vec::new();
    for (name, _) in classes() {
        let file = format!("{name}.pl");
        let commands: &[&[&str]] = match name {
            // The largest inputs go through `check`; the others through every command.
            "body_1m" | "flat_list_1m" | "minus_3m" => &[&["check"]],
            _ => &[&["check"], &["plan"], &["build", "--emit", "bt-xml"]],
        };
        for args in commands {
            match run(&dir, args, &file) {
                Ok((status, stderr)) => {
                    let crashed = ["overflowed its stack", "panicked", "internal compiler error", "memory allocation"]
                        .iter()
                        .find(|c| stderr.contains(*c));
                    if let Some(crash) = crashed {
                        failures.push(format!("{name} `{}`: {crash}", args.join(" ")));
                    } else if status != 0 && status != 1 {
                        failures.push(format!("{name} `{}`: exit status {status}", args.join(" ")));
                    } else if status == 1 && !stderr.contains("error[") {
                        failures.push(format!("{name} `{}`: exit status 1 without a diagnostic", args.join(" ")));
                    }
                }
                Err(why) => failures.push(format!("{name} `{}`: {why}", args.join(" "))),
            }
        }
    }
    for (file, code) in [("loop.pl", "error[E0308]"), ("exponential.pl", "error[E0308]")] {
        let (status, stderr) = run(&dir, &["plan"], file).expect("it runs");
        assert!(status == 1 && stderr.contains(code), "{file}: the step budget: {stderr}");
    }
    let (status, stderr) = run(&dir, &["check"], "minus_3m.pl").expect("it runs");
    assert!(status == 1 && stderr.contains("error[E0115]"), "the clause limit: {stderr}");
    assert!(failures.is_empty(), "hostile inputs that broke kbc:\n{}", failures.join("\n"));
}

#[test]
fn a_hostile_document_in_the_editor_is_checked_and_edited_away() {
    use serde_json::json;
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("hostile-lsp");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let mut client = lsp_client::Client::start(&dir, json!({ "debounceMs": 0 }));
    let uri = lsp_types::Url::from_file_path(dir.join("deep.pl")).expect("a path").to_string();
    let deep = format!("p({}).\nq :- {}.\n", "f(".repeat(30_000) + "a" + &")".repeat(30_000), "(".repeat(10_000));
    client.open(&uri, &deep);
    let diagnostics = client.diagnostics(&uri);
    assert!(!diagnostics.is_empty(), "the unclosed brackets are reported");
    assert!(diagnostics.len() <= 200, "repeated diagnostics are capped: {}", diagnostics.len());
    // Replace the whole text with a clean clause: the diagnostics go away.
    let end = json!({ "line": 2, "character": 0 });
    client.notify(
        "textDocument/didChange",
        json!({
            "textDocument": { "uri": uri, "version": 2 },
            "contentChanges": [{ "range": { "start": { "line": 0, "character": 0 }, "end": end }, "text": "p(a).\n" }],
        }),
    );
    assert_eq!(client.diagnostics(&uri), Vec::<serde_json::Value>::new());
    assert!(client.shutdown());
}

/// Every class above (but the includes, which need their files beside them) as an editor
/// document: each is checked (a `publishDiagnostics` comes back, the repeated ones capped),
/// then edited away, and the server still answers.
#[test]
fn every_hostile_class_is_checked_and_edited_away_in_the_editor() {
    use serde_json::json;
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("hostile-lsp-classes");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let mut client = lsp_client::Client::start(&dir, json!({ "debounceMs": 0 }));
    for (name, text) in classes() {
        if name.starts_with("inc_") || name == "diamond" {
            continue;
        }
        let uri = lsp_types::Url::from_file_path(dir.join(format!("{name}.pl"))).expect("a path").to_string();
        client.open(&uri, &text);
        let diagnostics = client.diagnostics(&uri);
        assert!(diagnostics.len() <= 200, "{name}: repeated diagnostics are capped: {}", diagnostics.len());
        let lines = text.lines().count() as u32;
        client.notify(
            "textDocument/didChange",
            json!({
                "textDocument": { "uri": uri, "version": 2 },
                "contentChanges": [{
                    "range": { "start": { "line": 0, "character": 0 }, "end": { "line": lines, "character": 0 } },
                    "text": "p(a).\n",
                }],
            }),
        );
        assert_eq!(client.diagnostics(&uri), Vec::<serde_json::Value>::new(), "{name}: edited away");
        client.notify("textDocument/didClose", json!({ "textDocument": { "uri": uri } }));
    }
    assert!(client.shutdown());
}

/// A grid KB whose relaxation is huge: 30 blocks and 8 agents on 30 × 30 cells, where a move
/// may go from any cell to any cell (`moving/6` has 8 × 30 × 900 × 900 instances).
fn huge_grid() -> String {
    let mut text = String::new();
    for a in 1..=8 {
        text += &format!("agent(a{a}).\n");
    }
    for b in 1..=30 {
        text += &format!("block(b{b}).\n");
    }
    for x in 1..=30 {
        for y in 1..=30 {
            text += &format!("pos({x}, {y}).\n");
        }
    }
    text += "resources(agent(_)).\n\
        action(move_start(A, B, X1, Y1, X2, Y2), [free(A), at(B, X1, Y1)],\n\
        \x20   [at(_, X2, Y2), moving(_, _, _, _, X2, Y2)], [], [agent(A), block(B), pos(X2, Y2)],\n\
        \x20   [del(free(A)), del(at(B, X1, Y1)), add(moving(A, B, X1, Y1, X2, Y2))]).\n\
        action(move_end(A, B, X1, Y1, X2, Y2), [moving(A, B, X1, Y1, _, _)], [], [], [],\n\
        \x20   [del(moving(A, B, X1, Y1, X2, Y2)), add(at(B, X2, Y2)), add(free(A))]).\n";
    let init: Vec<String> =
        (1..=8).map(|a| format!("free(a{a})")).chain((1..=30).map(|b| format!("at(b{b}, {b}, 1)"))).collect();
    let goal: Vec<String> = (1..=30).map(|b| format!("at(b{b}, {}, 2)", 31 - b)).collect();
    text + &format!("big :- go([{}], [{}]).\n", init.join(", "), goal.join(", "))
}

/// The megabytes after "process peak " in a diagnostic.
fn process_peak_mb(stderr: &str) -> Option<f64> {
    let rest = &stderr[stderr.find("process peak ")? + "process peak ".len()..];
    rest.split(' ').next()?.parse().ok()
}

/// `--max-memory` and `--timeout` bound the heuristic's set-up (grounding, the relaxation of
/// the initial state), not only the search: this KB once ran for minutes and took 24 GB
/// before expanding a state.
#[test]
fn the_heuristic_set_up_keeps_to_the_memory_and_time_budgets() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("hostile-setup");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    std::fs::write(dir.join("grid.pl"), huge_grid()).expect("written");
    let (status, stderr) = run(&dir, &["plan", "--max-memory", "64", "--timeout", "100"], "grid.pl").expect("it ends");
    assert_eq!(status, 1, "{stderr}");
    assert!(stderr.contains("error[E0305]") && stderr.contains("64 MB of memory"), "{stderr}");
    assert!(stderr.contains("the heuristic's set-up") && stderr.contains("--search paper"), "{stderr}");
    // The budget covers the relaxation's tables; the rest of the process (the KB, the task,
    // the allocator's slack) is far smaller than another 64 MB.
    let peak = process_peak_mb(&stderr).expect("the note gives the process's peak");
    assert!(peak < 128.0, "the process peaked at {peak} MB under a 64 MB budget");
    let (status, stderr) = run(&dir, &["plan", "--timeout", "1"], "grid.pl").expect("it ends");
    assert_eq!(status, 1, "{stderr}");
    assert!(stderr.contains("error[E0305]") && stderr.contains("ran out of time"), "{stderr}");
}
