" Vim syntax file for wsd scene files (.wsd) and include fragments (.wsdi).
" The word lists are the language's own (keywords, property names, property words, built-in
" functions and constants); the test suite checks that they match it.
if exists('b:current_syntax')
  finish
endif

let s:cpo_save = &cpo
set cpo&vim

syn case match
syn iskeyword a-z,A-Z,48-57,_

" Keywords.
syn keyword wsdControl else for if in include return
syn keyword wsdDeclaration fn let nextgroup=wsdDefinedName skipwhite
syn keyword wsdBlock box camera cone cylinder disc light mesh plane settings sphere torus triangle
syn keyword wsdCsg difference intersection union
syn keyword wsdGroup group object
syn keyword wsdValueBlock checker image material perlin
syn keyword wsdBoolean false true
syn match wsdDefinedName "\<[A-Za-z_][A-Za-z0-9_]*\>" contained

" Names the language looks up where they appear. A built-in function is a name followed by '('
" (min and max are also box properties); later matches win, so functions come last.
syn match wsdLightKind "\%(\<light\s\+\)\@<=\<\%(area\|point\|spot\)\>"
syn match wsdProperty "\<\%(aa_threshold\|absorption\|adaptive\|adaptive_supersampling\|ambient\|angle\|background\|bailout\|base\|base_radius\|bump\|bump_strength\|cap\|cap_radius\|caustic_photons\|center\|color\|colors\|diffuse\|distance\|emission\|exact_area_lights\|faces\|falloff\|file\|fov\|height\|hole\|indirect_bounces\|indirect_samples\|intensity\|ior\|kind\|look_at\|major\|max\|max_depth\|min\|minor\|normal\|normals\|octaves\|open\|position\|radius\|reflection\|rotate\|samples\|sampling\|scale\|seed\|shininess\|specular\|supersamples\|texture\|translate\|transmission\|u\|up\|uv\|uv_scale\|uvs\|v\|vertices\|width\)\>"
syn match wsdPropertyValue "\<\%(jittered\|marble\|noise\|turbulence\|uniform\|wood\)\>"
syn match wsdConstant "\<\%(clock\|frame\|off\|on\|pi\)\>"
syn match wsdFunction "\<\%(abs\|acos\|asin\|atan\|atan2\|ceil\|clamp\|cos\|cross\|degrees\|dot\|exp\|floor\|len\|length\|log\|max\|min\|mix\|normalize\|param\|pow\|radians\|random\|rgb\|round\|sin\|sqrt\|srgb\|tan\)\>\ze\s*("

" Literals.
syn match wsdNumber "\<\d\+\%(\.\%(\.\)\@!\d*\)\=\%([eE][+-]\=\d\+\)\=\>"
syn match wsdNumber "\%(\<\d\+\)\@<!\.\d\+\%([eE][+-]\=\d\+\)\=\>"
syn match wsdNumber "\<\d\+\.\%([.0-9A-Za-z_]\)\@!"
syn match wsdEscape "\\[\"\\nt]" contained
syn match wsdBadEscape "\\[^\"\\nt]" contained
syn region wsdString start=+"+ skip=+\\\\\|\\"+ end=+"+ end=+$+ contains=wsdEscape,wsdBadEscape oneline

" Operators and POV-Ray's preprocessor, which wsd does not have (before
" comments, so that a comment's '//' wins over '/').
syn match wsdOperator "\.\.\|==\|!=\|<=\|>=\|&&\|||\|[-+*/%!=]"
syn match wsdError "#\a*"

" Comments (block comments nest).
syn keyword wsdTodo TODO FIXME XXX contained
syn region wsdComment start="//" end="$" contains=wsdTodo,@Spell
syn region wsdBlockComment start="/\*" end="\*/" contains=wsdBlockComment,wsdTodo,@Spell fold

hi def link wsdControl Conditional
hi def link wsdDeclaration Keyword
hi def link wsdBlock Structure
hi def link wsdCsg Structure
hi def link wsdGroup Structure
hi def link wsdValueBlock Type
hi def link wsdBoolean Boolean
hi def link wsdDefinedName Identifier
hi def link wsdLightKind Constant
hi def link wsdProperty Identifier
hi def link wsdPropertyValue Constant
hi def link wsdConstant Constant
hi def link wsdFunction Function
hi def link wsdNumber Number
hi def link wsdEscape SpecialChar
hi def link wsdBadEscape Error
hi def link wsdString String
hi def link wsdTodo Todo
hi def link wsdComment Comment
hi def link wsdBlockComment Comment
hi def link wsdOperator Operator
hi def link wsdError Error

let b:current_syntax = 'wsd'

let &cpo = s:cpo_save
unlet s:cpo_save
