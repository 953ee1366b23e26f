//! A client for OpenAI-compatible chat-completion endpoints (`POST {base}/chat/completions`),
//! for `kbc draft`: a local llama.cpp or Ollama server, or a hosted one (with the `tls`
//! feature).
//!
//! Requests ask for temperature 0. Each attempt has a time limit; a 429 or a 5xx answer is
//! retried after a backoff that doubles from `Retry::first_backoff` up to `max_backoff` (or the
//! server's `Retry-After`, if it says less than that cap), at most `Retry::attempts` times in
//! all. Everything else fails at once with an [`LlmError`] that says what happened: the
//! endpoint could not be reached, did not answer in time, answered with an error status, or
//! answered something that is not a chat completion. The API key is sent as a bearer token and
//! never appears in an error, a log line or a `Debug` print.

use std::fmt;
use std::time::Duration;

use serde::Serialize;

pub use crate::draft::Message;

/// Where the model is.
#[derive(Clone)]
pub struct Endpoint {
    /// The API's base URL (`http://127.0.0.1:8080/v1`), or the full `/chat/completions` URL.
    pub url: String,
    /// The model name sent with each request.
    pub model: String,
    /// The bearer token, if the endpoint needs one.
    pub api_key: Option<String>,
}

impl fmt::Debug for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Endpoint")
            .field("url", &self.url)
            .field("model", &self.model)
            .field("api_key", &self.api_key.as_ref().map(|_| "<redacted>"))
            .finish()
    }
}

impl Endpoint {
    /// The URL requests go to.
    pub fn completions_url(&self) -> String {
        let base = self.url.trim_end_matches('/');
        if base.ends_with("/chat/completions") { base.to_string() } else { format!("{base}/chat/completions") }
    }
}

/// How often and how patiently to retry.
#[derive(Clone, Copy, Debug)]
pub struct Retry {
    /// Attempts in all, the first included (at least 1).
    pub attempts: u32,
    /// The wait before the second attempt; it doubles after each.
    pub first_backoff: Duration,
    /// The longest wait between attempts.
    pub max_backoff: Duration,
}

impl Default for Retry {
    fn default() -> Retry {
        Retry { attempts: 4, first_backoff: Duration::from_millis(500), max_backoff: Duration::from_secs(8) }
    }
}

/// A model's answer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Completion {
    /// The assistant's text.
    pub content: String,
    /// The model that answered, as the endpoint names it.
    pub model: Option<String>,
    /// Attempts it took (1 when the first succeeded).
    pub attempts: u32,
}

/// Why no completion came back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LlmError {
    /// The URL is not one the client can use.
    BadUrl { url: String, why: String },
    /// Nothing answered: connection refused, unknown host, network down.
    Unreachable { url: String, why: String },
    /// The endpoint took longer than the time limit.
    TimedOut { url: String, limit: Duration },
    /// The endpoint answered with an error status (after `attempts` attempts).
    Status { url: String, status: u16, message: String, attempts: u32 },
    /// The endpoint answered 200 with something that is not a chat completion.
    NotACompletion { url: String, why: String, excerpt: String },
}

impl fmt::Display for LlmError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LlmError::BadUrl { url, why } => write!(f, "cannot use the endpoint `{url}`: {why}"),
            LlmError::Unreachable { url, why } => write!(f, "cannot reach `{url}`: {why}"),
            LlmError::TimedOut { url, limit } => {
                write!(f, "`{url}` did not answer within {:.1} s", limit.as_secs_f64())
            }
            LlmError::Status { url, status, message, attempts } => {
                write!(f, "`{url}` answered HTTP {status}")?;
                if *attempts > 1 {
                    write!(f, " ({attempts} attempts)")?;
                }
                if !message.is_empty() {
                    write!(f, ": {message}")?;
                }
                Ok(())
            }
            LlmError::NotACompletion { url, why, excerpt } => {
                write!(f, "`{url}` did not answer with a chat completion ({why}); it began: {excerpt:?}")
            }
        }
    }
}

impl std::error::Error for LlmError {}

/// A chat-completion client.
pub struct Client {
    agent: ureq::Agent,
    endpoint: Endpoint,
    retry: Retry,
    timeout: Duration,
}

#[derive(Serialize)]
struct ChatRequest<'a> {
    model: &'a str,
    messages: &'a [Message],
    temperature: f64,
    stream: bool,
}

/// The largest answer read (a completion is text a person could review).
const MAX_BODY: u64 = 16 << 20;

impl Client {
    /// A client for `endpoint`; each attempt may take at most `timeout`.
    pub fn new(endpoint: Endpoint, timeout: Duration, retry: Retry) -> Result<Client, LlmError> {
        let url = endpoint.completions_url();
        if !(url.starts_with("http://") || url.starts_with("https://")) {
            return Err(LlmError::BadUrl { url, why: "expected an http:// or https:// URL".to_string() });
        }
        if url.starts_with("https://") && !cfg!(feature = "tls") {
            return Err(LlmError::BadUrl {
                url,
                why: "this kbc was built without TLS; build it with `--features tls`, or use a local http:// server"
                    .to_string(),
            });
        }
        let agent =
            ureq::Agent::config_builder().timeout_global(Some(timeout)).http_status_as_error(false).build().into();
        Ok(Client { agent, endpoint, retry: Retry { attempts: retry.attempts.max(1), ..retry }, timeout })
    }

    /// Asks for a completion of `messages` at temperature 0.
    pub fn complete(&self, messages: &[Message]) -> Result<Completion, LlmError> {
        let url = self.endpoint.completions_url();
        let body = ChatRequest { model: &self.endpoint.model, messages, temperature: 0.0, stream: false };
        let mut backoff = self.retry.first_backoff;
        for attempt in 1..=self.retry.attempts {
            let mut request = self.agent.post(&url).header("Accept", "application/json");
            if let Some(key) = &self.endpoint.api_key {
                request = request.header("Authorization", format!("Bearer {key}"));
            }
            let mut response = match request.send_json(&body) {
                Ok(response) => response,
                Err(error) => return Err(self.transport_error(&url, error)),
            };
            let status = response.status().as_u16();
            let retry_after = response
                .headers()
                .get("retry-after")
                .and_then(|v| v.to_str().ok())
                .and_then(|v| v.trim().parse::<u64>().ok())
                .map(Duration::from_secs);
            let text = match response.body_mut().with_config().limit(MAX_BODY).read_to_string() {
                Ok(text) => text,
                Err(error) => return Err(self.transport_error(&url, error)),
            };
            if status == 200 {
                return parse_completion(&url, &text, attempt);
            }
            let retryable = status == 429 || (500..600).contains(&status);
            if !retryable || attempt == self.retry.attempts {
                return Err(LlmError::Status { url, status, message: error_message(&text), attempts: attempt });
            }
            let wait = retry_after.map_or(backoff, |asked| asked.min(self.retry.max_backoff));
            std::thread::sleep(wait);
            backoff = (backoff * 2).min(self.retry.max_backoff);
        }
        unreachable!("the last attempt returns")
    }

    fn transport_error(&self, url: &str, error: ureq::Error) -> LlmError {
        let url = url.to_string();
        match error {
            ureq::Error::Timeout(_) => LlmError::TimedOut { url, limit: self.timeout },
            ureq::Error::Io(e) if e.kind() == std::io::ErrorKind::TimedOut => {
                LlmError::TimedOut { url, limit: self.timeout }
            }
            ureq::Error::BadUri(why) => LlmError::BadUrl { url, why },
            ureq::Error::HostNotFound => {
                LlmError::Unreachable { url, why: "the host name does not resolve".to_string() }
            }
            ureq::Error::ConnectionFailed => LlmError::Unreachable { url, why: "the connection failed".to_string() },
            ureq::Error::Io(e) => LlmError::Unreachable { url, why: e.to_string() },
            ureq::Error::BodyExceedsLimit(limit) => LlmError::NotACompletion {
                url,
                why: format!("the answer is larger than {limit} bytes"),
                excerpt: String::new(),
            },
            other => LlmError::Unreachable { url, why: other.to_string() },
        }
    }
}

/// The assistant's text of a chat-completion answer.
fn parse_completion(url: &str, text: &str, attempts: u32) -> Result<Completion, LlmError> {
    let not_a_completion =
        |why: &str| LlmError::NotACompletion { url: url.to_string(), why: why.to_string(), excerpt: excerpt(text) };
    let value: serde_json::Value = serde_json::from_str(text).map_err(|_| not_a_completion("not JSON"))?;
    let choice = value
        .get("choices")
        .and_then(|c| c.as_array())
        .and_then(|c| c.first())
        .ok_or_else(|| not_a_completion("no `choices`"))?;
    let content = choice
        .get("message")
        .and_then(|m| m.get("content"))
        .and_then(|c| c.as_str())
        .ok_or_else(|| not_a_completion("the first choice has no `message.content`"))?;
    let model = value.get("model").and_then(|m| m.as_str()).map(str::to_string);
    Ok(Completion { content: content.to_string(), model, attempts })
}

/// The message of an error answer: OpenAI's `{"error": {"message": ...}}`, or the text.
fn error_message(text: &str) -> String {
    let parsed: Option<serde_json::Value> = serde_json::from_str(text).ok();
    let message = parsed
        .as_ref()
        .and_then(|v| v.get("error").and_then(|e| e.get("message").and_then(|m| m.as_str()).or_else(|| e.as_str())));
    match message {
        Some(message) => message.to_string(),
        None => excerpt(text),
    }
}

/// The start of a text, for error messages.
fn excerpt(text: &str) -> String {
    let end = text.char_indices().nth(120).map_or(text.len(), |(i, _)| i);
    let mut out = text[..end].trim().to_string();
    if end < text.len() {
        out.push_str("...");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urls_take_a_base_or_the_full_path() {
        let endpoint = |url: &str| Endpoint { url: url.to_string(), model: "m".to_string(), api_key: None };
        assert_eq!(endpoint("http://h:1/v1").completions_url(), "http://h:1/v1/chat/completions");
        assert_eq!(endpoint("http://h:1/v1/").completions_url(), "http://h:1/v1/chat/completions");
        assert_eq!(endpoint("http://h:1/v1/chat/completions").completions_url(), "http://h:1/v1/chat/completions");
    }

    #[test]
    fn the_key_never_shows() {
        let endpoint = Endpoint { url: "http://h".into(), model: "m".into(), api_key: Some("sk-secret".into()) };
        assert!(!format!("{endpoint:?}").contains("sk-secret"));
    }

    #[test]
    fn completions_are_read_and_other_answers_refused() {
        let ok = r#"{"model":"m1","choices":[{"message":{"role":"assistant","content":"go."}}]}"#;
        assert_eq!(parse_completion("u", ok, 1).unwrap().content, "go.");
        for (text, why) in [
            ("<html>busy</html>", "not JSON"),
            (r#"{"choices":[]}"#, "no `choices`"),
            (r#"{"choices":[{"text":"legacy"}]}"#, "the first choice has no `message.content`"),
        ] {
            match parse_completion("u", text, 1) {
                Err(LlmError::NotACompletion { why: found, .. }) => assert_eq!(found, why),
                other => panic!("{text}: {other:?}"),
            }
        }
        assert_eq!(error_message(r#"{"error":{"message":"model not found"}}"#), "model not found");
        assert_eq!(error_message("plain"), "plain");
    }
}
