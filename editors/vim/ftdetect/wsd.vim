" wsd scene files (.wsd) and include fragments (.wsdi).
autocmd BufNewFile,BufRead *.wsd,*.wsdi setfiletype wsd
