" Vim filetype detection for .cat robot domain and problem files (catc).
" `set filetype` rather than `setfiletype`: *.cat is ours even if another script guessed.
autocmd BufRead,BufNewFile *.cat set filetype=cat
