" Re-indent every file of $CAT_FILES (one a line) with `gg=G' (after flushing every line
" left when $CAT_FLUSH is 1; with `syntax on' when $CAT_SYNTAX is 1) and write one line per
" file that changes, with its first changed line, to $CAT_OUT.  tests/editors/test_vim.py.
set nocompatible
" No swap file: the four variants run in parallel (pytest -n) on the same files, and another
" process's swap file makes `:edit' fail (E325) and Vim exit 1 without a word.
set noswapfile
let &rtp = $CAT_VIM_RTP . ',' . &rtp
filetype plugin indent on
if $CAT_SYNTAX ==# '1'
  syntax on
endif
let s:bad = []
for s:f in split($CAT_FILES, "\n")
  try
    execute 'silent edit ' . fnameescape(s:f)
  catch
    call add(s:bad, s:f . ': cannot edit: ' . v:exception)
    continue
  endtry
  let s:before = getline(1, '$')
  if $CAT_FLUSH ==# '1'
    silent! %s/^\s\+//
  endif
  silent normal! gg=G
  let s:after = getline(1, '$')
  for s:i in range(len(s:before))
    if s:before[s:i] !=# get(s:after, s:i, '')
      call add(s:bad, s:f . ':' . (s:i + 1) . ': ' . get(s:after, s:i, ''))
      break
    endif
  endfor
  silent bwipeout!
endfor
call writefile(s:bad, $CAT_OUT)
qall!
