" Vim filetype plugin for .cat robot domain and problem files (catc).
" License: MIT

if exists('b:did_ftplugin')
  finish
endif
let b:did_ftplugin = 1

let s:cpo_save = &cpo
set cpo&vim

setlocal comments=:;
setlocal commentstring=;\ %s
" Names contain '-' and keywords start with ':', so `w`, `*` and completion see
" `lidar-driver` and `:precondition` as one word.
setlocal iskeyword=@,48-57,_,192-255,-,:
setlocal formatoptions-=t formatoptions+=croql
setlocal expandtab shiftwidth=2 softtabstop=2

let b:undo_ftplugin = 'setlocal comments< commentstring< iskeyword<'
      \ . ' formatoptions< expandtab< shiftwidth< softtabstop<'

let &cpo = s:cpo_save
unlet s:cpo_save
