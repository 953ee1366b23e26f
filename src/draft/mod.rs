//! LLM-assisted drafting of KB parts (`kbc draft`, in progress): what the model's answer is
//! made into before the compiler checks it.
//!
//! Nothing a model writes is executed: its answer is text, the code in it is found here and
//! then parsed as data by the front end like any KB file. The network client is
//! `crate::cli::llm` (IO lives in `src/cli`).

pub mod extract;
