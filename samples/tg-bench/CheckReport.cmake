# Runs `tg-bench report --quick` and checks what it wrote: every section, every plot, and an
# error entry in every row of every table. Usage:
#   cmake -DTG_BENCH=<tg-bench> -DOUT=<folder> -P CheckReport.cmake
if(NOT TG_BENCH OR NOT OUT)
  message(FATAL_ERROR "usage: cmake -DTG_BENCH=<tg-bench> -DOUT=<folder> -P CheckReport.cmake")
endif()
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${TG_BENCH}" report --quick --out "${OUT}" RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "tg-bench report --quick failed (${result})")
endif()

foreach(file REPORT.md report.jsonl speed-vs-error.svg rebuild.svg toplevel.svg)
  if(NOT EXISTS "${OUT}/${file}")
    message(FATAL_ERROR "the report lacks ${file}")
  endif()
endforeach()

file(READ "${OUT}/REPORT.md" report)
foreach(section "## Top-level rebuild" "## Object rebuild" "## Scene build" "## Ray throughput"
        "## Frames" "## Scene-graph sync" "## Loading" "## Accuracy" "### leaks" "### t error"
        "### acne" "### contact shadows" "### thin glass" "### determinism"
        "## Static build against Embree" "## Two-level overhead" "## Thread scaling"
        "## Memory per triangle" "## Variants compared" "## Targets against Embree"
        "## The 2003 paper beside ours" "## Plots" "FLIP ")
  string(FIND "${report}" "${section}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the report lacks the section '${section}'")
  endif()
endforeach()
string(FIND "${report}" "Suite failed" at)
if(NOT at EQUAL -1)
  message(FATAL_ERROR "a suite failed; see ${OUT}/REPORT.md")
endif()

# Every row of a speed table ("| case | impl | median ms | ... | error |") has 8 cells, the
# last one (the error) not empty.
file(STRINGS "${OUT}/REPORT.md" lines)
set(in_table FALSE)
set(rows 0)
foreach(line IN LISTS lines)
  if(line MATCHES "^\\| case \\| impl \\| median ms")
    if(NOT line MATCHES "\\| error \\|$")
      message(FATAL_ERROR "a speed table has no error column: ${line}")
    endif()
    set(in_table TRUE)
  elseif(in_table AND line MATCHES "^\\|---")
  elseif(in_table AND line MATCHES "^\\| ")
    string(REGEX MATCHALL "\\|" bars "${line}")
    list(LENGTH bars count)
    if(NOT count EQUAL 9 OR line MATCHES "\\|[ ]*\\|$")
      message(FATAL_ERROR "a speed row lacks its error entry: ${line}")
    endif()
    math(EXPR rows "${rows} + 1")
  else()
    set(in_table FALSE)
  endif()
endforeach()
if(rows LESS 50)
  message(FATAL_ERROR "only ${rows} speed rows in the report")
endif()
message(STATUS "report: ${rows} speed rows, each with its error")
