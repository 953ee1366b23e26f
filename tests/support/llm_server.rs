//! A local HTTP server that plays recorded answers of a chat-completion endpoint, for tests of
//! `kbc draft` and its client. Each connection gets the next reply; the requests are kept.

#![allow(dead_code)] // Each test binary uses a different part.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpListener;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// One scripted answer.
#[derive(Clone, Debug)]
pub enum Reply {
    /// A status and a body, sent as JSON.
    Status(u16, String),
    /// A status, extra headers and a body.
    WithHeaders(u16, Vec<(String, String)>, String),
    /// Say nothing for this long, then close.
    Silence(Duration),
    /// A chat completion whose message is this text.
    Completion(String),
}

/// A request as received.
#[derive(Clone, Debug)]
pub struct Received {
    /// Header lines, lower-cased names.
    pub headers: Vec<(String, String)>,
    /// The body.
    pub body: String,
}

pub struct Server {
    /// `http://127.0.0.1:PORT/v1`.
    pub url: String,
    received: Arc<Mutex<Vec<Received>>>,
}

impl Server {
    /// Starts a server on a free port that answers with `replies`, in order.
    pub fn start(replies: Vec<Reply>) -> Server {
        let listener = TcpListener::bind("127.0.0.1:0").expect("a local port");
        let url = format!("http://{}/v1", listener.local_addr().unwrap());
        let received = Arc::new(Mutex::new(Vec::new()));
        let log = received.clone();
        std::thread::spawn(move || {
            for reply in replies {
                let Ok((stream, _)) = listener.accept() else { return };
                let mut reader = BufReader::new(stream.try_clone().expect("a socket"));
                let mut headers = Vec::new();
                let mut line = String::new();
                let mut length = 0;
                while reader.read_line(&mut line).is_ok_and(|n| n > 0) && line.trim() != "" {
                    if let Some((name, value)) = line.trim_end().split_once(':') {
                        let name = name.trim().to_ascii_lowercase();
                        if name == "content-length" {
                            length = value.trim().parse().unwrap_or(0);
                        }
                        headers.push((name, value.trim().to_string()));
                    }
                    line.clear();
                }
                let mut body = vec![0; length];
                let _ = reader.read_exact(&mut body);
                log.lock().unwrap().push(Received { headers, body: String::from_utf8_lossy(&body).into_owned() });
                let (status, extra, body) = match reply {
                    Reply::Silence(time) => {
                        std::thread::sleep(time);
                        continue;
                    }
                    Reply::Status(status, body) => (status, Vec::new(), body),
                    Reply::WithHeaders(status, extra, body) => (status, extra, body),
                    Reply::Completion(text) => (200, Vec::new(), completion(&text)),
                };
                let mut stream = stream;
                let mut head = format!(
                    "HTTP/1.1 {status} Scripted\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n",
                    body.len()
                );
                for (name, value) in extra {
                    head.push_str(&format!("{name}: {value}\r\n"));
                }
                let _ = stream.write_all(format!("{head}\r\n{body}").as_bytes());
            }
        });
        Server { url, received }
    }

    /// The requests received so far.
    pub fn received(&self) -> Vec<Received> {
        self.received.lock().unwrap().clone()
    }
}

/// A chat-completion answer carrying `text`.
pub fn completion(text: &str) -> String {
    serde_json::json!({
        "id": "chatcmpl-test",
        "object": "chat.completion",
        "model": "recorded",
        "choices": [{ "index": 0, "message": { "role": "assistant", "content": text }, "finish_reason": "stop" }],
    })
    .to_string()
}

/// A URL on which nothing listens.
pub fn unreachable_url() -> String {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a local port");
    let address = listener.local_addr().unwrap();
    drop(listener);
    format!("http://{address}/v1")
}
