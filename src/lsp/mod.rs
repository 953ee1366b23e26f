//! `kbc lsp`: a Language Server Protocol server for KB files.
//!
//! The server is synchronous, like the compiler: one thread takes messages from
//! lsp-server's channels and answers them in order, so a request always sees the effect of
//! every change sent before it. Checking is the library's front end (`driver::frontend`),
//! exactly what `kbc check` runs; diagnostics are the compiler's `Diagnostic` values converted
//! at the edge ([`analysis`]). Changes are debounced: a unit is re-checked once the client has
//! been quiet for a short while (15 ms by default, never more than four times that after the
//! first pending change), and any request that depends on positions first checks what is
//! pending, so its answer matches the text the client has.
//!
//! Only this module (and `src/cli`) does IO, and only this module knows `lsp_types`.
//!
//! - [`position`]: UTF-16 protocol positions to byte offsets and back.
//! - [`transport`]: stdio framing that survives malformed input and never hangs on exit.
//! - [`workspace`]: open documents, units (the folder's files checked together), publishing.
//! - [`analysis`]: one check of a unit, and the conversion of its diagnostics.
//! - [`index`]: where every predicate, action and problem occurs, in which role.
//! - [`features`]: hover, definition, references, symbols, completion, code actions.

pub mod analysis;
pub mod features;
pub mod index;
pub mod position;
pub mod transport;
pub mod workspace;

use std::collections::BTreeSet;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use lsp_server::{Connection, ErrorCode, Message, Notification, Request, RequestId, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, DidSaveTextDocument,
    Notification as NotificationTrait, PublishDiagnostics,
};
use lsp_types::request::{
    CodeActionRequest, Completion, DocumentSymbolRequest, GotoDefinition, HoverRequest, Initialize, References,
    Request as RequestTrait, Shutdown, WorkspaceSymbolRequest,
};
use lsp_types::{
    CodeActionKind, CodeActionOptions, CodeActionParams, CodeActionProviderCapability, CompletionOptions,
    CompletionParams, CompletionResponse, DocumentSymbolParams, DocumentSymbolResponse, GotoDefinitionParams,
    GotoDefinitionResponse, HoverParams, HoverProviderCapability, InitializeParams, InitializeResult, OneOf,
    PositionEncodingKind, PublishDiagnosticsParams, ReferenceParams, SaveOptions, ServerCapabilities, ServerInfo,
    TextDocumentPositionParams, TextDocumentSyncCapability, TextDocumentSyncKind, TextDocumentSyncOptions,
    TextDocumentSyncSaveOptions, WorkspaceSymbolParams, WorkspaceSymbolResponse,
};
use serde::de::DeserializeOwned;

use workspace::{Grouping, UnitId, Workspace};

/// The quiet period before a changed unit is re-checked, unless the client asks otherwise
/// (`initializationOptions.debounceMs`).
pub const DEFAULT_DEBOUNCE: Duration = Duration::from_millis(15);

/// Runs the server on stdin and stdout until the client sends `exit` or goes away. Exit
/// status 0 after `shutdown` then `exit`, 1 otherwise (as the protocol specifies).
pub fn run_stdio() -> ExitCode {
    let (connection, writer) = transport::stdio();
    let clean = serve(connection);
    // Every response is flushed before the process exits; the reader is not waited for.
    let _ = writer.join();
    if clean { ExitCode::SUCCESS } else { ExitCode::from(1) }
}

/// Serves one client over `connection` (stdio, or lsp-server's in-memory pair in tests).
/// Returns true when the session ended with `shutdown` and then `exit`.
pub fn serve(connection: Connection) -> bool {
    let mut server = Server {
        connection,
        workspace: None,
        debounce: DEFAULT_DEBOUNCE,
        pending: BTreeSet::new(),
        deadline: None,
        first_pending: None,
        shut_down: false,
    };
    server.run()
}

struct Server {
    connection: Connection,
    /// `None` until `initialize`.
    workspace: Option<Workspace>,
    debounce: Duration,
    /// Units changed since their last check.
    pending: BTreeSet<UnitId>,
    /// When the pending units are checked.
    deadline: Option<Instant>,
    /// When the oldest pending change arrived.
    first_pending: Option<Instant>,
    shut_down: bool,
}

/// A request's failure, as a response error.
struct Failure {
    code: ErrorCode,
    message: String,
}

impl Failure {
    fn invalid_params(message: impl Into<String>) -> Failure {
        Failure { code: ErrorCode::InvalidParams, message: message.into() }
    }
}

impl Server {
    fn run(&mut self) -> bool {
        loop {
            let received = match self.deadline {
                Some(deadline) => match self.connection.receiver.recv_deadline(deadline) {
                    Ok(message) => Some(message),
                    Err(crossbeam_channel::RecvTimeoutError::Timeout) => None,
                    Err(crossbeam_channel::RecvTimeoutError::Disconnected) => return false,
                },
                None => match self.connection.receiver.recv() {
                    Ok(message) => Some(message),
                    Err(_) => return false,
                },
            };
            match received {
                None => {
                    if catch_unwind(AssertUnwindSafe(|| self.check_pending())).is_err() {
                        // A compiler bug; the units stay as they were until the next change.
                        self.pending.clear();
                        eprintln!("kbc lsp: internal error while checking");
                    }
                }
                Some(Message::Request(request)) => self.on_request(request),
                Some(Message::Notification(notification)) if notification.method == "exit" => return self.shut_down,
                Some(Message::Notification(notification)) => self.on_notification(notification),
                Some(Message::Response(_)) => {}
            }
        }
    }

    fn send(&self, message: impl Into<Message>) {
        // A closed channel means the client is gone; the loop notices on its next receive.
        let _ = self.connection.sender.send(message.into());
    }

    fn on_request(&mut self, request: Request) {
        let id = request.id.clone();
        if self.workspace.is_none() && request.method != Initialize::METHOD {
            return self.fail(id, ErrorCode::ServerNotInitialized, "the server has not been initialised");
        }
        if self.shut_down {
            return self.fail(id, ErrorCode::InvalidRequest, "the server is shutting down");
        }
        let method = request.method.clone();
        let outcome = catch_unwind(AssertUnwindSafe(|| self.dispatch(request)));
        match outcome {
            Ok(Ok(result)) => self.send(Response { id, response_result: Ok(result) }),
            Ok(Err(failure)) => self.fail(id, failure.code, &failure.message),
            Err(_) => {
                // A compiler bug: the state may be half-updated, so start the checks afresh.
                self.pending.clear();
                self.fail(id, ErrorCode::InternalError, &format!("internal error while answering `{method}`"));
            }
        }
    }

    fn fail(&self, id: RequestId, code: ErrorCode, message: &str) {
        self.send(Response::new_err(id, code as i32, message.to_string()));
    }

    fn dispatch(&mut self, request: Request) -> Result<serde_json::Value, Failure> {
        fn to_value(value: impl serde::Serialize) -> Result<serde_json::Value, Failure> {
            serde_json::to_value(value)
                .map_err(|e| Failure { code: ErrorCode::InternalError, message: format!("cannot encode: {e}") })
        }
        let method = request.method.clone();
        match method.as_str() {
            Initialize::METHOD => to_value(self.initialize(params(request)?)?),
            Shutdown::METHOD => {
                self.shut_down = true;
                Ok(serde_json::Value::Null)
            }
            HoverRequest::METHOD => {
                let params: HoverParams = params(request)?;
                let at = self.locate(&params.text_document_position_params)?;
                to_value(at.and_then(|(analysis, file, offset)| features::hover(analysis, file, offset)))
            }
            GotoDefinition::METHOD => {
                let params: GotoDefinitionParams = params(request)?;
                let at = self.locate(&params.text_document_position_params)?;
                let locations = at.map(|(a, file, offset)| features::definition(a, file, offset)).unwrap_or_default();
                to_value((!locations.is_empty()).then_some(GotoDefinitionResponse::Array(locations)))
            }
            References::METHOD => {
                let params: ReferenceParams = params(request)?;
                let include = params.context.include_declaration;
                let at = self.locate(&params.text_document_position)?;
                let found = at.map(|(a, file, offset)| features::references(a, file, offset, include));
                to_value(found.unwrap_or_default())
            }
            DocumentSymbolRequest::METHOD => {
                let params: DocumentSymbolParams = params(request)?;
                self.check_pending();
                let symbols = self
                    .workspace()
                    .analysis_of(&params.text_document.uri)
                    .map(|(analysis, file)| features::document_symbols(analysis, file))
                    .unwrap_or_default();
                to_value(DocumentSymbolResponse::Nested(symbols))
            }
            WorkspaceSymbolRequest::METHOD => {
                let params: WorkspaceSymbolParams = params(request)?;
                self.check_pending();
                let symbols = features::workspace_symbols(self.workspace().analyses(), &params.query);
                to_value(WorkspaceSymbolResponse::Flat(symbols))
            }
            Completion::METHOD => {
                // Names from the last check are good enough while typing: no re-check here.
                let params: CompletionParams = params(request)?;
                let position = &params.text_document_position;
                let workspace = self.workspace();
                let uri = &position.text_document.uri;
                let document =
                    workspace.document(uri).ok_or_else(|| Failure::invalid_params(format!("`{uri}` is not open")))?;
                let starts = position::line_starts(&document.text);
                let offset = position::Lines::new(&document.text, &starts).offset(position.position);
                let analysis = workspace.analysis_of(uri).map(|(a, _)| a);
                let items = features::completion(analysis, &document.text, offset);
                to_value(CompletionResponse::Array(items))
            }
            CodeActionRequest::METHOD => {
                let params: CodeActionParams = params(request)?;
                self.check_pending();
                let actions = match self.workspace().analysis_of(&params.text_document.uri) {
                    Some((analysis, file)) => {
                        let lines = analysis.lines(file);
                        let bytes = lines.offsets(params.range);
                        features::code_actions(analysis, file, bytes.start as u32, bytes.end as u32)
                    }
                    None => Vec::new(),
                };
                to_value(actions)
            }
            other => Err(Failure { code: ErrorCode::MethodNotFound, message: format!("`{other}` is not supported") }),
        }
    }

    fn workspace(&self) -> &Workspace {
        self.workspace.as_ref().expect("requests other than initialize are refused before it")
    }

    /// The analysis, file and byte offset of a position, after checking what is pending.
    fn locate(
        &mut self,
        at: &TextDocumentPositionParams,
    ) -> Result<Option<(&analysis::Analysis, crate::source::FileId, u32)>, Failure> {
        self.check_pending();
        let uri = &at.text_document.uri;
        let Some((analysis, file)) = self.workspace().analysis_of(uri) else {
            return Ok(None);
        };
        Ok(Some((analysis, file, analysis.offset(file, at.position))))
    }

    fn initialize(&mut self, params: InitializeParams) -> Result<InitializeResult, Failure> {
        if self.workspace.is_some() {
            return Err(Failure { code: ErrorCode::InvalidRequest, message: "already initialised".to_string() });
        }
        #[allow(deprecated)] // `root_uri` is how older clients (Neovim 0.7) name the folder.
        let root = params
            .workspace_folders
            .as_ref()
            .and_then(|folders| folders.first().map(|f| f.uri.clone()))
            .or(params.root_uri.clone())
            .and_then(|uri| uri.to_file_path().ok());
        let options = params.initialization_options.unwrap_or_default();
        let grouping = match options.get("grouping").and_then(|g| g.as_str()) {
            Some("file") => Grouping::File,
            Some("folder") | None => Grouping::Folder,
            Some(other) => {
                return Err(Failure::invalid_params(format!(
                    "unknown grouping `{other}`: expected \"folder\" or \"file\""
                )));
            }
        };
        if let Some(ms) = options.get("debounceMs").and_then(|d| d.as_u64()) {
            self.debounce = Duration::from_millis(ms.min(10_000));
        }
        self.workspace = Some(Workspace::new(root, grouping));
        let capabilities = ServerCapabilities {
            position_encoding: Some(PositionEncodingKind::UTF16),
            text_document_sync: Some(TextDocumentSyncCapability::Options(TextDocumentSyncOptions {
                open_close: Some(true),
                change: Some(TextDocumentSyncKind::INCREMENTAL),
                save: Some(TextDocumentSyncSaveOptions::SaveOptions(SaveOptions { include_text: Some(false) })),
                ..TextDocumentSyncOptions::default()
            })),
            hover_provider: Some(HoverProviderCapability::Simple(true)),
            definition_provider: Some(OneOf::Left(true)),
            references_provider: Some(OneOf::Left(true)),
            document_symbol_provider: Some(OneOf::Left(true)),
            workspace_symbol_provider: Some(OneOf::Left(true)),
            completion_provider: Some(CompletionOptions::default()),
            code_action_provider: Some(CodeActionProviderCapability::Options(CodeActionOptions {
                code_action_kinds: Some(vec![CodeActionKind::QUICKFIX]),
                ..CodeActionOptions::default()
            })),
            ..ServerCapabilities::default()
        };
        Ok(InitializeResult {
            capabilities,
            server_info: Some(ServerInfo {
                name: "kbc".to_string(),
                version: Some(env!("CARGO_PKG_VERSION").to_string()),
            }),
        })
    }

    fn on_notification(&mut self, notification: Notification) {
        if self.workspace.is_none() {
            return;
        }
        let method = notification.method.clone();
        let result = catch_unwind(AssertUnwindSafe(|| self.handle_notification(notification)));
        match result {
            Ok(Ok(())) => {}
            Ok(Err(why)) => eprintln!("kbc lsp: ignored `{method}`: {why}"),
            Err(_) => {
                self.pending.clear();
                eprintln!("kbc lsp: internal error while handling `{method}`");
            }
        }
    }

    fn handle_notification(&mut self, notification: Notification) -> Result<(), String> {
        let workspace = self.workspace.as_mut().expect("checked by the caller");
        match notification.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let params: lsp_types::DidOpenTextDocumentParams = notification_params(notification)?;
                let document = params.text_document;
                let units = workspace.open(document.uri, document.text, document.version);
                // Opening is not typing: check at once.
                self.schedule(units, Duration::ZERO);
            }
            DidChangeTextDocument::METHOD => {
                let params: lsp_types::DidChangeTextDocumentParams = notification_params(notification)?;
                let document = params.text_document;
                let units = workspace.change(&document.uri, document.version, params.content_changes)?;
                self.schedule(units, self.debounce);
            }
            DidCloseTextDocument::METHOD => {
                let params: lsp_types::DidCloseTextDocumentParams = notification_params(notification)?;
                let units = workspace.close(&params.text_document.uri);
                self.schedule(units, Duration::ZERO);
            }
            DidSaveTextDocument::METHOD => {
                let params: lsp_types::DidSaveTextDocumentParams = notification_params(notification)?;
                let units = workspace.units_reading(&params.text_document.uri);
                self.schedule(units, Duration::ZERO);
            }
            // `initialized`, `$/cancelRequest` (answers are never queued) and the rest.
            _ => {}
        }
        Ok(())
    }

    /// Marks units for checking after `delay` of quiet.
    fn schedule(&mut self, units: Vec<UnitId>, delay: Duration) {
        let now = Instant::now();
        self.pending.extend(units);
        let first = *self.first_pending.get_or_insert(now);
        let latest = first + self.debounce * 4;
        self.deadline = Some((now + delay).min(latest));
    }

    /// Checks the pending units and publishes what changed.
    fn check_pending(&mut self) {
        self.deadline = None;
        self.first_pending = None;
        if self.pending.is_empty() {
            return;
        }
        let units: Vec<UnitId> = std::mem::take(&mut self.pending).into_iter().collect();
        let Some(workspace) = self.workspace.as_mut() else { return };
        for published in workspace.check(&units) {
            let params = PublishDiagnosticsParams {
                uri: published.uri,
                diagnostics: published.diagnostics,
                version: published.version,
            };
            self.send(Notification::new(PublishDiagnostics::METHOD.to_string(), params));
        }
    }
}

fn params<P: DeserializeOwned>(request: Request) -> Result<P, Failure> {
    serde_json::from_value(request.params)
        .map_err(|e| Failure::invalid_params(format!("invalid parameters for `{}`: {e}", request.method)))
}

fn notification_params<P: DeserializeOwned>(notification: Notification) -> Result<P, String> {
    serde_json::from_value(notification.params).map_err(|e| format!("invalid parameters: {e}"))
}
