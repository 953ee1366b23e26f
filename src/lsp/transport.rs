//! The stdio transport: a reader thread and a writer thread around lsp-server's channels.
//!
//! lsp-server has a stdio transport of its own; this one differs where a server must not die
//! or hang. A payload that is not JSON-RPC does not end the reader: it is reported on stderr
//! (and answered with an error response when its id can be read) and the next message is
//! read. The server never joins the reader: once the main loop returns, only the writer is
//! joined (so every response is flushed), and the process exits even if the client has left
//! stdin open.

use std::io::{self, BufRead, Write};
use std::thread::JoinHandle;

use lsp_server::{Connection, ErrorCode, Message, RequestId, Response};

/// A connection over stdin and stdout, and the writer thread to join after the main loop.
pub fn stdio() -> (Connection, JoinHandle<()>) {
    let (to_writer, from_server) = crossbeam_channel::unbounded::<Message>();
    let (to_server, from_reader) = crossbeam_channel::unbounded::<Message>();
    let reply = to_writer.clone();
    let writer = std::thread::Builder::new()
        .name("kbc-lsp-writer".to_string())
        .spawn(move || {
            let stdout = io::stdout();
            let mut out = stdout.lock();
            for message in from_server {
                if message.write(&mut out).is_err() {
                    break;
                }
            }
            let _ = out.flush();
        })
        .expect("spawning a thread at startup");
    // Detached on purpose (see the module header).
    std::thread::Builder::new()
        .name("kbc-lsp-reader".to_string())
        .spawn(move || {
            let stdin = io::stdin();
            read_messages(&mut stdin.lock(), &to_server, &reply);
        })
        .expect("spawning a thread at startup");
    (Connection { sender: to_writer, receiver: from_reader }, writer)
}

/// Reads framed messages from `input` until it ends, an `exit` notification arrives or the
/// server stops listening. Bad frames and bad payloads are skipped.
pub fn read_messages(
    input: &mut impl BufRead,
    to_server: &crossbeam_channel::Sender<Message>,
    reply: &crossbeam_channel::Sender<Message>,
) {
    loop {
        let payload = match read_frame(input) {
            Ok(Some(payload)) => payload,
            Ok(None) => return,
            Err(FrameError::Io(_)) => return,
            Err(FrameError::Header(why)) => {
                eprintln!("kbc lsp: skipped a message with a bad header: {why}");
                continue;
            }
        };
        match serde_json::from_str::<Message>(&payload) {
            Ok(message) => {
                let exit = matches!(&message, Message::Notification(n) if n.method == "exit");
                if to_server.send(message).is_err() || exit {
                    return;
                }
            }
            Err(error) => {
                eprintln!("kbc lsp: skipped a message that is not JSON-RPC: {error}");
                if let Some(id) = request_id(&payload) {
                    let response = Response::new_err(
                        id,
                        ErrorCode::InvalidRequest as i32,
                        format!("the request is not a valid JSON-RPC message: {error}"),
                    );
                    let _ = reply.send(response.into());
                }
            }
        }
    }
}

/// Why a frame could not be read.
#[derive(Debug)]
pub enum FrameError {
    /// The stream failed or ended inside a frame.
    Io(io::Error),
    /// The headers were unusable; the stream is still in step.
    Header(String),
}

/// The largest payload accepted (the 10,000-line benchmark KB is about 400 KB).
const MAX_PAYLOAD: usize = 256 << 20;

/// Reads one `Content-Length`-framed payload; `None` at the end of the stream.
pub fn read_frame(input: &mut impl BufRead) -> Result<Option<String>, FrameError> {
    let mut length = None;
    let mut line = String::new();
    let mut any_header = false;
    loop {
        line.clear();
        let read = input.read_line(&mut line).map_err(FrameError::Io)?;
        if read == 0 {
            return if any_header {
                Err(FrameError::Io(io::Error::new(io::ErrorKind::UnexpectedEof, "inside headers")))
            } else {
                Ok(None)
            };
        }
        let header = line.trim_end_matches(['\r', '\n']);
        if header.is_empty() {
            if any_header {
                break;
            }
            continue;
        }
        any_header = true;
        if let Some((name, value)) = header.split_once(':')
            && name.trim().eq_ignore_ascii_case("content-length")
        {
            length = value.trim().parse::<usize>().ok();
        }
    }
    let Some(length) = length.filter(|&n| n <= MAX_PAYLOAD) else {
        return Err(FrameError::Header("no usable Content-Length".to_string()));
    };
    let mut payload = vec![0u8; length];
    input.read_exact(&mut payload).map_err(FrameError::Io)?;
    String::from_utf8(payload).map(Some).map_err(|_| FrameError::Header("the payload is not UTF-8".to_string()))
}

/// The id of a request whose payload is JSON but not a valid message, if it has one.
fn request_id(payload: &str) -> Option<RequestId> {
    let value: serde_json::Value = serde_json::from_str(payload).ok()?;
    match value.get("id")? {
        serde_json::Value::Number(n) => n.as_i64().and_then(|n| i32::try_from(n).ok()).map(RequestId::from),
        serde_json::Value::String(s) => Some(RequestId::from(s.clone())),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(payload: &str) -> String {
        format!("Content-Length: {}\r\n\r\n{payload}", payload.len())
    }

    #[test]
    fn bad_payloads_are_skipped_and_requests_among_them_answered() {
        let input = [
            frame(r#"{"jsonrpc":"2.0","id":1,"method":"hover","params":{}}"#),
            frame("{not json"),
            frame(r#"{"jsonrpc":"2.0","id":7,"method":5}"#),
            "Content-Type: text/plain\r\n\r\n".to_string(),
            frame(r#"{"jsonrpc":"2.0","method":"exit"}"#),
            frame(r#"{"jsonrpc":"2.0","id":2,"method":"never-read"}"#),
        ]
        .concat();
        let (to_server, from_reader) = crossbeam_channel::unbounded();
        let (reply, replies) = crossbeam_channel::unbounded();
        read_messages(&mut input.as_bytes(), &to_server, &reply);
        let received: Vec<String> = from_reader
            .try_iter()
            .map(|m| match m {
                Message::Request(r) => r.method,
                Message::Notification(n) => n.method,
                Message::Response(_) => "response".to_string(),
            })
            .collect();
        assert_eq!(received, ["hover", "exit"]);
        let answered: Vec<_> = replies.try_iter().collect();
        assert_eq!(answered.len(), 1, "{answered:?}");
        let Message::Response(response) = &answered[0] else { panic!("{answered:?}") };
        assert_eq!(response.id, RequestId::from(7));
        assert!(response.response_result.is_err());
    }

    #[test]
    fn a_stream_that_ends_inside_a_frame_ends_the_reader() {
        let mut input = "Content-Length: 50\r\n\r\n{\"jsonrpc\"".as_bytes();
        assert!(matches!(read_frame(&mut input), Err(FrameError::Io(_))));
        assert!(read_frame(&mut "".as_bytes()).unwrap().is_none());
    }
}
