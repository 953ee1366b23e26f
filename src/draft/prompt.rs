//! The messages sent to the model: the first, in the shape of the paper's Figure "Example of
//! message used to query the LLM" (a sentence on what the cases do, the KB's own test cases
//! with their comments, the request), and the follow-ups that carry the compiler's
//! diagnostics.

use super::Want;
use crate::ir::hir::{Kb, Level, ProblemForm};
use crate::source::{SourceDb, Span};
use crate::stdlib::{STD_ARMS_NAME, STD_BLOCKS_NAME};

/// The source text of the KB's named test cases (`name :- go(...)`), each with the comment
/// lines written directly above it, in KB order.
pub fn test_case_examples(db: &SourceDb, kb: &Kb) -> Vec<String> {
    kb.problems.iter().filter(|p| matches!(p.form, ProblemForm::Go(_))).map(|p| with_comment(db, p.span)).collect()
}

/// The source text of the KB's `action/6` schemas, each with the comment lines directly above
/// it; those of the standard library too when it is the domain.
pub fn action_examples(db: &SourceDb, kb: &Kb) -> Vec<String> {
    kb.actions
        .iter()
        .filter(|a| a.level == Level::High)
        .filter(|a| kb.uses_std_domain || ![STD_ARMS_NAME, STD_BLOCKS_NAME].contains(&db.file(a.span.file).name()))
        .map(|a| with_comment(db, a.span))
        .collect()
}

/// The text of `span` (to the end of its clause's `.`), preceded by the `%` comment lines
/// directly above its first line.
fn with_comment(db: &SourceDb, span: Span) -> String {
    let file = db.file(span.file);
    let text = file.text();
    let mut end = span.end as usize;
    // An item's span is its term's: the clause's full stop comes after it.
    if let Some(dot) = text[end..].find('.') {
        if text[end..end + dot].trim().is_empty() {
            end += dot + 1;
        }
    }
    let mut line = file.line_index(span.start);
    while line > 0 && text[file.line_range(line - 1)].trim_start().starts_with('%') {
        line -= 1;
    }
    text[file.line_range(line).start..end].to_string()
}

/// The first message: what the examples are, the examples, and the request.
pub fn first_message(want: &Want, task: &str, examples: &[String]) -> String {
    let mut message = String::new();
    match want {
        Want::TestCase { name } => {
            message.push_str("Consider the following test cases.\n");
            message.push_str(
                "Each of them moves a set of boxes (b1, b2, b3, ...) from an initial state to a final state \
                 using agents (a1, a2, ...).\n\n",
            );
            for example in examples {
                message.push_str(example.trim_end());
                message.push_str("\n\n");
            }
            message.push_str(&format!(
                "Can you generate a prolog code containing a new test case, namely {name}, for the following task?\n\n"
            ));
            message.push_str(task.trim());
            message.push_str(&format!(
                "\n\nAnswer with the Prolog clause `{name} :- go(InitialState, GoalState).` only. Both states list \
                 every fact that holds in them, as the examples do."
            ));
        }
        Want::Actions => {
            message.push_str("Consider the following action schemas of a Prolog knowledge base.\n");
            message.push_str(
                "Each is action(Name, ValidConditions, InvalidConditions, InvalidConditionsAtEnd, ConditionsOnKB, \
                 Effects): conditions that must hold in the current state, that must not hold, that must not be \
                 wanted by the goal, that the knowledge base must prove, and the effects as add(Fact) and \
                 del(Fact).\n\n",
            );
            for example in examples {
                message.push_str(example.trim_end());
                message.push_str("\n\n");
            }
            message.push_str("Can you generate the Prolog action schemas for the following task?\n\n");
            message.push_str(task.trim());
            message.push_str("\n\nAnswer with the new action/6 clauses only.");
        }
    }
    message.push('\n');
    message
}

/// The follow-up after an answer with errors: the diagnostics as the terminal shows them.
pub fn follow_up(want: &Want, rendered: &str) -> String {
    let what = match want {
        Want::TestCase { name } => format!("the whole corrected test case `{name}`"),
        Want::Actions => "the whole corrected set of new action schemas".to_string(),
    };
    format!(
        "The Prolog compiler found these problems in your answer:\n\n{}\n\nPlease answer with {what}, as Prolog \
         code only.\n",
        rendered.trim_end()
    )
}
