-- kbc's language server in Neovim 0.7 or later: source this file from init.lua
-- (`dofile("/path/to/kbc/editors/nvim/kbc.lua")`) or copy it there.
--
-- Every `.pl` buffer is attached to one `kbc lsp` per folder it is opened from (the working
-- directory); the server checks the `.pl` files of a folder together, as `kbc check` would.
-- Set `vim.g.kbc_command` first to run another binary, and `vim.g.kbc_grouping = "file"` to
-- check every file on its own (for folders of unrelated examples).
local clients = {}

vim.api.nvim_create_autocmd({ "BufReadPost", "BufNewFile" }, {
  pattern = "*.pl",
  callback = function(args)
    local root = vim.fn.getcwd()
    if not clients[root] then
      clients[root] = vim.lsp.start_client({
        name = "kbc",
        cmd = vim.g.kbc_command or { "kbc", "lsp" },
        root_dir = root,
        init_options = { grouping = vim.g.kbc_grouping or "folder" },
      })
    end
    if clients[root] then
      vim.lsp.buf_attach_client(args.buf, clients[root])
    end
  end,
})
