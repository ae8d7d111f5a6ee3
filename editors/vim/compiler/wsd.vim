" Compiler: wsd check. `:make` checks the current file (arguments are passed on, as in
" `:make -D variant=2`) and fills the quickfix list from its diagnostics,
" `file:line:col: error|warning|note: message`; the source excerpts and help lines under each are
" left out. The executable is g:wsd_path (default "wsd").
if exists('current_compiler')
  finish
endif
let current_compiler = 'wsd'

if exists(':CompilerSet') != 2
  command -nargs=* CompilerSet setlocal <args>
endif

let s:cpo_save = &cpo
set cpo&vim

execute 'CompilerSet makeprg=' . escape(get(g:, 'wsd_path', 'wsd'), ' \|"') . '\ check\ %:S'
CompilerSet errorformat=
      \%f:%l:%c:\ %trror:\ %m,
      \%f:%l:%c:\ %tarning:\ %m,
      \%f:%l:%c:\ %tote:\ %m,
      \%+Gwsd:\ %m,
      \%-G%.%#

let &cpo = s:cpo_save
unlet s:cpo_save
