//! Printed terms as plain text: where their layout is and where they split, outside quoted
//! atoms and strings (which keep every character). For the one-line formats kbc writes and
//! reads back: the PDDL-style timed plan and the names of `kbc export pddl`.

/// Calls `visit` with each character of `text` and whether it stands outside quotes (a
/// quoted atom's `'`, a string's `"`, with `\` escapes inside them).
fn scan(text: &str, mut visit: impl FnMut(char, bool)) {
    let mut quote: Option<char> = None;
    let mut escaped = false;
    for c in text.chars() {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if c == '\\' {
                    escaped = true;
                } else if c == q {
                    quote = None; // a doubled quote closes and reopens: the same text
                }
                visit(c, false);
            }
            None => {
                if c == '\'' || c == '"' {
                    quote = Some(c);
                    visit(c, false);
                } else {
                    visit(c, true);
                }
            }
        }
    }
}

/// `text` without the spaces between its tokens (`f(a, b)` becomes `f(a,b)`, one word of a
/// PDDL action), keeping those inside quoted atoms and strings (`'room & hall'`).
pub(crate) fn without_layout(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    scan(text, |c, outside| {
        if !(outside && c == ' ') {
            out.push(c);
        }
    });
    out
}

/// `text` split where `separator` holds outside quotes and brackets, the pieces trimmed and
/// the empty ones left out: `a, f(b, c), 'x, y'` at commas, or `(grip a1 f(b,c))`'s inside at
/// spaces.
pub(crate) fn split_top_level(text: &str, separator: impl Fn(char) -> bool) -> Vec<String> {
    let mut pieces = Vec::new();
    let (mut depth, mut current) = (0i32, String::new());
    scan(text, |c, outside| {
        if outside {
            match c {
                '(' | '[' => depth += 1,
                ')' | ']' => depth -= 1,
                _ if depth == 0 && separator(c) => {
                    pieces.push(std::mem::take(&mut current));
                    return;
                }
                _ => {}
            }
        }
        current.push(c);
    });
    pieces.push(current);
    pieces.into_iter().map(|p| p.trim().to_string()).filter(|p| !p.is_empty()).collect()
}

/// The byte offset of the bracket that closes the one `text` starts with, outside quotes:
/// `(go 'a)b') [1]` gives 9. `None` if it is never closed.
pub(crate) fn closing_bracket(text: &str) -> Option<usize> {
    let (mut depth, mut at, mut found) = (0i32, 0usize, None);
    scan(text, |c, outside| {
        if found.is_none() && outside {
            match c {
                '(' | '[' => depth += 1,
                ')' | ']' => {
                    depth -= 1;
                    if depth == 0 {
                        found = Some(at);
                    }
                }
                _ => {}
            }
        }
        at += c.len_utf8();
    });
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_and_splits_stop_at_quotes_and_brackets() {
        assert_eq!(without_layout("f(a, 'room & hall', \"x y\")"), "f(a,'room & hall',\"x y\")");
        assert_eq!(split_top_level("a, f(b, c), 'x, y', [1, 2]", |c| c == ','), ["a", "f(b, c)", "'x, y'", "[1, 2]"]);
        assert_eq!(split_top_level("grip  a1 'b 2' f(x,y)", char::is_whitespace), ["grip", "a1", "'b 2'", "f(x,y)"]);
        assert_eq!(split_top_level("'it\\'s, here', b", |c| c == ','), ["'it\\'s, here'", "b"]);
        assert_eq!(closing_bracket("(go 'a)b') [1]"), Some(9));
        assert_eq!(closing_bracket("(f(x) 'it\\')') y"), Some(13));
        assert_eq!(closing_bracket("(open"), None);
    }
}
