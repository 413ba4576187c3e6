# Writes the man page OUT for the built program PROG (in folder BIN) with help2man: its --help
# and --version, each subcommand's --help (SUBS: "run;info;farm:submit", a colon for a nested
# one) as a COMMANDS section, and the hand-written sections of EXTRA (help2man's include format).
# -DHELP2MAN= -DBIN= -DPROG= -DNAME= -DSUBS= -DEXTRA= -DOUT=
set(ENV{PATH} "${BIN}:$ENV{PATH}")  # so that usage lines say `isg`, not the build path
set(inc "")
if(SUBS)
  string(APPEND inc "[COMMANDS]\n")
  foreach(sub ${SUBS})
    string(REPLACE ":" ";" args "${sub}")
    string(REPLACE ":" " " title "${sub}")
    execute_process(COMMAND ${PROG} ${args} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${PROG} ${title} --help failed (${rc})")
    endif()
    string(REPLACE "\\" "\\e" help "${help}")
    string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" help "${help}")
    string(APPEND inc ".SS \"${PROG} ${title}\"\n.nf\n${help}.fi\n")
  endforeach()
endif()
file(READ "${EXTRA}" extra)
file(WRITE "${OUT}.h2m" "${inc}${extra}")
execute_process(COMMAND ${HELP2MAN} --no-info --name=${NAME} --include=${OUT}.h2m
                        --output=${OUT} ${PROG} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "help2man ${PROG} failed (${rc})")
endif()
