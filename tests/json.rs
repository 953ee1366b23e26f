//! Every JSON line kbc writes with `--message-format json` matches the schema docs/json.md
//! gives for its `type`: the commands below cover each type, on inputs that give errors,
//! warnings, notes, fixes and both plan levels. The schemas are read from the document itself
//! (its ```json blocks), and checked with the subset of JSON Schema they use.

use std::collections::BTreeMap;
use std::process::Command;

use serde_json::Value;

/// The schemas of docs/json.md, by `$id`.
fn schemas() -> BTreeMap<String, Value> {
    let doc = std::fs::read_to_string("docs/json.md").expect("docs/json.md");
    let mut schemas = BTreeMap::new();
    for block in doc.split("```json\n").skip(1) {
        let text = block.split("```").next().expect("a closed block");
        let schema: Value = serde_json::from_str(text).unwrap_or_else(|e| panic!("a schema that does not parse: {e}"));
        let id = schema["$id"].as_str().expect("every schema has an $id").to_string();
        schemas.insert(id, schema);
    }
    schemas
}

/// Whether `value` has JSON Schema type `name`.
fn has_type(value: &Value, name: &str) -> bool {
    match name {
        "object" => value.is_object(),
        "array" => value.is_array(),
        "string" => value.is_string(),
        "integer" => value.is_i64() || value.is_u64(),
        "number" => value.is_number(),
        "boolean" => value.is_boolean(),
        "null" => value.is_null(),
        other => panic!("a type the checker does not know: {other}"),
    }
}

/// The ways `value` breaks `schema`, at `path`.
fn check(value: &Value, schema: &Value, path: &str, errors: &mut Vec<String>) {
    if let Some(types) = schema.get("type") {
        let ok = match types {
            Value::String(name) => has_type(value, name),
            Value::Array(names) => names.iter().any(|n| has_type(value, n.as_str().expect("a type name"))),
            _ => panic!("a malformed `type` at {path}"),
        };
        if !ok {
            errors.push(format!("{path}: {value} is not {types}"));
            return;
        }
    }
    if let Some(allowed) = schema.get("enum").and_then(Value::as_array)
        && !allowed.contains(value)
    {
        errors.push(format!("{path}: {value} is not one of {allowed:?}"));
    }
    if let Some(object) = value.as_object() {
        let properties = schema.get("properties").and_then(Value::as_object);
        for required in schema.get("required").and_then(Value::as_array).into_iter().flatten() {
            let key = required.as_str().expect("a field name");
            if !object.contains_key(key) {
                errors.push(format!("{path}: no `{key}`"));
            }
        }
        for (key, field) in object {
            match properties.and_then(|p| p.get(key)) {
                Some(sub) => check(field, sub, &format!("{path}.{key}"), errors),
                None if schema.get("additionalProperties") == Some(&Value::Bool(false)) => {
                    errors.push(format!("{path}: `{key}` is not in the schema"))
                }
                None => {}
            }
        }
    }
    if let Some(array) = value.as_array() {
        let count = array.len() as u64;
        if schema.get("minItems").and_then(Value::as_u64).is_some_and(|least| count < least) {
            errors.push(format!("{path}: {count} items, fewer than minItems"));
        }
        if schema.get("maxItems").and_then(Value::as_u64).is_some_and(|most| count > most) {
            errors.push(format!("{path}: {count} items, more than maxItems"));
        }
    }
    if let (Some(items), Some(array)) = (schema.get("items"), value.as_array()) {
        for (i, item) in array.iter().enumerate() {
            check(item, items, &format!("{path}[{i}]"), errors);
        }
    }
}

fn kbc(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_kbc")).args(args).output().expect("kbc runs");
    assert!(matches!(output.status.code(), Some(0 | 1)), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout).expect("UTF-8")
}

#[test]
fn every_json_line_matches_its_schema_in_docs_json_md() {
    let schemas = schemas();
    for id in ["diagnostic", "plan", "validation"] {
        assert!(schemas.contains_key(id), "docs/json.md has no schema for `{id}`");
    }
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("json");
    std::fs::create_dir_all(&dir).expect("writable");
    let plan_file = dir.join("plan.txt");
    std::fs::write(&plan_file, kbc(&["plan", "-q", "examples/02_llm_stacking/test_case.pl"])).expect("writable");
    let plan_file = plan_file.to_str().expect("UTF-8 path");
    let json = ["--message-format", "json"];
    let runs: Vec<Vec<&str>> = vec![
        // Errors with labels and fixes, warnings, notes.
        vec!["check", "tests/ui/syntax/missing_comma_in_list.pl"],
        vec!["check", "tests/corpus/llm_slips.pl"],
        vec!["plan", "tests/ui/plan/unreachable_position.pl"],
        vec!["plan", "--format", "json", "examples/02_llm_stacking/test_case.pl"],
        vec![
            "plan",
            "--format",
            "json",
            "--plan",
            "examples/06_partial_order/plan.txt",
            "examples/06_partial_order/kb.pl",
        ],
        vec!["plan", "--format", "json", "--level", "arm", "tests/corpus/crane_two_level.pl"],
        vec!["plan", "--level", "arm", "tests/ui/plan/arm_refinement_fails.pl"],
        vec!["validate", "examples/02_llm_stacking/test_case.pl", plan_file],
        vec!["validate", "examples/02_llm_stacking/test_case.pl", "tests/ui/plan/aux/bad_plan_file.plan"],
        vec!["build", "tests/ui/sim/no_mapping.pl", "--host", "sim", "-o", "-"],
    ];
    let mut seen = BTreeMap::<String, usize>::new();
    let mut errors = Vec::new();
    for args in &runs {
        let args: Vec<&str> = args.iter().copied().chain(json).collect();
        for line in kbc(&args).lines().filter(|l| !l.trim().is_empty()) {
            let value: Value = serde_json::from_str(line)
                .unwrap_or_else(|e| panic!("{args:?}: a line that is not JSON ({e}): {line}"));
            let kind = value["type"].as_str().unwrap_or_else(|| panic!("{args:?}: a line without `type`: {line}"));
            let schema = schemas.get(kind).unwrap_or_else(|| panic!("docs/json.md has no schema for `{kind}`"));
            *seen.entry(kind.to_string()).or_default() += 1;
            check(&value, schema, kind, &mut errors);
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    for id in ["diagnostic", "plan", "validation"] {
        assert!(seen.contains_key(id), "no command gave a `{id}` line: {seen:?}");
    }
}

#[test]
fn the_checker_rejects_what_breaks_a_schema() {
    let schemas = schemas();
    let mut errors = Vec::new();
    let wrong = serde_json::json!({ "type": "validation", "valid": "yes", "timed": false, "problem": "p", "extra": 1 });
    check(&wrong, &schemas["validation"], "validation", &mut errors);
    assert_eq!(errors.len(), 3, "a wrong type, an unknown field, a missing field: {errors:?}");
}

/// `kbc run --record` writes what docs/json.md documents, with one pose per block, gripper and
/// elbow in every frame, and frames in time order up to the run's end.
#[test]
fn the_recorded_run_matches_its_schema_in_docs_json_md() {
    let schemas = schemas();
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("json-record");
    std::fs::create_dir_all(&dir).expect("writable");
    let file = dir.join("run.json");
    let file_arg = file.to_str().expect("UTF-8 path");
    let timeline =
        kbc(&["run", "-q", "examples/02_llm_stacking/test_case.pl", "--fault", "drop:a2@1", "--record", file_arg]);
    let record: Value = serde_json::from_str(&std::fs::read_to_string(&file).expect("written")).expect("JSON");
    let mut errors = Vec::new();
    check(&record, &schemas["kbc-sim-record"], "record", &mut errors);
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    let (blocks, arms) = (record["blocks"].as_array().unwrap().len(), record["arms"].as_array().unwrap().len());
    assert_eq!((blocks, arms), (4, 3), "the example's blocks and arms");
    let frames = record["frames"].as_array().unwrap();
    let mut last = -1.0;
    for frame in frames {
        let t = frame["t"].as_f64().unwrap();
        assert!(t > last, "frames in time order");
        last = t;
        assert_eq!(frame["blocks"].as_array().unwrap().len(), blocks);
        assert_eq!(frame["grippers"].as_array().unwrap().len(), arms);
        assert_eq!(frame["elbows"].as_array().unwrap().len(), arms);
    }
    // The last frame is the run's end, as the timeline prints it.
    let end: f64 = timeline
        .lines()
        .find_map(|l| l.strip_prefix("% success at ")?.split(';').next()?.parse().ok())
        .expect("the run succeeds");
    assert!((last - end).abs() <= 0.05 + 1e-9, "last frame at {last} s, the run ended at {end} s");
    assert_eq!(record["faults"][0]["what"].as_str().map(|w| w.starts_with("drop")), Some(true));
}
