//! The repair loop: ask, check, and while the draft has errors and rounds are left, send the
//! diagnostics back and ask again. Every round is kept for the report: the answer, what the
//! checks found, and which problems of the round before are gone.

use super::check::{Checked, Checker};
use super::{Message, Model, prompt};
use crate::diag::{Code, render};

/// One error of an answer, as rounds are compared: its code and message (positions move
/// between answers, so they do not count).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mistake {
    /// The diagnostic's code.
    pub code: Option<Code>,
    /// Its message.
    pub message: String,
}

/// One answer and its check.
pub struct Round {
    /// The model's answer, as it came.
    pub answer: String,
    /// What checking it found.
    pub checked: Checked,
    /// The errors of the round before that this answer no longer has.
    pub fixed: Vec<Mistake>,
    /// Errors this answer has that the round before did not (all of them in the first round).
    pub new: Vec<Mistake>,
}

/// How drafting ended.
#[derive(Debug, PartialEq, Eq)]
pub enum Ending {
    /// The answer of this round (counted from 0) passed every check.
    Passed(usize),
    /// Every round was used and the last answer still has errors.
    OutOfRounds,
    /// The model gave no answer; the reason.
    ModelFailed(String),
}

/// A whole drafting session.
pub struct Drafted {
    /// The rounds, in order.
    pub rounds: Vec<Round>,
    /// How it ended.
    pub ending: Ending,
    /// The conversation as sent, the model's answers included.
    pub conversation: Vec<Message>,
}

impl Drafted {
    /// The round whose answer passed, if one did.
    pub fn passed(&self) -> Option<&Round> {
        match self.ending {
            Ending::Passed(i) => self.rounds.get(i),
            _ => None,
        }
    }
}

/// Drafts with `model`: the first message asks for `task` with `examples`, and at most
/// `rounds` answers are asked for in all (1: no repair).
pub fn draft(
    model: &mut dyn Model,
    checker: &mut Checker<'_>,
    task: &str,
    examples: &[String],
    rounds: usize,
) -> Drafted {
    let want = checker.want().clone();
    let mut conversation = vec![Message::new("user", prompt::first_message(&want, task, examples))];
    let mut done: Vec<Round> = Vec::new();
    for index in 0..rounds.max(1) {
        let answer = match model.answer(&conversation) {
            Ok(answer) => answer,
            Err(why) => return Drafted { rounds: done, ending: Ending::ModelFailed(why), conversation },
        };
        conversation.push(Message::new("assistant", answer.clone()));
        let checked = checker.check(&answer);
        let now = mistakes(&checked);
        let (fixed, new) = match done.last() {
            Some(previous) => {
                let before = mistakes(&previous.checked);
                let fixed = before.iter().filter(|p| !now.contains(p)).cloned().collect();
                let new = now.iter().filter(|p| !before.contains(p)).cloned().collect();
                (fixed, new)
            }
            None => (Vec::new(), now.clone()),
        };
        let passed = checked.passed();
        let rendered = render::all_to_string(&checked.db, &checked.diagnostics);
        done.push(Round { answer, checked, fixed, new });
        if passed {
            return Drafted { rounds: done, ending: Ending::Passed(index), conversation };
        }
        if index + 1 < rounds {
            conversation.push(Message::new("user", prompt::follow_up(&want, &rendered)));
        }
    }
    Drafted { rounds: done, ending: Ending::OutOfRounds, conversation }
}

/// A round's errors, in order.
fn mistakes(checked: &Checked) -> Vec<Mistake> {
    checked
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| Mistake { code: d.code, message: d.message.clone() })
        .collect()
}
