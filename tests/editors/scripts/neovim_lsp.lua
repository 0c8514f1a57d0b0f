-- Drive `catc lsp` from Neovim's built-in client, headless (tests/editors/test_neovim.py):
-- editors/neovim/lua/catc.lua sets it up; the answers are written as JSON to $CAT_OUT.
local out = {}
local function done()
  local f = io.open(os.getenv("CAT_OUT"), "w")
  f:write(vim.fn.json_encode(out))
  f:close()
  vim.cmd("qall!")
end

local ok, err = pcall(function()
vim.opt.runtimepath:prepend(os.getenv("CAT_NEOVIM_RTP"))
vim.opt.runtimepath:prepend(os.getenv("CAT_VIM_RTP"))
vim.cmd("filetype plugin indent on")
require("catc").setup({ cmd = { os.getenv("CAT_PYTHON"), "-m", "catc", "lsp" } })

vim.cmd("edit " .. os.getenv("CAT_FILE"))
out.filetype = vim.bo.filetype
local attached = vim.wait(60000, function() return #vim.lsp.buf_get_clients(0) > 0 end, 50)
out.attached = attached
-- diagnostics of the file as it is on disk
vim.wait(60000, function() return #vim.diagnostic.get(0) > 0 end, 50)
out.diagnostics = {}
for _, d in ipairs(vim.diagnostic.get(0)) do
  table.insert(out.diagnostics, { lnum = d.lnum, col = d.col, message = d.message, code = d.code,
                                  severity = d.severity })
end
-- hover on a resource: the position is given as line (0-based) and column
local line, col = tonumber(os.getenv("CAT_HOVER_LINE")), tonumber(os.getenv("CAT_HOVER_COL"))
local client = vim.lsp.buf_get_clients(0)[next(vim.lsp.buf_get_clients(0))]
local params = { textDocument = vim.lsp.util.make_text_document_params(), position = { line = line, character = col } }
local hover = vim.lsp.buf_request_sync(0, "textDocument/hover", params, 30000)
for _, r in pairs(hover or {}) do
  if r.result and r.result.contents then
    out.hover = r.result.contents.value or r.result.contents
  end
end
local def = vim.lsp.buf_request_sync(0, "textDocument/definition", params, 30000)
for _, r in pairs(def or {}) do
  if r.result then
    local loc = r.result[1] or r.result
    out.definition = { uri = loc.uri or loc.targetUri, line = (loc.range or loc.targetSelectionRange).start.line }
  end
end
-- an edit: the diagnostics follow the buffer, not the file
vim.api.nvim_buf_set_lines(0, 0, 0, false, { "(define (domain broken) (:resources (x reall)))" })
vim.wait(60000, function()
  for _, d in ipairs(vim.diagnostic.get(0)) do
    if d.lnum == 0 then return true end
  end
  return false
end, 50)
out.after_edit = {}
for _, d in ipairs(vim.diagnostic.get(0)) do
  table.insert(out.after_edit, { lnum = d.lnum, col = d.col, message = d.message })
end
out.client = client and client.name or nil
end)
if not ok then
  out.error = tostring(err)
end
done()
