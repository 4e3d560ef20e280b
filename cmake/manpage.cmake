# gapfe.1, the command's manual page, from its own help (cmake -P; examples/gapfe/CMakeLists.txt runs it
# after each build of the command): `gapfe --help` is the page's source, so the two cannot disagree.
#   cmake -DGAPFE=path/to/gapfe -DVERSION=x.y.z -DOUT=gapfe.1 -P cmake/manpage.cmake
function(gapfe_help out)
  execute_process(COMMAND ${GAPFE} ${ARGN} OUTPUT_VARIABLE text RESULT_VARIABLE code)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "manpage.cmake: ${GAPFE} ${ARGN} exited with ${code}")
  endif()
  # roff: a backslash is \e, an option's dash \-; a line starting with . or ' would be a request
  string(REPLACE "\\" "\\e" text "${text}")
  string(REPLACE "-" "\\-" text "${text}")  # a minus, not a hyphen: options stay searchable and copyable
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

gapfe_help(overview --help)
set(page ".TH GAPFE 1 \"\" \"gapfe ${VERSION}\" \"User Commands\"
.SH NAME
gapfe \\- axisymmetric finite elements with gaps, contact, friction and plasticity (BRL-CR-670 decks and scene files)
.SH SYNOPSIS
.B gapfe
.I COMMAND OPERAND
[options]
.SH DESCRIPTION
.nf
${overview}.fi
")
foreach(command run mesh info plot)
  gapfe_help(help ${command} --help)
  string(APPEND page ".SH \"GAPFE ${command}\"\n.nf\n${help}.fi\n")
endforeach()
string(APPEND page ".SH SEE ALSO
The manual in the source tree's docs/ folder: decks.md, scenes.md, output.md, process.md.
")
file(WRITE ${OUT} "${page}")
