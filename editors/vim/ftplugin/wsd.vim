" Filetype settings for wsd scene files: comments, and `:make` through `wsd check`.
if exists('b:did_ftplugin')
  finish
endif
let b:did_ftplugin = 1

setlocal commentstring=//\ %s
setlocal comments=s1:/*,mb:*,ex:*/,://
setlocal formatoptions-=t formatoptions+=croql
setlocal suffixesadd=.wsd,.wsdi
setlocal iskeyword=a-z,A-Z,48-57,_
compiler wsd

let b:undo_ftplugin = 'setlocal commentstring< comments< formatoptions< suffixesadd< iskeyword<'
      \ . ' makeprg< errorformat<'
