#!/usr/bin/env bash
# CTest: the Vim support in editors/vim. Vim, run in Ex mode with only that directory on its
# runtimepath, detects .wsd and .wsdi files, sets commentstring, loads the syntax file without an
# error and highlights keywords, properties, functions, numbers, strings and comments; `:make`
# (compiler wsd, through `wsd check`) fills the quickfix list with each diagnostic's file, line,
# column and kind, also for an error in an included file; nothing in the example scenes is
# highlighted as an error. Exits 77 (CTest's SKIP_RETURN_CODE) when Vim is not installed, except
# in CI (CI=true), where that is a failure.
# Usage: vim.sh WSD SOURCE_DIR
set -euo pipefail
wsd=$(realpath "$1")
src=$(realpath "$2")
if ! command -v vim >/dev/null 2>&1; then
  if [[ "${CI:-}" == true ]]; then
    echo "vim.sh: vim is not installed (CI installs the Debian package vim)" >&2
    exit 1
  fi
  echo "SKIPPED: vim is not installed (apt-get install vim)"
  exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/wsd-vim-XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"

cat >scene.wsd <<'WSD'
sphere { center <0, 1, 0>  radus 2  material { color <1, 0, 0> } }
let m = min(1, 2) // the smaller
light point { position <0, 5, 0> }
include "parts.wsdi"
WSD
printf 'let q = 1 +\n' >parts.wsdi

cat >check.vim <<'VIM'
let g:out = []
function! Note(line) abort
  call add(g:out, a:line)
endfunction
function! SynAt(line, col) abort
  return synIDattr(synID(a:line, a:col, 1), 'name')
endfunction
syntax on
filetype plugin on
let v:errmsg = ''
edit scene.wsd
call Note('filetype ' . &filetype)
call Note('commentstring ' . &commentstring)
call Note('syntax ' . get(b:, 'current_syntax', 'none'))
call Note('errors [' . v:errmsg . ']')
call Note('at 1:1 ' . SynAt(1, 1))
call Note('at 1:10 ' . SynAt(1, 10))
call Note('at 1:18 ' . SynAt(1, 18))
call Note('at 1:38 ' . SynAt(1, 38))
call Note('at 2:1 ' . SynAt(2, 1))
call Note('at 2:9 ' . SynAt(2, 9))
call Note('at 2:13 ' . SynAt(2, 13))
call Note('at 2:20 ' . SynAt(2, 20))
call Note('at 3:1 ' . SynAt(3, 1))
call Note('at 3:7 ' . SynAt(3, 7))
call Note('at 4:1 ' . SynAt(4, 1))
call Note('at 4:10 ' . SynAt(4, 10))
silent make!
for e in getqflist()
  if e.valid
    call Note(printf('qf %s:%d:%d:%s:%s', bufname(e.bufnr), e.lnum, e.col, e.type, e.text))
  endif
endfor
edit parts.wsdi
call Note('fragment filetype ' . &filetype)
" The example scenes are valid: nothing in them is highlighted as an error.
let g:bad = 0
let g:files = 0
for f in glob(g:examples . '/*.wsd', 0, 1) + glob(g:examples . '/include/*.wsdi', 0, 1)
  execute 'edit ' . fnameescape(f)
  let g:files += 1
  for l in range(1, line('$'))
    for c in range(1, col([l, '$']) - 1)
      if SynAt(l, c) =~# 'Error\|BadEscape'
        call Note(printf('error group %s at %s:%d:%d', SynAt(l, c), fnamemodify(f, ':t'), l, c))
        let g:bad += 1
        break
      endif
    endfor
  endfor
endfor
call Note('example errors ' . g:bad . (g:files >= 5 ? '' : ' (too few files: ' . g:files . ')'))
call writefile(g:out, 'out.txt')
qall!
VIM

vim -N -u NONE -i NONE -es --cmd "set runtimepath^=$src/editors/vim" --cmd "let g:wsd_path = '$wsd'" \
  --cmd "let g:examples = '$src/examples'" \
  -S check.vim </dev/null >vim.log 2>&1 || true

cat >expected.txt <<'TXT'
filetype wsd
commentstring // %s
syntax wsd
errors []
at 1:1 wsdBlock
at 1:10 wsdProperty
at 1:18 wsdNumber
at 1:38 wsdValueBlock
at 2:1 wsdDeclaration
at 2:9 wsdFunction
at 2:13 wsdNumber
at 2:20 wsdComment
at 3:1 wsdBlock
at 3:7 wsdLightKind
at 4:1 wsdControl
at 4:10 wsdString
qf scene.wsd:1:28:e:unknown property 'radus' in sphere
qf parts.wsdi:2:1:e:expected an expression, found end of file
qf scene.wsd:4:9:n:in file included from here
fragment filetype wsd
example errors 0
TXT
if ! diff -u expected.txt out.txt; then
  cat vim.log >&2
  echo "vim.sh: Vim's view of the scene differs from the expected one (above)" >&2
  exit 1
fi
echo "vim: filetype, syntax and :make with the wsd compiler work"
