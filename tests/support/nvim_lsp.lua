-- Neovim 0.7 as an LSP client of `kbc lsp`, for tests/nvim.rs, set up by the configuration
-- README.md gives (editors/nvim/kbc.lua). Environment: KBC_BIN (the kbc binary), KBC_CONFIG
-- (that file), KBC_ROOT (the folder holding kb.pl, also the working directory), KBC_OUT (where
-- to write what was seen, as JSON).
local kbc, root, out = os.getenv("KBC_BIN"), os.getenv("KBC_ROOT"), os.getenv("KBC_OUT")
local report = { steps = {} }

local function finish()
  local file = assert(io.open(out, "w"))
  file:write(vim.fn.json_encode(report))
  file:close()
  vim.cmd("qall!")
end

local function diagnostics(buffer)
  local seen = {}
  for _, d in ipairs(vim.diagnostic.get(buffer)) do
    table.insert(seen, {
      lnum = d.lnum, col = d.col, end_col = d.end_col, severity = d.severity,
      code = d.code, source = d.source, message = d.message,
    })
  end
  return seen
end

local ok, failure = pcall(function()
  vim.g.kbc_command = { kbc, "lsp" }
  dofile(os.getenv("KBC_CONFIG"))
  vim.cmd("edit " .. vim.fn.fnameescape(root .. "/kb.pl"))
  local buffer = vim.api.nvim_get_current_buf()
  -- The client counts as attached once the server has answered `initialize`.
  vim.wait(30000, function() return next(vim.lsp.buf_get_clients(buffer)) ~= nil end, 20)
  local client = next(vim.lsp.buf_get_clients(buffer))
  assert(client, "the configuration did not attach a client to the buffer")

  -- 1. The mistake in the file on disk is reported.
  report.steps.opened = vim.wait(30000, function() return #vim.diagnostic.get(buffer) > 0 end, 20)
  report.opened = diagnostics(buffer)

  -- 2. Hover over the misspelt name (line 5, 0-based 4): the explanation of its code.
  local hover = vim.lsp.buf_request_sync(buffer, "textDocument/hover", {
    textDocument = { uri = vim.uri_from_bufnr(buffer) },
    position = { line = 4, character = 27 },
  }, 10000)
  for _, response in pairs(hover or {}) do
    if response.result then report.hover = response.result.contents.value end
  end

  -- 3. Fix it in the buffer (Neovim sends an incremental change); the diagnostics go away.
  local line = vim.api.nvim_buf_get_lines(buffer, 4, 5, true)[1]
  local at = assert(line:find("ontabel", 1, true), "the misspelling is on line 5")
  vim.api.nvim_buf_set_text(buffer, 4, at - 1, 4, at - 1 + #"ontabel", { "ontable" })
  report.steps.fixed = vim.wait(30000, function() return #vim.diagnostic.get(buffer) == 0 end, 20)
  report.fixed = diagnostics(buffer)

  vim.lsp.stop_client(client)
end)
if not ok then report.error = tostring(failure) end
finish()
