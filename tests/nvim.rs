//! A real editor as the client: Neovim (0.7.2 in Debian, installed by `.ci/run`) runs headless
//! with tests/support/nvim_lsp.lua, which loads the configuration README.md gives
//! (editors/nvim/kbc.lua), opens a KB with a mistake (the configuration starts `kbc lsp` and
//! attaches it), hovers over the mistake, fixes it in the buffer, and writes down what it
//! received. Skips, saying so, when
//! `nvim` is not installed.

use std::process::Command;

/// Line 5 has a misspelt predicate after a comment with characters outside ASCII, one of them
/// outside the Basic Multilingual Plane, so the columns only agree if the server counts UTF-16
/// units and Neovim converts them to bytes.
fn kb() -> String {
    include_str!("support/one_arm.pl").replace("    [agent(A), ontabel(B)", "    /* é🤖 */ [agent(A), ontabel(B)")
}

#[test]
fn neovim_receives_diagnostics_hovers_and_sends_incremental_edits() {
    if Command::new("nvim").arg("--version").output().is_err() {
        eprintln!("skipped: nvim is not installed (`.ci/run` installs it; apt-get install neovim)");
        return;
    }
    let dir = std::env::temp_dir().join(format!("kbc-nvim-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let kb = kb();
    std::fs::write(dir.join("kb.pl"), &kb).unwrap();
    let out = dir.join("seen.json");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/support/nvim_lsp.lua");
    let status = Command::new("nvim")
        .args(["--headless", "--clean", "-n", "-c", &format!("luafile {script}")])
        .env("KBC_BIN", env!("CARGO_BIN_EXE_kbc"))
        .env("KBC_ROOT", &dir)
        .env("KBC_CONFIG", concat!(env!("CARGO_MANIFEST_DIR"), "/editors/nvim/kbc.lua"))
        .env("KBC_OUT", &out)
        .env("HOME", &dir)
        .env("XDG_STATE_HOME", &dir)
        .env("XDG_CACHE_HOME", &dir)
        .current_dir(&dir)
        .status()
        .expect("nvim runs");
    assert!(status.success(), "nvim exited with {status}");
    let seen: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("the script wrote its report")).unwrap();
    assert!(seen.get("error").is_none(), "the script failed: {seen:#}");
    assert_eq!(seen["steps"]["opened"], true, "no diagnostics arrived: {seen:#}");
    let opened = seen["opened"].as_array().unwrap();
    assert_eq!(opened.len(), 1, "{seen:#}");
    let diagnostic = &opened[0];
    assert_eq!(diagnostic["code"], "W0002");
    assert_eq!(diagnostic["source"], "kbc");
    assert_eq!(diagnostic["severity"], 2, "a warning");
    assert_eq!(diagnostic["lnum"], 4);
    // Neovim's columns are bytes: 4 spaces, `/* `, é (2 bytes), 🤖 (4), ` */ `, `[agent(A), `.
    let line = kb.lines().nth(4).unwrap();
    assert!(line.contains('🤖'));
    assert_eq!(diagnostic["col"], line.find("ontabel").unwrap());
    assert_eq!(diagnostic["end_col"], line.find("ontabel").unwrap() + "ontabel".len());
    assert!(diagnostic["message"].as_str().unwrap().contains("did you mean `ontable/1`?"), "{seen:#}");
    assert!(seen["hover"].as_str().unwrap_or("").contains("# W0002"), "{seen:#}");
    assert_eq!(seen["steps"]["fixed"], true, "the fix in the buffer did not clear the diagnostic: {seen:#}");
    let _ = std::fs::remove_dir_all(&dir);
}
