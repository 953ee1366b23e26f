//! LLM-assisted drafting of KB parts (`kbc draft`): the prompt, the checks a model's answer
//! must pass, the repair loop that feeds the compiler's diagnostics back to the model, and the
//! evaluation of drafts against reference answers (the paper's Table of LLM results).
//!
//! Nothing a model writes is executed: its answer is text, the code in it is found by
//! [`extract`] and then parsed as data by the front end like any KB file. This module does no
//! IO: the model is a [`Model`] (the network client is `crate::cli::llm`, recorded answers are
//! [`Recorded`]) and KB files come in as text.

pub mod check;
pub mod eval;
pub mod extract;
pub mod prompt;
pub mod repair;
pub mod state;

use serde::{Deserialize, Serialize};

/// One message of a conversation with a chat model.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Message {
    /// `system`, `user` or `assistant`.
    pub role: String,
    /// The text.
    pub content: String,
}

impl Message {
    /// A message with the given role.
    pub fn new(role: &str, content: impl Into<String>) -> Message {
        Message { role: role.to_string(), content: content.into() }
    }
}

/// A chat model: given the conversation so far (ending with a user message), its answer.
pub trait Model {
    /// The model's answer, or why there is none (the endpoint could not be reached, say).
    fn answer(&mut self, conversation: &[Message]) -> Result<String, String>;
}

/// A model that plays answers recorded earlier, in order, whatever it is asked.
#[derive(Clone, Debug)]
pub struct Recorded {
    answers: Vec<String>,
    next: usize,
}

impl Recorded {
    /// Plays `answers` in order.
    pub fn new(answers: Vec<String>) -> Recorded {
        Recorded { answers, next: 0 }
    }
}

impl Model for Recorded {
    fn answer(&mut self, _conversation: &[Message]) -> Result<String, String> {
        let answer = self.answers.get(self.next).cloned();
        self.next += 1;
        answer.ok_or_else(|| format!("no recorded answer for round {}", self.next))
    }
}

/// What the model is asked to write.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Want {
    /// A test case (`NAME :- go(Init, Goal).`) with this name.
    TestCase {
        /// The name the clause must have.
        name: String,
    },
    /// New `action/6` schemas.
    Actions,
}

impl Want {
    /// The file name the draft is checked under, as diagnostics show it.
    pub fn file_name(&self) -> String {
        match self {
            Want::TestCase { name } => format!("{name}.pl"),
            Want::Actions => "actions.pl".to_string(),
        }
    }
}
