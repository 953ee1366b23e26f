//! The language server, driven through the protocol in-process (lsp-server's memory
//! connection): a scripted editing session, malformed requests, folders checked together.

#[path = "support/lsp_client.rs"]
mod client;
#[path = "support/scratch.rs"]
mod scratch;

use std::path::Path;

use client::Client;
use kbc::lsp::position::apply_edit;
use lsp_types::Range;
use scratch::Scratch;
use serde_json::{Value, json};

/// A KB with one mistake: `ontabel` for `ontable` in pick_start's Valid list (warning W0002:
/// the action can never apply).
const KB: &str = include_str!("support/one_arm.pl");

fn scratch(name: &str) -> Scratch {
    Scratch::new("lsp", name)
}

fn uri(path: &Path) -> String {
    lsp_types::Url::from_file_path(path).expect("absolute").to_string()
}

/// The protocol position of the first occurrence of `needle` in `text`, plus `extra` columns.
fn position_of(text: &str, needle: &str, extra: u32) -> Value {
    let at = text.find(needle).unwrap_or_else(|| panic!("`{needle}` in the text"));
    let line = text[..at].matches('\n').count() as u32;
    let column = (at - text[..at].rfind('\n').map_or(0, |i| i + 1)) as u32 + extra;
    json!({ "line": line, "character": column })
}

/// Request parameters for the position of `needle` (plus `extra` columns) in `uri`'s `text`.
fn at(uri: &str, text: &str, needle: &str, extra: u32) -> Value {
    json!({ "textDocument": { "uri": uri }, "position": position_of(text, needle, extra) })
}

fn codes(diagnostics: &[Value]) -> Vec<String> {
    diagnostics.iter().map(|d| d["code"].as_str().unwrap_or("-").to_string()).collect()
}

fn lines_of(location: &Value) -> u64 {
    location["range"]["start"]["line"].as_u64().expect("a line")
}

#[test]
fn a_scripted_editing_session() {
    let dir = scratch("session");
    let path = dir.join("kb.pl");
    std::fs::write(&path, KB).unwrap();
    let uri = uri(&path);
    let mut client = Client::start(&dir, json!({ "debounceMs": 0 }));

    // Open a file with a mistake: its diagnostic arrives, with the code and the fix's hint.
    client.open(&uri, KB);
    let published = client.published(&uri);
    assert_eq!(published["version"], 1);
    let diagnostics = published["diagnostics"].as_array().unwrap().clone();
    assert_eq!(codes(&diagnostics), ["W0002"], "{diagnostics:#?}");
    let unknown = &diagnostics[0];
    assert_eq!(unknown["range"]["start"], position_of(KB, "ontabel", 0));
    assert_eq!(unknown["range"]["end"], position_of(KB, "ontabel", 7));
    assert_eq!(unknown["severity"], 2);
    assert_eq!(unknown["source"], "kbc");
    let message = unknown["message"].as_str().unwrap();
    assert!(message.starts_with("`ontabel/1` is never in any state"), "{message}");
    assert!(message.contains("help: did you mean `ontable/1`?"), "{message}");

    // An incremental edit that adds a second mistake: the updated set holds both.
    let mut text = KB.to_string();
    let end_of_test = position_of(&text, "[held(b1)])", 9);
    let edit = Range {
        start: serde_json::from_value(end_of_test.clone()).unwrap(),
        end: serde_json::from_value(end_of_test).unwrap(),
    };
    text = apply_edit(&text, edit, ", hled(b2)");
    client.notify(
        "textDocument/didChange",
        json!({
            "textDocument": { "uri": uri, "version": 2 },
            "contentChanges": [{ "range": edit, "text": ", hled(b2)" }],
        }),
    );
    let published = client.published(&uri);
    assert_eq!(published["version"], 2);
    let diagnostics = published["diagnostics"].as_array().unwrap().clone();
    assert_eq!(diagnostics.len(), 2, "{diagnostics:#?}");
    assert!(diagnostics[1]["message"].as_str().unwrap().contains("hled/1"), "{diagnostics:#?}");
    // Undo it with a second incremental edit.
    let start = position_of(&text, ", hled(b2)", 0);
    let end = position_of(&text, ", hled(b2)", 10);
    let undo: Range = serde_json::from_value(json!({ "start": start, "end": end })).unwrap();
    text = apply_edit(&text, undo, "");
    assert_eq!(text, KB);
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 3 }, "contentChanges": [{ "range": undo, "text": "" }] }),
    );
    assert_eq!(codes(&client.diagnostics(&uri)), ["W0002"]);

    // Hover on a state predicate: what adds and deletes it.
    let hover = client.request("textDocument/hover", at(&uri, KB, "holding(A, B)), add", 2)).unwrap();
    let value = hover["contents"]["value"].as_str().unwrap();
    assert!(value.contains("holding/2"), "{value}");
    assert!(value.contains("added by `pick_start`"), "{value}");
    assert!(value.contains("deleted by `pick_end`"), "{value}");
    assert_eq!(hover["range"]["start"], position_of(KB, "holding(A, B)), add", 0));
    // Hover on an action name: its slots and its duration.
    let hover = client.request("textDocument/hover", at(&uri, KB, "pick_end", 1)).unwrap();
    let value = hover["contents"]["value"].as_str().unwrap();
    assert!(value.contains("the end of durative action `pick`"), "{value}");
    assert!(value.contains("Effects: `[del(holding(A, B)), add(agent(A)), add(held(B))]`"), "{value}");
    assert!(value.contains("duration: `duration(pick(_, _), 1, 2).`"), "{value}");
    // Hover on the diagnostic: the code's explanation.
    let hover = client.request("textDocument/hover", at(&uri, KB, "ontabel", 3)).unwrap();
    assert!(hover["contents"]["value"].as_str().unwrap().contains("# W0002"), "{hover:#}");

    // Go to definition: the goal's `held(b1)` is defined where an action adds it.
    let definition = client.request("textDocument/definition", at(&uri, KB, "[held(b1)]", 2)).unwrap();
    let locations = definition.as_array().expect("a list of locations");
    assert_eq!(locations.len(), 1, "{definition:#}");
    assert_eq!(locations[0]["uri"], uri.as_str());
    assert_eq!(locations[0]["range"]["start"], position_of(KB, "held(B))])", 0));
    // From `pick` in the duration fact to both schemas of the durative action.
    let definition = client.request("textDocument/definition", at(&uri, KB, "pick(_, _)", 1)).unwrap();
    let lines: Vec<u64> = definition.as_array().unwrap().iter().map(lines_of).collect();
    assert_eq!(lines, [3, 6], "{definition:#}");
    // References of `agent/1`: the resource, two conditions and effects, the initial state.
    let references = client
        .request(
            "textDocument/references",
            json!({
                "textDocument": { "uri": uri },
                "position": position_of(KB, "agent(_)", 0),
                "context": { "includeDeclaration": true },
            }),
        )
        .unwrap();
    let lines: Vec<u64> = references.as_array().unwrap().iter().map(lines_of).collect();
    assert_eq!(lines, [2, 4, 5, 8, 12], "{references:#}");

    // Completion: the KB's names that start with what is typed, with their arities.
    let completion = client.request("textDocument/completion", at(&uri, KB, "holding(A, B)), add", 3)).unwrap();
    let labels: Vec<String> = completion
        .as_array()
        .unwrap()
        .iter()
        .map(|item| format!("{}{}", item["label"].as_str().unwrap(), item["labelDetails"]["detail"].as_str().unwrap()))
        .collect();
    assert!(labels.contains(&"holding/2".to_string()), "{labels:?}");
    assert!(labels.iter().all(|l| l.starts_with("hol")), "{labels:?}");

    // Outline and workspace symbols.
    let symbols = client.request("textDocument/documentSymbol", json!({ "textDocument": { "uri": uri } })).unwrap();
    let names: Vec<&str> = symbols.as_array().unwrap().iter().map(|s| s["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["pick_start/2", "pick_end/2", "duration/3", "test1"], "{symbols:#}");
    let found = client.request("workspace/symbol", json!({ "query": "pcks" })).unwrap();
    let names: Vec<&str> = found.as_array().unwrap().iter().map(|s| s["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["pick_start"], "{found:#}");

    // The quick fix for the misspelling, applied as the editor would, then re-checked.
    let actions = client
        .request(
            "textDocument/codeAction",
            json!({
                "textDocument": { "uri": uri },
                "range": { "start": position_of(KB, "ontabel", 2), "end": position_of(KB, "ontabel", 2) },
                "context": { "diagnostics": [] },
            }),
        )
        .unwrap();
    let actions = actions.as_array().unwrap();
    assert_eq!(actions.len(), 1, "{actions:#?}");
    assert_eq!(actions[0]["title"], "replace with `ontable`");
    assert_eq!(actions[0]["kind"], "quickfix");
    let edits = actions[0]["edit"]["changes"][uri.as_str()].as_array().unwrap().clone();
    let mut changes = Vec::new();
    for edit in edits.iter().rev() {
        let range: Range = serde_json::from_value(edit["range"].clone()).unwrap();
        let new_text = edit["newText"].as_str().unwrap();
        text = apply_edit(&text, range, new_text);
        changes.push(json!({ "range": range, "text": new_text }));
    }
    assert!(text.contains("[agent(A), ontable(B), clear(B)]"), "{text}");
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 4 }, "contentChanges": changes }),
    );
    assert_eq!(client.diagnostics(&uri), Vec::<Value>::new(), "the fix resolves the diagnostic");
    // After the fix, `ontable/1` is a state predicate the hover describes.
    let hover = client.request("textDocument/hover", at(&uri, &text, "ontable(B), clear", 1)).unwrap();
    assert!(hover["contents"]["value"].as_str().unwrap().contains("in the initial state of `test1`"), "{hover:#}");

    assert!(client.shutdown(), "a clean shutdown and exit");
}

#[test]
fn malformed_requests_get_errors_and_the_server_carries_on() {
    let dir = scratch("malformed");
    let path = dir.join("kb.pl");
    let uri = uri(&path);
    let mut client = Client::start(&dir, json!({ "debounceMs": 0 }));
    // Parameters of the wrong shape: InvalidParams (-32602).
    let error = client.request("textDocument/hover", json!({ "position": "here" })).unwrap_err();
    assert_eq!(error.code, -32602, "{error:?}");
    // An unknown method: MethodNotFound (-32601).
    let error = client.request("textDocument/frobnicate", json!({})).unwrap_err();
    assert_eq!(error.code, -32601, "{error:?}");
    // Positions far outside the file and requests on files never opened answer nothing.
    client.open(&uri, "on(a, b");
    let diagnostics = client.diagnostics(&uri);
    assert!(!diagnostics.is_empty(), "a syntax error is reported");
    let hover = client
        .request(
            "textDocument/hover",
            json!({ "textDocument": { "uri": uri }, "position": { "line": 999, "character": 999 } }),
        )
        .unwrap();
    // The position is clamped to the end of the text, where the missing `.` is reported.
    assert!(hover["contents"]["value"].as_str().unwrap().starts_with("# E0102"), "{hover:#}");
    let elsewhere = uri.replace("kb.pl", "never_opened.pl");
    let definition = client
        .request(
            "textDocument/definition",
            json!({ "textDocument": { "uri": elsewhere }, "position": { "line": 0, "character": 0 } }),
        )
        .unwrap();
    assert_eq!(definition, Value::Null);
    // A change to a document that is not open is ignored, not fatal.
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": elsewhere, "version": 2 }, "contentChanges": [{ "text": "x." }] }),
    );
    // Text that is not a KB at all, with characters beyond the BMP: diagnostics, no crash.
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 2 }, "contentChanges": [{ "text": "🤖 :- ((( [ '\n" }] }),
    );
    let diagnostics = client.diagnostics(&uri);
    assert!(!diagnostics.is_empty());
    for diagnostic in &diagnostics {
        assert!(diagnostic["range"]["start"]["line"].as_u64().unwrap() <= 1, "{diagnostic}");
    }
    assert!(client.shutdown());
}

#[test]
fn the_files_of_a_folder_are_checked_together() {
    let dir = scratch("folder");
    // A domain and a goal file that uses it, and a part included from a subfolder.
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(
        dir.join("domain.pl"),
        ":- include('parts/table.pl').\n".to_string()
            + &KB
                .replace("ontabel", "ontable")
                .replace("test1 :- go([agent(a1), ontable(b1), clear(b1)], [held(b1)]).\n", ""),
    )
    .unwrap();
    std::fs::write(dir.join("parts/table.pl"), "spot(1).\nspot(2).\n").unwrap();
    let goals = "test2 :- go([agent(a1), ontable(b2), clear(b2)], [held(b2)]).\n";
    std::fs::write(dir.join("goals.pl"), goals).unwrap();
    let goals_uri = uri(&dir.join("goals.pl"));
    let mut client = Client::start(&dir, json!({ "debounceMs": 0 }));
    client.open(&goals_uri, goals);
    // Checked with domain.pl, so `held/1` is known: no diagnostics.
    assert_eq!(client.diagnostics(&goals_uri), Vec::<Value>::new());
    // Misspell a predicate of the goal: the unit is re-checked and domain.pl's names suggested.
    let broken = goals.replace("[held(b2)]", "[hold(b2)]");
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": goals_uri, "version": 2 }, "contentChanges": [{ "text": broken }] }),
    );
    let diagnostics = client.diagnostics(&goals_uri);
    assert_eq!(codes(&diagnostics), ["E0210"], "{diagnostics:#?}");
    // Go to definition from the goal file into domain.pl.
    let definition = client
        .request(
            "textDocument/definition",
            json!({ "textDocument": { "uri": goals_uri }, "position": position_of(&broken, "agent(a1)", 1) }),
        )
        .unwrap();
    // `agent/1` is defined where it becomes true: an action's effect and the initial state.
    let targets: Vec<&str> = definition.as_array().unwrap().iter().map(|l| l["uri"].as_str().unwrap()).collect();
    assert_eq!(targets.len(), 2, "{definition:#}");
    assert!(targets[0].ends_with("/domain.pl") && targets[1].ends_with("/goals.pl"), "{definition:#}");
    // The included part, opened, is checked where it is included: its predicate is known
    // through domain.pl, and a mistake in it is reported on it.
    let part_uri = uri(&dir.join("parts/table.pl"));
    // Every file the unit read had its (empty) diagnostics published; skip to the new ones.
    assert!(client.backlog.iter().any(|n| n.params["uri"] == part_uri.as_str()));
    client.backlog.clear();
    client.open(&part_uri, "spot(1).\nspot(2)\n");
    let diagnostics = client.diagnostics(&part_uri);
    assert_eq!(diagnostics.len(), 1, "{diagnostics:#?}");
    assert_eq!(codes(&diagnostics), ["E0102"], "{diagnostics:#?}");
    assert!(client.shutdown());
}

/// The real binary over stdio: it answers, and exits promptly however the client leaves.
mod stdio {
    use std::io::{Read, Write};
    use std::process::{Child, Command, Stdio};
    use std::time::{Duration, Instant};

    fn spawn() -> Child {
        Command::new(env!("CARGO_BIN_EXE_kbc"))
            .args(["lsp", "--stdio"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("kbc runs")
    }

    fn frame(payload: &str) -> Vec<u8> {
        format!("Content-Length: {}\r\n\r\n{payload}", payload.len()).into_bytes()
    }

    fn wait(child: &mut Child) -> i32 {
        let deadline = Instant::now() + Duration::from_secs(30);
        loop {
            if let Some(status) = child.try_wait().expect("waitable") {
                return status.code().expect("exited, not killed");
            }
            if Instant::now() > deadline {
                let _ = child.kill();
                panic!("`kbc lsp` did not exit");
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    const INITIALIZE: &str = r#"{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}"#;

    #[test]
    fn shutdown_then_exit_ends_with_status_0_even_with_stdin_left_open() {
        let mut child = spawn();
        let mut stdin = child.stdin.take().unwrap();
        for payload in [
            INITIALIZE,
            r#"{"jsonrpc":"2.0","method":"initialized","params":{}}"#,
            "{ this is not json",
            r#"{"jsonrpc":"2.0","id":2,"method":"shutdown"}"#,
            r#"{"jsonrpc":"2.0","method":"exit"}"#,
        ] {
            stdin.write_all(&frame(payload)).unwrap();
        }
        stdin.flush().unwrap();
        // stdin stays open (held here) while the server is expected to exit.
        assert_eq!(wait(&mut child), 0);
        let mut out = String::new();
        child.stdout.take().unwrap().read_to_string(&mut out).unwrap();
        assert!(out.contains(r#""id":1,"result":{"capabilities""#), "{out}");
        assert!(out.contains(r#""id":2,"result":null"#), "{out}");
        drop(stdin);
    }

    #[test]
    fn a_client_that_goes_away_ends_the_server_with_status_1() {
        let mut child = spawn();
        let mut stdin = child.stdin.take().unwrap();
        stdin.write_all(&frame(INITIALIZE)).unwrap();
        drop(stdin);
        assert_eq!(wait(&mut child), 1);
        let mut child = spawn();
        let mut stdin = child.stdin.take().unwrap();
        stdin.write_all(&frame(INITIALIZE)).unwrap();
        stdin.write_all(&frame(r#"{"jsonrpc":"2.0","method":"exit"}"#)).unwrap();
        assert_eq!(wait(&mut child), 1, "exit without shutdown");
        drop(stdin);
    }
}

/// Each quick fix the issue names, applied as an editor applies a workspace edit: the
/// diagnostic it fixes is gone from the next set.
#[test]
fn quick_fixes_apply_and_the_file_is_rechecked() {
    let clean = KB.replace("ontabel", "ontable");
    let without_end = {
        let start = clean.find("action(pick_end").unwrap();
        let end = clean.find("duration(").unwrap();
        format!("{}{}", &clean[..start], &clean[end..])
    };
    let cases: Vec<(&str, String, &str, &str)> = vec![
        ("did-you-mean", KB.to_string(), "W0002", "replace with `ontable`"),
        ("operator", format!("{clean}differ(X, Y) :- X != Y.\n"), "E0107", "replace `!=` with `\\=`"),
        ("period", clean.replace("1, 2).", "1, 2)"), "E0102", "add `.`"),
        ("comma", clean.replace("ontable(B), clear(B)]", "ontable(B) clear(B)]"), "E0109", "add `,`"),
        ("end", without_end, "W0019", "declare `pick_end(A, B)`"),
    ];
    for (name, text, code, title) in cases {
        let dir = scratch(&format!("fix-{name}"));
        let uri = uri(&dir.join("kb.pl"));
        let mut client = Client::start(&dir, json!({ "debounceMs": 0 }));
        client.open(&uri, &text);
        let diagnostics = client.diagnostics(&uri);
        let diagnostic = diagnostics
            .iter()
            .find(|d| d["code"] == code)
            .unwrap_or_else(|| panic!("{name}: no {code} in {diagnostics:#?}"));
        let actions = client
            .request(
                "textDocument/codeAction",
                json!({
                    "textDocument": { "uri": uri },
                    "range": diagnostic["range"],
                    "context": { "diagnostics": [diagnostic] },
                }),
            )
            .unwrap();
        let action = actions
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["title"] == title)
            .unwrap_or_else(|| panic!("{name}: no action `{title}` in {actions:#}"));
        // Apply the edits last first, so earlier ranges stay valid.
        let mut edits = action["edit"]["changes"][uri.as_str()].as_array().unwrap().clone();
        edits.sort_by_key(|e| (e["range"]["start"]["line"].as_u64(), e["range"]["start"]["character"].as_u64()));
        let mut fixed = text.clone();
        for edit in edits.iter().rev() {
            let range: Range = serde_json::from_value(edit["range"].clone()).unwrap();
            fixed = apply_edit(&fixed, range, edit["newText"].as_str().unwrap());
        }
        client.notify(
            "textDocument/didChange",
            json!({ "textDocument": { "uri": uri, "version": 2 }, "contentChanges": [{ "text": fixed }] }),
        );
        let after = client.diagnostics(&uri);
        assert!(
            after.iter().all(|d| d["code"] != code),
            "{name}: {code} is still there after the fix:\n{fixed}\n{after:#?}"
        );
        if name != "end" {
            // The other fixes restore the clean KB exactly.
            assert_eq!(after, Vec::<Value>::new(), "{name}:\n{fixed}");
        }
        assert!(client.shutdown());
    }
}

/// Mappings: from a step to its arm-level action, from the mapped start to its schema, and an
/// action's references include the mapping; completion offers std's names too.
#[test]
fn mappings_navigate_both_ways() {
    let dir = scratch("mapping");
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/05_arm_refinement/kb.pl")).unwrap();
    let uri = uri(&dir.join("kb.pl"));
    let mut client = Client::start(&dir, json!({ "debounceMs": 0 }));
    client.open(&uri, &text);
    assert_eq!(client.diagnostics(&uri), Vec::<Value>::new());
    let at = |needle: &str, extra: u32| at(&uri, &text, needle, extra);
    let line = |needle: &str| position_of(&text, needle, 0)["line"].as_u64().unwrap();

    let step = client.request("textDocument/definition", at("close_gripper(A)]", 2)).unwrap();
    let lines: Vec<u64> = step.as_array().unwrap().iter().map(lines_of).collect();
    assert_eq!(lines, [line("ll_action(close_gripper")], "{step:#}");
    let mapped = client.request("textDocument/definition", at("pick_start(A, _)", 2)).unwrap();
    let lines: Vec<u64> = mapped.as_array().unwrap().iter().map(lines_of).collect();
    assert_eq!(lines, [line("action(pick_start")], "{mapped:#}");

    let mut params = at("action(pick_start", 8);
    params["context"] = json!({ "includeDeclaration": false });
    let references = client.request("textDocument/references", params).unwrap();
    let lines: Vec<u64> = references.as_array().unwrap().iter().map(lines_of).collect();
    assert_eq!(lines, [line("mapping(pick_start"), line("duration(pick")], "{references:#}");
    // `pick` in the duration fact is a reference of both schemas of the durative action.
    let mut params = at("action(pick_end", 8);
    params["context"] = json!({ "includeDeclaration": true });
    let references = client.request("textDocument/references", params).unwrap();
    let lines: Vec<u64> = references.as_array().unwrap().iter().map(lines_of).collect();
    assert_eq!(lines, [line("action(pick_end"), line("duration(pick")], "{references:#}");

    let hover = client.request("textDocument/hover", at("action(pick_start", 8)).unwrap();
    let value = hover["contents"]["value"].as_str().unwrap();
    assert!(
        value.contains("refined by `mapping(pick_start(A, _), [move_to_feeder(A), close_gripper(A)]).`"),
        "{value}"
    );

    // Completion at the start of a new line: std's `gripped/2` is offered though the KB has
    // no such name, and built-ins are.
    let labels = |completion: Value| -> Vec<String> {
        completion.as_array().unwrap().iter().map(|i| i["label"].as_str().unwrap().to_string()).collect()
    };
    let edited = format!("{text}gri");
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 2 }, "contentChanges": [{ "text": edited }] }),
    );
    let end = json!({ "line": edited.lines().count() - 1, "character": 3 });
    let completion =
        client.request("textDocument/completion", json!({ "textDocument": { "uri": uri }, "position": end })).unwrap();
    assert!(labels(completion).contains(&"gripped".to_string()));
    let completion = client
        .request("textDocument/completion", json!({ "textDocument": { "uri": uri }, "position": { "line": edited.lines().count() - 1, "character": 0 } }))
        .unwrap();
    let all = labels(completion);
    assert!(all.contains(&"member".to_string()) && all.contains(&"pick_start".to_string()), "{all:?}");
    // Nothing is offered inside a comment.
    let completion = client
        .request(
            "textDocument/completion",
            json!({ "textDocument": { "uri": uri }, "position": { "line": 0, "character": 10 } }),
        )
        .unwrap();
    assert_eq!(completion, json!([]));
    assert!(client.shutdown());
}

/// An independent reading of a protocol position: the text cut into lines at `\r\n`, `\n`
/// or `\r`, a line's length without its terminator in UTF-16 units, a column past it clamped
/// to it, a column inside a surrogate pair moved to the pair's start, a line past the last to
/// the text's end.
fn offset_by_units(text: &str, position: &Value) -> usize {
    let (line, column) =
        (position["line"].as_u64().unwrap() as usize, position["character"].as_u64().unwrap() as usize);
    let mut lines: Vec<(usize, &str)> = Vec::new();
    let mut rest = text;
    let mut start = 0;
    while let Some(at) = rest.find(['\r', '\n']) {
        let terminator = if rest[at..].starts_with("\r\n") { 2 } else { 1 };
        lines.push((start, &rest[..at]));
        start += at + terminator;
        rest = &rest[at + terminator..];
    }
    lines.push((start, rest));
    let Some(&(start, content)) = lines.get(line) else { return text.len() };
    let units: Vec<u16> = content.encode_utf16().collect();
    let mut prefix = &units[..column.min(units.len())];
    if prefix.last().is_some_and(|u| (0xD800..0xDC00).contains(u)) {
        prefix = &prefix[..prefix.len() - 1];
    }
    start + String::from_utf16(prefix).unwrap().len()
}

/// `text` with the protocol range between `a` and `b` replaced (a reversed range is empty).
fn edit_by_units(text: &str, a: &Value, b: &Value, insert: &str) -> String {
    let start = offset_by_units(text, a);
    let end = offset_by_units(text, b).max(start);
    format!("{}{insert}{}", &text[..start], &text[end..])
}

/// A random position in `text`, sometimes out of range or inside a surrogate pair.
fn random_position(rng: &mut kbvm::rng::Rng, text: &str) -> Value {
    let lines: Vec<&str> = text.split(['\n', '\r']).collect();
    let line = rng.below(lines.len() + 2);
    let width = lines.get(line).map_or(3, |l| l.encode_utf16().count() + 2);
    json!({ "line": line, "character": rng.below(width + 1) })
}

/// Random incremental edits with awkward text (astral characters, CRLF, quotes, operators),
/// ranges out of order or out of bounds, and requests at random positions between them: every
/// request is answered, and at the end the diagnostics equal those of a fresh server given the
/// text the edits should have produced, computed here independently of the server's code (so
/// the server applied every edit as the protocol says).
#[test]
fn random_edits_keep_the_server_in_step_with_the_client() {
    const PIECES: &[&str] =
        &["🤖", "é", "(", ")", ".", "\n", "\r\n", "'", "%", ":-", "[", "]", ",", "!=", "_", "X", "on(a, b).\n", ""];
    let dir = scratch("random");
    let uri = uri(&dir.join("kb.pl"));
    let mut rng = kbvm::rng::Rng::new(7);
    let mut client = Client::start(&dir, json!({ "debounceMs": 0 }));
    client.open(&uri, KB);
    client.diagnostics(&uri);
    let mut text = KB.to_string();
    for version in 2..200 {
        let (a, b) = (random_position(&mut rng, &text), random_position(&mut rng, &text));
        let range: Range = serde_json::from_value(json!({ "start": a, "end": b })).unwrap();
        let insert: String = (0..rng.below(3)).map(|_| PIECES[rng.below(PIECES.len())]).collect();
        text = edit_by_units(&text, &a, &b, &insert);
        client.notify(
            "textDocument/didChange",
            json!({
                "textDocument": { "uri": uri, "version": version },
                "contentChanges": [{ "range": range, "text": insert }],
            }),
        );
        let method = ["textDocument/hover", "textDocument/definition", "textDocument/completion"][version % 3];
        let position = random_position(&mut rng, &text);
        let answer = client.request(method, json!({ "textDocument": { "uri": uri }, "position": position }));
        assert!(answer.is_ok(), "{method} at {position} after edit {version}: {answer:?}\n{text}");
        let range = json!({ "start": random_position(&mut rng, &text), "end": random_position(&mut rng, &text) });
        let actions = client.request(
            "textDocument/codeAction",
            json!({ "textDocument": { "uri": uri }, "range": range, "context": { "diagnostics": [] } }),
        );
        assert!(actions.is_ok(), "{actions:?}");
    }
    client.backlog.clear();
    // Changing nothing re-checks and publishes the server's view of the final text.
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 200 }, "contentChanges": [] }),
    );
    let incremental = client.diagnostics(&uri);
    assert!(client.shutdown());

    let fresh_dir = scratch("random-fresh");
    let fresh_uri = crate::uri(&fresh_dir.join("kb.pl"));
    let mut fresh = Client::start(&fresh_dir, json!({ "debounceMs": 0 }));
    fresh.open(&fresh_uri, &text);
    let expected = fresh.diagnostics(&fresh_uri);
    assert!(fresh.shutdown());
    let strip = |diagnostics: Vec<Value>| -> Vec<Value> {
        diagnostics
            .into_iter()
            .map(|mut d| {
                // Related locations name the file, which differs between the two folders.
                d.as_object_mut().unwrap().remove("relatedInformation");
                d
            })
            .collect()
    };
    assert_eq!(strip(incremental), strip(expected), "the final text:\n{text}");
}

/// The document text after random incremental edits equals the independent reading of the
/// same edits, character for character (CRLF lines, astral characters, clamped positions).
#[test]
fn incremental_sync_matches_an_independent_reading_of_positions() {
    use kbc::lsp::workspace::{Grouping, Workspace};
    const PIECES: &[&str] = &["🤖", "é", "a", "\n", "\r\n", "\r", "X.", ""];
    let mut workspace = Workspace::new(None, Grouping::File);
    let uri = lsp_types::Url::parse("untitled:random.pl").unwrap();
    let mut text = "ab\r\n🤖é\r\n\nxyz".to_string();
    workspace.open(uri.clone(), text.clone(), 1);
    let mut rng = kbvm::rng::Rng::new(11);
    for version in 2..3000 {
        let (a, b) = (random_position(&mut rng, &text), random_position(&mut rng, &text));
        let insert: String = (0..rng.below(3)).map(|_| PIECES[rng.below(PIECES.len())]).collect();
        let expected = edit_by_units(&text, &a, &b, &insert);
        let change = serde_json::from_value(json!({ "range": { "start": a, "end": b }, "text": insert })).unwrap();
        workspace.change(&uri, version, vec![change]).unwrap();
        let got = &workspace.document(&uri).unwrap().text;
        assert_eq!(got, &expected, "edit {version}: {a} to {b} with {insert:?} in {text:?}");
        text = expected;
    }
}
