//! A scripted LSP client for tests and benchmarks: it runs `kbc::lsp::serve` on a thread over
//! lsp-server's in-memory connection and speaks JSON to it, as an editor would.

#![allow(dead_code)] // Each test binary uses a different part.

use std::time::{Duration, Instant};

use lsp_server::{Connection, Message, Notification, Request, RequestId, ResponseError};
use serde_json::{Value, json};

/// How long any wait may take before the test fails instead of hanging.
pub const PATIENCE: Duration = Duration::from_secs(60);

pub struct Client {
    connection: Connection,
    server: Option<std::thread::JoinHandle<bool>>,
    next_id: i32,
    /// Notifications received while waiting for something else, oldest first.
    pub backlog: Vec<Notification>,
}

impl Client {
    /// Starts a server and initialises it on `root` with `options` as initializationOptions.
    pub fn start(root: &std::path::Path, options: Value) -> Client {
        let (server_side, client_side) = Connection::memory();
        // As `kbc lsp` does, the server runs on a thread with a large stack (deep terms).
        let server = std::thread::Builder::new()
            .stack_size(1 << 30)
            .spawn(move || kbc::lsp::serve(server_side))
            .expect("a server thread");
        let mut client = Client { connection: client_side, server: Some(server), next_id: 1, backlog: Vec::new() };
        let root_uri = lsp_types::Url::from_file_path(root).expect("an absolute path");
        let result = client
            .request(
                "initialize",
                json!({ "processId": null, "rootUri": root_uri, "capabilities": {}, "initializationOptions": options }),
            )
            .expect("initialize succeeds");
        assert_eq!(result["capabilities"]["textDocumentSync"]["change"], 2, "incremental sync: {result}");
        client.notify("initialized", json!({}));
        client
    }

    /// Sends a request and waits for its response.
    pub fn request(&mut self, method: &str, params: Value) -> Result<Value, ResponseError> {
        let id = RequestId::from(self.next_id);
        self.next_id += 1;
        self.connection.sender.send(Request::new(id.clone(), method.to_string(), params).into()).expect("server alive");
        let deadline = Instant::now() + PATIENCE;
        loop {
            match self.connection.receiver.recv_deadline(deadline) {
                Ok(Message::Response(response)) if response.id == id => return response.response_result,
                Ok(Message::Response(other)) => panic!("a response to another request: {other:?}"),
                Ok(Message::Notification(n)) => self.backlog.push(n),
                Ok(Message::Request(r)) => panic!("the server asked the client something: {r:?}"),
                Err(e) => panic!("no response to `{method}`: {e}"),
            }
        }
    }

    /// Sends a notification.
    pub fn notify(&mut self, method: &str, params: Value) {
        self.connection.sender.send(Notification::new(method.to_string(), params).into()).expect("server alive");
    }

    /// Opens a Prolog document at version 1.
    pub fn open(&mut self, uri: &str, text: &str) {
        let document = serde_json::json!({ "uri": uri, "languageId": "prolog", "version": 1, "text": text });
        self.notify("textDocument/didOpen", serde_json::json!({ "textDocument": document }));
    }

    /// Waits for the next `publishDiagnostics` for `uri` and returns its diagnostics.
    pub fn diagnostics(&mut self, uri: &str) -> Vec<Value> {
        self.published(uri)["diagnostics"].as_array().cloned().unwrap_or_default()
    }

    /// Waits for the next `publishDiagnostics` for `uri` and returns its parameters.
    pub fn published(&mut self, uri: &str) -> Value {
        if let Some(at) = self.backlog.iter().position(|n| is_publish_for(n, uri)) {
            return self.backlog.remove(at).params;
        }
        let deadline = Instant::now() + PATIENCE;
        loop {
            match self.connection.receiver.recv_deadline(deadline) {
                Ok(Message::Notification(n)) if is_publish_for(&n, uri) => return n.params,
                Ok(Message::Notification(n)) => self.backlog.push(n),
                Ok(other) => panic!("unexpected message while waiting for diagnostics: {other:?}"),
                Err(e) => panic!("no diagnostics for {uri}: {e}"),
            }
        }
    }

    /// Sends `shutdown` and `exit`; returns what the server returned (true for a clean end).
    pub fn shutdown(mut self) -> bool {
        let result = self.request("shutdown", Value::Null).expect("shutdown succeeds");
        assert_eq!(result, Value::Null);
        self.notify("exit", Value::Null);
        let server = self.server.take().expect("started");
        let deadline = Instant::now() + PATIENCE;
        while !server.is_finished() {
            assert!(Instant::now() < deadline, "the server did not exit after `exit`");
            std::thread::sleep(Duration::from_millis(5));
        }
        server.join().expect("the server thread does not panic")
    }
}

fn is_publish_for(notification: &Notification, uri: &str) -> bool {
    notification.method == "textDocument/publishDiagnostics" && notification.params["uri"] == uri
}
