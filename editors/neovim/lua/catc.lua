-- catc for Neovim: the `.cat` filetype and the catc language server, with Neovim's
-- built-in LSP client (0.7 or later; no plugin needed).  Put editors/neovim on 'runtimepath'
-- (or copy the file to ~/.config/nvim/lua/) and call it from init.lua:
--
--   require("catc").setup()                       -- `catc lsp` on PATH
--   require("catc").setup({ cmd = { "/path/to/venv/bin/catc", "lsp" } })
--
-- The Vim files of editors/vim (highlighting, indentation as catc fmt lays out) work in
-- Neovim unchanged: add editors/vim to 'runtimepath' as well.
local M = {}

local function root_dir(path)
  -- the nearest folder with a .git, else the file's own folder
  local dir = vim.fn.fnamemodify(path, ":p:h")
  local found = vim.fn.finddir(".git", dir .. ";")
  if found ~= "" then
    return vim.fn.fnamemodify(found, ":p:h:h")
  end
  return dir
end

function M.setup(opts)
  opts = opts or {}
  local cmd = opts.cmd or { "catc", "lsp" }
  vim.cmd([[autocmd BufRead,BufNewFile *.cat setfiletype cat]])
  local group = vim.api.nvim_create_augroup("catc_lsp", { clear = true })
  vim.api.nvim_create_autocmd("FileType", {
    group = group,
    pattern = "cat",
    callback = function(args)
      local root = root_dir(vim.api.nvim_buf_get_name(args.buf))
      local id = vim.lsp.start_client({ name = "catc", cmd = cmd, root_dir = root })
      if id then
        vim.lsp.buf_attach_client(args.buf, id)
      end
      if opts.on_attach then
        opts.on_attach(id, args.buf)
      end
    end,
  })
end

return M
