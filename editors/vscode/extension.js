// A minimal VS Code client for `kbc lsp`: starts the server over stdio for Prolog files.
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function activate() {
  const config = vscode.workspace.getConfiguration("kbc");
  const server = { command: config.get("path", "kbc"), args: ["lsp"] };
  client = new LanguageClient("kbc", "kbc", server, {
    documentSelector: [{ scheme: "file", language: "prolog" }],
    initializationOptions: { grouping: config.get("grouping", "folder") },
  });
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
