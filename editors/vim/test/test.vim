" Headless test of the Vim support for .cat files.
"
"   vim -Nu NONE -es -S editors/vim/test/test.vim
"
" Opens sample.cat (next to this script) with editors/vim on 'runtimepath' and checks the
" filetype, the buffer options set by ftplugin/cat.vim, the syntax group at sample
" positions, and that re-indenting the sample (`gg=G`) changes nothing.
"
" When $CAT_KEYWORDS_JSON names a JSON file {"category": ["word", ...], ...} (the pytest
" wrapper tests/editors/test_vim.py writes one from catgrammar.symbols.all_keywords()),
" every word is also checked in a typical context, and as part of a longer name where it
" must not be highlighted.
"
" Prints the failures to stderr and exits non-zero on failure, zero on success.

set noswapfile
let s:here = expand('<sfile>:p:h')
let s:errors = []

function! s:Fail(message) abort
  call add(s:errors, a:message)
endfunction

function! s:GroupAt(line, col) abort
  return synIDattr(synID(a:line, a:col, 1), 'name')
endfunction

" Check that every character of `target` has syntax group `group` (a group name, or ''
" for none), where `target` is found inside the first line that contains `context`.
function! s:Expect(context, target, group) abort
  let l:lnum = 0
  let l:col = -1
  for l:candidate in range(1, line('$'))
    let l:col = stridx(getline(l:candidate), a:context)
    if l:col >= 0
      let l:lnum = l:candidate
      break
    endif
  endfor
  let l:offset = stridx(a:context, a:target)
  if l:lnum == 0 || l:offset < 0
    call s:Fail(printf('bad check: no line contains %s, or it does not contain %s', string(a:context), string(a:target)))
    return
  endif
  let l:col += l:offset + 1
  for l:i in range(strlen(a:target))
    let l:actual = s:GroupAt(l:lnum, l:col + l:i)
    if l:actual !=# a:group
      call s:Fail(printf('%d:%d %s in %s: expected %s, got %s',
            \ l:lnum, l:col + l:i, string(a:target), string(a:context), string(a:group), string(l:actual)))
      return
    endif
  endfor
endfunction

let &runtimepath = fnamemodify(s:here, ':h') . ',' . $VIMRUNTIME
filetype plugin indent on
syntax on

execute 'edit ' . fnameescape(s:here . '/sample.cat')

" ---------------------------------------------------------------- filetype & options
if &filetype !=# 'cat'
  call s:Fail('filetype of sample.cat: expected "cat", got ' . string(&filetype))
endif
if get(b:, 'current_syntax', '') !=# 'cat'
  call s:Fail('syntax/cat.vim was not loaded')
endif
for [s:option, s:expected] in [['commentstring', '; %s'], ['comments', ':;']]
  if eval('&l:' . s:option) !=# s:expected
    call s:Fail(printf('&%s: expected %s, got %s', s:option, string(s:expected), string(eval('&l:' . s:option))))
  endif
endfor
for s:char in ['-', ':']
  if index(split(&l:iskeyword, ','), s:char) < 0
    call s:Fail(printf('&iskeyword lacks %s: %s', string(s:char), &l:iskeyword))
  endif
endfor
call cursor(search('\V:precondition', 'cnw'), 1)
normal! ^
if expand('<cword>') !=# ':precondition'
  call s:Fail('<cword> on :precondition: got ' . string(expand('<cword>')))
endif

" ---------------------------------------------------------------- syntax at positions
call s:Expect('; detection domain -- ', '; detection domain -- ', 'catComment')
call s:Expect('-- TODO:', 'TODO', 'catTodo')
call s:Expect('-- TODO: more', ': more', 'catComment')
call s:Expect('(define (domain detection)', '(', 'catParen')
call s:Expect('(define (domain detection)', 'define', 'catStructure')
call s:Expect('(define (domain detection)', 'domain', 'catStructure')
call s:Expect('(define (domain detection)', 'detection', '')
call s:Expect('(:requirements :numeric', ':requirements', 'catSection')
call s:Expect(':numeric :sets :free-parameters :views', ':numeric', 'catRequirement')
call s:Expect(':numeric :sets :free-parameters :views', ':sets', 'catRequirement')
call s:Expect(':numeric :sets :free-parameters :views', ':free-parameters', 'catRequirement')
call s:Expect(':free-parameters :views :holes :recomposition)', ':recomposition', 'catRequirement')
call s:Expect('(:sorts module topic class - symbol', ':sorts', 'catSection')
call s:Expect('(:sorts module topic class - symbol', 'topic class', '')
call s:Expect('(:sorts module topic class - symbol', '-', 'catSymbolOperator')
call s:Expect('(:sorts module topic class - symbol', 'symbol', 'catType')
call s:Expect('(enum low high)', 'enum', 'catType')
call s:Expect('(enum low high)', 'low high', '')
call s:Expect('image-raw - topic', 'image-raw', '')
call s:Expect('(ram real :group compute', 'real', 'catType')
call s:Expect('(ram real :group compute', ':group', 'catOption')
call s:Expect('(ram real :group compute', 'compute', '')
call s:Expect(':bounds (0 *)', ':bounds', 'catOption')
call s:Expect(':bounds (0 *)', '0', 'catNumber')
call s:Expect(':bounds (0 *)', '*', 'catSymbolOperator')
call s:Expect('(topics (set topic)', 'set', 'catType')
call s:Expect('"published \"ROS\" topics; not a comment"', '"published ', 'catString')
call s:Expect('"published \"ROS\" topics; not a comment"', '\"', 'catEscape')
call s:Expect('"published \"ROS\" topics; not a comment"', '; not a comment"', 'catString')
call s:Expect('(:morphism camera-driver', ':morphism', 'catSection')
call s:Expect('(:morphism camera-driver', 'camera-driver', '')
call s:Expect(':kind software :churn 2 :uses 1', ':kind', 'catOption')
call s:Expect(':kind software :churn 2 :uses 1', 'software', 'catKind')
call s:Expect(':kind software :churn 2 :uses 1', ':churn', 'catOption')
call s:Expect(':kind software :churn 2 :uses 1', ':uses', 'catOption')
call s:Expect(':kind software :churn 2 :uses 1', '1', 'catNumber')
call s:Expect(':cost (+ 0.5', ':cost', 'catOption')
call s:Expect(':cost (+ 0.5', '+', 'catSymbolOperator')
call s:Expect(':cost (+ 0.5', '0.5', 'catNumber')
call s:Expect('(* 2 .25)', '*', 'catSymbolOperator')
call s:Expect('(* 2 .25)', '.25', 'catNumber')
call s:Expect(' 1e-3 ', '1e-3', 'catNumber')
call s:Expect('(-1.5E+2 *)', '-1.5E+2', 'catNumber')
call s:Expect('(- ram-req 0.25)', '(', 'catParen')
call s:Expect('(- ram-req 0.25)', '-', 'catSymbolOperator')
call s:Expect('(- ram-req 0.25)', 'ram-req', '')
call s:Expect('(- ram-req 0.25)', '0.25', 'catNumber')
call s:Expect('(ram-req real :bounds (0.5 4) :fixed)', 'ram-req', '')
call s:Expect('(ram-req real :bounds (0.5 4) :fixed)', ':fixed', 'catOption')
call s:Expect(':parameters ((out', ':parameters', 'catOption')
call s:Expect(':precondition (and (>= ram ram-req)', ':precondition', 'catOption')
call s:Expect(':precondition (and (>= ram ram-req)', 'and', 'catOperator')
call s:Expect(':precondition (and (>= ram ram-req)', '>=', 'catSymbolOperator')
call s:Expect('(not (member out topics))', 'not', 'catOperator')
call s:Expect('(not (member out topics))', 'member', 'catOperator')
call s:Expect(':effect (and (decrease ram ram-req) (add topics out))', ':effect', 'catOption')
call s:Expect(':effect (and (decrease ram ram-req) (add topics out))', 'decrease', 'catOperator')
call s:Expect(':effect (and (decrease ram ram-req) (add topics out))', 'add', 'catOperator')
call s:Expect('(:hole mu :view software :max-effects 2)', ':hole', 'catSection')
call s:Expect('(:hole mu :view software :max-effects 2)', ':view', 'catOption')
call s:Expect('(:hole mu :view software :max-effects 2)', ':max-effects', 'catOption')
call s:Expect('(:view software :drop (mounted', '(', 'catParen')
call s:Expect('(:view software :drop (mounted', ':view', 'catSection')
call s:Expect('(:view software :drop (mounted', ':drop', 'catOption')
call s:Expect('(define (problem p1)', 'problem', 'catStructure')
call s:Expect('(:domain detection)', ':domain', 'catSection')
call s:Expect('(:objects fire-extinguisher - class)', ':objects', 'catSection')
call s:Expect('(:objects fire-extinguisher - class)', 'fire-extinguisher', '')
call s:Expect('(:init (= ram 64) (= mounted {camera})', ':init', 'catSection')
call s:Expect('(:init (= ram 64) (= mounted {camera})', '=', 'catSymbolOperator')
call s:Expect('(:init (= ram 64) (= mounted {camera})', '64', 'catNumber')
call s:Expect('(:init (= ram 64) (= mounted {camera})', '{', 'catBrace')
call s:Expect('(:init (= ram 64) (= mounted {camera})', 'camera', '')
call s:Expect('(:init (= ram 64) (= mounted {camera})', '}', 'catBrace')
call s:Expect('(= armed false)', 'false', 'catConstant')
call s:Expect('(assign armed true)', 'assign', 'catOperator')
call s:Expect('(assign armed true)', 'true', 'catConstant')
call s:Expect('(:soft (>= ram 16) :weight 5)', ':soft', 'catSection')
call s:Expect('(:soft (>= ram 16) :weight 5)', ':weight', 'catOption')
call s:Expect('(:metric lex (minimize (total-churn)) (maximize ram))', ':metric', 'catSection')
call s:Expect('(:metric lex (minimize (total-churn)) (maximize ram))', 'lex', 'catMetric')
call s:Expect('(:metric lex (minimize (total-churn)) (maximize ram))', 'minimize', 'catMetric')
call s:Expect('(:metric lex (minimize (total-churn)) (maximize ram))', 'total-churn', 'catOperator')
call s:Expect('(:metric lex (minimize (total-churn)) (maximize ram))', 'maximize', 'catMetric')
call s:Expect('(:deployed camera-driver)', ':deployed', 'catSection')
call s:Expect('  (:view software))', ':view', 'catSection')
call s:Expect('and-gate not-ready total-churn-x x-or camera2 realistic - class)', 'and-gate not-ready total-churn-x x-or camera2 realistic', '')
call s:Expect('(armed bool :group safety)', 'bool', 'catType')

" ---------------------------------------------------------------- indentation
" sample.cat is indented as indent/cat.vim indents: re-indenting it changes nothing, and
" re-indenting it with every line flushed left restores it.
if &l:indentexpr !=# 'GetCatIndent()'
  call s:Fail('indentexpr: expected GetCatIndent(), got ' . string(&l:indentexpr))
endif
let s:expected = getline(1, '$')
for [s:what, s:prepare] in [['as is', ''], ['flushed left', 'silent %s/^\s\+//e']]
  if s:prepare !=# ''
    execute s:prepare
  endif
  normal! gg=G
  let s:after = getline(1, '$')
  for s:i in range(len(s:expected))
    if s:expected[s:i] !=# get(s:after, s:i, '')
      call s:Fail(printf('gg=G (%s) line %d: expected %s, got %s',
            \ s:what, s:i + 1, string(s:expected[s:i]), string(get(s:after, s:i, ''))))
    endif
  endfor
endfor

" ---------------------------------------------------------------- every keyword
" Group and context of each category; %s is the word.
let s:contexts = {
      \ 'structure': ['catStructure', '(%s x)'],
      \ 'section': ['catSection', '(%s x)'],
      \ 'option': ['catOption', '(x %s y)'],
      \ 'requirement': ['catRequirement', '(:requirements %s)'],
      \ 'operator': ['catOperator', '(%s x y)'],
      \ 'symbol-operator': ['catSymbolOperator', '(%s x y)'],
      \ 'type': ['catType', '(x %s)'],
      \ 'constant': ['catConstant', '(= x %s)'],
      \ 'kind': ['catKind', '(x :kind %s)'],
      \ 'metric': ['catMetric', '(:metric %s x)'],
      \ }
if !empty($CAT_KEYWORDS_JSON)
  let s:keywords = json_decode(join(readfile($CAT_KEYWORDS_JSON), "\n"))
  enew!
  setlocal filetype=cat
  let s:checks = []
  for [s:category, s:words] in items(s:keywords)
    if !has_key(s:contexts, s:category)
      call s:Fail('test.vim knows no syntax group for keyword category ' . string(s:category))
      continue
    endif
    let [s:group, s:context] = s:contexts[s:category]
    for s:word in s:words
      let s:text = printf(s:context, s:word)
      call append(line('$') - 1, s:text)
      call add(s:checks, [line('$') - 1, stridx(s:text, s:word) + 1, s:word, s:group, s:category])
      if s:word =~# '^:\=\a'
        " Glued to more name characters the word is some other name: not highlighted.
        let s:text = printf('(x %s-zz y)', s:word)
        call append(line('$') - 1, s:text)
        call add(s:checks, [line('$') - 1, 4, s:word . '-zz', '', s:category])
        if s:word[0] !=# ':'
          let s:text = printf('(x zz-%s y)', s:word)
          call append(line('$') - 1, s:text)
          call add(s:checks, [line('$') - 1, 4, 'zz-' . s:word, '', s:category])
        endif
      endif
    endfor
  endfor
  for [s:lnum, s:col, s:word, s:group, s:category] in s:checks
    for s:offset in range(strlen(s:word))
      let s:actual = s:GroupAt(s:lnum, s:col + s:offset)
      if s:actual !=# s:group
        call s:Fail(printf('%s %s in %s: expected %s, got %s at column %d',
              \ s:category, string(s:word), string(getline(s:lnum)), string(s:group), string(s:actual), s:col + s:offset))
        break
      endif
    endfor
  endfor
  let s:total = len(s:checks)
else
  let s:total = 0
endif

" ---------------------------------------------------------------- report
if empty(s:errors)
  call writefile([printf('vim: all checks passed (%d keyword checks)', s:total)], '/dev/stdout')
  qall!
endif
call writefile(map(copy(s:errors), '"FAIL: " . v:val'), '/dev/stderr')
cquit 1
