//! The chat-completion client of `kbc draft` against a local server that plays recorded
//! answers: a completion, retries on 429 and 5xx, errors that are not retried, answers that
//! are not completions, a silent server, and a port where nothing listens.

#[path = "support/llm_server.rs"]
mod server;

use std::time::{Duration, Instant};

use kbc::cli::llm::{Client, Endpoint, LlmError, Message, Retry};
use server::{Reply, Server};

fn client(url: &str, key: Option<&str>, attempts: u32, timeout: Duration) -> Client {
    let endpoint = Endpoint { url: url.to_string(), model: "test-model".to_string(), api_key: key.map(str::to_string) };
    let retry = Retry { attempts, first_backoff: Duration::from_millis(5), max_backoff: Duration::from_millis(20) };
    Client::new(endpoint, timeout, retry).expect("a usable URL")
}

fn ask(client: &Client) -> Result<kbc::cli::llm::Completion, LlmError> {
    client.complete(&[Message::new("system", "You write Prolog."), Message::new("user", "a test case")])
}

const PATIENT: Duration = Duration::from_secs(30);

#[test]
fn a_completion_is_read_and_the_request_is_what_the_api_expects() {
    let server = Server::start(vec![Reply::Completion("test_case :- go([], []).".to_string())]);
    let completion = ask(&client(&server.url, Some("sk-test"), 1, PATIENT)).unwrap();
    assert_eq!(completion.content, "test_case :- go([], []).");
    assert_eq!(completion.model.as_deref(), Some("recorded"));
    assert_eq!(completion.attempts, 1);
    let received = server.received();
    assert_eq!(received.len(), 1);
    let body: serde_json::Value = serde_json::from_str(&received[0].body).unwrap();
    assert_eq!(body["model"], "test-model");
    assert_eq!(body["temperature"], 0.0);
    assert_eq!(body["messages"][1]["role"], "user");
    assert_eq!(body["messages"][1]["content"], "a test case");
    let authorization = received[0].headers.iter().find(|(n, _)| n == "authorization").map(|(_, v)| v.as_str());
    assert_eq!(authorization, Some("Bearer sk-test"));
}

#[test]
fn too_many_requests_then_success() {
    let server = Server::start(vec![
        Reply::WithHeaders(
            429,
            vec![("Retry-After".into(), "0".into())],
            r#"{"error":{"message":"slow down"}}"#.into(),
        ),
        Reply::Status(503, "overloaded".into()),
        Reply::Completion("ok.".into()),
    ]);
    let completion = ask(&client(&server.url, None, 4, PATIENT)).unwrap();
    assert_eq!(completion.content, "ok.");
    assert_eq!(completion.attempts, 3);
    assert_eq!(server.received().len(), 3);
}

#[test]
fn server_errors_are_retried_up_to_the_limit_then_reported() {
    let server = Server::start(vec![Reply::Status(500, r#"{"error":{"message":"boom"}}"#.into()); 3]);
    let error = ask(&client(&server.url, None, 3, PATIENT)).unwrap_err();
    assert!(matches!(&error, LlmError::Status { status: 500, attempts: 3, .. }), "{error:?}");
    assert!(error.to_string().ends_with("answered HTTP 500 (3 attempts): boom"), "{error}");
    assert_eq!(server.received().len(), 3);
}

#[test]
fn client_errors_are_not_retried_and_the_key_is_not_shown() {
    let server = Server::start(vec![Reply::Status(401, r#"{"error":{"message":"invalid api key"}}"#.into()); 2]);
    let error = ask(&client(&server.url, Some("sk-very-secret"), 3, PATIENT)).unwrap_err();
    assert!(matches!(&error, LlmError::Status { status: 401, attempts: 1, .. }), "{error:?}");
    assert!(!format!("{error} {error:?}").contains("sk-very-secret"));
    assert_eq!(server.received().len(), 1);
}

#[test]
fn answers_that_are_not_completions_are_refused() {
    for (body, why) in [
        ("{\"choices\": [", "not JSON"),
        ("<html>gateway</html>", "not JSON"),
        (r#"{"object":"list","data":[]}"#, "no `choices`"),
    ] {
        let server = Server::start(vec![Reply::Status(200, body.to_string())]);
        match ask(&client(&server.url, None, 1, PATIENT)) {
            Err(LlmError::NotACompletion { why: found, excerpt, .. }) => {
                assert_eq!(found, why);
                assert!(body.starts_with(excerpt.trim_end_matches("...")), "{excerpt}");
            }
            other => panic!("{body}: {other:?}"),
        }
    }
}

#[test]
fn a_silent_server_times_out() {
    let server = Server::start(vec![Reply::Silence(Duration::from_secs(5))]);
    let started = Instant::now();
    let error = ask(&client(&server.url, None, 3, Duration::from_millis(300))).unwrap_err();
    assert!(matches!(error, LlmError::TimedOut { .. }), "{error:?}");
    assert!(error.to_string().contains("did not answer within 0.3 s"), "{error}");
    assert!(started.elapsed() < Duration::from_secs(4), "the time limit held");
}

#[test]
fn an_unreachable_port_is_reported_as_such() {
    let url = server::unreachable_url();
    let error = ask(&client(&url, None, 3, PATIENT)).unwrap_err();
    assert!(matches!(&error, LlmError::Unreachable { .. }), "{error:?}");
    assert!(error.to_string().starts_with(&format!("cannot reach `{url}/chat/completions`")), "{error}");
}

#[test]
fn urls_kbc_cannot_use_are_refused_up_front() {
    let endpoint = |url: &str| Endpoint { url: url.to_string(), model: "m".to_string(), api_key: None };
    let retry = Retry::default();
    assert!(matches!(Client::new(endpoint("ftp://h/v1"), PATIENT, retry), Err(LlmError::BadUrl { .. })));
    if !cfg!(feature = "tls") {
        match Client::new(endpoint("https://api.example.com/v1"), PATIENT, retry) {
            Err(LlmError::BadUrl { why, .. }) => assert!(why.contains("--features tls"), "{why}"),
            _ => panic!("https without TLS is refused"),
        }
    }
}
