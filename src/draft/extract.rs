//! Finding the code in a model's answer.
//!
//! Chat models wrap code in Markdown fences, usually tagged `prolog`, and surround it with
//! prose. The code is the contents of the fenced blocks tagged as Prolog (`prolog`, `pl`,
//! `swi`, `swipl`) or untagged, in order; when every fence has another tag, all of them. An
//! answer without fences is taken from the first line that starts a clause to the last line
//! that ends one, so a sentence before or after it is left out. A fence left open runs to the
//! end of the answer. Prose is told from code by its first line: after a complete clause, an
//! unindented line that starts no clause (a sentence starts with a capital letter, which no
//! clause can). Code whose last clause lacks its full stop runs to the end of the answer.

/// Where the code was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Found {
    /// In this many fenced blocks.
    Fenced(usize),
    /// Between the prose of an answer without fences.
    Bare,
}

/// The code of an answer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Extracted {
    /// The code, ending with a newline.
    pub code: String,
    /// Where it was found.
    pub found: Found,
}

/// The code in `answer`, or `None` when it holds none.
pub fn extract_code(answer: &str) -> Option<Extracted> {
    let blocks = fenced_blocks(answer);
    if !blocks.is_empty() {
        let prolog: Vec<&(String, String)> = blocks.iter().filter(|(tag, _)| is_prolog_tag(tag)).collect();
        let chosen: Vec<&(String, String)> = if prolog.is_empty() { blocks.iter().collect() } else { prolog };
        let code: String = chosen.iter().map(|(_, body)| body.as_str()).collect();
        return (!code.trim().is_empty()).then_some(Extracted { code, found: Found::Fenced(chosen.len()) });
    }
    let lines: Vec<&str> = answer.lines().collect();
    let first = lines.iter().position(|l| starts_clause(l))?;
    // Prose resumes at an unindented line, after a complete clause, that starts no clause.
    let mut end = lines.len();
    for (at, line) in lines.iter().enumerate().skip(first + 1) {
        let prose = !line.starts_with(char::is_whitespace)
            && !line.trim().is_empty()
            && !line.starts_with('%')
            && !starts_clause(line);
        if prose && ends_clause(lines[at - 1]) {
            end = at;
            break;
        }
    }
    // The code ends with its last full stop; without one (the model forgot it), it runs to
    // the last non-blank line, and the front end reports the missing `.`.
    let last = match lines[first..end].iter().rposition(|l| ends_clause(l)) {
        Some(last) => first + last,
        None => first + lines[first..end].iter().rposition(|l| !l.trim().is_empty())?,
    };
    let mut code = lines[first..=last].join("\n");
    code.push('\n');
    Some(Extracted { code, found: Found::Bare })
}

/// `(tag, body)` of each fenced block, in order.
fn fenced_blocks(answer: &str) -> Vec<(String, String)> {
    let mut blocks = Vec::new();
    let mut open: Option<(String, String)> = None;
    for line in answer.lines() {
        let trimmed = line.trim_start();
        match (&mut open, trimmed.strip_prefix("```")) {
            (None, Some(tag)) => open = Some((tag.trim().to_ascii_lowercase(), String::new())),
            (Some(_), Some(rest)) if rest.trim().is_empty() => blocks.extend(open.take()),
            (Some((_, body)), _) => {
                body.push_str(line);
                body.push('\n');
            }
            (None, None) => {}
        }
    }
    blocks.extend(open);
    blocks
}

fn is_prolog_tag(tag: &str) -> bool {
    matches!(tag, "" | "prolog" | "pl" | "swi" | "swipl" | "swi-prolog")
}

/// A line that begins a clause or directive: a lower-case name followed by `(`, ` :-` or `.`,
/// or `:-`.
fn starts_clause(line: &str) -> bool {
    let line = line.trim_start();
    if line.starts_with(":-") {
        return true;
    }
    let name_end = line.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(line.len());
    let (name, rest) = line.split_at(name_end);
    name.starts_with(|c: char| c.is_ascii_lowercase())
        && (rest.starts_with('(') || rest.trim_start().starts_with(":-") || rest.trim_start().starts_with('.'))
}

/// A line whose code (before a `%` comment) ends with the `.` that ends a clause.
fn ends_clause(line: &str) -> bool {
    let code = match line.find('%') {
        Some(at) => &line[..at],
        None => line,
    };
    code.trim_end().ends_with('.')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prolog_fences_are_taken_and_prose_left_out() {
        let answer = "Here is the test case:\n\n```prolog\ntest_case :- go([a], [b]).\n```\n\nIt moves b.\n";
        let found = extract_code(answer).unwrap();
        assert_eq!(found.code, "test_case :- go([a], [b]).\n");
        assert_eq!(found.found, Found::Fenced(1));
    }

    #[test]
    fn several_blocks_join_and_other_languages_are_skipped() {
        let answer = "```prolog\na(1).\n```\nand\n```bash\nswipl kb.pl\n```\n```\nb(2).\n```";
        assert_eq!(extract_code(answer).unwrap().code, "a(1).\nb(2).\n");
        let only_other = "```python\nx = 1\n```";
        assert_eq!(extract_code(only_other).unwrap().code, "x = 1\n");
    }

    #[test]
    fn an_open_fence_runs_to_the_end() {
        assert_eq!(extract_code("```prolog\na(1).\nb(2).").unwrap().code, "a(1).\nb(2).\n");
    }

    #[test]
    fn bare_code_is_cut_out_of_its_prose() {
        let answer = "Sure! The test case is:\ntest_case :- go([available(a1)],\n    [available(a1)]). % done\nI hope this helps.";
        let found = extract_code(answer).unwrap();
        assert_eq!(found.code, "test_case :- go([available(a1)],\n    [available(a1)]). % done\n");
        assert_eq!(found.found, Found::Bare);
    }

    #[test]
    fn bare_code_without_its_last_full_stop_runs_to_the_end() {
        let answer = "test_case :- go([available(a1)],\n  [available(a1)])\n\n";
        assert_eq!(extract_code(answer).unwrap().code, "test_case :- go([available(a1)],\n  [available(a1)])\n");
    }

    #[test]
    fn answers_without_code_have_none() {
        assert_eq!(extract_code("I cannot help with that."), None);
        assert_eq!(extract_code("```prolog\n\n```"), None);
        assert_eq!(extract_code(""), None);
    }
}
